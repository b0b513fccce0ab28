"""Duty cycles and damage: rainflow counting (ASTM E1049-85), S-N curves of ISO 6336-6
and the Palmgren-Miner sum.

* :func:`rainflow_cycles` counts a load history with the maintained ``rainflow``
  package (ASTM E1049-85 section 5.4.4): (range, mean, count) with half cycles 0.5.
* :func:`load_spectrum_from_series` turns a mesh-force time series into ISO 6336-6's
  load spectrum: every tooth contact is one load cycle at the force of that instant,
  so the force is binned and each bin counts its time times the contact frequency.
* :func:`cycles_to_failure` inverts the S-N curve that ISO 6336-6 builds from the life
  factors Z_NT / Y_NT of ISO 6336-2/-3 (knees and slopes of their tables, the last
  slope continued past 1e10 cycles).
* :func:`miner_damage` sums n_i / N_i.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from ...errors import CaseError
from . import factors as iso

__all__ = [
    "cycles_to_failure",
    "load_spectrum_from_series",
    "miner_damage",
    "rainflow_cycles",
    "sn_curve",
]


def rainflow_cycles(series: Sequence[float]) -> list[tuple[float, float, float]]:
    """(range, mean, count) of every cycle of ``series`` by ASTM E1049-85 rainflow
    counting (count 1.0 for a full cycle, 0.5 for a half cycle).

    Raises
    ------
    CaseError
        For a series of fewer than two finite values.
    """
    import rainflow

    values = np.asarray(series, dtype=float)
    if values.ndim != 1 or values.size < 2 or not np.all(np.isfinite(values)):
        raise CaseError("series must be a 1-D sequence of at least two finite values")
    return [(float(r), float(m), float(c)) for r, m, c, *_ in rainflow.extract_cycles(values)]


def load_spectrum_from_series(
    time: Sequence[float], force: Sequence[float], contact_frequency: float, bins: int = 32
) -> tuple[np.ndarray, np.ndarray]:
    """(force levels [N], tooth load cycles) of a mesh-force record.

    Each sample stands for half the interval to each neighbour; a bin's cycles are its
    time times the tooth contact frequency [Hz] (ISO 6336-6's counting of the load at
    each contact).  Levels
    are the bins' upper edges, so every cycle is counted at a load it never exceeds.
    """
    t = np.asarray(time, dtype=float)
    f = np.abs(np.asarray(force, dtype=float))
    if t.shape != f.shape or t.ndim != 1 or t.size < 2:
        raise CaseError("time and force must be 1-D of the same length >= 2")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(f))):
        raise CaseError("time and force must be finite")
    if np.any(np.diff(t) <= 0.0):
        raise CaseError("time must increase strictly")
    if not (math.isfinite(contact_frequency) and contact_frequency > 0.0):
        raise CaseError(f"contact_frequency must be > 0 Hz (got {contact_frequency})")
    step = np.empty_like(t)  # each sample stands for half the interval on each side
    step[1:-1] = 0.5 * (t[2:] - t[:-2])
    step[0] = 0.5 * (t[1] - t[0])
    step[-1] = 0.5 * (t[-1] - t[-2])
    edges = np.linspace(0.0, float(f.max()) * (1.0 + 1e-12), bins + 1)
    index = np.clip(np.searchsorted(edges, f, side="left") - 1, 0, bins - 1)
    time_in = np.bincount(index, weights=step, minlength=bins)
    keep = time_in > 0.0
    return edges[1:][keep], time_in[keep] * contact_frequency


def sn_curve(kind: str, reference: float, root: bool) -> Callable[[float], float]:
    """The S-N curve sigma(N) = reference x life factor(N) of ISO 6336-6: ``reference``
    is the strength at life factor 1 (sigma_hlim Z_L Z_v Z_R Z_W Z_X, or sigma_flim Y_ST
    Y_delta Y_R Y_X Y_M) [MPa]."""
    return lambda cycles: reference * iso.life_factor(kind, cycles, root)


def cycles_to_failure(kind: str, stress: float, reference: float, root: bool) -> float:
    """N at which the S-N curve of :func:`sn_curve` reaches ``stress``.

    Above the static limit (the curve's first knee) the part fails in the first knee's
    cycle count; below the last knee the last slope continues (no endurance limit, as
    ISO 6336-6 asks for damage sums).
    """
    if stress <= 0.0:
        return math.inf
    knees = iso.life_knees(kind, root)
    ratio = stress / reference
    if ratio >= knees[0][1]:
        return knees[0][0]
    for (n0, y0), (n1, y1) in zip(knees[:-1], knees[1:]):
        if ratio >= y1 or (n1, y1) == knees[-1]:
            slope = math.log(y1 / y0) / math.log(n1 / n0)
            return n0 * (ratio / y0) ** (1.0 / slope)
    raise AssertionError("unreachable")


def miner_damage(stresses: Sequence[float], cycles: Sequence[float],
                 life: Callable[[float], float]) -> float:
    """Palmgren-Miner damage D = sum n_i / N_i with N_i = life(stress_i)."""
    total = 0.0
    for stress, count in zip(stresses, cycles):
        if count > 0.0:
            total += count / life(stress)
    return total
