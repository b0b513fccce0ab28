"""A damaged tooth follows its own pair curve in the tooth-contact table.

The reference is the potential-energy module's own mesh stiffness (fortran
tooth_potential_energy, by its summation of the pair curves, not the table's):
``MeshStiffness.mesh`` over a healthy cycle and ``faulty_mesh`` while the damaged tooth
passes, its pair entering at s = 0.  The table holds the healthy curve as its tabulated
law and the damaged tooth's curve (``faulty_curve``) for that one tooth.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pygear import (
    Bearing,
    Carrier,
    Case,
    CaseError,
    Gear,
    Gearbox,
    Mesh,
    PlanetaryStage,
    PlanetBearing,
    ToothDefect,
)
from pygear.assembly import assemble
from pygear.assembly.contact_table import (
    LAW_CODES,
    ContactTable,
    build_contact_table,
    with_tooth_curves,
)
from pygear.assembly.tooth_stiffness import ChippedTooth, RootCrack, ToothBody, mesh_stiffness
from pygear.model import GearGeometry, MeshGeometry
from pygear.model.gear_geometry import root_radius

MODULE, WIDTH = 3.2e-3, 0.016  # m: Tian's (2004) pair, as in test_potential_energy
TEETH = (19, 48)
BODIES = (ToothBody(2.068e11, 0.3, 0.010), ToothBody(2.068e11, 0.3, 0.030))
N_CYCLE = 100


def healthy_table(curve: np.ndarray, mean: float, eps: float) -> ContactTable:
    """One mesh, Z1 = 19, Z2 = 48, tooth 0 of both gears in the pair entering at s = 0."""
    return ContactTable(
        names=("mesh",),
        gears=(("pinion", "wheel"),),
        angles=(("pinion", "ground"),),
        teeth=np.array([[TEETH[0]], [TEETH[1]]], dtype=np.int32, order="F"),
        cycle_sign=np.ones(1, dtype=np.int32),
        tooth_offset=np.zeros((2, 1), dtype=np.int32, order="F"),
        mean_stiffness=np.array([mean]),
        contact_ratio=np.array([eps]),
        end_to_peak=np.array([1.0]),
        phase=np.zeros(1),
        law=np.array([LAW_CODES["tabulated"]], dtype=np.int32),
        curve_start=np.zeros(1, dtype=np.int32),
        curve_size=np.array([curve.size], dtype=np.int32),
        curve=curve,
        factor_start=np.full((2, 1), -1, dtype=np.int32, order="F"),
        factor=np.ones(1),
        max_pairs=int(math.ceil(eps)) + 1,
    )


@pytest.mark.parametrize(
    "fault", [RootCrack(1, 2e-3, 45.0), RootCrack(2, 2e-3, 45.0), ChippedTooth(1, 0.3)]
)
def test_damaged_tooth_changes_the_table_only_while_in_mesh(fault):
    """Over two turns of gear 1: the stiffness equals the healthy table wherever the
    damaged tooth is out of mesh, and the potential-energy module's faulty mesh stiffness
    while its pair is in mesh (s in [0, eps) and again one turn of its gear later).

    Tolerances: the table interpolates 2001 samples of each curve linearly (1e-6 of the
    stiffness, as in test_potential_energy); elsewhere both tables run the same
    arithmetic on the same healthy pairs (1e-12 allows any rounding order)."""
    pair = MeshGeometry(
        GearGeometry(TEETH[0], MODULE, WIDTH), GearGeometry(TEETH[1], MODULE, WIDTH)
    )
    result = mesh_stiffness(pair, BODIES, fault=fault, n_sample=2001, n_cycle=N_CYCLE)
    curve, mean, eps = result.tabulated_curve()
    healthy = healthy_table(curve, mean, eps)
    damaged = with_tooth_curves(healthy, {(0, fault.gear, 0): result.faulty_curve()})
    turn = TEETH[fault.gear - 1]  # the damaged tooth is back after Z of its gear's cycles
    cycle = np.arange(-2 * N_CYCLE, (turn + 3) * N_CYCLE) / N_CYCLE
    theta = 2 * np.pi * cycle[:, None] / TEETH[0]
    with_damage = damaged.series(theta)["stiffness"][:, 0]
    without = healthy.series(theta)["stiffness"][:, 0]

    in_mesh = ((cycle >= 0) & (cycle < eps)) | ((cycle >= turn) & (cycle < turn + eps))
    np.testing.assert_allclose(with_damage[~in_mesh], without[~in_mesh], rtol=1e-12)
    assert np.max(np.abs(with_damage[in_mesh] / without[in_mesh] - 1)) > 1e-3  # it shows

    window = result.window_position  # [0, ceil(eps)), the damaged pair entering at 0
    for start in (0, turn):
        index = np.round((start + window) * N_CYCLE).astype(int) + 2 * N_CYCLE
        np.testing.assert_allclose(with_damage[index], result.faulty_mesh, rtol=1e-6)
    outside = (cycle >= 2) & (cycle < 3)  # a healthy cycle, against the module's own
    np.testing.assert_allclose(
        with_damage[outside], np.interp(cycle[outside] % 1, result.cycle_position, result.mesh),
        rtol=1e-6,
    )  # fmt: skip


def test_tooth_curve_keys_are_checked():
    """A curve for a tooth or gear the mesh does not have is refused before the kernel."""
    pair = MeshGeometry(
        GearGeometry(TEETH[0], MODULE, WIDTH), GearGeometry(TEETH[1], MODULE, WIDTH)
    )
    result = mesh_stiffness(pair, BODIES, n_sample=11)
    table = healthy_table(*result.tabulated_curve())
    with pytest.raises(ValueError, match="tooth not in 0 .. 18"):
        with_tooth_curves(table, {(0, 1, 19): result.faulty_curve()})
    with pytest.raises(ValueError, match="no such mesh and gear"):
        with_tooth_curves(table, {(0, 3, 0): result.faulty_curve()})


# --- a case's ToothDefect(fault=...) ---------------------------------------------------------

SUN, PLANET, RING = 21, 27, 75  # teeth of a 3 mm module stage at the standard centre distance
STAGE_MODULE, STAGE_WIDTH = 3e-3, 40e-3  # m


def geometry_case(defect: ToothDefect, *, geometry: bool = True) -> Case:
    """A spur planetary stage built from gear geometry (potential-energy law), or with
    typed radii and stiffness (no geometry), holding ``defect``."""
    gear = dict(normal_module=STAGE_MODULE, face_width=STAGE_WIDTH)
    shapes = {
        "sun": GearGeometry(SUN, **gear),
        "planet": GearGeometry(PLANET, **gear),
        "ring": GearGeometry(RING, internal=True, tip_alteration=-0.2, **gear),
    }
    alpha = math.radians(20.0)
    radius = {
        n: STAGE_MODULE * z / 2 * math.cos(alpha) for n, z in zip(shapes, (SUN, PLANET, RING))
    }
    teeth = {"sun": SUN, "planet": PLANET, "ring": RING}

    def member(name: str, mass: float, inertia: float) -> Gear:
        if geometry:
            return Gear(mass=mass, polar_inertia=inertia, tilt_inertia=inertia / 2,
                        geometry=shapes[name])  # fmt: skip
        return Gear(mass=mass, polar_inertia=inertia, tilt_inertia=inertia / 2,
                    base_radius=radius[name], teeth=teeth[name])  # fmt: skip

    mesh = (
        Mesh(law="potential_energy")
        if geometry
        else Mesh(stiffness=4e8, pressure_angle_deg=20.0, contact_ratio=1.6)
    )
    stage = PlanetaryStage(
        name="stage",
        carrier=Carrier(
            mass=6.0,
            polar_inertia=0.07,
            tilt_inertia=0.04,
            radius=(SUN + PLANET) * STAGE_MODULE / 2,
        ),  # fmt: skip
        ring=member("ring", 3.0, 0.06),
        sun=member("sun", 0.8, 2e-3),
        planet=member("planet", 0.3, 1e-4),
        planets=3,
        carrier_bearing=Bearing(radial=2e8, axial=1.5e8, tilt=3e6, torsional=0.0),
        ring_bearing=Bearing(radial=3e8, axial=2e8, tilt=4e6, torsional=5e7),
        sun_bearing=Bearing(radial=1e8, axial=1e8, tilt=2e6, torsional=0.0),
        planet_bearing=PlanetBearing(radial=1.2e8, axial=0.9e8, tilt=1.5e6),
        sun_mesh=mesh,
        ring_mesh=mesh,
    )
    return Case(name="faulty", gearbox=Gearbox(stages=(stage,)), defects=(defect,))


def test_a_case_fault_puts_the_damaged_curve_into_each_mesh_of_the_tooth():
    """A root crack on sun tooth 0: each sun-planet mesh holds, for sun tooth 0, the pair
    curve the potential-energy method gives with the crack on the sun (gear 1 of the
    (sun, planet) geometry, the planet driving: carrier in, sun out); the ring meshes
    hold none.  A planet tooth's crack reaches both of its meshes, on the geometry's
    planet side (gear 2 of (sun, planet), gear 1 of (planet, ring))."""
    crack = RootCrack(1, 1.5e-3, 45.0)
    case = geometry_case(ToothDefect("stage.sun", 0, fault=crack))
    table = build_contact_table(case, assemble(case))
    stage = case.gearbox.stages[0]
    bodies = tuple(
        ToothBody(206e9, 0.3, 0.5 * root_radius(g.geometry)) for g in (stage.sun, stage.planet)
    )
    geometry = MeshGeometry(stage.sun.geometry, stage.planet.geometry,
                            centre_distance=stage.carrier.radius)  # fmt: skip
    expected = mesh_stiffness(geometry, bodies, fault=crack, driving_gear=2).faulty_curve()
    for m, name in enumerate(table.names):
        block = table.tooth_curve_block[:, m]
        if name.startswith("ring"):
            assert (block == -1).all()
            continue
        assert block[1] == -1 and block[0] >= 0  # gear 1 of the table: the sun
        start, size = table.tooth_curve_start[block[0]], table.tooth_curve_size[block[0]]
        np.testing.assert_allclose(table.curve[start : start + size], expected, rtol=1e-12)
        assert (table.tooth_curve_size[block[0] + 1 : block[0] + SUN] == 0).all()

    planet_case = geometry_case(ToothDefect("stage.planet2", 3, fault=crack))
    planet_table = build_contact_table(planet_case, assemble(planet_case))
    for m, name in enumerate(planet_table.names):
        block = planet_table.tooth_curve_block[:, m]
        if name.endswith("planet2"):
            assert block[0] == -1 and block[1] >= 0  # gear 2 of the table: the planet
            assert planet_table.tooth_curve_size[block[1] + 3] > 0
        else:
            assert (block == -1).all()


def test_a_fault_without_gear_geometry_is_refused():
    case = geometry_case(
        ToothDefect("stage.sun", 0, fault=RootCrack(1, 1e-3, 45.0)), geometry=False
    )
    with pytest.raises(CaseError, match=r"fault needs gear geometry on both gears of the mesh"):
        build_contact_table(case, assemble(case))
    with pytest.raises(CaseError, match=r"fault must be a RootCrack, Spall or ChippedTooth"):
        ToothDefect("stage.sun", 0, fault="crack").validate("defects[0]")
