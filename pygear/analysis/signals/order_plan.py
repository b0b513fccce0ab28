"""A checked order-tracking request: which member, channel, record and angle sampling.

:func:`plan_order_tracking` refuses a bad request before any resampling, with one line
naming the parameter and the rule: an unknown member or channel, a reference that never
turns, stops or turns through too few revolutions, an order above what the time
sampling resolves, or an angle sampling coarser than the time sampling.  The rules
themselves are explained in :mod:`pygear.analysis.signals.order_tracking`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import xarray as xr

from .order_references import AngleReference, reference_angle, stored_mesh_orders
from .signal import SignalError

__all__ = [
    "CHANNEL_PAD",
    "MAX_ANGLE_SAMPLES",
    "MIN_SPEED_FRACTION",
    "MIN_WINDOWS",
    "OrderPlan",
    "plan_order_tracking",
]

MIN_SPEED_FRACTION = 0.1
"""Default start of the analysed record: the first instant the reference reaches this
share of its top speed.  It bounds the angle sampling, f_s / n_min <= 10 f_s / n_max."""

MIN_WINDOWS = 2
"""The reference must turn through at least this many order-map windows."""

MAX_ANGLE_SAMPLES = 2**24
"""Most angle samples one record may have; refused beyond.  The resampling and the
spectra peak at about 90 bytes a sample (171 MB for the study case's 1.9e6), so this
bounds them near 1.5 GB."""

CHANNEL_PAD = 16
"""Samples before the record's start that the channel's spline also passes through, so
its not-a-knot end condition sits outside the analysed record (its influence decays by
2 - sqrt(3) per sample)."""


@dataclass(frozen=True)
class OrderPlan:
    """A checked order-tracking request: what :func:`track_orders` computes.

    Attributes
    ----------
    reference : AngleReference
        The member's angle and speed over the run.
    channel : str
        The channel to resample.
    start, stop : int
        Indices of the first and one past the last time sample of the analysed record.
    samples_per_rev : int
        Angle samples per revolution of the reference.
    max_order : float
        Highest order kept (at most the resolvable one).
    resolvable_order : float
        f_s / (2 n_max): the highest order the time sampling resolves over the record.
    revolutions : float
        Revolutions of the reference over the record.
    window_revolutions, overlap : float
        Length of a map window [rev] and the share of it that the next window repeats.
    tracked_orders : tuple of float
        Orders of the slices.
    min_speed_rpm : float
        Reference speed at which the record starts [rpm].
    """

    reference: AngleReference
    channel: str
    start: int
    stop: int
    samples_per_rev: int
    max_order: float
    resolvable_order: float
    revolutions: float
    window_revolutions: float
    overlap: float
    tracked_orders: tuple[float, ...]
    min_speed_rpm: float


def _positive(name: str, value: float | None) -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, np.number)):
        raise SignalError(f"{name}: must be a number, got {value!r}")
    if not (np.isfinite(value) and value > 0):
        raise SignalError(f"{name}: must be finite and > 0, got {value!r}")
    return float(value)


def plan_order_tracking(
    run: xr.Dataset,
    reference: str,
    channel: str | None = None,
    *,
    after: float | None = None,
    min_speed_rpm: float | None = None,
    max_order: float | None = None,
    samples_per_rev: int | None = None,
    window_revolutions: float = 1.0,
    overlap: float = 0.5,
    tracked_orders: Sequence[float] | None = None,
) -> OrderPlan:
    """Check an order-tracking request against a run, before any resampling.

    Parameters
    ----------
    run : xarray.Dataset
        A run with channels along ``time`` (a ``pygear run`` file).
    reference : str
        The member whose angle is the reference (``planetary.carrier`` or ``carrier``).
    channel : str, optional
        Channel to resample (default: the run's first acceleration).
    after : float, optional
        Ignore samples before this time [s].
    min_speed_rpm : float, optional
        The record starts when the reference first reaches this speed [rpm] (default
        :data:`MIN_SPEED_FRACTION` of its top speed).
    max_order : float, optional
        Highest order kept (default: the highest the time sampling resolves).
    samples_per_rev : int, optional
        Angle samples per revolution (default and minimum: f_s / n_min, rounded up to an
        FFT-friendly length).
    window_revolutions : float
        Length of an order-map window [rev]; its order resolution is 1/window.
    overlap : float
        Share of a window that the next one repeats, in [0, 1).
    tracked_orders : sequence of float, optional
        Orders of the slices (default: the stages' mesh orders and their second and
        third harmonics, as far as ``max_order``).

    Raises
    ------
    SignalError
        One line naming the parameter and the rule it breaks.
    """
    from .analyze import pick_channel
    from .channels import channel_series

    angle = reference_angle(run, reference)
    name = pick_channel(run, channel)
    window_revolutions = _positive("window_revolutions (--window-revolutions)", window_revolutions)
    min_speed_rpm = _positive("min_speed_rpm", min_speed_rpm)
    max_order = _positive("max_order (--max-order)", max_order)
    if not (isinstance(overlap, (int, float, np.number)) and 0.0 <= overlap < 1.0):
        raise SignalError(f"overlap: must lie in [0, 1), got {overlap!r}")
    time, speed = angle.time, angle.speed
    kept = np.ones(time.size, dtype=bool)
    if after is not None:
        if not (isinstance(after, (int, float, np.number)) and np.isfinite(after)):
            raise SignalError(f"after (--after): must be a finite time in seconds, got {after!r}")
        kept = time >= after
        if not kept.any():
            raise SignalError(
                f"after (--after): {after:g} s is past the run's end ({time[-1]:g} s)"
            )
    top = float(np.max(speed[kept])) * 30.0 / math.pi
    threshold = min_speed_rpm if min_speed_rpm is not None else MIN_SPEED_FRACTION * top
    reached = np.flatnonzero(kept & (speed * 30.0 / math.pi >= threshold))
    if top <= 0.0 or reached.size == 0:
        raise SignalError(
            f"min_speed_rpm: the reference {angle.member!r} never reaches {threshold:.4g} rpm "
            f"(its top speed is {top:.4g} rpm); order tracking needs it turning"
        )
    # the spline's end conditions act CHANNEL_PAD samples outside the record
    start = max(int(reached[0]), CHANNEL_PAD)
    stop = time.size - CHANNEL_PAD
    if stop - start < 4:
        raise SignalError(
            f"after (--after): fewer than 4 samples left between the start "
            f"({time[start]:.4g} s) and {CHANNEL_PAD} samples before the run's end"
        )
    span_speed = speed[start:stop]
    if np.min(span_speed) <= 0.0:
        halt = start + int(np.argmax(span_speed <= 0.0))
        raise SignalError(
            f"--orders {angle.member!r}: the reference stops or reverses at t = {time[halt]:.4g} s "
            "after reaching its start speed; its angle must increase through the record "
            "(order tracking needs one running sense)"
        )
    revolutions = float(angle.angle[stop - 1] - angle.angle[start]) / (2.0 * math.pi)
    needed = MIN_WINDOWS * window_revolutions
    if revolutions < needed:
        raise SignalError(
            f"--orders {angle.member!r}: the reference turns through only {revolutions:.3g} "
            f"revolutions after reaching {threshold:.4g} rpm; resolving orders needs at least "
            f"{needed:g} ({MIN_WINDOWS} windows of --window-revolutions {window_revolutions:g}):"
            " use a longer run, an earlier --after or a lower min_speed_rpm"
        )
    step = float(np.max(np.diff(time[start - 1 : stop])))
    sample_rate = 1.0 / step
    top_rev_s = float(np.max(span_speed)) / (2.0 * math.pi)
    low_rev_s = float(np.min(span_speed)) / (2.0 * math.pi)
    resolvable = sample_rate / (2.0 * top_rev_s)
    if max_order is not None and max_order > resolvable * (1 + 1e-12):
        raise SignalError(
            f"max_order (--max-order): {max_order:g} is above the highest order the time "
            f"sampling resolves, f_s / (2 n_max) = {sample_rate:g} Hz / (2 x {top_rev_s:.4g} "
            f"rev/s) = {resolvable:.4g}"
        )
    values = channel_series(run, name).values[start - CHANNEL_PAD : stop + CHANNEL_PAD]
    if not np.issubdtype(values.dtype, np.number) or np.iscomplexobj(values):
        raise SignalError(f"--channel: {name!r} must hold real numbers (dtype {values.dtype})")
    if not np.all(np.isfinite(values)):
        raise SignalError(f"--channel: {name!r} holds NaN or inf in the analysed record")
    needed_rate = sample_rate / low_rev_s
    if samples_per_rev is None:
        from scipy.fft import next_fast_len

        samples_per_rev = next_fast_len(math.ceil(needed_rate), real=True)
    elif (
        isinstance(samples_per_rev, bool)
        or not isinstance(samples_per_rev, (int, np.integer))
        or samples_per_rev < needed_rate
    ):
        raise SignalError(
            f"samples_per_rev: must be a whole number >= f_s / n_min = {needed_rate:.6g} so "
            f"the angle steps are never coarser than the time steps (got {samples_per_rev!r})"
        )
    count = revolutions * samples_per_rev
    if count > MAX_ANGLE_SAMPLES:
        raise SignalError(
            f"min_speed_rpm: starting at {threshold:.4g} rpm needs {count:.3g} angle samples "
            f"(more than {MAX_ANGLE_SAMPLES}); raise min_speed_rpm or after"
        )
    top_order = resolvable if max_order is None else max_order
    tracked = _tracked_orders(run, angle, tracked_orders, top_order)
    return OrderPlan(
        reference=angle,
        channel=name,
        start=start,
        stop=stop,
        samples_per_rev=int(samples_per_rev),
        max_order=top_order,
        resolvable_order=resolvable,
        revolutions=revolutions,
        window_revolutions=window_revolutions,
        overlap=float(overlap),
        tracked_orders=tracked,
        min_speed_rpm=threshold,
    )


def _tracked_orders(
    run: xr.Dataset, angle: AngleReference, orders: Sequence[float] | None, top: float
) -> tuple[float, ...]:
    if orders is None:  # each stage's mesh order and its next two harmonics
        mesh = stored_mesh_orders(run, angle.member).values()
        return tuple(sorted(h * k for k in mesh for h in (1, 2, 3) if 0 < h * k <= top))
    checked = []
    for k in orders:
        value = _positive("tracked_orders", k)
        if value > top:
            raise SignalError(
                f"tracked_orders: order {value:g} is above max_order = {top:.4g} (the highest "
                "order the time sampling resolves, or the one asked for)"
            )
        checked.append(value)
    return tuple(checked)
