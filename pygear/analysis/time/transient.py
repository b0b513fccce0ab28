"""Transient analysis of a scene: the run-up of docs/model.md §6.3 and its equilibrium table.

:func:`transient_problem` turns a case and a scene with ``Transient`` settings into
a :class:`~pygear.kernel.newmark.BandedNewmark` integrator with its laws, meshes and
probes; :func:`run_transient` runs it and returns an ``xarray.Dataset`` (the probes
grouped by kind over ``time`` and named labels, docs/data_model.md; the equilibrium
speeds, t_s and every setting as attributes).  Writing it to files is
:func:`pygear.runs.transient_outputs.write_transient`.
"""

from __future__ import annotations

import dataclasses
import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ...assembly.dof_rows import dof_row, rigid_rotation
from ...assembly.matrices import Model, assemble
from ...assembly.mesh_backlash import line_of_action_backlash
from ...errors import CaseError
from ...kernel.newmark import (
    BandedNewmark,
    KernelProbe,
    MeshTerms,
    RunResult,
    TransientError,
)
from ...kernel.newmark_rotor import RotorTerms
from ...linalg import generalized_eigh
from ...model.case import Case, Scene
from ...model.transient_settings import Transient
from ...rigid_modes import rigid_body_mask
from ..condition.sensor_signal import compile_scene_probes
from ..signals.probes import RPM_PER_RAD_S, state_probes
from .bearing_element import BEARING_EFFECT, bearing_terms, static_displacement
from .run_dataset import equilibrium_table
from .run_dataset import run_dataset as _dataset
from .transient_checks import (
    check_static_deflection,
    check_transient_memory,
    peak_torque,
    with_soft_mesh_cause,
)
from .transient_loads import default_member, kinematic_ratio, law_arrays, member_row

__all__ = [
    "TransientProblem",
    "equilibrium_table",
    "runup_table_text",
    "integrate",
    "transient_summary",
    "member_speeds",
    "static_mesh_deflections",
    "run_transient",
    "transient_problem",
]


@dataclass
class TransientProblem:
    """Everything a transient run needs, built and checked before it starts."""

    case: Case
    scene: Scene
    settings: Transient
    model: Model
    solver: BandedNewmark
    probes: list[KernelProbe]
    input_label: str
    output_label: str
    ratio: float
    contact_sign: np.ndarray
    effects: tuple[str, ...]
    drive_sign: int = 1  # -1: input member and drive law mirrored in the kernel
    static_deflection: np.ndarray | None = None  # per mesh, under the peak drive [m]
    sensors: tuple = ()  # SensorPlan per sensor probe (pygear.analysis.condition.sensor_signal)
    initial_velocity: np.ndarray | None = None  # reduced DOFs at t = 0, None: at rest
    initial_displacement: np.ndarray | None = None  # reduced DOFs at t = 0, None: undeflected


def static_mesh_deflections(
    model: Model, input_row: np.ndarray, output_row: np.ndarray | None, torque: float = 1.0
) -> np.ndarray:
    """Mesh deflections b_m . q of the static state under ``torque`` on the input member.

    The output member is held (a stiff torsional spring); without one, the drive is
    balanced by the inertia forces of the rigid-body acceleration (inertia relief).
    """
    k = np.array(model.stiffness, dtype=np.float64)
    force = torque * input_row
    if output_row is not None and np.any(output_row):
        k = k + 1e3 * np.abs(np.diag(k)).max() * np.outer(output_row, output_row)
    else:
        values, vectors = generalized_eigh(k, model.mass)
        rigid = vectors[:, rigid_body_mask(values)]
        force = force - model.mass @ rigid @ (rigid.T @ force)
    q = np.linalg.lstsq(k, force, rcond=None)[0]
    return np.array([mesh.deflection @ q for mesh in model.meshes])


def transient_problem(
    case: Case,
    scene: Scene,
    *,
    formulation: str | None = None,
    model: Model | None = None,
    check_memory: bool = True,
    reuse: bool = False,
) -> TransientProblem:
    """Assemble, check and set up the transient of ``scene``; nothing is integrated.

    ``check_memory`` False leaves out the check that the whole record fits in memory
    (a streamed run holds one block of it: :mod:`pygear.runs.streaming`).

    The problem built last (by a call without ``reuse``) is kept for one call with
    ``reuse`` and the same inputs (case, scene, formulation, model, the ``PYGEAR_``
    environment), which takes it over instead of building it again: the checks of
    every scene before a run (:func:`pygear.runs.scene_checks.check_scenes`) build each
    scene's problem, and the run (:func:`pygear.runs.transient_outputs.write_transient`)
    takes it.

    Raises
    ------
    CaseError
        A setting, a member or a probe target that does not fit the model.
    """
    path = f"scenes.{scene.name}.transient"
    settings = scene.transient
    if settings is None:
        raise CaseError(f"{path}: scene {scene.name!r} has no transient settings")
    settings.validate(path)
    key = _problem_key(case, scene, formulation, model)
    built = _LAST_BUILT.pop(key, None) if reuse else None
    if built is not None:
        if check_memory:
            check_transient_memory(settings, len(built.probes), path)
        return built
    problem = _new_problem(case, scene, formulation, model, check_memory, path)
    _LAST_BUILT.clear()
    if not reuse:  # a run's own problem is not handed to the next run
        _LAST_BUILT[key] = problem
    return problem


_LAST_BUILT: dict = {}
"""The problem built last, by :func:`_problem_key`: handed over once to the next call."""


def _problem_key(case: Case, scene: Scene, formulation: str | None, model: Model | None) -> str:
    """Digest of what a problem is built from: the case (but its other scenes), the
    scene, the formulation and the model's matrices when given."""
    from ... import io

    fields = {f.name: getattr(case, f.name) for f in dataclasses.fields(case) if f.name != "scenes"}
    matrices = ()
    if model is not None:
        matrices = tuple(_matrix_bytes(m) for m in (model.mass, model.damping, model.stiffness)) + (
            model.formulation,
            model.dof_set,
            tuple(model.dof_labels),
        )
    environment = sorted((k, v) for k, v in os.environ.items() if k.startswith("PYGEAR_"))
    return io.stable_digest((fields, scene, formulation, matrices, environment))


def _matrix_bytes(matrix) -> str:
    """A digest of a dense or SciPy sparse matrix's values."""
    import hashlib

    digest = hashlib.sha256()
    if hasattr(matrix, "tocsr"):
        matrix = matrix.tocsr()
        for part in (matrix.data, matrix.indices, matrix.indptr):
            digest.update(np.ascontiguousarray(part).tobytes())
    else:
        digest.update(np.ascontiguousarray(matrix, dtype=np.float64).tobytes())
    return digest.hexdigest()


def _new_problem(
    case: Case,
    scene: Scene,
    formulation: str | None,
    model: Model | None,
    check_memory: bool,
    path: str,
) -> TransientProblem:
    """:func:`transient_problem` built anew."""
    settings = scene.transient
    if model is None and case.drivetrain is not None:  # the whole drivetrain
        from ...assembly.drivetrain_model import drivetrain_transient_model

        model = drivetrain_transient_model(case, scene)
    model = model or assemble(case, scene, formulation=formulation)
    effects = tuple(scene.effects)
    varying = "time_varying_mesh_stiffness" in effects
    separation = "tooth_separation" in effects
    if settings.restart_at_jumps and separation:
        raise CaseError(
            f"{path}.restart_at_jumps does not combine with the tooth_separation effect "
            "(an open contact is a contact state, not a stiffness jump of the table)"
        )
    backlash = None
    if separation and model.meshes:
        # the teeth part within the backlash and meet again on the coast flanks
        backlash = line_of_action_backlash(case, model, "tooth_separation")
    input_label = settings.input or default_member(case, "carrier")
    output_label = settings.output or default_member(case, "sun")
    input_row = member_row(model, input_label, f"{path}.input")
    output_row = member_row(model, output_label, f"{path}.output")
    load = settings.load
    ratio = math.nan
    if load is not None and load.kind == "generator":
        ratio = load.ratio or kinematic_ratio(case, model, input_label, output_label)
        if ratio < 0:
            # the output turns against the input: the law acts on its speed along the
            # input's sense, so it still brakes the output's actual rotation
            output_row = -output_row
            ratio = -ratio
    elif load is not None and peak_torque(load) > 0:
        # a law of time brakes the output's rotation too: against the input's sense
        # when the output turns the other way (a parallel stage, a generator behind it)
        try:
            if kinematic_ratio(case, model, input_label, output_label) < 0:
                output_row = -output_row
        except CaseError:
            pass  # no one rigid rotation links them: the load acts along the output DOF
    omega_0 = (settings.speed_reference_rpm or 0.0) / RPM_PER_RAD_S
    direction = settings.drive.direction() if settings.drive is not None else 1

    n_mesh = len(model.meshes)
    if settings.contact_sign is not None:
        if len(settings.contact_sign) != n_mesh:
            raise CaseError(f"{path}.contact_sign must hold one sign per mesh ({n_mesh})")
        contact_sign = np.array(settings.contact_sign, dtype=np.int32)
    else:
        deflection = static_mesh_deflections(model, input_row, output_row, float(direction))
        contact_sign = np.where(deflection < 0, -1, 1).astype(np.int32)
    # a load holds the output at equilibrium (the mesh carries the whole drive torque);
    # without one the drive only accelerates the gearbox (inertia relief)
    held = output_row if peak_torque(settings.load) > 0 else None
    static = check_static_deflection(
        model, settings, static_mesh_deflections(model, input_row, held), path
    )
    meshes = None
    if n_mesh:  # without either effect the kernel only reads them for mesh probes
        table = None
        angle = np.zeros((n_mesh, model.size))
        if varying:
            from ...assembly.contact_table import build_contact_table

            sun_driven = ".sun." not in input_label
            table = build_contact_table(
                case, model, scene, direction=direction, sun_driven=sun_driven
            )
            for m, members in enumerate(table.angles):
                for member, sign in zip(members, (1.0, -1.0)):
                    row = dof_row(model, f"{member}.theta_z")
                    if row is not None:
                        angle[m] += sign * row
        meshes = MeshTerms(
            deflection=np.array([mesh.deflection for mesh in model.meshes]),
            mean_stiffness=np.array([mesh.mean_stiffness for mesh in model.meshes]),
            contact_sign=contact_sign,
            angle=angle,
            table=table,
            time_varying=varying,
            separation=separation,
            names=[mesh.name for mesh in model.meshes],
            backlash=backlash,
            damping=np.array([mesh.damping for mesh in model.meshes]),
        )
    # rolling bearings in place of their springs, only when the scene asks for them
    bearings = bearing_terms(case, model) if BEARING_EFFECT in effects else None
    probes, sensors = compile_scene_probes(case, model, settings.probes, f"{path}.probes")
    if settings.full_state:
        probes += state_probes(model)
    if check_memory:
        check_transient_memory(settings, len(probes), path)
    solver = BandedNewmark(
        model.mass,
        model.damping,
        model.stiffness,
        settings.time_step,
        rotor=shaft_gyroscopics(model),
        integrator=settings.integrator,
        spectral_radius=settings.spectral_radius,
        meshes=meshes,
        equivalent_load=settings.equivalent_load,
        tolerance=settings.tolerance,
        max_iterations=settings.max_iterations,
        refactor_threshold=settings.refactor_threshold,
        restart_at_jumps=settings.restart_at_jumps,
        # the kernel measures the input speed (t_s) along the drive's sense: a negative
        # drive runs with the input member and the drive law mirrored (same force)
        drive=law_arrays(settings.drive, ratio, omega_0, sign=direction),
        load=law_arrays(load, ratio, omega_0),
        input_weights=direction * input_row,
        output_weights=output_row,
        speed_reference=omega_0,
        deflection_limit=settings.deflection_limit,
        labels=model.dof_labels,
        bearings=bearings,
    )
    problem = TransientProblem(
        case,
        scene,
        settings,
        model,
        solver,
        probes,
        input_label,
        output_label,
        ratio,
        contact_sign,
        effects,
        drive_sign=direction,
        static_deflection=static,
        sensors=sensors,
    )
    problem.initial_velocity = initial_velocity(problem)
    if settings.start_loaded:
        problem.initial_displacement = loaded_displacement(problem)
    return problem


def shaft_gyroscopics(model: Model) -> RotorTerms | None:
    """A whole drivetrain's shafts and discs spinning at their speed ratios times the
    rotor's own speed (its theta_z rate in the run): the kernel's gyroscopic force; None
    for a gearbox or a torsional model (no entries)."""
    gyroscopic = getattr(model, "shaft_gyroscopic", None)
    if gyroscopic is None:
        return None
    row = dof_row(model, "rotor.theta_z")
    if row is None or not np.any(row):
        return None
    return RotorTerms(gyroscopic, source="rotation", speed_weights=row)


def run_transient(
    case: Case,
    scene: Scene,
    *,
    formulation: str | None = None,
    progress: Callable[[int, int], None] | None = None,
    checkpoint: str | os.PathLike | None = None,
    checkpoint_every: float = 60.0,
    resume: str | os.PathLike | None = None,
    problem: TransientProblem | None = None,
) -> xr.Dataset:
    """Run the transient of ``scene`` and return its dataset (nothing is written).

    Raises
    ------
    CaseError
        Bad settings, refused before the run.
    TransientError
        The run diverged (message: time, DOF or mesh, likely cause).
    TransientInterrupted
        Ctrl-C between two chunks.
    """
    started = time.perf_counter()
    problem = problem or transient_problem(case, scene, formulation=formulation)
    result = integrate(
        problem,
        progress=progress,
        checkpoint=checkpoint,
        checkpoint_every=checkpoint_every,
        resume=resume,
    )
    dataset = _dataset(problem, result)
    dataset.attrs["wall_s"] = time.perf_counter() - started
    return dataset


def integrate(
    problem: TransientProblem,
    *,
    progress: Callable[[int, int], None] | None = None,
    checkpoint: str | os.PathLike | None = None,
    checkpoint_every: float = 60.0,
    resume: str | os.PathLike | None = None,
    sink=None,
) -> RunResult:
    """Run ``problem``'s integrator over the scene's steps (samples kept, or handed to
    ``sink``: :class:`pygear.kernel.newmark.SampleSink`); a divergence under a soft mesh
    says so (:func:`with_soft_mesh_cause`)."""
    settings = problem.settings
    keyed = checkpoint is not None or resume is not None
    try:
        return problem.solver.run(
            settings.steps,
            problem.probes,
            v0=problem.initial_velocity,
            q0=problem.initial_displacement,
            decimation=settings.decimation,
            window_steps=int(round(settings.mean_window / settings.time_step)),
            progress=progress,
            checkpoint=checkpoint,
            checkpoint_every=checkpoint_every,
            resume=resume,
            identity=checkpoint_identity(problem) if keyed else "",
            sink=sink,
        )
    except TransientError as error:
        static = problem.static_deflection
        if static is None:
            raise
        raise with_soft_mesh_cause(error, problem.model, static, settings) from None


def initial_velocity(problem: TransientProblem) -> np.ndarray | None:
    """The rigid-body rotation at ``initial_speed_rpm`` of the input member, or None
    (from rest)."""
    speed = problem.settings.initial_speed_rpm / RPM_PER_RAD_S
    if speed == 0.0:
        return None
    rigid = rigid_rotation(problem.model)
    path = f"scenes.{problem.scene.name}.transient.initial_speed_rpm"
    input_speed = dof_row(problem.model, problem.input_label) @ rigid if rigid is not None else 0
    if rigid is None or abs(input_speed) < 1e-9 * np.abs(rigid).max():
        raise CaseError(
            f"{path}: the model has no single free rigid-body rotation that turns the input "
            f"member {problem.input_label!r}, so there is no steady rotation to start on"
        )
    return rigid * (speed / input_speed)


def loaded_displacement(problem: TransientProblem) -> np.ndarray:
    """The static deflection under the torques at t = 0 with inertia relief.

    The kernel's own torques at t = 0 (drive T_D on the input, load T_L against the
    output, at the initial speed) give the force f = T_D w_in - T_L w_out.  Its part
    along the rigid-body rotations, M Phi Phi^T f (Phi mass-normalised), accelerates
    the drivetrain; the rest deflects it: K0 q = f - M Phi Phi^T f with Phi^T M q = 0,
    solved as (K0 + M Phi Phi^T M) q = f - M Phi Phi^T f.  The equation of motion then
    gives the rigid-body acceleration at t = 0 and no elastic one (at mean mesh
    stiffness), so nothing swings.  With rolling bearings in the run the balance holds
    their Hertz law (:func:`.bearing_element.static_displacement`).
    """
    model, solver = problem.model, problem.solver
    state = solver.start(v0=problem.initial_velocity)
    drive, load = float(state["rstate"][1]), float(state["rstate"][2])
    force = drive * solver.input_weights - load * solver.output_weights
    stiffness = np.asarray(model.stiffness, dtype=np.float64)
    mass = np.asarray(model.mass, dtype=np.float64)
    values, vectors = generalized_eigh(stiffness, mass)
    rigid = vectors[:, rigid_body_mask(values)]
    relieved = force - mass @ rigid @ (rigid.T @ force)
    regularised = stiffness + mass @ rigid @ rigid.T @ mass
    linear = np.linalg.solve(regularised, relieved)
    if solver.bearings is None:
        return linear
    # rolling bearings: the same balance with their Hertz law in place of the springs
    return static_displacement(solver.bearings, regularised, relieved, linear)


def checkpoint_identity(problem: TransientProblem) -> str:
    """Hash (16 hex digits) of what shapes a run's state and file beyond the solver's
    arrays: every input of the case and of the scene but its list of analyses (which
    write other files), the model's formulation and DOF set, the members driven, and
    the code (:func:`pygear.io.source_identity`).  A checkpoint keyed by it resumes
    only the run that wrote it."""
    from ... import io

    case = {f.name: getattr(problem.case, f.name) for f in dataclasses.fields(problem.case)}
    case.pop("scenes", None)  # other scenes do not shape this one
    scene = {f.name: getattr(problem.scene, f.name) for f in dataclasses.fields(problem.scene)}
    scene.pop("analyses", None)
    model = problem.model
    return io.stable_digest(
        (
            case,
            scene,
            (model.formulation, model.dof_set, problem.input_label, problem.output_label),
            (problem.ratio, problem.contact_sign, problem.effects),
            io.source_identity(),
        )
    )


def member_speeds(dataset: xr.Dataset) -> dict[str, float]:
    """Equilibrium speeds [rpm] by member: ``carrier``, ``sun``, ... for a single stage
    (its name dropped), ``stage.member`` for a gearbox."""
    speeds = dict(zip(dataset.body.values.tolist(), dataset.equilibrium_speed.values.tolist()))
    stages = {str(name).split(".", 1)[0] for name in speeds}
    if len(stages) != 1:
        return speeds
    return {str(name).split(".", 1)[1]: value for name, value in speeds.items()}


def transient_summary(dataset: xr.Dataset) -> dict:
    """The numbers ``pygear run --json`` prints for a transient scene."""
    tangential = dataset.planet_tangential_speed.values
    t_s = float(dataset.t_s)
    return {
        "t_s": t_s if math.isfinite(t_s) else None,
        "equilibrium_speed_rpm": member_speeds(dataset),
        "planet_tangential_speed": float(tangential[0]) if tangential.size else None,
        "steps": int(dataset.attrs["steps"]),
        "solver_wall_s": float(dataset.attrs["solver_wall_s"]),
        "equivalent_load": dataset.attrs["equivalent_load"],
    }


def runup_table_text(datasets: dict[str, xr.Dataset]) -> str:
    """The run-up table (the seed's Table 3) of several runs side by side."""
    names = list(datasets)
    rows = [("", [datasets[n].attrs["formulation"] for n in names])]
    speeds = {n: member_speeds(datasets[n]) for n in names}

    def speed(name: str, member: str) -> float:
        return speeds[name].get(member, math.nan)

    rows.append(("t_s [s]", [f"{float(datasets[n].t_s):.4f}" for n in names]))
    members = list(speeds[names[0]])
    if "carrier" not in members:  # a gearbox: every member's speed, stage by stage
        for member in members:
            rows.append((f"{member} [rpm]", [f"{speed(n, member):.3f}" for n in names]))
        return _table_text(names, rows)
    for member in ("carrier", "sun", "planet1"):
        rows.append((f"{member} [rpm]", [f"{speed(n, member):.3f}" for n in names]))
    rows.append(("sun/carrier", [f"{speed(n, 'sun') / speed(n, 'carrier'):.5f}" for n in names]))
    rows.append(
        (
            "planet1 tangential [m/s]",
            [
                f"{float(datasets[n].planet_tangential_speed[0]):.4f}"
                if datasets[n].planet_tangential_speed.size
                else "-"
                for n in names
            ],
        )
    )
    return _table_text(names, rows)


def _table_text(names: list[str], rows: list[tuple[str, list[str]]]) -> str:
    label_width = max(26, *(len(label) + 2 for label, _ in rows))
    width = max(12, *(len(n) for n in names))
    lines = [f"{'':<{label_width}}" + "".join(f"{n:>{width + 2}}" for n in names)]
    lines += [
        f"{label:<{label_width}}" + "".join(f"{v:>{width + 2}}" for v in values)
        for label, values in rows
    ]
    return "\n".join(lines)
