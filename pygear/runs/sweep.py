"""Parameter sweeps on Dask: one task and one NetCDF file per point, then one dataset.

A sweep changes case parameters (``stage.member.parameter``) over lists of values, as
a grid (outer product) or zipped (pairs).  Every point runs its scene's analyses in a
Dask task and writes ``point_<hash>.nc`` atomically, named by the hash of its inputs
(the modified case, scene, formulation and pygear's source identity, see
:func:`~pygear.runs.sweep_points.point_hash`), its parameter values held as length-1
dimensions, so that ``xarray.open_mfdataset(files, combine="by_coords")`` puts a grid
sweep's points back together.  A point is known by that hash alone, never by its place
in a sweep: any later sweep into the same directory, of either layout and in any order,
reuses a point whose file carries its hash, holds no NaN where a number belongs
(:data:`~pygear.runs.sweep_points.NAN_IS_A_RESULT`) and has no error record beside it.  A
failed point leaves ``point_<hash>.error.json`` and the others go on.  At the end the
points are combined into ``sweep_<hash>.nc`` (failed points as NaN), named by the
sweep's layout, parameters and point hashes.  No sweep deletes a file: several sweeps
share one directory and each keeps its combined dataset.
"""

from __future__ import annotations

import errno
import hashlib
import json
import math
import os
import sys
import time
import uuid
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..errors import CaseError
from ..io import index_labels, write_netcdf
from ..model.case import Case, Scene, load_case
from ..model.case_json import case_json
from ..resources import FLOAT_BYTES, format_bytes, require_disk
from .cluster import task_files
from .plan_checks import check_out_dir
from .progress import ProgressBar
from .sweep_points import (
    NAN_IS_A_RESULT,
    POINT_ANALYSES,
    PointTask,
    SweepParameter,
    apply_assignments,
    dimension_name,
    error_message,
    parse_param,
    point_hash,
    run_point,
    scene_with,
    sweep_points,
    validate_sweep,
    write_error_record,
)

__all__ = [
    "POINT_ANALYSES",
    "combine_points",
    "combined_path",
    "parse_param",
    "run_sweep",
    "sweep_summary",
    "validate_sweep",
]

# --------------------------------------------------------------------------- the files


def _point_path(directory: Path, digest: str) -> Path:
    return directory / f"point_{digest}.nc"


def _error_path(directory: Path, digest: str) -> Path:
    return directory / f"point_{digest}.error.json"


def combined_path(
    directory: str | os.PathLike,
    parameters: Sequence[SweepParameter],
    zipped: bool,
    point_hashes: Sequence[str],
) -> Path:
    """``<directory>/sweep_<hash>.nc``: the hash of the layout, the parameter paths and
    the point hashes in order, so that only a rerun of the same sweep replaces it."""
    text = json.dumps(
        {
            "layout": "zip" if zipped else "grid",
            "parameters": [p.path for p in parameters],
            "points": list(point_hashes),
        }
    )
    return Path(directory) / f"sweep_{hashlib.sha256(text.encode()).hexdigest()[:16]}.nc"


def _reusable_point(directory: Path, digest: str) -> xr.Dataset | None:
    """The point's results from an earlier run, or None when it must run: no file, an
    error record beside it, a file that cannot be read or carries another hash, or NaN
    in a result where NaN is no answer (:data:`NAN_IS_A_RESULT`)."""
    path = _point_path(directory, digest)
    if not path.is_file() or _error_path(directory, digest).exists():
        return None
    try:
        with task_files(), xr.open_dataset(path, engine="netcdf4") as opened:
            if opened.attrs.get("point_hash") != digest:
                return None
            data = index_labels(opened.load())
    except (OSError, ValueError, RuntimeError):
        return None
    for name, values in data.data_vars.items():
        if name in NAN_IS_A_RESULT or values.dtype.kind not in "fc":
            continue
        if np.isnan(values.values).any():
            return None
    return data


# --------------------------------------------------------------------------- the sweep


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
        numbers, or text as for :func:`~pygear.analysis.modes.sensitivity.parse_values`.
    zip_params : bool
        Pair the parameters' values one to one instead of forming their grid.
    scene : str, optional
        Scene to run (default: the case's first).
    formulation : str, optional
        Override of the scene's formulation.
    out_dir : path
        Directory of the point files (``point_<hash>.nc``, shared by every sweep that
        reaches the same inputs) and of the combined ``sweep_<hash>.nc``.  Sweeps may
        share it: none deletes a file, each reuses the points already there.
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
        zipped), ``point_status``, ``point_error`` and ``point_hash`` (the name of the
        point's files); attributes ``points``, ``points_computed``, ``points_reused``,
        ``points_failed`` and ``path`` (the combined file).

    Raises
    ------
    CaseError
        Before any work, for a bad parameter or value, scene, formulation or cluster
        option, an ``out_dir`` that cannot be a directory, or point files that would
        not fit on its disk.
    OSError
        ENOSPC, in one line naming the file and the space the rest needs, when the disk
        fills during the sweep (no partial file is left).
    """
    from .cluster import dask_client, validate_cluster_options

    started = time.perf_counter()
    case = case_ref if isinstance(case_ref, Case) else load_case(case_ref)
    chosen, resolved, parameters = validate_sweep(
        case, params, zip_params=zip_params, scene=scene, formulation=formulation
    )
    validate_cluster_options(workers, scheduler, cluster, cluster_options)
    out = Path(out_dir)
    check_out_dir("--out", out, "a sweep")
    points = sweep_points(parameters, zip_params)
    n_points = len(points)
    point_bytes = _point_file_bytes(case, chosen, resolved)
    require_disk(  # at most: every point runs (the reused ones are not known yet)
        "--param",
        2 * n_points * point_bytes,
        out,
        f"{n_points:,} point files and the combined file, about {format_bytes(point_bytes)} "
        "a point",
        "sweep fewer values or free some space",
    )
    out.mkdir(parents=True, exist_ok=True)
    shared_attrs = (
        ("case", case.name),
        ("scene", chosen.name),
        ("sweep_parameters", " ".join(p.path for p in parameters)),
        ("sweep_dimensions", " ".join(p.name for p in parameters)),
        ("sweep_layout", "zip" if zip_params else "grid"),
    )
    records, hashes, found, tasks = _plan_points(out, case, chosen, resolved, points, shared_attrs)

    timing = {"time_plan_s": time.perf_counter() - started}
    bar = ProgressBar(f"sweep {case.name}", enabled=progress)
    settled = sum(index in records or digest in found for index, digest in enumerate(hashes))
    if settled:
        bar(settled, n_points)
    outcome: dict[str, dict] = {}  # the run's record of every point hash it ran
    results: dict[str, xr.Dataset | Path] = dict(found)
    if tasks:
        sharing = {t.point_hash: hashes.count(t.point_hash) for t in tasks}  # zipped repeats
        with dask_client(
            workers=workers, scheduler=scheduler, cluster=cluster, cluster_options=cluster_options
        ) as client:
            for record in _run_tasks(client, tasks):
                if record.get("disk_full"):  # no other point can be written either
                    left = len(tasks) - len(outcome)
                    raise OSError(
                        errno.ENOSPC,
                        f"{record['error']} (about {format_bytes(point_bytes)} a point; "
                        f"the {left:,} points left and the combined file need about "
                        f"{format_bytes(2 * left * point_bytes)}); no partial file is left",
                    )
                digest = record["point_hash"]
                if "data" in record:
                    results[digest] = record.pop("data")
                elif record["status"] == "computed":
                    results[digest] = _point_path(out, digest)
                outcome[digest] = record
                settled += sharing[digest]
                bar(settled, n_points)
    timing["time_run_s"] = time.perf_counter() - started - timing["time_plan_s"]
    for index, digest in enumerate(hashes):
        if index in records:  # refused by the case
            continue
        if digest in found:
            records[index] = {"index": index, "status": "reused"}
        else:
            record = outcome[digest]
            records[index] = {"index": index, "status": record["status"]}
            if "error" in record:
                records[index]["error"] = record["error"]
    placed = {i: results[d] for i, d in enumerate(hashes) if records[i]["status"] != "failed"}
    combined = combine_points(placed, points, parameters, zip_params, records, n_points)
    dims = ("point",) if zip_params else tuple(p.name for p in parameters)
    combined["point_hash"] = (
        dims,
        np.array(hashes, dtype=object).reshape(combined.point_status.shape),
        {"long_name": "input hash of the point: its files are point_<hash>.nc (.error.json)"},
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
        combined_path(out, parameters, zip_params, hashes),
        title=f"Sweep of {case.name}, scene {chosen.name}, over "
        + ", ".join(p.path for p in parameters),
        input_hash=case.input_hash(),
        case_json=case_json(case.for_scene(chosen)),
    )
    combined.attrs["path"] = str(path)
    combined.attrs["wall_s"] = time.perf_counter() - started
    if progress:
        print(sweep_summary(combined), file=sys.stderr)
    return combined


POINT_FILE_OVERHEAD = 64_000
"""Bytes of a point file beyond its arrays: NetCDF4/HDF5 metadata, the case as JSON and
the attributes (a transient point of the planetary case writes 54 kB in all)."""


def _point_file_bytes(case: Case, scene: Scene, formulation: str) -> float:
    """A point file's size, at most about: the overhead and 8 bytes for every entry of
    an n x n table over the model's n DOFs (mode x DOF: the largest a point keeps)."""
    if case.drivetrain is not None:
        from .plan_checks import drivetrain_size

        dofs = drivetrain_size(case, scene.dof_set)[0]
    else:
        from ..assembly.matrices import assemble

        dofs = assemble(case.for_scene(scene), scene, formulation=formulation).size
    return POINT_FILE_OVERHEAD + FLOAT_BYTES * float(dofs) ** 2


def _plan_points(
    out: Path,
    case: Case,
    scene: Scene,
    formulation: str,
    points: list[dict],
    attrs: tuple,
) -> tuple[dict[int, dict], list[str], dict[str, xr.Dataset], list[PointTask]]:
    """Hash every point and sort it: failed at once (the case refuses a value), found
    (its file from an earlier run is sound) or to run (once per hash).

    Returns
    -------
    records, hashes, found, tasks
        Records of the points refused by the case, by index; the hash of every point
        in order; the results found, by hash; the tasks to run, one per hash.
    """
    records: dict[int, dict] = {}
    hashes: list[str] = []
    found: dict[str, xr.Dataset] = {}
    tasks: dict[str, PointTask] = {}
    for index, assignments in enumerate(points):
        try:
            modified = apply_assignments(case, assignments, scene)
            point_scene = scene_with(scene, assignments)  # a swept carrier speed
        except CaseError as error:
            digest = point_hash(case, scene, formulation + json.dumps(assignments))
            hashes.append(digest)
            error_path = _error_path(out, digest)
            task = PointTask(
                index, case, scene, formulation, assignments, "", str(error_path), digest
            )
            write_error_record(error_path, task, str(error))
            records[index] = {"index": index, "status": "failed", "error": str(error)}
            continue
        digest = point_hash(modified, point_scene, formulation)
        hashes.append(digest)
        if digest in found or digest in tasks:  # a zipped sweep may repeat a pair
            continue
        data = _reusable_point(out, digest)
        if data is not None:
            found[digest] = data
            continue
        tasks[digest] = PointTask(
            index,
            modified,
            point_scene,
            formulation,
            assignments,
            str(_point_path(out, digest)),
            str(_error_path(out, digest)),
            digest,
            attrs,
        )
    return records, hashes, found, list(tasks.values())


def _run_tasks(client, tasks: list[PointTask]):
    """Submit the points, yield their records as they finish (failures included)."""
    from distributed import as_completed

    run = uuid.uuid4().hex[:12]  # another sweep on the same scheduler has its own tasks
    futures = client.map(
        run_point, tasks, key=[f"pygear-point-{t.point_hash}-{run}" for t in tasks], pure=False
    )
    owner = {future.key: task for future, task in zip(futures, tasks)}
    finished = as_completed(futures, with_results=True, raise_errors=False, loop=client.loop)
    for future, result in finished:
        if future.status == "finished":
            yield result
            continue
        # e.g. a worker that died on the point: (type, error, traceback) or cancelled
        task = owner[future.key]
        error = result[1] if isinstance(result, tuple) else result
        message = f"the task did not finish: {error_message(error)}"
        write_error_record(task.error_path, task, message)
        yield {
            "index": task.index,
            "point_hash": task.point_hash,
            "status": "failed",
            "error": message,
        }


def _placed(data: xr.Dataset, assignments: Mapping, zipped: bool, index: int) -> xr.Dataset:
    """A point's results placed where this sweep has them: on ``point=[index]`` when
    zipped, else on a length-1 dimension per parameter.  The placement stored in the
    file (by whichever sweep wrote it) is taken off first."""
    data = data.drop_vars("scene", errors="ignore")  # a file's own; the sweep writes one
    stored = [dimension_name(p) for p in json.loads(data.attrs.get("point_parameters", "{}"))]
    data = data.isel({name: 0 for name in stored if name in data.dims}, drop=True)
    data = data.drop_vars([name for name in stored if name in data.variables])
    if zipped:
        return data.expand_dims(point=[index])
    return data.expand_dims({dimension_name(p): [v] for p, v in assignments.items()})


def combine_points(
    points: Mapping[int, xr.Dataset | Path],
    assignments: Sequence[Mapping],
    parameters: Sequence[SweepParameter],
    zipped: bool,
    records: Mapping[int, dict],
    n_points: int,
) -> xr.Dataset:
    """One dataset from the points (their datasets or files, by index), on the full
    grid (or point list) of the sweep.

    Every point is placed by its own parameter values, ``assignments[index]``, never by
    the index its file was written for.  Points without results (failed) hold NaN
    (empty text for text variables); ``point_status`` and ``point_error`` say what
    happened at every point.
    """
    if points:
        # what open_mfdataset(files, combine="by_coords") does, without dask arrays
        datasets = []
        with task_files():
            for index, point in sorted(points.items()):
                if not isinstance(point, xr.Dataset):
                    with xr.open_dataset(point, engine="netcdf4") as opened:
                        point = index_labels(opened.load())
                datasets.append(_placed(point, assignments[index], zipped, index))
        data = xr.combine_by_coords(
            datasets,
            data_vars="all",
            coords="different",
            compat="no_conflicts",
            join="outer",
            combine_attrs="override",  # keeps the variables' units and long names
        )
        data = data.drop_encoding()  # integer encodings of the files cannot hold NaN
        data.attrs = {}  # the first point's own (its hash): the sweep sets its own
    else:
        data = xr.Dataset()
    if zipped:
        data = data.reindex(point=np.arange(n_points)) if points else data
        data = data.assign_coords({p.name: ("point", list(p.values), p.attrs) for p in parameters})
        data = data.assign_coords(
            point=("point", np.arange(n_points), {"long_name": "sweep point"})
        )
        dims = ("point",)
    else:
        data = data.reindex({p.name: list(p.values) for p in parameters}) if points else data
        data = data.assign_coords({p.name: (p.name, list(p.values), p.attrs) for p in parameters})
        dims = tuple(p.name for p in parameters)
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
