"""Interpolation primitives for resampling a record at steps of a shaft's angle, shared
by computed order tracking (:mod:`.order_tracking`) and synchronous averaging
(:mod:`.synchronous_average`).

- :func:`crossing_times`: the times at which the cubic Hermite interpolant of
  angle(time), with the angular speed as slope, passes given angles (Newton's method).
  With exact slopes the interpolant's angle error is <= H^4 max|omega'''| / 384 for a
  sample step H.
- :func:`monotone_slopes`: slopes for that interpolant when only the samples are known,
  the piecewise cubic Hermite (PCHIP) derivatives of Fritsch & Carlson (1980) in the
  weighted harmonic-mean form of Fritsch & Butland (1984).  They keep the interpolant
  monotone between monotone samples; for smooth data they are second-order accurate, so
  the interpolant is third-order.
- :func:`hermite_values`: the cubic Hermite interpolant itself.
- :func:`local_cubic`: a channel at arbitrary times by the cubic through its four
  nearest samples (Lagrange), error <= max|x''''| |prod (t - t_i)| / 24, which is
  (9/16) H^4 max|x''''| / 24 at mid-interval on a uniform grid.

Arrays only (NumPy), no SciPy: the callers check their inputs.
"""

from __future__ import annotations

import numpy as np

from .signal import SignalError

__all__ = ["CROSSING_BLOCK", "crossing_times", "hermite_values", "local_cubic", "monotone_slopes"]

_NEWTON_ITERATIONS = 30
CROSSING_BLOCK = 1 << 16
"""Angle steps whose crossing times are solved together (bounds the temporaries)."""


def _block_crossing_times(
    time: np.ndarray, angle: np.ndarray, speed: np.ndarray, targets: np.ndarray
) -> np.ndarray:
    last = angle.size - 2
    interval = np.clip(np.searchsorted(angle, targets, side="right") - 1, 0, last)
    t0, step = time[interval], time[interval + 1] - time[interval]
    a0, a1 = angle[interval], angle[interval + 1]
    slope0, slope1 = speed[interval] * step, speed[interval + 1] * step
    s = np.clip((targets - a0) / (a1 - a0), 0.0, 1.0)  # the chord's crossing
    tolerance = 1e-14 * max(1.0, float(np.max(np.abs(angle))))
    for _ in range(_NEWTON_ITERATIONS):
        s2, s3 = s * s, s * s * s
        value = (
            a0 * (2 * s3 - 3 * s2 + 1)
            + slope0 * (s3 - 2 * s2 + s)
            + a1 * (3 * s2 - 2 * s3)
            + slope1 * (s3 - s2)
        )
        derivative = (
            (a0 - a1) * (6 * s2 - 6 * s) + slope0 * (3 * s2 - 4 * s + 1) + slope1 * (3 * s2 - 2 * s)
        )
        residual = value - targets
        pending = np.abs(residual) > tolerance
        if not np.any(pending):
            break
        if np.any(derivative[pending] <= 0.0):
            raise SignalError(
                "angle: not increasing between two samples (the speed and angle channels "
                "disagree); resampling at angle steps needs an increasing angle"
            )
        newton_step = np.where(pending, residual / np.where(pending, derivative, 1.0), 0.0)
        s = np.clip(s - newton_step, 0.0, 1.0)
    return t0 + s * step


def crossing_times(
    time: np.ndarray, angle: np.ndarray, speed: np.ndarray, targets: np.ndarray
) -> np.ndarray:
    """Times at which the cubic Hermite interpolant of ``angle(time)`` passes ``targets``.

    Parameters
    ----------
    time : numpy.ndarray
        Sample times [s], strictly increasing.
    angle : numpy.ndarray
        Angle at ``time`` [rad], strictly increasing.
    speed : numpy.ndarray
        d angle / dt at ``time`` [rad/s], the interpolant's slopes.
    targets : numpy.ndarray
        Angles [rad] within ``angle``'s range (targets outside are clamped to the ends).

    Returns
    -------
    numpy.ndarray
        The crossing times [s], solved by Newton's method to 1e-14 of the largest angle.

    Raises
    ------
    SignalError
        The interpolant does not increase through a target (speed and angle disagree).
    """
    targets = np.asarray(targets, dtype=float)
    if targets.size <= CROSSING_BLOCK:
        return _block_crossing_times(time, angle, speed, targets)
    return np.concatenate(  # in blocks: the Newton temporaries stay small
        [
            _block_crossing_times(time, angle, speed, targets[block : block + CROSSING_BLOCK])
            for block in range(0, targets.size, CROSSING_BLOCK)
        ]
    )


def monotone_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """PCHIP derivatives dy/dx at the samples (Fritsch & Carlson 1980; Fritsch & Butland
    1984).

    Inside, the weighted harmonic mean of the two neighbouring secants d_{k-1}, d_k with
    weights w1 = 2 h_k + h_{k-1}, w2 = h_k + 2 h_{k-1} (zero where the secants differ
    in sign); at the ends, the one-sided three-point formula, set to zero when its sign
    differs from the end secant's and limited to three times that secant when the
    secants change sign.

    Parameters
    ----------
    x : numpy.ndarray
        Strictly increasing abscissae, at least two.
    y : numpy.ndarray
        Values at ``x``.

    Returns
    -------
    numpy.ndarray
        The slopes, one per sample.
    """
    step = np.diff(x)
    secant = np.diff(y) / step
    if x.size == 2:
        return np.full(2, secant[0])
    slopes = np.empty_like(secant, shape=x.shape)
    left, right = secant[:-1], secant[1:]
    w1 = 2.0 * step[1:] + step[:-1]
    w2 = step[1:] + 2.0 * step[:-1]
    same_sign = left * right > 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        harmonic = (w1 + w2) / (w1 / left + w2 / right)
    slopes[1:-1] = np.where(same_sign, harmonic, 0.0)
    slopes[0] = _end_slope(step[0], step[1], secant[0], secant[1])
    slopes[-1] = _end_slope(step[-1], step[-2], secant[-1], secant[-2])
    return slopes


def _end_slope(h0: float, h1: float, d0: float, d1: float) -> float:
    slope = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1)
    if np.sign(slope) != np.sign(d0):
        return 0.0
    if np.sign(d0) != np.sign(d1) and abs(slope) > abs(3.0 * d0):
        return 3.0 * d0
    return float(slope)


def hermite_values(x: np.ndarray, y: np.ndarray, slopes: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The cubic Hermite interpolant through ``(x, y)`` with ``slopes``, at ``at``.

    ``at`` must lie within [x[0], x[-1]] (the caller checks); each point uses the
    interval that holds it.
    """
    at = np.asarray(at, dtype=float)
    interval = np.clip(np.searchsorted(x, at, side="right") - 1, 0, x.size - 2)
    step = x[interval + 1] - x[interval]
    s = (at - x[interval]) / step
    s2, s3 = s * s, s * s * s
    return (
        y[interval] * (2 * s3 - 3 * s2 + 1)
        + slopes[interval] * step * (s3 - 2 * s2 + s)
        + y[interval + 1] * (3 * s2 - 2 * s3)
        + slopes[interval + 1] * step * (s3 - s2)
    )


def local_cubic(time: np.ndarray, values: np.ndarray, at: np.ndarray) -> np.ndarray:
    """``values`` at the times ``at`` by the cubic through the four nearest samples.

    A point in [t_i, t_{i+1}] uses the samples i-1 .. i+2 (shifted inwards at the
    record's ends): the Lagrange cubic, exact for cubics and local, so a sample's
    influence ends two samples away.

    Parameters
    ----------
    time : numpy.ndarray
        Sample times [s], strictly increasing, at least four.
    values : numpy.ndarray
        The channel at ``time``.
    at : numpy.ndarray
        Times within [time[0], time[-1]].

    Returns
    -------
    numpy.ndarray
        The interpolated values, shaped like ``at``.
    """
    at = np.asarray(at, dtype=float)
    interval = np.searchsorted(time, at, side="right") - 1
    first = np.clip(interval - 1, 0, time.size - 4)
    nodes = time[first[..., None] + np.arange(4)]
    samples = values[first[..., None] + np.arange(4)]
    offset = at[..., None] - nodes  # t - t_m for the four nodes m
    result = np.zeros(at.shape)
    for m in range(4):
        basis = np.ones(at.shape)
        for other in range(4):
            if other != m:
                basis *= offset[..., other] / (nodes[..., m] - nodes[..., other])
        result += basis * samples[..., m]
    return result
