"""How the Newmark kernel holds M, C and K0: bands in RCM order, or one sparse pattern.

Either storage carries any model. On the banded paths the DOFs are renumbered by reverse
Cuthill-McKee (on the pattern of M + C + K0 and the meshes' couplings) and the matrices
go to the kernel as LAPACK band matrices, solved by the banded Cholesky factor or by a
dense inverse with one step of iterative refinement, the automatic choice from 10 to 40
DOFs (or, on request, by the dense inverse alone; :func:`~pygear.kernel.
newmark_support.choose_linear_solver`). On the sparse path the three matrices share one
lower-triangle pattern in compressed sparse columns, the kernel factors Khat and M with
CHOLMOD, which orders the DOFs itself (approximate minimum degree or nested dissection),
and the DOF order stays the caller's (``fortran/newmark_sparse.f90``).

Outside that range the automatic choice predicts what a step reads: the banded path two
triangular solves over the band, n (kd + 1) entries, and the products with C and K0 over
the same band; the sparse path the solves over CHOLMOD's factor, nnz(L) entries (from
CHOLMOD's own analysis of the pattern), and the products over the pattern, nnz(P). The
sparse path runs when :data:`SPARSE_OVERHEAD` (nnz(L) + nnz(P)) <= 2 n (kd + 1): its
indexed loads cost about a quarter more per entry than the band's (a spring chain, for
which both read the same count, runs 3 to 16 % slower sparse;
``benchmarks/bench_sparse_path.py``). A build without CHOLMOD keeps the banded path. In
equivalent-load mode ``refactor`` the sparse path refactors numerically on its pattern,
which holds the meshes' couplings. Dense input is turned into the pattern with NumPy
alone, so gear-stage models do not load SciPy's sparse package.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _kernel
from .band_ordering import band_half_width, reverse_cuthill_mckee
from .newmark_support import (
    LINEAR_SOLVER_VARIABLE,
    choose_linear_solver,
    dense_refined_fits,
    requested_linear_solver,
)

__all__ = [
    "SPARSE_OVERHEAD",
    "KernelStorage",
    "cholmod_available",
    "is_sparse_matrix",
    "kernel_storage",
]

SPARSE_SOLVER = "sparse_cholesky"

SPARSE_OVERHEAD = 1.25
"""Cost of an entry the sparse path reads relative to a band entry [-] (measured: a
spring chain, equal counts, 1.03 to 1.16 times slower sparse)."""


@dataclass
class KernelStorage:
    """The kernel's DOF order and matrices.

    Attributes
    ----------
    linear_solver : str
        ``dense_refined``, ``banded_cholesky``, ``sparse_cholesky`` or ``dense_inverse``.
    reason : str
        Why, in words (recorded in the output attributes).
    order : ndarray
        The kernel's DOF order (the kernel's DOF i is the caller's ``order[i]``).
    bandwidth : int
        Band half-width kd in that order (0 on the sparse path, whose bands are unused).
    bands : dict of ndarray
        ``mass``, ``damping``, ``stiffness`` in LAPACK lower band storage, (kd + 1, n).
    sparse : dict of ndarray
        The kernel's ``sparse_*`` arguments: 0-based lower-triangle CSC pattern and the
        three matrices' values on it (one inert entry on the banded paths).
    """

    linear_solver: str
    reason: str
    order: np.ndarray
    bandwidth: int
    bands: dict
    sparse: dict


def is_sparse_matrix(matrix: object) -> bool:
    """True for a SciPy sparse matrix or array (checked without importing SciPy)."""
    return type(matrix).__module__.startswith("scipy.sparse")


def kernel_storage(
    mass: object,
    damping: object,
    stiffness: object,
    deflection: np.ndarray | None,
    requested: str = "auto",
) -> KernelStorage:
    """Order and store M, C, K0 (dense arrays or SciPy sparse matrices) for the kernel.

    Parameters
    ----------
    mass, damping, stiffness : ndarray or scipy.sparse matrix, shape (n, n)
        M, C and K0.
    deflection : ndarray, shape (n_mesh, n), optional
        The meshes' deflection rows: their couplings join the banded pattern.
    requested : str
        ``auto``, ``dense_refined``, ``banded_cholesky``, ``sparse_cholesky`` or
        ``dense_inverse``; the
        environment variable :data:`~pygear.kernel.newmark_support.LINEAR_SOLVER_VARIABLE`
        overrides it.
    """
    choice, forced = requested_linear_solver(requested)
    n = int(mass.shape[0])
    lower = _lower_pattern(mass, damping, stiffness, deflection)
    if choice == SPARSE_SOLVER:
        source = f"{LINEAR_SOLVER_VARIABLE}={forced}" if forced else "linear_solver"
        if not cholmod_available():
            raise ValueError(
                f"{source} asks for the sparse path, and this build of pygear has no CHOLMOD: "
                "install SuiteSparse (Debian: libsuitesparse-dev) and rebuild, or use "
                "banded_cholesky"
            )
        reason = f"forced by {source} ({n} DOFs, {lower[1].size} stored entries)"
        return _sparse_storage(mass, damping, stiffness, lower, reason)
    if choice == "auto" and dense_refined_fits(n):  # the refined dense path (band storage)
        order, kd = _band_order(n, lower, deflection)
        return _band_storage((mass, damping, stiffness), order, kd, requested)
    if choice == "auto":
        order, kd = _band_order(n, lower, deflection)
        factor_entries = _factor_entries(n, *lower)
        if factor_entries is not None:
            band = n * (kd + 1)
            sparse = SPARSE_OVERHEAD * (factor_entries + lower[1].size)
            shape = (
                f"{n} DOFs, band half-width {kd} ({band} band entries), "
                f"CHOLMOD factor {factor_entries} and pattern {lower[1].size} entries"
            )
            if sparse <= 2 * band:
                reason = (
                    f"automatic: {shape}; a sparse step reads {2 * band / sparse:.2f} times less"
                )
                return _sparse_storage(mass, damping, stiffness, lower, reason)
    else:
        order, kd = _band_order(n, lower, deflection)
    storage = _band_storage((mass, damping, stiffness), order, kd, requested)
    if choice == "auto" and factor_entries is not None:
        storage.reason += f"; the banded step reads less than the sparse one ({shape})"
    return storage


def _band_storage(matrices, order: np.ndarray, kd: int, requested: str) -> KernelStorage:
    """LAPACK lower bands of M, C, K0 (dense or sparse, never densified) in ``order``."""
    n = order.size
    position = np.empty(n, dtype=np.int64)
    position[order] = np.arange(n)
    solver, reason = choose_linear_solver(n, kd, requested)
    bands = {}
    for name, matrix in zip(("mass", "damping", "stiffness"), matrices):
        rows, columns, values = _triplets(matrix)
        i, j = position[rows], position[columns]
        keep = i >= j  # the lower triangle in the kernel's order (the matrix is symmetric)
        band = np.zeros((kd + 1, n), order="F")
        np.add.at(band, (i[keep] - j[keep], j[keep]), values[keep])
        bands[name] = band
    inert = {
        "sparse_column_start": np.zeros(n + 1, dtype=np.int32),
        "sparse_row_index": np.zeros(1, dtype=np.int32),
        "sparse_mass": np.zeros(1),
        "sparse_damping": np.zeros(1),
        "sparse_stiffness": np.zeros(1),
    }
    return KernelStorage(solver, reason, order, kd, bands, inert)


def _triplets(matrix) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows, columns and values of a dense or sparse matrix's non-zero entries."""
    if is_sparse_matrix(matrix):
        coo = matrix.tocoo()
        keep = coo.data != 0
        return coo.row[keep].astype(np.int64), coo.col[keep].astype(np.int64), coo.data[keep]
    dense = np.asarray(matrix, dtype=np.float64)
    rows, columns = np.nonzero(dense)
    return rows, columns, dense[rows, columns]


def _lower_pattern(mass, damping, stiffness, deflection=None) -> tuple[np.ndarray, np.ndarray]:
    """0-based CSC column pointers and rows of the lower triangle (diagonal included) of
    the union of the three matrices' patterns, its transpose and the meshes' couplings
    b_m b_m^T (a refactor adds them)."""
    n = int(mass.shape[0])
    rows, columns = [np.arange(n)], [np.arange(n)]
    for row in () if deflection is None else np.asarray(deflection):
        (dofs,) = np.nonzero(row)
        i, j = np.meshgrid(dofs, dofs, indexing="ij")
        rows += [np.maximum(i, j).ravel()]
        columns += [np.minimum(i, j).ravel()]
    for matrix in (mass, damping, stiffness):
        i, j, _ = _triplets(matrix)
        rows += [np.maximum(i, j)]
        columns += [np.minimum(i, j)]
    keys = np.unique(np.concatenate(columns).astype(np.int64) * n + np.concatenate(rows))
    column, row = np.divmod(keys, n)
    column_start = np.zeros(n + 1, dtype=np.int32)
    np.cumsum(np.bincount(column, minlength=n), out=column_start[1:])
    return column_start, row.astype(np.int32)


def _band_order(n: int, lower, deflection) -> tuple[np.ndarray, int]:
    """RCM order and band half-width of the pattern and the meshes' couplings."""
    column_start, row = lower
    column = np.repeat(np.arange(n), np.diff(column_start))
    if n > 4000:  # NumPy's RCM works on a dense boolean pattern: SciPy's for large models
        import scipy.sparse
        import scipy.sparse.csgraph

        pattern = scipy.sparse.csr_matrix((np.ones(row.size), (row, column)), shape=(n, n))
        pattern = pattern + pattern.T
        if deflection is not None:
            coupled = scipy.sparse.csr_matrix(np.abs(deflection) > 0, dtype=np.float64)
            pattern = pattern + coupled.T @ coupled
        order = np.asarray(scipy.sparse.csgraph.reverse_cuthill_mckee(pattern.tocsr(), True))
        position = np.empty(n, dtype=np.int64)
        position[order] = np.arange(n)
        coo = pattern.tocoo()
        return order, int(np.abs(position[coo.row] - position[coo.col]).max(initial=0))
    pattern = np.zeros((n, n), dtype=bool)
    pattern[row, column] = True
    pattern |= pattern.T
    if deflection is not None:
        nz = np.abs(deflection) > 0
        pattern |= (nz.T.astype(int) @ nz.astype(int)) > 0
    order = reverse_cuthill_mckee(pattern)
    return order, band_half_width(pattern, order)


def cholmod_available() -> bool:
    """Whether the kernel was built with CHOLMOD (the sparse path and its analysis)."""
    flag = getattr(_kernel, "sparse_cholesky_available_flag", None)
    return flag is not None and int(flag()) == 1


def _factor_entries(n: int, column_start: np.ndarray, row: np.ndarray) -> int | None:
    """Entries of CHOLMOD's factor of a matrix with this pattern (its own ordering), from
    a diagonally dominant matrix on the pattern; None without CHOLMOD."""
    if not cholmod_available():
        return None
    column = np.repeat(np.arange(n), np.diff(column_start))
    off = row != column
    degree = np.bincount(row[off], minlength=n) + np.bincount(column[off], minlength=n)
    values = np.where(off, -1.0, degree[column] + 1.0)
    handle, _, ierr = _kernel.sparse_cholesky_create(column_start, row, values, 0, 0)
    if ierr:
        return None
    try:
        entries, _, _, _, ierr = _kernel.sparse_cholesky_stats(handle)
    finally:
        _kernel.sparse_cholesky_free(handle)
    return int(entries) if not ierr else None


def _sparse_storage(mass, damping, stiffness, lower, reason: str) -> KernelStorage:
    """The three matrices' lower triangles on the common pattern, for CHOLMOD."""
    column_start, row = lower
    n = column_start.size - 1
    keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(column_start)) * n + row
    values = {}
    for name, matrix in zip(("mass", "damping", "stiffness"), (mass, damping, stiffness)):
        i, j, data = _triplets(matrix)
        keep = i >= j
        on_pattern = np.zeros(row.size)
        where = np.searchsorted(keys, j[keep].astype(np.int64) * n + i[keep])
        np.add.at(on_pattern, where, data[keep])
        values[name] = on_pattern
    sparse = {
        "sparse_column_start": column_start,
        "sparse_row_index": row,
        "sparse_mass": values["mass"],
        "sparse_damping": values["damping"],
        "sparse_stiffness": values["stiffness"],
    }
    bands = {name: np.zeros((1, n), order="F") for name in ("mass", "damping", "stiffness")}
    return KernelStorage(SPARSE_SOLVER, reason, np.arange(n), 0, bands, sparse)
