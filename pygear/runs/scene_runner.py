"""The scene runner: run the analyses a scene names, write their files, draw their figures.

One place runs a scene, whoever asks: ``pygear run`` (:mod:`pygear.cli.run`) calls
:func:`run_scene` for each scene it is given, and a batch task
(:func:`pygear.runs.batch.run_scene_task`) calls it on a Dask worker.  Each analysis a
scene may name has one writer in :data:`SCENE_ANALYSES`; a scene naming one this
version cannot run gets it listed in its summary (``unsupported``) and the rest run.

Order within a scene: the model is assembled once and every analysis takes it; a
transient's NetCDF file and its signal analysis are written before any figure of it,
so that a run stopped while drawing has lost only pictures.  Sweeps reduce a point to
what they compare (:data:`pygear.runs.sweep_points.POINT_ANALYSES`) and share this
module's model step, :func:`scene_model_for`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from .cluster import task_files

if TYPE_CHECKING:
    import xarray as xr

    from ..analysis.modes.modal import ModalResult
    from ..assembly.matrices import Model
    from ..model.case import Case, Scene

__all__ = [
    "SCENE_ANALYSES",
    "RunOptions",
    "SceneOutcome",
    "modal_summary",
    "run_scene",
    "scene_model_for",
]


@dataclass(frozen=True)
class RunOptions:
    """How a scene is run and written.

    Attributes
    ----------
    formulation : str or None
        Overrides every scene's formulation (``None``: the scene's own).
    figures : bool
        Draw the figures after the NetCDF files.
    progress : callable or None
        ``progress(done, total)`` of a transient's time steps.
    checkpoint_every : float or None
        Wall-time seconds between checkpoints of a transient (``None``: none unless
        ``resume``).
    resume : bool
        Continue a transient from ``<scene>.checkpoint.npz`` when it exists.
    """

    formulation: str | None = None
    figures: bool = True
    progress: Callable[[int, int], None] | None = None
    checkpoint_every: float | None = None
    resume: bool = False


@dataclass
class SceneOutcome:
    """What running one scene gave: its model, its summary entry and its transient.

    ``summary`` holds ``formulation``, ``dof_set``, ``dofs``, ``files`` (paths as
    strings, in the order written), what each analysis reports (the modal table's
    numbers, a transient's ``t_s`` and equilibrium speeds, ...), ``unsupported`` (the
    analyses this version cannot run, if any) and ``wall_s``.
    """

    scene: str
    model: Model
    summary: dict = field(default_factory=dict)
    transient: xr.Dataset | None = None


@dataclass(frozen=True)
class _SceneContext:
    case: Case
    scene: Scene
    model: Model
    out: Path
    options: RunOptions


def modal_summary(modal: ModalResult) -> dict:
    """The numbers ``--json`` prints for a modal analysis
    (:func:`pygear.analysis.modes.modal.modal_results`)."""
    return {
        "case": modal.attrs["case"],
        "formulation": modal.attrs["formulation"],
        "dof_set": modal.attrs["dof_set"],
        "frequencies_hz": [float(f) for f in modal.frequency],
        "mode_class": [str(c) for c in modal.mode_class],
        "class_index": [int(i) for i in modal.class_index],
        "multiplicity": [int(m) for m in modal.multiplicity],
        "stage": [str(st) for st in modal.stage_name],
    }


def _modal(context: _SceneContext) -> tuple[dict, xr.Dataset | None]:
    from ..analysis.modes.modal import modal_dataset, modal_results
    from .outputs import write_modal_outputs

    modal = modal_results(context.model)
    with task_files():
        files = write_modal_outputs(
            context.case,
            context.scene,
            context.model,
            modal_dataset(modal),
            context.out,
            context.scene.name,
            figures=context.options.figures,
        )
    return {**modal_summary(modal), "files": [str(p) for p in files]}, None


def _sensitivity(context: _SceneContext) -> tuple[dict, xr.Dataset | None]:
    from ..analysis.modes.sensitivity import frequency_sensitivity
    from ..io import write_netcdf
    from ..model.case_json import case_json

    sensitivity = frequency_sensitivity(context.model)
    with task_files():
        path = write_netcdf(
            sensitivity.assign_attrs(scene=context.scene.name),
            context.out / f"{context.scene.name}_sensitivity.nc",
            input_hash=context.case.input_hash(),
            title=f"Frequency sensitivities of {context.case.name}",
            case_json=case_json(context.case),
        )
    return {"files": [str(path)]}, None


def _transient(context: _SceneContext) -> tuple[dict, xr.Dataset | None]:
    """The scene's transient and its signal analysis, NetCDF files first, then figures."""
    from ..analysis.time.transient import transient_summary
    from .outputs import write_run_signals
    from .transient_outputs import (
        write_load_figure,
        write_sensor_figures,
        write_speed_figure,
        write_transient,
    )

    case, scene, out, options = context.case, context.scene, context.out, context.options
    checkpoint = out / f"{scene.name}.checkpoint.npz"
    keep_checkpoint = options.checkpoint_every is not None or options.resume
    with task_files():
        dataset, files = write_transient(
            case,
            scene,
            out,
            progress=options.progress,
            figure=False,  # the speeds are drawn after the scene's spectra files are written
            model=context.model,
            # resuming keeps the file current: saved again on a signal, removed when done
            checkpoint=checkpoint if keep_checkpoint else None,
            checkpoint_every=(
                options.checkpoint_every if options.checkpoint_every is not None else math.inf
            ),
            resume=checkpoint if options.resume and checkpoint.is_file() else None,
        )
        if "signal" in scene.analyses:
            files = [
                *files,
                *write_run_signals(
                    case, context.model, dataset, out, scene.name, figures=options.figures
                ),
            ]
        if options.figures:
            speeds = write_speed_figure(dataset, out / f"{scene.name}_speeds.png")
            files += [speeds] if speeds is not None else []
            loads = out / f"{scene.name}_loads.png"  # what a whole drivetrain's run is for
            if dataset.attrs.get("whole_drivetrain") and write_load_figure(dataset, loads):
                files.append(loads)
            files += write_sensor_figures(dataset, out, scene.name)
    return {**transient_summary(dataset), "files": [str(p) for p in files]}, dataset


def _response(context: _SceneContext) -> tuple[dict, xr.Dataset | None]:
    """The periodic steady state over the scene's speeds (and its contact-loss branch),
    written as ``pygear response`` writes it: ``<stem>.nc`` and its figures, the stem
    being the scene's name when it says ``response``, else ``<scene>_response``."""
    from ..analysis.response import response_summary, scene_response
    from .response_outputs import write_response

    scene = context.scene
    linear, branch = scene_response(context.case, scene)
    stem = scene.name if "response" in scene.name else f"{scene.name}_response"
    with task_files():
        files = write_response(context.case, linear, context.out, figures=context.options.figures,
                               stem=stem, branch=branch)  # fmt: skip
    summary = response_summary(linear, branch, contact_loss=scene.response.contact_loss)
    return {"response": summary, "files": [str(p) for p in files]}, None


def _inside_transient(context: _SceneContext) -> tuple[dict, xr.Dataset | None]:
    return {}, None  # 'signal' runs inside the transient's writer, on its dataset


SCENE_ANALYSES: dict[str, Callable[[_SceneContext], tuple[dict, xr.Dataset | None]]] = {
    "modal": _modal,
    "sensitivity": _sensitivity,
    "transient": _transient,
    "signal": _inside_transient,
    "response": _response,
}
"""The writer of each analysis a scene may name: it returns the scene summary's entries
(``files`` among them) and the dataset a transient leaves for comparisons."""


def scene_model_for(case: Case, scene: Scene, formulation: str | None = None) -> tuple:
    """The case with the scene's parameter changes applied, and the scene's model."""
    from ..assembly.drivetrain_model import scene_model

    scene_case = case.for_scene(scene)
    return scene_case, scene_model(scene_case, scene, formulation=formulation)


def run_scene(
    case: Case, scene: Scene, out: str | Path, options: RunOptions | None = None
) -> SceneOutcome:
    """Run every analysis ``scene`` names and write its files into ``out``.

    Parameters
    ----------
    case : Case
        The case as loaded (the scene's parameter changes are applied here).
    scene : Scene
        One of the case's scenes.
    out : str or Path
        The output directory.
    options : RunOptions, optional
        Formulation override, figures, progress, checkpoints.

    Returns
    -------
    SceneOutcome
        The model, the summary entry and the transient's dataset (if any).

    Raises
    ------
    pygear.errors.CaseError
        Bad input the checks before the run did not see.
    pygear.runs.transient_outputs.TransientInterrupted
        Ctrl-C or SIGTERM during a transient (its checkpoint kept, when asked).
    """
    from ..model.rotor_transient import RotorScene

    options = options or RunOptions()
    started = time.perf_counter()
    if isinstance(scene, RotorScene):  # a plain rotor's transient (docs/rotors.md)
        return _rotor_scene(case, scene, Path(out), options, started)
    scene_case, model = scene_model_for(case, scene, options.formulation)
    outcome = SceneOutcome(scene.name, model)
    summary = outcome.summary
    summary.update(
        formulation=model.formulation, dof_set=model.dof_set, dofs=model.size, files=[]
    )
    context = _SceneContext(scene_case, scene, model, Path(out), options)
    for analysis in scene.analyses:
        writer = SCENE_ANALYSES.get(analysis)
        if writer is None:
            summary.setdefault("unsupported", []).append(analysis)
            continue
        entries, dataset = writer(context)
        summary["files"] += entries.pop("files", [])
        summary.update(entries)
        if dataset is not None:
            outcome.transient = dataset
    summary["wall_s"] = time.perf_counter() - started
    return outcome


def _rotor_scene(case, scene, out: Path, options: RunOptions, started: float) -> SceneOutcome:
    """A rotor scene's run: ``<scene>.nc`` (disc displacements, orbit radii, speed),
    then ``<scene>.png`` (orbit radius over speed)."""
    from ..analysis.time.rotor_transient import (
        rotor_summary,
        rotor_transient_problem,
        run_rotor_transient,
    )
    from ..io import write_netcdf
    from ..model.case_json import case_json

    problem = rotor_transient_problem(case, scene)
    outcome = SceneOutcome(scene.name, problem)
    dataset = run_rotor_transient(case, scene, progress=options.progress, problem=problem)
    with task_files():
        files = [
            write_netcdf(
                dataset,
                out / f"{scene.name}.nc",
                input_hash=case.input_hash(),
                title=f"Rotor transient {scene.name} of {case.name}",
                case_json=case_json(case),
            )
        ]
        if options.figures:
            from ..io import save_figure
            from ..plots.rotor import plot_rotor_run

            drawing = plot_rotor_run(dataset)
            path = out / f"{scene.name}.png"
            files.append(save_figure(drawing, path, dpi=drawing.dpi, release=True))
    outcome.summary.update(
        formulation=problem.formulation,
        dof_set=problem.dof_set,
        dofs=problem.size,
        files=[str(p) for p in files],
        **rotor_summary(dataset),
        wall_s=time.perf_counter() - started,
    )
    return outcome
