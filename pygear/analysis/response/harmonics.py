r"""The frequency-domain rung of the accuracy ladder: harmonic count against error and cost.

The balance of :mod:`.hill` converges in the harmonic count H: a stiffness that jumps
where a tooth pair enters or leaves contact has Fourier coefficients ~ 1/j, the mesh
deflection ~ 1/j^3, so the mesh forces of H harmonics approach the periodic steady
state roughly as H^-2.  :func:`harmonics_ladder` balances every speed of a response at
H = 2, 4, ..., and at a reference count (twice the largest), times each count, and
measures against the reference:

- the mesh-force error: max over the period and the meshes of |F_H - F_ref| over the
  largest reference mesh force at that speed (the quantity the response's tolerance
  speaks of: docs/response.md, "Harmonic count and residual");
- the dynamic-factor error: max over the meshes of |K_v,H - K_v,ref| / K_v,ref;
- the residual the automatic count reads (the deflection harmonics H+1..2H would add).

A speed is judged only where the reference's own error is small against the
tolerance.  On the study case the error falls as H^-2 (a factor 3.7-4.3 per doubling
at 1675 and 2400 rpm), so the reference's error is about a third of its change from
half its count (the ladder's largest count); a speed is judged where that change is at
most :data:`JUDGED_SHARE` of the tolerance, i.e. the reference's error at most a tenth
of it.  :func:`recommend_harmonics` then picks the smallest H whose error meets the
tolerance at every judged speed.
"""

from __future__ import annotations

import contextlib
import time

import numpy as np
import xarray as xr

from ...errors import CaseError
from .hill import AUTO_HARMONICS, fourier_coefficients, mesh_signals, solve_hill
from .system import ResponseSystem

__all__ = [
    "JUDGED_SHARE",
    "LADDER",
    "harmonics_ladder",
    "harmonics_table_text",
    "recommend_harmonics",
]

LADDER = AUTO_HARMONICS
"""Harmonic counts of the ladder, as the automatic count tries them (2 to 128)."""

JUDGED_SHARE = 0.3
"""A speed is judged where the reference changes from the ladder's largest count by at
most this share of the tolerance: with the H^-2 convergence the reference's own error,
about a third of that change, then stays within a tenth of the tolerance."""


def _thread_limit() -> contextlib.AbstractContextManager:
    """One BLAS thread, as the sweep runs (:mod:`.sweep`), so the times compare."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - a dependency
        return contextlib.nullcontext()
    return threadpool_limits(1, user_api="blas")


def _forces(system: ResponseSystem, omega: float, count: int, coefficients: np.ndarray):
    solution = solve_hill(system, omega, count, coefficients)
    _, force = mesh_signals(system, solution)
    return force, solution.residual


def harmonics_ladder(
    system: ResponseSystem,
    speeds: np.ndarray,
    counts: tuple[int, ...] = LADDER,
    reference: int | None = None,
) -> xr.Dataset:
    """Error and wall time of every harmonic count at every speed.

    Parameters
    ----------
    system : ResponseSystem
        The model (:func:`.response_system`).
    speeds : array_like
        Input member speeds [rpm], > 0.
    counts : tuple of int
        Harmonic counts of the ladder, increasing, >= 1.
    reference : int, optional
        Count of the reference (default twice the largest count).

    Returns
    -------
    xarray.Dataset
        Over ``harmonics`` and ``speed``: ``mesh_force_error``, ``dynamic_factor_error``,
        ``residual``; ``wall_time`` per count (all speeds, one thread); ``judged`` and
        ``reference_change`` (the largest count's error) per speed.
    """
    speeds = np.asarray(speeds, dtype=np.float64).reshape(-1)
    if speeds.size == 0 or not np.all(np.isfinite(speeds) & (speeds > 0)):
        raise CaseError("speeds must be finite and > 0 rpm")
    if system.groups > 1:
        raise CaseError(
            f"the harmonic ladder balances one mesh frequency; {system.attrs.get('case', '')!r} "
            f"has {system.groups} frequency groups (pygear response reports each speed's "
            "residual instead)"
        )
    counts = tuple(int(c) for c in counts)
    if not counts or counts[0] < 1 or any(b <= a for a, b in zip(counts, counts[1:])):
        raise CaseError(f"harmonic counts must increase from >= 1 (got {counts!r})")
    reference = 2 * counts[-1] if reference is None else int(reference)
    if reference <= counts[-1]:
        raise CaseError(f"the reference count {reference} must exceed the ladder's {counts[-1]}")
    coefficients = fourier_coefficients(system.stiffness_variation, 3 * reference)
    shape = (len(counts), speeds.size)
    force_error, kv_error, residual = np.empty(shape), np.empty(shape), np.empty(shape)
    wall = np.zeros(len(counts))
    started = time.perf_counter()
    with _thread_limit():
        for j, speed in enumerate(speeds):
            omega = system.omega(float(speed))
            ref, _ = _forces(system, omega, reference, coefficients)
            scale = np.abs(ref).max()
            ref_kv = ref.max(axis=0) / ref.mean(axis=0)
            for i, count in enumerate(counts):
                tick = time.perf_counter()
                force, residual[i, j] = _forces(system, omega, count, coefficients)
                wall[i] += time.perf_counter() - tick
                force_error[i, j] = np.abs(force - ref).max() / scale
                kv = force.max(axis=0) / force.mean(axis=0)
                kv_error[i, j] = np.abs(kv / ref_kv - 1.0).max()
    data = {
        "mesh_force_error": (("harmonics", "speed"), force_error,
                             {"units": "1", "long_name": "largest mesh-force difference from "
                              "the reference over the largest reference mesh force"}),
        "dynamic_factor_error": (("harmonics", "speed"), kv_error,
                                 {"units": "1", "long_name": "largest relative dynamic-factor "
                                  "difference from the reference"}),
        "residual": (("harmonics", "speed"), residual,
                     {"units": "1", "long_name": "residual of the balance (deflection of "
                      "harmonics H+1..2H over the largest static mesh deflection)"}),
        "wall_time": ("harmonics", wall,
                      {"units": "s", "long_name": "wall time of the balance and the mesh "
                       "forces over every speed, one BLAS thread"}),
        "reference_change": ("speed", force_error[-1],
                             {"units": "1", "long_name": "the reference's change from the "
                              "ladder's largest count (bounds its own error)"}),
    }  # fmt: skip
    coords = {
        "harmonics": ("harmonics", np.array(counts, dtype=np.int32),
                      {"units": "1", "long_name": "harmonics H balanced"}),
        "speed": ("speed", speeds, {"units": "rpm", "long_name": "input member speed"}),
    }  # fmt: skip
    attrs = {
        **system.attrs,
        "reference_harmonics": reference,
        "ladder_wall_s": time.perf_counter() - started,
        "method": "harmonic balance at each count against a reference count",
    }
    return xr.Dataset(data, coords, attrs)


def recommend_harmonics(ladder: xr.Dataset, tolerance: float) -> xr.Dataset:
    """Judge the ladder at ``tolerance`` and name the smallest count that meets it.

    Adds ``judged`` (per speed: the reference's change from the largest count is at
    most :data:`JUDGED_SHARE` of the tolerance) and the
    attributes ``tolerance``, ``recommended_harmonics`` (-1: no count meets it at every
    judged speed, or no speed is judged), ``recommended_max_error`` and
    ``recommended_wall_time``.
    """
    if not (np.isfinite(tolerance) and tolerance > 0):
        raise CaseError(f"--tolerance must be > 0 (got {tolerance!r})")
    judged = ladder.reference_change.values <= JUDGED_SHARE * tolerance
    worst = np.where(judged[None, :], ladder.mesh_force_error.values, 0.0).max(axis=1)
    meets = np.flatnonzero(worst <= tolerance) if judged.any() else np.array([], dtype=int)
    out = ladder.copy()
    out["judged"] = ("speed", judged.astype(np.int8),
                     {"units": "1", "long_name": "1 where the reference's change from the "
                      "largest count is within 0.3 of the tolerance (judged)"})  # fmt: skip
    out["max_judged_error"] = ("harmonics", worst,
                               {"units": "1", "long_name": "largest mesh-force error over the "
                                "judged speeds"})  # fmt: skip
    best = int(meets[0]) if meets.size else -1
    out.attrs.update(
        tolerance=float(tolerance),
        recommended_harmonics=int(ladder.harmonics.values[best]) if best >= 0 else -1,
        recommended_max_error=float(worst[best]) if best >= 0 else float("nan"),
        recommended_wall_time=float(ladder.wall_time.values[best]) if best >= 0 else float("nan"),
        speeds_judged=int(judged.sum()),
    )
    return out


def harmonics_table_text(ladder: xr.Dataset) -> str:
    """The judged ladder (:func:`recommend_harmonics`) as the table ``pygear accuracy``
    prints: per count the largest error over the judged speeds, the median, the largest
    residual and the wall time, the recommended count marked."""
    attrs = ladder.attrs
    tolerance = attrs["tolerance"]
    judged = ladder.judged.values > 0
    lines = [
        f"{attrs.get('case', '')} / {attrs.get('scene', '')}: harmonic count against the "
        f"reference H = {attrs['reference_harmonics']} at {ladder.sizes['speed']} speeds "
        f"({int(judged.sum())} judged: the reference changes by at most "
        f"{JUDGED_SHARE * tolerance:.2g} from H = {int(ladder.harmonics.values[-1])})",
        f"{'H':>5} {'max error':>10} {'median':>10} {'max K_v err':>11} {'residual':>10} "
        f"{'wall [s]':>9}",
    ]
    for i, count in enumerate(ladder.harmonics.values):
        errors = ladder.mesh_force_error.values[i]
        kv = ladder.dynamic_factor_error.values[i]
        median = float(np.median(errors[judged])) if judged.any() else float("nan")
        worst_kv = float(kv[judged].max()) if judged.any() else float("nan")
        mark = "  <- recommended" if count == attrs["recommended_harmonics"] else ""
        lines.append(
            f"{int(count):>5} {ladder.max_judged_error.values[i]:>10.2e} {median:>10.2e} "
            f"{worst_kv:>11.2e} {ladder.residual.values[i].max():>10.2e} "
            f"{ladder.wall_time.values[i]:>9.3f}{mark}"
        )
    if attrs["recommended_harmonics"] < 0:
        lines.append(f"no count of the ladder meets {tolerance:g} at every judged speed"
                     if judged.any() else "no speed judged: the reference itself has not "
                     "converged well enough; raise the ladder (--levels)")  # fmt: skip
    else:
        lines.append(f"recommended: --harmonics {attrs['recommended_harmonics']} (largest "
                     f"error {attrs['recommended_max_error']:.2e} <= {tolerance:g}, "
                     f"{attrs['recommended_wall_time']:.3f} s for the speeds)")  # fmt: skip
    unjudged = ladder.speed.values[~judged]
    if unjudged.size:
        lines.append(f"not judged ({unjudged.size} speeds, {unjudged.min():g} to "
                     f"{unjudged.max():g} rpm): the reference changes by more than the "
                     f"share {JUDGED_SHARE:g} of the tolerance there")  # fmt: skip
    return "\n".join(lines)
