"""Modes followed from speed to speed by their shapes, not by their frequency order.

A mode keeps its number from one speed to the next through the mass-weighted modal
assurance criterion, MAC = |a^H M b|^2 / ((a^H M a)(b^H M b)) (Allemang & Brown 1982):

- every mode at the last speed is scored against every mode at the next (either member
  of its conjugate pair: a frequency may pass through zero in a carrier frame) by its
  MAC less :data:`JUMP_WEIGHT` times the eigenvalue jump over the speed step, and the
  one-to-one assignment of highest total score is taken (Hungarian algorithm).  The
  jump term keeps a forward mode from continuing as the conjugate of its backward twin,
  which has nearly its shape but an eigenvalue 2 omega away;
- where several modes share one eigenvalue (a translational pair at zero speed, the
  planet modes of equally spaced planets) any basis of their span is a set of modes;
  the basis is first turned to face the modes across the step;
- a step is ambiguous when an assigned MAC is below :data:`MAC_ACCEPT` or another
  candidate scores within :data:`MAC_MARGIN` of it; it is then halved, up to
  :data:`REFINE_DEPTH` times, and tracked through the midpoints.  A step still
  ambiguous at the smallest substep (two modes coalescing into a flutter pair, where
  their shapes become one) is tracked as found and marked.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence

import numpy as np
import scipy.optimize

from .gyroscopic import SpeedModes, mass_weighted_mac

__all__ = ["MAC_ACCEPT", "MAC_MARGIN", "REFINE_DEPTH", "ModeTracker", "Tracking"]

MAC_ACCEPT = 0.8
"""An assigned MAC below this makes a step ambiguous."""

MAC_MARGIN = 0.3
"""A second candidate within this of the assigned MAC makes a step ambiguous."""

REFINE_DEPTH = 5
"""Halvings of an ambiguous step (down to 1/32 of it)."""

JUMP_WEIGHT = 0.05
"""Score lost per unit of eigenvalue jump [rad/s] over speed step [rad/s]."""

DEGENERATE = 1e-7
"""Eigenvalues within this fraction of omega_s count as one (a repeated frequency)."""


@dataclasses.dataclass
class Tracking:
    """Modes tracked over speeds: ``modes[k]`` holds the modes at ``speeds[k]`` with
    column m the tracked mode m; ``mac[k, m]`` its MAC with the previous speed's (the
    lowest over refined substeps; 1 at the first speed); ``ambiguous[k]`` whether the
    step to speed k stayed ambiguous after refinement."""

    speeds: np.ndarray
    modes: list[SpeedModes]
    mac: np.ndarray
    ambiguous: np.ndarray
    refinements: int


class ModeTracker:
    """Solves the modes at a speed (cached) and carries mode numbers across steps.

    Parameters
    ----------
    solve : callable
        speed [rpm] -> :class:`~pygear.analysis.modes.gyroscopic.SpeedModes`.
    mass : ndarray
        The mass matrix the MAC is weighted with.
    """

    def __init__(self, solve: Callable[[float], SpeedModes], mass: np.ndarray) -> None:
        self._solve = solve
        self.mass = mass
        self.cache: dict[float, SpeedModes] = {}
        self.refinements = 0

    def solve(self, speed: float) -> SpeedModes:
        """The modes at ``speed`` [rpm] (each speed solved once)."""
        if speed not in self.cache:
            self.cache[speed] = self._solve(speed)
        return self.cache[speed]

    def unstable(self, speed: float) -> bool:
        """Whether any mode grows at ``speed``."""
        return bool(np.isin(self.solve(speed).stability, (1, 2)).any())

    def track(self, speeds: Sequence[float]) -> Tracking:
        """Modes at every speed, numbered by the first speed's frequency order."""
        speeds = np.asarray(speeds, dtype=float)
        first = self.solve(float(speeds[0]))
        tracked = [first]
        macs = [np.ones(first.eigenvalues.size)]
        ambiguous = [False]
        for start, stop in zip(speeds[:-1], speeds[1:]):
            turned, modes, mac, unclear = self._advance(tracked[-1], float(start), float(stop), 0)
            tracked[-1] = turned  # a repeated eigenvalue's basis, turned to face the step
            tracked.append(modes)
            macs.append(mac)
            ambiguous.append(unclear)
        return Tracking(speeds, tracked, np.array(macs), np.array(ambiguous), self.refinements)

    def _advance(
        self, previous: SpeedModes, start: float, stop: float, depth: int
    ) -> tuple[SpeedModes, SpeedModes, np.ndarray, bool]:
        """``previous`` (at ``start``) with its repeated eigenvalues' bases turned, the
        modes at ``stop`` numbered as it, their MACs and whether the step stayed
        ambiguous."""
        step = abs(stop - start) * math.pi / 30.0
        turned, ordered, mac, clear = _assign(self.mass, previous, self.solve(stop), step)
        if clear or depth >= REFINE_DEPTH:
            return turned, ordered, mac, not clear
        self.refinements += 1
        middle = 0.5 * (start + stop)
        turned, halfway, mac_first, unclear_first = self._advance(
            previous, start, middle, depth + 1
        )
        _, ordered, mac_second, unclear_second = self._advance(halfway, middle, stop, depth + 1)
        return turned, ordered, np.minimum(mac_first, mac_second), unclear_first or unclear_second


def _clusters(modes: SpeedModes) -> list[np.ndarray]:
    """Groups of modes sharing one eigenvalue (within :data:`DEGENERATE` of omega_s)."""
    values = modes.eigenvalues
    order = np.lexsort((values.real, values.imag))
    groups: list[list[int]] = []
    for index in order:
        if groups and abs(values[index] - values[groups[-1][0]]) <= DEGENERATE * modes.scale:
            groups[-1].append(int(index))
        else:
            groups.append([int(index)])
    return [np.array(g) for g in groups]


def _face(mass: np.ndarray, modes: SpeedModes, towards: np.ndarray) -> SpeedModes:
    """Turn the basis of every repeated eigenvalue of ``modes`` to face ``towards``.

    Within a group of modes sharing one eigenvalue any basis is a set of modes; the
    shapes of ``towards`` that project most onto the group's span, projected onto it
    (M-orthogonally), become its basis.  Each new basis vector takes the place of the
    old one it resembles most, so a mode that already has a number keeps it."""
    shapes = modes.shapes.copy()
    for group in _clusters(modes):
        if group.size < 2:
            continue
        basis = shapes[:, group]
        gram = basis.conj().T @ mass @ basis
        coefficients = np.linalg.solve(gram, basis.conj().T @ mass @ towards)
        share = np.einsum("km,kl,lm->m", coefficients.conj(), gram, coefficients).real
        share /= np.einsum("im,im->m", towards.conj(), mass @ towards).real
        chosen = np.argsort(-share, kind="stable")[: group.size]
        turned = basis @ coefficients[:, chosen]
        if np.linalg.matrix_rank(turned, tol=1e-8 * np.abs(turned).max()) < group.size:
            continue
        turned = _m_orthonormal(mass, turned)
        overlap = mass_weighted_mac(mass, basis, turned)
        rows, columns = scipy.optimize.linear_sum_assignment(-overlap)
        shapes[:, group[rows]] = turned[:, columns]
    return dataclasses.replace(modes, shapes=shapes)


def _m_orthonormal(mass: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Gram-Schmidt in the M inner product, in the vectors' order."""
    out = vectors.astype(complex).copy()
    for k in range(out.shape[1]):
        for j in range(k):
            out[:, k] -= (out[:, j].conj() @ mass @ out[:, k]) * out[:, j]
        out[:, k] /= math.sqrt((out[:, k].conj() @ mass @ out[:, k]).real)
    return out


def _assign(
    mass: np.ndarray, previous: SpeedModes, following: SpeedModes, step: float
) -> tuple[SpeedModes, SpeedModes, np.ndarray, bool]:
    """``previous`` with its repeated eigenvalues' bases turned towards ``following``,
    ``following`` renumbered to match it, the assigned MACs, and whether the
    assignment is clear.

    Each mode of ``following`` stands for a conjugate pair; either member may continue
    a mode of ``previous`` (a frequency passing through zero in the carrier frame comes
    back as the conjugate).  A candidate's score is its MAC less
    :data:`JUMP_WEIGHT` times its eigenvalue jump over the speed step ``step`` [rad/s],
    which keeps a forward mode from continuing as the conjugate of its backward twin
    (alike in shape, an eigenvalue 2 omega away)."""
    previous = _face(mass, previous, following.shapes)
    following = _face(mass, following, previous.shapes)
    step = max(step, 1e-12 * previous.scale)
    scores, macs = [], []
    for values, shapes in (
        (following.eigenvalues, following.shapes),
        (following.eigenvalues.conj(), following.shapes.conj()),
    ):
        mac = mass_weighted_mac(mass, previous.shapes, shapes)
        jump = np.abs(previous.eigenvalues[:, None] - values[None, :])
        scores.append(mac - JUMP_WEIGHT * jump / step)
        macs.append(mac)
    conjugate = scores[1] > scores[0]
    score = np.where(conjugate, scores[1], scores[0])
    mac = np.where(conjugate, macs[1], macs[0])
    rows, columns = scipy.optimize.linear_sum_assignment(-score)
    order = columns[np.argsort(rows)]
    index = np.arange(mac.shape[0])
    assigned = mac[index, order]
    best = score[index, order]
    others = score.copy()
    others[index, order] = -np.inf
    rival = others.max(axis=1) if mac.shape[1] > 1 else np.full(mac.shape[0], -np.inf)
    clear = bool(np.all(assigned >= MAC_ACCEPT) and np.all(best - rival >= MAC_MARGIN))
    flip = conjugate[index, order]
    values = following.eigenvalues[order]
    shapes = following.shapes[:, order]
    ordered = SpeedModes(
        np.where(flip, values.conj(), values),
        np.where(flip, shapes.conj(), shapes),
        following.rigid[order],
        following.scale,
    )
    return previous, ordered, assigned, clear
