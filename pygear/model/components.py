"""Components of a gearbox: bodies, bearings, meshes and planetary stages.

Every component is a frozen dataclass holding SI values (m, kg, s, N, rad); only
parameters whose name says so are in degrees (``pressure_angle_deg``).  Nothing is
checked when a component is built: :func:`validate` walks a whole gearbox and names
the first parameter that breaks a rule by its full path (``planetary.sun.mass``),
before any work starts; a value outside its plausible range only warns
(:mod:`pygear.model.plausibility`).

Each family lives in its own module with its validation beside its fields:
:mod:`~pygear.model.bodies` (Body, Gear, Carrier), :mod:`~pygear.model.bearings`,
:mod:`~pygear.model.meshes`, :mod:`~pygear.model.planetary` and
:mod:`~pygear.model.defects`; the rules they share are in
:mod:`~pygear.model.component_rules`.  This module gathers every public name, so
``from pygear.model.components import Gear`` keeps working.
"""

from __future__ import annotations

from ..errors import CaseError  # re-exported: pygear.errors.CaseError
from .bearings import Bearing, PlanetBearing
from .bodies import (
    DEFAULT_BORE_RATIO,
    FOUNDATION_RATIO_RANGE,
    MODULE_PRESSURE_ANGLE_DEG,
    TOOTH_RATIO_TOLERANCE,
    Body,
    Carrier,
    Gear,
    check_foundation_bore,
    foundation_bore_radius,
    require_matching_teeth,
    ring_rim_ratio,
)
from .component_rules import (
    AXIAL_LIMIT,
    MAGNITUDE_LIMIT,
    check_backlash,
    derived_record,
    is_finite_number,
    is_whole_number,
    looks_like_radians,
    plain_numbers,
    require_axial_position,
    require_non_negative,
    require_positive,
    transverse_module_of,
    validate_component,
)
from .defects import ToothDefect
from .meshes import MAX_CONTACT_RATIO, Mesh
from .planetary import PlanetaryStage

__all__ = [
    "AXIAL_LIMIT",
    "DEFAULT_BORE_RATIO",
    "FOUNDATION_RATIO_RANGE",
    "MAGNITUDE_LIMIT",
    "MAX_CONTACT_RATIO",
    "MODULE_PRESSURE_ANGLE_DEG",
    "TOOTH_RATIO_TOLERANCE",
    "Bearing",
    "Body",
    "CaseError",
    "Carrier",
    "check_backlash",
    "check_foundation_bore",
    "Gear",
    "Mesh",
    "PlanetBearing",
    "PlanetaryStage",
    "ToothDefect",
    "derived_record",
    "foundation_bore_radius",
    "is_finite_number",
    "is_whole_number",
    "looks_like_radians",
    "plain_numbers",
    "require_axial_position",
    "require_matching_teeth",
    "require_non_negative",
    "require_positive",
    "ring_rim_ratio",
    "transverse_module_of",
    "validate_component",
]
