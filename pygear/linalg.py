"""The symmetric generalized eigenproblem K x = lambda M x, in NumPy alone.

Assembly counts a gearbox's rigid-body modes with it, modal analysis takes its
frequencies and shapes from it, and the kernel's rigid-body rebasing its rigid modes: a
base module, so that the kernel needs nothing from assembly.  It reduces the problem
the way LAPACK's ``dsygv`` does (Golub & Van Loan, *Matrix Computations*, 4th ed.,
§8.7.2): with the Cholesky factor M = L L^T, the standard problem (L^-1 K L^-T) y =
lambda y has the same eigenvalues, and x = L^-T y are the eigenvectors, orthonormal in M
(x^T M x = I).
Written with ``numpy.linalg`` so that a modal analysis does not load ``scipy.linalg``
(0.2 s and 25 MB of imports for matrices of at most a few hundred rows).
"""

from __future__ import annotations

import numpy as np

__all__ = ["generalized_eigh"]


def generalized_eigh(
    stiffness: np.ndarray, mass: np.ndarray, *, eigenvalues_only: bool = False
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (ascending) and M-orthonormal eigenvectors of K x = lambda M x.

    Parameters
    ----------
    stiffness : (n, n) array
        Symmetric K [N/m, N m/rad].
    mass : (n, n) array
        Symmetric positive definite M [kg, kg m^2].
    eigenvalues_only : bool
        Return the eigenvalues alone.

    Returns
    -------
    eigenvalues : (n,) array
        lambda = omega^2 [rad^2/s^2], ascending.
    vectors : (n, n) array
        Column m is the mode of ``eigenvalues[m]``, with x^T M x = 1 (not returned
        with ``eigenvalues_only``).

    Raises
    ------
    numpy.linalg.LinAlgError
        M is not positive definite (as ``scipy.linalg.eigh`` raises).
    """
    factor = np.linalg.cholesky(mass)
    left = np.linalg.solve(factor, stiffness)  # L^-1 K
    reduced = np.linalg.solve(factor, left.T)  # L^-1 K^T L^-T = L^-1 K L^-T, K symmetric
    reduced = 0.5 * (reduced + reduced.T)  # symmetric to the round-off of the two solves
    if eigenvalues_only:
        return np.linalg.eigvalsh(reduced)
    eigenvalues, vectors = np.linalg.eigh(reduced)
    return eigenvalues, np.linalg.solve(factor.T, vectors)
