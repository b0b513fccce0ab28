"""Campbell diagram of a gearbox: natural frequencies over a speed range, modes tracked
by their shapes, crossings with mesh and shaft orders, and unstable speed ranges.

At each speed the modes come from :func:`pygear.analysis.modes.gyroscopic.solve_at_speed`
(Cooley & Parker's gyroscopic and centripetal terms of every member).  A mode keeps its
number from speed to speed by its shape (:mod:`pygear.analysis.modes.mode_tracking`).

An excitation is a line f = order |n_ref| / 60 through the origin.  A planetary stage
meshes Z_r |n_c - n_r| / 60 times a second (Z_s |n_s - n_c| / 60 without ring teeth), a
parallel pair Z_1 |n_1| / 60; the orders are those times 1..``harmonics``.  A shaft
order is a body's speed relative to the frame of its coordinates (a planetary stage's
members and planets in its carrier's frame), times 1..``shaft_harmonics``.  A crossing
is where a tracked mode's frequency minus a line changes sign between two speeds, placed
by linear interpolation; its excitability is, for a mesh order, the share of the mode's
strain energy held by that stage's meshes, and for a shaft order the share of its
kinetic energy in that body's in-plane translation (what an unbalance pushes).

A speed is unstable when a mode has an eigenvalue with positive real part: divergence
(real) or flutter (complex).  Unstable runs of the grid are reported as ranges whose
ends are refined by bisection on the stability of all modes.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import xarray as xr

from ...assembly.matrices import assemble
from ...assembly.speed_terms import SpeedTerms, reference_label, speed_terms
from ...errors import CaseError
from ...model.case import Case, Scene
from ...model.components import PlanetaryStage
from ...model.gearbox import ParallelStage
from ...model.scene_settings import scene_settings
from .gyroscopic import (
    STABILITY_CODES,
    SpeedModes,
    rigid_motions,
    solve_at_speed,
    whirl_names,
    whirl_ratios,
)
from .modal import classify_by_stage, model_attributes
from .mode_tracking import MAC_ACCEPT, MAC_MARGIN, REFINE_DEPTH, ModeTracker, Tracking

__all__ = ["campbell_diagram", "check_speeds", "unstable_ranges"]

SPEED_EFFECTS = ("speed_dependent_planet_terms", "gyroscopic_all_members")
"""Effects a Campbell diagram replaces with its own speed terms."""

SPEED_TERMS_NOTES = {
    "all": "Cooley & Parker (2012): gyroscopic and centripetal terms of every member of "
    "every planetary stage, in its carrier's frame",
    "planets": "Cooley & Parker (2012): gyroscopic and centripetal terms of the planets, "
    "in their carrier's frame; carrier, ring and sun in the inertial frame",
}
"""What each choice of ``members`` puts in the model."""

FREQUENCY_FRAMES = {
    "all": "each planetary stage's carrier frame; inertial elsewhere",
    "planets": "inertial (the planets' coordinates in their carrier's frame)",
}
"""The frame each choice of ``members`` gives its frequencies in."""

MAX_SPEEDS = 100_000
"""Most speeds one diagram computes."""


def check_speeds(speeds_rpm: Sequence[float], name: str = "--speeds") -> np.ndarray:
    """The speeds as an array: finite, at least two, strictly increasing."""
    try:
        speeds = np.asarray(speeds_rpm, dtype=float).ravel()
    except (TypeError, ValueError):
        raise CaseError(f"{name} must be numbers (got {speeds_rpm!r})") from None
    if speeds.size < 2:
        raise CaseError(f"{name} needs at least 2 speeds (got {speeds.size})")
    if speeds.size > MAX_SPEEDS:
        raise CaseError(f"{name} may hold at most {MAX_SPEEDS} speeds (got {speeds.size})")
    if not np.all(np.isfinite(speeds)):
        raise CaseError(f"{name} must be finite numbers")
    if np.any(np.diff(speeds) <= 0):
        raise CaseError(f"{name} must increase strictly (START < STOP)")
    return speeds


def campbell_diagram(
    case: Case,
    speeds_rpm: Sequence[float],
    *,
    scene: Scene | None = None,
    member: str = "carrier",
    harmonics: int = 3,
    shaft_harmonics: int = 2,
    damping: bool = False,
    members: str = "all",
) -> xr.Dataset:
    """Natural frequencies over a speed range, tracked, with crossings and instabilities.

    Parameters
    ----------
    case : Case
        The case.
    speeds_rpm : sequence of float
        Speeds of the reference member [rpm], strictly increasing.
    scene : Scene, optional
        The scene whose formulation, DOF set and parameter changes apply (its own
        speed-dependent effects are replaced by this diagram's terms).
    member : {"carrier", "input"}
        Reference member: the first planetary stage's carrier or the gearbox input.
    harmonics, shaft_harmonics : int
        Mesh harmonics and shaft orders per body to cross with.
    damping : bool
        Include the case's damping (damping ratios; flutter thresholds move).
    members : {"all", "planets"}
        Cooley & Parker's terms on every member, each stage in its carrier's frame;
        or on the planets only, with carrier, ring and sun in the inertial frame (the
        terms a drivetrain's gearbox block carries, whose central members share their
        shafts' DOFs).

    Returns
    -------
    xarray.Dataset
        Over (``speed``, ``mode``): ``frequency``, ``growth_rate``, ``damping_ratio``,
        ``stability``, ``whirl``, ``whirl_ratio``, ``mode_class``, ``tracking_mac``;
        ``mesh_energy_share`` over (``speed``, ``mode``, ``mesh``) and
        ``excitation_energy_share`` over (``speed``, ``mode``, ``excitation``); the
        excitation lines over ``excitation``; the crossings over ``crossing``; the
        unstable ranges over ``unstable_range``.
    """
    speeds = check_speeds(speeds_rpm)
    for name, value in (("--harmonics", harmonics), ("shaft_harmonics", shaft_harmonics)):
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise CaseError(f"{name} must be a whole number >= 0 (got {value!r})")
    reference = reference_label(case, member)
    settings = scene_settings(scene)
    if settings is not None:
        case = case.for_scene(scene)
        settings = dataclasses.replace(
            settings,
            effects=tuple(e for e in settings.effects if e not in SPEED_EFFECTS),
            carrier_speed_rpm=0.0,
        )
    model = assemble(case, settings)
    terms = speed_terms(model, case, reference, members)
    rigid_count = rigid_motions(model)

    def solve(speed: float) -> SpeedModes:
        return solve_at_speed(
            model, terms, speed, damping=damping, method="state-space", rigid_count=rigid_count
        )

    tracker = ModeTracker(solve, model.mass)
    tracking = tracker.track(speeds)
    excitations = _excitations(case, terms, harmonics, shaft_harmonics)
    dataset = _dataset(model, terms, tracking, excitations)
    dataset = _with_crossings(dataset, excitations)
    dataset = dataset.assign(**unstable_ranges(tracking, tracker.unstable))
    dataset.attrs.update(
        {
            **model_attributes(model),
            "scene": scene.name if scene is not None else "none",
            "reference": reference,
            "member": member,
            "damping_included": int(damping),
            "speed_terms": SPEED_TERMS_NOTES[members],
            "frequency_frame": FREQUENCY_FRAMES[members],
            "stage_carrier_speed_ratios": ", ".join(
                f"{k}: {v:.6g}" for k, v in terms.frame_ratios.items()
            ),
            "tracking": f"mass-weighted MAC, accept {MAC_ACCEPT}, margin {MAC_MARGIN}, "
            f"up to {REFINE_DEPTH} halvings",
            "tracking_refinements": tracking.refinements,
        }
    )
    return dataset


# --------------------------------------------------------------------------- excitations


@dataclasses.dataclass(frozen=True)
class _Excitation:
    name: str
    kind: str  # mesh or shaft
    stage: str
    harmonic: int
    order: float  # per revolution of the reference
    sources: tuple[str, ...]  # meshes (stage.sun_mesh, ...) or bodies (stage.member)


def _excitations(
    case: Case, terms: SpeedTerms, harmonics: int, shaft_harmonics: int
) -> list[_Excitation]:
    """Mesh harmonics of every mesh (a stage's sun and ring meshes as one line when their
    orders agree to 1e-9) and shaft orders of every turning body."""
    ratio = terms.speed_ratios
    found: list[_Excitation] = []
    for stage in case.gearbox.stages:
        meshes = _mesh_orders(stage, ratio)
        if len(meshes) == 2 and abs(meshes[0][1] - meshes[1][1]) <= 1e-9 * meshes[0][1]:
            meshes = [(f"{stage.name} mesh", meshes[0][1], meshes[0][2] + meshes[1][2])]
        for label, order, sources in meshes:
            for h in range(1, harmonics + 1):
                found.append(
                    _Excitation(f"{label} {h}x", "mesh", stage.name, h, h * order, sources)
                )
    lines: dict[tuple[str, float], list[str]] = {}
    for pair in terms.pairs:
        relative = abs(pair.spin_ratio - pair.frame_ratio)
        if relative <= 1e-9:
            continue
        key = (pair.stage, round(relative, 9))
        lines.setdefault(key, []).append(pair.body)
    for (stage, relative), bodies in lines.items():
        label = bodies[0] if len(bodies) == 1 else f"{stage}.planets"
        for h in range(1, shaft_harmonics + 1):
            found.append(
                _Excitation(f"{label} {h}x", "shaft", stage, h, h * relative, tuple(bodies))
            )
    return found


def _mesh_orders(stage: Any, ratio: dict[str, float]) -> list[tuple[str, float, tuple[str]]]:
    """(label, mesh events per revolution of the reference, mesh keys) of a stage's
    meshes with tooth numbers: Z_s |n_s - n_c| and Z_r |n_c - n_r| for a planetary
    stage (equal when the base radii follow the tooth numbers), Z_1 |n_1| for a pair."""
    name = stage.name
    if isinstance(stage, PlanetaryStage):
        carrier, ring, sun = (
            ratio.get(f"{name}.{member}", 0.0) for member in ("carrier", "ring", "sun")
        )
        meshes = []
        if stage.sun.teeth:
            order = stage.sun.teeth * abs(sun - carrier)
            meshes.append((f"{name} sun mesh", order, (f"{name}.sun_mesh",)))
        if stage.ring.teeth:
            order = stage.ring.teeth * abs(carrier - ring)
            meshes.append((f"{name} ring mesh", order, (f"{name}.ring_mesh",)))
        return meshes
    if isinstance(stage, ParallelStage) and stage.input_gear.teeth:
        order = stage.input_gear.teeth * abs(ratio.get(f"{name}.input_gear", 0.0))
        return [(f"{name} mesh", order, (f"{name}.mesh",))]
    return []


# --------------------------------------------------------------------------- the dataset


def _mesh_key(spring: Any) -> str:
    """``stage.sun_mesh``, ``stage.ring_mesh`` or ``stage.mesh``: the spring's stiffness
    parameter without ``.stiffness``."""
    return spring.parameters[0].removesuffix(".stiffness")


def _mesh_shares(model: Any, shapes: np.ndarray, meshes: list[str]) -> np.ndarray:
    """Share of each mode's strain energy (mean stiffness) in each mesh (all planets)."""
    full = model.reduction @ shapes
    total = np.zeros(shapes.shape[1])
    per_mesh = np.zeros((shapes.shape[1], len(meshes)))
    for spring in model.springs:
        stretch = np.abs(spring.deflection.T @ full[spring.dofs]) ** 2  # springs x modes
        energy = spring.stiffness @ stretch
        total += energy
        if spring.kind == "mesh":
            per_mesh[:, meshes.index(_mesh_key(spring))] += energy
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(total[:, None] > 0, per_mesh / total[:, None], 0.0)


def _body_shares(terms: SpeedTerms, shapes: np.ndarray) -> dict[str, np.ndarray]:
    """Share of each mode's kinetic energy in each body's in-plane translation."""
    return {
        pair.body: pair.mass
        * (np.abs(pair.first @ shapes) ** 2 + np.abs(pair.second @ shapes) ** 2)
        for pair in terms.pairs
    }


def _dataset(
    model: Any, terms: SpeedTerms, tracking: Tracking, excitations: list[_Excitation]
) -> xr.Dataset:
    speeds, tracked = tracking.speeds, tracking.modes
    tracking_mac, ambiguous = tracking.mac, tracking.ambiguous
    n_modes = tracked[0].eigenvalues.size
    meshes = list(dict.fromkeys(_mesh_key(s) for s in model.springs if s.kind == "mesh"))
    frequency = np.array([m.frequencies for m in tracked])
    growth = np.array([m.eigenvalues.real for m in tracked])
    damping = np.array([m.damping_ratios for m in tracked])
    stability = np.array([m.stability for m in tracked])
    whirl_ratio = np.zeros((speeds.size, n_modes))
    whirl = np.empty((speeds.size, n_modes), dtype=object)
    classes = np.empty((speeds.size, n_modes), dtype=object)
    mesh_share = np.zeros((speeds.size, n_modes, len(meshes)))
    excited_share = np.zeros((speeds.size, n_modes, len(excitations)))
    for k, (speed, modes) in enumerate(zip(speeds, tracked)):
        ratio, translating = whirl_ratios(terms, modes, float(speed))
        whirl_ratio[k] = ratio
        whirl[k] = whirl_names(ratio, modes.rigid | ~translating)
        classes[k] = classify_by_stage(model, modes.shapes)[1]
        mesh_share[k] = _mesh_shares(model, modes.shapes, meshes)
        bodies = _body_shares(terms, modes.shapes)
        for e, excitation in enumerate(excitations):
            if excitation.kind == "mesh":
                chosen = [meshes.index(key) for key in excitation.sources if key in meshes]
                excited_share[k, :, e] = mesh_share[k][:, chosen].sum(axis=1)
            else:
                excited_share[k, :, e] = sum(bodies[b] for b in excitation.sources)
    dims = ("speed", "mode")

    def var(dims, values, units, long_name):
        return dims, values, {"units": units, "long_name": long_name}

    dataset = xr.Dataset(
        {
            "frequency": var(dims, frequency, "Hz", "natural frequency of the tracked mode"),
            "growth_rate": var(dims, growth, "1/s", "real part of the eigenvalue"),
            "damping_ratio": var(dims, damping, "1", "modal damping ratio -Re/|lambda|"),
            "stability": var(dims, stability, "1", "0 stable, 1 divergence, 2 flutter, 3 rigid"),
            "whirl": var(dims, whirl, "1", "whirl direction seen from the housing"),
            "whirl_ratio": var(dims, whirl_ratio, "1", "(forward - backward)/(forward + backward)"),
            "mode_class": var(dims, classes, "1", "mode class (Lin & Parker families)"),
            "tracking_mac": var(
                dims,
                tracking_mac,
                "1",
                "MAC with the same mode at the previous speed (lowest over refined substeps)",
            ),
            "tracking_ambiguous": var(
                ("speed",),
                ambiguous.astype(np.int8),
                "1",
                "1 where the step from the previous speed stayed ambiguous after refinement",
            ),
            "mesh_energy_share": var(
                (*dims, "mesh"),
                mesh_share,
                "1",
                "share of the mode's strain energy in the mesh (all its planets)",
            ),
            "excitation_order": var(
                ("excitation",),
                np.array([e.order for e in excitations], dtype=float),
                "1",
                "excitation frequency per revolution of the reference member",
            ),
            "excitation_kind": var(
                ("excitation",),
                np.array([e.kind for e in excitations], dtype=object),
                "1",
                "mesh harmonic or shaft order",
            ),
            "excitation_stage": var(
                ("excitation",),
                np.array([e.stage for e in excitations], dtype=object),
                "1",
                "stage of the excitation",
            ),
            "excitation_harmonic": var(
                ("excitation",),
                np.array([e.harmonic for e in excitations], dtype=np.int64),
                "1",
                "harmonic of the mesh frequency or of the shaft speed",
            ),
            "excitation_energy_share": var(
                (*dims, "excitation"),
                excited_share,
                "1",
                "excitability: mesh lines, the share of the mode's strain energy in their "
                "meshes; shaft lines, the share of its kinetic energy in the in-plane "
                "translation of their bodies",
            ),
        },
        coords={
            "speed": var(("speed",), speeds, "rpm", "speed of the reference member"),
            "mode": var(("mode",), np.arange(1, n_modes + 1), "1", "tracked mode number"),
            "mesh": var(
                ("mesh",), np.array(meshes, dtype=object), "1", "mesh (stage.sun_mesh, ...)"
            ),
            "excitation": var(
                ("excitation",),
                np.array([e.name for e in excitations], dtype=object),
                "1",
                "excitation line",
            ),
        },
    )
    return dataset


def _with_crossings(dataset: xr.Dataset, excitations: list[_Excitation]) -> xr.Dataset:
    speeds = dataset.speed.values
    frequency = dataset.frequency.values
    rows = []
    for e, excitation in enumerate(excitations):
        line = excitation.order * np.abs(speeds) / 60.0
        for m in range(frequency.shape[1]):
            difference = frequency[:, m] - line
            for k in range(speeds.size - 1):
                a, b = difference[k], difference[k + 1]
                if frequency[k, m] <= 0 or frequency[k + 1, m] <= 0:
                    continue
                if not (a == 0 or a * b < 0):
                    continue
                weight = 0.0 if a == 0 else a / (a - b)
                speed = speeds[k] + weight * (speeds[k + 1] - speeds[k])
                shares = dataset.excitation_energy_share.values[:, :, e]
                share = (1 - weight) * shares[k, m] + weight * shares[k + 1, m]
                rows.append(
                    (
                        speed,
                        m + 1,
                        excitation.order,
                        excitation.name,
                        excitation.order * abs(speed) / 60.0,
                        share,
                    )
                )
    rows.sort(key=lambda r: (r[0], r[1]))
    columns = list(zip(*rows)) if rows else [[] for _ in range(6)]

    def var(values, dtype, units, long_name):
        attrs = {"units": units, "long_name": long_name}
        return ("crossing",), np.array(values, dtype=dtype), attrs

    return dataset.assign(
        crossing_speed=var(columns[0], float, "rpm", "speed of the crossing (linear in the step)"),
        crossing_mode=var(columns[1], np.int64, "1", "tracked mode crossing the line"),
        crossing_order=var(columns[2], float, "1", "order of the line (per reference revolution)"),
        crossing_excitation=var(columns[3], object, "1", "excitation line"),
        crossing_frequency=var(columns[4], float, "Hz", "frequency at the crossing"),
        crossing_excitability=var(
            columns[5],
            float,
            "1",
            "mesh orders: the stage's meshes' share of modal strain energy; shaft orders: "
            "the bodies' share of modal kinetic energy in in-plane translation",
        ),
    )


def unstable_ranges(tracking: Tracking, unstable_at: Callable[[float], bool]) -> dict[str, tuple]:
    """Unstable runs of the grid as ``unstable_*`` variables over ``unstable_range``.

    A run's ends are bisected between the last stable and first unstable speed with
    ``unstable_at`` (a range reaching the end of the grid ends there)."""
    speeds = tracking.speeds
    stability = np.array([m.stability for m in tracking.modes])
    unstable = np.isin(stability, (1, 2)).any(axis=1)
    ranges = []
    k = 0
    while k < speeds.size:
        if not unstable[k]:
            k += 1
            continue
        first = k
        while k + 1 < speeds.size and unstable[k + 1]:
            k += 1
        last = k
        start = speeds[first]
        if first > 0:
            start = _edge(unstable_at, speeds[first - 1], speeds[first])
        stop = speeds[last]
        if last < speeds.size - 1:
            stop = _edge(unstable_at, speeds[last + 1], speeds[last])
        codes = stability[first : last + 1]
        kinds = sorted({STABILITY_CODES[int(c)] for c in codes.ravel() if c in (1, 2)})
        modes = sorted({int(m) + 1 for m in np.flatnonzero(np.isin(codes, (1, 2)).any(axis=0))})
        ranges.append((start, stop, "+".join(kinds), " ".join(map(str, modes))))
        k += 1
    columns = list(zip(*ranges)) if ranges else [[] for _ in range(4)]

    def var(values, dtype, units, long_name):
        attrs = {"units": units, "long_name": long_name}
        return ("unstable_range",), np.array(values, dtype=dtype), attrs

    return {
        "unstable_start": var(columns[0], float, "rpm", "first unstable speed (bisected)"),
        "unstable_stop": var(columns[1], float, "rpm", "last unstable speed (bisected)"),
        "unstable_kind": var(columns[2], object, "1", "divergence and/or flutter"),
        "unstable_modes": var(columns[3], object, "1", "tracked modes unstable in the range"),
    }


def _edge(unstable_at: Callable[[float], bool], stable: float, unstable: float) -> float:
    """Bisect between a stable and an unstable speed to 1e-9 of their magnitude."""
    tolerance = 1e-9 * max(abs(stable), abs(unstable), 1.0)
    for _ in range(80):
        if abs(unstable - stable) <= tolerance:
            break
        middle = 0.5 * (stable + unstable)
        if unstable_at(middle):
            unstable = middle
        else:
            stable = middle
    return float(unstable)
