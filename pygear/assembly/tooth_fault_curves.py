"""Pair curves of damaged teeth for the tooth-contact table (``ToothDefect(fault=...)``).

For every mesh a defective tooth meets, the potential-energy method
(:func:`pygear.assembly.tooth_stiffness.mesh_stiffness`) computes the mesh's pair curve
with the fault on that tooth; :meth:`MeshStiffness.faulty_curve` puts it on the scale of
the healthy curve (unit mean), and the table reads it as k_pair = (k-bar / eps) c(p)
with the mesh's own k-bar and contact ratio.  With the ``potential_energy`` law this is
the damaged pair itself; with another law the damaged-to-healthy shape of the geometry
is carried over to that law's mean stiffness (an approximation the docs state).

The mesh geometry orders the gears (sun, planet), (planet, ring) or (input, output);
the table's gear 1 is the central member (sun or ring) or the input gear, so the fault
goes to the geometry's side of the defective gear.  The curve is computed for power
from the carrier to the sun (or input to output), as the mesh law's is, and reversed
along the path of contact for the other flow.

:func:`deviation_curves` does the same for the single pitch deviations and the runout
of a gear on a ``loaded_contact`` mesh: the loaded contact tabulated over a revolution
of that gear gives every one of its teeth its own pair curve
(:func:`pygear.assembly.loaded_contact_table.tooth_pair_curves`), so the mesh stiffness
repeats once per revolution of the gear, not once per mesh cycle.  Every planet of a
stage shares the planet's ``Gear`` and so its deviations, tooth for tooth.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import CaseError
from ..model.case import Case
from ..model.components import ToothDefect
from ..model.gearbox import ParallelStage
from .loaded_contact_table import operating_force, tooth_pair_curves
from .mesh_laws import mesh_law, tooth_bodies
from .tooth_stiffness import mesh_stiffness

__all__ = ["deviation_curves", "fault_curves"]


def _geometry_gears(stage: object, member: str) -> tuple[tuple[str, str], int]:
    """The (gear 1, gear 2) members of a mesh's geometry and its driving gear (as
    :func:`pygear.assembly.mesh_laws.mesh_law` computes the healthy curve)."""
    if isinstance(stage, ParallelStage):
        return ("input_gear", "output_gear"), 1
    planet = "planet"
    return ((member, planet) if member == "sun" else (planet, "ring")), 2


def fault_curves(
    case: Case,
    meshes: list[tuple[str, str, tuple[str, str]]],
    defects: tuple[ToothDefect, ...],
    sun_driven: bool,
) -> dict[tuple[int, int, int], np.ndarray]:
    """The damaged teeth's pair curves, keyed as :func:`with_tooth_curves` takes them.

    Parameters
    ----------
    case : Case
        The case.
    meshes : list of (stage, member, (gear 1, gear 2))
        The table's meshes in order: stage name, ``sun``/``ring``/``mesh`` and the
        table's gear names (``stage.sun``, ``stage.planet2``).
    defects : tuple of ToothDefect
        The case's and scene's defects; those without a fault are skipped.
    sun_driven : bool
        The power flow (see :func:`pygear.assembly.contact_table.build_contact_table`).

    Raises
    ------
    CaseError
        A mesh of a faulty tooth has no gear geometry on both gears, or the fault does
        not fit the tooth (the potential-energy method's message).
    """
    curves: dict[tuple[int, int, int], np.ndarray] = {}
    for index, defect in enumerate(defects):
        if defect.fault is None:
            continue
        for m, (stage_name, member, gears) in enumerate(meshes):
            if defect.gear not in gears:
                continue
            stage = case.gearbox.stage(stage_name)
            law = mesh_law(stage, member)
            path = f"defects[{index}] ({defect.gear} tooth {defect.tooth})"
            if law.geometry is None:
                raise CaseError(
                    f"{path}.fault needs gear geometry on both gears of the mesh "
                    f"{stage_name}.{member if member == 'mesh' else member + '_mesh'}"
                )
            members, driving = _geometry_gears(stage, member)
            side = 1 if defect.member.startswith(members[0]) else 2
            component = stage.mesh if member == "mesh" else getattr(stage, f"{member}_mesh")
            radii = tuple(getattr(stage, name).foundation_radius for name in members)
            bodies = tooth_bodies(component, law.geometry, radii)
            result = mesh_stiffness(
                law.geometry,
                bodies,
                fault=dataclasses.replace(defect.fault, gear=side),
                driving_gear=driving,
                path=path,
            )
            curve = result.faulty_curve()
            if not sun_driven:
                curve = np.ascontiguousarray(curve[::-1])
            curves[(m, gears.index(defect.gear) + 1, int(defect.tooth))] = curve
    return curves


def _per_tooth(gear: object) -> bool:
    """True when the gear's deviations differ tooth by tooth (pitch or runout)."""
    mods = getattr(gear, "modifications", None)
    deviations = mods.deviations if mods is not None else None
    return deviations is not None and bool(deviations.pitch or deviations.runout)


def deviation_curves(
    case: Case,
    meshes: list[tuple[str, str, tuple[str, str]]],
    sun_driven: bool,
) -> dict[tuple[int, int, int], np.ndarray]:
    """Every tooth's pair curve on ``loaded_contact`` meshes whose gear has single pitch
    deviations or runout, keyed as :func:`with_tooth_curves` takes them.

    Parameters
    ----------
    case : Case
        The case.
    meshes : list of (stage, member, (gear 1, gear 2))
        The table's meshes in order, as for :func:`fault_curves`.
    sun_driven : bool
        The power flow: curves are reversed along the path for the other flow.

    Raises
    ------
    CaseError
        Both gears of a mesh carry per-tooth deviations (their common period would be
        the least common multiple of the tooth numbers; give them to one gear).
    """
    curves: dict[tuple[int, int, int], np.ndarray] = {}
    for m, (stage_name, member, gears) in enumerate(meshes):
        stage = case.gearbox.stage(stage_name)
        law = mesh_law(stage, member)
        if law.law != "loaded_contact" or law.geometry is None:
            continue
        members, driving = _geometry_gears(stage, member)
        objects = tuple(getattr(stage, name) for name in members)
        sides = [side for side, gear in enumerate(objects, start=1) if _per_tooth(gear)]
        if not sides:
            continue
        path = f"{stage_name}.{member if member == 'mesh' else member + '_mesh'}"
        if len(sides) == 2:
            raise CaseError(
                f"{path}: both gears carry single pitch deviations or runout; the loaded "
                "contact takes the per-tooth deviations of one gear per mesh"
            )
        side = sides[0]
        component = stage.mesh if member == "mesh" else getattr(stage, f"{member}_mesh")
        radii = tuple(gear.foundation_radius for gear in objects)
        bodies = tooth_bodies(component, law.geometry, radii)
        mods = tuple(getattr(gear, "modifications", None) for gear in objects)
        teeth = tooth_pair_curves(
            law.geometry, bodies, mods, operating_force(law.geometry, component.line_load),
            side, driving_gear=driving, path=path, samples=law.curve.size,
        )  # fmt: skip
        # the tabulated law's scale: k_pair = (k-bar / eps) c(p)
        teeth = teeth / (law.mean_stiffness / law.contact_ratio)
        if not sun_driven:
            teeth = np.ascontiguousarray(teeth[:, ::-1])
        name = members[side - 1]
        index = 2 if name == "planet" else 1 + [g.split(".", 1)[1] for g in gears].index(name)
        for tooth, curve in enumerate(teeth):
            curves[(m, index, tooth)] = curve
    return curves
