"""Campbell diagrams: modes tracked by shape, crossings with orders, unstable ranges,
the ``pygear campbell`` command and sweeps over the carrier speed.

Constructed systems have closed forms (a mode crossing another, a rotor whose frequency
passes through zero in its rotating frame, an anisotropic rotor's divergence band);
the study case is checked against independent paths (modal analysis at zero speed, the
modes solved at each crossing's speed, the strain energy from Model.stiffness_of).
"""

from __future__ import annotations

import dataclasses
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
import xarray as xr

from pygear import Scene, load_case
from pygear.analysis.modes.campbell import campbell_diagram, check_speeds, unstable_ranges
from pygear.analysis.modes.gyroscopic import (
    GROWTH_TOLERANCE,
    quadratic_modes,
    speed_dependent_modes,
    whirl_ratios,
)
from pygear.analysis.modes.modal import modal_analysis
from pygear.analysis.modes.mode_tracking import ModeTracker
from pygear.assembly.matrices import assemble
from pygear.assembly.speed_terms import SpeedTerms, TranslationPair, speed_terms
from pygear.cli.parser import main
from pygear.errors import CaseError
from pygear.io import write_netcdf
from pygear.runs.sweep import run_sweep

CASES = Path(__file__).resolve().parent.parent / "cases"
RPM = math.pi / 30.0  # rad/s per rpm


def matrix_tracker(mass, stiffness_at, first_order_at) -> ModeTracker:
    """A tracker over a system given by matrices as functions of the speed [rad/s]."""

    def solve(speed_rpm: float):
        speed = speed_rpm * RPM
        return quadratic_modes(mass, stiffness_at(speed), first_order_at(speed), rigid_count=0)

    return ModeTracker(solve, mass)


# --------------------------------------------------------------------------- tracking


@pytest.mark.parametrize("coupling", [0.0, 10.0])
def test_tracking_keeps_a_mode_through_a_crossing_that_sorting_swaps(coupling):
    """Mode e1 softens (k1 - Omega^2) through mode e2 (k2) at Omega = 2 pi 80 rad/s =
    4800 rpm.  Uncoupled they cross; with a weak coupling (10 (rad/s)^2 against a k of
    1.4e5) they veer within 0.2 rpm, far inside the smallest refined step (6 rpm), so
    the e1-like mode keeps its number while its sorted place changes.  The grid steps
    over 4800 rpm, where a veering's modes are half e1, half e2."""
    k1, k2 = (2 * math.pi * 100) ** 2, (2 * math.pi * 60) ** 2
    mass = np.eye(2)

    def stiffness(speed):
        return np.array([[k1 - speed**2, coupling], [coupling, k2]])

    tracker = matrix_tracker(mass, stiffness, lambda speed: np.zeros((2, 2)))
    speeds = np.linspace(0.0, 5600.0, 28)
    tracking = tracker.track(speeds)
    frequency = np.array([m.frequencies for m in tracking.modes])
    # numbered by frequency at the first speed: mode 2 is e1 (100 Hz)
    e1 = 1
    for k, speed in enumerate(speeds):
        values, vectors = np.linalg.eigh(stiffness(speed * RPM))
        like_e1 = int(np.argmax(np.abs(vectors[0])))  # the eigenvector mostly along e1
        expected = math.sqrt(values[like_e1]) / (2 * math.pi)
        # two symmetric 2x2 eigensolvers (eigh, the scaled state space): round-off only
        assert frequency[k, e1] == pytest.approx(expected, rel=1e-10)
        shape = tracking.modes[k].shapes[:, e1]
        assert abs(shape[0]) ** 2 / np.sum(np.abs(shape) ** 2) > 0.99
    assert frequency[0, e1] > frequency[0, 1 - e1] and frequency[-1, e1] < frequency[-1, 1 - e1]
    assert not tracking.ambiguous.any()


def test_tracking_follows_a_frequency_through_zero():
    """A rotor in its rotating frame: the forward mode's frequency |omega_n - Omega|
    falls to zero at Omega = omega_n and rises again; its eigenvalue passes through zero
    and comes back as its conjugate.  Tracking keeps it (forward whirl throughout), and
    sorting would have taken the backward one at omega_n + Omega nowhere near it."""
    mass, stiffness = 2.0, 8.0e4
    natural = math.sqrt(stiffness / mass)
    pair = TranslationPair(
        "rotor.body", "rotor", "central", mass, np.array([1.0, 0.0]), np.array([0.0, 1.0]), 1, 1
    )
    gyroscopic = 2 * mass * np.array([[0.0, -1.0], [1.0, 0.0]])
    terms = SpeedTerms("r", "all", gyroscopic, mass * np.eye(2), (pair,), {}, {})
    tracker = matrix_tracker(
        mass * np.eye(2),
        lambda speed: (stiffness - mass * speed**2) * np.eye(2),
        lambda speed: speed * gyroscopic,
    )
    speeds = np.linspace(50.0, 3800.0, 31)  # 5.2 to 398 rad/s, across omega_n = 200
    tracking = tracker.track(speeds)
    forward = int(np.argmin(tracking.modes[0].frequencies))
    for speed, modes in zip(speeds, tracking.modes):
        assert modes.frequencies[forward] * 2 * math.pi == pytest.approx(
            abs(natural - speed * RPM), rel=1e-9, abs=1e-9 * natural
        )
        ratio, _ = whirl_ratios(terms, modes, speed)
        assert ratio[forward] > 0.99 and ratio[1 - forward] < -0.99


def test_anisotropic_rotor_diverges_between_its_two_frequencies():
    """m(x'' - 2 Omega y' - Omega^2 x) + k1 x = 0, m(y'' + 2 Omega x' - Omega^2 y) +
    k2 y = 0: (lambda^2 + w1^2 - Omega^2)(lambda^2 + w2^2 - Omega^2) + 4 Omega^2 lambda^2
    has a positive real root exactly when w1 < Omega < w2 (its value at lambda = 0 is
    negative there), and the undamped system is stable elsewhere."""
    mass, w1, w2 = 1.5, 100.0, 120.0
    stiffness = mass * np.diag([w1**2, w2**2])
    gyroscopic = 2 * mass * np.array([[0.0, -1.0], [1.0, 0.0]])
    tracker = matrix_tracker(
        mass * np.eye(2),
        lambda speed: stiffness - mass * speed**2 * np.eye(2),
        lambda speed: speed * gyroscopic,
    )
    speeds = np.linspace(0.0, 2000.0, 41)
    tracking = tracker.track(speeds)
    ranges = unstable_ranges(tracking, tracker.unstable)
    start, stop = ranges["unstable_start"][1], ranges["unstable_stop"][1]
    assert list(ranges["unstable_kind"][1]) == ["divergence"]
    # bisected to 1e-9 of the speed; the growth threshold (1e-7 omega_s) moves the edge
    # by (threshold)^2 / (d sigma^2 / d Omega), 1e-12 relative
    assert start[0] == pytest.approx(w1 / RPM, rel=1e-8)
    assert stop[0] == pytest.approx(w2 / RPM, rel=1e-8)


# --------------------------------------------------------------------------- the study case


@pytest.fixture(scope="module")
def study_campbell(study_case):
    speeds = np.linspace(0.0, 8000.0, 17)
    return campbell_diagram(study_case, speeds, scene=study_case.scene("modal"))


def test_study_case_diagram_is_modal_analysis_at_zero_and_a_reordering_elsewhere(
    study_case, study_campbell
):
    model = assemble(study_case, study_case.scene("modal"))
    reference = modal_analysis(model).frequency.values
    first = study_campbell.frequency.values[0]
    # the scaled state space at zero speed: round-off of a few eps * omega_max
    np.testing.assert_allclose(np.sort(first), reference, rtol=1e-9, atol=1e-9)
    for speed, row in zip(study_campbell.speed.values[1:], study_campbell.frequency.values[1:]):
        direct = speed_dependent_modes(model, study_case, float(speed)).frequency.values
        np.testing.assert_allclose(np.sort(row), np.sort(direct), rtol=1e-12)
    assert study_campbell.tracking_mac.values.min() > 0.8
    assert study_campbell.sizes["unstable_range"] == 0  # stable below 45 000 rpm
    for name in [*study_campbell.data_vars, *study_campbell.coords]:
        attrs = study_campbell[name].attrs
        assert attrs.get("units") and attrs.get("long_name"), name


def test_crossings_lie_on_their_lines(study_case, study_campbell):
    """Each crossing's frequency, solved afresh at its speed, is on the order line:
    linear interpolation over 500 rpm steps leaves the curvature's h^2/8, 1e-4 here."""
    model = assemble(study_case, study_case.scene("modal"))
    rotational_mesh = 0
    for speed, mode, order, name, frequency in zip(
        study_campbell.crossing_speed.values,
        study_campbell.crossing_mode.values,
        study_campbell.crossing_order.values,
        study_campbell.crossing_excitation.values,
        study_campbell.crossing_frequency.values,
    ):
        assert frequency == pytest.approx(order * speed / 60.0, rel=1e-12)
        if "mesh" not in str(name):
            continue
        direct = speed_dependent_modes(model, study_case, float(speed)).frequency.values
        assert np.min(np.abs(direct / frequency - 1)) < 1e-4
        rotational_mesh += mode == 18
    # the highest rotational mode (11 824 Hz at rest) meets harmonics 1..3 of both the
    # ring mesh (96 carrier orders) and the sun mesh (Z_s r_br/r_bs = 95.93: Table 1's
    # base radii and tooth numbers differ by 0.07 %) in range
    assert rotational_mesh == 6
    names = set(study_campbell.excitation.values)
    assert {"planetary ring mesh 1x", "planetary sun mesh 1x"} <= names
    orders = dict(zip(study_campbell.excitation.values, study_campbell.excitation_order.values))
    stage = study_case.gearbox.stages[0]
    assert orders["planetary ring mesh 1x"] == pytest.approx(stage.ring.teeth, rel=1e-9)
    assert orders["planetary sun mesh 1x"] == pytest.approx(
        stage.sun.teeth * stage.ring.base_radius / stage.sun.base_radius, rel=1e-9
    )


def test_mesh_excitability_is_the_meshes_share_of_strain_energy(study_case, study_campbell):
    """For the simple (rotational) modes at zero speed: phi^T (sum_m k_m dK/dk_m) phi /
    phi^T K0 phi from Model.stiffness_of, an independent path through the springs."""
    model = assemble(study_case, study_case.scene("modal"))
    modal = modal_analysis(model)
    stage = study_case.gearbox.stages[0]
    meshes = stage.sun_mesh.stiffness * model.stiffness_of(
        "planetary.sun_mesh.stiffness"
    ) + stage.ring_mesh.stiffness * model.stiffness_of("planetary.ring_mesh.stiffness")
    first = study_campbell.isel(speed=0)
    for m in np.flatnonzero(modal.multiplicity.values == 1)[1:]:  # skip the free rotation
        shape = modal.shape.values[:, m]
        expected = shape @ meshes @ shape / (shape @ model.stiffness @ shape)
        tracked = int(np.argmin(np.abs(first.frequency.values - modal.frequency.values[m])))
        share = float(first.mesh_energy_share.values[tracked].sum())
        # two sums of the same spring energies in another order: round-off
        assert share == pytest.approx(expected, rel=1e-9)


def test_campbell_round_trips_netcdf(tmp_path, study_campbell):
    path = write_netcdf(study_campbell, tmp_path / "campbell.nc", title="test")
    with xr.open_dataset(path) as opened:
        for name in ("crossing_speed", "crossing_mode", "crossing_excitability", "frequency"):
            np.testing.assert_array_equal(opened[name].values, study_campbell[name].values)
        assert list(opened.crossing_excitation.values) == list(
            study_campbell.crossing_excitation.values
        )


def test_lin_parker_free_rotation_diverges_from_the_first_speed(study_case):
    """Lin & Parker's coordinates let K_Omega soften the free rotation (one negative
    eigenvalue of K - Omega^2 K_Omega at any speed): divergence at a rate sigma =
    c Omega, c = sqrt(v^T K_Omega v / v^T M v) for the free rotation v.  The onset
    bisects to where sigma passes the growth threshold, 1e-7 omega_s."""
    scene = study_case.scene("modal_lin_parker")
    campbell = campbell_diagram(study_case, np.linspace(0.0, 3000.0, 7), scene=scene)
    assert campbell.sizes["unstable_range"] == 1
    assert campbell.unstable_kind.values[0] == "divergence"
    assert campbell.unstable_stop.values[0] == 3000.0
    model = assemble(study_case, scene)
    values, vectors = scipy.linalg.eigh(model.stiffness, model.mass)
    rigid = vectors[:, np.argmin(np.abs(values))]
    terms = speed_terms(model, study_case)
    rate = math.sqrt((rigid @ terms.centripetal @ rigid) / (rigid @ model.mass @ rigid))
    scale = math.sqrt(np.abs(values).max())  # omega_s
    expected = GROWTH_TOLERANCE * scale / rate / RPM  # rpm
    # Rayleigh's quotient to 1e-5 at these speeds; bisection to 1e-9 of 500 rpm.  The
    # free rotation is a double zero eigenvalue (a Jordan block) of the state matrix, so
    # its computed eigenvalues carry round-off of order sqrt(eps) omega_s = 1.5e-8
    # omega_s (Wilkinson), up to 0.15 of the 1e-7 omega_s threshold that fixes the onset:
    # within 1e-3 under Haswell, 1.1e-3 under Prescott.  0.15 still catches a doubled K_Omega
    # (onset / sqrt 2, 29 % off).
    assert campbell.unstable_start.values[0] == pytest.approx(expected, rel=0.15)


@pytest.mark.parametrize(
    "speeds, message",
    [([1.0], "at least 2"), ([2.0, 1.0], "increase strictly"), ([0.0, np.inf], "finite")],
)
def test_check_speeds(speeds, message):
    with pytest.raises(CaseError, match=message):
        check_speeds(speeds)


# --------------------------------------------------------------------------- the command


def test_command_json_and_files(tmp_path, capsys):
    out = tmp_path / "out"
    code = main(
        [
            "campbell",
            str(CASES / "yang2016_planetary"),
            "--speeds",
            "0:2000:5",
            "--json",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert {"speeds_rpm", "frequencies_hz", "crossings", "unstable"} <= set(summary)
    assert summary["speeds_rpm"] == [0.0, 500.0, 1000.0, 1500.0, 2000.0]
    assert len(summary["frequencies_hz"]) == 5 and len(summary["frequencies_hz"][0]) == 18
    assert summary["crossings"] and summary["unstable"] == []
    assert {"speed_rpm", "mode", "order"} <= set(summary["crossings"][0])
    assert (out / "campbell.nc").is_file() and (out / "campbell.png").is_file()


@pytest.mark.parametrize(
    "arguments, parameter",
    [
        (["--speeds", "10:0:5"], "--speeds"),
        (["--speeds", "0:10:1"], "--speeds"),
        (["--speeds", "0:10"], "--speeds"),
        (["--speeds", "0:10:4", "--member", "sun"], "--member"),
        (["--speeds", "0:10:4", "--scene", "nope"], "--scene"),
        (["--speeds", "0:10:4", "--harmonics", "x"], "--harmonics"),
    ],
)
def test_command_refuses_bad_input(tmp_path, capsys, arguments, parameter):
    out = tmp_path / "out"
    code = main(["campbell", str(CASES / "yang2016_planetary"), *arguments, "--out", str(out)])
    assert code == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and parameter in error
    assert not out.exists()


def test_help_loads_no_analysis():
    code = (
        "import sys\n"
        "from pygear.cli.parser import build_parser\n"
        "build_parser().format_help()\n"
        "print(sorted(m for m in ('scipy', 'xarray', 'matplotlib') if m in sys.modules))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert result.stdout.strip() == "[]"


# --------------------------------------------------------------------------- sweeps


def spinning_case(study_case):
    spinning = Scene(
        "spinning",
        analyses=("modal",),
        formulation="improved",
        dof_set="planar",
        effects=("gyroscopic_all_members",),
        carrier_speed_rpm=120.0,
    )
    return dataclasses.replace(study_case, scenes=(*study_case.scenes, spinning))


def test_sweep_over_the_carrier_speed(tmp_path, scheduler, study_case):
    case = spinning_case(study_case)
    speeds = [0.0, 1500.0, 3000.0]
    swept = run_sweep(
        case,
        [("scene.carrier_speed_rpm", speeds)],
        scene="spinning",
        out_dir=tmp_path,
        scheduler=scheduler,
        progress=False,
    )
    assert swept["scene__carrier_speed_rpm"].attrs["units"] == "rpm"
    model = assemble(study_case, study_case.scene("modal"))
    for speed in speeds:
        found = swept.frequency.sel(scene__carrier_speed_rpm=speed).values
        direct = speed_dependent_modes(model, study_case, speed).frequency.values
        # modal.py's unscaled state space against the scaled one: 3e-10 relative
        np.testing.assert_allclose(np.sort(found), np.sort(direct), rtol=1e-8, atol=1e-6)


@pytest.mark.parametrize(
    "path, scene, message",
    [
        ("scene.carrier_speed_rpm", "runup", "run-up drives the speed itself"),
        ("scene.carrier_speed_rpm", "modal", "no speed-dependent effect"),
        ("scene.duration", "spinning", "scene settings a sweep varies"),
    ],
)
def test_sweep_over_speed_refusals(tmp_path, study_case, path, scene, message):
    with pytest.raises(CaseError, match=message):
        run_sweep(
            spinning_case(study_case),
            [(path, "0,100")],
            scene=scene,
            out_dir=tmp_path,
            progress=False,
        )


def test_every_stage_turns_at_its_own_carrier_speed():
    """In Yang et al.'s gearbox stage 1's sun drives stage 2's carrier: stage 2's frame
    turns at stage 1's ratio 1 + r_br/r_bs times the input (ring held), and the
    parallel pair's mesh order is Z_1 times its input gear's speed ratio."""
    case = load_case(CASES / "yang2016_gearbox")
    model = assemble(case, case.scene("modal"))
    terms = speed_terms(model, case)
    first, second, parallel = case.gearbox.stages
    assert terms.frame_ratios[first.name] == pytest.approx(1.0, rel=1e-12)
    # the free rotation's ratios against the ideal kinematics of the base radii
    assert terms.frame_ratios[second.name] == pytest.approx(first.speed_ratio, rel=1e-9)
    input_gear = terms.speed_ratios[f"{parallel.name}.input_gear"]
    assert input_gear == pytest.approx(first.speed_ratio * second.speed_ratio, rel=1e-9)
