"""The seed paper's gearbox (Yang, Jiang & Han 2016, section 6): two planetary stages and
a helical parallel stage.

Stage 1 is the study case with 4 planets, stage 2 the study case with 3 (Table 1); the
parallel stage follows Table 4.  Stage 1's sun turns rigidly with stage 2's carrier, and
stage 2's sun drives the parallel stage's input gear through a torsional spring.  Every
value the paper lost is marked ASSUMED with the reason.
"""

import dataclasses
import importlib.util
from pathlib import Path

from pygear import (
    Bearing,
    Case,
    Gear,
    Gearbox,
    Mesh,
    ParallelStage,
    Probe,
    RayleighDamping,
    RigidLink,
    Scene,
    TorqueLaw,
    TorsionalSpring,
    Transient,
)

# The planetary stages reuse the study case's stage unchanged (Table 1).
_spec = importlib.util.spec_from_file_location(
    "yang2016_planetary_case", Path(__file__).parent.parent / "yang2016_planetary" / "case.py"
)
_study = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_study)

stage1 = dataclasses.replace(
    _study.stage,
    name="stage1",
    planets=4,
    # ASSUMED: with Z_s = 27 and Z_r = 96, (Z_s + Z_r)/4 is not a whole number, so four
    # equally spaced planets cannot be assembled; Z_r = 97 = Z_s + 2 Z_p (standard gears)
    # can. Tooth numbers only set mesh frequencies and phases: the rigid model's ratios
    # use the base radii, which stay as in Table 1.
    ring=dataclasses.replace(_study.stage.ring, teeth=97),
    axial_position=0.0,
)
stage2 = dataclasses.replace(_study.stage, name="stage2", axial_position=0.3)  # m, ASSUMED

GEAR_MASS = 2.0  # kg, Table 4
GEAR_BASE_RADIUS = 50e-3  # m, Table 4 ("radius")
# ASSUMED: solid discs, I_p = m r^2 / 2 and I_t = I_p / 2 (Table 4's inertias were lost)
GEAR_POLAR_INERTIA = 0.5 * GEAR_MASS * GEAR_BASE_RADIUS**2
parallel_gear = Gear(
    mass=GEAR_MASS,
    polar_inertia=GEAR_POLAR_INERTIA,
    tilt_inertia=GEAR_POLAR_INERTIA / 2,
    base_radius=GEAR_BASE_RADIUS,
    # ASSUMED: the paper gives no tooth numbers for the pair. Table 4's 21.173 deg is the
    # transverse pressure angle of a 20 deg normal angle at a 20 deg helix, so the
    # reference radius is r_b / cos(21.173 deg) = 53.6 mm; a normal module of about
    # 3 mm then gives Z = 2 r cos(20 deg) / m_n = 34 (and an overlap ratio of 0.37
    # for a 10 mm face width).
    teeth=34,
)
# ASSUMED: Table 4's bearing stiffnesses were lost; the planetary stages' 1e8 N/m
# radially and axially, and 1e6 N m/rad in tilt; both gears turn freely.
parallel_bearing = Bearing(radial=1e8, axial=1e8, tilt=1e6, torsional=0.0)
parallel = ParallelStage(
    name="parallel",
    input_gear=parallel_gear,
    output_gear=parallel_gear,
    input_bearing=parallel_bearing,
    output_bearing=parallel_bearing,
    # ASSUMED: mesh stiffness 5e8 N/m like the planetary meshes (Table 4's was lost);
    # pressure angle 21.173 deg, transverse contact ratio 1.58 (Table 4)
    mesh=Mesh(stiffness=5e8, pressure_angle_deg=21.173, contact_ratio=1.58, end_to_peak=0.6),
    overlap_ratio=0.37,  # Table 4
    base_helix_angle_deg=20.0,  # Table 4 gives 20 deg; taken as the base helix angle
    centre_angle_deg=0.0,
    axial_position=0.6,  # m, ASSUMED
)

# ASSUMED: the coupling spring's stiffness was lost; 1e6 N m/rad is a stiff shaft.
COUPLING_STIFFNESS = 1e6  # N m/rad

# Run-up (paper section 6, Tables 7 and 8, Figures 18 and 19; docs/model.md §6.3): from rest, a
# constant drive torque on stage 1's carrier; the parallel stage's output gear carries the
# load law T_L = (T_D/i)(w_out/(i w_0))^n from t_s on, i = w_out/w_in = -20.73 from the
# kinematics (the parallel pair reverses the sense; the law brakes the actual rotation).
RUNUP_SPEED_RPM = 60.0  # omega_0 [rpm]: Tables 7/8 show the first carrier at 59.86 rpm
# ASSUMED (lost): T_D chosen so that the damped theory of docs/model.md §6.3 gives the paper's
# t_s = 0.327 s with this file's inertias (J_eq = 4.864 kg m^2 reduced to the input):
# T_D = alpha J_eq w_0 / (1 - exp(-alpha t_s)).
DRIVE_TORQUE = 95.5  # N m
LOAD_EXPONENT = 2.0  # n of the load law, ASSUMED as for the study case (docs/model.md §6.3)
RUNUP = Transient(
    duration=4.0,  # s: long enough for t_s, settling and a 1 s averaging window
    time_step=2.5e-5,  # s, as the paper's study case
    sample_rate=40e3,  # Hz, as the paper's study case
    integrator="newmark",  # average acceleration (docs/model.md §6.1)
    equivalent_load="predictor",  # the paper's explicit mesh term (eq. 25)
    input="stage1.carrier.theta_z",
    output="parallel.output_gear.theta_z",
    drive=TorqueLaw.constant(DRIVE_TORQUE),
    load=TorqueLaw.generator(rated_drive_torque=DRIVE_TORQUE, exponent=LOAD_EXPONENT),
    speed_reference_rpm=RUNUP_SPEED_RPM,
    probes=(
        Probe("speed", "stage1.carrier"),
        Probe("speed", "stage1.sun"),
        Probe("speed", "stage1.planet1"),  # spin relative to the carrier
        Probe("speed", "stage2.carrier"),
        Probe("speed", "stage2.sun"),
        Probe("speed", "stage2.planet1"),
        Probe("speed", "parallel.input_gear"),
        Probe("speed", "parallel.output_gear"),
        Probe("acceleration", "stage1.ring.y"),  # seed Fig. 18
        Probe("acceleration", "parallel.output_gear.theta_z"),  # seed Fig. 19
        Probe("mesh_force", "stage1.sun-planet1"),
        Probe("mesh_force", "stage1.ring-planet1"),
        Probe("mesh_force", "stage2.sun-planet1"),
        Probe("mesh_force", "stage2.ring-planet1"),
        Probe("mesh_force", "parallel.input-output"),
        Probe("drive_torque"),
        Probe("load_torque"),
    ),
    mean_window=1.0,  # s: equilibrium speeds are means over the last 1 s
)

case = Case(
    name="yang2016_gearbox",
    description="Gearbox of Yang, Jiang & Han (2016), section 6",
    gearbox=Gearbox(
        stages=(stage1, stage2, parallel),
        couplings=(
            RigidLink("stage1.sun.theta_z", "stage2.carrier.theta_z"),
            TorsionalSpring(
                "stage2_to_parallel",
                "stage2.sun.theta_z",
                "parallel.input_gear.theta_z",
                stiffness=COUPLING_STIFFNESS,
            ),
        ),
        input_dof="stage1.carrier.theta_z",
        output_dof="parallel.output_gear.theta_z",
    ),
    formulation="improved",  # the paper's model
    # ASSUMED as for the study case (docs/model.md §3.7)
    damping=RayleighDamping(mass_coefficient=0.13, stiffness_coefficient=1e-6),
    scenes=(
        Scene("modal", analyses=("modal",)),
        # Table 7: constant (mean) mesh stiffness
        Scene("runup", analyses=("transient", "signal"), transient=RUNUP),
        # Table 8: time-varying mesh stiffness of every mesh, the parallel pair's by its
        # helical contact-line length (docs/model.md §5.2)
        Scene(
            "runup_tv",
            analyses=("transient", "signal"),
            effects=("time_varying_mesh_stiffness",),
            transient=RUNUP,
        ),
    ),
)

# Accuracy study (`pygear accuracy yang2016_gearbox`, docs/accuracy.md): the ladder of
# fidelities and time steps around the scene `runup`.
accuracy = dict(
    # s: shortened from 4 s so the ladder runs in minutes; t_s (0.33 s) and a 0.5 s
    # equilibrium window still fit (ASSUMED long enough to settle)
    duration=1.5,
    mean_window=0.5,  # s: equilibrium speeds and mesh-force RMS/peak over 1.0-1.5 s
    signal_after=1.0,  # s: spectra skip the start-up (docs/model.md §8)
    coarsest_time_step=2.5e-5,  # s, the paper's step as the coarsest
    levels=4,  # 2.5e-5 s halving down to 3.125e-6 s
    sample_rate=40e3,  # Hz, every run sampled at the same instants
    formulations=("improved",),  # lin-parker describes a single stage only
    repeats=1,  # one timed run per setting keeps the 89-DOF rungs within minutes
)
