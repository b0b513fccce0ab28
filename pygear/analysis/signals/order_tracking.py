"""Computed order tracking of run-ups: one channel resampled at constant increments of a
member's angle, its order spectrum, order-speed map and order slices.

The method (docs/order_tracking.md; Potter & Gribler 1989; Fyfe & Munck 1997):

0. **The request** is checked first (:mod:`.order_plan`).
1. **Reference angle** theta(t) [rad] of the member (:mod:`.order_references`): its
   ``theta_z`` displacement channel when the run recorded one, else the trapezoid
   integral of its speed channel.
2. **Crossing times** t_j of the uniform angle steps theta_j = j dtheta: Newton's method
   on the cubic Hermite interpolant of theta(t) through the samples with the speed as
   slope (angle error <= H^4 max|omega'''| / 384 for a sample step H).
3. **Channel at t_j**: a not-a-knot cubic spline through the channel's samples (error
   <= (5/384) H^4 max|x''''| away from the record's ends, Hall & Meyer 1976).
4. **Anti-aliasing**: an order k at reference speed n [rev/s] is the frequency k n, so
   the time samples resolve orders up to ``max_order = f_s / (2 n_max)`` over the whole
   record; higher orders are refused.  The angle steps are chosen at least as dense as
   the time samples everywhere (``samples_per_rev >= f_s / n_min``), so no content of
   the time record folds onto another order when it is resampled.
5. **Spectra** on FFTW (the plan cache of :mod:`.signal`): a Hann-windowed,
   amplitude-corrected order spectrum of the whole record, short-angle-window spectra
   against the window's mean reference speed (the order-speed map), and the amplitude
   of chosen orders in each window by a direct Fourier sum at exactly that order (the
   order slices).  Peaks are refined with Grandke's (1983) interpolation for the Hann
   window.

Every function takes and returns xarray objects whose variables carry ``units`` and
``long_name``; nothing here reads files or draws.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import xarray as xr

from .angle_resampling import crossing_times
from .channels import channel_series
from .order_plan import CHANNEL_PAD, OrderPlan, plan_order_tracking
from .order_references import stored_mesh_orders
from .signal import _fft_options, _one_sided_amplitude

__all__ = [
    "OrderPlan",
    "angle_order_spectrum",
    "order_peaks",
    "order_slices",
    "order_speed_map",
    "order_summary",
    "plan_order_tracking",
    "resample_to_angle",
    "track_orders",
]

# --------------------------------------------------------------------------- resampling


def resample_to_angle(plan: OrderPlan, run: xr.Dataset) -> xr.DataArray:
    """The plan's channel at uniform steps of the reference angle.

    Parameters
    ----------
    plan : OrderPlan
        From :func:`plan_order_tracking`.
    run : xarray.Dataset
        The run the plan was made for.

    Returns
    -------
    xarray.DataArray
        The channel along ``revolution`` [1] (the reference's angle in revolutions,
        every ``1 / samples_per_rev``), with the crossing ``time`` [s] and the reference
        ``speed`` [rpm] as coordinates along it.
    """
    reference, start, stop = plan.reference, plan.start, plan.stop
    span = slice(start, stop)
    time, angle, speed = reference.time[span], reference.angle[span], reference.speed[span]
    spr = plan.samples_per_rev
    first = math.ceil(angle[0] / (2 * math.pi) * spr - 1e-9)
    last = math.floor(angle[-1] / (2 * math.pi) * spr + 1e-9)
    revolutions = np.arange(first, last + 1) / spr
    targets = revolutions * 2 * math.pi
    crossing = crossing_times(time, angle, speed, targets)  # in blocks: bounded memory
    signal = channel_series(run, plan.channel)
    padded = slice(start - CHANNEL_PAD, stop + CHANNEL_PAD)
    values = np.asarray(signal.values[padded], dtype=float)  # finite: checked by the plan
    from scipy.interpolate import make_interp_spline

    resampled = make_interp_spline(reference.time[padded], values, k=3)(crossing)
    speed_at = np.interp(crossing, time, speed) * 30.0 / math.pi
    member = reference.member
    return xr.DataArray(
        resampled,
        dims="revolution",
        coords={
            "revolution": (
                "revolution",
                revolutions,
                {"units": "1", "long_name": f"angle of {member} [revolutions]"},
            ),
            "time": ("revolution", crossing, {"units": "s", "long_name": "crossing time"}),
            "speed": ("revolution", speed_at, {"units": "rpm", "long_name": f"speed of {member}"}),
        },
        name=plan.channel,
        attrs={
            "units": signal.attrs.get("units", "1"),
            "long_name": f"{signal.attrs.get('long_name', plan.channel)} at uniform angle steps "
            f"of {member}",
            "samples_per_rev": spr,
            "reference": member,
            "interpolation": "cubic spline (not-a-knot) at Hermite crossing times",
        },
    )


# --------------------------------------------------------------------------- spectra


def _order_axis(values: np.ndarray, member: str) -> xr.DataArray:
    return xr.DataArray(
        values,
        dims="order",
        attrs={"units": "1", "long_name": f"order (cycles per revolution of {member})"},
    )


def _largest_fast_length(count: int) -> int:
    """The largest 2-3-5-smooth length <= ``count`` (an FFT-friendly record)."""
    from scipy.fft import next_fast_len

    length = count
    while next_fast_len(length, real=True) != length:
        length -= 1
    return length


def angle_order_spectrum(
    resampled: xr.DataArray,
    max_order: float,
    *,
    threads: int | None = None,
    planner_effort: str | None = None,
) -> xr.DataArray:
    """Hann-windowed, amplitude-corrected order spectrum of an angle-domain record.

    An order of amplitude A on a bin reads A; the record's mean is removed first.

    Parameters
    ----------
    resampled : xarray.DataArray
        From :func:`resample_to_angle`.
    max_order : float
        Orders above it are dropped.
    threads, planner_effort
        FFTW options, as in :func:`pygear.analysis.signals.signal.amplitude_spectrum`.

    Returns
    -------
    xarray.DataArray
        Amplitude in the channel's units along ``order`` [1].
    """
    threads, effort = _fft_options(threads, planner_effort)
    spr = int(resampled.attrs["samples_per_rev"])
    length = _largest_fast_length(resampled.size)
    rows = np.asarray(resampled.values[:length], dtype=float)[np.newaxis, :]
    rows = rows - rows.mean()
    amplitude = _one_sided_amplitude(rows, "hann", threads, effort)[0]
    orders = np.arange(amplitude.size) * (spr / length)
    keep = orders <= max_order * (1 + 1e-12)
    member = _member(resampled)
    return xr.DataArray(
        amplitude[keep],
        dims="order",
        coords={"order": _order_axis(orders[keep], member)},
        name="order_amplitude",
        attrs={
            "units": resampled.attrs["units"],
            "long_name": f"order spectrum of {resampled.name} (Hann, whole record)",
            "revolutions": length / spr,
        },
    )


def _member(resampled: xr.DataArray) -> str:
    return str(resampled.attrs["reference"])


def _windows(resampled: xr.DataArray, window_revolutions: float, overlap: float):
    spr = int(resampled.attrs["samples_per_rev"])
    length = max(int(round(window_revolutions * spr)), 16)
    hop = max(int(round(length * (1.0 - overlap))), 1)
    starts = np.arange(0, resampled.size - length + 1, hop)
    time = resampled["time"].values
    mean_speed = ((length - 1) / spr) / (time[starts + length - 1] - time[starts]) * 60.0
    centre = 0.5 * (time[starts] + time[starts + length - 1])
    coords = {
        "window": ("window", np.arange(starts.size), {"units": "1", "long_name": "window"}),
        "speed": (
            "window",
            mean_speed,
            {"units": "rpm", "long_name": f"mean speed of {_member(resampled)} in the window"},
        ),
        "window_time": ("window", centre, {"units": "s", "long_name": "centre of the window"}),
    }
    return starts, length, coords


def order_speed_map(
    resampled: xr.DataArray,
    max_order: float,
    *,
    window_revolutions: float = 1.0,
    overlap: float = 0.5,
    threads: int | None = None,
    planner_effort: str | None = None,
) -> xr.DataArray:
    """Order spectra of short angle windows against the reference speed (waterfall data).

    Parameters
    ----------
    resampled : xarray.DataArray
        From :func:`resample_to_angle`.
    max_order : float
        Orders above it are dropped.
    window_revolutions : float
        Window length [rev]: order resolution 1 / window_revolutions.
    overlap : float
        Share of a window the next one repeats.
    threads, planner_effort
        FFTW options.

    Returns
    -------
    xarray.DataArray
        Amplitude over (``window``, ``order``), with the window's mean reference
        ``speed`` [rpm] and centre ``window_time`` [s] as coordinates.
    """
    threads, effort = _fft_options(threads, planner_effort)
    starts, length, coords = _windows(resampled, window_revolutions, overlap)
    spr = int(resampled.attrs["samples_per_rev"])
    orders = np.arange(length // 2 + 1) * (spr / length)
    keep = orders <= max_order * (1 + 1e-12)
    values = np.asarray(resampled.values, dtype=float)
    amplitude = np.empty((starts.size, int(np.count_nonzero(keep))))
    for row, start in enumerate(starts):  # one window at a time: memory of one window
        window = values[start : start + length]
        window = (window - window.mean())[np.newaxis, :]
        amplitude[row] = _one_sided_amplitude(window, "hann", threads, effort)[0, keep]
    coords["order"] = _order_axis(orders[keep], _member(resampled))
    return xr.DataArray(
        amplitude,
        dims=("window", "order"),
        coords=coords,
        name="order_map_amplitude",
        attrs={
            "units": resampled.attrs["units"],
            "long_name": f"order spectrum of {resampled.name} in windows of "
            f"{length / spr:g} revolutions (Hann)",
        },
    )


def order_slices(
    resampled: xr.DataArray,
    orders: Sequence[float],
    *,
    window_revolutions: float = 1.0,
    overlap: float = 0.5,
) -> xr.DataArray:
    """Amplitude of each order in each angle window, against the reference speed.

    Each window's Hann-weighted Fourier sum is taken at exactly the order, so an order
    between two bins reads its amplitude with no scalloping loss.

    Parameters
    ----------
    resampled : xarray.DataArray
        From :func:`resample_to_angle`.
    orders : sequence of float
        The orders to follow.
    window_revolutions, overlap : float
        As in :func:`order_speed_map`.

    Returns
    -------
    xarray.DataArray
        Amplitude over (``tracked_order``, ``window``), with ``speed`` [rpm] and
        ``window_time`` [s] along ``window``.
    """
    starts, length, coords = _windows(resampled, window_revolutions, overlap)
    weights = 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(length) / length)
    # every window starts on an angle step, so its angles from its start are j / spr
    spr = int(resampled.attrs["samples_per_rev"])
    angle = np.arange(length) / spr
    kernels = np.exp(-2j * np.pi * np.outer(np.asarray(orders, dtype=float), angle))
    signal = np.asarray(resampled.values, dtype=float)
    values = np.empty((len(orders), starts.size))
    for column, start in enumerate(starts):
        window = signal[start : start + length]
        values[:, column] = np.abs(kernels @ ((window - window.mean()) * weights))
    values *= 2.0 / weights.sum()
    coords["tracked_order"] = (
        "tracked_order",
        np.asarray(orders, dtype=float),
        {"units": "1", "long_name": f"tracked order of {_member(resampled)}"},
    )
    return xr.DataArray(
        values,
        dims=("tracked_order", "window"),
        coords=coords,
        name="order_slice_amplitude",
        attrs={
            "units": resampled.attrs["units"],
            "long_name": f"amplitude of each tracked order of {resampled.name} per window (Hann)",
        },
    )


def order_peaks(spectrum: xr.DataArray, count: int = 10, min_order: float | None = None) -> list:
    """The strongest peaks of a Hann order spectrum, refined between bins.

    Grandke's (1983) interpolation for the Hann window: with the largest bin k and its
    larger neighbour at ratio a = |X_{k+-1}| / |X_k|, the tone sits at
    delta = (2a - 1)/(a + 1) bins from k towards that neighbour, and its amplitude is
    |X_k| (1 - delta^2) / sinc(delta).

    Parameters
    ----------
    spectrum : xarray.DataArray
        From :func:`angle_order_spectrum`.
    count : int
        Peaks returned, strongest first.
    min_order : float, optional
        Ignore orders below it (default: three bins, the window's main lobe).

    Returns
    -------
    list of dict
        ``{"order": ..., "amplitude": ...}``; peaks below 1e-6 of the largest are dropped.
    """
    amplitude = np.asarray(spectrum.values, dtype=float)
    orders = np.asarray(spectrum["order"].values, dtype=float)
    if amplitude.size < 3:
        return []
    step = orders[1] - orders[0]
    low = 3 * step if min_order is None else min_order
    inner = np.arange(1, amplitude.size - 1)
    local = inner[
        (amplitude[inner] > amplitude[inner - 1])
        & (amplitude[inner] >= amplitude[inner + 1])
        & (orders[inner] >= low)
    ]
    local = local[np.argsort(amplitude[local])[::-1]][:count]
    peaks = []
    for k in local:
        side = 1 if amplitude[k + 1] >= amplitude[k - 1] else -1
        ratio = amplitude[k + side] / amplitude[k]
        delta = min(max((2.0 * ratio - 1.0) / (ratio + 1.0), 0.0), 0.5)
        gain = np.sinc(delta) / (1.0 - delta * delta)
        order = float(orders[k] + side * delta * step)
        peaks.append({"order": order, "amplitude": float(amplitude[k] / gain)})
    largest = max((p["amplitude"] for p in peaks), default=0.0)
    return [p for p in peaks if p["amplitude"] >= 1e-6 * largest]


# --------------------------------------------------------------------------- the whole analysis


def track_orders(
    run: xr.Dataset,
    plan: OrderPlan,
    *,
    threads: int | None = None,
    planner_effort: str | None = None,
) -> xr.Dataset:
    """Order spectrum, order-speed map and order slices of a checked plan.

    Parameters
    ----------
    run : xarray.Dataset
        The run the plan was made for.
    plan : OrderPlan
        From :func:`plan_order_tracking`.
    threads, planner_effort
        FFTW options.

    Returns
    -------
    xarray.Dataset
        ``order_amplitude`` (order), ``order_map_amplitude`` (window, map_order),
        ``order_slice_amplitude`` (tracked_order, window) and ``mesh_order``
        (mesh_stage), with the plan as attributes.
    """
    resampled = resample_to_angle(plan, run)
    options = dict(threads=threads, planner_effort=planner_effort)
    spectrum = angle_order_spectrum(resampled, plan.max_order, **options)
    windows = dict(window_revolutions=plan.window_revolutions, overlap=plan.overlap)
    speed_map = order_speed_map(resampled, plan.max_order, **windows, **options)
    speed_map = speed_map.rename(order="map_order")
    slices = order_slices(resampled, plan.tracked_orders, **windows)
    mesh = stored_mesh_orders(run, plan.reference.member)
    result = xr.Dataset(
        {
            "order_amplitude": spectrum,
            "order_map_amplitude": speed_map,
            "order_slice_amplitude": slices,
            "mesh_order": (
                "mesh_stage",
                np.array(list(mesh.values()), dtype=float),
                {
                    "units": "1",
                    "long_name": f"mesh order of each stage relative to {plan.reference.member}",
                },
            ),
        },
        coords={
            "mesh_stage": (
                "mesh_stage",
                np.array(list(mesh), dtype=str),
                {"units": "1", "long_name": "gear stage"},
            )
        },
    )
    result["map_order"].attrs["long_name"] = "order of the map windows"
    result.attrs.update(
        reference=plan.reference.member,
        angle_source=plan.reference.source,
        channel=plan.channel,
        samples_per_rev=plan.samples_per_rev,
        max_order=plan.max_order,
        resolvable_order=plan.resolvable_order,
        revolutions=plan.revolutions,
        window_revolutions=plan.window_revolutions,
        overlap=plan.overlap,
        min_speed_rpm=plan.min_speed_rpm,
        start_time=float(plan.reference.time[plan.start]),
        window="hann",
        interpolation=resampled.attrs["interpolation"],
    )
    return result


def order_summary(result: xr.Dataset, peaks: int = 10) -> dict:
    """The result of :func:`track_orders` as plain data (for ``--json``)."""
    spectrum = result["order_amplitude"]
    speed = result["speed"].values
    return {
        "reference": result.attrs["reference"],
        "channel": result.attrs["channel"],
        "angle_source": result.attrs["angle_source"],
        "units": spectrum.attrs["units"],
        "max_order": float(result.attrs["max_order"]),
        "resolvable_order": float(result.attrs["resolvable_order"]),
        "samples_per_rev": int(result.attrs["samples_per_rev"]),
        "revolutions": float(result.attrs["revolutions"]),
        "order_resolution": float(spectrum["order"].values[1] - spectrum["order"].values[0]),
        "speed_range_rpm": [float(speed.min()), float(speed.max())] if speed.size else [],
        "orders": order_peaks(spectrum, peaks),
        "mesh_orders": {
            str(stage): float(order)
            for stage, order in zip(result.mesh_stage.values, result.mesh_order.values)
        },
    }
