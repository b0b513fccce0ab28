"""Peak memory and throughput of a long run, streamed and whole (issue #32).

The NREL 5 MW gearbox run-up (``cases/nrel5mw_gearbox``, scene ``runup``: 54 DOFs,
time-varying mesh stiffness, 15 probes at 20 kHz, 5e-5 s steps) lengthened to
``--duration`` seconds (600 s: an IEC 61400 design load case) and written by
:func:`pygear.runs.transient_outputs.write_transient` in a fresh process per run, once
streamed and once held whole.  Each run reports its peak RSS (``ru_maxrss`` of the
child), wall time, steps per second, samples per second and the file size.

A streamed run returns its finished file opened lazily (``pygear.io.open_dataset``),
which indexes ``time`` (8 bytes a sample, read and indexed: about 2 x 96 MB at 600 s);
the child reports the peak before that open too (``peak_rss_before_open_mib``, the run
and its file alone).

Before a long run, what it needs: the record is channels x samples x 8 bytes (600 s:
15 x 12 000 001 x 8 = 1.44 GB), held twice by the whole run (2.9 GB of memory); the
file is at most the record plus its time coordinate uncompressed (1.5 GB; about 0.9 GB
compressed).  The streamed run holds one block (16 MiB) whatever the duration.

    .venv/bin/python benchmarks/bench_long_run.py --duration 600 --out /tmp/long
    .venv/bin/python benchmarks/bench_long_run.py --duration 60 --only streamed
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CASE = ROOT / "cases" / "nrel5mw_gearbox"

CHILD = """
import dataclasses, json, os, resource, sys, time
from pygear import load_case
from pygear.runs import transient_outputs
from pygear.runs.transient_outputs import write_transient

def high_water_mib():
    with open("/proc/self/status") as status:
        line = next(l for l in status if l.startswith("VmHWM:"))
    return int(line.split()[1]) / 1024

opened = {}  # the peak before the finished file is opened for the caller
real_open = transient_outputs.open_dataset
def measured_open(path, **options):
    opened["peak_rss_before_open_mib"] = high_water_mib()
    return real_open(path, **options)
transient_outputs.open_dataset = measured_open

case = load_case(sys.argv[1])
scene = case.scene("runup")
settings = dataclasses.replace(scene.transient, duration=float(sys.argv[3]))
scene = dataclasses.replace(scene, transient=settings, analyses=("transient",))
started = time.perf_counter()
dataset, files = write_transient(case, scene, sys.argv[2], figure=False,
                                 stream=sys.argv[4] == "streamed")
wall = time.perf_counter() - started
print(json.dumps({
    "peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    "wall_s": wall,
    "solver_wall_s": float(dataset.attrs["solver_wall_s"]),
    "steps": int(dataset.attrs["steps"]),
    "samples": int(dataset.sizes["time"]),
    "channels": sum(1 for v in dataset.data_vars.values() if "time" in v.dims),
    "file_mib": os.path.getsize(files[0]) / 2**20,
    **opened,
}))
"""


def run(duration: float, mode: str, out: Path) -> dict:
    """One run in a fresh process; its numbers."""
    target = out / f"{mode}_{duration:g}"
    shutil.rmtree(target, ignore_errors=True)
    result = subprocess.run(
        [sys.executable, "-c", CHILD, str(CASE), str(target), str(duration), mode],
        capture_output=True,
        text=True,
        check=False,
        env={**os.environ, "PYGEAR_PROGRESS": "0"},
    )
    if result.returncode:
        raise SystemExit(f"{mode} run failed:\n{result.stderr}")
    numbers = json.loads(result.stdout.strip().splitlines()[-1])
    numbers["steps_per_s"] = numbers["steps"] / numbers["wall_s"]
    numbers["samples_per_s"] = numbers["samples"] / numbers["wall_s"]
    shutil.rmtree(target, ignore_errors=True)
    return {"mode": mode, "duration_s": duration, **numbers}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--duration", type=float, nargs="+", default=[600.0])
    parser.add_argument("--only", choices=("streamed", "whole"))
    parser.add_argument(
        "--out", type=Path, default=Path(f"/tmp/pygear_bench_long_run_{os.getpid()}")
    )
    args = parser.parse_args(argv)
    modes = [args.only] if args.only else ["streamed", "whole"]
    print(
        f"{'mode':<9}{'duration':>10}{'peak RSS':>12}{'wall':>9}{'steps/s':>10}"
        f"{'samples/s':>11}{'file':>10}",
        flush=True,
    )
    rows = []
    for duration in args.duration:
        for mode in modes:  # each row as soon as its run ends (a 600 s pair takes minutes)
            row = run(duration, mode, args.out)
            rows.append(row)
            before = row.get("peak_rss_before_open_mib")
            print(
                f"{row['mode']:<9}{row['duration_s']:>9g}s{row['peak_rss_mib']:>8.0f} MiB"
                f"{row['wall_s']:>8.1f}s{row['steps_per_s']:>10.0f}"
                f"{row['samples_per_s']:>11.0f}{row['file_mib']:>6.0f} MiB"
                + (f"  (run and file: {before:.0f} MiB)" if before else ""),
                flush=True,
            )
    print(json.dumps(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
