"""Which eigenvalues of K x = lambda M x are rigid-body motions (lambda = 0).

A computed zero eigenvalue is not zero: it comes out at round-off of the largest, about
eps ||K|| / ||M|| times a modest factor.  A gearbox's modes span three to five decades,
so "below 1e-8 of the largest" told them apart.  A drivetrain's do not: short stiff shaft
elements put the largest eigenvalue near 1e10 (rad/s)^2 and the first torsional mode of
a wind turbine near 150 (2 Hz), a ratio of 1.5e-8.  An eigenvalue is therefore rigid
only when it is also far below every elastic one (:data:`ZERO_GAP`): rounding cannot
lift a zero four decades above the round-off scale, and a soft elastic mode stands
apart from the zeros by many decades more.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ZERO_GAP", "ZERO_SCALE", "rigid_body_mask"]

ZERO_SCALE = 1e-8
"""A rigid eigenvalue lies below this share of the scale (the largest eigenvalue) [-]."""

ZERO_GAP = 1e-4
"""... and below this share of the smallest eigenvalue that is not rigid [-]."""


def rigid_body_mask(eigenvalues: np.ndarray, scale: float | None = None) -> np.ndarray:
    """True for the eigenvalues that are rigid-body motions.

    Parameters
    ----------
    eigenvalues : ndarray
        Eigenvalues lambda = omega^2 [rad^2/s^2] (all of them, or the lowest few).
    scale : float, optional
        The largest eigenvalue or an estimate of it (for the lowest few alone); default
        the largest given.
    """
    values = np.abs(np.asarray(eigenvalues, dtype=np.float64))
    if values.size == 0:
        return np.zeros(0, dtype=bool)
    reference = max(float(values.max()) if scale is None else float(scale), 1e-300)
    zero = values <= ZERO_SCALE * reference
    if np.any(~zero):
        zero &= values <= ZERO_GAP * values[~zero].min()
    return zero
