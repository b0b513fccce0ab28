"""``pygear response --contact-loss``: the branch with backlash after the linear sweep,
its file, figure and jump speeds against the library's continuation, and the flags it
refuses before any work."""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import numpy as np
import pytest

from pygear.analysis.response import case_law, continue_response, response_system
from pygear.cli import main
from pygear.io import open_dataset
from pygear.model.case import load_case

PAIR = textwrap.dedent(
    """
    import math
    from pygear import Bearing, Case, Gear, Gearbox, Mesh, ParallelStage, RayleighDamping, Scene

    def gear(teeth):
        radius = 4e-3 * teeth * math.cos(math.radians(20)) / 2
        mass = 3.0 * (teeth / 23) ** 2
        inertia = 0.5 * mass * (radius / math.cos(math.radians(20))) ** 2
        return Gear(mass=mass, polar_inertia=inertia, tilt_inertia=inertia / 2,
                    base_radius=radius, teeth=teeth)

    bearing = Bearing(radial=5e8, axial=5e8, tilt=1e10, torsional=0.0)
    stage = ParallelStage(
        name="pair", input_gear=gear(23), output_gear=gear(41), input_bearing=bearing,
        output_bearing=bearing, overlap_ratio=0.0, base_helix_angle_deg=0.0,
        mesh=Mesh(stiffness=3e8, pressure_angle_deg=20.0, contact_ratio=1.6,
                  end_to_peak=0.9, backlash=0.1e-3),
    )
    case = Case(name="pair", gearbox=Gearbox(stages=(stage,)), formulation="improved",
                damping=RayleighDamping(0.0, 2e-6),
                scenes=(Scene("modal", dof_set="planar"),))
    """
)
"""The spur pair of tests/test_response_backlash.py (23:41, 4 mm, contact ratio 1.6,
j_wt = 0.1 mm): under 50 N m it loses contact through its main resonance."""

SPEEDS = (6500.0, 7500.0, 21)
TORQUE = 50.0


@pytest.fixture(scope="module")
def pair_dir(tmp_path_factory) -> Path:
    directory = tmp_path_factory.mktemp("cases") / "pair"
    directory.mkdir()
    (directory / "case.py").write_text(PAIR)
    return directory


@pytest.fixture(scope="module")
def cli_run(pair_dir, tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    argv = ["response", str(pair_dir), "--scene", "modal", "--speeds",
            "{:g}:{:g}:{:d}".format(*SPEEDS), "--harmonics", "16", "--torque", f"{TORQUE:g}",
            "--contact-loss", "--json", "--out", str(out)]  # fmt: skip
    import contextlib
    import io

    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        code = main(argv)
    assert code == 0
    return json.loads(buffer.getvalue()), out


def test_cli_jumps_equal_the_library_continuation(cli_run, pair_dir):
    """The CLI's jump speeds are those of ``continue_response`` over the sweep's range
    with the case's flank law at the same torque and H (the same computation, so to
    1e-9 relative: only the order of floating-point work could differ).  Independently
    of the code, the softening loop must straddle the linear sweep's first separated
    speed: on the lower branch the balance is the linear one until the teeth part, so
    the up-sweep jump lies past it (within one sweep step), and the down-sweep jump
    below it."""
    summary, out = cli_run
    case = load_case(pair_dir)
    scene = case.scene("modal")
    system = response_system(case, scene, torque=TORQUE)
    branch = continue_response(system, case_law(case, system, scene), SPEEDS[:2],
                               harmonics=16, stability=False)  # fmt: skip
    up, down = summary["jump_up_rpm"]["input-output"], summary["jump_down_rpm"]["input-output"]
    assert len(up) == 1 and len(down) == 1
    assert up == pytest.approx(list(branch.attrs["up_sweep_jumps"]), rel=1e-9)
    assert down == pytest.approx(list(branch.attrs["down_sweep_jumps"]), rel=1e-9)
    separated = [s for s, flag in zip(summary["speeds_rpm"], summary["separation"]["input-output"])
                 if flag]  # fmt: skip
    step = (SPEEDS[1] - SPEEDS[0]) / (SPEEDS[2] - 1)
    assert separated and separated[0] - step <= up[0] and down[0] < separated[0]


def test_branch_file_and_figure(cli_run):
    """The branch is written beside response.nc with the jump speeds as attributes and
    a stability flag for every point; the loop's return branch between the folds has
    the drive flanks parting at every point, and the figure is drawn."""
    summary, out = cli_run
    assert str(out / "response_backlash.nc") in summary["files"]
    assert (out / "response_backlash.png").stat().st_size > 10_000
    with open_dataset(out / "response_backlash.nc") as branch:
        assert np.atleast_1d(branch.attrs["up_sweep_jumps"]) == pytest.approx(
            summary["jump_up_rpm"]["input-output"], rel=1e-12
        )
        assert branch.speed.attrs["units"] == "rpm"
        assert set(np.unique(branch.stable.values)) <= {0, 1}
        first, second = np.flatnonzero(branch.turning.values)
        assert branch.separation.values[first + 1 : second + 1, 0].all()
        # the middle branch of a fold is unstable (a multiplier through +1)
        assert not branch.stable.values[first + 2 : second].all()


def test_no_separation_writes_no_branch(pair_dir, tmp_path, capsys):
    """Below the resonance the linear sweep keeps the teeth together: no branch, no
    file, and empty jump lists for the mesh."""
    code = main(["response", str(pair_dir), "--scene", "modal", "--speeds", "5000:5500:3",
                 "--harmonics", "16", "--torque", "50", "--contact-loss", "--json",
                 "--no-stability", "--out", str(tmp_path), "--no-figures"])  # fmt: skip
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["jump_up_rpm"] == {"input-output": []}
    assert summary["jump_down_rpm"] == {"input-output": []}
    assert not (tmp_path / "response_backlash.nc").exists()


def _no_case(*args, **kwargs):
    raise AssertionError("the case was loaded before the options were checked")


@pytest.mark.parametrize(
    ("argv", "flag"),
    [
        (["--torque", "0"], "--torque"),
        (["--torque", "-50"], "--torque"),
        (["--torque", "nan"], "--torque"),
        (["--torque", "inf"], "--torque"),
        (["--torque", "fifty"], "--torque"),
        (["--contact-loss", "--harmonics", "0"], "--harmonics"),
        (["--contact-loss", "--harmonics", "200"], "--harmonics"),
    ],
)
def test_bad_flags_are_refused_before_the_case(argv, flag, capsys, monkeypatch):
    """One line naming the flag, exit 2, before the case is loaded."""
    monkeypatch.setattr("pygear.model.case.load_case", _no_case)
    assert main(["response", "no-such-case", "--speeds", "100:200:3", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert err.startswith("pygear response: error:") and flag in err


def test_torque_scales_the_linear_response(pair_dir, tmp_path, capsys):
    """Without contact loss the response is linear in the torque: twice the torque,
    twice the mean mesh force, the same dynamic factor (to the solver's round-off)."""
    forces = []
    for torque in ("50", "100"):
        out = tmp_path / torque
        assert main(["response", str(pair_dir), "--scene", "modal", "--speeds", "3000:3000:1",
                     "--harmonics", "8", "--torque", torque, "--no-stability", "--out",
                     str(out), "--no-figures"]) == 0  # fmt: skip
        with open_dataset(out / "response.nc") as data:
            forces.append((float(data.mesh_force_mean[0, 0]), float(data.dynamic_factor[0, 0])))
    capsys.readouterr()
    (f1, k1), (f2, k2) = forces
    assert f2 / f1 == pytest.approx(2.0, rel=1e-10)
    assert k2 == pytest.approx(k1, rel=1e-10)
    # the mean force is the torque over the pinion's base radius (a 23-tooth, 4 mm pinion)
    assert f1 == pytest.approx(50.0 / (4e-3 * 23 * math.cos(math.radians(20)) / 2), rel=1e-6)
