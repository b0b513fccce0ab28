"""The drivetrain model (pygear.model.drivetrain, pygear.assembly.drivetrain) and the
NREL 5 MW drivetrain case against closed forms and Jonkman et al. (2009).

References, never the code's own output:

* the two-inertia closed form f = (1/2 pi) sqrt(k (1/J_1 + 1/J_2)) of a free-free
  rotor-spring-generator chain, J_2 the generator side referred to the low-speed shaft
  (N^2 J), k the springs in series (G J / L of each shaft, the couplings);
* Jonkman, Butterfield, Musial & Scott, NREL/TP-500-38060 (2009), section 5: the
  equivalent drive-shaft spring 867 637 000 N m/rad and damper 6 215 000 N m s/rad,
  rotor and generator inertias, ratio 97, the damper 5 % of critical.  The comparable
  value for a model with rigid blades and a free generator is the free-free
  drivetrain mode of those constants (2.22 Hz), not Table 9-1's drivetrain entry:
  Table 9-1 was computed for a stationary rotor with a locked generator and flexible
  blades (J. Jonkman, NREL forum, "Full-system natural frequencies", topic 1462), so
  it holds the blades' edgewise compliance in series and no generator inertia.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from pygear import Bearing, Body, CaseError, GearboxMount, RigidLink, ShaftInertia
from pygear.analysis.modes.drivetrain_modal import drivetrain_modes, modal_damping_ratios
from pygear.assembly.drivetrain import assemble_drivetrain, build_structure
from pygear.cli import main
from pygear.linalg import generalized_eigh
from pygear.model.case_files import load_case_module
from pygear.model.drivetrain import ShaftSection
from pygear.model.gearbox import Gearbox

JONKMAN_SPRING = 867_637_000.0  # N m/rad, section 5
JONKMAN_DAMPER = 6_215_000.0  # N m s/rad, section 5
JONKMAN_GENERATOR_INERTIA = 534.116  # kg m^2, section 5
JONKMAN_RATIO = 97.0  # section 5
JONKMAN_DAMPING_RATIO = 0.05  # "5 % critical", section 5


@pytest.fixture(scope="module")
def module():
    return load_case_module("nrel5mw_drivetrain")[1]


def two_inertia_hz(stiffness: float, rotor: float, generator_side: float) -> float:
    """Free-free two-inertia frequency [Hz]."""
    return math.sqrt(stiffness * (1.0 / rotor + 1.0 / generator_side)) / (2.0 * math.pi)


def shaft_inertia(shaft) -> float:
    """rho J_p L of a shaft [kg m^2] (closed form of a tube)."""
    return sum(
        shaft.density * math.pi * (s.outer_diameter**4 - s.inner_diameter**4) / 32.0 * s.length
        for s in shaft.sections
    )


def shaft_twist_stiffness(shaft) -> float:
    """G J_p / L of a shaft, its sections in series [N m/rad]."""
    return 1.0 / sum(
        s.length
        / (shaft.shear_modulus * math.pi * (s.outer_diameter**4 - s.inner_diameter**4) / 32)
        for s in shaft.sections
    )


def ratio_case(module, ratio: float):
    """The case with its gearbox replaced by its ratio: two massless-like inertias
    joined by a rigid link (the gearbox's rigid limit)."""
    tiny = Body(mass=1.0, polar_inertia=1e-6, tilt_inertia=1e-6)
    support = Bearing(radial=1e9, axial=1e9, tilt=1e9, torsional=0.0)
    gearbox = Gearbox(
        stages=(ShaftInertia("lss", tiny, support), ShaftInertia("hss", tiny, support)),
        couplings=(RigidLink("lss.body.theta_z", "hss.body.theta_z", ratio),),
    )
    drivetrain = dataclasses.replace(
        module.case.drivetrain,
        gearbox=gearbox,
        mounts=(
            GearboxMount("lss.body", "main_shaft.end"),
            GearboxMount("hss.body", "high_speed_shaft.start"),
        ),
    )
    return dataclasses.replace(module.case, gearbox=gearbox, drivetrain=drivetrain, scenes=())


def closed_form_inputs(module, ratio: float) -> tuple[float, float, float]:
    """(k, J_1, J_2) of the rigid-gearbox chain from the case's inputs: the hub
    coupling, hub stub, main shaft and high-speed shaft (N^2 G J / L) in series; the
    rotor (and hub stub) on one side, N^2 (J_gen + J_hss) and the main shaft on the other."""
    drivetrain = module.case.drivetrain
    hub, main_shaft, high_speed = (
        drivetrain.shaft(n) for n in ("hub_shaft", "main_shaft", "high_speed_shaft")
    )
    compliance = (
        1.0 / drivetrain.couplings[0].torsional
        + 1.0 / shaft_twist_stiffness(hub)
        + 1.0 / shaft_twist_stiffness(main_shaft)
        + 1.0 / (ratio**2 * shaft_twist_stiffness(high_speed))
    )
    rotor_side = drivetrain.rotor.polar_inertia + shaft_inertia(hub)
    generator_side = ratio**2 * (drivetrain.generator.polar_inertia + shaft_inertia(high_speed))
    return 1.0 / compliance, rotor_side, generator_side + shaft_inertia(main_shaft)


def first_elastic(modes) -> tuple[float, int]:
    index = int(np.flatnonzero(modes.frequencies_hz > 0)[0])
    return float(modes.frequencies_hz[index]), index


def test_rigid_gearbox_matches_two_inertia_closed_form(module):
    """Gearbox replaced by its ratio: the first torsional frequency is the two-inertia
    closed form of the same inputs.  Error budget: the main shaft's 370 kg m^2 sits
    inside the spring, lumped here on the generator side: at most 370 / 5.0e6 = 7e-5
    of J_2, so < 4e-5 in f; the high-speed shaft twists 0.1 % of the total, so lumping
    its inertia is good to 1e-3 x 1.8 % = 2e-5; the shafts' linear torsion elements
    are exact in statics.  Tolerance 2e-4 covers these with a margin."""
    for ratio in (JONKMAN_RATIO, module.GEARBOX_RATIO):
        model = assemble_drivetrain(ratio_case(module, ratio), dof_set="torsional")
        frequency, _ = first_elastic(drivetrain_modes(model, 4))
        expected = two_inertia_hz(*closed_form_inputs(module, ratio))
        assert frequency == pytest.approx(expected, rel=2e-4)
    # the case splits Jonkman's spring so that the rigid-gearbox chain is his spring
    stiffness, _, _ = closed_form_inputs(module, module.GEARBOX_RATIO)
    assert stiffness == pytest.approx(JONKMAN_SPRING, rel=1e-12)  # round-off of 4 inverses


def test_rigid_gearbox_against_jonkman_frequency_and_damping(module):
    """Jonkman's own two-inertia drivetrain (his spring, rotor, N = 97, generator):
    2.2226 Hz.  The model with the gearbox rigid at N = 97 adds the high-speed shaft's
    inertia, N^2 rho J L = 8.9e4 kg m^2, 1.8 % of N^2 J_gen: the frequency drops by
    1.8 % x J_1/(J_1 + J_2) / 2 = 0.79 %; 1 % bounds it.  The damper gives
    c omega / (2 k) = 5.00 % of critical at Jonkman's frequency, his stated ratio; the
    model spreads it as C = (c / k) K over the low-speed chain, so its ratio is
    (c / k) omega / 2 at its own, 0.79 % lower, frequency (1 % again)."""
    rotor = module.case.drivetrain.rotor.polar_inertia
    jonkman_hz = two_inertia_hz(JONKMAN_SPRING, rotor, JONKMAN_RATIO**2 * JONKMAN_GENERATOR_INERTIA)
    assert jonkman_hz == pytest.approx(2.2226, abs=5e-4)  # derived from section 5's values
    jonkman_zeta = JONKMAN_DAMPER * 2 * math.pi * jonkman_hz / (2 * JONKMAN_SPRING)
    assert jonkman_zeta == pytest.approx(JONKMAN_DAMPING_RATIO, rel=2e-3)  # rounded "5 %"

    model = assemble_drivetrain(ratio_case(module, JONKMAN_RATIO), dof_set="torsional")
    modes = drivetrain_modes(model, 4)
    frequency, index = first_elastic(modes)
    assert frequency == pytest.approx(jonkman_hz, rel=0.01)
    assert frequency < jonkman_hz  # the shaft inertia only adds
    zeta = modal_damping_ratios(model, modes)[index]
    assert zeta == pytest.approx(JONKMAN_DAMPING_RATIO, rel=0.01)


def test_flexible_gearbox_lies_below_by_its_series_compliance(module):
    """The case's own gearbox: the meshes add compliance in series and the members
    inertia, so the frequency lies below the rigid limit (Rayleigh: less stiffness,
    more mass).  By how much: the two-inertia form with k' = 1/(1/k + c_gb) and
    J_2' = J_2 + J_gb, c_gb the gearbox's static compliance referred to the low-speed
    shaft (carrier held, torque on the pinion, divided by N^2; a static solve, not an
    eigenproblem) and J_gb the kinetic energy of its rigid rotation per unit carrier
    speed.  Lumping J_gb on the generator side errs by the share of the gearbox's
    compliance that lies behind its inertia: c_gb k = 12 % of the twist, J_gb / J_2' =
    12 % of the inertia, at most 0.12 x 0.12 / 2 = 0.7 % in f; 1 % bounds it."""
    model = assemble_drivetrain(module.case, dof_set="torsional")
    frequency, _ = first_elastic(drivetrain_modes(model, 4))
    rigid_hz = two_inertia_hz(*closed_form_inputs(module, module.GEARBOX_RATIO))

    gearbox = model.gearbox
    carrier = gearbox.dof_labels.index("stage1.carrier.theta_z")
    pinion = gearbox.dof_labels.index("parallel.output_gear.theta_z")
    keep = [i for i in range(gearbox.size) if i != carrier]
    load = np.zeros(len(keep))
    load[keep.index(pinion)] = 1.0
    twist = np.linalg.solve(gearbox.stiffness[np.ix_(keep, keep)], load)[keep.index(pinion)]
    _, vectors = generalized_eigh(gearbox.stiffness, gearbox.mass)
    rigid = vectors[:, 0] / vectors[carrier, 0]
    ratio = rigid[pinion]
    assert abs(ratio) == pytest.approx(module.GEARBOX_RATIO, rel=1e-9)  # kinematics
    gearbox_compliance = twist / ratio**2
    gearbox_inertia = rigid @ gearbox.mass @ rigid

    stiffness, rotor_side, generator_side = closed_form_inputs(module, module.GEARBOX_RATIO)
    series = 1.0 / (1.0 / stiffness + gearbox_compliance)
    estimate = two_inertia_hz(series, rotor_side, generator_side + gearbox_inertia)
    assert frequency < rigid_hz
    assert frequency == pytest.approx(estimate, rel=0.01)
    assert 1 - frequency / rigid_hz > 0.05  # the gearbox is not negligible here


def test_elimination_shifts_nothing_a_stiff_coupling_would_not(module):
    """The exact tie against the same joint written as a coupling of growing stiffness:
    the carrier on a 1 mm, 2 m thick stub joined to the main shaft's end.  The first
    elastic mode of the coupled model converges to the eliminated model's as the
    coupling stiffens: the coupling's 1/k_t and the stub's 1.3e-14 rad/(N m) add in
    series to the drivetrain's 1.29e-9, at k_t = 1e13 N m/rad 8e-5 of it, which moves
    f by half that, 4e-5 (< 1e-4); any shift the tie made beyond that would show."""
    case = module.case
    stub_section = ShaftSection(1e-3, 2.0)
    main = case.drivetrain.shaft("main_shaft")
    stub = dataclasses.replace(
        main, name="carrier_stub", sections=(stub_section,), elements_per_section=1
    )
    tie = dataclasses.replace(
        case.drivetrain.couplings[0],
        name="tie",
        a="main_shaft.end",
        b="carrier_stub.start",
        torsional_damping=0.0,
    )
    reference = drivetrain_modes(assemble_drivetrain(case, dof_set="torsional"), 6).frequencies_hz
    errors = []
    for stiffness in (1e11, 1e13):
        drivetrain = dataclasses.replace(
            case.drivetrain,
            shafts=(*case.drivetrain.shafts, stub),
            couplings=(*case.drivetrain.couplings, dataclasses.replace(tie, torsional=stiffness)),
            mounts=(GearboxMount("stage1.carrier", "carrier_stub.end"), case.drivetrain.mounts[1]),
        )
        coupled = dataclasses.replace(case, drivetrain=drivetrain, scenes=())
        frequencies = drivetrain_modes(
            assemble_drivetrain(coupled, dof_set="torsional"), 6
        ).frequencies_hz
        errors.append(abs(frequencies[1] / reference[1] - 1))
    assert errors[1] < 1e-4
    assert errors[1] < errors[0]


def test_torsional_set_equals_spatial_torsion_when_nothing_couples(module):
    """With the gearbox replaced by its ratio no element couples torsion to bending or
    translation, so the torsional DOF set is exact: the spatial model has the same
    torsional frequency (to the eigensolver's round-off, 1e-9 relative)."""
    case = ratio_case(module, JONKMAN_RATIO)
    structure, _ = build_structure(case.drivetrain)
    assert structure.assemble().torsion_is_decoupled()
    torsional, _ = first_elastic(
        drivetrain_modes(assemble_drivetrain(case, dof_set="torsional"), 3)
    )
    spatial = drivetrain_modes(assemble_drivetrain(case, dof_set="spatial"), 12).frequencies_hz
    assert np.min(abs(spatial / torsional - 1)) < 1e-9


def test_gearbox_block_sits_at_its_offset(module):
    """The gearbox's reduced matrices appear unchanged at the offset, except where the
    eliminated shaft nodes add their own terms."""
    model = assemble_drivetrain(module.case, dof_set="spatial")
    block = slice(model.gearbox_offset, model.size)
    assert model.labels[block] == model.gearbox.dof_labels
    tied = [model.index(label) - model.gearbox_offset for label in model.tied]
    free = np.setdiff1d(np.arange(model.gearbox.size), tied)
    mass = model.mass[block, block].toarray()
    np.testing.assert_array_equal(mass[np.ix_(free, free)], model.gearbox.mass[np.ix_(free, free)])


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (
            lambda d: {
                "shafts": (
                    dataclasses.replace(d.shafts[0], sections=(ShaftSection(0.2, 1.0, 1.0),)),
                    *d.shafts[1:],
                )
            },
            r"^drivetrain\.shafts\[0\]\.sections\[0\]\.inner_diameter must be below outer_diameter",
        ),
        (
            lambda d: {"shafts": (dataclasses.replace(d.shafts[0], density=-1.0), *d.shafts[1:])},
            r"^drivetrain\.shafts\[0\]\.density must be a positive finite number",
        ),
        (
            lambda d: {
                "bearings": (dataclasses.replace(d.bearings[0], position=0.3), *d.bearings[1:])
            },
            r"^drivetrain\.bearings\[0\]\.position must be a node of shaft 'main_shaft'",
        ),
        (
            lambda d: {
                "bearings": (dataclasses.replace(d.bearings[0], radial=-1.0), *d.bearings[1:])
            },
            r"^drivetrain\.bearings\[0\]\.radial must be a finite number >= 0",
        ),
        (
            lambda d: {
                "bearings": (dataclasses.replace(d.bearings[0], shaft="nowhere"), *d.bearings[1:])
            },
            r"^drivetrain\.bearings\[0\]\.shaft: no shaft named 'nowhere'",
        ),
        (
            lambda d: {"mounts": (GearboxMount("stage1.planet1", "main_shaft.end"),)},
            r"^drivetrain\.mounts\[0\]\.member 'stage1\.planet1'",
        ),
    ],
)
def test_bad_input_gives_one_line_errors(module, change, message):
    drivetrain = module.case.drivetrain
    with pytest.raises(CaseError, match=message) as error:
        dataclasses.replace(
            module.case, drivetrain=dataclasses.replace(drivetrain, **change(drivetrain))
        )
    assert "\n" not in str(error.value)


def test_modal_command_runs_on_the_drivetrain(capsys):
    assert (
        main(["modal", "nrel5mw_drivetrain", "--dof-set", "torsional", "--modes", "4", "--json"])
        == 0
    )
    result = json.loads(capsys.readouterr().out)
    assert result["dof_set"] == "torsional" and len(result["frequencies_hz"]) == 4
    assert result["frequencies_hz"][0] == 0.0  # the free rotation
    assert 1.5 < result["frequencies_hz"][1] < 2.3  # below the rigid limit, 2.22 Hz
