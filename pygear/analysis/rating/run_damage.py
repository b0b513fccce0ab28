"""Gear damage from the model's own loads: a run's mesh forces, counted by rainflow.

A pygear run records each mesh's force along its line of action (``mesh_force``, by
``mesh_label`` such as ``stage1.sun-planet1``).  Its rainflow cycles (ASTM E1049-85,
those of the ``rainflow`` package) are gathered into the range x mean matrix that a streamed
run's reductions write (:class:`pygear.analysis.time.reductions.Pow2Histogram`: bins a
power of two wide), so a run file's whole record and a file holding only the streamed
matrices (or a batch's combined matrices in the same variables) give the same damage.

ISO 6336-6 counts one load cycle per tooth contact, so the kinematics fix how many
cycles a tooth sees and the rainflow matrix how they are loaded: the peaks of the
counted cycles (the bin's upper mean edge plus half its upper range edge: never below
a cycle's own peak) share out the record's tooth contacts in proportion to their
counts.  A tooth of a gear turning at n_rel relative to its carrier meets one planet
mesh n_rel T / 60 times in a record of T seconds; a sun or ring tooth meets every
planet, so its cycles are the sum over the planet meshes (N / m times the m recorded
ones, assumed alike); a planet's flank and a pinion's tooth meet one mesh, so the
worst recorded planet counts.  (Counting each rainflow cycle as a contact would count
the mesh's vibration cycles as contacts: at 12 rpm stage 1 of the NREL gearbox's
meshes engage about eleven teeth a second, its forces ring at hundreds of hertz.)
Taking every contact at a cycle's peak errs on the safe side.

The force F along the line of action gives ISO 6336's tangential load at the
reference circle, F_t = F cos(beta_b) cos(alpha_t).  Each peak is rated to ISO 6336
with K_A = K_gamma = K_v = 1 (the run's forces hold the dynamics and the load
sharing), the face and transverse factors at that load, and its S-N curve gives N_i
(:mod:`.duty`).  The record's damage is scaled to the service life.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from ...errors import CaseError
from ...model import gear_geometry as geo
from .duty import cycles_to_failure
from .gear_rating import FactorValue, PairLoad, rate_pair

__all__ = [
    "DEFAULT_BINS",
    "CycleMatrix",
    "cycle_matrix",
    "mesh_for_label",
    "spectrum_damage",
    "tangential_load",
]

DEFAULT_BINS = 64
"""Bins per axis of a rainflow matrix counted from a record (the streamed reductions'
default, :class:`pygear.model.reduction_settings.Reductions`)."""

_RUN = "in the run's mesh forces"


@dataclass(frozen=True)
class CycleMatrix:
    """Rainflow cycles of one recorded mesh force: ``counts[range, mean]`` (half cycles
    0.5) and the bin edges [N] of each axis."""

    label: str
    counts: np.ndarray
    range_edges: np.ndarray
    mean_edges: np.ndarray

    def peaks(self) -> tuple[np.ndarray, np.ndarray]:
        """(peak force [N], cycles) of the occupied bins: upper mean edge plus half the
        upper range edge (a cycle's peak mean + range/2 lies at or below it)."""
        ranges, means = np.nonzero(self.counts > 0.0)
        peak = self.mean_edges[means + 1] + 0.5 * self.range_edges[ranges + 1]
        return peak, self.counts[ranges, means]


def cycle_matrix(label: str, force: Sequence[float], bins: int = DEFAULT_BINS) -> CycleMatrix:
    """The rainflow matrix of a whole record, as a streamed run counts it (the same
    counter, :class:`pygear.analysis.time.reductions.StreamingRainflow`, whose cycles
    are ``rainflow.extract_cycles``'s: its reversals found by NumPy, only they loop)."""
    from ..time.reductions import Pow2Histogram, StreamingRainflow

    values = np.asarray(force, dtype=float)
    if values.ndim != 1 or values.size < 2 or not np.all(np.isfinite(values)):
        raise CaseError(f"mesh_force of {label!r} must be a finite record of >= 2 samples")
    counter = StreamingRainflow()
    cycles = np.concatenate([counter.update(values), counter.finish()])
    histogram = Pow2Histogram(2, bins)
    histogram.update(cycles[:, :2], cycles[:, 2])
    counts, edges = histogram.result()
    return CycleMatrix(label, counts[..., 0], edges[0], edges[1])


def mesh_for_label(label: str, meshes: Sequence[str]) -> str | None:
    """The rated mesh (``stage1.sun_mesh``) of a run's mesh label (``stage1.sun-planet2``,
    ``parallel.input-output``), or None if the rating has no such mesh."""
    stage, _, name = str(label).rpartition(".")
    kind = name.split("-", 1)[0]
    for candidate in (f"{stage}.{kind}_mesh", f"{stage}.mesh"):
        if candidate in meshes:
            return candidate
    return None


def tangential_load(load: PairLoad, force: float) -> float:
    """ISO 6336's F_t [N] at gear 1's reference circle of a force [N] along the line
    of action: F cos(beta_b) cos(alpha_t)."""
    gear = load.geometry.gear1
    return force * math.cos(geo.base_helix_angle(gear)) * math.cos(
        geo.transverse_pressure_angle(gear))


def _unit(name: str) -> FactorValue:
    return FactorValue(1.0, f"{name} = 1: {_RUN}", "run")


def spectrum_damage(
    load: PairLoad, planets: int, matrices: Sequence[CycleMatrix], record_s: float,
    service_life_h: float, speed_scale: float = 1.0,
) -> list[tuple[float, float]]:
    """(pitting, bending) damage over the service life of gear 1 and gear 2 of one
    mesh from its recorded planets' cycle matrices (see the module docstring).

    Parameters
    ----------
    load : PairLoad
        The mesh as rated (geometry, materials, speeds, given factors).
    planets : int
        Planets of the stage (1 for a parallel pair).
    matrices : sequence of CycleMatrix
        One per recorded planet mesh of this mesh kind.
    record_s : float
        Duration the matrices count [s].
    service_life_h : float
        Hours the damage is scaled to.
    speed_scale : float
        The record's mean input speed over the speed ``load`` was rated at.
    """
    if not matrices:
        raise CaseError("matrices must hold at least one recorded mesh")
    if not (math.isfinite(record_s) and record_s > 0.0):
        raise CaseError(f"record duration must be > 0 s (got {record_s})")
    given = {**load.given, "K_v": _unit("K_v")}
    base = replace(load, application_factor=_unit("K_A"), load_sharing=_unit("K_gamma"),
                   given=given)
    # one tooth's contacts with one planet mesh over the record
    contacts = [abs(n) * speed_scale * record_s / 60.0 for n in load.speeds]
    radius = geo.pitch_radius(load.geometry.gear1)
    stresses: dict[float, tuple] = {}
    per_channel = []
    for matrix in matrices:
        peak, counts = matrix.peaks()
        share = counts / counts.sum() if counts.sum() > 0.0 else counts
        damage = np.zeros((2, 2))
        for force, weight in zip(peak, share):
            if force <= 0.0:
                continue  # the flank is unloaded (separation): no cycle on it
            if force not in stresses:
                torque = tangential_load(load, float(force)) * radius
                stresses[force] = rate_pair(replace(base, torque1=torque)).gears
            for side in (0, 1):
                values = stresses[force][side]
                kind = load.materials[side].kind
                for k, (stress, reference, root) in enumerate((
                        ("sigma_H", "sigma_HG_ref", False), ("sigma_F", "sigma_FG_ref", True))):
                    life = cycles_to_failure(kind, values[stress].value,
                                             values[reference].value, root)
                    damage[side, k] += weight * contacts[side] / life
        per_channel.append(damage)
    scale = service_life_h * 3600.0 / record_s
    out = []
    for side in (0, 1):
        if load.contacts[side] > 1:  # meets every planet: the sum, unrecorded alike
            total = sum(d[side] for d in per_channel) * planets / len(per_channel)
        else:  # one planet's flank, or a pinion: the worst recorded
            total = np.max([d[side] for d in per_channel], axis=0)
        out.append((float(total[0] * scale), float(total[1] * scale)))
    return out


def matrices_by_mesh(matrices: Sequence[CycleMatrix], meshes: Sequence[str]
                     ) -> tuple[dict[str, list[CycleMatrix]], list[str]]:
    """The matrices grouped by rated mesh, and the labels that match none."""
    grouped: dict[str, list[CycleMatrix]] = {}
    unknown = []
    for matrix in matrices:
        mesh = mesh_for_label(matrix.label, meshes)
        if mesh is None:
            unknown.append(matrix.label)
        else:
            grouped.setdefault(mesh, []).append(matrix)
    return grouped, unknown


def run_planets(stage_planets: Mapping[str, int], mesh: str) -> int:
    """The planet count of a rated mesh's stage (1 for a parallel stage)."""
    return int(stage_planets.get(mesh.rpartition(".")[0], 1))
