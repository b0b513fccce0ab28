"""The synchronous average of one gear of a planetary stage from a run's sensor channel,
and its condition indicators.

A run that records a sensor (``Probe("sensor", ...)``) and the angles of the carrier,
the sun and the planets (``Probe("displacement", "<stage>.<member>.theta_z")``) holds
all the synchronous averages need.  :func:`gear_average` picks the right one:

* the sun: McFadden's sun average over the sun's angle relative to each planet, each
  planet under its window at the sensor (:func:`~.synchronous_average.sun_average`);
* planet n: the planet's own windowed average over its angle relative to the carrier
  (:func:`~.synchronous_average.planet_average`), the planet's angle channel negated
  where it turns backwards on the carrier (a held ring turns the planets against it);
* the ring: the plain average over the carrier's angle (every planet meets each ring
  tooth once per carrier turn).

The windows are the sensor's own (its angle, width and shape), so a planet is averaged
where the sensor hears it.  Everything comes from the run file: the sensor channel's
attributes carry the sensor, the planets' positions and the tooth counts
(:func:`pygear.analysis.sensor_signal.sensor_signal`), so no case file is read.  The
mesh order of the indicators is the gear's tooth count.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..errors import CaseError
from .gear_indicators import gear_indicators
from .synchronous_average import (
    planet_synchronous_average,
    sun_synchronous_average,
    time_synchronous_average,
)

__all__ = ["angle_variable", "gear_average", "gear_indicator_values", "parse_gear"]


def angle_variable(stage: str, member: str) -> str:
    """The name a run gives the angle probe of ``stage.member`` (theta_z displacement)."""
    return f"{stage}_{member}_theta_z_displacement"


def _sensor_attributes(run: xr.Dataset, channel: str) -> dict:
    if channel not in run:
        raise CaseError(f"--channel: the run has no variable {channel!r}")
    attrs = run[channel].attrs
    if attrs.get("quantity") != "sensor" or "sensor_teeth_sun_planet_ring" not in attrs:
        sensors = [n for n, v in run.data_vars.items() if v.attrs.get("quantity") == "sensor"]
        raise CaseError(
            f"--channel {channel!r} is not a sensor channel (a gear's windowed average needs "
            f"the sensor's angle and window; sensor channels: {', '.join(sensors) or 'none'})"
        )
    return attrs


def parse_gear(gear: str, stage: str, planets: int) -> str:
    """The member of ``gear`` (``sun``, ``ring``, ``planet<n>``, optionally after
    ``<stage>.``), checked against the sensor's stage."""
    prefix, _, member = gear.rpartition(".")
    names = ["sun", "ring", *(f"planet{n}" for n in range(1, planets + 1))]
    if prefix not in ("", stage) or member not in names:
        raise CaseError(
            f"--tsa {gear!r}: name a gear of the sensor's stage {stage!r}: "
            f"{', '.join(f'{stage}.{n}' for n in names)}"
        )
    return member


def _angle(run: xr.Dataset, stage: str, member: str, gear: str) -> xr.DataArray:
    name = angle_variable(stage, member)
    if name not in run:
        raise CaseError(
            f"the run has no channel {name!r}, which the average of {gear} needs: record "
            f"it with Probe('displacement', '{stage}.{member}.theta_z')"
        )
    return run[name]


def gear_average(
    run: xr.Dataset, gear: str, channel: str, samples_per_tooth: int = 32
) -> xr.DataArray:
    """The synchronous average of ``gear`` in the sensor ``channel`` of ``run``.

    Parameters
    ----------
    run : xarray.Dataset
        A transient's result with the sensor channel and the members' angle channels.
    gear : str
        ``sun``, ``ring`` or ``planet<n>`` of the sensor's stage (``<stage>.`` may lead).
    channel : str
        A sensor channel of the run.
    samples_per_tooth : int
        Angle steps per tooth period; the average has ``teeth x samples_per_tooth``.

    Returns
    -------
    xarray.DataArray
        Along ``angle`` [rad] over one revolution, with the attributes of
        :mod:`.synchronous_average` plus ``gear`` and ``teeth``.
    """
    attrs = _sensor_attributes(run, channel)
    stage = str(attrs["sensor_stage"])
    positions = [math.radians(a) for a in np.atleast_1d(attrs["sensor_planet_angles_deg"])]
    member = parse_gear(gear, stage, len(positions))
    sun, planet, ring = (int(t) for t in np.atleast_1d(attrs["sensor_teeth_sun_planet_ring"]))
    teeth = {"sun": sun, "ring": ring}.get(member, planet)
    if teeth < 1:
        raise CaseError(f"--tsa {gear!r}: the case gives no tooth count for the {member}")
    gear = f"{stage}.{member}"
    steps = teeth * int(samples_per_tooth)
    carrier = _angle(run, stage, "carrier", gear)
    signal = run[channel]
    window = {
        "sensor_angle_rad": math.radians(float(attrs["sensor_angle_deg"])),
        "width_rad": math.radians(float(attrs["sensor_window_width_deg"])),
        "samples_per_revolution": steps,
        "shape": str(attrs["sensor_window"]),
    }
    direction = 1.0 if float(carrier[-1] - carrier[0]) >= 0 else -1.0
    if member == "ring":
        average = time_synchronous_average(signal, direction * carrier, steps)
    elif member == "sun":
        sun_angle = _angle(run, stage, "sun", gear)
        average = sun_synchronous_average(
            signal, direction * sun_angle, direction * carrier, positions, **window
        )
    else:
        spin = _angle(run, stage, member, gear)
        sense = 1.0 if float(spin[-1] - spin[0]) >= 0 else -1.0
        position = positions[int(member.removeprefix("planet")) - 1]
        average = planet_synchronous_average(
            signal, direction * carrier, sense * spin, position, **window
        )
    return average.assign_attrs(gear=gear, teeth=teeth)


def gear_indicator_values(average: xr.DataArray, history: list | None = None) -> dict[str, float]:
    """The condition indicators of a gear's average (mesh order = its tooth count)."""
    return gear_indicators(average.values, int(average.attrs["teeth"]), history=history)
