"""How `pygear modal` on a drivetrain scales with the DOF count: 8 and 30 modes of the
NREL 5 MW drivetrain meshed from about 1e3 to 1.2e5 DOFs.

The model family is the one `pygear modal cases/nrel5mw_drivetrain` assembles, with every
shaft cut into ``elements_per_section`` Timoshenko elements instead of 1-4 (18 DOFs per
element across the three shafts, plus the gearbox's and the bodies'): the lowest modes
(one rigid rotation at 0 Hz, the drivetrain's 1.72-1.89 Hz cluster, then shaft and
gearbox modes up to 55 Hz at 30 modes) stay put while the element-level frequencies grow
with the mesh.  Per size and mode count, in this process:

* ``drivetrain_modes`` (what the command runs after assembly): median wall time and the
  number of (K - sigma M)^-1 solves its shift-invert Lanczos made;
* the former solver, same factor and Lanczos but the former default shift (1e-4 of the
  reference frequency sqrt(median(K_ii / M_ii)) / 2 pi) and the BLAS's own threads, as
  the baseline; ARPACK is stopped after ``--baseline-restarts`` restarts, which the
  former shift exceeds from 1.2e5 DOFs on (shown as a lower bound, '>');
* the same Lanczos with the new shift and the BLAS's own threads, to separate the two
  causes (shift: the solve count; threads: the time per ARPACK step on a busy machine).

Medians of repeats (benchmarks/timing.py); ratios are against the baseline measured in
the same process, so they hold on a loaded machine where the absolute times do not.

Last, the 10 000-DOF member of benchmarks/bench_sparse_path.py's synthetic family (four
shafts on stiff bearings, lowest elastic mode 66 Hz), whose 30 modes the README quoted,
with the same three variants.

Run: ``.venv/bin/python benchmarks/bench_sparse_modal.py`` (14 minutes on a 2-core
machine under a load of 12, most of it the former solver; ``--quick`` stops at 2.4e4
DOFs).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import time
from functools import partial

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from threadpoolctl import threadpool_limits

sys.path.insert(0, os.path.dirname(__file__))
from timing import median_seconds  # noqa: E402

from pygear import load_case  # noqa: E402
from pygear.analysis.modes.drivetrain_modal import drivetrain_modes  # noqa: E402
from pygear.analysis.modes.sparse_modal import (  # noqa: E402
    SHIFT_FRACTION,
    _default_shift_hz,
)
from pygear.assembly.drivetrain import DrivetrainModel, assemble_drivetrain  # noqa: E402
from pygear.kernel.sparse_cholesky import SparseCholesky  # noqa: E402

ELEMENTS = (54, 553, 1330, 6662)
"""Elements per shaft section: 1 062, 10 044, 24 030 and 120 006 DOFs."""
MODES = (8, 30)
FORMER_SHIFT_FRACTION = 1e-4
"""The default shift_hz / reference frequency before the fix."""


def drivetrain_model(elements: int) -> DrivetrainModel:
    """The NREL 5 MW drivetrain, spatial DOF set, each shaft section in ``elements``."""
    case = load_case("nrel5mw_drivetrain")
    drivetrain = case.drivetrain
    shafts = tuple(
        dataclasses.replace(shaft, elements_per_section=elements) for shaft in drivetrain.shafts
    )
    return assemble_drivetrain(
        dataclasses.replace(case, drivetrain=dataclasses.replace(drivetrain, shafts=shafts))
    )


def lanczos(
    stiffness: sp.csc_matrix,
    mass: sp.csc_matrix,
    modes: int,
    shift_hz: float,
    restarts: int | None,
) -> tuple[np.ndarray | None, int]:
    """Shift-invert Lanczos as sparse_modes runs it, but with the BLAS's own threads and
    a given shift: lowest frequencies [Hz] (None when ARPACK stopped first) and solves."""
    sigma = -((2 * np.pi * shift_hz) ** 2)
    solves = 0
    n = stiffness.shape[0]
    with SparseCholesky((stiffness - sigma * mass).tocsc()) as factor:

        def solve(x: np.ndarray) -> np.ndarray:
            nonlocal solves
            solves += 1
            return factor.solve(x)

        operator = spla.LinearOperator((n, n), matvec=solve, dtype=float)
        start = np.random.default_rng(0).standard_normal(n)
        try:
            eigenvalues = spla.eigsh(
                stiffness,
                k=modes,
                M=mass,
                sigma=sigma,
                which="LM",
                OPinv=operator,
                v0=start,
                maxiter=restarts,
                return_eigenvectors=False,
            )
        except spla.ArpackNoConvergence:
            return None, solves
    return np.sort(np.sqrt(np.clip(eigenvalues, 0, None)) / (2 * np.pi)), solves


def timed(function, repeats: int) -> tuple[float, object]:
    """Median wall time of ``repeats`` calls [s] and the last call's result."""
    results = []

    def call() -> None:
        results.append(function())

    return median_seconds(call, repeats), results[-1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="sizes up to 2.4e4 DOFs")
    parser.add_argument("--repeats", type=int, default=3, help="repeats per timing (3)")
    parser.add_argument(
        "--baseline-restarts",
        type=int,
        default=100,
        help="ARPACK restarts before the former solver is stopped (100)",
    )
    arguments = parser.parse_args()
    sizes = ELEMENTS[:3] if arguments.quick else ELEMENTS
    blas = threadpool_limits().get_original_num_threads().get("blas")
    print(f"BLAS threads available: {blas}; cores: {os.cpu_count()}")
    rows = []
    started = time.perf_counter()
    for elements in sizes:
        model = drivetrain_model(elements)
        new_hz = _default_shift_hz(model.stiffness, model.mass)
        former_hz = FORMER_SHIFT_FRACTION / SHIFT_FRACTION * new_hz
        for modes in MODES:
            repeats = arguments.repeats
            now_s, result = timed(partial(drivetrain_modes, model, modes), repeats)
            solves = result.solves
            threads_s, (_, threads_solves) = timed(
                partial(lanczos, model.stiffness, model.mass, modes, new_hz, None), repeats
            )
            before_s, (before_hz, before_solves) = timed(
                partial(
                    lanczos,
                    model.stiffness,
                    model.mass,
                    modes,
                    former_hz,
                    arguments.baseline_restarts,
                ),
                1 if model.size > 50_000 else repeats,
            )
            if before_hz is not None:
                agree = np.max(
                    np.abs(before_hz[1:] - result.frequencies_hz[1:]) / result.frequencies_hz[1:]
                )
                agreement = f"{agree:.1e}"
            else:
                agreement = "-"
            bound = ">" if before_hz is None else ""
            rows.append(
                f"{model.size:>7} {modes:>5} {1e3 * now_s:>9.0f} {solves:>6} "
                f"{1e3 * threads_s:>10.0f} {threads_solves:>6} "
                f"{bound + format(1e3 * before_s, '.0f'):>10} {bound + str(before_solves):>7} "
                f"{bound + format(before_s / now_s, '.0f'):>7} "
                f"{threads_s / now_s:>7.1f} {agreement:>8} "
                f"{result.frequencies_hz[1]:>6.3f} {result.frequencies_hz[-1]:>6.2f}"
            )
            print(
                f"  {model.size} DOFs, {modes} modes done ({time.perf_counter() - started:.0f} s)",
                flush=True,
            )
    print(
        "\nLowest modes of the NREL 5 MW drivetrain meshed finer: median wall times [ms]"
        "\n(now: drivetrain_modes, one BLAS thread in Lanczos, shift 1e-6 f_ref; threads: "
        "the same\nLanczos with the BLAS's threads; before: the former 1e-4 f_ref shift "
        "with the BLAS's threads;\nagree: max relative difference of the elastic "
        "frequencies, before against now)"
    )
    print(
        f"{'DOFs':>7} {'modes':>5} {'now':>9} {'solves':>6} {'threads':>10} {'solves':>6} "
        f"{'before':>10} {'solves':>7} {'bef/now':>7} {'thr/now':>7} {'agree':>8} "
        f"{'f1 Hz':>6} {'fk Hz':>6}"
    )
    print("\n".join(rows))
    synthetic_row(arguments.repeats)


def synthetic_row(repeats: int) -> None:
    """30 modes of bench_sparse_path's 10 000-DOF synthetic drivetrain, three ways."""
    from bench_sparse_path import drivetrain

    from pygear.analysis.modes.sparse_modal import sparse_modes

    mass, _, stiffness, n = drivetrain(10_002)
    new_hz = _default_shift_hz(stiffness, mass)
    former_hz = FORMER_SHIFT_FRACTION / SHIFT_FRACTION * new_hz
    now_s, result = timed(partial(sparse_modes, stiffness, mass, modes=30), repeats)
    threads_s, (_, threads_solves) = timed(
        partial(lanczos, stiffness, mass, 30, new_hz, None), repeats
    )
    before_s, (_, before_solves) = timed(
        partial(lanczos, stiffness, mass, 30, former_hz, None), repeats
    )
    print(
        f"\nbench_sparse_path's synthetic drivetrain, {n} DOFs, 30 modes "
        f"({result.frequencies_hz[1]:.1f}-{result.frequencies_hz[-1]:.1f} Hz): "
        f"now {1e3 * now_s:.0f} ms ({result.solves} solves), threads "
        f"{1e3 * threads_s:.0f} ms ({threads_solves}), before {1e3 * before_s:.0f} ms "
        f"({before_solves}); before/now {before_s / now_s:.1f}"
    )


if __name__ == "__main__":
    main()
