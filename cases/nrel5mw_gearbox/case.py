"""The NREL 5 MW reference gearbox on the NREL 5 MW turbine's rotor and generator.

Gearbox: Nejad, Guo, Gao & Moan, "Development of a 5 MW reference gearbox for offshore
wind turbines", Wind Energy 19 (2016) 1089-1106, doi:10.1002/we.1884.  Turbine: Jonkman,
Butterfield, Musial & Scott, NREL/TP-500-38060 (2009).

Two planetary stages (three planets each, ring held, carrier in, sun out) and a helical
parallel stage, ratio (1 + 56/19)(1 + 93/18)(95/24) = 96.354, between the rotor (on the
main shaft) and the generator (on the high-speed shaft).  Every gear carries its
geometry (``Gear(geometry=GearGeometry(...))``: teeth, module, profile shift, face
width, tip alteration); pygear derives base radii, working pressure angles, contact and
overlap ratios, backlash and the base helix angle from it.  The four planetary meshes
and the helical pair run the potential-energy law (pair curve and mean stiffness from
the tooth geometry, bores and material; the helical pair sliced along its face width).
The scene ``modal_iso6336`` puts ISO 6336-1's stiffness on every mesh instead.

Sources, as tagged in the comments below:

* [P-V], [P-VI,IX]: the paper's gear table (Table V) and bearing tables (Tables VI and
  IX) as reproduced by G. Rebouças' public Drivetrain model (MATLAB, NTNU), docstrings
  of ``@NREL_5MW/NREL_5MW.m``; the table numbers are the ones that reproduction cites.
* [SIMPACK]: the parameter file of the first author's SIMPACK model in the same
  repository (``@NREL_5MW/NREL_5MW.Nejad.subvar``): unrounded bearing stiffnesses,
  backlash, bearing damping; it repeats every gear value of [P-V].
* [Repro]: values of that reproduction that are not the paper's (tip alterations
  "taken from KISSsoft", shaft sizes "based mainly on the SIMPACK simulation").
* [Jonkman]: the turbine as in NREL's own OpenFAST regression decks (OpenFAST/r-test,
  5MW_Land_DLL_WTurb ElastoDyn input and DISCON controller).

The gear table is internally consistent: its tooth numbers, modules, pressure angles,
helix angle, profile shifts and tip alterations reproduce every tabulated centre
distance to 9 um and every tip and root diameter to 0.09 mm (ISO 21771; checked in
tests/test_nrel5mw.py).  Masses and inertias are not in the tables: they are ASSUMED
from the geometry (steel annuli).  Every other value not found in a source is marked
ASSUMED with its reason.
"""

import dataclasses
import math

from pygear import (
    Bearing,
    Body,
    Carrier,
    Case,
    Gear,
    Gearbox,
    Mesh,
    ParallelStage,
    PlanetaryStage,
    PlanetBearing,
    Probe,
    RayleighDamping,
    Scene,
    ShaftInertia,
    TorqueLaw,
    TorsionalSpring,
    Transient,
)
from pygear.assembly.mesh_stiffness_laws import iso6336_mesh_stiffness
from pygear.model import (
    GearGeometry,
    MeshGeometry,
    base_radius,
    normal_backlash,
    working_pressure_angle,
)
from pygear.model.dlc_settings import DesignLoadCases
from pygear.model.rating import Material, Rating, RollingBearingData, iso6336_5_material
from pygear.model.reduction_settings import Reductions
from pygear.model.rolling_bearing import BearingDefect, RollingBearing
from pygear.model.sensors import Sensor, StructuralMode

# ----------------------------------------------------------------------------------
# Gear geometry [P-V]; the SIMPACK model repeats m_n, b, a_w, alpha_n, beta, z and x
# ----------------------------------------------------------------------------------

NORMAL_PRESSURE_ANGLE_DEG = 20.0  # alpha_n, all stages [P-V]
# Basic rack h_aP = 1.0 m_n, h_fP = 1.25 m_n [SIMPACK]; the reproduction names ISO 53
# profile A [Repro], whose root fillet rho_fP = 0.38 m_n sets where the involute starts.
ADDENDUM_FACTOR = 1.0
DEDENDUM_FACTOR = 1.25
ROOT_FILLET_FACTOR = 0.38

STAGE1_MODULE = 45e-3  # m_n [m] [P-V]
STAGE1_FACE_WIDTH = 0.491  # b [m] [P-V]
STAGE1_TEETH = {"sun": 19, "planet": 17, "ring": 56}  # [P-V]
# Profile shift coefficients [P-V]; the ring's in ISO 21771's sign (x > 0 moves its tip
# towards the axis): with this sign the tabulated ring tip and root diameters come out.
STAGE1_SHIFT = {"sun": 0.617, "planet": 0.802, "ring": -0.501}
STAGE1_CENTRE_DISTANCE = 0.863  # a_w [m] [P-V]: the carrier radius
# Tip alteration k m_n = -10.861 mm of sun and planet [Repro]; with it the tip diameters
# of [P-V] (978.839 and 905.440 mm) come out to 0.03 mm.  The ring has none.
STAGE1_TIP_ALTERATION = -10.861e-3 / STAGE1_MODULE

STAGE2_MODULE = 21e-3  # m_n [m] [P-V]
STAGE2_FACE_WIDTH = 0.550  # b [m] [P-V]
STAGE2_TEETH = {"sun": 18, "planet": 36, "ring": 93}  # [P-V]
STAGE2_SHIFT = {"sun": 0.389, "planet": 0.504, "ring": 0.117}  # [P-V], ISO 21771 sign
STAGE2_CENTRE_DISTANCE = 0.584  # a_w [m] [P-V]
STAGE2_TIP_ALTERATION = -1.75e-3 / STAGE2_MODULE  # k m_n = -1.75 mm, sun and planet [Repro]

STAGE3_MODULE = 14e-3  # m_n [m] [P-V]
STAGE3_FACE_WIDTH = 0.360  # b [m] [P-V]
STAGE3_HELIX_ANGLE_DEG = 10.0  # beta [P-V]
STAGE3_TEETH = {"pinion": 24, "wheel": 95}  # [P-V]
STAGE3_SHIFT = {"pinion": 0.480, "wheel": 0.669}  # [P-V]
STAGE3_CENTRE_DISTANCE = 0.861  # a_w [m] [P-V]
STAGE3_TIP_ALTERATION = -0.938e-3 / STAGE3_MODULE  # k m_n = -0.938 mm, both gears [Repro]
# ASSUMED: the tables give no hand of helix; pinion right hand (+), wheel left hand (-).
# Any opposite pair meshes; the hand only sets the sign of the axial mesh force.
PINION_HAND, WHEEL_HAND = +1.0, -1.0


def spur_gear(stage: int, member: str) -> GearGeometry:
    """Geometry of a planetary stage's sun, planet or ring ([P-V], [Repro])."""
    module, width, teeth, shift, tip_alteration = {
        1: (STAGE1_MODULE, STAGE1_FACE_WIDTH, STAGE1_TEETH, STAGE1_SHIFT, STAGE1_TIP_ALTERATION),
        2: (STAGE2_MODULE, STAGE2_FACE_WIDTH, STAGE2_TEETH, STAGE2_SHIFT, STAGE2_TIP_ALTERATION),
    }[stage]
    ring = member == "ring"
    return GearGeometry(
        teeth=teeth[member],
        normal_module=module,
        face_width=width,
        normal_pressure_angle_deg=NORMAL_PRESSURE_ANGLE_DEG,
        profile_shift=shift[member],
        addendum_factor=ADDENDUM_FACTOR,
        dedendum_factor=DEDENDUM_FACTOR,
        tip_root_radius_factor=ROOT_FILLET_FACTOR,
        internal=ring,
        tip_alteration=0.0 if ring else tip_alteration,
    )


def helical_gear(member: str) -> GearGeometry:
    """Geometry of the parallel stage's pinion or wheel ([P-V], [Repro])."""
    hand = PINION_HAND if member == "pinion" else WHEEL_HAND
    return GearGeometry(
        teeth=STAGE3_TEETH[member],
        normal_module=STAGE3_MODULE,
        face_width=STAGE3_FACE_WIDTH,
        normal_pressure_angle_deg=NORMAL_PRESSURE_ANGLE_DEG,
        helix_angle_deg=hand * STAGE3_HELIX_ANGLE_DEG,
        profile_shift=STAGE3_SHIFT[member],
        addendum_factor=ADDENDUM_FACTOR,
        dedendum_factor=DEDENDUM_FACTOR,
        tip_root_radius_factor=ROOT_FILLET_FACTOR,
        tip_alteration=STAGE3_TIP_ALTERATION,
    )


GEOMETRY = {
    "stage1": {member: spur_gear(1, member) for member in ("sun", "planet", "ring")},
    "stage2": {member: spur_gear(2, member) for member in ("sun", "planet", "ring")},
    "parallel": {member: helical_gear(member) for member in ("pinion", "wheel")},
}


# Centre distances and backlash.  The printed a_w (863, 584, 861 mm) and profile shifts
# (three decimals) are both rounded.  At the printed a_w and without thinned teeth,
# stage 1's planet-ring mesh (-5.6 um) and both meshes of stage 2 (-2.1 and -0.2 um)
# have negative backlash, which pygear refuses (the teeth would jam).  Leaving the
# centre distance to the profile shifts does not help a planetary stage: an external
# (sun-planet) mesh needs a >= its zero-backlash distance, an internal (planet-ring)
# mesh a <= its own, and the rounded shifts put the planet-ring distance below the
# sun-planet one (862.991 < 862.996 mm; 584.000 < 584.002 mm), so no carrier radius
# suits both.  The teeth are therefore thinned to the SIMPACK model's 0.40 mm normal
# backlash in every mesh, at the printed centre distances.
NORMAL_BACKLASH = 0.40e-3  # m, every mesh [SIMPACK] ($_Norm_Backlash)
CENTRE_DISTANCE = {
    "stage1": STAGE1_CENTRE_DISTANCE,
    "stage2": STAGE2_CENTRE_DISTANCE,
    "parallel": STAGE3_CENTRE_DISTANCE,
}


def operating_centre_distance(stage: str) -> float | None:
    """The printed a_w of a planetary stage (its carrier radius); None for the parallel
    stage, which pygear sets at the zero-backlash distance of its profile shifts
    (860.999 mm, the table's 861 mm)."""
    return None if stage == "parallel" else CENTRE_DISTANCE[stage]


def thickness_allowances(stage: str) -> dict[str, float]:
    """Normal tooth thickness allowances A_sn [m] giving every mesh of ``stage`` the
    normal backlash :data:`NORMAL_BACKLASH` at its operating centre distance.

    ISO 21771: thinning the teeth by A_sn1 + A_sn2 < 0 adds -(A_sn1 + A_sn2) cos(alpha_n)
    to the normal backlash j_bn, for spur and helical pairs alike.  ASSUMED split (the
    SIMPACK model gives the mesh backlash only): the planet (or, in the parallel stage,
    each gear) takes half of it; the sun and the ring take the rest of their mesh's,
    which also absorbs the few micrometres the rounding left.
    """
    gears, distance = GEOMETRY[stage], operating_centre_distance(stage)
    cosine = math.cos(math.radians(NORMAL_PRESSURE_ANGLE_DEG))
    half = -NORMAL_BACKLASH / (2.0 * cosine)

    def rest(first: str, second: str, fixed: float) -> float:
        unthinned = normal_backlash(
            MeshGeometry(gears[first], gears[second], centre_distance=distance)
        )
        return (unthinned - NORMAL_BACKLASH) / cosine - fixed

    if stage == "parallel":
        both = rest("wheel", "pinion", 0.0) / 2.0
        return {"wheel": both, "pinion": both}
    return {
        "planet": half,
        "sun": rest("sun", "planet", half),
        "ring": rest("planet", "ring", half),
    }


def mesh_geometry(stage: str, first: str, second: str) -> MeshGeometry:
    """The pair (first, second) of ``stage`` at its operating centre distance, thinned
    to the SIMPACK backlash."""
    gears, allowances = GEOMETRY[stage], thickness_allowances(stage)
    return MeshGeometry(
        gears[first],
        gears[second],
        centre_distance=operating_centre_distance(stage),
        thickness_allowances=(allowances[first], allowances[second]),
    )


# ----------------------------------------------------------------------------------
# Masses and inertias: not in the tables.  ASSUMED from the geometry: steel annuli.
# ----------------------------------------------------------------------------------

# ASSUMED: structural steel (the reproduction's material file has 7830 kg/m^3, 0.26 %
# less); the tables give no masses.
STEEL_DENSITY = 7850.0  # kg/m^3
# ASSUMED bores [m] from the reproduction's bore ratios [Repro]; the planets' equal the
# bores of their bearings, PL and IMS-PL [P-VI,IX] (a planet turning on its pin).  The
# bores also set the potential-energy law's fillet-foundation term (h_fi = r_f / r_int).
BORE_DIAMETER = {
    ("stage1", "sun"): 0.400,
    ("stage1", "planet"): 0.400,
    ("stage2", "sun"): 0.200,
    ("stage2", "planet"): 0.380,
    ("parallel", "pinion"): 0.200,
    ("parallel", "wheel"): 0.500,
}
# ASSUMED: a ring is an annulus from its reference diameter to 1.2 times it [Repro].
RING_OUTER_DIAMETER_FACTOR = 1.2
# ASSUMED: a carrier is an annulus from 1.4 a_w to 2.6 a_w in diameter, 1.2 b wide (the
# reproduction's SIMPACK carrier envelope [Repro]).  A solid annulus has no planet
# windows: an upper bound on a real carrier's mass.
CARRIER_RADII = (0.7, 1.3)  # inner and outer radius, times a_w
CARRIER_WIDTH_FACTOR = 1.2  # times b


def annulus(inner_radius: float, outer_radius: float, width: float) -> dict[str, float]:
    """Mass, polar and tilt inertia of a steel annulus (ASSUMED body shape).

    I_p = m (r_o^2 + r_i^2) / 2 and I_t = m (3 (r_o^2 + r_i^2) + b^2) / 12 about a
    diameter through the centre.
    """
    mass = STEEL_DENSITY * math.pi * (outer_radius**2 - inner_radius**2) * width
    squares = outer_radius**2 + inner_radius**2
    return {
        "mass": mass,
        "polar_inertia": mass * squares / 2.0,
        "tilt_inertia": mass * (3.0 * squares + width**2) / 12.0,
    }


def gear_body(stage: str, member: str) -> dict[str, float]:
    """Annulus of a gear: bore to reference diameter; a ring, reference to 1.2 times."""
    geometry = GEOMETRY[stage][member]
    reference = (
        geometry.teeth * geometry.normal_module / math.cos(math.radians(geometry.helix_angle_deg))
    )
    if geometry.internal:
        inner, outer = reference / 2.0, RING_OUTER_DIAMETER_FACTOR * reference / 2.0
    else:
        inner, outer = BORE_DIAMETER[(stage, member)] / 2.0, reference / 2.0
    return annulus(inner, outer, geometry.face_width)


def carrier_body(stage: str) -> dict[str, float]:
    """Annulus of a carrier (ASSUMED envelope, see CARRIER_RADII)."""
    radius = CENTRE_DISTANCE[stage]
    width = GEOMETRY[stage]["sun"].face_width * CARRIER_WIDTH_FACTOR
    return annulus(CARRIER_RADII[0] * radius, CARRIER_RADII[1] * radius, width)


# ----------------------------------------------------------------------------------
# Bearings [P-VI,IX]: (K_x axial [N/m], K_y, K_z radial [N/m], K_beta, K_gamma tilt
# [N m/rad]), x along the shaft.  The SIMPACK model's unrounded values agree within
# rounding except where noted.
# ----------------------------------------------------------------------------------

MAIN_BEARING_A = (0.0, 1.5e10, 1.5e10, 5e6, 5e6)  # INP-A, CARB [P-VI,IX]
MAIN_BEARING_B = (4.06e8, 1.54e10, 1.54e10, 0.0, 0.0)  # INP-B, SRB [P-VI,IX]
STAGE1_PLANET_BEARING = (9.1e4, 9.4e9, 3.2e9, 1.4e6, 4.5e6)  # PL-A = PL-B, CRB [P-VI,IX]
STAGE1_PLANET_BEARING_WIDTH = 0.272  # m, PL-A/B width [P-VI,IX]
# PLC-A (rotor side, SRB) and PLC-B (CRB) [P-VI,IX]; the SIMPACK model has K_z = K_y =
# 1.77e9 and tilt 1.39e6: the two sources disagree, the paper's table is taken.
STAGE1_CARRIER_BEARINGS = ((6.6e4, 1.7e9, 1.1e9, 5.6e5, 1.3e5), (6.6e7, 1.7e9, 1.1e9, 5.6e5, 1.3e5))
# IMS-PL-A = IMS-PL-B (CRB) and IMS-PLC-A (CARB), IMS-PLC-B (CRB) [P-VI,IX].  The same
# (K_y, K_z, tilt) = (6e7, 1.2e9, 7.5e4) repeats for five stage-2 bearings and 6e7 N/m
# is 150 times softer than stage 1's planet bearings: probably a placeholder in
# the paper's table, kept as printed (sweep it: stage2.planet_bearing.radial).
STAGE2_PLANET_BEARING = (9.1e4, 6e7, 1.2e9, 7.5e4, 7.5e4)
STAGE2_PLANET_BEARING_WIDTH = 0.140  # m, IMS-PL-A/B width [P-VI,IX]
STAGE2_CARRIER_BEARINGS = ((9.1e4, 6e7, 1.2e9, 7.5e4, 7.5e4), (9.1e7, 6e7, 1.2e9, 7.5e4, 7.5e4))
# Wheel shaft IMS-A (CRB), IMS-B and IMS-C (TRB); pinion shaft HS-A (CRB), HS-B and
# HS-C (TRB) [P-VI,IX]; their K_z also in IdahoLab's Type 5 wind turbine drivetrain
# model (2014), which uses them for another 5 MW gearbox.
WHEEL_SHAFT_BEARINGS = (
    (0.0, 6e7, 1.2e9, 7.5e4, 7.5e4),
    (7.4e7, 5e8, 5e8, 1.6e6, 1.8e6),
    (7.8e7, 7.4e8, 3.3e8, 1.1e6, 2.5e6),
)
PINION_SHAFT_BEARINGS = (
    (1.3e8, 8.2e8, 8.2e8, 1.7e5, 1e6),
    (6.7e7, 8e8, 1.3e8, 1.7e5, 1e6),
    (8e7, 1e9, 7.3e7, 1.7e5, 1e6),
)


# ASSUMED: pygear's bearings take one radial and one tilt stiffness; the tables give
# two directions (the planet bearings are anisotropic, 9.4e9 and 3.2e9 N/m): their mean.
def radial_mean(row: tuple[float, ...]) -> float:
    """One radial stiffness of a table row: the mean of K_y and K_z [N/m]."""
    return (row[1] + row[2]) / 2.0


def tilt_mean(row: tuple[float, ...]) -> float:
    """One tilt stiffness of a table row: the mean of K_beta and K_gamma [N m/rad]."""
    return (row[3] + row[4]) / 2.0


def bearing_pair(rows: tuple[tuple[float, ...], ...], spacing: float) -> dict[str, float]:
    """Two bearings of one member as one six-spring support.

    ASSUMED combination (the tables give each bearing, pygear one support), in
    parallel: radial and axial stiffnesses add; the tilt stiffness is the pair's radial
    springs at +-spacing/2 from the member centre, 2 k_r (spacing/2)^2 with k_r their
    mean, plus the bearings' own tilt stiffnesses.
    """
    radial = sum(radial_mean(row) for row in rows)
    return {
        "radial": radial,
        "axial": sum(row[0] for row in rows),
        "tilt": radial * (spacing / 2.0) ** 2 + sum(tilt_mean(row) for row in rows),
    }


# ASSUMED: the two planet bearings sit side by side, their centres +-width/2 from the
# planet centre (the tables give widths, not positions).  Each planet: two identical
# bearings.  Stage 1's two 272 mm bearings are wider together than its 491 mm face, so
# they may sit in the carrier's cheeks instead, with about 8 times this tilt stiffness;
# only spatial scenes see it.  Their small axial stiffness (cylindrical rollers) gives
# a planet-axial mode near 2 Hz in a spatial scene; the spur stages run planar unless a
# scene asks otherwise.
STAGE1_PLANET_SUPPORT = bearing_pair((STAGE1_PLANET_BEARING,) * 2, STAGE1_PLANET_BEARING_WIDTH)
STAGE2_PLANET_SUPPORT = bearing_pair((STAGE2_PLANET_BEARING,) * 2, STAGE2_PLANET_BEARING_WIDTH)
# ASSUMED: the carrier bearings sit at the carrier's faces, 1.2 b apart (the carrier
# envelope above).
STAGE1_CARRIER_SUPPORT = bearing_pair(
    STAGE1_CARRIER_BEARINGS, CARRIER_WIDTH_FACTOR * STAGE1_FACE_WIDTH
)
STAGE2_CARRIER_SUPPORT = bearing_pair(
    STAGE2_CARRIER_BEARINGS, CARRIER_WIDTH_FACTOR * STAGE2_FACE_WIDTH
)
# ASSUMED: the two main bearings at the ends of the 2 m main shaft [Repro] (their
# positions are not tabulated).
MAIN_SHAFT_LENGTH = 2.0  # m [Repro]
MAIN_BEARINGS = bearing_pair((MAIN_BEARING_A, MAIN_BEARING_B), MAIN_SHAFT_LENGTH)
# ASSUMED: the three supports of each parallel-stage shaft add radially and axially; their
# spacing is not given, so the shafts' tilt stiffness is ASSUMED 1e8 N m/rad, far above
# what the mesh moments call for (sweep it: parallel.input_bearing.tilt).
PARALLEL_SHAFT_TILT = 1e8  # N m/rad
WHEEL_SUPPORT = Bearing(
    radial=sum(radial_mean(row) for row in WHEEL_SHAFT_BEARINGS),
    axial=sum(row[0] for row in WHEEL_SHAFT_BEARINGS),
    tilt=PARALLEL_SHAFT_TILT,
    torsional=0.0,  # turns freely
)
PINION_SUPPORT = Bearing(
    radial=sum(radial_mean(row) for row in PINION_SHAFT_BEARINGS),
    axial=sum(row[0] for row in PINION_SHAFT_BEARINGS),
    tilt=PARALLEL_SHAFT_TILT,
    torsional=0.0,
)
# ASSUMED: the tables give the suns no bearing: they float, centred by the three planets
# (radial 0); an axial and a tilt spring only keep spatial scenes non-singular.
SUN_SUPPORT = Bearing(radial=0.0, axial=1e8, tilt=1e6, torsional=0.0)
# ASSUMED: the rings are bolted into the housing, whose stiffness is not given: 1e10 N/m
# (at least the mesh stiffness, so the ring does not set the low modes) and torsionally
# 1e10 N/m at the ring's base radius (sweep it: stage1.ring_bearing.torsional).
HOUSING_STIFFNESS = 1e10  # N/m


def ring_support(stage: str) -> Bearing:
    """Housing support of a ring (ASSUMED stiffness, see HOUSING_STIFFNESS)."""
    ring_base_radius = base_radius(GEOMETRY[stage]["ring"])
    return Bearing(
        radial=HOUSING_STIFFNESS,
        axial=HOUSING_STIFFNESS,
        tilt=HOUSING_STIFFNESS,
        torsional=HOUSING_STIFFNESS * ring_base_radius**2,
    )


# ----------------------------------------------------------------------------------
# Shafts [Repro] and the turbine [Jonkman]
# ----------------------------------------------------------------------------------

YOUNG_MODULUS = 206e9  # Pa, steel [Repro] (material file and SIMPACK writer)
POISSON_RATIO = 0.3  # [Repro]
SHEAR_MODULUS = YOUNG_MODULUS / (2.0 * (1.0 + POISSON_RATIO))


def shaft_stiffness(diameter: float, length: float) -> float:
    """Torsional stiffness G J / L of a solid shaft [N m/rad], J = pi d^4 / 32."""
    return SHEAR_MODULUS * math.pi * diameter**4 / 32.0 / length


# Shaft diameters and lengths [m] [Repro] ("based mainly on the SIMPACK simulation").
# The main shaft's 9.34e8 N m/rad replaces Jonkman's whole-drivetrain spring (8.676e8
# N m/rad, ElastoDyn DTTorSpr, 8 % softer): that spring stands for the gearbox too,
# which is explicit here, so the two are not put in series.
MAIN_SHAFT_STIFFNESS = shaft_stiffness(0.700, MAIN_SHAFT_LENGTH)  # rotor -> carrier 1
INTERMEDIATE_SHAFT_STIFFNESS = shaft_stiffness(0.533, 0.500)  # sun 1 -> carrier 2
HS_INTERMEDIATE_SHAFT_STIFFNESS = shaft_stiffness(0.333, 0.666)  # sun 2 -> wheel
HIGH_SPEED_SHAFT_STIFFNESS = shaft_stiffness(0.333, 1.000)  # pinion -> generator
# ASSUMED: Jonkman's drivetrain damper (ElastoDyn DTTorDmp, 5 % of critical in the
# free-free drivetrain mode with his spring) acts across the main shaft.
MAIN_SHAFT_DAMPING = 6.215e6  # N m s/rad [Jonkman]

ROTOR_MASS = 110_000.0  # kg, Jonkman's Table 1-1 (as cited by [Repro])
# Rotor inertia about the shaft [kg m^2], the value used with Jonkman's model in public
# code (not found printed in his report): with GenIner 534.116 kg m^2, gearbox ratio 97
# and his spring it gives his drivetrain damper 5.00 % of critical, as he chose it.
# r-test's summary of today's blade file prints 38 677 041 (0.21 % less).
ROTOR_POLAR_INERTIA = 38_759_228.0
# ASSUMED: the rotor as a flat disc, I_tilt = I_polar / 2 (perpendicular-axis theorem);
# only a spatial scene uses it.
ROTOR_TILT_INERTIA = ROTOR_POLAR_INERTIA / 2.0
GENERATOR_POLAR_INERTIA = 534.116  # kg m^2 about the high-speed shaft [Jonkman] (GenIner)
# ASSUMED: 1900 kg, the reproduction's generator mass, which it does not source itself.
GENERATOR_MASS = 1900.0
GENERATOR_TILT_INERTIA = GENERATOR_POLAR_INERTIA / 2.0  # ASSUMED: flat disc, as the rotor
# ASSUMED: the generator's bearings are not in the tables; stiff enough to keep its
# lateral modes (about 115 Hz) far from the drivetrain's torsion.
GENERATOR_SUPPORT = Bearing(radial=1e9, axial=1e9, tilt=1e8, torsional=0.0)

RATED_ROTOR_SPEED_RPM = 12.1  # [Jonkman] (ElastoDyn RotSpeed)
RATED_POWER = 5e6  # W [Jonkman]
# 5 MW at 12.1 rpm: 3.946 MN m.  (The rated generator torque 43 093.55 N m [Jonkman]
# (DISCON) times 97 is 4.180 MN m: the generator's 94.4 % efficiency.)
RATED_ROTOR_TORQUE = RATED_POWER / (RATED_ROTOR_SPEED_RPM * math.pi / 30.0)


# ----------------------------------------------------------------------------------
# Stages
# ----------------------------------------------------------------------------------


def ring_rim_radius(stage: str) -> float:
    """Outer radius of a ring's rim [m]: the ASSUMED annulus of the ring's body
    (RING_OUTER_DIAMETER_FACTOR times its reference radius), where the housing holds it."""
    geometry = GEOMETRY[stage]["ring"]
    return RING_OUTER_DIAMETER_FACTOR * geometry.teeth * geometry.normal_module / 2.0


def gear(stage: str, member: str) -> Gear:
    """A gear from its geometry (base radius and teeth derived), with its ASSUMED annulus
    body; its bore (a ring: its rim) also sets the fillet-foundation term of the
    potential-energy law."""
    geometry = GEOMETRY[stage][member]
    if geometry.internal:
        # ASSUMED rim (RING_OUTER_DIAMETER_FACTOR): with it the ring's teeth sit on a
        # compliant rim, which brings stage 1's ring mesh from 1.48 to 1.02 times ISO
        # 6336-1's c_gamma_alpha b (docs/potential_energy.md)
        return Gear(
            **gear_body(stage, member), geometry=geometry, rim_radius=ring_rim_radius(stage)
        )
    return Gear(
        **gear_body(stage, member),
        geometry=geometry,
        bore_radius=BORE_DIAMETER[(stage, member)] / 2.0,
    )


def mesh(stage: str, first: str, second: str, law: str = "potential_energy") -> Mesh:
    """A mesh whose stiffness ``law`` derives from the geometry of its two gears.

    The potential-energy law (the default) takes its pair curve from the tooth
    geometry, the material [Repro], the gears' bores and the rings' rims (ASSUMED,
    :func:`ring_rim_radius`).  Pressure angle, contact ratio and backlash come from the geometry.
    ``first``, ``second``: the mesh geometry's order, (sun, planet) or (planet, ring).
    """
    allowances = thickness_allowances(stage)
    return Mesh(
        law=law,
        young_modulus=YOUNG_MODULUS,
        poisson_ratio=POISSON_RATIO,
        thickness_allowances=(allowances[first], allowances[second]),
    )


def iso6336_typed_mesh(stage: str, first: str, second: str, law: str) -> Mesh:
    """A mesh with ISO 6336-1's c_gamma_alpha b typed, evaluated with the gear of the
    larger profile shift as ISO's gear 1.

    ISO's q' regression holds for x1 >= x2.  pygear's ``iso6336`` law takes the smaller
    gear as gear 1 (ISO's pinion), and the NREL design gives the larger gear the larger
    shift in stage 2 (sun 0.389, planet 0.504) and stage 3 (pinion 0.480, wheel 0.669):
    the law refuses those pairs.  With the larger shift first the regression is inside
    its range, but gear 1 is no longer the smaller gear, so the value is an estimate.
    At rated torque the line load is about 550 N/mm (stage 2) to 1700 N/mm (stage 1),
    above ISO's 100 N/mm, so no load correction applies.  ``first``, ``second``: the
    mesh geometry's order, (sun, planet) or (input, output gear).
    """
    allowances = thickness_allowances(stage)
    gears = GEOMETRY[stage]
    ordered = sorted((first, second), key=lambda member: -gears[member].profile_shift)
    path = f"{stage}.{first}-{second}"
    iso = iso6336_mesh_stiffness(mesh_geometry(stage, *ordered), path=path)
    return Mesh(
        law=law,
        stiffness=iso.mesh_stiffness_alpha_total,
        # a constant pair stiffness on a spur mesh, as pygear's own iso6336 law
        stiffness_curve=None if law == "helical" else (1.0, 1.0),
        thickness_allowances=(allowances[first], allowances[second]),
    )


def planetary_stage(name: str, axial_position: float) -> PlanetaryStage:
    """A planetary stage: ring held, carrier in, sun out, three planets [P-V]; carrier
    radius = the printed a_w, base helix angle 0 (spur) derived from the geometry."""
    carrier = Carrier(**carrier_body(name), radius=CENTRE_DISTANCE[name])
    planet_support = STAGE1_PLANET_SUPPORT if name == "stage1" else STAGE2_PLANET_SUPPORT
    carrier_support = STAGE1_CARRIER_SUPPORT if name == "stage1" else STAGE2_CARRIER_SUPPORT
    return PlanetaryStage(
        name=name,
        carrier=carrier,
        ring=gear(name, "ring"),
        sun=gear(name, "sun"),
        planet=gear(name, "planet"),
        planets=3,  # [P-V]
        carrier_bearing=Bearing(**carrier_support, torsional=0.0),  # turns freely
        ring_bearing=ring_support(name),
        sun_bearing=SUN_SUPPORT,
        planet_bearing=PlanetBearing(**planet_support),
        sun_mesh=mesh(name, "sun", "planet"),
        ring_mesh=mesh(name, "planet", "ring"),
        axial_position=axial_position,
    )


# ASSUMED axial positions [m] along the drivetrain (not tabulated; only spatial scenes
# use them): rotor hub ahead of the main shaft, stages and generator behind.
rotor = ShaftInertia(
    name="rotor",
    body=Body(mass=ROTOR_MASS, polar_inertia=ROTOR_POLAR_INERTIA, tilt_inertia=ROTOR_TILT_INERTIA),
    bearing=Bearing(**MAIN_BEARINGS, torsional=0.0),
    axial_position=-3.0,
)
stage1 = planetary_stage("stage1", axial_position=0.0)
stage2 = planetary_stage("stage2", axial_position=1.0)
# The wheel sits on the intermediate shaft, driven by stage 2's sun; the pinion drives
# the generator, so pygear's parallel input gear is the wheel.  Its mesh runs the
# potential-energy law like the planetary meshes, the face width sliced along the helix
# so that eps_beta emerges from the geometry.  With x = 0.669 the 95-tooth wheel's root
# circle lies above its base circle: the tooth meets its body at the root circle (half
# angle 0.0259 rad, below pi/95), not at the base circle.
parallel = ParallelStage(
    name="parallel",
    input_gear=gear("parallel", "wheel"),
    output_gear=gear("parallel", "pinion"),
    input_bearing=WHEEL_SUPPORT,
    output_bearing=PINION_SUPPORT,
    mesh=mesh("parallel", "wheel", "pinion"),
    centre_angle_deg=0.0,  # ASSUMED: pinion beside the wheel along x
    axial_position=2.0,
)
generator = ShaftInertia(
    name="generator",
    body=Body(
        mass=GENERATOR_MASS,
        polar_inertia=GENERATOR_POLAR_INERTIA,
        tilt_inertia=GENERATOR_TILT_INERTIA,
    ),
    bearing=GENERATOR_SUPPORT,
    axial_position=4.0,
)

gearbox = Gearbox(
    stages=(rotor, stage1, stage2, parallel, generator),
    couplings=(
        TorsionalSpring(
            "main_shaft",
            "rotor.body.theta_z",
            "stage1.carrier.theta_z",
            stiffness=MAIN_SHAFT_STIFFNESS,
            damping=MAIN_SHAFT_DAMPING,
        ),
        TorsionalSpring(
            "intermediate_shaft",
            "stage1.sun.theta_z",
            "stage2.carrier.theta_z",
            stiffness=INTERMEDIATE_SHAFT_STIFFNESS,
        ),
        TorsionalSpring(
            "hs_intermediate_shaft",
            "stage2.sun.theta_z",
            "parallel.input_gear.theta_z",
            stiffness=HS_INTERMEDIATE_SHAFT_STIFFNESS,
        ),
        TorsionalSpring(
            "high_speed_shaft",
            "parallel.output_gear.theta_z",
            "generator.body.theta_z",
            stiffness=HIGH_SPEED_SHAFT_STIFFNESS,
        ),
    ),
    input_dof="rotor.body.theta_z",
    output_dof="generator.body.theta_z",
)

# Run-up: from rest, the rated rotor torque on the rotor; the generator carries the load
# law T_L = (T_D/i)(w_gen/(i w_0))^n from t_s on (the first instant the rotor reaches
# w_0), i = 96.354 from the kinematics.  At rated speed the drivetrain's 4.4e7 kg m^2
# (rotor-referred) would need 14 s to run up; a run of 2 s must use a low reference
# speed instead.
# ASSUMED: a constant drive at the rated torque (5 MW at 12.1 rpm [Jonkman]), the
# generator law's T_D the same, so that its equilibrium load is the rated one.
RUNUP_DRIVE_TORQUE = RATED_ROTOR_TORQUE  # N m
# ASSUMED: w_0 = 0.6 rpm, 5 % of rated, so that t_s (about 0.7 s) and the approach to
# the law's equilibrium fit into 2 s.  The 2 Hz drivetrain mode, 5 % damped, the load's
# onset at t_s excites still rings at 2 s (about 2 % of the carrier speed).
RUNUP_SPEED_RPM = 0.6
LOAD_EXPONENT = 2.0  # n of the load law, ASSUMED as in the repository's other cases
RUNUP = Transient(
    duration=2.0,  # s
    # s: 10 steps per period of the highest mode (1.93 kHz, stage 2's sun), 40 per
    # period at 500 Hz
    time_step=5e-5,
    sample_rate=2e4,  # Hz, every step
    integrator="newmark",  # average acceleration
    equivalent_load="predictor",
    input="rotor.body.theta_z",
    output="generator.body.theta_z",
    drive=TorqueLaw.constant(RUNUP_DRIVE_TORQUE),
    load=TorqueLaw.generator(rated_drive_torque=RUNUP_DRIVE_TORQUE, exponent=LOAD_EXPONENT),
    speed_reference_rpm=RUNUP_SPEED_RPM,
    probes=(
        Probe("speed", "rotor.body"),
        Probe("speed", "stage1.carrier"),
        Probe("speed", "stage1.sun"),
        Probe("speed", "stage2.carrier"),
        Probe("speed", "stage2.sun"),
        Probe("speed", "parallel.input_gear"),
        Probe("speed", "parallel.output_gear"),
        Probe("speed", "generator.body"),
        Probe("mesh_force", "stage1.sun-planet1"),
        Probe("mesh_force", "stage1.ring-planet1"),
        Probe("mesh_force", "stage2.sun-planet1"),
        Probe("mesh_force", "stage2.ring-planet1"),
        Probe("mesh_force", "parallel.input-output"),
        Probe("drive_torque"),
        Probe("load_torque"),
    ),
    mean_window=0.5,  # s: equilibrium speeds are means over the last 0.5 s
)

# ISO 6336-1 in place of the potential-energy law (scene "modal_iso6336"): pygear's
# iso6336 law where its pinion-first order lies in the regression's range (stage 1's
# sun mesh: the 17-tooth planet has the larger shift; the ring meshes, which have no
# order rule), ISO's value typed with the larger shift first for stage 2's sun mesh and
# the helical pair.
ISO6336_MESHES = {
    "stage1.sun_mesh": mesh("stage1", "sun", "planet", law="iso6336"),
    "stage1.ring_mesh": mesh("stage1", "planet", "ring", law="iso6336"),
    "stage2.sun_mesh": iso6336_typed_mesh("stage2", "sun", "planet", law="tabulated"),
    "stage2.ring_mesh": mesh("stage2", "planet", "ring", law="iso6336"),
    # the helical pair: the contact-line law over eps_alpha + eps_beta with ISO's mean
    # stiffness, the wheel (larger shift) first
    "parallel.mesh": iso6336_typed_mesh("parallel", "wheel", "pinion", law="helical"),
}

# ASSUMED damping: no mass-proportional part, which would brake the rotor's rigid
# rotation (alpha J_rotor w) like a torque to ground; beta = 5e-6 s gives the mesh and
# bearing modes 0.8 % (500 Hz) to 3 % (2 kHz) of critical; the drivetrain mode's
# damping comes from the main shaft's damper.
DAMPING = RayleighDamping(mass_coefficient=0.0, stiffness_coefficient=5e-6)

case = Case(
    name="nrel5mw_gearbox",
    description="NREL 5 MW reference gearbox (Nejad et al. 2016) with the NREL 5 MW rotor",
    gearbox=gearbox,
    formulation="consistent",  # the planet's exact kinetic energy
    damping=DAMPING,
    scenes=(
        Scene("modal", analyses=("modal",)),
        Scene("modal_iso6336", analyses=("modal",), parameters=ISO6336_MESHES),
        Scene(
            "runup",
            analyses=("transient",),
            effects=("time_varying_mesh_stiffness",),
            transient=RUNUP,
        ),
    ),
)

# ----------------------------------------------------------------------------------
# Rating data (pygear rate: ISO 6336 and ISO 281).  Sources beyond the tags above:
# [Repro-KS] the reproduction's KISSsoft reports of the three stages
# (``@NREL_5MW/stage_01.rtf``, ``stage_02.rtf``, ``stage_03.rtf``, ISO 6336:2006 method
# B): materials, roughness, oil, accuracy grade, K_A, K_gamma, K_Hbeta, required
# safeties and life, which follow IEC 61400-4.
# ----------------------------------------------------------------------------------

CARBURIZED = iso6336_5_material(
    "18CrNiMo7-6",
    "case_carburized",
    "MQ",  # ISO 6336-5 MQ, sigma_Hlim 1500 MPa, sigma_Flim 425 MPa ([Repro-KS]: 430)
    flank_roughness_rz=4.8e-6,  # [Repro-KS]
    root_roughness_rz=20e-6,  # [Repro-KS]
    young_modulus=YOUNG_MODULUS,
    poisson_ratio=POISSON_RATIO,
)
# Through-hardened ring [Repro-KS] (34CrNiMo6, HBW 240): its material data base gives
# sigma_Hlim 700 and sigma_Flim 290 MPa (ISO 6336-5's MQ line at 300 HV would give
# 637 and 235 MPa).
RING_STEEL = Material(
    name="34CrNiMo6",
    kind="through_hardened",
    grade="MQ",
    sigma_hlim=700e6,
    sigma_flim=290e6,
    hardness_hb=240.0,
    flank_roughness_rz=8.0e-6,  # [Repro-KS]
    root_roughness_rz=20e-6,  # [Repro-KS]
    young_modulus=YOUNG_MODULUS,
    poisson_ratio=POISSON_RATIO,
)
RATING_MATERIALS = {
    **{f"{stage}.{member}": CARBURIZED for stage in ("stage1", "stage2")
       for member in ("sun", "planet")},
    "stage1.ring": RING_STEEL,
    "stage2.ring": RING_STEEL,  # [Repro-KS] (stage 2: sigma_FE 580 MPa)
    # the parallel stage carburized like the planetary suns and planets [Repro-KS]
    "parallel.input_gear": CARBURIZED,
    "parallel.output_gear": CARBURIZED,
}
# Face load factors K_Hbeta [Repro-KS]: IEC 61400-4's minimum 1.15 everywhere but stage
# 2's sun mesh, whose slender sun (b/d = 1.46) the report rates at 2.06
FACE_LOAD_FACTOR = {mesh: 1.15 for mesh in (
    "stage1.sun_mesh", "stage1.ring_mesh", "stage2.ring_mesh", "parallel.mesh",
)}
FACE_LOAD_FACTOR["stage2.sun_mesh"] = 2.06


def planet_bearing(name: str, stage: str, c: float, c0: float, pitch_diameter: float):
    """A planet bearing: one of the two CRBs on each planet pin [P-VI,IX], half the pin's
    load each.  C and C0 are not in the tables: ASSUMED estimates by ISO 281's rating
    formulas for a full-complement double-row CRB of the tabulated envelope
    (C = b_m f_c (i L_we)^(7/9) Z^(3/4) D_we^(29/27), b_m = 1.1; roller size and count
    ASSUMED from the section height); replace them with the catalogue's."""
    return RollingBearingData(
        name=name,
        kind="roller",
        C=c,
        C0=c0,
        location=f"{stage}.planet",
        share=0.5,
        pitch_diameter=pitch_diameter,
        contamination=0.5,  # ASSUMED: ISO 281 Table 13, normal cleanliness, filtered oil
        viscosity=68.0,  # ASSUMED: 220 cSt oil [Repro-KS] at about 70 degC
    )


# High-speed shaft bearings HS-A (CRB, 360 x 200 x 98 mm) and HS-B, HS-C (TRB, 460 x 300 x
# 100 mm; the table's 200 mm bore read as 300 [Repro]) [P-VI,IX].  Their loads come from
# the helical pair's forces on the pinion at the rated torque: F_t = 2 T_pinion / d,
# F_r = F_t tan(alpha_wt), F_a = F_t tan(beta).  ASSUMED: the pinion midway between
# HS-A and the HS-B/HS-C pair (HS-A half the radial resultant, HS-B and HS-C a quarter
# each) and HS-B carrying the whole axial force; the tables give no bearing positions.
# C, C0: ASSUMED estimates by ISO 281's rating formulas for the tabulated envelopes
# (roller size and count from the section height), as for the planet bearings; a TRB's
# e = 1.5 tan(15 deg) = 0.40, X = 0.4, Y = 0.4 cot(15 deg) = 1.49 (ISO 281 cl. 6, ASSUMED
# 15 deg contact angle).
PINION_TORQUE = RATED_ROTOR_TORQUE / (
    (1 + STAGE1_TEETH["ring"] / STAGE1_TEETH["sun"])
    * (1 + STAGE2_TEETH["ring"] / STAGE2_TEETH["sun"])
    * (STAGE3_TEETH["wheel"] / STAGE3_TEETH["pinion"])
)
PINION_SPEED_FACTOR = RATED_ROTOR_TORQUE / PINION_TORQUE  # pinion speed / rotor speed
_PAIR = mesh_geometry("parallel", "wheel", "pinion")
HS_TANGENTIAL = 2.0 * PINION_TORQUE / (
    STAGE3_TEETH["pinion"] * STAGE3_MODULE / math.cos(math.radians(STAGE3_HELIX_ANGLE_DEG))
)
HS_RADIAL = HS_TANGENTIAL * math.tan(working_pressure_angle(_PAIR))
HS_AXIAL = HS_TANGENTIAL * math.tan(math.radians(STAGE3_HELIX_ANGLE_DEG))
HS_RESULTANT = math.hypot(HS_TANGENTIAL, HS_RADIAL)


def shaft_bearing(name: str, c: float, c0: float, share: float, axial: float,
                  pitch_diameter: float, **factors: float):
    """A high-speed shaft bearing with its ASSUMED share of the pinion's forces."""
    return RollingBearingData(
        name=name,
        kind="roller",
        C=c,
        C0=c0,
        location="parallel.output_gear",
        radial_load=share * HS_RESULTANT,
        axial_load=axial,
        speed_factor=PINION_SPEED_FACTOR,
        pitch_diameter=pitch_diameter,
        contamination=0.5,  # ASSUMED, as the planet bearings
        viscosity=68.0,  # ASSUMED, as the planet bearings
        **factors,
    )


TAPERED = {"e": 0.40, "X": 0.4, "Y": 1.49}  # ASSUMED 15 deg contact angle, see above

rating = Rating(
    materials=RATING_MATERIALS,
    rated_torque=RATED_ROTOR_TORQUE,  # 5 MW at 12.1 rpm [Jonkman]
    rated_speed_rpm=RATED_ROTOR_SPEED_RPM,
    application_factor=1.25,  # K_A [Repro-KS], IEC 61400-4
    required_sh=1.25,  # S_Hmin [Repro-KS], IEC 61400-4
    required_sf=1.56,  # S_Fmin [Repro-KS], IEC 61400-4
    service_life_h=20 * 8760.0,  # 20 years [Repro-KS] (175 200 h)
    # K_gamma: the 3-planet default 1.10 (as [Repro-KS]); K_v by method B
    face_load_factor=FACE_LOAD_FACTOR,
    accuracy_grade=6,  # ISO 1328 grade 6 [Repro-KS]
    oil_viscosity_40=220.0,  # [Repro-KS]
    bearings=(
        # PL-A, PL-B: 600 x 400 x 272 mm CRB [P-VI,IX]; d_m 0.5 m; ASSUMED C, C0
        planet_bearing("PL-A", "stage1", c=5.7e6, c0=14.1e6, pitch_diameter=0.500),
        planet_bearing("PL-B", "stage1", c=5.7e6, c0=14.1e6, pitch_diameter=0.500),
        # IMS-PL-A, IMS-PL-B: 520 x 380 x 140 mm CRB [P-VI,IX]; ASSUMED C, C0
        planet_bearing("IMS-PL-A", "stage2", c=2.6e6, c0=6.3e6, pitch_diameter=0.450),
        planet_bearing("IMS-PL-B", "stage2", c=2.6e6, c0=6.3e6, pitch_diameter=0.450),
        shaft_bearing("HS-A", c=1.37e6, c0=2.16e6, share=0.5, axial=0.0,
                      pitch_diameter=0.280),
        shaft_bearing("HS-B", c=1.46e6, c0=2.8e6, share=0.25, axial=HS_AXIAL,
                      pitch_diameter=0.380, **TAPERED),
        shaft_bearing("HS-C", c=1.46e6, c0=2.8e6, share=0.25, axial=0.0,
                      pitch_diameter=0.380, **TAPERED),
    ),
)

# Planet bearings as rolling-element geometry (#33; pygear.model.rolling_bearing), for
# their load zone, varying compliance, characteristic frequencies and defects.  Types and
# envelopes [P-VI,IX]: PL-A/B 600 x 400 x 272 mm and IMS-PL-A/B 520 x 380 x 140 mm
# double-row CRBs, two per planet pin; the pitch diameter is the envelope's mean.
# ASSUMED (not in the tables): roller diameter ~0.55 of the section height, roller count
# from a caged pitch of ~1.15 roller diameters, two rows of ~0.4 of the width each (with
# these ISO 281's C formula gives 6.0e6 N and 2.7e6 N, near the ratings assumed above),
# and a diametral clearance in ISO 5753's normal group for the bore (0.12 and 0.10 mm).
# Outer ring = the planet's bore, inner ring = the carrier's pin.
ROLLING_BEARING_SIZES = {  # name: (stage, Z, D_pw, D_we, L_we per row, P_d) [m]
    "PL-A": ("stage1", 24, 0.500, 0.055, 0.110, 120e-6),
    "PL-B": ("stage1", 24, 0.500, 0.055, 0.110, 120e-6),
    "IMS-PL-A": ("stage2", 28, 0.450, 0.040, 0.055, 100e-6),
    "IMS-PL-B": ("stage2", 28, 0.450, 0.040, 0.055, 100e-6),
}
rolling_bearings = tuple(
    RollingBearing(
        name=name,
        type="roller",
        elements=z,
        pitch_diameter=pitch,
        element_diameter=roller,
        roller_length=length,
        rows=2,
        diametral_clearance=clearance,
        location=f"{stage}.planet",
        # N s/m, ASSUMED: 5 % of critical damping of one roller contact (linearised
        # 1.8e9 .. 3.9e9 N/m from no load to the rated one) carrying a planet (1.3 t,
        # 1.4 t): c_c = 2 zeta sqrt(k_c m) = 1.6e5 .. 2.2e5; lubricated rolling contacts
        # are modelled with a few per cent (docs/bearings.md)
        contact_damping=2.0e5,
    )
    for name, (stage, z, pitch, roller, length, clearance) in ROLLING_BEARING_SIZES.items()
)
# the planet bearings by geometry: their characteristic frequencies go into every run
# file of this case, so `pygear analyze` names them
case = dataclasses.replace(case, rolling_bearings=rolling_bearings)

# ----------------------------------------------------------------------------------
# Design load cases (pygear batch nrel5mw_gearbox --dlc): IEC 61400-1 ed.3 DLC 1.2,
# power production in normal turbulence.  Each load case runs the run-up scene's model
# driven by the rotor torque of a Kaimal wind through the NREL 5 MW rotor's Cp curve
# (pygear.analysis.time.wind), the generator law holding the mean speed, and reduces
# its channels on the fly; the batch sums them into load_spectrum.nc per year.
# ----------------------------------------------------------------------------------

design_load_cases = DesignLoadCases(
    scene="runup",
    # m/s: cut-in 3 to cut-out 25 m/s [Jonkman] in bins of 2 m/s, IEC 61400-1's widest
    wind_speeds=tuple(float(v) for v in range(4, 25, 2)),
    seeds=(1, 2, 3, 4, 5, 6),  # six 10-minute seeds per wind speed (IEC 61400-1 ed.3 7.5)
    duration=600.0,  # s, IEC 61400-1's 10 minutes
    # ASSUMED: turbulence category B (I_ref = 0.14) and the wind class I distribution
    # (Rayleigh, mean 0.2 V_ref = 10 m/s): the reference turbine's IEC class IB [Jonkman]
    turbulence_class="B",
    weibull_shape=2.0,
    weibull_mean=10.0,
    input_rate=20.0,  # Hz, ASSUMED: OpenFAST's usual 0.05 s output step
    regulation_time_constant=5.0,  # s, ASSUMED (see pygear.analysis.time.wind)
    probes=RUNUP.probes
    + (
        Probe("bearing_force", "stage1.planet1_bearing.zeta"),  # radial, planet frame
        Probe("bearing_force", "stage1.planet1_bearing.eta"),  # tangential
        Probe("bearing_force", "stage2.planet1_bearing.zeta"),  # radial, planet frame
        Probe("bearing_force", "stage2.planet1_bearing.eta"),  # tangential
    ),
    reductions=Reductions(
        statistics=True,
        rainflow=("mesh_force", "bearing_force"),
        load_duration=("drive_torque", "load_torque"),
        bins=64,  # ASSUMED: 64 range x 64 mean bins, fine enough for a damage sum
    ),
)

# ----------------------------------------------------------------------------------
# A spalled planet bearing heard by an accelerometer on the ring (scene
# "planet_bearing_outer_race", docs/bearings.md): the bearings are Hertz contacts with
# clearance (effect rolling_bearing_contact) and planet 1's IMS-PL-A carries a spall in
# its outer race, the planet's bore, which turns with the planet through the load zone
# fixed on the carrier.  Stage 2's rather than stage 1's: its planets spin 3 times as
# fast relative to the carrier (2.06 Hz against 0.66 Hz), so a record of a few seconds
# holds several passes of the spall through the load zone.
# ----------------------------------------------------------------------------------
STAGE2_RING_MASS = case.gearbox.stage("stage2").ring.mass  # kg, the annulus above
RING_SENSOR = Sensor(
    name="ring_sensor",
    stage="stage2",
    angle_deg=90.0,  # ASSUMED: at the top
    direction="radial",
    window="hann",
    window_width_deg=180.0,  # ASSUMED: a planet is heard over the half of the ring facing it
    mesh_gain=1.0 / STAGE2_RING_MASS,  # (m/s^2)/N, ASSUMED: the rigid ring's mass
    bearing_gain=1.0 / STAGE2_RING_MASS,  # (m/s^2)/N, ASSUMED: the same rigid ring
    # ASSUMED: one ring-housing mode at 1.5 kHz with 5 % damping, as strong as the flat path
    structure=(StructuralMode(frequency=1500.0, damping_ratio=0.05, gain=1.0),),
)
# ASSUMED spall: 4 mm along the race (6 % of the roller pitch), 10 um deep (a fifth of
# the rollers' contact deflection at the rated load), at the bore's angle 0
PLANET_BEARING_SPALL = BearingDefect("outer", width=4e-3, depth=10e-6, planet=1)
BEARING_SCENE = Transient(
    duration=6.0,  # s: 12 turns of a planet relative to the carrier
    time_step=5e-5,  # s, the run-up's
    sample_rate=2e4,  # Hz, every step
    integrator="newmark",
    equivalent_load="predictor",  # as the run-up (benchmarks/bench_bearing.py)
    input="rotor.body.theta_z",
    output="generator.body.theta_z",
    drive=TorqueLaw.constant(RATED_ROTOR_TORQUE),
    load=TorqueLaw.generator(rated_drive_torque=RATED_ROTOR_TORQUE, exponent=LOAD_EXPONENT),
    # steady at the rated speed, loaded from the start (the static balance with the
    # bearings' Hertz law)
    speed_reference_rpm=RATED_ROTOR_SPEED_RPM,
    initial_speed_rpm=RATED_ROTOR_SPEED_RPM,
    start_loaded=True,
    probes=(
        Probe("sensor", "ring_sensor"),
        Probe("speed", "stage2.carrier"),
        Probe("speed", "stage2.planet1"),  # spin relative to the carrier
        Probe("displacement", "stage2.planet1.zeta"),
        Probe("displacement", "stage2.planet1.eta"),
        Probe("mesh_force", "stage2.ring-planet1"),
    ),
    mean_window=1.0,
)
case = dataclasses.replace(
    case,
    sensors=(RING_SENSOR,),
    scenes=(
        *case.scenes,
        Scene(
            "planet_bearing_outer_race",
            analyses=("transient",),
            effects=("time_varying_mesh_stiffness", "rolling_bearing_contact"),
            transient=BEARING_SCENE,
            parameters={"rolling_bearings.IMS-PL-A.defects": (PLANET_BEARING_SPALL,)},
        ),
    ),
)
