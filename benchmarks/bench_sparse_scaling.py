"""How the sparse Cholesky path scales from 20 to 20 000 DOFs, against SuperLU and
LAPACK's banded Cholesky.

The model family: a spring-mass chain (a shaft line, fixed at one end) with seeded
long-range springs, one per 50 DOFs between random DOFs (meshes and bearings that tie
distant shafts), so the matrix is not banded; the banded solver gets the reverse
Cuthill-McKee ordering (SciPy's) and whatever band that leaves.  Per size:

- factor: CHOLMOD (simplicial and supernodal; analysis + numeric), its numeric
  refactorization alone, SciPy's splu (SuperLU in its symmetric mode: minimum degree on
  A' + A, diagonal pivots), LAPACK dpbtrf (scipy.linalg.cholesky_banded) when the band
  fits the memory and flop budgets;
- solve: one right-hand side through each Python call (CHOLMOD via SparseCholesky.solve,
  splu's solve, cho_solve_banded) and CHOLMOD inside the kernel (a Fortran loop of
  sparse_factor_solve, what the Newmark kernel sees);
- modal: the first 30 modes by sparse_modes (shift-invert Lanczos on a CHOLMOD factor,
  then on splu) and, up to 2000 DOFs, dense scipy.linalg.eigh of those 30.

Medians of repeats (benchmarks/timing.py).  A benchmark, not a test: run it on a quiet
machine (`.venv/bin/python benchmarks/bench_sparse_scaling.py [--quick]`).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as spla
from timing import median_seconds

from pygear.analysis.modes.sparse_modal import sparse_modes
from pygear.kernel import _kernel
from pygear.kernel.sparse_cholesky import SparseCholesky, sparse_cholesky_available

SIZES = (20, 60, 200, 600, 2000, 6000, 20000)
LINKS_PER_DOF = 1 / 50
MODES = 30
BAND_MEMORY_BYTES = 400e6  # the band's storage, (kd + 1) n doubles
BAND_FLOPS = 2e10  # n kd^2 of dpbtrf: a few seconds per factorization at most
DENSE_EIGEN_LIMIT = 2000


def chain_model(n: int, seed: int = 0) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    """K (positive definite: fixed at DOF 0) and a diagonal M of the chain family."""
    rng = np.random.default_rng(seed)
    rows = [np.arange(n - 1)]
    columns = [np.arange(1, n)]
    stiffness = [rng.uniform(0.5, 2.0, n - 1) * 1e8]
    links = max(1, int(n * LINKS_PER_DOF))
    first = rng.integers(0, n, links)
    second = rng.integers(0, n, links)
    distinct = first != second
    rows.append(first[distinct])
    columns.append(second[distinct])
    stiffness.append(rng.uniform(0.1, 1.0, int(distinct.sum())) * 1e8)
    i, j, k = (np.concatenate(parts) for parts in (rows, columns, stiffness))
    springs = sp.coo_matrix((k, (i, j)), shape=(n, n)).tocsc()
    springs = springs + springs.T
    degree = np.asarray(springs.sum(axis=1)).ravel()
    degree[0] += 1e8  # the ground spring at DOF 0
    matrix = (sp.diags(degree) - springs).tocsc()
    matrix.sum_duplicates()
    mass = sp.diags(rng.uniform(1.0, 5.0, n), format="csc")
    return matrix, mass


def lower_arrays(matrix: sp.csc_matrix) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    lower = sp.tril(matrix, format="csc")
    lower.sort_indices()
    return lower.indptr.astype(np.int32), lower.indices.astype(np.int32), lower.data


def cholmod_times(matrix: sp.csc_matrix, method: int, repeats: int) -> dict[str, float]:
    """Factor, refactor and solve times of CHOLMOD through the kernel's wrappers."""
    indptr, indices, data = lower_arrays(matrix)
    n = matrix.shape[0]

    def create() -> int:
        handle, _, ierr = _kernel.sparse_cholesky_create(indptr, indices, data, 0, method)
        assert ierr == 0, ierr
        return handle

    def create_and_free() -> None:
        _kernel.sparse_cholesky_free(create())

    factor_s = median_seconds(create_and_free, repeats, warm_up=True)
    handle = create()
    try:
        refactor_s = median_seconds(
            lambda: _kernel.sparse_cholesky_refactor(handle, data), repeats, warm_up=True
        )
        rhs = np.ones(n)
        loops = max(20, int(2e6 / n))
        per_solve = []
        for _ in range(max(repeats, 7)):
            solution, elapsed, ierr = _kernel.sparse_cholesky_solve_benchmark(handle, rhs, loops)
            assert ierr == 0, ierr
            per_solve.append(elapsed / loops)
        kernel_solve_s = float(np.median(per_solve))
        nnz_factor, _, supernodal, _, _ = _kernel.sparse_cholesky_stats(handle)
    finally:
        _kernel.sparse_cholesky_free(handle)
    with SparseCholesky(matrix, method=("simplicial", "supernodal")[method - 1]) as factor:
        python_solve_s = median_seconds(lambda: factor.solve(rhs), 5 * repeats, warm_up=True)
    residual = np.linalg.norm(matrix @ solution - rhs) / np.linalg.norm(rhs)
    return {
        "factor": factor_s,
        "refactor": refactor_s,
        "solve": python_solve_s,
        "kernel solve": kernel_solve_s,
        "nnz(L)": float(nnz_factor),
        "supernodal": float(supernodal),
        "residual": float(residual),
    }


def splu_times(matrix: sp.csc_matrix, repeats: int) -> dict[str, float]:
    def factor() -> spla.SuperLU:
        return spla.splu(
            matrix,
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )

    lu = factor()
    rhs = np.ones(matrix.shape[0])
    return {
        "factor": median_seconds(factor, repeats),
        "solve": median_seconds(lambda: lu.solve(rhs), 5 * repeats, warm_up=True),
        "nnz(L+U)": float(lu.L.nnz + lu.U.nnz),
    }


def banded_times(matrix: sp.csc_matrix, repeats: int) -> tuple[dict[str, float], int, str]:
    """dpbtrf/dpbtrs on the RCM-ordered band, or why it was skipped."""
    n = matrix.shape[0]
    order = csgraph.reverse_cuthill_mckee(matrix.tocsr(), symmetric_mode=True)
    permuted = matrix[order][:, order].tocoo()
    kd = int(np.max(np.abs(permuted.row - permuted.col)))
    if (kd + 1) * n * 8 > BAND_MEMORY_BYTES:
        return {}, kd, "band over memory budget"
    if n * kd**2 > BAND_FLOPS:
        return {}, kd, "band over flop budget"
    band = np.zeros((kd + 1, n))
    lower = permuted.row >= permuted.col
    band[(permuted.row - permuted.col)[lower], permuted.col[lower]] = permuted.data[lower]
    factor = scipy.linalg.cholesky_banded(band, lower=True, check_finite=False)
    rhs = np.ones(n)
    times = {
        "factor": median_seconds(
            lambda: scipy.linalg.cholesky_banded(band, lower=True, check_finite=False), repeats
        ),
        "solve": median_seconds(
            lambda: scipy.linalg.cho_solve_banded((factor, True), rhs, check_finite=False),
            5 * repeats,
            warm_up=True,
        ),
    }
    return times, kd, ""


def modal_times(
    stiffness: sp.csc_matrix, mass: sp.csc_matrix, repeats: int
) -> dict[str, float | None]:
    n = stiffness.shape[0]
    count = min(MODES, n - 2)
    times: dict[str, float | None] = {}
    times["cholmod"] = median_seconds(lambda: sparse_modes(stiffness, mass, modes=count), repeats)
    times["splu"] = median_seconds(
        lambda: sparse_modes(stiffness, mass, modes=count, factorization="splu"), repeats
    )
    if n <= DENSE_EIGEN_LIMIT:
        k_dense, m_dense = stiffness.toarray(), mass.toarray()
        times["dense"] = median_seconds(
            lambda: scipy.linalg.eigh(k_dense, m_dense, subset_by_index=[0, count - 1]),
            max(1, repeats // 2),
        )
    else:
        times["dense"] = None
    return times


def milliseconds(seconds: float | None) -> str:
    return "-" if seconds is None else f"{1e3 * seconds:.3g}"


def microseconds(seconds: float | None) -> str:
    return "-" if seconds is None else f"{1e6 * seconds:.3g}"


def ratio(numerator: float | None, denominator: float | None) -> str:
    if numerator is None or denominator is None or denominator <= 0:
        return "-"
    return f"{numerator / denominator:.2g}x"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="sizes up to 2000, fewer repeats")
    arguments = parser.parse_args()
    if not sparse_cholesky_available():
        raise SystemExit("the kernel was built without CHOLMOD: install libsuitesparse-dev")
    sizes = [n for n in SIZES if not arguments.quick or n <= 2000]
    started = time.perf_counter()
    factor_rows, solve_rows, modal_rows, ratio_rows = [], [], [], []
    for n in sizes:
        stiffness, mass = chain_model(n)
        repeats = 3 if arguments.quick else (7 if n <= 2000 else 3)
        simplicial = cholmod_times(stiffness, 1, repeats)
        supernodal = cholmod_times(stiffness, 2, repeats)
        superlu = splu_times(stiffness, repeats)
        banded, kd, skipped = banded_times(stiffness, repeats)
        modal = modal_times(stiffness, mass, max(1, repeats // 2))
        best = min(simplicial["factor"], supernodal["factor"])
        best_solve = min(simplicial["solve"], supernodal["solve"])
        factor_rows.append(
            f"{n:>6} {stiffness.nnz:>7} {int(simplicial['nnz(L)']):>8} {kd:>5} "
            f"{milliseconds(simplicial['factor']):>9} {milliseconds(simplicial['refactor']):>9} "
            f"{milliseconds(supernodal['factor']):>9} {milliseconds(supernodal['refactor']):>9} "
            f"{milliseconds(superlu['factor']):>9} "
            f"{milliseconds(banded.get('factor')) if banded else skipped:>9}"
        )
        solve_rows.append(
            f"{n:>6} {microseconds(simplicial['kernel solve']):>9} "
            f"{microseconds(supernodal['kernel solve']):>9} "
            f"{microseconds(simplicial['solve']):>9} {microseconds(supernodal['solve']):>9} "
            f"{microseconds(superlu['solve']):>9} "
            f"{microseconds(banded.get('solve')) if banded else '-':>9} "
            f"{max(simplicial['residual'], supernodal['residual']):>9.1e}"
        )
        modal_rows.append(
            f"{n:>6} {milliseconds(modal['cholmod']):>9} {milliseconds(modal['splu']):>9} "
            f"{milliseconds(modal['dense']):>9}"
        )
        ratio_rows.append(
            f"{n:>6} {ratio(superlu['factor'], best):>9} "
            f"{ratio(banded.get('factor'), best):>9} "
            f"{ratio(supernodal['factor'], simplicial['factor']):>9} "
            f"{ratio(superlu['solve'], best_solve):>9} "
            f"{ratio(banded.get('solve'), best_solve):>9} "
            f"{ratio(modal['splu'], modal['cholmod']):>9} "
            f"{ratio(modal['dense'], modal['cholmod']):>9}"
        )
        print(f"  n = {n} done ({time.perf_counter() - started:.0f} s)", flush=True)

    print("\nFactor [ms] (CHOLMOD: analysis + numeric; refactor: numeric alone)")
    print(
        f"{'DOFs':>6} {'nnz(K)':>7} {'nnz(L)':>8} {'band':>5} {'simpl.':>9} {'simpl.re':>9} "
        f"{'supern.':>9} {'supern.re':>9} {'splu':>9} {'dpbtrf':>9}"
    )
    print("\n".join(factor_rows))
    print("\nSolve, one right-hand side [us] (kernel: Fortran loop; others: one Python call)")
    print(
        f"{'DOFs':>6} {'k.simpl':>9} {'k.supern':>9} {'simpl.':>9} {'supern.':>9} "
        f"{'splu':>9} {'dpbtrs':>9} {'residual':>9}"
    )
    print("\n".join(solve_rows))
    print(f"\nModal, first {MODES} modes [ms] (shift-invert Lanczos; dense: eigh subset)")
    print(f"{'DOFs':>6} {'cholmod':>9} {'splu':>9} {'dense':>9}")
    print("\n".join(modal_rows))
    print("\nRatios (other / best CHOLMOD; > 1: CHOLMOD faster)")
    print(
        f"{'DOFs':>6} {'splu fac':>9} {'band fac':>9} {'sup/simp':>9} {'splu sol':>9} "
        f"{'band sol':>9} {'splu mod':>9} {'dense mod':>9}"
    )
    print("\n".join(ratio_rows))


if __name__ == "__main__":
    main()
