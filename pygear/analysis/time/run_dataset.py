"""A transient run's dataset as docs/data_model.md lays it out, whole or in blocks.

:func:`run_dataset` builds the dataset of a run held in memory; a streamed run
(:mod:`pygear.runs.streaming`) builds the same variables block by block with
:func:`channel_variables` and adds, at its end, what only the end gives
(:func:`summary_variables`, :func:`result_attributes`): the two paths share every
layout rule, so their files are equal.  ``problem`` is a
:class:`pygear.analysis.time.transient.TransientProblem` and ``result`` a
:class:`pygear.kernel.newmark.RunResult` throughout.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import xarray as xr

from ...assembly.dof_rows import dof_row
from ...assembly.effects import effect_attributes
from ...assembly.matrices import Model
from ...model.case import Case, defects_json
from ...model.components import PlanetaryStage
from ..condition.sensor_signal import AUXILIARY_PREFIX, sensor_signal
from ..signals.probes import RPM_PER_RAD_S
from .run_layout import grouped_variables, sensor_coordinates

__all__ = [
    "channel_series",
    "channel_variables",
    "equilibrium_table",
    "result_attributes",
    "run_dataset",
    "sample_times",
    "static_attributes",
    "summary_variables",
    "time_coordinate",
]


def equilibrium_table(model: Model, mean_velocity: np.ndarray) -> dict:
    """Member speeds [rpm] and planet tangential speeds [m/s] from mean DOF velocities.

    Keys are the bodies' names (``planetary.carrier``, ``stage1.sun``), as a run file's
    ``body`` and ``member`` coordinates give them.  A planet's speed is its theta_z DOF:
    the spin relative to the carrier (improved, consistent) or in the carrier frame
    (lin-parker).
    """
    speeds, tangential = {}, {}
    for node in model.nodes:
        if node.role == "housing":
            continue
        key = node.name
        row = dof_row(model, f"{node.name}.theta_z")
        if row is not None:
            speeds[key] = float(row @ mean_velocity * RPM_PER_RAD_S)
        eta = dof_row(model, f"{node.name}.eta")
        if node.role == "planet" and eta is not None:
            tangential[key] = float(eta @ mean_velocity)
    return {"speed_rpm": speeds, "tangential_speed": tangential}


def run_dataset(problem, result) -> xr.Dataset:
    """The run as docs/data_model.md lays it out: channels grouped by kind over labels."""
    data_vars, coords = channel_variables(problem, result.samples)
    summary_vars, summary_coords = summary_variables(problem, result)
    data_vars.update(summary_vars)
    coords["time"] = time_coordinate(result.time)
    coords.update(summary_coords)
    attrs = {**static_attributes(problem), **result_attributes(problem, result)}
    return xr.Dataset(data_vars, coords, _in_order(attrs))


def time_coordinate(values: np.ndarray) -> tuple:
    """The ``time`` coordinate over the sample times ``values`` [s]."""
    return ("time", values, {"units": "s", "long_name": "time since the start"})


def sample_times(problem, first: int, count: int) -> np.ndarray:
    """Times of samples ``first .. first + count - 1`` of a run [s], as
    :meth:`BandedNewmark.run` gives them (sample k at k decimation time_step)."""
    settings = problem.settings
    return np.arange(first, first + count) * settings.decimation * problem.solver.time_step


def channel_series(
    problem, samples: np.ndarray, sensor: Callable | None = None
) -> tuple[list, list]:
    """Each output channel of ``samples`` (probe, sample) as (name, values, attrs), and
    each grouped sensor's (name, attrs).

    ``sensor(plan, auxiliary)`` gives a sensor's values and attributes from its
    auxiliary channels (default: :func:`sensor_signal` over the whole record; a
    streamed run passes one that carries its filter state from block to block).
    """
    settings = problem.settings
    series = []
    auxiliary = {}
    for probe, values in zip(problem.probes, samples):
        if problem.sensors and probe.name.startswith(AUXILIARY_PREFIX):
            auxiliary[probe.name] = values
            continue
        if probe.kind == "drive_torque":  # as the case gives it (kernel: mirrored)
            values = problem.drive_sign * values
        series.append((probe.name, values, probe.attrs))
    sensors = []
    if problem.sensors:
        rate = 1.0 / (settings.decimation * settings.time_step)
        if sensor is None:

            def sensor(plan, channels):
                return sensor_signal(plan, channels, rate)

        for plan in problem.sensors:
            values, attrs = sensor(plan, auxiliary)
            if plan.named:
                series.append((plan.variable, values, {**attrs, "named": True}))
            else:
                series.append((plan.variable, values, {**attrs, "label": plan.sensor.name}))
                sensors.append((plan.sensor.name, attrs))
    return series, sensors


def channel_variables(
    problem, samples: np.ndarray, sensor: Callable | None = None
) -> tuple[dict, dict]:
    """The variables over ``time`` of a record (or of a block of it) and their label
    coordinates (:func:`grouped_variables`, :func:`sensor_coordinates`)."""
    series, sensors = channel_series(problem, samples, sensor)
    data_vars, coords = grouped_variables(series)
    coords.update(sensor_coordinates(sensors))
    return data_vars, coords


def summary_variables(problem, result) -> tuple[dict, dict]:
    """The variables a run gives once it is over (equilibrium speeds over the mean
    window, planet tangential speeds, t_s), from the kernel's final state (the window's
    velocity sum), never from the samples; and their coordinates."""
    settings = problem.settings
    table = equilibrium_table(problem.model, result.mean_velocity)
    bodies = list(table["speed_rpm"])
    planets = list(table["tangential_speed"])
    data_vars = {}
    data_vars["equilibrium_speed"] = (
        ("body",),
        np.array([table["speed_rpm"][m] for m in bodies]),
        {
            "units": "rpm",
            "long_name": f"mean theta_z speed over the last {settings.mean_window:g} s",
        },
    )
    data_vars["planet_tangential_speed"] = (
        ("planet",),
        np.array([table["tangential_speed"][p] for p in planets]),
        {
            "units": "m/s",
            "long_name": f"mean eta velocity over the last {settings.mean_window:g} s",
        },
    )
    data_vars["t_s"] = (
        (),
        result.t_s,
        {"units": "s", "long_name": "first instant the input speed reaches omega_0"},
    )
    coords = {
        "body": ("body", np.array(bodies, dtype=object), {"long_name": "rotating body"}),
        "planet": ("planet", np.array(planets, dtype=object), {"long_name": "planet"}),
    }
    return data_vars, coords


def static_attributes(problem) -> dict:
    """The attributes of a run file known before it runs (settings, solver, effects)."""
    model, settings, solver = problem.model, problem.settings, problem.solver
    c = solver.coefficients
    attrs = {
        "case": problem.case.name,
        "scene": problem.scene.name,
        "formulation": model.formulation,
        "dof_set": model.dof_set,
        "whole_drivetrain": int(model.attributes.get("drivetrain", 0)),
        "start_loaded": int(settings.start_loaded),
        "effects": ", ".join(problem.effects) or "none (constant mesh stiffness)",
        "integrator": settings.integrator,
        "spectral_radius": c["rho_inf"],
        "newmark_beta": c["beta"],
        "newmark_gamma": c["gamma"],
        "alpha_m": c["alpha_m"],
        "alpha_f": c["alpha_f"],
        "equivalent_load": solver.equivalent_load,
        "tolerance": settings.tolerance,
        "time_step": settings.time_step,
        "sample_rate": 1.0 / (settings.decimation * settings.time_step),
        "bandwidth": solver.bandwidth,
        "linear_solver": solver.linear_solver,  # pygear.kernel.newmark_support
        "linear_solver_reason": solver.linear_solver_reason,
        "input": problem.input_label,
        "output": problem.output_label,
        "drive": settings.drive.describe() if settings.drive else "none",
        "load": settings.load.describe() if settings.load else "none",
        "speed_ratio": problem.ratio,
        "speed_reference_rpm": settings.speed_reference_rpm or 0.0,
        "rayleigh_alpha": problem.case.damping.mass_coefficient,
        "rayleigh_beta": problem.case.damping.stiffness_coefficient,
        "contact_sign": " ".join(str(int(s)) for s in problem.contact_sign),
        "mean_window": settings.mean_window,
        **effect_attributes(model, solver.equivalent_load),  # pygear.assembly.effects
    }
    attrs["tooth_defects"] = defects_json(problem.case, problem.scene)
    return attrs


def result_attributes(problem, result) -> dict:
    """The attributes a run gives once it is over: its length, the solver's wall time
    and counters, and the first ring's mesh frequency at the equilibrium speeds."""
    settings = problem.settings
    attrs = {
        "duration": result.steps * settings.time_step,
        "steps": result.steps,
        "solver_wall_s": result.solver_wall_s,
        **{f"solver_{k}": v for k, v in result.counters.items()},
    }
    table = equilibrium_table(problem.model, result.mean_velocity)
    ring, carrier = _first_ring_teeth(problem.case)
    if ring and carrier in table["speed_rpm"] and len(problem.case.gearbox.stages) == 1:
        attrs["mesh_frequency_hz"] = ring * table["speed_rpm"][carrier] / 60.0
    return attrs


_ATTRIBUTE_ORDER = (
    "case", "scene", "formulation", "dof_set", "whole_drivetrain", "start_loaded", "effects",
    "integrator", "spectral_radius", "newmark_beta", "newmark_gamma", "alpha_m", "alpha_f",
    "equivalent_load", "tolerance", "time_step", "duration", "sample_rate", "steps",
)  # fmt: skip


def _in_order(attrs: dict) -> dict:
    """``attrs`` with the leading keys in the order run files have always listed them."""
    head = {k: attrs[k] for k in _ATTRIBUTE_ORDER if k in attrs}
    return {**head, **{k: v for k, v in attrs.items() if k not in head}}


def _first_ring_teeth(case: Case) -> tuple[int | None, str]:
    """The ring's tooth count and the carrier's body name of the first planetary stage."""
    for stage in case.gearbox.stages:
        if isinstance(stage, PlanetaryStage):
            return stage.ring.teeth, f"{stage.name}.carrier"
    return None, ""
