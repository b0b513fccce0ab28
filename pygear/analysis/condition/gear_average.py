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
where the sensor hears it.  Everything comes from the run file: the sensor's
coordinates carry its position, window, the planets' positions and the tooth counts
(:func:`pygear.analysis.signals.channels.channel_series` gives them to one sensor's series as
attributes), so no case file is read.  The
mesh order of the indicators is the gear's tooth count.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ...errors import CaseError
from ..signals.channels import channel_names, channel_series, find_channel
from .gear_indicators import gear_indicators
from .synchronous_average import (
    angle_from_tachometer,
    planet_synchronous_average,
    sun_synchronous_average,
    synthetic_tachometer,
    time_synchronous_average,
)

__all__ = [
    "check_tsa_sampling",
    "gear_average",
    "gear_indicator_values",
    "member_angle",
    "parse_gear",
]


def member_angle(run: xr.Dataset, stage: str, member: str) -> xr.DataArray | None:
    """The angle of ``stage.member`` (its theta_z displacement) recorded by ``run``, or
    None (:func:`pygear.analysis.signals.channels.find_channel`)."""
    return find_channel(run, "displacement", f"{stage}.{member}.theta_z")


def _sensor_attributes(run: xr.Dataset, channel: str) -> dict:
    series = channel_series(run, channel)
    sensors = [n for n in channel_names(run) if n.startswith("sensor_acceleration:")]
    if series is None:
        raise CaseError(
            f"--channel: the run has no channel {channel!r} "
            f"(sensor channels: {', '.join(sensors) or 'none'})"
        )
    attrs = series.attrs
    if attrs.get("quantity") != "sensor" or "sensor_teeth_sun_planet_ring" not in attrs:
        raise CaseError(
            f"--channel {channel!r} is not a sensor channel (a gear's windowed average needs "
            f"the sensor's angle and window; sensor channels: {', '.join(sensors) or 'none'})"
        )
    return dict(attrs)


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
    angle = member_angle(run, stage, member)
    if angle is None:
        raise CaseError(
            f"the run has no angle of {stage}.{member}.theta_z, which the average of {gear} "
            f"needs: record it with Probe('displacement', '{stage}.{member}.theta_z')"
        )
    return angle


def _tachometer_angles(
    run: xr.Dataset,
    carrier: xr.DataArray,
    teeth: tuple[int, int, int],
    pulses: int,
    jitter: float,
    seed: int,
) -> tuple[xr.Dataset, dict[str, xr.DataArray]]:
    """The run within a synthetic tachometer's pulses on the carrier, and the angles an
    analyst derives from them: the carrier's rebuilt from the pulses (PCHIP), the sun's
    and a planet's from the carrier's by the stage's kinematics with the ring held,
    theta_s = (1 + Z_r / Z_s) theta_c and, on the carrier, (Z_r / Z_p) theta_c."""
    time = run.time.values
    true = carrier.values * (1.0 if carrier.values[-1] >= carrier.values[0] else -1.0)
    marks = synthetic_tachometer(time, true, pulses, jitter=jitter, seed=seed)
    inside = (time >= marks[0]) & (time <= marks[-1])
    step = 2 * math.pi / pulses
    first = math.ceil(true[0] / step - 1e-9) * step  # the mark the first pulse is
    angle = first + angle_from_tachometer(marks, pulses, time[inside])
    run = run.isel(time=np.flatnonzero(inside))
    sun, planet, ring = teeth
    derived = {
        "carrier": angle,
        "sun": angle * (1 + ring / sun) if sun else None,
        "planet": angle * ring / planet if planet else None,
    }
    arrays = {
        name: xr.DataArray(values, dims="time", coords={"time": run.time}, attrs={"units": "rad"})
        for name, values in derived.items()
        if values is not None
    }
    return run, arrays


def check_tsa_sampling(run: xr.Dataset, gear: str, channel: str, source: str) -> float:
    """Refuse an average whose mesh frequency the run's samples do not resolve; return
    the highest frequency the average needs [Hz].

    The sensor's stage meshes at Z_r |omega_c| / 2 pi with its ring held (what the
    averages assume), highest where the carrier turns fastest in the record (or at the
    mesh frequency the file stores, if higher).  The gear's indicators separate the mesh
    harmonic from its first sidebands, one order of the gear above it: that frequency,
    mesh x (1 + 1 / Z), must lie below the Nyquist frequency of the record, or the
    average and every indicator are made of aliases.

    Raises
    ------
    CaseError
        Naming ``--tsa``, the frequencies and the sample rate the run would need.
    """
    attrs = _sensor_attributes(run, channel)
    stage = str(attrs["sensor_stage"])
    positions = np.atleast_1d(attrs["sensor_planet_angles_deg"])
    member = parse_gear(gear, stage, len(positions))
    sun, planet, ring = (int(t) for t in np.atleast_1d(attrs["sensor_teeth_sun_planet_ring"]))
    teeth = {"sun": sun, "ring": ring}.get(member, planet)
    carrier = _angle(run, stage, "carrier", f"{stage}.{member}")
    time = np.asarray(carrier["time"].values, dtype=float)
    if time.size < 2 or teeth < 1:
        return 0.0
    rate = (time.size - 1) / float(time[-1] - time[0])
    speed = float(np.max(np.abs(np.gradient(np.asarray(carrier.values, float), time))))
    mesh = ring * speed / (2 * math.pi)
    if "mesh_frequency" in run and "mesh_stage" in run.coords:
        stored = run["mesh_frequency"].where(run["mesh_stage"] == stage, drop=True)
        if stored.size:
            mesh = max(mesh, float(np.nanmax(stored.values)))
    needed = mesh * (1 + 1 / teeth)
    if not needed < rate / 2:
        raise CaseError(
            f"--tsa {gear}: the mesh frequency of {stage} reaches {mesh:.6g} Hz and the "
            f"average of the {member} ({teeth} teeth) needs {needed:.6g} Hz with its first "
            f"sideband, not below the Nyquist frequency {rate / 2:.6g} Hz of {source} "
            f"(sample rate {rate:.6g} Hz): it would average aliases; rerun the scene "
            f"sampled above {2 * needed:.6g} Hz"
        )
    return needed


def gear_average(
    run: xr.Dataset,
    gear: str,
    channel: str,
    samples_per_tooth: int = 32,
    *,
    tachometer: int | None = None,
    jitter: float = 0.0,
    seed: int = 0,
) -> xr.DataArray:
    """The synchronous average of ``gear`` in the sensor ``channel`` of ``run``.

    Parameters
    ----------
    run : xarray.Dataset
        A transient's result with the sensor channel and the members' angle channels.
    gear : str
        ``sun``, ``ring`` or ``planet<n>`` of the sensor's stage (``<stage>.`` may lead).
    channel : str
        A sensor channel of the run (``sensor_acceleration:<sensor>``, the sensor's
        name, or a named sensor probe's variable).
    samples_per_tooth : int
        Angle steps per tooth period; the average has ``teeth x samples_per_tooth``.
    tachometer : int, optional
        Average on the angles a tachometer with this many pulses a carrier turn gives
        (:func:`.synchronous_average.synthetic_tachometer`, the carrier's angle rebuilt
        from the pulses, the sun's and the planets' from it by the kinematics) instead of
        the simulated angles.
    jitter, seed : float, int
        The tachometer's timing jitter [s] (standard deviation) and its seed.

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
    derived: dict[str, xr.DataArray] = {}
    if tachometer is not None:
        run, derived = _tachometer_angles(
            run, carrier, (sun, planet, ring), tachometer, jitter, seed
        )
        carrier = derived["carrier"]
    signal = channel_series(run, channel)
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
        sun_angle = derived["sun"] if derived else _angle(run, stage, "sun", gear)
        average = sun_synchronous_average(
            signal, direction * sun_angle, direction * carrier, positions, **window
        )
    else:
        spin = derived["planet"] if derived else _angle(run, stage, member, gear)
        sense = 1.0 if float(spin[-1] - spin[0]) >= 0 else -1.0
        position = positions[int(member.removeprefix("planet")) - 1]
        average = planet_synchronous_average(
            signal, direction * carrier, sense * spin, position, **window
        )
    angles = "simulated" if tachometer is None else f"tachometer, {tachometer} pulses/turn"
    if tachometer is not None:
        angles += f", jitter {jitter:g} s"
    return average.assign_attrs(gear=gear, teeth=teeth, angles=angles)


def gear_indicator_values(average: xr.DataArray, history: list | None = None) -> dict[str, float]:
    """The condition indicators of a gear's average (mesh order = its tooth count)."""
    return gear_indicators(average.values, int(average.attrs["teeth"]), history=history)
