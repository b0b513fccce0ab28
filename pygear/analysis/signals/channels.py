"""The channels of a run file: how probes are grouped by kind, and names that pick one.

A transient's file (docs/data_model.md) groups its probes by kind into variables over
``time`` and one label dimension each, so that a notebook selects by name::

    run.speed.sel(member="planetary.sun")
    run.mesh_force.sel(mesh="planetary.sun-planet1")
    run.rotation_acceleration.sel(rotation_dof="planetary.sun.theta_z")

(a file read back by :func:`pygear.io.open_dataset`, or with
:func:`pygear.io.index_labels` as ``preprocess``).  A DOF quantity is split by unit
(CF gives a variable one ``units``): translations in ``translation_<quantity>
(translation_dof, time)`` [m, m/s, m/s^2], rotations in ``rotation_<quantity>
(rotation_dof, time)`` [rad, rad/s, rad/s^2].  Variables sharing a
label dimension hold NaN at a label their quantity was not asked for.  A probe given a
``name`` keeps a variable of that name over ``time`` alone.

One series is named by a *channel name*: ``<kind>:<label>`` for a grouped variable
(``acceleration:planetary.sun.theta_z``, ``speed:planetary.sun``,
``mesh_force:planetary.sun-planet1``, ``sensor_acceleration:ring_sensor``), or the
variable's own name for a variable over ``time`` alone (``drive_torque``, a named
probe, a channel of a file not written by pygear).  :func:`channel_series` resolves
such a name, the label alone when one channel has it, a grouped variable's name when
it holds one channel, and the grouped variable's name or the probe's quantity in place
of the kind (``rotation_acceleration:planetary.sun.theta_z``, ``sensor:ring_sensor``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from .probes import ROTATIONS

__all__ = [
    "ChannelLayout",
    "SENSOR_COORDINATES",
    "channel_file_part",
    "channel_layout",
    "channel_names",
    "channel_series",
    "find_channel",
    "run_channels",
]

DOF_QUANTITIES = ("displacement", "velocity", "acceleration")


@dataclass(frozen=True)
class ChannelLayout:
    """Where a probe's series lives in a run file.

    ``variable`` over (``time``, ``dimension``), at ``label`` of ``dimension``; a
    ``dimension`` of None: a variable over ``time`` alone.  ``kind`` leads its channel
    name (the variable's name without a ``translation_`` or ``rotation_`` prefix).
    """

    variable: str
    dimension: str | None
    kind: str


def channel_layout(quantity: str, target: str) -> ChannelLayout:
    """The grouped variable and label dimension of an unnamed probe.

    Parameters
    ----------
    quantity : str
        The probe's quantity (:data:`pygear.model.transient_settings.PROBE_QUANTITIES`).
    target : str
        Its target, as the file labels it.
    """
    if quantity == "speed":
        return ChannelLayout("speed", "member", "speed")
    if quantity in DOF_QUANTITIES:
        kind = "rotation" if target.rsplit(".", 1)[-1] in ROTATIONS else "translation"
        return ChannelLayout(f"{kind}_{quantity}", f"{kind}_dof", quantity)
    if quantity.startswith("mesh_"):
        return ChannelLayout(quantity, "mesh", quantity)
    if quantity == "bearing_force":
        if target.rsplit(".", 1)[-1].startswith("theta"):
            return ChannelLayout("bearing_moment", "bearing_rotation", "bearing_moment")
        return ChannelLayout("bearing_force", "bearing", "bearing_force")
    if quantity == "sensor":
        return ChannelLayout("sensor_acceleration", "sensor", "sensor_acceleration")
    return ChannelLayout(quantity, None, quantity)  # drive_torque, load_torque


SENSOR_COORDINATES = {
    "sensor_stage": "sensor_stage",
    "sensor_angle": "sensor_angle_deg",
    "sensor_direction": "sensor_direction",
    "sensor_window": "sensor_window",
    "sensor_window_width": "sensor_window_width_deg",
    "sensor_mesh_gain": "sensor_mesh_gain",
    "sensor_bearing_gain": "sensor_bearing_gain",
    "sensor_structure_modes": "sensor_structure_modes",
    "sensor_noise_snr": "sensor_noise_snr_db",
    "sensor_noise_seed": "sensor_noise_seed",
    "sensor_planet_angle": "sensor_planet_angles_deg",
    "sensor_teeth": "sensor_teeth_sun_planet_ring",
}
"""Coordinates along ``sensor`` of a run file, and the attribute each becomes on one
sensor's series (:func:`channel_series`), where the synchronous averages read them."""


def _label_dimension(variable: xr.DataArray) -> str | None:
    """The label dimension of a grouped variable (over it and ``time``), else None."""
    if variable.ndim != 2 or "time" not in variable.dims or "quantity" not in variable.attrs:
        return None
    (dimension,) = (str(d) for d in variable.dims if d != "time")
    return dimension if dimension in variable.coords else None


def _recorded(variable: xr.DataArray) -> np.ndarray:
    """Which labels of a grouped variable hold a series (a probe never starts at NaN)."""
    first = np.asarray(variable.isel(time=0).values, dtype=float)
    return ~np.isnan(first)


def run_channels(run: xr.Dataset) -> dict[str, tuple[str, str | None, str | None]]:
    """Every channel of ``run``: ``{channel name: (variable, dimension, label)}``.

    Grouped variables give one channel per recorded label (in file order), variables
    over ``time`` alone one each under their own name.
    """
    found: dict[str, tuple[str, str | None, str | None]] = {}
    for name, variable in run.data_vars.items():
        if variable.dims == ("time",):
            found[str(name)] = (str(name), None, None)
        elif _label_dimension(variable) is not None:
            dimension = str(_label_dimension(variable))
            kind = str(name).removeprefix("translation_").removeprefix("rotation_")
            labels = [str(label) for label in variable[dimension].values]
            for label, recorded in zip(labels, _recorded(variable)):
                if recorded:
                    found[f"{kind}:{label}"] = (str(name), dimension, label)
    return found


def channel_names(run: xr.Dataset) -> list[str]:
    """The channel names of ``run`` (for messages and ``--channel`` choices)."""
    return list(run_channels(run))


def _resolve(run: xr.Dataset, name: str) -> tuple[str, str | None, str | None] | None:
    channels = run_channels(run)
    if name in channels:
        return channels[name]
    prefix, colon, label = name.partition(":")
    if colon:
        for variable, dimension, known in channels.values():
            if known != label:
                continue
            aliases = {variable, str(run[variable].attrs.get("quantity", ""))}
            if prefix in aliases:
                return variable, dimension, known
        return None
    matches = [entry for entry in channels.values() if entry[2] == name]
    if not matches:  # a grouped variable's name, when it holds one channel
        matches = [entry for entry in channels.values() if entry[0] == name]
    return matches[0] if len(matches) == 1 else None


def channel_series(run: xr.Dataset, name: str) -> xr.DataArray | None:
    """One channel of ``run`` over ``time``, or None when ``run`` has no such channel.

    The series keeps its variable's attributes, with ``long_name`` for the one series,
    ``target`` (its label) and ``channel`` (its channel name); a sensor's series also
    carries the sensor's coordinates as attributes (:data:`SENSOR_COORDINATES`).
    """
    found = _resolve(run, name)
    if found is None:
        return None
    variable, dimension, label = found
    if dimension is None:
        series = run[variable].reset_coords(drop=True)
        return series.assign_attrs(channel=variable)
    grouped = run[variable]
    series = grouped.sel({dimension: label})
    attrs = dict(grouped.attrs)
    kind = variable.removeprefix("translation_").removeprefix("rotation_")
    quantity = str(attrs.get("quantity", kind))
    attrs.update(
        long_name=f"{kind.replace('_', ' ')} of {label}",
        target=label,
        channel=f"{kind}:{label}",
    )
    if dimension == "sensor":
        attrs["quantity"] = quantity
        for coordinate, key in SENSOR_COORDINATES.items():
            if coordinate in run.variables and "sensor" in run[coordinate].dims:
                attrs[key] = _attribute_value(run[coordinate].sel(sensor=label).values)
    return series.reset_coords(drop=True).rename(variable).assign_attrs(attrs)


def _attribute_value(values: np.ndarray):
    if values.ndim == 0:
        value = values.item()
        if isinstance(value, float) and math.isnan(value):
            return "none"
        return value
    flat = [v for v in values.tolist() if not (isinstance(v, float) and math.isnan(v))]
    return flat


def find_channel(run: xr.Dataset, quantity: str, target: str) -> xr.DataArray | None:
    """The series of ``quantity`` at ``target`` (a probe's quantity and target), grouped
    or a named probe's; None when the run did not record it."""
    layout = channel_layout(quantity, target)
    if layout.dimension is None:
        return channel_series(run, layout.variable)
    found = channel_series(run, f"{layout.kind}:{target}")
    if found is not None:
        return found
    for name, variable in run.data_vars.items():
        attrs = variable.attrs
        if variable.dims == ("time",) and (attrs.get("quantity"), attrs.get("target")) == (
            quantity,
            target,
        ):
            return run[name].assign_attrs(channel=str(name))
    return None


def channel_file_part(name: str) -> str:
    """A channel name as part of a file name: ``:`` becomes ``_``, dots stay."""
    return name.replace(":", "_").replace("/", "_")
