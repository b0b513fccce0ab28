"""Scale-out of a parameter sweep at two sizes (8 and 40 points by default): what a
sweep costs beyond its points, per sweep and per point, and its parallel efficiency
on 2 workers against 1.

Two views, medians of repeats:

* **warm**: the sweep alone on a running local cluster (started by
  ``pygear.runs.cluster.dask_client``, as the commands start theirs), so what is left
  is planning, the tasks and combining the points into ``sweep_<hash>.nc``;
* **command**: the whole ``pygear sweep`` process as typed, cluster start-up, imports
  and shutdown included; after each, the processes of its session are counted (none
  may be left).

The fixed cost per sweep and the cost per point come from the two sizes (intercept
and slope); a point's own run is measured in this process (its analyses alone, and
with its NetCDF file).  The load average is printed: on a shared 2-core machine other
work takes cores from the workers.

    python benchmarks/bench_sweep.py                       # run-up points, 8 and 40
    python benchmarks/bench_sweep.py --scene modal --points 8 96
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import psutil
from timing import median_seconds

from pygear import load_case
from pygear.assembly import assemble
from pygear.runs.cluster import dask_client
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
        analyses_only()  # warm: first-use costs are not a point's
        return median_seconds(analyses_only, repeats) / n, median_seconds(with_files, repeats) / n
    finally:
        shutil.rmtree(scratch)


def warm_seconds(address: str, scene: str | None, n: int, repeats: int) -> float:
    """Median wall time of an ``n``-point sweep on the running cluster at ``address``."""

    def once() -> None:
        with tempfile.TemporaryDirectory(prefix="bench_sweep_") as out:
            result = run_sweep(CASE, [(PARAMETER, values(n))], scene=scene, out_dir=out,
                               scheduler=address, progress=False)  # fmt: skip
            assert result.attrs["points_failed"] == 0, result.point_error.values

    return median_seconds(once, repeats)


def _session_processes(session: int) -> int:
    count = 0
    for process in psutil.process_iter():
        try:
            count += os.getsid(process.pid) == session
        except (ProcessLookupError, PermissionError, psutil.Error):
            continue
    return count


def command_seconds(workers: int, scene: str | None, n: int, repeats: int) -> tuple[float, int]:
    """Median wall time of a whole ``pygear sweep`` process, and the most processes of
    its session found after it exited."""
    script = Path(sys.executable).with_name("pygear")
    command = [str(script)] if script.is_file() else [sys.executable, "-m", "pygear"]
    walls, left = [], 0
    for _ in range(repeats):
        with tempfile.TemporaryDirectory(prefix="bench_sweep_command_") as out:
            argv = ["sweep", str(CASE), "--param", f"{PARAMETER}={values(n)}",
                    "--workers", str(workers), "--out", out, "--json"]  # fmt: skip
            if scene:
                argv += ["--scene", scene]
            started = time.perf_counter()
            process = subprocess.Popen(
                command + argv,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
                start_new_session=True,
            )
            _, err = process.communicate()
            walls.append(time.perf_counter() - started)
            if process.returncode != 0:
                raise RuntimeError(f"pygear {' '.join(argv)} failed:\n{err.decode()}")
            left = max(left, _session_processes(process.pid))
    return statistics.median(walls), left


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, nargs=2, default=(8, 40), help="the two sizes")
    parser.add_argument("--repeats", type=int, default=3, help="repeats (median)")
    parser.add_argument("--scene", default="runup", help="scene of the points (default runup)")
    args = parser.parse_args()
    small, large = sorted(args.points)
    load_before = os.getloadavg()[0]
    analyses, with_file = serial_per_point(load_case(CASE), args.scene, 4, args.repeats)
    warm: dict[tuple[int, int], float] = {}
    for workers in (1, 2):
        with dask_client(workers=workers) as client:
            warm_seconds(client.scheduler.address, args.scene, 4, 1)  # first tasks
            for n in (small, large):
                warm[workers, n] = warm_seconds(client.scheduler.address, args.scene, n,
                                                args.repeats)  # fmt: skip
    cold: dict[tuple[int, int], float] = {}
    left = 0
    for workers in (1, 2):
        for n in (small, large):
            cold[workers, n], stray = command_seconds(workers, args.scene, n, args.repeats)
            left = max(left, stray)

    def fit(times: dict[tuple[int, int], float], workers: int) -> tuple[float, float]:
        slope = (times[workers, large] - times[workers, small]) / (large - small)
        return times[workers, small] - slope * small, slope

    print(f"sweeps of {small} and {large} points over {PARAMETER} ({CASE.name}, scene "
          f"{args.scene}), medians of {args.repeats}, "
          f"load average {load_before:.2f} -> {os.getloadavg()[0]:.2f}")  # fmt: skip
    print(f"point: analyses alone, serial {analyses * 1e3:.0f} ms; with its NetCDF file "
          f"{with_file * 1e3:.0f} ms")  # fmt: skip
    print(f"{'':<34} {'fixed [s]':>9} {'per point [ms]':>15} "
          f"{f'{small} points [s]':>14} {f'{large} points [s]':>14}")  # fmt: skip
    for label, times in (("warm cluster", warm), ("whole `pygear sweep`", cold)):
        for workers in (1, 2):
            fixed, slope = fit(times, workers)
            print(f"{label + f', {workers} worker' + 's' * (workers > 1):<34} {fixed:>9.2f} "
                  f"{slope * 1e3:>15.0f} {times[workers, small]:>14.2f} "
                  f"{times[workers, large]:>14.2f}")  # fmt: skip
        efficiency = [times[1, n] / times[2, n] / 2 * 100 for n in (small, large)]
        print(f"{label + ', parallel efficiency':<34} {'':>9} {'':>15} "
              f"{efficiency[0]:>13.0f}% {efficiency[1]:>13.0f}%")  # fmt: skip
    overhead = fit(warm, 1)[1] - with_file
    print(f"overhead per point beyond its run and file, warm, 1 worker: {overhead * 1e3:.0f} ms")
    print(f"processes left in a command's session after it exited: {left}")


if __name__ == "__main__":
    main()
