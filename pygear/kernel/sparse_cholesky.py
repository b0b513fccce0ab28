"""Sparse Cholesky factorization A = L L' of symmetric positive definite matrices by
SuiteSparse's CHOLMOD, through the Fortran kernel (module ``sparse_cholesky`` over the C
layer ``fortran/cholmod_shim.c``).

CHOLMOD (Chen, Davis, Hager & Rajamanickam, "Algorithm 887: CHOLMOD, supernodal sparse
Cholesky factorization and update/downdate", ACM TOMS 35(3), 2008) chooses a
fill-reducing ordering (AMD, or METIS when AMD fills much), analyses the pattern once and
factors column by column (simplicial) or in dense blocks through the BLAS (supernodal).
:class:`SparseCholesky` analyses and factors once; :meth:`SparseCholesky.refactor` takes
new values on the same pattern, and solves reuse the factor's buffers.

The kernel is built with CHOLMOD when the build finds it (Debian: ``libsuitesparse-dev``);
without it :func:`sparse_cholesky_available` is false and :class:`SparseCholesky` refuses
with a message that says what to install.
"""

from __future__ import annotations

import weakref
from types import TracebackType
from typing import Literal

import numpy as np
import scipy.sparse as sp

from . import _kernel

__all__ = [
    "SparseCholesky",
    "SparseCholeskyError",
    "NotPositiveDefiniteError",
    "SparseCholeskyUnavailableError",
    "sparse_cholesky_available",
]

OrderingName = Literal["auto", "natural", "amd"]
MethodName = Literal["auto", "simplicial", "supernodal"]

_ORDERING_CODES = {"auto": 0, "natural": 1, "amd": 2}
_METHOD_CODES = {"auto": 0, "simplicial": 1, "supernodal": 2}
_ORDERING_NAMES = {
    0: "natural",
    1: "given",
    2: "amd",
    3: "metis",
    4: "nesdis",
    5: "colamd",
    6: "postordered",
}
"""CHOLMOD's codes of the ordering its analysis used (``L->ordering``)."""

# The kernel's error codes (module sparse_cholesky's sp_* parameters).
_UNAVAILABLE, _MEMORY, _DEFINITE, _PATTERN, _ARGUMENT = 1, 2, 3, 4, 5
_FAILED, _UNFACTORED, _HANDLE, _FULL = 6, 7, 8, 9
_REASONS = {
    _MEMORY: "out of memory",
    _PATTERN: "is not a sorted lower triangle in compressed sparse columns",
    _ARGUMENT: "an argument does not fit the factor",
    _FAILED: "CHOLMOD failed",
    _UNFACTORED: "has no valid factor (its last factorization failed)",
    _HANDLE: "the factor was freed",
    _FULL: "too many factors are open at once",
}
_UNAVAILABLE_MESSAGE = (
    "the sparse Cholesky path needs CHOLMOD: pygear's kernel was built without it "
    "(install libsuitesparse-dev, Debian/Ubuntu, and rebuild)"
)

_SYMMETRY_TOLERANCE = 1e-10
"""Largest |A - A'| accepted, relative to max |A|: assembly sums in different orders leave
differences of a few ulps (1e-16 relative) per term; 1e-10 allows thousands of terms and
still catches a matrix that is not symmetric by design."""


class SparseCholeskyError(RuntimeError):
    """The sparse Cholesky kernel reported an error."""


class NotPositiveDefiniteError(SparseCholeskyError, np.linalg.LinAlgError):
    """The matrix is not positive definite; ``column`` is where the factorization failed."""

    def __init__(self, message: str, column: int) -> None:
        super().__init__(message)
        self.column = column


class SparseCholeskyUnavailableError(SparseCholeskyError):
    """The kernel was built without CHOLMOD."""


def sparse_cholesky_available() -> bool:
    """Whether the kernel was built with CHOLMOD.

    Returns
    -------
    bool
        True when :class:`SparseCholesky` can factor.
    """
    flag = getattr(_kernel, "sparse_cholesky_available_flag", None)
    return flag is not None and int(flag()) == 1


def _lower_triangle(matrix: object, name: str) -> sp.csc_matrix:
    """The lower triangle of a square symmetric sparse matrix, canonical CSC (sorted, no
    duplicates), with int32 indices; ValueError naming ``name`` otherwise."""
    if not sp.issparse(matrix):
        raise ValueError(f"{name} must be a scipy.sparse matrix, not {type(matrix).__name__}")
    csc = sp.csc_matrix(matrix, dtype=np.float64)
    rows, columns = csc.shape
    if rows != columns or rows == 0:
        raise ValueError(f"{name} must be square and non-empty (shape {rows} x {columns})")
    if csc.nnz and not np.all(np.isfinite(csc.data)):
        raise ValueError(f"{name} must hold finite values only")
    scale = float(abs(csc).max()) if csc.nnz else 0.0
    asymmetry = float(abs(csc - csc.T).max()) if csc.nnz else 0.0
    if asymmetry > _SYMMETRY_TOLERANCE * scale:
        raise ValueError(
            f"{name} must be symmetric (max |A - A'| = {asymmetry:.3g}, max |A| = {scale:.3g})"
        )
    lower = sp.tril(csc, format="csc")
    lower.sum_duplicates()
    lower.sort_indices()
    return sp.csc_matrix(
        (
            lower.data,
            lower.indices.astype(np.int32, copy=False),
            lower.indptr.astype(np.int32, copy=False),
        ),
        shape=lower.shape,
    )


def _free_factor(handle: int) -> None:
    """Free a kernel factor (finalizer: never raises)."""
    _kernel.sparse_cholesky_free(handle)


class SparseCholesky:
    """A = L L' of a sparse symmetric positive definite matrix, analysed once.

    Parameters
    ----------
    matrix : scipy.sparse matrix
        Square, symmetric, positive definite; only its lower triangle is read after the
        symmetry check.
    ordering : {"auto", "natural", "amd"}
        Fill-reducing ordering: CHOLMOD's choice (AMD, or METIS when AMD fills much), none
        (a banded matrix keeps its band), or approximate minimum degree.
    method : {"auto", "simplicial", "supernodal"}
        CHOLMOD's choice by flops per nonzero of L, column by column, or dense supernodes
        through the BLAS.
    name : str
        What the matrix is, for error messages ("stiffness is not positive definite").

    Raises
    ------
    ValueError
        A matrix that is not square, not symmetric or not finite, or an unknown option.
    NotPositiveDefiniteError
        The factorization met a non-positive pivot (the column, 0-based, is named).
    SparseCholeskyUnavailableError
        The kernel was built without CHOLMOD.
    """

    def __init__(
        self,
        matrix: sp.spmatrix | sp.sparray,
        ordering: OrderingName = "auto",
        method: MethodName = "auto",
        *,
        name: str = "matrix",
    ) -> None:
        if ordering not in _ORDERING_CODES:
            raise ValueError(f"ordering must be one of {sorted(_ORDERING_CODES)}, not {ordering!r}")
        if method not in _METHOD_CODES:
            raise ValueError(f"method must be one of {sorted(_METHOD_CODES)}, not {method!r}")
        self.name = name
        self._handle = 0
        self._finalizer: weakref.finalize | None = None
        if not sparse_cholesky_available():
            raise SparseCholeskyUnavailableError(f"{name}: {_UNAVAILABLE_MESSAGE}")
        lower = _lower_triangle(matrix, name)
        self.n = int(lower.shape[0])
        self._indptr = lower.indptr
        self._indices = lower.indices
        handle, bad, ierr = _kernel.sparse_cholesky_create(
            lower.indptr,
            lower.indices,
            lower.data,
            _ORDERING_CODES[ordering],
            _METHOD_CODES[method],
        )
        self._raise_for(int(ierr), int(bad))
        self._handle = int(handle)
        self._finalizer = weakref.finalize(self, _free_factor, self._handle)
        nnz_factor, ordering_code, supernodal, flops, ierr = _kernel.sparse_cholesky_stats(
            self._handle
        )
        self._raise_for(int(ierr), 0)
        self.nnz_factor = int(nnz_factor)
        """Nonzeros of L, diagonal included."""
        self.ordering = _ORDERING_NAMES.get(int(ordering_code), f"code {int(ordering_code)}")
        """The ordering CHOLMOD used: "natural", "amd", "metis", "nesdis", ..."""
        self.supernodal = bool(supernodal)
        """Whether the factor is supernodal (else simplicial)."""
        self.flops = float(flops)
        """Floating-point operations of one numeric factorization."""

    def _raise_for(self, ierr: int, bad: int) -> None:
        """Turn a kernel error code into the exception that says what went wrong."""
        if ierr == 0:
            return
        if ierr == _DEFINITE:
            column = bad - 1
            raise NotPositiveDefiniteError(
                f"{self.name} is not positive definite (column {column}, 0-based)", column
            )
        if ierr == _UNAVAILABLE:
            raise SparseCholeskyUnavailableError(f"{self.name}: {_UNAVAILABLE_MESSAGE}")
        reason = _REASONS.get(ierr, f"error code {ierr}")
        raise SparseCholeskyError(f"{self.name}: {reason}")

    def _live_handle(self) -> int:
        if self._handle == 0:
            raise SparseCholeskyError(f"{self.name}: the factor is closed")
        return self._handle

    def refactor(self, matrix: sp.spmatrix | sp.sparray) -> None:
        """Factor new values on the same pattern (numeric factorization only).

        Parameters
        ----------
        matrix : scipy.sparse matrix
            Same shape and same lower-triangle pattern as the matrix first factored.

        Raises
        ------
        ValueError
            Another shape or pattern (create a new :class:`SparseCholesky` instead).
        NotPositiveDefiniteError
            The new matrix is not positive definite; solves are refused until a refactor
            succeeds.
        """
        handle = self._live_handle()
        lower = _lower_triangle(matrix, self.name)
        if (
            lower.shape[0] != self.n
            or not np.array_equal(lower.indptr, self._indptr)
            or not np.array_equal(lower.indices, self._indices)
        ):
            raise ValueError(
                f"{self.name} must keep the sparsity pattern of the factored matrix to be "
                "refactored (build a new SparseCholesky for another pattern)"
            )
        bad, ierr = _kernel.sparse_cholesky_refactor(handle, lower.data)
        self._raise_for(int(ierr), int(bad))

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """Solve A x = b.

        Parameters
        ----------
        rhs : ndarray, shape (n,) or (n, k)
            One right-hand side or k of them.

        Returns
        -------
        ndarray
            x, the shape of ``rhs`` (a new array; ``rhs`` is left alone).
        """
        handle = self._live_handle()
        b = np.asarray(rhs)
        if b.ndim not in (1, 2) or b.shape[0] != self.n or b.size == 0:
            raise ValueError(
                f"right-hand side of {self.name} must have shape ({self.n},) or "
                f"({self.n}, k), not {b.shape}"
            )
        columns = np.array(b.reshape(self.n, -1), dtype=np.float64, order="F", copy=True)
        ierr = _kernel.sparse_cholesky_solve(handle, columns)
        self._raise_for(int(ierr), 0)
        return columns.reshape(b.shape) if b.ndim == 1 else columns

    def close(self) -> None:
        """Free the factor now (also done on garbage collection); idempotent."""
        if self._finalizer is not None:
            self._finalizer()
        self._handle = 0

    def __enter__(self) -> SparseCholesky:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "closed" if self._handle == 0 else f"nnz(L)={self.nnz_factor}"
        kind = "supernodal" if self.supernodal else "simplicial"
        return f"SparseCholesky({self.name}, n={self.n}, {self.ordering}, {kind}, {state})"
