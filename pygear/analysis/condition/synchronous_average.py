"""Time-synchronous averaging (TSA): a channel averaged over revolutions of a shaft's
angle, with McFadden's windowed averages of the planets and the sun of a planetary
stage, and a tachometer's pulses and the angle rebuilt from them.

**The average** (Braun 1975; McFadden 1987).  With the angle theta(t) of the shaft,
the channel x(t) is read at the times t_{r,j} at which theta passes the angle steps
j P / M (j = 0 .. M-1, M ``samples_per_revolution``, P ``angle_period``, 2 pi for one
revolution) of R whole consecutive revolutions, and averaged per step:

    xbar_j = sum_r w_{r,j} x(t_{r,j}) / sum_r w_{r,j}    (w = 1 without weights).

Components locked to theta add up coherently; noise uncorrelated between revolutions
of variance sigma^2 is left with sigma^2 / R (sigma^2 sum w^2 / (sum w)^2 weighted).
The crossing times come from the cubic Hermite interpolant of theta(t) with the speed
as slope (:func:`.angle_resampling.crossing_times`; PCHIP slopes when no speed is given),
the channel and the weights at them from the cubic through their four nearest samples
(:func:`.angle_resampling.local_cubic`), whose error on a uniform step H is at most
(9/16) H^4 max|x''''| / 24.  A weight interpolated below zero at a sharp edge counts
as zero.

**Conventions.**  Every angle is in radians and increases in its member's running
direction (negate one that decreases).  The M steps start at the angle origin, so a
feature at angle a of the shaft lands at step a M / P whichever revolution the record
starts in.  Tooth k of a gear with Z teeth is the k-th tooth to pass a fixed point after
tooth 0: it sits 2 pi k / Z behind tooth 0 in the gear's frame, so when the angle origin
is the orientation with tooth 0 at the point, tooth k appears at 2 pi k / Z.

**Planetary stages** (McFadden 1991; McFadden 1994).  A transducer on the ring at angle
``sensor_angle_rad`` hears a planet best when the planet passes it.  Planet p, at
``planet_position_rad`` phi_p on the carrier, is at theta_c + phi_p in the fixed frame
(theta_c the carrier's angle, every angle measured from one origin in the carrier's
running direction); its window w_p = W(wrap(theta_c + phi_p - sensor)) is centred on the
transducer (:func:`planet_window`).  A planet's average is the weighted TSA over the
planet's own angle relative to the carrier (its running direction there, which in a
stage with a held ring is against the carrier's); the sun's is the TSA over the sun's
angle relative to each planet, alpha_p = theta_s - theta_c - phi_p, with the
contributions of every planet, each under its own window, summed in numerator and
denominator.  alpha_p = 0 when the sun's tooth 0 meshes with planet p (the sun's angle
origin is its orientation relative to the carrier with tooth 0 facing the planet at
phi = 0), and sun tooth k meshes with planet p at alpha_p = 2 pi k / Z_s.

**Tachometer.**  :func:`synthetic_tachometer` gives the times at which a shaft passes
multiples of 2 pi / N, with Gaussian timing jitter; :func:`angle_from_tachometer`
interpolates the pulse count (PCHIP) back into an angle.  Gaussian jitter of standard
deviation sigma_t at speed Omega moves an angle step that falls on a pulse by an angle
of standard deviation sigma_theta = Omega sigma_t, and averaging over it multiplies
order k there by exp(-k^2 sigma_theta^2 / 2), the jitter's characteristic function
(Souders, Flach, Hagwood & Yang 1990).  Between pulses the rebuilt angle blends the
errors of neighbouring pulses.

Equations and sources: ``docs/condition_monitoring.md``.  Inputs are checked first; a
bad one raises :class:`~pygear.analysis.signals.signal.SignalError` naming the parameter.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from ..signals.angle_resampling import local_cubic
from ..signals.signal import SignalError
from .angle_average import (
    TWO_PI,
    WINDOW_SHAPES,
    AngleAverage,
    angle_from_tachometer,
    angle_slopes,
    bin_sums,
    check_array,
    check_bins,
    check_increasing,
    check_number,
    check_time,
    check_whole_number,
    check_window,
    step_crossings,
    synthetic_tachometer,
    weighted_angle_average,
)

__all__ = [
    "WINDOW_SHAPES",
    "AngleAverage",
    "angle_from_tachometer",
    "planet_average",
    "planet_synchronous_average",
    "planet_window",
    "sun_average",
    "sun_synchronous_average",
    "synthetic_tachometer",
    "time_synchronous_average",
    "weighted_angle_average",
]

_COVERAGE = "record more carrier revolutions (or widen width_rad) so that every tooth passes"


# --------------------------------------------------------------------------- planetary stages


def planet_window(
    carrier_angle: Any,
    planet_position_rad: float,
    sensor_angle_rad: float,
    width_rad: float,
    shape: str = "hann",
) -> np.ndarray:
    """The weight of a planet's pass at a transducer on the ring (McFadden 1991, 1994).

    With delta = wrap(theta_c + phi_p - sensor) in [-pi, pi), the planet's angle from
    the transducer, and L = ``width_rad``:

    - ``"hann"``: cos^2(pi delta / L) = (1 + cos(2 pi delta / L)) / 2 for |delta| < L/2,
      else 0;
    - ``"rectangular"``: 1 for -L/2 <= delta < L/2, else 0.

    The windows of N planets spaced 2 pi / N apart sum to a constant at every carrier
    angle when L = 2 pi k / N: k / 2 for Hann windows with k >= 2 (L = 4 pi / N makes
    neighbours overlap by half and sum to 1; L = 2 pi / N does not, its sum falls to 0
    midway between planets), k for rectangular ones.  A constant sum uses every part of
    the record with the same total weight across the planets.

    Parameters
    ----------
    carrier_angle : array_like
        The carrier's angle theta_c [rad].
    planet_position_rad : float
        The planet's angle phi_p on the carrier from the carrier's angle origin [rad].
    sensor_angle_rad : float
        The transducer's angle in the fixed frame [rad].
    width_rad : float
        The window's extent L in carrier angle, in (0, 2 pi] [rad].
    shape : str
        One of :data:`WINDOW_SHAPES`.

    Returns
    -------
    numpy.ndarray
        The weight in [0, 1], shaped like ``carrier_angle``.
    """
    try:
        carrier = np.asarray(carrier_angle, dtype=float)
    except (TypeError, ValueError):
        raise SignalError("carrier_angle: must be an array of real numbers") from None
    if not np.all(np.isfinite(carrier)):
        raise SignalError("carrier_angle: holds NaN or inf")
    position = check_number(planet_position_rad, "planet_position_rad")
    sensor = check_number(sensor_angle_rad, "sensor_angle_rad")
    width = check_window(width_rad, shape)
    delta = np.mod(carrier + (position - sensor) + math.pi, TWO_PI) - math.pi
    if shape == "rectangular":
        return ((delta >= -0.5 * width) & (delta < 0.5 * width)).astype(float)
    inside = np.abs(delta) < 0.5 * width
    return np.where(inside, 0.5 * (1.0 + np.cos(TWO_PI * delta / width)), 0.0)


def planet_average(
    signal: Any,
    time: Any,
    carrier_angle: Any,
    planet_spin_angle: Any,
    planet_position_rad: float,
    sensor_angle_rad: float,
    width_rad: float,
    samples_per_revolution: int,
    *,
    shape: str = "hann",
    planet_spin_speed: Any = None,
) -> AngleAverage:
    """A planet's windowed synchronous average over its own angle (McFadden 1991, 1994).

    xbar_j = sum_r w_p(theta_c(t_{r,j})) x(t_{r,j}) / sum_r w_p(theta_c(t_{r,j})), the
    t_{r,j} the crossings of the planet's angle relative to the carrier.

    Parameters
    ----------
    signal : array_like
        The transducer's channel at ``time``.
    time : array_like
        Sample times [s], strictly increasing.
    carrier_angle : array_like
        The carrier's angle theta_c at ``time`` [rad].
    planet_spin_angle : array_like
        The planet's angle relative to the carrier at ``time`` [rad], strictly
        increasing (its running direction relative to the carrier).
    planet_position_rad, sensor_angle_rad, width_rad, shape
        The planet's window, as in :func:`planet_window`.
    samples_per_revolution : int
        Angle steps per planet revolution (>= 2).
    planet_spin_speed : array_like, optional
        d planet_spin_angle / dt at ``time`` [rad/s]; PCHIP slopes without it.

    Returns
    -------
    AngleAverage
        Over one planet revolution relative to the carrier.
    """
    time = check_time(time)
    spin = check_increasing(planet_spin_angle, "planet_spin_angle", time.size)
    signal = check_array(signal, "signal", time.size)
    carrier = check_array(carrier_angle, "carrier_angle", time.size)
    spr = check_whole_number(samples_per_revolution, "samples_per_revolution", 2)
    planet_window(0.0, planet_position_rad, sensor_angle_rad, width_rad, shape)  # the checks
    slopes = angle_slopes(planet_spin_speed, "planet_spin_speed", time, spin)
    crossing, bins, revolutions = step_crossings(
        time, spin, slopes, spr, TWO_PI, name="planet_spin_angle"
    )
    weight = planet_window(
        local_cubic(time, carrier, crossing),
        planet_position_rad,
        sensor_angle_rad,
        width_rad,
        shape,
    )
    values = local_cubic(time, signal, crossing)
    weighted, weight_sum = bin_sums([(bins, values, weight)], spr)
    check_bins(weight_sum, TWO_PI, "time", _COVERAGE)
    return AngleAverage(weighted / weight_sum, revolutions, weight_sum)


def sun_average(
    signal: Any,
    time: Any,
    sun_angle: Any,
    carrier_angle: Any,
    planet_positions_rad: Sequence[float],
    sensor_angle_rad: float,
    width_rad: float,
    samples_per_revolution: int,
    *,
    shape: str = "hann",
    sun_relative_speed: Any = None,
) -> AngleAverage:
    """The sun's windowed synchronous average over its angle relative to the planets
    (McFadden 1991, 1994).

    xbar_j = sum_p sum_r w_p x(t^p_{r,j}) / sum_p sum_r w_p, the t^p_{r,j} the
    crossings of alpha_p = theta_s - theta_c - phi_p through the steps 2 pi j / M and
    w_p planet p's window at the carrier's angle then.

    Parameters
    ----------
    signal : array_like
        The transducer's channel at ``time``.
    time : array_like
        Sample times [s], strictly increasing.
    sun_angle, carrier_angle : array_like
        theta_s and theta_c at ``time`` [rad]; theta_s - theta_c must increase strictly.
    planet_positions_rad : sequence of float
        phi_p of every planet on the carrier [rad].
    sensor_angle_rad, width_rad, shape
        The planets' windows, as in :func:`planet_window`.
    samples_per_revolution : int
        Angle steps per sun revolution relative to a planet (>= 2).
    sun_relative_speed : array_like, optional
        d(theta_s - theta_c)/dt at ``time`` [rad/s]; PCHIP slopes without it.

    Returns
    -------
    AngleAverage
        Over one sun revolution relative to the carrier; ``revolutions`` sums every
        planet's whole revolutions.
    """
    time = check_time(time)
    signal = check_array(signal, "signal", time.size)
    carrier = check_array(carrier_angle, "carrier_angle", time.size)
    sun = check_array(sun_angle, "sun_angle", time.size)
    relative = sun - carrier
    if not np.all(np.diff(relative) > 0.0):
        raise SignalError(
            "sun_angle: sun_angle - carrier_angle must increase strictly with time (the "
            "sun's running direction relative to the carrier)"
        )
    positions = np.atleast_1d(np.asarray(planet_positions_rad, dtype=object))
    if positions.ndim != 1 or positions.size < 1:
        raise SignalError("planet_positions_rad: must list at least one planet angle [rad]")
    positions = [check_number(p, "planet_positions_rad") for p in positions]
    spr = check_whole_number(samples_per_revolution, "samples_per_revolution", 2)
    planet_window(0.0, positions[0], sensor_angle_rad, width_rad, shape)  # the checks
    slopes = angle_slopes(sun_relative_speed, "sun_relative_speed", time, relative)
    parts, revolutions = [], 0
    for position in positions:
        crossing, bins, count = step_crossings(
            time, relative, slopes, spr, TWO_PI, offset=position, name="sun_angle"
        )
        weight = planet_window(
            local_cubic(time, carrier, crossing), position, sensor_angle_rad, width_rad, shape
        )
        parts.append((bins, local_cubic(time, signal, crossing), weight))
        revolutions += count
    weighted, weight_sum = bin_sums(parts, spr)
    check_bins(weight_sum, TWO_PI, "time", _COVERAGE)
    return AngleAverage(weighted / weight_sum, revolutions, weight_sum)


# --------------------------------------------------------------------------- xarray


def _time_channel(channel: Any, name: str) -> tuple[np.ndarray, np.ndarray]:
    if not isinstance(channel, xr.DataArray):
        raise SignalError(f"{name}: must be an xarray.DataArray along a 'time' coordinate")
    if channel.dims != ("time",) or "time" not in channel.coords:
        raise SignalError(
            f"{name}: must be one-dimensional along a 'time' coordinate [s], got dims "
            f"{channel.dims}"
        )
    return np.asarray(channel["time"].values, dtype=float), np.asarray(channel.values)


def _along(channel: Any, name: str, time: np.ndarray, units: dict[str, float]) -> np.ndarray:
    """``channel``'s values on the time coordinate ``time``, in the first unit of
    ``units`` (``{unit: factor to it}``; a channel without units is taken in it)."""
    own_time, values = _time_channel(channel, name)
    if own_time.shape != time.shape or not np.array_equal(own_time, time):
        raise SignalError(
            f"{name}: must share the channel's time coordinate (select the channel's span "
            f"with channel.sel(time={name}.time))"
        )
    unit = str(channel.attrs.get("units", next(iter(units))))
    if unit not in units:
        raise SignalError(f"{name}: units must be one of {', '.join(units)}, got {unit!r}")
    return check_array(values, name, time.size) * units[unit]


_ANGLE_UNITS = {"rad": 1.0}
_SPEED_UNITS = {"rad/s": 1.0, "rpm": math.pi / 30.0}


def _member(angle: xr.DataArray) -> str | None:
    """The member an angle channel belongs to: its ``member`` attribute, or the
    ``target`` a pygear probe writes (``planetary.carrier.theta_z``)."""
    if angle.attrs.get("member"):
        return str(angle.attrs["member"])
    target = str(angle.attrs.get("target", ""))
    return target.removesuffix(".theta_z") if target.endswith(".theta_z") else None


def _average_array(
    result: AngleAverage,
    channel: xr.DataArray,
    period: float,
    over: str,
    member: str | None,
    **settings: Any,
) -> xr.DataArray:
    steps = result.average.size
    of = f" of {member}" if member else ""
    attrs = {
        "units": str(channel.attrs.get("units", "1")),
        "long_name": f"time-synchronous average of {channel.attrs.get('long_name', channel.name)}"
        f" over the {over}{of}",
        "revolutions": int(result.revolutions),
        "samples_per_revolution": steps,
        "angle_period": period,
        **settings,
    }
    if member:
        attrs["member"] = member
    return xr.DataArray(
        result.average,
        dims="angle",
        coords={
            "angle": (
                "angle",
                np.arange(steps) * (period / steps),
                {"units": "rad", "long_name": f"{over}{of}"},
            ),
            "weight_sum": (
                "angle",
                result.weight_sum,
                {"units": "1", "long_name": "sum of the weights averaged at the angle step"},
            ),
        },
        name=channel.name,
        attrs=attrs,
    )


def time_synchronous_average(
    channel: xr.DataArray,
    angle: xr.DataArray,
    samples_per_revolution: int,
    *,
    weights: xr.DataArray | None = None,
    speed: xr.DataArray | None = None,
    angle_period: float = TWO_PI,
) -> xr.DataArray:
    """The TSA of a channel over one period of a member's angle
    (:func:`weighted_angle_average` on xarray channels).

    Parameters
    ----------
    channel : xarray.DataArray
        Along ``time`` [s]; its ``units`` and ``long_name`` carry over.
    angle : xarray.DataArray
        The member's angle [rad] on the same ``time``: a run's angle channel, or
        :func:`angle_from_tachometer` wrapped on the channel's times within the pulses.
    samples_per_revolution : int
        Angle steps per period.
    weights : xarray.DataArray, optional
        Weights >= 0 on the same ``time``.
    speed : xarray.DataArray, optional
        d angle / dt on the same ``time``, in rad/s or rpm.
    angle_period : float
        The period of the average [rad].

    Returns
    -------
    xarray.DataArray
        Along ``angle`` [rad] (0 .. P over the steps), with ``weight_sum`` along it and
        the attributes ``revolutions``, ``samples_per_revolution``, ``angle_period``
        and ``member`` (when the angle names one: its ``member`` attribute or a probe's
        ``target``).
    """
    time, values = _time_channel(channel, "channel")
    angle_values = _along(angle, "angle", time, _ANGLE_UNITS)
    result = weighted_angle_average(
        values,
        time,
        angle_values,
        samples_per_revolution,
        None if weights is None else _along(weights, "weights", time, {"1": 1.0}),
        angle_period,
        speed=None if speed is None else _along(speed, "speed", time, _SPEED_UNITS),
    )
    period = float(angle_period)
    return _average_array(result, channel, period, "angle", _member(angle))


def planet_synchronous_average(
    channel: xr.DataArray,
    carrier_angle: xr.DataArray,
    planet_spin_angle: xr.DataArray,
    planet_position_rad: float,
    sensor_angle_rad: float,
    width_rad: float,
    samples_per_revolution: int,
    *,
    shape: str = "hann",
    planet_spin_speed: xr.DataArray | None = None,
) -> xr.DataArray:
    """A planet's windowed TSA (:func:`planet_average`) on xarray channels.

    The channels share one ``time`` coordinate; angles in rad, the speed in rad/s or
    rpm.  Returns the average along ``angle`` (the planet's angle relative to the
    carrier, 0 .. 2 pi) with ``weight_sum`` along it, the window's settings and
    ``revolutions`` as attributes, and ``member`` when the spin angle names one.
    """
    time, values = _time_channel(channel, "channel")
    result = planet_average(
        values,
        time,
        _along(carrier_angle, "carrier_angle", time, _ANGLE_UNITS),
        _along(planet_spin_angle, "planet_spin_angle", time, _ANGLE_UNITS),
        planet_position_rad,
        sensor_angle_rad,
        width_rad,
        samples_per_revolution,
        shape=shape,
        planet_spin_speed=None
        if planet_spin_speed is None
        else _along(planet_spin_speed, "planet_spin_speed", time, _SPEED_UNITS),
    )
    return _average_array(
        result,
        channel,
        TWO_PI,
        "planet's angle relative to the carrier",
        _member(planet_spin_angle),
        planet_position_rad=float(planet_position_rad),
        sensor_angle_rad=float(sensor_angle_rad),
        width_rad=float(width_rad),
        window=shape,
    )


def sun_synchronous_average(
    channel: xr.DataArray,
    sun_angle: xr.DataArray,
    carrier_angle: xr.DataArray,
    planet_positions_rad: Sequence[float],
    sensor_angle_rad: float,
    width_rad: float,
    samples_per_revolution: int,
    *,
    shape: str = "hann",
    sun_relative_speed: xr.DataArray | None = None,
) -> xr.DataArray:
    """The sun's windowed TSA (:func:`sun_average`) on xarray channels.

    The channels share one ``time`` coordinate; angles in rad, the speed in rad/s or
    rpm.  Returns the average along ``angle`` (the sun's angle relative to a planet,
    0 .. 2 pi) with ``weight_sum`` along it, the windows' settings and
    ``revolutions`` (summed over the planets) as attributes, and ``member`` when the
    sun angle names one.
    """
    time, values = _time_channel(channel, "channel")
    result = sun_average(
        values,
        time,
        _along(sun_angle, "sun_angle", time, _ANGLE_UNITS),
        _along(carrier_angle, "carrier_angle", time, _ANGLE_UNITS),
        planet_positions_rad,
        sensor_angle_rad,
        width_rad,
        samples_per_revolution,
        shape=shape,
        sun_relative_speed=None
        if sun_relative_speed is None
        else _along(sun_relative_speed, "sun_relative_speed", time, _SPEED_UNITS),
    )
    return _average_array(
        result,
        channel,
        TWO_PI,
        "sun's angle relative to each planet",
        _member(sun_angle),
        planet_positions_rad=[float(p) for p in planet_positions_rad],
        sensor_angle_rad=float(sensor_angle_rad),
        width_rad=float(width_rad),
        window=shape,
    )
