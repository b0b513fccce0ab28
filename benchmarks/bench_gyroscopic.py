"""What the gyroscopic term costs per Newmark step.

The kernel adds -Omega(t) G v to a step's loads and iterates it with the step's
velocity on the factor it already has (fortran/newmark_gyroscopic.f90).  This script
times, in this process, medians of repeats (benchmarks/timing.py):

* Friswell et al.'s Example 5.9.1 rotor (cases/friswell_rotor) refined to about 200 and
  1200 DOFs, 2000 steps of 1e-4 s at a constant 4000 rpm with the case's unbalance,
  on the banded and the sparse path, at the rotor scenes' default tolerance 1e-8:
  with the gyroscopic term against the same run
  with the unbalance alone (the baseline does the same steps, loads and probes; the
  difference is the term and its iterations);
* the NREL 5 MW drivetrain's spatial emergency stop (cases/nrel5mw_drivetrain), 2000
  steps, with the shafts' gyroscopics (the default) and without.

Printed per model: seconds per 1000 steps each way, their ratio, and the solves per step
the iteration took.  Run: ``.venv/bin/python benchmarks/bench_gyroscopic.py
[--repeats 3]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
from timing import median_seconds  # noqa: E402

STEPS = 2000


def rotor_runs(elements: int, path: str):
    """Two integrators of the refined Friswell rotor: with G and without."""
    from pygear.analysis.time.rotor_transient import rotor_transient_problem
    from pygear.kernel.newmark import BandedNewmark
    from pygear.kernel.newmark_rotor import RotorTerms
    from pygear.model.case import load_case

    case = load_case("friswell_rotor")
    shaft = dataclasses.replace(case.drivetrain.shafts[0], elements_per_section=elements)
    case = dataclasses.replace(
        case, drivetrain=dataclasses.replace(case.drivetrain, shafts=(shaft,))
    )
    scene = case.scene("whirl_4000rpm")
    problem = rotor_transient_problem(case, scene)
    model = problem.model
    speeds = {"times": (0.0,), "speeds": (4000 * 3.141592653589793 / 30,)}
    unbalance = RotorTerms(None, unbalances=_unbalances(problem), **speeds)
    spinning = RotorTerms(model.gyroscopic, unbalances=_unbalances(problem), **speeds)
    k, c = model.at_speed(4000.0)
    solvers = [
        BandedNewmark(model.mass, c, k, 1e-4, tolerance=1e-8, linear_solver=path, rotor=terms)
        for terms in (spinning, unbalance)
    ]
    return model.size, solvers, problem.probes


def _unbalances(problem):
    from pygear.kernel.newmark_rotor import Unbalance

    x, y = problem.disc_dofs["disc_right"]
    return (Unbalance(x, y, 1e-4),)


def drivetrain_runs():
    """The NREL drivetrain's spatial stop, with its shafts' gyroscopics and without."""
    from pygear.analysis.time.transient import transient_problem
    from pygear.model.case import load_case

    case = load_case("nrel5mw_drivetrain")
    scene = case.scene("emergency_stop_spatial")
    with_terms = transient_problem(case, scene)
    model = dataclasses.replace(with_terms.model, shaft_gyroscopic=None)
    without = transient_problem(case, scene, model=model)
    return model.size, [with_terms.solver, without.solver], with_terms.probes


def measure(solvers, probes, repeats: int):
    """Seconds per 1000 steps of each solver, and the solves per step of each."""
    seconds, solves = [], []
    for solver in solvers:
        result = {}

        def run(solver=solver, result=result):
            result["run"] = solver.run(STEPS, probes)

        seconds.append(median_seconds(run, repeats, warm_up=True) * 1000 / STEPS)
        solves.append(result["run"].counters["iterations"] / STEPS)
    return seconds, solves


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print(f"{'model':<34} {'DOFs':>5} {'with G':>9} {'without':>9} {'ratio':>6} "
          f"{'solves/step':>12}")  # fmt: skip
    cases = [
        (f"Friswell rotor, {path}", *rotor_runs(elements, path))
        for elements in (11, 66)
        for path in ("banded_cholesky", "sparse_cholesky")
    ]
    cases.append(("NREL drivetrain spatial stop", *drivetrain_runs()))
    for name, size, solvers, probes in cases:
        (spun, plain), (spun_solves, plain_solves) = measure(solvers, probes, args.repeats)
        print(
            f"{name:<34} {size:>5} {spun:>8.4f}s {plain:>8.4f}s {spun / plain:>6.2f} "
            f"{spun_solves:>5.2f} / {plain_solves:.2f}"
        )
    print(f"(seconds per 1000 steps, medians of {args.repeats}; solves per step with / without)")


if __name__ == "__main__":
    main()
