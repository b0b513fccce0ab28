"""The accuracy ladder's frequency-domain rung (``pygear accuracy CASE --scene <response
scene>``): the harmonic count it recommends for a tolerance meets it against an
independent steady state (time integration by exact exponentials), half that count does
not; bad options are refused in one line."""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from pygear.analysis.response import mesh_signals, response_system, solve_hill
from pygear.cli import main
from pygear.io import open_dataset
from pygear.model.case import load_case

ROOT = Path(__file__).resolve().parent.parent
PLANETARY = ROOT / "cases" / "yang2016_planetary"
SPEEDS = (1675.0, 2400.0, 2)
"""The speeds at which tests/test_response.py validates the balance against time
integration (the ring-planet K_v peak next to the 1662 rpm mode, and above it)."""

CASE_FILE = textwrap.dedent(
    f"""
    import dataclasses
    from pygear import Scene, load_case
    from pygear.model.response_settings import Response

    base = load_case(r"{PLANETARY}")
    scene = Scene("resp", analyses=("response",), formulation="improved", dof_set="planar",
                  effects=("time_varying_mesh_stiffness",),
                  response=Response(speeds_rpm={SPEEDS!r}))
    case = dataclasses.replace(base, scenes=base.scenes + (scene,))
    """
)


@pytest.fixture(scope="module")
def case_dir(tmp_path_factory) -> Path:
    directory = tmp_path_factory.mktemp("cases") / "planetary_accuracy"
    directory.mkdir()
    (directory / "case.py").write_text(CASE_FILE)
    return directory


def _period_map_forces(system, omega: float, segments: int) -> np.ndarray:
    """Mesh forces at tau = i / segments of the periodic orbit of a time integration:
    each interval's exact exponential (stiffness at its trapezoidal mean, the load in an
    augmented row), composed over a period, x0 = (I - Phi)^-1 p (as tests/test_response.py
    integrates; independent of the balance)."""
    n = system.size
    step = system.stiffness.shape[0] // segments
    dk = system.stiffness_variation
    means = (dk.reshape(segments, step, -1).sum(axis=1) - 0.5 * dk[::step]
             + 0.5 * np.roll(dk, -step, axis=0)[::step]) / step  # fmt: skip
    a = np.zeros((segments, 2 * n + 1, 2 * n + 1))
    a[:, :n, n : 2 * n] = np.eye(n)
    a[:, n : 2 * n, :n] = -(np.diag(system.eigenvalues) + np.einsum(
        "mi,sm,mj->sij", system.mesh_rows, means, system.mesh_rows))  # fmt: skip
    a[:, n : 2 * n, n : 2 * n] = -system.damping
    a[:, n : 2 * n, 2 * n] = system.force
    exponentials = scipy.linalg.expm(a * (2 * math.pi / omega / segments))
    running = np.eye(2 * n + 1)
    maps = [running]
    for e in exponentials[:-1]:
        running = e @ running
        maps.append(running)
    period = exponentials[-1] @ running
    x0 = np.linalg.solve(np.eye(2 * n) - period[: 2 * n, : 2 * n], period[: 2 * n, 2 * n])
    states = np.array([m[: 2 * n, : 2 * n] @ x0 + m[: 2 * n, 2 * n] for m in maps])
    deflection = states[:, :n] @ system.mesh_rows.T
    return system.contact_sign * system.stiffness[::step] * deflection


@pytest.fixture(scope="module")
def integrated(case_dir):
    """The system and, per speed, the time integration's mesh forces at 1024 instants
    (its own error below 3e-5 of the largest force at these speeds, asserted in
    tests/test_response.py: far below the tolerances judged here)."""
    case = load_case(case_dir)
    system = response_system(case, case.scene("resp"))
    speeds = np.linspace(*SPEEDS[:2], SPEEDS[2])
    return system, {s: _period_map_forces(system, system.omega(s), 1024) for s in speeds}


def _true_error(system, reference: dict, count: int) -> float:
    """Largest mesh-force error of H = count against the integration, over the speeds,
    in units of each speed's largest mesh force."""
    worst = 0.0
    for speed, forces in reference.items():
        _, force = mesh_signals(system, solve_hill(system, system.omega(speed), count))
        stride = force.shape[0] // forces.shape[0]
        worst = max(worst, np.abs(force[::stride] - forces).max() / np.abs(forces).max())
    return worst


@pytest.mark.parametrize("tolerance", ["1%", "0.1%"])
def test_recommended_count_meets_the_tolerance_and_half_does_not(
    case_dir, integrated, tolerance, tmp_path, capsys
):
    code = main(["accuracy", str(case_dir), "--scene", "resp", "--tolerance", tolerance,
                 "--json", "--out", str(tmp_path)])  # fmt: skip
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    value = float(tolerance.rstrip("%")) / 100
    best = summary["recommendation"]["harmonics"]
    assert summary["speeds_judged"] == 2 and summary["reference_harmonics"] == 256
    assert best >= 4  # there is a half count in the ladder to check
    system, reference = integrated
    assert _true_error(system, reference, best) <= value
    assert _true_error(system, reference, best // 2) > value
    with open_dataset(tmp_path / "accuracy_resp.nc") as ladder:
        assert ladder.attrs["recommended_harmonics"] == best
        assert ladder.max_judged_error.sel(harmonics=best) <= value
        assert np.all(ladder.wall_time.values > 0)
    assert (tmp_path / "accuracy_resp_harmonics.png").stat().st_size > 10_000
    assert (tmp_path / "accuracy_resp.txt").read_text().count("<- recommended") == 1


def test_table_is_printed_without_json(case_dir, tmp_path, capsys):
    assert main(["accuracy", str(case_dir), "--scene", "resp", "--levels", "4",
                 "--out", str(tmp_path)]) == 0  # fmt: skip
    out = capsys.readouterr().out
    assert "reference H = 32" in out and "recommended" in out


def _no_case(*args, **kwargs):
    raise AssertionError("the case was loaded before the options were checked")


@pytest.mark.parametrize(
    ("argv", "flag"),
    [
        (["--duration", "1.0"], "--duration"),
        (["--coarsest-time-step", "1e-4"], "--coarsest-time-step"),
        (["--formulation", "improved"], "--formulation"),
        (["--levels", "0"], "--levels"),
        (["--levels", "12"], "--levels"),
        (["--tolerance", "0"], "--tolerance"),
        (["--tolerance=-1%"], "--tolerance"),
    ],
)
def test_bad_options_for_a_response_scene(case_dir, argv, flag, tmp_path, capsys):
    code = main(["accuracy", str(case_dir), "--scene", "resp", "--out", str(tmp_path), *argv])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1
    assert err.startswith("pygear accuracy: error:") and flag in err
    assert not list(tmp_path.glob("accuracy_*"))
