"""The NREL 5 MW reference turbine's drivetrain with the NREL 5 MW reference gearbox.

Turbine: Jonkman, Butterfield, Musial & Scott, "Definition of a 5-MW reference wind
turbine for offshore system development", NREL/TP-500-38060 (2009), section 5: rotor
inertia about the shaft, generator inertia 534.116 kg m^2 about the high-speed shaft,
gearbox ratio 97, and an equivalent drive-shaft torsional spring of 867 637 000 N m/rad
with a damper of 6 215 000 N m s/rad, both referred to the low-speed shaft [Jonkman].
Gearbox: Nejad, Guo, Gao & Moan, Wind Energy 19 (2016) 1089-1106: the stages of
cases/nrel5mw_gearbox, imported from that case (its tags [P-V], [P-VI,IX], [Repro]).

Jonkman's spring stands for the whole low-speed side's torsional compliance.  Here the
main shaft is a finite-element shaft of Nejad's size, so the spring is split: the hub
shaft, the main shaft and the high-speed shaft (referred to the low-speed side) keep
their own G J / L, and a coupling between hub and main shaft holds the remainder.  With
a rigid gearbox the low-speed side is then exactly Jonkman's spring; the meshes of the
explicit gearbox add their compliance in series (docs/drivetrain.md).  His damper is
spread in the same proportion, C = beta K with beta = c / k on every torsional element
of that chain, so the drivetrain mode keeps his damping ratio.
"""

import dataclasses
import importlib.util
import math
from pathlib import Path

from pygear import (
    Case,
    Coupling,
    Drivetrain,
    Gearbox,
    GearboxMount,
    Generator,
    Probe,
    Rotor,
    Scene,
    Shaft,
    ShaftBearing,
    ShaftSection,
    TorqueLaw,
    Transient,
)

# The gearbox case: stages, bearing tables, material, rotor and generator values.
_spec = importlib.util.spec_from_file_location(
    "nrel5mw_gearbox_case", Path(__file__).parent.parent / "nrel5mw_gearbox" / "case.py"
)
_gearbox_case = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_gearbox_case)
G = _gearbox_case

# ----------------------------------------------------------------------------------
# The gearbox: the three stages and the two intermediate shafts between them (as
# torsional springs, [Repro] sizes); the rotor, the main shaft, the high-speed shaft and
# the generator are the drivetrain's below.
# ----------------------------------------------------------------------------------

INTERNAL_SHAFTS = ("intermediate_shaft", "hs_intermediate_shaft")
gearbox = Gearbox(
    stages=(G.stage1, G.stage2, G.parallel),
    couplings=tuple(c for c in G.gearbox.couplings if c.name in INTERNAL_SHAFTS),
    input_dof="stage1.carrier.theta_z",
    output_dof="parallel.output_gear.theta_z",
)
# Kinematic ratio of the tooth numbers [P-V]: (1 + 56/19)(1 + 93/18)(95/24) = 96.354
# (Jonkman's 97 rounds it).
GEARBOX_RATIO = (
    (1 + G.STAGE1_TEETH["ring"] / G.STAGE1_TEETH["sun"])
    * (1 + G.STAGE2_TEETH["ring"] / G.STAGE2_TEETH["sun"])
    * (G.STAGE3_TEETH["wheel"] / G.STAGE3_TEETH["pinion"])
)

# ----------------------------------------------------------------------------------
# The turbine [Jonkman]
# ----------------------------------------------------------------------------------

DRIVE_SHAFT_STIFFNESS = 867_637_000.0  # N m/rad, low-speed side [Jonkman] (DTTorSpr)
DRIVE_SHAFT_DAMPING = 6_215_000.0  # N m s/rad, low-speed side [Jonkman] (DTTorDmp)
JONKMAN_GEARBOX_RATIO = 97.0  # [Jonkman]
ROTOR_POLAR_INERTIA = G.ROTOR_POLAR_INERTIA  # kg m^2, see the gearbox case's comment
GENERATOR_POLAR_INERTIA = 534.116  # kg m^2 about the high-speed shaft [Jonkman] (GenIner)
# Stiffness-proportional damping of the low-speed chain [s]: each element's damper is
# beta times its spring, so the chain's damping is Jonkman's damper across his spring.
TORSIONAL_DAMPING = DRIVE_SHAFT_DAMPING / DRIVE_SHAFT_STIFFNESS

# ----------------------------------------------------------------------------------
# Shafts [Repro] ("based mainly on the SIMPACK simulation") and bearings [P-VI,IX]
# ----------------------------------------------------------------------------------

STEEL = dict(
    young_modulus=G.YOUNG_MODULUS,  # [Repro]
    shear_modulus=G.SHEAR_MODULUS,  # from E and Poisson's ratio 0.3 [Repro]
    density=G.STEEL_DENSITY,  # ASSUMED: structural steel (see the gearbox case)
)
MAIN_SHAFT_DIAMETER = 0.700  # m, solid [Repro]
MAIN_SHAFT_LENGTH = G.MAIN_SHAFT_LENGTH  # 2.0 m [Repro]
HIGH_SPEED_SHAFT_DIAMETER = 0.333  # m, solid [Repro]
HIGH_SPEED_SHAFT_LENGTH = 1.000  # m [Repro]
# ASSUMED: a 0.2 m long, 1.0 m thick stub (the hub flange) carries the hub (the
# overhang is not tabulated); it gives the hub coupling a shaft end to sit on.
HUB_SHAFT_LENGTH = 0.200  # m
HUB_SHAFT_DIAMETER = 1.000  # m


def torsional_stiffness(diameter: float, length: float) -> float:
    """G J / L of a solid shaft [N m/rad], J = pi d^4 / 32."""
    return G.SHEAR_MODULUS * math.pi * diameter**4 / 32.0 / length


# ASSUMED: the hub coupling (flange and shrink disc) holds what Jonkman's spring leaves
# after the hub stub, the main shaft and the high-speed shaft (times the ratio squared):
# with a rigid gearbox the series is exactly his spring.  1.8e10 N m/rad: Nejad's main
# shaft alone (9.34e8 N m/rad) is 93 % of his low-speed compliance.
HUB_COUPLING_STIFFNESS = 1.0 / (
    1.0 / DRIVE_SHAFT_STIFFNESS
    - 1.0 / torsional_stiffness(HUB_SHAFT_DIAMETER, HUB_SHAFT_LENGTH)
    - 1.0 / torsional_stiffness(MAIN_SHAFT_DIAMETER, MAIN_SHAFT_LENGTH)
    - 1.0
    / (GEARBOX_RATIO**2 * torsional_stiffness(HIGH_SPEED_SHAFT_DIAMETER, HIGH_SPEED_SHAFT_LENGTH))
)
# ASSUMED: the coupling is laterally and angularly as stiff as the main bearings
# (a bolted flange), so it does not set the rotor's lateral modes.
HUB_COUPLING_LATERAL = 1.5e10  # N/m
HUB_COUPLING_ANGULAR = 1e10  # N m/rad

# ASSUMED: 4 Timoshenko elements per shaft (nodes every 0.5 m on the main shaft, every
# 0.25 m on the high-speed shaft); the bending modes of interest lie far below the
# fourth element mode.
hub_shaft = Shaft(
    "hub_shaft",
    (ShaftSection(HUB_SHAFT_LENGTH, HUB_SHAFT_DIAMETER),),
    **STEEL,
    elements_per_section=1,
    torsional_damping=TORSIONAL_DAMPING,
)
main_shaft = Shaft(
    "main_shaft",
    (ShaftSection(MAIN_SHAFT_LENGTH, MAIN_SHAFT_DIAMETER),),
    **STEEL,
    elements_per_section=4,
    torsional_damping=TORSIONAL_DAMPING,
)
high_speed_shaft = Shaft(
    "high_speed_shaft",
    (ShaftSection(HIGH_SPEED_SHAFT_LENGTH, HIGH_SPEED_SHAFT_DIAMETER),),
    **STEEL,
    elements_per_section=4,
    torsional_damping=TORSIONAL_DAMPING,
)


def shaft_bearing(name: str, shaft: str, position: float, row: tuple[float, ...]) -> ShaftBearing:
    """A bearing from a table row (K_axial, K_y, K_z, K_beta, K_gamma) [P-VI,IX]: the
    mean of the two radial and of the two tilt stiffnesses (ASSUMED, as the gearbox case)."""
    return ShaftBearing(
        name,
        shaft,
        position,
        radial=G.radial_mean(row),
        axial=row[0],
        tilt=G.tilt_mean(row),
    )


# ASSUMED positions: the main bearings at the two ends of the 2 m main shaft, as in the
# gearbox case (the tables give no positions); no bearing damping is tabulated.
MAIN_BEARINGS = (
    shaft_bearing("main_bearing_a", "main_shaft", 0.0, G.MAIN_BEARING_A),  # INP-A, CARB
    shaft_bearing("main_bearing_b", "main_shaft", MAIN_SHAFT_LENGTH, G.MAIN_BEARING_B),  # SRB
)
# ASSUMED: the generator's bearing as the gearbox case's generator support.
GENERATOR_BEARING = ShaftBearing(
    "generator_bearing",
    "high_speed_shaft",
    HIGH_SPEED_SHAFT_LENGTH,
    radial=G.GENERATOR_SUPPORT.radial,
    axial=G.GENERATOR_SUPPORT.axial,
    tilt=G.GENERATOR_SUPPORT.tilt,
)

drivetrain = Drivetrain(
    shafts=(hub_shaft, main_shaft, high_speed_shaft),
    gearbox=gearbox,
    mounts=(
        GearboxMount("stage1.carrier", at="main_shaft.end"),  # the carrier is driven
        GearboxMount("parallel.output_gear", at="high_speed_shaft.start"),  # the pinion
    ),
    rotor=Rotor(
        mass=G.ROTOR_MASS,  # 110 t [Jonkman] Table 1-1
        polar_inertia=ROTOR_POLAR_INERTIA,
        diametral_inertia=G.ROTOR_TILT_INERTIA,  # ASSUMED: a flat disc, I_p / 2
        at="hub_shaft.start",
    ),
    generator=Generator(
        polar_inertia=GENERATOR_POLAR_INERTIA,
        mass=G.GENERATOR_MASS,  # ASSUMED in the gearbox case (1900 kg)
        diametral_inertia=G.GENERATOR_TILT_INERTIA,  # ASSUMED: a flat disc
        at="high_speed_shaft.end",
    ),
    bearings=(*MAIN_BEARINGS, GENERATOR_BEARING),
    couplings=(
        Coupling(
            "hub_coupling",
            "hub_shaft.end",
            "main_shaft.start",
            torsional=HUB_COUPLING_STIFFNESS,
            radial=HUB_COUPLING_LATERAL,
            axial=HUB_COUPLING_LATERAL,
            angular=HUB_COUPLING_ANGULAR,
            torsional_damping=TORSIONAL_DAMPING * HUB_COUPLING_STIFFNESS,
        ),
    ),
)

# ----------------------------------------------------------------------------------
# Transients of the whole drivetrain (rotor and generator are the drivetrain's bodies)
# ----------------------------------------------------------------------------------

# What every transient records: the speeds along the train, one mesh of each stage, and
# the torques at both ends.
PROBES = (
    Probe("speed", "rotor"),
    Probe("speed", "stage1.carrier"),
    Probe("speed", "stage2.carrier"),
    Probe("speed", "parallel.input_gear"),
    Probe("speed", "generator"),
    Probe("mesh_force", "stage1.sun-planet1"),
    Probe("mesh_force", "stage1.ring-planet1"),
    Probe("mesh_force", "stage2.sun-planet1"),
    Probe("mesh_force", "stage2.ring-planet1"),
    Probe("mesh_force", "parallel.input-output"),
    Probe("drive_torque"),
    Probe("load_torque"),
)

# The run-up of the gearbox case, from rest, on the whole drivetrain: the rotor's rated
# torque against the paper's generator law (eq. 31) once the rotor passes 0.6 rpm.
RUNUP = Transient(
    duration=2.0,  # s
    time_step=5e-5,  # s: as the gearbox case (10 steps per period of its highest mode)
    sample_rate=2e4,  # Hz
    integrator="newmark",
    equivalent_load="predictor",
    input="rotor.theta_z",
    output="generator.theta_z",
    drive=TorqueLaw.constant(G.RUNUP_DRIVE_TORQUE),
    load=TorqueLaw.generator(rated_drive_torque=G.RUNUP_DRIVE_TORQUE, exponent=G.LOAD_EXPONENT),
    speed_reference_rpm=G.RUNUP_SPEED_RPM,
    probes=PROBES,
    mean_window=0.5,  # s
)

# Emergency stop at rated operation: the turbine runs at rated speed and torque; at
# STOP_TIME the grid is lost (the generator torque drops to zero within one step) and
# the high-speed-shaft brake closes over its deployment time, while the blades pitch
# the aerodynamic torque away.  The step of the generator torque excites the
# drivetrain's torsional mode (about 2 Hz), whose swing the gearbox's meshes carry.
RATED_GENERATOR_TORQUE = 43_093.55  # N m on the high-speed shaft [Jonkman] Table 1-1
STOP_TIME = 0.5  # s: ASSUMED, rated operation settles the record first
# ASSUMED: NREL's 5 MW ServoDyn brake of the OpenFAST regression decks (HSSBrTqF,
# HSSBrDT): 28 116.2 N m fully deployed after 0.6 s.
BRAKE_TORQUE = 28_116.2  # N m on the high-speed shaft
BRAKE_DEPLOYMENT = 0.6  # s
# ASSUMED: the blades pitch to feather at 8 deg/s (Jonkman's pitch-rate limit), taking
# the aerodynamic torque linearly to zero in about 11 s; only its start matters here.
# The generator torque's step excites the drivetrain's torsional mode; its swing is
# larger than the mean torque, so the meshes unload and reverse (coast flanks).
FEATHER_TIME = 11.0  # s
EMERGENCY_STOP = Transient(
    duration=3.0,  # s: the step and about five periods of the torsional mode
    time_step=5e-5,  # s
    sample_rate=2e4,  # Hz
    integrator="newmark",
    # the torque reverses in the meshes: the teeth part and meet on the coast flanks,
    # a contact state that the iteration settles within each step
    equivalent_load="iterate",
    input="rotor.theta_z",
    output="generator.theta_z",
    initial_speed_rpm=G.RATED_ROTOR_SPEED_RPM,
    start_loaded=True,  # twisted by the rated torques: no swing before the stop
    drive=TorqueLaw.table(
        (0.0, STOP_TIME, STOP_TIME + FEATHER_TIME),
        (G.RATED_ROTOR_TORQUE, G.RATED_ROTOR_TORQUE, 0.0),
    ),
    load=TorqueLaw.table(
        (0.0, STOP_TIME, STOP_TIME + 5e-5, STOP_TIME + BRAKE_DEPLOYMENT),
        (RATED_GENERATOR_TORQUE, RATED_GENERATOR_TORQUE, 0.0, BRAKE_TORQUE),
    ),
    probes=PROBES,
    mean_window=0.4,  # s: the speeds at the end of the record
)
# The same stop on the spatial model (144 DOFs): the planets' bearings carry the
# meshes' reversal to the carrier, and the rotor's weightless tilt and the planets'
# axial modes lie near the torsional one (docs/drivetrain.md).
EMERGENCY_STOP_SPATIAL = dataclasses.replace(
    EMERGENCY_STOP,
    duration=1.5,  # s: the step and two swings
    probes=PROBES
    + (
        Probe("bearing_force", "stage1.planet1_bearing.zeta"),  # radial, planet frame
        Probe("bearing_force", "stage1.planet1_bearing.eta"),  # tangential: the torque
        Probe("bearing_force", "stage1.carrier_bearing.y"),
    ),
)

case = Case(
    name="nrel5mw_drivetrain",
    description=(
        "NREL 5 MW drivetrain (Jonkman et al. 2009) with the NREL 5 MW reference gearbox "
        "(Nejad et al. 2016) on finite-element shafts"
    ),
    gearbox=gearbox,
    drivetrain=drivetrain,
    formulation="consistent",
    damping=G.DAMPING,  # the gearbox's Rayleigh damping (ASSUMED there)
    scenes=(
        Scene("modal_torsional", analyses=("modal",), dof_set="torsional"),
        Scene("modal", analyses=("modal",), dof_set="spatial"),
        Scene(
            "runup",
            analyses=("transient",),
            effects=("time_varying_mesh_stiffness",),
            dof_set="torsional",
            transient=RUNUP,
        ),
        Scene(
            "emergency_stop",
            analyses=("transient",),
            effects=("time_varying_mesh_stiffness", "tooth_separation"),
            dof_set="torsional",
            transient=EMERGENCY_STOP,
        ),
        Scene(
            "emergency_stop_spatial",
            analyses=("transient",),
            effects=("time_varying_mesh_stiffness", "tooth_separation"),
            dof_set="spatial",
            transient=EMERGENCY_STOP_SPATIAL,
        ),
    ),
)

# The gearbox's rating data (pygear rate): the same stages, materials and bearings.
rating = G.rating
