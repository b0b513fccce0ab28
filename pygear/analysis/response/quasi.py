r"""Multi-frequency (quasi-periodic) harmonic balance of a gearbox of several stages.

The meshes of a gearbox fall into frequency groups (:func:`.system.frequency_groups`):
group g's stiffness variations are periodic in the phase theta_g = omega_g t, and the
fundamentals omega_g of different groups are in general incommensurate (their common
period, if any, holds thousands of mesh cycles).  The steady state is then
quasi-periodic and is sought on a truncated lattice of combination frequencies,

    y(t) = sum_{k in L} y_k e^{i (k . omega) t},   k in Z^G,

with dk_m(t) = sum_j c_{m,j} e^{i j omega_{g(m)} t} for mesh m of group g(m).  Balancing
every lattice frequency (a Galerkin projection, as Hill's method on one axis) gives,
condensed onto the mesh deflections delta_k = B y_k as in :mod:`.hill`,

    delta_k + G(k . omega) (T delta)_k = B D(0)^-1 f [k = 0],
    (T delta)_{k,m} = sum_j c_{m,j} delta_{k - j e_{g(m)}, m},                 (3)

with G(w) = B D(w)^-1 B^T the receptance at mean stiffness: a mesh's stiffness couples
lattice points only along its own group's axis, the dynamic compliance couples meshes
at one lattice point.  With one group (3) is exactly (2) of :mod:`.hill`.

Truncation.  L holds every point with |k_g| <= H_g on the axes (the harmonics of each
group's own mesh frequency and the response of every mesh to them) and the
combination points with two or more nonzero components up to a total order
sum_g |k_g| <= M.  A combination amplitude is of second order in the stiffness
variations, so M is small.

Solution.  (3) is solved by GMRES with a block-Jacobi preconditioner: for every group
and every lattice line parallel to its axis, the exact inverse of (3) restricted to that
line and to the group's own meshes, i.e. the single-frequency Hill system of that stage
at the line's frequency offset (the axis through the origin by the real-form LU of
:func:`.hill.real_factor`, the shorter offset lines by stacked dense inverses).  What it
leaves out couples different stages through G alone, so GMRES converges in a few
iterations.

Residual.  As for one frequency: the deflection the next lattice layer would add (the
points of the lattice with orders 2 H_g and 2 M not in L), one block-Jacobi step of (3),
sampled on a quasi-periodic grid of the torus (a Kronecker sequence) and divided by the
largest static mesh deflection.
"""

from __future__ import annotations

import functools
import itertools
import logging
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from .hill import fourier_coefficients, real_factor, real_solve
from .system import ResponseSystem

__all__ = [
    "DEFAULT_MIXED_ORDER",
    "Lattice",
    "QuasiSolution",
    "group_coefficients",
    "lattice",
    "quasi_receptance",
    "solve_quasi",
    "torus_phases",
    "torus_samples",
]

DEFAULT_MIXED_ORDER = 4
"""Total order M of the combination frequencies kept (two or more nonzero components)."""

GMRES_TOLERANCE = 1e-11
GMRES_ACCEPT = 1e-8
GMRES_RESTART = 60
GMRES_CYCLES = 4
"""GMRES on (3): relative residual aimed at, relative residual below which a stop short
of it passes without a warning, Krylov vectors, restarts."""

_log = logging.getLogger("pygear")


@dataclass(frozen=True)
class Lattice:
    """A truncated lattice of combination frequencies.

    Attributes
    ----------
    points : ndarray of int, shape (P, G)
        k of every point, the origin first.
    orders : tuple of int
        H_g, the largest |k_g| on each axis.
    mixed : int
        M, the total order bound of the points with two or more nonzero components.
    """

    points: np.ndarray
    orders: tuple[int, ...]
    mixed: int

    @property
    def size(self) -> int:
        """Points P."""
        return self.points.shape[0]

    def _codes(self, k: np.ndarray) -> np.ndarray:
        span = 8 * max(max(self.orders), self.mixed) + 1
        code = np.zeros(k.shape[0], np.int64)
        for g in range(k.shape[1]):
            code = code * (2 * span + 1) + (k[:, g] + span)
        return code

    @functools.cached_property
    def _sorted(self) -> tuple[np.ndarray, np.ndarray]:
        codes = self._codes(self.points)
        order = np.argsort(codes)
        return order, codes[order]

    def index(self, k: np.ndarray) -> np.ndarray:
        """Row of every point of ``k`` (shape (N, G)) in :attr:`points`, -1 where absent."""
        order, sorted_codes = self._sorted
        wanted = self._codes(np.asarray(k, np.int64))
        at = np.clip(np.searchsorted(sorted_codes, wanted), 0, sorted_codes.size - 1)
        return np.where(sorted_codes[at] == wanted, order[at], -1)


def lattice(orders: tuple[int, ...] | list[int], mixed: int) -> Lattice:
    """The lattice with |k_g| <= H_g on the axes and combinations of total order <= M.

    Parameters
    ----------
    orders : sequence of int
        H_g >= 0 for every group.
    mixed : int
        M >= 0 (below 2 no combination is kept).
    """
    orders = tuple(int(h) for h in orders)
    dims = len(orders)
    rows = [np.zeros(dims, np.int64)]
    for g, h in enumerate(orders):
        for a in (*range(1, h + 1), *range(-h, 0)):
            k = np.zeros(dims, np.int64)
            k[g] = a
            rows.append(k)
    if dims > 1 and mixed >= 2:
        ranges = [range(-min(h, mixed), min(h, mixed) + 1) for h in orders]
        for k in itertools.product(*ranges):
            k = np.array(k, np.int64)
            if np.count_nonzero(k) >= 2 and np.abs(k).sum() <= mixed:
                rows.append(k)
    return Lattice(np.array(rows, np.int64).reshape(-1, dims), orders, int(mixed))


def _outer_layer(inner: Lattice) -> Lattice:
    """The points of the lattice of orders 2 H_g and 2 M that ``inner`` lacks."""
    outer = lattice(tuple(2 * h for h in inner.orders), 2 * inner.mixed)
    missing = inner.index(outer.points) < 0
    return Lattice(outer.points[missing], outer.orders, outer.mixed)


def _poles(system: ResponseSystem) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The first-order form's eigenvalues s and the matrices of the pole expansion
    D(w)^-1 = V_y diag(1 / (i w - s)) W_f (cached on the system)."""
    cached = getattr(system, "_quasi_poles", None)
    if cached is not None:
        return cached
    n = system.size
    state = np.zeros((2 * n, 2 * n))
    state[:n, n:] = np.eye(n)
    state[n:, :n] = -np.diag(system.eigenvalues)
    state[n:, n:] = -system.damping
    poles, vectors = scipy.linalg.eig(state)
    inverse = np.linalg.inv(vectors)
    cached = (poles, vectors[:n], inverse[:, n:], system.mesh_rows @ vectors[:n])
    system._quasi_poles = cached  # type: ignore[attr-defined]
    return cached


def _diagonal_damping(system: ResponseSystem) -> bool:
    c = system.damping
    return np.abs(c - np.diag(np.diag(c))).max() <= 1e-12 * max(np.abs(c).max(), 1e-300)


def quasi_receptance(system: ResponseSystem, frequencies: np.ndarray) -> np.ndarray:
    """G(w) = B D(w)^-1 B^T at every angular frequency w (any sign) [m/N].

    Rayleigh damping (diagonal in the modes) sums the modes; a damping that couples them
    goes through the poles of the first-order form, computed once per system.

    Returns
    -------
    ndarray, complex, shape (len(frequencies), n_mesh, n_mesh)
    """
    w = np.asarray(frequencies, dtype=np.float64)
    rows = system.mesh_rows
    if _diagonal_damping(system):
        inverse = 1.0 / (
            system.eigenvalues[None, :]
            - w[:, None] ** 2
            + 1j * w[:, None] * np.diag(system.damping)[None, :]
        )
        return (rows[None, :, :] * inverse[:, None, :]) @ rows.T
    poles, _, right, left = _poles(system)
    inverse = 1.0 / (1j * w[:, None] - poles[None, :])
    return (left[None, :, :] * inverse[:, None, :]) @ (right @ rows.T)


def _modal_solve(system: ResponseSystem, frequencies: np.ndarray, loads: np.ndarray) -> np.ndarray:
    """D(w_p)^-1 v_p for every point (loads shape (P, n)) in modal coordinates."""
    w = np.asarray(frequencies, dtype=np.float64)
    if _diagonal_damping(system):
        d = (
            system.eigenvalues[None, :]
            - w[:, None] ** 2
            + 1j * w[:, None] * np.diag(system.damping)[None, :]
        )
        return loads / d
    poles, top, right, _ = _poles(system)
    inverse = 1.0 / (1j * w[:, None] - poles[None, :])
    return ((loads @ right.T) * inverse) @ top.T


@dataclass
class QuasiSolution:
    """A quasi-periodic solution on a lattice of combination frequencies.

    Attributes
    ----------
    lattice : Lattice
        The points k.
    omegas : ndarray, shape (G,)
        Group fundamentals [rad/s].
    deflection : ndarray, complex, shape (P, n_mesh)
        delta_k [m].
    coordinates : ndarray, complex, shape (P, n)
        y_k (modal coordinates).
    residual : float
        Deflection of the next lattice layer over the largest static mesh deflection [-].
    iterations : int
        GMRES iterations.
    residual_parts : ndarray, shape (G + 1,)
        The residual of the next layer's points on each axis, and of its combination
        points (last): which order the automatic choice raises.
    """

    lattice: Lattice
    omegas: np.ndarray
    deflection: np.ndarray
    coordinates: np.ndarray
    residual: float = math.nan
    iterations: int = 0
    residual_parts: np.ndarray | None = None

    @property
    def harmonics(self) -> int:
        """Largest axis order max_g H_g."""
        return int(max(self.lattice.orders))


def group_coefficients(system: ResponseSystem, order: int) -> np.ndarray:
    """c_{m,j}, j = -order..order, of every mesh over its own group's period."""
    return fourier_coefficients(system.stiffness_variation, order)


def _coupling(
    system: ResponseSystem, rows: Lattice, columns: Lattice, coefficients: np.ndarray
) -> scipy.sparse.csr_matrix:
    """T of (3) from the points of ``columns`` to those of ``rows`` (flattened point-major,
    mesh-minor): entry ((p, m), (q, m)) = c_{m, j} where k_p - k_q = j e_{g(m)}."""
    n_mesh = system.mesh_rows.shape[0]
    group = _mesh_group(system)
    centre = coefficients.shape[0] // 2
    r_idx, c_idx, values = [], [], []
    for m in range(n_mesh):
        g = group[m]
        top = rows.orders[g] + columns.orders[g]
        for j in range(-min(top, centre), min(top, centre) + 1):
            c = coefficients[centre + j, m]
            if c == 0:
                continue
            source = rows.points.copy()
            source[:, g] -= j
            at = columns.index(source)
            ok = np.flatnonzero(at >= 0)
            r_idx.append(ok * n_mesh + m)
            c_idx.append(at[ok] * n_mesh + m)
            values.append(np.full(ok.size, c))
    shape = (rows.size * n_mesh, columns.size * n_mesh)
    if not values:
        return scipy.sparse.csr_matrix(shape, dtype=complex)
    return scipy.sparse.csr_matrix(
        (np.concatenate(values), (np.concatenate(r_idx), np.concatenate(c_idx))), shape=shape
    )


def _mesh_group(system: ResponseSystem) -> np.ndarray:
    n_mesh = system.mesh_rows.shape[0]
    return np.zeros(n_mesh, np.int64) if system.mesh_group is None else system.mesh_group


def _lines(points: Lattice, system: ResponseSystem) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """(group, point rows sorted along its axis, the group's meshes) of every lattice line
    parallel to a group's axis: the preconditioner's blocks (a group's axis itself,
    through the origin, first)."""
    group = _mesh_group(system)
    out = []
    for g in range(points.points.shape[1]):
        meshes = np.flatnonzero(group == g)
        if meshes.size == 0:
            continue
        rest = np.delete(points.points, g, axis=1)
        _, label = np.unique(rest, axis=0, return_inverse=True)
        label = label.reshape(-1)
        origin = label[0]
        for key in [origin, *(k for k in range(label.max() + 1) if k != origin)]:
            members = np.flatnonzero(label == key)
            members = members[np.argsort(points.points[members, g])]
            out.append((g, members, meshes))
    return out


@dataclass
class _Plan:
    """What a lattice costs once per system, not per speed: the coupling T of (3) on
    the lattice and onto its next layer, the preconditioner's lines, the mirror."""

    inner: Lattice
    outer: Lattice
    coupling: scipy.sparse.csr_matrix
    outer_coupling: scipy.sparse.csr_matrix
    lines: list
    mirror: np.ndarray
    coefficients: np.ndarray
    outer_phases: np.ndarray | None = None
    outer_kind: np.ndarray | None = None

    def phases(self) -> tuple[np.ndarray, np.ndarray]:
        """e^{i k . theta} of the next layer's points at the residual's torus samples
        (computed once), and each point's kind: its axis g, or -1 for a combination."""
        if self.outer_phases is None:
            points = self.outer.points
            samples = torus_samples(points.shape[1], 8 * (2 * max(self.inner.orders) + 1))
            self.outer_phases = torus_phases(samples, points)
            nonzero = points != 0
            self.outer_kind = np.where(nonzero.sum(axis=1) == 1, nonzero.argmax(axis=1), -1)
        return self.outer_phases, self.outer_kind


def _plan(system: ResponseSystem, orders: tuple[int, ...], mixed: int) -> _Plan:
    plans = getattr(system, "_quasi_plans", None)
    if plans is None:
        plans = {}
        system._quasi_plans = plans  # type: ignore[attr-defined]
    key = (tuple(int(h) for h in orders), int(mixed))
    if key not in plans:
        inner = lattice(*key)
        outer = _outer_layer(inner)
        top = 3 * max(max(inner.orders), inner.mixed, 1)
        coefficients = group_coefficients(system, top)
        plans[key] = _Plan(
            inner,
            outer,
            _coupling(system, inner, inner, coefficients),
            _coupling(system, outer, inner, coefficients),
            _lines(inner, system),
            inner.index(-inner.points),
            coefficients,
        )
    return plans[key]


def solve_quasi(
    system: ResponseSystem,
    omegas: np.ndarray,
    orders: tuple[int, ...] | list[int],
    mixed: int = DEFAULT_MIXED_ORDER,
) -> QuasiSolution:
    """Solve (3) on the lattice of ``orders`` H_g and mixed order M.

    Parameters
    ----------
    system : ResponseSystem
        The model, with its frequency groups (one group works too).
    omegas : ndarray, shape (G,)
        Group fundamentals [rad/s], > 0.
    orders : sequence of int
        H_g per group.
    mixed : int
        M, the total order of the combination frequencies.

    Returns
    -------
    QuasiSolution
    """
    omegas = np.asarray(omegas, dtype=np.float64).reshape(-1)
    plan = _plan(system, orders, mixed)
    inner = plan.inner
    n_mesh = system.mesh_rows.shape[0]
    frequency = inner.points @ omegas
    receptance = quasi_receptance(system, frequency)
    static = (system.mesh_rows @ (system.force / system.eigenvalues)).astype(complex)
    rhs = np.zeros((inner.size, n_mesh), complex)
    rhs[0] = static

    def apply(x: np.ndarray) -> np.ndarray:
        load = (plan.coupling @ x).reshape(inner.size, n_mesh)
        return x + np.einsum("pmn,pn->pm", receptance, load).reshape(-1)

    blocks = _factor_lines(plan, receptance, n_mesh)

    def precondition(x: np.ndarray) -> np.ndarray:
        out = x.copy()
        for kind, index, factor, half in blocks:
            if kind == "axis":  # conjugate-symmetric along the axis: real form
                part = x[index].reshape(-1, factor[2])
                out[index] = real_solve(factor, part[half:]).reshape(-1)
            else:  # inverses of equal blocks, stacked
                part = x[index].reshape(factor.shape[0], -1)
                out[index] = (factor @ part[:, :, None])[:, :, 0].reshape(-1)
        return out

    size = inner.size * n_mesh
    count = [0]

    def counted(_: float) -> None:
        count[0] += 1

    solution, info = scipy.sparse.linalg.gmres(
        scipy.sparse.linalg.LinearOperator((size, size), apply, dtype=complex),
        rhs.reshape(-1),
        M=scipy.sparse.linalg.LinearOperator((size, size), precondition, dtype=complex),
        rtol=GMRES_TOLERANCE,
        atol=0.0,
        restart=GMRES_RESTART,
        maxiter=GMRES_CYCLES,
        callback=counted,
        callback_type="pr_norm",
    )
    if info != 0:
        miss = np.linalg.norm(apply(solution) - rhs.reshape(-1)) / np.linalg.norm(rhs)
        if not miss <= GMRES_ACCEPT:
            _log.warning(
                f"response: the lattice's GMRES stopped at a relative residual of {miss:.1e} "
                f"after {count[0]} iterations (frequencies {omegas / (2 * math.pi)} Hz)"
            )
    deflection = solution.reshape(inner.size, n_mesh)
    # the real solution's symmetry delta_{-k} = conj(delta_k), exact
    deflection = 0.5 * (deflection + np.conj(deflection[plan.mirror]))
    load = (plan.coupling @ deflection.reshape(-1)).reshape(inner.size, n_mesh)
    forcing = -load @ system.mesh_rows
    forcing[0] += system.force
    coordinates = _modal_solve(system, frequency, forcing)
    residual, parts = _residual(system, plan, omegas, deflection, static)
    return QuasiSolution(inner, omegas, deflection, coordinates, residual, count[0], parts)


def _factor_lines(plan: _Plan, receptance: np.ndarray, n_mesh: int) -> list:
    """The preconditioner's factors: a group's axis through the origin in the real form of
    :func:`.hill.real_factor`, every other line of two or more points by a complex LU,
    single points (the mean of the sampled stiffness off its model value) inverted."""
    blocks = []
    centre = plan.coefficients.shape[0] // 2
    stacks: dict[int, list[tuple[np.ndarray, np.ndarray]]] = {}
    for g, members, meshes in plan.lines:
        index = (members[:, None] * n_mesh + meshes[None, :]).reshape(-1)
        a = plan.inner.points[members, g]
        sub = receptance[members][:, meshes][:, :, meshes]  # (L, n_g, n_g)
        if members.size > 1 and members[a.size // 2] == 0:  # the axis: a = -H..H
            h = a.size // 2
            window = plan.coefficients[centre - 3 * h : centre + 3 * h + 1][:, meshes]
            blocks.append(("axis", index, real_factor(sub[h:], window, h), h))
            continue
        c = plan.coefficients[centre + a[:, None] - a[None, :]][:, :, meshes]  # (L, L, n_g)
        block = np.einsum("pmn,pqn->pmqn", sub, c).reshape(index.size, index.size)
        stacks.setdefault(index.size, []).append((index, block))
    for size, chosen in stacks.items():
        index = np.concatenate([i for i, _ in chosen])
        inverse = np.linalg.inv(np.eye(size)[None] + np.array([b for _, b in chosen]))
        blocks.append(("stack", index, inverse, 0))
    return blocks


def torus_samples(dims: int, count: int) -> np.ndarray:
    """``count`` points of the torus [0, 2 pi)^dims from a Kronecker sequence
    (theta_n = 2 pi frac(n alpha), alpha from the generalised golden ratio), a
    quasi-periodic grid that fills the torus evenly; the origin first."""
    # the root phi_d of x^(d+1) = x + 1 gives alpha_g = phi_d^-(g+1) (Roberts' R_d sequence)
    phi = 2.0
    for _ in range(60):
        phi = (1.0 + phi) ** (1.0 / (dims + 1))
    alpha = phi ** -np.arange(1, dims + 1)
    n = np.arange(count)[:, None]
    return 2 * math.pi * np.mod(n * alpha[None, :], 1.0)


def torus_phases(samples: np.ndarray, points: np.ndarray) -> np.ndarray:
    """e^{i k . theta} for every sample theta (rows) and lattice point k (columns), as
    products of every axis's powers (a complex exponential per axis and order only)."""
    out = np.ones((samples.shape[0], points.shape[0]), complex)
    for g in range(points.shape[1]):
        top = int(np.abs(points[:, g]).max()) if points.size else 0
        powers = np.exp(1j * samples[:, g : g + 1] * np.arange(-top, top + 1)[None, :])
        out *= powers[:, points[:, g] + top]
    return out


def _residual(
    system: ResponseSystem,
    plan: _Plan,
    omegas: np.ndarray,
    deflection: np.ndarray,
    static: np.ndarray,
) -> tuple[float, np.ndarray]:
    """Deflection of the next lattice layer, sampled, over the largest static deflection:
    in all, and of its points on every axis and of its combination points (last)."""
    groups = plan.inner.points.shape[1]
    scale = float(np.abs(static).max())
    if not np.any(plan.coefficients) or scale == 0:
        return (0.0 if scale > 0 else math.inf), np.zeros(groups + 1)
    outer = plan.outer
    load = (plan.outer_coupling @ deflection.reshape(-1)).reshape(outer.size, -1)
    receptance = quasi_receptance(system, outer.points @ omegas)
    extra = -np.einsum("pmn,pn->pm", receptance, load)
    phases, kind = plan.phases()
    parts = np.zeros(groups + 1)
    for g in range(-1, groups):
        chosen = kind == g
        if chosen.any():  # k and -k both held: the signal is real
            parts[g] = np.abs(np.real(phases[:, chosen] @ extra[chosen])).max() / scale
    total = float(np.abs(np.real(phases @ extra)).max() / scale)
    return total, parts
