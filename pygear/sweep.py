"""Parameter sweeps on Dask: one task and one NetCDF file per point, then one dataset.

A sweep changes case parameters (``stage.member.parameter``) over lists of values, as
a grid (outer product) or zipped (pairs).  Every point runs its scene's analyses in a
Dask task and writes ``point_<index>_<hash>.nc`` atomically, its parameter values held
as length-1 dimensions, so that ``xarray.open_mfdataset(files, combine="by_coords")``
puts the points back together.  A rerun skips every point whose file carries the same
input hash; a failed point leaves ``point_<index>.error.json`` and the others go on.
At the end the points are combined into ``sweep.nc`` (failed points as NaN).
"""

from __future__ import annotations

import json
import math
import os
import re
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from .case import Case, Scene, load_case
from .cluster import task_files
from .components import CaseError
from .io import write_netcdf
from .progress import ProgressBar
from .sweep_points import (
    POINT_ANALYSES,
    PointTask,
    SweepParameter,
    apply_assignments,
    error_message,
    parse_param,
    point_hash,
    run_point,
    sweep_points,
    validate_sweep,
    write_error_record,
)

__all__ = [
    "COMBINED_NAME",
    "POINT_ANALYSES",
    "combine_points",
    "parse_param",
    "run_sweep",
    "sweep_summary",
    "validate_sweep",
]

COMBINED_NAME = "sweep.nc"
"""File name of the combined dataset in the sweep's directory."""

_POINT_FILE = re.compile(r"^point_(\d+)_([0-9a-f]{16})\.nc$")
_ERROR_FILE = re.compile(r"^point_(\d+)\.error\.json$")


# --------------------------------------------------------------------------- the sweep


def _stored_hash(path: Path) -> str | None:
    import netCDF4

    try:
        with task_files(), netCDF4.Dataset(path) as dataset:
            return str(dataset.getncattr("point_hash"))
    except (OSError, AttributeError, RuntimeError):
        return None


def _existing_files(directory: Path) -> dict[str, Path]:
    """Point files of earlier runs in ``directory``, by their hash."""
    found = {}
    for path in directory.glob("point_*.nc"):
        match = _POINT_FILE.match(path.name)
        if match:
            found[match.group(2)] = path
    return found


def _remove_stale(directory: Path, keep: set[str]) -> None:
    """Remove point files and error records that belong to no point of this sweep."""
    for path in directory.glob("point_*"):
        if (_POINT_FILE.match(path.name) or _ERROR_FILE.match(path.name)) and path.name not in keep:
            path.unlink()


def run_sweep(
    case_ref: str | os.PathLike | Case,
    params: Sequence[tuple[str, object]],
    *,
    zip_params: bool = False,
    scene: str | None = None,
    formulation: str | None = None,
    out_dir: str | os.PathLike,
    workers: int = 2,
    scheduler: str | None = None,
    cluster: str | None = None,
    cluster_options: Mapping[str, Any] | None = None,
    progress: bool = True,
) -> xr.Dataset:
    """Run a scene at every point of a parameter grid (or zipped list) on Dask.

    Parameters
    ----------
    case_ref : path, case name or Case
        The case to modify.
    params : sequence of (path, values)
        Parameter paths such as ``planetary.sun_mesh.stiffness`` and their values:
        numbers, or text as for :func:`~pygear.sensitivity.parse_values`.
    zip_params : bool
        Pair the parameters' values one to one instead of forming their grid.
    scene : str, optional
        Scene to run (default: the case's first).
    formulation : str, optional
        Override of the scene's formulation.
    out_dir : path
        Directory of the point files and of ``sweep.nc``; it holds one sweep.
    workers : int
        Workers of the local cluster.
    scheduler : str, optional
        Address of a running Dask scheduler to use instead.
    cluster : {"slurm", "pbs"}, optional
        Start a dask-jobqueue cluster with ``cluster_options`` (queue, walltime,
        memory, cores, jobs).
    progress : bool
        Draw a progress bar and print a summary on stderr.

    Returns
    -------
    xarray.Dataset
        The combined results: one dimension per swept parameter (or ``point`` when
        zipped), ``point_status`` and ``point_error``; attributes ``points``,
        ``points_computed``, ``points_reused`` and ``points_failed``.

    Raises
    ------
    CaseError
        Before any work, for a bad parameter, scene, formulation or cluster option.
    """
    from .cluster import dask_client, validate_cluster_options

    started = time.perf_counter()
    case = case_ref if isinstance(case_ref, Case) else load_case(case_ref)
    chosen, resolved, parameters = validate_sweep(
        case, params, zip_params=zip_params, scene=scene, formulation=formulation
    )
    validate_cluster_options(workers, scheduler, cluster, cluster_options)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    points = sweep_points(parameters, zip_params)
    n_points = len(points)
    shared_attrs = (
        ("case", case.name),
        ("scene", chosen.name),
        ("sweep_parameters", " ".join(p.path for p in parameters)),
        ("sweep_layout", "zip" if zip_params else "grid"),
    )
    records, files, tasks = _plan_points(
        out, case, chosen, resolved, points, zip_params, shared_attrs
    )

    timing = {"time_plan_s": time.perf_counter() - started}
    bar = ProgressBar(f"sweep {case.name}", enabled=progress)
    settled = len(records)
    if settled:
        bar(settled, n_points)
    results: dict[int, xr.Dataset | Path] = {}
    if tasks:
        with dask_client(
            workers=workers, scheduler=scheduler, cluster=cluster, cluster_options=cluster_options
        ) as client:
            for record in _run_tasks(client, tasks, lambda n: bar(settled + n, n_points)):
                if "data" in record:
                    results[record["index"]] = record.pop("data")
                records[record["index"]] = record
    timing["time_run_s"] = time.perf_counter() - started - timing["time_plan_s"]
    for index, path in files.items():
        if records[index]["status"] != "failed":
            results.setdefault(index, path)
    combined = combine_points(
        [results[i] for i in sorted(results)], parameters, zip_params, records, n_points
    )
    combined.attrs.update(dict(shared_attrs))
    combined.attrs.update(
        {
            "formulation": resolved,
            "input_hash": case.input_hash(),
            "points": n_points,
            "points_computed": sum(r["status"] == "computed" for r in records.values()),
            "points_reused": sum(r["status"] == "reused" for r in records.values()),
            "points_failed": sum(r["status"] == "failed" for r in records.values()),
            **timing,
        }
    )
    path = write_netcdf(
        combined,
        out / COMBINED_NAME,
        title=f"Sweep of {case.name}, scene {chosen.name}, over "
        + ", ".join(p.path for p in parameters),
        input_hash=case.input_hash(),
    )
    combined.attrs["path"] = str(path)
    combined.attrs["wall_s"] = time.perf_counter() - started
    if progress:
        print(sweep_summary(combined), file=sys.stderr)
    return combined


def _plan_points(
    out: Path,
    case: Case,
    scene: Scene,
    formulation: str,
    points: list[dict],
    zipped: bool,
    attrs: tuple,
) -> tuple[dict[int, dict], dict[int, Path], list[PointTask]]:
    """Sort the points into reused (a file with the same hash exists), failed at once
    (the case refuses a value) and to run; remove files of points no longer in the sweep.

    Returns
    -------
    records, files, tasks
        Records of the settled points by index, the file of every point that has or
        will have one, and the tasks to run.
    """
    width = max(4, len(str(len(points) - 1)))
    existing = _existing_files(out)
    records: dict[int, dict] = {}
    files: dict[int, Path] = {}
    tasks: list[PointTask] = []
    keep: set[str] = set()
    for index, assignments in enumerate(points):
        name = f"point_{index:0{width}d}"
        error_path = out / f"{name}.error.json"
        try:
            modified = apply_assignments(case, assignments, scene)
        except CaseError as error:
            digest = point_hash(case, scene, formulation + json.dumps(assignments))
            task = PointTask(
                index, case, scene, formulation, assignments, zipped, "", str(error_path), digest
            )
            write_error_record(error_path, task, str(error))
            records[index] = {"index": index, "status": "failed", "error": str(error)}
            keep.add(error_path.name)
            continue
        digest = point_hash(modified, scene, formulation)
        path = out / f"{name}_{digest}.nc"
        earlier = existing.get(digest)
        if earlier is not None and earlier != path and _stored_hash(earlier) == digest:
            os.replace(earlier, path)  # the same point at another index (a changed grid)
        files[index] = path
        keep.add(path.name)
        if path.is_file() and _stored_hash(path) == digest:
            records[index] = {"index": index, "status": "reused"}
            continue
        keep.add(error_path.name)  # an earlier failure stays until the point succeeds
        tasks.append(
            PointTask(
                index,
                modified,
                scene,
                formulation,
                assignments,
                zipped,
                str(path),
                str(error_path),
                digest,
                attrs,
            )
        )
    _remove_stale(out, keep)
    return records, files, tasks


def _run_tasks(client, tasks: list[PointTask], advance: Callable[[int], None]):
    """Submit the points, yield their records as they finish (failures included)."""
    from distributed import as_completed

    futures = client.map(
        run_point, tasks, key=[f"pygear-point-{t.index}-{t.point_hash}" for t in tasks], pure=False
    )
    owner = {future.key: task for future, task in zip(futures, tasks)}
    finished = as_completed(futures, with_results=True, raise_errors=False, loop=client.loop)
    for done, (future, result) in enumerate(finished, start=1):
        if future.status == "finished":
            record = result
        else:  # e.g. a worker that died on the point: (type, error, traceback) or cancelled
            task = owner[future.key]
            error = result[1] if isinstance(result, tuple) else result
            message = f"the task did not finish: {error_message(error)}"
            write_error_record(task.error_path, task, message)
            record = {"index": task.index, "status": "failed", "error": message}
        advance(done)
        yield record


def combine_points(
    points: Sequence[xr.Dataset | Path],
    parameters: Sequence[SweepParameter],
    zipped: bool,
    records: Mapping[int, dict],
    n_points: int,
) -> xr.Dataset:
    """One dataset from the points (their datasets or files), on the full grid (or point
    list) of the sweep.

    Points without a file (failed) hold NaN (empty text for text variables);
    ``point_status`` and ``point_error`` say what happened at every point.
    """
    if points:
        # what open_mfdataset(files, combine="by_coords") does, without dask arrays
        datasets = []
        with task_files():
            for point in points:
                if isinstance(point, xr.Dataset):
                    datasets.append(point)
                    continue
                with xr.open_dataset(point, engine="netcdf4") as opened:
                    datasets.append(opened.load())
        data = xr.combine_by_coords(
            datasets,
            data_vars="all",
            coords="different",
            compat="no_conflicts",
            join="outer",
            combine_attrs="drop",
        )
        data = data.drop_encoding()  # integer encodings of the files cannot hold NaN
    else:
        data = xr.Dataset()
    if zipped:
        data = data.reindex(point=np.arange(n_points)) if points else data
        data = data.assign_coords({p.path: ("point", list(p.values), p.attrs) for p in parameters})
        data = data.assign_coords(
            point=("point", np.arange(n_points), {"long_name": "sweep point"})
        )
        dims = ("point",)
    else:
        data = data.reindex({p.path: list(p.values) for p in parameters}) if points else data
        data = data.assign_coords({p.path: (p.path, list(p.values), p.attrs) for p in parameters})
        dims = tuple(p.path for p in parameters)
    for name in list(data.data_vars):
        if data[name].dtype == object:  # text: a failed point holds "" rather than NaN
            values = data[name].values
            text = [v if isinstance(v, str) else "" for v in values.ravel()]
            data[name] = data[name].copy(data=np.array(text, dtype=object).reshape(values.shape))
    shape = tuple(data.sizes[d] for d in dims)
    status = np.array([records[i]["status"] for i in range(n_points)], dtype=object)
    errors = np.array([records[i].get("error", "") for i in range(n_points)], dtype=object)
    data["point_status"] = (
        dims,
        status.reshape(shape),
        {"long_name": "computed, reused (file of an earlier run) or failed"},
    )
    data["point_error"] = (dims, errors.reshape(shape), {"long_name": "error of a failed point"})
    return data


def sweep_summary(sweep: xr.Dataset) -> str:
    """A few lines: points computed, reused and failed, the first errors, the file."""
    attrs = sweep.attrs
    lines = [
        f"sweep of {attrs.get('case')} (scene {attrs.get('scene')}, "
        f"{attrs.get('formulation')}) over {attrs.get('sweep_parameters')}: "
        f"{attrs.get('points')} points, {attrs.get('points_computed')} computed, "
        f"{attrs.get('points_reused')} reused, {attrs.get('points_failed')} failed "
        f"in {attrs.get('wall_s', math.nan):.1f} s"
    ]
    failed = np.flatnonzero(sweep.point_status.values.ravel() == "failed")
    for index in failed[:5]:
        lines.append(f"  point {index}: {sweep.point_error.values.ravel()[index]}")
    if failed.size > 5:
        lines.append(f"  ... and {failed.size - 5} more (see point_*.error.json)")
    if "path" in attrs:
        lines.append(f"  wrote {attrs['path']}")
    return "\n".join(lines)
