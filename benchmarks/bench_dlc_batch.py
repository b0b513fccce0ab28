"""Parallel efficiency of a design load case batch: 20 load cases on 2 Dask workers
against the same 20 load cases run one after the other in one process.

The case is the NREL 5 MW gearbox (``cases/nrel5mw_gearbox``) with its design load
case table cut to 5 wind speeds (6, 9, 12, 15, 18 m/s) x 4 seeds of ``--duration``
seconds each (default 2 s: 40 000 steps of 5e-5 s, 19 probes at 20 kHz, rainflow and
load duration reductions).  Each load case does the same work in both modes
(:func:`pygear.runs.dlc.run_load_case`: load the case, draw the Kaimal torque, check
and assemble the scene, run it streamed into its file):

* serial: a fresh process imports what the workers' fork server imports and loads the
  case, then runs the 20 load cases in turn; their wall time is T_1;
* parallel: a fresh process starts the fork server (as ``pygear batch`` does), imports
  and waits for the server to serve, then runs :func:`run_dlc_batch` on a local cluster
  of 2 single-threaded workers; T_2 is that call's wall time: the cluster's start, the
  load cases, the load spectrum and the cluster's end.

The imports stay off the clock in both (printed beside it): in this editable checkout
each fresh process first asks meson whether the Fortran kernel must be rebuilt, which
takes seconds to minutes while the sources change, and a wheel install never does.

Parallel efficiency = T_1 / (2 T_2).  Medians of ``--repeats`` pairs.  With each pair
the load cases' processor time (summed over the tasks, ``time.process_time`` of the
process running them) and the share of a core they had (processor over wall time) are
printed, and the machine's load average: on a shared machine other jobs take cores
from the workers, which the share shows.

    .venv/bin/python benchmarks/bench_dlc_batch.py
    .venv/bin/python benchmarks/bench_dlc_batch.py --duration 10 --repeats 3
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CASE_FILE = """
import dataclasses

from pygear.model.case_files import load_case_module

_, _base = load_case_module("nrel5mw_gearbox")
case = dataclasses.replace(_base.case, name="dlc_bench")
design_load_cases = dataclasses.replace(
    _base.design_load_cases, wind_speeds=(6.0, 9.0, 12.0, 15.0, 18.0), seeds=(1, 2, 3, 4),
    duration={duration},
)
"""

SERIAL = """
import sys, time
began = time.perf_counter()
import pygear.runs.cluster as cluster
for module in cluster.WORKER_MODULES:  # what the workers' fork server imports
    __import__(module)
from pygear.runs.dlc import _cached_table, run_load_case
_, table, _ = _cached_table(sys.argv[1])
started = time.perf_counter()
rows = [run_load_case(sys.argv[1], load.name, sys.argv[2]) for load in table.load_cases()]
ended = time.perf_counter()
bad = [r for r in rows if r["status"] != "ok"]
assert not bad, bad
print(started - began, ended - started, sum(r["cpu_s"] for r in rows),
      sum(r["wall_s"] for r in rows))
"""

PARALLEL = """
import sys, time
began = time.perf_counter()
from pygear.runs.cluster import local_worker_server
with local_worker_server():  # as pygear batch does: the fork server imports meanwhile
    import multiprocessing
    from pygear.runs.dlc import run_dlc_batch
    # wait for the fork server to have imported the workers' modules (a fork from it
    # returns once it serves)
    probe = multiprocessing.get_context("forkserver").Process(target=len, args=((),))
    probe.start()
    probe.join()
    started = time.perf_counter()
    summary, spectrum = run_dlc_batch(sys.argv[1], out_dir=sys.argv[2], workers=2,
                                      progress=False)
    ended = time.perf_counter()
assert (summary["status"] == "ok").all() and spectrum is not None, summary
print(started - began, ended - started, summary["cpu_s"].sum(), summary["wall_s"].sum())
"""


def _timed(script: str, *args: str) -> tuple[float, float, float, float]:
    """Wall time of the imports, of the batch, and the sums of the load cases'
    processor and wall times [s]."""
    done = subprocess.run(
        [sys.executable, "-c", script, *args], capture_output=True, text=True, check=False
    )
    if done.returncode != 0:
        raise SystemExit(done.stderr[-3000:])
    imports, wall, cpu, tasks = (float(v) for v in done.stdout.split()[-4:])
    return imports, wall, cpu, tasks


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--duration", type=float, default=2.0, help="s per load case")
    parser.add_argument("--repeats", type=int, default=3, help="serial/parallel pairs")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    args = parser.parse_args()
    root = Path(tempfile.mkdtemp(prefix="bench_dlc_"))
    try:
        case_dir = root / "dlc_bench"
        case_dir.mkdir()
        (case_dir / "case.py").write_text(CASE_FILE.format(duration=args.duration))
        pairs = []
        for repeat in range(args.repeats):
            load_before = os.getloadavg()[0]
            serial_out = root / f"serial_{repeat}"
            serial_out.mkdir()
            i_serial, t_serial, cpu_serial, tasks_serial = _timed(
                SERIAL, str(case_dir), str(serial_out)
            )
            i_parallel, t_parallel, cpu_parallel, tasks_parallel = _timed(
                PARALLEL, str(case_dir), str(root / f"parallel_{repeat}")
            )
            pair = {
                "serial_s": t_serial,
                "parallel_s": t_parallel,
                "imports_serial_s": i_serial,
                "imports_parallel_s": i_parallel,
                "efficiency": t_serial / (2.0 * t_parallel),
                # the share of a core a load case had: < 1 where other jobs took the CPUs
                "core_share_serial": cpu_serial / tasks_serial,
                "core_share_parallel": cpu_parallel / tasks_parallel,
                "load_case_cpu_serial_s": cpu_serial,
                "load_case_cpu_parallel_s": cpu_parallel,
                "load_average_1min_before": load_before,
                "load_average_1min_after": os.getloadavg()[0],
            }
            pairs.append(pair)
            if not args.json:
                print(
                    f"repeat {repeat + 1}: serial {t_serial:.1f} s, 2 workers "
                    f"{t_parallel:.1f} s, efficiency {pair['efficiency']:.1%}; load cases' CPU "
                    f"{cpu_serial:.1f} s / {cpu_parallel:.1f} s, share of a core "
                    f"{pair['core_share_serial']:.2f} / {pair['core_share_parallel']:.2f} "
                    f"(load average {load_before:.1f} -> {pair['load_average_1min_after']:.1f}; "
                    f"imports before the clock {i_serial:.1f} s / {i_parallel:.1f} s)",
                    flush=True,
                )
        result = {
            "load_cases": 20,
            "duration_s": args.duration,
            "workers": 2,
            "cpus": os.cpu_count(),
            "median_serial_s": statistics.median(p["serial_s"] for p in pairs),
            "median_parallel_s": statistics.median(p["parallel_s"] for p in pairs),
            "median_efficiency": statistics.median(p["efficiency"] for p in pairs),
            "repeats": pairs,
            "when": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()),
        }
        if args.json:
            print(json.dumps(result, indent=2))
        else:
            print(
                f"median: serial {result['median_serial_s']:.1f} s, 2 workers "
                f"{result['median_parallel_s']:.1f} s, parallel efficiency "
                f"{result['median_efficiency']:.1%} on {result['cpus']} CPUs"
            )
    finally:
        shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main()
