"""Gear and mesh geometry (pygear.model): published worked examples, hand calculations
and one minimal bad input per refusal rule.

References
----------
KHK Gear Technical Reference (profile shifted spur gears), as reproduced with a 56.500 mm
centre distance by the "Profile Shifted External Spur Gears" table of Bolsover's
Utilities for Alibre (z = 12/24, m = 3 mm, x = 0.6/0.36).
"Gear Generating Profile Shift Calculations" (ISO 21771:2007 equations; m_n = 3.5 mm,
z = 31/30, beta = 21 deg, a = 116.5 mm), Scribd document 376176518.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from pygear.model import (
    GearGeometry,
    MeshGeometry,
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
    root_radius,
    tip_radius,
    tip_thickness,
    transverse_contact_ratio,
    transverse_module,
    transverse_pressure_angle,
    trochoid_interference_margin,
    typed_value_mismatches,
    working_pitch_radii,
    working_pressure_angle,
)
from pygear.model.components import CaseError

MM = 1e-3


def gear(teeth: int, module_mm: float = 3.0, **options: object) -> GearGeometry:
    """A 30 mm wide gear of ``module_mm`` with the ISO 53 rack unless told otherwise."""
    return GearGeometry(teeth=teeth, normal_module=module_mm * MM, face_width=0.03, **options)


def close_to_printed(value: float, printed: float, decimals: int) -> bool:
    """``value`` rounds to ``printed``: within half a unit of the last printed digit
    (plus 1e-9 of that unit for binary round-off)."""
    return abs(value - printed) <= 0.5 * 10.0**-decimals * (1.0 + 1e-9)


# ----------------------------------------------------------------------------------
# published worked examples
# ----------------------------------------------------------------------------------


def test_khk_profile_shifted_spur_pair_matches_the_printed_table() -> None:
    """KHK's profile-shifted spur pair at a = 56.500 mm: every printed quantity, to its
    printed digits, with the tips shortened to the basic rack's clearance as the table
    does (addendum (1 + y - x_mate) m)."""
    nominal = MeshGeometry(
        gear(12, profile_shift=0.6), gear(24, profile_shift=0.36), centre_distance=56.5 * MM
    )
    k = clearance_tip_alteration(nominal)
    assert close_to_printed((56.5 - 54.0) / 3.0, 0.83333, 5)  # y, the table's item 11
    assert k == pytest.approx(0.83333333 - 0.96, abs=1e-8)  # k = y - (x1 + x2)
    pinion = gear(12, profile_shift=0.6, tip_alteration=k)
    wheel = gear(24, profile_shift=0.36, tip_alteration=k)
    mesh = MeshGeometry(pinion, wheel, centre_distance=56.5 * MM)
    mesh.validate("khk")
    alpha_w = working_pressure_angle(mesh)
    assert close_to_printed(involute(math.radians(20.0)), 0.014904, 6)
    assert close_to_printed(involute(alpha_w), 0.034317, 6)
    assert close_to_printed(math.degrees(alpha_w), 26.0888, 4)
    assert close_to_printed(2 * base_radius(pinion) / MM, 33.8289, 4)
    assert close_to_printed(2 * base_radius(wheel) / MM, 67.6579, 4)
    working1, working2 = working_pitch_radii(mesh)
    assert close_to_printed(2 * working1 / MM, 37.667, 3)
    assert close_to_printed(2 * working2 / MM, 75.333, 3)
    assert close_to_printed((tip_radius(pinion) - pitch_radius(pinion)) / MM, 4.420, 3)
    assert close_to_printed((tip_radius(wheel) - pitch_radius(wheel)) / MM, 3.700, 3)
    assert close_to_printed(2 * tip_radius(pinion) / MM, 44.840, 3)
    assert close_to_printed(2 * tip_radius(wheel) / MM, 79.400, 3)
    assert close_to_printed(2 * root_radius(pinion) / MM, 32.100, 3)
    assert close_to_printed(2 * root_radius(wheel) / MM, 66.660, 3)
    assert close_to_printed(transverse_contact_ratio(mesh), 1.202, 3)
    # the designers' shifts give 56.500 mm as their own zero-backlash distance
    shifts_only = MeshGeometry(pinion, wheel)
    assert close_to_printed(centre_distance(shifts_only) / MM, 56.500, 3)


def test_iso21771_helical_pair_from_its_centre_distance() -> None:
    """The ISO 21771 example: working transverse pressure angle from a = 116.5 mm, and
    back, the centre distance from the profile shift sum it prints (10 digits)."""
    helix = 21.0
    # the printed reference centre distance 114.3447280708 mm pins beta = 21 deg
    reference = 3.5 * (31 + 30) / (2 * math.cos(math.radians(helix)))
    assert close_to_printed(reference, 114.3447280708, 10)
    pinion = gear(31, 3.5, helix_angle_deg=helix)
    wheel = gear(30, 3.5, helix_angle_deg=-helix)
    mesh = MeshGeometry(pinion, wheel, centre_distance=116.5 * MM)
    alpha_t = transverse_pressure_angle(pinion)
    assert close_to_printed(math.degrees(alpha_t), 21.2990642859, 10)
    assert close_to_printed(involute(alpha_t), 0.0181260949, 10)
    alpha_wt = working_pressure_angle(mesh)
    assert close_to_printed(math.degrees(alpha_wt), 23.8707609654, 10)
    assert close_to_printed(involute(alpha_wt), 0.0259052382, 10)
    # shifts summing to the printed 0.6518771312 (split as printed: x1 = 0.291)
    shifted = MeshGeometry(
        gear(31, 3.5, helix_angle_deg=helix, profile_shift=0.291),
        gear(30, 3.5, helix_angle_deg=-helix, profile_shift=0.6518771312 - 0.291),
    )
    # 10 printed digits of the sum move a by ~1e-12 m; 1e-9 relative is round-off room
    assert centre_distance(shifted) == pytest.approx(116.5 * MM, rel=1e-9)
    assert math.degrees(working_pressure_angle(shifted)) == pytest.approx(23.8707609654, abs=1e-8)
    assert circumferential_backlash(shifted) == pytest.approx(0.0, abs=1e-12)


# ----------------------------------------------------------------------------------
# hand calculations
# ----------------------------------------------------------------------------------


def test_helical_gear_radii_and_angles_by_hand() -> None:
    """m_n = 4 mm, z = 25, beta = 15 deg, x = 0.2 (hand values, 10 digits, from
    m_t = m_n/cos(beta), tan(alpha_t) = tan(alpha_n)/cos(beta), r = z m_t/2,
    r_b = r cos(alpha_t), r_a = r + m_n (1 + x), r_f = r - m_n (1.25 - x),
    tan(beta_b) = tan(beta) cos(alpha_t))."""
    helical = GearGeometry(
        teeth=25, normal_module=4 * MM, face_width=0.05, helix_angle_deg=15.0, profile_shift=0.2
    )
    assert transverse_module(helical) / MM == pytest.approx(4.141104722, rel=1e-9)
    assert math.degrees(transverse_pressure_angle(helical)) == pytest.approx(20.64689649, rel=1e-9)
    assert pitch_radius(helical) / MM == pytest.approx(51.76380902, rel=1e-9)
    assert base_radius(helical) / MM == pytest.approx(48.43908378, rel=1e-9)
    assert tip_radius(helical) / MM == pytest.approx(56.56380902, rel=1e-9)
    assert root_radius(helical) / MM == pytest.approx(47.56380902, rel=1e-9)
    assert math.degrees(base_helix_angle(helical)) == pytest.approx(14.07609542, rel=1e-9)
    mate = GearGeometry(teeth=60, normal_module=4 * MM, face_width=0.05, helix_angle_deg=-15.0)
    # eps_beta = b sin(beta) / (pi m_n) = 50 sin(15 deg) / (4 pi)
    assert overlap_ratio(MeshGeometry(helical, mate)) == pytest.approx(1.029808260, rel=1e-9)


def test_involute_function_and_its_inverse() -> None:
    """inv(20 deg) = 0.014904384 (tables); the inverse recovers angles to 1e-12 rad."""
    assert close_to_printed(involute(math.radians(20.0)), 0.014904384, 9)
    for degrees in (0.5, 14.5, 20.0, 31.3, 55.0, 80.0):
        angle = math.radians(degrees)
        assert inverse_involute(involute(angle)) == pytest.approx(angle, abs=1e-12)
    with pytest.raises(ValueError):
        inverse_involute(-0.01)


def test_standard_spur_and_internal_contact_ratios_by_hand() -> None:
    """Closed forms at x = 0 (alpha_w = alpha): z 20/40, m 5 mm, external, and z 35/97,
    m 3 mm, internal with the ring tips shortened by 0.1 m (r_a2 = 142.8 mm)."""
    external = MeshGeometry(gear(20, 5.0), gear(40, 5.0))
    assert centre_distance(external) / MM == pytest.approx(150.0, rel=1e-12)
    assert transverse_contact_ratio(external) == pytest.approx(1.635185964, rel=1e-9)
    ring = gear(97, internal=True, tip_alteration=-0.1)
    internal = MeshGeometry(gear(35), ring)
    internal.validate("internal")
    assert tip_radius(ring) / MM == pytest.approx(142.8, rel=1e-12)
    assert root_radius(ring) / MM == pytest.approx(145.5 + 3.75, rel=1e-12)
    assert centre_distance(internal) / MM == pytest.approx(93.0, rel=1e-12)
    assert math.degrees(working_pressure_angle(internal)) == pytest.approx(20.0, rel=1e-12)
    assert transverse_contact_ratio(internal) == pytest.approx(1.809472044, rel=1e-9)


@pytest.mark.parametrize(("x_pinion", "x_ring"), [(0.3, 0.2), (0.0, -0.4), (0.25, -0.25)])
def test_internal_working_angle_agrees_with_the_catalogue_sign_convention(
    x_pinion: float, x_ring: float
) -> None:
    """Independent path: catalogues (KHK, SDP/SI) write internal pairs with unsigned
    teeth and the ring's shift of opposite sign, inv(alpha_w) = 2 tan(alpha)
    (x2' - x1)/(z2 - z1) + inv(alpha), a = (z2 - z1) m cos(alpha) / (2 cos(alpha_w)),
    x2' = -x2 (ISO 21771)."""
    mesh = MeshGeometry(
        gear(24, profile_shift=x_pinion), gear(60, internal=True, profile_shift=x_ring)
    )
    alpha = math.radians(20.0)
    catalogue = 2 * math.tan(alpha) * (-x_ring - x_pinion) / (60 - 24) + involute(alpha)
    alpha_w = inverse_involute(catalogue)
    assert working_pressure_angle(mesh) == pytest.approx(alpha_w, abs=1e-12)
    distance = (60 - 24) * 3 * MM * math.cos(alpha) / (2 * math.cos(alpha_w))
    assert centre_distance(mesh) == pytest.approx(distance, rel=1e-12)
    assert circumferential_backlash(mesh) == pytest.approx(0.0, abs=1e-12)


def test_backlash_from_allowances_and_from_a_wider_centre_distance() -> None:
    """At x = 0 the operating and reference circles coincide, so thinning the teeth by
    A_sn opens j_wt = -(A_sn1 + A_sn2)/cos(beta) exactly (external and internal); a
    centre distance wider by da opens j_wt = 2 da tan(alpha_wt) to first order."""
    helix = 10.0
    cosine = math.cos(math.radians(helix))
    thin = (-40e-6, -25e-6)
    external = MeshGeometry(
        gear(20, helix_angle_deg=helix), gear(50, helix_angle_deg=-helix), thickness_allowances=thin
    )
    assert circumferential_backlash(external) == pytest.approx(65e-6 / cosine, rel=1e-9)
    alpha_t = transverse_pressure_angle(external.gear1)
    expected_normal = (
        65e-6 / cosine * math.cos(alpha_t) * math.cos(base_helix_angle(external.gear1))
    )
    assert normal_backlash(external) == pytest.approx(expected_normal, rel=1e-9)
    internal = MeshGeometry(
        gear(20), gear(61, internal=True, tip_alteration=-0.2), thickness_allowances=thin
    )
    assert circumferential_backlash(internal) == pytest.approx(65e-6, rel=1e-9)
    standard = MeshGeometry(gear(20), gear(50))
    widened = MeshGeometry(gear(20), gear(50), centre_distance=centre_distance(standard) + 1e-6)
    first_order = 2 * 1e-6 * math.tan(math.radians(20.0))
    # the second-order term is ~da^2/r ~ 1e-11 m against 7.3e-7 m: 1e-4 relative
    assert circumferential_backlash(widened) == pytest.approx(first_order, rel=1e-4)


def test_tip_thickness_by_hand() -> None:
    """z = 20, m = 5 mm, x = 0: s_at = 2 r_a (s/(2r) + inv(alpha) - inv(alpha_a)) =
    3.474399923 mm; a ring's tooth is thinner at its tip than at its pitch circle."""
    assert tip_thickness(gear(20, 5.0)) / MM == pytest.approx(3.474399923, rel=1e-9)
    ring = gear(97, internal=True, tip_alteration=-0.1)
    assert 0.0 < tip_thickness(ring) < math.pi * 3 * MM / 2


# ----------------------------------------------------------------------------------
# trochoid interference: closed form against a brute-force rolling simulation
# ----------------------------------------------------------------------------------


def deepest_tip_intrusion(mesh: MeshGeometry, samples: int = 200_001) -> float:
    """Deepest penetration [m] of a pinion tip corner into ring tooth material over
    half a pinion turn each side of the pitch point, in the ring's frame.

    Built from the kinematics alone: ring and pinion turn the same way with
    omega1/omega2 = z2/z1 about fixed centres; a pinion tooth is centred in a ring space
    at the pitch point; ring tooth material at radius rho lies beyond the space's half
    angle eta(rho) = e/(2 r2) + inv(alpha_t) - inv(alpha_rho) from a space centre.
    """
    pinion, ring = mesh.gear1, mesh.gear2
    alpha_t = transverse_pressure_angle(pinion)
    module_t = transverse_module(pinion)
    alpha_n = math.radians(pinion.normal_pressure_angle_deg)
    tip1 = tip_radius(pinion)
    thickness1 = module_t * (math.pi / 2 + 2 * pinion.profile_shift * math.tan(alpha_n))
    corner = (
        thickness1 / (2 * pitch_radius(pinion))
        + involute(alpha_t)
        - involute(math.acos(base_radius(pinion) / tip1))
    )
    space2 = module_t * (math.pi / 2 - 2 * ring.profile_shift * math.tan(alpha_n))
    turn1 = np.linspace(-math.pi / 2, math.pi / 2, samples)
    turn2 = turn1 * pinion.teeth / ring.teeth
    distance = centre_distance(mesh)
    pitch2 = 2 * math.pi / ring.teeth
    worst = 0.0
    for offset in (-corner, corner):
        for tooth in (-1, 0, 1):
            angle = turn1 + offset + 2 * math.pi * tooth / pinion.teeth
            x = distance + tip1 * np.cos(angle)
            y = tip1 * np.sin(angle)
            x_ring = np.cos(turn2) * x + np.sin(turn2) * y  # rotate by -turn2
            y_ring = -np.sin(turn2) * x + np.cos(turn2) * y
            rho = np.hypot(x_ring, y_ring)
            zone = (rho > tip_radius(ring)) & (rho < root_radius(ring))
            rho, polar = rho[zone], np.arctan2(y_ring[zone], x_ring[zone])
            alpha_rho = np.arccos(np.minimum(base_radius(ring) / rho, 1.0))
            half_space = (
                space2 / (2 * pitch_radius(ring))
                + involute(alpha_t)
                - (np.tan(alpha_rho) - alpha_rho)
            )
            from_centre = np.abs((polar + pitch2 / 2) % pitch2 - pitch2 / 2)
            if rho.size:
                worst = max(worst, float(np.max((from_centre - half_space) * rho)))
    return worst


@pytest.mark.parametrize("extra_teeth", [6, 7, 8, 9, 10, 12])
def test_trochoid_margin_agrees_with_a_rolling_simulation(extra_teeth: int) -> None:
    """The closed-form margin is negative exactly when the simulated tip corner cuts a
    ring tooth (35-tooth standard pinion; z2 - z1 = 8 cuts 28 um deep, 9 clears).
    Sampling 2e5 positions resolves intrusions above 1e-7 m."""
    mesh = MeshGeometry(gear(35), gear(35 + extra_teeth, internal=True))
    margin = trochoid_interference_margin(mesh)
    intrusion = deepest_tip_intrusion(mesh)
    assert (margin < 0.0) == (intrusion > 1e-7)
    # the margin is an angle on the ring: the intrusion depth is of order margin r_a2
    if margin < 0.0:
        assert intrusion == pytest.approx(-margin * tip_radius(mesh.gear2), rel=0.3)


# ----------------------------------------------------------------------------------
# refusal rules: one minimal bad input each
# ----------------------------------------------------------------------------------


def refused(mesh: MeshGeometry, *words: str) -> str:
    with pytest.raises(CaseError) as caught:
        mesh.validate("stage.sun_mesh", pointed_tip="error")
    message = str(caught.value)
    assert "\n" not in message and message.startswith("stage.sun_mesh")
    for word in words:
        assert word in message
    return message


def test_refuses_gears_that_do_not_mesh() -> None:
    refused(MeshGeometry(gear(20), gear(40, 3.5)), "gear2.normal_module", "modules")
    refused(
        MeshGeometry(gear(20), gear(40, normal_pressure_angle_deg=25.0)),
        "gear2.normal_pressure_angle_deg",
    )
    same_hand = MeshGeometry(gear(20, helix_angle_deg=15.0), gear(40, helix_angle_deg=15.0))
    refused(same_hand, "gear2.helix_angle_deg", "opposite hands")
    ring = gear(97, internal=True, helix_angle_deg=-15.0, tip_alteration=-0.1)
    refused(MeshGeometry(gear(35, helix_angle_deg=15.0), ring), "same hand")
    refused(MeshGeometry(gear(35, internal=True), gear(97)), "gear1.internal")
    refused(MeshGeometry(gear(40), gear(35, internal=True)), "gear2.teeth", "surrounds")


def test_refuses_bad_parameters() -> None:
    refused(
        MeshGeometry(GearGeometry(teeth=20.0, normal_module=3 * MM, face_width=0.03), gear(40)),
        "gear1.teeth",
    )
    refused(MeshGeometry(gear(20, normal_pressure_angle_deg=0.349), gear(40)), "radians")
    refused(MeshGeometry(gear(20, -3.0), gear(40, -3.0)), "gear1.normal_module")
    refused(MeshGeometry(gear(20, dedendum_factor=0.9), gear(40)), "gear1.dedendum_factor")
    refused(MeshGeometry(gear(20, tip_relief=-1e-5), gear(40)), "gear1.tip_relief")
    refused(
        MeshGeometry(gear(20), gear(40), centre_distance=0.09, working_pressure_angle_deg=21.0),
        "not both",
    )
    refused(
        MeshGeometry(gear(20), gear(40), centre_distance=0.08), "centre_distance", "r_b1 + r_b2"
    )
    refused(MeshGeometry(gear(20), gear(40), thickness_allowances=(-1e-5,)), "thickness_allowances")


def test_refuses_undercut() -> None:
    """17 teeth at x = 0 fall just short of z_min = 2 h_FfP* / sin^2(20 deg) = 17.097."""
    message = refused(MeshGeometry(gear(17), gear(40)), "gear1.profile_shift", "undercut")
    assert "0.0057" in message  # x_min = 0.99997 - 17 sin^2(20 deg)/2 = 0.00570
    MeshGeometry(gear(18), gear(40)).validate("ok")
    MeshGeometry(gear(17, profile_shift=0.006), gear(40)).validate("ok")


def test_refuses_interference_at_the_root() -> None:
    long_tips = MeshGeometry(gear(18), gear(60, addendum_factor=1.15, dedendum_factor=1.4))
    refused(long_tips, "active profile", "gear1 root")
    very_long = MeshGeometry(gear(18), gear(60, addendum_factor=1.8, dedendum_factor=2.05))
    refused(very_long, "involute interference", "base circle")


def test_refuses_internal_mesh_interference() -> None:
    """Ring tip on the planet root (full ring addendum, 35/97), ring tip inside its base
    circle (30 teeth), and trochoid interference (35/41 with shortened ring tips)."""
    refused(MeshGeometry(gear(35), gear(97, internal=True)), "ring) tip", "gear1 root")
    refused(MeshGeometry(gear(18), gear(30, internal=True)), "base radius")
    trochoid = MeshGeometry(gear(35), gear(41, internal=True, tip_alteration=-0.2))
    refused(trochoid, "trochoid", "41 - 35")
    assert deepest_tip_intrusion(trochoid) > 1e-5  # the simulation agrees: it cuts


def test_refuses_contact_ratio_below_one_and_negative_backlash() -> None:
    stubs = MeshGeometry(
        gear(30, addendum_factor=0.4, dedendum_factor=0.65),
        gear(60, addendum_factor=0.4, dedendum_factor=0.65),
    )
    refused(stubs, "contact ratio", "below 1")
    standard = MeshGeometry(gear(20), gear(40))
    tight = MeshGeometry(gear(20), gear(40), centre_distance=centre_distance(standard) - 1e-6)
    refused(tight, "backlash", "negative")
    thick = MeshGeometry(gear(20), gear(40), thickness_allowances=(1e-5, 0.0))
    refused(thick, "backlash")
    negative_shift = MeshGeometry(gear(60, profile_shift=-1.9), gear(60, profile_shift=-1.9))
    refused(negative_shift, "working pressure angle")


def test_pointed_tips_warn_or_refuse() -> None:
    """x = 0.75 on 14 teeth leaves 0.16 m_n at the tip: a warning by default, an error on
    request, nothing when ignored."""
    pointed = MeshGeometry(gear(14, profile_shift=0.75), gear(40))
    assert tip_thickness(pointed.gear1) < 0.2 * 3 * MM
    refused(pointed, "tip too pointed", "gear1")
    with pytest.warns(UserWarning, match="tip too pointed"):
        pointed.validate("m")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pointed.validate("m", pointed_tip="ignore")


# ----------------------------------------------------------------------------------
# derived model inputs against typed ones
# ----------------------------------------------------------------------------------


def test_typed_values_are_compared_within_stated_tolerances() -> None:
    """The KHK pair's derived inputs against values typed as a paper prints them."""
    k = 0.83333333333 - 0.96
    mesh = MeshGeometry(
        gear(12, profile_shift=0.6, tip_alteration=k),
        gear(24, profile_shift=0.36, tip_alteration=k),
        centre_distance=56.5 * MM,
    )
    derived = mesh_model_inputs(mesh)
    assert derived.centre_distance == pytest.approx(56.5 * MM, rel=1e-12)
    typed = dict(
        base_radii=(16.91 * MM, 33.83 * MM),
        pressure_angle_deg=26.1,
        contact_ratio=1.2,
        overlap_ratio=0.0,
    )
    assert typed_value_mismatches(derived, **typed) == ()
    require_typed_values_match(derived, "stage.sun_mesh", **typed)
    wrong = dict(typed, base_radii=(17.5 * MM, None), contact_ratio=1.4)
    found = typed_value_mismatches(derived, **wrong)
    assert len(found) == 2 and "gear 1" in found[0] and "contact ratio" in found[1]
    with pytest.raises(CaseError, match="stage.sun_mesh: typed values disagree"):
        require_typed_values_match(derived, "stage.sun_mesh", **wrong)
