"""A peer on the same problem: pygear's Newmark kernel against Exudyn's implicit solver.

Exudyn (Gerstmayr's flexible multibody library, C++ under Python; ``pip install
exudyn``, or the ``peers`` extra) takes a linear second-order system as one
``ObjectGenericODE2`` with mass, damping and stiffness matrices.  Both codes integrate
the same system with the same rule, Newmark's average acceleration (beta 1/4, gamma 1/2)
at the same step, from the same initial displacement:

* the study case's and the gearbox's matrices at mean mesh stiffness (18 and 50 DOFs),
  as ``pygear.assembly.matrices.assemble`` gives them: the linear part of a gear run,
  without the tooth contact, which Exudyn does not model;
* free vibration from a seeded random displacement of 1e-7 (m, rad), 100 000 steps of
  2.5e-5 s;
* pygear: ``BandedNewmark.run`` whole (its automatic linear solver, the Python chunk
  loop, one probe); Exudyn: ``SolveDynamic`` whole, as its documentation sets it up
  (generalized-alpha in its Newmark form, modified Newton, no solution file), once with
  its dense and once with its sparse (Eigen) linear solver.

Wall times per step, medians of alternating repeats in this process, and each as a ratio
to pygear's; the final states are compared, relative to their largest coordinate, to
show that both solved the same problem.  Without Exudyn the script says how to get it
and exits.

    python benchmarks/bench_peer.py [--steps 100000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings

import numpy as np

from pygear import load_case
from pygear.assembly.matrices import assemble
from pygear.kernel.newmark import BandedNewmark, KernelProbe

CASES = (("yang2016_planetary", "runup"), ("yang2016_gearbox", "runup_tv"))
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
    started = time.perf_counter()
    exu.SolveDynamic(system, settings)
    seconds = (time.perf_counter() - started) / steps
    return seconds, np.array(system.systemData.GetODE2Coordinates())


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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=100_000, help="steps per run")
    parser.add_argument("--repeats", type=int, default=5, help="repeats (median)")
    args = parser.parse_args()
    try:
        import exudyn as exu
    except ImportError:
        print("Exudyn is not installed: pip install exudyn (or pip install '.[peers]')")
        return
    print(
        f"Exudyn {exu.__version__} against pygear on the same linear system: Newmark "
        f"(1/4, 1/2), dt = {TIME_STEP:g} s, {args.steps} steps of free vibration; wall "
        f"time per step, medians of {args.repeats} alternating repeats"
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
        for _ in range(args.repeats):  # alternating: each repeat sees the same machine
            seconds, pygear_q, solver = pygear_run(matrices, q0, args.steps)
            times["pygear"].append(seconds)
            for kind in ("dense", "sparse"):
                seconds, exudyn_q = exudyn_run(exu, matrices, q0, args.steps, kind == "sparse")
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


if __name__ == "__main__":
    main()
