"""The seed paper's planetary study case (Yang, Jiang & Han 2016, section 5, Table 1).

The parameters are Lin & Parker's (1999) example; Table 1 prints them with a
"base diameter" heading, but the values are radii.  Every value not printed in the
paper is marked ASSUMED with the reason.
"""

import dataclasses
import math

from pygear import (
    Bearing,
    Carrier,
    Case,
    Gear,
    Gearbox,
    Mesh,
    PlanetaryStage,
    PlanetBearing,
    Probe,
    RayleighDamping,
    Scene,
    Sensor,
    StructuralMode,
    TorqueLaw,
    Transient,
)
from pygear.model.response_settings import Response

# Spur study: the paper fixes the axial and tilting DOFs. Their bending inertias and
# out-of-plane stiffnesses only matter for a spatial scene. ASSUMED: a thin disc's
# bending inertia I_t = I_p / 2, and out-of-plane bearing stiffnesses equal to the
# radial one (axial, N/m) and radial stiffness x (0.1 m)^2 (tilt, N m/rad).
BEARING_STIFFNESS = 1e8  # N/m, Table 1 (carrier, ring, sun and planets, x and y)
AXIAL_STIFFNESS = 1e8  # N/m, ASSUMED (spatial scenes only)
TILT_STIFFNESS = 1e8 * 0.1**2  # N m/rad, ASSUMED (spatial scenes only)
RING_BASE_RADIUS = 137.5e-3  # m, Table 1

stage = PlanetaryStage(
    name="planetary",
    carrier=Carrier(mass=5.43, polar_inertia=59.1e-3, tilt_inertia=59.1e-3 / 2, radius=96.9e-3),
    ring=Gear(
        mass=2.35,
        polar_inertia=56.7e-3,
        tilt_inertia=56.7e-3 / 2,
        base_radius=RING_BASE_RADIUS,
        teeth=96,
    ),
    sun=Gear(
        mass=0.4, polar_inertia=0.58e-3, tilt_inertia=0.58e-3 / 2, base_radius=38.7e-3, teeth=27
    ),
    planet=Gear(
        mass=0.66, polar_inertia=1.53e-3, tilt_inertia=1.53e-3 / 2, base_radius=50.2e-3, teeth=35
    ),
    planets=3,
    carrier_bearing=Bearing(
        radial=BEARING_STIFFNESS, axial=AXIAL_STIFFNESS, tilt=TILT_STIFFNESS, torsional=0.0
    ),  # carrier turns freely
    # ring held by a torsional spring of 1e9 N/m at its base radius (Table 1)
    ring_bearing=Bearing(
        radial=BEARING_STIFFNESS,
        axial=AXIAL_STIFFNESS,
        tilt=TILT_STIFFNESS,
        torsional=1e9 * RING_BASE_RADIUS**2,
    ),
    sun_bearing=Bearing(
        radial=BEARING_STIFFNESS, axial=AXIAL_STIFFNESS, tilt=TILT_STIFFNESS, torsional=0.0
    ),  # sun turns freely
    planet_bearing=PlanetBearing(
        radial=BEARING_STIFFNESS, axial=AXIAL_STIFFNESS, tilt=TILT_STIFFNESS
    ),
    # mean mesh stiffness 5e8 N/m, pressure angle 24.6 deg, contact ratio 1.24 (Table 1);
    # end-to-peak ratio ASSUMED 0.6 external / 0.7 internal (docs/model.md §5.2)
    sun_mesh=Mesh(stiffness=5e8, pressure_angle_deg=24.6, contact_ratio=1.24, end_to_peak=0.6),
    ring_mesh=Mesh(stiffness=5e8, pressure_angle_deg=24.6, contact_ratio=1.24, end_to_peak=0.7),
    base_helix_angle_deg=0.0,  # spur (Table 1)
)

# Run-up (paper section 5.3, Table 3 and Figure 9; docs/model.md §6.3): from rest, a constant
# drive torque on the carrier; the sun carries the paper's load law (eq. 31), zero until
# t_s (the first instant the carrier reaches omega_0) and T_L = (T_D/i)(w_sun/(i w_0))^n
# afterwards, i = 1 + r_br/r_bs.  Equilibrium speeds are means over the last 1 s.
RUNUP_SPEED_RPM = 120.0  # omega_0 [rpm], paper section 5.3
DRIVE_TORQUE = 10.0  # T_D [N m], ASSUMED (lost): gives the paper's t_s = 0.156 s (theory)
LOAD_EXPONENT = 2.0  # n of the load law, ASSUMED (lost; docs/model.md §6.3)
RUNUP = Transient(
    duration=5.0,  # s, paper section 5.3
    time_step=2.5e-5,  # s, paper section 5.3
    sample_rate=40e3,  # Hz, paper section 5.3
    integrator="newmark",  # average acceleration (docs/model.md §6.1)
    # the paper's explicit equivalent load (eq. 25) at its predictor; 'iterate' makes the
    # mesh term implicit (the predictor diverges at twice this time step)
    equivalent_load="predictor",
    input="planetary.carrier.theta_z",
    output="planetary.sun.theta_z",
    drive=TorqueLaw.constant(DRIVE_TORQUE),
    load=TorqueLaw.generator(rated_drive_torque=DRIVE_TORQUE, exponent=LOAD_EXPONENT),
    speed_reference_rpm=RUNUP_SPEED_RPM,
    probes=(
        Probe("speed", "planetary.carrier"),
        Probe("speed", "planetary.sun"),
        Probe("speed", "planetary.planet1"),  # spin relative to the carrier
        Probe("velocity", "planetary.planet1.eta", name="planet1_tangential_velocity"),
        Probe("acceleration", "planetary.sun.theta_z"),  # seed Figs. 13-14
        Probe("acceleration", "planetary.ring.y"),  # seed Figs. 10-12
        Probe("mesh_force", "sun-planet1"),
        Probe("mesh_force", "ring-planet1"),
        Probe("drive_torque"),
        Probe("load_torque"),
    ),
    mean_window=1.0,  # s: equilibrium speeds are means over the last 1 s (paper)
)

# Torque reversal (not in the paper): the carrier's drive rises to +10 N m, holds, and
# falls through zero to -10 N m; no load, so the meshes carry the inertia forces of the
# accelerating sun and planets.  When the torque reverses the sun overruns, the drive
# flanks part, the teeth cross the backlash and strike the coast flanks.
REVERSAL_TORQUE = 10.0  # N m, ASSUMED: the run-up's drive, both ways
# ASSUMED: 0.1 mm circumferential backlash j_wt on both meshes, typical for the ~3 mm
# module of this stage (r_b/cos(alpha) 2/z = 3.15 mm): DIN 3967 tooth thickness
# allowances of about 0.03-0.05 m_n per gear give 0.1-0.2 mm.
REVERSAL_BACKLASH = 0.1e-3  # m
TORQUE_REVERSAL = Transient(
    duration=0.06,  # s, ASSUMED: the reversal and a few impacts, a short run
    time_step=1e-5,  # s, ASSUMED: 20 steps per contact half-period of the sun on its meshes
    sample_rate=100e3,  # Hz: every step, to see each impact
    integrator="newmark",  # average acceleration: impacts neither damped nor amplified
    # the contact state changes within a step: iterate it to convergence
    equivalent_load="iterate",
    input="planetary.carrier.theta_z",
    output="planetary.sun.theta_z",
    drive=TorqueLaw.table(
        [0.0, 0.005, 0.02, 0.025, 0.06],  # s, ASSUMED ramps of 5 ms
        [0.0, REVERSAL_TORQUE, REVERSAL_TORQUE, -REVERSAL_TORQUE, -REVERSAL_TORQUE],
    ),
    load=None,
    probes=(
        Probe("speed", "planetary.carrier"),
        Probe("speed", "planetary.sun"),
        Probe("mesh_force", "sun-planet1"),  # > 0 drive flank, < 0 coast flank
        Probe("mesh_force", "ring-planet1"),
        Probe("mesh_deflection", "sun-planet1"),
        Probe("mesh_deflection", "ring-planet1"),
        Probe("drive_torque"),
    ),
    mean_window=0.01,  # s: the last 10 ms, after the reversal
)

# Wide run-up (not in the paper): the carrier's speed rises along a straight line from
# rest to twice the run-up's 120 rpm under the rated mesh load, so the mesh harmonics
# 4-10 sweep through the 1334 Hz rotational mode (docs/campbell.md, "The run-up meets the
# Campbell diagram").  The drive balances the load, accelerates the gearbox's
# carrier-referred inertia J at a constant rate A and adds alpha J A t, the mass-
# proportional damping's torque on the rigid rotation: J w' + alpha J w = J A (1 + alpha t)
# holds for w = A t, so the speed is linear in time.
MASS_DAMPING = 0.13  # alpha [1/s] of the case's Rayleigh damping, ASSUMED (see below)
WIDE_TOP_SPEED_RPM = 240.0  # ASSUMED: twice omega_0 (the run-up settles at 118.8 rpm)
# s, ASSUMED: 60 rpm/s, about a second of computation; an order-tracking window of W
# revolutions at n rpm then spans 3600 W / n rpm of speed
WIDE_DURATION = 4.0
WIDE_RATIO = 1.0 + RING_BASE_RADIUS / stage.sun.base_radius  # i = n_sun / n_carrier
# J [kg m^2] of the improved formulation's rigid rotation, planet spin taken relative to
# the carrier: J_c + N (m_p r_c^2 + J_p (r_br/r_bp)^2) + J_s i^2 = 0.12415 (Table 1)
WIDE_INERTIA = (
    stage.carrier.polar_inertia
    + stage.planets
    * (
        stage.planet.mass * stage.carrier.radius**2
        + stage.planet.polar_inertia * (RING_BASE_RADIUS / stage.planet.base_radius) ** 2
    )
    + stage.sun.polar_inertia * WIDE_RATIO**2
)
WIDE_LOAD = DRIVE_TORQUE / WIDE_RATIO  # N m on the sun, ASSUMED: the rated 10 N m load
WIDE_ACCELERATION_TORQUE = (  # J A [N m], A = top speed / duration
    WIDE_INERTIA * WIDE_TOP_SPEED_RPM * 2.0 * math.pi / 60.0 / WIDE_DURATION
)
RUNUP_WIDE = Transient(
    duration=WIDE_DURATION,
    time_step=2.5e-5,  # s, the run-up's (paper section 5.3)
    sample_rate=40e3,  # Hz, the run-up's: orders up to f_s / (2 n_max) = 5000 at 240 rpm
    integrator="newmark",
    equivalent_load="predictor",  # as the run-up
    input="planetary.carrier.theta_z",
    output="planetary.sun.theta_z",
    drive=TorqueLaw.table(
        [0.0, WIDE_DURATION],
        [
            WIDE_RATIO * WIDE_LOAD + WIDE_ACCELERATION_TORQUE,
            WIDE_RATIO * WIDE_LOAD
            + WIDE_ACCELERATION_TORQUE * (1.0 + MASS_DAMPING * WIDE_DURATION),
        ],
    ),
    load=TorqueLaw.constant(WIDE_LOAD),
    probes=(
        Probe("speed", "planetary.carrier"),  # the order-tracking reference
        Probe("acceleration", "planetary.sun.theta_z"),  # sees the rotational modes
        Probe("mesh_force", "sun-planet1"),
        Probe("mesh_force", "ring-planet1"),
        Probe("drive_torque"),
    ),
    # s: the ramp never settles; the "equilibrium" speeds are those of its last 0.1 s
    # (their ratios give pygear analyze its mesh orders)
    mean_window=0.1,
)

# A radial accelerometer on the ring at the top (not in the paper; docs/condition_monitoring.md).
# Each planet's ring-mesh force reaches it through a Hann window of the planet's angle
# from the sensor (McFadden & Smith 1985) and the ring's bearing force directly.
RING_SENSOR = Sensor(
    name="ring_sensor",  # recorded as sensor_acceleration(sensor="ring_sensor", time)
    stage="planetary",
    angle_deg=90.0,  # at the top, +y
    direction="radial",
    window="hann",
    # deg, ASSUMED: a planet is heard while it is on the half of the ring facing the
    # sensor (wider than 360/3, so the windows do not sum to a constant: the pass of each
    # planet modulates what the sensor hears, as on a real ring)
    window_width_deg=180.0,
    mesh_gain=1.0 / 2.35,  # (m/s^2)/N, ASSUMED: the rigid ring's mass, 2.35 kg (Table 1)
    bearing_gain=1.0 / 2.35,  # (m/s^2)/N, ASSUMED: the same rigid ring
    # ASSUMED: one ring-housing mode at 2.5 kHz with 5 % damping, as strong as the flat path
    structure=(StructuralMode(frequency=2500.0, damping_ratio=0.05, gain=1.0),),
)
SENSOR_PROBES = (
    Probe("sensor", "ring_sensor"),  # sensor_acceleration(sensor="ring_sensor")
    Probe("displacement", "planetary.carrier.theta_z"),  # angle for synchronous averages
    Probe("displacement", "planetary.sun.theta_z"),
    Probe("displacement", "planetary.planet1.theta_z"),  # spin relative to the carrier
    Probe("speed", "planetary.carrier"),
    Probe("speed", "planetary.sun"),
    Probe("mesh_force", "ring-planet1"),
    Probe("mesh_force", "ring-planet2"),
    Probe("mesh_force", "ring-planet3"),
)
# the run-up names its sensor channel ring_sensor_acceleration (a variable of its own)
RUNUP_SENSOR = dataclasses.replace(
    RUNUP,
    probes=(Probe("sensor", "ring_sensor", name="ring_sensor_acceleration"), *SENSOR_PROBES[1:]),
)
# Steady operation at omega_0 (not in the paper), for the sensor's carrier orders: the
# run-up's drive and load law, started at 120 rpm; 207 steps and 69 samples per mesh
# period (multiples of the three planets: neither the step quantisation nor the aliases
# of the contact jumps tell the planets apart, docs/condition_monitoring.md)
STEADY_MESH_FREQUENCY = 96 * RUNUP_SPEED_RPM / 60.0  # Hz: 192 Hz
STEADY_SENSOR = dataclasses.replace(
    RUNUP,
    probes=SENSOR_PROBES,
    duration=4.0,  # s: 8 carrier revolutions
    time_step=1.0 / (207 * STEADY_MESH_FREQUENCY),  # s: 2.52e-5, the run-up's 2.5e-5 rounded
    sample_rate=69 * STEADY_MESH_FREQUENCY,  # Hz: 13.2 kHz
    initial_speed_rpm=RUNUP_SPEED_RPM,
)

case = Case(
    name="yang2016_planetary",
    description="Planetary study case of Yang, Jiang & Han (2016), Table 1",
    gearbox=Gearbox(stages=(stage,)),
    formulation="improved",  # the seed's own model; scenes name the others
    sensors=(RING_SENSOR,),
    # ASSUMED: the paper's Rayleigh coefficients were lost; alpha = 0.13 1/s reproduces
    # its Table 3 with the load law of docs/model.md §6.3, beta = 1e-6 s (§3.7)
    damping=RayleighDamping(mass_coefficient=MASS_DAMPING, stiffness_coefficient=1e-6),
    scenes=(
        Scene("modal", analyses=("modal",), formulation="improved", dof_set="planar"),
        Scene("modal_lin_parker", analyses=("modal",), formulation="lin-parker", dof_set="planar"),
        Scene("modal_consistent", analyses=("modal",), formulation="consistent", dof_set="planar"),
        *(
            Scene(
                name,
                analyses=("transient", "signal"),  # signal: seed Figs. 10-14
                formulation=formulation,
                dof_set="planar",
                effects=("time_varying_mesh_stiffness",),
                transient=RUNUP,
            )
            for name, formulation in (
                ("runup", "improved"),
                ("runup_lin_parker", "lin-parker"),
                ("runup_consistent", "consistent"),
            )
        ),
        # The symmetric study case excites no translational mode (Parker's selection rule:
        # equally spaced, in-phase planets); a realistic assembly error does. ASSUMED:
        # planet 2 placed 0.1 deg off its nominal 120 deg.
        Scene(
            "runup_planet_error",
            analyses=("transient", "signal"),
            formulation="improved",
            dof_set="planar",
            effects=("time_varying_mesh_stiffness",),
            transient=RUNUP,
            parameters={"planetary.planet_angles_deg": (0.0, 120.1, 240.0)},
        ),
        # 0 -> 240 rpm at a constant rate for order tracking against the Campbell diagram
        # (no "signal": a spectrum over a sweep smears every order)
        Scene(
            "runup_wide",
            analyses=("transient",),
            formulation="improved",
            dof_set="planar",
            effects=("time_varying_mesh_stiffness",),
            transient=RUNUP_WIDE,
        ),
        # the run-up as an accelerometer on the ring records it
        Scene(
            "runup_sensor",
            analyses=("transient",),
            formulation="improved",
            dof_set="planar",
            effects=("time_varying_mesh_stiffness",),
            transient=RUNUP_SENSOR,
        ),
        # the same, steady at 120 rpm: without the mass-proportional damping, which brakes the
        # rigid rotation like a torque (the drive then holds 120 rpm exactly)
        Scene(
            "steady_sensor",
            analyses=("transient",),
            formulation="improved",
            dof_set="planar",
            effects=("time_varying_mesh_stiffness",),
            transient=STEADY_SENSOR,
            parameters={"damping.mass_coefficient": 0.0},
        ),
        Scene(
            "torque_reversal",
            analyses=("transient",),
            formulation="improved",
            dof_set="planar",
            effects=("time_varying_mesh_stiffness", "tooth_separation"),
            transient=TORQUE_REVERSAL,
            parameters={
                "planetary.sun_mesh.backlash": REVERSAL_BACKLASH,
                "planetary.ring_mesh.backlash": REVERSAL_BACKLASH,
            },
        ),
        # periodic steady state over the carrier speed by harmonic balance (`pygear run
        # yang2016_planetary --scene response`, docs/response.md): K_v, K_gamma, DTE and
        # Floquet stability from 100 to 1500 rpm under the run-up's 10 N m; a sweep maps
        # K_gamma over a planet pin error with --param
        # scene.response.pin_errors.planetary.planet1=...
        Scene(
            "response",
            analyses=("response",),
            formulation="improved",
            dof_set="planar",
            effects=("time_varying_mesh_stiffness",),
            # from 250 rpm: below it the mesh harmonics that reach the mesh modes need
            # more than the 128 harmonics the default tolerance allows (pygear accuracy)
            response=Response(speeds_rpm=(250.0, 1500.0, 200)),
        ),
    ),
)

# Accuracy study (`pygear accuracy yang2016_planetary`, docs/accuracy.md): the ladder of
# fidelities and time steps around the scene `runup`.
accuracy = dict(
    # s: shortened from 5 s so the whole ladder runs in minutes; t_s (0.16 s) and a 0.5 s
    # equilibrium window after the start-up still fit (ASSUMED long enough to settle)
    duration=1.5,
    mean_window=0.5,  # s: equilibrium speeds and mesh-force RMS/peak over 1.0-1.5 s
    signal_after=1.0,  # s: spectra skip the start-up, as the paper's (docs/model.md §8)
    # the paper's 2.5e-5 s is the coarsest step: the predictor diverges at 5e-5 s, and
    # the paper's 40 kHz output needs steps of 2.5e-5 s or less
    coarsest_time_step=2.5e-5,
    levels=5,  # 2.5e-5 s halving down to 1.5625e-6 s
    sample_rate=40e3,  # Hz, the paper's, for every run (same sampling instants)
    formulations=("improved", "lin-parker"),  # the paper's two models
    repeats=3,  # timed repeats per setting (median)
)
