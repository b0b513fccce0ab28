"""The mesh load factor K_gamma of a planetary stage from pygear's own model.

ISO 6336-1:2019 cl. 5 defines K_gamma as the most loaded planet's mesh force over the
mean one.  :func:`load_sharing_from_model` solves the static state of the case's model
(mean mesh stiffnesses, the output held, the rated torque on the input) with a position
error on each planet and reads the planets' sun-mesh forces:

* a planet's error e_i [m] is an equivalent mesh position error along the line of
  action (a pin ahead of its place in the loaded sense, e_i > 0), applied to its sun and
  ring meshes alike: the mesh force is k_m (b_m q + s_m e_i), s_m the loaded sense of
  mesh m, so the static state solves K q = T r_in - sum k_m s_m e_i b_m;
* the floating members float as the case's bearings let them: three planets around a
  radially free sun share equally whatever their errors (the sun finds the one place
  where the three forces balance), a fourth planet or a held sun does not.

What the model leaves out (carrier and pin deflection, bearing clearance, gravity, the
rotor's bending moments) is why wind-turbine practice keeps a K_gamma of at least 1.1
for three planets; this gives the geometric part.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ...errors import CaseError

__all__ = ["load_sharing_from_model", "planet_mesh_forces"]


def planet_mesh_forces(case, errors: Mapping[str, Sequence[float]], torque: float,
                       dof_set: str = "planar") -> dict[str, np.ndarray]:
    """Sun-mesh force of every planet [N] (along the line of action, positive in the
    loaded sense) per planetary stage, static, at input ``torque`` [N m]."""
    from ...assembly.dof_rows import dof_row
    from ...assembly.matrices import assemble

    model = assemble(case, None, dof_set=dof_set)
    input_row = dof_row(model, case.gearbox.input)
    output_row = dof_row(model, case.gearbox.output)
    if input_row is None or output_row is None or not np.any(output_row):
        raise CaseError("load sharing needs the gearbox's input and output DOFs in the model")
    stiffness = np.array(model.stiffness, dtype=np.float64)
    stiffness += 1e3 * np.abs(np.diag(stiffness)).max() * np.outer(output_row, output_row)
    drive = torque * input_row
    nominal = np.linalg.solve(stiffness, drive)
    sense = {id(m): np.sign(m.deflection @ nominal) or 1.0 for m in model.meshes}
    stages = {m.stage for m in model.meshes if m.planet}
    for stage, values in errors.items():
        if stage not in stages:
            raise CaseError(f"rating.planet_position_errors names {stage!r}, not a planetary "
                            f"stage of the case (it has {sorted(stages)})")
        count = max(m.planet for m in model.meshes if m.stage == stage)
        if len(values) != count:
            raise CaseError(f"rating.planet_position_errors[{stage!r}] needs one error per "
                            f"planet ({count}; got {len(values)})")

    def error(mesh) -> float:
        values = errors.get(mesh.stage)
        return 0.0 if values is None or not mesh.planet else float(values[mesh.planet - 1])

    force = drive.copy()
    for mesh in model.meshes:
        force -= mesh.mean_stiffness * sense[id(mesh)] * error(mesh) * mesh.deflection
    q = np.linalg.solve(stiffness, force)
    out: dict[str, list[float]] = {}
    for mesh in model.meshes:
        if mesh.planet and mesh.kind == "external":
            loaded = sense[id(mesh)] * (mesh.deflection @ q) + error(mesh)
            out.setdefault(mesh.stage, []).append(mesh.mean_stiffness * loaded)
    return {stage: np.array(values) for stage, values in out.items()}


def load_sharing_from_model(case, errors: Mapping[str, Sequence[float]], torque: float,
                            dof_set: str = "planar") -> dict[str, float]:
    """K_gamma = max F_i / mean F_i of each stage named in ``errors`` (see the module
    docstring)."""
    forces = planet_mesh_forces(case, errors, torque, dof_set)
    out = {}
    for stage in errors:
        values = forces[stage]
        if np.any(values <= 0.0):
            raise CaseError(f"rating.planet_position_errors[{stage!r}] unloads a planet "
                            "entirely at the rated torque: K_gamma is not defined there")
        out[stage] = float(values.max() / values.mean())
    return out
