"""Rotor commands: ``pygear modal --speed``, ``pygear campbell`` and ``pygear frf`` on
rotor and drivetrain cases; critical speeds of a Jeffcott rotor from its Campbell
diagram; the drivetrain's gyroscopic terms at each shaft's speed ratio."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from pygear.analysis.modes.sparse_gyroscopic import rotor_campbell, rotor_modes
from pygear.assembly.drivetrain import assemble_drivetrain
from pygear.cli.parser import main
from pygear.model.case import load_case

CASES = Path(__file__).resolve().parent.parent / "cases"
FRISWELL = str(CASES / "friswell_rotor")
# Friswell et al. (2010) Example 5.9.1 at 4000 rev/min as printed [rad/s] by ROSS's
# documentation of the example (as in test_rotor.py).
FRISWELL_4000RPM_RAD_S = (85.389467, 87.7958637, 251.78460413, 294.71333087)


def test_modal_at_a_speed_prints_whirl(capsys):
    assert main(["modal", FRISWELL, "--speed", "4000", "--modes", "4", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(
        result["frequencies_hz"], np.array(FRISWELL_4000RPM_RAD_S) / (2 * math.pi), rtol=1e-7
    )
    assert result["whirl"] == ["backward", "forward", "backward", "forward"]


def test_campbell_of_a_rotor_finds_the_critical_speeds(tmp_path, capsys):
    """A critical speed is where a mode's frequency meets the 1x line: the mode's
    frequency there equals speed / 60 (linear interpolation in a 50 rpm step: 1e-3)."""
    out = tmp_path / "out"
    code = main(["campbell", FRISWELL, "--speeds", "0:4000:81", "--json", "--out", str(out)])
    assert code == 0
    result = json.loads(capsys.readouterr().out)
    assert (out / "campbell.nc").exists() and (out / "campbell.png").exists()
    critical = result["critical_speeds"]
    assert [c["whirl"] for c in critical] == ["backward", "forward", "backward", "forward"]
    model = assemble_drivetrain(load_case("friswell_rotor"))
    for c in critical:
        modes = rotor_modes(model, c["speed_rpm"], 6)
        lateral = modes.frequency.values[modes.kind.values == "lateral"]
        assert np.min(np.abs(lateral - c["speed_rpm"] / 60.0)) < 1e-3 * c["speed_rpm"] / 60.0


def test_jeffcott_critical_speed_is_its_damped_natural_frequency():
    """A disc at midspan has no gyroscopic couple: its frequency stays omega_n
    sqrt(1 - zeta^2) at every speed, and the 1x line meets it at 60 times that.  The
    model's massless shaft on 1e13 N/m bearings puts modes at 3e7 Hz: the dense state
    space cannot tell 14 Hz from its round-off floor for zero (sqrt(eps) omega_max),
    the sparse shift-invert solver can."""
    from test_rotor import JEFFCOTT_MASS, JEFFCOTT_STIFFNESS, ZETA, _jeffcott

    _, model = _jeffcott()
    damped = math.sqrt(JEFFCOTT_STIFFNESS / JEFFCOTT_MASS * (1 - ZETA**2)) / (2 * math.pi)
    campbell = rotor_campbell(model, np.linspace(0.0, 2 * 60 * damped, 9), 2, solver="sparse")
    speeds = campbell.critical_speed.values
    assert speeds.size == 2  # the forward and backward circles of the same frequency
    np.testing.assert_allclose(speeds, 60 * damped, rtol=1e-6)


def test_drivetrain_gyroscopic_terms_follow_each_shaft_speed_ratio():
    """Each shaft's and disc's G is its own times its shaft's speed over the rotor's (the
    gear ratio from the tooth numbers: the high-speed shaft turns at -96.354 x): the
    assembled G equals, shaft by shaft, the ratio times G assembled with every ratio 1."""
    from pygear.assembly.drivetrain import build_structure

    case = load_case("nrel5mw_drivetrain")
    model = assemble_drivetrain(case, dof_set="spatial")
    ratios = model.speed_ratios
    kinematic = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)  # Nejad et al.'s tooth numbers
    assert ratios["high_speed_shaft"] == pytest.approx(-kinematic, rel=1e-9)
    scaled = build_structure(case.drivetrain, ratios)[0].assemble()
    plain = build_structure(case.drivetrain, None)[0].assemble()
    for shaft, ratio in ratios.items():
        rows = [i for i, label in enumerate(plain.labels) if label.startswith(f"{shaft}_")]
        own = plain.gyroscopic[rows][:, rows].toarray()
        assert np.abs(own).max() > 0
        np.testing.assert_allclose(
            scaled.gyroscopic[rows][:, rows].toarray(), ratio * own, rtol=1e-12, atol=0
        )
    block = model.gyroscopic.toarray()
    np.testing.assert_allclose(block, -block.T, atol=1e-12 * np.abs(block).max())


@pytest.mark.parametrize(
    ("arguments", "parameter"),
    [
        (["frf", FRISWELL, "--speeds", "100:4000:20", "--unbalance", "nope:1e-4:0"], "--unbalance"),
        (
            ["frf", FRISWELL, "--speeds", "100:4000:20", "--unbalance", "disc_left:-1:0"],
            "--unbalance",
        ),
        (["frf", FRISWELL, "--speeds", "100:4000:20"], "--unbalance"),
        (
            [
                "frf",
                FRISWELL,
                "--speeds",
                "100:4000:20",
                "--unbalance",
                "disc_left:1e-4",
                "--operating",
                "5:1",
            ],
            "--operating",
        ),
        (["frf", FRISWELL, "--frf", "shaft_2.x", "--frequencies", "1:10:5"], "--frf"),
        (["campbell", FRISWELL, "--speeds", "0:10:4", "--solver", "qr"], "--solver"),
        (["modal", FRISWELL, "--speed", "nan"], "--speed"),
        (["campbell", FRISWELL, "--speeds", "0:10:4", "--scene", "modal"], "--scene"),
    ],
)
def test_rotor_commands_refuse_bad_input(tmp_path, capsys, arguments, parameter):
    code = main(
        [*arguments, "--out", str(tmp_path / "out")] if arguments[0] != "modal" else arguments
    )
    assert code == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and parameter in error


def test_frf_writes_bode_and_polar_and_api684_margins(tmp_path, capsys):
    out = tmp_path / "out"
    code = main(
        [
            "frf",
            FRISWELL,
            "--speeds",
            "100:4000:60",
            "--unbalance",
            "disc_right:1e-4:0",
            "--operating",
            "3000:3600",
            "--json",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    result = json.loads(capsys.readouterr().out)
    assert (out / "unbalance.nc").exists() and (out / "unbalance.png").exists()
    peaks = result["peaks"]["disc_right"]
    assert peaks and all(p["actual_margin_pct"] is not None for p in peaks)
    for p in peaks:  # undamped: a sharp peak, API 684 asks for its largest margins
        assert p["amplification_factor"] is None or p["amplification_factor"] > 2.5
