"""How the Newmark kernel holds M, C and K0: bands in RCM order, or one sparse pattern.

Gear-stage models (tens to a few hundred DOFs, dense NumPy matrices) go to the kernel as
LAPACK band matrices in reverse Cuthill-McKee order, solved by the banded Cholesky
factor or, on request, by a dense inverse (:func:`~pygear.kernel.newmark_support.
choose_linear_solver`).  Flexible drivetrains (SciPy sparse matrices, up to tens of
thousands of DOFs) go as one lower-triangle pattern in compressed sparse columns shared
by the three matrices, and the kernel factors Khat and M with CHOLMOD, which orders the
DOFs itself (approximate minimum degree or nested dissection): the DOF order here stays
the caller's (``fortran/newmark_sparse.f90``).

The automatic choice for sparse input compares what one solve costs: a banded
triangular solve reads n (kd + 1) entries of the factor for the RCM half-width kd, a
CHOLMOD solve about the entries of its factor, at least the pattern's.  The sparse
path is taken when the band would hold :data:`SPARSE_BAND_RATIO` times the pattern's
entries or more, or when the model has :data:`SPARSE_MIN_DOFS` DOFs or more (the
banded path's n (kd + 1)^2 factorization and 4 n (kd + 1) doubles of storage then
dominate); ``benchmarks/bench_sparse_path.py`` measures where the two cross.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from .band_ordering import band_half_width, reverse_cuthill_mckee
from .newmark_support import LINEAR_SOLVER_CODES, LINEAR_SOLVER_VARIABLE, choose_linear_solver

__all__ = [
    "SPARSE_BAND_RATIO",
    "SPARSE_MIN_DOFS",
    "KernelStorage",
    "is_sparse_matrix",
    "kernel_storage",
]

SPARSE_SOLVER = "sparse_cholesky"

SPARSE_MIN_DOFS = 2000
"""Sparse models of this many DOFs or more go to CHOLMOD whatever their band [DOFs]."""

SPARSE_BAND_RATIO = 4.0
"""Band entries n (kd + 1) per stored lower-triangle entry from which CHOLMOD is chosen [-]."""


@dataclass
class KernelStorage:
    """The kernel's DOF order and matrices.

    Attributes
    ----------
    linear_solver : str
        ``banded_cholesky``, ``dense_inverse`` or ``sparse_cholesky``.
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
        ``auto``, ``banded_cholesky``, ``dense_inverse`` or ``sparse_cholesky``; the
        environment variable :data:`~pygear.kernel.newmark_support.LINEAR_SOLVER_VARIABLE`
        overrides it.
    """
    forced = os.environ.get(LINEAR_SOLVER_VARIABLE, "").strip()
    choice = forced or requested
    sparse_input = any(is_sparse_matrix(x) for x in (mass, damping, stiffness))
    n = int(mass.shape[0])
    if choice == SPARSE_SOLVER or (sparse_input and choice == "auto"):
        import scipy.sparse

        matrices = [
            scipy.sparse.csc_matrix(x, dtype=np.float64) for x in (mass, damping, stiffness)
        ]
        pattern = _pattern(matrices)
        if choice == SPARSE_SOLVER:
            source = f"{LINEAR_SOLVER_VARIABLE}={forced}" if forced else "linear_solver"
            reason = f"forced by {source} ({n} DOFs, {pattern.nnz} stored entries)"
            return _sparse_storage(matrices, pattern, reason)
        import scipy.sparse.csgraph

        symmetric = (pattern + pattern.T).tocsr()
        order = np.asarray(scipy.sparse.csgraph.reverse_cuthill_mckee(symmetric, True))
        permuted = symmetric[order][:, order].tocoo()
        kd = int(np.abs(permuted.row - permuted.col).max(initial=0))
        band_entries = n * (kd + 1)
        shape = f"{n} DOFs, RCM band half-width {kd}, {pattern.nnz} stored entries"
        if n >= SPARSE_MIN_DOFS or band_entries >= SPARSE_BAND_RATIO * pattern.nnz:
            reason = (
                f"automatic: {shape}; the band would hold {band_entries / pattern.nnz:.1f} "
                "times the pattern's entries, so CHOLMOD factors the pattern"
            )
            return _sparse_storage(matrices, pattern, reason)
        mass, damping, stiffness = (x.toarray() for x in matrices)
    elif choice not in (*LINEAR_SOLVER_CODES, "auto"):
        where = f"environment variable {LINEAR_SOLVER_VARIABLE}" if forced else "linear_solver"
        raise ValueError(
            f"{where} must be one of {', '.join((*LINEAR_SOLVER_CODES, 'auto'))} (got {choice!r})"
        )
    elif sparse_input:  # a banded path asked for by name
        mass, damping, stiffness = (
            x.toarray() if is_sparse_matrix(x) else x for x in (mass, damping, stiffness)
        )
    return _band_storage(mass, damping, stiffness, deflection, requested)


def _band_storage(mass, damping, stiffness, deflection, requested: str) -> KernelStorage:
    """Bands of dense M, C, K0 in the RCM order of their pattern and the meshes'."""
    mass, damping, stiffness = (np.asarray(x, dtype=np.float64) for x in (mass, damping, stiffness))
    n = mass.shape[0]
    pattern = (np.abs(mass) + np.abs(damping) + np.abs(stiffness)) > 0
    if deflection is not None:
        nz = np.abs(deflection) > 0
        pattern |= (nz.T.astype(int) @ nz.astype(int)) > 0
    pattern |= np.eye(n, dtype=bool)
    order = reverse_cuthill_mckee(pattern)
    kd = band_half_width(pattern, order)
    solver, reason = choose_linear_solver(n, kd, requested)
    bands = {}
    for name, matrix in (("mass", mass), ("damping", damping), ("stiffness", stiffness)):
        permuted = matrix[np.ix_(order, order)]
        band = np.zeros((kd + 1, n), order="F")
        for d in range(kd + 1):
            band[d, : n - d] = np.diagonal(permuted, -d)
        bands[name] = band
    inert = {
        "sparse_column_start": np.zeros(n + 1, dtype=np.int32),
        "sparse_row_index": np.zeros(1, dtype=np.int32),
        "sparse_mass": np.zeros(1),
        "sparse_damping": np.zeros(1),
        "sparse_stiffness": np.zeros(1),
    }
    return KernelStorage(solver, reason, order, kd, bands, inert)


def _pattern(matrices: list) -> object:
    """The lower triangle (diagonal included) of the union of the matrices' patterns."""
    import scipy.sparse

    n = matrices[0].shape[0]
    union = abs(matrices[0]) + abs(matrices[1]) + abs(matrices[2])
    union = union + abs(union.T) + scipy.sparse.identity(n, format="csc")
    lower = scipy.sparse.tril(union, format="csc")
    lower.sort_indices()
    return lower


def _sparse_storage(matrices: list, pattern, reason: str) -> KernelStorage:
    """The three matrices' lower triangles on the common pattern, for CHOLMOD."""
    import scipy.sparse

    n = pattern.shape[0]
    columns = np.repeat(np.arange(n, dtype=np.int64), np.diff(pattern.indptr))
    keys = columns * n + pattern.indices
    values = {}
    for name, matrix in zip(("mass", "damping", "stiffness"), matrices):
        lower = scipy.sparse.tril(matrix, format="coo")
        on_pattern = np.zeros(pattern.nnz)
        where = np.searchsorted(keys, lower.col.astype(np.int64) * n + lower.row)
        np.add.at(on_pattern, where, lower.data)
        values[name] = on_pattern
    sparse = {
        "sparse_column_start": np.asarray(pattern.indptr, dtype=np.int32),
        "sparse_row_index": np.asarray(pattern.indices, dtype=np.int32),
        "sparse_mass": values["mass"],
        "sparse_damping": values["damping"],
        "sparse_stiffness": values["stiffness"],
    }
    bands = {name: np.zeros((1, n), order="F") for name in ("mass", "damping", "stiffness")}
    return KernelStorage(SPARSE_SOLVER, reason, np.arange(n), 0, bands, sparse)
