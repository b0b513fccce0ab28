"""K_Hbeta from the model's static deflection: the mismatch follows the supports'
stiffness, zero mismatch leaves the manufacturing-only value, and ISO 6336-1's
F_betax -> F_betay -> K_Hbeta chain by hand from the model's mismatch."""

from __future__ import annotations

import dataclasses
import math

import pytest

from pygear.analysis.rating import deflection
from pygear.analysis.rating.deflection import mesh_misalignments
from pygear.analysis.rating.gearbox_rating import rate_gearbox
from pygear.model.rating import load_rating

MESH = "parallel.mesh"


@pytest.fixture(scope="module")
def nrel():
    case, rating = load_rating("nrel5mw_gearbox")
    # the helical pair's K_Hbeta from the model instead of the typed 1.15
    table = {k: v for k, v in rating.face_load_factor.items() if k != MESH}
    return case, dataclasses.replace(rating, face_load_factor=table, face_load_from_model=True)


def _stiffer(case, factor: float):
    """The case with the helical pair's bearings ``factor`` times stiffer in tilt."""
    stage = case.gearbox.stage("parallel")
    stiff = dataclasses.replace(
        stage,
        input_bearing=dataclasses.replace(stage.input_bearing,
                                          tilt=factor * stage.input_bearing.tilt),
        output_bearing=dataclasses.replace(stage.output_bearing,
                                           tilt=factor * stage.output_bearing.tilt))
    gearbox = dataclasses.replace(case.gearbox, stages=tuple(
        stiff if s.name == "parallel" else s for s in case.gearbox.stages))
    return dataclasses.replace(case, gearbox=gearbox)


def _k_hbeta(result, mesh: str = MESH):
    return {m.name: m.rating.mesh for m in result.meshes}[mesh]


def test_stiffer_bearings_give_a_smaller_mismatch_and_k_hbeta(nrel):
    case, rating = nrel
    slopes, factors = [], []
    for factor in (1.0, 2.0, 10.0):
        stiffer = _stiffer(case, factor)
        slopes.append(mesh_misalignments(stiffer, rating.rated_torque)["parallel.input-output"])
        factors.append(_k_hbeta(rate_gearbox(stiffer, rating))["K_Hbeta"].value)
    # the gearbox's pair tilts only on these bearings' tilt springs: a linear static
    # state, so the slope falls as 1/k exactly (round-off of a dense solve, 1e-9)
    assert slopes[0] != 0.0
    assert slopes[1] == pytest.approx(slopes[0] / 2.0, rel=1e-9)
    assert slopes[2] == pytest.approx(slopes[0] / 10.0, rel=1e-9)
    assert factors[0] > factors[1] > factors[2]


def test_the_static_state_is_linear_in_the_torque(nrel):
    case, rating = nrel
    one = mesh_misalignments(case, rating.rated_torque)
    two = mesh_misalignments(case, 2.0 * rating.rated_torque)
    for mesh, slope in one.items():
        assert two[mesh] == pytest.approx(2.0 * slope, rel=1e-9, abs=1e-18)


def test_zero_mismatch_gives_the_manufacturing_only_value(nrel, monkeypatch):
    case, rating = nrel
    plain = _k_hbeta(rate_gearbox(case, dataclasses.replace(rating,
                                                            face_load_from_model=False)))
    monkeypatch.setattr(deflection, "mesh_misalignments",
                        lambda case, torque: {"parallel.input-output": 0.0})
    level = _k_hbeta(rate_gearbox(case, rating))
    assert level["f_sh"].value == 0.0 and level["K_Hbeta"].source == "model"
    assert plain["K_Hbeta"].source == "computed"
    # same arithmetic once f_sh = 0: equal to round-off
    assert level["K_Hbeta"].value == pytest.approx(plain["K_Hbeta"].value, rel=1e-14)
    # the planetary meshes are symmetric: no tilt, the manufacturing-only value too
    monkeypatch.undo()
    slopes = mesh_misalignments(case, rating.rated_torque)
    assert all(abs(v) < 1e-15 for k, v in slopes.items() if not k.startswith("parallel"))


def test_annex_e_chain_by_hand(nrel):
    # ISO 6336-1:2019 cl. 7: f_sh = |slope| b at the line load F_m / b (the static
    # state at the nominal F_t scaled to F_m = F_t K_A K_gamma K_v), F_betax = f_sh +
    # f_ma with f_ma = f_Hbeta of ISO 1328-1 grade 6, y_beta = 0.15 F_betax (<= 6 um,
    # both gears hardened), F_betay = F_betax - y_beta, c_gamma_beta = 0.85
    # c_gamma_alpha, K_Hbeta = 1 + c_gamma_beta F_betay b / (2 F_m) up to 2, else
    # sqrt(2 c_gamma_beta F_betay b / F_m)
    case, rating = nrel
    slope = abs(mesh_misalignments(case, rating.rated_torque)["parallel.input-output"])
    mesh = _k_hbeta(rate_gearbox(case, rating))
    pinion = case.gearbox.stage("parallel")
    g1 = pinion.input_gear.geometry
    g2 = pinion.output_gear.geometry
    b = 1e3 * min(g1.face_width, g2.face_width)  # mm
    f_t = mesh["F_t"].value
    f_m = f_t * mesh["K_A"].value * mesh["K_gamma"].value * mesh["K_v"].value
    f_sh = slope * b * 1e3 * (f_m / f_t)  # um: slope [um/mm] x b [mm] at F_m
    beta = math.radians(abs(g1.helix_angle_deg))
    d = [g.teeth * g.normal_module * 1e3 / math.cos(beta) for g in (g1, g2)]
    f_hb = (0.07 * math.sqrt(max(d)) + 0.45 * math.sqrt(0.4 * max(d)) + 3.0) * 2.0**0.5
    f_bx = max(f_sh + f_hb, 0.005 * f_m / b)
    f_by = f_bx - min(0.15 * f_bx, 6.0)
    c_gb = 0.85 * mesh["c_gamma_alpha"].value
    ratio = c_gb * f_by * b / (2.0 * f_m)
    hand = 1.0 + ratio if ratio <= 1.0 else math.sqrt(4.0 * ratio)
    assert mesh["f_sh"].value == pytest.approx(f_sh, rel=1e-9)
    assert mesh["K_Hbeta"].value == pytest.approx(hand, rel=1e-9)
    assert f_sh > 1.0  # the model's mismatch matters here (um)


def test_the_command_takes_the_model_mismatch(capsys):
    import json

    from pygear.cli.parser import main

    argv = ["rate", "nrel5mw_drivetrain", "--dynamic-factor", "iso", "--json"]
    assert main([*argv, "--face-load", "model"]) == 0
    model = json.loads(capsys.readouterr().out)["meshes"][MESH]
    assert main([*argv, "--face-load", "iso"]) == 0
    plain = json.loads(capsys.readouterr().out)["meshes"][MESH]
    # the drivetrain's case types K_Hbeta of the helical pair: the given value stays
    assert model["K_Hbeta"] == plain["K_Hbeta"] and "K_Hbeta" in model["given"]
    assert "f_sh" not in model


def test_a_crowned_pair_takes_k_hbeta_from_the_loaded_contact_analysis(nrel):
    # crowning on the helical pair's input gear: K_Hbeta is the LTCA's face load peak
    # over its mean at the rated F_m with the model's mismatch (either sign, the larger),
    # and a mismatch loads the crowned face off centre: above the aligned pair's
    from pygear.analysis.contact.ltca_case import case_loaded_contact
    from pygear.model.micro_geometry import Misalignment, Modifications

    case, rating = nrel
    stage = case.gearbox.stage("parallel")
    crowned = dataclasses.replace(stage, input_gear=dataclasses.replace(
        stage.input_gear, modifications=Modifications(crowning=20e-6)))
    gearbox = dataclasses.replace(case.gearbox, stages=tuple(
        crowned if s.name == "parallel" else s for s in case.gearbox.stages))
    crowned_case = dataclasses.replace(case, gearbox=gearbox)
    mesh = _k_hbeta(rate_gearbox(crowned_case, rating))
    factor = mesh["K_Hbeta"]
    assert factor.source == "model" and "loaded tooth contact analysis" in factor.clause
    # the same analysis by hand: the force along the transverse line of action at F_m
    slope = abs(mesh_misalignments(crowned_case, rating.rated_torque)["parallel.input-output"])
    g1 = crowned.input_gear.geometry
    beta = math.radians(abs(g1.helix_angle_deg))
    alpha_t = math.atan(math.tan(math.radians(g1.normal_pressure_angle_deg)) / math.cos(beta))
    f_m = mesh["F_t"].value * mesh["K_A"].value * mesh["K_gamma"].value * mesh["K_v"].value
    torque = f_m / math.cos(alpha_t) * crowned.input_gear.base_radius
    b = min(g1.face_width, crowned.output_gear.geometry.face_width)

    def k_hbeta(mismatch: float) -> float:
        mods = Modifications(crowning=20e-6, misalignment=Misalignment(mismatch=mismatch))
        tilted = dataclasses.replace(crowned, input_gear=dataclasses.replace(
            crowned.input_gear, modifications=mods))
        box = dataclasses.replace(case.gearbox, stages=tuple(
            tilted if s.name == "parallel" else s for s in case.gearbox.stages))
        ds = case_loaded_contact(dataclasses.replace(case, gearbox=box),
                                 "parallel.input-output", torque)
        return float(ds.k_h_beta.values[0])

    hand = max(k_hbeta(slope * b), k_hbeta(-slope * b))
    assert factor.value == pytest.approx(hand, rel=1e-9)
    assert factor.value > k_hbeta(0.0) * 1.01
