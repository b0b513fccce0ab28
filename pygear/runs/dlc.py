"""Design load case batches: every load case of a case's table as one Dask task, one
streamed file each, resumable, combined into a load spectrum per year.

``pygear batch CASE --dlc`` (:func:`run_dlc_batch`) runs the ``design_load_cases`` a
case file defines (:class:`pygear.model.dlc_settings.DesignLoadCases`):

* each load case is the table's scene with the rotor torque series as its drive
  (``TorqueLaw.table``), written as ``<out>/<case>/dlc/<load case>.nc``, streamed
  (it grows under a hidden name marked ``complete = 0`` and takes its name when whole);
* a load case whose file is complete is not run again; a half-written one (a killed
  worker, a killed batch) is run again from its start; each load case adds a line to
  ``dlc_journal.log`` when its run starts and another when its file is complete;
* when every load case is complete their rainflow matrices and load duration
  distributions are summed, each weighted by the hours a year its wind speed blows,
  into ``load_spectrum.nc`` (:mod:`pygear.runs.dlc_spectrum`).

The generator holds the drivetrain's speed: its load law (T_D / i)(omega_out /
(i omega_0))^n balances the drive at the series' mean torque T_D and mean speed
omega_0; the run starts at that speed, loaded.
"""

from __future__ import annotations

import dataclasses
import os
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from ..errors import CaseError
from ..io import atomic_path
from ..model.case import Case, Scene
from ..model.dlc_settings import DesignLoadCases, LoadCase, load_design_load_cases
from ..model.transient_settings import TorqueLaw
from .cluster import task_files
from .progress import ProgressBar

__all__ = [
    "DLC_SUMMARY_COLUMNS",
    "JOURNAL_NAME",
    "SPECTRUM_NAME",
    "case_file_complete",
    "load_case_scene",
    "load_case_series",
    "run_dlc_batch",
    "run_load_case",
]

JOURNAL_NAME = "dlc_journal.log"
"""Lines ``started <load case> <pid>`` when a load case's run starts and ``completed
<load case> <pid> <wall s>`` when its file is complete."""

SPECTRUM_NAME = "load_spectrum.nc"
SUMMARY_NAME = "dlc_summary.csv"

DLC_SUMMARY_COLUMNS = (
    "load_case",
    "wind_speed",
    "seed",
    "hours_per_year",
    "status",
    "wall_s",
    "cpu_s",
    "file",
    "error",
)
"""Columns of the DLC batch summary; ``status`` is ``ok`` (run now), ``reused`` (its
file was complete) or ``error``; ``wall_s`` and ``cpu_s`` are the task's wall and
processor time (the share of a core it had on a loaded machine)."""


def load_case_series(
    table: DesignLoadCases, load: LoadCase, directory: str | os.PathLike = "."
) -> xr.Dataset:
    """The rotor torque [N m] and speed [rpm] over the load case's duration, from
    ``t = 0``: synthetic (Kaimal) or read from its OpenFAST file (the file's first
    ``duration`` seconds)."""
    if table.source == "openfast":
        from ..io_openfast import read_openfast_output

        series = read_openfast_output(Path(directory) / str(load.openfast_file))
        time_s = series.time.values - series.time.values[0]
        if time_s[-1] < table.duration * (1 - 1e-9):
            raise CaseError(
                f"design_load_cases.openfast_files: {load.openfast_file!r} holds "
                f"{time_s[-1]:g} s, less than the duration {table.duration:g} s"
            )
        series = series.assign_coords(time=("time", time_s, series.time.attrs))
        return series.where(series.time <= table.duration * (1 + 1e-9), drop=True)
    from ..analysis.time.wind import NREL5MW_ROTOR, kaimal_wind, rotor_torque_series

    count = int(round(table.duration * table.input_rate)) + 1
    wind = kaimal_wind(
        load.wind_speed,
        count / table.input_rate,
        table.input_rate,
        load.seed,
        turbulence_class=table.turbulence_class,
        hub_height=NREL5MW_ROTOR.hub_height,
    )
    series = rotor_torque_series(
        wind, table.input_rate, NREL5MW_ROTOR, table.regulation_time_constant, load.wind_speed
    )
    return series.assign_attrs(
        wind_speed=load.wind_speed, seed=load.seed, turbulence_class=table.turbulence_class
    )


def load_case_scene(
    case: Case, table: DesignLoadCases, load: LoadCase, series: xr.Dataset
) -> Scene:
    """The table's scene driven by the series: drive = the torque table, load = the
    generator law balancing the mean torque at the mean speed, from that speed, loaded."""
    base = case.scene(table.scene)
    transient = base.transient
    assert transient is not None
    sign = transient.drive.direction() if transient.drive is not None else 1
    torque = series.rotor_torque.values
    speed = float(np.mean(np.abs(series.rotor_speed.values)))
    mean_torque = float(np.mean(torque))
    if not (mean_torque > 0 and speed > 0):
        raise CaseError(
            f"load case {load.name}: the rotor torque and speed must have positive means "
            f"(got {mean_torque:g} N m, {speed:g} rpm)"
        )
    exponent = (
        transient.load.exponent
        if transient.load is not None and transient.load.kind == "generator"
        else 2.0
    )
    changed = dataclasses.replace(
        transient,
        duration=table.duration,
        drive=TorqueLaw.table(series.time.values, sign * torque),
        load=TorqueLaw.generator(rated_drive_torque=mean_torque, exponent=exponent),
        speed_reference_rpm=speed,
        initial_speed_rpm=sign * speed,
        start_loaded=True,
        mean_window=min(transient.mean_window, table.duration),
        reductions=table.reductions if table.reductions is not None else transient.reductions,
        probes=table.probes or transient.probes,
    )
    return dataclasses.replace(base, name=load.name, analyses=("transient",), transient=changed)


def case_file_complete(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a finished run file (``complete = 1``; a whole-record file,
    written under another name and renamed, has no mark and is complete when there)."""
    path = Path(path)
    if not path.is_file():
        return False
    try:
        import netCDF4

        with netCDF4.Dataset(path) as handle:
            return int(getattr(handle, "complete", 1)) == 1
    except (OSError, ValueError):
        return False


def _journal(out: Path, line: str) -> None:
    """Append one line to the batch's journal (one short write: whole, whatever the
    other workers append)."""
    with open(out / JOURNAL_NAME, "a") as journal:
        journal.write(line + "\n")


_TABLES: dict[tuple[str, int], tuple] = {}
"""The case and table each case file gave this process, by path and modification time:
a worker runs many load cases of one case, and executing the case file (building the
gearbox's geometry) each time would repeat work that does not change."""


def _cached_table(case_dir: str) -> tuple:
    path = Path(case_dir)
    file = path / "case.py" if path.is_dir() else path
    key = (str(file.resolve()) if file.exists() else str(path), _mtime(file))
    if key not in _TABLES:
        _TABLES.clear()  # one case at a time: keep none of another's
        _TABLES[key] = load_design_load_cases(case_dir)
    return _TABLES[key]


def _mtime(path: Path) -> int:
    try:
        return path.stat().st_mtime_ns
    except OSError:
        return -1


def run_load_case(case_dir: str, name: str, out_dir: str) -> dict:
    """Run one load case of the case's table into ``out_dir/<name>.nc`` (a Dask task;
    never raises).  A load case whose file is complete already is ``reused``."""
    from .scene_checks import check_scenes
    from .scene_runner import scene_model_for
    from .transient_outputs import write_transient

    started, cpu = time.perf_counter(), time.process_time()
    out = Path(out_dir)
    row: dict[str, Any] = {"load_case": name, "file": str(out / f"{name}.nc"), "error": ""}
    try:
        case, table, directory = _cached_table(case_dir)
        load = next(c for c in table.load_cases() if c.name == name)
        row.update(wind_speed=load.wind_speed, seed=load.seed, hours_per_year=load.hours_per_year)
        if case_file_complete(out / f"{name}.nc"):
            row.update(status="reused", wall_s=time.perf_counter() - started)
            return row
        scene = load_case_scene(case, table, load, load_case_series(table, load, directory))
        assert scene.transient is not None
        out.mkdir(parents=True, exist_ok=True)
        check_scenes(case, [scene], out=out)
        _journal(out, f"started {name} {os.getpid()}")
        scene_case, model = scene_model_for(case, scene)
        with task_files():
            dataset, _ = write_transient(
                scene_case, scene, out, figure=False, model=model, stream=True
            )
            dataset.close()
        wall = time.perf_counter() - started
        _journal(out, f"completed {name} {os.getpid()} {wall:.3f}")
        row.update(status="ok", wall_s=wall, cpu_s=time.process_time() - cpu)
    except Exception as error:  # noqa: BLE001 - one failing load case must not stop the batch
        row.update(
            status="error",
            error=str(error) if isinstance(error, CaseError) else repr(error),
            wall_s=time.perf_counter() - started,
        )
    return row


def run_dlc_batch(
    reference: str | os.PathLike,
    *,
    out_dir: str | os.PathLike,
    workers: int = 2,
    scheduler: str | None = None,
    cluster: str | None = None,
    cluster_options: Mapping[str, Any] | None = None,
    progress: bool = True,
    only: int | None = None,
) -> tuple[pd.DataFrame, Path | None]:
    """Run the case's design load cases on Dask and combine them into a load spectrum.

    Parameters
    ----------
    reference : path or str
        Case directory or name; its case file defines ``design_load_cases``.
    out_dir : path
        Load case files go to ``out_dir/<case>/dlc/``, the summary and the load
        spectrum beside them (``dlc_summary.csv``, ``load_spectrum.nc``).
    workers, scheduler, cluster, cluster_options
        As :func:`pygear.runs.cluster.dask_client`.
    progress : bool
        Draw a progress bar on stderr.
    only : int, optional
        Run the first ``only`` load cases still to run (the rest wait for a later
        call; the spectrum is written once every load case is complete).

    Returns
    -------
    (pandas.DataFrame, Path or None)
        One row per load case (:data:`DLC_SUMMARY_COLUMNS`) and the load spectrum's
        path (None while some load case is not complete).
    """
    from .cluster import dask_client, validate_cluster_options
    from .dlc_spectrum import write_load_spectrum
    from .plan_checks import check_out_dir

    validate_cluster_options(workers, scheduler, cluster, cluster_options)
    case, table, directory = load_design_load_cases(reference)
    if only is not None and (isinstance(only, bool) or not isinstance(only, int) or only < 1):
        raise CaseError(f"--only must be a whole number >= 1 (got {only!r})")
    out = Path(out_dir) / case.name
    check_out_dir("--out", Path(out_dir), "a design load case batch")
    files = out / "dlc"
    files.mkdir(parents=True, exist_ok=True)
    loads = table.load_cases()
    rows: dict[str, dict] = {}
    pending = []
    for load in loads:
        if case_file_complete(files / f"{load.name}.nc"):
            rows[load.name] = {
                "load_case": load.name,
                "status": "reused",
                "wall_s": 0.0,
                "file": str(files / f"{load.name}.nc"),
                "error": "",
            }
        else:
            pending.append(load)
    if only is not None:
        pending = pending[:only]
    bar = ProgressBar("dlc", enabled=progress)
    if pending:
        with dask_client(
            workers=workers, scheduler=scheduler, cluster=cluster, cluster_options=cluster_options
        ) as client:
            from distributed import as_completed

            futures = client.map(
                run_load_case,
                [str(directory)] * len(pending),
                [load.name for load in pending],
                [str(files)] * len(pending),
                pure=False,
            )
            owner = {future.key: load.name for future, load in zip(futures, pending)}
            for done, future in enumerate(as_completed(futures, loop=client.loop), start=1):
                try:
                    row = future.result()
                except Exception as error:  # noqa: BLE001 - e.g. a worker that died too often
                    name = owner[future.key]
                    row = {
                        "load_case": name,
                        "status": "error",
                        "error": f"the task did not finish: {error!r}",
                    }
                rows[row["load_case"]] = row
                bar(done, len(pending))
    table_rows = []
    for load in loads:
        row = rows.get(load.name, {"load_case": load.name, "status": "pending", "error": ""})
        row.update(wind_speed=load.wind_speed, seed=load.seed, hours_per_year=load.hours_per_year)
        row.setdefault("file", str(files / f"{load.name}.nc"))
        table_rows.append(row)
    summary = pd.DataFrame(table_rows).reindex(columns=list(DLC_SUMMARY_COLUMNS))
    summary["error"] = summary["error"].fillna("")
    with atomic_path(out / SUMMARY_NAME) as temporary:
        summary.to_csv(temporary, index=False)
    if not all(case_file_complete(files / f"{load.name}.nc") for load in loads):
        return summary, None
    spectrum = write_load_spectrum(
        [(files / f"{load.name}.nc", load) for load in loads],
        table,
        out / SPECTRUM_NAME,
        case_name=case.name,
    )
    return summary, spectrum
