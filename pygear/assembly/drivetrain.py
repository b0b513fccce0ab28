"""A drivetrain as one sparse model: flexible shafts around an assembled gearbox.

The shafts, bearings, couplings, rotor and generator of a
:class:`~pygear.model.drivetrain.Drivetrain` go through
:class:`~pygear.assembly.structure.Structure` (Timoshenko shaft elements, discs,
bearing and coupling springs; Friswell, Penny, Garvey & Lees, *Dynamics of Rotating
Machines*, 2010, ch. 5).  The gearbox is assembled by :func:`~pygear.assembly.matrices
.assemble` as usual, and its reduced matrices enter as one dense block.

Ties by exact elimination
    A gearbox member that sits on a shaft end (a :class:`GearboxMount`) shares that
    node's DOFs: each structure DOF of the node that the gearbox model keeps is
    replaced by the member's DOF (q_node = q_member, a rigid joint written as a
    change of variables, not as a spring).  A stiff tie spring would add a tie mode
    at a frequency set by an arbitrary stiffness and spoil the conditioning of the
    shift-invert eigensolver; elimination adds neither, and it changes no frequency
    that the joint does not change (the test compares with the same joint written
    through a coupling of growing stiffness).  The node's DOFs that the gearbox model
    drops (the out-of-plane ones of a planar stage) stay the structure's own.

Numbering
    The structure's own DOFs come first, then the gearbox's reduced DOFs as one
    contiguous block at ``gearbox_offset``, in the gearbox model's order: a vector
    ``v`` over the gearbox's reduced DOFs (a mesh's deflection row) is the global
    vector with ``v`` placed at ``gearbox_offset``.

DOF sets
    ``spatial`` keeps all six DOFs of every shaft node and the gearbox's spatial DOFs.
    ``torsional`` keeps theta_z of every shaft node and the gearbox's torsional DOFs.
    For the shafts, discs, bearings and couplings this is exact (a straight
    axisymmetric shaft, diagonal bearings and couplings on one axis couple no
    torsion to bending or translation); the gear meshes do couple the members'
    rotations to their translations, so with a gearbox the torsional set is the
    gearbox's torsional model (bearings rigid in translation, Lin & Parker 1999).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp

from ..errors import CaseError
from ..linalg import generalized_eigh
from ..model.case import FORMULATIONS, Case, check_choice
from ..model.drivetrain import Drivetrain, Shaft
from ..model.scene_settings import scene_settings
from .matrices import Model, assemble
from .shaft_elements import (
    ElementMatrices,
    bearing_element,
    coupling_element,
    disc_element,
    shaft_element,
)
from .structure import NODE_DOFS, Structure, StructureMatrices

if TYPE_CHECKING:
    from ..model.case import Scene
    from ..model.scene_settings import SceneSettings

__all__ = [
    "DRIVETRAIN_DOF_SETS",
    "BearingTable",
    "DrivetrainModel",
    "assemble_drivetrain",
    "bearing_tables",
    "build_structure",
    "drivetrain_formulation",
    "node_number",
    "shaft_speed_ratios",
]

DRIVETRAIN_DOF_SETS = ("spatial", "torsional")
"""DOF sets of a drivetrain model."""


@dataclass
class DrivetrainModel:
    """An assembled drivetrain: sparse matrices over the structure's and the gearbox's DOFs.

    Attributes
    ----------
    case_name : str
        The case.
    dof_set : str
        ``spatial`` or ``torsional``.
    labels : list of str
        One label per DOF: ``<node>.<dof>`` for shaft nodes (``main_shaft_3.theta_z``),
        the gearbox model's ``stage.member.dof`` for its block.
    mass, stiffness, damping : scipy.sparse.csc_matrix
        M, K and C [SI].
    gyroscopic : scipy.sparse.csc_matrix
        G per unit rotor speed [kg m^2]: each shaft element's own G times its shaft's
        speed over the rotor's, so that ``Omega_rotor G`` is the drivetrain's term.
    gearbox : Model or None
        The gearbox's assembled model (its reduced DOFs are the block); None for a
        plain rotor.
    gearbox_offset : int
        First global index of the gearbox block (the size for a plain rotor).
    end_nodes : dict of str to str
        The node name of every shaft end (``"main_shaft.end" -> "main_shaft_4"``).
    tied : dict of str to str
        Every eliminated structure DOF and the gearbox member DOF it became (a full
        gearbox label; a rigid link may have removed it from the reduced ones).
    speed_ratios : dict of str to float
        Each shaft's speed over the rotor's [-].
    bearing_tables : list of BearingTable
        Bearings whose lateral coefficients come from a
        :class:`~pygear.model.rotor.BearingCoefficients` table: not in ``stiffness``
        and ``damping``; :meth:`at_speed` adds them at a speed.
    """

    case_name: str
    dof_set: str
    labels: list[str]
    mass: sp.csc_matrix
    stiffness: sp.csc_matrix
    damping: sp.csc_matrix
    gyroscopic: sp.csc_matrix
    gearbox: Model | None
    gearbox_offset: int
    end_nodes: dict[str, str]
    tied: dict[str, str] = field(default_factory=dict)
    speed_ratios: dict[str, float] = field(default_factory=dict)
    bearing_tables: list[BearingTable] = field(default_factory=list)

    @property
    def size(self) -> int:
        """Number of DOFs."""
        return len(self.labels)

    def at_speed(self, speed_rpm: float) -> tuple[sp.csc_matrix, sp.csc_matrix]:
        """K and C at a rotor speed [rpm]: the table bearings' coefficients interpolated
        at their shafts' speeds added to ``stiffness`` and ``damping``."""
        if not self.bearing_tables:
            return self.stiffness, self.damping
        rows, columns, k_values, c_values = [], [], [], []
        for table in self.bearing_tables:
            stiffness, damping = table.coefficients.at(speed_rpm * table.speed_ratio)
            dofs = [self.index(label) for label in table.labels]
            for i in range(2):
                for j in range(2):
                    rows.append(dofs[i])
                    columns.append(dofs[j])
                    k_values.append(stiffness[i, j])
                    c_values.append(damping[i, j])
        shape = (self.size, self.size)
        added_k = sp.csc_matrix((k_values, (rows, columns)), shape=shape)
        added_c = sp.csc_matrix((c_values, (rows, columns)), shape=shape)
        return sp.csc_matrix(self.stiffness + added_k), sp.csc_matrix(self.damping + added_c)

    def index(self, label: str) -> int:
        """Global index of a DOF label; an eliminated node DOF gives its gearbox DOF."""
        label = self.tied.get(label, label)
        if (
            label not in self.labels
            and self.gearbox is not None
            and label in self.gearbox.full_labels
        ):
            column = self.gearbox.reduction[self.gearbox.full_labels.index(label)]
            label = self.gearbox.dof_labels[int(np.argmax(abs(column)))]  # its master
        try:
            return self.labels.index(label)
        except ValueError:
            raise CaseError(f"{label!r} is not a DOF of this drivetrain model") from None

    def end_label(self, end: str, dof: str = "theta_z") -> str:
        """The global label of a shaft end's DOF (``"main_shaft.end"``)."""
        label = f"{self.end_nodes[end]}.{dof}"
        return self.tied.get(label, label)

    def node_label(self, shaft: Shaft, position: float, dof: str) -> str:
        """The global label of a DOF at the node of ``shaft`` nearest ``position`` [m]."""
        label = f"{shaft.name}_{node_number(shaft, position)}.{dof}"
        return self.tied.get(label, label)


@dataclass(frozen=True)
class BearingTable:
    """A bearing whose x-y stiffness and damping come from a coefficient table.

    Attributes
    ----------
    name : str
        The bearing.
    labels : tuple of str
        Its node's ``x`` and ``y`` DOF labels.
    coefficients : BearingCoefficients
        The table (speeds of the bearing's shaft).
    speed_ratio : float
        Its shaft's speed over the rotor's [-].
    """

    name: str
    labels: tuple[str, str]
    coefficients: Any
    speed_ratio: float = 1.0


def assemble_drivetrain(
    case: Case,
    scene: Scene | SceneSettings | None = None,
    *,
    dof_set: str | None = None,
    formulation: str | None = None,
    gearbox_model: Model | None = None,
) -> DrivetrainModel:
    """Assemble the case's drivetrain for a scene.

    Parameters
    ----------
    case : Case
        A case with a drivetrain.
    scene : Scene or SceneSettings, optional
        Its DOF set (``spatial`` or ``torsional``) and formulation apply.
    dof_set : str, optional
        Overrides the scene's DOF set; ``spatial`` when neither gives one.
    formulation : str, optional
        The gearbox's formulation, overriding the scene's and the case's: ``improved``
        or ``consistent`` (their carrier, ring and sun are in the inertial frame, as
        the shafts are); ``lin-parker``, a stage in its carrier's rotating frame, is
        refused.
    gearbox_model : Model, optional
        The gearbox block to use instead of assembling the case's gearbox (a model of
        the same gearbox with the DOF set's DOFs: a test's rigid or scaled gearbox).
    """
    drivetrain = case.drivetrain
    if drivetrain is None:
        raise CaseError(f"case {case.name!r} has no drivetrain (Case.drivetrain)")
    settings = scene_settings(scene)
    dof_set = dof_set or (settings.dof_set if settings else None) or "spatial"
    check_choice("dof_set", dof_set, DRIVETRAIN_DOF_SETS)
    if drivetrain.gearbox is None:
        return _rotor_model(case.name, drivetrain, dof_set)
    formulation = drivetrain_formulation(case, settings, formulation)
    gearbox = gearbox_model or assemble(case, settings, formulation=formulation, dof_set=dof_set)
    ratios = shaft_speed_ratios(case)
    structure, end_nodes = build_structure(drivetrain, ratios)
    matrices = structure.assemble()
    if dof_set == "torsional":
        matrices = matrices.torsional()
    model = _combine(case.name, dof_set, matrices, gearbox, drivetrain, end_nodes, ratios)
    if dof_set == "spatial":
        model.bearing_tables = bearing_tables(drivetrain, ratios)
    return model


def _rotor_model(name: str, drivetrain: Drivetrain, dof_set: str) -> DrivetrainModel:
    """A plain rotor (no gearbox): the structure alone; every shaft turns with the rotor
    (they can be joined by couplings only)."""
    ratios = {shaft.name: 1.0 for shaft in drivetrain.shafts}
    structure, end_nodes = build_structure(drivetrain, ratios)
    matrices = structure.assemble()
    if dof_set == "torsional":
        matrices = matrices.torsional()
    return DrivetrainModel(
        case_name=name,
        dof_set=dof_set,
        labels=list(matrices.labels),
        mass=matrices.mass,
        stiffness=matrices.stiffness,
        damping=matrices.damping,
        gyroscopic=matrices.gyroscopic,
        gearbox=None,
        gearbox_offset=matrices.size,
        end_nodes=end_nodes,
        speed_ratios=ratios,
        bearing_tables=bearing_tables(drivetrain, ratios) if dof_set == "spatial" else [],
    )


def drivetrain_formulation(
    case: Case,
    scene: Scene | SceneSettings | None = None,
    formulation: str | None = None,
    parameter: str = "formulation",
) -> str:
    """The formulation of a drivetrain's gearbox: ``formulation``, else the scene's,
    else the case's.

    Raises
    ------
    CaseError
        Naming ``parameter`` (or the scene's setting) for ``lin-parker``: a stage in
        its carrier's rotating frame, whose members cannot share the shafts' inertial
        DOFs.
    """
    settings = scene_settings(scene)
    chosen = formulation
    if chosen is None and settings is not None and settings.formulation is not None:
        chosen, parameter = settings.formulation, f"scenes.{settings.name}.formulation"
    chosen = chosen or case.formulation
    check_choice(parameter, chosen, FORMULATIONS)
    if chosen == "lin-parker":
        raise CaseError(
            f"{parameter} 'lin-parker' describes a stage in its carrier's rotating frame, "
            "which a drivetrain's shafts cannot join; a drivetrain's gearbox needs "
            "'improved' or 'consistent'"
        )
    return chosen


def build_structure(
    drivetrain: Drivetrain, speed_ratios: dict[str, float] | None = None
) -> tuple[Structure, dict[str, str]]:
    """The shafts, bearings, couplings, rotor and generator as a :class:`Structure`.

    Returns the structure and the node name of every shaft end.  Each shaft element's
    gyroscopic matrix is scaled by its shaft's speed ratio (1 when not given).
    """
    structure = Structure()
    end_nodes: dict[str, str] = {}
    node_of: dict[str, list[int]] = {}
    for shaft in drivetrain.shafts:
        ratio = (speed_ratios or {}).get(shaft.name, 1.0)
        nodes = _add_shaft(structure, shaft, ratio)
        node_of[shaft.name] = nodes
        end_nodes[f"{shaft.name}.start"] = structure.node_names[nodes[0]]
        end_nodes[f"{shaft.name}.end"] = structure.node_names[nodes[-1]]

    def node_at(end: str) -> int:
        return structure.node(end_nodes[end])

    for bearing in drivetrain.bearings:
        k = node_number(drivetrain.shaft(bearing.shaft), bearing.position)
        # a coefficient table's x-y part enters per speed (DrivetrainModel.at_speed)
        stiffness = [bearing.radial, bearing.radial, bearing.axial, bearing.tilt, bearing.tilt, 0]
        damping = [bearing.radial_damping, bearing.radial_damping, bearing.axial_damping, 0, 0, 0]
        structure.add_ground_element(node_of[bearing.shaft][k], bearing_element(stiffness, damping))
    for disc in drivetrain.discs:
        k = node_number(drivetrain.shaft(disc.shaft), disc.position)
        element = disc_element(disc.mass, disc.polar_inertia, disc.diametral_inertia)
        ratio = (speed_ratios or {}).get(disc.shaft, 1.0)
        structure.add_element(node_of[disc.shaft][k], _scaled_gyroscopic(element, ratio))
    for coupling in drivetrain.couplings:
        element = coupling_element(
            coupling.torsional,
            radial=coupling.radial,
            axial=coupling.axial,
            angular=coupling.angular,
            torsional_damping=coupling.torsional_damping,
        )
        structure.add_element([node_at(coupling.a), node_at(coupling.b)], element)
    for part in (p for p in (drivetrain.rotor, drivetrain.generator) if p is not None):
        disc = disc_element(part.mass, part.polar_inertia, part.diametral_inertia)
        ratio = (speed_ratios or {}).get(part.at.split(".")[0], 1.0)
        structure.add_element(node_at(part.at), _scaled_gyroscopic(disc, ratio))
    return structure, end_nodes


def _add_shaft(structure: Structure, shaft: Shaft, ratio: float) -> list[int]:
    """Nodes ``<shaft>_0 .. <shaft>_n`` and the shaft's elements; with torsional
    damping, a damper beta G J / L beside each element's twist; with Rayleigh damping,
    alpha M_e + beta K_e on each element."""
    nodes = [structure.add_node(f"{shaft.name}_0")]
    theta_z = (NODE_DOFS.index("theta_z"), 6 + NODE_DOFS.index("theta_z"))
    for section in shaft.sections:
        length = section.length / shaft.elements_per_section
        element = shaft_element(
            length,
            section.outer_diameter,
            section.inner_diameter,
            youngs_modulus=shaft.young_modulus,
            shear_modulus=shaft.shear_modulus,
            density=shaft.density,
            shear_deformation=shaft.shear_deformation,
            shear_coefficient=shaft.shear_coefficient,
        )
        element = _scaled_gyroscopic(element, ratio)
        damping = shaft.rayleigh_mass * element.mass + shaft.rayleigh_stiffness * element.stiffness
        if shaft.torsional_damping > 0.0:
            polar_moment = np.pi * (section.outer_diameter**4 - section.inner_diameter**4) / 32.0
            twist = shaft.shear_modulus * polar_moment / length  # G J / L [N m/rad]
            damping[np.ix_(theta_z, theta_z)] += (
                shaft.torsional_damping * twist * np.array([[1.0, -1.0], [-1.0, 1.0]])
            )
        if np.any(damping):
            element = ElementMatrices(element.mass, element.stiffness, damping, element.gyroscopic)
        for _ in range(shaft.elements_per_section):
            nodes.append(structure.add_node(f"{shaft.name}_{len(nodes)}"))
            structure.add_element([nodes[-2], nodes[-1]], element)
    return nodes


def node_number(shaft: Shaft, position: float) -> int:
    """The number k of the node ``<shaft>_k`` nearest ``position`` [m] from its start."""
    positions = shaft.node_positions()
    return int(np.argmin([abs(p - position) for p in positions]))


def bearing_tables(
    drivetrain: Drivetrain, speed_ratios: dict[str, float] | None = None
) -> list[BearingTable]:
    """The bearings with a coefficient table, their nodes' x and y labels (structure
    labels), and their shafts' speed ratios."""
    tables = []
    for bearing in drivetrain.bearings:
        if bearing.coefficients is None:
            continue
        node = f"{bearing.shaft}_{node_number(drivetrain.shaft(bearing.shaft), bearing.position)}"
        ratio = (speed_ratios or {}).get(bearing.shaft, 1.0)
        tables.append(
            BearingTable(bearing.name, (f"{node}.x", f"{node}.y"), bearing.coefficients, ratio)
        )
    return tables


def _scaled_gyroscopic(element: ElementMatrices, ratio: float) -> ElementMatrices:
    if ratio == 1.0:
        return element
    return ElementMatrices(
        element.mass, element.stiffness, element.damping, ratio * element.gyroscopic
    )


def shaft_speed_ratios(case: Case) -> dict[str, float]:
    """Each shaft's speed over the rotor's, from the gearbox's rigid-body rotation.

    A shaft turns with the gearbox member mounted on it, or with the shafts it is
    coupled to; the member's speed is its theta_z in the gearbox's free rotation (the
    null vector of its torsional stiffness).
    """
    drivetrain = case.drivetrain
    gearbox = assemble(case, dof_set="torsional")
    eigenvalues, vectors = generalized_eigh(gearbox.stiffness, gearbox.mass)
    rigid = gearbox.reduction @ vectors[:, int(np.argmin(abs(eigenvalues)))]
    speed = {
        mount.at.split(".")[0]: rigid[gearbox.full_labels.index(f"{mount.member}.theta_z")]
        for mount in drivetrain.mounts
    }
    group = _coupled_groups(drivetrain)
    by_group = {group[shaft]: value for shaft, value in speed.items()}
    rotor_speed = by_group[group[drivetrain.rotor.at.split(".")[0]]]
    return {s.name: float(by_group[group[s.name]] / rotor_speed) for s in drivetrain.shafts}


def _coupled_groups(drivetrain: Drivetrain) -> dict[str, int]:
    """A group number per shaft: shafts joined by couplings share one."""
    group = {shaft.name: n for n, shaft in enumerate(drivetrain.shafts)}
    changed = True
    while changed:
        changed = False
        for coupling in drivetrain.couplings:
            a, b = coupling.a.split(".")[0], coupling.b.split(".")[0]
            low = min(group[a], group[b])
            for name in (a, b):
                if group[name] != low:
                    group[name], changed = low, True
    return group


def _combine(
    case_name: str,
    dof_set: str,
    matrices: StructureMatrices,
    gearbox: Model,
    drivetrain: Drivetrain,
    end_nodes: dict[str, str],
    ratios: dict[str, float],
) -> DrivetrainModel:
    """Structure and gearbox in one numbering, the mounted nodes' DOFs eliminated.

    A node DOF becomes its member's full DOF, written in the gearbox's reduced DOFs by
    the member's row of the reduction T (a plain column, or a rigid link's ratio).
    """
    full_index = {label: i for i, label in enumerate(gearbox.full_labels)}
    tied: dict[str, np.ndarray] = {}
    names: dict[str, str] = {}
    for mount in drivetrain.mounts:
        for dof in NODE_DOFS:
            row = gearbox.reduction[full_index[f"{mount.member}.{dof}"]]
            if np.any(row):
                node_label = f"{end_nodes[mount.at]}.{dof}"
                tied[node_label] = row
                names[node_label] = f"{mount.member}.{dof}"
    if not any(label in tied for label in matrices.labels):
        raise CaseError("drivetrain.mounts: no gearbox member DOF is kept in this DOF set")
    own = [label for label in matrices.labels if label not in tied]
    offset = len(own)
    position = {label: n for n, label in enumerate(own)}
    size = offset + gearbox.size
    rows, columns, values = [], [], []
    for n, label in enumerate(matrices.labels):
        if label in tied:
            (nonzero,) = np.nonzero(tied[label])
            rows.extend([n] * nonzero.size)
            columns.extend(offset + nonzero)
            values.extend(tied[label][nonzero])
        else:
            rows.append(n)
            columns.append(position[label])
            values.append(1.0)
    placement = sp.csc_matrix((values, (rows, columns)), shape=(len(matrices.labels), size))

    def combined(structure_part: sp.spmatrix, gearbox_part: np.ndarray | None) -> sp.csc_matrix:
        total = placement.T @ structure_part @ placement
        if gearbox_part is not None:
            block = sp.block_diag((sp.csc_matrix((offset, offset)), sp.csc_matrix(gearbox_part)))
            total = total + block
        return sp.csc_matrix(total)

    return DrivetrainModel(
        case_name=case_name,
        dof_set=dof_set,
        labels=own + list(gearbox.dof_labels),
        mass=combined(matrices.mass, gearbox.mass),
        stiffness=combined(matrices.stiffness, gearbox.stiffness),
        damping=combined(matrices.damping, gearbox.damping),
        gyroscopic=combined(matrices.gyroscopic, None),
        gearbox=gearbox,
        gearbox_offset=offset,
        end_nodes=end_nodes,
        tied=names,
        speed_ratios=ratios,
    )
