r"""Harmonic balance (Hill's method) of the linear time-periodic gearbox model.

With y(tau) = sum_{k=-H}^{H} y_k e^{i k omega t} and the stiffness variation
dk_m(t) = sum_j c_{m,j} e^{i j omega t}, balancing the harmonics -H..H of

    y'' + C_r y' + (Lambda + B^T diag(dk(t)) B) y = f

gives Hill's block system (a Galerkin projection; Hill 1886, Bolotin 1964):

    D_j y_j + B^T sum_k diag(c_{j-k}) B y_k = f delta_{j0},
    D_j = Lambda - (j omega)^2 I + i j omega C_r,                     (1)

whose blocks :func:`hill_matrix` assembles as a sparse matrix (the form an AFT Newton
solver for contact loss linearises around).  Because the time-varying part has rank
n_mesh, (1) is solved condensed onto the mesh deflections delta_k = B y_k: with the
receptance G_j = B D_j^-1 B^T (n_mesh x n_mesh) and the convolution (T delta)_j =
sum_k diag(c_{j-k}) delta_k,

    (I + G T) delta = B D^-1 f,                                        (2)

an n_mesh (2H + 1) system, one LU factorisation per speed; y_j = D_j^-1 (f delta_{j0} -
B^T (T delta)_j) follows.  (2) is (1) with y eliminated (a Schur complement), exact.

Harmonic count.  A mesh stiffness that jumps when a pair enters or leaves contact has
Fourier coefficients c_j ~ 1/j, so the force residual of a truncated series does not
fall below the Gibbs overshoot at a jump, whatever H; the deflection, whose second
derivative carries the jump, has coefficients ~ 1/j^3.  The residual reported is
therefore the deflection the harmonics H+1..2H would add, one block-Jacobi step of (2)
from the solution (delta_j ~ -G_j (T delta)_j for H < |j| <= 2H), sampled at 8 (2H + 1)
instants of a period and divided by the largest static mesh deflection: the force
residual M q'' + C q' + K(t) q - F of those harmonics, mapped through the system's own
dynamic compliance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from ...errors import CaseError
from .system import ResponseSystem

__all__ = [
    "AUTO_HARMONICS",
    "HillSolution",
    "fourier_coefficients",
    "harmonic_balance",
    "hill_matrix",
    "mesh_signals",
    "solve_hill",
]

AUTO_HARMONICS = (2, 4, 8, 16, 32, 64, 128)
"""Harmonic counts tried in turn when the count is chosen by the tolerance."""

ITERATIVE_ROWS = 1000
"""Complex rows of (2) from which ``solve_hill(method="auto")`` iterates."""

PRECONDITIONED_BAND = 8
"""Harmonics |j| <= this are inverted exactly in the GMRES preconditioner."""

GMRES_TOLERANCE = 1e-12
GMRES_ACCEPT = 1e-10
GMRES_RESTART = 80
GMRES_CYCLES = 1
"""GMRES: relative residual of (2) aimed at, relative residual accepted when GMRES stops
short of it (far above the mesh modes the coupling is so weak that round-off of the
FFT convolution stalls it near 1e-12), Krylov vectors, restarts.  Above the mesh modes a
few to thirty iterations converge; where the harmonics ring the mesh modes (low speed)
GMRES would need more than a hundred, and its Arnoldi loop then costs more than the LU,
so it hands over after these."""


@dataclass
class HillSolution:
    """A periodic solution: harmonics -H..H at one fundamental frequency.

    Attributes
    ----------
    harmonics : int
        H.
    omega : float
        Fundamental angular frequency [rad/s].
    deflection : ndarray, complex, shape (2H + 1, n_mesh)
        delta_k, row k + H [m].
    coordinates : ndarray, complex, shape (2H + 1, n)
        y_k, row k + H (modal coordinates).
    residual : float
        Deflection of the next harmonics over the largest static mesh deflection [-].
    """

    harmonics: int
    omega: float
    deflection: np.ndarray
    coordinates: np.ndarray
    residual: float = math.nan


def fourier_coefficients(samples: np.ndarray, order: int) -> np.ndarray:
    """Complex Fourier coefficients c_j, j = -order..order, of equally spaced samples.

    Parameters
    ----------
    samples : ndarray, shape (N, ...)
        Values over one period at tau = i / N.
    order : int
        Highest harmonic; N must exceed 2 order.

    Returns
    -------
    ndarray, shape (2 order + 1, ...)
        Row j + order is c_j with samples = sum_j c_j e^{2 pi i j tau}.
    """
    n = samples.shape[0]
    if n <= 2 * order:
        raise ValueError(f"{n} samples cannot resolve harmonic {order}")
    spectrum = np.fft.fft(samples, axis=0) / n
    return spectrum[np.arange(-order, order + 1) % n]


def _receptance(system: ResponseSystem, omega: float, orders: np.ndarray) -> tuple:
    """D_j^-1 B^T (shape (J, n, n_mesh)) and G_j = B D_j^-1 B^T for harmonics ``orders``."""
    rows = system.mesh_rows
    lam = system.eigenvalues
    c = system.damping
    w = orders * omega
    diagonal = np.abs(c - np.diag(np.diag(c))).max() <= 1e-12 * max(np.abs(c).max(), 1e-300)
    if diagonal:
        inverse = 1.0 / (lam[None, :] - w[:, None] ** 2 + 1j * w[:, None] * np.diag(c)[None, :])
        solved = inverse[:, :, None] * rows.T[None, :, :]
    else:
        d = (
            np.diag(lam)[None]
            - (w**2)[:, None, None] * np.eye(lam.size)[None]
            + 1j * w[:, None, None] * c[None]
        )
        solved = np.linalg.solve(d, np.broadcast_to(rows.T, (w.size, *rows.T.shape)))
    return solved, np.einsum("mi,jin->jmn", rows, solved)


def _toeplitz(coefficients: np.ndarray, harmonics: int) -> np.ndarray:
    """T[j, k, m] = c_{m, j-k} for j, k in -H..H (``coefficients`` over -2H..2H or more)."""
    centre = coefficients.shape[0] // 2
    j = np.arange(-harmonics, harmonics + 1)
    return coefficients[centre + j[:, None] - j[None, :]]


def solve_hill(
    system: ResponseSystem,
    omega: float,
    harmonics: int,
    coefficients: np.ndarray | None = None,
    *,
    method: str = "auto",
) -> HillSolution:
    """Solve Hill's system (2) at one fundamental frequency and harmonic count.

    ``direct``: the solution is real, delta_{-k} = conj(delta_k), so (2) is solved for
    harmonics 0..H in real form (unknowns Re delta_0..H and Im delta_1..H, equations the
    real parts of harmonics 0..H and the imaginary parts of 1..H, that of harmonic 0
    holding identically), one LU factorisation of n_mesh (2H + 1) real rows: a quarter
    of the complex factorisation's work.

    ``iterative``: GMRES on (2) with the convolution T applied by FFT, preconditioned by
    the exact inverse of the band |j| <= :data:`PRECONDITIONED_BAND` and the block
    diagonal (I + G_j c_0)^-1 above it; the higher harmonics couple weakly (G_j falls
    as 1/j^2 above the mesh modes), so a few to a few tens of iterations reach a
    relative residual of 1e-12 (1e-10 accepted) where the LU costs n^3.  Should GMRES
    stall above that, the direct solve takes over.  ``auto`` iterates from
    :data:`ITERATIVE_ROWS` complex rows on.

    Parameters
    ----------
    system : ResponseSystem
        The model.
    omega : float
        Fundamental angular frequency [rad/s], > 0.
    harmonics : int
        H >= 0.
    coefficients : ndarray, optional
        Fourier coefficients of the stiffness variation over -3H..3H (or more);
        computed from ``system.stiffness`` when not given.
    method : str
        ``auto``, ``direct`` or ``iterative``.

    Returns
    -------
    HillSolution
        With its residual estimate.
    """
    h = int(harmonics)
    if method not in ("auto", "direct", "iterative"):
        raise ValueError(f"method must be auto, direct or iterative (got {method!r})")
    if coefficients is None:
        coefficients = fourier_coefficients(system.stiffness_variation, 3 * h)
    centre = coefficients.shape[0] // 2
    coefficients = coefficients[centre - 3 * h : centre + 3 * h + 1]
    solved, receptance = _receptance(system, omega, np.arange(0, 2 * h + 1))
    n_mesh = system.mesh_rows.shape[0]
    forcing = np.zeros((h + 1, system.size), dtype=complex)
    forcing[0] = system.force
    if system.harmonic_force is not None:
        extra = system.harmonic_force[:h]
        forcing[1 : 1 + extra.shape[0]] = extra
    response = np.einsum("jin,ji->jn", solved[: h + 1], forcing)  # B D_j^-1 f_j
    deflection = None
    if method == "iterative" or (method == "auto" and (2 * h + 1) * n_mesh >= ITERATIVE_ROWS):
        deflection = _iterative(receptance[: h + 1], coefficients, response, h)
    if deflection is None:
        deflection = _direct(receptance[: h + 1], coefficients, response, h)
    toeplitz = _toeplitz(coefficients[h : 5 * h + 1], h)  # c over -2H..2H
    load = np.einsum("jkm,km->jm", toeplitz, deflection)[h:]  # (T delta)_j, j = 0..H
    lam, c = system.eigenvalues, system.damping
    w = np.arange(h + 1) * omega
    dynamic = (
        np.diag(lam)[None]
        - (w**2)[:, None, None] * np.eye(lam.size)
        + 1j * w[:, None, None] * c[None]
    )
    upper = np.linalg.solve(dynamic, (forcing - load @ system.mesh_rows)[..., None])[..., 0]
    coordinates = np.concatenate([np.conj(upper[:0:-1]), upper])
    residual = _residual(system, receptance, coefficients, deflection, h)
    return HillSolution(h, omega, deflection, coordinates, residual)


def _direct(
    receptance: np.ndarray, coefficients: np.ndarray, response: np.ndarray, h: int
) -> np.ndarray:
    """delta_-H..H of (2) by one real LU factorisation (receptances of orders 0..H)."""
    return real_solve(real_factor(receptance, coefficients, h), response)


def real_factor(receptance: np.ndarray, coefficients: np.ndarray, h: int) -> tuple:
    """LU factors of (2) in real form (unknowns Re delta_0..H, Im delta_1..H).

    Parameters
    ----------
    receptance : ndarray, complex, shape (H + 1, n_mesh, n_mesh)
        G_j, j = 0..H.
    coefficients : ndarray, complex, shape (>= 6H + 1, n_mesh)
        c_j over -3H..3H (row 3H is c_0).
    h : int
        H.
    """
    n_mesh = receptance.shape[1]
    c = lambda order: coefficients[3 * h + order]  # noqa: E731 (c_order, any sign)
    j = np.arange(h + 1)
    same = receptance[:, :, None, :] * c(j[:, None] - j[None, :])[:, None, :, :]
    same[j, :, j, :] += np.eye(n_mesh)
    mirror = receptance[:, :, None, :] * c(j[:, None] + j[None, :])[:, None, :, :]
    mirror[:, :, 0, :] = 0.0  # delta_0 enters once, through c_j
    plus, minus = same + mirror, same - mirror
    size = (h + 1) * n_mesh
    real_rows = np.concatenate(
        [plus.real.reshape(size, size), -minus.imag.reshape(size, size)[:, n_mesh:]], axis=1
    )
    imag_rows = np.concatenate(
        [plus.imag.reshape(size, size), minus.real.reshape(size, size)[:, n_mesh:]], axis=1
    )[n_mesh:]
    matrix = np.concatenate([real_rows, imag_rows], axis=0)
    return scipy.linalg.lu_factor(matrix, check_finite=False), h, n_mesh


def real_solve(factor: tuple, response: np.ndarray) -> np.ndarray:
    """delta_-H..H from :func:`real_factor`'s factors and the right side of harmonics
    0..H (shape (H + 1, n_mesh); the right side of harmonic -k is its conjugate)."""
    lu, h, n_mesh = factor
    size = (h + 1) * n_mesh
    rhs = np.concatenate([response.real.reshape(-1), response.imag[1:].reshape(-1)])
    unknowns = scipy.linalg.lu_solve(lu, rhs, check_finite=False)
    half = unknowns[:size].reshape(h + 1, n_mesh).astype(complex)
    half[1:] += 1j * unknowns[size:].reshape(h, n_mesh)
    return np.concatenate([np.conj(half[:0:-1]), half])  # -H..H


def _iterative(
    receptance: np.ndarray, coefficients: np.ndarray, response: np.ndarray, h: int
) -> np.ndarray | None:
    """delta_-H..H of (2) by preconditioned GMRES, or None when it does not converge."""
    n_mesh = receptance.shape[1]
    rows = 2 * h + 1
    full = np.concatenate([np.conj(receptance[:0:-1]), receptance])  # G_-H..H
    c = coefficients[h : 5 * h + 1]  # c_-2H..2H
    size = 1 << (rows + c.shape[0] - 2).bit_length()
    c_spectrum = np.fft.fft(c, size, axis=0)

    def apply(x: np.ndarray) -> np.ndarray:
        d = x.reshape(rows, n_mesh)
        conv = np.fft.ifft(c_spectrum * np.fft.fft(d, size, axis=0), axis=0)[2 * h : 2 * h + rows]
        return (d + np.einsum("jmn,jn->jm", full, conv)).reshape(-1)

    band = min(h, PRECONDITIONED_BAND)
    low = slice(h - band, h + band + 1)
    k = np.arange(-band, band + 1)
    toeplitz = coefficients[3 * h + k[:, None] - k[None, :]]
    block = (full[low][:, :, None, :] * toeplitz[:, None, :, :]).reshape(
        (2 * band + 1) * n_mesh, -1
    ) + np.eye((2 * band + 1) * n_mesh)
    factor = scipy.linalg.lu_factor(block, check_finite=False)
    diagonal = np.linalg.inv(np.eye(n_mesh)[None] + full * coefficients[3 * h][None, None, :])

    def precondition(x: np.ndarray) -> np.ndarray:
        d = x.reshape(rows, n_mesh)
        out = np.einsum("jmn,jn->jm", diagonal, d)
        out[low] = scipy.linalg.lu_solve(factor, d[low].reshape(-1), check_finite=False).reshape(
            2 * band + 1, n_mesh
        )
        return out.reshape(-1)

    rhs = np.zeros((rows, n_mesh), dtype=complex)
    rhs[h:] = response
    rhs[:h] = np.conj(response[:0:-1])
    shape = (rows * n_mesh, rows * n_mesh)
    solution, info = scipy.sparse.linalg.gmres(
        scipy.sparse.linalg.LinearOperator(shape, apply, dtype=complex),
        rhs.reshape(-1),
        M=scipy.sparse.linalg.LinearOperator(shape, precondition, dtype=complex),
        rtol=GMRES_TOLERANCE,
        atol=0.0,
        restart=GMRES_RESTART,
        maxiter=GMRES_CYCLES,
    )
    if not np.all(np.isfinite(solution)):
        return None
    if info != 0:  # stopped: keep the iterate only if its own residual is small enough
        rhs_norm = np.linalg.norm(rhs)
        if np.linalg.norm(apply(solution) - rhs.reshape(-1)) > GMRES_ACCEPT * rhs_norm:
            return None
    d = solution.reshape(rows, n_mesh)
    return 0.5 * (d + np.conj(d[::-1]))  # the real solution's symmetry, exact


def _residual(
    system: ResponseSystem,
    receptance: np.ndarray,
    coefficients: np.ndarray,
    deflection: np.ndarray,
    h: int,
) -> float:
    """Deflection the harmonics H+1..2H would add, sampled, over the static deflection."""
    scale = np.abs(system.static_deflection()).max()
    if h == 0 or not np.any(coefficients):
        return 0.0
    centre = coefficients.shape[0] // 2
    upper = np.arange(h + 1, 2 * h + 1)
    k = np.arange(-h, h + 1)
    conv = coefficients[centre + upper[:, None] - k[None, :]]  # (band, 2H+1, n_mesh)
    load = np.einsum("jkm,km->jm", conv, deflection)
    extra = -np.einsum("jmn,jn->jm", receptance[h + 1 :], load)  # orders H+1..2H
    samples = 8 * (2 * h + 1)
    tau = np.arange(samples) / samples
    phase = np.exp(2j * math.pi * np.outer(tau, upper))
    signal = 2 * np.real(phase @ extra)
    return float(np.abs(signal).max() / scale) if scale > 0 else math.inf


def harmonic_balance(
    system: ResponseSystem,
    omega: float,
    harmonics: int | str = "auto",
    *,
    tolerance: float = 1e-4,
    max_harmonics: int = AUTO_HARMONICS[-1],
    start: int = AUTO_HARMONICS[0],
    coefficients: np.ndarray | None = None,
) -> HillSolution:
    """The periodic steady state at one fundamental frequency.

    Parameters
    ----------
    system : ResponseSystem
        The model.
    omega : float
        Fundamental angular frequency [rad/s].
    harmonics : int or "auto"
        H, or ``auto``: the first count of :data:`AUTO_HARMONICS` from ``start`` whose
        residual falls below ``tolerance`` (the last one tried when none does).
    tolerance : float
        Residual the automatic count must reach [-].
    max_harmonics, start : int
        Largest and first count tried by ``auto``.
    coefficients : ndarray, optional
        Stiffness coefficients over at least -3 max_harmonics..3 max_harmonics.
    """
    if not (math.isfinite(omega) and omega > 0):
        raise CaseError(f"the fundamental frequency must be > 0 rad/s (got {omega!r})")
    if harmonics != "auto":
        return solve_hill(system, omega, int(harmonics), coefficients)
    counts = [c for c in AUTO_HARMONICS if start <= c <= max_harmonics] or [max_harmonics]
    if coefficients is None:
        coefficients = fourier_coefficients(system.stiffness_variation, 3 * counts[-1])
    solution = None
    for count in counts:  # doubling: the residual falls about as H^-2
        solution = solve_hill(system, omega, count, coefficients)
        if solution.residual <= tolerance:
            break
    return solution


def mesh_signals(system: ResponseSystem, solution: HillSolution) -> tuple[np.ndarray, np.ndarray]:
    """Mesh deflection and mesh force over one period at the stiffness samples.

    Returns
    -------
    deflection : ndarray, shape (N, n_mesh)
        delta_m(tau) [m] from the Fourier series.
    force : ndarray, shape (N, n_mesh)
        s_m k_m(tau) (delta_m(tau) - s_m e_m(tau)) [N], > 0 with the loaded flanks
        pressed together, with the sampled (not truncated) stiffness (e_m the mesh's
        displacement excitation, :mod:`.mesh_excitation`; 0 without).
    """
    n = system.stiffness.shape[0]
    h = solution.harmonics
    spectrum = np.zeros((n, solution.deflection.shape[1]), dtype=complex)
    spectrum[np.arange(-h, h + 1) % n] = solution.deflection
    deflection = np.real(np.fft.ifft(spectrum, axis=0)) * n
    force = system.contact_sign * system.stiffness * deflection
    if system.excitation is not None:
        force = system.contact_sign * system.stiffness * (deflection - system.excitation)
    return deflection, force


def hill_matrix(
    system: ResponseSystem, omega: float, harmonics: int, coefficients: np.ndarray | None = None
) -> scipy.sparse.csc_matrix:
    """Hill's block matrix (1) over the modal coordinates of harmonics -H..H.

    Block (j, k) is D_j delta_jk + B^T diag(c_{j-k}) B; unknowns ordered harmonic by
    harmonic.  The condensed solve of :func:`solve_hill` is the same system; an AFT
    Newton solver for contact loss linearises the contact forces around this matrix.
    """
    h = int(harmonics)
    if coefficients is None:
        coefficients = fourier_coefficients(system.stiffness_variation, 2 * h)
    centre = coefficients.shape[0] // 2
    n = system.size
    rows = system.mesh_rows
    blocks = []
    for j in range(-h, h + 1):
        line = []
        for k in range(-h, h + 1):
            block = rows.T @ (coefficients[centre + j - k][:, None] * rows)
            if j == k:
                w = j * omega
                block = block + np.diag(system.eigenvalues) - w * w * np.eye(n)
                block = block + 1j * w * system.damping
            line.append(block)
        blocks.append(line)
    return scipy.sparse.csc_matrix(np.block(blocks))
