"""What the user waits for: whole ``pygear`` processes, start to exit, against the
solver's own time.

Each command runs as a fresh process (as typed at a shell: the ``pygear`` script
beside this Python), so the wall time holds the interpreter's start, every import,
the work, the files and the figures.  Its peak resident memory is the child's own
``ru_maxrss`` from ``os.wait4`` (the counter ``/usr/bin/time -v`` reports, read
without a second program).  A run's solver time is the ``solver_wall_s`` attribute of
the ``<scene>.nc`` it wrote (the kernel's integration only), and every time is also
given as a ratio to the median of those.  Medians of repeats; the load average is
printed, since other work on a shared machine takes cores from the commands, and so is
each command's CPU time (user and system, from the same ``wait4``), which that other
work changes far less than the wall time.

Then each figure of the run-up is drawn again in this process from the run's files
(median of repeats after one untimed drawing), and Matplotlib's first import is timed:
what each figure adds to ``pygear run``.

    python benchmarks/bench_end_to_end.py              # 5 repeats
    python benchmarks/bench_end_to_end.py --repeats 3 --case yang2016_planetary
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

from timing import median_seconds

ROOT = Path(__file__).resolve().parent.parent


def pygear_command() -> list[str]:
    """The ``pygear`` console script of this environment, else ``python -m pygear``."""
    script = Path(sys.executable).with_name("pygear")
    return [str(script)] if script.is_file() else [sys.executable, "-m", "pygear"]


def run_once(arguments: list[str], cwd: Path, command: list[str] | None = None):
    """Wall time [s], peak resident memory [MiB] and CPU time [s] (user and system, with
    the children it waited for) of one process (output discarded); ``command`` instead of
    ``pygear`` runs another program."""
    started = time.perf_counter()
    process = subprocess.Popen(
        (pygear_command() if command is None else command) + arguments,
        cwd=cwd,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - started
    stderr = process.stderr.read().decode(errors="replace") if process.stderr else ""
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        raise RuntimeError(f"pygear {' '.join(arguments)} failed:\n{stderr}")
    # ru_maxrss is in kilobytes on Linux, bytes on macOS
    scale = 1.0 if sys.platform == "darwin" else 1024.0
    return wall, usage.ru_maxrss * scale / 2**20, usage.ru_utime + usage.ru_stime


def solver_seconds(path: Path) -> float:
    """The kernel's integration time a run recorded in its file."""
    import netCDF4  # not before the commands: a child forked from a bigger parent counts
    # the parent's pages in its peak memory until it runs pygear

    with netCDF4.Dataset(path) as dataset:
        return float(dataset.getncattr("solver_wall_s"))


def figure_costs(run_file: Path, scratch: Path, repeats: int) -> list[tuple[str, float]]:
    """Seconds to draw each figure ``pygear run`` draws for a run-up, from its file;
    the first row is Matplotlib's import (with pyplot and the Agg backend)."""
    from pygear.analysis.signals.analyze import analyze_channel
    from pygear.io import open_dataset
    from pygear.model.case import SIGNAL_AFTER
    from pygear.runs.outputs import acceleration_channels, stored_references

    with open_dataset(run_file) as opened:  # labels as indexes, time in s
        run = opened.load()
    natural, mesh = stored_references(run, run_file)
    started = time.perf_counter()
    from pygear.io import save_figure
    from pygear.plots.signal import plot_run_analysis
    from pygear.plots.transient import plot_speeds

    rows = [("import matplotlib (Agg canvas) and pygear.plots", time.perf_counter() - started)]
    target = scratch / "figure.png"

    def saved(figure) -> None:  # drawn and written, as pygear run does
        save_figure(figure, target, dpi=figure.dpi)

    speeds = lambda: saved(plot_speeds([run]))  # noqa: E731
    speeds()
    rows.append(("speeds (runup_speeds.png)", median_seconds(speeds, repeats)))
    for channel in acceleration_channels(run):
        analysis = analyze_channel(
            run, channel, after=SIGNAL_AFTER, natural_frequencies=natural, mesh_frequency=mesh
        )
        draw = lambda a=analysis: saved(plot_run_analysis(a, run_attrs=run.attrs))  # noqa: E731
        draw()
        rows.append((f"signal analysis of {channel}", median_seconds(draw, repeats)))
    return rows


def supports(arguments: list[str], option: str) -> bool:
    """Whether ``pygear ARGUMENTS --help`` lists ``option``."""
    shown = subprocess.run(
        pygear_command() + arguments + ["--help"], capture_output=True, text=True, check=True
    )
    return option in shown.stdout


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="repeats per command (median)")
    parser.add_argument("--case", default="yang2016_planetary", help="case name or directory")
    parser.add_argument("--scene", default="runup", help="transient scene to run")
    args = parser.parse_args()
    scratch = Path(tempfile.mkdtemp(prefix="bench_end_to_end_"))
    run = ["run", args.case, "--scene", args.scene]
    interpreter = [sys.executable, "-c", "pass"]
    commands = [
        ("python -c pass (the interpreter alone)", interpreter, None),
        ("pygear --help", ["--help"], None),
        (f"pygear modal {args.case}", ["modal", args.case], None),
        (f"pygear {' '.join(run)}", run + ["--out", str(scratch / "figures")], "figures"),
    ]
    if supports(["run"], "--no-figures"):
        commands.append(
            (
                f"pygear {' '.join(run)} --no-figures",
                run + ["--no-figures", "--out", str(scratch / "plain")],
                "plain",
            )
        )
    load_before = os.getloadavg()[0]
    results = []
    solver: list[float] = []
    try:
        run_once(["--help"], ROOT)  # a kernel rebuild after an edit is not what we time
        for name, arguments, out in commands:
            walls, peaks, cpus = [], [], []
            for _ in range(args.repeats):
                if arguments is interpreter:
                    wall, peak, cpu = run_once([], ROOT, command=interpreter)
                else:
                    wall, peak, cpu = run_once(arguments, ROOT)
                walls.append(wall)
                peaks.append(peak)
                cpus.append(cpu)
                if out is not None:
                    solver.append(solver_seconds(scratch / out / f"{args.scene}.nc"))
            results.append(
                (name, statistics.median(walls), statistics.median(peaks), statistics.median(cpus))
            )
        figures = figure_costs(scratch / "figures" / f"{args.scene}.nc", scratch, args.repeats)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    solver_median = statistics.median(solver)
    print(
        f"whole processes, medians of {args.repeats}; solver (solver_wall_s of the runs) "
        f"{solver_median * 1e3:.0f} ms; load average {load_before:.2f} -> "
        f"{os.getloadavg()[0]:.2f}"
    )
    print(
        f"{'command':<58} {'wall [s]':>8} {'x solver':>8} {'peak RSS [MiB]':>15} "
        f"{'CPU [s]':>8}"
    )
    for name, wall, peak, cpu in results:
        print(
            f"{name:<58} {wall:>8.2f} {wall / solver_median:>8.2f} {peak:>15.0f} {cpu:>8.2f}"
        )
    print(f"\n{'figure of the run, drawn in this process':<58} {'wall [s]':>8} {'x solver':>8}")
    for name, seconds in figures:
        print(f"{name:<58} {seconds:>8.3f} {seconds / solver_median:>8.2f}")


if __name__ == "__main__":
    main()
