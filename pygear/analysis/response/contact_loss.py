r"""Periodic steady state with tooth separation: alternating frequency-time Newton (AFT).

Where the linear balance (:mod:`.hill`) finds a mesh force below zero, the teeth part:
the mesh spring carries k_m(t) delta_m while s_m delta_m > 0 and nothing otherwise
(no coast-flank contact: the backlash is taken as larger than the separation).  The
condensed balance (2) of :mod:`.hill` becomes, with the mesh forces' nonlinear part
N_m(t) = k_m(t) delta_m H(s_m delta_m) - kbar_m delta_m (kbar inside K0),

    R(delta) = delta + G N(delta) - B D^-1 f = 0,

evaluated by alternating frequency and time (Cameron & Griffin 1989): delta_k to
delta(t) by inverse FFT on the stiffness samples, N(t) there, its harmonics by FFT.
Newton's Jacobian is the Hill matrix of (2) with the stiffness variation replaced by
e_m(t) = k_m(t) H(s_m delta_m(t)) - kbar_m (a semismooth Newton step for the
piecewise-linear contact), so each step reuses the linear balance's condensed solve.
Kahraman & Singh (1990) solved the spur pair with backlash by harmonic balance in this
spirit; continuation along speed (pseudo-arclength, to pass turning points of the
softening resonance) is the next step and is not here: each speed starts from the
linear solution.
"""

from __future__ import annotations

import numpy as np

from .hill import HillSolution, _direct, _receptance, fourier_coefficients, solve_hill
from .system import ResponseSystem

__all__ = ["ContactLossError", "contact_loss_balance"]

TOLERANCE = 1e-10
"""Newton stops when the residual's largest harmonic falls below this share of the
largest static mesh deflection."""

MAX_ITERATIONS = 60
MAX_HALVINGS = 12
"""Newton steps, and halvings of a step that does not lower the residual (a
backtracking line search: the contact switches make the full step overshoot)."""


class ContactLossError(RuntimeError):
    """The AFT Newton iteration did not converge."""


def _signals(system: ResponseSystem, deflection: np.ndarray) -> np.ndarray:
    n = system.stiffness.shape[0]
    h = deflection.shape[0] // 2
    spectrum = np.zeros((n, deflection.shape[1]), dtype=complex)
    spectrum[np.arange(-h, h + 1) % n] = deflection
    return np.real(np.fft.ifft(spectrum, axis=0)) * n


def _nonlinear(system: ResponseSystem, deflection: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Harmonics -H..H of N(t) and the samples of e(t) (the Jacobian's stiffness)."""
    h = deflection.shape[0] // 2
    signal = _signals(system, deflection)
    contact = (system.contact_sign * signal) > 0
    force = system.stiffness * signal * contact - system.mean_stiffness * signal
    return fourier_coefficients(force, h), system.stiffness * contact - system.mean_stiffness


def _coordinates(system: ResponseSystem, omega: float, load: np.ndarray, h: int) -> np.ndarray:
    """y_j = D_j^-1 (f delta_j0 - B^T N_j) for j = -H..H."""
    w = np.arange(-h, h + 1) * omega
    lam, c = system.eigenvalues, system.damping
    dynamic = (
        np.diag(lam)[None]
        - (w**2)[:, None, None] * np.eye(lam.size)
        + 1j * w[:, None, None] * c[None]
    )
    forcing = -load @ system.mesh_rows
    forcing[h] += system.force
    return np.linalg.solve(dynamic, forcing[..., None])[..., 0]


def contact_loss_balance(
    system: ResponseSystem,
    omega: float,
    harmonics: int,
    *,
    start: HillSolution | None = None,
) -> tuple[HillSolution, int]:
    """The periodic steady state with tooth separation at one fundamental frequency.

    Parameters
    ----------
    system : ResponseSystem
        The model (static load only; ``harmonic_force`` is not taken).
    omega : float
        Fundamental angular frequency [rad/s].
    harmonics : int
        H >= 1.
    start : HillSolution, optional
        Initial guess with H harmonics; default the linear balance.

    Returns
    -------
    solution : HillSolution
        Mesh deflection and modal coordinate harmonics; ``residual`` is the Newton
        residual over the largest static mesh deflection.
    iterations : int
        Newton steps taken.

    Raises
    ------
    ContactLossError
        No convergence within :data:`MAX_ITERATIONS` steps.
    """
    h = int(harmonics)
    guess = start or solve_hill(system, omega, h, method="direct")
    deflection = guess.deflection.copy()
    _, receptance = _receptance(system, omega, np.arange(-h, h + 1))
    linear = np.zeros_like(deflection)
    linear[h] = system.mesh_rows @ (system.force / system.eigenvalues)
    scale = np.abs(system.static_deflection()).max()
    positive = receptance[h:]

    def residual_of(candidate: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        load, jacobian_stiffness = _nonlinear(system, candidate)
        value = candidate + np.einsum("jmn,jn->jm", receptance, load) - linear
        return value, jacobian_stiffness

    residual, jacobian_stiffness = residual_of(deflection)
    norm = float(np.abs(residual).max()) / scale
    for iteration in range(MAX_ITERATIONS):
        if norm < TOLERANCE:
            load, _ = _nonlinear(system, deflection)
            coordinates = _coordinates(system, omega, load, h)
            return HillSolution(h, omega, deflection, coordinates, norm), iteration
        coefficients = fourier_coefficients(jacobian_stiffness, 3 * h)
        step = _direct(positive, coefficients, -residual[h:], h)
        length = 1.0
        for _ in range(MAX_HALVINGS):  # backtrack until the residual falls
            trial = deflection + length * step
            trial_residual, trial_stiffness = residual_of(trial)
            trial_norm = float(np.abs(trial_residual).max()) / scale
            if trial_norm < (1 - 1e-4 * length) * norm:
                break
            length *= 0.5
        deflection, residual, jacobian_stiffness, norm = (
            trial,
            trial_residual,
            trial_stiffness,
            trial_norm,
        )
    raise ContactLossError(
        f"contact-loss balance did not converge in {MAX_ITERATIONS} Newton steps "
        f"(residual {norm:.2e} of the static deflection)"
    )
