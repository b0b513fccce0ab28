"""The documentation site's own code and examples.

- The case that docs/writing_a_case.md builds part by part
  (``docs/tutorials/four_planet_stage/case.py``) loads, and its derived geometry, mode
  structure and run-up agree with closed forms: standard involute geometry (ISO 21771),
  Lin & Parker's (1999) mode classes of equally spaced planets, and the rigid-body
  run-up of docs/model.md §6.3.
- The page includes every part of the file it names (the markers exist).
- The generator of the case-parameter reference finds every field of every dataclass
  documented with a unit, and reports a field that is not.
- The names lists of docs/scenes.md: the parser of the page's items, and the mode
  classes that the classifier can return.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
TUTORIAL_CASE = DOCS / "tutorials" / "four_planet_stage"
sys.path.insert(0, str(DOCS / "_ext"))

import parameter_reference  # noqa: E402
import vocabulary  # noqa: E402

from pygear import load_case  # noqa: E402

MODULE = 4e-3  # m, the tutorial's normal module
PRESSURE_ANGLE = math.radians(20.0)  # ISO 53 basic rack, the GearGeometry default
SUN_TEETH, PLANET_TEETH, RING_TEETH = 28, 26, 80


@pytest.fixture(scope="module")
def tutorial():
    spec = importlib.util.spec_from_file_location("four_planet_stage", TUTORIAL_CASE / "case.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_page_shows_every_part_of_the_case_file():
    """Each ``:start-after: "# [part]"`` of the page has its two markers in the file."""
    page = (DOCS / "writing_a_case.md").read_text()
    source = (TUTORIAL_CASE / "case.py").read_text()
    parts = re.findall(r':start-after: "# \[(\w+)\]"', page)
    assert len(parts) >= 9  # imports ... case
    for part in parts:
        assert f"# [{part}]\n" in source and f"# [/{part}]\n" in source, part
        assert f':end-before: "# [/{part}]"' in page, part


def test_tutorial_geometry_is_standard_involute_geometry(tutorial):
    """Zero profile shift: r_b = m Z cos(alpha) / 2, the carrier radius is the reference
    centre distance m (Z_s + Z_p) / 2, both meshes work at 20 degrees, and the sun-planet
    contact ratio is the textbook formula with tip radii r + m."""
    stage = load_case(TUTORIAL_CASE).gearbox.stages[0]

    def base(teeth: int) -> float:
        return MODULE * teeth * math.cos(PRESSURE_ANGLE) / 2

    # round-off of the inverse involute and the cosines: 1e-12 relative
    assert stage.sun.base_radius == pytest.approx(base(SUN_TEETH), rel=1e-12)
    assert stage.planet.base_radius == pytest.approx(base(PLANET_TEETH), rel=1e-12)
    assert stage.ring.base_radius == pytest.approx(base(RING_TEETH), rel=1e-12)
    centre = MODULE * (SUN_TEETH + PLANET_TEETH) / 2
    assert stage.carrier.radius == pytest.approx(centre, rel=1e-12)
    assert stage.sun_mesh.pressure_angle_deg == pytest.approx(20.0, rel=1e-12)
    assert stage.ring_mesh.pressure_angle_deg == pytest.approx(20.0, rel=1e-12)
    tip_sun, tip_planet = MODULE * SUN_TEETH / 2 + MODULE, MODULE * PLANET_TEETH / 2 + MODULE
    path = (
        math.sqrt(tip_sun**2 - base(SUN_TEETH) ** 2)
        + math.sqrt(tip_planet**2 - base(PLANET_TEETH) ** 2)
        - centre * math.sin(PRESSURE_ANGLE)
    )
    contact_ratio = path / (math.pi * MODULE * math.cos(PRESSURE_ANGLE))
    assert stage.sun_mesh.contact_ratio == pytest.approx(contact_ratio, rel=1e-12)


def test_tutorial_modes_have_lin_and_parkers_structure(tutorial):
    """Four equally spaced planets, planar: 6 rotational frequencies (one the rigid
    rotation at 0 Hz), 6 translational ones twice each, 3 planet ones N - 3 = 1 time
    each; 21 modes (Lin & Parker 1999)."""
    from pygear.analysis.modes.modal import modal_analysis
    from pygear.assembly.matrices import assemble

    case = load_case(TUTORIAL_CASE)
    modal = modal_analysis(assemble(case, case.scene("modal")))
    classes = list(modal.mode_class.values)
    multiplicity = dict(zip(classes, modal.multiplicity.values))
    assert modal.attrs["dof_set"] == "planar"
    assert len(classes) == 21
    assert classes.count("rotational") == 6
    assert classes.count("translational") == 12 and multiplicity["translational"] == 2
    assert classes.count("planet") == 3 and multiplicity["planet"] == 1
    assert modal.frequency.values[0] == 0.0 and modal.frequency.values[1] > 100.0


def test_tutorial_runup_follows_the_rigid_body_theory(tutorial):
    """docs/model.md §6.3 for the consistent formulation: J_eq = J_c + J_s i^2 +
    N (m r_c^2 + I_p w^2), i = 1 + Z_r/Z_s, w = Z_r/Z_p - 1; t_s = -ln(1 - alpha J_eq
    omega_0 / T_D) / alpha, and the equilibrium x = omega/omega_0 solves
    T_D (1 - x^2) = alpha J_eq omega_0 x.  The speed ratios are the ideal kinematics."""
    from pygear.analysis.time.transient import run_transient

    case = load_case(TUTORIAL_CASE)
    stage = case.gearbox.stages[0]
    run = run_transient(case, case.scene("runup"))
    ratio = 1 + RING_TEETH / SUN_TEETH
    spin = RING_TEETH / PLANET_TEETH - 1  # absolute planet spin per carrier turn
    inertia = (
        stage.carrier.polar_inertia
        + stage.sun.polar_inertia * ratio**2
        + stage.planets
        * (stage.planet.mass * stage.carrier.radius**2 + stage.planet.polar_inertia * spin**2)
    )
    alpha = case.damping.mass_coefficient
    omega_0 = tutorial.SPEED_RPM * math.pi / 30
    torque = tutorial.DRIVE_TORQUE
    t_s = -math.log(1 - alpha * inertia * omega_0 / torque) / alpha
    # the kernel finds t_s at a step and the elastic wind-up delays it slightly: two steps
    assert float(run.t_s) == pytest.approx(t_s, abs=2 * tutorial.runup.time_step)
    b = alpha * inertia * omega_0
    x = (-b + math.sqrt(b**2 + 4 * torque**2)) / (2 * torque)
    speeds = dict(zip(run.body.values.tolist(), run.equilibrium_speed.values.tolist()))
    # means over 0.5 s of the mesh-frequency ripple: measured 1e-8 off, 1e-6 allowed
    assert speeds["planetary.carrier"] == pytest.approx(x * tutorial.SPEED_RPM, rel=1e-6)
    sun_over_carrier = speeds["planetary.sun"] / speeds["planetary.carrier"]
    assert sun_over_carrier == pytest.approx(ratio, rel=1e-6)
    planet_over_carrier = speeds["planetary.planet1"] / speeds["planetary.carrier"]
    assert planet_over_carrier == pytest.approx(-RING_TEETH / PLANET_TEETH, rel=1e-6)


def test_every_case_parameter_is_documented_with_a_unit():
    """The reference the site generates lists every field; nothing is missing."""
    problems: list[str] = []
    text = parameter_reference.page(problems)
    assert problems == []
    for name in ("``stiffness``", "``planet_angles_deg``", "``noise_snr_db``", "``depth``"):
        assert name in text
    assert "N/m" in text and "kg m^2" in text


def test_an_undocumented_field_fails_the_reference():
    """A field without a Parameters entry, or a real number without a unit, is reported."""

    @dataclasses.dataclass(frozen=True)
    class Spring:
        """A spring.

        Parameters
        ----------
        stiffness : float
            Stiffness [N/m], >= 0.
        preload : float
            Force at rest.
        """

        stiffness: float
        preload: float = 0.0
        length: float = 1.0

    problems: list[str] = []
    rows = parameter_reference.rows(Spring, problems)
    assert [row.name for row in rows] == ["stiffness", "preload"]
    assert rows[0].unit == "N/m" and rows[0].default == "required"
    assert problems == [
        "Spring.preload: a real number without a unit (write it in brackets, [-] for a "
        "pure number)",
        "Spring.length: no description in Parameters",
    ]


@pytest.mark.parametrize(
    ("description", "count", "units"),
    [
        (["Material of both gears [Pa, -], for the law."], 2, ["Pa", "-"]),
        (["Table samples [s], [N m]; linear."], 2, ["s", "N m"]),
        (["Ramp start and length [s]."], 2, ["s", "s"]),
        (["Stiffness factor [-], in [0, 1]: 1 healthy."], 1, ["-"]),
        (["Stiffness factor in [0, 1]."], 1, [""]),
    ],
)
def test_units_are_read_from_brackets_but_not_from_intervals(description, count, units):
    assert parameter_reference._units(description, count) == units


def test_the_page_items_are_read_with_continuation_lines():
    items = vocabulary._items(["- `modal`: natural", "  frequencies.", "", "- `signal`: spectra."])
    assert items == {"modal": "natural frequencies.", "signal": "spectra."}


def test_mode_classes_are_those_the_model_page_names():
    """Every class in docs/model.md §10's table, and `mixed`, and nothing else."""
    expected = {
        "planet", "planet-out-of-plane", "planet-coupled", "rotational", "axial",
        "rotational-axial", "translational", "tilting", "translational-tilting", "mixed",
    }  # fmt: skip
    assert set(vocabulary.mode_classes()) == expected
