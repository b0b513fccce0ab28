"""One point of a parameter sweep: checking the parameters, hashing a point's inputs,
and running its analyses into a NetCDF file (:func:`run_point`, a Dask task).

A point is known by its input hash (:func:`point_hash`), never by its place in a
sweep: its file holds its parameter values on length-1 dimensions, and a sweep of
either layout places it on its own grid or point list when it combines the files.

:mod:`pygear.runs.sweep` plans the points, runs them on Dask and combines the files.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
import os
import re
import sys
import time
import traceback
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from .._version import __version__
from ..analysis.modes.modal import modal_analysis
from ..analysis.modes.sensitivity import frequency_sensitivity, parse_values
from ..assembly.drivetrain_model import scene_model
from ..assembly.matrices import Model, assemble
from ..errors import CaseError
from ..io import atomic_path, source_identity, write_netcdf
from ..model.case import FORMULATIONS, Case, Scene, check_choice, get_parameter
from ..model.case import replace_parameter as _replace
from ..model.case_json import case_json
from ..resources import require_memory
from .cluster import task_files
from .plan_checks import disk_full

__all__ = [
    "NAN_IS_A_RESULT",
    "POINT_ANALYSES",
    "PointTask",
    "SweepParameter",
    "apply_assignments",
    "dimension_name",
    "disk_full",
    "error_message",
    "parse_param",
    "point_hash",
    "run_point",
    "scene_with",
    "sweep_points",
    "validate_sweep",
    "write_error_record",
]

SWEEP_FORMAT = "3"
"""Version of the point files; part of every point hash, so a change reruns the points."""

NAN_IS_A_RESULT = {"t_s": "the input speed never reaches omega_0 in the run"}
"""Point variables where NaN is an answer; NaN anywhere else marks a point file that
a rerun does not trust (it runs the point again)."""

_UNITS = {
    "carrier_speed_rpm": "rpm",
    "stiffness": "N/m",
    "radial": "N/m",
    "axial": "N/m",
    "tilt": "N m/rad",
    "torsional": "N m/rad",
    "mass": "kg",
    "polar_inertia": "kg m2",
    "tilt_inertia": "kg m2",
    "base_radius": "m",
    "radius": "m",
    "axial_position": "m",
    "pressure_angle_deg": "degree",
    "base_helix_angle_deg": "degree",
    "centre_angle_deg": "degree",
    "contact_ratio": "1",
    "overlap_ratio": "1",
    "end_to_peak": "1",
    "planets": "1",
    "teeth": "1",
    "mass_coefficient": "s-1",
    "stiffness_coefficient": "s",
}


# --------------------------------------------------------------------------- validation


def dimension_name(path: str) -> str:
    """The dimension a swept parameter's path names in the files: every ``.`` as ``__``
    (``planetary.sun_mesh.stiffness`` -> ``planetary__sun_mesh__stiffness``), any other
    character that is not a letter, digit or ``_`` as ``_``: a valid identifier, so that
    ``sweep.sel(planetary__sun_mesh__stiffness=4e8)`` takes it as a keyword."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", path.replace(".", "__"))
    return name if name[:1].isalpha() else f"p_{name}"


@dataclass(frozen=True)
class SweepParameter:
    """One swept parameter: its dotted path and its values (numbers, in the given order)."""

    path: str
    values: tuple

    @property
    def name(self) -> str:
        """Its dimension in the files (:func:`dimension_name`)."""
        return dimension_name(self.path)

    @property
    def attrs(self) -> dict[str, str]:
        """CF attributes of the parameter's coordinate; ``parameter_path`` is the path."""
        attrs = {"long_name": self.path, "parameter_path": self.path}
        units = _UNITS.get(self.path.rsplit(".", 1)[-1])
        if self.path.startswith(f"scene.{PIN_ERROR_PREFIX}"):
            units = "m"
        attrs["units"] = units or "1"
        return attrs


def parse_param(text: str) -> tuple[str, np.ndarray]:
    """Split ``stage.member.parameter=VALUES`` (VALUES as for :func:`parse_values`).

    Raises
    ------
    CaseError
        When the ``=`` is missing or the values are not numbers.
    """
    path, sep, values = str(text).partition("=")
    path = path.strip()
    if not sep or not path or not values.strip():
        raise CaseError(
            f"--param {text!r} must read stage.member.parameter=VALUES, e.g. "
            "planetary.sun_mesh.stiffness=logspace(7,10,7)"
        )
    return path, parse_values(values, name=f"--param {path}")


SCENE_PARAMETERS = ("carrier_speed_rpm",)
"""Scene settings a sweep may vary, as ``scene.<name>``: the carrier speed of a modal
scene's speed-dependent terms."""

PIN_ERROR_PREFIX = "response.pin_errors."
"""A response scene's planet pin error [m] is swept as ``scene.response.pin_errors.<planet>``
(``scene.response.pin_errors.planetary.planet1``)."""


def _parameter_values(case: Case, path: str, values: object) -> SweepParameter:
    if path.startswith("scene."):
        name = path.removeprefix("scene.")
        pin = name.startswith(PIN_ERROR_PREFIX) and len(name) > len(PIN_ERROR_PREFIX)
        if name not in SCENE_PARAMETERS and not pin:
            allowed = ", ".join(f"scene.{name}" for name in SCENE_PARAMETERS)
            raise CaseError(f"--param {path}: the scene settings a sweep varies are {allowed} "
                            f"and scene.{PIN_ERROR_PREFIX}<planet>")  # fmt: skip
        current: object = 0.0
    else:
        current = get_parameter(case, path)  # names the path when it does not exist
    if isinstance(current, bool) or not isinstance(current, (int, float)):
        raise CaseError(
            f"--param {path}: only numbers can be swept, and {path} holds "
            f"{type(current).__name__} {current!r}"
        )
    if isinstance(values, str) or (
        isinstance(values, Sequence) and values and all(isinstance(v, str) for v in values)
    ):
        array = parse_values(values, name=f"--param {path}")
    else:
        try:
            array = np.asarray(values, dtype=float).ravel()
        except (TypeError, ValueError):
            raise CaseError(f"--param {path}: values must be numbers (got {values!r})") from None
        if array.size == 0:
            raise CaseError(f"--param {path} needs at least one value")
        if not np.all(np.isfinite(array)):
            raise CaseError(f"--param {path}: values must be finite numbers (got {values!r})")
    if isinstance(current, int) and np.all(array == np.round(array)):
        return SweepParameter(path, tuple(int(v) for v in array))
    return SweepParameter(path, tuple(float(v) for v in array))


def validate_sweep(
    case: Case,
    params: Sequence[tuple[str, object]],
    *,
    zip_params: bool = False,
    scene: str | None = None,
    formulation: str | None = None,
) -> tuple[Scene, str, list[SweepParameter]]:
    """Check a sweep before any work: the scene, its formulation and every parameter.

    Returns
    -------
    scene, formulation, parameters
        The scene to run, the formulation in force and the parsed parameters.

    Raises
    ------
    CaseError
        Naming the parameter (unknown path, values not numbers, duplicate values,
        zipped lengths that differ) or the scene and the analysis it cannot run.
    """
    if not params:
        raise CaseError("--param: give at least one stage.member.parameter=VALUES")
    parsed = [_parameter_values(case, str(path), values) for path, values in params]
    paths = [p.path for p in parsed]
    names = [p.name for p in parsed]
    for path, name in zip(paths, names):
        if paths.count(path) > 1:
            raise CaseError(f"--param {path} is given twice")
        if names.count(name) > 1:
            raise CaseError(f"--param {path}: two paths give the dimension name {name!r}")
        if name in ("point", "mode", "body", "planet", "mesh"):
            raise CaseError(f"--param {path}: the name is taken by a dimension of the results")
    if zip_params:
        lengths = {p.path: len(p.values) for p in parsed}
        if len(set(lengths.values())) > 1:
            listed = ", ".join(f"{k} has {n}" for k, n in lengths.items())
            raise CaseError(f"--zip pairs values one to one, so their counts must agree: {listed}")
    else:
        for p in parsed:
            if len(set(p.values)) != len(p.values):
                raise CaseError(
                    f"--param {p.path}: a value is given twice in a grid ({list(p.values)})"
                )
    _check_point_memory(parsed, zip_params)
    chosen = case.scene(scene) if scene is not None else _default_scene(case)
    unsupported = [a for a in chosen.analyses if a not in POINT_ANALYSES]
    if unsupported:
        raise CaseError(
            f"scene {chosen.name!r} asks for {', '.join(map(repr, unsupported))}, which a sweep "
            f"of this pygear cannot run yet (supported: {', '.join(POINT_ANALYSES)}); "
            "pick another scene with --scene"
        )
    _check_scene_parameters(chosen, parsed)
    _check_values(case, chosen, parsed)
    check_choice("--formulation", formulation, FORMULATIONS, allow_none=True)
    resolved = formulation or chosen.formulation or case.formulation
    assemble(case.for_scene(chosen), chosen, formulation=resolved)  # e.g. lin-parker, 2 stages
    if case.drivetrain is not None:  # a point runs the whole drivetrain, dense
        from .plan_checks import check_drivetrain_memory

        check_drivetrain_memory(case, dense=True, dof_set=chosen.dof_set)
    return chosen, resolved, parsed


def _check_values(case: Case, scene: Scene, parsed: Sequence[SweepParameter]) -> None:
    """Every swept value set alone in the case (or the scene) and checked by the model's
    own validation, before any point is planned: a value no point can take is bad input.
    Values that are refused only together, on some points of a grid, fail those points."""
    for parameter in parsed:
        for value in dict.fromkeys(parameter.values):
            assignment = {parameter.path: value}
            try:
                apply_assignments(case, assignment, scene)
                scene_with(scene, assignment)
            except CaseError as error:
                raise CaseError(f"--param {parameter.path}={value!r}: {error}") from None


def _check_scene_parameters(scene: Scene, parsed: Sequence[SweepParameter]) -> None:
    """Refuse a swept carrier speed where it changes nothing or is not the scene's to set."""
    for parameter in parsed:
        if not parameter.path.startswith("scene."):
            continue
        if parameter.path.startswith(f"scene.{PIN_ERROR_PREFIX}"):
            if "response" not in scene.analyses:
                raise CaseError(f"--param {parameter.path}: scene {scene.name!r} has no "
                                "'response' analysis, whose pin errors this sets")  # fmt: skip
            continue
        if "transient" in scene.analyses:
            raise CaseError(
                f"--param {parameter.path}: scene {scene.name!r} runs a transient, whose "
                "run-up drives the speed itself; sweep a modal scene"
            )
        speed_effects = ("gyroscopic_all_members", "speed_dependent_planet_terms")
        if not any(effect in scene.effects for effect in speed_effects):
            raise CaseError(
                f"--param {parameter.path}: scene {scene.name!r} has no speed-dependent "
                f"effect ({' or '.join(map(repr, speed_effects))}), so the carrier speed "
                "changes none of its results"
            )


def _check_point_memory(parsed: Sequence[SweepParameter], zip_params: bool) -> None:
    """Refuse a grid whose points alone outgrow the memory: every point is held as its
    assignment dict (measured on the first one) before any runs, a lower bound."""
    count = len(parsed[0].values) if zip_params else math.prod(len(p.values) for p in parsed)
    first = {p.path: p.values[0] for p in parsed}
    size = sys.getsizeof(first) + sum(sys.getsizeof(v) for v in first.values())
    require_memory(
        "--param",
        count * size,
        f"{count:g} points x {size} bytes for each point's values, at least",
        "sweep fewer values",
    )


def _default_scene(case: Case) -> Scene:
    if not case.scenes:
        return Scene("modal")
    return case.scenes[0]


def sweep_points(parameters: Sequence[SweepParameter], zip_params: bool) -> list[dict]:
    """Parameter assignments of every point, in point-index order (C order for a grid)."""
    if zip_params:
        return [{p.path: p.values[i] for p in parameters} for i in range(len(parameters[0].values))]
    return [
        dict(zip([p.path for p in parameters], combo))
        for combo in itertools.product(*[p.values for p in parameters])
    ]


def apply_assignments(
    case: Case, assignments: Mapping[str, object], scene: Scene | None = None
) -> Case:
    """The case as ``scene`` sees it (its own parameter changes, as ``pygear run``
    applies them), then every parameter of ``assignments`` set (validated after each)."""
    if scene is not None:
        case = case.for_scene(scene)
    for path, value in assignments.items():
        if not path.startswith("scene."):
            case = _replace(case, path, value)
    return case


def scene_with(scene: Scene, assignments: Mapping[str, object]) -> Scene:
    """``scene`` with the swept scene settings (``scene.carrier_speed_rpm``) set and
    validated; the scene itself when the point sets none."""
    changes = {
        path.removeprefix("scene."): value
        for path, value in assignments.items()
        if path.startswith("scene.")
    }
    if not changes:
        return scene
    pins = {k.removeprefix(PIN_ERROR_PREFIX): float(v)
            for k, v in changes.items() if k.startswith(PIN_ERROR_PREFIX)}  # fmt: skip
    changes = {k: v for k, v in changes.items() if not k.startswith(PIN_ERROR_PREFIX)}
    if pins and scene.response is not None:
        errors = {**dict(scene.response.pin_errors), **pins}
        changes["response"] = dataclasses.replace(scene.response, pin_errors=errors)
    changed = dataclasses.replace(scene, **changes)
    changed.validate(f"scenes.{scene.name}")
    return changed


def point_hash(case: Case, scene: Scene, formulation: str) -> str:
    """Hash of a point's inputs: the modified case, the scene, the formulation, the
    pygear version, the identity of its Python and Fortran sources
    (:func:`pygear.io.source_identity`) and the point-file format."""
    identity = source_identity()
    text = "\n".join([repr(case), repr(scene), formulation, __version__, identity, SWEEP_FORMAT])
    return hashlib.sha256(text.encode()).hexdigest()[:16]


# --------------------------------------------------------------------------- one point


def _modal_point(case: Case, scene: Scene, model: Model) -> xr.Dataset:
    return modal_analysis(model).drop_vars(["shape", "dof"])


def _sensitivity_point(case: Case, scene: Scene, model: Model) -> xr.Dataset:
    return frequency_sensitivity(model)


def _transient_point(case: Case, scene: Scene, model: Model) -> xr.Dataset:
    """A run reduced to what a sweep compares: t_s, equilibrium speeds, and the RMS and
    peak of each mesh force's dynamic part over the averaging window."""
    from ..analysis.time.transient import run_transient

    run = run_transient(case, scene, formulation=model.formulation)
    window = float(run.attrs.get("mean_window", 1.0))
    late = run.sel(time=slice(float(run.time[-1]) - window, None))
    result = run[["t_s", "equilibrium_speed", "planet_tangential_speed"]]
    if "mesh_force" in late:  # recorded meshes only: a label of mesh_force may hold NaN
        force = late.mesh_force
        dynamic = force - force.mean("time")
        result["mesh_force_rms"] = np.sqrt((dynamic**2).mean("time")).assign_attrs(
            units="N",
            long_name=f"RMS of the dynamic part of each mesh force (last {window:g} s)",
        )
        result["mesh_force_peak"] = (
            abs(dynamic)
            .max("time")
            .assign_attrs(
                units="N",
                long_name=f"peak of the dynamic part of each mesh force (last {window:g} s)",
            )
        )
    return result


RESPONSE_POINT_VARIABLES = (
    "dynamic_factor",
    "dte_rms",
    "separation",
    "load_sharing",
    "load_sharing_peak",
    "floquet_multiplier",
    "stable",
    "harmonics",
    "residual",
)
"""What a sweep point keeps of a response: per speed (and mesh or stage), so the points
combine by their parameter coordinates while every point shares the scene's speeds."""


def _response_point(case: Case, scene: Scene, model: Model) -> xr.Dataset:
    """The scene's response over its speeds, reduced to :data:`RESPONSE_POINT_VARIABLES`
    (the contact-loss branch, whose points differ in number, adds the jump speeds of
    its first fold each way, NaN where there is none)."""
    from ..analysis.response import scene_response

    linear, branch = scene_response(case, scene)
    kept = [name for name in RESPONSE_POINT_VARIABLES if name in linear]
    result = linear[kept].drop_vars("mesh_order", errors="ignore")
    if scene.response.contact_loss:
        for key in ("up", "down"):
            jumps = np.atleast_1d(branch.attrs[f"{key}_sweep_jumps"]) if branch else []
            result[f"jump_{key}_rpm"] = ((), float(jumps[0]) if len(jumps) else math.nan, {
                "units": "rpm", "long_name": f"first {key}-sweep jump speed of the "
                "contact-loss branch (NaN: none)"})  # fmt: skip
    return result


POINT_ANALYSES: dict[str, Callable[[Case, Scene, Model], xr.Dataset]] = {
    "modal": _modal_point,
    "sensitivity": _sensitivity_point,
    "transient": _transient_point,
    "signal": lambda case, scene, model: xr.Dataset(),  # a sweep keeps no spectra
    "response": _response_point,
}
"""What a sweep point computes for each analysis a scene may ask for."""


RETURN_LIMIT = 1_000_000
"""A point's results up to this size [bytes] go back to the client with its record."""


@dataclass(frozen=True)
class PointTask:
    """Everything one point needs; run by :func:`run_point` on a Dask worker.

    ``index`` is the point's place in the sweep that runs it (for its record only);
    ``path`` and ``error_path`` are named by ``point_hash``.
    """

    index: int
    case: Case
    scene: Scene
    formulation: str
    assignments: dict
    path: str
    error_path: str
    point_hash: str
    attrs: tuple = ()


def run_point(task: PointTask) -> dict:
    """Run one point's analyses and write its file; never raises.

    Returns
    -------
    dict
        ``index``, ``point_hash``, ``status`` ("computed" or "failed"), ``wall_s``,
        ``error``, and the point's dataset as ``data`` when it is small
        (:data:`RETURN_LIMIT`).
    """
    started = time.perf_counter()
    try:
        model = scene_model(task.case, task.scene, formulation=task.formulation)
        parts = [POINT_ANALYSES[a](task.case, task.scene, model) for a in task.scene.analyses]
        data = xr.merge(parts, compat="override", join="outer", combine_attrs="override")
        data["point_wall_time"] = (
            (),
            time.perf_counter() - started,
            {"units": "s", "long_name": "wall time of the point's analyses"},
        )
        data = _place_point(data, task)
        data.attrs.update(dict(task.attrs))
        data.attrs.update(
            {
                "point_hash": task.point_hash,
                "point_parameters": json.dumps(task.assignments),
            }
        )
        with task_files():
            write_netcdf(
                data,
                task.path,
                title=f"Sweep point {task.point_hash} of {task.case.name}, scene {task.scene.name}",
                input_hash=task.case.input_hash(),
                case_json=case_json(task.case),
            )
        if os.path.exists(task.error_path):
            os.remove(task.error_path)
        record = {
            "index": task.index,
            "point_hash": task.point_hash,
            "status": "computed",
            "wall_s": time.perf_counter() - started,
        }
        if data.nbytes <= RETURN_LIMIT:
            record["data"] = data  # spares the client reading the file back
        return record
    except Exception as error:  # noqa: BLE001 - a point's failure must not stop the sweep
        record = {
            "index": task.index,
            "point_hash": task.point_hash,
            "status": "failed",
            "wall_s": time.perf_counter() - started,
        }
        if disk_full(error):  # the sweep stops: no other point can be written either
            return {
                **record,
                "error": f"no space left on device writing {task.path}",
                "disk_full": 1,
            }
        message = error_message(error)
        try:
            write_error_record(task.error_path, task, message, traceback.format_exc())
        except OSError as written:
            if not disk_full(written):
                raise
            message = f"no space left on device writing {task.error_path}"
            return {**record, "error": message, "disk_full": 1}
        return {**record, "error": message}


def error_message(error: BaseException) -> str:
    if isinstance(error, CaseError):
        return str(error)
    return f"{type(error).__name__}: {error}"


def _place_point(data: xr.Dataset, task: PointTask) -> xr.Dataset:
    """Give the point's parameter values as coordinates on length-1 dimensions named by
    :func:`dimension_name` (in either layout: a point file belongs to no sweep in
    particular), with each path in the coordinate's attributes."""
    data = data.expand_dims(
        {dimension_name(path): [value] for path, value in task.assignments.items()}
    )
    for path in task.assignments:
        data[dimension_name(path)].attrs.update(SweepParameter(path, ()).attrs)
    return data


def write_error_record(
    path: str | os.PathLike, task: PointTask, message: str, trace: str | None = None
) -> None:
    """Write ``point_<hash>.error.json``: the message, the parameters and the hash."""
    record = {
        "parameters": task.assignments,
        "error": message,
        "case": task.case.name,
        "scene": task.scene.name,
        "formulation": task.formulation,
        "point_hash": task.point_hash,
    }
    if trace and "CaseError" not in trace.splitlines()[-1]:
        record["traceback"] = trace
    with atomic_path(path) as temporary:
        Path(temporary).write_text(json.dumps(record, indent=1))
