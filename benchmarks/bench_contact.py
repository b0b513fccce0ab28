"""Benchmark: cost of evaluating the tooth-contact table (all meshes at one state).

Times, for the study case's 6 meshes:

* the Fortran evaluation alone: ``contact_table_benchmark`` evaluates M states
  ``--passes`` times inside one kernel call and measures the loop with
  ``system_clock``, so Python's call overhead is excluded (the Newmark loop will
  call the module routine the same way);
* one state per Python call: the raw f2py routine, and ``ContactTable.evaluate``;
* M states in one Python call (``ContactTable.series``), per state.

Variants: healthy gears with the parabola, defects on three gears (factor
look-ups), and the tabulated law.  Each figure is the median of ``--repeats``
runs after a warm-up.

Usage::

    PYTHONPATH=. python benchmarks/bench_contact.py [--states 100000] [--repeats 7]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import statistics
import timeit

import numpy as np
from timing import median_seconds

from pygear.assembly import assemble
from pygear.assembly.contact_table import ContactTable, build_contact_table
from pygear.kernel.calls import _kernel
from pygear.model.case import load_case
from pygear.model.components import ToothDefect


def study_tables() -> dict[str, ContactTable]:
    case = load_case("yang2016_planetary")
    stage = case.gearbox.stages[0]
    p = np.linspace(0.0, 1.24, 25)
    curve = tuple(1 - 0.4 * (2 * p / 1.24 - 1) ** 2)
    tabulated = dataclasses.replace(
        case,
        gearbox=dataclasses.replace(
            case.gearbox,
            stages=(
                dataclasses.replace(
                    stage,
                    sun_mesh=dataclasses.replace(stage.sun_mesh, stiffness_curve=curve),
                    ring_mesh=dataclasses.replace(stage.ring_mesh, stiffness_curve=curve),
                ),
            ),
        ),
    )
    defects = dataclasses.replace(
        case,
        defects=(
            ToothDefect("planetary.sun", 3, 0.5),
            ToothDefect("planetary.ring", 10, 0.7),
            ToothDefect("planetary.planet1", 4, 0.0),
        ),
    )
    return {
        name: build_contact_table(c, assemble(c))
        for name, c in (
            ("parabola, healthy", case),
            ("parabola, 3 defective gears", defects),
            ("tabulated (25 samples)", tabulated),
        )
    }


def states(table: ContactTable, count: int) -> np.ndarray:
    """Relative angles along the constant-speed kinematics, 120 rpm, 40 kHz sampling,
    starting far from zero (a late time step of a long run)."""
    omega_c = 4 * math.pi
    ratio = 137.5 / 38.7
    speed = np.array([ratio * omega_c if g[0].endswith("sun") else omega_c for g in table.gears])
    time_ = 4.0 + np.arange(count) / 40_000.0
    return np.outer(time_, speed)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--states", type=int, default=100_000, help="states M per kernel call")
    parser.add_argument("--passes", type=int, default=10, help="passes over the states per call")
    parser.add_argument("--repeats", type=int, default=7, help="repeats (median)")
    args = parser.parse_args()

    print(
        f"tooth-contact table, study case, 6 meshes; M = {args.states} states, "
        f"{args.passes} passes per kernel call, median of {args.repeats}"
    )
    for name, table in study_tables().items():
        theta = states(table, args.states)
        theta_f = np.asfortranarray(theta.T)
        handle = table.handle

        def inside(theta_f=theta_f, handle=handle):
            elapsed, checksum, ierr = _kernel.contact_table_benchmark(
                handle=handle, theta=theta_f, n_repeat=args.passes
            )
            assert ierr == 0 and checksum > 0
            return elapsed

        inside()
        fortran = statistics.median(inside() for _ in range(args.repeats))
        per_state = fortran / (args.states * args.passes) * 1e6

        one = np.ascontiguousarray(theta[0])
        loops = 20_000
        raw = (
            min(
                timeit.repeat(
                    lambda one=one, table=table: _kernel.contact_table_evaluate(
                        handle=table.handle, max_pairs=table.max_pairs, theta=one
                    ),
                    number=loops,
                    repeat=args.repeats,
                )
            )
            / loops
            * 1e6
        )
        wrapped = (
            min(
                timeit.repeat(
                    lambda one=one, table=table: table.evaluate(one),
                    number=loops // 4,
                    repeat=args.repeats,
                )
            )
            / (loops // 4)
            * 1e6
        )
        series = median_seconds(
            lambda table=table, theta=theta: table.series(theta), args.repeats, warm_up=True
        )

        print(f"\n{name}")
        print(
            f"  Fortran loop inside one call : {per_state * 1e3:8.1f} ns per state "
            f"({per_state:.4f} us, all 6 meshes)"
        )
        print(
            f"  one state per Python call    : {raw:8.2f} us (raw f2py), "
            f"{wrapped:.2f} us (ContactTable.evaluate)"
        )
        print(
            f"  M states in one Python call  : {series / args.states * 1e6:8.3f} us per state "
            f"(ContactTable.series, outputs included)"
        )


if __name__ == "__main__":
    main()
