"""Bearing defects in kernel runs, found by the envelope analysis of
``pygear analyze --bearing-envelope`` (:func:`bearing_envelope_analysis`: cepstral
pre-whitening, kurtogram band, squared envelope spectrum; Randall & Antoni 2011).

A shaft of 0.5 kg turns at 25 Hz in the CWRU 6205 under 2 kN; its acceleration plus
white measurement noise (10 m/s^2 RMS, seeded) is the signal.  A 1 mm wide, 2 um deep
spall on the stationary outer race or on the turning inner race is a depth the kernel
subtracts from every element passing it.  References are the closed forms
BPFO = (Z/2) f_r (1 - d cos(alpha) / D), BPFI = (Z/2) f_r (1 + d cos(alpha) / D)
(Harris & Kotzalas 2007, ch. 8; Randall & Antoni 2011, eqs. 1-4), not the code's own."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_bearing_kernel import SKF_6205, shaft_in_bearing

from pygear.analysis.condition.bearing_envelope import bearing_envelope_analysis
from pygear.kernel.newmark import KernelProbe

SHAFT_HZ = 25.0
TIME_STEP = 1e-5
DECIMATION = 2
GAMMA = SKF_6205.element_diameter / SKF_6205.pitch_diameter  # alpha = 0
BPFO = 0.5 * SKF_6205.elements * SHAFT_HZ * (1 - GAMMA)
BPFI = 0.5 * SKF_6205.elements * SHAFT_HZ * (1 + GAMMA)
RING = {"outer": 1, "inner": 2}


def run_signal(location: str | None) -> np.ndarray:
    """The shaft's x acceleration over 2.1 s after 0.1 s of start-up, plus the noise."""
    defects = ()
    if location is not None:
        d, pitch = SKF_6205.element_diameter, SKF_6205.pitch_diameter
        radius = 0.5 * (pitch + (d if location == "outer" else -d))
        defects = (((1, RING[location], 1), (0.0, 1e-3 / radius, 2e-6)),)
    solver = shaft_in_bearing(
        SKF_6205, 2e3, mass=0.5, damping_ratio=0.05, time_step=TIME_STEP, defects=defects
    )
    probe = KernelProbe("ax", "acceleration", np.array([1.0, 0.0, 0.0]))
    v0 = np.array([0.0, 0.0, 2 * math.pi * SHAFT_HZ])
    signal = solver.run(220_000, [probe], v0=v0, decimation=DECIMATION).samples[0, 10_000:]
    return signal + 10.0 * np.random.default_rng(1).standard_normal(signal.size)


@pytest.fixture(scope="module")
def detections() -> dict:
    rate = 1.0 / (DECIMATION * TIME_STEP)
    found = {}
    for location in ("outer", "inner", None):
        _, found[location] = bearing_envelope_analysis(
            run_signal(location), rate, {"BPFO": BPFO, "BPFI": BPFI},
            modulation={"BPFI": SHAFT_HZ},
        )  # fmt: skip
    return found


def test_outer_race_spall_gives_bpfo_and_harmonics(detections):
    """BPFO and its harmonics to the resolution (one bin, 0.5 Hz), 10 dB over the
    envelope spectrum's median and clearly above BPFI's level."""
    found = detections["outer"]
    assert bool(found.detected.sel(line="BPFO"))
    width = found.attrs["bin_width"]
    line = found.sel(line="BPFO", sideband=0)
    for harmonic in (1, 2, 3):
        frequency = float(line.found_frequency.sel(harmonic=harmonic))
        assert abs(frequency - harmonic * BPFO) <= width
    snr = found.snr_fundamental
    assert float(snr.sel(line="BPFO")) > float(snr.sel(line="BPFI")) + 6.0


def test_inner_race_spall_gives_bpfi_with_shaft_rate_sidebands(detections):
    """BPFI and harmonics to a bin, and the load zone's modulation: sidebands at
    BPFI +- the shaft rate found; BPFO not detected."""
    found = detections["inner"]
    assert bool(found.detected.sel(line="BPFI"))
    assert not bool(found.detected.sel(line="BPFO"))
    width = found.attrs["bin_width"]
    line = found.sel(line="BPFI")
    for harmonic in (1, 2, 3):
        frequency = float(line.found_frequency.sel(harmonic=harmonic, sideband=0))
        assert abs(frequency - harmonic * BPFI) <= width
    for side in (-1, 1):
        first = line.sel(harmonic=1, sideband=side)
        assert bool(first.found)
        assert abs(float(first.found_frequency) - (BPFI + side * SHAFT_HZ)) <= width


def test_healthy_bearing_shows_neither_line(detections):
    """The healthy bearing's varying compliance is smooth: under the same noise no
    defect line is detected (the control of the two tests above)."""
    found = detections[None]
    assert not bool(found.detected.sel(line="BPFO"))
    assert not bool(found.detected.sel(line="BPFI"))
