"""Involute gear and mesh geometry (ISO 21771 conventions), in SI units.

A :class:`GearGeometry` describes one cylindrical involute gear by its basic rack and
profile shift; a :class:`MeshGeometry` pairs two of them, optionally at a given centre
distance or working pressure angle.  The functions below derive what pygear's mesh
models take by hand today (base radii, working pressure angle, contact and overlap
ratios) plus backlash and tip thickness; :mod:`pygear.model.gear_checks` holds the
refusal rules.  Equations and sources: docs/gear_geometry.md.

Conventions (ISO 21771): lengths in metres, angles in degrees in the dataclasses and
radians in the derived values; helix angles are signed (+ right hand, - left hand); an
internal gear (ring) carries ``internal=True`` and a positive tooth count, and its
profile shift keeps ISO 21771's sign: x > 0 thickens the ring tooth and moves its tip
and root circles towards the axis.  Some catalogues (KHK, SDP/SI) use the opposite sign
for internal gears: x_ISO = -x_catalogue.  Radii returned here are magnitudes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "GearGeometry",
    "MeshGeometry",
    "involute",
    "inverse_involute",
    "transverse_module",
    "transverse_pressure_angle",
    "base_helix_angle",
    "pitch_radius",
    "base_radius",
    "tip_radius",
    "root_radius",
    "root_form_radius",
    "transverse_base_pitch",
    "base_half_thickness",
    "tip_thickness",
    "undercut_limit_shift",
    "working_pressure_angle",
    "centre_distance",
    "working_pitch_radii",
    "transverse_contact_ratio",
    "overlap_ratio",
    "total_contact_ratio",
    "circumferential_backlash",
    "normal_backlash",
    "clearance_tip_alteration",
    "MeshModelInputs",
    "mesh_model_inputs",
    "typed_value_mismatches",
    "require_typed_values_match",
    "TYPED_BASE_RADIUS_RTOL",
    "TYPED_PRESSURE_ANGLE_ATOL_DEG",
    "TYPED_RATIO_ATOL",
]


@dataclass(frozen=True)
class GearGeometry:
    """One cylindrical involute gear, cut by a basic rack (ISO 53 profile by default).

    Parameters
    ----------
    teeth : int
        Number of teeth z (positive, also for an internal gear).
    normal_module : float
        Normal module m_n [m].
    face_width : float
        Face width b [m].
    normal_pressure_angle_deg : float
        Normal pressure angle of the basic rack alpha_n [deg].
    helix_angle_deg : float
        Reference helix angle beta [deg]: + right hand, - left hand, 0 spur.
    profile_shift : float
        Profile shift coefficient x [-] (ISO 21771 sign, also for internal gears).
    addendum_factor : float
        Basic rack addendum h_aP / m_n [-].
    dedendum_factor : float
        Basic rack dedendum h_fP / m_n [-].
    tip_root_radius_factor : float
        Root fillet radius of the basic rack rho_fP / m_n [-] (the cutter's tip radius);
        it sets where the involute starts (the root form circle).
    tip_relief : float or None
        Depth of a tip relief C_a [m], kept for contact laws; None for no relief.
    internal : bool
        True for an internal gear (ring).
    tip_alteration : float
        Tip alteration coefficient k [-] (ISO 21771): the tip circle moves by k m_n
        (k < 0 shortens the teeth, e.g. to keep the bottom clearance at a centre
        distance widened by profile shift; see :func:`clearance_tip_alteration`).
    """

    teeth: int
    normal_module: float
    face_width: float
    normal_pressure_angle_deg: float = 20.0
    helix_angle_deg: float = 0.0
    profile_shift: float = 0.0
    addendum_factor: float = 1.0
    dedendum_factor: float = 1.25
    tip_root_radius_factor: float = 0.38
    tip_relief: float | None = None
    internal: bool = False
    tip_alteration: float = 0.0

    def validate(self, path: str) -> None:
        """Raise CaseError naming the first parameter that breaks its rule."""
        from .gear_checks import check_gear

        check_gear(self, path)


@dataclass(frozen=True)
class MeshGeometry:
    """A gear pair: gear 1 external (pinion, sun or planet), gear 2 external or internal.

    Parameters
    ----------
    gear1, gear2 : GearGeometry
        The two gears; only gear 2 may be internal (the ring of a ring-planet mesh).
    centre_distance : float or None
        Operating centre distance a [m].  None: the zero-backlash distance of the
        profile shifts (or the one of ``working_pressure_angle_deg``).
    working_pressure_angle_deg : float or None
        Operating transverse pressure angle alpha_wt [deg] instead of a centre
        distance.  At most one of the two may be given.
    thickness_allowances : tuple of float
        Normal tooth thickness allowances (A_sn1, A_sn2) [m], negative for thinner
        teeth (backlash); for the ring, of its tooth.
    """

    gear1: GearGeometry
    gear2: GearGeometry
    centre_distance: float | None = None
    working_pressure_angle_deg: float | None = None
    thickness_allowances: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        if isinstance(self.thickness_allowances, list):
            object.__setattr__(self, "thickness_allowances", tuple(self.thickness_allowances))

    @property
    def internal(self) -> bool:
        """True for an internal mesh (gear 2 is a ring)."""
        return bool(self.gear2.internal)

    def validate(self, path: str, *, pointed_tip: str = "warn") -> None:
        """Raise CaseError naming the first parameter that breaks a meshing rule.

        ``pointed_tip`` decides what a tip thinner than 0.2 m_n does: "warn"
        (a :class:`UserWarning`), "error" (CaseError) or "ignore".
        """
        from .gear_checks import check_mesh

        check_mesh(self, path, pointed_tip=pointed_tip)


# ----------------------------------------------------------------------------------
# involute function
# ----------------------------------------------------------------------------------


def involute(angle: float) -> float:
    """inv(alpha) = tan(alpha) - alpha [rad]."""
    return math.tan(angle) - angle


def inverse_involute(value: float) -> float:
    """The angle alpha in (0, pi/2) with inv(alpha) = value > 0 [rad] (Newton's method).

    Raises
    ------
    ValueError
        For a value that is not a positive finite number.
    """
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"inverse_involute needs a positive finite value (got {value!r})")
    # start from the series inv(a) ~ a^3/3 (small angles), capped below pi/2
    angle = min((3.0 * value) ** (1.0 / 3.0), 1.5)
    for _ in range(100):
        tangent = math.tan(angle)
        step = (tangent - angle - value) / (tangent * tangent)  # d inv/d alpha = tan^2
        angle -= step
        if angle <= 0.0:
            angle = 1e-6
        elif angle >= math.pi / 2:
            angle = 0.5 * (math.pi / 2 + angle + step)
        if abs(step) <= 1e-15 * max(angle, 1.0):
            break
    return angle


# ----------------------------------------------------------------------------------
# one gear
# ----------------------------------------------------------------------------------


def _helix(gear: GearGeometry) -> float:
    return math.radians(abs(gear.helix_angle_deg))


def transverse_module(gear: GearGeometry) -> float:
    """m_t = m_n / cos(beta) [m]."""
    return gear.normal_module / math.cos(_helix(gear))


def transverse_pressure_angle(gear: GearGeometry) -> float:
    """alpha_t = atan(tan(alpha_n) / cos(beta)) [rad]."""
    return math.atan(
        math.tan(math.radians(gear.normal_pressure_angle_deg)) / math.cos(_helix(gear))
    )


def base_helix_angle(gear: GearGeometry) -> float:
    """|beta_b| = atan(tan|beta| cos(alpha_t)) [rad]."""
    return math.atan(math.tan(_helix(gear)) * math.cos(transverse_pressure_angle(gear)))


def pitch_radius(gear: GearGeometry) -> float:
    """Reference (pitch) radius r = z m_t / 2 [m]."""
    return gear.teeth * transverse_module(gear) / 2.0


def base_radius(gear: GearGeometry) -> float:
    """r_b = r cos(alpha_t) [m]."""
    return pitch_radius(gear) * math.cos(transverse_pressure_angle(gear))


def _side(gear: GearGeometry) -> float:
    """+1 for an external gear, -1 for an internal one (ISO 21771's signed z)."""
    return -1.0 if gear.internal else 1.0


def tip_radius(gear: GearGeometry) -> float:
    """Tip radius r_a = r + m_n (h_aP* + x + k), external; r - m_n (h_aP* + x + k),
    internal (ISO 21771 with signed z) [m]."""
    addendum = gear.normal_module * (
        gear.addendum_factor + gear.profile_shift + gear.tip_alteration
    )
    return pitch_radius(gear) + _side(gear) * addendum


def root_radius(gear: GearGeometry) -> float:
    """Root radius r_f = r - m_n (h_fP* - x), external; r + m_n (h_fP* - x), internal [m]."""
    dedendum = gear.normal_module * (gear.dedendum_factor - gear.profile_shift)
    return pitch_radius(gear) - _side(gear) * dedendum


def _flank_end_depth(gear: GearGeometry) -> float:
    """Depth below the reference line where the rack-generated involute ends:
    (h_fP - rho_fP (1 - sin alpha_n) - x m_n) [m] (the cutter's straight flank ends
    where its tip fillet begins)."""
    alpha_n = math.radians(gear.normal_pressure_angle_deg)
    straight = gear.dedendum_factor - gear.tip_root_radius_factor * (1.0 - math.sin(alpha_n))
    return gear.normal_module * (straight - gear.profile_shift)


def _form_roll_length(gear: GearGeometry) -> float:
    """Length along the line of action from the base-circle tangent point T to the
    point where the generated involute starts; negative means undercut [m]."""
    alpha_t = transverse_pressure_angle(gear)
    pitch_to_start = _flank_end_depth(gear) / math.sin(alpha_t)
    return pitch_radius(gear) * math.sin(alpha_t) - _side(gear) * pitch_to_start


def root_form_radius(gear: GearGeometry) -> float:
    """Radius where the involute starts (external: lowest point; internal: outermost),
    for a gear generated by its basic rack [m].

    For an internal gear (cut by a pinion cutter in practice) the rack is an
    approximation.  For an undercut external gear the result is the base radius.
    """
    roll = max(_form_roll_length(gear), 0.0)
    return math.hypot(base_radius(gear), roll)


def undercut_limit_shift(gear: GearGeometry) -> float:
    """Smallest profile shift coefficient without undercut, external gears:
    x_min = h_FfP* - z sin^2(alpha_t) / (2 cos beta), h_FfP* = h_fP* - rho_fP* (1 - sin alpha_n)."""
    alpha_n = math.radians(gear.normal_pressure_angle_deg)
    alpha_t = transverse_pressure_angle(gear)
    straight = gear.dedendum_factor - gear.tip_root_radius_factor * (1.0 - math.sin(alpha_n))
    return straight - gear.teeth * math.sin(alpha_t) ** 2 / (2.0 * math.cos(_helix(gear)))


def transverse_base_pitch(gear: GearGeometry) -> float:
    """p_bt = pi m_t cos(alpha_t) [m]."""
    return math.pi * transverse_module(gear) * math.cos(transverse_pressure_angle(gear))


def _reference_thickness(gear: GearGeometry, allowance: float = 0.0) -> float:
    """Transverse tooth thickness at the reference circle,
    s_t = m_t (pi/2 + 2 x tan alpha_n) + A_sn / cos(beta) [m]."""
    alpha_n = math.radians(gear.normal_pressure_angle_deg)
    nominal = transverse_module(gear) * (
        math.pi / 2.0 + 2.0 * gear.profile_shift * math.tan(alpha_n)
    )
    return nominal + allowance / math.cos(_helix(gear))


def _half_angle(gear: GearGeometry, radius: float, allowance: float = 0.0) -> float:
    """Half the angle the tooth (external) or the tooth space (internal) subtends at
    ``radius`` on the involute [rad]: s/(2r) + inv(alpha_t) - inv(alpha_y)."""
    r = pitch_radius(gear)
    alpha_y = math.acos(min(base_radius(gear) / radius, 1.0))
    width = _reference_thickness(gear, allowance)
    if gear.internal:
        width = math.pi * transverse_module(gear) - width  # the ring's space width
    return width / (2.0 * r) + involute(transverse_pressure_angle(gear)) - involute(alpha_y)


def base_half_thickness(gear: GearGeometry) -> float:
    """Half the chordal thickness of an external tooth at its base circle,
    r_b sin(s_b / (2 r_b)) [m]: where the tooth of the potential-energy model meets its
    body, the reference for a root crack's depth."""
    if gear.internal:
        raise ValueError("base_half_thickness: an internal gear's tooth meets its rim elsewhere")
    radius = base_radius(gear)
    return radius * math.sin(_half_angle(gear, radius))


def tip_thickness(gear: GearGeometry) -> float:
    """Normal tooth thickness at the tip circle s_an = s_at cos(beta_a) [m]
    (negative: the flanks meet inside the tip circle)."""
    radius = tip_radius(gear)
    half = _half_angle(gear, radius)
    if gear.internal:
        half = math.pi / gear.teeth - half  # the ring tooth is the complement of its space
    transverse = 2.0 * radius * half
    beta_a = math.atan(math.tan(_helix(gear)) * radius / pitch_radius(gear))
    return transverse * math.cos(beta_a)


# ----------------------------------------------------------------------------------
# the mesh
# ----------------------------------------------------------------------------------


def _base_sum(mesh: MeshGeometry) -> float:
    """r_b1 + r_b2 (external) or r_b2 - r_b1 (internal) [m]."""
    return base_radius(mesh.gear2) + _side(mesh.gear2) * base_radius(mesh.gear1)


def _shift_involute(mesh: MeshGeometry) -> float:
    """inv(alpha_wt) of the zero-backlash mesh of the profile shifts (ISO 21771):
    inv(alpha_t) + 2 tan(alpha_n) (x1 + x2) / (z1 + z2), z2 < 0 for an internal gear."""
    gear1, gear2 = mesh.gear1, mesh.gear2
    alpha_n = math.radians(gear1.normal_pressure_angle_deg)
    signed_sum = gear1.teeth + _side(gear2) * gear2.teeth
    shift_sum = gear1.profile_shift + gear2.profile_shift
    return (
        involute(transverse_pressure_angle(gear1))
        + 2.0 * math.tan(alpha_n) * shift_sum / signed_sum
    )


def working_pressure_angle(mesh: MeshGeometry) -> float:
    """Operating transverse pressure angle alpha_wt [rad].

    From the given centre distance (cos alpha_wt = (r_b1 +- r_b2)/a), else the given
    working pressure angle, else the zero-backlash value of the profile shifts
    (involute function, ISO 21771).
    """
    if mesh.centre_distance is not None:
        return math.acos(_base_sum(mesh) / mesh.centre_distance)
    if mesh.working_pressure_angle_deg is not None:
        return math.radians(mesh.working_pressure_angle_deg)
    return inverse_involute(_shift_involute(mesh))


def centre_distance(mesh: MeshGeometry) -> float:
    """Operating centre distance a = (r_b1 +- r_b2) / cos(alpha_wt) [m]."""
    if mesh.centre_distance is not None:
        return mesh.centre_distance
    return _base_sum(mesh) / math.cos(working_pressure_angle(mesh))


def working_pitch_radii(mesh: MeshGeometry) -> tuple[float, float]:
    """Operating pitch radii r_w = r_b / cos(alpha_wt) of gears 1 and 2 [m]."""
    cosine = math.cos(working_pressure_angle(mesh))
    return base_radius(mesh.gear1) / cosine, base_radius(mesh.gear2) / cosine


def _tip_roll(gear: GearGeometry) -> float:
    """sqrt(r_a^2 - r_b^2): tip point to base tangent point on the line of action [m]."""
    radius, base = tip_radius(gear), base_radius(gear)
    return math.sqrt(max(radius * radius - base * base, 0.0))


def transverse_contact_ratio(mesh: MeshGeometry) -> float:
    """eps_alpha = g_alpha / p_bt, with the length of the path of contact
    g_alpha = sqrt(r_a1^2 - r_b1^2) + sqrt(r_a2^2 - r_b2^2) - a sin(alpha_wt) (external),
    sqrt(r_a1^2 - r_b1^2) - sqrt(r_a2^2 - r_b2^2) + a sin(alpha_wt) (internal).

    Assumes both tips reach only involute flank (checked by MeshGeometry.validate).
    """
    approach = centre_distance(mesh) * math.sin(working_pressure_angle(mesh))
    side = _side(mesh.gear2)
    length = _tip_roll(mesh.gear1) + side * (_tip_roll(mesh.gear2) - approach)
    return length / transverse_base_pitch(mesh.gear1)


def overlap_ratio(mesh: MeshGeometry) -> float:
    """eps_beta = b sin|beta| / (pi m_n), b the common face width [m]."""
    width = min(mesh.gear1.face_width, mesh.gear2.face_width)
    return width * math.sin(_helix(mesh.gear1)) / (math.pi * mesh.gear1.normal_module)


def total_contact_ratio(mesh: MeshGeometry) -> float:
    """eps_gamma = eps_alpha + eps_beta."""
    return transverse_contact_ratio(mesh) + overlap_ratio(mesh)


def circumferential_backlash(mesh: MeshGeometry) -> float:
    """Circumferential backlash j_wt on the operating pitch circles [m].

    External: j_wt = p_wt - s_wt1 - s_wt2; internal: j_wt = e_wt2 - s_wt1, with the
    thicknesses (and the ring's space width) carried from the reference to the
    operating pitch circle along the involute, thickness allowances included.  Zero
    for the profile shifts' own centre distance without allowances.
    """
    radius1, radius2 = working_pitch_radii(mesh)
    allowance1, allowance2 = mesh.thickness_allowances
    tooth1 = 2.0 * radius1 * _half_angle(mesh.gear1, radius1, allowance1)
    other = 2.0 * radius2 * _half_angle(mesh.gear2, radius2, allowance2)
    if mesh.internal:
        return other - tooth1  # the ring's space width less the pinion's tooth
    pitch = 2.0 * math.pi * radius1 / mesh.gear1.teeth
    return pitch - tooth1 - other


def normal_backlash(mesh: MeshGeometry) -> float:
    """Normal backlash j_bn = j_wt cos(alpha_wt) cos(beta_b) [m]."""
    return (
        circumferential_backlash(mesh)
        * math.cos(working_pressure_angle(mesh))
        * math.cos(base_helix_angle(mesh.gear1))
    )


def clearance_tip_alteration(mesh: MeshGeometry) -> float:
    """Tip alteration coefficient k that restores the basic rack's bottom clearance at
    the operating centre distance: k = (a - a_d)/m_n - (x1 + x2) for an external pair
    (a_d the reference centre distance); for an internal pair k = (a_d - a)/m_n -
    (x1 + x2) (ISO 21771).  Negative: the tips are shortened.  Apply the same k to both
    gears to reproduce catalogue tables that shorten tips this way.
    """
    gear1, gear2 = mesh.gear1, mesh.gear2
    reference = abs(gear1.teeth + _side(gear2) * gear2.teeth) * transverse_module(gear1) / 2.0
    increase = (centre_distance(mesh) - reference) / gear1.normal_module
    return _side(gear2) * increase - (gear1.profile_shift + gear2.profile_shift)


# ----------------------------------------------------------------------------------
# what pygear's mesh models take, and a check of typed values against it
# ----------------------------------------------------------------------------------

TYPED_BASE_RADIUS_RTOL = 5e-3
"""Relative tolerance on a typed base radius: papers print three or four significant
digits (38.7 mm), i.e. a rounding error up to 0.13 %; 0.5 % leaves room for a module
or pressure angle that was itself rounded."""

TYPED_PRESSURE_ANGLE_ATOL_DEG = 0.1
"""Tolerance on a typed working pressure angle [deg]: printed to 0.1 deg (24.6 deg)."""

TYPED_RATIO_ATOL = 0.02
"""Tolerance on a typed contact or overlap ratio: printed to 0.01 (1.24), plus the
spread between tip-diameter conventions (rounded tips, chamfers)."""


@dataclass(frozen=True)
class MeshModelInputs:
    """The mesh quantities pygear's models take by hand, derived from geometry.

    Attributes
    ----------
    base_radii : tuple of float
        Base radii of gears 1 and 2 [m] (``Gear.base_radius``).
    pressure_angle_deg : float
        Operating transverse pressure angle [deg] (``Mesh.pressure_angle_deg``).
    contact_ratio : float
        Transverse contact ratio eps_alpha (``Mesh.contact_ratio``).
    overlap_ratio : float
        Overlap ratio eps_beta (the helical contact law's parameter).
    base_helix_angle_deg : float
        Base helix angle [deg] (``PlanetaryStage.base_helix_angle_deg``).
    centre_distance : float
        Operating centre distance [m] (a planetary stage's carrier radius).
    """

    base_radii: tuple[float, float]
    pressure_angle_deg: float
    contact_ratio: float
    overlap_ratio: float
    base_helix_angle_deg: float
    centre_distance: float


def mesh_model_inputs(mesh: MeshGeometry, path: str = "mesh") -> MeshModelInputs:
    """Validate ``mesh`` (pointed tips only warn) and derive :class:`MeshModelInputs`."""
    mesh.validate(path)
    return MeshModelInputs(
        base_radii=(base_radius(mesh.gear1), base_radius(mesh.gear2)),
        pressure_angle_deg=math.degrees(working_pressure_angle(mesh)),
        contact_ratio=transverse_contact_ratio(mesh),
        overlap_ratio=overlap_ratio(mesh),
        base_helix_angle_deg=math.degrees(base_helix_angle(mesh.gear1)),
        centre_distance=centre_distance(mesh),
    )


def typed_value_mismatches(
    derived: MeshModelInputs,
    *,
    base_radii: tuple[float | None, float | None] | None = None,
    pressure_angle_deg: float | None = None,
    contact_ratio: float | None = None,
    overlap_ratio: float | None = None,
    base_radius_rtol: float = TYPED_BASE_RADIUS_RTOL,
    pressure_angle_atol_deg: float = TYPED_PRESSURE_ANGLE_ATOL_DEG,
    ratio_atol: float = TYPED_RATIO_ATOL,
) -> tuple[str, ...]:
    """Compare typed values (None: not typed) with derived ones; one line per value
    outside its tolerance, empty when all agree."""
    found: list[str] = []
    for index, typed in enumerate(base_radii or (None, None)):
        value = derived.base_radii[index]
        if typed is not None and abs(typed - value) > base_radius_rtol * value:
            found.append(
                f"base radius of gear {index + 1}: typed {typed:.6g} m, geometry gives "
                f"{value:.6g} m (tolerance {base_radius_rtol:.2%})"
            )
    pairs = (
        (
            "working pressure angle",
            pressure_angle_deg,
            derived.pressure_angle_deg,
            pressure_angle_atol_deg,
            " deg",
        ),
        ("transverse contact ratio", contact_ratio, derived.contact_ratio, ratio_atol, ""),
        ("overlap ratio", overlap_ratio, derived.overlap_ratio, ratio_atol, ""),
    )
    for name, typed, value, tolerance, unit in pairs:
        if typed is not None and abs(typed - value) > tolerance:
            found.append(
                f"{name}: typed {typed:.6g}{unit}, geometry gives {value:.6g}{unit} "
                f"(tolerance {tolerance:g}{unit})"
            )
    return tuple(found)


def require_typed_values_match(derived: MeshModelInputs, path: str, **typed: object) -> None:
    """Raise CaseError (one line, naming ``path``) when :func:`typed_value_mismatches`
    finds any; keyword arguments as there."""
    from ..errors import CaseError

    found = typed_value_mismatches(derived, **typed)  # type: ignore[arg-type]
    if found:
        raise CaseError(
            f"{path}: typed values disagree with the gear geometry: " + "; ".join(found)
        )
