"""A peer on the same problem: pygear's Newmark kernel against Exudyn's implicit solver.

Exudyn (Gerstmayr's flexible multibody library, C++ under Python; ``pip install
exudyn``, or the ``peers`` extra) takes a linear second-order system as one
``ObjectGenericODE2`` with mass, damping and stiffness matrices, and anything beyond
them as that object's ``forceUserFunction``.  Both codes integrate with the same rule,
Newmark's average acceleration (beta 1/4, gamma 1/2), at the same step.  Two problems:

* **a gear run**: the study case's run-up (18 DOFs, 6 meshes) as the kernel integrates
  it, over its first ``--gear-steps`` steps: the time-varying mesh stiffness of the
  tooth-contact table (each mesh's stiffness from its tooth-pair positions, the
  parabola law, entering as the equivalent load (k(theta) - k_mean) delta), the constant
  drive torque and the speed-power load that switches on when the input reaches its
  reference speed.  Exudyn has no tooth contact and no gear-mesh element whose stiffness
  follows the mesh angle; its symbolic (compiled) user functions serve connectors and
  loads that read one or two coordinates and time, not a mesh deflection and angle
  that combine many coordinates, so the contact law is a Python ``forceUserFunction``
  of ``ObjectGenericODE2`` (called at every residual evaluation of Exudyn's Newton
  iteration; the load's switch a pre-step function).  Exudyn solves the implicit step
  (mesh force and load at the end of the step); pygear runs its default ``predictor``
  (mesh force at the Newmark predictor, one solve a step) and ``iterate`` (the implicit
  step, as Exudyn) equivalent loads.  Compared: wall time per step of whole calls,
  t_s and the channels' final values (speeds and accelerations);
* **linear free vibration**: the study case's and the gearbox's matrices at mean mesh
  stiffness (18 and 50 DOFs), from a seeded random displacement of 1e-7 (m, rad),
  ``--steps`` steps of 2.5e-5 s, Exudyn once with its dense and once with its sparse
  (Eigen) linear solver; the final states are compared.

pygear: ``run`` whole (its automatic linear solver, the Python chunk loop); Exudyn:
``SolveDynamic`` whole, as its documentation sets it up (generalized-alpha in its
Newmark form, modified Newton, no solution file).  Wall times per step, medians of
alternating repeats in this process, and each as a ratio to pygear's.  Without Exudyn
the script says how to get it and exits.

    PYTHONPATH=. python benchmarks/bench_peer.py [--only gear|linear] [--gear-steps 8000]
        [--steps 100000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import statistics
import time
import warnings

import numpy as np
from bare_loop import LoopArrays, _dense, loop_arrays

from pygear import load_case
from pygear.analysis.time.transient import transient_problem
from pygear.assembly.matrices import assemble
from pygear.kernel.newmark import BandedNewmark, KernelProbe
from pygear.kernel.newmark_support import LINEAR_SOLVER_VARIABLE

CASES = (("yang2016_planetary", "runup"), ("yang2016_gearbox", "runup_tv"))
GEAR_RUN = ("yang2016_planetary", "runup")
TIME_STEP = 2.5e-5
"""The paper's step [s]."""


def exudyn_run(exu, matrices, q0: np.ndarray, steps: int, sparse: bool):
    """Seconds per step of ``SolveDynamic`` whole, and the final displacements."""
    from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2

    mass, damping, stiffness = matrices
    n = mass.shape[0]
    container = exu.SystemContainer()
    system = container.AddSystem()
    node = system.AddNode(
        NodeGenericODE2(
            numberOfODE2Coordinates=n,
            referenceCoordinates=[0.0] * n,
            initialCoordinates=q0.tolist(),
            initialCoordinates_t=[0.0] * n,
        )
    )
    system.AddObject(
        ObjectGenericODE2(
            nodeNumbers=[node], massMatrix=mass, stiffnessMatrix=stiffness, dampingMatrix=damping
        )
    )
    system.Assemble()
    settings = newmark_settings(exu, steps, sparse)
    started = time.perf_counter()
    exu.SolveDynamic(system, settings)
    seconds = (time.perf_counter() - started) / steps
    return seconds, np.array(system.systemData.GetODE2Coordinates())


def newmark_settings(exu, steps: int, sparse: bool):
    """Exudyn's simulation settings: Newmark (1/4, 1/2) at ``TIME_STEP``, modified Newton,
    no output files."""
    settings = exu.SimulationSettings()
    integration = settings.timeIntegration
    integration.numberOfSteps = steps
    integration.endTime = steps * TIME_STEP
    integration.verboseMode = 0
    integration.generalizedAlpha.useNewmark = True
    integration.generalizedAlpha.newmarkBeta = 0.25
    integration.generalizedAlpha.newmarkGamma = 0.5
    integration.generalizedAlpha.spectralRadius = 1.0
    integration.generalizedAlpha.computeInitialAccelerations = True
    integration.newton.useModifiedNewton = True
    with warnings.catch_warnings():  # the older names still work; keep them quiet
        warnings.simplefilter("ignore", DeprecationWarning)
        settings.solutionSettings.writeSolutionToFile = False
        settings.linearSolverType = (
            exu.LinearSolverType.EigenSparse if sparse else exu.LinearSolverType.EXUdense
        )
    return settings


def pygear_run(matrices, q0: np.ndarray, steps: int):
    """Seconds per step of ``BandedNewmark.run`` whole, the final displacements and the
    linear solver the automatic choice took."""
    mass, damping, stiffness = matrices
    newmark = BandedNewmark(mass, damping, stiffness, TIME_STEP)
    probe = [KernelProbe("first", "displacement", np.eye(mass.shape[0])[0])]
    started = time.perf_counter()
    result = newmark.run(steps, probe, q0=q0, decimation=steps)
    seconds = (time.perf_counter() - started) / steps
    return seconds, result.q, newmark.linear_solver


def gear_problem(steps: int, equivalent_load: str = "predictor", banded: bool = False):
    """The gear run's scene as the kernel integrates it, cut to ``steps`` steps (its
    automatic linear solver, or the banded one, whose bands ``loop_arrays`` reads)."""
    case_name, scene_name = GEAR_RUN
    case = load_case(case_name)
    scene = case.scene(scene_name)
    settings = scene.transient
    settings = dataclasses.replace(
        settings,
        duration=steps * settings.time_step,
        mean_window=settings.time_step,
        equivalent_load=equivalent_load,
    )
    forced = os.environ.pop(LINEAR_SOLVER_VARIABLE, None)
    if banded:
        os.environ[LINEAR_SOLVER_VARIABLE] = "banded_cholesky"
    try:
        return transient_problem(case, dataclasses.replace(scene, transient=settings))
    finally:
        os.environ.pop(LINEAR_SOLVER_VARIABLE, None)
        if forced is not None:
            os.environ[LINEAR_SOLVER_VARIABLE] = forced


def mesh_stiffness(arrays: LoopArrays, theta: np.ndarray) -> np.ndarray:
    """Each mesh's stiffness at the mesh angles ``theta`` [N/m]: the sum over the tooth
    pairs in contact of the pair law, the parabola for spur meshes and the contact-line
    law for helical ones (as the kernel's table and ``bare_loop.numpy_fused``)."""
    kbar, eps, lam = arrays.mean_stiffness, arrays.contact_ratio, arrays.end_to_peak
    cycle = arrays.cycle_sign * arrays.teeth / (2 * math.pi) * theta + arrays.phase
    p = (cycle - np.floor(cycle)) + np.arange(arrays.max_pairs)[:, None]
    k = np.zeros_like(kbar)
    spur, helical = ~arrays.helical, arrays.helical
    if spur.any():
        e, ls, ps = eps[spur], lam[spur], p[:, spur]
        pair = 3 * kbar[spur] / (e * (2 + ls)) * (1 - (1 - ls) * (2 * ps / e - 1) ** 2)
        k[spur] = np.where(ps < e, pair, 0.0).sum(axis=0)
    if helical.any():
        e, lh, ph = eps[helical], lam[helical], p[:, helical]
        transverse = e - lh
        pair = kbar[helical] * np.minimum(
            np.minimum(ph, e - ph), np.minimum(transverse, lh)
        ) / (transverse * lh)
        k[helical] = np.where(ph < e, pair, 0.0).sum(axis=0)
    return k


def exudyn_gear_run(exu, arrays: LoopArrays, mass_band: np.ndarray, steps: int):
    """Seconds per step of ``SolveDynamic`` whole on the gear run, t_s [s], the final
    velocities and accelerations (kernel DOF order) and the user function's calls."""
    from exudyn.itemInterface import NodeGenericODE2, ObjectGenericODE2

    n = arrays.n
    mass, damping, stiffness = (
        _dense(band) for band in (mass_band, arrays.damping_band, arrays.stiffness_band)
    )
    p1, p2, p3 = arrays.load
    omega_0, dt = arrays.speed_reference, arrays.time_step
    switch = {"on": False, "t_s": math.nan, "speed": 0.0, "calls": 0}

    def force(mbs, t, item, q, q_t):
        switch["calls"] += 1
        q, q_t = np.asarray(q), np.asarray(q_t)
        delta = arrays.deflection @ q
        k = mesh_stiffness(arrays, arrays.angle @ q)
        f = arrays.drive * arrays.w_in - arrays.deflection.T @ ((k - arrays.mean_stiffness) * delta)
        if switch["on"]:
            speed = float(arrays.w_out @ q_t)
            f -= math.copysign(p1 * abs(speed / p2) ** p3, speed) * arrays.w_out
        return f

    def pre_step(mbs, t):  # t: the end of the step to come; the state is at t - dt
        if not switch["on"]:
            speed = float(arrays.w_in @ np.asarray(mbs.systemData.GetODE2Coordinates_t()))
            if speed >= omega_0:
                switch["on"] = True
                old = switch["speed"]
                switch["t_s"] = t - 2 * dt + dt * (omega_0 - old) / (speed - old)
            switch["speed"] = speed
        return True

    container = exu.SystemContainer()
    system = container.AddSystem()
    node = system.AddNode(
        NodeGenericODE2(
            numberOfODE2Coordinates=n,
            referenceCoordinates=[0.0] * n,
            initialCoordinates=[0.0] * n,
            initialCoordinates_t=[0.0] * n,
        )
    )
    system.AddObject(
        ObjectGenericODE2(
            nodeNumbers=[node], massMatrix=mass, stiffnessMatrix=stiffness,
            dampingMatrix=damping, forceUserFunction=force,
        )
    )
    system.SetPreStepUserFunction(pre_step)
    system.Assemble()
    settings = newmark_settings(exu, steps, sparse=False)
    started = time.perf_counter()
    exu.SolveDynamic(system, settings)
    seconds = (time.perf_counter() - started) / steps
    data = system.systemData
    return (
        seconds,
        switch["t_s"],
        np.array(data.GetODE2Coordinates_t()),
        np.array(data.GetODE2Coordinates_tt()),
        switch["calls"],
    )


def gear_comparison(exu, steps: int, repeats: int) -> None:
    """The gear run: pygear (predictor, iterate) against Exudyn, alternating repeats."""
    problems = {mode: gear_problem(steps, mode) for mode in ("predictor", "iterate")}
    banded = gear_problem(steps, banded=True)
    arrays = loop_arrays(banded)
    mass_band = banded.solver.bands["mass"]
    kinds = [kind for _, kind, _ in arrays.linear]
    names = [probe.name for probe in problems["predictor"].probes]
    rows = [names.index(name) for name, _, _ in arrays.linear]
    times: dict[str, list[float]] = {"predictor": [], "iterate": [], "Exudyn": []}
    results = {}
    for _ in range(repeats):
        for mode, problem in problems.items():
            started = time.perf_counter()
            result = problem.solver.run(
                steps, problem.probes, decimation=problem.settings.decimation
            )
            times[mode].append((time.perf_counter() - started) / result.steps)
            results[mode] = result
        seconds, t_s, v, a, calls = exudyn_gear_run(exu, arrays, mass_band, steps)
        times["Exudyn"].append(seconds)
    exudyn_final = np.array(
        [w @ (v if kind == "velocity" else a) for (_, kind, w) in arrays.linear]
    )
    median = {k: statistics.median(t) * 1e6 for k, t in times.items()}
    print(
        f"\ngear run: {GEAR_RUN[0]} {GEAR_RUN[1]}, {arrays.n} DOFs, "
        f"{len(arrays.mean_stiffness)} meshes, time-varying mesh stiffness, {steps} steps of "
        f"{arrays.time_step:g} s from rest; wall time per step, medians of {repeats} "
        f"alternating repeats; Exudyn called its user function {calls / steps:.1f} times a step"
    )
    for mode in ("predictor", "iterate"):
        result = results[mode]
        ratio = statistics.median(a / b for a, b in zip(times["Exudyn"], times[mode]))
        final = result.samples[rows, -1]
        scale = {
            kind: np.abs(result.samples[[r for r, k in zip(rows, kinds) if k == kind]]).max()
            for kind in set(kinds)
        }
        worst = {
            kind: max(
                abs(f - e) / scale[kind]
                for f, e, k in zip(final, exudyn_final, kinds)
                if k == kind
            )
            for kind in set(kinds)
        }
        agreement = ", ".join(f"{kind} {worst[kind]:.1e}" for kind in sorted(worst))
        print(
            f"  pygear ({mode:9s}) {median[mode]:8.2f} us; Exudyn {median['Exudyn']:8.1f} us "
            f"= {ratio:6.1f} x pygear; t_s {result.t_s:.6f} against {t_s:.6f} s; final "
            f"channels differ by {agreement} (of each kind's largest value)"
        )


def linear_comparison(exu, steps: int, repeats: int) -> None:
    """Linear free vibration: pygear against Exudyn dense and sparse, alternating repeats."""
    print(
        f"Exudyn {exu.__version__} against pygear on the same linear system: Newmark "
        f"(1/4, 1/2), dt = {TIME_STEP:g} s, {steps} steps of free vibration; wall "
        f"time per step, medians of {repeats} alternating repeats"
    )
    print(
        f"{'case':<20} {'DOFs':>5} {'pygear [us]':>12} {'Exudyn dense':>13} "
        f"{'Exudyn sparse':>14} {'final states':>13}"
    )
    for case_name, scene_name in CASES:
        case = load_case(case_name)
        model = assemble(case, case.scene(scene_name))
        matrices = tuple(
            np.asarray(m, dtype=np.float64) for m in (model.mass, model.damping, model.stiffness)
        )
        q0 = 1e-7 * np.random.default_rng(0).standard_normal(model.size)
        times: dict[str, list[float]] = {"pygear": [], "dense": [], "sparse": []}
        for _ in range(repeats):  # alternating: each repeat sees the same machine
            seconds, pygear_q, solver = pygear_run(matrices, q0, steps)
            times["pygear"].append(seconds)
            for kind in ("dense", "sparse"):
                seconds, exudyn_q = exudyn_run(exu, matrices, q0, steps, kind == "sparse")
                times[kind].append(seconds)
        difference = np.abs(pygear_q - exudyn_q).max() / np.abs(exudyn_q).max()
        median = {k: statistics.median(v) * 1e6 for k, v in times.items()}
        ratio = {
            k: statistics.median(a / b for a, b in zip(times[k], times["pygear"]))
            for k in ("dense", "sparse")
        }
        print(
            f"{case_name:<20} {model.size:>5} {median['pygear']:>12.2f} "
            f"{median['dense']:>7.2f} ({ratio['dense']:.1f}x) "
            f"{median['sparse']:>7.2f} ({ratio['sparse']:.1f}x) {difference:>13.1e}"
        )
        print(f"{'':<20} pygear's linear solver: {solver}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=100_000, help="steps per linear run")
    parser.add_argument(
        "--gear-steps", type=int, default=8_000, help="steps per gear run (t_s at 6305)"
    )
    parser.add_argument("--only", choices=("gear", "linear"), help="one of the two problems")
    parser.add_argument("--repeats", type=int, default=5, help="repeats (median)")
    args = parser.parse_args()
    try:
        import exudyn as exu
    except ImportError:
        print("Exudyn is not installed: pip install exudyn (or pip install '.[peers]')")
        return
    if args.only != "gear":
        linear_comparison(exu, args.steps, args.repeats)
    if args.only != "linear":
        gear_comparison(exu, args.gear_steps, args.repeats)


if __name__ == "__main__":
    main()
