"""Batch runs of many cases on Dask, and the ``batch`` and ``sweep`` commands.

``run_batch`` finds every case directory under the given paths and runs every scene
of every case as one Dask task, writing what ``pygear run`` writes (``<scene>.nc``
and its figures) into ``<out>/<case>/``.  A scene that fails is recorded with its
error and the others go on; a scene asking for an analysis this pygear cannot run
yet is reported as ``unsupported``.  The ``batch`` and ``sweep`` commands are in
:mod:`pygear.cli.batch`.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Iterable, Sequence
from pathlib import Path

import pandas as pd

from ..errors import CaseError
from ..io import atomic_path
from ..model.case import find_case_dir, load_case
from .plan_checks import check_drivetrain_memory, check_out_dir
from .progress import ProgressBar
from .scene_checks import check_scenes
from .scene_runner import SCENE_ANALYSES, RunOptions, run_scene

__all__ = [
    "SUMMARY_COLUMNS",
    "find_case_dirs",
    "run_batch",
    "run_scene_task",
]

SUMMARY_COLUMNS = (
    "case",
    "scene",
    "analyses",
    "status",
    "wall_s",
    "formulation",
    "dof_set",
    "dofs",
    "lowest_hz",
    "t_s",
    "files",
    "error",
)
"""Columns of the batch summary table."""

SUMMARY_NAME = "batch_summary.csv"
"""File name of the summary table in the batch's output directory."""


def find_case_dirs(paths: Iterable[str | os.PathLike]) -> list[Path]:
    """Every case directory given or found under the given paths, in order, once.

    A path is a case directory (it holds ``case.py``), a directory searched for case
    directories at any depth, or a case name under ``cases/``.

    Raises
    ------
    CaseError
        For a path that does not exist, a directory without any case, or two cases
        with the same directory name (their outputs would collide).
    """
    found: list[Path] = []
    for reference in paths:
        path = Path(reference)
        if (path / "case.py").is_file() or path.name == "case.py":
            found.append(find_case_dir(path))
        elif path.is_dir():
            below = sorted(
                p.parent.resolve()
                for p in path.rglob("case.py")
                if not any(part.startswith((".", "__")) for part in p.relative_to(path).parts)
            )
            if not below:
                raise CaseError(f"DIR {str(reference)!r} holds no case directory (no case.py)")
            found.extend(below)
        elif not path.exists() and len(path.parts) == 1:
            found.append(find_case_dir(path))  # a case name; names the places looked in
        else:
            raise CaseError(f"DIR {str(reference)!r} does not exist")
    unique = list(dict.fromkeys(found))
    names = [p.name for p in unique]
    for name in names:
        if names.count(name) > 1:
            clash = ", ".join(str(p) for p in unique if p.name == name)
            raise CaseError(f"two cases are named {name!r} ({clash}); their outputs would collide")
    return unique


def run_scene_task(case_dir: str, scene_name: str, out_dir: str, figures: bool = True) -> dict:
    """Run one scene of one case as ``pygear run`` does (:func:`.scene_runner.run_scene`)
    and return its row; never raises (a Dask task).

    Returns
    -------
    dict
        One row of the summary table (:data:`SUMMARY_COLUMNS`).
    """
    started = time.perf_counter()
    row: dict = {"case": Path(case_dir).name, "scene": scene_name, "files": [], "error": ""}
    try:
        case = load_case(case_dir)
        scene = case.scene(scene_name)
        check_drivetrain_memory(case, dense=True, dof_set=scene.dof_set)  # before assembling
        check_scenes(case, [scene], out=out_dir)  # probe targets, memory, disk: before any work
        row["analyses"] = ",".join(scene.analyses)
        outcome = run_scene(case, scene, out_dir, RunOptions(figures=figures))
        summary = outcome.summary
        frequencies = [f for f in summary.get("frequencies_hz", []) if f > 0]
        row.update(
            formulation=summary["formulation"],
            dof_set=summary["dof_set"],
            dofs=summary["dofs"],
            files=summary["files"],
            lowest_hz=min(frequencies) if frequencies else math.nan,
            t_s=_settling_instant(summary.get("t_s")),
        )
        unsupported = summary.get("unsupported", [])
        if unsupported:
            row["status"] = "unsupported"
            row["error"] = (
                f"batch runs cannot run {', '.join(map(repr, unsupported))} yet "
                f"(they run: {', '.join(SCENE_ANALYSES)})"
            )
        else:
            row["status"] = "ok"
    except Exception as error:  # noqa: BLE001 - one failing scene must not stop the batch
        row["status"] = "error"
        row["error"] = str(error) if isinstance(error, CaseError) else repr(error)
    row["wall_s"] = time.perf_counter() - started
    return row


def _settling_instant(t_s: float | None) -> float:
    """The run's settling instant [s] to the nanosecond: a steady scene settles at its
    start, which the time grid's round-off puts at 1e-17 s or so; NaN when none."""
    if t_s is None or not math.isfinite(t_s):
        return math.nan
    return round(float(t_s), 9) + 0.0  # + 0.0: no "-0"


def run_batch(
    paths: Sequence[str | os.PathLike],
    *,
    out_dir: str | os.PathLike,
    workers: int,
    scheduler: str | None = None,
    progress: bool = True,
    figures: bool = True,
) -> pd.DataFrame:
    """Run every scene of every case found under ``paths`` in parallel on Dask.

    Parameters
    ----------
    paths : sequence of path
        Case directories, directories holding case directories, or case names.
    out_dir : path
        Outputs go to ``out_dir/<case>/``; the summary to ``out_dir/batch_summary.csv``.
    workers : int
        Workers of the local cluster (ignored with ``scheduler``).
    scheduler : str, optional
        Address of a running Dask scheduler.
    progress : bool
        Draw a progress bar on stderr.
    figures : bool
        Draw each scene's figures (after its NetCDF files); False writes NetCDF only.

    Returns
    -------
    pandas.DataFrame
        One row per case and scene (:data:`SUMMARY_COLUMNS`); ``status`` is ``ok``,
        ``error`` (with the message in ``error``) or ``unsupported``.  A case whose
        ``case.py`` cannot be loaded has one row with an empty scene.
    """
    from .cluster import dask_client, validate_cluster_options

    validate_cluster_options(workers, scheduler)
    out = Path(out_dir)
    check_out_dir("--out", out, "a batch")
    rows: list[dict] = []
    tasks: list[tuple[str, str, str]] = []
    directories = find_case_dirs(paths)
    for directory in directories:
        try:
            case = load_case(directory)
        except Exception as error:  # noqa: BLE001 - a broken case.py is one failing case
            message = str(error) if isinstance(error, CaseError) else repr(error)
            rows.append({"case": directory.name, "scene": "", "status": "error", "error": message})
            continue
        if not case.scenes:
            rows.append({"case": directory.name, "scene": "", "status": "ok", "error": "no scenes"})
        for scene in case.scenes:
            tasks.append((str(directory), scene.name, str(out / directory.name)))
    bar = ProgressBar("batch", enabled=progress)
    if tasks:
        with dask_client(workers=workers, scheduler=scheduler) as client:
            from distributed import as_completed

            futures = client.map(run_scene_task, *zip(*tasks), figures=figures, pure=False)
            owner = {future.key: task for future, task in zip(futures, tasks)}
            for done, future in enumerate(as_completed(futures, loop=client.loop), start=1):
                try:
                    rows.append(future.result())
                except Exception as error:  # noqa: BLE001 - e.g. a worker that died
                    case_dir, scene_name, _ = owner[future.key]
                    rows.append(
                        {
                            "case": Path(case_dir).name,
                            "scene": scene_name,
                            "status": "error",
                            "error": f"the task did not finish: {error!r}",
                        }
                    )
                bar(done, len(tasks))
    case_order = {d.name: i for i, d in enumerate(directories)}
    scene_order = {(Path(d).name, s): i for i, (d, s, _) in enumerate(tasks)}
    rows.sort(key=lambda r: (case_order[r["case"]], scene_order.get((r["case"], r["scene"]), -1)))
    table = pd.DataFrame(rows).reindex(columns=list(SUMMARY_COLUMNS))
    table["files"] = table["files"].apply(lambda f: f if isinstance(f, list) else [])
    table["error"] = table["error"].fillna("")
    out.mkdir(parents=True, exist_ok=True)
    with atomic_path(out / SUMMARY_NAME) as temporary:
        table.assign(files=table["files"].apply(" ".join)).to_csv(temporary, index=False)
    return table
