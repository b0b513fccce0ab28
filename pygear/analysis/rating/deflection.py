"""Mesh misalignment from the model's static deflection, for the face load factor.

ISO 6336-1:2019 cl. 7 builds K_Hbeta from the effective mismatch F_betay across the
face width: the component f_sh from the deflections of the shafts, bearings and
housing, and the manufacturing part f_ma.  Method C estimates f_sh from the pinion's
proportions; Annex E takes it from an analysis of the deflections.  Here it comes from
pygear's own model: :func:`mesh_misalignments` solves the static state of the case in
the spatial DOF set (the drivetrain's shafts as beams and its bearings as springs where
the case has a drivetrain, the gearbox's bearing tilt springs otherwise) under the
rated torque, the output held, and reads each gear's tilt.

A gear tilted by (theta_x, theta_y) about its face centre moves a point of its face at
axial position z by (theta_y z, -theta_x z) in its plane; along the mesh's line of
action, whose direction the mesh's deflection row holds (its coefficients on the
gear's x and y, or a planet's zeta and eta), the gap therefore changes along the face
by the slope sum_g (b_xg theta_yg - b_yg theta_xg) [m/m].  The mismatch over the face
width b is f_sh = |slope| b.  The model's gears are points on their shafts: the
twist of a pinion body along its face (part of ISO's f_sh for a long pinion) and the
housing are left out.

The static state is linear in the torque, so f_sh scales with the load: it is kept as
f_sh per unit line load F_m / b (um per N/mm, the form of ISO's own estimate f_sh =
0.023 gamma F_m / b), and each duty-cycle bin takes it at its own F_m.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...errors import CaseError

__all__ = ["has_micro_geometry", "ltca_face_load_factor", "mesh_misalignments"]

_TILTS = {"x": ("theta_y", 1.0), "y": ("theta_x", -1.0),
          "zeta": ("theta_eta", 1.0), "eta": ("theta_zeta", -1.0)}
"""Translation DOF -> (the tilt that moves it along z, sign of theta x z)."""


def _input_output(case) -> tuple[str, str | None]:
    settings = next((s.transient for s in case.scenes
                     if s.transient is not None and s.transient.input), None)
    if settings is not None:
        return settings.input, settings.output
    return case.gearbox.input, case.gearbox.output


def mesh_misalignments(case, torque: float) -> dict[str, float]:
    """Mismatch slope [m/m] in the plane of action of every mesh of the case's model
    (``stage1.sun-planet1``, ``parallel.input-output``), static under input ``torque``
    [N m] (see the module docstring).

    Raises
    ------
    CaseError
        A model without the input and output members or without tilt DOFs.
    """
    from ...assembly.dof_rows import dof_row
    from ...assembly.drivetrain_model import scene_model
    from ...assembly.matrices import assemble
    from ...model.case import Scene

    if case.drivetrain is not None:
        model = scene_model(case, Scene("rating_deflection", analyses=("modal",),
                                        dof_set="spatial"))
    else:
        model = assemble(case, None, dof_set="spatial")
    input_label, output_label = _input_output(case)
    input_row = dof_row(model, input_label)
    output_row = dof_row(model, output_label) if output_label else None
    if input_row is None or output_row is None or not np.any(output_row):
        raise CaseError("the misalignment needs the model's input and output members "
                        f"({input_label!r}, {output_label!r})")
    stiffness = np.array(model.stiffness, dtype=np.float64)
    stiffness += 1e3 * np.abs(np.diag(stiffness)).max() * np.outer(output_row, output_row)
    q = np.linalg.solve(stiffness, torque * input_row)
    labels = model.dof_labels
    out: dict[str, float] = {}
    found_tilt = False
    for mesh in model.meshes:
        slope = 0.0
        for i in np.flatnonzero(mesh.deflection):
            node, _, dof = labels[i].rpartition(".")
            if dof not in _TILTS:
                continue
            tilt, sign = _TILTS[dof]
            row = dof_row(model, f"{node}.{tilt}")
            if row is None:
                continue
            found_tilt = True
            slope += sign * float(mesh.deflection[i]) * float(row @ q)
        out[f"{mesh.stage}.{mesh.name}"] = slope
    if not found_tilt:
        raise CaseError(f"case {case.name!r}: its spatial model has no gear tilt DOFs")
    return out


def _with_gear(case, stage, member: str, gear):
    """``case`` with ``stage``'s ``member`` gear replaced (and its drivetrain's gearbox)."""
    changed = replace(stage, **{member: gear})
    gearbox = replace(case.gearbox, stages=tuple(
        changed if s.name == stage.name else s for s in case.gearbox.stages))
    if case.drivetrain is not None:
        return replace(case, gearbox=gearbox,
                       drivetrain=replace(case.drivetrain, gearbox=gearbox))
    return replace(case, gearbox=gearbox)


def has_micro_geometry(case, label: str) -> bool:
    """Whether a gear of the mesh ``label`` carries modifications (micro-geometry)."""
    from ..contact.ltca_case import case_mesh

    return any(getattr(g, "modifications", None) is not None
               for g in case_mesh(case, label).gears)


def ltca_face_load_factor(case, label: str, force: float, slope: float) -> float:
    """K_Hbeta of the mesh ``label`` from the loaded tooth contact analysis with its
    gears' micro-geometry, at ``force`` [N] along the transverse line of action, with the
    model's mismatch ``slope`` [m/m] added to the first gear's misalignment: the peak of
    the face load's mean over the mesh cycle over F/b (:func:`pygear.analysis.contact.
    ltca_case.case_loaded_contact`).  The slope's sign is taken both ways and the larger
    K_Hbeta kept (a crowning or helix modification meets the tilt from one side)."""
    from ...model.micro_geometry import Misalignment, Modifications
    from ..contact.ltca_case import case_loaded_contact, case_mesh

    mesh = case_mesh(case, label)
    member = {"sun": "sun", "ring": "planet", "mesh": "input_gear"}[mesh.member]
    gear = mesh.gears[0]
    width = min(mesh.geometry.gear1.face_width, mesh.geometry.gear2.face_width)
    modifications = gear.modifications or Modifications()
    misalignment = modifications.misalignment or Misalignment()
    worst = 0.0
    for sign in ((1.0, -1.0) if slope else (1.0,)):
        tilted = replace(modifications, misalignment=replace(
            misalignment, mismatch=misalignment.mismatch + sign * abs(slope) * width))
        changed = _with_gear(case, mesh.stage, member, replace(gear, modifications=tilted))
        ds = case_loaded_contact(changed, label, force * mesh.torque_radius)
        worst = max(worst, float(ds["k_h_beta"].values[0]))
    return worst
