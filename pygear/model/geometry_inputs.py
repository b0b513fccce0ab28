"""Gear geometry in a case: the values it may leave out, and those it may not contradict.

A :class:`~pygear.model.components.Gear` with a ``geometry`` (:class:`GearGeometry`)
gets its base radius and tooth number from it.  A stage whose gears carry geometry gets,
for each mesh whose two gears have one, the working transverse pressure angle, the
transverse contact ratio, the overlap ratio and the circumferential backlash; the stage
gets its base helix angle, and a planetary stage its carrier radius when that is left
out (ISO 21771, :mod:`pygear.model.gear_geometry`).  The mesh geometry of a planetary
stage is (sun, planet) for the sun-planet mesh and (planet, ring) for the ring-planet
mesh, at the carrier radius as centre distance; a parallel stage's is (input gear,
output gear) at the zero-backlash centre distance of the profile shifts.

Values are filled in when a component is built, as far as the geometry can be
evaluated (a geometry that cannot leaves them empty), and refused when the case is
validated: :func:`check_gear`, :func:`check_planetary_geometry` and
:func:`check_parallel_geometry` raise :class:`~pygear.errors.CaseError` for a geometry
that breaks a rule of :mod:`pygear.model.gear_checks`, and for a typed value that
contradicts a derived one, beyond the tolerances of :mod:`pygear.model.gear_geometry`
(0.5 % on radii and centre distances, 0.1 deg on angles, 0.02 on contact and overlap
ratios).  A typed value within them is kept as typed.

Filled values are recorded in the component's ``_derived`` field, so a copy made by
:func:`dataclasses.replace` with another geometry (a sweep over a module, a scene's
parameter) derives them again instead of taking the old ones as typed.

This module imports no component class; it reads and fills the components' fields, so
:mod:`pygear.model.components` and :mod:`pygear.model.gearbox` can call it.
"""

from __future__ import annotations

import dataclasses
import math

from ..errors import CaseError
from . import gear_geometry as geo
from .gear_geometry import GearGeometry, MeshGeometry
from .names import LAWS
from .values import is_finite_number, is_whole_number

__all__ = [
    "GEOMETRY_LAWS",
    "LAWS",
    "check_gear",
    "check_mesh_law",
    "check_parallel_geometry",
    "check_planetary_geometry",
    "effective_law",
    "fill_gear",
    "fill_parallel_stage",
    "fill_planetary_stage",
    "parallel_mesh_geometry",
    "planetary_mesh_geometry",
    "typed_value",
]

GEOMETRY_LAWS = ("iso6336", "potential_energy", "loaded_contact")
"""Laws that derive the mesh stiffness from the gear geometry (typing it is an error)."""

RADIUS_RTOL = geo.TYPED_BASE_RADIUS_RTOL
"""Relative tolerance on typed base radii, modules and the carrier radius (0.5 %)."""

_MESH_VALUES = ("pressure_angle_deg", "contact_ratio", "overlap_ratio", "backlash")
_ARITHMETIC = (ArithmeticError, ValueError, TypeError, AttributeError)


# ----------------------------------------------------------------------------------
# typed and derived values
# ----------------------------------------------------------------------------------


def _empty(value: object) -> bool:
    """True for a field left out (None); a typed NaN is a value, which the field's own
    rule refuses (it is no finite number), not a request to derive it."""
    return value is None


def _record(component: object) -> dict[str, object]:
    """The component's record of derived values (anything else in ``_derived``, such as
    a value a fuzzer put there, counts as no record)."""
    try:
        return {
            name: value
            for name, value in getattr(component, "_derived", ())
            if isinstance(name, str)
        }
    except (TypeError, ValueError):
        return {}


def typed_value(component: object, name: str) -> object:
    """The value of field ``name`` as the case typed it, or None: None also when the
    field is empty (None or NaN) or holds the value derived for it before."""
    value = getattr(component, name, None)
    if _empty(value):
        return None
    record = _record(component)
    if name in record and type(value) is type(record[name]) and value == record[name]:
        return None
    return value


def _refill(component: object, name: str, derived: object, empty: object) -> bool:
    """Give field ``name`` of a component under construction its derived value unless a
    value is typed; a field that held a derived value no longer derivable is emptied.
    Returns True when the field changed."""
    if typed_value(component, name) is not None:
        return False
    value = empty if derived is None else derived
    record = _record(component)
    if derived is None:
        record.pop(name, None)
    else:
        record[name] = derived
    changed = not (getattr(component, name) is value or getattr(component, name) == value)
    object.__setattr__(component, name, value)
    object.__setattr__(component, "_derived", tuple(sorted(record.items())))
    return changed


def _attempt(function, *arguments) -> float | None:
    """``function(*arguments)`` as a float, or None where the geometry cannot give it."""
    try:
        value = float(function(*arguments))
    except _ARITHMETIC:
        return None
    return value if math.isfinite(value) else None


def _close(typed: object, derived: float, tolerance: float) -> bool:
    """True unless ``typed`` is a number farther than ``tolerance`` from ``derived``
    (a typed value that is no number is left to the parameter's own rule)."""
    return not is_finite_number(typed) or abs(typed - derived) <= tolerance


# ----------------------------------------------------------------------------------
# gears
# ----------------------------------------------------------------------------------


def fill_gear(gear: object) -> None:
    """Base radius and tooth number of a gear from its geometry (in ``__post_init__``)."""
    geometry = gear.geometry
    radius = teeth = None
    if isinstance(geometry, GearGeometry):
        radius = _attempt(geo.base_radius, geometry)
        teeth = int(geometry.teeth) if is_whole_number(geometry.teeth) else None
    _refill(gear, "base_radius", radius, None)
    _refill(gear, "teeth", teeth, None)


def check_gear(gear: object, path: str) -> None:
    """Refuse a gear geometry that breaks a rule, or typed values that contradict it."""
    geometry = gear.geometry
    if geometry is None:
        return
    if not isinstance(geometry, GearGeometry):
        raise CaseError(
            f"{path}.geometry must be a GearGeometry or None (got {type(geometry).__name__})"
        )
    geometry.validate(f"{path}.geometry")
    radius = geo.base_radius(geometry)
    typed = typed_value(gear, "base_radius")
    if not _close(typed, radius, RADIUS_RTOL * radius):
        raise CaseError(
            f"{path}.base_radius {typed:.6g} m contradicts {path}.geometry, which gives "
            f"r_b = z m_t cos(alpha_t) / 2 = {radius:.6g} m (tolerance {RADIUS_RTOL:.1%}); "
            "leave base_radius out to derive it"
        )
    typed = typed_value(gear, "teeth")
    if typed is not None and typed != geometry.teeth:
        raise CaseError(
            f"{path}.teeth {typed!r} contradicts {path}.geometry.teeth {geometry.teeth}; "
            "leave teeth out to derive it"
        )
    module = geo.transverse_module(geometry)
    if gear.module is not None and not _close(gear.module, module, RADIUS_RTOL * module):
        raise CaseError(
            f"{path}.module {gear.module:.6g} m contradicts {path}.geometry, whose transverse "
            f"module m_n / cos(beta) is {module:.6g} m (tolerance {RADIUS_RTOL:.1%})"
        )


# ----------------------------------------------------------------------------------
# mesh geometry of a stage
# ----------------------------------------------------------------------------------


def _pair(first: object, second: object, distance: object, mesh: object) -> MeshGeometry | None:
    if not (isinstance(first, GearGeometry) and isinstance(second, GearGeometry)):
        return None
    allowances = getattr(mesh, "thickness_allowances", (0.0, 0.0))
    return MeshGeometry(
        first,
        second,
        centre_distance=distance if is_finite_number(distance) and distance > 0 else None,
        thickness_allowances=allowances,
    )


def planetary_mesh_geometry(stage: object, member: str) -> MeshGeometry | None:
    """The geometry of a planetary stage's ``sun`` or ``ring`` mesh: (sun, planet) or
    (planet, ring) at the carrier radius, with the mesh's thickness allowances; None
    unless both gears have a geometry."""
    first, second = (stage.sun, stage.planet) if member == "sun" else (stage.planet, stage.ring)
    mesh = getattr(stage, f"{member}_mesh")
    return _pair(first.geometry, second.geometry, stage.carrier.radius, mesh)


def parallel_mesh_geometry(stage: object) -> MeshGeometry | None:
    """The geometry of a parallel stage's mesh: (input gear, output gear) at the
    zero-backlash centre distance of the profile shifts; None unless both have one."""
    return _pair(stage.input_gear.geometry, stage.output_gear.geometry, None, stage.mesh)


def _zero_backlash_distance(geometry: MeshGeometry) -> float | None:
    return _attempt(geo.centre_distance, dataclasses.replace(geometry, centre_distance=None))


def _mesh_values(geometry: MeshGeometry | None) -> dict[str, float | None]:
    """Working pressure angle [deg], eps_alpha, eps_beta and backlash [m] of a mesh."""
    if geometry is None:
        return dict.fromkeys(_MESH_VALUES)
    angle = _attempt(geo.working_pressure_angle, geometry)
    backlash = _attempt(geo.circumferential_backlash, geometry)
    return {
        "pressure_angle_deg": None if angle is None else math.degrees(angle),
        "contact_ratio": _attempt(geo.transverse_contact_ratio, geometry),
        "overlap_ratio": _attempt(geo.overlap_ratio, geometry),
        # round-off of a zero-backlash pair can come out as -1e-18 m
        "backlash": None if backlash is None else max(backlash, 0.0),
    }


def _signed_base_helix(geometry: object, sign: float) -> float | None:
    """Base helix angle [deg] with the sign of the hand of ``geometry`` times ``sign``."""
    if not isinstance(geometry, GearGeometry):
        return None
    angle = _attempt(geo.base_helix_angle, geometry)
    if angle is None or not is_finite_number(geometry.helix_angle_deg):
        return None
    return math.copysign(math.degrees(angle), sign * geometry.helix_angle_deg) if angle else 0.0


def _with_values(component: object, values: dict[str, object]) -> object:
    """A copy of a (shared) component with derived values filled in, or the component
    itself when nothing changes (or when it is no component: validate names it)."""
    if not (dataclasses.is_dataclass(component) and hasattr(component, "_derived")):
        return component
    copy = dataclasses.replace(component)
    changed = False
    for name, (value, empty) in values.items():
        changed |= _refill(copy, name, value, empty)
    return copy if changed or copy._derived != component._derived else component


def _fill_mesh(stage: object, attribute: str, geometry: MeshGeometry | None, **extra) -> None:
    values = {name: (value, None) for name, value in _mesh_values(geometry).items()}
    values.update({name: (value, None) for name, value in extra.items()})
    mesh = getattr(stage, attribute)
    object.__setattr__(stage, attribute, _with_values(mesh, values))


def fill_planetary_stage(stage: object) -> None:
    """Carrier radius, mesh values and base helix angle of a planetary stage from its
    gears' geometry (in ``__post_init__``; the gears have filled their own values)."""
    if not all(hasattr(getattr(stage, m, None), "geometry") for m in ("sun", "planet", "ring")):
        return  # validate names the member that is no gear
    if not hasattr(stage.carrier, "radius"):
        return
    sun, planet, ring = stage.sun.geometry, stage.planet.geometry, stage.ring.geometry
    distance = None
    for first, second in ((sun, planet), (planet, ring)):
        pair = _pair(first, second, None, None)
        if pair is not None and distance is None:
            distance = _zero_backlash_distance(pair)
    object.__setattr__(stage, "carrier", _with_values(stage.carrier, {"radius": (distance, None)}))
    for member in ("sun", "ring"):
        _fill_mesh(stage, f"{member}_mesh", planetary_mesh_geometry(stage, member))
    helix = next(
        (
            value
            for value in (
                _signed_base_helix(sun, 1.0),
                _signed_base_helix(planet, -1.0),
                _signed_base_helix(ring, -1.0),
            )
            if value is not None
        ),
        0.0,
    )
    _refill(stage, "base_helix_angle_deg", helix, 0.0)


def fill_parallel_stage(stage: object) -> None:
    """Mesh values, overlap ratio and base helix angle of a parallel stage from its
    gears' geometry (in ``__post_init__``).  Without geometry a spur pair's overlap
    ratio is 0; a helical pair's stays empty unless typed on the stage or the mesh."""
    if not all(hasattr(getattr(stage, m, None), "geometry") for m in ("input_gear", "output_gear")):
        return  # validate names the member that is no gear
    geometry = parallel_mesh_geometry(stage)
    helix = _signed_base_helix(stage.input_gear.geometry, 1.0)
    if helix is None:
        helix = _signed_base_helix(stage.output_gear.geometry, -1.0)
    _refill(stage, "base_helix_angle_deg", 0.0 if helix is None else helix, 0.0)
    overlap = _mesh_values(geometry)["overlap_ratio"]
    if overlap is None:
        overlap = typed_value(stage.mesh, "overlap_ratio")
    if overlap is None and stage.base_helix_angle_deg == 0.0:
        overlap = 0.0
    _refill(stage, "overlap_ratio", overlap, None)
    _fill_mesh(stage, "mesh", geometry, overlap_ratio=stage.overlap_ratio)


# ----------------------------------------------------------------------------------
# refusals
# ----------------------------------------------------------------------------------


def _check_mesh_geometry(
    geometry: MeshGeometry, mesh: object, mesh_path: str, geometry_path: str
) -> None:
    """The pair meshes, and the mesh's typed values agree with what it gives."""
    geometry.validate(geometry_path)
    checks = (
        ("pressure_angle_deg", math.degrees(geo.working_pressure_angle(geometry)),
         geo.TYPED_PRESSURE_ANGLE_ATOL_DEG, "a working transverse pressure angle alpha_wt",
         " deg"),
        ("contact_ratio", geo.transverse_contact_ratio(geometry), geo.TYPED_RATIO_ATOL,
         "a transverse contact ratio eps_alpha", ""),
        ("overlap_ratio", geo.overlap_ratio(geometry), geo.TYPED_RATIO_ATOL,
         "an overlap ratio eps_beta", ""),
    )  # fmt: skip
    for name, value, tolerance, what, unit in checks:
        typed = typed_value(mesh, name)
        if not _close(typed, value, tolerance):
            raise CaseError(
                f"{mesh_path}.{name} {typed:.6g}{unit} contradicts the gear geometry, which "
                f"gives {what} of {value:.6g}{unit} (tolerance {tolerance:g}{unit}); leave "
                f"{name} out to derive it"
            )
    allowances = getattr(mesh, "thickness_allowances", (0.0, 0.0))
    if typed_value(mesh, "backlash") is not None and any(allowances):
        raise CaseError(
            f"{mesh_path}: give backlash or thickness_allowances, not both (with gear geometry "
            "the allowances fix the backlash)"
        )


def _check_helix(stage: object, path: str, derived: float | None) -> None:
    typed = typed_value(stage, "base_helix_angle_deg")
    if derived is None or _close(typed, derived, geo.TYPED_PRESSURE_ANGLE_ATOL_DEG):
        return
    raise CaseError(
        f"{path}.base_helix_angle_deg {typed!r} contradicts the gear geometry, which gives "
        f"beta_b = {derived:.6g} deg (signed with the hand of the sun or input gear; "
        f"tolerance {geo.TYPED_PRESSURE_ANGLE_ATOL_DEG:g} deg); leave it out to derive it"
    )


def check_planetary_geometry(stage: object, path: str) -> None:
    """Refuse a planetary stage's gear geometry that cannot mesh at the carrier radius,
    a carrier radius off either mesh's zero-backlash centre distance, and typed mesh
    values or a base helix angle that contradict the geometry."""
    for member, role, internal in (("sun", "sun", False), ("planet", "planet", False),
                                   ("ring", "ring", True)):  # fmt: skip
        geometry = getattr(stage, member).geometry
        if isinstance(geometry, GearGeometry) and geometry.internal is not internal:
            kind = "an internal gear" if internal else "an external gear"
            raise CaseError(
                f"{path}.{member}.geometry.internal must be {internal}: the {role} is {kind}"
            )
    radius = stage.carrier.radius
    for member, pair in (("sun", "sun, planet"), ("ring", "planet, ring")):
        geometry = planetary_mesh_geometry(stage, member)
        if geometry is None:
            continue
        geometry_path = f"{path}.{member}_mesh[{pair}]"
        zero = dataclasses.replace(geometry, centre_distance=None, thickness_allowances=(0.0, 0.0))
        zero.validate(geometry_path, pointed_tip="ignore")  # warned once, at r_c below
        distance = geo.centre_distance(zero)
        if not _close(radius, distance, RADIUS_RTOL * distance):
            raise CaseError(
                f"{path}.carrier.radius {radius:.6g} m disagrees with the {member}-planet "
                f"geometry's centre distance {distance:.6g} m (zero-backlash distance of its "
                f"profile shifts, ISO 21771; tolerance {RADIUS_RTOL:.1%}): the carrier radius "
                "is the centre distance of both meshes; leave it out to derive it"
            )
        _check_mesh_geometry(geometry, getattr(stage, f"{member}_mesh"), f"{path}.{member}_mesh",
                             geometry_path)  # fmt: skip
    helix = next(
        (
            value
            for value in (
                _signed_base_helix(stage.sun.geometry, 1.0),
                _signed_base_helix(stage.planet.geometry, -1.0),
                _signed_base_helix(stage.ring.geometry, -1.0),
            )
            if value is not None
        ),
        None,
    )
    _check_helix(stage, path, helix)
    helical = stage.base_helix_angle_deg != 0.0
    for member in ("sun", "ring"):
        mesh = getattr(stage, f"{member}_mesh")
        gears = "sun and planet" if member == "sun" else "planet and ring"
        check_mesh_law(
            mesh,
            f"{path}.{member}_mesh",
            planetary_mesh_geometry(stage, member) is not None,
            gears,
            helical,
            mesh.overlap_ratio,
            f"{path}.base_helix_angle_deg",
        )


def check_parallel_geometry(stage: object, path: str) -> None:
    """Refuse a parallel stage's gear geometry that cannot mesh, and typed values that
    contradict it (mesh values, overlap ratio, base helix angle)."""
    for member in ("input_gear", "output_gear"):
        geometry = getattr(stage, member).geometry
        if isinstance(geometry, GearGeometry) and geometry.internal:
            raise CaseError(f"{path}.{member}.geometry.internal must be False (external pair)")
    geometry = parallel_mesh_geometry(stage)
    overlap = stage.overlap_ratio
    if geometry is not None:
        _check_mesh_geometry(geometry, stage.mesh, f"{path}.mesh",
                             f"{path}.mesh[input_gear, output_gear]")  # fmt: skip
        derived = geo.overlap_ratio(geometry)
        typed = typed_value(stage, "overlap_ratio")
        if not _close(typed, derived, geo.TYPED_RATIO_ATOL):
            raise CaseError(
                f"{path}.overlap_ratio {typed:.6g} contradicts the gear geometry, which gives "
                f"eps_beta = {derived:.6g} (tolerance {geo.TYPED_RATIO_ATOL:g}); leave it out"
            )
    mesh_overlap = typed_value(stage.mesh, "overlap_ratio")
    if is_finite_number(overlap) and not _close(mesh_overlap, overlap, geo.TYPED_RATIO_ATOL):
        raise CaseError(
            f"{path}.mesh.overlap_ratio {mesh_overlap!r} contradicts {path}.overlap_ratio "
            f"{overlap!r}; give it once"
        )
    helix = _signed_base_helix(stage.input_gear.geometry, 1.0)
    if helix is None:
        helix = _signed_base_helix(stage.output_gear.geometry, -1.0)
    _check_helix(stage, path, helix)
    check_mesh_law(
        stage.mesh,
        f"{path}.mesh",
        geometry is not None,
        "input_gear and output_gear",
        stage.base_helix_angle_deg != 0.0,
        overlap,
        f"{path}.base_helix_angle_deg",
        overlap_path=f"{path}.overlap_ratio",
    )


def effective_law(mesh: object, helical: bool, overlap_ratio: float | None) -> str:
    """The law a mesh runs: its own, else ``tabulated`` with a stiffness curve, else
    ``helical`` on a helical stage with an overlap ratio above 0, else ``parabola``."""
    if mesh.law is not None:
        return mesh.law
    if mesh.stiffness_curve is not None:
        return "tabulated"
    if helical and is_finite_number(overlap_ratio) and overlap_ratio > 0:
        return "helical"
    return "parabola"


def check_mesh_law(
    mesh: object,
    path: str,
    has_geometry: bool,
    gears: str,
    helical: bool,
    overlap_ratio: float | None,
    helix_path: str,
    *,
    overlap_path: str | None = None,
) -> None:
    """Refuse a law the mesh cannot run: an unknown name, a geometry law without gear
    geometry on both gears, a helical stage without an overlap ratio, the helical law
    without one above 0, a missing stiffness."""
    law = mesh.law
    if law is not None and law not in LAWS:
        raise CaseError(f"{path}.law must be one of {', '.join(LAWS)} or None (got {law!r})")
    if law in GEOMETRY_LAWS and not has_geometry:
        raise CaseError(
            f"{path}.law {law!r} derives the mesh stiffness from gear geometry: give the "
            f"{gears} a geometry (GearGeometry)"
        )
    overlap_path = overlap_path or f"{path}.overlap_ratio"
    if helical and not is_finite_number(overlap_ratio):
        raise CaseError(
            f"{overlap_path} must be given for a helical stage ({helix_path} is not 0), or "
            f"give the {gears} a geometry: a helical mesh runs the helical contact-line law, "
            "which needs the overlap ratio"
        )
    chosen = effective_law(mesh, helical, overlap_ratio)
    if chosen == "helical" and not (is_finite_number(overlap_ratio) and overlap_ratio > 0):
        raise CaseError(
            f"{path}.law 'helical' needs an overlap ratio above 0 ({overlap_path} is "
            f"{overlap_ratio!r}): the contact line of a spur mesh does not grow along the face"
        )
    if chosen not in GEOMETRY_LAWS and mesh.stiffness is None:
        hint = (
            "; or choose law 'iso6336' or 'potential_energy', which derive it from the gear "
            "geometry"
            if has_geometry
            else ""
        )
        raise CaseError(f"{path}.stiffness must be given for law {chosen!r}{hint}")
