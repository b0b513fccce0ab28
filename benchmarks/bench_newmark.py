"""Benchmark: cost per step of the Newmark kernel against its floor and a NumPy loop.

On the study case's run-up (18 DOFs, band half-width 13 of 17, time-varying mesh
stiffness, ``predictor`` equivalent load, the paper's 2.5e-5 s step), or with ``--case
gearbox`` the gearbox's (50 DOFs, 15 meshes, the helical pair by its contact-line law,
the output reversed), this measures, alternating within each of ``--repeats`` repeats
and reporting medians:

* the kernel: microseconds per step inside ``transient_advance`` (chunks of steps per
  call; Python only between chunks), on the path the automatic choice takes (the refined
  dense path for the study case, CHOLMOD's sparse factor for the gearbox) and forced
  onto each other path: CHOLMOD, the banded path and the bare dense inverse
  (``dense_inverse``, on request only);
* the floors, the bare Fortran loops of the algorithms that this benchmark compiles
  (``bare_newmark.f90.in`` through ``bare_loop.py``: gfortran -O3, linked against the
  same scipy-openblas32 OpenBLAS, the same channels recorded every step): CHOLMOD's
  solve through the kernel's own C shim after one pass over the CSC pattern for
  C v + K0 q; band products and dpbtrs; one fused dgemv per step for the dense inverse
  (the fastest algorithm at these sizes, but not backward stable); that dgemv and one
  step of iterative refinement (three more dgemv, the refined path's algorithm); and the
  right-hand side by one dgemv with two triangular solves on a dense Cholesky factor
  (the other backward stable dense algorithm, measured to choose between the two);
* a plain fused NumPy loop of the same algorithm (``bare_loop.numpy_fused``: a
  precomputed dense inverse folded with the state update and every read-out into one
  matrix-vector product per step, each mesh's own contact law and no other, the same
  channels, and the kernel's two runaway bounds checked every step as the kernel checks
  them), and the same loop without those checks, which does less than the kernel;
* each as a ratio to the kernel of the same repeat (median of the ratios); the three
  trajectories are compared;
* what rigid-body rebasing costs, a run that rebases and one that never does alternating
  within each repeat (median of the ratios), and memory: the peak of traced allocations
  for runs of different lengths and probe counts, against the full state (steps x DOFs x
  q, v, a).

Times are the CPU time of the running thread (the kernel's and NumPy's thread, the bare
program's process with one OpenBLAS thread): on a small machine shared with other work a
run loses whole scheduler slices (4 ms) to other processes, which CPU time does not
count; the kernel's wall clock is printed beside it.

Usage::

    PYTHONPATH=. python benchmarks/bench_newmark.py [--case gearbox] [--steps 100000] [--repeats 7]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import statistics
import time
import tracemalloc

import numpy as np
from bare_loop import BareLoop, loop_arrays, numpy_fused

from pygear import Probe, load_case
from pygear.analysis.time.transient import transient_problem
from pygear.kernel.newmark_support import LINEAR_SOLVER_VARIABLE

CASES = {  # case, scene, the speed and mesh-force channels of the memory runs
    "study": ("yang2016_planetary", "runup", ("planetary.carrier", "sun-planet1")),
    "gearbox": ("yang2016_gearbox", "runup_tv", ("stage1.carrier", "stage1.sun-planet1")),
}
CASE = "study"


def problem_for(steps: int, probes: tuple | None = None, linear_solver: str | None = None):
    """The case's run-up scene, cut to ``steps`` steps (optionally other probes, or the
    kernel's linear solver forced)."""
    name, scene_name, _ = CASES[CASE]
    case = load_case(name)
    scene = case.scene(scene_name)
    settings = scene.transient
    changes = {"duration": steps * settings.time_step, "mean_window": settings.time_step}
    if probes is not None:
        changes["probes"] = probes
    settings = dataclasses.replace(settings, **changes)
    forced = os.environ.pop(LINEAR_SOLVER_VARIABLE, None)
    if linear_solver is not None:
        os.environ[LINEAR_SOLVER_VARIABLE] = linear_solver
    try:
        return transient_problem(case, dataclasses.replace(scene, transient=settings))
    finally:
        os.environ.pop(LINEAR_SOLVER_VARIABLE, None)
        if forced is not None:
            os.environ[LINEAR_SOLVER_VARIABLE] = forced


def _kernel_has_cholmod() -> bool:
    from pygear.kernel.newmark_storage import cholmod_available

    return cholmod_available()


def kernel_run(problem, steps: int):
    return problem.solver.run(steps, problem.probes, decimation=problem.settings.decimation)


def kernel_times(problem, steps: int) -> tuple[float, float]:
    """CPU time of this thread and wall clock inside ``transient_advance`` [us per step]."""
    solver = problem.solver
    advance = type(solver)._advance
    spent = [0.0]

    def timed(*arguments):
        started = time.thread_time()
        try:
            return advance(solver, *arguments)
        finally:
            spent[0] += time.thread_time() - started

    solver._advance = timed
    try:
        result = kernel_run(problem, steps)
    finally:
        del solver._advance
    return spent[0] / result.steps * 1e6, result.solver_wall_s / result.steps * 1e6


def _numpy_cpu_us(arrays, steps: int, checks: bool = True) -> float:
    started = time.thread_time()
    numpy_fused(arrays, steps, checks=checks)
    return (time.thread_time() - started) / steps * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=100_000, help="kernel steps per run")
    parser.add_argument("--numpy-steps", type=int, default=8_000, help="NumPy steps per run")
    parser.add_argument("--repeats", type=int, default=7, help="repeats (median)")
    parser.add_argument("--case", choices=sorted(CASES), default="study", help="which run-up")
    args = parser.parse_args()
    global CASE
    CASE = args.case
    speed_channel = CASES[CASE][2][0]

    problem = problem_for(args.steps)
    banded = problem_for(args.steps, linear_solver="banded_cholesky")
    inverse = problem_for(args.steps, linear_solver="dense_inverse")
    paths = {"banded_cholesky": banded, "dense_inverse": inverse}
    for path in ("dense_refined", "sparse_cholesky"):
        if path != problem.solver.linear_solver and (
            path != "sparse_cholesky" or _kernel_has_cholmod()
        ):
            paths[path] = problem_for(args.steps, linear_solver=path)
    solver = problem.solver
    print(
        f"{CASES[CASE][0]} {CASES[CASE][1]}: {problem.model.size} DOFs, "
        f"band half-width {banded.solver.bandwidth} "
        f"(reverse Cuthill-McKee), {solver.meshes.size} meshes, time-varying mesh stiffness, "
        f"equivalent load '{solver.equivalent_load}', dt = {problem.settings.time_step:g} s, "
        f"{len(problem.probes)} probes at 40 kHz\n"
        f"kernel linear solver: {solver.linear_solver} ({solver.linear_solver_reason})"
    )
    arrays = loop_arrays(banded)  # the bare loops read the band matrices
    bare = BareLoop(arrays, args.steps)
    for warm in (problem, *paths.values()):
        kernel_run(warm, 2000)

    def kernel_row(measured):
        return lambda: kernel_times(measured, args.steps)

    def bare_row(variant):
        return lambda: (bare.run(variant).cpu_us_per_step, None)

    rows = {"kernel": kernel_row(problem)}  # name: function giving CPU us per step
    names = {  # kernel path: its row and the bare loop of its algorithm
        "dense_refined": ("kernel, refined dense", "bare loop, refined dense", "refined"),
        "sparse_cholesky": ("kernel, CHOLMOD", "bare loop, CHOLMOD", "sparse"),
        "banded_cholesky": ("kernel, banded path", "bare loop, banded", "band"),
        "dense_inverse": ("kernel, dense inverse", "bare loop, dense inverse", "dense_blas"),
    }
    floors = {}
    for path, (kernel_name, bare_name, variant) in names.items():
        if path in paths:
            rows[kernel_name] = kernel_row(paths[path])
        if path in paths or path == solver.linear_solver:
            rows[bare_name] = bare_row(variant)
            floors[path] = bare_name
    rows["bare loop, dense Cholesky"] = bare_row("dense_cholesky")
    rows["fused NumPy loop"] = lambda: (_numpy_cpu_us(arrays, args.numpy_steps), None)
    rows["NumPy loop, no checks"] = lambda: (_numpy_cpu_us(arrays, args.numpy_steps, False), None)
    times: dict[str, list[float]] = {name: [] for name in rows}
    wall: dict[str, list[float]] = {name: [] for name in rows if name.startswith("kernel")}
    for _ in range(args.repeats):  # alternating, so that every repeat sees the same machine
        for name, measure in rows.items():
            cpu, wall_clock = measure()
            times[name].append(cpu)
            if wall_clock is not None:
                wall[name].append(wall_clock)

    def ratio(name: str, to: str) -> float:
        return statistics.median(a / b for a, b in zip(times[name], times[to]))

    print(f"\nmicroseconds per step, medians of {args.repeats} alternating repeats (CPU time):")
    for name in rows:
        line = f"  {name:27s} {statistics.median(times[name]):9.3f}"
        if name in wall:
            line += f"   (wall clock {statistics.median(wall[name]):.3f})"
        print(line)
    print("ratios, medians over the repeats:")
    default = solver.linear_solver
    for path, bare_name in floors.items():  # each kernel path against its own floor
        kernel_name = "kernel" if path == default else names[path][0]
        label = f"{kernel_name} ({path}) / {bare_name}"
        print(f"  {label:58s} {ratio(kernel_name, bare_name):6.2f}")
    others = ("bare loop, dense inverse", "bare loop, dense Cholesky", "bare loop, CHOLMOD")
    for bare_name in others:
        if bare_name in times and bare_name != floors.get(default):
            label = f"kernel ({default}) / {bare_name}"
            print(f"  {label:58s} {ratio('kernel', bare_name):6.2f}   (another algorithm)")
    for path in paths:
        label = f"{names[path][0]} / kernel ({default})"
        print(f"  {label:58s} {ratio(names[path][0], 'kernel'):6.2f}")
    numpy_ratio = ratio("fused NumPy loop", "kernel")
    print(f"  fused NumPy loop / kernel                   {numpy_ratio:6.1f}")
    unchecked = ratio("NumPy loop, no checks", "kernel")
    print(f"  NumPy loop without the checks / kernel      {unchecked:6.1f}   (does less)")

    # the same trajectory: every channel of the kernel, the bare loop and the NumPy loop,
    # against the largest value of its kind (a symmetric stage's ring acceleration is zero
    # in exact arithmetic: round-off against the other accelerations)
    result = kernel_run(problem_for(args.numpy_steps), args.numpy_steps)
    reference, numpy_t_s = numpy_fused(arrays, args.numpy_steps)
    floor = bare.run(names[default][2])
    names = [probe.name for probe in problem.probes]
    kinds = [kind for _, kind, _ in arrays.linear] + ["force"] * len(arrays.forces) + ["torque"] * 2
    kernel = np.array([result.samples[names.index(name), 1:] for name in arrays.names])
    scale = {kind: np.abs(kernel[np.array(kinds) == kind]).max() for kind in set(kinds)}
    worst = {}
    for label, samples in (("bare loop", floor.samples), ("NumPy loop", reference)):
        difference = np.abs(samples[:, : args.numpy_steps] - kernel).max(axis=1)
        worst[label] = max(d / scale[kind] for d, kind in zip(difference, kinds))
    print(
        f"kernel against the references over {args.numpy_steps} steps (largest difference of "
        f"a channel, relative to its kind's largest value): bare loop {worst['bare loop']:.1e}, "
        f"NumPy loop {worst['NumPy loop']:.1e}; t_s {result.t_s:.6f} and {numpy_t_s:.6f} s "
        f"(NaN: not reached)"
    )

    # rigid-body rebasing (pygear.kernel.newmark_rebase) against a run that never
    # rebases, the two alternating within each repeat
    import pygear.kernel.newmark_rebase as rebase

    def run_us(rebase_steps: int) -> tuple[float, float]:
        """CPU time of this thread and wall clock of a whole run [us per step]."""
        default_steps = rebase.REBASE_STEPS
        rebase.REBASE_STEPS = rebase_steps
        try:
            wall_started, cpu_started = time.perf_counter(), time.thread_time()
            result = kernel_run(problem, args.steps)
            cpu, wall_clock = time.thread_time() - cpu_started, time.perf_counter() - wall_started
        finally:
            rebase.REBASE_STEPS = default_steps
        return cpu / result.steps * 1e6, wall_clock / result.steps * 1e6

    every = rebase.REBASE_STEPS
    rebasing: dict[str, list[tuple[float, float]]] = {"rebasing": [], "never": []}
    for _ in range(args.repeats):
        rebasing["rebasing"].append(run_us(every))
        rebasing["never"].append(run_us(1 << 62))
    cost = statistics.median(
        a[0] / b[0] - 1 for a, b in zip(rebasing["rebasing"], rebasing["never"])
    )
    with_it, without = (
        statistics.median(t[0] for t in rebasing[k]) for k in ("rebasing", "never")
    )
    print(
        f"rebasing every {every} steps costs {100 * cost:+.1f} % of a whole run's CPU time "
        f"(median of {args.repeats} alternating pairs; {with_it:.3f} against {without:.3f} "
        f"us per step without it)"
    )

    print("\nmemory (peak of traced allocations during the run):")
    print(
        f"{'steps':>8} {'probes':>6} {'peak [MB]':>10} {'probes x samples [MB]':>22} "
        f"{'full state 3 x steps x DOFs [MB]':>33}"
    )
    few = (Probe("speed", speed_channel),)
    for steps, probes in ((50_000, few), (200_000, few), (200_000, None)):
        measured = problem_for(steps, probes)
        tracemalloc.start()
        kernel_run(measured, steps)
        peak = tracemalloc.get_traced_memory()[1] / 1e6
        tracemalloc.stop()
        count = len(measured.probes)
        print(
            f"{steps:>8} {count:>6} {peak:>10.1f} {count * (steps + 1) * 8 / 1e6:>22.1f} "
            f"{3 * steps * measured.model.size * 8 / 1e6:>33.1f}"
        )


if __name__ == "__main__":
    main()
