"""What the multi-frequency (quasi-periodic) balance of a gearbox of several stages costs.

1. The NREL 5 MW gearbox (three stages, three frequency groups), 200 input speeds over
   its operating range at H = 32 on every axis; 20 of them with the harmonics chosen by
   the default tolerance, 10 with the per-group Floquet stability; wall and CPU time
   (the machine may be shared: CPU time is the cost, wall time what a user waits).
   Baseline: the same speeds balanced stage by stage with the single-frequency solver
   (each stage varying alone, at the orders the lattice chose), i.e. what the lattice's
   cross terms cost on top.
2. Cost per speed against the modal size and the axis order H: a synthetic model of
   three stages (13 meshes as the NREL gearbox: 6 + 6 + 1) with n elastic modes and a
   damping that couples them, fixed lattice (H on every axis, M = 4), median of three
   solves after a first one that builds the lattice.

Run: ``.venv/bin/python benchmarks/bench_response_multistage.py [--quick]``.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from pygear import load_case
from pygear.analysis.response import response_system, solve_hill, sweep_system
from pygear.analysis.response.quasi import solve_quasi
from pygear.analysis.response.quasi_sweep import quasi_balance
from pygear.analysis.response.sweep import _cover_frequency
from pygear.analysis.response.system import ResponseSystem

CASE = Path(__file__).resolve().parent.parent / "cases" / "nrel5mw_gearbox"
SPEEDS = np.linspace(6.9, 12.1, 200)  # rotor rpm: the NREL 5 MW turbine's operating range
MODES = (20, 60, 200)
ORDERS = (8, 16, 32)


def _timed(function):
    wall, cpu = time.perf_counter(), time.process_time()
    result = function()
    return result, time.perf_counter() - wall, time.process_time() - cpu


def sweep(speeds: np.ndarray, sample: int) -> None:
    system = response_system(load_case(CASE))
    print(f"NREL 5 MW gearbox: {system.size} elastic modes, {len(system.names)} meshes, "
          f"{system.groups} frequency groups; speeds {speeds[0]:g}-{speeds[-1]:g} rpm")  # fmt: skip
    data, wall, cpu = _timed(lambda: sweep_system(system, speeds, harmonics=32, stability=False))
    print(f"  {speeds.size} speeds, H = 32 on every axis (M = 4): wall {wall:.1f} s, CPU "
          f"{cpu:.1f} s ({1e3 * cpu / speeds.size:.0f} ms a speed), residual "
          f"{float(data.residual.min()):.2g}-{float(data.residual.max()):.2g}")  # fmt: skip
    subset = speeds[:: max(1, speeds.size // sample)]
    data, wall, cpu = _timed(lambda: sweep_system(system, subset, stability=False))
    print(f"  {subset.size} of them, harmonics auto (tolerance 5e-3): wall {wall:.1f} s, CPU "
          f"{cpu:.1f} s ({1e3 * cpu / subset.size:.0f} ms a speed), axis orders up to "
          f"{int(data.harmonics.max())}, residual {float(data.residual.min()):.2g}-"
          f"{float(data.residual.max()):.2g}")  # fmt: skip
    fewer = subset[::2]
    _, wall, cpu = _timed(lambda: sweep_system(system, fewer, harmonics=32, stability=True))
    print(f"  {fewer.size} of them, H = 32 with per-group Floquet stability: wall {wall:.1f} "
          f"s, CPU {cpu:.1f} s ({1e3 * cpu / fewer.size:.0f} ms a speed)")  # fmt: skip
    cover = _cover_frequency(system)
    orders_used = []
    with threadpool_limits(1, user_api="blas"):
        for speed in fewer:
            solution = quasi_balance(system, float(speed), tolerance=5e-3, cover=cover)
            orders_used.append(solution.lattice.orders)
        _, wall, cpu = _timed(
            lambda: [quasi_balance(system, float(s), tolerance=5e-3, cover=cover) for s in fewer]
        )

        def stage_by_stage() -> None:
            for speed, orders in zip(fewer, orders_used):
                omegas = system.group_omegas(float(speed))
                for g, h in enumerate(orders):
                    solve_hill(system.group_system(g), omegas[g], h)

        _, wall_b, cpu_b = _timed(stage_by_stage)
    print(f"  {fewer.size} speeds, auto: the lattice {1e3 * cpu / fewer.size:.0f} ms CPU a "
          f"speed; baseline, each stage alone at the orders it chose (single-frequency): "
          f"{1e3 * cpu_b / fewer.size:.0f} ms a speed; ratio {cpu / cpu_b:.2f}")  # fmt: skip


def synthetic(modes: int, seed: int = 0) -> ResponseSystem:
    """Three stages, 13 meshes, ``modes`` elastic modes 50 Hz - 5 kHz, 2 % modal damping
    plus a random coupling, mesh stiffness a trapezoid-like wave of +-20 %."""
    rng = np.random.default_rng(seed)
    frequencies = np.geomspace(50.0, 5000.0, modes)
    lam = (2 * math.pi * frequencies) ** 2
    coupling = rng.normal(size=(modes, modes)) * 0.002
    damping = np.diag(2 * 0.02 * np.sqrt(lam)) + (coupling @ coupling.T) * np.sqrt(lam).mean()
    groups = np.array([0] * 6 + [1] * 6 + [2])
    mean = np.full(13, 5e8)
    rows = rng.normal(size=(13, modes)) * 1e-5 / np.sqrt(1 + np.arange(modes))[None, :]
    tau = np.arange(1024) / 1024
    wave = np.clip(3 * np.sin(2 * math.pi * tau), -1, 1) * 0.2
    stiffness = mean[None, :] * (1 + np.stack([np.roll(wave, 37 * m) for m in range(13)], 1))
    return ResponseSystem(
        eigenvalues=lam, damping=damping, mesh_rows=rows, force=rng.normal(size=modes),
        mean_stiffness=mean, stiffness=stiffness, contact_sign=np.ones(13, int),
        mesh_order=np.ones(13, int), fundamental_per_rad_s=1.0, names=[f"m{i}" for i in range(13)],
        stages=[f"s{g}" for g in groups], planets=[0] * 13, modes=np.eye(modes),
        mesh_group=groups, group_fundamentals=np.array([1.0, 6.556, 41.3]),
    )  # fmt: skip


def scaling(modes_list=MODES, orders_list=ORDERS) -> None:
    print("cost per speed [ms, CPU, median of 3] against elastic modes (rows) and axis order H")
    print("modes " + " ".join(f"{'H=' + str(h):>9}" for h in orders_list))
    with threadpool_limits(1, user_api="blas"):
        for modes in modes_list:
            system = synthetic(modes)
            omegas = 2 * math.pi * 20.0 * system.group_fundamentals
            cells = []
            for h in orders_list:
                solve_quasi(system, omegas, [h] * 3, 4)  # builds the lattice and the poles
                times = [
                    _timed(lambda s=system, w=omegas, h=h: solve_quasi(s, w, [h] * 3, 4))[2]
                    for _ in range(3)
                ]
                cells.append(f"{1e3 * float(np.median(times)):>9.0f}")
            print(f"{modes:>5} " + " ".join(cells))


def main() -> None:
    quick = "--quick" in sys.argv
    sweep(SPEEDS[::10] if quick else SPEEDS, 10 if quick else 20)
    scaling(MODES[:2], ORDERS[:2]) if quick else scaling()


if __name__ == "__main__":
    main()
