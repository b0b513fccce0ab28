"""Modes of a turning gearbox: the quadratic eigenproblem with gyroscopic and
centripetal terms, solved through its state-space form.

The free motion at reference speed Omega (Cooley & Parker, J. Vib. Acoust. 134 (2012)
061014; :mod:`pygear.assembly.speed_terms`) is

    M q'' + (C + Omega G) q' + (K - Omega^2 K_Omega) q = 0,   q = phi e^(lambda t).

With M = L L^T and p = L^T q the state x = (omega_s p, p') obeys x' = A x with

    A = [[0, omega_s I], [-L^-1 K_eff L^-T / omega_s, -L^-1 (C + Omega G) L^-T]],

where omega_s scales both blocks to the same size (the square root of the largest
eigenvalue of L^-1 K L^-T), so the eigenvalues come out with round-off relative to the
largest natural frequency rather than to its square.  Each mode is one eigenvalue of a
conjugate pair (Im lambda > 0); a real pair (divergence, or an overdamped pair) is one
mode represented by its larger eigenvalue.  At zero speed without damping the symmetric
solver of :func:`pygear.analysis.modes.modal.solve_eigenproblem` runs instead, so the
frequencies are today's modal analysis.

Whirl: a body's centre moves as Re[(a_1, a_2) e^(i w t)] in its frame, which turns at
Omega_f; the motion is a circle of amplitude |a_1 + i a_2|/2 turning in the positive
sense at +w and one of amplitude |a_1 - i a_2|/2 turning in the negative sense (-w), i.e.
at w + Omega_f and -w + Omega_f seen from the housing.  A component turns "forward"
when it turns, seen from the housing, in the sense of the body's own rotation; a planet
(whose centre the carrier carries) and a body at rest take their carrier's sense.
``whirl_ratio`` is (forward - backward)/(forward + backward) of the squared amplitudes,
weighted by each body's mass; a mode whirls forward above +0.1, backward below -0.1,
and is counted planar (straight-line) between.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg
import xarray as xr

from ...assembly.matrices import Model
from ...assembly.speed_terms import SpeedTerms, speed_terms
from .modal import ZERO_EIGENVALUE, classify_by_stage, model_attributes, solve_eigenproblem

__all__ = [
    "STABILITY_CODES",
    "SpeedModes",
    "mass_weighted_mac",
    "quadratic_modes",
    "rigid_motions",
    "solve_at_speed",
    "speed_dependent_modes",
    "whirl_names",
    "whirl_ratios",
]

RIGID_FRACTION = 1e-7
"""|lambda| below this fraction of omega_s is a free rigid-body motion (0 Hz)."""

GROWTH_TOLERANCE = 1e-7
"""Re lambda above this fraction of omega_s is growth: the mode is unstable.  A
conservative gyroscopic system's purely imaginary eigenvalues come out with |Re| of a
few 1e-13 omega_s; next to a double eigenvalue (a coalescence) round-off grows like the
square root of machine epsilon, 1e-8 omega_s."""

WHIRL_THRESHOLD = 0.1
"""|whirl_ratio| above this classifies a mode as forward or backward."""

STABILITY_CODES = {0: "stable", 1: "divergence", 2: "flutter", 3: "rigid"}
"""Meaning of ``stability`` values: divergence is a real positive eigenvalue, flutter a
complex one with positive real part, rigid a free rigid-body motion."""


@dataclass(frozen=True)
class SpeedModes:
    """Eigenvalues and displacement shapes of the modes at one speed.

    ``eigenvalues`` [rad/s] and ``shapes`` (reduced DOFs x mode, mass-normalised
    complex) hold one representative per mode, rigid-body modes first then by
    frequency; ``rigid`` marks the free rigid-body motions.
    """

    eigenvalues: np.ndarray
    shapes: np.ndarray
    rigid: np.ndarray
    scale: float

    @property
    def frequencies(self) -> np.ndarray:
        """|Im lambda| / 2 pi [Hz]; 0 for rigid-body and real (divergent) modes."""
        return np.abs(self.eigenvalues.imag) / (2 * math.pi)

    @property
    def stability(self) -> np.ndarray:
        """Codes of :data:`STABILITY_CODES` for every mode."""
        growth = self.eigenvalues.real > GROWTH_TOLERANCE * self.scale
        real = np.abs(self.eigenvalues.imag) <= GROWTH_TOLERANCE * self.scale
        codes = np.where(growth, np.where(real, 1, 2), 0)
        return np.where(self.rigid, 3, codes)

    @property
    def damping_ratios(self) -> np.ndarray:
        """-Re lambda / |lambda| (0 for rigid-body modes)."""
        size = np.abs(self.eigenvalues)
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.where(size > 0, -self.eigenvalues.real / size, 0.0)
        return np.where(self.rigid, 0.0, ratio)


def mass_weighted_mac(mass: np.ndarray, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """MAC_ij = |a_i^H M b_j|^2 / ((a_i^H M a_i)(b_j^H M b_j)) of complex shapes."""
    # M times the shapes once (a matrix product), not a three-operand einsum, which
    # loops over M for every mode
    mass_first, mass_second = mass @ first, mass @ second
    cross = first.conj().T @ mass_second
    norm_a = np.einsum("im,im->m", first.conj(), mass_first).real
    norm_b = np.einsum("im,im->m", second.conj(), mass_second).real
    return np.abs(cross) ** 2 / np.outer(norm_a, norm_b)


def quadratic_modes(
    mass: np.ndarray,
    stiffness: np.ndarray,
    first_order: np.ndarray | None = None,
    rigid_count: int | None = None,
) -> SpeedModes:
    """Modes of M q'' + D q' + K q = 0 (D = C + Omega G, K = K_eff), state space.

    Parameters
    ----------
    mass, stiffness : ndarray
        M (symmetric positive definite) and K_eff.
    first_order : ndarray, optional
        D; zero when omitted.
    rigid_count : int, optional
        At most how many free rigid-body motions to expect (those of K at zero speed);
        the eigenvalue pairs nearest zero, if below :data:`RIGID_FRACTION` of omega_s,
        are taken as those.  A rigid motion the speed terms act on (``lin-parker``'s
        free rotation) leaves zero and is a mode like the others.  Default: as many
        as fall below the threshold.
    """
    n = mass.shape[0]
    lower = np.linalg.cholesky(mass)
    inverse = scipy.linalg.solve_triangular(lower, np.eye(n), lower=True)
    stiffness_n = inverse @ stiffness @ inverse.T
    symmetric = 0.5 * (stiffness_n + stiffness_n.T)
    scale = math.sqrt(max(np.abs(np.linalg.eigvalsh(symmetric)).max(), 1.0))
    state = np.zeros((2 * n, 2 * n))
    state[:n, n:] = scale * np.eye(n)
    state[n:, :n] = -stiffness_n / scale
    if first_order is not None:
        state[n:, n:] = -(inverse @ first_order @ inverse.T)
    eigenvalues, vectors = scipy.linalg.eig(state)
    shapes_all = inverse.T @ vectors[:n] / scale  # q = L^-T p
    size = np.abs(eigenvalues)
    order = np.argsort(size)
    below = int(np.sum(size < RIGID_FRACTION * scale)) // 2
    rigid_count = below if rigid_count is None else min(rigid_count, below)
    rigid_pick = order[: 2 * rigid_count]
    rest = np.setdiff1d(np.arange(2 * n), rigid_pick)
    chosen = _one_per_pair(eigenvalues[rest], scale)
    picked = rest[chosen]
    by_frequency = np.lexsort((eigenvalues[picked].real, np.abs(eigenvalues[picked].imag)))
    picked = picked[by_frequency]
    rigid_shapes = _rigid_shapes(stiffness, mass, rigid_count)
    values = np.concatenate([np.zeros(rigid_count, complex), eigenvalues[picked]])
    shapes = np.concatenate([rigid_shapes.astype(complex), shapes_all[:, picked]], axis=1)
    modal_mass = np.einsum("im,ij,jm->m", shapes.conj(), mass, shapes).real
    shapes = shapes / np.sqrt(modal_mass)
    rigid = np.arange(values.size) < rigid_count
    return SpeedModes(values, shapes, rigid, scale)


def _one_per_pair(eigenvalues: np.ndarray, scale: float) -> np.ndarray:
    """Indices of one eigenvalue per mode: Im > 0 for complex pairs; real eigenvalues
    paired largest with smallest, the larger one kept."""
    real = np.abs(eigenvalues.imag) <= GROWTH_TOLERANCE * scale
    complex_pick = np.flatnonzero(~real & (eigenvalues.imag > 0))
    real_index = np.flatnonzero(real)
    real_index = real_index[np.argsort(-eigenvalues[real_index].real)]
    kept = real_index[: (real_index.size + 1) // 2]
    return np.concatenate([complex_pick, kept]).astype(int)


def _rigid_shapes(stiffness: np.ndarray, mass: np.ndarray, count: int) -> np.ndarray:
    if count == 0:
        return np.zeros((mass.shape[0], 0))
    values, vectors = scipy.linalg.eigh(stiffness, mass)
    return vectors[:, np.argsort(np.abs(values))[:count]]


def speed_dependent_modes(
    model: Model,
    case: Any,
    speed_rpm: float,
    *,
    reference: str | None = None,
    damping: bool = False,
    terms: SpeedTerms | None = None,
    method: str = "auto",
) -> xr.Dataset:
    """Modes of the gearbox with Cooley & Parker's terms at one reference speed.

    Parameters
    ----------
    model : Model
        The assembled model at zero speed (no speed-dependent effect in force).
    case : Case
        Its case.
    speed_rpm : float
        Speed of the reference member [rpm].
    reference : str, optional
        DOF label of the reference member; default the first planetary carrier.
    damping : bool
        Include the model's damping (modal damping ratios); undamped otherwise.
    terms : SpeedTerms, optional
        Precomputed :func:`~pygear.assembly.speed_terms.speed_terms` of the model.
    method : {"auto", "state-space"}
        ``auto`` takes the symmetric solver at zero speed without damping.

    Returns
    -------
    xarray.Dataset
        Over ``mode``: ``frequency`` [Hz], ``growth_rate`` [1/s], ``damping_ratio``,
        ``stability`` (codes of :data:`STABILITY_CODES`), ``whirl`` and
        ``whirl_ratio``, ``mode_class`` and ``stage_name``; ``shape_real`` and
        ``shape_imag`` over (``dof``, ``mode``).
    """
    if method not in ("auto", "state-space"):
        raise ValueError(f"method must be 'auto' or 'state-space' (got {method!r})")
    terms = terms or speed_terms(model, case, reference)
    modes = solve_at_speed(model, terms, speed_rpm, damping=damping, method=method)
    whirl_ratio, translating = whirl_ratios(terms, modes, speed_rpm)
    dominant, classes, _ = classify_by_stage(model, modes.shapes)

    def variable(values, units, long_name, dims=("mode",)):
        return dims, values, {"units": units, "long_name": long_name}

    names = whirl_names(whirl_ratio, modes.rigid | ~translating)
    return xr.Dataset(
        {
            "frequency": variable(
                modes.frequencies, "Hz", "natural frequency in the carrier frame"
            ),
            "growth_rate": variable(modes.eigenvalues.real, "1/s", "real part of the eigenvalue"),
            "damping_ratio": variable(
                modes.damping_ratios, "1", "modal damping ratio -Re(lambda)/|lambda|"
            ),
            "stability": variable(
                modes.stability, "1", "0 stable, 1 divergence, 2 flutter, 3 rigid body"
            ),
            "whirl": variable(
                np.array(names, dtype=object), "1", "whirl direction seen from the housing"
            ),
            "whirl_ratio": variable(
                whirl_ratio, "1", "(forward - backward)/(forward + backward) whirl, mass-weighted"
            ),
            "mode_class": variable(
                np.array(classes, dtype=object), "1", "mode class (Lin & Parker families)"
            ),
            "stage_name": variable(
                np.array(dominant, dtype=object), "1", "stage holding most of the kinetic energy"
            ),
            "shape_real": variable(
                modes.shapes.real, "1", "mass-normalised mode shape, real part", ("dof", "mode")
            ),
            "shape_imag": variable(
                modes.shapes.imag, "1", "mass-normalised mode shape, imag part", ("dof", "mode")
            ),
        },
        coords={
            "mode": variable(np.arange(1, modes.eigenvalues.size + 1), "1", "mode number"),
            "dof": variable(np.array(model.dof_labels, dtype=object), "1", "reduced DOF", ("dof",)),
        },
        attrs={
            **model_attributes(model),
            "speed_rpm": float(speed_rpm),
            "reference": terms.reference,
            "speed_terms": f"Cooley & Parker (2012), {terms.members} members",
            "damping_included": int(damping),
        },
    )


def solve_at_speed(
    model: Model,
    terms: SpeedTerms,
    speed_rpm: float,
    *,
    damping: bool = False,
    method: str = "auto",
    rigid_count: int | None = None,
) -> SpeedModes:
    """The :class:`SpeedModes` of a zero-speed model at a reference speed [rpm].

    ``rigid_count`` is the model's count of free rigid-body motions (computed when
    omitted)."""
    omega = speed_rpm * math.pi / 30.0
    if method == "auto" and omega == 0.0 and not damping:
        frequencies, shapes = solve_eigenproblem(model)
        rigid = frequencies == 0.0
        scale = 2 * math.pi * max(frequencies.max(initial=0.0), 1.0)
        return SpeedModes(2j * math.pi * frequencies, shapes.astype(complex), rigid, scale)
    gyroscopic, centripetal = terms.at(omega)
    first_order = gyroscopic + (model.damping if damping else 0.0)
    if rigid_count is None:
        rigid_count = rigid_motions(model)
    return quadratic_modes(
        model.mass, model.stiffness - centripetal, first_order, rigid_count=rigid_count
    )


def rigid_motions(model: Model) -> int:
    """Count of free rigid-body motions of the zero-speed model (as modal analysis)."""
    values = scipy.linalg.eigvalsh(model.stiffness, model.mass)
    scale = max(abs(values).max(), 1.0)
    return int(np.sum(values < ZERO_EIGENVALUE * scale))


def whirl_ratios(
    terms: SpeedTerms, modes: SpeedModes, speed_rpm: float
) -> tuple[np.ndarray, np.ndarray]:
    """Mass-weighted (forward - backward)/(forward + backward) whirl of every mode, and
    whether the mode translates any body at all (translational kinetic energy above
    1e-9 of the mode's, for mass-normalised shapes)."""
    sense = 1.0 if speed_rpm >= 0 else -1.0
    omega = abs(speed_rpm) * math.pi / 30.0
    forward = np.zeros(modes.eigenvalues.size)
    backward = np.zeros(modes.eigenvalues.size)
    frequency = np.abs(modes.eigenvalues.imag)
    flip = modes.eigenvalues.imag < 0  # keep e^{+i w t}: conjugate the shape
    for pair in terms.pairs:
        first = pair.first @ modes.shapes
        second = pair.second @ modes.shapes
        first = np.where(flip, first.conj(), first)
        second = np.where(flip, second.conj(), second)
        carried = pair.role == "planet" or abs(pair.spin_ratio) <= 1e-9
        turning = pair.frame_ratio if carried else pair.spin_ratio
        own_sense = sense * (1.0 if turning >= 0 else -1.0)
        frame_speed = sense * pair.frame_ratio * omega
        # x + i y = (a1 + i a2)/2 e^{iwt} + (conj(a1) + i conj(a2))/2 e^{-iwt}
        positive = np.abs(first + 1j * second) ** 2 / 4  # circle turning +, at +w
        negative = np.abs(first - 1j * second) ** 2 / 4  # circle turning -, at -w
        for amplitude, direction in ((positive, frequency), (negative, -frequency)):
            seen = direction + frame_speed
            with_body = np.sign(seen) * own_sense > 0
            forward += pair.mass * np.where(with_body, amplitude, 0.0)
            backward += pair.mass * np.where(with_body, 0.0, amplitude)
    total = forward + backward
    translating = total > 1e-9
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(translating, (forward - backward) / total, 0.0)
    return np.where(modes.rigid, 0.0, ratio), translating


def whirl_names(ratio: np.ndarray, still: np.ndarray) -> list[str]:
    """``forward``, ``backward``, ``planar`` or ``none`` (``still``: rigid body, or no
    translation)."""
    names = []
    for value, is_still in zip(ratio, still):
        if is_still:
            names.append("none")
        elif value > WHIRL_THRESHOLD:
            names.append("forward")
        elif value < -WHIRL_THRESHOLD:
            names.append("backward")
        else:
            names.append("planar")
    return names
