"""``pygear analyze RUN.nc --bearing-envelope``: a run file holding a synthetic outer-race
fault and the bearing frequencies ``pygear run`` stores beside the mesh frequencies."""

from __future__ import annotations

import json
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr
from scipy.signal import lfilter

from pygear.cli import main
from pygear.model.rolling_bearing import RollingBearing
from pygear.runs.outputs import bearing_references

RATE, DURATION, SHAFT_RPM = 20000.0, 2.5, 1500.0
# SKF 6205 geometry (CWRU): BPFO = 3.5848 x the shaft rate = 89.6 Hz at 1500 rpm
BEARING = RollingBearing("DE", "ball", elements=9, pitch_diameter=1.537 * 0.0254,
                         element_diameter=0.3126 * 0.0254, location="hss")  # fmt: skip


def _signal(fault_hz: float) -> np.ndarray:
    """Impulses at ``fault_hz`` (1 % jitter) ringing 4 kHz at 5 % damping, plus noise."""
    rng = np.random.default_rng(7)
    count = int(RATE * DURATION)
    times = np.arange(int(DURATION * fault_hz)) / fault_hz
    times = times + rng.normal(0, 0.01 / fault_hz, times.size)
    impulses = np.zeros(count)
    index = np.clip(np.round(times * RATE).astype(int), 0, count - 1)
    np.add.at(impulses, index, 1.0)
    omega, zeta, step = 2 * math.pi * 4000.0, 0.05, 1 / RATE
    r, damped = math.exp(-zeta * omega * step), omega * math.sqrt(1 - zeta**2) * step
    ringing = lfilter([0, r * math.sin(damped)], [1, -2 * r * math.cos(damped), r * r], impulses)
    return ringing / np.std(ringing) + 0.5 * rng.normal(size=count)


def _run(path: Path, *, stored: bool) -> Path:
    time = np.arange(int(RATE * DURATION)) / RATE
    run = xr.Dataset(
        {
            "housing_acceleration": ("time", _signal(3.5848 * SHAFT_RPM / 60), {"units": "m/s^2"}),
            "equilibrium_speed": ("body", [SHAFT_RPM], {"units": "rpm"}),
        },
        coords={"time": ("time", time, {"units": "s"}), "body": ("body", ["hss"])},
        attrs={"t_s": 0.5},
    )
    if stored:
        run = run.merge(bearing_references(SimpleNamespace(rolling_bearings=(BEARING,)), run))
    run.to_netcdf(path)
    return path


def test_run_file_stores_bearing_frequencies_of_a_case_with_rolling_bearings(tmp_path):
    path = _run(tmp_path / "run.nc", stored=True)
    with xr.open_dataset(path) as run:
        bpfo = float(run.bearing_frequency.sel(rolling_bearing="DE", bearing_line="BPFO"))
        # CWRU's published 3.5848 orders at 25 Hz, to its 5 digits
        assert bpfo == pytest.approx(3.5848 * 25.0, rel=3e-4)
        assert run.bearing_frequency.attrs["units"] == "Hz"
    # a case without rolling bearings adds nothing
    assert not bearing_references(SimpleNamespace(), xr.Dataset()).data_vars


def test_bearing_envelope_lists_the_stored_lines_with_snr(tmp_path, capsys):
    path = _run(tmp_path / "run.nc", stored=True)
    assert main(["analyze", str(path), "--bearing-envelope", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    lines = {row["line"]: row for row in result["lines"]}
    assert set(lines) == {"DE:BPFO", "DE:BPFI", "DE:BSF"}
    assert lines["DE:BPFO"]["detected"] and lines["DE:BPFO"]["snr_db"] > 10.0
    found = lines["DE:BPFO"]["harmonics"][0]["found_hz"]
    assert abs(found - 3.5848 * 25.0) <= result["bin_width_hz"] + 1e-9
    assert not lines["DE:BPFI"]["detected"] and not lines["DE:BSF"]["detected"]
    # the band the kurtogram picked holds the 4 kHz resonance
    assert result["band_hz"][0] <= 4000.0 <= result["band_hz"][1]
    # the inner-race line's shaft-rate sidebands were looked for
    assert [s["m"] for s in lines["DE:BPFI"]["sidebands"]] == [-1, 1]
    assert main(["analyze", str(path), "--bearing-envelope"]) == 0
    text = capsys.readouterr().out
    assert "DE:BPFO" in text and "yes" in text


@pytest.mark.parametrize("drs", [[], ["--drs"]])
def test_given_bpfo_serves_a_file_without_stored_frequencies(tmp_path, capsys, drs):
    path = _run(tmp_path / "run.nc", stored=False)
    argv = ["analyze", str(path), "--bearing-envelope", "--bpfo", str(3.5848 * 25.0), "--json"]
    assert main([*argv, *drs]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["discrete_random_separation"] == bool(drs)
    rows = result["lines"]
    assert rows[0]["line"] == "BPFO" and rows[0]["detected"]


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ([], "stores no bearing frequencies"),
        (["--bpfo", "-3"], "--bpfo must be a positive frequency in Hz"),
    ],
)
def test_bearing_envelope_refusals_are_one_line_exit_2(tmp_path, capsys, extra, message):
    path = _run(tmp_path / "run.nc", stored=False)
    assert main(["analyze", str(path), "--bearing-envelope", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1


@pytest.mark.parametrize("flag", [["--bpfo", "90"], ["--drs"]])
def test_bearing_flags_without_bearing_envelope_are_refused(tmp_path, capsys, flag):
    path = _run(tmp_path / "run.nc", stored=False)
    assert main(["analyze", str(path), *flag]) == 2
    assert "ask for the bearing envelope with --bearing-envelope" in capsys.readouterr().err


def test_analysis_references_of_a_real_case_carry_its_planet_bearings():
    from pygear.model.case import load_case
    from pygear.runs.outputs import analysis_references
    from pygear.runs.scene_runner import scene_model_for

    case = load_case("yang2016_planetary")
    _, model = scene_model_for(case, case.scenes[0])
    planet = RollingBearing("PL", "roller", elements=14, pitch_diameter=0.05,
                            element_diameter=0.006, roller_length=0.01,
                            location="planetary.planet")  # fmt: skip
    # the attribute the writer reads (rolling_bearings_of), on the case as loaded
    object.__setattr__(case, "rolling_bearings", (planet,))
    bodies = ["planetary.carrier", "planetary.ring", "planetary.sun", "planetary.planet1"]
    run = xr.Dataset(
        {"equilibrium_speed": ("body", [100.0, 0.0, 400.0, -300.0], {"units": "rpm"})},
        coords={"body": ("body", bodies)},
    )
    references = analysis_references(case, model, run)
    assert "mesh_frequency" in references and "natural_frequency" in references
    gamma = 0.006 / 0.05
    # the planet turns 300 rpm = 5 Hz on its pin, relative to the carrier (its theta_z)
    bpfo = float(references.bearing_frequency.sel(rolling_bearing="PL", bearing_line="BPFO"))
    assert bpfo == pytest.approx(14 / 2 * 5.0 * (1 - gamma), rel=1e-12)
    assert float(references.bearing_carrier_frequency.sel(rolling_bearing="PL")) == pytest.approx(
        100 / 60
    )


def test_a_run_whose_bearings_stand_still_is_refused_in_one_line(tmp_path, capsys):
    path = _run(tmp_path / "run.nc", stored=False)
    with xr.open_dataset(path) as opened:
        run = opened.load()
    run["equilibrium_speed"][:] = 0.0
    stored = run.merge(bearing_references(SimpleNamespace(rolling_bearings=(BEARING,)), run))
    stored.to_netcdf(tmp_path / "still.nc")
    assert main(["analyze", str(tmp_path / "still.nc"), "--bearing-envelope"]) == 2
    err = capsys.readouterr().err.strip()
    assert "none of its rolling bearings turns" in err and len(err.splitlines()) == 1


def test_rolling_bearing_frequencies_keep_clear_of_the_bearing_force_channels(tmp_path):
    """A run's bearing-force channels are over ``bearing`` (the springs); the rolling
    bearings' frequencies are over their own dimension, so a case with both writes."""
    path = _run(tmp_path / "run.nc", stored=False)
    with xr.open_dataset(path) as run:
        run = run.load()
    springs = ["stage1.planet1_bearing", "stage1.planet2_bearing", "stage1.planet3_bearing"]
    run = run.assign(
        bearing_force=(("time", "bearing"), np.zeros((run.sizes["time"], 3)), {"units": "N"})
    ).assign_coords(bearing=("bearing", springs))
    run = run.merge(bearing_references(SimpleNamespace(rolling_bearings=(BEARING,)), run))
    assert run.sizes["bearing"] == 3 and run.sizes["rolling_bearing"] == 1
    run.to_netcdf(tmp_path / "both.nc")
