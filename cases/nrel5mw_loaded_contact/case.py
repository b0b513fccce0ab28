"""The NREL 5 MW reference gearbox with every mesh on its loaded tooth contact.

The gearbox, rotor, generator and run-up of cases/nrel5mw_gearbox (imported from that
case, with its sources), its five meshes (two planetary stages and the helical pair) on
the ``loaded_contact`` law: each pair's loaded tooth contact with the gears'
micro-geometry, tabulated once per mesh at its rated mesh force, enters the run-up as
its secant stiffness with the unloaded TE as a displacement excitation (docs/contact.md,
"The loaded contact as a mesh law").  The
operating line loads follow from the rated rotor torque through the tooth counts; the
micro-geometry is ASSUMED (the references give none), its reasons beside it.
"""

import dataclasses
import importlib.util
from pathlib import Path

from pygear.model.micro_geometry import Modifications

_spec = importlib.util.spec_from_file_location(
    "nrel5mw_gearbox_case", Path(__file__).parent.parent / "nrel5mw_gearbox" / "case.py"
)
_gearbox_case = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_gearbox_case)
G = _gearbox_case

PLANETS = 3  # every planetary stage [P-V]


def planetary_line_load(stage, carrier_torque: float) -> tuple[float, float]:
    """The sun torque and the line load [N/mm] of a planetary stage's meshes at a carrier
    torque: T_s = T_c / (1 + Z_r / Z_s), F = T_s / (N r_bs) on each sun and ring mesh,
    over the common face width of sun and planet."""
    sun_torque = carrier_torque / (1 + stage.ring.teeth / stage.sun.teeth)
    force = sun_torque / (PLANETS * stage.sun.base_radius)
    width = min(stage.sun.geometry.face_width, stage.planet.geometry.face_width)
    return sun_torque, force / width / 1e3


STAGE1_SUN_TORQUE, STAGE1_LINE_LOAD = planetary_line_load(G.stage1, G.RATED_ROTOR_TORQUE)
STAGE2_SUN_TORQUE, STAGE2_LINE_LOAD = planetary_line_load(G.stage2, STAGE1_SUN_TORQUE)
# the helical pair: the wheel (input gear) takes stage 2's sun torque
PARALLEL_LINE_LOAD = (
    STAGE2_SUN_TORQUE
    / G.parallel.input_gear.base_radius
    / min(G.parallel.input_gear.geometry.face_width, G.parallel.output_gear.geometry.face_width)
    / 1e3
)

# ASSUMED: 10 um crowning of every sun and of the helical pinion, a usual allowance of
# wind-turbine gear stages for shaft and carrier deflections (the references give none)
CROWNED = Modifications(crowning=10e-6)


def on_loaded_contact(stage, line_load: float):
    """A stage whose meshes run the loaded_contact law at ``line_load`` [N/mm]."""
    if stage is G.parallel:
        return dataclasses.replace(
            stage,
            output_gear=dataclasses.replace(stage.output_gear, modifications=CROWNED),
            mesh=dataclasses.replace(stage.mesh, law="loaded_contact", line_load=line_load),
        )
    return dataclasses.replace(
        stage,
        sun=dataclasses.replace(stage.sun, modifications=CROWNED),
        sun_mesh=dataclasses.replace(stage.sun_mesh, law="loaded_contact", line_load=line_load),
        ring_mesh=dataclasses.replace(stage.ring_mesh, law="loaded_contact", line_load=line_load),
    )


LINE_LOADS = {"stage1": STAGE1_LINE_LOAD, "stage2": STAGE2_LINE_LOAD,
              "parallel": PARALLEL_LINE_LOAD}  # fmt: skip
stages = tuple(
    on_loaded_contact(stage, LINE_LOADS[stage.name]) if stage.name in LINE_LOADS else stage
    for stage in G.case.gearbox.stages
)
case = dataclasses.replace(
    G.case,
    name="nrel5mw_loaded_contact",
    description="NREL 5 MW gearbox, every mesh on its loaded tooth contact (crowned suns)",
    gearbox=dataclasses.replace(G.case.gearbox, stages=stages),
    scenes=tuple(s for s in G.case.scenes if s.name in ("modal", "runup")),
)
