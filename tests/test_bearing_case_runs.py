"""Rolling bearings in a case's transient run (scene effect ``rolling_bearing_contact``):
the study planetary stage with a roller bearing on every planet pin, carrier driven at
120 rpm with 200 N m.  References: the quasi-static load distribution at the pin load
T / (N r_c) (Harris & Kotzalas 2007, ch. 7) and the cage kinematics f_c = (1 + gamma) f_o
/ 2 of a bearing whose inner ring (the pin) and load stand still in the carrier frame
(Harris & Kotzalas ch. 8)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pygear.analysis.condition.bearing_load import load_distribution
from pygear.analysis.time.transient import run_transient
from pygear.errors import CaseError
from pygear.model.case import Scene, load_case_module
from pygear.model.rolling_bearing import BearingDefect, RollingBearing
from pygear.model.transient_settings import Probe, TorqueLaw

TORQUE = 200.0  # N m on the carrier
PIN_BEARING = RollingBearing(
    "PB", "roller", elements=14, pitch_diameter=0.05, element_diameter=0.008,
    roller_length=0.008, diametral_clearance=5e-6, location="planetary.planet",
)  # fmt: skip


@pytest.fixture(scope="module")
def study():
    _, module = load_case_module("yang2016_planetary")
    return module


def steady_scene(study, effects: tuple[str, ...], duration: float = 2.0) -> Scene:
    settings = dataclasses.replace(
        study.STEADY_SENSOR,
        duration=duration,
        mean_window=min(1.0, duration),
        drive=TorqueLaw.constant(TORQUE),
        load=TorqueLaw.generator(rated_drive_torque=TORQUE, exponent=study.LOAD_EXPONENT),
        equivalent_load="iterate",
        start_loaded=True,
        probes=(
            Probe("speed", "planetary.planet1"),  # spin relative to the carrier [rpm]
            Probe("displacement", "planetary.planet1.zeta"),
            Probe("displacement", "planetary.planet1.eta"),
        ),
    )
    return Scene(
        "bearing_run", analyses=("transient",), formulation="improved", dof_set="planar",
        effects=effects, transient=settings, parameters={"damping.mass_coefficient": 0.0},
    )  # fmt: skip


@pytest.fixture(scope="module")
def bearing_run(study):
    case = dataclasses.replace(study.case, rolling_bearings=(PIN_BEARING,))
    return run_transient(case, steady_scene(study, ("rolling_bearing_contact",)))


def test_planet_bearings_carry_the_pin_load(study, bearing_run):
    """The planet's mean deflection on its pin over the last second lies within the
    quasi-static load distribution's range over a cage turn at the pin load T / (3 r_c)
    (the carrier's own displacement is zero by symmetry; 0.2 % for what the damped
    start leaves)."""
    late = bearing_run.time.values >= 1.0
    zeta, eta = bearing_run.translation_displacement.values[:, late]
    deflection = np.hypot(zeta.mean(), eta.mean())
    load = TORQUE / (3 * study.stage.carrier.radius)
    extremes = [
        load_distribution(PIN_BEARING, load, cage_angle_deg=a).attrs["radial_deflection"]
        for a in (0.0, 180.0 / PIN_BEARING.elements)
    ]
    assert min(extremes) * 0.998 <= deflection <= max(extremes) * 1.002


def test_planet_bearing_varies_at_z_times_the_cage_rate(bearing_run):
    """The pin's rollers pass the load (fixed in the carrier frame) at Z f_c,
    f_c = (1 + gamma) f_o / 2, f_o the planet's spin relative to the carrier: the
    largest line of the tangential deflection above 5 Hz, within one bin (1 Hz)."""
    late = bearing_run.time.values >= 1.0
    eta = bearing_run.translation_displacement.values[1, late]
    rate = 1.0 / float(np.diff(bearing_run.time.values[:2])[0])
    spectrum = np.abs(np.fft.rfft((eta - eta.mean()) * np.hanning(eta.size)))
    frequency = np.fft.rfftfreq(eta.size, 1.0 / rate)
    spin_hz = abs(float(bearing_run.speed.values[0, late].mean())) / 60.0
    expected = PIN_BEARING.elements * 0.5 * (1 + PIN_BEARING.gamma) * spin_hz
    above = frequency > 5.0
    found = frequency[above][np.argmax(spectrum[above])]
    assert abs(found - expected) <= frequency[1]


def test_a_scene_without_the_effect_runs_the_linear_springs(study):
    """Rolling bearings in the case change nothing in a scene that does not call for
    them: the same run as without them (the same path: to round-off)."""
    scene = steady_scene(study, (), duration=0.2)
    with_bearings = dataclasses.replace(study.case, rolling_bearings=(PIN_BEARING,))
    plain = run_transient(study.case, scene).translation_displacement.values
    carried = run_transient(with_bearings, scene).translation_displacement.values
    np.testing.assert_allclose(carried, plain, rtol=0, atol=1e-12 * np.abs(plain).max())


def test_an_element_defect_is_refused_before_the_run(study):
    """Element defects are not in the kernel: one line naming the bearing and defect."""
    spalled = dataclasses.replace(
        PIN_BEARING, defects=(BearingDefect("element", width=1e-3, depth=5e-6),)
    )
    case = dataclasses.replace(study.case, rolling_bearings=(spalled,))
    with pytest.raises(CaseError, match=r"defects\[0\]\.location 'element'"):
        run_transient(case, steady_scene(study, ("rolling_bearing_contact",), duration=0.01))


def test_nrel_scene_puts_the_spall_on_planet_one_and_runs():
    """The NREL 5 MW case's planet_bearing_outer_race scene: all 12 planet bearings
    (two per pin, three pins per stage, two stages) are Hertz contacts, and only
    planet 1's IMS-PL-A carries the spall, as its outer-race width over the
    race radius (D + d) / 2 and its depth; a short stretch of the scene runs with the
    ring sensor recording."""
    from pygear.analysis.time.transient import transient_problem
    from pygear.model.case import load_case

    case = load_case("nrel5mw_gearbox")
    scene = case.scene("planet_bearing_outer_race")
    short = dataclasses.replace(
        scene, transient=dataclasses.replace(scene.transient, duration=0.2, mean_window=0.1)
    )
    problem = transient_problem(case.for_scene(short), short)
    terms = problem.solver.bearings
    assert terms.size == 12
    (spalled,) = terms.defects[0]
    name = terms.names[spalled - 1]
    assert name == "IMS-PL-A@stage2.planet1"
    bearing = next(b for b in case.rolling_bearings if b.name == "IMS-PL-A")
    radius = 0.5 * (bearing.pitch_diameter + bearing.element_diameter)
    assert terms.defects[1, 0] == 1  # the outer ring
    np.testing.assert_allclose(terms.defect_values[1:, 0], [4e-3 / radius, 10e-6], rtol=1e-12)
    run = run_transient(case.for_scene(short), short, problem=problem)
    assert np.isfinite(run.sensor_acceleration.values).all()
