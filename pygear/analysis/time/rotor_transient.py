"""Transient of a plain rotor's scene: run-ups through critical speeds, constant speeds.

:func:`rotor_transient_problem` turns a :class:`~pygear.model.rotor_case.RotorCase` and
one of its :class:`~pygear.model.rotor_transient.RotorScene` into a
:class:`~pygear.kernel.newmark.BandedNewmark` integrator of the rotor's assembled
matrices (:func:`~pygear.assembly.drivetrain.assemble_drivetrain`, spatial DOF set)
with its gyroscopic matrix at the scene's speed profile and the unbalances at their
discs (:mod:`pygear.kernel.newmark_rotor`); :func:`run_rotor_transient` runs it and
returns the run's dataset: the x and y displacement of every disc over ``time``, as a
gearbox run lays out its probes (``displacement`` over ``displacement_target``), the
orbit's radius per disc and the speed.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ...assembly.drivetrain import DrivetrainModel, assemble_drivetrain, node_number
from ...errors import CaseError
from ...kernel.newmark import BandedNewmark, KernelProbe, RunResult
from ...kernel.newmark_rotor import RotorTerms, Unbalance
from ...model.rotor_case import RotorCase
from ...model.rotor_transient import RotorScene
from ..signals.probes import RPM_PER_RAD_S
from .run_layout import grouped_variables

__all__ = ["RotorTransientProblem", "rotor_transient_problem", "run_rotor_transient"]


@dataclass
class RotorTransientProblem:
    """A rotor scene set up for the kernel: model, integrator, probes, disc DOFs."""

    case: RotorCase
    scene: RotorScene
    model: DrivetrainModel
    solver: BandedNewmark
    probes: list[KernelProbe]
    disc_dofs: dict[str, tuple[int, int]]

    @property
    def formulation(self) -> str:
        """What ``pygear run`` prints as the model's formulation."""
        return "shaft elements"

    @property
    def dof_set(self) -> str:
        """The model's DOF set (spatial)."""
        return self.model.dof_set

    @property
    def size(self) -> int:
        """Number of DOFs."""
        return self.model.size


def rotor_transient_problem(case: RotorCase, scene: RotorScene) -> RotorTransientProblem:
    """Assemble the rotor and set up the scene's integrator; nothing is integrated.

    Raises
    ------
    CaseError
        A bearing whose coefficients change with speed on a profile whose speed
        changes (the kernel holds K and C constant over a run).
    """
    path = f"scenes.{scene.name}.run"
    run = scene.run
    run.validate(path)
    model = assemble_drivetrain(case, dof_set="spatial")
    speeds = np.asarray(run.speeds_rpm, dtype=float)
    varying = [t.name for t in model.bearing_tables if t.coefficients.speed_dependent]
    if varying and np.ptp(speeds) > 0:
        raise CaseError(
            f"{path}.speeds_rpm: bearing {varying[0]!r} has speed-dependent coefficients, "
            "which a transient holds constant; run it at one speed (one sample)"
        )
    stiffness, damping = model.at_speed(float(speeds[0]))
    drivetrain = case.drivetrain
    disc_dofs = {}
    for disc in drivetrain.discs:
        node = f"{disc.shaft}_{node_number(drivetrain.shaft(disc.shaft), disc.position)}"
        disc_dofs[disc.name] = (model.index(f"{node}.x"), model.index(f"{node}.y"))
    unbalances = tuple(
        Unbalance(
            *disc_dofs[u.disc],
            mass_eccentricity=u.mass_eccentricity,
            angle=math.radians(u.phase_deg),
            ratio=model.speed_ratios.get(drivetrain_shaft(case, u.disc), 1.0),
        )
        for u in run.unbalances
    )
    terms = RotorTerms(
        model.gyroscopic,
        times=tuple(float(t) for t in run.times),
        speeds=tuple(float(s) / RPM_PER_RAD_S for s in speeds),
        unbalances=unbalances,
    )
    probes = []
    for disc, dofs in disc_dofs.items():
        for axis, dof in zip(("x", "y"), dofs):
            row = np.zeros(model.size)
            row[dof] = 1.0
            label = f"{disc}.{axis}"
            attrs = {"quantity": "displacement", "target": label, "label": label, "units": "m"}
            probes.append(KernelProbe(f"displacement_{disc}_{axis}", "displacement", row,
                                      attrs=attrs))  # fmt: skip
    solver = BandedNewmark(
        model.mass,
        damping,
        stiffness,
        run.time_step,
        integrator=run.integrator,
        tolerance=run.tolerance,
        labels=model.labels,
        rotor=terms,
    )
    return RotorTransientProblem(case, scene, model, solver, probes, disc_dofs)


def drivetrain_shaft(case: RotorCase, disc: str) -> str:
    """The shaft a disc sits on."""
    return next(d.shaft for d in case.drivetrain.discs if d.name == disc)


def run_rotor_transient(
    case: RotorCase, scene: RotorScene, *, progress=None, problem=None
) -> xr.Dataset:
    """Run the scene and return its dataset (nothing is written)."""
    started = time.perf_counter()
    problem = problem or rotor_transient_problem(case, scene)
    run = scene.run
    result = problem.solver.run(
        run.steps, problem.probes, decimation=run.decimation, progress=progress
    )
    dataset = rotor_dataset(problem, result)
    dataset.attrs["wall_s"] = time.perf_counter() - started
    return dataset


def rotor_dataset(problem: RotorTransientProblem, result: RunResult) -> xr.Dataset:
    """The run's channels grouped as a gearbox run's, with the speed and each disc's
    orbit radius sqrt(x^2 + y^2)."""
    run = problem.scene.run
    series = [(p.name, values, p.attrs) for p, values in zip(problem.probes, result.samples)]
    data_vars, coords = grouped_variables(series)
    coords["time"] = ("time", result.time, {"units": "s", "long_name": "time since the start"})
    speed = np.interp(result.time, run.times, run.speeds_rpm)
    data_vars["speed"] = (("time",), speed, {"units": "rpm", "long_name": "rotor speed"})
    discs = list(problem.disc_dofs)
    radius = np.array(
        [np.hypot(result.samples[2 * k], result.samples[2 * k + 1]) for k in range(len(discs))]
    )
    coords["disc"] = ("disc", discs, {"long_name": "disc"})
    data_vars["orbit_radius"] = (
        ("disc", "time"),
        radius,
        {"units": "m", "long_name": "distance of the disc centre from the axis"},
    )
    peak = radius.argmax(axis=1)
    data_vars["peak_radius"] = (
        ("disc",), radius[np.arange(len(discs)), peak],
        {"units": "m", "long_name": "largest orbit radius of the run"},
    )  # fmt: skip
    data_vars["peak_speed"] = (
        ("disc",), speed[peak], {"units": "rpm", "long_name": "rotor speed at the largest radius"},
    )  # fmt: skip
    attrs = {
        "case": problem.case.name,
        "scene": problem.scene.name,
        "analysis": "rotor_transient",
        "dofs": problem.model.size,
        "time_step": run.time_step,
        "integrator": run.integrator,
        "linear_solver": problem.solver.linear_solver,
        "steps": result.steps,
        "iterations": result.counters["iterations"],
        "solver_wall_s": result.solver_wall_s,
    }
    return xr.Dataset(data_vars, coords, attrs)


def rotor_summary(dataset: xr.Dataset) -> dict:
    """Each disc's largest orbit radius and the speed it came at."""
    return {
        "peaks": {
            str(d): {
                "radius_m": float(dataset.peak_radius.sel(disc=d)),
                "speed_rpm": float(dataset.peak_speed.sel(disc=d)),
            }
            for d in dataset.disc.values
        },
        "steps": int(dataset.attrs["steps"]),
        "iterations": int(dataset.attrs["iterations"]),
    }
