"""``pygear accuracy CASE [--scene NAME] [--tolerance 1%]``: the accuracy-cost study.

Runs :func:`pygear.runs.accuracy.accuracy_study` and writes ``accuracy_<scene>.nc`` (the
whole grid), ``accuracy_<scene>.txt`` (the table that is also printed) and one Pareto
plot per formulation, ``accuracy_<scene>_<formulation>.png``.

For a scene with a ``response`` analysis the ladder is the frequency-domain rung
(:func:`pygear.runs.accuracy.harmonics_study`): the harmonic count H = 2 .. 2^levels
against a reference of twice the largest, and the recommended H for the tolerance;
``accuracy_<scene>.nc``, ``.txt`` and ``accuracy_<scene>_harmonics.png``.
"""

from __future__ import annotations

import argparse
import dataclasses
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import CaseError
from ..model.names import FORMULATIONS

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "HANDLERS",
    "add_parsers",
    "parse_tolerance",
    "write_accuracy",
    "write_harmonics_accuracy",
]


def parse_tolerance(text: str) -> float:
    """``1%`` or ``0.01`` as a fraction; refuses anything not > 0."""
    text = str(text).strip()
    try:
        value = float(text[:-1]) / 100 if text.endswith("%") else float(text)
    except ValueError:
        raise CaseError(f"--tolerance must be a number or a percentage (got {text!r})") from None
    if not value > 0 or value != value or value == float("inf"):
        raise CaseError(f"--tolerance must be > 0 (got {text!r})")
    return value


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """The ``accuracy`` subcommand."""
    parser = commands.add_parser(
        "accuracy", help="error against wall time over a ladder of fidelities and time steps"
    )
    parser.add_argument("case", metavar="CASE", help="case directory or case name under cases/")
    parser.add_argument(
        "--scene",
        help="transient scene (default: the first transient scene), or a response scene: "
        "then the ladder is over the harmonic count",
    )
    parser.add_argument("--tolerance", default="1%", help="accepted error, e.g. 1%% or 0.01")
    parser.add_argument("--out", type=Path, help="output directory (default: out/<case>)")
    parser.add_argument("--workers", type=int, default=2, help="local Dask workers (1: serial)")
    parser.add_argument("--repeats", type=int, help="timed repeats per setting")
    parser.add_argument("--duration", type=float, help="simulated time of every run [s]")
    parser.add_argument("--mean-window", type=float, help="equilibrium window [s]")
    parser.add_argument(
        "--levels",
        type=int,
        help="time steps, halving from the coarsest (a response scene: harmonic counts "
        "2..2^LEVELS, default 7)",
    )
    parser.add_argument("--coarsest-time-step", type=float, help="first time step [s]")
    parser.add_argument("--formulation", nargs="+", choices=FORMULATIONS, help="formulations")
    parser.add_argument("--json", action="store_true", help="print the recommendations as JSON")


def write_accuracy(ds: xr.Dataset, out: Path) -> list[Path]:
    """Write the grid, the table and the Pareto plots of a study into ``out``."""
    from ..analysis.time.accuracy import accuracy_table_text
    from ..io import atomic_path, save_figure, write_netcdf
    from ..plots.accuracy import plot_pareto

    stem = f"accuracy_{ds.attrs['scene']}"
    written = [
        write_netcdf(
            ds,
            out / f"{stem}.nc",
            title=f"Accuracy and cost of {ds.attrs['case']} / {ds.attrs['scene']}",
        )
    ]
    table = out / f"{stem}.txt"
    with atomic_path(table) as temporary:
        temporary.write_text(accuracy_table_text(ds) + "\n")
    written.append(table)
    for formulation in ds.formulation.values.tolist():
        figure = plot_pareto(ds, formulation)
        written.append(
            save_figure(figure, out / f"{stem}_{formulation}.png", dpi=figure.dpi, release=True)
        )
    return written


TIME_ONLY = ("repeats", "duration", "mean_window", "coarsest_time_step", "formulation")
"""Options of the time ladder that a response scene's harmonic ladder has no use for."""


def write_harmonics_accuracy(ds: xr.Dataset, out: Path) -> list[Path]:
    """Write a judged harmonic ladder, its table and its figure into ``out``."""
    from ..analysis.response.harmonics import harmonics_table_text
    from ..io import atomic_path, save_figure, write_netcdf
    from ..plots.response import DPI, plot_harmonics_accuracy

    stem = f"accuracy_{ds.attrs['scene']}"
    out.mkdir(parents=True, exist_ok=True)
    written = [
        write_netcdf(
            ds,
            out / f"{stem}.nc",
            title=f"Harmonic count against error and cost, {ds.attrs['case']} / "
            f"{ds.attrs['scene']}",
        )  # fmt: skip
    ]
    table = out / f"{stem}.txt"
    with atomic_path(table) as temporary:
        temporary.write_text(harmonics_table_text(ds) + "\n")
    written.append(table)
    figure = plot_harmonics_accuracy(ds)
    written.append(save_figure(figure, out / f"{stem}_harmonics.png", dpi=DPI, release=True))
    return written


def _harmonics_accuracy(args: argparse.Namespace, case, scene, tolerance: float) -> int:
    """The frequency-domain rung of a response scene."""
    from ..analysis.response.harmonics import harmonics_table_text
    from ..runs.accuracy import harmonics_study
    from ..runs.json_output import json_text

    for name in TIME_ONLY:
        if getattr(args, name) is not None:
            flag = "--" + name.replace("_", "-")
            raise CaseError(
                f"{flag}: scene {scene.name!r} is a response scene, whose ladder is over "
                "the harmonic count (only --tolerance and --levels apply)"
            )
    ds = harmonics_study(case, scene, tolerance, 7 if args.levels is None else args.levels)
    files = write_harmonics_accuracy(ds, args.out or Path("out") / case.name)
    if args.json:
        keys = ("harmonics", "max_error", "wall_time")
        summary = {k: ds.attrs[f"recommended_{k}"] for k in keys}
        print(json_text({"recommendation": summary, "tolerance": tolerance,
                         "reference_harmonics": int(ds.attrs["reference_harmonics"]),
                         "speeds_judged": int(ds.attrs["speeds_judged"]),
                         "files": [str(p) for p in files]}))  # fmt: skip
        return 0
    print(harmonics_table_text(ds))
    for path in files:
        print(f"wrote {path}")
    return 0


def _accuracy(args: argparse.Namespace) -> int:
    from ..analysis.time.accuracy import AccuracyStudy, accuracy_table_text, load_accuracy_study
    from ..model.case import load_case
    from ..runs.accuracy import accuracy_study
    from ..runs.json_output import json_text
    from ..runs.plan_checks import check_out_dir
    from ..runs.progress import ProgressBar

    tolerance = parse_tolerance(args.tolerance)
    check_out_dir("--out", args.out, "accuracy")
    case = load_case(args.case)
    if args.scene:
        scene = case.scene(args.scene)
    else:
        scene = next((s for s in case.scenes if s.transient is not None), None)
        if scene is None:
            raise CaseError(f"--scene: case {case.name!r} has no transient scene to study")
    if "response" in scene.analyses and scene.transient is None:
        return _harmonics_accuracy(args, case, scene, tolerance)
    study = load_accuracy_study(args.case) or AccuracyStudy()
    changes = {"tolerance": tolerance}
    for name in ("repeats", "duration", "mean_window", "levels", "coarsest_time_step"):
        if getattr(args, name) is not None:
            changes[name] = getattr(args, name)
    if args.formulation:
        changes["formulations"] = tuple(args.formulation)
    if args.workers < 1:
        raise CaseError(f"--workers must be >= 1 (got {args.workers})")
    study = dataclasses.replace(study, **changes)
    study.validate()
    ds = accuracy_study(
        case,
        scene,
        study,
        workers=args.workers,
        progress=ProgressBar(f"accuracy {scene.name}", enabled=not args.json),
    )
    files = write_accuracy(ds, args.out or Path("out") / case.name)
    if args.json:
        keys = ("fidelity", "time_step", "wall_time", "max_error")
        summary = {
            f: {k: ds.attrs[f"recommendation_{f}_{k}"] for k in keys}
            for f in ds.formulation.values.tolist()
        }
        print(json_text({"recommendation": summary, "files": [str(p) for p in files]}))
        return 0
    print(accuracy_table_text(ds))
    print(f"ladder wall time {ds.attrs['study_wall_s']:.1f} s on {args.workers} worker(s)")
    for path in files:
        print(f"wrote {path}")
    return 0


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {"accuracy": _accuracy}
