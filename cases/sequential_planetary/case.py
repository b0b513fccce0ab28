"""A sequentially phased planetary stage with an accelerometer on its ring.

A stage for condition-monitoring studies (not from a paper): three equally spaced planets
whose ring meshes are a third of a mesh cycle apart (Z_r / N = 97 / 3 is not whole), the
case McFadden & Smith (1985) explain and Inalpolat & Kahraman (2009) measure: the mesh
frequency itself is suppressed at a sensor on the ring and its energy appears at the
nearest carrier orders that are multiples of N.  The gears are given by their involute
geometry and every mesh runs the potential-energy law, so tooth faults (root cracks,
spalls, chipped or missing teeth) enter as the damaged tooth's own stiffness curve.
Sizes are of a small industrial stage like the study case's (about 3 mm module);
everything here is ASSUMED unless it follows from the geometry.
"""

import math

from pygear import (
    Bearing,
    Carrier,
    Case,
    Gear,
    Gearbox,
    GearGeometry,
    Mesh,
    PlanetaryStage,
    PlanetBearing,
    Probe,
    RayleighDamping,
    Scene,
    Sensor,
    StructuralMode,
    ToothDefect,
    TorqueLaw,
    Transient,
)
from pygear.model.gear_geometry import base_half_thickness
from pygear.model.tooth_faults import RootCrack

# --- geometry (ASSUMED: a standard 20 deg, 3 mm spur set, no profile shift) ----------------
# Z_r = Z_s + 2 Z_p (coaxial) and (Z_s + Z_r) / 3 = 42 whole (three equally spaced planets
# assemble), Z_r / 3 and Z_s / 3 not whole (sequentially phased meshes).
TEETH = {"sun": 29, "planet": 34, "ring": 97}
MODULE = 3e-3  # m, ASSUMED
FACE_WIDTH = 30e-3  # m, ASSUMED
CENTRE_DISTANCE = MODULE * (TEETH["sun"] + TEETH["planet"]) / 2  # m: 94.5 mm, zero shift


def geometry(member: str) -> GearGeometry:
    """The ISO 53 profile A gear of ``member``."""
    return GearGeometry(
        teeth=TEETH[member],
        normal_module=MODULE,
        face_width=FACE_WIDTH,
        normal_pressure_angle_deg=20.0,
        internal=member == "ring",
        # ASSUMED: the ring's addendum shortened to 0.75 m_n, the usual remedy for the tip
        # interference of a full-depth internal tooth with a 34-tooth planet's root
        tip_alteration=-0.25 if member == "ring" else 0.0,
    )


# --- bodies: steel annuli (ASSUMED density 7850 kg/m^3) -------------------------------------
STEEL_DENSITY = 7850.0  # kg/m^3, ASSUMED
BORE_RADIUS = {"sun": 15e-3, "planet": 20e-3}  # m, ASSUMED: shaft seat and planet bearing
RING_OUTER_RADIUS = 165e-3  # m, ASSUMED: rim of about 3.5 modules below the root circle


def annulus(inner: float, outer: float) -> dict[str, float]:
    """Mass, polar and tilt inertia of a steel annulus of the face width."""
    mass = STEEL_DENSITY * math.pi * (outer**2 - inner**2) * FACE_WIDTH
    polar = mass * (outer**2 + inner**2) / 2
    return {"mass": mass, "polar_inertia": polar, "tilt_inertia": polar / 2}


def gear(member: str) -> Gear:
    pitch = MODULE * TEETH[member] / 2
    if member == "ring":
        body = annulus(pitch, RING_OUTER_RADIUS)
        # the rim radius puts the ring's teeth on a compliant rim (potential-energy law)
        return Gear(**body, geometry=geometry(member), rim_radius=RING_OUTER_RADIUS)
    body = annulus(BORE_RADIUS[member], pitch)
    return Gear(**body, geometry=geometry(member), bore_radius=BORE_RADIUS[member])


BEARING = Bearing(radial=1e8, axial=1e8, tilt=1e6, torsional=0.0)  # ASSUMED, as the study case
RING_SUPPORT = Bearing(
    radial=1e8, axial=1e8, tilt=1e6, torsional=1e9 * (MODULE * TEETH["ring"] / 2) ** 2
)  # ASSUMED: the study case's 1e9 N/m at the ring's pitch radius

stage = PlanetaryStage(
    name="planetary",
    # ASSUMED: two steel carrier plates of the study case's carrier, 5.4 kg
    carrier=Carrier(
        mass=5.43, polar_inertia=59.1e-3, tilt_inertia=59.1e-3 / 2, radius=CENTRE_DISTANCE
    ),
    ring=gear("ring"),
    sun=gear("sun"),
    planet=gear("planet"),
    planets=3,
    carrier_bearing=BEARING,
    ring_bearing=RING_SUPPORT,
    sun_bearing=BEARING,
    planet_bearing=PlanetBearing(radial=1e8, axial=1e8, tilt=1e6),  # ASSUMED, as the study case
    sun_mesh=Mesh(law="potential_energy"),  # steel: E = 206 GPa, nu = 0.3 (defaults)
    ring_mesh=Mesh(law="potential_energy"),
)

# --- the sensor ----------------------------------------------------------------------------
RING_SENSOR = Sensor(
    name="ring_sensor",  # recorded as sensor_acceleration(sensor="ring_sensor", time)
    stage="planetary",
    angle_deg=90.0,  # at the top
    direction="radial",
    window="hann",
    window_width_deg=180.0,  # deg, ASSUMED: heard over the half of the ring facing it
    mesh_gain=1.0 / 4.0,  # (m/s^2)/N, ASSUMED: about the rigid ring's mass (4 kg)
    bearing_gain=1.0 / 4.0,  # (m/s^2)/N, ASSUMED: the same rigid ring
    # ASSUMED: one ring-housing mode at 3 kHz with 5 % damping, as strong as the flat path
    structure=(StructuralMode(frequency=3000.0, damping_ratio=0.05, gain=1.0),),
)

# --- steady operation ----------------------------------------------------------------------
CARRIER_SPEED_RPM = 120.0  # ASSUMED: the study case's omega_0
CARRIER_TORQUE = 500.0  # N m, ASSUMED: about 0.94 kN per mesh, 31 N/mm of face
MESH_FREQUENCY = TEETH["ring"] * CARRIER_SPEED_RPM / 60.0  # Hz: 194 Hz
# Steps and samples per mesh period: whole and multiples of 3, so that the tooth pairs of
# the three sequentially phased planets (a third of a cycle apart) enter and leave contact
# at the same step phase in every cycle and are sampled at the same phase.  An
# incommensurate step adds a beat of the step and mesh rates that is not the stage's
# (40 kHz - 206 x 194 Hz = 36 Hz at 2.5e-5 s), and a sample count per carrier turn that
# is not a multiple of 3 aliases the mesh harmonics of the contact jumps onto the carrier
# orders that equally spaced planets cancel (docs/condition_monitoring.md).
STEPS_PER_MESH_PERIOD = 207  # 69 samples per mesh period at every third step
STEADY = Transient(
    duration=4.0,  # s: 8 carrier revolutions, 27 of the sun and 23 of a planet on the carrier
    time_step=1.0 / (STEPS_PER_MESH_PERIOD * MESH_FREQUENCY),  # s: 2.49e-5
    sample_rate=STEPS_PER_MESH_PERIOD * MESH_FREQUENCY / 3,  # Hz: 13.4 kHz
    integrator="newmark",
    equivalent_load="predictor",
    input="planetary.carrier.theta_z",
    output="planetary.sun.theta_z",
    drive=TorqueLaw.constant(CARRIER_TORQUE),
    # the sun's load balances the drive at the carrier speed (the load law of the study case)
    load=TorqueLaw.generator(rated_drive_torque=CARRIER_TORQUE, exponent=2.0),
    speed_reference_rpm=CARRIER_SPEED_RPM,
    initial_speed_rpm=CARRIER_SPEED_RPM,  # start turning: no run-up from rest
    probes=(
        Probe("sensor", "ring_sensor"),
        Probe("displacement", "planetary.carrier.theta_z"),  # angles for synchronous averages
        Probe("displacement", "planetary.sun.theta_z"),
        Probe("displacement", "planetary.planet1.theta_z"),  # spin relative to the carrier
        Probe("speed", "planetary.carrier"),
        Probe("mesh_force", "ring-planet1"),
        Probe("mesh_force", "sun-planet1"),
    ),
    mean_window=1.0,
)

# A root crack (Tian 2004) at 45 deg: depth ratio q sin(45 deg) / h_b of 0.3, h_b the
# half tooth thickness at the base circle (docs/condition_monitoring.md).
CRACK_ANGLE_DEG = 45.0  # ASSUMED: the angle of Tian's (2004) and Chen & Shao's (2011) studies
SUN_CRACK = RootCrack(
    gear=1,
    depth=0.3 * base_half_thickness(geometry("sun")) / math.sin(math.radians(CRACK_ANGLE_DEG)),
    angle_deg=CRACK_ANGLE_DEG,
)

case = Case(
    name="sequential_planetary",
    description="Sequentially phased planetary stage with a ring accelerometer (ASSUMED sizes)",
    gearbox=Gearbox(stages=(stage,)),
    formulation="improved",
    # ASSUMED: stiffness-proportional damping only (no brake on the rigid rotation); 1e-6 s
    # as the study case: about 1 % of critical at 3 kHz
    damping=RayleighDamping(mass_coefficient=0.0, stiffness_coefficient=1e-6),
    sensors=(RING_SENSOR,),
    scenes=(
        Scene("modal", analyses=("modal",), dof_set="planar"),
        Scene(
            "steady_sensor",
            analyses=("transient",),
            dof_set="planar",
            effects=("time_varying_mesh_stiffness",),
            transient=STEADY,
        ),
        Scene(
            "sun_crack",
            analyses=("transient",),
            dof_set="planar",
            effects=("time_varying_mesh_stiffness",),
            transient=STEADY,
            defects=(ToothDefect("planetary.sun", 0, fault=SUN_CRACK),),
        ),
        Scene(
            "planet_missing_tooth",
            analyses=("transient",),
            dof_set="planar",
            effects=("time_varying_mesh_stiffness",),
            transient=STEADY,
            defects=(ToothDefect("planetary.planet1", 0, factor=0.0),),
        ),
    ),
)
