"""Missing and cracked teeth in the study case and the gearbox (issue: hard cases).

A defective tooth weakens every tooth pair it is part of once per passage, so the
response is modulated at the defect's passing frequency, derived here from the run's
own equilibrium speeds: N (n_s - n_c)/60 for a sun tooth meeting N planets, n/60 for a
tooth of a gear on a fixed axis.  The runs must complete (no NaN) and the envelope
spectrum must show that frequency family well above the healthy run's.
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pygear import ToothDefect, load_case
from pygear.analysis.contact.mesh_stiffness import ContactLossWarning
from pygear.analysis.signals.channels import channel_series
from pygear.analysis.signals.signal import envelope_spectrum
from pygear.analysis.time.transient import member_speeds, run_transient

CASES = Path(__file__).resolve().parent.parent / "cases"
DURATION = 2.5  # s: t_s, settling, and 1.5 s of steady running after the 1 s start-up
HARMONICS = 5  # passing-frequency harmonics summed

Speeds = dict[str, float]
DEFECT_CASES: dict[str, tuple[str, str, str, str, Callable[[Speeds], float]]] = {
    # name: case, scene, gear, channel, passing frequency [Hz] from the speeds [rpm]
    "study sun": (
        "yang2016_planetary",
        "runup",
        "planetary.sun",
        "acceleration:planetary.sun.theta_z",
        lambda s: 3 * (s["sun"] - s["carrier"]) / 60,
    ),
    "gearbox stage 1 sun": (
        "yang2016_gearbox",
        "runup_tv",
        "stage1.sun",
        "acceleration:stage1.ring.y",
        lambda s: 4 * (s["stage1.sun"] - s["stage1.carrier"]) / 60,
    ),
    "gearbox parallel input": (
        "yang2016_gearbox",
        "runup_tv",
        "parallel.input_gear",
        "acceleration:parallel.output_gear.theta_z",
        lambda s: abs(s["parallel.input_gear"]) / 60,
    ),
}


def _run(name: str, factor: float | None) -> tuple[xr.Dataset, float]:
    """The run with tooth 0 of the gear at ``factor`` (None: healthy) and its passing
    frequency."""
    case_name, scene_name, gear, _, passing = DEFECT_CASES[name]
    case = load_case(CASES / case_name)
    scene = case.scene(scene_name)
    defects = () if factor is None else (ToothDefect(gear, 0, factor),)
    scene = dataclasses.replace(
        scene,
        analyses=("transient",),
        defects=defects,
        transient=dataclasses.replace(scene.transient, duration=DURATION),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ContactLossWarning)  # a missing tooth loses contact
        run = run_transient(case, scene)
    speeds = member_speeds(run)
    return run, passing(speeds)


def _family_amplitude(run: xr.Dataset, channel: str, frequency: float) -> float:
    """Sum over harmonics 1..5 of the envelope spectrum's largest value within two bins."""
    envelope = envelope_spectrum(channel_series(run, channel), after=1.0)
    bins = envelope.frequency.values
    total = 0.0
    for harmonic in range(1, HARMONICS + 1):
        centre = int(np.argmin(np.abs(bins - harmonic * frequency)))
        total += float(envelope.values[max(centre - 2, 0) : centre + 3].max())
    return total


@pytest.fixture(scope="module", params=list(DEFECT_CASES))
def defect_runs(request) -> dict:
    name = request.param
    runs = {label: _run(name, factor) for label, factor in (("healthy", None), ("cracked", 0.5))}
    runs["missing"] = _run(name, 0.0)
    return {"name": name, "channel": DEFECT_CASES[name][3], **runs}


def test_defective_runs_complete(defect_runs):
    for label in ("cracked", "missing"):
        run, _ = defect_runs[label]
        assert int(run.attrs["steps"]) == round(DURATION / run.attrs["time_step"])
        for name, values in run.data_vars.items():
            assert np.all(np.isfinite(values.values)), (label, name)


def test_missing_tooth_shows_at_its_passing_frequency(defect_runs):
    """Missing tooth: the passing-frequency family is at least 10 times the healthy
    run's, and the envelope's largest peak from 2 Hz to 6.5 passing frequencies is one
    of its harmonics."""
    channel = defect_runs["channel"]
    healthy, frequency = defect_runs["healthy"]
    missing, missing_frequency = defect_runs["missing"]
    assert missing_frequency == pytest.approx(frequency, rel=0.01)
    ratio = _family_amplitude(missing, channel, frequency) / _family_amplitude(
        healthy, channel, frequency
    )
    assert ratio > 10.0, ratio
    envelope = envelope_spectrum(channel_series(missing, channel), after=1.0)
    window = (envelope.frequency > 2.0) & (envelope.frequency < 6.5 * frequency)
    low = envelope.where(window, 0.0).values
    peak = float(envelope.frequency[int(np.argmax(low))])
    order = peak / frequency
    bin_width = float(envelope.frequency[1] - envelope.frequency[0])
    assert abs(order - round(order)) * frequency <= 2 * bin_width, (peak, frequency)


def test_cracked_tooth_shows_at_its_passing_frequency(defect_runs):
    """Cracked tooth (half its stiffness): the family stands out above the healthy run
    (measured 1.55x for the study case's sun, 2.1x and 6.6x in the gearbox)."""
    channel = defect_runs["channel"]
    healthy, frequency = defect_runs["healthy"]
    cracked, _ = defect_runs["cracked"]
    ratio = _family_amplitude(cracked, channel, frequency) / _family_amplitude(
        healthy, channel, frequency
    )
    assert ratio > 1.3, ratio
