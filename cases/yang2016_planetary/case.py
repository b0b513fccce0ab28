"""The seed paper's planetary study case (Yang, Jiang & Han 2016, section 5, Table 1).

The parameters are Lin & Parker's (1999) example; Table 1 prints them with a
"base diameter" heading, but the values are radii.  Every value not printed in the
paper is marked ASSUMED with the reason.
"""

from pygear import (
    Bearing,
    Carrier,
    Case,
    Gear,
    Gearbox,
    Mesh,
    PlanetaryStage,
    PlanetBearing,
    RayleighDamping,
    Scene,
)

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
    # end-to-peak ratio ASSUMED 0.6 external / 0.7 internal (PHYSICS.md 5)
    sun_mesh=Mesh(stiffness=5e8, pressure_angle_deg=24.6, contact_ratio=1.24, end_to_peak=0.6),
    ring_mesh=Mesh(stiffness=5e8, pressure_angle_deg=24.6, contact_ratio=1.24, end_to_peak=0.7),
    base_helix_angle_deg=0.0,  # spur (Table 1)
)

case = Case(
    name="yang2016_planetary",
    description="Planetary study case of Yang, Jiang & Han (2016), Table 1",
    gearbox=Gearbox(stages=(stage,)),
    formulation="improved",  # the seed's own model; scenes name the others
    # ASSUMED: the paper's Rayleigh coefficients were lost; alpha = 0.13 1/s reproduces
    # its Table 3 with the load law of PHYSICS.md 6, beta = 1e-6 s (PHYSICS.md 3.7)
    damping=RayleighDamping(mass_coefficient=0.13, stiffness_coefficient=1e-6),
    scenes=(
        Scene("modal", analyses=("modal",), formulation="improved", dof_set="planar"),
        Scene("modal_lin_parker", analyses=("modal",), formulation="lin-parker", dof_set="planar"),
        Scene("modal_consistent", analyses=("modal",), formulation="consistent", dof_set="planar"),
    ),
)
