"""The NREL 5 MW reference gearbox case (cases/nrel5mw_gearbox).

References: the gear table of Nejad, Guo, Gao & Moan (Wind Energy 19 (2016) 1089-1106,
Table V, as reproduced publicly by Rebouças' Drivetrain model), hand calculations of
ISO 21771 (contact ratios from the table's own tip diameters and centre distances) and
ISO 6336-1:2019 method B (the q' series, written out below), and Rayleigh's principle
for the first drivetrain mode.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from pygear import Case
from pygear.analysis.modes.modal import modal_analysis
from pygear.assembly import assemble
from pygear.assembly.mesh_laws import mesh_law, planetary_mesh_geometry
from pygear.assembly.tooth_stiffness import ToothBody
from pygear.assembly.tooth_stiffness import mesh_stiffness as tooth_mesh_stiffness
from pygear.model import MeshGeometry, centre_distance, root_radius, tip_radius
from pygear.model.case import load_case_module

CASE_DIR = Path(__file__).resolve().parent.parent / "cases" / "nrel5mw_gearbox"

# Table V [mm]: centre distances, tip and root diameters (three decimals)
PUBLISHED_CENTRE_DISTANCE = {"stage1": 863.0, "stage2": 584.0, "parallel": 861.0}
PUBLISHED_TIP_DIAMETER = {
    ("stage1", "sun"): 978.839,
    ("stage1", "planet"): 905.440,
    ("stage1", "ring"): 2475.087,
    ("stage2", "sun"): 432.845,
    ("stage2", "planet"): 815.655,
    ("stage2", "ring"): 1906.074,
    ("parallel", "pinion"): 380.751,
    ("parallel", "wheel"): 1395.372,
}
PUBLISHED_ROOT_DIAMETER = {
    ("stage1", "sun"): 798.061,
    ("stage1", "planet"): 724.662,
    ("stage1", "ring"): 2677.507,
    ("stage2", "sun"): 341.845,
    ("stage2", "planet"): 724.655,
    ("stage2", "ring"): 2000.574,
    ("parallel", "pinion"): 319.627,
    ("parallel", "wheel"): 1334.248,
}
# The meshes as (stage, gear 1, gear 2): gear 1 the one with the larger profile shift,
# as ISO 6336-1's q' regression requires of external pairs.
MESHES = (
    ("stage1", "planet", "sun"),
    ("stage1", "planet", "ring"),
    ("stage2", "planet", "sun"),
    ("stage2", "planet", "ring"),
    ("parallel", "wheel", "pinion"),
)
# Transverse contact ratio by hand (ISO 21771): path of contact from Table V's tip
# diameters and centre distance, sqrt(r_a1^2 - r_b1^2) +- sqrt(r_a2^2 - r_b2^2) -+
# a_w sin(alpha_wt), over the transverse base pitch pi m_t cos(alpha_t).
HAND_CONTACT_RATIO = {
    ("stage1", "planet", "sun"): 1.115,
    ("stage1", "planet", "ring"): 1.279,
    ("stage2", "planet", "sun"): 1.370,
    ("stage2", "planet", "ring"): 1.618,
    ("parallel", "wheel", "pinion"): 1.463,
}


@pytest.fixture(scope="module")
def nrel():
    """The case module: its case and its geometry tables."""
    return load_case_module(CASE_DIR)[1]


@pytest.fixture(scope="module")
def nrel_modal(nrel):
    return modal_analysis(assemble(nrel.case))


def geometry(nrel, stage: str, member: str):
    """The GearGeometry the case's gear carries."""
    found = nrel.case.gearbox.stage(stage)
    if stage == "parallel":
        return {"wheel": found.input_gear, "pinion": found.output_gear}[member].geometry
    return getattr(found, member).geometry


def test_case_loads(nrel):
    case = nrel.case
    assert isinstance(case, Case)
    assert [stage.name for stage in case.gearbox.stages] == [
        "rotor",
        "stage1",
        "stage2",
        "parallel",
        "generator",
    ]
    assert {scene.name for scene in case.scenes} >= {"modal", "runup"}


def test_ratio_from_teeth(nrel):
    """(1 + 56/19)(1 + 93/18)(95/24) = 96.354 (Table V prints 1:3.947, 1:6.167, 1:3.958;
    the SIMPACK model 96.3542)."""
    hand = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)
    assert hand == pytest.approx(96.354, abs=5e-4)  # printed to three decimals
    gearbox = nrel.case.gearbox
    # a planetary stage's speed_ratio is sun over carrier speed, a parallel stage's input
    # over output speed (the wheel drives the pinion)
    ratio = (
        gearbox.stage("stage1").speed_ratio
        * gearbox.stage("stage2").speed_ratio
        / gearbox.stage("parallel").speed_ratio
    )
    # the base radii of a stage share m_n and alpha_n, so their ratios are the teeth's
    # up to a few ulps of round-off
    assert ratio == pytest.approx(hand, rel=1e-12)


@pytest.mark.parametrize("stage, first, second", MESHES)
def test_profile_shifts_reproduce_published_centre_distances(nrel, stage, first, second):
    """The zero-backlash centre distance of the profile shifts (ISO 21771) is Table V's
    a_w within 0.1 mm: x is printed to three decimals, and 0.0005 on each of two shifts
    moves a_w by up to about m_n x 0.001 = 0.045 mm (stage 1)."""
    pair = MeshGeometry(geometry(nrel, stage, first), geometry(nrel, stage, second))
    assert centre_distance(pair) * 1e3 == pytest.approx(PUBLISHED_CENTRE_DISTANCE[stage], abs=0.1)


@pytest.mark.parametrize("stage, member", sorted(PUBLISHED_TIP_DIAMETER))
def test_geometry_reproduces_published_diameters(nrel, stage, member):
    """Tip and root diameters against Table V within 0.1 mm: 2 m_n times the 0.0005
    rounding of x is 0.045 mm at m_n = 45 mm."""
    gear = geometry(nrel, stage, member)
    assert 2e3 * tip_radius(gear) == pytest.approx(PUBLISHED_TIP_DIAMETER[(stage, member)], abs=0.1)
    assert 2e3 * root_radius(gear) == pytest.approx(
        PUBLISHED_ROOT_DIAMETER[(stage, member)], abs=0.1
    )


def case_mesh(nrel, stage: str, first: str, second: str):
    """The case's Mesh between ``first`` and ``second``."""
    found = nrel.case.gearbox.stage(stage)
    if stage == "parallel":
        return found.mesh
    return found.ring_mesh if "ring" in (first, second) else found.sun_mesh


@pytest.mark.parametrize("stage, first, second", MESHES)
def test_every_mesh_has_the_simpack_backlash(nrel, stage, first, second):
    """Thinned teeth give every mesh the SIMPACK model's 0.40 mm normal backlash at the
    printed centre distance: j_bn = j_wt cos(alpha_wt) cos(beta_b) (ISO 21771), beta_b =
    asin(sin 10 deg cos 20 deg) on the helical pair; 1e-9 m is round-off."""
    found = case_mesh(nrel, stage, first, second)
    helix = 10.0 if stage == "parallel" else 0.0
    base_helix = math.asin(math.sin(math.radians(helix)) * math.cos(math.radians(20.0)))
    normal = (
        found.backlash * math.cos(math.radians(found.pressure_angle_deg)) * math.cos(base_helix)
    )
    assert normal == pytest.approx(0.40e-3, abs=1e-9)


@pytest.mark.parametrize("stage, first, second", MESHES)
def test_contact_ratios_from_geometry(nrel, stage, first, second):
    """Every derived transverse contact ratio exceeds 1 and agrees with the hand value
    from Table V's own tip diameters within 0.002.  The geometry's tip diameters differ
    from the table's by at most 0.031 mm (m_n = 45 mm, p_bt = 133 mm), 0.013 mm (21 mm)
    and 0.004 mm (14 mm), which moves eps_alpha by under 0.001; the hand values carry
    three decimals."""
    ratio = case_mesh(nrel, stage, first, second).contact_ratio
    assert ratio > 1.0
    assert ratio == pytest.approx(HAND_CONTACT_RATIO[(stage, first, second)], abs=2e-3)


def test_first_drivetrain_mode_lies_below_the_rigid_gearbox_bound(nrel, nrel_modal):
    """The first nonzero natural frequency is the rotor turning against the gearbox and
    generator through the main shaft.

    Upper bound (Rayleigh's principle, Courant-Fischer): restricting the motion to the
    rotor angle and a rigid turn of the whole gearbox (every member at its kinematic
    ratio, no mesh, bearing or shaft spring strained but the main shaft) can only raise
    the second eigenvalue, and leaving out planets' and shafts' inertia raises it again.
    That leaves two inertias on the main shaft spring k:
    f_max = sqrt(k (1/J_rotor + 1/J_gearbox)) / (2 pi), J_gearbox the central members'
    and the generator's polar inertias times their speed ratio squared.

    Lower limit, a judgement: the gearbox's own springs referred to the main shaft are
    each 20 to 60 times its 9.3e8 N m/rad (stage 1's sun meshes 3 x 7.6e9 N/m x
    (0.402 m)^2 x 3.95^2 = 5.7e10 N m/rad; its planet bearings 3 x 1.26e10 N/m x
    (0.863 m)^2 = 2.8e10; stage 2's planet bearings 3 x 1.26e9 x 0.584^2 x 3.95^2 =
    2.0e10; stage 1's ring in the housing 1e10 x 1.184^2 / (1 - 19/75)^2 = 2.5e10), so
    in series they soften the chain by some 20 % and lower f by some 10 %, far from
    the factor 4 in stiffness that halves f.  A wrong digit in the generator inertia,
    the main shaft or a ratio moves f out of the range.
    """
    gearbox = nrel.case.gearbox
    stage1, stage2 = gearbox.stage("stage1"), gearbox.stage("stage2")
    parallel = gearbox.stage("parallel")
    ratio1 = 1 + 56 / 19
    ratio12 = ratio1 * (1 + 93 / 18)
    ratio = ratio12 * 95 / 24
    gearbox_inertia = (
        stage1.carrier.polar_inertia
        + (stage1.sun.polar_inertia + stage2.carrier.polar_inertia) * ratio1**2
        + (stage2.sun.polar_inertia + parallel.input_gear.polar_inertia) * ratio12**2
        + (parallel.output_gear.polar_inertia + gearbox.stage("generator").body.polar_inertia)
        * ratio**2
    )
    rotor_inertia = gearbox.stage("rotor").body.polar_inertia
    main_shaft = next(c for c in gearbox.couplings if c.name == "main_shaft").stiffness
    upper = math.sqrt(main_shaft * (1 / rotor_inertia + 1 / gearbox_inertia)) / (2 * math.pi)
    frequencies = nrel_modal.frequency.values
    assert frequencies[0] == pytest.approx(0.0, abs=1e-6)  # the drivetrain turns freely
    first = float(frequencies[1])
    assert math.isfinite(first)
    # 1e-9: the eigensolver's relative round-off on a 2 Hz mode among kHz modes
    assert 0.5 * upper <= first <= upper * (1 + 1e-9)


# ISO 6336-1:2019 method B, clause 9: minimum flexibility q' = C1 + C2/z_n1 + C3/z_n2 +
# C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2 + C8 x1^2 + C9 x2^2 [mm um/N]
ISO_Q_COEFFICIENTS = (
    0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182,
)  # fmt: skip


def iso6336_by_hand(z1, x1, z2, x2, helix_deg, face_width, contact_ratio):
    """c_gamma_alpha b [N/m] of a pair (z2 None for a ring: z_n2 = infinity), solid
    blanks (C_R = 1), C_M = 0.8, basic rack h_fP = 1.25 m_n at alpha_n = 20 deg
    (C_B = 1 + 0.5 (1.2 - 1.25) = 0.975), line load at or above 100 N/mm."""
    c1, c2, c3, c4, c5, c6, c7, c8, c9 = ISO_Q_COEFFICIENTS
    helix = math.radians(helix_deg)
    base_helix = math.asin(math.sin(helix) * math.cos(math.radians(20.0)))
    virtual = 1.0 / (math.cos(base_helix) ** 2 * math.cos(helix))
    zn1 = z1 * virtual
    inverse_zn2 = 0.0 if z2 is None else 1.0 / (z2 * virtual)
    flexibility = (
        c1 + c2 / zn1 + c3 * inverse_zn2 + c4 * x1 + c5 * x1 / zn1 + c6 * x2
        + c7 * x2 * inverse_zn2 + c8 * x1**2 + c9 * x2**2
    )  # fmt: skip
    single = (1.0 / flexibility) * 0.8 * 1.0 * 0.975 * math.cos(helix)
    mesh = single * (0.75 * contact_ratio + 0.25)  # c_gamma_alpha [N/(mm um)]
    return mesh * face_width * 1e9  # N/(mm um) x m -> N/m


def mean_mesh_stiffness(nrel, stage: str, first: str, second: str) -> float:
    """The mean stiffness the case's mesh law gives the mesh [N/m]."""
    member = "mesh" if stage == "parallel" else ("ring" if "ring" in (first, second) else "sun")
    return mesh_law(nrel.case.gearbox.stage(stage), member).mean_stiffness


# Stage 1's ring mesh is left to its own test: the potential-energy law takes the ring's
# rim as rigid (Sainsot's fillet-foundation fit is for a tooth on a bore, not for a ring),
# and on stage 1 that alone puts the mesh 48 % above ISO's rack-based value.
EXTERNAL_AND_STAGE2_RING = tuple(mesh for mesh in MESHES if mesh != ("stage1", "planet", "ring"))


def iso6336_reference(nrel, stage: str, first: str, second: str) -> float:
    """ISO 6336-1 method B c_gamma_alpha b of a case mesh, by hand [N/m]."""
    one, two = geometry(nrel, stage, first), geometry(nrel, stage, second)
    return iso6336_by_hand(
        one.teeth,
        one.profile_shift,
        None if two.internal else two.teeth,
        two.profile_shift,
        abs(one.helix_angle_deg),
        min(one.face_width, two.face_width),
        HAND_CONTACT_RATIO[(stage, first, second)],
    )


@pytest.mark.parametrize("stage, first, second", EXTERNAL_AND_STAGE2_RING)
def test_mesh_stiffness_near_iso6336(nrel, stage, first, second):
    """Each mean mesh stiffness lies within 30 % of ISO 6336-1's c_gamma_alpha b.

    ISO's value is a regression over profile shifts and tooth numbers with blanket
    factors (C_M = 0.8 against the theory); the NREL pairs sit at the edge of its range
    (large positive shifts), and the first author's SIMPACK model itself has mesh
    stiffnesses 7 to 12 % above it for stages 1 and 3.  30 % bounds a model that keeps
    the physics of a tooth pair while catching a lost factor (2, or the c_gamma_beta
    that some implementations add) or a wrong face width.
    """
    reference = iso6336_reference(nrel, stage, first, second)
    assert mean_mesh_stiffness(nrel, stage, first, second) == pytest.approx(reference, rel=0.3)


def test_stage1_ring_mesh_rim_against_iso6336(nrel):
    """The stage 1 ring mesh: far above ISO with a rigid rim, near it with the case's rim.

    ISO 6336-1 treats the ring as a rack on an elastic body.  With no rim the law gives
    the ring tooth no fillet-foundation compliance (a rigid rim) and the mean must lie
    well above ISO's value; the case gives the ring its rim (``Gear.rim_radius``), whose
    foundation term must bring the mean within the 30 % of the other meshes: the rim is
    the whole difference.
    """
    stage = nrel.case.gearbox.stage("stage1")
    law_mean = mean_mesh_stiffness(nrel, "stage1", "planet", "ring")  # the case: rim given
    reference = iso6336_reference(nrel, "stage1", "planet", "ring")
    mesh = stage.ring_mesh
    geometry_pair = planetary_mesh_geometry(stage, "ring")
    rigid_bodies = (  # no rim radius for the ring: a rigid rim
        ToothBody(mesh.young_modulus, mesh.poisson_ratio, stage.planet.bore_radius),
        ToothBody(mesh.young_modulus, mesh.poisson_ratio, 0.0),
    )
    result = tooth_mesh_stiffness(geometry_pair, rigid_bodies, driving_gear=2)
    pair = 1.0 / sum(result.compliance.values())
    # the mean mesh stiffness is eps_alpha times the pair curve's trapezoid mean
    rigid = result.contact_ratio * float(
        (pair.sum() - 0.5 * (pair[0] + pair[-1])) / (pair.size - 1)
    )
    assert rigid > 1.3 * reference
    assert law_mean < rigid
    assert law_mean == pytest.approx(reference, rel=0.3)
