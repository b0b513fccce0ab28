"""The sequentially phased planetary stage running its loaded tooth contact.

The stage, bodies, sensor and time step of cases/sequential_planetary (imported from
that case), its two meshes on the ``loaded_contact`` law: the loaded tooth contact of
each pair with the gears' micro-geometry, tabulated once per mesh over position and
load at the operating line load, enters the time loop and the harmonic balance as its
secant stiffness with the unloaded TE as a displacement excitation (docs/contact.md,
"The loaded contact as a mesh law").  The
carrier torque is ten times the sequential case's, a line load of 313 N/mm (an
industrial gear's), so that the flanks' micro-geometry and deviations of a few
micrometres stay below the mesh's static deflection (about 18 um).

Scenes: ``steady_sensor`` (tip relief on sun and planet), ``unmodified`` (perfect
flanks: the potential-energy pair), ``sun_pitch_error`` (a single pitch deviation on
sun tooth 0: once per turn of the sun relative to the carrier in the mesh force, and
sidebands of the mesh frequency in the ring sensor's spectrum) and ``response`` (the
harmonic balance over speed).  Everything not taken from the sequential case is
ASSUMED, with its reason beside it.
"""

import dataclasses
import importlib.util
import math
from pathlib import Path

from pygear import Response, Scene, TorqueLaw
from pygear.assembly.ltca_geometry import flank_roll_limits
from pygear.model.gear_geometry import transverse_contact_ratio
from pygear.model.geometry_inputs import planetary_mesh_geometry
from pygear.model.micro_geometry import Deviations, Modifications, ProfileRelief

_spec = importlib.util.spec_from_file_location(
    "sequential_planetary_case",
    Path(__file__).parent.parent / "sequential_planetary" / "case.py",
)
_sequential = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_sequential)
S = _sequential

CARRIER_TORQUE = 5000.0  # N m, ASSUMED: 313 N/mm on the sun meshes, an industrial load
SUN_TORQUE = CARRIER_TORQUE / (1 + S.TEETH["ring"] / S.TEETH["sun"])
SUN_BASE_RADIUS = S.stage.sun.base_radius
# the mesh force of one planet's sun mesh along the line of action, per face width [N/mm]:
# the loaded_contact law's operating load (both meshes carry the same tangential force)
LINE_LOAD = SUN_TORQUE / (S.stage.planets * SUN_BASE_RADIUS) / S.FACE_WIDTH / 1e3


def tip_relief(member: str, amount: float) -> ProfileRelief:
    """Linear tip relief over the double-contact zone at the tip: the last
    (eps_alpha - 1) base pitches of the gear's roll length."""
    geometry = S.geometry(member)
    tip, _, base_radius = flank_roll_limits(geometry)
    pitch = 2 * math.pi * base_radius / geometry.teeth
    start = tip - (CONTACT_RATIO - 1) * pitch
    return ProfileRelief(amount=amount, start_roll_angle_deg=math.degrees(start / base_radius))


# eps_alpha of the sun mesh, from the geometry (1.663)
CONTACT_RATIO = transverse_contact_ratio(planetary_mesh_geometry(S.stage, "sun"))
# ASSUMED: 25 um, about the single-pair deflection at the operating load (27 um; Harris
# 1958); the planet's relief acts on both of its meshes
RELIEF = 25e-6
SUN_MODS = Modifications(tip_relief=tip_relief("sun", RELIEF))
PLANET_MODS = Modifications(tip_relief=tip_relief("planet", RELIEF))
# ASSUMED: 5 um single pitch deviation of sun tooth 0 (ISO 1328-1 grade 5 to 6 at this size)
PITCH_DEVIATION = 5e-6
PITCHED_SUN = dataclasses.replace(
    SUN_MODS,
    deviations=Deviations(pitch=(PITCH_DEVIATION,) + (0.0,) * (S.TEETH["sun"] - 1)),
)

stage = dataclasses.replace(
    S.stage,
    sun=dataclasses.replace(S.stage.sun, modifications=SUN_MODS),
    planet=dataclasses.replace(S.stage.planet, modifications=PLANET_MODS),
    sun_mesh=dataclasses.replace(S.stage.sun_mesh, law="loaded_contact", line_load=LINE_LOAD),
    ring_mesh=dataclasses.replace(S.stage.ring_mesh, law="loaded_contact", line_load=LINE_LOAD),
)

STEADY = dataclasses.replace(
    S.STEADY,
    duration=3.5,  # s: 7 carrier turns, 23 turns of the sun on the carrier
    drive=TorqueLaw.constant(CARRIER_TORQUE),
    load=TorqueLaw.generator(rated_drive_torque=CARRIER_TORQUE, exponent=2.0),
    mean_window=1.0,
)


def steady(name: str, parameters: dict | None = None) -> Scene:
    """A steady scene of the stage at 120 rpm with the ring sensor."""
    return Scene(
        name,
        analyses=("transient",),
        dof_set="planar",
        effects=("time_varying_mesh_stiffness",),
        transient=STEADY,
        parameters=parameters or {},
    )


case = dataclasses.replace(
    S.case,
    name="loaded_contact_planetary",
    description="Sequential planetary stage on its loaded tooth contact (ASSUMED sizes)",
    gearbox=dataclasses.replace(S.case.gearbox, stages=(stage,)),
    scenes=(
        Scene("modal", analyses=("modal",), dof_set="planar"),
        steady("steady_sensor"),
        steady("unmodified", {"planetary.sun.modifications": Modifications(),
                              "planetary.planet.modifications": Modifications()}),
        steady("sun_pitch_error", {"planetary.sun.modifications": PITCHED_SUN}),
        Scene(
            "response",
            analyses=("response",),
            dof_set="planar",
            effects=("time_varying_mesh_stiffness",),
            transient=STEADY,
            # ASSUMED: carrier 30 to 300 rpm, the 194 Hz mesh frequency's tenth to 2.5 times
            response=Response(speeds_rpm=(30.0, 300.0, 16), harmonics=32),
        ),
    ),
)
