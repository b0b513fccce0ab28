"""How long the periodic steady state of the study case takes over 200 speeds, against
time integration to the same steady-state accuracy.

1. Harmonic balance (``pygear.analysis.response``) of yang2016_planetary with its
   time-varying mesh stiffness, 200 speeds from 100 to 1500 carrier rpm, harmonics chosen
   per speed (tolerances 1e-2, the default 5e-3 and 1e-3), Floquet stability included;
   wall and CPU time (the machine may be shared: CPU time is the cost, wall time what a
   user waits).
2. At a few speeds, time integration of the same linear time-periodic system from its
   static deflection until its mesh forces are within 1e-4 of the largest mesh force of
   the steady state (the fixed point of the integration's own period map): exact
   exponentials of 1024 intervals of constant stiffness per mesh period (computed once,
   reused every period), one matrix-vector product per interval.  The harmonic balance
   at 128 harmonics reaches that accuracy at these speeds (tests/test_response.py);
   its time is the median of three solves.  Both run on one BLAS thread.
3. For scale, the pygear Newmark kernel's cost per step on the study case, and the
   steps it would need: the settling time of 2. at a step where the average-acceleration
   rule's period error (omega dt)^2 / 12 is 1e-4 at the highest mesh mode (an estimate,
   not a run).

Run: ``.venv/bin/python benchmarks/bench_response.py``.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import scipy.linalg
from threadpoolctl import threadpool_limits

from pygear import load_case
from pygear.analysis.response import response_system, solve_hill, sweep_system

CASE = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"
SPEEDS = np.linspace(100.0, 1500.0, 200)
CHECK_SPEEDS = (700.0, 1675.0, 2400.0)
SEGMENTS = 1024
ACCURACY = 1e-4


def _timed(function):
    wall, cpu = time.perf_counter(), time.process_time()
    result = function()
    return result, time.perf_counter() - wall, time.process_time() - cpu


def _propagators(system, omega: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact exponentials of the intervals (load in an augmented column)."""
    n = system.size
    samples = system.stiffness.shape[0]
    step = samples // SEGMENTS
    dk = system.stiffness_variation
    means = (
        dk.reshape(SEGMENTS, step, -1).sum(axis=1)
        - 0.5 * dk[::step]
        + 0.5 * np.roll(dk, -step, axis=0)[::step]
    ) / step
    a = np.zeros((SEGMENTS, 2 * n + 1, 2 * n + 1))
    a[:, :n, n : 2 * n] = np.eye(n)
    a[:, n : 2 * n, :n] = -(
        np.diag(system.eigenvalues)
        + np.einsum("mi,sm,mj->sij", system.mesh_rows, means, system.mesh_rows)
    )
    a[:, n : 2 * n, n : 2 * n] = -system.damping
    a[:, n : 2 * n, 2 * n] = system.force
    return scipy.linalg.expm(a * (2 * math.pi / omega / SEGMENTS)), means


def integrate_to_steady_state(system, omega: float) -> dict:
    """Step from the static deflection until the period-start mesh forces settle."""
    n = system.size
    started, cpu = time.perf_counter(), time.process_time()
    exponentials, _ = _propagators(system, omega)
    setup = time.perf_counter() - started
    period = np.eye(2 * n + 1)
    for e in exponentials:
        period = e @ period
    fixed = np.linalg.solve(np.eye(2 * n) - period[: 2 * n, : 2 * n], period[: 2 * n, 2 * n])
    state = np.zeros(2 * n + 1)
    state[:n] = system.force / system.eigenvalues  # static deflection at mean stiffness
    state[2 * n] = 1.0
    scale = np.abs(system.mean_stiffness * (system.mesh_rows @ fixed[:n])).max()
    periods = 0
    started = time.perf_counter()
    while True:
        error = np.abs(system.stiffness[0] * (system.mesh_rows @ (state[:n] - fixed[:n]))).max()
        if error <= ACCURACY * scale or periods > 100_000:
            break
        for e in exponentials:
            state = e @ state
        periods += 1
    return {
        "setup_s": setup,
        "cpu_s": time.process_time() - cpu,
        "stepping_s": time.perf_counter() - started,
        "periods": periods,
        "settle_s": periods * 2 * math.pi / omega,
    }


def kernel_step_seconds(case) -> float:
    """Median cost of one Newmark step of the study case's run-up (TVMS) [s]."""
    from pygear.analysis.time.transient import transient_problem

    problem = transient_problem(case, case.scene("runup"))
    steps = 4000
    times = []
    for _ in range(3):
        start = time.perf_counter()
        problem.solver.run(steps, problem.probes)
        times.append((time.perf_counter() - start) / steps)
    return float(np.median(times))


def main() -> None:
    case = load_case(CASE)
    system, build_wall, _ = _timed(lambda: response_system(case))
    samples = system.stiffness.shape[0]
    print(f"response system built in {build_wall:.2f} s ({system.size} modes, "
          f"{len(system.names)} meshes, {samples} stiffness samples)")  # fmt: skip
    for tolerance in (1e-2, 5e-3, 1e-3):
        dataset, wall, cpu = _timed(lambda t=tolerance: sweep_system(system, SPEEDS, tolerance=t))
        h = dataset.harmonics.values
        print(f"harmonic balance, tolerance {tolerance:g}, {SPEEDS.size} speeds "
              f"{SPEEDS[0]:g}-{SPEEDS[-1]:g} rpm: wall {wall:.2f} s, CPU {cpu:.2f} s "
              f"({1e3 * cpu / SPEEDS.size:.0f} ms CPU a speed); harmonics {h.min()}-{h.max()} "
              f"(median {int(np.median(h))}), largest residual "
              f"{dataset.residual.values.max():.1e}")  # fmt: skip
    main_mode = int(np.argmax(system.mesh_energy_share()))
    omega_top = 2 * math.pi * system.natural_frequencies[main_mode]
    step = math.sqrt(12 * ACCURACY) / omega_top
    try:
        per_step = kernel_step_seconds(case)
    except Exception as error:  # noqa: BLE001 - the estimate is context, not the benchmark
        per_step = math.nan
        print(f"kernel step not measured: {error}")
    columns = [("speed", 8), ("HB(128) s", 10), ("CPU s", 6), ("HB res", 8), ("TI setup s", 10),
               ("TI step s", 10), ("TI CPU s", 8), ("periods", 8), ("settle s", 9),
               ("TI/HB CPU", 9), ("kernel est. s", 13), ("kernel/HB", 9)]  # fmt: skip
    print(" ".join(f"{name:>{width}}" for name, width in columns))
    for speed in CHECK_SPEEDS:
        omega = system.omega(speed)
        with threadpool_limits(1, user_api="blas"):  # as sweep_system runs it
            runs = [_timed(lambda o=omega: solve_hill(system, o, 128)) for _ in range(3)]
        solution = runs[0][0]
        hb_wall = float(np.median([r[1] for r in runs]))
        hb_cpu = float(np.median([r[2] for r in runs]))
        with threadpool_limits(1, user_api="blas"):
            result = integrate_to_steady_state(system, omega)
        kernel = result["settle_s"] / step * per_step
        values = (f"{speed:8.0f}", f"{hb_wall:10.3f}", f"{hb_cpu:6.3f}",
                  f"{solution.residual:8.1e}", f"{result['setup_s']:10.2f}",
                  f"{result['stepping_s']:10.2f}", f"{result['cpu_s']:8.2f}",
                  f"{result['periods']:8d}", f"{result['settle_s']:9.3f}",
                  f"{result['cpu_s'] / hb_cpu:9.0f}", f"{kernel:13.2f}",
                  f"{kernel / hb_cpu:9.0f}")  # fmt: skip
        print(" ".join(values))
    top_hz = omega_top / 2 / math.pi
    print(f"kernel: {1e6 * per_step:.1f} us a step at the run-up's settings; the estimate "
          f"takes dt = {step:.2e} s: period error {ACCURACY:g} at {top_hz:.0f} Hz")  # fmt: skip


if __name__ == "__main__":
    main()
