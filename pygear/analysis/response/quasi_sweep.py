r"""One speed of a gearbox of several frequency groups: the lattice chosen by the
tolerance, the mesh forces over the torus, bearing forces and per-group stability.

What a quasi-periodic response reports, against the periodic one of :mod:`.sweep`:

- **Peaks** (K_v, the smallest force, DTE peak to peak, bearing forces) are taken over
  the torus of phases (theta_1, ..., theta_G), which the motion fills densely: mesh m
  of group g is sampled on a regular grid of its own phase theta_g (where its stiffness
  jumps) times a Kronecker sequence of the other groups' phases.
- **Means and RMS** are exact on the lattice: the mean mesh force is the torus average
  of k_m(theta_g) delta_m, which only the points on group g's axis reach (the sum of
  their amplitudes against the coefficients of all the stiffness samples), and the DTE
  RMS about the mean is sqrt(sum_{k != 0} |delta_{k,m}|^2) (Parseval).
- **Stability.**  A quasi-periodic linear system has no monodromy matrix, so Floquet
  theory does not define its stability.  What is reported is the Floquet stability of
  every group on its own (that group's stiffness varying at its fundamental, every other
  mesh at its mean stiffness): the largest multiplier modulus over the groups, stable
  when every group is.  A parametric resonance of one stage shows; one driven by the
  combination of two stages' variations does not.
"""

from __future__ import annotations

import math

import numpy as np

from .floquet import DEFAULT_SEGMENTS, system_multipliers
from .hill import AUTO_HARMONICS
from .quasi import (
    DEFAULT_MIXED_ORDER,
    QuasiSolution,
    solve_quasi,
    torus_phases,
    torus_samples,
)
from .system import ResponseSystem

__all__ = [
    "MAX_MIXED_ORDER",
    "quasi_balance",
    "quasi_multipliers",
    "quasi_record",
    "start_orders",
]

MAX_MIXED_ORDER = 8
"""Largest total order M of the combination frequencies the automatic choice reaches."""

REST_SAMPLES = 32
"""Kronecker samples of the other groups' phases per own-phase grid point (peaks)."""

BEARING_SAMPLES = 2048
"""Kronecker samples of the torus for the bearing force peaks."""


def _power_of_two(value: float) -> int:
    return 1 << max(0, math.ceil(math.log2(max(value, 1.0))))


def start_orders(
    omegas: np.ndarray, cover: float, max_harmonics: int, first: int = AUTO_HARMONICS[1]
) -> tuple[int, ...]:
    """First axis orders of the automatic choice: at least ``first`` harmonics and enough
    to reach ``cover`` [rad/s] on every axis, rounded up to a power of two (a sweep then
    reuses few lattices), at most ``max_harmonics``."""
    return tuple(
        min(max_harmonics, _power_of_two(max(first, math.ceil(cover / w)))) for w in omegas
    )


def quasi_balance(
    system: ResponseSystem,
    speed_rpm: float,
    harmonics: int | str = "auto",
    *,
    tolerance: float,
    max_harmonics: int = AUTO_HARMONICS[-1],
    cover: float = 0.0,
) -> QuasiSolution:
    """The quasi-periodic steady state at one input speed.

    Parameters
    ----------
    system : ResponseSystem
        A model with its frequency groups.
    speed_rpm : float
        Input speed [rpm].
    harmonics : int or "auto"
        H for every axis, with M = min(H, :data:`DEFAULT_MIXED_ORDER`); or ``auto``:
        from :func:`start_orders` and M = 2, solve, and double every axis order and M
        whose part of the residual (its points of the next layer) exceeds half the
        tolerance, until the residual meets the tolerance, nothing can grow (axes up
        to ``max_harmonics``, M up to :data:`MAX_MIXED_ORDER`), or a part at its limit
        misses the tolerance by itself.
    tolerance : float
        Residual the automatic choice reaches.
    max_harmonics : int
        Largest axis order of the automatic choice.
    cover : float
        Angular frequency [rad/s] every axis reaches first (the stiffness jumps ring the
        modes below it).
    """
    omegas = system.group_omegas(speed_rpm)
    if harmonics != "auto":
        h = int(harmonics)
        mixed = max(2, min(h, DEFAULT_MIXED_ORDER))
        return solve_quasi(system, omegas, [h] * omegas.size, mixed)
    orders = list(start_orders(omegas, cover, max_harmonics))
    mixed = 2
    while True:
        solution = solve_quasi(system, omegas, orders, mixed)
        if solution.residual <= tolerance:
            return solution
        parts = solution.residual_parts
        stuck = [orders[g] >= max_harmonics for g in range(omegas.size)] + [
            mixed >= MAX_MIXED_ORDER
        ]
        if any(p > tolerance and s for p, s in zip(parts, stuck)):
            return solution  # an order at its limit misses the tolerance on its own
        grown = False
        for g in range(omegas.size):
            if parts[g] > 0.5 * tolerance and orders[g] < max_harmonics:
                orders[g] = min(max_harmonics, 2 * orders[g])
                grown = True
        if parts[-1] > 0.5 * tolerance and mixed < MAX_MIXED_ORDER:
            mixed = min(MAX_MIXED_ORDER, 2 * mixed)
            grown = True
        if not grown:
            return solution


def quasi_record(system: ResponseSystem, solution: QuasiSolution) -> dict:
    """What the dataset keeps of one speed (the keys of :func:`.sweep._speed_record`)."""
    points = solution.lattice.points
    groups = points.shape[1]
    n_mesh = system.mesh_rows.shape[0]
    group = system.mesh_group if system.mesh_group is not None else np.zeros(n_mesh, int)
    samples = system.stiffness.shape[0]
    rest = torus_samples(groups, REST_SAMPLES)
    mean = np.empty(n_mesh)
    peak = np.empty(n_mesh)
    low = np.empty(n_mesh)
    pp = np.empty(n_mesh)
    h_top = solution.harmonics
    amplitude = np.full((n_mesh, h_top + 1), np.nan)
    for g in range(groups):
        meshes = np.flatnonzero(group == g)
        if meshes.size == 0:
            continue
        h = solution.lattice.orders[g]
        grid = min(samples, _power_of_two(16 * (2 * h + 1)))
        stiffness = system.stiffness[:: samples // grid, meshes]  # (grid, n_g)
        theta = rest.copy()
        theta[:, g] = 0.0
        phases = torus_phases(theta, points)  # (R, P): the other groups' phases
        own = points[:, g] % grid
        spectrum = np.zeros((grid, REST_SAMPLES, meshes.size), complex)
        np.add.at(spectrum, own, phases.T[:, :, None] * solution.deflection[:, None, meshes])
        deflection = np.real(np.fft.ifft(spectrum, axis=0)) * grid  # (grid, R, n_g)
        force = system.contact_sign[meshes] * stiffness[:, None, :] * deflection
        axis = np.flatnonzero(np.count_nonzero(np.delete(points, g, axis=1), axis=1) == 0)
        # torus mean of k_m(theta_g) delta_m = sum_j khat_{m,-j} delta_{j e_g, m}, with the
        # coefficients of all the stiffness samples (the periodic balance's mean, exactly)
        spectrum_k = np.fft.fft(system.stiffness[:, meshes], axis=0) / samples
        khat = spectrum_k[(-points[axis, g]) % samples]  # (axis points, n_g)
        overlap = np.real((khat * solution.deflection[axis][:, meshes]).sum(axis=0))
        mean[meshes] = system.contact_sign[meshes] * overlap
        peak[meshes] = force.max(axis=(0, 1))
        low[meshes] = force.min(axis=(0, 1))
        pp[meshes] = deflection.max(axis=(0, 1)) - deflection.min(axis=(0, 1))
        order = points[axis, g]
        keep = order >= 0
        values = np.abs(solution.deflection[axis[keep]][:, meshes])
        values[order[keep] > 0] *= 2  # one-sided amplitudes
        amplitude[np.ix_(meshes, order[keep])] = values.T
    dynamic = np.sqrt((np.abs(solution.deflection[1:]) ** 2).sum(axis=0))  # Parseval
    return {
        "harmonics": h_top,
        "residual": solution.residual,
        "dynamic_factor": peak / mean,
        "force_mean": mean,
        "force_max": peak,
        "force_min": low,
        "dte_rms": dynamic,
        "dte_pp": pp,
        "amplitude": amplitude,
        "bearing": _bearing_forces(system, solution),
    }


def _bearing_forces(system: ResponseSystem, solution: QuasiSolution) -> np.ndarray:
    """Largest in-plane force magnitude of every bearing over the torus samples [N]."""
    if system.model is None:
        return np.zeros(0)
    springs = [s for s in system.model.springs if s.kind in ("central_bearing", "planet_bearing")]
    if not springs:
        return np.zeros(0)
    full = system.model.reduction @ system.modes  # (full DOFs, n)
    rows = []
    for spring in springs:
        radial = spring.deflection[:, :2] * spring.stiffness[:2]  # (dofs, 2)
        rows.append(radial.T @ full[spring.dofs])  # (2, n)
    mapping = np.concatenate(rows)  # (2 n_bearing, n)
    harmonics = solution.coordinates @ mapping.T  # (P, 2 n_bearing)
    theta = torus_samples(solution.lattice.points.shape[1], BEARING_SAMPLES)
    signal = np.real(torus_phases(theta, solution.lattice.points) @ harmonics)
    pairs = signal.reshape(BEARING_SAMPLES, len(springs), 2)
    return np.sqrt((pairs**2).sum(axis=2)).max(axis=0)


def quasi_multipliers(
    system: ResponseSystem, speed_rpm: float, segments: int = DEFAULT_SEGMENTS
) -> tuple[float, np.ndarray]:
    """Largest Floquet multiplier modulus of every group on its own (the group's meshes
    varying at its fundamental, the others at mean stiffness), and their largest."""
    omegas = system.group_omegas(speed_rpm)
    moduli = np.array(
        [
            float(np.abs(system_multipliers(system.group_system(g), omegas[g], segments)[0]))
            for g in range(omegas.size)
        ]
    )
    return float(moduli.max()), moduli
