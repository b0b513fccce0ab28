"""The files of a transient scene: ``<scene>.nc`` written atomically, with the speed
figure beside it, and what a signal while writing leaves behind."""

from __future__ import annotations

import os
import signal
from collections.abc import Callable
from pathlib import Path

import numpy as np
import xarray as xr

from ..analysis.time.transient import run_transient, transient_problem
from ..analysis.time.transient_checks import check_transient_disk
from ..assembly.matrices import Model
from ..errors import CaseError
from ..io import WriteInterrupted, save_figure, signals_interrupt, write_netcdf
from ..kernel.newmark import TransientInterrupted
from ..model.case import Case, Scene
from ..model.case_json import case_json
from .outputs import analysis_references

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
) -> tuple[xr.Dataset, list[Path]]:
    """Run the scene's transient and write ``<scene>.nc`` (and ``<scene>_speeds.png``).

    The file is written under a temporary name and renamed when complete; a run
    that fails or is interrupted writes nothing (but its checkpoint, when asked).
    The file carries the frequencies ``pygear analyze`` names peaks with
    (:func:`pygear.runs.outputs.analysis_references`).  A checkpoint holds the finished
    run until the result is written, and is removed then: Ctrl-C or SIGTERM while
    writing removes the temporary file and keeps the checkpoint, from which a resumed
    run writes the result without integrating again.

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
            problem = transient_problem(case, scene, formulation=formulation, model=model)
            check_transient_disk(
                problem.settings, len(problem.probes), directory, f"scenes.{scene.name}.transient"
            )
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
            dataset = dataset.merge(analysis_references(case, problem.model, dataset))
            # the inputs that made it, kept for what is computed from it (its spectra)
            dataset.attrs.update(input_hash=case.input_hash(), case_json=case_json(case))
            path = write_netcdf(
                dataset,
                directory / f"{scene.name}.nc",
                title=f"Transient {scene.name} of {case.name} ({dataset.attrs['formulation']})",
            )
            written = [path]
            if figure:
                speeds = write_speed_figure(dataset, directory / f"{scene.name}_speeds.png")
                written += [speeds] if speeds is not None else []
                written += write_sensor_figures(dataset, directory, scene.name)
        except WriteInterrupted as interrupt:
            raise TransientInterrupted(
                _interrupted_writing(interrupt, stage, path, checkpoint), interrupt.signal_number
            ) from None
    if checkpoint is not None:
        Path(checkpoint).unlink(missing_ok=True)
    return dataset, written


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
