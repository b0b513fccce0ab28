r"""Floquet stability of the linear time-periodic model: the monodromy matrix.

The homogeneous elastic equations y'' + C_r y' + K(t) y = 0 in first-order form
x' = A(t) x, x = (y, y'), A = [[0, I], [-K(t), -C_r]], have the monodromy matrix
Phi(T) over one period T of the fundamental; its eigenvalues are the Floquet
multipliers, and the periodic steady state is asymptotically stable when every
multiplier lies inside the unit circle (Floquet 1883; Nayfeh & Mook, *Nonlinear
Oscillations*, 1979, §5.2).

Phi(T) is the ordered product of the exact exponentials of A over ``segments`` equal
intervals, the stiffness held at its mean over each interval (the second-order Magnus
step, exact for a stiffness constant on each interval, such as the rectangular wave
of a Meissner equation).  The exponentials are evaluated together by scaling and
squaring of a degree-12 Taylor polynomial (truncation 0.5^13 / 13! = 2e-14 at norm 1/2),
batched over the intervals, which costs a few batched matrix products where
:func:`scipy.linalg.expm` checks and factorises every matrix on its own.
"""

from __future__ import annotations

import math

import numpy as np

from .system import ResponseSystem

__all__ = [
    "DEFAULT_SEGMENTS",
    "batched_expm",
    "floquet_multipliers",
    "monodromy",
    "system_multipliers",
]

DEFAULT_SEGMENTS = 128
"""Intervals of constant stiffness per period."""

_TAYLOR_DEGREE = 12
_NORM_TARGET = 0.5


def batched_expm(matrices: np.ndarray) -> np.ndarray:
    """exp(A) of a stack of square matrices by scaling and squaring of a Taylor series.

    Parameters
    ----------
    matrices : ndarray, shape (..., n, n)
        Real or complex matrices.

    Returns
    -------
    ndarray, shape (..., n, n)
    """
    norms = np.abs(matrices).sum(axis=-2).max(axis=-1)  # 1-norms
    largest = float(norms.max()) if norms.size else 0.0
    squarings = max(0, math.ceil(math.log2(largest / _NORM_TARGET))) if largest > 0 else 0
    scaled = matrices / 2.0**squarings
    identity = np.broadcast_to(np.eye(matrices.shape[-1]), matrices.shape)
    result = identity + scaled / _TAYLOR_DEGREE
    for k in range(_TAYLOR_DEGREE - 1, 0, -1):  # Horner: I + A/1 (I + A/2 (I + ...))
        result = identity + (scaled @ result) / k
    for _ in range(squarings):
        result = result @ result
    return result


def monodromy(stiffness: np.ndarray, damping: np.ndarray, period: float) -> np.ndarray:
    """Monodromy matrix of y'' + C y' + K_i y = 0 with K_i constant on equal intervals.

    Parameters
    ----------
    stiffness : ndarray, shape (segments, n, n)
        K on each interval (unit mass) [1/s^2].
    damping : ndarray, shape (n, n)
        C [1/s].
    period : float
        T [s].

    Returns
    -------
    ndarray, shape (2n, 2n)
        Phi(T) acting on (y, y' / s), s the square root of the largest stiffness entry
        (similar to the monodromy on (y, y'): the same multipliers).
    """
    segments, n, _ = stiffness.shape
    step = period / segments
    # state (y, y' / s), s ~ the largest natural frequency: a similarity transform
    # (same multipliers) that balances A, whose norm would otherwise be set by K ~ s^2
    # and cost the exponentials some twenty squarings at low speed
    scale = math.sqrt(max(float(np.abs(stiffness).max()), 1e-300))
    a = np.zeros((segments, 2 * n, 2 * n))
    a[:, :n, n:] = scale * np.eye(n)
    a[:, n:, :n] = -stiffness / scale
    a[:, n:, n:] = -damping
    exponentials = batched_expm(a * step)
    while exponentials.shape[0] > 1:  # pairwise products, later intervals on the left
        if exponentials.shape[0] % 2:  # an identity after the last interval
            exponentials = np.concatenate([exponentials, np.eye(2 * n)[None]])
        exponentials = exponentials[1::2] @ exponentials[0::2]
    return exponentials[0]


def floquet_multipliers(stiffness: np.ndarray, damping: np.ndarray, period: float) -> np.ndarray:
    """Floquet multipliers of y'' + C y' + K(t) y = 0, largest modulus first.

    Parameters are those of :func:`monodromy`.
    """
    values = np.linalg.eigvals(monodromy(stiffness, damping, period))
    return values[np.argsort(-np.abs(values))]


def segment_means(samples: np.ndarray, segments: int) -> np.ndarray:
    """Means over ``segments`` equal intervals of a periodic function sampled at
    tau = i / N (N a multiple of ``segments``), by the trapezoidal rule over each
    interval's end points (a plain block mean would centre each interval half a sample
    early, a phase error that grows with the frequencies the stiffness rings)."""
    n = samples.shape[0]
    if n % segments:
        raise ValueError(f"{n} samples do not split into {segments} equal intervals")
    step = n // segments
    blocks = samples.reshape(segments, step, *samples.shape[1:]).sum(axis=1)
    ends = np.roll(samples, -step, axis=0)[::step]
    return (blocks - 0.5 * samples[::step] + 0.5 * ends) / step


def system_multipliers(
    system: ResponseSystem, omega: float, segments: int = DEFAULT_SEGMENTS
) -> np.ndarray:
    """Floquet multipliers of a gearbox model at fundamental frequency ``omega``.

    Parameters
    ----------
    system : ResponseSystem
        The model (its stiffness samples, elastic modal form).
    omega : float
        Fundamental angular frequency [rad/s].
    segments : int
        Intervals of constant stiffness per period.

    Returns
    -------
    ndarray, complex
        The 2n multipliers, largest modulus first.
    """
    variation = segment_means(system.stiffness_variation, segments)
    rows = system.mesh_rows
    stiffness = np.diag(system.eigenvalues)[None] + np.einsum(
        "mi,sm,mj->sij", rows, variation, rows
    )
    return floquet_multipliers(stiffness, system.damping, 2 * math.pi / omega)
