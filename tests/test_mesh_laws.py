"""Gear geometry in a case and the mesh stiffness laws it feeds (pygear.assembly.mesh_laws).

The stage: 3 planets, sun 21 / planet 27 / ring 75 teeth, m = 3 mm, alpha_n = 20 deg,
b = 40 mm, standard basic rack, no profile shift, carrier radius (Z_s + Z_p) m / 2 =
72 mm.  Z_r = Z_s + 2 Z_p (coaxial at x = 0) and (Z_s + Z_r)/3 = 32 (equally spaced
planets assemble).  The ring's tips are shortened by 0.2 m (tip_alteration): a standard
ring tip meets this planet below its root form circle (docs/gear_geometry.md, rule 6).
References are hand calculations (ISO 21771 formulas written out here), the ISO 6336
and potential-energy callers the laws wrap, and the closed form of the helical
contact-line length.
"""

from __future__ import annotations

import dataclasses
import json
import math
import textwrap
from pathlib import Path

import numpy as np
import pytest
from conftest import consistent_stage

from pygear import (
    Bearing,
    Carrier,
    Case,
    CaseError,
    Gear,
    Gearbox,
    Mesh,
    ParallelStage,
    PlanetaryStage,
    PlanetBearing,
)
from pygear.analysis.contact.mesh_stiffness import mesh_stiffness_at_constant_speed
from pygear.assembly.contact_table import build_contact_table
from pygear.assembly.matrices import assemble
from pygear.assembly.mesh_laws import LAW_CODES, mesh_law
from pygear.assembly.mesh_stiffness_laws import iso6336_mesh_stiffness
from pygear.assembly.tooth_stiffness import ToothBody
from pygear.assembly.tooth_stiffness import mesh_stiffness as potential_energy
from pygear.cli.parser import main
from pygear.model.case import replace_parameter
from pygear.model.gear_geometry import GearGeometry, MeshGeometry, root_radius

TEETH = {"sun": 21, "planet": 27, "ring": 75}
PLANETS = 3
MODULE = 3e-3  # m
ALPHA = math.radians(20.0)
WIDTH = 40e-3  # m
CARRIER_RADIUS = (TEETH["sun"] + TEETH["planet"]) * MODULE / 2  # 72 mm
RING_TIP_ALTERATION = -0.2
HELIX_DEG = 15.0
ONE_OVERLAP_WIDTH = math.pi * MODULE / math.sin(math.radians(HELIX_DEG))
"""b with eps_beta = b sin(beta) / (pi m_n) = 1 exactly."""


def geometries(helix_deg: float = 0.0, width: float = WIDTH) -> dict[str, GearGeometry]:
    """Sun, planet and ring; the sun right-handed, the planet and ring left-handed."""
    return {
        "sun": GearGeometry(TEETH["sun"], MODULE, width, helix_angle_deg=helix_deg),
        "planet": GearGeometry(TEETH["planet"], MODULE, width, helix_angle_deg=-helix_deg),
        "ring": GearGeometry(
            TEETH["ring"],
            MODULE,
            width,
            helix_angle_deg=-helix_deg,
            internal=True,
            tip_alteration=RING_TIP_ALTERATION,
        ),
    }


def geometry_stage(
    *,
    helix_deg: float = 0.0,
    width: float = WIDTH,
    carrier_radius: float | None = CARRIER_RADIUS,
    sun: dict | None = None,
    **mesh: object,
) -> PlanetaryStage:
    """The test stage built from gear geometry; ``mesh`` goes to both meshes (default
    law iso6336), ``sun`` to the sun's Gear."""
    gears = geometries(helix_deg, width)
    mesh = {"law": "iso6336", **mesh}
    carrier = dict(mass=6.0, polar_inertia=0.07, tilt_inertia=0.04)
    if carrier_radius is not None:
        carrier["radius"] = carrier_radius
    return PlanetaryStage(
        name="stage",
        carrier=Carrier(**carrier),
        ring=Gear(mass=3.0, polar_inertia=0.06, tilt_inertia=0.03, geometry=gears["ring"]),
        sun=Gear(
            mass=0.8,
            polar_inertia=2.0e-3,
            tilt_inertia=1.1e-3,
            geometry=gears["sun"],
            **(sun or {}),
        ),
        planet=Gear(mass=0.3, polar_inertia=1.0e-4, tilt_inertia=0.6e-4, geometry=gears["planet"]),
        planets=PLANETS,
        carrier_bearing=Bearing(radial=2e8, axial=1.5e8, tilt=3e6, torsional=0.0),
        ring_bearing=Bearing(radial=3e8, axial=2e8, tilt=4e6, torsional=5e7),
        sun_bearing=Bearing(radial=1e8, axial=1e8, tilt=2e6, torsional=0.0),
        planet_bearing=PlanetBearing(radial=1.2e8, axial=0.9e8, tilt=1.5e6),
        sun_mesh=Mesh(**mesh),
        ring_mesh=Mesh(**mesh),
    )


def case_of(stage: PlanetaryStage | ParallelStage) -> Case:
    return Case(name="geometry", gearbox=Gearbox(stages=(stage,)))


def standard_contact_ratio(
    z1: int, z2: int, internal: bool, ring_tip_alteration: float = RING_TIP_ALTERATION
) -> float:
    """eps_alpha of a standard spur pair at its reference centre distance, by hand:
    [sqrt(r_a1^2 - r_b1^2) +- sqrt(r_a2^2 - r_b2^2) -+ a sin(alpha)] / (pi m cos(alpha)),
    r = m z / 2, r_b = r cos(alpha), r_a = r + m (external), r - m (1 + k) (ring)."""
    r1, r2 = MODULE * z1 / 2, MODULE * z2 / 2
    a = r2 - r1 if internal else r1 + r2
    tip1 = math.sqrt((r1 + MODULE) ** 2 - (r1 * math.cos(ALPHA)) ** 2)
    if internal:
        ring_tip = r2 - MODULE * (1 + ring_tip_alteration)
        tip2 = math.sqrt(ring_tip**2 - (r2 * math.cos(ALPHA)) ** 2)
        length = tip1 - tip2 + a * math.sin(ALPHA)
    else:
        tip2 = math.sqrt((r2 + MODULE) ** 2 - (r2 * math.cos(ALPHA)) ** 2)
        length = tip1 + tip2 - a * math.sin(ALPHA)
    return length / (math.pi * MODULE * math.cos(ALPHA))


# --------------------------------------------------------------------------- the stage


def test_the_test_stage_is_a_planetary_stage():
    # preconditions of the stage, by its tooth numbers
    assert TEETH["ring"] == TEETH["sun"] + 2 * TEETH["planet"]
    assert (TEETH["sun"] + TEETH["ring"]) % PLANETS == 0


def test_geometry_stage_loads_with_derived_values():
    stage = geometry_stage()
    case = case_of(stage)
    case.validate()
    for member in ("sun", "planet", "ring"):
        gear = getattr(stage, member)
        # r_b = m z cos(alpha) / 2 (hand calculation); one rounding per operation
        assert gear.base_radius == pytest.approx(
            MODULE * TEETH[member] * math.cos(ALPHA) / 2, rel=1e-14
        )
        assert gear.teeth == TEETH[member]
    for name, expected in (
        ("sun_mesh", standard_contact_ratio(TEETH["sun"], TEETH["planet"], False)),
        ("ring_mesh", standard_contact_ratio(TEETH["planet"], TEETH["ring"], True)),
    ):
        mesh = getattr(stage, name)
        # at the reference centre distance the working angle is the rack's 20 deg
        assert mesh.pressure_angle_deg == pytest.approx(20.0, abs=1e-12)
        assert mesh.contact_ratio == pytest.approx(expected, rel=1e-12)
        assert mesh.overlap_ratio == 0.0
        assert mesh.backlash == pytest.approx(0.0, abs=1e-15)  # zero-backlash distance
    assert stage.base_helix_angle_deg == 0.0
    model = assemble(case)
    assert len(model.meshes) == 2 * PLANETS
    # the carrier radius is derived when left out: the zero-backlash centre distance
    assert geometry_stage(carrier_radius=None).carrier.radius == pytest.approx(
        CARRIER_RADIUS, rel=1e-14
    )


def test_agreeing_typed_values_are_kept():
    # 29.60 mm against the geometry's 29.6003 mm: within 0.5 %, kept as typed
    stage = geometry_stage(sun={"base_radius": 29.60e-3, "teeth": 21})
    case_of(stage).validate()
    assert stage.sun.base_radius == 29.60e-3


def test_a_changed_geometry_derives_again():
    # a scene or sweep that changes the geometry (dataclasses.replace down the path)
    # must not take the old derived values for typed ones
    case = case_of(geometry_stage())
    before = case.gearbox.stages[0].ring_mesh.contact_ratio
    changed = replace_parameter(case, "stage.ring.geometry.tip_alteration", -0.3)
    after = changed.gearbox.stages[0].ring_mesh.contact_ratio
    assert after < before - 0.05  # shorter ring tips, a shorter path of contact
    assert after == pytest.approx(
        standard_contact_ratio(TEETH["planet"], TEETH["ring"], True, -0.3), rel=1e-12
    )


# --------------------------------------------------------------------------- iso6336


def test_iso6336_law_mean_is_c_gamma_alpha_b_and_the_table_keeps_it():
    stage = geometry_stage()
    case = case_of(stage)
    gears = geometries()
    references = {
        "sun": iso6336_mesh_stiffness(
            MeshGeometry(gears["sun"], gears["planet"], centre_distance=CARRIER_RADIUS)
        ).mesh_stiffness_alpha_total,
        "ring": iso6336_mesh_stiffness(
            MeshGeometry(gears["planet"], gears["ring"], centre_distance=CARRIER_RADIUS)
        ).mesh_stiffness_alpha_total,
    }
    model = assemble(case)
    for member, reference in references.items():
        law = mesh_law(stage, member)
        assert law.law == "iso6336"
        assert law.code == LAW_CODES["tabulated"]
        # the same call: equal to round-off
        assert law.mean_stiffness == pytest.approx(reference, rel=1e-12)
        for element in model.meshes:
            if element.name.startswith(member):
                assert element.mean_stiffness == pytest.approx(reference, rel=1e-12)
    # the table's time mean over 10 mesh cycles (150 Hz at 120 rpm: Z_r * 2 rev/s).  A
    # constant pair stiffness makes k_m a step function, level * (pairs in contact), with
    # two jumps per cycle; 4000 samples a cycle misplace each by at most one sample, so
    # the sampled mean is off by at most 2 level / 4000 per cycle, i.e. 2 / (4000 eps)
    # = 3e-4 relative to the mean level * eps (eps >= 1.6), plus 3e-5 for the extra
    # sample at the end; 1e-3 holds that.
    data = mesh_stiffness_at_constant_speed(case, duration=10 / 150, samples_per_cycle=4000)
    for name in data.mesh.values:
        member = str(name).split("-")[0]
        mean = float(data.mesh_stiffness.sel(mesh=name).mean())
        assert mean == pytest.approx(references[member], rel=1e-3), name


# --------------------------------------------------------------------------- potential energy


def test_potential_energy_table_reproduces_the_callers_mesh_curve():
    stage = geometry_stage(law="potential_energy")
    case = case_of(stage)
    gears = geometries()
    model = assemble(case)
    table = build_contact_table(case, model)
    for member, pair in (("sun", ("sun", "planet")), ("ring", ("planet", "ring"))):
        geometry = MeshGeometry(gears[pair[0]], gears[pair[1]], centre_distance=CARRIER_RADIUS)
        # the default bore is half the root radius; the ring's rim is rigid either way
        bodies = tuple(ToothBody(206e9, 0.3, 0.5 * root_radius(gears[g])) for g in pair)
        # carrier in, sun out: the planet drives the sun, the ring drives the planet,
        # gear 2 of both geometries
        caller = potential_energy(geometry, bodies, driving_gear=2)
        index = table.names.index(f"{member}-planet1")
        cycle = caller.cycle_position
        theta = (
            (cycle - table.phase[index])
            * 2
            * np.pi
            / (table.cycle_sign[index] * table.teeth[0, index])
        )
        states = np.zeros((cycle.size, table.size))
        states[:, index] = theta
        k_table = table.series(states)["stiffness"][:, index]
        # The caller sums its pair curve at s, s + 1, ...; the table interpolates that curve
        # linearly between its 201 samples: error <= h^2/8 max|k''| per pair in contact,
        # h = eps / 200.  k'' is bounded from the samples' second differences (times 2 for
        # what they smooth); a state within a sample of a pair entering or leaving may
        # count that pair on one side only and is left out.
        h = caller.total_contact_ratio / (caller.pair.size - 1)
        curvature = 2 * np.abs(np.diff(caller.pair, 2)).max() / h**2
        bound = math.ceil(caller.total_contact_ratio) * h**2 / 8 * curvature
        ends = np.concatenate([cycle, cycle + 1.0])
        near_switch = np.min(
            np.abs((ends[:, None] - caller.total_contact_ratio) % 1.0 - np.array([0.0, 1.0])),
            axis=1,
        )
        keep = np.minimum(near_switch[: cycle.size], near_switch[cycle.size :]) > 1.5 / 200
        keep &= np.minimum(cycle, 1 - cycle) > 1.5 / 200
        assert keep.sum() > 100
        error = np.abs(k_table[keep] - caller.mesh[keep])
        assert error.max() <= bound + 1e-12 * caller.mesh.max(), (member, error.max(), bound)
        assert mesh_law(stage, member).mean_stiffness == pytest.approx(
            caller.mean_stiffness, rel=1e-12
        )


def test_potential_energy_mean_is_near_iso6336_for_standard_gears():
    # Standard external gears: ISO 6336-1's c_gamma_alpha b and the potential-energy mean
    # agree to some 10-20 % (docs/potential_energy.md: Tian's 19/48 pair, ratio 0.88).
    # The ring-planet pair is left out: ISO takes z_n2 as infinite there (its own
    # approximation) and the potential-energy law a rigid ring rim.
    energy = mesh_law(geometry_stage(law="potential_energy"), "sun").mean_stiffness
    iso = mesh_law(geometry_stage(law="iso6336"), "sun").mean_stiffness
    assert 0.7 < energy / iso < 1.3


# --------------------------------------------------------------------------- helical stage


def helical_stage(**mesh) -> PlanetaryStage:
    return geometry_stage(helix_deg=HELIX_DEG, width=ONE_OVERLAP_WIDTH, carrier_radius=None, **mesh)


def test_helical_planetary_stage_runs_the_helical_law():
    stage = helical_stage(law=None, stiffness=5e8)
    case_of(stage).validate()
    # carrier radius (Z_s + Z_p) m_n / (2 cos beta), by hand
    assert stage.carrier.radius == pytest.approx(
        (TEETH["sun"] + TEETH["planet"]) * MODULE / (2 * math.cos(math.radians(HELIX_DEG))),
        rel=1e-14,
    )
    alpha_t = math.atan(math.tan(ALPHA) / math.cos(math.radians(HELIX_DEG)))
    beta_b = math.degrees(math.atan(math.tan(math.radians(HELIX_DEG)) * math.cos(alpha_t)))
    assert stage.base_helix_angle_deg == pytest.approx(beta_b, rel=1e-13)
    for member in ("sun", "ring"):
        law = mesh_law(stage, member)
        assert law.code == LAW_CODES["helical"]
        assert law.overlap_ratio == pytest.approx(1.0, rel=1e-14)
        assert law.contact_ratio == pytest.approx(
            getattr(stage, f"{member}_mesh").contact_ratio + 1.0, rel=1e-14
        )


@pytest.mark.parametrize(
    ("stage_of", "limit"),
    [
        # eps_beta = 1: the total contact-line length is constant (a closed form of the
        # helical law: sum over pairs of min(p, eps - p, eps_a, 1) = eps_a for every s),
        # so only the table's round-off is left
        (lambda: helical_stage(law=None, stiffness=5e8), ("below", 0.05)),
        # spur, constant pair stiffness: one or two pairs, (2 - 1) / eps_alpha ~ 0.62
        (lambda: geometry_stage(law="iso6336"), ("above", 0.20)),
    ],
    ids=["helical-eps_beta-1", "spur"],
)
def test_overlap_ratio_one_smooths_the_mesh_stiffness(stage_of, limit):
    stage = stage_of()
    data = mesh_stiffness_at_constant_speed(case_of(stage), duration=3 / 150)
    for name in data.mesh.values:
        k = data.mesh_stiffness.sel(mesh=name).values
        fluctuation = (k.max() - k.min()) / k.mean()
        if limit[0] == "below":
            assert fluctuation < limit[1], (name, fluctuation)
        else:
            assert fluctuation > limit[1], (name, fluctuation)


def test_axial_mesh_force_of_a_helical_planetary_mesh_is_tangential_times_tan_beta_b():
    stage = helical_stage(law=None, stiffness=5e8)
    model = assemble(case_of(stage))
    alpha_t = math.atan(math.tan(ALPHA) / math.cos(math.radians(HELIX_DEG)))
    tan_beta_b = math.tan(math.radians(HELIX_DEG)) * math.cos(alpha_t)  # hand calculation
    found = 0
    for spring in model.springs:
        if spring.kind != "mesh":
            continue
        # the force k delta acts along b; its first three entries are the sun's or the
        # ring's x, y, z: F_a / F_t = b_z / |b_xy|
        b = spring.deflection[:3, 0]
        ratio = b[2] / math.hypot(b[0], b[1])
        # sun right-handed: beta_b > 0 as the stage derives it
        assert ratio == pytest.approx(tan_beta_b, rel=1e-12), spring.name
        found += 1
    assert found == 2 * PLANETS


# --------------------------------------------------------------------------- refusals


def _refused(build, pattern: str) -> str:
    with pytest.raises(CaseError, match=pattern) as error:
        case_of(build()).validate()
    message = str(error.value)
    assert "\n" not in message
    return message


def test_typed_stiffness_with_a_geometry_law_is_refused():
    _refused(
        lambda: geometry_stage(law="iso6336", stiffness=5e8),
        r"stage\.sun_mesh\.stiffness must be left out with law 'iso6336'",
    )


def test_contradicting_base_radius_is_refused():
    # 30.0 mm against the geometry's 29.60 mm: 1.4 % off
    message = _refused(
        lambda: geometry_stage(sun={"base_radius": 30.0e-3}),
        r"stage\.sun\.base_radius 0\.03 m contradicts stage\.sun\.geometry",
    )
    assert "0.0296003" in message and "0.5%" in message


def test_contradicting_contact_ratio_is_refused():
    _refused(
        lambda: geometry_stage(contact_ratio=1.24),
        r"stage\.sun_mesh\.contact_ratio 1\.24 contradicts the gear geometry",
    )


def test_helical_stage_without_overlap_ratio_or_geometry_is_refused():
    # typed radii and meshes without an overlap ratio, made helical
    _refused(
        lambda: dataclasses.replace(consistent_stage(3, name="stage"), base_helix_angle_deg=15.0),
        r"stage\.sun_mesh\.overlap_ratio must be given for a helical stage",
    )


def test_carrier_radius_off_the_centre_distance_is_refused():
    # 73.5 mm against the zero-backlash 72 mm of the profile shifts: 2 % off
    message = _refused(
        lambda: geometry_stage(carrier_radius=73.5e-3),
        r"stage\.carrier\.radius 0\.0735 m disagrees with the sun-planet geometry's centre "
        r"distance 0\.072 m",
    )
    assert "0.5%" in message


def test_geometry_law_without_geometry_is_refused():
    stage = consistent_stage(3, name="stage")
    mesh = dataclasses.replace(stage.sun_mesh, law="potential_energy", stiffness=None)
    with pytest.raises(CaseError, match=r"stage\.sun_mesh\.law 'potential_energy' derives"):
        case_of(dataclasses.replace(stage, sun_mesh=mesh)).validate()


# --------------------------------------------------------------------------- command line

CASE_FILE = """
from pygear import Bearing, Carrier, Case, Gear, Gearbox, Mesh, PlanetaryStage, PlanetBearing
from pygear.model.gear_geometry import GearGeometry

# every value below is ASSUMED: a test stage, not a published gearbox
gear = dict(normal_module=3e-3, face_width=40e-3)
stage = PlanetaryStage(
    name="stage",
    carrier=Carrier(mass=6.0, polar_inertia=0.07, tilt_inertia=0.04, radius=72e-3),
    ring=Gear(mass=3.0, polar_inertia=0.06, tilt_inertia=0.03,
              geometry=GearGeometry(75, internal=True, tip_alteration=-0.2, **gear)),
    sun=Gear(mass=0.8, polar_inertia=2e-3, tilt_inertia=1.1e-3, geometry=GearGeometry(21, **gear)),
    planet=Gear(mass=0.3, polar_inertia=1e-4, tilt_inertia=6e-5, geometry=GearGeometry(27, **gear)),
    planets=3,
    carrier_bearing=Bearing(radial=2e8, axial=1.5e8, tilt=3e6),
    ring_bearing=Bearing(radial=3e8, axial=2e8, tilt=4e6, torsional=5e7),
    sun_bearing=Bearing(radial=1e8, axial=1e8, tilt=2e6),
    planet_bearing=PlanetBearing(radial=1.2e8, axial=0.9e8, tilt=1.5e6),
    sun_mesh=Mesh(law="iso6336"),
    ring_mesh=Mesh(law="iso6336"),
)
case = Case(name="geometry_stage", gearbox=Gearbox(stages=(stage,)))
"""

KEYS = {
    "law", "teeth", "normal_module", "face_width", "profile_shift", "helix_angle_deg",
    "normal_pressure_angle_deg", "transverse_contact_ratio", "overlap_ratio",
    "mean_stiffness", "max_stiffness", "backlash",
}  # fmt: skip


def _json(argv: list[str], capsys) -> dict:
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_mesh_stiffness_json_keys_and_units(tmp_path, capsys):
    (tmp_path / "case.py").write_text(textwrap.dedent(CASE_FILE))
    meshes = _json(["mesh-stiffness", str(tmp_path), "--json"], capsys)["meshes"]
    assert sorted(meshes) == sorted(
        f"{gear}-planet{n}" for gear in ("sun", "ring") for n in range(1, PLANETS + 1)
    )
    gears = geometries()
    iso = iso6336_mesh_stiffness(
        MeshGeometry(gears["sun"], gears["planet"], centre_distance=CARRIER_RADIUS)
    ).mesh_stiffness_alpha_total
    sun, ring = meshes["sun-planet1"], meshes["ring-planet2"]
    assert KEYS <= set(sun)
    assert sun["law"] == "iso6336"
    assert sun["teeth"] == [21, 27] and ring["teeth"] == [75, 27]  # gear 1 sun or ring
    assert sun["normal_module"] == 3e-3  # m, not mm
    assert sun["face_width"] == 40e-3  # m
    assert sun["profile_shift"] == [0.0, 0.0]
    assert sun["helix_angle_deg"] == 0.0 and sun["normal_pressure_angle_deg"] == 20.0
    assert sun["transverse_contact_ratio"] == pytest.approx(
        standard_contact_ratio(21, 27, False), rel=1e-12
    )
    assert sun["overlap_ratio"] == 0.0
    assert sun["mean_stiffness"] == pytest.approx(iso, rel=1e-12)  # N/m
    # the constant pair stiffness of two pairs in contact: 2 k-bar / eps_alpha
    assert sun["max_stiffness"] == pytest.approx(
        2 * iso / sun["transverse_contact_ratio"], rel=1e-12
    )
    assert sun["backlash"] == pytest.approx(0.0, abs=1e-15)  # m, zero-backlash distance
    energy = _json(
        ["mesh-stiffness", str(tmp_path), "--json", "--law", "potential_energy"], capsys
    )["meshes"]
    assert {entry["law"] for entry in energy.values()} == {"potential_energy"}


def test_mesh_stiffness_json_without_geometry_has_null_geometry(capsys):
    meshes = _json(["mesh-stiffness", "yang2016_planetary", "--json"], capsys)["meshes"]
    entry = meshes["ring-planet1"]
    assert KEYS <= set(entry)
    for key in ("normal_module", "face_width", "profile_shift", "helix_angle_deg",
                "normal_pressure_angle_deg"):  # fmt: skip
        assert entry[key] is None, key
    assert entry["law"] == "parabola"
    assert entry["teeth"] == [96, 35]
    assert entry["mean_stiffness"] == 5e8  # Table 1 of the study case, typed


def test_mesh_stiffness_law_needs_what_it_derives_from(capsys):
    assert main(["mesh-stiffness", "yang2016_planetary", "--law", "iso6336"]) == 2
    assert "gear geometry" in capsys.readouterr().err


def test_law_override_refuses_a_pair_outside_its_range_when_asked():
    """ISO 6336-1's q' regression holds for x1 >= x2; the NREL 5 MW stage 2 sun mesh
    (sun 0.389, planet 0.504, the sun ISO's gear 1) is outside it.  The override says so
    itself, naming the mesh, not the assembly that would come later."""
    from pygear import load_case
    from pygear.assembly.mesh_laws import with_mesh_law

    case = load_case(Path(__file__).resolve().parent.parent / "cases" / "nrel5mw_gearbox")
    with pytest.raises(CaseError, match=r"stage2\.sun_mesh.*x1 >= x2"):
        with_mesh_law(case, "iso6336")


# --------------------------------------------------------------------------- parallel stage


def test_helical_parallel_pair_from_geometry():
    # 23/61 teeth, m_n = 3 mm, beta = 15 deg (input right-handed), b = 40 mm, no shift
    beta = math.radians(HELIX_DEG)
    first = GearGeometry(23, MODULE, WIDTH, helix_angle_deg=HELIX_DEG)
    second = GearGeometry(61, MODULE, WIDTH, helix_angle_deg=-HELIX_DEG)
    body = dict(mass=2.0, polar_inertia=2.5e-3, tilt_inertia=1.25e-3)
    bearing = Bearing(radial=1e8, axial=1e8, tilt=1e6)
    pair = ParallelStage(
        name="pair",
        input_gear=Gear(**body, geometry=first),
        output_gear=Gear(**body, geometry=second),
        input_bearing=bearing,
        output_bearing=bearing,
        mesh=Mesh(law="iso6336"),
    )
    model = assemble(case_of(pair))
    # hand calculations: eps_beta = b sin(beta) / (pi m_n), a = (z1 + z2) m_n / (2 cos beta),
    # tan(beta_b) = tan(beta) cos(alpha_t), tan(alpha_t) = tan(alpha_n) / cos(beta)
    assert pair.overlap_ratio == pytest.approx(
        WIDTH * math.sin(beta) / (math.pi * MODULE), rel=1e-14
    )
    assert pair.centre_distance == pytest.approx(
        (23 + 61) * MODULE / (2 * math.cos(beta)), rel=1e-13
    )
    alpha_t = math.atan(math.tan(ALPHA) / math.cos(beta))
    tan_beta_b = math.tan(beta) * math.cos(alpha_t)
    assert math.tan(math.radians(pair.base_helix_angle_deg)) == pytest.approx(tan_beta_b, rel=1e-13)
    law = mesh_law(pair, "mesh")
    assert law.code == LAW_CODES["helical"]
    assert law.contact_ratio == pytest.approx(
        pair.mesh.contact_ratio + pair.overlap_ratio, rel=1e-14
    )
    iso = iso6336_mesh_stiffness(MeshGeometry(first, second)).mesh_stiffness_alpha_total
    assert law.mean_stiffness == pytest.approx(iso, rel=1e-12)
    (spring,) = [s for s in model.springs if s.kind == "mesh"]
    b = spring.deflection[:3, 0]  # the input gear's x, y, z
    assert b[2] / math.hypot(b[0], b[1]) == pytest.approx(tan_beta_b, rel=1e-12)


def test_helical_parallel_pair_without_overlap_ratio_is_refused():
    body = dict(mass=2.0, polar_inertia=2.5e-3, tilt_inertia=1.25e-3)
    bearing = Bearing(radial=1e8, axial=1e8, tilt=1e6)
    pair = ParallelStage(
        name="pair",
        input_gear=Gear(**body, base_radius=0.05, teeth=34),
        output_gear=Gear(**body, base_radius=0.05, teeth=34),
        input_bearing=bearing,
        output_bearing=bearing,
        mesh=Mesh(stiffness=5e8, pressure_angle_deg=21.2, contact_ratio=1.58),
        base_helix_angle_deg=20.0,
    )
    with pytest.raises(CaseError, match=r"pair\.overlap_ratio must be given for a helical stage"):
        case_of(pair).validate()
