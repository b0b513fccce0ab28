"""The sparse Cholesky factorization through CHOLMOD (pygear.kernel.sparse_cholesky).

Accuracy bounds come from the backward stability of Cholesky's method (Higham, *Accuracy
and Stability of Numerical Algorithms*, 2nd ed., SIAM 2002, Theorem 10.4 and eq. 10.8
onwards): the computed x solves (A + dA) x = b with |dA| <= gamma_{k+1} |L| |L'|, k the
longest row of L, and || |L| |L'| ||_2 <= n ||A||_2 for a positive definite A.  Hence the
normwise backward error ||b - A x|| / (||A|| ||x||) is below n gamma_{k+1} whatever the
condition number, and the forward error ||x - x_true|| / ||x_true|| below kappa(A) times
that (Higham, Theorem 7.2).  Both use k <= n and gamma_m = m u / (1 - m u).
"""

from __future__ import annotations

import gc

import numpy as np
import pytest
import scipy.sparse as sp

from pygear.kernel import _kernel
from pygear.kernel import sparse_cholesky as module
from pygear.kernel.sparse_cholesky import (
    NotPositiveDefiniteError,
    SparseCholesky,
    SparseCholeskyError,
    SparseCholeskyUnavailableError,
    sparse_cholesky_available,
)

pytestmark = pytest.mark.skipif(
    not sparse_cholesky_available(), reason="kernel built without CHOLMOD"
)

UNIT_ROUNDOFF = np.finfo(float).eps / 2
METHODS = ("simplicial", "supernodal", "auto")
ORDERINGS = ("auto", "natural", "amd")


def backward_error_bound(n: int) -> float:
    """n gamma_{n+1}: the normwise backward error Cholesky can leave (module docstring)."""
    m = n + 1
    return n * m * UNIT_ROUNDOFF / (1 - m * UNIT_ROUNDOFF)


def random_spd(n: int, seed: int) -> sp.csc_matrix:
    """A sparse random symmetric positive definite matrix: B B' + shift I, its smallest
    eigenvalue at least the shift (B B' is semidefinite)."""
    rng = np.random.default_rng(seed)
    factor = sp.random(n, n, density=3.0 / n, random_state=rng, format="csc")
    return (factor @ factor.T + 0.05 * sp.identity(n)).tocsc()


def laplacian_chain(n: int) -> sp.csc_matrix:
    """tridiag(-1, 2, -1) of order n: a fixed-fixed spring chain."""
    off = -np.ones(n - 1)
    return sp.diags([off, 2 * np.ones(n), off], [-1, 0, 1], format="csc")


def backward_error(matrix: sp.spmatrix, x: np.ndarray, b: np.ndarray) -> float:
    """||b - A x||_2 / (||A||_2 ||x||_2), ||A||_2 exactly from the dense matrix."""
    norm_a = np.linalg.norm(matrix.toarray(), 2)
    return float(np.linalg.norm(b - matrix @ x) / (norm_a * np.linalg.norm(x)))


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("ordering", ORDERINGS)
@pytest.mark.parametrize("seed", [1, 2])
def test_random_spd_solve_is_backward_stable(method: str, ordering: str, seed: int) -> None:
    n = 300
    matrix = random_spd(n, seed)
    rng = np.random.default_rng(100 + seed)
    x_true = rng.standard_normal(n)
    b = matrix @ x_true
    with SparseCholesky(matrix, ordering=ordering, method=method) as factor:
        x = factor.solve(b)
        assert factor.supernodal == (method == "supernodal") or method == "auto"
    eta = backward_error(matrix, x, b)
    assert eta < backward_error_bound(n)
    # the measured backward error is a few u in practice: n gamma_{n+1} is the worst case
    assert eta < 1e-14
    kappa = np.linalg.cond(matrix.toarray())
    assert np.linalg.norm(x - x_true) / np.linalg.norm(x_true) < kappa * backward_error_bound(n)


def test_laplacian_chain_against_its_closed_form() -> None:
    # A x = 1 for tridiag(-1, 2, -1) has x_i = (i + 1)(n - i) / 2 (0-based; a string under
    # uniform load); kappa = cot^2(pi / (2 (n + 1))) from the eigenvalues 2 - 2 cos(j pi/(n+1))
    n = 2000
    matrix = laplacian_chain(n)
    index = np.arange(n)
    exact = (index + 1) * (n - index) / 2.0
    kappa = 1.0 / np.tan(np.pi / (2 * (n + 1))) ** 2
    for method in ("simplicial", "supernodal"):
        with SparseCholesky(matrix, method=method) as factor:
            x = factor.solve(np.ones(n))
            assert factor.nnz_factor == 2 * n - 1  # a tridiagonal matrix fills nothing
        forward = np.linalg.norm(x - exact) / np.linalg.norm(exact)
        assert forward < kappa * backward_error_bound(n)
        # measured ~1e-12 with kappa ~ 1.6e6: well inside kappa * a few u
        assert forward < kappa * 1e3 * UNIT_ROUNDOFF


def test_natural_ordering_is_kept_and_amd_is_reported() -> None:
    matrix = random_spd(200, 3)
    with SparseCholesky(matrix, ordering="natural") as factor:
        assert factor.ordering == "natural"
    with SparseCholesky(matrix, ordering="amd") as factor:
        assert factor.ordering == "amd"
        amd_fill = factor.nnz_factor
    dense_fill = 200 * 201 // 2
    assert amd_fill < dense_fill  # a fill-reducing ordering leaves L sparse


def test_refactor_with_new_values() -> None:
    n = 300
    matrix = random_spd(n, 4)
    rng = np.random.default_rng(5)
    # same pattern, other values: scale the off-diagonal part, raise the diagonal
    updated = (0.5 * matrix + sp.diags(rng.uniform(1.0, 2.0, n))).tocsc()
    b = rng.standard_normal(n)
    with SparseCholesky(matrix, name="stiffness") as factor:
        factor.refactor(updated)
        x = factor.solve(b)
    assert backward_error(updated, x, b) < backward_error_bound(n)
    reference = np.linalg.solve(updated.toarray(), b)
    kappa = np.linalg.cond(updated.toarray())
    assert np.linalg.norm(x - reference) / np.linalg.norm(reference) < 2 * kappa * (
        backward_error_bound(n)
    )


@pytest.mark.parametrize("method", ("simplicial", "supernodal"))
def test_multiple_right_hand_sides(method: str) -> None:
    n = 300
    matrix = random_spd(n, 6)
    rng = np.random.default_rng(7)
    rhs = rng.standard_normal((n, 7))  # 7: not a multiple of the 4-column simplicial blocks
    with SparseCholesky(matrix, method=method) as factor:
        solutions = factor.solve(rhs)
        one_by_one = np.column_stack([factor.solve(rhs[:, j]) for j in range(7)])
        again = factor.solve(rhs[:, :3])  # another width reuses the factor
    assert solutions.shape == (n, 7)
    for j in range(7):
        assert backward_error(matrix, solutions[:, j], rhs[:, j]) < backward_error_bound(n)
    # a column solved alone or in a block takes the same operations in the same order
    # up to the blocking of the triangular solves: equal to a few u relative
    scale = np.abs(solutions).max()
    assert np.abs(solutions - one_by_one).max() < 1e3 * UNIT_ROUNDOFF * scale
    assert np.abs(again - solutions[:, :3]).max() < 1e3 * UNIT_ROUNDOFF * scale
    assert np.all(rhs == np.random.default_rng(7).standard_normal((n, 7)))  # input untouched


@pytest.mark.parametrize("method", METHODS)
def test_not_positive_definite_names_the_column(method: str) -> None:
    # diagonally dominant except column 17: every principal submatrix without 17 is
    # positive definite, and the pivot of 17 is at most a_17,17 < 0 in any ordering
    n = 50
    matrix = laplacian_chain(n).tolil()
    matrix.setdiag(3.0)
    matrix[17, 17] = -1.0
    with pytest.raises(
        NotPositiveDefiniteError, match=r"^stiffness is not positive definite \(column 17"
    ):
        SparseCholesky(matrix.tocsc(), method=method, name="stiffness")
    healthy = laplacian_chain(n)
    factor = SparseCholesky(healthy, method=method, name="stiffness")
    with pytest.raises(NotPositiveDefiniteError) as caught:
        factor.refactor(matrix.tocsc())
    assert caught.value.column == 17
    with pytest.raises(SparseCholeskyError, match="no valid factor"):
        factor.solve(np.ones(n))  # the failed factor is not used
    factor.refactor(healthy)
    assert np.allclose(healthy @ factor.solve(np.ones(n)), 1.0, rtol=0, atol=1e-12)
    factor.close()


def test_bad_matrices_are_refused() -> None:
    with pytest.raises(ValueError, match="stiffness must be square"):
        SparseCholesky(sp.random(4, 5, density=0.5, random_state=1), name="stiffness")
    asymmetric = laplacian_chain(10).tolil()
    asymmetric[0, 3] = 0.5
    with pytest.raises(ValueError, match="mass must be symmetric"):
        SparseCholesky(asymmetric.tocsc(), name="mass")
    with pytest.raises(ValueError, match="scipy.sparse"):
        SparseCholesky(np.eye(3))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="ordering must be one of"):
        SparseCholesky(laplacian_chain(3), ordering="metis")  # type: ignore[arg-type]


def test_refactor_refuses_another_pattern() -> None:
    matrix = laplacian_chain(20)
    wider = (matrix + 0.1 * sp.eye(20, k=2) + 0.1 * sp.eye(20, k=-2)).tocsc()
    with SparseCholesky(matrix, name="stiffness") as factor:
        with pytest.raises(ValueError, match="stiffness must keep the sparsity pattern"):
            factor.refactor(wider)
        with pytest.raises(ValueError, match="shape"):
            factor.solve(np.ones(21))


def test_handles_are_freed_and_stale_handles_refused() -> None:
    factor = SparseCholesky(laplacian_chain(10))
    handle = factor._handle
    factor.close()
    factor.close()  # idempotent
    ierr = _kernel.sparse_cholesky_solve(handle, np.ones((10, 1), order="F"))
    assert ierr == module._HANDLE
    with pytest.raises(SparseCholeskyError, match="closed"):
        factor.solve(np.ones(10))
    # garbage collection frees a factor nobody closed
    forgotten = SparseCholesky(laplacian_chain(10))
    handle = forgotten._handle
    del forgotten
    gc.collect()
    *_, ierr = _kernel.sparse_cholesky_stats(handle)
    assert ierr == module._HANDLE


def test_unavailable_kernel_says_what_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(module, "sparse_cholesky_available", lambda: False)
    with pytest.raises(SparseCholeskyUnavailableError, match="libsuitesparse-dev"):
        SparseCholesky(laplacian_chain(3), name="stiffness")
