r"""Newton's method and pseudo-arclength continuation of R(x, p) = 0 in one parameter.

The branch of solutions (x(s), p(s)) is followed by arclength s in scaled variables
(x / x_scale, p / p_scale), so a branch that folds back in p (a turning point, where
the Jacobian R_x is singular) is passed without trouble (Keller 1977, *Numerical
solution of bifurcation and nonlinear eigenvalue problems*, in Rabinowitz (ed.),
*Applications of Bifurcation Theory*, 359-384; Seydel 2010, *Practical Bifurcation and
Stability Analysis*, §4.4-4.6):

- tangent: [R_x, R_p; t_prev^T] t = [0; 1], normalised, oriented along the last one;
- predictor: X + h t;
- corrector: Newton on [R(X) = 0; t^T (X - X_pred) = 0] (the hyperplane through the
  predicted point normal to the tangent);
- step control: h grows by 1.5 after a corrector that took at most
  :data:`EASY_ITERATIONS` iterations and halves on a failure or a turn of the tangent
  wider than :data:`MAX_TURN`, unless the turn stays as wide at half the step (a
  corner, :data:`CORNER`);
- turning points: where the tangent's p component changes sign, crossed by a step no
  longer than ``fold_step``; located on the cubic Hermite interpolant of p(s) between
  the two points, whose slope vanishes there (error O(h^4) on a smooth branch).

:func:`continue_response` follows the contact-loss balance of :mod:`.nonlinear` in
speed this way and returns the branch, its folds and its stability as a Dataset;
:func:`separated_response` connects it to the linear sweep of :mod:`.sweep` (and
:func:`.nonlinear.case_law` to a case).
"""

from __future__ import annotations

import contextlib
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from ...errors import CaseError
from .floquet import DEFAULT_SEGMENTS
from .nonlinear import BacklashLaw, BacklashProblem
from .system import ResponseSystem

__all__ = [
    "Branch",
    "continue_branch",
    "continue_response",
    "newton",
    "separated_response",
]

SEPARATION_SAMPLES = 1024
"""Instants per period at which the reported signals are read."""

Residual = Callable[[np.ndarray, float], tuple[np.ndarray, np.ndarray, np.ndarray]]
"""(x, p) -> (R, dR/dx, dR/dp)."""

EASY_ITERATIONS = 3
"""Corrector iterations below which the step grows."""

MAX_TURN = math.radians(20.0)
"""Largest angle between consecutive tangents before the step is retried smaller."""

CORNER = 0.7
"""A step turning by more than this share of the turn at twice its length passes a
corner of the branch: it is taken, not shortened further."""


def newton(
    fun: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
    x0: np.ndarray,
    *,
    tolerance: float,
    max_iterations: int = 30,
) -> tuple[np.ndarray, list[float], bool]:
    """Newton's method with a backtracking line search on the residual norm.

    Parameters
    ----------
    fun : callable
        x -> (R(x), dR/dx).
    x0 : ndarray
        Start.
    tolerance : float
        Converged when the residual's max norm is at most this.
    max_iterations : int
        Iterations allowed.

    Returns
    -------
    x : ndarray
        The last iterate.
    history : list of float
        Residual max norm at each iterate, the start's first.
    converged : bool
    """
    x = np.array(x0, dtype=np.float64)
    r, jac = fun(x)
    history = [float(np.abs(r).max())]
    for _ in range(max_iterations):
        if history[-1] <= tolerance:
            return x, history, True
        try:
            step = np.linalg.solve(jac, -r)
        except np.linalg.LinAlgError:
            return x, history, False
        scale = 1.0
        for _ in range(12):  # halve until the residual falls (full steps near the root)
            trial = x + scale * step
            r_t, jac_t = fun(trial)
            if float(np.abs(r_t).max()) < history[-1] or scale < 1e-3:
                break
            scale *= 0.5
        x, r, jac = trial, r_t, jac_t
        history.append(float(np.abs(r).max()))
    return x, history, history[-1] <= tolerance


@dataclass
class Branch:
    """A solution branch from pseudo-arclength continuation.

    Attributes
    ----------
    states : ndarray, shape (points, n)
        x at each point.
    parameter : ndarray, shape (points,)
        p at each point.
    arclength : ndarray, shape (points,)
        s in the scaled variables.
    tangent_parameter : ndarray, shape (points,)
        dp/ds (scaled): its sign change marks a turning point.
    iterations : ndarray of int, shape (points,)
        Corrector iterations.
    turning : list of dict
        Each turning point: ``index`` (the point before it), ``parameter`` (p there,
        from the Hermite interpolant), ``state`` (x there, interpolated linearly),
        ``kind`` (+1: p turns from rising to falling, a largest p; -1: a smallest p).
    finished : bool
        The branch reached the end parameter (False: step or point limit).
    """

    states: np.ndarray
    parameter: np.ndarray
    arclength: np.ndarray
    tangent_parameter: np.ndarray
    iterations: np.ndarray
    turning: list = field(default_factory=list)
    finished: bool = True


def _tangent(jac: np.ndarray, dp: np.ndarray, previous: np.ndarray) -> np.ndarray:
    """Unit tangent of the scaled branch, oriented along ``previous``."""
    n = jac.shape[0]
    matrix = np.zeros((n + 1, n + 1))
    matrix[:n, :n] = jac
    matrix[:n, n] = dp
    matrix[n] = previous
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0
    t = np.linalg.solve(matrix, rhs)
    t /= np.linalg.norm(t)
    return t if t @ previous >= 0 else -t


def _turning_point(
    s0: float, s1: float, p0: float, p1: float, t0: float, t1: float
) -> tuple[float, float]:
    """Extreme of the cubic Hermite interpolant of p(s) on [s0, s1] with slopes t0, t1
    at the ends of opposite sign (scaled p), and where it lies (0..1)."""
    h = s1 - s0
    # p(u) = h00 p0 + h10 h t0 + h01 p1 + h11 h t1, u in [0, 1]; dp/du = a u^2 + b u + c
    a = 6 * p0 + 3 * h * t0 - 6 * p1 + 3 * h * t1
    b = -6 * p0 - 4 * h * t0 + 6 * p1 - 2 * h * t1
    c = h * t0
    roots = np.roots([a, b, c]) if abs(a) > 1e-300 else np.array([-c / b])
    roots = [
        float(r.real)
        for r in np.atleast_1d(roots)
        if abs(r.imag) < 1e-12 and -1e-9 <= r.real <= 1 + 1e-9
    ]
    u = min(roots, key=lambda r: abs(r - 0.5)) if roots else t0 / (t0 - t1)
    h00, h10 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u
    h01, h11 = -2 * u**3 + 3 * u**2, u**3 - u**2
    return float(h00 * p0 + h10 * h * t0 + h01 * p1 + h11 * h * t1), u


def continue_branch(
    residual: Residual,
    x0: np.ndarray,
    p0: float,
    p_end: float,
    *,
    x_scale: float,
    p_scale: float,
    step: float = 0.02,
    step_min: float = 1e-6,
    step_max: float = 0.1,
    tolerance: float = 1e-10,
    max_points: int = 2000,
    max_iterations: int = 12,
    resolution: float = 2e-3,
    fold_step: float = 2e-3,
) -> Branch:
    """Follow R(x, p) = 0 from a solution (x0, p0) until p passes ``p_end``.

    Parameters
    ----------
    residual : callable
        (x, p) -> (R, dR/dx, dR/dp); R in the units of x.
    x0 : ndarray
        A solution at p0 (corrected by Newton at fixed p first).
    p0, p_end : float
        Start and end parameter; the branch leaves p0 towards p_end.
    x_scale, p_scale : float
        Units of the scaled arclength (e.g. the static deflection and the start
        frequency).
    step, step_min, step_max : float
        First, smallest and largest arclength step (scaled).
    tolerance : float
        Corrector convergence: residual max norm over ``x_scale``.
    max_points : int
        Points at most.
    max_iterations : int
        Corrector iterations before the step is halved.
    resolution : float
        Scaled distance in p below which two opposite turning points are a wiggle of
        a piecewise-smooth branch, not two folds (:func:`_turning_points`).
    fold_step : float
        Longest step across a turning point: a longer one is retried shorter, so the
        Hermite location's O(h^4) error stays below ~1e-10.

    Returns
    -------
    Branch
    """
    tol = tolerance * x_scale
    x, history, ok = newton(lambda z: residual(z, p0)[:2], x0, tolerance=tol)
    if not ok:
        raise RuntimeError(
            f"no solution at the start parameter {p0!r} (residual {history[-1]:.3g})"
        )
    n = x.size
    direction = 1.0 if p_end >= p0 else -1.0

    def scaled_system(big: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r, jx, jp = residual(big[:n] * x_scale, big[n] * p_scale)
        # R / x_scale as a function of the scaled unknowns
        return r / x_scale, jx, jp * p_scale / x_scale

    big = np.concatenate([x / x_scale, [p0 / p_scale]])
    _, jx, jp = scaled_system(big)
    start = np.zeros(n + 1)
    start[n] = direction
    t = _tangent(jx, jp, start)
    states, params, arcs, tps, its = [x], [p0], [0.0], [t[n]], [len(history) - 1]
    s = 0.0
    h = step
    finished = False
    previous_turn = math.inf  # turn of the last step rejected for turning too far
    since_turn = 0  # steps taken since
    while len(states) < max_points:
        if direction * (big[n] * p_scale - p_end) >= 0:
            finished = True
            break
        predicted = big + h * t
        guess = predicted.copy()
        converged = False
        for k in range(1, max_iterations + 1):
            r, jx, jp = scaled_system(guess)
            aug = np.concatenate([r, [t @ (guess - predicted)]])
            if np.abs(aug).max() <= tolerance and k > 1:
                converged = True
                break
            matrix = np.zeros((n + 1, n + 1))
            matrix[:n, :n] = jx
            matrix[:n, n] = jp
            matrix[n] = t
            try:
                guess = guess - np.linalg.solve(matrix, aug)
            except np.linalg.LinAlgError:
                break
        new_t = None
        if converged:
            new_t = _tangent(jx, jp, t)
            turn = math.acos(min(1.0, float(new_t @ t)))
            # a smooth branch turns by ~ h * curvature: halving h halves the turn; a
            # corner (a contact switch of the sampled law) turns as much at any h
            if turn > MAX_TURN and h > step_min and not turn > CORNER * previous_turn:
                converged = False
                previous_turn, since_turn = turn, 0
            elif new_t[n] * t[n] < 0 and h > fold_step:  # approach a fold in short steps
                converged = False
        if not converged:
            h *= 0.5
            if h < step_min:
                break
            continue
        since_turn += 1
        if turn > MAX_TURN or since_turn > 5:  # a corner passed, or none met lately
            previous_turn = math.inf
        s += float(np.linalg.norm(guess - big))
        big, t = guess, new_t
        states.append(big[:n] * x_scale)
        params.append(big[n] * p_scale)
        arcs.append(s)
        tps.append(t[n])
        its.append(k - 1)
        if k - 1 <= EASY_ITERATIONS:
            h = min(step_max, 1.5 * h)
    branch = Branch(
        states=np.array(states),
        parameter=np.array(params),
        arclength=np.array(arcs),
        tangent_parameter=np.array(tps),
        iterations=np.array(its, dtype=np.int64),
        finished=finished,
    )
    branch.turning = _turning_points(branch, p_scale, resolution)
    return branch


def _turning_points(branch: Branch, p_scale: float, resolution: float) -> list[dict]:
    """Sign changes of dp/ds along a branch, located on the Hermite interpolant.

    A branch of a piecewise-smooth residual (the AFT of a contact law at N instants)
    has small corners where a sample changes contact state; where the branch runs
    nearly normal to p they can flip the sign of dp/ds twice within a few steps.  Two
    consecutive turning points of opposite kind closer than ``resolution`` (scaled p)
    are such a wiggle and cancel; a fold that remains takes the extreme p of the
    points and interpolants within ``resolution`` of it.
    """
    kept: list[dict] = []
    tp = branch.tangent_parameter
    p = branch.parameter / p_scale
    for i in np.flatnonzero(np.sign(tp[:-1]) * np.sign(tp[1:]) < 0):
        s0, s1 = branch.arclength[i], branch.arclength[i + 1]
        value, u = _turning_point(s0, s1, p[i], p[i + 1], tp[i], tp[i + 1])
        kind = 1 if tp[i] > 0 else -1
        value = max(value, p[i], p[i + 1]) if kind > 0 else min(value, p[i], p[i + 1])
        if kept and kept[-1]["kind"] == -kind and abs(kept[-1]["scaled"] - value) < resolution:
            kept.pop()
            if kept and kept[-1]["kind"] == kind and abs(kept[-1]["scaled"] - value) < resolution:
                best = max if kind > 0 else min
                kept[-1]["scaled"] = best(kept[-1]["scaled"], value)
            continue
        state = (1 - u) * branch.states[i] + u * branch.states[i + 1]
        kept.append({"index": int(i), "scaled": value, "state": state, "kind": kind})
    for t in kept:
        t["parameter"] = t.pop("scaled") * p_scale
    return kept


def continue_response(
    system: ResponseSystem,
    law: BacklashLaw,
    speeds: tuple[float, float],
    *,
    harmonics: int = 16,
    samples: int | None = None,
    step: float = 0.02,
    step_max: float = 0.05,
    tolerance: float = 1e-10,
    stability: bool = True,
    segments: int = DEFAULT_SEGMENTS,
    max_points: int = 2000,
    start: np.ndarray | None = None,
) -> xr.Dataset:
    """The periodic steady state with contact loss, continued in speed.

    Newton's method finds the solution at the first speed (from ``start``, else the
    linear solution there), and pseudo-arclength continuation follows it to the
    second, through every turning point.

    Parameters
    ----------
    system : ResponseSystem
        The linear model.
    law : BacklashLaw
        The flank law of every mesh.
    speeds : tuple of float
        First and last input speed [rpm] (either order).
    harmonics : int
        H, harmonics of the fundamental balanced.
    samples : int, optional
        AFT instants per period.
    step, step_max : float
        First and largest arclength step, in deflections over the largest static mesh
        deflection and frequencies over the first.
    tolerance : float
        Residual of every point over the largest static mesh deflection.
    stability : bool
        Floquet multipliers of every point (the contact state's stiffness per instant).
    segments : int
        Intervals of constant stiffness of the monodromy.
    max_points : int
        Branch points at most.
    start : ndarray, optional
        Unknowns at the first speed to start Newton from.

    Returns
    -------
    xarray.Dataset
        Over ``point`` and ``mesh``: ``speed``, ``frequency``, mesh force max / min /
        mean, DTE RMS and peak to peak, ``separation`` and ``coast_contact`` flags,
        ``floquet_multiplier``, ``stable``, ``turning`` (+1 where an up sweep jumps
        off the branch, -1 where a down sweep does, at the point before the fold); the
        attributes ``up_sweep_jumps`` and ``down_sweep_jumps`` [rpm] list the folds.

    Raises
    ------
    CaseError
        A speed not > 0, or no static mesh load (nothing presses the flanks).
    RuntimeError
        Newton finds no solution at the first speed (start where the response is
        mild, away from resonances, or give ``start``).
    """
    started = time.perf_counter()
    if not all(math.isfinite(float(v)) and float(v) > 0 for v in speeds):
        raise CaseError(f"speeds must be finite and > 0 rpm (got {tuple(speeds)!r})")
    problem = BacklashProblem(system, law, harmonics, samples)
    w0, w1 = system.omega(float(speeds[0])), system.omega(float(speeds[1]))
    scale = float(np.abs(system.static_deflection()).max())
    if not scale > 0:
        raise CaseError("no static mesh load: the contact-loss balance needs a torque")
    with _thread_limit():
        branch = continue_branch(
            problem.residual,
            problem.linear_solution(w0) if start is None else start,
            w0,
            w1,
            x_scale=scale,
            p_scale=w0,
            step=step,
            step_max=step_max,
            tolerance=tolerance,
            max_points=max_points,
        )
        records = [
            problem.summary(x, SEPARATION_SAMPLES, w)
            for x, w in zip(branch.states, branch.parameter)
        ]
        multiplier = np.full(branch.parameter.size, np.nan, dtype=complex)
        if stability:
            for i, (x, w) in enumerate(zip(branch.states, branch.parameter)):
                multiplier[i] = problem.multipliers(x, w, segments)[0]
    per_rpm = system.omega(1.0)
    turning = np.zeros(branch.parameter.size, dtype=np.int8)
    for fold in branch.turning:
        turning[fold["index"]] = fold["kind"]
    wall = time.perf_counter() - started
    return _dataset(system, problem, branch, records, multiplier, turning, per_rpm, wall)


def separated_response(
    system: ResponseSystem, linear: xr.Dataset, law: BacklashLaw, **options: object
) -> xr.Dataset | None:
    """The contact-loss response over a linear sweep's speed range, where it separates.

    The hook for :func:`.sweep.sweep_system`: when its dataset flags tooth separation
    at any speed, the branch with the flank law is continued over the sweep's speed
    range from its lowest speed (from its highest when Newton finds no solution at the
    lowest), so every fold and branch between them comes out.

    Parameters
    ----------
    system : ResponseSystem
        The model the linear sweep balanced.
    linear : xarray.Dataset
        The linear sweep (``speed`` and ``separation``).
    law : BacklashLaw
        The flank law (:func:`case_law`).
    **options
        Passed to :func:`continue_response`.

    Returns
    -------
    xarray.Dataset or None
        None when no mesh separates in the linear sweep.
    """
    if not bool(np.any(linear["separation"].values)):
        return None
    low, high = float(linear["speed"].values.min()), float(linear["speed"].values.max())
    try:
        return continue_response(system, law, (low, high), **options)
    except RuntimeError:
        return continue_response(system, law, (high, low), **options)


def _thread_limit() -> contextlib.AbstractContextManager:
    """One BLAS thread: the matrices are small, and two threads on a shared machine
    slow their factorisations down (as in :mod:`.sweep`)."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - a dependency
        return contextlib.nullcontext()
    return threadpool_limits(1, user_api="blas")


def _dataset(
    system: ResponseSystem,
    problem: BacklashProblem,
    branch: Branch,
    records: list[dict],
    multiplier: np.ndarray,
    turning: np.ndarray,
    per_rpm: float,
    wall: float,
) -> xr.Dataset:
    """The branch as an ``xarray.Dataset`` (see :func:`continue_response`)."""

    def stack(key: str) -> np.ndarray:
        return np.array([r[key] for r in records])

    per_mesh = ("point", "mesh")
    speed = branch.parameter / per_rpm
    data = {
        "speed": ("point", speed, {"units": "rpm", "long_name": "input member speed"}),
        "frequency": ("point", branch.parameter,
                      {"units": "rad/s", "long_name": "fundamental angular frequency"}),
        "arclength": ("point", branch.arclength,
                      {"units": "1", "long_name": "scaled arclength along the branch"}),
        "mesh_force_max": (per_mesh, stack("force_max"),
                           {"units": "N", "long_name": "largest contact force over a period"}),
        "mesh_force_min": (per_mesh, stack("force_min"),
                           {"units": "N", "long_name": "smallest contact force over a period "
                            "(< 0 on the coast flank)"}),
        "mesh_force_mean": (per_mesh, stack("force_mean"),
                            {"units": "N", "long_name": "mean contact force"}),
        "dte_rms": (per_mesh, stack("dte_rms"),
                    {"units": "m", "long_name": "dynamic transmission error, RMS about its "
                     "mean along the line of action"}),
        "dte_peak_to_peak": (per_mesh, stack("dte_pp"),
                             {"units": "m", "long_name": "dynamic transmission error, peak "
                              "to peak"}),
        "separation": (per_mesh, stack("separation").astype(np.int8),
                       {"units": "1", "long_name": "1 where the drive flanks part in the "
                        "period"}),
        "coast_contact": (per_mesh, stack("coast").astype(np.int8),
                          {"units": "1", "long_name": "1 where the coast flanks meet in "
                           "the period (back-side impact)"}),
        "turning": ("point", turning,
                    {"units": "1", "long_name": "+1 before a fold where an up sweep jumps, "
                     "-1 before one where a down sweep jumps"}),
        "deflection_coefficients": (("point", "term", "mesh"),
                                    branch.states.reshape(speed.size, -1, len(system.names)),
                                    {"units": "m", "long_name": "real Fourier coefficients of "
                                     "the mesh deflection: a_0, a_1..a_H (cos), b_1..b_H (sin)"}),
        "iterations": ("point", branch.iterations.astype(np.int32),
                       {"units": "1", "long_name": "Newton corrector iterations"}),
    }  # fmt: skip
    if not np.all(np.isnan(multiplier)):
        data.update({
            "floquet_multiplier": ("point", np.abs(multiplier),
                                   {"units": "1", "long_name": "largest Floquet multiplier "
                                    "modulus of the linearised periodic system"}),
            "floquet_argument": ("point", np.angle(multiplier),
                                 {"units": "rad", "long_name": "argument of the largest Floquet "
                                  "multiplier: 0 where it leaves the unit circle at +1 (fold), "
                                  "pi at -1 (period doubling), else a torus (Neimark-Sacker)"}),
            "stable": ("point", (np.abs(multiplier) < 1.0).astype(np.int8),
                       {"units": "1", "long_name": "1 where every Floquet multiplier lies "
                        "inside the unit circle"}),
        })  # fmt: skip
    coords = {
        "point": ("point", np.arange(speed.size, dtype=np.int32), {"long_name": "branch point"}),
        "mesh": ("mesh", np.array(system.names, dtype=object), {"long_name": "mesh"}),
    }
    folds = [(f["parameter"] / per_rpm, f["kind"]) for f in branch.turning]
    attrs = {
        **system.attrs,
        "method": "AFT harmonic balance with the flank law, pseudo-arclength continuation "
        "in speed, Floquet multipliers of the contact state's stiffness",
        "harmonics": problem.harmonics,
        "aft_samples": problem.samples,
        "backlash": np.asarray(problem.law.backlash, dtype=np.float64),
        "smoothing": float(problem.law.smoothing),
        "switched_mesh_damping": problem.damper,
        "up_sweep_jumps": np.array([s for s, k in folds if k > 0]),
        "down_sweep_jumps": np.array([s for s, k in folds if k < 0]),
        "finished": int(branch.finished),
        "wall_s": wall,
    }
    return xr.Dataset(data, coords, attrs)
