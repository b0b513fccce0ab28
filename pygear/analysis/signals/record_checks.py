"""The checks every ``pygear analyze`` path makes on a run's record before any work.

Plain ``analyze`` (spectra), ``--orders`` and ``--tsa`` all read one record of a run
file: a ``time`` coordinate in seconds from ``--after`` on.  Each path checks it here,
with the same rules and one-line messages that name the flag or the file:

* :func:`check_record_time` - samples exist, time is finite, strictly increasing and
  uniform (one step to within :data:`~.signal.UNIFORM_TOLERANCE`): a gap of 10 ms in a
  record sampled at 40 kHz moves a gear's NB4 from 4.24 to 6.36, and one of 0.5 s gives
  an FM4 of 695, which reads as a severe fault;
* :func:`check_after` - ``--after`` lies in the run and leaves enough samples;
* :func:`check_band` - ``--band`` lies inside (0, Nyquist) of the file;
* :func:`default_after` and :func:`default_band` - defaults that follow the file (its
  settling instant, its Nyquist frequency) instead of the study case's 1 s and 5-10 kHz.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import xarray as xr

from ...errors import CaseError
from .signal import MIN_SAMPLES, UNIFORM_TOLERANCE, fast_length

__all__ = [
    "check_after",
    "check_band",
    "check_record_time",
    "default_after",
    "default_band",
    "record_sample_rate",
]


def _time(run: xr.Dataset, source: str) -> np.ndarray:
    if "time" not in run.variables or run["time"].ndim != 1:
        raise CaseError(f"{source} holds no time coordinate: analyze reads series over time")
    time = np.asarray(run["time"].values)
    if not np.issubdtype(time.dtype, np.number) or np.iscomplexobj(time):
        raise CaseError(f"{source}: its time coordinate is not numeric seconds ({time.dtype})")
    return time.astype(float)


def check_record_time(
    run: xr.Dataset, source: str, after: float | None = None, *, samples: int = MIN_SAMPLES
) -> np.ndarray:
    """The times of ``run``'s record from ``after`` (``--after``) on, checked; raises
    :class:`~pygear.errors.CaseError` naming ``source`` (the file) or the flag, and the
    rule.

    The run must hold samples, its times be finite and strictly increasing; ``after``
    must lie in the run and leave ``samples`` samples (:func:`check_after`); and the
    record's steps must equal their mean to within :data:`~.signal.UNIFORM_TOLERANCE`
    (the rule the spectra apply): every analysis takes one sample rate.  A gap before
    ``after`` is no concern of the record's.
    """
    time = _time(run, source)
    if time.size == 0:
        raise CaseError(f"{source} holds no samples (its time dimension is empty)")
    if not np.all(np.isfinite(time)):
        bad = int(np.flatnonzero(~np.isfinite(time))[0])
        raise CaseError(f"{source}: time must be finite (sample {bad} is {time[bad]})")
    steps = np.diff(time)
    if np.any(steps <= 0):
        bad = int(np.flatnonzero(steps <= 0)[0])
        raise CaseError(
            f"{source}: time must increase strictly (sample {bad + 1} at {time[bad + 1]:g} s "
            f"follows {time[bad]:g} s)"
        )
    if after is not None:
        check_after(time, after, source, samples=samples)
    kept = time if after is None else time[time >= after]
    if kept.size < 2:
        return kept
    steps = np.diff(kept)
    mean = (kept[-1] - kept[0]) / (kept.size - 1)
    deviation = np.abs(steps - mean) / mean
    worst = int(np.argmax(deviation))
    if deviation[worst] > UNIFORM_TOLERANCE:
        where = "" if after is None else f" from --after {after:g} s"
        raise CaseError(
            f"{source}: time is not uniformly sampled{where} (a step of {steps[worst]:.6g} s "
            f"at t = {kept[worst]:.6g} s, mean step {mean:.6g} s; the steps may differ by a "
            f"fraction {UNIFORM_TOLERANCE:g} at most): every analysis assumes one sample rate; "
            "resample the record, or start after the gap with --after"
        )
    return kept


def record_sample_rate(time: np.ndarray) -> float:
    """Samples per second of a checked, uniform record (its mean step)."""
    return (time.size - 1) / float(time[-1] - time[0])


def default_after(run: xr.Dataset, fallback: float) -> float:
    """The start-up to skip by default, from the file: ``fallback`` (the study case's
    habit: 1 s for spectra, 0.5 s for an average) but at most half the record, so a
    short run keeps its second half; and never less than the run's own settling instant
    ``t_s`` (the first instant its input speed reaches omega_0) when that lies in it."""
    time = _time(run, "RUN.nc")
    end = float(time[-1] - time[0]) if time.size else 0.0
    start = float(time[0]) if time.size else 0.0
    settled = start
    if "t_s" in run.variables and run["t_s"].size == 1:
        value = float(np.asarray(run["t_s"].values, dtype=float).reshape(-1)[0])
        if math.isfinite(value) and start <= value < start + end:
            settled = value
    return max(settled, start + min(float(fallback), end / 2.0))


def check_after(time: np.ndarray, after: float, source: str, *, samples: int = MIN_SAMPLES) -> None:
    """``--after`` must be finite, lie in the run and leave ``samples`` samples."""
    end = float(time[-1])
    if not (isinstance(after, (int, float)) and math.isfinite(after) and 0 <= after < end):
        raise CaseError(f"--after {after!r} s must lie within the run {source} (0 .. {end:g} s)")
    left = int(np.count_nonzero(time >= after))
    if left < samples:
        raise CaseError(
            f"--after {after:g} s leaves {left} samples of {source} (it ends at {end:g} s); "
            f"the analysis needs at least {samples}: start earlier"
        )


def default_band(sample_rate: float) -> tuple[float, float]:
    """The DRA band by default: a quarter to a half of the Nyquist frequency, the
    paper's 5-10 kHz at its 40 kHz sample rate."""
    nyquist = sample_rate / 2.0
    return nyquist / 4.0, nyquist / 2.0


def check_band(band: Sequence[float], sample_rate: float, samples: int, source: str) -> None:
    """``--band LOW HIGH`` must lie inside (0, Nyquist) of the record and span two bins."""
    lower, upper = (float(edge) for edge in band)
    nyquist = sample_rate / 2.0
    if not (math.isfinite(lower) and math.isfinite(upper)) or not 0 < lower < upper < nyquist:
        raise CaseError(
            f"--band {lower:g} {upper:g}: the band must satisfy 0 < LOW < HIGH < Nyquist = "
            f"{nyquist:g} Hz of {source} (sample rate {sample_rate:g} Hz)"
        )
    resolution = sample_rate / fast_length(samples)  # the spectra's record
    if upper - lower < 2 * resolution:
        raise CaseError(
            f"--band {lower:g} {upper:g}: narrower than two frequency bins of the record "
            f"({resolution:g} Hz each); widen it or start earlier with --after"
        )
