"""Scale-out of a parameter sweep: parallel efficiency on 2 workers against 1, and the
overhead per point against the point's own run.

The same sweep runs into a fresh directory on a warm local cluster (worker processes
started and pygear imported before timing), as ``run_sweep`` starts its own, at two
sizes, so that the fixed cost of a sweep (connecting, planning, combining, writing
``sweep_<hash>.nc``) and the cost per point separate; medians of repeats.
The point's own run is measured in this process: its analyses alone, and with its
NetCDF file written (``pygear.runs.sweep_points.run_point``).  The machine's load average
is printed: on a shared 2-core machine other work takes cores from the workers.

    python benchmarks/bench_sweep.py                 # modal points of the study case
    python benchmarks/bench_sweep.py --scene runup   # transient points, once supported
"""

from __future__ import annotations

import argparse
import os
import shutil
import tempfile
from pathlib import Path

from distributed import LocalCluster
from timing import median_seconds

from pygear import load_case
from pygear.assembly import assemble
from pygear.runs.sweep import POINT_ANALYSES, run_sweep
from pygear.runs.sweep_points import (
    PointTask,
    apply_assignments,
    point_hash,
    run_point,
    sweep_points,
    validate_sweep,
)

CASE = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"
PARAMETER = "planetary.sun_mesh.stiffness"


def values(n: int) -> str:
    # +-40 % around the study case's 5e8 N/m: the run-up's explicit mesh-stiffness load is
    # stable there at the paper's time step (stiffer meshes need 'iterate' or a smaller step)
    return f"linspace(3e8,7e8,{n})"


def serial_per_point(case, scene: str | None, n: int, repeats: int) -> tuple[float, float]:
    """Seconds per point, one after another in this process: the analyses alone, and
    the analyses with the point file."""
    chosen, formulation, parameters = validate_sweep(case, [(PARAMETER, values(n))], scene=scene)
    points = sweep_points(parameters, zip_params=False)
    cases = [apply_assignments(case, a, chosen) for a in points]
    scratch = Path(tempfile.mkdtemp(prefix="bench_sweep_serial_"))

    def analyses_only() -> None:
        for modified in cases:
            model = assemble(modified, chosen, formulation=formulation)
            for analysis in chosen.analyses:
                POINT_ANALYSES[analysis](modified, chosen, model)

    def with_files() -> None:
        for i, (modified, assignments) in enumerate(zip(cases, points)):
            path, error = str(scratch / f"p{i}.nc"), str(scratch / f"p{i}.json")
            digest = point_hash(modified, chosen, formulation)
            task = PointTask(i, modified, chosen, formulation, assignments, path, error, digest)
            assert run_point(task)["status"] == "computed"

    try:
        return median_seconds(analyses_only, repeats) / n, median_seconds(with_files, repeats) / n
    finally:
        shutil.rmtree(scratch)


def sweep_seconds(address: str, scene: str | None, n: int, repeats: int) -> float:
    def once() -> None:
        with tempfile.TemporaryDirectory(prefix="bench_sweep_") as out:
            result = run_sweep(CASE, [(PARAMETER, values(n))], scene=scene, out_dir=out,
                               scheduler=address, progress=False)  # fmt: skip
            assert result.attrs["points_failed"] == 0, result.point_error.values

    return median_seconds(once, repeats)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=96, help="points of the large sweep")
    parser.add_argument("--repeats", type=int, default=5, help="repeats (median)")
    parser.add_argument("--scene", help="scene of the points (default: the case's first)")
    args = parser.parse_args()
    large, small = args.points, max(2, args.points // 4)
    load_before = os.getloadavg()[0]
    analyses, with_file = serial_per_point(load_case(CASE), args.scene, large, 3)
    timings: dict[tuple[int, int], float] = {}
    for workers in (1, 2):
        with LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster:
            sweep_seconds(cluster.scheduler_address, args.scene, 4, 1)  # warm up
            for n in (small, large):
                timings[workers, n] = sweep_seconds(
                    cluster.scheduler_address, args.scene, n, args.repeats
                )
    slope = {w: (timings[w, large] - timings[w, small]) / (large - small) for w in (1, 2)}
    fixed = {w: timings[w, large] - slope[w] * large for w in (1, 2)}
    print(f"sweeps of {small} and {large} points over {PARAMETER} ({CASE.name}, scene "
          f"{args.scene or 'first'}), medians of {args.repeats}, "
          f"load average {load_before:.2f} -> {os.getloadavg()[0]:.2f}")  # fmt: skip
    rows = [
        ("point: analyses alone, serial", analyses * 1e3, "ms"),
        ("point: analyses + its NetCDF file, serial", with_file * 1e3, "ms"),
        ("sweep, 1 worker: per point", slope[1] * 1e3, "ms"),
        ("sweep, 2 workers: per point", slope[2] * 1e3, "ms"),
        ("overhead per point, 1 worker", (slope[1] - analyses) * 1e3, "ms"),
        ("  of which the point file", (with_file - analyses) * 1e3, "ms"),
        ("  of which Dask and the client", (slope[1] - with_file) * 1e3, "ms"),
        ("fixed cost of a sweep, 1 / 2 workers", fixed[1], f"s / {fixed[2]:.2f} s"),
        (f"{large} points, 1 / 2 workers", timings[1, large], f"s / {timings[2, large]:.2f} s"),
        (
            f"parallel efficiency, {large} points",
            timings[1, large] / timings[2, large] / 2 * 100,
            "%",
        ),  # fmt: skip
        ("parallel efficiency per point (slopes)", slope[1] / slope[2] / 2 * 100, "%"),
    ]
    for name, value, unit in rows:
        print(f"{name:<42} {value:>8.2f} {unit}")


if __name__ == "__main__":
    main()
