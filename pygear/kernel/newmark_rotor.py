"""Rotor terms of a transient: gyroscopic force at a speed and unbalance forces.

:class:`RotorTerms` says what :class:`~pygear.kernel.newmark.BandedNewmark` hands the
kernel's module ``newmark_gyroscopic`` (``fortran/newmark_gyroscopic.f90``): the
skew-symmetric gyroscopic matrix G per rad/s of a reference speed (every shaft's part
already scaled by its speed ratio), where that speed comes from (a prescribed profile
of time, or the run's own rotation w . v), and unbalances m e at a disc's x and y.
The kernel adds -Omega_ref(t) G v and the unbalance forces to the step's loads and
iterates the gyroscopic force with the step's velocity; a problem without rotor terms
runs its paths unchanged.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

__all__ = ["RotorTerms", "Unbalance", "rotor_arguments"]

SPEED_SOURCES = {"profile": 1, "rotation": 2}
"""Kernel codes of the reference speed's source."""


@dataclass(frozen=True)
class Unbalance:
    """An unbalance m e at the DOFs ``x`` and ``y`` (0-based, the caller's order).

    The shaft's angle is ``ratio`` times the reference angle plus ``angle`` [rad]; the
    force is m e (psi'^2 cos psi + psi'' sin psi, psi'^2 sin psi - psi'' cos psi).
    """

    x: int
    y: int
    mass_eccentricity: float
    angle: float = 0.0
    ratio: float = 1.0


@dataclass
class RotorTerms:
    """Gyroscopic and unbalance loads of a transient (module docstring).

    Attributes
    ----------
    gyroscopic : ndarray or scipy.sparse matrix, shape (n, n), optional
        G per unit reference speed [kg m^2]; its skew part is used.
    source : str
        ``profile`` (``times``, ``speeds``) or ``rotation`` (``speed_weights``).
    times, speeds : sequence of float
        The prescribed reference speed [rad/s] at times [s], linear between, held
        beyond.
    speed_weights : ndarray, shape (n,), optional
        Omega_ref = speed_weights . v for ``rotation``.
    unbalances : sequence of Unbalance
        Only with ``profile``.
    """

    gyroscopic: object | None = None
    source: str = "profile"
    times: Sequence[float] = (0.0,)
    speeds: Sequence[float] = (0.0,)
    speed_weights: np.ndarray | None = None
    unbalances: Sequence[Unbalance] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        if self.source not in SPEED_SOURCES:
            raise ValueError(f"RotorTerms.source must be one of {sorted(SPEED_SOURCES)}")
        times = np.asarray(self.times, dtype=np.float64)
        speeds = np.asarray(self.speeds, dtype=np.float64)
        if times.ndim != 1 or times.shape != speeds.shape or times.size < 1:
            raise ValueError("RotorTerms.times and speeds must be equally long, non-empty")
        if not (np.all(np.isfinite(times)) and np.all(np.isfinite(speeds))):
            raise ValueError("RotorTerms.times and speeds must be finite")
        if np.any(np.diff(times) <= 0):
            raise ValueError("RotorTerms.times must increase strictly")
        if self.source == "rotation" and self.speed_weights is None:
            raise ValueError("RotorTerms.speed_weights is needed with source 'rotation'")
        if self.unbalances and self.source != "profile":
            raise ValueError("RotorTerms.unbalances need a prescribed speed profile")
        for u in self.unbalances:
            if not math.isfinite(u.mass_eccentricity):
                raise ValueError("Unbalance.mass_eccentricity must be finite")

    def skew_entries(self, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Rows i < j, columns j and values G(i, j) of the skew part of G (0-based)."""
        if self.gyroscopic is None:
            empty = np.zeros(0, dtype=int)
            return empty, empty, np.zeros(0)
        g = self.gyroscopic
        if hasattr(g, "tocoo"):
            g = g.tocsr()
            skew = (0.5 * (g - g.T)).tocoo()
            rows, columns, values = skew.row, skew.col, skew.data
        else:
            dense = np.asarray(g, dtype=np.float64)
            skew = 0.5 * (dense - dense.T)
            rows, columns = np.nonzero(skew)
            values = skew[rows, columns]
        if (rows.size and (rows.max() >= n or columns.max() >= n)) or g.shape != (n, n):
            raise ValueError(f"RotorTerms.gyroscopic must be {n} x {n}")
        upper = (rows < columns) & (values != 0)
        return rows[upper], columns[upper], np.asarray(values[upper], dtype=np.float64)


def rotor_arguments(terms: RotorTerms, position: np.ndarray) -> dict:
    """The keyword arguments of ``transient_problem_set_rotor`` for a problem whose
    DOF ``i`` sits at kernel position ``position[i]`` (0-based)."""
    n = len(position)
    rows, columns, values = terms.skew_entries(n)
    stored = max(rows.size, 1)
    row = np.ones(stored, np.int32)
    column = np.full(stored, 2 if n > 1 else 1, np.int32)
    value = np.zeros(stored)
    row[: rows.size] = position[rows] + 1
    column[: rows.size] = position[columns] + 1
    value[: rows.size] = values
    if terms.source == "rotation":
        w = np.asarray(terms.speed_weights, dtype=np.float64)
        (nz,) = np.nonzero(w)
        speed_index = (position[nz] + 1).astype(np.int32) if nz.size else np.ones(1, np.int32)
        speed_value = w[nz] if nz.size else np.zeros(1)
    else:
        speed_index, speed_value = np.ones(1, np.int32), np.zeros(1)
    count = len(terms.unbalances)
    dofs = np.ones((2, max(count, 1)), np.int32, order="F")
    data = np.zeros((3, max(count, 1)), order="F")
    for u, unbalance in enumerate(terms.unbalances):
        dofs[:, u] = position[[unbalance.x, unbalance.y]] + 1
        data[:, u] = (unbalance.mass_eccentricity, unbalance.angle, unbalance.ratio)
    return {
        "n_entries": rows.size,
        "row": row,
        "column": column,
        "value": value,
        "source": SPEED_SOURCES[terms.source],
        "profile": np.asfortranarray(np.array([terms.times, terms.speeds], dtype=np.float64)),
        "speed_index": speed_index,
        "speed_value": np.asarray(speed_value, dtype=np.float64),
        "n_unbalance": count,
        "unbalance_dof": dofs,
        "unbalance": data,
    }
