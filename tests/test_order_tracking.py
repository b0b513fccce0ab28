"""Computed order tracking (docs/order_tracking.md; Fyfe & Munck 1997).

Synthetic run-ups whose order content is known in closed form check the numerics: a
chirp of one order recovers its order and amplitude, two orders keep theirs, a
constant-amplitude order's slice is flat, and resampling a pure angle-domain signal is
exact to the cubic-spline and Hermite-crossing errors derived in the docs.  A short
run-up of the study case (Yang, Jiang & Han 2016) checks the angle reconstruction
against the kernel's own angle, the mesh orders against the tooth numbers, and the
``pygear analyze --orders`` command (its JSON, its files and its refusals, exit 2).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pygear.analysis.signals.order_plan import plan_order_tracking
from pygear.analysis.signals.order_references import (
    mesh_orders,
    reference_angle,
    stored_mesh_orders,
)
from pygear.analysis.signals.order_tracking import (
    angle_order_spectrum,
    order_peaks,
    order_slices,
    order_summary,
    resample_to_angle,
    track_orders,
)
from pygear.analysis.signals.signal import SignalError
from pygear.assembly.matrices import assemble
from pygear.cli import main
from pygear.io import open_dataset

STUDY = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"
RING_TEETH = 96  # Z_r of the study case (Yang, Jiang & Han 2016, Table 1)

SAMPLE_RATE = 4096.0  # Hz
DURATION = 4.0  # s
START_REV_S, END_REV_S = 1.0, 10.0  # linear speed ramp of the synthetic reference [rev/s]
ORDER = 17.5  # order of the synthetic chirp


def _run(time, speed_rev_s, channels, angle_rev=None) -> xr.Dataset:
    """A run file as ``pygear run`` writes it: probe attributes on every channel."""
    data = {
        "carrier_speed": (
            "time",
            60.0 * speed_rev_s,
            {"units": "rpm", "quantity": "speed", "target": "planetary.carrier"},
        )
    }
    if angle_rev is not None:
        data["carrier_angle"] = (
            "time",
            2 * np.pi * angle_rev,
            {
                "units": "rad",
                "quantity": "displacement",
                "target": "planetary.carrier.theta_z",
            },
        )
    for name, values in channels.items():
        data[name] = ("time", values, {"units": "m/s^2", "long_name": name})
    return xr.Dataset(data, coords={"time": ("time", time, {"units": "s"})})


def _ramp():
    """Time, speed [rev/s] and angle [rev] of a reference ramping linearly 60 -> 600 rpm."""
    time = np.arange(int(DURATION * SAMPLE_RATE) + 1) / SAMPLE_RATE
    slope = (END_REV_S - START_REV_S) / DURATION
    return time, START_REV_S + slope * time, START_REV_S * time + 0.5 * slope * time**2


def _spline_bound(order: float, top_rev_s: float, amplitude: float = 1.0) -> float:
    """(5/384) H^4 max|x''''| of a cubic spline through A cos(2 pi k r(t)) at H = 1/f_s
    (Hall & Meyer 1976), with |x''''| <= A (2 pi k n_max)^4 when the ramp's own
    derivatives are negligible (2 pi k n' / (2 pi k n)^2 < 1e-3 here)."""
    return 5.0 / 384.0 * amplitude * (2 * np.pi * order * top_rev_s / SAMPLE_RATE) ** 4


# --- synthetic run-ups -------------------------------------------------------------------


def test_chirp_of_one_order_recovers_its_order_and_amplitude():
    time, speed, angle = _ramp()
    run = _run(time, speed, {"chirp": np.cos(2 * np.pi * ORDER * angle)})
    plan = plan_order_tracking(run, "carrier", "chirp")
    # the trapezoid rule integrates a linear speed exactly: the angle is the closed form
    assert plan.reference.angle == pytest.approx(2 * np.pi * angle, abs=1e-9)
    # f_s / (2 n_max) over the record (it ends 16 samples before the run)
    assert plan.resolvable_order == pytest.approx(SAMPLE_RATE / (2 * END_REV_S), rel=1e-3)
    spectrum = angle_order_spectrum(resample_to_angle(plan, run), plan.max_order)
    peak = order_peaks(spectrum, 1)[0]
    assert peak["order"] == pytest.approx(ORDER, rel=1e-3)  # measured 2e-10
    # amplitude: spline error <= 6.8e-5 (_spline_bound) plus the Hann leakage of the
    # order's mirror image 2 x 17.5 x 22 rev = 770 bins away (1/(pi 770^3) = 7e-10);
    # Grandke's interpolation is exact for the Hann window's transform.  Measured 2e-6.
    assert peak["amplitude"] == pytest.approx(1.0, abs=1e-4)
    assert _spline_bound(ORDER, END_REV_S) < 1e-4


def test_two_orders_keep_their_amplitudes():
    time, speed, angle = _ramp()
    second, second_amplitude = 23.25, 0.3
    signal = np.cos(2 * np.pi * ORDER * angle) + second_amplitude * np.cos(
        2 * np.pi * second * angle + 0.7
    )
    run = _run(time, speed, {"two": signal})
    result = track_orders(run, plan_order_tracking(run, "carrier", "two", max_order=60.0))
    peaks = sorted(order_summary(result, 2)["orders"], key=lambda p: p["order"])
    assert [p["order"] for p in peaks] == pytest.approx([ORDER, second], rel=1e-3)
    # each within its spline bound (2.1e-4 A for order 23.25) plus the Hann sidelobe of
    # the other order 5.75 x 22 = 126 bins away (1/(pi 126^3) = 1.6e-7): 5e-4 relative
    # (measured 2e-6 and 6e-6)
    assert _spline_bound(second, END_REV_S) < 2.5e-4
    assert peaks[0]["amplitude"] == pytest.approx(1.0, rel=5e-4)
    assert peaks[1]["amplitude"] == pytest.approx(second_amplitude, rel=5e-4)


def test_slice_of_a_constant_amplitude_order_is_flat():
    time, speed, angle = _ramp()
    run = _run(time, speed, {"chirp": np.cos(2 * np.pi * ORDER * angle)})
    plan = plan_order_tracking(run, "carrier", "chirp")
    resampled = resample_to_angle(plan, run)
    slices = order_slices(resampled, [ORDER], window_revolutions=2.0, overlap=0.5)
    values = slices.sel(tracked_order=ORDER).values
    assert values.size >= 15  # 22 revolutions in half-overlapping windows of 2
    # a Fourier sum at exactly the order: no scalloping; spline error <= 6.8e-5 and the
    # mirror image 2 x 17.5 x 2 = 70 bins away leaks 1/(pi 70^3) = 9e-7.  Measured 6e-6.
    assert np.max(np.abs(values - 1.0)) < 1e-4
    # a window's mean speed is the ramp's speed at its centre time (linear ramp)
    centre = slices["window_time"].values
    slope = (END_REV_S - START_REV_S) / DURATION
    expected = 60.0 * (START_REV_S + slope * centre)
    # the Hermite crossing times are exact for a quadratic angle: round-off (7e-15)
    assert slices["speed"].values == pytest.approx(expected, rel=1e-9)
    assert np.all(np.diff(slices["speed"].values) > 0)


def test_resampling_a_pure_angle_signal_is_exact_to_the_interpolation_error():
    """x = cos(2 pi k r(t)) sampled in time is cos(2 pi k r_j) at the angle steps r_j, up
    to the spline error (5/384) H^4 max|x''''| and the crossing-time error of the Hermite
    angle, H^4 max|theta''''| / 384 / omega_min, times max|x'|."""
    time = np.arange(int(3.0 * SAMPLE_RATE) + 1) / SAMPLE_RATE
    n0, slope, ripple, ripple_hz = 2.0, 1.5, 0.4, 3.0  # rev/s, rev/s^2, rev/s, Hz
    w = 2 * np.pi * ripple_hz
    speed = n0 + slope * time + ripple * np.sin(w * time)
    angle = n0 * time + 0.5 * slope * time**2 + ripple * (1 - np.cos(w * time)) / w
    order = 11.0
    run = _run(time, speed, {"x": np.cos(2 * np.pi * order * angle)}, angle_rev=angle)
    plan = plan_order_tracking(run, "carrier", "x", min_speed_rpm=60.0)
    assert plan.reference.source.startswith("angle channel")
    resampled = resample_to_angle(plan, run)
    error = np.max(np.abs(resampled.values - np.cos(2 * np.pi * order * resampled.revolution)))
    # derivatives of phi = 2 pi k r(t) (r'' = slope + ripple w cos, ...), bounded termwise
    k = 2 * np.pi * order
    d1 = k * np.max(speed)
    d2 = k * (slope + ripple * w)
    d3, d4 = k * ripple * w**2, k * ripple * w**3
    # |d^4 cos(phi)| by Faa di Bruno: phi'^4 + 6 phi'^2 phi'' + 3 phi''^2 + 4 phi' phi''' + phi''''
    fourth = d1**4 + 6 * d1**2 * d2 + 3 * d2**2 + 4 * d1 * d3 + d4
    step = 1 / SAMPLE_RATE
    omega_min = 2 * np.pi * np.min(speed[plan.start : plan.stop])
    theta_fourth = 2 * np.pi * ripple * w**3  # |theta''''| = |omega'''|
    bound = 5 / 384 * step**4 * fourth + d1 * step**4 * theta_fourth / (384 * omega_min)
    assert error <= bound  # measured 3.9e-7 against a bound of 2.0e-6
    assert bound < 1e-5


def test_trapezoid_angle_error_is_the_euler_maclaurin_term():
    """Without an angle channel the angle is the trapezoid integral of the speed, which
    exceeds the exact angle by (H^2/12)(n'(t) - n'(0)) + O(H^4) revolutions at time t
    (Euler-Maclaurin)."""
    time = np.arange(int(3.0 * SAMPLE_RATE) + 1) / SAMPLE_RATE
    n0, slope, ripple, ripple_hz = 2.0, 1.5, 0.4, 3.0  # rev/s, rev/s^2, rev/s, Hz
    w = 2 * np.pi * ripple_hz
    speed = n0 + slope * time + ripple * np.sin(w * time)
    angle = n0 * time + 0.5 * slope * time**2 + ripple * (1 - np.cos(w * time)) / w
    reference = reference_angle(_run(time, speed, {}), "carrier")
    error = reference.angle / (2 * np.pi) - angle
    step = 1 / SAMPLE_RATE
    # n' = slope + ripple w cos(w t)
    leading = step**2 / 12 * ripple * w * (np.cos(w * time) - 1.0)
    # the O(H^4) rest: H^4/720 |n'''(t) - n'''(0)| <= 2 ripple w^3 H^4/720 = 3e-15 rev
    assert np.max(np.abs(error - leading)) < 1e-12
    # the largest error, 7.5e-8 rev, where cos(w t) = -1
    assert np.max(np.abs(error)) == pytest.approx(step**2 / 12 * 2 * ripple * w, rel=1e-3)


def test_refused_requests_name_the_parameter():
    time, speed, angle = _ramp()
    run = _run(time, speed, {"chirp": np.cos(2 * np.pi * ORDER * angle)})
    with pytest.raises(SignalError, match=r"max_order \(--max-order\).*f_s / \(2 n_max\)"):
        plan_order_tracking(run, "carrier", "chirp", max_order=300.0)  # resolvable: 205
    with pytest.raises(SignalError, match="samples_per_rev.*never coarser"):
        plan_order_tracking(run, "carrier", "chirp", samples_per_rev=1000)  # needs 4096
    with pytest.raises(SignalError, match="--orders 'sun' is not a member"):
        plan_order_tracking(run, "sun", "chirp")
    with pytest.raises(SignalError, match="tracked_orders: order 250"):
        plan_order_tracking(run, "carrier", "chirp", tracked_orders=[250.0])
    spoiled = run.copy(deep=True)
    spoiled["chirp"][len(time) // 2] = np.nan
    with pytest.raises(SignalError, match="--channel: 'chirp' holds NaN"):
        plan_order_tracking(spoiled, "carrier", "chirp")
    # a reference that turns back: no single running sense
    turning = _run(time, 5.0 * np.cos(np.pi * time / DURATION), {"chirp": np.cos(time)})
    with pytest.raises(SignalError, match="stops or reverses"):
        plan_order_tracking(turning, "carrier", "chirp")


def test_a_negative_running_sense_gives_the_same_orders():
    """A mirrored run (negative drive) turns the reference the other way: the same
    orders and amplitudes."""
    time, speed, angle = _ramp()
    forward = _run(time, speed, {"chirp": np.cos(2 * np.pi * ORDER * angle)})
    mirrored = _run(time, -speed, {"chirp": np.cos(2 * np.pi * ORDER * angle)})
    assert reference_angle(mirrored, "carrier").sense == -1
    a, b = (
        order_summary(track_orders(r, plan_order_tracking(r, "carrier", "chirp")), 1)["orders"][0]
        for r in (forward, mirrored)
    )
    assert b["order"] == pytest.approx(a["order"], rel=1e-12)
    assert b["amplitude"] == pytest.approx(a["amplitude"], rel=1e-9)


# --- the study case ----------------------------------------------------------------------

RUN_DURATION = 1.5  # s: past t_s = 0.156 s, 2.8 carrier revolutions at about 120 rpm
SHORT_CASE = f"""
import dataclasses

from pygear import Probe, load_case

base = load_case({str(STUDY)!r})
runup = base.scene("runup")
settings = dataclasses.replace(
    runup.transient,
    duration={RUN_DURATION},
    mean_window=0.5,
    probes=runup.transient.probes + (Probe("displacement", "planetary.carrier.theta_z"),),
)
case = dataclasses.replace(
    base,
    name="short_runup",
    scenes=(dataclasses.replace(runup, name="short", analyses=("transient",),
                                transient=settings),),
)
"""


@pytest.fixture(scope="module")
def run_file(tmp_path_factory) -> Path:
    """A 1.5 s run-up of the study case that also records the carrier's angle."""
    case = tmp_path_factory.mktemp("orders_case")
    (case / "case.py").write_text(SHORT_CASE)
    out = tmp_path_factory.mktemp("orders_run")
    assert main(["run", str(case), "--out", str(out), "--json"]) == 0
    return out / "short.nc"


@pytest.fixture(scope="module")
def run(run_file) -> xr.Dataset:
    with open_dataset(run_file) as opened:
        return opened.load()


def test_integrated_speed_is_the_kernel_angle(run):
    """Average-acceleration Newmark updates q by h (v_n + v_n+1)/2: the trapezoid integral
    of the speed channel is the carrier's theta_z displacement, to round-off."""
    from_speed = reference_angle(run.drop_vars("rotation_displacement"), "carrier")
    recorded = run.rotation_displacement.sel(rotation_dof="planetary.carrier.theta_z").values
    assert from_speed.source.startswith("trapezoid")
    # 6e4 additions of steps near 1e-3 rad to angles up to 18 rad: round-off <= 6e4 x
    # 2.2e-16 x 18 = 2.4e-10 rad (measured 1.4e-13)
    assert np.max(np.abs(from_speed.angle - (recorded - recorded[0]))) < 1e-9


def test_mesh_orders_are_the_tooth_numbers(study_case, run):
    """Relative to the carrier (ring held) the planetary mesh order is Z_r; relative to
    the sun, Z_r / (1 + r_br/r_bs) (Willis, ring held); relative to a planet's spin on
    the carrier, Z_r r_bp / r_br."""
    scene = study_case.scene("runup")
    model = assemble(study_case.for_scene(scene), scene)
    stage = study_case.gearbox.stages[0]
    ring, sun, planet = stage.ring.base_radius, stage.sun.base_radius, stage.planet.base_radius
    expected = {
        "planetary.carrier": RING_TEETH,
        "planetary.sun": RING_TEETH / (1 + ring / sun),
        "planetary.planet1": RING_TEETH * planet / ring,
    }
    for member, order in expected.items():
        kinematic = mesh_orders(study_case, model, member)["planetary"]
        assert kinematic == pytest.approx(order, rel=1e-9)  # rigid-body mode: round-off
        # from the file: equilibrium speeds of an elastic run (measured 2e-8 from rigid)
        assert stored_mesh_orders(run, member)["planetary"] == pytest.approx(order, rel=1e-6)
    # each mesh: the sun turns at n_c (1 + r_br/r_bs) (Willis, ring held), so its meshes
    # cycle at Z_s (r_br/r_bs) carrier orders: 95.93 against Z_r = 96, since Table 1's
    # radii give r_br/r_bs = 3.5530 and its tooth numbers Z_r/Z_s = 3.5556
    per_mesh = mesh_orders(study_case, model, "planetary.carrier", per_mesh=True)
    assert per_mesh == pytest.approx(
        {"planetary.sun-planet": stage.sun.teeth * ring / sun, "planetary.ring-planet": 96.0},
        rel=1e-9,
    )


def test_analyze_orders_json_and_files(run_file, tmp_path, capsys):
    out = tmp_path / "orders"
    argv = ["analyze", str(run_file), "--orders", "planetary.carrier", "--json"]
    argv += ["--channel", "planetary.sun.theta_z", "--max-order", "150"]  # the label alone
    assert main([*argv, "--out", str(out)]) == 0
    result = json.loads(capsys.readouterr().out)
    for key in ("reference", "channel", "max_order", "orders", "mesh_orders", "files"):
        assert key in result
    assert result["reference"] == "planetary.carrier"
    assert result["channel"] == "acceleration:planetary.sun.theta_z"
    assert result["max_order"] == 150.0
    assert result["mesh_orders"]["planetary"] == pytest.approx(RING_TEETH, rel=1e-6)
    # the sun's rotational acceleration carries the mesh order: a peak within one order
    # bin of Z_r (2.8 revolutions: bins of 0.36 orders)
    near = [p for p in result["orders"] if abs(p["order"] - RING_TEETH) <= 1.0]
    assert near, result["orders"]
    assert all(Path(f).is_file() for f in result["files"])
    assert sorted(p.name for p in out.iterdir()) == sorted(Path(f).name for f in result["files"])
    with xr.open_dataset(out / "orders.nc") as orders:
        spectrum = orders["order_amplitude"]
        floor = float(np.median(spectrum.sel(order=slice(50, 150)).values))
        # it stands out of the run-up's broadband floor (measured 0.29 against 0.03)
        assert near[0]["amplitude"] > 5 * floor
        for name, variable in {**orders.data_vars, **orders.coords}.items():
            assert "long_name" in variable.attrs, name
            assert "units" in variable.attrs or variable.dtype.kind in "OUS", name  # text
        assert orders["tracked_order"].values == pytest.approx([RING_TEETH], rel=1e-6)
        assert orders["order_map_amplitude"].sizes["window"] >= 3
        assert orders.attrs["angle_source"].startswith("angle channel")


@pytest.mark.parametrize(
    ("extra", "rule"),
    [
        (["--orders", "planetary.bogus"], "is not a member"),
        (["--orders", "ring"], "is not a member"),  # no speed or angle channel kept
        (["--orders", "carrier", "--channel", "missing"], "--channel: 'missing'"),
        (["--orders", "carrier", "--window-revolutions", "2"], "turns through only"),
        (["--orders", "carrier", "--max-order", "1e6"], "--max-order"),
        (["--orders", "carrier", "--after", "9"], "--after"),
        (["--orders", "carrier", "--out", "x.nc"], "is a directory"),
    ],
)
def test_analyze_orders_refuses_bad_input(run_file, tmp_path, monkeypatch, capsys, extra, rule):
    monkeypatch.chdir(tmp_path)
    assert main(["analyze", str(run_file), *extra]) == 2
    error = capsys.readouterr().err.strip()
    assert rule in error and "\n" not in error
    assert not run_file.with_name(f"{run_file.stem}_orders").exists()  # before any work
    assert not (tmp_path / "x.nc").exists()


def test_analyze_orders_never_runs_code(run_file, tmp_path, capsys):
    """A run file naming a case directory is tracked without executing its case.py."""
    marker = tmp_path / "executed.txt"
    case = tmp_path / "hostile"
    case.mkdir()
    (case / "case.py").write_text(f"from pathlib import Path\nPath({str(marker)!r}).touch()\n")
    with xr.open_dataset(run_file) as opened:
        copied = opened.load()
    copied.attrs["case"] = str(case)
    copied.to_netcdf(tmp_path / "run.nc")
    argv = ["analyze", str(tmp_path / "run.nc"), "--orders", "carrier", "--max-order", "150"]
    assert main([*argv, "--json"]) == 0
    assert not marker.exists()
    assert json.loads(capsys.readouterr().out)["files"][0].endswith("run_orders/orders.nc")
    with xr.open_dataset(tmp_path / "run_orders" / "orders.nc") as orders:
        assert orders.attrs["max_order"] == 150.0
