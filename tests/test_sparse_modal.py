"""Shift-invert Lanczos modes of large sparse models (pygear.analysis.modes.sparse_modal),
against closed forms of spring-mass chains and the dense symmetric-definite solver.

Spring-mass chains of N equal masses m and springs k, K = k T with T tridiagonal
(-1, 2, -1) and one or both end rows changed; derived independently of the code:
- fixed-free (T_NN = 1): x_i = sin(i theta) satisfies every row of T x = lambda x with
  lambda = 2 - 2 cos theta, the last one when sin((N+1) theta) = sin(N theta), i.e.
  theta_j = (2j - 1) pi / (2N + 1); so omega_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2N + 1)));
- free-free (T_11 = T_NN = 1): x_i = cos((i - 1/2) theta) with theta_j = (j - 1) pi / N,
  so omega_j = 2 sqrt(k/m) sin((j - 1) pi / (2N)), a rigid mode (j = 1) at 0.

Tolerances: the factorization of K - sigma M solves a system perturbed by at most
n gamma_{n+1} ||K - sigma M|| (Higham, *Accuracy and Stability of Numerical Algorithms*,
2002, Theorem 10.4), which by Weyl's theorem moves each omega^2 by at most that over m;
ARPACK with tol = 0 converges the Ritz values to machine precision.  So
|d omega / omega| <= n gamma_{n+1} ||K|| / (2 m omega^2), largest for the lowest mode.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp

from pygear.analysis.modes import sparse_modal
from pygear.analysis.modes.sparse_modal import sparse_modes

UNIT_ROUNDOFF = np.finfo(float).eps / 2
STIFFNESS = 4.0e8  # k [N/m]: a gear-mesh order of magnitude
MASS = 2.5  # m [kg]


def factor_error(n: int) -> float:
    """n gamma_{n+1}, the relative backward error of the Cholesky solves."""
    return n * (n + 1) * UNIT_ROUNDOFF / (1 - (n + 1) * UNIT_ROUNDOFF)


def chain(n: int, *, fixed: bool) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    """K and M of N masses in a line, each spring k; the first mass tied to ground when
    ``fixed``, the last one free."""
    diagonal = np.full(n, 2 * STIFFNESS)
    diagonal[-1] = STIFFNESS
    if not fixed:
        diagonal[0] = STIFFNESS
    off = np.full(n - 1, -STIFFNESS)
    stiffness = sp.diags([off, diagonal, off], [-1, 0, 1], format="csc")
    return stiffness, sp.identity(n, format="csc") * MASS


def fixed_free_hz(n: int, count: int) -> np.ndarray:
    j = np.arange(1, count + 1)
    omega = 2 * np.sqrt(STIFFNESS / MASS) * np.sin((2 * j - 1) * np.pi / (2 * (2 * n + 1)))
    return omega / (2 * np.pi)


def free_free_hz(n: int, count: int) -> np.ndarray:
    j = np.arange(1, count + 1)
    return 2 * np.sqrt(STIFFNESS / MASS) * np.sin((j - 1) * np.pi / (2 * n)) / (2 * np.pi)


def frequency_tolerance(n: int, frequencies_hz: np.ndarray) -> np.ndarray:
    """|d f / f| allowed per mode (module docstring): n gamma_{n+1} ||K|| / (2 m omega^2)."""
    omega_squared = (2 * np.pi * frequencies_hz) ** 2
    return factor_error(n) * 4 * STIFFNESS / (2 * MASS * omega_squared)


def test_fixed_free_chain_of_2000_against_the_closed_form() -> None:
    n = 2000
    stiffness, mass = chain(n, fixed=True)
    result = sparse_modes(stiffness, mass, modes=30)
    frequencies, shapes = result
    exact = fixed_free_hz(n, 30)
    assert result.solver == "cholmod"
    assert frequencies.shape == (30,) and shapes.shape == (n, 30)
    relative = np.abs(frequencies - exact) / exact
    assert np.all(relative < frequency_tolerance(n, exact))
    # measured: below 1e-12 for every mode, far inside the worst case above
    assert relative.max() < 1e-9
    # mass-normalised: Phi' M Phi = I to round-off of n-term sums (n u)
    assert np.abs(shapes.T @ (mass @ shapes) - np.eye(30)).max() < n * UNIT_ROUNDOFF * 10


def test_random_model_against_the_dense_solver() -> None:
    n = 300
    rng = np.random.default_rng(11)
    coupling = sp.random(n, n, density=4.0 / n, random_state=rng, format="csc")
    stiffness = (1e6 * (coupling @ coupling.T) + 1e3 * sp.identity(n)).tocsc()
    mass_coupling = sp.random(n, n, density=1.0 / n, random_state=rng, format="csc")
    mass = (0.01 * (mass_coupling @ mass_coupling.T) + sp.diags(rng.uniform(0.5, 2.0, n))).tocsc()
    result = sparse_modes(stiffness, mass, modes=20)
    assert result.solver == "cholmod"  # 300 DOFs: above the dense limit, Lanczos ran
    eigenvalues = scipy.linalg.eigh(stiffness.toarray(), mass.toarray(), eigvals_only=True)
    reference_hz = np.sqrt(eigenvalues[:20]) / (2 * np.pi)
    # both solvers are backward stable: omega^2 moves by at most c u lambda_max, so
    # |d f / f| <= c u lambda_max / (2 lambda_j), c = n gamma_{n+1} / u
    allowed = factor_error(n) * eigenvalues[-1] / (2 * eigenvalues[:20])
    assert np.all(np.abs(result.frequencies_hz - reference_hz) / reference_hz < allowed)
    # each shape solves K phi = omega^2 M phi: residual against ||K|| ||phi||
    for f, phi in zip(result.frequencies_hz, result.shapes.T, strict=True):
        residual = stiffness @ phi - (2 * np.pi * f) ** 2 * (mass @ phi)
        assert np.linalg.norm(residual) < factor_error(n) * eigenvalues[-1] * np.linalg.norm(phi)


def test_below_hz_returns_exactly_the_modes_below() -> None:
    n = 2000
    stiffness, mass = chain(n, fixed=True)
    exact = fixed_free_hz(n, 60)
    limit = 0.5 * (exact[39] + exact[40])  # 40 modes below: more than the first request
    frequencies, shapes = sparse_modes(stiffness, mass, below_hz=limit)
    assert frequencies.size == 40 and shapes.shape == (n, 40)
    assert np.all(frequencies < limit)
    assert np.all(
        np.abs(frequencies - exact[:40]) / exact[:40] < frequency_tolerance(n, exact[:40])
    )


def test_free_chain_has_its_rigid_mode_at_zero() -> None:
    n = 1000
    stiffness, mass = chain(n, fixed=False)
    frequencies, shapes = sparse_modes(stiffness, mass, modes=6)
    exact = free_free_hz(n, 6)
    # the rigid mode: omega^2 within the factor's backward error of 0, i.e. a frequency
    # below sqrt(n gamma ||K|| / m) / 2 pi
    assert frequencies[0] < np.sqrt(factor_error(n) * 4 * STIFFNESS / MASS) / (2 * np.pi)
    assert frequencies[0] < 1e-4 * exact[1]
    rigid = shapes[:, 0] * np.sign(shapes[0, 0])
    assert np.allclose(rigid, 1 / np.sqrt(n * MASS), rtol=1e-8)  # uniform, mass-normalised
    relative = np.abs(frequencies[1:] - exact[1:]) / exact[1:]
    assert np.all(relative < frequency_tolerance(n, exact[1:]))


def test_without_cholmod_falls_back_to_splu_and_says_so(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(sparse_modal, "sparse_cholesky_available", lambda: False)
    n = 500
    stiffness, mass = chain(n, fixed=True)
    result = sparse_modes(stiffness, mass, modes=5)
    assert result.solver.startswith("splu") and "CHOLMOD not available" in result.solver
    exact = fixed_free_hz(n, 5)
    assert np.all(np.abs(result.frequencies_hz - exact) / exact < frequency_tolerance(n, exact))


def test_splu_on_request() -> None:
    n = 500
    stiffness, mass = chain(n, fixed=True)
    result = sparse_modes(stiffness, mass, modes=5, factorization="splu")
    assert result.solver == "splu"
    exact = fixed_free_hz(n, 5)
    assert np.all(np.abs(result.frequencies_hz - exact) / exact < frequency_tolerance(n, exact))


def test_small_models_are_solved_densely() -> None:
    stiffness, mass = chain(50, fixed=True)
    result = sparse_modes(stiffness, mass, modes=50)
    assert result.solver == "dense"
    exact = fixed_free_hz(50, 50)
    assert np.all(np.abs(result.frequencies_hz - exact) / exact < frequency_tolerance(50, exact))


def test_bad_requests_are_refused() -> None:
    stiffness, mass = chain(300, fixed=True)
    with pytest.raises(ValueError, match="needs modes"):
        sparse_modes(stiffness, mass)
    with pytest.raises(ValueError, match="modes must be between 1"):
        sparse_modes(stiffness, mass, modes=0)
    with pytest.raises(ValueError, match="below_hz must be a positive"):
        sparse_modes(stiffness, mass, below_hz=-1.0)
    with pytest.raises(ValueError, match="shift_hz must be positive"):
        sparse_modes(stiffness, mass, modes=3, shift_hz=0.0)
    with pytest.raises(ValueError, match="factorization must be"):
        sparse_modes(stiffness, mass, modes=3, factorization="umfpack")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="mass must have the shape of stiffness"):
        sparse_modes(stiffness, sp.identity(299, format="csc"), modes=3)
