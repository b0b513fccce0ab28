"""Lowest natural frequencies and mode shapes of large sparse models (flexible
drivetrains of thousands of DOFs) by shift-invert Lanczos.

The generalized problem K phi = omega^2 M phi is turned into the standard one
(K - sigma M)^-1 M phi = phi / (omega^2 - sigma), whose largest eigenvalues belong to the
omega^2 nearest sigma (Ericsson & Ruhe, "The spectral transformation Lanczos method for
the numerical solution of large sparse generalized symmetric eigenvalue problems",
Math. Comp. 35(152), 1980; Grimes, Lewis & Simon, SIAM J. Matrix Anal. Appl. 15(1),
1994).  ARPACK's implicitly restarted Lanczos (scipy.sparse.linalg.eigsh, Lehoucq,
Sorensen & Yang, *ARPACK Users' Guide*, SIAM 1998, section 3.2) runs on it, each step a
solve with one factorization of K - sigma M: a CHOLMOD Cholesky factor
(:class:`pygear.kernel.sparse_cholesky.SparseCholesky`), or SciPy's SuperLU when the
kernel was built without CHOLMOD.

A free structure (a drivetrain not tied to ground in rotation) has a singular K and
zero-frequency rigid-body modes.  The shift is therefore negative, sigma =
-(2 pi shift_hz)^2: K - sigma M = K + |sigma| M is then positive definite for any
positive semidefinite K and positive definite M, and the rigid modes are found at 0 Hz
like the others.

**Where the shift goes.**  Lanczos converges on the transformed eigenvalues
theta = 1 / (omega^2 + |sigma|) at a rate set by their relative gaps.  While |sigma| stays
below the lowest wanted omega^2 those gaps are the gaps of 1 / omega^2 (wide: 8 modes take
about 30 solves); once |sigma| is far above them every wanted theta is about 1 / |sigma|
and the gaps shrink as (omega_j^2 - omega_i^2) / |sigma|.  The shift is therefore taken
as small as the factorization allows: |sigma| = SHIFT_FRACTION^2 median(K_ii / M_ii),
about 5e3 unit roundoffs of the stiffness scale, which keeps the pivots of the rigid
directions (|sigma| times a mass) above the Cholesky rounding of K (u times a stiffness
entry).  A diagonal ratio grows as 1 / h^2 when the shafts are meshed finer (h the element
length) while the lowest modes stay put, so a shift proportional to it must be a tiny
fraction: the earlier 1e-4 of the reference frequency put the shift at 116 Hz for a
24 000-DOF drivetrain whose modes of interest lie at 1.7 Hz (350-460 solves for 8 modes,
30-70 s on a loaded machine) and at 580 Hz for 120 000 DOFs (over 1 200 solves, no
convergence in 100 restarts); now 28 and 40 (benchmarks/bench_sparse_modal.py).  Should CHOLMOD
meet a non-positive pivot at the default shift, |sigma| grows a hundredfold and the
factorization is retried.

**Threads.**  ARPACK's own work per step is level-2 BLAS on an n x ncv panel (ncv about
2k); threads gain nothing there and, on a machine whose cores are busy, OpenBLAS threads
waiting for each other made each step about 50 times slower than one thread (10 ms
against 0.2 ms at 24 000 DOFs).  The Lanczos iteration runs with one BLAS thread.
"""

from __future__ import annotations

import contextlib
import functools
import logging
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Literal

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ...kernel.sparse_cholesky import (
    NotPositiveDefiniteError,
    SparseCholesky,
    sparse_cholesky_available,
)

__all__ = ["SparseModes", "sparse_modes"]

_log = logging.getLogger(__name__)

DENSE_LIMIT = 200
"""Models of at most this many DOFs (or requests for nearly all their modes) are solved
densely by scipy.linalg.eigh: Lanczos needs k < n - 1 and gains nothing there."""

SHIFT_FRACTION = 1e-6
"""Default shift_hz as a fraction of the model's reference frequency sqrt(median(K_ii /
M_ii)) / 2 pi, so |sigma| = 1e-12 median(K_ii / M_ii), about 4.5e3 u: far enough above
the rounding of the rigid directions' pivots that CHOLMOD factors a free structure (a
free spring chain breaks down near 1e-18, i.e. 5e-3 u), and below the lowest elastic
omega^2 of models up to f_1 / f_ref = 1e-6 (the NREL drivetrain meshed to 24 000 DOFs:
2e-6; to 120 000: 4e-7, where |sigma| is 11 omega_1^2 and 8 modes still take 41 solves).
The former 1e-4 left the shift far above the lowest modes of finely meshed models
(module docstring)."""

SHIFT_RETRIES = 2
"""Times the default shift grows (shift_hz by 10, |sigma| by 100) while CHOLMOD meets a
non-positive pivot; the last try is the former SHIFT_FRACTION, 1e-4."""

FIRST_REQUEST = 12
"""Modes asked for first when only ``below_hz`` is given; doubled until enough."""


@dataclass(frozen=True)
class SparseModes:
    """Natural frequencies and mass-normalised mode shapes, lowest first.

    Unpacks as ``frequencies_hz, shapes = sparse_modes(...)``.

    Attributes
    ----------
    frequencies_hz : ndarray, shape (k,)
        Natural frequencies [Hz], ascending; rigid-body modes at 0.
    shapes : ndarray, shape (n, k)
        Mode shapes, M-orthonormal (Phi' M Phi = I).
    solver : str
        How K - sigma M was factored: "cholmod", "splu (CHOLMOD not available ...)"
        or "dense".
    shift_hz : float
        The shift used, sigma = -(2 pi shift_hz)^2 [Hz].
    solves : int
        Applications of (K - sigma M)^-1 by the Lanczos iterations (every request of a
        ``below_hz`` search summed); 0 for the dense solver.  ARPACK's cost is this count
        times a solve plus its own orthogonalization per step.
    """

    frequencies_hz: np.ndarray
    shapes: np.ndarray
    solver: str
    shift_hz: float
    solves: int = 0

    def __iter__(self) -> Iterator[np.ndarray]:
        yield self.frequencies_hz
        yield self.shapes


def _checked_pair(
    stiffness: sp.spmatrix | sp.sparray, mass: sp.spmatrix | sp.sparray
) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    """K and M as CSC, square and of one size; ValueError naming the one at fault."""
    matrices = []
    for name, matrix in (("stiffness", stiffness), ("mass", mass)):
        if not sp.issparse(matrix):
            raise ValueError(f"{name} must be a scipy.sparse matrix, not {type(matrix).__name__}")
        rows, columns = matrix.shape
        if rows != columns or rows < 2:
            raise ValueError(
                f"{name} must be square with at least 2 rows (shape {rows} x {columns})"
            )
        matrices.append(sp.csc_matrix(matrix, dtype=np.float64))
    if matrices[0].shape != matrices[1].shape:
        raise ValueError(
            f"mass must have the shape of stiffness ({matrices[1].shape} vs {matrices[0].shape})"
        )
    return matrices[0], matrices[1]


def _default_shift_hz(stiffness: sp.csc_matrix, mass: sp.csc_matrix) -> float:
    """SHIFT_FRACTION of the reference frequency sqrt(median(K_ii / M_ii)) / 2 pi."""
    k_diagonal = stiffness.diagonal()
    m_diagonal = mass.diagonal()
    usable = (m_diagonal > 0) & (k_diagonal > 0)
    if not np.any(usable):
        raise ValueError("stiffness and mass must have a positive diagonal entry in a common DOF")
    reference = np.sqrt(np.median(k_diagonal[usable] / m_diagonal[usable])) / (2 * np.pi)
    return SHIFT_FRACTION * float(reference)


class _CountingInverse(spla.LinearOperator):
    """(K - sigma M)^-1 as ARPACK's OPinv, counting the right-hand sides it solves."""

    def __init__(self, solve: Callable[[np.ndarray], np.ndarray], n: int) -> None:
        super().__init__(np.dtype(np.float64), (n, n))
        self._solve = solve
        self.solves = 0

    def _matvec(self, x: np.ndarray) -> np.ndarray:
        self.solves += 1
        return self._solve(x)

    def _matmat(self, x: np.ndarray) -> np.ndarray:
        self.solves += x.shape[1]
        return self._solve(x)


def _shifted_inverse(
    shifted: sp.csc_matrix, factorization: str
) -> tuple[_CountingInverse, str, SparseCholesky | None]:
    """A counting LinearOperator applying (K - sigma M)^-1, the factorization's name, and
    the CHOLMOD factor to close (None with SuperLU).  NotPositiveDefiniteError when
    CHOLMOD meets a non-positive pivot."""
    n = shifted.shape[0]
    if factorization == "splu":
        return _CountingInverse(spla.splu(shifted).solve, n), "splu", None
    if sparse_cholesky_available():
        factor = SparseCholesky(shifted, name="stiffness - shift * mass")
        return _CountingInverse(factor.solve, n), "cholmod", factor
    _log.info("CHOLMOD not available: factoring K - sigma M with scipy's splu")
    return (
        _CountingInverse(spla.splu(shifted).solve, n),
        "splu (CHOLMOD not available: install libsuitesparse-dev)",
        None,
    )


@functools.cache
def _blas_controller() -> object | None:
    """threadpoolctl's view of the loaded BLAS libraries, found once (a search of the
    loaded libraries takes milliseconds, a small model's whole Lanczos)."""
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:  # pragma: no cover - a dependency
        return None
    return ThreadpoolController()


def _one_blas_thread() -> contextlib.AbstractContextManager:
    """One BLAS thread for ARPACK's steps (module docstring, Threads)."""
    controller = _blas_controller()
    if controller is None:  # pragma: no cover - a dependency
        return contextlib.nullcontext()
    return controller.limit(limits=1, user_api="blas")


def _dense_modes(stiffness: sp.csc_matrix, mass: sp.csc_matrix) -> tuple[np.ndarray, np.ndarray]:
    """Every eigenpair, ascending, by the dense symmetric-definite solver."""
    eigenvalues, shapes = scipy.linalg.eigh(stiffness.toarray(), mass.toarray())
    return eigenvalues, shapes


def sparse_modes(
    stiffness: sp.spmatrix | sp.sparray,
    mass: sp.spmatrix | sp.sparray,
    *,
    modes: int | None = None,
    below_hz: float | None = None,
    shift_hz: float | None = None,
    factorization: Literal["auto", "splu"] = "auto",
) -> SparseModes:
    """The lowest natural frequencies and mode shapes of K phi = omega^2 M phi.

    Parameters
    ----------
    stiffness : scipy.sparse matrix, shape (n, n)
        K, symmetric positive semidefinite [N/m, N m/rad].
    mass : scipy.sparse matrix, shape (n, n)
        M, symmetric positive definite [kg, kg m^2].
    modes : int, optional
        How many of the lowest modes to return; with ``below_hz``, how many to ask for
        first.
    below_hz : float, optional
        Return exactly the modes below this frequency [Hz]: the request grows (doubling)
        until the highest mode found lies above it.
    shift_hz : float, optional
        Shift sigma = -(2 pi shift_hz)^2 [Hz], > 0, used as given.  Default:
        SHIFT_FRACTION of sqrt(median(K_ii / M_ii)) / 2 pi, grown tenfold (at most
        SHIFT_RETRIES times) while CHOLMOD meets a non-positive pivot.
    factorization : {"auto", "splu"}
        How K - sigma M is factored: CHOLMOD when the kernel has it (else SuperLU), or
        SuperLU (scipy.sparse.linalg.splu) in any case, for comparisons.

    Returns
    -------
    SparseModes
        Frequencies [Hz] and M-orthonormal shapes, lowest first, and the solver used;
        unpacks as ``frequencies_hz, shapes``.

    Raises
    ------
    ValueError
        Matrices that are not square or not of one size, neither ``modes`` nor
        ``below_hz`` given, a non-positive count, limit or shift, or an unknown
        factorization.
    NotPositiveDefiniteError
        K - sigma M is not positive definite at a given shift, or at the last default
        one (K not positive semidefinite, or M not positive definite).
    """
    if factorization not in ("auto", "splu"):
        raise ValueError(f"factorization must be 'auto' or 'splu', not {factorization!r}")
    k_matrix, m_matrix = _checked_pair(stiffness, mass)
    n = k_matrix.shape[0]
    if modes is None and below_hz is None:
        raise ValueError("sparse_modes needs modes (a count) or below_hz (a frequency limit)")
    if modes is not None and not 1 <= modes <= n:
        raise ValueError(f"modes must be between 1 and the {n} DOFs, not {modes}")
    if below_hz is not None and not (np.isfinite(below_hz) and below_hz > 0):
        raise ValueError(f"below_hz must be a positive frequency, not {below_hz}")
    default_shift = shift_hz is None
    if shift_hz is None:
        shift_hz = _default_shift_hz(k_matrix, m_matrix)
    elif not (np.isfinite(shift_hz) and shift_hz > 0):
        raise ValueError(
            f"shift_hz must be positive (the shift is -(2 pi shift_hz)^2), not {shift_hz}"
        )
    request = modes if modes is not None else min(FIRST_REQUEST, n)
    solves = 0

    if n <= DENSE_LIMIT:
        eigenvalues, shapes = _dense_modes(k_matrix, m_matrix)
        solver = "dense"
    else:
        for attempt in range(SHIFT_RETRIES + 1):
            sigma = -((2 * np.pi * shift_hz) ** 2)
            try:
                operator, solver, factor = _shifted_inverse(
                    (k_matrix - sigma * m_matrix).tocsc(), factorization
                )
                break
            except NotPositiveDefiniteError:
                if not default_shift or attempt == SHIFT_RETRIES:
                    raise
                _log.info(
                    "K - sigma M not positive definite at shift %.3g Hz: retrying at %.3g Hz",
                    shift_hz,
                    10 * shift_hz,
                )
                shift_hz *= 10  # |sigma| x 100
        start = np.random.default_rng(0).standard_normal(n)  # reproducible Lanczos start
        try:
            with _one_blas_thread():
                while True:
                    if request >= n - 1:
                        eigenvalues, shapes = _dense_modes(k_matrix, m_matrix)
                        solver = "dense"
                        break
                    eigenvalues, shapes = spla.eigsh(
                        k_matrix,
                        k=request,
                        M=m_matrix,
                        sigma=sigma,
                        which="LM",
                        OPinv=operator,
                        v0=start,
                    )
                    order = np.argsort(eigenvalues)
                    eigenvalues, shapes = eigenvalues[order], shapes[:, order]
                    highest_hz = np.sqrt(max(eigenvalues[-1], 0.0)) / (2 * np.pi)
                    if below_hz is None or highest_hz > below_hz:
                        break
                    request = min(2 * request, n - 1)
        finally:
            solves = operator.solves
            if factor is not None:
                factor.close()
        _log.debug(
            "shift-invert Lanczos: %d DOFs, %d modes, shift %.3g Hz, %d solves (%s)",
            n,
            request,
            shift_hz,
            solves,
            solver,
        )

    frequencies = np.sqrt(np.clip(eigenvalues, 0.0, None)) / (2 * np.pi)
    if below_hz is not None:
        keep = frequencies < below_hz
    else:
        keep = np.arange(frequencies.size) < request
    return SparseModes(
        frequencies_hz=frequencies[keep],
        shapes=np.ascontiguousarray(shapes[:, keep]),
        solver=solver,
        shift_hz=float(shift_hz),
        solves=solves,
    )
