"""A four-planet spur stage written from nothing: the case of docs/writing_a_case.md.

Not a published gearbox: a plain 4 mm module stage (sun 28, planets 26, ring 80 teeth,
40 mm face width) whose every value is either derived below from its geometry or
marked ASSUMED with the reason.  The page walks through it part by part; the markers
``# [name]`` and ``# [/name]`` delimit the parts it shows.
"""

# [imports]
import math

from pygear import (
    Bearing,
    Body,
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
    TorqueLaw,
    Transient,
)

# [/imports]

# [bodies]
STEEL_DENSITY = 7850.0  # kg/m^3
MODULE = 4e-3  # m, normal module of every gear
FACE_WIDTH = 0.040  # m
SUN_TEETH, PLANET_TEETH, RING_TEETH = 28, 26, 80  # Z_r = Z_s + 2 Z_p; (28 + 80) / 4 whole


def disc(outer_radius: float, inner_radius: float) -> Body:
    """A steel disc (or annulus) of the face width: mass, polar and tilt inertia."""
    mass = STEEL_DENSITY * math.pi * (outer_radius**2 - inner_radius**2) * FACE_WIDTH
    polar = mass * (outer_radius**2 + inner_radius**2) / 2
    tilt = polar / 2 + mass * FACE_WIDTH**2 / 12  # thin disc about a diameter
    return Body(mass=mass, polar_inertia=polar, tilt_inertia=tilt)


# the gears as discs of their pitch radius m Z / 2
sun_body = disc(MODULE * SUN_TEETH / 2, 0.0)  # solid sun
planet_body = disc(MODULE * PLANET_TEETH / 2, 0.020)  # ASSUMED: a 20 mm bearing seat
ring_body = disc(MODULE * RING_TEETH / 2 + 0.030, MODULE * RING_TEETH / 2)  # ASSUMED: 30 mm rim
# [/bodies]

# [gears]
sun = Gear(
    mass=sun_body.mass,
    polar_inertia=sun_body.polar_inertia,
    tilt_inertia=sun_body.tilt_inertia,
    geometry=GearGeometry(teeth=SUN_TEETH, normal_module=MODULE, face_width=FACE_WIDTH),
)
planet = Gear(
    mass=planet_body.mass,
    polar_inertia=planet_body.polar_inertia,
    tilt_inertia=planet_body.tilt_inertia,
    geometry=GearGeometry(teeth=PLANET_TEETH, normal_module=MODULE, face_width=FACE_WIDTH),
)
ring = Gear(
    mass=ring_body.mass,
    polar_inertia=ring_body.polar_inertia,
    tilt_inertia=ring_body.tilt_inertia,
    # a full-depth ring tooth reaches into the planet's root fillet (pygear refuses it:
    # interference at the planet's root); ring teeth shortened by 0.2 m_n clear it
    geometry=GearGeometry(
        teeth=RING_TEETH,
        normal_module=MODULE,
        face_width=FACE_WIDTH,
        internal=True,
        tip_alteration=-0.2,
    ),
)
# ASSUMED: a carrier of 15 kg with 0.15 kg m^2 about its axis (two plates and four pins
# around the 108 mm carrier radius); its radius comes from the gears' centre distance
carrier = Carrier(mass=15.0, polar_inertia=0.15, tilt_inertia=0.08)
# [/gears]

# [bearings]
RADIAL_STIFFNESS = 1e8  # N/m, ASSUMED: a stiff rolling bearing of this size
AXIAL_STIFFNESS = 1e8  # N/m, ASSUMED equal to the radial one (spatial scenes only)
TILT_STIFFNESS = 1e8 * 0.05**2  # N m/rad, ASSUMED: radial stiffness x (50 mm)^2
RING_TORSIONAL_STIFFNESS = 1e9 * (MODULE * RING_TEETH / 2) ** 2  # N m/rad, ASSUMED: 1e9 N/m
#   at the ring's pitch radius, a ring held in the housing by splines

free = dict(radial=RADIAL_STIFFNESS, axial=AXIAL_STIFFNESS, tilt=TILT_STIFFNESS)
carrier_bearing = Bearing(**free, torsional=0.0)  # the carrier turns
sun_bearing = Bearing(**free, torsional=0.0)  # the sun turns
ring_bearing = Bearing(**free, torsional=RING_TORSIONAL_STIFFNESS)  # the ring is held
planet_bearing = PlanetBearing(radial=RADIAL_STIFFNESS, axial=AXIAL_STIFFNESS, tilt=TILT_STIFFNESS)
# [/bearings]

# [meshes]
# ASSUMED: mean mesh stiffness c_gamma b with ISO 6336-1's typical 20 N/(mm um) for
# steel spur gears, 20e9 N/m^2 x 0.040 m; end-to-peak ratios as in the yang2016 cases
MESH_STIFFNESS = 20e9 * FACE_WIDTH  # N/m
sun_mesh = Mesh(stiffness=MESH_STIFFNESS, end_to_peak=0.6)
ring_mesh = Mesh(stiffness=MESH_STIFFNESS, end_to_peak=0.7)
# pressure angles and contact ratios are derived from the gear geometry
# [/meshes]

# [stage]
stage = PlanetaryStage(
    name="planetary",
    carrier=carrier,
    ring=ring,
    sun=sun,
    planet=planet,
    planets=4,
    carrier_bearing=carrier_bearing,
    ring_bearing=ring_bearing,
    sun_bearing=sun_bearing,
    planet_bearing=planet_bearing,
    sun_mesh=sun_mesh,
    ring_mesh=ring_mesh,
)
# [/stage]

# [sensor]
ring_sensor = Sensor(
    name="ring_top",  # recorded as ring_top_acceleration
    stage="planetary",
    angle_deg=90.0,  # at the top of the ring, +y
    direction="radial",
    mesh_gain=1.0 / ring_body.mass,  # (m/s^2)/N, ASSUMED: the ring as a rigid mass
)
# [/sensor]

# [runup]
SPEED_RPM = 100.0  # omega_0 of the carrier [rpm], ASSUMED: a slow wind-turbine stage
DRIVE_TORQUE = 50.0  # N m on the carrier, ASSUMED: reaches omega_0 in about 0.1 s
runup = Transient(
    duration=1.0,  # s: the start-up and 0.5 s of steady running
    time_step=2.5e-5,  # s: 300 steps per mesh period at 100 rpm (133 Hz)
    sample_rate=20e3,  # Hz: every second step
    input="planetary.carrier.theta_z",
    output="planetary.sun.theta_z",
    drive=TorqueLaw.constant(DRIVE_TORQUE),
    load=TorqueLaw.generator(rated_drive_torque=DRIVE_TORQUE, exponent=2.0),
    speed_reference_rpm=SPEED_RPM,
    mean_window=0.5,  # s: equilibrium speeds over the last half second
    probes=(
        Probe("speed", "planetary.carrier"),
        Probe("speed", "planetary.sun"),
        Probe("mesh_force", "sun-planet1"),
        Probe("acceleration", "planetary.sun.theta_z"),
        Probe("sensor", "ring_top"),
    ),
)
# [/runup]

# [case]
case = Case(
    name="four_planet_stage",
    description="A four-planet spur stage written from nothing (docs/writing_a_case.md)",
    gearbox=Gearbox(stages=(stage,)),
    formulation="consistent",
    # ASSUMED: alpha = 0.13 1/s and beta = 1e-6 s as in the yang2016 cases
    damping=RayleighDamping(mass_coefficient=0.13, stiffness_coefficient=1e-6),
    sensors=(ring_sensor,),
    scenes=(
        Scene("modal", analyses=("modal",)),
        Scene(
            "runup",
            analyses=("transient",),
            effects=("time_varying_mesh_stiffness",),
            transient=runup,
        ),
    ),
)
# [/case]
