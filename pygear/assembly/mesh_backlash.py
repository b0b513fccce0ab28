"""Backlash of the assembled meshes, on the line the kernel measures their deflection.

A case gives a mesh's backlash as ISO 21771 does: the circumferential backlash j_wt
on the working pitch circles (``Mesh.backlash``, typed or derived from the gear
geometry and its tooth thickness allowances).  The kernel's mesh deflection
delta = b . q lies along the normal to the flanks (the mesh element carries
r_b cos(beta_b) per radian of each gear), so the gap the teeth cross there is the
normal backlash (ISO 21771; DIN 3967)

    j_bn = j_wt cos(alpha_wt) cos(beta_b),

alpha_wt the transverse working pressure angle and beta_b the base helix angle.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import CaseError
from ..model.case import Case
from ..model.gearbox import ParallelStage
from .matrices import Model

__all__ = ["line_of_action_backlash", "mesh_component"]


def mesh_component(case: Case, stage_name: str, mesh_name: str) -> tuple[object, str]:
    """The case's ``Mesh`` behind an assembled mesh and its parameter path.

    Parameters
    ----------
    case : Case
        The case (as the scene sees it).
    stage_name, mesh_name : str
        The assembled mesh's stage and name (``sun-planet1``, ``ring-planet2``).
    """
    stage = case.gearbox.stage(stage_name)
    if isinstance(stage, ParallelStage):
        return stage.mesh, f"{stage.name}.mesh"
    central = mesh_name.split("-", 1)[0]
    return getattr(stage, f"{central}_mesh"), f"{stage.name}.{central}_mesh"


def line_of_action_backlash(case: Case, model: Model, effect: str) -> np.ndarray:
    """Normal backlash j_bn [m] of every assembled mesh, in the model's mesh order.

    Parameters
    ----------
    case : Case
        The case as the scene sees it (its parameter changes applied).
    model : Model
        The assembled model.
    effect : str
        The effect that needs the backlash, for the message.

    Raises
    ------
    CaseError
        A mesh has no backlash, typed or derived from gear geometry: after the teeth
        part, where the coast flanks meet is then unknown.
    """
    values = []
    for mesh in model.meshes:
        component, path = mesh_component(case, mesh.stage, mesh.name)
        circumferential = getattr(component, "backlash", None)
        if circumferential is None:
            raise CaseError(
                f"{path}.backlash is needed by the {effect} effect: the circumferential "
                "backlash on the working pitch circle [m] (ISO 21771 j_wt, e.g. 0.1e-3 for a "
                "3 mm module), or gear geometry with thickness_allowances to derive it; 0 "
                "makes the mesh a two-sided contact"
            )
        stage = case.gearbox.stage(mesh.stage)
        helix = math.radians(getattr(stage, "base_helix_angle_deg", 0.0) or 0.0)
        values.append(float(circumferential) * math.cos(component.pressure_angle) * math.cos(helix))
    return np.array(values, dtype=np.float64)
