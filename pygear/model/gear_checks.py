"""Refusal rules for gear and mesh geometry: each raises
:class:`pygear.errors.CaseError` with one line naming the parameter and the rule,
before anything is derived from a geometry that cannot mesh (docs/gear_geometry.md)."""

from __future__ import annotations

import math
import warnings

from ..errors import CaseError
from . import gear_geometry as geo
from .plausibility import warn_if_implausible
from .values import is_finite_number

__all__ = [
    "POINTED_TIP_LIMIT",
    "check_gear",
    "check_mesh",
    "trochoid_interference_margin",
]

POINTED_TIP_LIMIT = 0.2
"""Smallest normal tooth thickness at the tip, in normal modules (common design rule
s_an >= 0.2 m_n for through-hardened teeth; docs/gear_geometry.md)."""

_RELATIVE = 1e-9
"""Round-off allowed when two parameters must be equal or a limit is reached exactly."""


def _number(path: str, value: object, low: float, high: float, rule: str) -> None:
    if not is_finite_number(value) or not low < value < high:
        raise CaseError(f"{path} must be {rule} (got {value!r})")


def check_gear(gear: geo.GearGeometry, path: str) -> None:
    """Parameter rules of one gear; undercut for external gears."""
    teeth = gear.teeth
    if isinstance(teeth, bool) or not isinstance(teeth, int) or teeth < 3:
        raise CaseError(f"{path}.teeth must be a whole number of at least 3 (got {teeth!r})")
    _number(f"{path}.normal_module", gear.normal_module, 0.0, 1.0, "a positive length below 1 m")
    _number(f"{path}.face_width", gear.face_width, 0.0, 10.0, "a positive length below 10 m")
    warn_if_implausible(f"{path}.normal_module", "module", gear.normal_module)
    warn_if_implausible(
        f"{path}.face_width / normal_module ({gear.face_width!r} m / {gear.normal_module!r} m)",
        "face_width_ratio",
        gear.face_width / gear.normal_module,
    )
    angle = gear.normal_pressure_angle_deg
    _number(f"{path}.normal_pressure_angle_deg", angle, 0.0, 45.0, "in (0, 45) degrees")
    if angle < 1.0:
        raise CaseError(
            f"{path}.normal_pressure_angle_deg must be given in degrees: {angle!r} looks like "
            "radians"
        )
    _number(f"{path}.helix_angle_deg", gear.helix_angle_deg, -45.0, 45.0, "in (-45, 45) degrees")
    _number(f"{path}.profile_shift", gear.profile_shift, -3.0, 3.0, "in (-3, 3)")
    _number(f"{path}.addendum_factor", gear.addendum_factor, 0.0, 3.0, "in (0, 3)")
    _number(f"{path}.tip_alteration", gear.tip_alteration, -3.0, 3.0, "in (-3, 3)")
    _number(
        f"{path}.dedendum_factor",
        gear.dedendum_factor,
        gear.addendum_factor,
        3.0,
        f"above the addendum factor {gear.addendum_factor!r} (bottom clearance) and below 3",
    )
    fillet_limit = gear.dedendum_factor / (1.0 - math.sin(math.radians(angle)))
    rho = gear.tip_root_radius_factor
    if not is_finite_number(rho) or not 0.0 <= rho < fillet_limit:
        raise CaseError(
            f"{path}.tip_root_radius_factor must lie in [0, {fillet_limit:.4g}) so that the "
            f"rack's fillet fits in its dedendum (got {rho!r})"
        )
    relief = gear.tip_relief
    if relief is not None and (
        not is_finite_number(relief) or not 0.0 <= relief < gear.normal_module
    ):
        raise CaseError(
            f"{path}.tip_relief must be None or a depth in [0, normal_module) metres "
            f"(got {relief!r})"
        )
    if not isinstance(gear.internal, bool):
        raise CaseError(f"{path}.internal must be True or False (got {gear.internal!r})")
    if gear.internal:
        if geo.tip_radius(gear) <= geo.base_radius(gear) * (1.0 + _RELATIVE):
            raise CaseError(
                f"{path}: an internal gear's tip radius {geo.tip_radius(gear):.6g} m must exceed "
                f"its base radius {geo.base_radius(gear):.6g} m (no involute inside the base "
                "circle); lower profile_shift or addendum_factor"
            )
        return
    x_min = geo.undercut_limit_shift(gear)
    if gear.profile_shift < x_min - _RELATIVE:
        raise CaseError(
            f"{path}.profile_shift {gear.profile_shift!r} undercuts {teeth} teeth: the rack's "
            f"flank reaches below the base circle unless profile_shift >= {x_min:.4f}"
        )


def _check_pair(mesh: geo.MeshGeometry, path: str) -> None:
    """The two gears can mesh: same module and pressure angle, matching hands."""
    gear1, gear2 = mesh.gear1, mesh.gear2
    if gear1.internal:
        raise CaseError(f"{path}.gear1.internal must be False: only gear 2 may be an internal gear")
    if not math.isclose(gear1.normal_module, gear2.normal_module, rel_tol=_RELATIVE):
        raise CaseError(
            f"{path}.gear2.normal_module {gear2.normal_module!r} must equal gear1's "
            f"{gear1.normal_module!r}: gears of different modules do not mesh"
        )
    if not math.isclose(
        gear1.normal_pressure_angle_deg, gear2.normal_pressure_angle_deg, rel_tol=_RELATIVE
    ):
        raise CaseError(
            f"{path}.gear2.normal_pressure_angle_deg {gear2.normal_pressure_angle_deg!r} must "
            f"equal gear1's {gear1.normal_pressure_angle_deg!r}: the racks must match"
        )
    beta1, beta2 = gear1.helix_angle_deg, gear2.helix_angle_deg
    if gear2.internal:
        if not math.isclose(beta1, beta2, rel_tol=_RELATIVE, abs_tol=1e-12):
            raise CaseError(
                f"{path}.gear2.helix_angle_deg {beta2!r} must equal gear1's {beta1!r}: an "
                "internal pair has helices of the same hand and angle"
            )
        if gear2.teeth <= gear1.teeth:
            raise CaseError(
                f"{path}.gear2.teeth {gear2.teeth} must exceed gear1's {gear1.teeth}: the ring "
                "surrounds the pinion"
            )
    elif not math.isclose(beta1, -beta2, rel_tol=_RELATIVE, abs_tol=1e-12):
        raise CaseError(
            f"{path}.gear2.helix_angle_deg {beta2!r} must be -({beta1!r}): an external pair has "
            "helices of equal angle and opposite hands"
        )


def _check_operating_point(mesh: geo.MeshGeometry, path: str) -> None:
    """Centre distance or working pressure angle: at most one, and each reachable."""
    if mesh.centre_distance is not None and mesh.working_pressure_angle_deg is not None:
        raise CaseError(
            f"{path}: give centre_distance or working_pressure_angle_deg, not both (each fixes "
            "the other)"
        )
    allowances = mesh.thickness_allowances
    if (
        not isinstance(allowances, tuple)
        or len(allowances) != 2
        or not all(is_finite_number(a) and abs(a) < mesh.gear1.normal_module for a in allowances)
    ):
        raise CaseError(
            f"{path}.thickness_allowances must be two lengths (A_sn1, A_sn2) smaller than the "
            f"module in size, metres (got {allowances!r})"
        )
    base_sum = geo._base_sum(mesh)
    if mesh.centre_distance is not None:
        distance = mesh.centre_distance
        if not is_finite_number(distance) or not base_sum < distance < 10.0 * base_sum:
            kind = "r_b2 - r_b1" if mesh.internal else "r_b1 + r_b2"
            raise CaseError(
                f"{path}.centre_distance must exceed {kind} = {base_sum:.6g} m (the base "
                f"circles' tangent) and stay below 10 times it (got {distance!r})"
            )
    elif mesh.working_pressure_angle_deg is not None:
        _number(
            f"{path}.working_pressure_angle_deg",
            mesh.working_pressure_angle_deg,
            1.0,
            60.0,
            "in (1, 60) degrees",
        )
    elif not geo._shift_involute(mesh) > 0.0:
        shift_sum = mesh.gear1.profile_shift + mesh.gear2.profile_shift
        raise CaseError(
            f"{path}: profile shifts x1 + x2 = {shift_sum:.4g} leave no positive working "
            "pressure angle (inv(alpha_wt) <= 0); raise the profile shifts"
        )


def _check_root_reach(mesh: geo.MeshGeometry, path: str) -> None:
    """Each tip meets its mate's flank on the involute, above the active-profile start."""
    gear1, gear2 = mesh.gear1, mesh.gear2
    approach = geo.centre_distance(mesh) * math.sin(geo.working_pressure_angle(mesh))
    roll1, roll2 = geo._tip_roll(gear1), geo._tip_roll(gear2)
    scale = gear1.normal_module * _RELATIVE
    if mesh.internal:
        # ring tip on the pinion (planet) flank: distance from T1 along the line of action
        on_pinion = roll2 - approach
        on_mate = approach + roll1  # pinion tip on the ring flank, from T2
        names = ("gear2 (ring) tip", "gear1 root", "gear1 (pinion) tip", "gear2 root")
    else:
        on_pinion = approach - roll2
        on_mate = approach - roll1
        names = ("gear2 tip", "gear1 root", "gear1 tip", "gear2 root")
    if on_pinion < -scale:
        raise CaseError(
            f"{path}: involute interference, the {names[0]} reaches inside gear1's base circle "
            f"by {-on_pinion:.4g} m along the line of action; shorten gear2's tip or shift gear1"
        )
    reach = math.hypot(geo.base_radius(gear1), on_pinion)
    form = geo.root_form_radius(gear1)
    if reach < form * (1.0 - _RELATIVE):
        raise CaseError(
            f"{path}: the {names[0]} meets gear1 at radius {reach:.6g} m, below the start of "
            f"its active profile (root form radius {form:.6g} m); interference at {names[1]}"
        )
    if on_mate < -scale:
        raise CaseError(
            f"{path}: involute interference, the {names[2]} reaches inside gear2's base circle "
            f"by {-on_mate:.4g} m along the line of action; shorten gear1's tip or shift gear2"
        )
    reach = math.hypot(geo.base_radius(gear2), on_mate)
    form = geo.root_form_radius(gear2)
    beyond = reach > form * (1.0 + _RELATIVE) if mesh.internal else reach < form * (1.0 - _RELATIVE)
    if beyond:
        raise CaseError(
            f"{path}: the {names[2]} meets gear2 at radius {reach:.6g} m, beyond the start of "
            f"its active profile (root form radius {form:.6g} m); interference at {names[3]}"
        )


def trochoid_interference_margin(mesh: geo.MeshGeometry) -> float:
    """Angular margin [rad] against trochoid (tip) interference of an internal pair:
    theta1 z1/z2 + inv(alpha_w) - inv(alpha_a2) - theta2, negative when the pinion's tip
    corner cuts the ring's tip as it leaves the mesh (KHK Gear Technical Reference,
    internal gears; docs/gear_geometry.md), with

    theta1 = acos((r_a2^2 - r_a1^2 - a^2)/(2 a r_a1)) + inv(alpha_a1) - inv(alpha_w),
    theta2 = acos((a^2 + r_a2^2 - r_a1^2)/(2 a r_a2)).

    Returns +inf when the tip circles do not intersect (the pinion's tips never leave
    the ring's tip circle, or the pair is external), -inf when a tip circle lies inside
    its base circle (no involute tip to compare).
    """
    if not mesh.internal:
        return math.inf
    gear1, gear2 = mesh.gear1, mesh.gear2
    distance = geo.centre_distance(mesh)
    tip1, tip2 = geo.tip_radius(gear1), geo.tip_radius(gear2)
    if tip1 <= geo.base_radius(gear1) or tip2 <= geo.base_radius(gear2):
        return -math.inf
    cos1 = (tip2**2 - tip1**2 - distance**2) / (2.0 * distance * tip1)
    cos2 = (distance**2 + tip2**2 - tip1**2) / (2.0 * distance * tip2)
    if not (-1.0 <= cos1 <= 1.0 and -1.0 <= cos2 <= 1.0):
        return math.inf
    alpha_w = geo.working_pressure_angle(mesh)
    alpha_a1 = math.acos(geo.base_radius(gear1) / tip1)
    alpha_a2 = math.acos(geo.base_radius(gear2) / tip2)
    theta1 = math.acos(cos1) + geo.involute(alpha_a1) - geo.involute(alpha_w)
    theta2 = math.acos(cos2)
    ratio = gear1.teeth / gear2.teeth
    return theta1 * ratio + geo.involute(alpha_w) - geo.involute(alpha_a2) - theta2


def _check_tips(mesh: geo.MeshGeometry, path: str, pointed_tip: str) -> None:
    for name, gear in (("gear1", mesh.gear1), ("gear2", mesh.gear2)):
        thickness = geo.tip_thickness(gear)
        limit = POINTED_TIP_LIMIT * gear.normal_module
        if thickness <= 0.0:
            raise CaseError(
                f"{path}.{name}: the flanks meet below the tip circle (tip thickness "
                f"{thickness:.4g} m <= 0); lower profile_shift or addendum_factor"
            )
        if thickness < limit and pointed_tip != "ignore":
            message = (
                f"{path}.{name}: tip too pointed, normal tip thickness {thickness:.4g} m is "
                f"below {POINTED_TIP_LIMIT} m_n = {limit:.4g} m"
            )
            if pointed_tip == "error":
                raise CaseError(message)
            warnings.warn(message, UserWarning, stacklevel=4)


def check_mesh(mesh: geo.MeshGeometry, path: str, *, pointed_tip: str = "warn") -> None:
    """Every rule of a gear pair, in the order parameters, pair, operating point,
    interference, contact ratio, tip thickness, backlash."""
    if pointed_tip not in ("warn", "error", "ignore"):
        raise CaseError(f"pointed_tip must be 'warn', 'error' or 'ignore' (got {pointed_tip!r})")
    if not isinstance(mesh.gear1, geo.GearGeometry) or not isinstance(mesh.gear2, geo.GearGeometry):
        raise CaseError(f"{path}.gear1 and {path}.gear2 must be GearGeometry")
    check_gear(mesh.gear1, f"{path}.gear1")
    check_gear(mesh.gear2, f"{path}.gear2")
    _check_pair(mesh, path)
    _check_operating_point(mesh, path)
    _check_root_reach(mesh, path)
    if mesh.internal:
        margin = trochoid_interference_margin(mesh)
        if margin < 0.0:
            raise CaseError(
                f"{path}: trochoid (tip) interference, the pinion's tip cuts the ring's tip as "
                f"it leaves the mesh (margin {margin:.4g} rad < 0); ring minus pinion teeth "
                f"({mesh.gear2.teeth} - {mesh.gear1.teeth}) is too small for these tips"
            )
    ratio = geo.transverse_contact_ratio(mesh)
    if ratio < 1.0:
        raise CaseError(
            f"{path}: transverse contact ratio {ratio:.4f} is below 1 (contact would break "
            "between tooth pairs); lengthen the tips or reduce the working pressure angle"
        )
    _check_tips(mesh, path, pointed_tip)
    backlash = geo.circumferential_backlash(mesh)
    if backlash < -_RELATIVE * mesh.gear1.normal_module:
        raise CaseError(
            f"{path}: circumferential backlash {backlash:.4g} m is negative, the teeth jam; "
            "increase centre_distance or thin the teeth (thickness_allowances < 0)"
        )
