"""Files a scene writes: modal results and figures, signal analyses of a run.

Shared by ``pygear run`` and batch runs, so both write the same files.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .case import Case, Scene
from .io import write_netcdf

__all__ = [
    "write_run_signals",
    "acceleration_channels",
    "mesh_frequency",
    "write_modal_outputs",
    "write_signal_analysis",
]


def write_modal_outputs(
    case: Case, scene: Scene | None, model, modal, directory: Path, stem: str
) -> list[Path]:
    """Write ``<stem>.nc`` and the modal figures into ``directory``."""
    from .plots import plot_modal_energy, plot_mode_shape

    directory.mkdir(parents=True, exist_ok=True)
    written = [
        write_netcdf(
            modal,
            directory / f"{stem}.nc",
            input_hash=case.input_hash(),
            title=f"Modal analysis of {case.name} ({model.formulation})",
        )
    ]
    energy = directory / f"{stem}_energy.png"
    plot_modal_energy(modal, energy)
    written.append(energy)
    rotational = [
        m
        for m, (c, i) in enumerate(zip(modal.mode_class.values, modal.class_index.values))
        if c == "rotational" and i == 2
    ]
    if rotational and case.gearbox.stages[0].kind == "planetary":
        shape = directory / f"{stem}_mode_shape.png"
        plot_mode_shape(case, model, modal, rotational[0], shape)
        written.append(shape)
    return written


def mesh_frequency(case: Case | None, run) -> float | dict[str, float] | None:
    """Mesh frequencies of a run at its equilibrium speeds (mean over its last window).

    A planetary stage meshes at Z_r |n_c - n_r| / 60, a parallel pair at Z_1 |n_1| / 60.
    One stage: a number; several: ``{stage: frequency}`` for the stages with tooth
    numbers.  Without a case, the run's ``mesh_frequency_hz`` attribute.
    """
    if case is None or "equilibrium_speed" not in run:
        return run.attrs.get("mesh_frequency_hz")
    speeds = dict(zip(run.member.values.tolist(), run.equilibrium_speed.values.tolist()))
    stages = case.gearbox.stages
    frequencies = {}
    for stage in stages:
        prefix = f"{stage.name}." if len(stages) > 1 else ""
        kind = getattr(stage, "kind", "")
        if kind == "planetary" and stage.ring.teeth:
            relative = speeds.get(prefix + "carrier", np.nan) - speeds.get(prefix + "ring", 0.0)
            frequencies[stage.name] = stage.ring.teeth * abs(relative) / 60.0
        elif kind == "parallel" and stage.input_gear.teeth:
            speed = speeds.get(prefix + "input_gear", np.nan)
            frequencies[stage.name] = stage.input_gear.teeth * abs(speed) / 60.0
    frequencies = {k: f for k, f in frequencies.items() if np.isfinite(f) and f > 0}
    if not frequencies:
        return run.attrs.get("mesh_frequency_hz")
    if len(stages) == 1:
        return next(iter(frequencies.values()))
    return frequencies


def write_signal_analysis(
    run,
    stem: Path,
    *,
    channel=None,
    band=(5000.0, 10000.0),
    after=1.0,
    natural=None,
    mesh_frequency=None,
):
    """Analyse one channel of a run; write ``<stem>_<channel>.nc`` and ``.png``."""
    from .analyze import analyze_channel
    from .plots_signal import plot_run_analysis

    analysis = analyze_channel(
        run,
        channel,
        band=band,
        after=after,
        natural_frequencies=natural,
        mesh_frequency=mesh_frequency,
    )
    base = stem.with_name(f"{stem.name}_{analysis.channel}")
    spectra = analysis.spectra.copy()
    if isinstance(mesh_frequency, dict):
        spectra.attrs["mesh_frequency_hz"] = list(mesh_frequency.values())
        spectra.attrs["mesh_frequency_stage"] = list(mesh_frequency)
    else:
        spectra.attrs["mesh_frequency_hz"] = mesh_frequency or float("nan")
    spectra.attrs["strongest_peaks"] = "; ".join(
        f"{row.frequency_hz:.1f} Hz {row.identification}"
        for row in analysis.peaks["spectrum"].head(5).itertuples()
    )
    path = write_netcdf(spectra, base.with_suffix(".nc"), title=f"Spectra of {analysis.channel}")
    figure = base.with_suffix(".png")
    plot_run_analysis(analysis, figure)
    return analysis, [path, figure]


def acceleration_channels(dataset) -> list[str]:
    return [
        name
        for name, v in dataset.data_vars.items()
        if v.dims == ("time",) and str(v.attrs.get("units", "")).endswith("s^2")
    ]


def write_run_signals(case: Case, model, dataset, directory: Path, stem: str) -> list[Path]:
    """Signal analysis of every acceleration channel of a run, after the start-up."""
    from .case import SIGNAL_AFTER
    from .modal import modal_analysis

    natural = modal_analysis(model)
    files: list[Path] = []
    for channel in acceleration_channels(dataset):
        _, written = write_signal_analysis(
            dataset,
            directory / stem,
            channel=channel,
            after=SIGNAL_AFTER,
            natural=natural,
            mesh_frequency=mesh_frequency(case, dataset),
        )
        files += written
    return files
