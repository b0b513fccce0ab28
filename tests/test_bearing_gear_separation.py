"""A gear fault and a bearing fault in one kernel run, separated by cepstral
pre-whitening (Sawalhi & Randall 2011; Randall & Antoni 2011, sec. 3).

The sequentially phased planetary stage's ``sun_crack`` scene (a root crack on the
sun) with a roller bearing on every planet pin and the ``rolling_bearing_contact``
effect; planet 1's pin carries a 20 um spall at the load.  The ring sensor hears the
meshes, the cracked sun and the bearing.  The pin and the load stand still in the
carrier frame, so the rollers pass the spall, and the load, at
BPFI = (Z/2) f_o (1 + d/D) (Harris & Kotzalas 2007, ch. 8), f_o the planet's spin
relative to the carrier (measured by the run's speed probe): a healthy pin's varying
compliance and the spall's impacts share that frequency.  Pre-whitening flattens the
periodic part (meshes, varying compliance) and keeps the impacts."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from pygear import Probe
from pygear.analysis.condition.bearing_envelope import bearing_envelope_analysis
from pygear.analysis.time.transient import run_transient
from pygear.cli import main
from pygear.model.case import load_case
from pygear.model.rolling_bearing import BearingDefect, RollingBearing
from pygear.runs.outputs import bearing_references

PIN = RollingBearing(
    "PB", "roller", elements=11, pitch_diameter=0.05, element_diameter=0.0065,
    roller_length=0.008, diametral_clearance=5e-6, location="planetary.planet",
)  # fmt: skip
"""A pin bearing sized for the test: its BPFI (35.5 Hz) keeps 1 % from the stage's own
lines (carrier, planet and sun rates and their harmonics at 120 rpm)."""
SPALL = BearingDefect("inner", width=2e-3, depth=20e-6, angle_deg=90.0, planet=1)


def kernel_run(spalled: bool):
    """The scene's run with the pins as Hertz contacts (and the case it ran)."""
    base = load_case("sequential_planetary")
    bearing = dataclasses.replace(PIN, defects=(SPALL,) if spalled else ())
    case = dataclasses.replace(base, rolling_bearings=(bearing,))
    scene = case.scene("sun_crack")
    probes = (*scene.transient.probes, Probe("speed", "planetary.planet1"))
    scene = dataclasses.replace(
        scene,
        effects=(*scene.effects, "rolling_bearing_contact"),
        transient=dataclasses.replace(scene.transient, probes=probes),
    )
    return run_transient(case, scene), case


def sensor_record(run):
    """The ring sensor after 0.5 s, its sample rate and the pin's BPFI."""
    run = run.sel(time=slice(0.5, None))
    spin_hz = abs(float(run.speed.sel(member="planetary.planet1").mean())) / 60.0
    bpfi = 0.5 * PIN.elements * spin_hz * (1 + PIN.element_diameter / PIN.pitch_diameter)
    rate = 1.0 / float(run.time[1] - run.time[0])
    return run.sensor_acceleration.values.ravel(), rate, bpfi


@pytest.fixture(scope="module")
def runs():
    return {spalled: kernel_run(spalled) for spalled in (True, False)}


@pytest.fixture(scope="module")
def records(runs):
    return {spalled: sensor_record(run) for spalled, (run, _) in runs.items()}


def test_prewhitening_finds_the_pin_spall_beside_the_cracked_sun(records):
    """Whitened: BPFI and two harmonics, 10 dB over the envelope spectrum's median, at
    the closed form to a bin."""
    signal, rate, bpfi = records[True]
    _, found = bearing_envelope_analysis(signal, rate, {"BPFI": bpfi})
    assert bool(found.detected.sel(line="BPFI"))
    line = found.sel(line="BPFI", sideband=0)
    for harmonic in (1, 2, 3):
        frequency = float(line.found_frequency.sel(harmonic=harmonic))
        assert abs(frequency - harmonic * bpfi) <= found.attrs["bin_width"]
        assert float(line.snr.sel(harmonic=harmonic)) > 10.0


def test_prewhitening_removes_the_healthy_pins_varying_compliance(records):
    """Healthy pins, cracked sun: the varying compliance stands at BPFI far over the
    raw envelope spectrum (a false alarm without whitening); whitened, nothing is
    detected there."""
    signal, rate, bpfi = records[False]
    _, raw = bearing_envelope_analysis(signal, rate, {"BPFI": bpfi}, whiten=False)
    _, white = bearing_envelope_analysis(signal, rate, {"BPFI": bpfi})
    assert float(raw.snr_fundamental.sel(line="BPFI")) > 30.0
    assert not bool(white.detected.sel(line="BPFI"))
    assert float(white.snr_fundamental.sel(line="BPFI")) < 10.0
    assert np.isfinite(signal).all()


def test_analyze_bearing_envelope_finds_the_spall_in_the_run_file(runs, records, tmp_path, capsys):
    """``pygear analyze RUN.nc --bearing-envelope`` on the run file (with the bearing
    frequencies ``pygear run`` stores): the pin's BPFI detected at the closed form (to
    0.1 %: the stored one is at the equilibrium speed of the run's last second), its
    BPFO not."""
    run, case = runs[True]
    path = tmp_path / "run.nc"
    run.merge(bearing_references(case, run)).to_netcdf(path)
    assert main(["analyze", str(path), "--bearing-envelope", "--json"]) == 0
    lines = {line["line"]: line for line in json.loads(capsys.readouterr().out)["lines"]}
    bpfi = lines["PB:BPFI"]
    assert bpfi["detected"]
    assert bpfi["expected_hz"] == pytest.approx(records[True][2], rel=1e-3)
    assert abs(bpfi["harmonics"][0]["found_hz"] - bpfi["expected_hz"]) <= 0.02 * bpfi["expected_hz"]
    assert not lines["PB:BPFO"]["detected"]
