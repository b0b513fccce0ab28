"""Where the Newmark kernel's sparse path (CHOLMOD) beats its banded path, and what a
10 000-DOF drivetrain costs.

A synthetic family of flexible drivetrains: ``shafts`` hollow steel shafts of Timoshenko
elements (6 DOFs per node), each on two bearings, joined end to end by flexible
couplings, and every shaft's middle node tied to the first shaft's middle node by a
soft torsional spring (the cross-couplings a gear stage makes between shafts; they
widen the RCM band to the whole model while adding a few entries).  The size grows by
refining the shafts, from about 20 to 20 000 DOFs.  For each size the script times, in
this process, with medians of repeats:

* the kernel's step, whole Newmark steps in the kernel, on the banded path (while its
  band fits in ``--band-memory`` MB) and on the sparse path, and their ratio;
* the set-up of each path (ordering, band or pattern, factorizations): the banded path's
  n (kd + 1)^2 factorization is what excludes it from large models;
* the first 30 modes by shift-invert Lanczos on a CHOLMOD factor (``sparse_modes``), and
  the same with SciPy's ``splu`` as the factor (the baseline a SciPy user would write);

and for the 10 000-DOF member, 1 000 Newmark steps and the 30 modes, whole.  Memory: the
peak resident size of this process after each size (``resource.getrusage``).  The growth
of each cost with the DOF count is the slope of a log-log fit over the sizes.

First, the models users run: the study case's and the gearbox's run-ups, the NREL 5 MW
drivetrain's emergency stop and a plain spring chain, each on every path (forced by
``PYGEAR_LINEAR_SOLVER``) beside the path the automatic choice takes, to show that the
choice is the faster path.

Run: ``.venv/bin/python benchmarks/bench_sparse_path.py`` (about 2 minutes on 2 cores).
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from timing import median_seconds  # noqa: E402

SIZES = (24, 60, 120, 240, 480, 960, 1920, 4800, 10002, 20004)


def drivetrain(dofs: int, shafts: int = 4):
    """M, C, K0 (SciPy CSC) of a synthetic drivetrain with about ``dofs`` DOFs."""
    import scipy.sparse

    from pygear.assembly.shaft_elements import bearing_element, coupling_element
    from pygear.assembly.structure import Structure

    nodes_per_shaft = max(2, dofs // (6 * shafts))
    structure = Structure()
    bearing = bearing_element([1e9, 1e9, 1e8, 1e7, 1e7, 0.0], [1e4, 1e4, 1e3, 0, 0, 0])
    previous_end, middles = None, []
    for s in range(shafts):
        nodes = structure.add_shaft(
            f"shaft{s}", 1.5, 0.4 - 0.05 * s, 0.1, elements=nodes_per_shaft - 1
        )
        structure.add_ground_element(nodes[0], bearing)
        structure.add_ground_element(nodes[-1], bearing)
        if previous_end is not None:
            coupling = coupling_element(5e7, radial=1e8, axial=1e8, angular=1e6)
            structure.add_element([previous_end, nodes[0]], coupling)
        previous_end = nodes[-1]
        middles.append(nodes[len(nodes) // 2])
    for middle in middles[1:]:
        structure.add_element([middles[0], middle], coupling_element(1e6))
    matrices = structure.assemble()
    n = matrices.size
    # Rayleigh damping on K: C = 1e-5 K, the pattern of K
    return (
        scipy.sparse.csc_matrix(matrices.mass),
        1e-5 * scipy.sparse.csc_matrix(matrices.stiffness),
        scipy.sparse.csc_matrix(matrices.stiffness),
        n,
    )


def step_time(mass, damping, stiffness, solver: str, steps: int, repeats: int) -> tuple:
    """Median kernel time per step [s] and set-up time [s] on one path."""
    from pygear.kernel.newmark import BandedNewmark, KernelProbe

    n = mass.shape[0]
    started = time.perf_counter()
    newmark = BandedNewmark(mass, damping, stiffness, 1e-4, linear_solver=solver)
    newmark.start()  # factors (banded) or the problem with its CHOLMOD factors
    setup = time.perf_counter() - started
    weights = np.zeros(n)
    weights[n // 2] = 1.0
    probe = [KernelProbe("middle", "displacement", weights)]
    q0 = 1e-6 * np.sin(np.linspace(0, 3.0, n))

    def run():
        return newmark.run(steps, probe, q0=q0, decimation=10).solver_wall_s

    run()
    walls = [run() for _ in range(repeats)]
    return float(np.median(walls)) / steps, setup


def modal_time(mass, stiffness, modes: int, repeats: int) -> tuple:
    """Median time of the first ``modes`` modes with CHOLMOD and with SciPy's splu [s]."""
    import scipy.sparse.linalg

    from pygear.analysis.modes.sparse_modal import sparse_modes

    def cholmod():
        return sparse_modes(stiffness, mass, modes=modes)

    def splu():
        shift = -1.0
        factor = scipy.sparse.linalg.splu((stiffness - shift * mass).tocsc())
        operator = scipy.sparse.linalg.LinearOperator(
            stiffness.shape, matvec=factor.solve, dtype=float
        )
        return scipy.sparse.linalg.eigsh(
            stiffness, k=modes, M=mass, sigma=shift, OPinv=operator, which="LM"
        )

    return median_seconds(cholmod, repeats, warm_up=True), median_seconds(splu, repeats)


def band_half_width(mass, damping, stiffness) -> int:
    """RCM band half-width of the union pattern."""
    import scipy.sparse.csgraph

    pattern = (abs(mass) + abs(damping) + abs(stiffness)).tocsr()
    order = scipy.sparse.csgraph.reverse_cuthill_mckee(pattern, True)
    permuted = pattern[order][:, order].tocoo()
    return int(np.abs(permuted.row - permuted.col).max())


def peak_mb() -> float:
    """Peak resident size of this process so far [MB]."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def scene_step_times(repeats: int) -> None:
    """Kernel time per step of real scenes on each path, and the automatic choice."""
    import dataclasses

    from pygear import load_case
    from pygear.analysis.time.transient import run_transient, transient_problem
    from pygear.kernel.newmark_support import LINEAR_SOLVER_VARIABLE

    scenes = (
        ("yang2016_planetary", "runup", 0.2),
        ("yang2016_gearbox", "runup_tv", 0.05),
        ("nrel5mw_drivetrain", "emergency_stop", 0.2),
    )
    print(
        f"{'case / scene':<36} {'DOFs':>5} {'auto':>16} "
        f"{'banded':>8} {'sparse':>8} {'dense':>8}  us/step"
    )
    for case_name, scene_name, duration in scenes:
        case = load_case(case_name)
        scene = case.scene(scene_name)
        settings = dataclasses.replace(
            scene.transient,
            duration=duration,
            mean_window=min(duration, scene.transient.mean_window),
        )
        scene = dataclasses.replace(scene, transient=settings, analyses=("transient",))
        os.environ.pop(LINEAR_SOLVER_VARIABLE, None)
        problem = transient_problem(case, scene)
        auto, n = problem.solver.linear_solver, problem.model.size
        paths = ("banded_cholesky", "sparse_cholesky", "dense_inverse")
        walls: dict[str, list[float]] = {path: [] for path in paths}
        for _ in range(repeats):  # paths alternate, so a drift of the machine hits all
            for path in paths:
                os.environ[LINEAR_SOLVER_VARIABLE] = path
                run = run_transient(case, scene)
                walls[path].append(run.attrs["solver_wall_s"] / run.attrs["steps"])
        times = {path: float(np.median(walls[path])) * 1e6 for path in paths}
        os.environ.pop(LINEAR_SOLVER_VARIABLE, None)
        print(
            f"{case_name + ' / ' + scene_name:<36} {n:>5} {auto:>16} "
            f"{times['banded_cholesky']:>8.2f} {times['sparse_cholesky']:>8.2f} "
            f"{times['dense_inverse']:>8.2f}"
        )
        sys.stdout.flush()
    chain_step_times(1000, repeats)


def chain_step_times(n: int, repeats: int) -> None:
    """The same for a plain spring-mass chain of ``n`` masses (fixed at one end), whose
    band is its pattern: the automatic choice keeps it banded."""
    import scipy.sparse as sp

    from pygear.kernel.newmark import BandedNewmark

    spring, mass_value = 1.0e6, 2.0
    main_diagonal = np.full(n, 2.0 * spring)
    main_diagonal[-1] = spring
    stiffness = sp.diags(
        [main_diagonal, np.full(n - 1, -spring), np.full(n - 1, -spring)], [0, -1, 1]
    ).tocsc()
    mass = sp.identity(n, format="csc") * mass_value
    damping = 1e-4 * stiffness
    auto = BandedNewmark(mass, damping, stiffness, 1e-4).linear_solver
    steps = 2000
    times = {  # paths alternate within each repeat
        path: [] for path in ("banded_cholesky", "sparse_cholesky")
    }
    for _ in range(repeats):
        for path in times:
            times[path].append(step_time(mass, damping, stiffness, path, steps, 1)[0] * 1e6)
    print(
        f"{f'spring chain, {n} masses':<36} {n:>5} {auto:>16} "
        f"{np.median(times['banded_cholesky']):>8.2f} "
        f"{np.median(times['sparse_cholesky']):>8.2f} {'-':>8}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=SIZES)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--band-memory", type=float, default=400.0, help="band limit [MB]")
    parser.add_argument("--modes", type=int, default=30)
    args = parser.parse_args()

    scene_step_times(args.repeats)
    print("\nsynthetic drivetrain: 4 Timoshenko shafts on bearings, couplings, cross ties")
    growth: dict[str, list[tuple[int, float]]] = {"banded": [], "sparse": [], "modal": []}
    header = (
        f"{'DOFs':>6} {'kd':>6} {'banded us/step':>15} {'sparse us/step':>15} "
        f"{'banded/sparse':>13} {'setup b/s [s]':>15} {'modal chol [s]':>14} "
        f"{'splu/chol':>9} {'peak MB':>8}"
    )
    print(header)
    for target in args.sizes:
        mass, damping, stiffness, n = drivetrain(target)
        kd = band_half_width(mass, damping, stiffness)
        steps = int(max(50, min(2000, 2e6 / n)))
        band_mb = 4 * n * (kd + 1) * 8 / 1e6
        if band_mb <= args.band_memory:
            banded, banded_setup = step_time(
                mass, damping, stiffness, "banded_cholesky", steps, args.repeats
            )
        else:
            banded, banded_setup = float("nan"), float("nan")
        sparse, sparse_setup = step_time(
            mass, damping, stiffness, "sparse_cholesky", steps, args.repeats
        )
        modes = min(args.modes, n // 4)
        modal, modal_splu = modal_time(mass, stiffness, modes, max(1, args.repeats - 2))
        growth["sparse"].append((n, sparse))
        growth["modal"].append((n, modal))
        if np.isfinite(banded):
            growth["banded"].append((n, banded))
        print(
            f"{n:>6} {kd:>6} {banded * 1e6:>15.2f} {sparse * 1e6:>15.2f} "
            f"{banded / sparse:>13.2f} {banded_setup:>7.3f}/{sparse_setup:<7.3f} "
            f"{modal:>14.3f} {modal_splu / modal:>9.2f} {peak_mb():>8.0f}"
        )
        sys.stdout.flush()

    for name, points in growth.items():
        if len(points) >= 3:
            sizes, costs = np.log([p[0] for p in points]), np.log([p[1] for p in points])
            large = sizes >= np.log(200)  # past the fixed costs of small models
            slope = np.polyfit(sizes[large], costs[large], 1)[0] if large.sum() >= 2 else np.nan
            print(f"growth of the {name} cost above 200 DOFs: n^{slope:.2f}")

    mass, damping, stiffness, n = drivetrain(10002)
    from pygear.kernel.newmark import BandedNewmark, KernelProbe

    started = time.perf_counter()
    newmark = BandedNewmark(mass, damping, stiffness, 1e-4)
    weights = np.zeros(n)
    weights[n // 2] = 1.0
    result = newmark.run(1000, [KernelProbe("middle", "displacement", weights)])
    whole = time.perf_counter() - started
    from pygear.analysis.modes.sparse_modal import sparse_modes

    started = time.perf_counter()
    sparse_modes(stiffness, mass, modes=30)
    modal = time.perf_counter() - started
    print(
        f"\n{n}-DOF model: 1000 Newmark steps in {whole:.2f} s whole ({result.solver_wall_s:.2f} s "
        f"in the kernel, path {newmark.linear_solver}); the first 30 modes in {modal:.2f} s"
    )


if __name__ == "__main__":
    main()
