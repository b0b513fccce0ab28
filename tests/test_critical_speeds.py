"""Undamped critical speeds and their map against bearing stiffness.

References, never the code's own output:

* a disc at the middle of a massless, pinned, Euler-Bernoulli shaft of length L on two
  bearings of radial stiffness k (Jeffcott 1919 with flexible supports; Friswell,
  Penny, Garvey & Lees, *Dynamics of Rotating Machines*, 2010, §3.5 and §3.6): the
  disc's translation sees 48 EI / L^3 in series with 2k, so
  Omega_1^2 = k_t / m, 1 / k_t = L^3 / (48 EI) + 1 / (2k), for both whirls (the
  symmetric mode does not tilt the disc); its tilt sees 12 EI / L (a moment at the
  middle of a pinned beam turns it by M L / (12 EI)) in series with k L^2 / 2 (the
  bearings' reactions +-M / L), so Omega^2 = k_r / (I_d - I_p) forward and
  k_r / (I_d + I_p) backward;
* the rigid-bearing limit k -> oo: 48 EI / (m L^3); the soft limit: 2k / m;
* Friswell's Example 5.9.1 case's critical speeds from its Campbell crossings
  (825.1 B, 829.9 F, 2487.8 B, 2756.1 F rpm, tests/test_rotor_cli.py), which the map
  at the case's own bearing stiffness (1e6 N/m) must list as well.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from pygear import Disc, Drivetrain, RotorCase, Shaft, ShaftBearing, ShaftSection
from pygear.analysis.modes.critical_speeds import critical_speed_map
from pygear.cli import main

pytestmark = pytest.mark.filterwarnings(
    "ignore::pygear.model.plausibility.PlausibilityWarning"  # the nearly massless shaft
)

LENGTH, DIAMETER, YOUNG = 1.0, 0.05, 2.1e11
MASS, POLAR, DIAMETRAL = 20.0, 0.05, 0.15  # a long disc: I_d > I_p, a forward conical
SHAFT_DENSITY = 7.85e-3  # kg/m^3: a nearly massless shaft
BENDING = YOUNG * math.pi * DIAMETER**4 / 64  # EI [N m^2]


def jeffcott_case() -> RotorCase:
    """The disc at mid-span of a shaft 1e-6 times as dense as steel, pinned bearings."""
    shaft = Shaft(
        "shaft",
        (ShaftSection(LENGTH / 2, DIAMETER), ShaftSection(LENGTH / 2, DIAMETER)),
        young_modulus=YOUNG,
        shear_modulus=8.1e10,
        density=SHAFT_DENSITY,
        elements_per_section=2,
        shear_deformation=False,
    )
    disc = Disc(
        "disc", "shaft", LENGTH / 2, mass=MASS, polar_inertia=POLAR, diametral_inertia=DIAMETRAL
    )
    bearings = (
        ShaftBearing("left", "shaft", 0.0, radial=1e6),
        ShaftBearing("right", "shaft", LENGTH, radial=1e6),
    )
    return RotorCase(
        name="jeffcott", drivetrain=Drivetrain(shafts=(shaft,), discs=(disc,), bearings=bearings)
    )


def closed_form_rpm(k: float) -> np.ndarray:
    """The four synchronous critical speeds [rpm], ascending."""
    translation = 1.0 / (LENGTH**3 / (48 * BENDING) + 1.0 / (2 * k))
    tilt = 1.0 / (LENGTH / (12 * BENDING) + 2.0 / (k * LENGTH**2))
    omega = [math.sqrt(translation / MASS)] * 2 + [
        math.sqrt(tilt / (DIAMETRAL + POLAR)),
        math.sqrt(tilt / (DIAMETRAL - POLAR)),
    ]
    return np.sort(omega) * 30 / math.pi


def test_map_follows_the_jeffcott_closed_form_from_soft_to_rigid_bearings():
    """Over k = 1e3 .. 1e11 N/m the four critical speeds equal the closed form.

    Tolerance: the shaft's mass m_s next to the disc's m, and its diametral inertia
    about the middle, m_s L^2 / 12, next to the tilt inertia I_d - I_p that the forward
    conical mode sees: each frequency moves by at most half the larger ratio (the whole
    of it for the soft, rigid-body end), so twice that bound, 2.6e-5.  The forward
    conical one whirls forward, the two of the backward circle backward."""
    shaft_mass = SHAFT_DENSITY * math.pi * DIAMETER**2 / 4 * LENGTH
    tolerance = max(shaft_mass / MASS, shaft_mass * LENGTH**2 / 12 / (DIAMETRAL - POLAR))
    assert tolerance < 3e-5
    stiffness = np.geomspace(1e3, 1e11, 9)
    critical = critical_speed_map(jeffcott_case(), stiffness, 4)
    assert critical.sizes["line"] == 1
    for i, k in enumerate(stiffness):
        found = critical.critical_speed.values[i, 0]
        np.testing.assert_allclose(found, closed_form_rpm(k), rtol=tolerance)
        whirl = list(critical.whirl.values[i, 0])
        assert whirl[3] == "forward"  # I_d - I_p: the conical mode stiffened by the spin
        assert whirl[2] == "backward"
        assert sorted(whirl[:2]) == ["backward", "forward"]
    # the limits, each within the other spring's share of the series: k_s / 2k at the
    # stiff end, 2k / k_s at the soft end (the frequency moves by half of it)
    shaft = 48 * BENDING / LENGTH**3
    rigid = math.sqrt(shaft / MASS) * 30 / math.pi
    soft = math.sqrt(2 * stiffness[0] / MASS) * 30 / math.pi
    assert critical.critical_speed.values[-1, 0, 0] == pytest.approx(
        rigid, rel=shaft / (2 * stiffness[-1])
    )
    assert critical.critical_speed.values[0, 0, 0] == pytest.approx(
        soft, rel=2 * stiffness[0] / shaft
    )


def test_map_command_writes_its_files_and_lists_the_campbell_crossings(tmp_path, capsys):
    """At Friswell's bearing stiffness the map lists the crossings of the Campbell
    diagram (to the 0.1 rpm the book's diagram gives them); a disc heavier in polar
    than diametral inertia has no forward conical critical speed to list."""
    out = tmp_path / "map"
    assert (
        main(
            [
                "campbell",
                "friswell_rotor",
                "--critical-speed-map",
                "1e5:1e7:3",
                "--modes",
                "4",
                "--out",
                str(out),
                "--json",
            ]
        )
        == 0
    )
    summary = json.loads(capsys.readouterr().out)
    assert (out / "critical_speed_map.nc").is_file()
    assert (out / "critical_speed_map.png").is_file()
    assert summary["bearing_stiffness_n_per_m"][1] == pytest.approx(1e6)
    np.testing.assert_allclose(
        summary["critical_speeds_rpm"][1][0], [825.1, 829.9, 2487.8, 2756.1], atol=0.05
    )
    assert summary["whirl"][1][0] == ["backward", "forward", "backward", "forward"]


@pytest.mark.parametrize(
    ("arguments", "parameter"),
    [
        (["--critical-speed-map", "0:1e7:3"], "--critical-speed-map"),
        (["--critical-speed-map", "1e5:1e7"], "--critical-speed-map"),
        (["--critical-speed-map", "1e5:1e7:3", "--speeds", "0:10:3"], "--speeds"),
        ([], "--speeds"),
    ],
)
def test_map_refuses_bad_input(capsys, arguments, parameter):
    assert main(["campbell", "friswell_rotor", *arguments]) == 2
    error = capsys.readouterr().err
    assert parameter in error and len(error.strip().splitlines()) == 1


def test_map_refuses_a_gearbox_case(capsys):
    assert main(["campbell", "yang2016_planetary", "--critical-speed-map", "1e5:1e7:3"]) == 2
    assert "rotor and drivetrain" in capsys.readouterr().err
