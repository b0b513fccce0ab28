"""The probes of a run laid out as a file holds them: grouped by kind over named labels.

:func:`grouped_variables` turns a run's kernel channels into the variables of
docs/data_model.md: ``speed(member, time)``, ``translation_acceleration(translation_dof,
time)``, ``mesh_force(mesh, time)``, ``sensor_acceleration(sensor, time)``,
``drive_torque(time)``, ..., with one label coordinate per dimension, and a variable of
its own for each probe given a ``name``.  The label dimension comes first, as CF
(section 2.4) recommends for dimensions other than time.  Which variable and dimension
a probe lands in is :func:`pygear.analysis.signals.channels.channel_layout`.
"""

from __future__ import annotations

import math

import numpy as np

from ..signals.channels import channel_layout

__all__ = ["LABEL_NAMES", "VARIABLE_NAMES", "grouped_variables", "sensor_coordinates"]

LABEL_NAMES = {
    "member": "member of a stage (stage.member)",
    "translation_dof": "translational DOF (stage.member.dof)",
    "rotation_dof": "rotational DOF (stage.member.dof)",
    "mesh": "mesh (stage.mesh)",
    "bearing": "bearing spring, translational component (stage.bearing.component)",
    "bearing_rotation": "bearing spring, rotational component (stage.bearing.component)",
    "sensor": "sensor of the case",
}
"""The label dimensions of a run file and their long names."""

VARIABLE_NAMES = {
    "speed": "rotation speed (theta_z) of each member",
    "translation_displacement": "displacement of each translational DOF",
    "translation_velocity": "velocity of each translational DOF",
    "translation_acceleration": "acceleration of each translational DOF",
    "rotation_displacement": "angle of each rotational DOF",
    "rotation_velocity": "angular velocity of each rotational DOF",
    "rotation_acceleration": "angular acceleration of each rotational DOF",
    "mesh_force": "mesh force of each mesh, compression positive",
    "mesh_deflection": "deflection b.q of each mesh",
    "mesh_stiffness": "mesh stiffness in force of each mesh",
    "bearing_force": "bearing force k delta of each bearing spring component",
    "bearing_moment": "bearing moment k delta of each rotational bearing spring component",
    "sensor_acceleration": "acceleration at each sensor",
    "drive_torque": "drive torque on the input member",
    "load_torque": "load torque on the output member",
}
"""Every grouped variable a run file may hold, with its long name."""


def grouped_variables(
    series: list[tuple[str, np.ndarray, dict]],
) -> tuple[dict, dict]:
    """Data variables and label coordinates of a run's channels.

    Parameters
    ----------
    series : list of (name, values, attrs)
        Each channel: its probe's variable name, its samples over ``time`` and the
        attributes of :func:`pygear.analysis.signals.probes.compile_probes` (``quantity``,
        ``label``, ``named``, ``units``, ``long_name``).

    Returns
    -------
    (dict, dict)
        ``{name: (dims, values, attrs)}`` of the variables and ``{dimension: (dimension,
        labels, attrs)}`` of the label coordinates.  A grouped variable holds NaN at a
        label of its dimension that its quantity was not recorded at.
    """
    data_vars: dict = {}
    groups: dict[str, dict] = {}
    labels: dict[str, list[str]] = {}
    for name, values, attrs in series:
        attrs = dict(attrs)
        label = str(attrs.pop("label", attrs.get("target", "")))
        named = bool(attrs.pop("named", False))
        quantity = str(attrs.get("quantity", ""))
        layout = channel_layout(quantity, label)
        if named or quantity not in _QUANTITIES:
            data_vars[name] = (("time",), values, attrs)
            continue
        if layout.dimension is None:
            attrs["long_name"] = VARIABLE_NAMES[layout.variable]
            data_vars.setdefault(layout.variable, (("time",), values, attrs))
            continue
        group = groups.setdefault(
            layout.variable,
            {"dimension": layout.dimension, "columns": {}, "units": attrs.get("units", "1")},
        )
        group["columns"].setdefault(label, values)
        known = labels.setdefault(layout.dimension, [])
        if label not in known:
            known.append(label)
    for variable, group in groups.items():
        dimension = group["dimension"]
        order = labels[dimension]
        columns = group["columns"]
        length = len(next(iter(columns.values())))
        stacked = np.full((len(order), length), math.nan)
        for k, label in enumerate(order):
            if label in columns:
                stacked[k] = columns[label]
        quantity = "sensor" if variable == "sensor_acceleration" else _quantity(variable)
        data_vars[variable] = (
            (dimension, "time"),  # CF 2.4: other dimensions left of time
            stacked,
            {
                "units": group["units"],
                "long_name": VARIABLE_NAMES[variable],
                "quantity": quantity,
            },
        )
    coords = {
        dimension: (dimension, np.array(names, dtype=object), {"long_name": LABEL_NAMES[dimension]})
        for dimension, names in labels.items()
    }
    return data_vars, coords


_QUANTITIES = frozenset(
    {
        "displacement",
        "velocity",
        "acceleration",
        "speed",
        "mesh_deflection",
        "mesh_force",
        "mesh_stiffness",
        "bearing_force",
        "drive_torque",
        "load_torque",
        "sensor",
    }
)


def _quantity(variable: str) -> str:
    if variable == "bearing_moment":
        return "bearing_force"
    return variable.removeprefix("translation_").removeprefix("rotation_")


def sensor_coordinates(sensors: list[tuple[str, dict]]) -> dict:
    """Coordinates along ``sensor`` from each sensor's attributes
    (:func:`pygear.analysis.condition.sensor_signal.sensor_signal`), in the order of ``sensors``.

    Planet angles run along ``sensor_planet`` (NaN past a stage's planets), tooth counts
    along ``sensor_gear`` (sun, planet, ring; 0 where the case gives none).
    """
    if not sensors:
        return {}
    names = [name for name, _ in sensors]

    def column(key: str, dtype=object) -> np.ndarray:
        return np.array([attrs[key] for _, attrs in sensors], dtype=dtype)

    snr = [attrs["sensor_noise_snr_db"] for _, attrs in sensors]
    planets = max(len(attrs["sensor_planet_angles_deg"]) for _, attrs in sensors)
    angles = np.full((len(sensors), planets), math.nan)
    for k, (_, attrs) in enumerate(sensors):
        angles[k, : len(attrs["sensor_planet_angles_deg"])] = attrs["sensor_planet_angles_deg"]
    dims = ("sensor",)
    return {
        "sensor_stage": (dims, column("sensor_stage"), {"long_name": "stage of the sensor"}),
        "sensor_angle": (
            dims,
            column("sensor_angle_deg", float),
            {"units": "degree", "long_name": "angle of the sensor about the stage axis"},
        ),
        "sensor_direction": (
            dims,
            column("sensor_direction"),
            {"long_name": "measured direction (radial or tangential)"},
        ),
        "sensor_window": (
            dims,
            column("sensor_window"),
            {"long_name": "shape of the angle window through which a planet reaches the sensor"},
        ),
        "sensor_window_width": (
            dims,
            column("sensor_window_width_deg", float),
            {"units": "degree", "long_name": "width of the sensor's angle window"},
        ),
        "sensor_mesh_gain": (
            dims,
            column("sensor_mesh_gain", float),
            {"units": "m s-2 N-1", "long_name": "gain of the ring-mesh force path"},
        ),
        "sensor_bearing_gain": (
            dims,
            column("sensor_bearing_gain", float),
            {"units": "m s-2 N-1", "long_name": "gain of the ring-bearing force path"},
        ),
        "sensor_structure_modes": (
            dims,
            column("sensor_structure_modes", np.int32),
            {"units": "1", "long_name": "number of structural modes on the sensor's path"},
        ),
        "sensor_noise_snr": (
            dims,
            np.array([math.nan if v == "none" else float(v) for v in snr]),
            {
                "units": "1",
                "long_name": "signal-to-noise ratio of the added noise in decibels (NaN: no noise)",
            },
        ),
        "sensor_noise_seed": (
            dims,
            column("sensor_noise_seed", np.int64),
            {"units": "1", "long_name": "seed of the sensor's noise"},
        ),
        "sensor_planet_angle": (
            ("sensor", "sensor_planet"),
            angles,
            {
                "units": "degree",
                "long_name": "angle psi_n of each planet of the sensor's stage (NaN past "
                "its planets)",
            },
        ),
        "sensor_teeth": (
            ("sensor", "sensor_gear"),
            np.array([attrs["sensor_teeth_sun_planet_ring"] for _, attrs in sensors], np.int32),
            {"units": "1", "long_name": "tooth counts of the sensor's stage (0: not given)"},
        ),
        "sensor_gear": (
            ("sensor_gear",),
            np.array(["sun", "planet", "ring"], dtype=object),
            {"long_name": "gear of the sensor's stage a tooth count belongs to"},
        ),
        "sensor_planet": (
            ("sensor_planet",),
            np.arange(1, planets + 1, dtype=np.int32),
            {"units": "1", "long_name": "planet number n"},
        ),
        "sensor": (dims, np.array(names, dtype=object), {"long_name": LABEL_NAMES["sensor"]}),
    }
