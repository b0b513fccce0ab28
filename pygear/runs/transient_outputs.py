"""The files of a transient scene: ``<scene>.nc`` written atomically, with the speed
figure beside it, and what a signal while writing leaves behind."""

from __future__ import annotations

import os
import signal
import time
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import xarray as xr

from ..analysis.time.reductions import scene_reductions
from ..analysis.time.run_dataset import result_attributes, summary_variables
from ..analysis.time.transient import (
    checkpoint_identity,
    integrate,
    run_transient,
    transient_problem,
)
from ..analysis.time.transient_checks import check_transient_disk, check_transient_memory
from ..assembly.matrices import Model
from ..errors import CaseError
from ..io import WriteInterrupted, open_dataset, save_figure, signals_interrupt, write_netcdf
from ..kernel.newmark import TransientInterrupted
from ..model.case import Case, Scene
from ..model.case_json import case_json
from .outputs import analysis_references
from .streaming import StreamedFile, partial_path, stream_wanted, usable_partial

__all__ = ["write_speed_figure", "write_transient"]


def write_transient(
    case: Case,
    scene: Scene,
    directory: str | os.PathLike,
    *,
    formulation: str | None = None,
    progress: Callable[[int, int], None] | None = None,
    figure: bool = True,
    model: Model | None = None,
    checkpoint: str | os.PathLike | None = None,
    checkpoint_every: float = 60.0,
    resume: str | os.PathLike | None = None,
    stream: bool | None = None,
    problem=None,
) -> tuple[xr.Dataset, list[Path]]:
    """Run the scene's transient and write ``<scene>.nc`` (and ``<scene>_speeds.png``).

    The file is written under a temporary name and renamed when complete; a run
    that fails or is interrupted writes nothing (but its checkpoint, when asked).
    The file carries the frequencies ``pygear analyze`` names peaks with
    (:func:`pygear.runs.outputs.analysis_references`).  A checkpoint holds the finished
    run until the result is written, and is removed then: Ctrl-C or SIGTERM while
    writing removes the temporary file and keeps the checkpoint, from which a resumed
    run writes the result without integrating again.

    A long run streams (``stream`` None: :func:`pygear.runs.streaming.stream_wanted`):
    its samples go into the file as the run goes (:mod:`pygear.runs.streaming`), under
    a hidden name and marked ``complete = 0`` until the end, and the dataset returned is
    the finished file opened lazily (:func:`pygear.io.open_dataset`).  A streamed run
    resumed from its checkpoint continues its partial file; without a checkpoint a
    failed streamed run removes it.  ``problem`` is the scene's
    :func:`~pygear.analysis.time.transient.transient_problem` when the caller built it
    already (its checks).

    Raises
    ------
    TransientInterrupted
        Ctrl-C or SIGTERM, during the run or while its files are written.
    """
    directory = Path(directory)
    stage = "setting up the run"
    path = None
    with signals_interrupt():  # a signal while writing raises, so temporaries are removed
        try:
            if problem is None:
                problem = transient_problem(
                    case,
                    scene,
                    formulation=formulation,
                    model=model,
                    check_memory=False,
                    reuse=True,  # the problem the checks before the run built
                )
            where = f"scenes.{scene.name}.transient"
            check_transient_disk(problem.settings, len(problem.probes), directory, where)
            if stream_wanted(problem, stream):
                dataset, path = _write_streamed(
                    case,
                    problem,
                    directory / f"{scene.name}.nc",
                    progress=progress,
                    checkpoint=checkpoint,
                    checkpoint_every=checkpoint_every,
                    resume=resume,
                )
                stage = "writing the result"
            else:
                check_transient_memory(problem.settings, len(problem.probes), where)
                consumers = scene_reductions(problem)  # a variable it lacks: refused first
                dataset = run_transient(
                    case,
                    scene,
                    progress=progress,
                    problem=problem,
                    checkpoint=checkpoint,
                    checkpoint_every=checkpoint_every,
                    resume=resume,
                )
                stage = "writing the result"
                dataset = _reduced(dataset, consumers)
                dataset = dataset.merge(analysis_references(case, problem.model, dataset))
                # the inputs that made it, kept for what is computed from it (its spectra)
                dataset.attrs.update(input_hash=case.input_hash(), case_json=case_json(case))
                path = write_netcdf(
                    dataset,
                    directory / f"{scene.name}.nc",
                    title=f"Transient {scene.name} of {case.name} ({dataset.attrs['formulation']})",
                )
            written = [path, *_figures(dataset, directory, scene.name, figure)]
        except WriteInterrupted as interrupt:
            raise TransientInterrupted(
                _interrupted_writing(interrupt, stage, path, checkpoint), interrupt.signal_number
            ) from None
    if checkpoint is not None:
        Path(checkpoint).unlink(missing_ok=True)
    return dataset, written


def _figures(dataset: xr.Dataset, directory: Path, scene: str, figure: bool) -> list[Path]:
    """The speed figure and the sensor figures of a written run (none unless ``figure``)."""
    if not figure:
        return []
    speeds = write_speed_figure(dataset, directory / f"{scene}_speeds.png")
    return ([speeds] if speeds is not None else []) + write_sensor_figures(
        dataset, directory, scene
    )


def _write_streamed(
    case: Case,
    problem,
    target: Path,
    *,
    progress,
    checkpoint,
    checkpoint_every: float,
    resume,
) -> tuple[xr.Dataset, Path]:
    """Run ``problem`` streaming its samples into ``target`` (:mod:`pygear.runs.streaming`);
    the finished file opened lazily, and its path."""
    started = time.perf_counter()
    identity = checkpoint_identity(problem)
    partial = partial_path(target)
    if resume is not None:
        reason = usable_partial(partial, identity, _checkpoint_samples(resume))
        if reason:  # the samples before the checkpoint are lost: run from the start
            warnings.warn(f"resume: {reason}; running {target.name} from the start", stacklevel=3)
            resume = None
    sink = StreamedFile(
        problem,
        target,
        title=f"Transient {problem.scene.name} of {case.name} ({problem.model.formulation})",
        input_hash=case.input_hash(),
        case_json=case_json(case),
        identity=identity,
        consumers=scene_reductions(problem),
    )
    try:
        result = integrate(
            problem,
            progress=progress,
            checkpoint=checkpoint,
            checkpoint_every=checkpoint_every,
            resume=resume,
            sink=sink,
        )
        summary_vars, summary_coords = summary_variables(problem, result)
        tail = xr.Dataset(summary_vars, summary_coords)
        tail = tail.merge(analysis_references(case, problem.model, tail))
        attrs = result_attributes(problem, result)
        attrs["wall_s"] = time.perf_counter() - started
        path = sink.finish(tail, attrs)
    except BaseException:
        if checkpoint is None:  # nothing could resume it
            sink.discard()
        raise
    return open_dataset(path), path


def _reduced(dataset: xr.Dataset, consumers: list) -> xr.Dataset:
    """``dataset`` with the scene's reductions of its whole record (the streamed run
    computes the same block by block: :mod:`pygear.analysis.time.reductions`)."""
    if not consumers:
        return dataset
    columns = {name: v.values for name, v in dataset.data_vars.items() if "time" in v.dims}
    columns["time"] = dataset["time"].values
    for consumer in consumers:
        consumer.update(0, columns)
        dataset = dataset.merge(consumer.variables(), combine_attrs="override")
    return dataset


def _checkpoint_samples(path) -> int:
    """The samples a checkpoint says its run has written (0 when it cannot be read)."""
    try:
        with np.load(path) as data:
            return int(data["written"])
    except (OSError, KeyError, ValueError):
        return 0


def write_speed_figure(dataset: xr.Dataset, target: Path) -> Path | None:
    """Draw a run's speeds into ``target`` (PNG, atomically); None, and no file, when
    the run has no speed channel."""
    if not any(v.attrs.get("quantity") == "speed" for v in dataset.data_vars.values()):
        return None
    from ..plots.transient import plot_speeds  # Matplotlib loads only for a figure

    figure = plot_speeds([dataset])
    return save_figure(figure, target, dpi=figure.dpi, release=True)  # atomic


def write_load_figure(dataset: xr.Dataset, target: Path) -> Path | None:
    """Draw a run's mesh forces and torques into ``target`` (PNG, atomically); None, and
    no file, when the run records no mesh force."""
    if not any(v.attrs.get("quantity") == "mesh_force" for v in dataset.data_vars.values()):
        return None
    from ..plots.transient import plot_loads  # Matplotlib loads only for a figure

    figure = plot_loads([dataset])
    return save_figure(figure, target, dpi=figure.dpi, release=True)  # atomic


def write_sensor_figures(dataset: xr.Dataset, directory: Path, scene: str) -> list[Path]:
    """Each sensor channel's carrier-order spectrum around the first two mesh harmonics,
    sidebands labelled (``<scene>_<channel>_orders.png``); none for a run shorter than
    two carrier revolutions or without the carrier's angle."""
    from ..analysis.condition.sensor_signal import sensor_carrier_orders
    from ..analysis.signals.channels import channel_file_part, channel_series, run_channels

    written = []
    for name, (variable_name, _, _) in run_channels(dataset).items():
        if dataset[variable_name].attrs.get("quantity") != "sensor":
            continue
        variable = channel_series(dataset, name)
        try:
            orders, amplitude, revolutions = sensor_carrier_orders(dataset, name)
        except CaseError:
            continue
        from ..plots.condition_monitoring import plot_sensor_orders
        from ..plots.layout import result_title

        ring = int(np.atleast_1d(variable.attrs["sensor_teeth_sun_planet_ring"])[2])
        planets = len(np.atleast_1d(variable.attrs["sensor_planet_angles_deg"]))
        if ring < 1 or 2 * ring + 10 >= orders.size:
            continue
        figure = plot_sensor_orders(
            orders,
            amplitude,
            ring_teeth=ring,
            planets=planets,
            title=f"{result_title(dataset.attrs, scene=scene)}: {name}, "
            f"last {revolutions} carrier revolutions",
        )
        target = directory / f"{scene}_{channel_file_part(name)}_orders.png"
        written.append(save_figure(figure, target, dpi=figure.dpi, release=True))
    return written


def _interrupted_writing(interrupt, stage: str, path: Path | None, checkpoint) -> str:
    """One line on what a signal outside the integration left behind."""
    name = signal.Signals(interrupt.signal_number).name
    if stage != "writing the result":
        return f"interrupted by {name} while {stage}; no result file written"
    if path is not None:
        return f"interrupted by {name} after writing {path}; its figure was not written"
    if checkpoint is not None:
        kept = (
            f"the finished run is kept in {checkpoint}: `pygear run --resume` writes the "
            "result from it without running again"
        )
    else:
        kept = "the run is lost (no checkpoint: --checkpoint-every or --resume keeps one)"
    return f"interrupted by {name} while writing the result; {kept}; no result file written"
