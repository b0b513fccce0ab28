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
    RayleighDamping,
    RigidLink,
    Scene,
    TorsionalSpring,
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
    teeth=None,  # ASSUMED unknown: the paper gives no tooth numbers for the pair
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
    # ASSUMED as for the study case (PHYSICS.md 3.7)
    damping=RayleighDamping(mass_coefficient=0.13, stiffness_coefficient=1e-6),
    scenes=(Scene("modal", analyses=("modal",)),),
)
