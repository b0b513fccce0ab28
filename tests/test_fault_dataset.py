"""Faults seen through the ring sensor: indicators against crack depth, a missing tooth
in the planet's average, the labelled dataset and the command line."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

from pygear.analysis.condition.gear_average import gear_average, gear_indicator_values
from pygear.analysis.condition.gear_indicators import difference_signal
from pygear.analysis.time.transient import run_transient
from pygear.cli.parser import main
from pygear.io import open_mfdataset
from pygear.model.case import load_case
from pygear.runs.fault_dataset import _grid, _record_case, plan_dataset, run_dataset

CASE = "sequential_planetary"
SENSOR = "sensor_acceleration:ring_sensor"  # the channel of a run
RECORD_SENSOR = "sensor_acceleration"  # a record's noisy series over time


@pytest.mark.parametrize("gear", ["planetary.sun", "planetary.planet1"])
def test_fm4_and_na4_rise_with_crack_depth(gear):
    """A deeper root crack softens its tooth more (Tian 2004), so the tooth's pass stands
    out more from the regular meshing in the gear's average: FM4 (Stewart 1977) and the
    NA4 trend (Zakrajsek et al. 1993) rise with every step of depth.  No noise."""
    plan = plan_dataset(
        CASE, "crack_depth=0:0.4:5", speeds="120", loads="500", gear=gear, duration=2.5
    )
    history, fm4, na4 = [], [], []
    for labels in _grid(plan):
        case, scene = _record_case(plan, labels)
        run = run_transient(case, scene)
        average = gear_average(run.sel(time=slice(0.5, None)), gear, SENSOR)
        values = gear_indicator_values(average, history=history)
        history.append(values)
        fm4.append(values["fm4"])
        na4.append(values["na4"])
    assert np.all(np.diff(fm4) > 0), fm4
    assert np.all(np.diff(na4) > 0), na4
    assert fm4[-1] > 1.5 * fm4[0] and na4[-1] > 1.5 * na4[0]  # clearly, not by round-off


def _tooth_rms(average: xr.DataArray) -> np.ndarray:
    """RMS of the difference signal over each tooth period of the average."""
    teeth = int(average.attrs["teeth"])
    difference = difference_signal(average.values, teeth)
    return np.sqrt(np.mean(difference.reshape(teeth, -1) ** 2, axis=1))


@pytest.fixture(scope="module")
def missing_tooth_runs():
    case = load_case(CASE)
    return {
        scene: run_transient(case, case.scene(scene)).sel(time=slice(0.5, None))
        for scene in ("planet_missing_tooth", "steady_sensor")
    }


def test_missing_planet_tooth_is_found_at_its_angle(missing_tooth_runs):
    """Planet 1's tooth 0 is gone.  At the reference state it is in the newest sun-planet
    pair (planet angle 0); a planet tooth reaches the ring (Z_p + 1)/2 = 17.5 tooth periods
    after the sun's pitch point (the two pitch points are half a turn apart and the ring
    loads the other flank, half a tooth on), and the ring's contact lasts eps_r = 1.63
    periods.  With the pitch points p <= eps from the start of contact, the ring sensor
    hears the gap within tooth periods [17.5 - 1.63, 17.5 + 2 x 1.63] = [15.9, 20.8]."""
    faulty, healthy = (
        _tooth_rms(gear_average(missing_tooth_runs[scene], "planet1", SENSOR))
        for scene in ("planet_missing_tooth", "steady_sensor")
    )
    assert 15 <= int(np.argmax(faulty)) <= 20, np.round(faulty / np.median(faulty), 2)
    assert faulty.max() > 3 * np.median(faulty)
    assert healthy.max() < 2 * np.median(healthy)  # a healthy planet shows no tooth


def test_tachometer_angles_find_the_tooth_and_jitter_blurs_it(missing_tooth_runs):
    """A once-per-turn carrier tachometer, with the sun's and planets' angles from the
    kinematics, finds the same tooth.  Timing jitter sigma_t smears the planet's angle by
    sigma = (Z_r/Z_p) Omega_c sigma_t and scales its order k by exp(-k^2 sigma^2 / 2)
    (Souders et al. 1990): at 200 us, sigma = 7.2e-3 rad keeps the mesh order 34 (0.97)
    but damps order 340, the gap's tenth mesh harmonic, to 0.05, so the gap's impulse
    spreads and FM4 falls well below its jitter-free value."""
    run = missing_tooth_runs["planet_missing_tooth"]
    average = gear_average(run, "planet1", SENSOR, tachometer=1)
    assert average.attrs["angles"].startswith("tachometer")
    assert 15 <= int(np.argmax(_tooth_rms(average))) <= 20
    sharp = gear_indicator_values(average)["fm4"]
    blurred = gear_average(run, "planet1", SENSOR, tachometer=1, jitter=200e-6, seed=3)
    assert gear_indicator_values(blurred)["fm4"] < 0.5 * sharp


@pytest.fixture(scope="module")
def dataset_dir(tmp_path_factory):
    """A 5-severity x 2-speed x 2-seed dataset (2 s per run) on two worker processes (the
    kernel's runs do not share one process's threads)."""
    out = tmp_path_factory.mktemp("dataset")
    plan = plan_dataset(
        CASE, "crack_depth=0:0.4:5", speeds="60,120", loads="500", seeds=2, duration=2.0
    )
    first = run_dataset(plan, out, workers=2, progress=False)
    return plan, out, first


def test_dataset_labels_match_its_inputs(dataset_dir):
    plan, out, data = dataset_dir
    assert data.attrs["records"] == 20 and data.attrs["records_failed"] == 0
    labels = set(zip(data.severity.values, data.speed_rpm.values, data.seed.values))
    grid = {
        (s, v, seed) for s in (0.0, 0.1, 0.2, 0.3, 0.4) for v in (60.0, 120.0) for seed in (0, 1)
    }
    assert labels == grid
    assert set(data.fault_kind.values) == {"crack_depth"} and set(data.load_nm.values) == {500.0}
    # the tachometer turns at the record's speed: one pulse per carrier turn
    for record in range(data.sizes["record"]):
        pulses = data.tachometer_pulse_time.isel(record=record).dropna("pulse").values
        speed = 60.0 / np.median(np.diff(pulses))
        assert speed == pytest.approx(float(data.speed_rpm[record]), rel=1e-3)
    # seeds differ in their noise only: same run, different sensor signal
    pair = data.where((data.severity == 0.2) & (data.speed_rpm == 120.0), drop=True)
    assert not np.allclose(pair[RECORD_SENSOR].isel(record=0), pair[RECORD_SENSOR].isel(record=1))
    np.testing.assert_array_equal(
        pair.tachometer_angle.isel(record=0), pair.tachometer_angle.isel(record=1)
    )
    assert (out / data.attrs["path"].split("/")[-1]).with_suffix(".md").is_file()


def test_dataset_na4_trend_is_the_running_average_of_zakrajsek(dataset_dir):
    """NA4 trend of record i: its residual's 4th moment over the squared mean residual
    variance of the records of its speed, load and seed up to its severity (Zakrajsek et
    al. 1993), recomputed here record by record; 1e-12 allows the round-off of a mean."""
    _, _, data = dataset_dir
    for i in range(data.sizes["record"]):
        record = data.isel(record=i)
        same = (
            (data.speed_rpm == record.speed_rpm)
            & (data.load_nm == record.load_nm)
            & (data.seed == record.seed)
            & (data.severity <= record.severity)
        )
        mean = float(data.residual_variance.where(same).mean())
        fourth = float(record.na4) * float(record.residual_variance) ** 2
        assert float(record.na4_trend) == pytest.approx(fourth / mean**2, rel=1e-12)
        if float(record.severity) == 0.0:
            assert float(record.na4_trend) == pytest.approx(float(record.na4), rel=1e-12)


def test_dataset_rerun_reuses_every_record(dataset_dir):
    plan, out, first = dataset_dir
    again = run_dataset(plan, out, workers=2, progress=False)
    assert again.attrs["records_reused"] == 20 and again.attrs["records_computed"] == 0
    np.testing.assert_array_equal(again.fm4.values, first.fm4.values)
    files = sorted(out.glob("record_*.nc"))
    assert len(files) == 20
    with open_mfdataset(files, concat_dim="record", join="outer") as records:
        assert records.sizes["record"] == 20


def test_analyze_tsa_prints_indicators_and_kurtogram(tmp_path, capsys):
    case = load_case(CASE)
    scene = case.scene("sun_crack")
    run = run_transient(case, scene)
    path = tmp_path / "sun_crack.nc"
    run.to_netcdf(path)
    argv = ["analyze", str(path), "--tsa", "sun", "--indicators", "--json", "--no-figures"]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["gear"] == "planetary.sun" and summary["revolutions"] > 10
    assert {"fm0", "fm4", "na4", "nb4", "m6a", "m8a"} <= set(summary["indicators"])
    best = summary["kurtogram"]
    assert 0 < best["centre_frequency_hz"] < run.attrs["sample_rate"] / 2
    assert math.isfinite(best["kurtosis"])
    assert (tmp_path / "sun_crack_tsa_planetary_sun.nc").is_file()


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--tsa", "moon"], ["--tsa 'moon'", "planetary.sun"]),
        (["--tsa", "sun", "--channel", "mesh_force:planetary.ring-planet1"], ["not a sensor"]),
        (["--indicators"], ["--tsa GEAR"]),
    ],
)
def test_analyze_tsa_refuses_bad_requests_in_one_line(tmp_path, capsys, argv, words):
    case = load_case(CASE)
    run = run_transient(case, case.scene("steady_sensor")).sel(time=slice(0, 1.0))
    path = tmp_path / "run.nc"
    run.to_netcdf(path)
    assert main(["analyze", str(path), *argv]) == 2
    error = capsys.readouterr().err.strip()
    assert "\n" not in error and all(word in error for word in words), error


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--faults", "rust=0:1:3"], ["--faults", "crack_depth, stiffness_factor"]),
        (["--faults", "crack_depth=0:1.2:3"], ["[0, 1)"]),
        (["--faults", "crack_depth=0:0.4:3", "--speeds", "-60"], ["--speeds", "positive"]),
        (["--faults", "crack_depth=0:0.4:3", "--gear", "planetary.ring"], ["external gear"]),
        (["--faults", "stiffness_factor=0.5", "--tooth", "97"], ["tooth 97", "0 .. 28"]),
    ],
)
def test_dataset_refuses_bad_requests_before_any_run(tmp_path, capsys, argv, words):
    base = {"--speeds": "120", "--loads": "500"}
    for key, value in base.items():
        if key not in argv:
            argv = [*argv, key, value]
    assert main(["dataset", CASE, *argv, "--out", str(tmp_path / "d")]) == 2
    error = capsys.readouterr().err.strip()
    assert "\n" not in error and all(word in error for word in words), error
    assert not (tmp_path / "d").exists()
