"""The members and torque laws of a transient, as the kernel takes them.

The input and output members are rows of the reduction (a member's rotation in the
reduced DOFs); the output's speed over the input's, the kinematic ratio, comes from the
stage's ratio or the model's rigid-body rotation; the case's torque laws become the
kernel's law codes and parameters (``fortran/newmark_support.f90``).
"""

from __future__ import annotations

import math

import numpy as np

from ...assembly.dof_rows import dof_row, rigid_rotation
from ...assembly.matrices import Model
from ...errors import CaseError
from ...kernel.newmark import LawArrays
from ...model.case import Case
from ...model.components import PlanetaryStage
from ...model.transient_settings import TorqueLaw

__all__ = ["default_member", "kinematic_ratio", "law_arrays", "member_row"]


def default_member(case: Case, member: str) -> str:
    """``member``'s theta_z label in the case's first planetary stage (the default input
    is its carrier, the default output its sun)."""
    for stage in case.gearbox.stages:
        if isinstance(stage, PlanetaryStage):
            return f"{stage.name}.{member}.theta_z"
    raise CaseError(f"transient.input and transient.output must be given for {case.name!r}")


def member_row(model: Model, label: str, path: str) -> np.ndarray:
    """The rotation of the member DOF ``label`` per reduced DOF; CaseError naming ``path``
    when it is not a DOF of the model or is held fixed."""
    row = dof_row(model, label)
    if row is None or not np.any(row):
        kind = "not a DOF" if row is None else "a DOF held fixed"
        raise CaseError(
            f"{path}: {label!r} is {kind} of this model (e.g. planetary.carrier.theta_z)"
        )
    return row


def kinematic_ratio(case: Case, model: Model, input_label: str, output_label: str) -> float:
    """Output over input speed, i of docs/model.md §6.3: the stage's 1 + r_br/r_bs for its
    carrier and sun, else the ratio in the model's rigid-body rotation (negative when
    the output turns against the input)."""
    for stage in case.gearbox.stages:
        if isinstance(stage, PlanetaryStage):
            carrier, sun = f"{stage.name}.carrier.theta_z", f"{stage.name}.sun.theta_z"
            if (input_label, output_label) == (carrier, sun):
                return stage.speed_ratio
            if (input_label, output_label) == (sun, carrier):
                return 1.0 / stage.speed_ratio
    rigid = rigid_rotation(model)
    speed_in = dof_row(model, input_label) @ rigid if rigid is not None else 0.0
    speed_out = dof_row(model, output_label) @ rigid if rigid is not None else 0.0
    scale = 1e-9 * np.abs(rigid).max() if rigid is not None else math.inf
    if not (abs(speed_in) > scale and abs(speed_out) > scale):
        raise CaseError(
            "transient.load.ratio: the input and output are not linked by one rigid-body "
            "rotation; give the generator law its ratio"
        )
    return float(speed_out / speed_in)


def law_arrays(
    law: TorqueLaw | None, ratio: float, speed_reference: float, sign: int = 1
) -> LawArrays:
    """The kernel's form of a law; ``sign`` = -1 mirrors a drive law's torque."""
    if law is None:
        return LawArrays()
    if law.kind == "constant":
        return LawArrays("constant", (sign * law.torque, 0.0, 0.0, 0.0))
    if law.kind == "ramp":
        return LawArrays("ramp", (sign * law.torque, law.start, law.ramp_time, 0.0))
    if law.kind == "table":
        return LawArrays("table", times=law.times, torques=tuple(sign * t for t in law.torques))
    i = law.ratio or ratio
    return LawArrays("speed_power", (law.torque / i, i * speed_reference, law.exponent, 0.0))
