"""Plain-Python description of a case: gear and mesh geometry (ISO 21771).

The geometry's names below load on first use (PEP 562): importing a module of this
package, such as :mod:`pygear.model.names` for the command line's choices, does not
load NumPy and the geometry with it.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .gear_checks import POINTED_TIP_LIMIT, check_gear, check_mesh, trochoid_interference_margin
    from .gear_geometry import (
        GearGeometry,
        MeshGeometry,
        MeshModelInputs,
        base_helix_angle,
        base_radius,
        centre_distance,
        circumferential_backlash,
        clearance_tip_alteration,
        inverse_involute,
        involute,
        mesh_model_inputs,
        normal_backlash,
        overlap_ratio,
        pitch_radius,
        require_typed_values_match,
        root_form_radius,
        root_radius,
        tip_radius,
        tip_thickness,
        total_contact_ratio,
        transverse_base_pitch,
        transverse_contact_ratio,
        transverse_module,
        transverse_pressure_angle,
        typed_value_mismatches,
        undercut_limit_shift,
        working_pitch_radii,
        working_pressure_angle,
    )

_SOURCES = {
    ".gear_checks": (
        "POINTED_TIP_LIMIT",
        "check_gear",
        "check_mesh",
        "trochoid_interference_margin",
    ),
    ".gear_geometry": (
        "GearGeometry",
        "MeshGeometry",
        "MeshModelInputs",
        "base_helix_angle",
        "base_radius",
        "centre_distance",
        "circumferential_backlash",
        "clearance_tip_alteration",
        "inverse_involute",
        "involute",
        "mesh_model_inputs",
        "normal_backlash",
        "overlap_ratio",
        "pitch_radius",
        "require_typed_values_match",
        "root_form_radius",
        "root_radius",
        "tip_radius",
        "tip_thickness",
        "total_contact_ratio",
        "transverse_base_pitch",
        "transverse_contact_ratio",
        "transverse_module",
        "transverse_pressure_angle",
        "typed_value_mismatches",
        "undercut_limit_shift",
        "working_pitch_radii",
        "working_pressure_angle",
    ),
}
_MODULE_OF = {name: module for module, names in _SOURCES.items() for name in names}
"""The module each lazily loaded name comes from."""


def __getattr__(name: str) -> object:
    module = _MODULE_OF.get(name)
    if module is None:
        raise AttributeError(f"module 'pygear.model' has no attribute {name!r}")
    value = getattr(importlib.import_module(module, __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_MODULE_OF))


__all__ = [
    "POINTED_TIP_LIMIT",
    "GearGeometry",
    "MeshGeometry",
    "MeshModelInputs",
    "base_helix_angle",
    "base_radius",
    "centre_distance",
    "check_gear",
    "check_mesh",
    "circumferential_backlash",
    "clearance_tip_alteration",
    "inverse_involute",
    "involute",
    "mesh_model_inputs",
    "normal_backlash",
    "overlap_ratio",
    "pitch_radius",
    "require_typed_values_match",
    "root_form_radius",
    "root_radius",
    "tip_radius",
    "tip_thickness",
    "total_contact_ratio",
    "transverse_base_pitch",
    "transverse_contact_ratio",
    "transverse_module",
    "transverse_pressure_angle",
    "trochoid_interference_margin",
    "typed_value_mismatches",
    "undercut_limit_shift",
    "working_pitch_radii",
    "working_pressure_angle",
]
