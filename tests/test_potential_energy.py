"""Potential-energy tooth and mesh stiffness (pygear.assembly.tooth_stiffness).

References: the published closed forms of Tian (2004) / Wu, Zuo & Parey (2008) for the
bending, shear and axial integrals (healthy and with Tian's cracked section), Yang &
Lin (1987) for the Hertz term, the polynomial and coefficient table of Sainsot, Velex &
Duverger (2004), and ISO 6336-1 method B for the size of the mesh stiffness.  The
closed forms are evaluated here with scipy's adaptive quadrature, independently of the
kernel's Gauss-Legendre segments.  Gear data: the 19/48 pair of Tian 2004 and Wu et al.
2008 (m = 3.2 mm, 20 deg, b = 16 mm, E = 206.8 GPa, nu = 0.3).
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from pygear import load_case
from pygear.assembly.mesh_laws import mesh_law
from pygear.assembly.mesh_stiffness_laws import iso6336_mesh_stiffness
from pygear.assembly.tooth_stiffness import (
    ChippedTooth,
    RootCrack,
    Spall,
    ToothBody,
    mesh_stiffness,
    tooth_compliance,
)
from pygear.kernel.calls import _kernel
from pygear.model import GearGeometry, MeshGeometry
from pygear.model import gear_geometry as geo
from pygear.model.case import replace_parameter
from pygear.model.components import CaseError
from pygear.model.geometry_inputs import planetary_mesh_geometry
from pygear.model.plausibility import PlausibilityWarning

MODULE = 3.2e-3
WIDTH = 0.016
YOUNG = 2.068e11
POISSON = 0.3
PINION_BODY = ToothBody(YOUNG, POISSON, 0.010)
WHEEL_BODY = ToothBody(YOUNG, POISSON, 0.030)
ALPHA = math.radians(20.0)


def tian_pair() -> MeshGeometry:
    return MeshGeometry(GearGeometry(19, MODULE, WIDTH), GearGeometry(48, MODULE, WIDTH))


def base_root_tooth(teeth: int = 40) -> GearGeometry:
    """Root circle on the base circle, the tooth of Tian's closed forms (z = 40 puts
    it at a dedendum of 1.21 m, a legal bottom clearance)."""
    return GearGeometry(teeth, MODULE, WIDTH, dedendum_factor=teeth * (1 - math.cos(ALPHA)) / 2)


def tian_integrals(
    teeth: int, alpha1: float, crack_height: float | None = None, root_radius: float = 0.0
):
    """Tian (2004) eqs. for 1/k_b, 1/k_s, 1/k_a with alpha2 = pi/(2N) + inv(alpha0);
    with ``crack_height`` h_q the cracked section h + min(h, h_q) replaces 2h.  A
    ``root_radius`` above the base circle ends the integral where the involute meets it,
    at alpha = alpha2 - sqrt((r_f / r_b)^2 - 1)."""
    rb = MODULE * teeth / 2 * math.cos(ALPHA)
    alpha2 = math.pi / (2 * teeth) + math.tan(ALPHA) - ALPHA
    upper = alpha2 - math.sqrt(max((root_radius / rb) ** 2 - 1.0, 0.0))
    shear_modulus = YOUNG / (2 * (1 + POISSON))

    def height(a: float) -> float:
        half = rb * (math.sin(a) + (alpha2 - a) * math.cos(a))
        return 2 * half if crack_height is None else half + min(half, crack_height)

    def jacobian(a: float) -> float:
        return rb * (alpha2 - a) * math.cos(a)

    def arm(a: float) -> float:
        return rb * (1 + math.cos(alpha1) * ((alpha2 - a) * math.sin(a) - math.cos(a)))

    integrands = (
        lambda a: 12 * arm(a) ** 2 * jacobian(a) / (YOUNG * WIDTH * height(a) ** 3),
        lambda a: 1.2 * math.cos(alpha1) ** 2 * jacobian(a) / (shear_modulus * WIDTH * height(a)),
        lambda a: math.sin(alpha1) ** 2 * jacobian(a) / (YOUNG * WIDTH * height(a)),
    )
    points = None
    if crack_height is not None:
        half = lambda a: rb * (math.sin(a) + (alpha2 - a) * math.cos(a)) - crack_height  # noqa: E731
        if half(-alpha1) * half(upper) < 0:
            points = [brentq(half, -alpha1, upper, xtol=1e-15)]
    return [
        quad(f, -alpha1, upper, epsabs=0, epsrel=1e-12, points=points, limit=200)[0]
        for f in integrands
    ]


def path_start(pair: MeshGeometry) -> float:
    """Roll distance of gear 1's contact at the start of contact: a sin(alpha_w) minus
    the gear 2 tip's roll distance."""
    tip2, base2 = geo.tip_radius(pair.gear2), geo.base_radius(pair.gear2)
    approach = geo.centre_distance(pair) * math.sin(geo.working_pressure_angle(pair))
    return approach - math.sqrt(tip2**2 - base2**2)


def tooth_radii(gear: GearGeometry, count: int = 5) -> np.ndarray:
    return np.linspace(1.01 * geo.base_radius(gear), geo.tip_radius(gear), count)


def test_bending_shear_axial_match_tian_closed_form():
    gear = base_root_tooth()
    radii = tooth_radii(gear)
    result = tooth_compliance(gear, ToothBody(YOUNG, POISSON, 0.0), radii, n_quad=32)
    alpha2 = math.pi / 80 + math.tan(ALPHA) - ALPHA
    rb = geo.base_radius(gear)
    for i, radius in enumerate(radii):
        alpha1 = math.tan(math.acos(rb / radius)) - alpha2  # Tian's load angle
        assert result["load_angle"][i] == pytest.approx(alpha1, rel=1e-12, abs=1e-14)
        reference = tian_integrals(40, alpha1)
        # quad to 1e-12, 32-point Gauss on analytic integrands: both at round-off
        for name, value in zip(("bending", "shear", "axial"), reference):
            assert result[name][i] == pytest.approx(value, rel=1e-9)
    assert np.all(result["foundation"] == 0.0)  # bore 0: rigid body, as in Tian


def test_root_above_base_circle_integrates_from_the_root():
    """A 60-tooth standard gear has its root circle (28.75 m) above its base circle
    (28.19 m): the tooth is the involute from the root circle up, Tian's integrals with
    their upper limit where the involute meets the root circle."""
    gear = GearGeometry(60, MODULE, WIDTH)
    assert geo.root_radius(gear) > geo.base_radius(gear)
    radii = np.linspace(1.01 * geo.root_radius(gear), geo.tip_radius(gear), 5)
    result = tooth_compliance(gear, ToothBody(YOUNG, POISSON, 0.0), radii, n_quad=32)
    alpha2 = math.pi / 120 + math.tan(ALPHA) - ALPHA
    rb = geo.base_radius(gear)
    for i, radius in enumerate(radii):
        alpha1 = math.tan(math.acos(rb / radius)) - alpha2
        reference = tian_integrals(60, alpha1, root_radius=geo.root_radius(gear))
        # quad to 1e-12, 32-point Gauss on analytic integrands: both at round-off
        for name, value in zip(("bending", "shear", "axial"), reference):
            assert result[name][i] == pytest.approx(value, rel=1e-9)


def test_thick_rooted_tooth_is_checked_at_its_root_circle():
    """The NREL 5 MW wheel (z = 95, x = 0.669, beta = 10 deg): its involute's half
    angle at the base circle exceeds pi/z (a virtual tooth inside the body), at the root
    circle it does not; the tooth is accepted and stiff."""
    gear = GearGeometry(95, 0.014, 0.27, helix_angle_deg=10.0, profile_shift=0.669)
    alpha_t = geo.transverse_pressure_angle(gear)
    thickness = geo.transverse_module(gear) * (math.pi / 2 + 2 * 0.669 * math.tan(ALPHA))
    at_base = thickness / (2 * geo.pitch_radius(gear)) + geo.involute(alpha_t)
    rb, rf = geo.base_radius(gear), geo.root_radius(gear)
    at_root = at_base - geo.involute(math.acos(rb / rf))
    assert at_root < math.pi / 95 < at_base
    radii = np.linspace(1.01 * rf, geo.tip_radius(gear), 3)
    result = tooth_compliance(gear, ToothBody(YOUNG, POISSON, 0.0), radii)
    bending = result["bending"]
    assert np.all(bending > 0.0) and np.all(np.diff(bending) > 0.0)  # softer towards the tip


@pytest.mark.parametrize(("depth", "angle"), [(0.5e-3, 45.0), (1.5e-3, 45.0), (2.5e-3, 70.0)])
def test_cracked_tooth_matches_tian_clipped_section(depth, angle):
    gear = base_root_tooth()
    rb = geo.base_radius(gear)
    alpha2 = math.pi / 80 + math.tan(ALPHA) - ALPHA
    crack_height = rb * math.sin(alpha2) - depth * math.sin(math.radians(angle))
    radii = tooth_radii(gear, 4)
    result = tooth_compliance(
        gear, ToothBody(YOUNG, POISSON, 0.0), radii, fault=RootCrack(1, depth, angle), n_quad=32
    )
    for i, radius in enumerate(radii):
        alpha1 = math.tan(math.acos(rb / radius)) - alpha2
        reference = tian_integrals(40, alpha1, crack_height)
        # both integrate piecewise-analytic integrands split at the clipping height
        for name, value in zip(("bending", "shear", "axial"), reference):
            assert result[name][i] == pytest.approx(value, rel=1e-9)


def test_foundation_matches_sainsot_polynomial():
    # Sainsot, Velex & Duverger (2004), coefficient table for L*, M*, P*, Q*
    table = np.array(
        [
            [-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045],
            [60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086],
            [-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236],
            [-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904],
        ]
    )
    gear = GearGeometry(19, MODULE, WIDTH)
    rb, rf = geo.base_radius(gear), geo.root_radius(gear)
    psi_b = math.pi / 38 + math.tan(ALPHA) - ALPHA
    theta_f = math.asin(rb * math.sin(psi_b) / rf)  # straight flank below the base circle
    h_fi = rf / PINION_BODY.bore_radius
    lmpq = table @ np.array([1 / theta_f**2, h_fi**2, h_fi / theta_f, 1 / theta_f, h_fi, 1])
    radii = tooth_radii(gear)
    result = tooth_compliance(gear, PINION_BODY, radii)
    for i, radius in enumerate(radii):
        alpha_c = math.acos(rb / radius)
        psi = psi_b - (math.tan(alpha_c) - alpha_c)
        beta = result["load_angle"][i]
        u_f = radius * math.cos(psi) - radius * math.sin(psi) * math.tan(beta) - rf
        ratio = u_f / (2 * rf * theta_f)
        expected = (
            math.cos(beta) ** 2
            / (YOUNG * WIDTH)
            * (lmpq[0] * ratio**2 + lmpq[1] * ratio + lmpq[2] * (1 + lmpq[3] * math.tan(beta) ** 2))
        )
        assert result["foundation"][i] == pytest.approx(expected, rel=1e-12)  # same formula


def test_hertz_term_is_yang_lin_and_independent_of_position():
    result = mesh_stiffness(tian_pair(), (PINION_BODY, WHEEL_BODY), n_sample=51)
    hertz = result.compliance["hertz"]
    expected = 4 * (1 - POISSON**2) / (math.pi * YOUNG * WIDTH)  # 1 / k_h of Yang & Lin
    np.testing.assert_allclose(hertz, expected, rtol=1e-13)  # one division, round-off


def test_mesh_size_agrees_with_iso6336_method_b():
    result = mesh_stiffness(tian_pair(), (PINION_BODY, WHEEL_BODY))
    iso = iso6336_mesh_stiffness(tian_pair())
    # ISO's method B is a regression of solid steel gears; potential-energy models with
    # a foundation term land within some 10-20 % of it (measured here: 0.88 and 0.90)
    assert 0.75 < result.mean_stiffness / iso.mesh_stiffness_alpha_total < 1.25
    assert 0.75 < result.pair.max() / iso.single_stiffness_total < 1.25
    assert result.contact_ratio == pytest.approx(geo.transverse_contact_ratio(tian_pair()), 1e-12)


def test_mesh_is_the_sum_of_shifted_pairs():
    result = mesh_stiffness(tian_pair(), (PINION_BODY, WHEEL_BODY), n_sample=4001, n_cycle=400)
    eps = result.contact_ratio
    s = result.cycle_position
    expected = sum(np.interp(s + k, result.position, result.pair, right=0.0) for k in range(3))
    # linear interpolation of a smooth curve sampled at 4001 points: ~1e-7 relative
    np.testing.assert_allclose(result.mesh, expected, rtol=1e-6)
    double = result.mesh > 1.25 * result.pair.max()
    assert double.mean() == pytest.approx(eps - 1, abs=1.5 / s.size)  # two pairs for eps - 1
    # the mean of the cycle samples (rectangle rule across two jumps) against the integral
    assert result.mesh.mean() == pytest.approx(result.mean_stiffness, rel=5e-3)


def test_tabulated_curve_reproduces_mesh_in_contact_table():
    result = mesh_stiffness(tian_pair(), (PINION_BODY, WHEEL_BODY), n_sample=2001, n_cycle=50)
    curve, mean, eps = result.tabulated_curve()
    assert (curve.sum() - 0.5 * (curve[0] + curve[-1])) / (curve.size - 1) == pytest.approx(
        1.0, abs=1e-12
    )
    teeth = np.array([[19], [48]], dtype=np.int32, order="F")
    args = (
        teeth,
        np.array([1], np.int32),
        np.zeros((2, 1), np.int32, order="F"),
        np.array([mean]),
        np.array([eps]),
        np.array([1.0]),
        np.array([0.0]),
        np.array([2], np.int32),
        np.array([0], np.int32),
        np.array([curve.size], np.int32),
        curve,
        -np.ones((2, 1), np.int32, order="F"),
        np.ones(1),
        -np.ones((2, 1), np.int32, order="F"),  # no tooth with a curve of its own
        np.zeros(1, np.int32),
        np.zeros(1, np.int32),
        np.zeros(1, np.int32),  # no displacement excitation
        np.zeros(1, np.int32),
        np.zeros(1),
        4,
    )
    handle, _, ierr = _kernel.contact_table_create(*args)
    assert ierr == 0
    try:
        for s, expected in zip(result.cycle_position, result.mesh):
            theta = np.array([2 * math.pi * s / 19])
            stiffness = _kernel.contact_table_evaluate(handle=handle, max_pairs=4, theta=theta)[0]
            # interpolation of 2001 samples
            assert stiffness[0] == pytest.approx(expected, rel=1e-6)
    finally:
        _kernel.contact_table_free(handle)


@pytest.mark.parametrize("n_quad", [4, 8, 16, 24])
def test_integrals_converge_with_gauss_points(n_quad):
    fault = Spall(1, 0.031, 1.0e-3, 0.2e-3, 0.008)
    reference = mesh_stiffness(
        tian_pair(), (PINION_BODY, WHEEL_BODY), fault=fault, n_sample=41, n_quad=64
    )
    coarse = mesh_stiffness(
        tian_pair(), (PINION_BODY, WHEEL_BODY), fault=fault, n_sample=41, n_quad=n_quad
    )
    error = np.max(np.abs(coarse.faulty_pair / reference.faulty_pair - 1))
    # exponential convergence of Gauss-Legendre on analytic segments (measured 3e-3,
    # 4e-5, 2e-9, 5e-14): each bound allows a factor 10 over the measured error
    assert error < {4: 3e-2, 8: 4e-4, 16: 2e-8, 24: 5e-13}[n_quad]


def test_crack_reduction_grows_with_depth_and_stays_on_its_pass():
    healthy = None
    previous = None
    for depth in (0.5e-3, 1.0e-3, 2.0e-3, 3.0e-3):
        result = mesh_stiffness(
            tian_pair(), (PINION_BODY, WHEEL_BODY), fault=RootCrack(1, depth, 45.0), n_cycle=100
        )
        healthy = result.pair
        assert np.all(result.faulty_pair <= healthy * (1 + 1e-14))
        loss = 1 - result.faulty_pair / healthy
        assert loss[-1] > loss[0]  # largest with the load at the cracked tooth's tip
        if previous is not None:
            assert np.all(loss > previous)
        previous = loss
        # outside the damaged pass the mesh is the healthy one, cycle after cycle
        n_cycle = result.cycle_position.size
        pass_end = math.ceil(result.contact_ratio * n_cycle)
        window = result.faulty_mesh
        tail = window[pass_end + 1 :]
        np.testing.assert_allclose(
            tail, np.resize(result.mesh, window.size)[pass_end + 1 :], rtol=1e-13
        )
        assert np.all(window[1:pass_end] < np.resize(result.mesh, window.size)[1:pass_end])


def test_spall_acts_only_above_its_band():
    gear1 = tian_pair().gear1
    rb = geo.base_radius(gear1)
    centre, length = geo.pitch_radius(gear1), 1.0e-3
    fault = Spall(1, centre, length, 0.2e-3, WIDTH)
    result = mesh_stiffness(tian_pair(), (PINION_BODY, WHEEL_BODY), fault=fault, n_sample=401)
    eps = result.contact_ratio
    start = result.position[0]
    roll = math.sqrt(centre**2 - rb**2)
    arc_low = 0.5 * roll**2 / rb - 0.5 * length  # involute arc length r_b t^2 / 2
    roll_low = math.sqrt(2 * arc_low * rb)
    below = (path_start(tian_pair()) + result.position * result.base_pitch) < roll_low - 1e-9
    assert below.any() and start == 0.0 and result.position[-1] == pytest.approx(eps)
    # same integrals; the damaged width is combined in parallel: round-off only
    np.testing.assert_allclose(result.faulty_pair[below], result.pair[below], rtol=1e-13)
    assert np.all(result.faulty_pair[~below] < result.pair[~below])


def test_chipped_tooth_loses_contact_beyond_the_chip():
    pair = tian_pair()
    result = mesh_stiffness(pair, (PINION_BODY, WHEEL_BODY), fault=ChippedTooth(1, 0.3))
    gear1 = pair.gear1
    ra, rf, rb = geo.tip_radius(gear1), geo.root_radius(gear1), geo.base_radius(gear1)
    chip_roll = math.sqrt((ra - 0.3 * (ra - rf)) ** 2 - rb**2)
    roll = path_start(pair) + result.position * result.base_pitch
    lost = roll > chip_roll + 1e-12
    assert lost.any() and (~lost).any()
    assert np.all(result.faulty_pair[lost] == 0.0)
    np.testing.assert_array_equal(result.faulty_pair[~lost], result.pair[~lost])
    missing = mesh_stiffness(pair, (PINION_BODY, WHEEL_BODY), fault=ChippedTooth(1, 1.0))
    assert np.all(missing.faulty_pair == 0.0)


def test_helical_pair_with_unit_overlap_is_almost_constant():
    normal_module, width = 3.0e-3, 0.040
    helix = math.degrees(math.asin(math.pi * normal_module / width))  # eps_beta = 1
    bodies = (ToothBody(YOUNG, POISSON, 0.015), ToothBody(YOUNG, POISSON, 0.050))
    helical = MeshGeometry(
        GearGeometry(23, normal_module, width, helix_angle_deg=helix),
        GearGeometry(61, normal_module, width, helix_angle_deg=-helix),
    )
    spur = MeshGeometry(
        GearGeometry(23, normal_module, width), GearGeometry(61, normal_module, width)
    )
    result = mesh_stiffness(helical, bodies, n_slice=100)
    assert result.overlap_ratio == pytest.approx(1.0, rel=1e-12)
    assert result.position[-1] == pytest.approx(result.contact_ratio + 1.0, rel=1e-12)
    fluctuation = np.ptp(result.mesh) / result.mesh.mean()
    spur_mesh = mesh_stiffness(spur, bodies).mesh
    spur_fluctuation = np.ptp(spur_mesh) / spur_mesh.mean()
    # measured: 0.5 % helical (100 slices) against 51 % spur
    assert fluctuation < 0.02
    assert spur_fluctuation > 0.3
    coarse = mesh_stiffness(helical, bodies, n_slice=25)
    assert np.ptp(coarse.mesh) / coarse.mesh.mean() > fluctuation  # slicing converges


def test_ring_mesh_and_driving_direction():
    planet = GearGeometry(31, MODULE, WIDTH)
    ring = GearGeometry(81, MODULE, WIDTH, internal=True, tip_alteration=-0.1)
    bodies = (PINION_BODY, ToothBody(YOUNG, POISSON, 0.0))
    forward = mesh_stiffness(MeshGeometry(planet, ring), bodies, fault=RootCrack(2, 1e-3, 45.0))
    backward = mesh_stiffness(
        MeshGeometry(planet, ring), bodies, fault=RootCrack(2, 1e-3, 45.0), driving_gear=2
    )
    assert forward.contact_ratio == pytest.approx(
        geo.transverse_contact_ratio(MeshGeometry(planet, ring)), rel=1e-12
    )
    np.testing.assert_allclose(backward.pair, forward.pair[::-1], rtol=1e-12)
    np.testing.assert_allclose(backward.faulty_pair, forward.faulty_pair[::-1], rtol=1e-12)
    assert np.all(forward.compliance["foundation2"] == 0.0)  # rigid ring rim
    assert np.all(forward.faulty_pair <= forward.pair * (1 + 1e-14))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"bodies": (ToothBody(-1.0, 0.3, 0.01), WHEEL_BODY)}, "young_modulus"),
        ({"bodies": (ToothBody(YOUNG, 0.6, 0.01), WHEEL_BODY)}, "poisson_ratio"),
        ({"bodies": (ToothBody(YOUNG, 0.3, 0.5), WHEEL_BODY)}, "bore_radius"),
        ({"fault": RootCrack(3, 1e-3, 45.0)}, "fault.gear"),
        ({"fault": RootCrack(1, 9e-3, 90.0)}, r"fault\.depth = 0\.009"),
        ({"fault": Spall(1, 0.031, 1e-3, 1e-4, 0.02)}, "face_width"),
        ({"fault": ChippedTooth(1, 1.5)}, "missing_fraction"),
        ({"n_quad": 0}, "n_quad"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, message):
    bodies = kwargs.pop("bodies", (PINION_BODY, WHEEL_BODY))
    with pytest.raises(CaseError, match=message):
        mesh_stiffness(tian_pair(), bodies, **kwargs)


# --- issue #27.2: the fillet-foundation fit's range and the ring's rim ----------------------


def test_small_bore_is_taken_at_the_fits_edge_with_a_warning():
    # Tian's pinion: r_f = m (z/2 - 1.25) = 26.4 mm; a 1 mm bore is h_fi = 26.4, far
    # beyond Sainsot et al.'s h_fi <= 7, where the quadratic fit makes the body ~10^2
    # times too soft.  The law takes r_int = r_f / 7 and says so.
    root = MODULE * (19 / 2 - 1.25)
    at_edge = mesh_stiffness(tian_pair(), (ToothBody(YOUNG, POISSON, root / 7), WHEEL_BODY))
    with pytest.warns(PlausibilityWarning, match=r"bodies\[0\]\.bore_radius = 0\.001 m gives "
                      r"h_fi = r_f / r_int = 26\.4 mm / 1 mm = 26\.4, outside the range 1\.4 "
                      r"\.\. 7"):  # fmt: skip
        small = mesh_stiffness(tian_pair(), (ToothBody(YOUNG, POISSON, 1e-3), WHEEL_BODY))
    assert small.mean_stiffness == pytest.approx(at_edge.mean_stiffness, rel=1e-12)
    # a rigid body (bore 0) is stiffer, by the foundation term (the largest compliance,
    # about half the pair's here), not by the orders of magnitude of the raw fit
    rigid = mesh_stiffness(tian_pair(), (ToothBody(YOUNG, POISSON, 0.0), WHEEL_BODY))
    assert 1.0 < rigid.mean_stiffness / small.mean_stiffness < 3.0


def test_bore_inside_the_fits_range_is_used_as_typed():
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        mesh_stiffness(tian_pair(), (PINION_BODY, WHEEL_BODY))  # h_fi = 2.64 and 2.1


def test_case_bore_outside_the_fit_warns_naming_the_case_parameter():
    case = load_case(Path(__file__).resolve().parent.parent / "cases" / "sequential_planetary")
    with pytest.warns(PlausibilityWarning, match=r"^planetary\.sun\.bore_radius = 0\.001 m gives"):
        changed = replace_parameter(case, "planetary.sun.bore_radius", 1e-3)
    # the sun's root radius is 39.75 mm: 1 mm and 39.75 / 7 mm give the same mesh
    edge = replace_parameter(case, "planetary.sun.bore_radius", 39.75e-3 / 7)
    assert mesh_law(changed.gearbox.stages[0], "sun").mean_stiffness == pytest.approx(
        mesh_law(edge.gearbox.stages[0], "sun").mean_stiffness, rel=1e-12
    )
    with pytest.raises(CaseError, match=r"^planetary\.sun\.bore_radius must lie below the root"):
        replace_parameter(case, "planetary.sun.bore_radius", 0.05)


def ring_foundation_by_hand(ring: GearGeometry, rim: float, radius: np.ndarray) -> np.ndarray:
    """Sainsot's term mirrored onto a zero-shift internal tooth, written out here: psi(r)
    = pi/(2z) - inv(alpha) + inv(alpha_r) (ISO 21771, the space of the ring is the tooth
    of the mating rack's gear), load angle alpha_r + psi, h = r_o/r_f within [1.4, 7]."""
    table = np.array(
        [
            [-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045],
            [60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086],
            [-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236],
            [-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904],
        ]
    )
    rb = ring.teeth * MODULE * math.cos(ALPHA) / 2
    rf = MODULE * (ring.teeth / 2 + 1.25)
    psi_b = math.pi / (2 * ring.teeth) - (math.tan(ALPHA) - ALPHA)
    alpha_f = math.acos(rb / rf)
    theta_f = psi_b + math.tan(alpha_f) - alpha_f
    h = min(max(rim / rf, 1.4), 7.0)
    lmpq = table @ np.array([1 / theta_f**2, h**2, h / theta_f, 1 / theta_f, h, 1])
    out = []
    for r in radius:
        alpha = math.acos(rb / r)
        psi = psi_b + math.tan(alpha) - alpha
        beta = alpha + psi
        u_f = rf - r * math.cos(psi) - r * math.sin(psi) * math.tan(beta)
        ratio = u_f / (2 * rf * theta_f)
        out.append(
            math.cos(beta) ** 2
            / (YOUNG * WIDTH)
            * (lmpq[0] * ratio**2 + lmpq[1] * ratio + lmpq[2] * (1 + lmpq[3] * math.tan(beta) ** 2))
        )
    return np.array(out)


@pytest.mark.parametrize("rim", [0.16, 0.25])  # h = 1.2 (thin rim: the fit's edge) and 1.88
def test_ring_rim_foundation_matches_the_mirrored_sainsot_term(rim):
    ring = GearGeometry(81, MODULE, WIDTH, internal=True, tip_alteration=-0.1)
    radii = np.linspace(geo.tip_radius(ring) * 1.001, geo.root_form_radius(ring) * 0.999, 6)
    result = tooth_compliance(ring, ToothBody(YOUNG, POISSON, 0.0, rim_radius=rim), radii)
    np.testing.assert_allclose(result["foundation"], ring_foundation_by_hand(ring, rim, radii),
                               rtol=1e-12)  # fmt: skip
    rigid = tooth_compliance(ring, ToothBody(YOUNG, POISSON, 0.0), radii)
    assert np.all(rigid["foundation"] == 0.0)


def test_compliant_rim_adds_in_series_to_every_ring_pair():
    planet = GearGeometry(31, MODULE, WIDTH)
    ring = GearGeometry(81, MODULE, WIDTH, internal=True, tip_alteration=-0.1)
    pair = MeshGeometry(planet, ring)
    rigid = mesh_stiffness(pair, (PINION_BODY, ToothBody(YOUNG, POISSON, 0.0)), driving_gear=2)
    rimmed = mesh_stiffness(
        pair, (PINION_BODY, ToothBody(YOUNG, POISSON, 0.0, rim_radius=0.16)), driving_gear=2
    )
    # contact radius on the ring along the path (ring drives: p = 0 at the planet's tip)
    base_pitch = math.pi * MODULE * math.cos(ALPHA)
    span = geo.centre_distance(pair) * math.sin(geo.working_pressure_angle(pair))
    planet_roll = math.sqrt(geo.tip_radius(planet) ** 2 - geo.base_radius(planet) ** 2)
    roll = planet_roll - rigid.spur_position * base_pitch + span
    radius = np.sqrt(geo.base_radius(ring) ** 2 + roll**2)
    expected = 1 / (1 / rigid.pair + ring_foundation_by_hand(ring, 0.16, radius))
    np.testing.assert_allclose(rimmed.pair, expected, rtol=1e-10)
    assert rimmed.mean_stiffness < 0.95 * rigid.mean_stiffness


def test_nrel_stage1_ring_mesh_with_its_rim_agrees_with_iso6336():
    # Issue #27.2: with the rim rigid the stage 1 ring mesh came out 1.48 times ISO
    # 6336-1's c_gamma_alpha b; the case's rim (1.2 times the reference radius) must bring
    # it within the 15 % that ISO's regression and the potential-energy method agree to
    # on external pairs (0.88 .. 1.16 in this file and tests/test_nrel5mw.py).
    case = load_case(Path(__file__).resolve().parent.parent / "cases" / "nrel5mw_gearbox")
    stage = case.gearbox.stage("stage1")
    iso = iso6336_mesh_stiffness(planetary_mesh_geometry(stage, "ring"))
    ratio = mesh_law(stage, "ring").mean_stiffness / iso.mesh_stiffness_alpha_total
    assert 0.85 < ratio < 1.15


def test_helical_ring_pair_is_the_sum_of_its_shifted_transverse_slices():
    # the rim enters a helical pair slice by slice: each of n slices is the whole-face
    # transverse pair at its own position, shifted by (j + 1/2) eps_beta / n, over n.
    # Rebuilt so from the kernel's transverse compliances, the rigid pair must be the
    # kernel's (linear interpolation of 801 samples: ~3e-7), in both driving directions.
    planet = GearGeometry(31, MODULE, WIDTH, helix_angle_deg=15.0)
    ring = GearGeometry(81, MODULE, WIDTH, internal=True, tip_alteration=-0.1, helix_angle_deg=15.0)
    pair = MeshGeometry(planet, ring)
    for driving in (1, 2):
        rigid = mesh_stiffness(pair, (PINION_BODY, ToothBody(YOUNG, POISSON, 0.0)),
                               driving_gear=driving, n_sample=801)  # fmt: skip
        k = 1 / sum(rigid.compliance.values())
        transverse = np.linspace(0.0, rigid.contact_ratio, k.size)
        shifts = (np.arange(100) + 0.5) * rigid.overlap_ratio / 100
        points = rigid.position[:, None] - shifts[None, :]
        rebuilt = np.interp(points, transverse, k, left=0.0, right=0.0).mean(axis=1)
        assert np.abs(rebuilt - rigid.pair).max() < 1e-5 * rigid.pair.max()
        rimmed = mesh_stiffness(
            pair, (PINION_BODY, ToothBody(YOUNG, POISSON, 0.0, rim_radius=0.16)),
            driving_gear=driving, n_sample=801,
        )  # fmt: skip
        assert np.all(rimmed.pair <= rigid.pair * (1 + 1e-12))
        assert rimmed.mean_stiffness < 0.9 * rigid.mean_stiffness


def test_rim_acts_in_series_with_a_damaged_ring_tooth_too():
    planet = GearGeometry(31, MODULE, WIDTH)
    ring = GearGeometry(81, MODULE, WIDTH, internal=True, tip_alteration=-0.1)
    crack = RootCrack(2, 1e-3, 45.0)
    rigid_body, rim_body = ToothBody(YOUNG, POISSON, 0.0), ToothBody(YOUNG, POISSON, 0.0, 0.16)
    rigid = mesh_stiffness(MeshGeometry(planet, ring), (PINION_BODY, rigid_body), fault=crack)
    rimmed = mesh_stiffness(MeshGeometry(planet, ring), (PINION_BODY, rim_body), fault=crack)
    rim = rimmed.compliance["foundation2"]
    np.testing.assert_allclose(rimmed.faulty_pair, 1 / (1 / rigid.faulty_pair + rim), rtol=1e-12)
    np.testing.assert_allclose(rimmed.pair, 1 / (1 / rigid.pair + rim), rtol=1e-12)
    # the cycle and the damaged window are summed again from the rimmed pairs
    assert rimmed.mesh.mean() == pytest.approx(rimmed.mean_stiffness, rel=5e-3)
    outside = rimmed.window_position >= rimmed.total_contact_ratio + 0.01  # crack gone by
    np.testing.assert_allclose(
        rimmed.faulty_mesh[outside],
        np.tile(rimmed.mesh, 3)[: rimmed.faulty_mesh.size][outside],
        rtol=1e-9,
    )


def test_a_rings_bore_is_named_as_unread_and_its_rim_checked():
    case = load_case(Path(__file__).resolve().parent.parent / "cases" / "sequential_planetary")
    with pytest.warns(PlausibilityWarning, match=r"^planetary\.ring\.bore_radius is not read for "
                      r"a ring .* rim_radius"):  # fmt: skip
        replace_parameter(case, "planetary.ring.bore_radius", 0.165)
    # the ring's root circle: m (z/2 + 1.25) = 3 mm * 49.75 = 149.25 mm
    with pytest.raises(CaseError, match=r"^planetary\.ring\.rim_radius must exceed the ring's "
                       r"root radius r_f = 149\.2"):  # fmt: skip
        replace_parameter(case, "planetary.ring.rim_radius", 0.140)
    with pytest.raises(CaseError, match=r"^planetary\.sun\.rim_radius is the outer radius of a "
                       r"ring's rim"):  # fmt: skip
        replace_parameter(case, "planetary.sun.rim_radius", 0.05)
