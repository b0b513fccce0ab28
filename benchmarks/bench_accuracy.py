"""Accuracy study of the study case: the whole ladder's wall time, and what pruning saves.

``python benchmarks/bench_accuracy.py`` runs ``accuracy_study`` on the study case's
``runup`` with its case-file settings on 2 workers and reports the ladder's wall time.
Pruning is measured two ways in the same run: (1) the run-up as the scene asks for it
(pygear's planar pick, its own effects) against always running the full model (spatial
DOFs), medians of repeats; (2) over the ladder's grid, the wall time of every pruned
rung (planar) against its spatial twin at the same effects and time step.
``--grid FILE`` reuses a grid written by ``pygear accuracy`` instead of running the ladder.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

sys.path.insert(0, str(Path(__file__).resolve().parent))
from timing import median_seconds  # noqa: E402

from pygear import load_case  # noqa: E402
from pygear.analysis.time.accuracy import load_accuracy_study  # noqa: E402
from pygear.analysis.time.transient import run_transient  # noqa: E402
from pygear.io import open_dataset  # noqa: E402
from pygear.runs.accuracy import accuracy_study  # noqa: E402


def direct_pruning(repeats: int = 5) -> dict[str, float]:
    """Median wall time of the scene's run (1.5 s) pruned and as the full spatial model."""
    case = load_case("yang2016_planetary")
    scene = case.scene("runup")
    short = dataclasses.replace(scene.transient, duration=1.5, mean_window=0.5)
    pruned = dataclasses.replace(scene, dof_set=None, transient=short)
    full = dataclasses.replace(pruned, dof_set="spatial")
    constant = dataclasses.replace(pruned, effects=())
    times = {
        name: median_seconds(lambda s=s: run_transient(case, s), repeats, warm_up=True)
        for name, s in (("pruned", pruned), ("full", full), ("constant", constant))
    }
    return times


def grid_pruning(ds: xr.Dataset) -> float:
    """Median over formulations, stiffness, modes and steps of wall(planar)/wall(spatial)."""
    ratios = []
    for fidelity in ds.fidelity.values:
        dof_set, rest = str(fidelity).split("/", 1)
        twin = f"spatial/{rest}"
        if dof_set == "planar" and twin in ds.fidelity.values:
            a = ds.wall_time.sel(fidelity=fidelity).values
            b = ds.wall_time.sel(fidelity=twin).values
            ok = np.isfinite(a) & np.isfinite(b)
            ratios += list(a[ok] / b[ok])
    return float(np.median(ratios))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--grid", type=Path, help="reuse this accuracy grid (NetCDF)")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    if args.grid:
        with open_dataset(args.grid) as opened:  # labels as indexes
            ds = opened.load()
    else:
        case = load_case("yang2016_planetary")
        started = time.perf_counter()
        ds = accuracy_study(
            case,
            case.scene("runup"),
            load_accuracy_study("yang2016_planetary"),
            workers=args.workers,
        )
        print(f"ladder measured in this run: {time.perf_counter() - started:.1f} s")
    runs = int((ds.status == "ok").sum() + (ds.status != "ok").sum()) * ds.attrs["repeats"]
    print(
        f"accuracy ladder of yang2016_planetary/runup: {ds.sizes['formulation']} formulations x "
        f"{ds.sizes['fidelity']} fidelities x {ds.sizes['time_step']} time steps "
        f"({runs} timed runs): {ds.attrs['study_wall_s']:.1f} s on {ds.attrs['workers']} workers"
    )
    ratio = grid_pruning(ds)
    print(f"grid: planar rung / its spatial twin, median wall-time ratio {ratio:.2f}")
    times = direct_pruning()
    print(
        f"run-up 1.5 s at 2.5e-5 s: pruned (planar) {times['pruned'] * 1e3:.0f} ms, full "
        f"(spatial) {times['full'] * 1e3:.0f} ms: pruning saves "
        f"{(1 - times['pruned'] / times['full']) * 100:.0f} %; constant stiffness "
        f"{times['constant'] * 1e3:.0f} ms (table never evaluated)"
    )


if __name__ == "__main__":
    main()
