"""Files a scene writes: modal results and figures, signal analyses of a run.

Shared by ``pygear run`` and batch runs, so both write the same files.  A run file
carries the frequencies its signal analysis names peaks with
(:func:`analysis_references`), so ``pygear analyze`` reads them back
(:func:`stored_references`) and never loads, let alone executes, a case.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from ..analysis.signals.signal import SignalError
from ..io import write_netcdf
from ..model.case import Case, Scene
from ..model.case_json import case_json

__all__ = [
    "SPECTRA_DIRECTORY",
    "analysis_references",
    "bearing_references",
    "stored_references",
    "write_run_signals",
    "acceleration_channels",
    "file_kind",
    "mesh_frequency",
    "read_run_file",
    "write_modal_outputs",
    "write_signal_analysis",
]


SPECTRA_DIRECTORY = "spectra"
"""Where a scene's signal analyses go, below its output directory."""


def write_modal_outputs(
    case: Case,
    scene: Scene | None,
    model,
    modal,
    directory: Path,
    stem: str,
    *,
    figures: bool = True,
) -> list[Path]:
    """Write ``<stem>.nc`` and then, with ``figures``, the modal figures into ``directory``."""
    directory.mkdir(parents=True, exist_ok=True)
    if scene is not None:
        modal = modal.assign_attrs(scene=scene.name)
    written = [
        write_netcdf(
            modal,
            directory / f"{stem}.nc",
            input_hash=case.input_hash(),
            title=f"Modal analysis of {case.name} ({model.formulation})",
            case_json=case_json(case),
        )
    ]
    if not figures:
        return written
    from ..io import save_figure
    from ..plots.modal import plot_modal_energy, plot_mode_shape
    from ..plots.mode_shape import stage_mode

    drawings = {f"{stem}_energy.png": plot_modal_energy(modal)}
    rotational = [
        m
        for m, (c, i) in enumerate(zip(modal.mode_class.values, modal.class_index.values))
        if c == "rotational" and i == 2
    ]
    if rotational and case.gearbox.stages[0].kind == "planetary":
        drawings[f"{stem}_mode_shape.png"] = plot_mode_shape(case, model, modal, rotational[0])
    for stage in case.gearbox.stages:  # a helical stage's mode moves out of plane too
        mode = stage_mode(modal, stage.name) if not stage.spur else None
        if mode is not None and stage.kind in ("planetary", "parallel"):
            drawings[f"{stem}_mode_shape_{stage.name}.png"] = plot_mode_shape(
                case, model, modal, mode, stage=stage.name
            )
    for name, drawing in drawings.items():
        written.append(save_figure(drawing, directory / name, dpi=drawing.dpi, release=True))
    return written


def _stage_mesh_frequencies(case: Case, run) -> dict[str, tuple[int, float]]:
    """``{stage: (teeth, mesh frequency [Hz])}`` at a run's equilibrium speeds, for the
    stages with tooth numbers and a finite, positive frequency.

    A planetary stage meshes at Z_r |n_c - n_r| / 60, a parallel pair at Z_1 |n_1| / 60.
    """
    if "equilibrium_speed" not in run:
        return {}
    speeds = dict(zip(run.body.values.tolist(), run.equilibrium_speed.values.tolist()))
    stages = case.gearbox.stages
    found = {}
    for stage in stages:
        prefix = f"{stage.name}."
        kind = getattr(stage, "kind", "")
        if kind == "planetary" and stage.ring.teeth:
            relative = speeds.get(prefix + "carrier", np.nan) - speeds.get(prefix + "ring", 0.0)
            found[stage.name] = (stage.ring.teeth, stage.ring.teeth * abs(relative) / 60.0)
        elif kind == "parallel" and stage.input_gear.teeth:
            speed = speeds.get(prefix + "input_gear", np.nan)
            found[stage.name] = (stage.input_gear.teeth, stage.input_gear.teeth * abs(speed) / 60.0)
    return {k: (z, f) for k, (z, f) in found.items() if np.isfinite(f) and f > 0}


def _as_mesh_frequency(frequencies: dict[str, float], stage_count: int, fallback=None):
    """One stage: a number; several: ``{stage: frequency}``; none: ``fallback``."""
    if not frequencies:
        return fallback
    if stage_count == 1:
        return next(iter(frequencies.values()))
    return frequencies


def mesh_frequency(case: Case | None, run) -> float | dict[str, float] | None:
    """Mesh frequencies of a run at its equilibrium speeds (mean over its last window).

    One stage: a number; several: ``{stage: frequency}`` for the stages with tooth
    numbers.  Without a case, the run's ``mesh_frequency_hz`` attribute.
    """
    fallback = run.attrs.get("mesh_frequency_hz")
    if case is None:
        return fallback
    found = _stage_mesh_frequencies(case, run)
    return _as_mesh_frequency(
        {k: f for k, (_, f) in found.items()}, len(case.gearbox.stages), fallback
    )


def analysis_references(case: Case, model, run: xr.Dataset) -> xr.Dataset:
    """The frequencies a run's signal analysis names peaks with, to store in its file.

    ``natural_frequency`` and ``mode_class`` over ``mode``: the modes of the run's own
    model (mean mesh stiffness); ``mesh_frequency`` and ``mesh_teeth`` over
    ``mesh_stage``: each stage's mesh frequency at the run's equilibrium speeds and
    the tooth number it counts (:func:`mesh_frequency`); with rolling bearings in the
    case, their characteristic frequencies beside them (:func:`bearing_references`).
    """
    from ..analysis.modes.modal import modal_analysis

    modal = modal_analysis(model)
    stages = _stage_mesh_frequencies(case, run)
    references = xr.Dataset(
        {
            "natural_frequency": (
                ("mode",),
                np.asarray(modal.frequency.values, dtype=np.float64),
                {
                    "units": "Hz",
                    "long_name": "natural frequency of the run's model (mean mesh stiffness)",
                },
            ),
            "mesh_frequency": (
                ("mesh_stage",),
                np.array([f for _, f in stages.values()], dtype=np.float64),
                {
                    "units": "Hz",
                    "long_name": "mesh frequency at the equilibrium speeds: Z_r |n_c - n_r| "
                    "/ 60 for a planetary stage, Z_1 |n_1| / 60 for a parallel pair",
                    "gearbox_stages": len(case.gearbox.stages),
                },
            ),
            "mesh_teeth": (
                ("mesh_stage",),
                np.array([z for z, _ in stages.values()], dtype=np.int32),
                {"units": "1", "long_name": "tooth number Z of the mesh frequency"},
            ),
        },
        coords={
            "mode": (("mode",), modal.mode.values, {"units": "1", "long_name": "mode number"}),
            "mode_class": (
                ("mode",),
                np.asarray(modal.mode_class.values).astype(str),
                {"units": "1", "long_name": "mode class"},
            ),
            "mesh_stage": (
                ("mesh_stage",),
                list(stages),
                {"units": "1", "long_name": "gear stage of the mesh frequency"},
            ),
        },
    )
    return references.merge(bearing_references(case, run))


def bearing_references(case: Case, run: xr.Dataset) -> xr.Dataset:
    """The characteristic frequencies (FTF, BPFO, BPFI, BSF) of the case's rolling
    bearings at the run's equilibrium speeds
    (:func:`pygear.analysis.condition.bearing_kinematics.run_frequencies`); an empty
    Dataset when the case has none or the run holds no speeds."""
    from ..analysis.condition.bearing_kinematics import frequency_table, run_frequencies
    from ..model.rolling_bearing import rolling_bearings_of

    bearings = rolling_bearings_of(case)
    if not bearings or "equilibrium_speed" not in run:
        return xr.Dataset()
    speeds = dict(zip(run.body.values.tolist(), run.equilibrium_speed.values.tolist()))
    found = run_frequencies(bearings, speeds)
    return frequency_table(found) if found else xr.Dataset()


FILE_KINDS = (
    ("Transient ", None),
    (
        "Modal analysis of",
        "a modal analysis (natural frequencies and mode shapes) written "
        "by `pygear run` for a modal scene",
    ),
    (
        "Natural frequencies of",
        "a parameter study of natural frequencies written by `pygear modal`",
    ),
    ("Campbell diagram of", "a Campbell diagram written by `pygear campbell`"),
    ("Time-varying mesh stiffness of", "a mesh stiffness written by `pygear mesh-stiffness`"),
    ("Frequency sensitivities of", "frequency sensitivities written by `pygear run`"),
    ("Fault dataset of", "a fault dataset (indicators per record) written by `pygear dataset`"),
    ("Fault record", "one fault record (indicators of one run) written by `pygear dataset`"),
    ("Sweep", "a parameter sweep written by `pygear sweep`"),
    ("Accuracy and cost of", "an accuracy study written by `pygear accuracy`"),
    ("Spectra of", "spectra written by `pygear analyze`"),
    ("Order tracking of", "an order tracking written by `pygear analyze --orders`"),
    ("Synchronous average of", "a synchronous average written by `pygear analyze --tsa`"),
)
"""``(title prefix, what the file is)`` of the files pygear writes (their ``title``
attribute); None for a transient's run, the file ``pygear analyze`` reads."""


def file_kind(dataset: xr.Dataset) -> str | None:
    """What wrote ``dataset``, from its ``title``, when it is a pygear file other than a
    run; None for a run or a file of unknown origin."""
    title = str(dataset.attrs.get("title", ""))
    for prefix, kind in FILE_KINDS:
        if title.startswith(prefix):
            return kind
    return None


def _first_line(error: BaseException) -> str:
    text = " ".join(str(error).split())
    text = text if len(text) <= 160 else text[:157] + "..."
    return f"{type(error).__name__}: {text}" if text else type(error).__name__


def read_run_file(path: str | Path, needs: str) -> xr.Dataset:
    """A run file, read as data (labels as indexes, time in s), checked before any work.

    ``needs`` says what the analysis asks of the file (ends the message of a file of
    another kind).  A file that does not exist, is empty, is no NetCDF (text, random or
    damaged bytes), was written by another command (its ``title``), or holds no samples
    over time raises :class:`~pygear.errors.CaseError` naming it and what is wrong.  The
    file is read by xarray's netCDF4 engine: nothing in it is executed.
    """
    from ..analysis.signals.channels import run_channels
    from ..errors import CaseError
    from ..io import index_labels

    path = Path(path)
    name = f"RUN.nc {str(path)!r}"
    if not path.exists():
        raise CaseError(f"{name} does not exist")
    if not path.is_file():
        raise CaseError(f"{name} is not a file")
    if path.stat().st_size == 0:
        raise CaseError(f"{name} is empty (0 bytes), not a NetCDF file")
    try:
        with xr.open_dataset(path, engine="netcdf4", decode_times=False) as opened:
            run = index_labels(opened.load())  # labels as indexes, time in s
    except Exception as error:  # noqa: BLE001 - any damage reads as one message
        raise CaseError(f"{name} cannot be read as NetCDF ({_first_line(error)})") from None
    kind = file_kind(run)
    if kind is not None:
        raise CaseError(f"{name} is {kind}, not a run: {needs}")
    if "time" not in run.dims:
        raise CaseError(f"{name} holds no series over time: {needs}")
    if run.sizes["time"] == 0:
        raise CaseError(f"{name} holds no samples (its time dimension is empty): {needs}")
    try:
        channels = run_channels(run)
    except Exception as error:  # noqa: BLE001 - a damaged layout, not a pygear bug
        raise CaseError(f"{name} has channels pygear cannot read ({_first_line(error)})") from None
    if not channels:
        raise CaseError(f"{name} holds no channel over time: {needs}")
    return run


def stored_references(run: xr.Dataset, source: str | Path = "RUN.nc"):
    """The natural frequencies and mesh frequency a run file carries.

    Returns
    -------
    (xarray.Dataset or None, float or dict or None)
        ``frequency`` and ``mode_class`` of the modes, and the mesh frequency (a
        number for one stage, ``{stage: Hz}`` for several).  A file that names no
        case (not a pygear run) gives no modes and its ``mesh_frequency_hz``.

    Raises
    ------
    SignalError
        A pygear run file written before the frequencies were stored: rerun it.
    """
    if "natural_frequency" not in run or "mesh_frequency" not in run:
        if "case" in run.attrs:
            raise SignalError(
                f"RUN.nc {str(source)!r} holds no natural_frequency and mesh_frequency "
                "(written by an older pygear); rerun its scene with `pygear run` to "
                "analyse it with named peaks"
            )
        return None, run.attrs.get("mesh_frequency_hz")
    natural = xr.Dataset(
        {"frequency": run.natural_frequency, "mode_class": run.mode_class.astype(str)}
    )
    frequencies = {
        str(stage): float(value)
        for stage, value in zip(run.mesh_stage.values, run.mesh_frequency.values)
    }
    stage_count = int(run.mesh_frequency.attrs.get("gearbox_stages", len(frequencies)))
    return natural, _as_mesh_frequency(frequencies, stage_count, run.attrs.get("mesh_frequency_hz"))


def write_signal_analysis(
    run,
    stem: Path,
    *,
    channel=None,
    band=(5000.0, 10000.0),
    after=1.0,
    natural=None,
    mesh_frequency=None,
    figure=True,
):
    """Analyse one channel of a run; write ``<stem>_<channel>.nc`` and then, with
    ``figure``, ``<stem>_<channel>.png`` (the channel name with ``:`` as ``_``,
    :func:`pygear.analysis.signals.channels.channel_file_part`).  The spectra file keeps the
    run's case, scene, formulation, input hash and case JSON."""
    from ..analysis.signals.analyze import analyze_channel
    from ..analysis.signals.channels import channel_file_part

    analysis = analyze_channel(
        run,
        channel,
        band=band,
        after=after,
        natural_frequencies=natural,
        mesh_frequency=mesh_frequency,
    )
    base = stem.with_name(f"{stem.name}_{channel_file_part(analysis.channel)}")
    # suffixes appended, never substituted: a channel name with a dot keeps its own files
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
    path = write_netcdf(
        spectra,
        base.with_name(f"{base.name}.nc"),
        title=f"Spectra of {analysis.channel}",
        provenance=run.attrs,
    )
    if not figure:
        return analysis, [path]
    return analysis, [path, _signal_figure(analysis, base, run.attrs)]


def _signal_figure(analysis, base: Path, run_attrs) -> Path:
    from ..io import save_figure
    from ..plots.signal import plot_run_analysis  # Matplotlib loads only for a figure

    figure = plot_run_analysis(analysis, run_attrs=run_attrs)
    return save_figure(figure, base.with_name(f"{base.name}.png"), dpi=figure.dpi, release=True)


def acceleration_channels(dataset) -> list[str]:
    """The channel names (:mod:`pygear.analysis.signals.channels`) of a run's accelerations."""
    from ..analysis.signals.channels import run_channels

    return [
        name
        for name, (variable, _, _) in run_channels(dataset).items()
        if str(dataset[variable].attrs.get("units", "")).endswith("s^2")
    ]


def write_run_signals(
    case: Case, model, dataset, directory: Path, stem: str, *, figures: bool = True
) -> list[Path]:
    """Signal analysis of every acceleration channel of a run, after the start-up:
    every channel's ``.nc`` first, then (with ``figures``) every channel's figure.

    They go to ``directory/spectra/<stem>_<channel>.*``: beside the scene files, a
    glob such as ``runup*.nc`` then finds the scenes alone (open_mfdataset of a batch).
    """
    from ..analysis.signals.channels import channel_file_part
    from ..model.case import SIGNAL_AFTER

    directory = Path(directory) / SPECTRA_DIRECTORY

    if "natural_frequency" not in dataset:  # a run not from write_transient
        dataset = dataset.merge(analysis_references(case, model, dataset))
    natural, mesh = stored_references(dataset)
    files: list[Path] = []
    analyses = []
    for channel in acceleration_channels(dataset):
        analysis, written = write_signal_analysis(
            dataset,
            directory / stem,
            channel=channel,
            after=SIGNAL_AFTER,
            natural=natural,
            mesh_frequency=mesh,
            figure=False,
        )
        files += written
        analyses.append(analysis)
    if figures:
        from ..analysis.signals.signal import clear_plan_cache

        clear_plan_cache()  # the FFT plans' aligned buffers (MBs each) before the figures
        for analysis in analyses:
            base = directory / f"{stem}_{channel_file_part(analysis.channel)}"
            files.append(_signal_figure(analysis, base, dataset.attrs))
    return files
