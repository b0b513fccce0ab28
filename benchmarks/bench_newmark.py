"""Benchmark: cost per step of the banded Newmark kernel against a plain NumPy loop.

On the study case's run-up (18 DOFs, time-varying mesh stiffness, ``predictor``
equivalent load, the paper's 2.5e-5 s step), or with ``--case gearbox`` the
gearbox's (50 DOFs, 15 meshes, the helical pair by its contact-line law, the
output reversed), this measures, in one run:

* the kernel: microseconds per step inside ``transient_advance`` (chunks of steps
  per call; Python only between chunks), median of ``--repeats`` runs;
* a plain NumPy loop of the same algorithm on the same matrices (average
  acceleration in acceleration form, the same predictor, the tooth-contact
  parabola vectorised over meshes, the same drive and load laws, K-hat inverted
  once), median of ``--repeats`` shorter runs; the two trajectories are compared;
* memory: the peak of traced allocations for runs of different lengths and probe
  counts, against what the full state (steps x DOFs x q, v, a) would need.

Usage::

    PYTHONPATH=. python benchmarks/bench_newmark.py [--case gearbox] [--steps 200000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import statistics
import time
import tracemalloc

import numpy as np

from pygear import Probe, load_case
from pygear.analysis.transient import _kinematic_ratio, transient_problem
from pygear.assembly.contact_table import LAW_CODES

CASES = {  # case, scene, channels compared with the NumPy loop
    "study": ("yang2016_planetary", "runup", ("planetary.carrier", "sun-planet1")),
    "gearbox": ("yang2016_gearbox", "runup_tv", ("stage1.carrier", "stage1.sun-planet1")),
}
CASE = "study"


def problem_for(steps: int, probes: tuple | None = None):
    """The case's run-up scene, cut to ``steps`` steps (optionally other probes)."""
    name, scene_name, _ = CASES[CASE]
    case = load_case(name)
    scene = case.scene(scene_name)
    settings = scene.transient
    changes = {"duration": steps * settings.time_step, "mean_window": settings.time_step}
    if probes is not None:
        changes["probes"] = probes
    settings = dataclasses.replace(settings, **changes)
    return transient_problem(case, dataclasses.replace(scene, transient=settings))


def kernel_run(problem, steps: int):
    return problem.solver.run(steps, problem.probes, decimation=problem.settings.decimation)


def numpy_newmark(problem, steps: int) -> dict[str, np.ndarray]:
    """The kernel's algorithm, step by step in NumPy (dense matrices, no band storage)."""
    model, solver, settings = problem.model, problem.solver, problem.settings
    table = solver.meshes.table
    mass, damping, stiffness = model.mass, model.damping, model.stiffness
    dt, beta, gamma = settings.time_step, 0.25, 0.5
    khat = stiffness + mass / (beta * dt * dt) + gamma / (beta * dt) * damping
    khat_inverse = np.linalg.inv(khat)
    scale = 1.0 / (beta * dt * dt)
    b = solver.meshes.deflection
    angle = solver.meshes.angle
    kbar = solver.meshes.mean_stiffness
    z1 = table.teeth[0].astype(float)
    sigma, phase = table.cycle_sign.astype(float), table.phase
    eps, lam = table.contact_ratio, table.end_to_peak
    peak = 3 * kbar / (eps * (2 + lam))
    helical = table.law == LAW_CODES["helical"]
    transverse = np.where(helical, eps - lam, 1.0)
    offsets = np.arange(table.max_pairs)[:, None]
    w_in = _member(problem, problem.input_label)
    w_out = _member(problem, problem.output_label)
    if _kinematic_ratio(problem.case, model, problem.input_label, problem.output_label) < 0:
        w_out = -w_out  # the load law brakes the reversed output
    drive = settings.drive.torque
    ratio = problem.ratio
    omega_0 = settings.speed_reference_rpm * math.pi / 30
    load_scale, load_speed = drive / ratio, ratio * omega_0
    n = model.size
    q, v = np.zeros(n), np.zeros(n)
    a = np.linalg.solve(mass, drive * w_in)
    load_on, t_s = False, math.nan
    carrier = np.empty(steps)
    force = np.empty(steps)
    for step in range(steps):
        qt = q + dt * v + (dt * dt * (0.5 - beta)) * a
        vt = v + (dt * (1 - gamma)) * a
        rhs = -(damping @ vt) - stiffness @ qt
        # mesh stiffness at the Newmark predictor: pairs at frac(s) + k while < eps
        s = sigma * z1 * (angle @ qt) / (2 * np.pi) + phase
        p = (s - np.floor(s)) + offsets
        x = 2 * p / eps - 1
        pair = np.where(
            helical,
            kbar
            * np.minimum(np.minimum(p, eps - p), np.minimum(transverse, lam))
            / (transverse * lam),
            peak * (1 - (1 - lam) * x * x),
        )
        k = np.where(p < eps, pair, 0.0).sum(axis=0)
        delta = b @ qt
        rhs -= b.T @ ((k - kbar) * delta)
        speed_out = w_out @ vt
        load = load_scale * abs(speed_out / load_speed) ** 2 * np.sign(speed_out) if load_on else 0
        rhs += drive * w_in - load * w_out
        a_new = khat_inverse @ (scale * rhs)
        speed_old = w_in @ v
        q = qt + (beta * dt * dt) * a_new
        v = vt + (gamma * dt) * a_new
        a = a_new
        speed = w_in @ v
        if not load_on and speed >= omega_0:
            load_on = True
            t_s = step * dt + dt * (omega_0 - speed_old) / (speed - speed_old)
        carrier[step] = speed * 30 / math.pi
        force[step] = -k[0] * (b[0] @ q)
    return {"carrier": carrier, "force": force, "t_s": t_s}


def _member(problem, label: str) -> np.ndarray:
    index = problem.model.full_labels.index(label)
    return np.array(problem.model.reduction[index])


def median(function, repeats: int) -> float:
    return statistics.median(function() for _ in range(repeats))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200_000, help="kernel steps per run")
    parser.add_argument("--numpy-steps", type=int, default=20_000, help="NumPy steps per run")
    parser.add_argument("--repeats", type=int, default=5, help="repeats (median)")
    parser.add_argument("--case", choices=sorted(CASES), default="study", help="which run-up")
    args = parser.parse_args()
    global CASE
    CASE = args.case
    speed_channel, force_channel = CASES[CASE][2]

    problem = problem_for(args.steps)
    solver = problem.solver
    print(
        f"{CASES[CASE][0]} {CASES[CASE][1]}: {problem.model.size} DOFs, "
        f"band half-width {solver.bandwidth} "
        f"(reverse Cuthill-McKee), {solver.meshes.size} meshes, time-varying mesh stiffness, "
        f"equivalent load '{solver.equivalent_load}', dt = {problem.settings.time_step:g} s, "
        f"{len(problem.probes)} probes at 40 kHz"
    )
    kernel_run(problem, 1000)  # warm-up

    def kernel_us() -> float:
        result = kernel_run(problem, args.steps)
        return result.solver_wall_s / result.steps * 1e6

    def wall_us() -> float:
        started = time.perf_counter()
        result = kernel_run(problem, args.steps)
        return (time.perf_counter() - started) / result.steps * 1e6

    kernel = median(kernel_us, args.repeats)
    whole = median(wall_us, args.repeats)

    def numpy_us() -> float:
        started = time.perf_counter()
        numpy_newmark(problem, args.numpy_steps)
        return (time.perf_counter() - started) / args.numpy_steps * 1e6

    plain = median(numpy_us, args.repeats)
    print(f"\nkernel (inside transient_advance) : {kernel:8.3f} us per step")
    print(f"kernel run incl. Python per chunk : {whole:8.3f} us per step")
    print(f"plain NumPy loop, same algorithm  : {plain:8.3f} us per step")
    print(f"ratio NumPy / kernel              : {plain / kernel:8.1f} x")

    # rigid-body rebasing (pygear.kernel.newmark_rebase) against a run that never rebases
    import pygear.kernel.newmark_rebase as rebase

    default_steps = rebase.REBASE_STEPS
    rebase.REBASE_STEPS = 1 << 62
    try:
        never = median(wall_us, args.repeats)
    finally:
        rebase.REBASE_STEPS = default_steps
    print(
        f"rebasing every {default_steps} steps costs {100 * (whole / never - 1):+.1f} % "
        f"({whole:.3f} against {never:.3f} us per step without it)"
    )

    # the same trajectory: carrier speed and sun-planet1 mesh force of both loops
    reference = numpy_newmark(problem, args.numpy_steps)
    check = problem_for(
        args.numpy_steps,
        (Probe("speed", speed_channel), Probe("mesh_force", force_channel)),
    )
    result = kernel_run(check, args.numpy_steps)
    speed_error = np.max(np.abs(result.samples[0, 1:] - reference["carrier"])) / np.max(
        np.abs(reference["carrier"])
    )
    force_error = np.max(np.abs(result.samples[1, 1:] - reference["force"])) / np.max(
        np.abs(reference["force"])
    )
    print(
        f"kernel vs NumPy over {args.numpy_steps} steps: carrier speed {speed_error:.1e}, "
        f"mesh force {force_error:.1e} (max relative difference), t_s {result.t_s:.6f} vs "
        f"{reference['t_s']:.6f} s"
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
