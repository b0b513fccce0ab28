"""Speed-dependent modes of a whole drivetrain: the shafts' gyroscopic terms at their own
speed ratios together with the gearbox block's planets' frame terms.

References, never the code's own output:

* the gearbox alone: its own Campbell diagram (``campbell_diagram`` on a gearbox case,
  Cooley & Parker's terms on the planets, carrier, ring and sun inertial), which a
  drivetrain whose shafts are short, stiff and light next to the gearbox members must
  reproduce on the gearbox's modes;
* an overhung disc on a massless Euler-Bernoulli cantilever (Friswell, Penny, Garvey &
  Lees, *Dynamics of Rotating Machines*, 2010, §3.6 and §5.3): tip stiffness
  EI / L^3 [[12, -6L], [-6L, 4L^2]] from the cantilever's compliance, disc mass m,
  diametral and polar inertias I_d, I_p, spin Omega.  A circular whirl r = R e^(i w t)
  (w > 0 forward, w < 0 backward) satisfies
  (k11 - m w^2)(k22 - I_d w^2 + I_p Omega w) - k12^2 = 0, a quartic in w solved here by
  ``numpy.roots``;
* the spin of the fast shaft from the tooth numbers of Nejad et al.'s gearbox,
  (1 + 56/19)(1 + 93/18)(95/24) times the rotor's.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from pygear import (
    Case,
    Drivetrain,
    GearboxMount,
    Generator,
    Rotor,
    Scene,
    Shaft,
    ShaftBearing,
    ShaftSection,
)
from pygear.analysis.modes.campbell import campbell_diagram
from pygear.analysis.modes.sparse_gyroscopic import modes_at_speed
from pygear.assembly.drivetrain import assemble_drivetrain
from pygear.assembly.speed_terms import drivetrain_frame_terms
from pygear.cli import main
from pygear.model.case import RayleighDamping, load_case

pytestmark = pytest.mark.filterwarnings(
    "ignore::pygear.model.plausibility.PlausibilityWarning"  # the deliberately light shafts
)

KINEMATIC_RATIO = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)  # Nejad et al.'s tooth numbers
YOUNG, SHEAR = 2.1e11, 8.1e10  # Pa, steel


@pytest.fixture(scope="module")
def gearbox():
    return load_case("nrel5mw_drivetrain").gearbox


def light_stub(name: str, density: float) -> Shaft:
    """A 0.1 m long, 0.3 m thick steel stub of the given density."""
    return Shaft(
        name,
        (ShaftSection(0.1, 0.3),),
        young_modulus=YOUNG,
        shear_modulus=SHEAR,
        density=density,
        elements_per_section=1,
    )


def quiet_case(**fields) -> Case:
    """An undamped test case (its light shafts warn as implausible: filtered above)."""
    if "drivetrain" in fields:
        fields["drivetrain"] = Drivetrain(**fields["drivetrain"])
    return Case(formulation="consistent", damping=RayleighDamping(), **fields)


# ------------------------------------------------------- rigid shafts: the gearbox alone


def test_drivetrain_with_rigid_light_shafts_is_the_gearbox_campbell(gearbox):
    """The rotor sits on the fast side (the output gear's stub) and the generator on the
    carrier's: the rotor turns at -96.35 times the carrier, so the planets' terms must
    enter at the carrier's speed ratio, sign included.  The gearbox case's Campbell
    diagram over the carrier speed n must equal the drivetrain's at rotor speed
    -n / 96.35 on the 30 lowest modes.

    Tolerance: the stubs, rotor and generator add mass delta m and tilt inertia
    delta I to the two mounted members; the Rayleigh quotient moves each omega^2 by at
    most the larger ratio r of the added to the member's own mass or inertia, so the
    frequencies agree within r (measured 2.5e-6, r = 4e-4).  The stubs' stiffness
    (EI/L 1e9 times the members' bearing stiffness) adds nothing at this size.
    """
    density = 7.85  # kg/m^3, a thousandth of steel
    shafts = (light_stub("slow", density), light_stub("fast", density))
    light = dict(mass=0.01, polar_inertia=1e-4, diametral_inertia=1e-4)
    drivetrain = dict(
        shafts=shafts,
        gearbox=gearbox,
        mounts=(
            GearboxMount("stage1.carrier", at="slow.end"),
            GearboxMount("parallel.output_gear", at="fast.start"),
        ),
        rotor=Rotor(**light, at="fast.end"),
        generator=Generator(**light, at="slow.start"),
    )
    case = quiet_case(name="rigid_shafts", gearbox=gearbox, drivetrain=drivetrain)
    gearbox_case = quiet_case(
        name="gearbox_alone",
        gearbox=gearbox,
        scenes=(Scene("modal", analyses=("modal",), dof_set="spatial"),),
    )
    model = assemble_drivetrain(case, dof_set="spatial")
    carrier_over_rotor = model.speed_ratios["slow"]
    assert carrier_over_rotor == pytest.approx(-1 / KINEMATIC_RATIO, rel=1e-9)
    carrier_speeds = np.linspace(0.0, 600.0, 4)  # rpm: the split of the in-plane pairs
    rotor_speeds = carrier_speeds / carrier_over_rotor  # decreasing: solve them in reverse
    frame_terms = drivetrain_frame_terms(model, case)
    assert frame_terms.carrier_ratios["stage1"] == pytest.approx(carrier_over_rotor, rel=1e-9)
    modes = 30
    alone = campbell_diagram(
        gearbox_case, carrier_speeds, scene=gearbox_case.scenes[0], members="planets"
    )
    # the drivetrain's diagram at the same speeds, untracked: the frequencies are
    # compared sorted, and tracking across the rotor's 58 000 rpm steps only refines
    whole = [
        modes_at_speed(model, speed, modes, solver="sparse", frame_terms=frame_terms)
        for speed in rotor_speeds
    ]

    # the added mass and inertia against the mounted members' own (their mass rows)
    block = model.gearbox
    added = []
    for member in ("stage1.carrier", "parallel.output_gear"):
        for dof, extra in (
            ("x", 2 * 0.01 + density * math.pi / 4 * 0.09 * 0.1),
            ("theta_x", 2e-4 + 0.01 * 0.01 + density * math.pi / 4 * 0.09 * 0.1 * 0.1**2 / 3),
        ):
            i = block.dof_labels.index(f"{member}.{dof}")
            added.append(extra / block.mass[i, i])
    tolerance = max(added)
    assert tolerance < 1e-3  # the shafts are light next to the members
    changed = 0.0
    for k in range(carrier_speeds.size):
        drivetrain_hz = np.sort(whole[k].frequencies)
        gearbox_hz = np.sort(alone.frequency.values[k][alone.frequency.values[k] > 0])[:modes]
        np.testing.assert_allclose(drivetrain_hz, gearbox_hz, rtol=tolerance)
        changed = max(
            changed,
            np.abs(
                gearbox_hz
                / np.sort(alone.frequency.values[0][alone.frequency.values[0] > 0])[:modes]
                - 1
            ).max(),
        )
    assert changed > 0.05  # the speed moves the modes compared: the frame terms matter


# ------------------------------------------------ each shaft at its own speed: a disc


def overhung_disc_hz(
    stiffness: float, length: float, mass: float, diametral: float, polar: float, spin: float
) -> np.ndarray:
    """The four whirl frequencies [Hz] (two forward, two backward, ascending |w|) of a
    disc on a massless cantilever of bending stiffness EI = ``stiffness`` at spin
    Omega [rad/s]."""
    k11 = 12 * stiffness / length**3
    k12 = -6 * stiffness / length**2
    k22 = 4 * stiffness / length
    # (k11 - m w^2)(k22 - I_d w^2 + I_p W w) - k12^2, expanded in powers of w
    quartic = np.polymul([-mass, 0.0, k11], [-diametral, polar * spin, k22])
    quartic[-1] -= k12**2
    roots = np.roots(quartic)
    assert np.all(np.abs(roots.imag) < 1e-9 * np.abs(roots).max())
    return np.sort(np.abs(roots.real)) / (2 * math.pi)


def test_disc_on_the_fast_shaft_splits_with_that_shafts_speed(gearbox):
    """A 50 kg disc overhangs the high-speed shaft (1 m, 80 mm, Euler-Bernoulli) whose
    start is clamped by a bearing 1e13 N/m and N m/rad stiff on the output gear; the
    rotor sits on a light stub on the carrier.  At rotor speed n the disc's four whirl
    frequencies are the closed form's at the fast shaft's spin 96.35 n, not at n.

    Tolerance: the clamp's compliance against the cantilever's (12 EI / L^3 = 5e6 N/m,
    4 EI / L = 1.7e6 N m/rad against 1e13: 5e-7) and the shaft's mass against the
    disc's (4 g of a shaft of 1e-4 times steel's density against 50 kg: 8e-5).  Near
    the forward conical mode's asymptote w = I_p Omega / I_d the disc's effective tilt
    inertia I_d - I_p Omega / w shrinks, which magnifies the shaft's share by
    I_d / (I_d - I_p Omega / w), below 5 at these speeds: 5e-4.
    """
    length, diameter = 1.0, 0.08
    bending = YOUNG * math.pi * diameter**4 / 64  # EI [N m^2]
    disc = dict(mass=50.0, polar_inertia=1.0, diametral_inertia=0.5)
    fast = Shaft(
        "fast",
        (ShaftSection(length, diameter),),
        young_modulus=YOUNG,
        shear_modulus=SHEAR,
        density=0.785,
        elements_per_section=4,
        shear_deformation=False,
    )
    drivetrain = dict(
        shafts=(light_stub("slow", 7850.0), fast),
        gearbox=gearbox,
        mounts=(
            GearboxMount("stage1.carrier", at="slow.end"),
            GearboxMount("parallel.output_gear", at="fast.start"),
        ),
        rotor=Rotor(mass=1.0, polar_inertia=0.01, diametral_inertia=0.01, at="slow.start"),
        generator=Generator(**disc, at="fast.end"),
        bearings=(ShaftBearing("clamp", "fast", 0.0, radial=1e13, tilt=1e13),),
    )
    case = quiet_case(name="overhung", gearbox=gearbox, drivetrain=drivetrain)
    model = assemble_drivetrain(case, dof_set="spatial")
    frame_terms = drivetrain_frame_terms(model, case)
    node = model.end_nodes["fast.end"]
    disc_dofs = [model.index(f"{node}.{d}") for d in ("x", "y", "theta_x", "theta_y")]
    splits = []
    for rotor_rpm in (0.0, 40.0, 80.0):
        found = modes_at_speed(
            model, rotor_rpm, model.size, solver="dense", frame_terms=frame_terms
        )
        shapes = found.shapes
        weights = np.array(
            [disc["mass"], disc["mass"], disc["diametral_inertia"], disc["diametral_inertia"]]
        )
        share = (weights[:, None] * np.abs(shapes[disc_dofs]) ** 2).sum(axis=0)
        on_disc = np.sort(found.frequencies[np.argsort(share)[-4:]])
        spin = KINEMATIC_RATIO * rotor_rpm * math.pi / 30
        expected = overhung_disc_hz(
            bending, length, disc["mass"], disc["diametral_inertia"], disc["polar_inertia"], spin
        )
        np.testing.assert_allclose(on_disc, expected, rtol=5e-4)
        if rotor_rpm > 0:
            at_rotor_speed = overhung_disc_hz(
                bending,
                length,
                disc["mass"],
                disc["diametral_inertia"],
                disc["polar_inertia"],
                rotor_rpm * math.pi / 30,
            )
            assert np.abs(on_disc / at_rotor_speed - 1).max() > 1e-2  # the ratio matters
        splits.append(on_disc[3] - on_disc[2])  # the conical pair: forward minus backward
    assert splits[0] < splits[1] < splits[2]


# ------------------------------------------------------------- the commands, every kind


@pytest.mark.parametrize(
    ("case", "speeds"),
    [
        ("yang2016_planetary", "0:3000:4"),
        ("nrel5mw_gearbox", "0:600:3"),
        ("nrel5mw_drivetrain", "0:12:2"),
        ("friswell_rotor", "0:4000:5"),
    ],
)
def test_campbell_and_modal_at_a_speed_on_every_case_kind(tmp_path, capsys, case, speeds):
    """``pygear modal --speed`` lists modes whirling both ways and ``pygear campbell``
    writes its files on a planetary stage, a gearbox, a drivetrain and a rotor; a
    drivetrain's high-speed shaft turns at the tooth numbers' ratio and its planets carry
    their frame terms; a rotor's critical speeds are 1x crossings (f = n / 60)."""
    top = float(speeds.split(":")[1])
    assert main(["modal", case, "--speed", str(top), "--json"]) == 0
    modal = json.loads(capsys.readouterr().out)
    assert modal["speed_rpm"] == top
    assert len(modal["frequencies_hz"]) == len(modal["whirl"]) > 0
    assert {"forward", "backward"} <= set(modal["whirl"])
    out = tmp_path / case
    rotor_like = case in ("nrel5mw_drivetrain", "friswell_rotor")
    extra = ["--modes", "4"] if rotor_like else []
    assert main(["campbell", case, "--speeds", speeds, "--out", str(out), "--json", *extra]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (out / "campbell.nc").is_file() and (out / "campbell.png").is_file()
    frequencies = np.array(summary["frequencies_hz"])
    assert frequencies.shape[0] == int(speeds.split(":")[2])
    if case == "nrel5mw_drivetrain":
        assert "planets' Coriolis and centripetal terms" in summary["gyroscopic"]
        assert summary["speed_ratios"]["high_speed_shaft"] == pytest.approx(-KINEMATIC_RATIO)
    elif case == "friswell_rotor":
        assert summary["critical_speeds"]
        for critical in summary["critical_speeds"]:
            assert critical["frequency_hz"] == pytest.approx(critical["speed_rpm"] / 60)
    else:
        assert summary["reference"].endswith("carrier.theta_z")
        assert summary["crossings"]  # mesh orders cross the diagram's modes


def test_speed_terms_choice_is_checked_and_for_gearboxes(capsys):
    assert (
        main(["campbell", "yang2016_planetary", "--speeds", "0:10:3", "--speed-terms", "some"]) == 2
    )
    assert "--speed-terms" in capsys.readouterr().err
    assert (
        main(["campbell", "friswell_rotor", "--speeds", "0:10:3", "--speed-terms", "planets"]) == 2
    )
    assert "--speed-terms" in capsys.readouterr().err


def test_planets_only_terms_read_the_central_members_inertially():
    """With members="planets" only planets carry G and K_Omega, and every central
    member's pair has frame ratio 0 (its whirl is seen from the ground)."""
    from pygear.assembly.matrices import assemble
    from pygear.assembly.speed_terms import speed_terms

    case = load_case("yang2016_planetary")
    model = assemble(case)
    both = speed_terms(model, case, members="all")
    planets = speed_terms(model, case, members="planets")
    for pair in planets.pairs:
        assert (pair.frame_ratio == 0.0) == (pair.role != "planet")
    planet_rows = [i for i, label in enumerate(model.dof_labels) if ".planet" in label]
    others = [i for i in range(len(model.dof_labels)) if i not in planet_rows]
    assert np.abs(planets.gyroscopic[np.ix_(others, others)]).max() == 0.0
    assert np.abs(both.gyroscopic[np.ix_(others, others)]).max() > 0.0
    np.testing.assert_array_equal(
        planets.gyroscopic[np.ix_(planet_rows, planet_rows)],
        both.gyroscopic[np.ix_(planet_rows, planet_rows)],
    )
    assert dataclasses.is_dataclass(planets)


def test_unbalance_response_of_a_drivetrain_carries_the_planets_terms(gearbox):
    """``with_frame_terms`` gives the unbalance response the planets' terms: the disc's
    response equals a dense solve of (K - W_c^2 K_Omega - W^2 M + i W (C + W G_shafts +
    W G_planets)) X = m e W^2 (1, -i), with the gearbox's own terms per unit speed of
    the first carrier, which the rotor drives, placed at its block.  Tolerance: two LU
    solves of one system, 1e-8; the terms move the disc's response by 100 times that."""
    from pygear import Disc
    from pygear.analysis.response.rotor import Unbalance, unbalance_response
    from pygear.assembly.speed_terms import speed_terms, with_frame_terms

    drivetrain = dict(
        shafts=(light_stub("slow", 7850.0), light_stub("fast", 7850.0)),
        gearbox=gearbox,
        mounts=(
            GearboxMount("stage1.carrier", at="slow.end"),
            GearboxMount("parallel.output_gear", at="fast.start"),
        ),
        rotor=Rotor(mass=1.0, polar_inertia=0.01, diametral_inertia=0.01, at="slow.start"),
        generator=Generator(polar_inertia=0.01, mass=1.0, diametral_inertia=0.01, at="fast.end"),
        discs=(Disc("disc", "slow", 0.1, mass=5.0, polar_inertia=0.02, diametral_inertia=0.01),),
    )
    case = quiet_case(name="unbalanced", gearbox=gearbox, drivetrain=drivetrain)
    model = assemble_drivetrain(case, dof_set="spatial")
    spinning = with_frame_terms(model, drivetrain_frame_terms(model, case))
    speed = 600.0  # rpm of the rotor and the first carrier
    response = unbalance_response(spinning, case.drivetrain, [Unbalance("disc", 1e-3)], [speed])
    plain = unbalance_response(model, case.drivetrain, [Unbalance("disc", 1e-3)], [speed])

    omega = speed * math.pi / 30
    carrier = omega
    terms = speed_terms(model.gearbox, case, "stage1.carrier.theta_z", "planets")
    block = slice(model.gearbox_offset, model.size)
    stiffness = model.stiffness.toarray()
    first = (model.damping + omega * model.gyroscopic).toarray()
    stiffness[block, block] -= carrier**2 * terms.centripetal
    first[block, block] += carrier * terms.gyroscopic
    force = np.zeros(model.size, complex)
    node = model.end_nodes["slow.end"]
    force[model.index(f"{node}.x")] = 1e-3 * omega**2
    force[model.index(f"{node}.y")] = -1j * 1e-3 * omega**2
    dynamic = stiffness - omega**2 * model.mass.toarray() + 1j * omega * first
    expected = np.linalg.solve(dynamic, force)
    found = response.x_amplitude.sel(location="disc").values[0]
    assert found == pytest.approx(abs(expected[model.index(f"{node}.x")]), rel=1e-8)
    without = plain.x_amplitude.sel(location="disc").values[0]
    assert abs(without / found - 1) > 1e-6  # the terms are seen at this speed
