"""The synchronous average over whole revolutions of an angle, its input checks, and
a tachometer's pulses and the angle rebuilt from them (the arrays behind
:mod:`.synchronous_average`, which describes the method and its conventions).

The checks (``check_*``), :func:`step_crossings`, :func:`bin_sums` and
:func:`check_bins` are shared with the planet and sun averages of
:mod:`.synchronous_average`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

from ..signals.angle_resampling import crossing_times, hermite_values, local_cubic, monotone_slopes
from ..signals.signal import SignalError

__all__ = [
    "AngleAverage",
    "angle_from_tachometer",
    "synthetic_tachometer",
    "weighted_angle_average",
]

TWO_PI = 2.0 * math.pi
WINDOW_SHAPES = ("hann", "rectangular")
"""Planet window shapes: raised cosine, and McFadden's (1991) rectangular window."""
MIN_SAMPLES = 4
"""Fewest time samples: the cubic through four samples needs four."""
EMPTY_BIN = 1e-12
"""A bin whose weight sum is at most this share of the largest bin's counts as empty."""
_BIN_SLACK = 1e-9
"""Angle steps of rounding allowed when the record's first and last steps are counted."""


class AngleAverage(NamedTuple):
    """A synchronous average and what went into it.

    Attributes
    ----------
    average : numpy.ndarray
        The average at the M angle steps j P / M, j = 0 .. M-1.
    revolutions : int
        Whole revolutions (periods P) averaged; for the sun, summed over the planets.
    weight_sum : numpy.ndarray
        The sum of the weights in each step (R without weights).
    """

    average: np.ndarray
    revolutions: int
    weight_sum: np.ndarray


# --------------------------------------------------------------------------- input checks


def check_number(value: Any, name: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise SignalError(f"{name}: must be a real number, got {value!r}") from None
    if not math.isfinite(number):
        raise SignalError(f"{name}: must be finite, got {value!r}")
    return number


def check_whole_number(value: Any, name: str, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise SignalError(f"{name}: must be a whole number >= {minimum}, got {value!r}")
    return int(value)


def check_array(values: Any, name: str, size: int | None = None) -> np.ndarray:
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise SignalError(f"{name}: must be an array of real numbers") from None
    if array.ndim != 1:
        raise SignalError(f"{name}: must be one-dimensional, got shape {array.shape}")
    if size is not None and array.size != size:
        raise SignalError(f"{name}: must have one value per time sample ({size}), got {array.size}")
    if not np.all(np.isfinite(array)):
        raise SignalError(f"{name}: holds NaN or inf")
    return array


def check_time(time: Any, name: str = "time") -> np.ndarray:
    time = check_array(time, name)
    if time.size < MIN_SAMPLES:
        raise SignalError(f"{name}: needs at least {MIN_SAMPLES} samples, got {time.size}")
    if not np.all(np.diff(time) > 0.0):
        raise SignalError(f"{name}: must increase strictly [s]")
    return time


def check_increasing(values: Any, name: str, size: int) -> np.ndarray:
    angle = check_array(values, name, size)
    if not np.all(np.diff(angle) > 0.0):
        raise SignalError(
            f"{name}: must increase strictly with time (angles run in the member's running "
            "direction: negate one that decreases)"
        )
    return angle


def angle_slopes(speed: Any, name: str, time: np.ndarray, angle: np.ndarray) -> np.ndarray:
    if speed is None:
        return monotone_slopes(time, angle)
    slopes = check_array(speed, name, time.size)
    if not np.all(slopes > 0.0):
        raise SignalError(f"{name}: must be > 0 (d angle / dt of an increasing angle) [rad/s]")
    return slopes


def check_window(width_rad: Any, shape: Any) -> float:
    width = check_number(width_rad, "width_rad")
    if not 0.0 < width <= TWO_PI:
        raise SignalError(f"width_rad: must lie in (0, 2 pi] [rad], got {width_rad!r}")
    if shape not in WINDOW_SHAPES:
        raise SignalError(f"shape: must be one of {', '.join(WINDOW_SHAPES)}, got {shape!r}")
    return width


# --------------------------------------------------------------------------- the average


def step_crossings(
    time: np.ndarray,
    angle: np.ndarray,
    slopes: np.ndarray,
    samples_per_revolution: int,
    period: float,
    offset: float = 0.0,
    name: str = "angle",
) -> tuple[np.ndarray, np.ndarray, int]:
    """Crossing times of ``angle - offset`` through the steps of R whole revolutions.

    Returns the crossing times, the bin of each (its step modulo M) and R.  The first
    step is the first one at or after the record's start, so the R M steps fill every
    bin R times whatever step the record starts on.
    """
    step = period / samples_per_revolution
    first = math.ceil((angle[0] - offset) / step - _BIN_SLACK)
    last = math.floor((angle[-1] - offset) / step + _BIN_SLACK)
    revolutions = (last - first + 1) // samples_per_revolution
    if revolutions < 1:
        span = float(angle[-1] - angle[0])
        raise SignalError(
            f"{name}: spans {span:.6g} rad, less than one angle period of {period:.6g} rad; "
            "the average needs at least one whole revolution"
        )
    index = first + np.arange(revolutions * samples_per_revolution)
    crossing = crossing_times(time, angle, slopes, index * step + offset)
    return crossing, np.mod(index, samples_per_revolution), revolutions


def bin_sums(
    parts: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]], samples_per_revolution: int
) -> tuple[np.ndarray, np.ndarray]:
    """Sum of w x and of w per bin over ``(bins, values, weights)`` parts."""
    weighted = np.zeros(samples_per_revolution)
    weight_sum = np.zeros(samples_per_revolution)
    for bins, values, weights in parts:
        weighted += np.bincount(bins, weights=weights * values, minlength=samples_per_revolution)
        weight_sum += np.bincount(bins, weights=weights, minlength=samples_per_revolution)
    return weighted, weight_sum


def check_bins(weight_sum: np.ndarray, period: float, name: str, remedy: str) -> None:
    empty = weight_sum <= EMPTY_BIN * float(np.max(weight_sum, initial=0.0))
    if np.any(empty):
        first = int(np.argmax(empty)) * period / weight_sum.size
        raise SignalError(
            f"{name}: the weight sum is zero in {int(np.count_nonzero(empty))} of "
            f"{weight_sum.size} angle steps (the first at {first:.6g} rad); {remedy}"
        )


def weighted_angle_average(
    signal: Any,
    time: Any,
    angle: Any,
    samples_per_revolution: int,
    weights: Any = None,
    angle_period: float = TWO_PI,
    *,
    speed: Any = None,
) -> AngleAverage:
    """Synchronous average of ``signal`` over whole revolutions of ``angle``.

    xbar_j = sum_r w_{r,j} x(t_{r,j}) / sum_r w_{r,j} at the angle steps j P / M, with
    the crossing times t_{r,j} of R whole revolutions (the method and its conventions:
    :mod:`.synchronous_average`).

    Parameters
    ----------
    signal : array_like
        The channel at ``time``.
    time : array_like
        Sample times [s], strictly increasing, at least 4.
    angle : array_like
        The shaft's angle at ``time`` [rad], strictly increasing.
    samples_per_revolution : int
        Angle steps M per period (>= 2).
    weights : array_like, optional
        Weights >= 0 at ``time``, read at the crossing times like the signal.
    angle_period : float
        The period P of the average [rad]: 2 pi for one revolution, a multiple of it for
        a hunting-tooth cycle.
    speed : array_like, optional
        d angle / dt at ``time`` [rad/s] (> 0); without it, the PCHIP slopes of
        ``angle``.

    Returns
    -------
    AngleAverage
        The average at the M steps, R, and each step's weight sum.

    Raises
    ------
    SignalError
        A bad input, less than one whole revolution, or a step with zero weight sum.
    """
    time = check_time(time)
    angle = check_increasing(angle, "angle", time.size)
    signal = check_array(signal, "signal", time.size)
    spr = check_whole_number(samples_per_revolution, "samples_per_revolution", 2)
    period = check_number(angle_period, "angle_period")
    if not period > 0.0:
        raise SignalError(f"angle_period: must be > 0 [rad], got {angle_period!r}")
    if weights is not None:
        weights = check_array(weights, "weights", time.size)
        if np.any(weights < 0.0):
            raise SignalError("weights: must be >= 0")
    slopes = angle_slopes(speed, "speed", time, angle)
    crossing, bins, revolutions = step_crossings(time, angle, slopes, spr, period)
    values = local_cubic(time, signal, crossing)
    if weights is None:
        weight = np.ones(crossing.size)
    else:
        weight = np.maximum(local_cubic(time, weights, crossing), 0.0)
    weighted, weight_sum = bin_sums([(bins, values, weight)], spr)
    check_bins(
        weight_sum, period, "weights", "record more revolutions so that weight reaches every step"
    )
    return AngleAverage(weighted / weight_sum, revolutions, weight_sum)


# --------------------------------------------------------------------------- tachometer


def synthetic_tachometer(
    time: Any,
    angle: Any,
    pulses_per_revolution: int,
    jitter: float = 0.0,
    seed: int | None = None,
    *,
    speed: Any = None,
) -> np.ndarray:
    """The pulse times of a tachometer with N marks on a shaft.

    A pulse at each time the shaft's angle passes a multiple of 2 pi / N (the crossing
    times of the cubic Hermite interpolant of ``angle``), plus independent Gaussian
    timing errors of standard deviation ``jitter``.  The first pulse is the first
    multiple of 2 pi / N at or after ``angle[0]``.

    Parameters
    ----------
    time : array_like
        Sample times [s], strictly increasing, at least 4.
    angle : array_like
        The shaft's unwrapped angle at ``time`` [rad], strictly increasing.
    pulses_per_revolution : int
        N marks per revolution (>= 1).
    jitter : float
        Standard deviation of the timing error [s] (>= 0).
    seed : int, optional
        Seed of the jitter's random generator (:func:`numpy.random.default_rng`).
    speed : array_like, optional
        d angle / dt at ``time`` [rad/s]; PCHIP slopes without it.

    Returns
    -------
    numpy.ndarray
        The pulse times [s], increasing.

    Raises
    ------
    SignalError
        A bad input, no pulse in the record, or a jitter that puts two pulses out of
        order (keep it well under the pulse spacing).
    """
    time = check_time(time)
    angle = check_increasing(angle, "angle", time.size)
    pulses = check_whole_number(pulses_per_revolution, "pulses_per_revolution", 1)
    jitter = check_number(jitter, "jitter")
    if jitter < 0.0:
        raise SignalError(f"jitter: must be >= 0 [s], got {jitter!r}")
    slopes = angle_slopes(speed, "speed", time, angle)
    step = TWO_PI / pulses
    first = math.ceil(angle[0] / step - _BIN_SLACK)
    last = math.floor(angle[-1] / step + _BIN_SLACK)
    if last < first:
        raise SignalError(f"angle: passes no multiple of 2 pi / {pulses} rad, so no pulse")
    pulse_times = crossing_times(time, angle, slopes, np.arange(first, last + 1) * step)
    if jitter > 0.0:
        pulse_times = pulse_times + np.random.default_rng(seed).normal(
            0.0, jitter, pulse_times.size
        )
        if np.any(np.diff(pulse_times) <= 0.0):
            raise SignalError(
                f"jitter: {jitter:.6g} s puts pulses out of order; keep it well under the "
                "pulse spacing (a few standard deviations)"
            )
    return pulse_times


def angle_from_tachometer(pulse_times: Any, pulses_per_revolution: int, time: Any) -> np.ndarray:
    """The shaft's angle at ``time`` rebuilt from tachometer pulses.

    The pulse count times 2 pi / N, interpolated by the monotone piecewise cubic
    Hermite interpolant (PCHIP; Fritsch & Carlson 1980): zero at the first pulse,
    2 pi i / N at pulse i, increasing in between.  The angle is only defined between
    the first and the last pulse: a time outside raises (no extrapolation).

    Parameters
    ----------
    pulse_times : array_like
        Pulse times [s], strictly increasing, at least 2.
    pulses_per_revolution : int
        N pulses per revolution (>= 1).
    time : array_like
        Times [s] within [pulse_times[0], pulse_times[-1]].

    Returns
    -------
    numpy.ndarray
        The angle [rad] at ``time``.

    Raises
    ------
    SignalError
        A bad input, or a time outside the pulses' span.
    """
    pulse_times = check_array(pulse_times, "pulse_times")
    if pulse_times.size < 2 or not np.all(np.diff(pulse_times) > 0.0):
        raise SignalError("pulse_times: needs at least 2 pulse times, strictly increasing [s]")
    pulses = check_whole_number(pulses_per_revolution, "pulses_per_revolution", 1)
    at = check_array(time, "time")
    outside = (at < pulse_times[0]) | (at > pulse_times[-1])
    if np.any(outside):
        raise SignalError(
            f"time: {int(np.count_nonzero(outside))} times lie outside the pulses' span "
            f"[{pulse_times[0]:.9g}, {pulse_times[-1]:.9g}] s, where the angle is undefined"
        )
    count_angle = np.arange(pulse_times.size) * (TWO_PI / pulses)
    slopes = monotone_slopes(pulse_times, count_angle)
    return hermite_values(pulse_times, count_angle, slopes, at)
