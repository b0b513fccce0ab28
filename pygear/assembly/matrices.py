"""Element assembly of a gearbox: DOF numbering, element matrices, constraints.

The steps are the paper's (docs/model.md §4): number the DOFs node by node, add every
element at its DOFs, then apply the constraints through a reduction matrix T
(q_full = T q): the housing and every DOF outside the scene's DOF set have no
column; a planet's revolution phi shares the carrier's theta_z column.

This module is longer than 600 lines because the element builder places every element
kind of both stage types against one DOF map; the DOF-row helpers and the contact table
already live beside it (:mod:`.dof_rows`, :mod:`.contact_table`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import CaseError
from ..kernel import _kernel
from ..kernel.calls import FORMULATION_CODES, MESH_KINDS, call
from ..model.case import DOF_SETS, FORMULATIONS, Case, check_choice
from ..model.components import PlanetaryStage
from ..model.gearbox import CENTRAL_DOFS, PLANET_DOFS, ParallelStage, RigidLink, TorsionalSpring
from ..model.scene_settings import SceneSettings, scene_settings
from .mesh_laws import mesh_law

if TYPE_CHECKING:  # a Scene is only resolved here (model.scene_settings), never read
    from ..model.case import Scene

__all__ = [
    "CENTRAL_DOFS",
    "PLANET_DOFS",
    "MassPart",
    "MeshElement",
    "Model",
    "SpringElement",
    "assemble",
    "choose_dof_set",
]

IN_PLANE_DOFS = frozenset({"x", "y", "theta_z", "zeta", "eta", "phi"})
DOF_SET_MEMBERS = {
    "spatial": frozenset(CENTRAL_DOFS + PLANET_DOFS),
    "planar": IN_PLANE_DOFS,
    "torsional": frozenset({"theta_z", "phi"}),
}
TRANSLATION_DOFS = frozenset({"x", "y", "z", "zeta", "eta", "phi"})


@dataclass(frozen=True)
class Node:
    """A rigid body and the slice of the full DOF vector that belongs to it."""

    name: str
    role: str  # housing, central or planet
    dof_names: tuple[str, ...]
    first: int

    @property
    def dofs(self) -> np.ndarray:
        """Full DOF indices of this node."""
        return np.arange(self.first, self.first + len(self.dof_names))


@dataclass(frozen=True)
class SpringElement:
    """An elastic element as springs k_s with deflection vectors b_s over full DOFs."""

    name: str
    kind: str
    parameters: tuple[str, ...]
    dofs: np.ndarray
    deflection: np.ndarray
    stiffness: np.ndarray


@dataclass(frozen=True)
class MassPart:
    """One part of a body's kinetic energy (translation or rotation, in or out of plane)."""

    body: str
    role: str
    motion: str
    plane: str
    dofs: np.ndarray
    matrix: np.ndarray


@dataclass(frozen=True)
class MeshElement:
    """A gear mesh as the transient and the contact table see it."""

    name: str
    stage: str
    kind: str  # external or internal
    mean_stiffness: float
    contact_ratio: float
    end_to_peak: float
    planet: int
    planet_angle: float
    deflection: np.ndarray  # over the reduced DOFs
    # c_m [N s/m]: the mesh's damper inside the model's C, c_m b b^T along the deflection
    # (beta kbar of the Rayleigh damping beta K0); tooth separation switches it off
    # while the flanks are apart
    damping: float = 0.0


@dataclass
class Model:
    """An assembled, reduced gearbox model.

    Attributes
    ----------
    mass, stiffness, damping : ndarray
        Reduced M, K0 (mean mesh stiffness) and Rayleigh C.
    gyroscopic : ndarray or None
        Reduced Coriolis matrix when the scene asks for speed-dependent terms.
    shaft_gyroscopic : scipy.sparse matrix or None
        A whole drivetrain's spinning shafts and discs: G per rad/s of the rotor
        (each shaft's part times its speed ratio), which the transient applies at the
        rotor's own speed (:mod:`pygear.kernel.newmark_rotor`).
    reduction : ndarray
        T with q_full = T q.
    dof_labels, full_labels : list of str
        Names of the reduced and the full DOFs (``stage.member.dof``).
    """

    case_name: str
    formulation: str
    dof_set: str
    dof_set_reason: str
    nodes: list[Node]
    full_labels: list[str]
    dof_labels: list[str]
    reduction: np.ndarray
    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    springs: list[SpringElement]
    mass_parts: list[MassPart]
    meshes: list[MeshElement]
    effects: tuple[str, ...] = ()
    gyroscopic: np.ndarray | None = None
    attributes: dict = field(default_factory=dict)
    spatial_size: int = 0  # reduced DOFs of the same gearbox with the spatial DOF set
    shaft_gyroscopic: Any = None

    @property
    def size(self) -> int:
        """Number of reduced DOFs."""
        return self.mass.shape[0]

    def reduce(self, full_matrix: np.ndarray) -> np.ndarray:
        """T^T A T for a matrix over the full DOFs."""
        return self.reduction.T @ full_matrix @ self.reduction

    def stiffness_of(self, parameter: str) -> np.ndarray:
        """dK/dp: the reduced stiffness of the springs scaled by ``parameter``."""
        n_full = len(self.full_labels)
        full = np.zeros((n_full, n_full))
        found = False
        for spring in self.springs:
            chosen = np.array([p == parameter for p in spring.parameters])
            if chosen.any():
                found = True
                b = spring.deflection[:, chosen]
                full[np.ix_(spring.dofs, spring.dofs)] += b @ b.T
        if not found:
            known = sorted({p for s in self.springs for p in s.parameters})
            raise CaseError(
                f"--parameter {parameter!r} is not a stiffness of this model "
                f"(stiffness parameters: {', '.join(known)})"
            )
        return self.reduce(full)

    def stiffness_parameters(self) -> list[str]:
        """Every stiffness parameter path that scales springs of this model."""
        return sorted({p for s in self.springs for p in s.parameters})


def choose_dof_set(
    case: Case, scene: SceneSettings | None, override: str | None = None
) -> tuple[str, str]:
    """The DOF set for a scene (its resolved settings), and why.

    A scene's own choice wins; otherwise a gearbox of spur stages is planar (its
    out-of-plane DOFs are decoupled, so the in-plane answer is exact), any helical
    stage makes it spatial.
    """
    if override is not None:
        check_choice("--dof-set", override, DOF_SETS)
        return override, "asked for on the command line"
    if scene is not None and scene.dof_set is not None:
        return scene.dof_set, f"set by scene {scene.name!r}"
    spatial = _spatial_stages(case)
    if not spatial:
        return "planar", "chosen: spur stages only, out-of-plane DOFs decoupled"
    if len(spatial) == len(case.gearbox.stages):
        return "spatial", "chosen: every stage couples in-plane and out-of-plane DOFs"
    return "per-stage", (
        f"chosen: {', '.join(sorted(spatial))} spatial (helical, or coupled out of plane), "
        "the spur stages planar (their out-of-plane DOFs are decoupled)"
    )


def _spatial_stages(case: Case) -> set[str]:
    """Stages whose out-of-plane DOFs a scene cannot drop: helical ones, and those a
    coupling reaches out of plane."""
    spatial = {stage.name for stage in case.gearbox.stages if not stage.spur}
    for coupling in case.gearbox.couplings:
        for label in (coupling.a, coupling.b):
            stage, _, dof = label.split(".")
            if dof not in IN_PLANE_DOFS:
                spatial.add(stage)
    return spatial


def _kept_dofs(case: Case, dof_set: str) -> dict[str, frozenset[str]]:
    """DOF names kept at the nodes of each stage."""
    if dof_set != "per-stage":
        return {stage.name: DOF_SET_MEMBERS[dof_set] for stage in case.gearbox.stages}
    spatial = _spatial_stages(case)
    return {
        stage.name: DOF_SET_MEMBERS["spatial" if stage.name in spatial else "planar"]
        for stage in case.gearbox.stages
    }


def assemble(
    case: Case,
    scene: Scene | SceneSettings | None = None,
    *,
    formulation: str | None = None,
    dof_set: str | None = None,
) -> Model:
    """Assemble and reduce the case's gearbox for a scene.

    Parameters
    ----------
    case : Case
        The case (validated on construction).
    scene : Scene or SceneSettings, optional
        Scene whose formulation, DOF set and effects apply; a ``Scene`` is resolved
        into its :class:`~pygear.model.scene_settings.SceneSettings` first, and only
        those are read.
    formulation, dof_set : str, optional
        Overrides of the scene's choices.
    """
    case.validate()
    scene = scene_settings(scene)
    formulation = formulation or (scene.formulation if scene else None) or case.formulation
    check_choice("formulation", formulation, FORMULATIONS)
    dof_set, reason = choose_dof_set(case, scene, dof_set)
    if formulation == "lin-parker" and len(case.gearbox.stages) > 1:
        raise CaseError(
            "formulation 'lin-parker' describes one stage in its carrier's rotating frame; "
            "a gearbox of several stages needs 'improved' or 'consistent'"
        )
    effects = scene.effects if scene else ()

    builder = _Builder(formulation)
    builder.add_node("housing", "housing", CENTRAL_DOFS)
    for stage in case.gearbox.stages:
        if isinstance(stage, PlanetaryStage):
            builder.add_planetary_stage(stage, effects, scene)
        elif isinstance(stage, ParallelStage):
            builder.add_parallel_stage(stage)
        else:
            builder.add_central_member(stage, "body", stage.body, stage.bearing)
    coupling_damping = builder.add_couplings(case.gearbox.couplings)

    reduction, reduced = builder.reduction(_kept_dofs(case, dof_set))
    spatial_size = builder.reduction(_kept_dofs(case, "spatial"))[0].shape[1]
    mass_full = sum(_embed(len(builder.labels), p.dofs, p.matrix) for p in builder.mass_parts)
    stiffness_full = np.zeros_like(mass_full)
    for spring in builder.springs:
        b = spring.deflection
        stiffness_full[np.ix_(spring.dofs, spring.dofs)] += (b * spring.stiffness) @ b.T
    stiffness_full += builder.extra_stiffness(mass_full.shape[0])
    mass = reduction.T @ mass_full @ reduction
    stiffness = reduction.T @ stiffness_full @ reduction
    damping = (
        case.damping.mass_coefficient * mass
        + case.damping.stiffness_coefficient * stiffness
        + reduction.T @ coupling_damping @ reduction
    )
    _check_rigid_body_modes(case, mass, stiffness)
    gyroscopic = None
    if builder.gyroscopic_parts:
        gyroscopic_full = sum(
            _embed(len(builder.labels), dofs, g) for dofs, g in builder.gyroscopic_parts
        )
        gyroscopic = reduction.T @ gyroscopic_full @ reduction

    meshes = [
        MeshElement(
            **info,
            deflection=reduction.T @ _vector(len(builder.labels), dofs, b),
            damping=case.damping.stiffness_coefficient * info["mean_stiffness"],
        )
        for info, dofs, b in builder.mesh_records
    ]
    model = Model(
        case_name=case.name,
        formulation=formulation,
        dof_set=dof_set,
        dof_set_reason=reason,
        nodes=builder.nodes,
        full_labels=builder.labels,
        dof_labels=[builder.labels[i] for i in reduced],
        reduction=reduction,
        mass=_symmetric(mass),
        stiffness=_symmetric(stiffness),
        damping=_symmetric(damping),
        springs=builder.springs,
        mass_parts=builder.mass_parts,
        meshes=meshes,
        effects=tuple(effects),
        gyroscopic=gyroscopic,
        attributes=_scene_attributes(case, scene),
        spatial_size=spatial_size,
    )
    if "gyroscopic_all_members" in effects:  # Cooley & Parker's terms, every member
        from .speed_terms import apply_speed_terms

        model = apply_speed_terms(model, case, scene.carrier_speed_rpm)
    return model


def _scene_attributes(case: Case, scene: SceneSettings | None) -> dict:
    """What the scene asks for beyond the matrices, for the record of effects in force."""
    from ..model.case import merged_defects

    damping = case.damping
    return {
        "damping": (
            f"Rayleigh alpha = {damping.mass_coefficient:g} 1/s, "
            f"beta = {damping.stiffness_coefficient:g} s"
        ),
        "tooth_defects": len(merged_defects(case, scene)),
        "helical_stages": tuple(s.name for s in case.gearbox.stages if not s.spur),
        "carrier_speed_rpm": scene.carrier_speed_rpm if scene else 0.0,
    }


class _Builder:
    """Collects nodes, mass parts, springs and ties while a gearbox is numbered."""

    def __init__(self, formulation: str) -> None:
        self.formulation = formulation
        self.code = FORMULATION_CODES[formulation]
        self.nodes: list[Node] = []
        self.labels: list[str] = []
        self.springs: list[SpringElement] = []
        self.mass_parts: list[MassPart] = []
        self.mesh_records: list[tuple[dict, np.ndarray, np.ndarray]] = []
        self.ties: dict[int, tuple[int, float, str]] = {}
        self.centrifugal_parts: list[tuple[np.ndarray, np.ndarray]] = []
        self.gyroscopic_parts: list[tuple[np.ndarray, np.ndarray]] = []

    def add_node(self, name: str, role: str, dof_names: tuple[str, ...]) -> Node:
        node = Node(name, role, dof_names, len(self.labels))
        self.nodes.append(node)
        self.labels.extend(f"{name}.{d}" for d in dof_names)
        return node

    def add_body_mass(self, node: Node, translation: np.ndarray, rotation: np.ndarray) -> None:
        n = len(node.dof_names)
        for motion, matrix in (
            ("translation", translation[:n, :n]),
            ("rotation", rotation[:n, :n]),
        ):
            for plane in ("in-plane", "out-of-plane"):
                keep = np.array(
                    [(d in IN_PLANE_DOFS) == (plane == "in-plane") for d in node.dof_names]
                )
                part = np.where(np.outer(keep, keep), matrix, 0.0)
                if np.any(part):
                    self.mass_parts.append(
                        MassPart(node.name, node.role, motion, plane, node.dofs, part)
                    )

    def add_planetary_stage(
        self, stage: PlanetaryStage, effects: tuple[str, ...], scene: SceneSettings | None
    ) -> None:
        lin_parker = self.formulation == "lin-parker"
        planet_dofs = PLANET_DOFS[:6] if lin_parker else PLANET_DOFS
        central = {}
        for member in ("carrier", "ring", "sun"):
            central[member] = self.add_central_member(
                stage, member, getattr(stage, member), getattr(stage, f"{member}_bearing")
            )

        carrier = central["carrier"]
        r_c = stage.carrier.radius
        planet_mass = call(
            "planet_mass_matrix",
            self.code,
            stage.planet.mass,
            stage.planet.tilt_inertia,
            stage.planet.polar_inertia,
            r_c,
        )
        carrier_speed = scene.carrier_speed_rpm * math.pi / 30 if scene else 0.0
        for n, psi in enumerate(stage.planet_angles, start=1):
            node = self.add_node(f"{stage.name}.planet{n}", "planet", planet_dofs)
            self.add_body_mass(node, *planet_mass)
            theta_c = carrier.first + CENTRAL_DOFS.index("theta_z")
            if lin_parker:
                # a torsional Lin-Parker set keeps eta on the carrier's rigid turning
                self.ties[node.first + 1] = (theta_c, r_c, "torsional")
            else:
                self.ties[node.first + 6] = (theta_c, 1.0, "always")
            deflection, stiffness = call(
                "planet_bearing_springs",
                psi,
                r_c,
                stage.planet_bearing.radial,
                stage.planet_bearing.axial,
                stage.planet_bearing.tilt,
            )
            size = len(CENTRAL_DOFS) + len(planet_dofs)
            prefix = f"{stage.name}.planet_bearing."
            self.springs.append(
                SpringElement(
                    f"{stage.name}.planet{n}_bearing",
                    "planet_bearing",
                    tuple(prefix + p for p in ("radial", "radial", "axial", "tilt", "tilt")),
                    np.concatenate([carrier.dofs, node.dofs]),
                    deflection[:size],
                    stiffness,
                )
            )
            for gear_name, mesh in (("sun", stage.sun_mesh), ("ring", stage.ring_mesh)):
                gear = getattr(stage, gear_name)
                (deflection,) = call(
                    "planetary_mesh_vector",
                    MESH_KINDS[gear_name],
                    psi,
                    mesh.pressure_angle,
                    gear.base_radius,
                    stage.planet.base_radius,
                    r_c,
                    stage.base_helix_angle,
                )
                dofs = np.concatenate([central[gear_name].dofs, node.dofs])
                b = deflection[:size].reshape(-1, 1)
                mean_stiffness = mesh_law(stage, gear_name).mean_stiffness  # typed or derived
                self.springs.append(
                    SpringElement(
                        f"{stage.name}.{gear_name}-planet{n}",
                        "mesh",
                        (f"{stage.name}.{gear_name}_mesh.stiffness",),
                        dofs,
                        b,
                        np.array([mean_stiffness]),
                    )
                )
                info = dict(
                    name=f"{gear_name}-planet{n}",
                    stage=stage.name,
                    kind="external" if gear_name == "sun" else "internal",
                    mean_stiffness=mean_stiffness,
                    contact_ratio=mesh.contact_ratio,
                    end_to_peak=mesh.end_to_peak,
                    planet=n,
                    planet_angle=psi,
                )
                self.mesh_records.append((info, dofs, b[:, 0]))
            if "speed_dependent_planet_terms" in effects and carrier_speed != 0.0:
                gyroscopic, centrifugal = _kernel.planet_speed_matrices(
                    stage.planet.mass, carrier_speed
                )
                n_dofs = len(planet_dofs)
                self.gyroscopic_parts.append((node.dofs, gyroscopic[:n_dofs, :n_dofs]))
                self.centrifugal_parts.append((node.dofs, centrifugal[:n_dofs, :n_dofs]))

    def extra_stiffness(self, n_full: int) -> np.ndarray:
        """Centrifugal softening of the planets (zero unless the scene asks for it)."""
        total = np.zeros((n_full, n_full))
        for dofs, matrix in self.centrifugal_parts:
            total[np.ix_(dofs, dofs)] += matrix
        return total

    def reduction(self, kept_by_stage: dict[str, frozenset[str]]) -> tuple[np.ndarray, list[int]]:
        """Reduction matrix T and the full index of each reduced DOF."""
        n_full = len(self.labels)
        dof_name = [label.rsplit(".", 1)[1] for label in self.labels]
        housing = set(self.nodes[0].dofs.tolist())
        stage_of = [label.split(".", 1)[0] for label in self.labels]
        torsional = all("x" not in kept for kept in kept_by_stage.values())
        free = []
        for i in range(n_full):
            tie = self.ties.get(i)
            if tie and (tie[2] == "always" or torsional):
                continue
            if i in housing or dof_name[i] not in kept_by_stage[stage_of[i]]:
                continue
            free.append(i)
        column = {full: col for col, full in enumerate(free)}
        reduction = np.zeros((n_full, len(free)))
        for full, col in column.items():
            reduction[full, col] = 1.0
        for i, (target, factor, when) in self.ties.items():
            if when != "always" and not torsional:
                continue
            while target in self.ties and self.ties[target][2] == "always":
                factor *= self.ties[target][1]
                target = self.ties[target][0]
            if target in column:
                reduction[i, column[target]] = factor
        return reduction, free

    def add_central_member(self, stage, member: str, body, bearing) -> Node:
        """A 6-DOF body in the inertial frame with its bearing to the housing."""
        node = self.add_node(f"{stage.name}.{member}", "central", CENTRAL_DOFS)
        self.add_body_mass(
            node, *call("central_mass_matrix", body.mass, body.tilt_inertia, body.polar_inertia)
        )
        position = (
            np.array(stage.position(member))
            if hasattr(stage, "position")
            else np.array([0.0, 0.0, stage.axial_position])
        )
        deflection, stiffness = call(
            "central_bearing_springs",
            bearing.radial,
            bearing.axial,
            bearing.tilt,
            bearing.torsional,
            position,
        )
        name = "bearing" if member == "body" else f"{member.removesuffix('_gear')}_bearing"
        prefix = f"{stage.name}.{name}."
        self.springs.append(
            SpringElement(
                f"{stage.name}.{member}_bearing",
                "central_bearing",
                tuple(
                    prefix + p for p in ("radial", "radial", "axial", "tilt", "tilt", "torsional")
                ),
                np.concatenate([node.dofs, self.nodes[0].dofs]),
                deflection,
                stiffness,
            )
        )
        return node

    def add_parallel_stage(self, stage: ParallelStage) -> None:
        """Input and output gear with their bearings and the (helical) mesh."""
        gear_in = self.add_central_member(
            stage, "input_gear", stage.input_gear, stage.input_bearing
        )
        gear_out = self.add_central_member(
            stage, "output_gear", stage.output_gear, stage.output_bearing
        )
        (deflection,) = call(
            "parallel_mesh_vector",
            math.radians(stage.centre_angle_deg),
            stage.mesh.pressure_angle,
            stage.input_gear.base_radius,
            stage.output_gear.base_radius,
            math.radians(stage.base_helix_angle_deg),
        )
        dofs = np.concatenate([gear_in.dofs, gear_out.dofs])
        mean_stiffness = mesh_law(stage, "mesh").mean_stiffness  # typed or derived
        self.springs.append(
            SpringElement(
                f"{stage.name}.mesh",
                "mesh",
                (f"{stage.name}.mesh.stiffness",),
                dofs,
                deflection.reshape(-1, 1),
                np.array([mean_stiffness]),
            )
        )
        info = dict(
            name="input-output",
            stage=stage.name,
            kind="external",
            mean_stiffness=mean_stiffness,
            contact_ratio=stage.mesh.contact_ratio,
            end_to_peak=stage.mesh.end_to_peak,
            planet=0,
            planet_angle=math.radians(stage.centre_angle_deg),
        )
        self.mesh_records.append((info, dofs, deflection))

    def add_couplings(self, couplings: tuple) -> np.ndarray:
        """Rigid links become ties; torsional springs become springs. Returns the
        couplings' damping over the full DOFs."""
        index = {label: i for i, label in enumerate(self.labels)}
        damping = np.zeros((len(self.labels), len(self.labels)))
        for coupling in couplings:
            a, b = index[coupling.a], index[coupling.b]
            if isinstance(coupling, RigidLink):
                self.ties[b] = (a, coupling.ratio, "always")
            elif isinstance(coupling, TorsionalSpring):
                vector = np.array([[1.0], [-1.0]])
                self.springs.append(
                    SpringElement(
                        f"couplings.{coupling.name}",
                        "coupling",
                        (f"couplings.{coupling.name}.stiffness",),
                        np.array([a, b]),
                        vector,
                        np.array([coupling.stiffness]),
                    )
                )
                damping[np.ix_([a, b], [a, b])] += coupling.damping * (vector @ vector.T)
        return damping


def _check_rigid_body_modes(case: Case, mass: np.ndarray, stiffness: np.ndarray) -> None:
    """Refuse a gearbox whose count of free rigid-body motions is not the declared one."""
    from ..linalg import generalized_eigh

    eigenvalues = generalized_eigh(stiffness, mass, eigenvalues_only=True)
    count = int(np.sum(eigenvalues < 1e-10 * max(abs(eigenvalues).max(), 1.0)))
    expected = case.gearbox.rigid_body_modes
    if count != expected:
        raise CaseError(
            f"gearbox.rigid_body_modes: the assembled gearbox has {count} free rigid-body "
            f"motions, {expected} expected: a part is disconnected or held twice "
            "(check couplings and torsional bearing stiffnesses)"
        )


def _embed(n: int, dofs: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    full = np.zeros((n, n))
    full[np.ix_(dofs, dofs)] = matrix
    return full


def _vector(n: int, dofs: np.ndarray, values: np.ndarray) -> np.ndarray:
    full = np.zeros(n)
    full[dofs] = values
    return full


def _symmetric(matrix: np.ndarray) -> np.ndarray:
    return 0.5 * (matrix + matrix.T)
