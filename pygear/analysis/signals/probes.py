"""Output probes of a transient: what a scene asks to keep, as kernel channels.

Every probe becomes one :class:`~pygear.kernel.newmark.KernelProbe`: a weight vector over
the reduced DOFs (displacements, velocities, accelerations, body speeds, mesh
deflections, bearing forces, each a linear function of the state) or a mesh index
(mesh force and stiffness, which depend on the contact state).  Targets are checked
against the assembled model before the run; an unknown one is refused with the
probe's path and the names that exist.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ...assembly.dof_rows import dof_row
from ...assembly.matrices import Model
from ...errors import CaseError
from ...kernel.newmark import KernelProbe
from ...model.transient_settings import Probe, where_written

__all__ = ["ROTATIONS", "compile_probes", "dof_row", "mesh_index", "state_probes"]

ROTATIONS = frozenset({"theta_x", "theta_y", "theta_z", "theta_zeta", "theta_eta", "phi"})
"""DOF names measured in radians."""

BEARING_COMPONENTS = {
    "central_bearing": ("x", "y", "z", "theta_x", "theta_y", "theta_z"),
    "planet_bearing": ("zeta", "eta", "z", "theta_zeta", "theta_eta"),
}
"""Spring order of each bearing element (docs/model.md §3.2, §3.3)."""

RPM_PER_RAD_S = 30.0 / math.pi


def mesh_index(model: Model, name: str) -> int | None:
    """0-based index of a mesh named ``sun-planet1`` or ``stage.sun-planet1``."""
    for m, mesh in enumerate(model.meshes):
        if name in (mesh.name, f"{mesh.stage}.{mesh.name}"):
            return m
    return None


def _units(dof: str, order: int) -> str:
    base = "rad" if dof in ROTATIONS else "m"
    return [base, f"{base}/s", f"{base}/s^2"][order]


def compile_probes(
    model: Model, probes: Sequence[Probe], path: str, first_index: int = 0
) -> list[KernelProbe]:
    """Kernel channels of a scene's probes.

    Parameters
    ----------
    model : Model
        The assembled model.
    probes : sequence of Probe
        The scene's probes.
    path : str
        Parameter path of the probe list, for messages.
    first_index : int, optional
        Index of ``probes[0]`` in the scene's list (for messages, when a caller
        compiles the list one probe at a time).

    Raises
    ------
    CaseError
        A target that is not a DOF, body, mesh or bearing spring of this model.
    """
    compiled = []
    for k, probe in enumerate(probes, start=first_index):
        where = f"{path}[{k}].target"
        quantity, target = probe.quantity, probe.target
        # label: the target as the run file's coordinate names it; named: the probe keeps
        # a variable of its own (pygear.analysis.time.run_layout)
        attrs = {"quantity": quantity, "target": target, "label": target, "named": bool(probe.name)}
        if quantity in ("displacement", "velocity", "acceleration"):
            row = _require(
                dof_row(model, target),
                where + where_written(probe),
                target,
                "DOF",
                model.full_labels,
            )
            dof = target.rsplit(".", 1)[-1]
            order = ("displacement", "velocity", "acceleration").index(quantity)
            attrs.update(units=_units(dof, order), long_name=f"{quantity} of {target}")
            compiled.append(KernelProbe(probe.variable, quantity, row, attrs=attrs))
        elif quantity == "speed":
            row = _require(
                dof_row(model, f"{target}.theta_z"),
                where + where_written(probe),
                target,
                "body",
                _bodies(model),
            )
            attrs.update(units="rpm", long_name=f"rotation speed of {target} (theta_z)")
            compiled.append(
                KernelProbe(probe.variable, "velocity", row * RPM_PER_RAD_S, attrs=attrs)
            )
        elif quantity.startswith("mesh_"):
            m = _require(
                mesh_index(model, target),
                where + where_written(probe),
                target,
                "mesh",
                _meshes(model),
            )
            attrs["label"] = f"{model.meshes[m].stage}.{model.meshes[m].name}"
            if quantity == "mesh_deflection":
                attrs.update(units="m", long_name=f"deflection b.q of mesh {target}")
                compiled.append(
                    KernelProbe(
                        probe.variable, "displacement", model.meshes[m].deflection, attrs=attrs
                    )
                )
            elif quantity == "mesh_force":
                attrs.update(units="N", long_name=f"mesh force of {target}, compression positive")
                compiled.append(KernelProbe(probe.variable, "mesh_force", mesh=m, attrs=attrs))
            else:
                attrs.update(units="N/m", long_name=f"mesh stiffness in force of {target}")
                compiled.append(KernelProbe(probe.variable, "mesh_stiffness", mesh=m, attrs=attrs))
        elif quantity == "bearing_force":
            row, rotational = _bearing_row(model, target, where + where_written(probe))
            attrs.update(
                units="N m" if rotational else "N", long_name=f"bearing force k delta of {target}"
            )
            compiled.append(KernelProbe(probe.variable, "displacement", row, attrs=attrs))
        else:
            member = "input" if quantity == "drive_torque" else "output"
            attrs.update(
                units="N m", long_name=f"{quantity.replace('_', ' ')} on the {member} member"
            )
            compiled.append(KernelProbe(probe.variable, quantity, attrs=attrs))
    return compiled


def state_probes(model: Model) -> list[KernelProbe]:
    """Displacement, velocity and acceleration of every reduced DOF (full state)."""
    probes = []
    for order, quantity in enumerate(("displacement", "velocity", "acceleration")):
        for i, label in enumerate(model.dof_labels):
            row = np.zeros(model.size)
            row[i] = 1.0
            attrs = {
                "quantity": quantity,
                "target": label,
                "label": label,
                "named": False,
                "units": _units(label.rsplit(".", 1)[-1], order),
            }
            probes.append(KernelProbe(f"__{quantity}_{i}", quantity, row, attrs=attrs))
    return probes


_PLURALS = {"DOF": "DOFs", "body": "bodies", "mesh": "meshes", "bearing spring": "bearing springs"}
"""What a probe can target, in the plural its message lists them under."""


def _require(value, where: str, target: str, what: str, known: Sequence[str]):
    if value is None:
        shown = ", ".join(list(known)[:12]) + (", ..." if len(known) > 12 else "")
        plural = _PLURALS.get(what, f"{what}s")
        raise CaseError(f"{where}: {target!r} is not a {what} of this model ({plural}: {shown})")
    return value


def _bodies(model: Model) -> list[str]:
    return [node.name for node in model.nodes if node.role != "housing"]


def _meshes(model: Model) -> list[str]:
    return [mesh.name for mesh in model.meshes]


def _bearing_row(model: Model, target: str, where: str) -> tuple[np.ndarray, bool]:
    """k b^T T for the bearing spring ``element.component``."""
    element, _, component = target.rpartition(".")
    known = []
    for spring in model.springs:
        components = BEARING_COMPONENTS.get(spring.kind)
        if components is None:
            continue
        known.extend(f"{spring.name}.{c}" for c in components)
        if spring.name == element and component in components:
            s = components.index(component)
            full = np.zeros(len(model.full_labels))
            full[spring.dofs] = spring.deflection[:, s] * spring.stiffness[s]
            return full @ model.reduction, component.startswith("theta")
    _require(None, where, target, "bearing spring", known)
    raise AssertionError  # unreachable
