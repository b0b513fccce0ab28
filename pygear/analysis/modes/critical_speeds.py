"""Undamped critical speeds of a rotor or drivetrain, and their map against the bearings'
stiffness.

A mode crosses a shaft's 1x line (frequency r |Omega| for a shaft turning at r times
the rotor) where M q'' + Omega G q' + (K - Omega^2 K_Omega) q = 0 has the eigenvalue
lambda = i r Omega.  Put in, that is the linear eigenproblem in Omega^2

    K phi = Omega^2 (r^2 M - i r G + K_Omega) phi,

whose right-hand matrix is Hermitian (G is skew) but not always definite: a disc whose
polar inertia exceeds its diametral one has no forward conical critical speed (a
negative Omega^2, left out).  Each positive root is one synchronous critical speed,
found directly rather than by the crossings of a Campbell diagram's grid; the root's
shape says whether the crossing mode whirls forward or backward.  Damping is left out
(an undamped map, API 684 §1.3.2 and Friswell, Penny, Garvey & Lees, *Dynamics of
Rotating Machines*, 2010, §5.9); the bearings' coefficient tables and radial damping
with it.

The map sets the radial stiffness of every shaft bearing of the case to one value k,
isotropic (k_xx = k_yy = k, no cross-coupling), over a range of k: K(k) = K_0 + k K_1,
both assembled once.  Its soft end holds the rigid rotor on springs, its stiff end the
rigid-bearing limit of the shaft's bending.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
import scipy.linalg
import xarray as xr

from ...errors import CaseError
from .gyroscopic import SpeedModes
from .sparse_gyroscopic import _structure_groups, whirl_and_kind

__all__ = ["MAX_DOFS", "critical_speed_map", "synchronous_critical_speeds"]

MAX_DOFS = 3000
"""Largest model the dense solver of the map takes."""

NULL_SPACE = 1e-12
"""A singular value of K below this fraction of its largest is a free rigid-body motion."""


def synchronous_critical_speeds(
    mass: np.ndarray,
    stiffness: np.ndarray,
    gyroscopic: np.ndarray,
    count: int,
    *,
    line_ratio: float = 1.0,
    centripetal: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` lowest speeds [rad/s of the rotor] where a mode crosses the line
    f = line_ratio |Omega| / 2 pi, and their shapes (columns).

    Parameters
    ----------
    mass, stiffness, gyroscopic : ndarray
        M, K and G per unit rotor speed (dense).
    count : int
        How many (fewer when the model has fewer).
    line_ratio : float
        The line's speed over the rotor's, > 0.
    centripetal : ndarray, optional
        K_Omega per unit rotor speed squared (the softening is -Omega^2 K_Omega).
    """
    r = float(line_ratio)
    right = r * r * mass - 1j * r * gyroscopic
    if centripetal is not None:
        right = right + centripetal
    # K is positive semi-definite and the right-hand matrix Hermitian, so every finite
    # root is real: an imaginary part is round-off (relative to the largest root, which
    # near-massless nodes make large), and the real part is kept.  The free rigid-body
    # motions are K's null space, counted from its singular values and removed as the
    # roots nearest zero.
    singular = np.linalg.svd(stiffness, compute_uv=False)
    rigid = int(np.sum(singular < NULL_SPACE * singular.max(initial=0.0)))
    values, vectors = scipy.linalg.eig(stiffness, right)
    finite = np.flatnonzero(np.isfinite(values))
    finite = finite[np.argsort(np.abs(values[finite]))][rigid:]
    roots = values.real[finite]
    positive = finite[roots > 0]
    chosen = positive[np.argsort(values.real[positive])][:count]
    return np.sqrt(values.real[chosen]), vectors[:, chosen]


def critical_speed_map(
    case: Any,
    stiffness_values: np.ndarray,
    count: int = 4,
) -> xr.Dataset:
    """Undamped synchronous critical speeds against the shaft bearings' radial stiffness.

    Parameters
    ----------
    case : Case
        A rotor or drivetrain case with at least one shaft bearing.
    stiffness_values : array of float
        Radial stiffness k [N/m] every shaft bearing takes in turn, > 0.
    count : int
        Critical speeds per value and 1x line (the lowest).

    Returns
    -------
    xarray.Dataset
        ``critical_speed`` [rpm of the rotor] over (``bearing_stiffness``, ``line``,
        ``critical``), NaN where fewer exist; ``whirl`` and ``kind`` of each; the 1x
        lines' speed ratios and shafts over ``line``.
    """
    from ...assembly.drivetrain import assemble_drivetrain
    from ...assembly.speed_terms import drivetrain_frame_terms

    values = np.asarray(stiffness_values, dtype=float).ravel()
    if values.size < 1 or not np.all(np.isfinite(values)) or np.any(values <= 0):
        raise CaseError("--critical-speed-map stiffnesses must be finite and > 0 N/m")
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
        raise CaseError(f"--modes must be a whole number >= 1 (got {count!r})")
    bearings = case.drivetrain.bearings
    if not bearings:
        raise CaseError(
            "drivetrain.bearings: the critical-speed map varies the shaft "
            "bearings' stiffness, and this case has none"
        )

    def with_radial(k: float):
        changed = tuple(
            dataclasses.replace(b, radial=k, radial_damping=0.0, coefficients=None)
            for b in bearings
        )
        drivetrain = dataclasses.replace(case.drivetrain, bearings=changed)
        return dataclasses.replace(case, drivetrain=drivetrain)

    free_case = with_radial(0.0)
    free = assemble_drivetrain(free_case, dof_set="spatial")
    if free.size > MAX_DOFS:
        raise CaseError(
            f"--critical-speed-map solves densely up to {MAX_DOFS} DOFs "
            f"(this model has {free.size})"
        )
    unit = assemble_drivetrain(with_radial(1.0), dof_set="spatial")
    mass = free.mass.toarray()
    base = free.stiffness.toarray()
    per_stiffness = unit.stiffness.toarray() - base
    gyroscopic = free.gyroscopic.toarray()
    centripetal = None
    frame_terms = drivetrain_frame_terms(free, free_case)
    if frame_terms is not None:
        gyroscopic = gyroscopic + frame_terms.gyroscopic.toarray()
        centripetal = frame_terms.centripetal.toarray()
    lines: dict[float, list[str]] = {}
    for shaft, ratio in free.speed_ratios.items():
        lines.setdefault(round(abs(ratio), 12), []).append(shaft)
    ratios = sorted(lines)
    speeds = np.full((values.size, len(ratios), count), np.nan)
    whirl = np.full(speeds.shape, "", dtype=object)
    kind = np.full(speeds.shape, "", dtype=object)
    for i, k in enumerate(values):
        stiffness = base + k * per_stiffness
        for j, ratio in enumerate(ratios):
            omega, shapes = synchronous_critical_speeds(
                mass, stiffness, gyroscopic, count, line_ratio=ratio, centripetal=centripetal
            )
            if omega.size == 0:
                continue
            shapes = _split_repeated(free, omega, shapes)
            found = SpeedModes(1j * ratio * omega, shapes, np.zeros(omega.size, bool), 1.0)
            _, names, kinds = whirl_and_kind(free, found, 1.0)
            speeds[i, j, : omega.size] = omega * 30.0 / math.pi
            whirl[i, j, : omega.size] = names
            kind[i, j, : omega.size] = kinds
    dims = ("bearing_stiffness", "line", "critical")

    def var(dims, data, units, long_name):
        return dims, data, {"units": units, "long_name": long_name}

    return xr.Dataset(
        {
            "critical_speed": var(
                dims,
                speeds,
                "rpm",
                "undamped synchronous critical speed (rotor speed where the mode crosses the line)",
            ),
            "whirl": var(dims, whirl, "1", "whirl of the crossing mode seen from the ground"),
            "kind": var(dims, kind, "1", "lateral, axial or torsional"),
            "line_shafts": var(
                ("line",),
                np.array([" ".join(lines[r]) for r in ratios], dtype=object),
                "1",
                "shafts of the 1x line",
            ),
        },
        coords={
            "bearing_stiffness": var(
                ("bearing_stiffness",), values, "N/m", "radial stiffness of every shaft bearing"
            ),
            "line": var(
                ("line",), np.array(ratios, dtype=float), "1", "1x line's speed over the rotor's"
            ),
            "critical": var(
                ("critical",), np.arange(1, count + 1), "1", "critical speed number, ascending"
            ),
        },
        attrs={
            "case": case.name,
            "dofs": free.size,
            "bearings": ", ".join(b.name for b in bearings),
            "method": "K phi = Omega^2 (r^2 M - i r G + K_Omega) phi per 1x line r; "
            "undamped, isotropic bearings",
        },
    )


REPEATED = 1e-7
"""Critical speeds this close (relative) are one repeated root."""


def _split_repeated(model: Any, omega: np.ndarray, shapes: np.ndarray) -> np.ndarray:
    """Shapes of a repeated critical speed turned into its forward and backward circles.

    An axisymmetric mode that the spin does not touch (a disc translating at the middle
    of a symmetric shaft) crosses the 1x line with both circles at one speed; the solver
    returns any two combinations of them.  Within each repeated root the Hermitian form
    of the shaft nodes' whirl, sum of s w (|x + i y|^2 - |x - i y|^2), is diagonalised
    against M, which gives back the pure circles."""
    groups = _structure_groups(model)
    n = shapes.shape[0]
    whirl = np.zeros((n, n), dtype=complex)
    weights = np.asarray(model.mass.diagonal())[groups["x"]]
    sense = np.where(groups["ratio"] >= 0, 1.0, -1.0)
    for a, b, w, s in zip(groups["x"], groups["y"], weights, sense):
        whirl[a, b] += 2j * w * s  # |x + iy|^2 - |x - iy|^2 = 2i (conj(x) y - conj(y) x)
        whirl[b, a] -= 2j * w * s
    mass = model.mass.toarray()
    out = shapes.copy()
    start = 0
    while start < omega.size:
        stop = start + 1
        while stop < omega.size and omega[stop] - omega[start] <= REPEATED * omega[start]:
            stop += 1
        if stop - start > 1:
            basis = shapes[:, start:stop]
            _, turn = scipy.linalg.eigh(
                basis.conj().T @ whirl @ basis, basis.conj().T @ mass @ basis
            )
            out[:, start:stop] = basis @ turn
        start = stop
    return out
