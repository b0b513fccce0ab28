"""Rules every component's validation shares: positive and bounded SI values, axial
positions, the record of derived values, NumPy scalars made plain.

A component keeps its own rules beside its fields (:mod:`pygear.model.bodies`,
:mod:`pygear.model.bearings`, :mod:`pygear.model.meshes`, :mod:`pygear.model.planetary`,
:mod:`pygear.model.defects`); what they share sits here, below all of them.
"""

from __future__ import annotations

import math
from dataclasses import field, fields, is_dataclass

import numpy as np

from ..errors import CaseError
from . import gear_geometry as geo
from .plausibility import warn_if_implausible
from .values import is_finite_number, is_whole_number

__all__ = [
    "AXIAL_LIMIT",
    "MAGNITUDE_LIMIT",
    "check_backlash",
    "derived_record",
    "is_finite_number",
    "is_whole_number",
    "looks_like_radians",
    "plain_numbers",
    "require_axial_position",
    "require_non_negative",
    "require_positive",
    "transverse_module_of",
    "validate_component",
]


def plain_numbers(value: object) -> object:
    """``value`` with every NumPy scalar replaced by the Python int, float or bool it holds.

    Dataclasses (frozen or not) are updated in place, field by field; tuples, lists and
    dicts are rebuilt only where an item changed.  A case so holds the same numbers,
    the same ``repr`` (input hash) and the same double-precision arithmetic whether a
    value was written as ``0.4`` or as ``np.float32(0.4)``.
    """
    if isinstance(value, (np.number, np.bool_)):
        return value.item()
    if is_dataclass(value) and not isinstance(value, type):
        for spec in fields(value):
            current = getattr(value, spec.name, None)
            converted = plain_numbers(current)
            if converted is not current:
                object.__setattr__(value, spec.name, converted)
        return value
    if isinstance(value, (tuple, list)):
        items = [plain_numbers(v) for v in value]
        if all(a is b for a, b in zip(items, value)):
            return value
        return type(value)(items) if type(value) in (tuple, list) else value
    if isinstance(value, dict):
        pairs = [(plain_numbers(k), plain_numbers(v)) for k, v in value.items()]
        if all(a is k and b is v for (a, b), (k, v) in zip(pairs, value.items())):
            return value
        return dict(pairs)
    return value


_finite = is_finite_number

AXIAL_LIMIT = 100.0
"""Stages sit within this distance of the gearbox origin along its axis [m]."""


def require_axial_position(path: str, value: object) -> None:
    """Raise :class:`CaseError` unless ``value`` is a finite position within
    :data:`AXIAL_LIMIT` of the gearbox origin."""
    if not is_finite_number(value) or abs(value) > AXIAL_LIMIT:
        raise CaseError(
            f"{path} must be a finite position within {AXIAL_LIMIT:g} m of the "
            f"gearbox origin (got {value!r})"
        )


MAGNITUDE_LIMIT = 1e15
"""No SI value of a gearbox (kg, kg m^2, m, N/m, s) comes near 1e15 or 1e-15: beyond,
the assembled matrices overflow or lose every digit, so such a value is a typo."""


def require_positive(path: str, value: float) -> None:
    """Raise :class:`CaseError` unless ``value`` is a finite number > 0 (within
    1e-15 .. 1e15, :data:`MAGNITUDE_LIMIT`)."""
    if not _finite(value) or value <= 0:
        raise CaseError(f"{path} must be a positive finite number (got {value!r})")
    if not 1 / MAGNITUDE_LIMIT <= value <= MAGNITUDE_LIMIT:
        raise CaseError(
            f"{path} must be a positive finite number between {1 / MAGNITUDE_LIMIT:g} and "
            f"{MAGNITUDE_LIMIT:g} in SI units (got {value!r})"
        )


def require_non_negative(path: str, value: float) -> None:
    """Raise :class:`CaseError` unless ``value`` is a finite number >= 0 (at most 1e15)."""
    if not _finite(value) or value < 0:
        raise CaseError(f"{path} must be a finite number >= 0 (got {value!r})")
    if value > MAGNITUDE_LIMIT:
        raise CaseError(
            f"{path} must be a finite number >= 0 and at most {MAGNITUDE_LIMIT:g} in SI units "
            f"(got {value!r})"
        )


def derived_record() -> tuple:
    """The ``_derived`` field of a component whose values gear geometry may fill in: the
    (name, value) pairs filled so far (:mod:`pygear.model.geometry_inputs`), keyword-only
    and left out of ``repr`` and comparisons."""
    return field(default=(), repr=False, compare=False, kw_only=True)


def looks_like_radians(value: float) -> bool:
    """True for a non-zero angle in degrees below 1 in size: no gear angle of a
    ``_deg`` parameter is that small, a value in radians often is."""
    return _finite(value) and 0 < abs(value) < 1


def validate_component(component: object, path: str, *, validate: bool = True) -> None:
    """Validate any component that has a ``validate(path)`` method (``validate=False``:
    only check that it is one)."""
    if not is_dataclass(component) or not hasattr(component, "validate"):
        raise CaseError(f"{path} is not a pygear component (got {type(component).__name__})")
    if validate:
        component.validate(path)


def transverse_module_of(gear: object, pressure_angle_deg: float | None) -> float | None:
    """The transverse module m_t of a gear [m]: from its geometry, else from its base
    radius and teeth, 2 r_b / (Z cos alpha) at the mesh's pressure angle; None when
    neither is known (a gear without tooth number)."""
    geometry = getattr(gear, "geometry", None)
    if geometry is not None:
        try:
            return float(geo.transverse_module(geometry))
        except (ArithmeticError, ValueError, TypeError, AttributeError):
            return None
    teeth = getattr(gear, "teeth", None)
    if teeth is None or not is_finite_number(pressure_angle_deg):
        return None
    return 2.0 * gear.base_radius / (teeth * math.cos(math.radians(pressure_angle_deg)))


def check_backlash(path: str, backlash: float | None, module: float | None) -> None:
    """Raise :class:`CaseError` for a backlash of a whole circular pitch pi m_t or more
    (the mating tooth would have no thickness); warn (:mod:`pygear.model.plausibility`)
    above a quarter of the module, a unit mistake (mm typed as m) or a worn-out gear."""
    if backlash is None or module is None or not is_finite_number(backlash) or module <= 0:
        return
    pitch = math.pi * module
    if backlash >= pitch:
        raise CaseError(
            f"{path} must be below the circular pitch pi m_t = {pitch * 1e3:.4g} mm "
            f"(got {backlash!r} m = {backlash * 1e3:.4g} mm: the mating tooth would have no "
            f"thickness; a value in mm typed as m?)"
        )
    warn_if_implausible(
        f"{path} / m_t ({backlash!r} m / {module * 1e3:.4g} mm)",
        "backlash_ratio",
        backlash / module,
    )
