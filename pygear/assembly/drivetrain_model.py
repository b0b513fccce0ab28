"""A drivetrain in the form the transient takes: a :class:`~pygear.assembly.matrices.Model`.

The transient (tooth-contact tables, mesh terms, probes, bearing forces, the output
file) reads a gearbox :class:`Model`: reduced matrices, the reduction T from full DOF
labels to reduced DOFs, the nodes, springs, mass parts and meshes.  A
:class:`~pygear.assembly.drivetrain.DrivetrainModel` is the gearbox's reduced DOFs as one
block behind the structure's own DOFs, so it maps onto a Model directly:

* the reduced DOFs are the drivetrain's (structure DOFs, then the gearbox block);
* the full DOFs are the structure's own DOFs (T = I), the gearbox's full DOFs (T = the
  gearbox's reduction, placed at the block), and aliases: every shaft-node DOF that
  was eliminated into a gearbox member (its member's row), and the rotor's and the
  generator's DOFs as ``rotor.<dof>`` and ``generator.<dof>`` (their nodes' rows), so
  that probes and loads name them as in a gearbox case;
* the gearbox's nodes, springs and mass parts keep their full DOFs, shifted past the
  structure's; its meshes' deflection rows are placed at the block.

The matrices stay dense here: the transient's static solutions and checks are written
for gearbox-sized models, and a drivetrain of a few hundred DOFs costs nothing dense.
The Newmark kernel still chooses its storage from the pattern, and drivetrains go to
CHOLMOD when a sparse step reads less (:mod:`pygear.kernel.newmark_storage`).
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

import numpy as np

from ..errors import CaseError
from ..model.case import Case
from ..model.scene_settings import scene_settings
from .matrices import Model, Node, assemble

if TYPE_CHECKING:
    from ..model.case import Scene
    from ..model.scene_settings import SceneSettings
    from .drivetrain import DrivetrainModel

__all__ = ["DRIVETRAIN_BODIES", "drivetrain_transient_model", "scene_model"]

DRIVETRAIN_BODIES = ("rotor", "generator")
"""Bodies of a drivetrain that probes and loads may name like a gearbox's members."""

_SPEED_EFFECTS = ("gyroscopic", "centripetal", "speed_dependent")


def scene_model(
    case: Case, scene: Scene | SceneSettings | None = None, *, formulation: str | None = None
) -> Model:
    """The model a scene runs on: the whole drivetrain when the case has one (its
    gearbox's formulation is the case's or the scene's), else the gearbox alone."""
    if case.drivetrain is not None:
        if formulation is not None and formulation != case.formulation:
            raise CaseError(
                f"--formulation {formulation!r}: a drivetrain case runs its gearbox in the "
                f"case's or the scene's formulation ({case.formulation!r})"
            )
        return drivetrain_transient_model(case, scene)
    return assemble(case, scene, formulation=formulation)


def drivetrain_transient_model(case: Case, scene: Scene | SceneSettings | None = None) -> Model:
    """The case's whole drivetrain as a :class:`Model` for the transient of ``scene``.

    Raises
    ------
    CaseError
        The scene asks for speed-dependent terms (not yet carried by drivetrains).
    """
    if case.drivetrain.gearbox is None:
        raise CaseError(
            f"case {case.name!r} is a plain rotor (no gearbox): its scenes do not run; "
            "use pygear modal --speed, pygear campbell or pygear frf"
        )
    settings = scene_settings(scene)
    if settings is not None:
        asked = [e for e in settings.effects if any(word in e for word in _SPEED_EFFECTS)]
        if asked:
            raise CaseError(
                f"scenes.{settings.name}.effects: {asked[0]!r} is not available for a whole "
                "drivetrain yet (its shafts' and discs' gyroscopic terms are always in its "
                "transient, at each shaft's speed); remove it or run the gearbox case"
            )
    # SciPy's sparse package loads for drivetrains only: a gearbox run does without it
    from .drivetrain import assemble_drivetrain

    return as_model(assemble_drivetrain(case, settings), case)


def as_model(drivetrain: DrivetrainModel, case: Case) -> Model:
    """A :class:`Model` over the drivetrain's DOFs (see the module docstring)."""
    gearbox = drivetrain.gearbox
    offset = drivetrain.gearbox_offset
    n = drivetrain.size
    own = drivetrain.labels[:offset]
    shift = len(own)
    aliases: dict[str, np.ndarray] = {}
    gearbox_rows = {label: i for i, label in enumerate(gearbox.full_labels)}

    def row_of(label: str) -> np.ndarray:
        row = np.zeros(n)
        if label in drivetrain.labels[:offset]:
            row[drivetrain.labels.index(label)] = 1.0
        elif label in gearbox_rows:
            row[offset:] = gearbox.reduction[gearbox_rows[label]]
        return row

    for node_label, member_label in drivetrain.tied.items():
        aliases[node_label] = row_of(member_label)
    body_nodes = {
        "rotor": drivetrain.end_nodes[case.drivetrain.rotor.at],
        "generator": drivetrain.end_nodes[case.drivetrain.generator.at],
    }
    body_dofs = {}
    for body, node in body_nodes.items():
        kept = []
        for dof in ("x", "y", "z", "theta_x", "theta_y", "theta_z"):
            label = drivetrain.tied.get(f"{node}.{dof}", f"{node}.{dof}")
            row = row_of(label)
            if np.any(row):
                aliases[f"{body}.{dof}"] = row
                kept.append(dof)
        if "theta_z" not in kept:
            raise CaseError(f"drivetrain.{body}: its node {node!r} has no theta_z in this model")
        body_dofs[body] = tuple(kept)

    full_labels = own + list(gearbox.full_labels) + list(aliases)
    reduction = np.zeros((len(full_labels), n))
    reduction[:shift, :shift] = np.eye(shift)
    reduction[shift : shift + len(gearbox.full_labels), offset:] = gearbox.reduction
    first_alias = shift + len(gearbox.full_labels)
    for i, row in enumerate(aliases.values()):
        reduction[first_alias + i] = row
    nodes = [dataclasses.replace(node, first=node.first + shift) for node in gearbox.nodes]
    alias_index = {label: first_alias + i for i, label in enumerate(aliases)}
    for body, dofs in body_dofs.items():
        nodes.append(Node(body, "central", dofs, alias_index[f"{body}.{dofs[0]}"]))

    def padded(vector: np.ndarray) -> np.ndarray:
        placed = np.zeros(n)
        placed[offset:] = vector
        return placed

    attributes = dict(gearbox.attributes)
    attributes.update(
        drivetrain=1,
        drivetrain_dofs=n,
        drivetrain_structure_dofs=offset,
    )
    return Model(
        case_name=drivetrain.case_name,
        formulation=gearbox.formulation,
        dof_set=drivetrain.dof_set,
        dof_set_reason=f"the whole drivetrain, {drivetrain.dof_set} DOF set",
        nodes=nodes,
        full_labels=full_labels,
        dof_labels=list(drivetrain.labels),
        reduction=reduction,
        mass=drivetrain.mass.toarray(),
        stiffness=drivetrain.stiffness.toarray(),
        damping=drivetrain.damping.toarray(),
        springs=[
            dataclasses.replace(spring, dofs=spring.dofs + shift) for spring in gearbox.springs
        ],
        mass_parts=[
            dataclasses.replace(part, dofs=part.dofs + shift) for part in gearbox.mass_parts
        ],
        meshes=[
            dataclasses.replace(mesh, deflection=padded(mesh.deflection)) for mesh in gearbox.meshes
        ],
        effects=gearbox.effects,
        gyroscopic=None,
        attributes=attributes,
        spatial_size=n,
        shaft_gyroscopic=drivetrain.gyroscopic if drivetrain.gyroscopic.nnz else None,
    )
