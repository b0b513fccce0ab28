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
        description="With --dlc, run the design load cases the case file defines "
        "(design_load_cases = DesignLoadCases(...)) instead: one streamed file per load "
        "case in <out>/<case>/dlc/, a complete one never run again (a rerun resumes the "
        "batch; a half-written one runs again), then load_spectrum.nc, the load cases' "
        "rainflow matrices and load duration distributions summed per year.  "
        "Exit code 0 when every scene ran, 1 when some failed, 2 for bad input.",
    )
    batch.add_argument("dirs", metavar="DIR", nargs="+", help="case directories or their parents")
    batch.add_argument("--out", type=Path, default=Path("out"), help="output root (default: out)")
    batch.add_argument(
        "--dlc", action="store_true", help="run the case's design load cases (load spectrum)"
    )
    _add_dask_options(batch)
    _add_cluster_options(batch)
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
    _add_cluster_options(sweep)
    sweep.add_argument("--json", action="store_true", help="print a JSON summary on stdout")


def _add_dask_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--workers", type=int, default=2, help="local Dask workers (default 2)")
    parser.add_argument("--scheduler", metavar="ADDRESS", help="use a running Dask scheduler")


def _add_cluster_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--cluster", choices=("slurm", "pbs"), help="run on a job queue")
    parser.add_argument("--queue", help="job queue (partition)")
    parser.add_argument("--walltime", metavar="HH:MM:SS", help="wall time of each job")
    parser.add_argument("--memory", metavar="4GB", help="memory of each job (default 4GB)")
    parser.add_argument("--cores", type=int, help="cores of each job, one worker each (default 1)")
    parser.add_argument("--jobs", type=int, help="jobs to submit (default: enough for --workers)")


def _cluster_options(args: argparse.Namespace) -> dict:
    return {name: getattr(args, name) for name in ("queue", "walltime", "memory", "cores", "jobs")}


def _batch(args: argparse.Namespace) -> int:
    from ..runs.cluster import local_worker_server

    # the local workers' fork server imports their code while this process loads its own
    with local_worker_server(local=args.scheduler is None and args.cluster is None):
        return _run_dlc(args) if args.dlc else _run_batch(args)


def _sweep(args: argparse.Namespace) -> int:
    from ..runs.cluster import local_worker_server

    with local_worker_server(local=args.scheduler is None and args.cluster is None):
        return _run_sweep(args)


def _run_dlc(args: argparse.Namespace) -> int:
    from ..runs.batch import find_case_dirs
    from ..runs.cluster import validate_cluster_options
    from ..runs.dlc import run_dlc_batch
    from ..runs.json_output import json_text

    validate_cluster_options(args.workers, args.scheduler, args.cluster, _cluster_options(args))
    failed, reports = False, []
    for directory in find_case_dirs(args.dirs):
        summary, spectrum = run_dlc_batch(
            directory,
            out_dir=args.out,
            workers=args.workers,
            scheduler=args.scheduler,
            cluster=args.cluster,
            cluster_options=_cluster_options(args),
            progress=not args.json and progress_wanted(),
        )
        failed |= bool((summary["status"] == "error").any())
        records = json.loads(summary.to_json(orient="records"))
        reports.append({"case": directory.name, "load_cases": records,
                        "load_spectrum": None if spectrum is None else str(spectrum)})  # fmt: skip
        if not args.json:
            shown = summary.drop(columns=["file"])
            print(shown.to_string(index=False, float_format=lambda v: f"{v:.4g}", na_rep="-"))
            counts = summary["status"].value_counts().to_dict()
            print(
                f"{directory.name}: {len(summary)} load cases: "
                + ", ".join(f"{n} {status}" for status, n in counts.items())
                + (f"; load spectrum in {spectrum}" if spectrum else "; no load spectrum yet")
            )
    if args.json:
        print(json_text({"out": str(args.out), "dlc": reports}))
    return 1 if failed else 0


def _run_batch(args: argparse.Namespace) -> int:
    from ..runs.batch import SUMMARY_NAME, run_batch
    from ..runs.json_output import json_text

    if args.cluster is not None:
        from ..errors import CaseError

        raise CaseError("--cluster applies to design load cases and sweeps: add --dlc")
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
    options = _cluster_options(args)
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
