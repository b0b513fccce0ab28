"""K_gamma from pygear's static model with planet position errors, against the closed
form of a torsional stage and the statics of a floating sun."""

from __future__ import annotations

import dataclasses
import math

import pytest

from pygear.analysis.rating.load_sharing import load_sharing_from_model, planet_mesh_forces
from pygear.assembly.matrices import assemble
from pygear.errors import CaseError
from pygear.model.case import load_case

TORQUE = 5e6 / (12.1 * math.pi / 30.0)  # the NREL 5 MW rated rotor torque [N m]


@pytest.fixture(scope="module")
def case():
    return load_case("nrel5mw_gearbox")


def test_torsional_stage_matches_the_closed_form(case):
    # Torsional model: every planet sees the same carrier and sun rotations; its own
    # rotation balances its two meshes (F_sun = F_ring), so F_i = k_s k_r/(k_s + k_r)
    # (a + b + 2 e_i) and F_i - mean F = k_eq (e_i - mean e), k_eq = 2 k_s k_r/(k_s + k_r).
    # The mean force is the nominal T_sun / (N r_b,sun).  Tolerance 1e-9: a linear solve.
    model = assemble(case, None, dof_set="torsional")
    k_s = next(m.mean_stiffness for m in model.meshes
               if m.stage == "stage1" and m.kind == "external")
    k_r = next(m.mean_stiffness for m in model.meshes
               if m.stage == "stage1" and m.kind == "internal")
    k_eq = 2.0 * k_s * k_r / (k_s + k_r)
    t_sun = TORQUE / (1.0 + 56.0 / 19.0)
    mean = t_sun / (3 * 19 * 0.045 / 2.0 * math.cos(math.radians(20.0)))
    errors = (50e-6, -10e-6, 0.0)
    hand = 1.0 + k_eq * (max(errors) - sum(errors) / 3.0) / mean
    found = load_sharing_from_model(case, {"stage1": errors}, TORQUE, dof_set="torsional")
    assert found["stage1"] == pytest.approx(hand, rel=1e-9)


def test_three_planets_round_a_floating_sun_share_equally(case):
    # statically determinate: the radially free sun (NREL's sun support has radial 0)
    # moves until the three forces balance, whatever one pin's error
    found = load_sharing_from_model(case, {"stage1": (50e-6, 0.0, 0.0)}, TORQUE)
    assert found["stage1"] == pytest.approx(1.0, abs=1e-9)


def test_errors_move_load_between_planets_but_keep_the_torque(case):
    # a held sun: the errored planet carries more, the sum stays the nominal N F
    from pygear import Bearing

    stage = case.gearbox.stage("stage1")
    held = dataclasses.replace(stage, sun_bearing=Bearing(radial=1e10, axial=1e8, tilt=1e6,
                                                          torsional=0.0))
    gearbox = dataclasses.replace(case.gearbox, stages=tuple(
        held if s.name == "stage1" else s for s in case.gearbox.stages))
    stiff = dataclasses.replace(case, gearbox=gearbox)
    forces = planet_mesh_forces(stiff, {"stage1": (50e-6, 0.0, 0.0)}, TORQUE)["stage1"]
    nominal = TORQUE / (1.0 + 56.0 / 19.0) / (19 * 0.045 / 2.0 * math.cos(math.radians(20.0)))
    assert forces.sum() == pytest.approx(nominal, rel=1e-9)
    assert forces[0] > forces[1] == pytest.approx(forces[2], rel=1e-9)


def test_rating_takes_the_models_k_gamma(case):
    from pygear.analysis.rating.gearbox_rating import rate_gearbox
    from pygear.model.rating import load_rating

    _, rating = load_rating("nrel5mw_gearbox")
    errored = dataclasses.replace(rating, planet_position_errors={"stage1": (5e-5, 0.0, 0.0)})
    result = rate_gearbox(case, errored)
    k_gamma = {m.name: m.rating.mesh["K_gamma"] for m in result.meshes}["stage1.sun_mesh"]
    assert k_gamma.source == "model" and k_gamma.value == pytest.approx(1.0, abs=1e-9)
    with pytest.raises(CaseError, match="give load_sharing or planet_position_errors"):
        dataclasses.replace(rating, load_sharing={"stage1": 1.1},
                            planet_position_errors={"stage1": (0.0, 0.0, 0.0)})
    with pytest.raises(CaseError, match=r"needs one error per planet \(3; got 2\)"):
        rate_gearbox(case, dataclasses.replace(
            rating, planet_position_errors={"stage1": (0.0, 0.0)}))
    with pytest.raises(CaseError, match=r"must be a finite error in m below 1 mm"):
        dataclasses.replace(rating, planet_position_errors={"stage1": (0.05, 0.0, 0.0)})


def test_a_planet_position_error_rates_lower_by_the_models_load_sharing(case):
    # a held sun: stage 1 with one pin 50 um out rates below the perfect stage, and the
    # contact safety of the sun falls by 1/sqrt(K_gamma) with K_gamma = max / mean of the
    # planets' sun-mesh forces (K_v and K_Halpha, which follow the line load, divided
    # out exactly); the damage rises
    from pygear import Bearing
    from pygear.analysis.rating.gearbox_rating import rate_gearbox
    from pygear.model.rating import load_rating

    stage = case.gearbox.stage("stage1")
    held = dataclasses.replace(stage, sun_bearing=Bearing(radial=1e10, axial=1e8, tilt=1e6,
                                                          torsional=0.0))
    gearbox = dataclasses.replace(case.gearbox, stages=tuple(
        held if s.name == "stage1" else s for s in case.gearbox.stages))
    stiff = dataclasses.replace(case, gearbox=gearbox)
    _, rating = load_rating("nrel5mw_gearbox")
    errors = (50e-6, 0.0, 0.0)
    rating = dataclasses.replace(rating, load_sharing={})
    perfect = rate_gearbox(stiff, dataclasses.replace(
        rating, planet_position_errors={"stage1": (0.0, 0.0, 0.0)}))
    errored = rate_gearbox(stiff, dataclasses.replace(
        rating, planet_position_errors={"stage1": errors}))
    forces = planet_mesh_forces(stiff, {"stage1": errors}, rating.rated_torque)["stage1"]
    k_gamma = forces.max() / forces.mean()
    assert k_gamma > 1.02  # the error matters (3 % at 50 um)
    mesh = {m.name: m for m in perfect.meshes}["stage1.sun_mesh"].rating
    worse = {m.name: m for m in errored.meshes}["stage1.sun_mesh"].rating
    assert mesh.mesh["K_gamma"].value == pytest.approx(1.0, abs=1e-9)
    assert worse.mesh["K_gamma"].value == pytest.approx(k_gamma, rel=1e-9)
    k_v = worse.mesh["K_v"].value / mesh.mesh["K_v"].value
    k_alpha = worse.mesh["K_Halpha"].value / mesh.mesh["K_Halpha"].value
    ratio = worse.gears[0]["S_H"].value / mesh.gears[0]["S_H"].value
    assert ratio == pytest.approx(1.0 / math.sqrt(k_gamma * k_v * k_alpha), rel=1e-12)
    assert worse.gears[0]["S_F"].value < mesh.gears[0]["S_F"].value
    assert errored.damage["stage1.sun"]["pitting"] > perfect.damage["stage1.sun"]["pitting"]
