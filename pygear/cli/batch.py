"""``pygear batch`` and ``pygear sweep``: many cases, or one scene over a parameter grid,
on Dask.  Handlers import the runners (and Dask) when called."""

from __future__ import annotations

import argparse
import json
from collections.abc import Callable
from pathlib import Path

from ..model.names import FORMULATIONS
from ..runs.progress import progress_wanted

__all__ = ["HANDLERS", "add_parsers"]


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``batch`` and ``sweep`` subcommands to pygear's subparsers."""
    batch = commands.add_parser(
        "batch",
        help="run every scene of every case under DIRs in parallel (Dask)",
        description="Exit code 0 when every scene ran, 1 when some failed, 2 for bad input.",
    )
    batch.add_argument("dirs", metavar="DIR", nargs="+", help="case directories or their parents")
    batch.add_argument("--out", type=Path, default=Path("out"), help="output root (default: out)")
    _add_dask_options(batch)
    batch.add_argument(
        "--no-figures",
        action="store_true",
        help="write the NetCDF results only (figures are otherwise drawn after them)",
    )
    batch.add_argument("--json", action="store_true", help="print the summary as JSON")

    sweep = commands.add_parser(
        "sweep",
        help="run a scene over a grid of parameter values (Dask), one file per point",
        description="Each point's file, point_<hash>.nc, is named by the hash of its inputs: "
        "the case, scene, formulation, parameter values and pygear's Python and Fortran "
        "sources.  Sweeps may share one --out: a rerun or another sweep reuses every point "
        "already there, in any order and either layout, and no sweep deletes a file; a "
        "point with an error record or NaN results runs again, and so does every point "
        "after the code changes.  Each sweep writes its combined dataset to "
        "sweep_<hash>.nc and prints its name.  "
        "Exit code 0 when every point ran, 1 when some failed, 2 for bad input.",
    )
    sweep.add_argument("case", metavar="CASE", help="case directory or case name under cases/")
    sweep.add_argument(
        "--param",
        action="append",
        required=True,
        metavar="PATH=VALUES",
        help="e.g. planetary.sun_mesh.stiffness=logspace(7,10,7) (repeatable: a grid)",
    )
    sweep.add_argument("--zip", action="store_true", help="pair the values instead of a grid")
    sweep.add_argument("--scene", help="scene to run (default: the case's first)")
    sweep.add_argument("--formulation", choices=FORMULATIONS, help="override the scene's")
    sweep.add_argument(
        "--out",
        type=Path,
        help="sweep directory, may hold other sweeps (default: out/<case>/sweep_<paths>)",
    )
    _add_dask_options(sweep)
    sweep.add_argument("--cluster", choices=("slurm", "pbs"), help="run on a job queue")
    sweep.add_argument("--queue", help="job queue (partition)")
    sweep.add_argument("--walltime", metavar="HH:MM:SS", help="wall time of each job")
    sweep.add_argument("--memory", metavar="4GB", help="memory of each job (default 4GB)")
    sweep.add_argument("--cores", type=int, help="cores of each job, one worker each (default 1)")
    sweep.add_argument("--jobs", type=int, help="jobs to submit (default: enough for --workers)")
    sweep.add_argument("--json", action="store_true", help="print a JSON summary on stdout")


def _add_dask_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--workers", type=int, default=2, help="local Dask workers (default 2)")
    parser.add_argument("--scheduler", metavar="ADDRESS", help="use a running Dask scheduler")


def _batch(args: argparse.Namespace) -> int:
    from ..runs.cluster import local_worker_server

    # the local workers' fork server imports their code while this process loads its own
    with local_worker_server(local=args.scheduler is None):
        return _run_batch(args)


def _sweep(args: argparse.Namespace) -> int:
    from ..runs.cluster import local_worker_server

    with local_worker_server(local=args.scheduler is None and args.cluster is None):
        return _run_sweep(args)


def _run_batch(args: argparse.Namespace) -> int:
    from ..runs.batch import SUMMARY_NAME, run_batch
    from ..runs.json_output import json_text

    table = run_batch(
        args.dirs,
        out_dir=args.out,
        workers=args.workers,
        scheduler=args.scheduler,
        progress=not args.json and progress_wanted(),  # -q: none
        figures=not args.no_figures,
    )
    if args.json:
        records = json.loads(table.to_json(orient="records"))
        print(json_text({"out": str(args.out), "runs": records}))
    else:
        shown = table.assign(files=table["files"].apply(len)).drop(columns=["analyses"])
        print(shown.to_string(index=False, float_format=lambda v: f"{v:.4g}", na_rep="-"))
        counts = table["status"].value_counts().to_dict()
        print(
            f"{len(table)} runs: "
            + ", ".join(f"{n} {status}" for status, n in counts.items())
            + f"; summary in {Path(args.out) / SUMMARY_NAME}"
        )
    return 1 if (table["status"] == "error").any() else 0


def _run_sweep(args: argparse.Namespace) -> int:
    import numpy as np

    from ..model.case import load_case
    from ..runs.json_output import json_text
    from ..runs.sweep import parse_param, run_sweep

    params = [parse_param(text) for text in args.param]
    case = load_case(args.case)
    out = args.out or Path("out") / case.name / (
        "sweep_" + "__".join(path.replace(".", "_") for path, _ in params)
    )
    options = {
        "queue": args.queue,
        "walltime": args.walltime,
        "memory": args.memory,
        "cores": args.cores,
        "jobs": args.jobs,
    }
    result = run_sweep(
        case,
        params,
        zip_params=args.zip,
        scene=args.scene,
        formulation=args.formulation,
        out_dir=out,
        workers=args.workers,
        scheduler=args.scheduler,
        cluster=args.cluster,
        cluster_options=options,
        progress=not args.json and progress_wanted(),  # -q: none
    )
    failed = int(result.attrs["points_failed"])
    if args.json:
        status = result.point_status.values.ravel()
        errors = result.point_error.values.ravel()
        print(
            json_text(
                {
                    "case": result.attrs["case"],
                    "scene": result.attrs["scene"],
                    "formulation": result.attrs["formulation"],
                    "parameters": {path: values.tolist() for path, values in params},
                    "zip": bool(args.zip),
                    **{
                        key: int(result.attrs[key])
                        for key in ("points", "points_computed", "points_reused", "points_failed")
                    },
                    "failures": [
                        {"index": int(i), "error": str(errors[i])}
                        for i in np.flatnonzero(status == "failed")
                    ],
                    "file": result.attrs["path"],
                }
            )
        )
    return 1 if failed else 0


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {"batch": _batch, "sweep": _sweep}
"""Handlers of the commands :func:`add_parsers` adds; each returns the exit code."""
