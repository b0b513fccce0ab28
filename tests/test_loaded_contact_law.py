"""The mesh law ``loaded_contact``: the LTCA tabulated once per mesh and run by the
dynamics, against the potential-energy law, its own load table, and kinematics."""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from pygear import TorqueLaw
from pygear.analysis.time.transient import run_transient
from pygear.assembly.ltca import loaded_contact
from pygear.assembly.ltca_geometry import flank_roll_limits
from pygear.assembly.mesh_laws import mesh_law, tooth_bodies
from pygear.model.case import load_case
from pygear.model.micro_geometry import Deviations, Modifications, ProfileRelief

CARRIER_TORQUE = 5000.0
"""N m on the sequential stage's carrier: F_0 = 9.38 kN per sun mesh (313 N/mm), a static
deflection of about 18 um (F_0 over k-bar), above the 5 um pitch deviation below."""

PITCH_DEVIATION = 5e-6
"""f_pt of one sun tooth [m] (ISO 1328-1 grade 5 to 6 at m = 3 mm, d = 87 mm)."""


def _stage_case(sun_mods=None, planet_mods=None, law="loaded_contact", ring_law=None):
    """The sequentially phased stage on ``law``, its operating line load the mesh force
    of the carrier torque F_0 = T_s / (N r_bs), T_s = T_c / (1 + Z_r / Z_s)."""
    case = load_case("sequential_planetary")
    stage = case.gearbox.stages[0]
    sun_torque = CARRIER_TORQUE / (1 + stage.ring.teeth / stage.sun.teeth)
    line_load = sun_torque / (3 * stage.sun.base_radius) / stage.sun.geometry.face_width / 1e3
    mesh = {"law": law, "line_load": line_load} if law == "loaded_contact" else {"law": law}
    stage = dataclasses.replace(
        stage,
        sun=dataclasses.replace(stage.sun, modifications=sun_mods),
        planet=dataclasses.replace(stage.planet, modifications=planet_mods),
        sun_mesh=dataclasses.replace(stage.sun_mesh, **mesh),
        ring_mesh=dataclasses.replace(stage.ring_mesh, **(mesh if ring_law is None
                                                           else {"law": ring_law})),
    )
    return dataclasses.replace(case, gearbox=dataclasses.replace(case.gearbox, stages=(stage,)))


def _scene(case, duration=3.5):
    scene = case.scene("steady_sensor")
    transient = dataclasses.replace(
        scene.transient,
        duration=duration,
        drive=TorqueLaw.constant(CARRIER_TORQUE),
        load=TorqueLaw.generator(rated_drive_torque=CARRIER_TORQUE, exponent=2.0),
    )
    return dataclasses.replace(scene, transient=transient)


def test_unmodified_pair_has_the_potential_energy_stiffness():
    """Perfect flanks: delta_0 = 0, the TE-equivalent offset c is 0 and the pair curve is
    the potential-energy law's.  Tolerance 1e-3: the LTCA samples 40 positions per cycle
    and interpolates the law's 201 compliances linearly (measured 6e-5 on the mean)."""
    for member in ("sun", "ring"):
        energy = mesh_law(_stage_case(law="potential_energy").gearbox.stages[0], member)
        loaded = mesh_law(_stage_case().gearbox.stages[0], member)
        assert loaded.law == "loaded_contact" and loaded.table.te_offset() == 0.0
        assert loaded.mean_stiffness == pytest.approx(energy.mean_stiffness, rel=1e-3)
        assert loaded.contact_ratio == pytest.approx(energy.contact_ratio, rel=1e-12)
        np.testing.assert_allclose(loaded.curve, energy.curve, atol=2e-3)


def _tip_relief(gear_geometry, contact_ratio: float, amount: float) -> ProfileRelief:
    """Linear tip relief over the double-contact zone at the tip: the last
    (eps_alpha - 1) base pitches of the gear's roll length."""
    tip, _, base_radius = flank_roll_limits(gear_geometry)
    pitch = 2 * math.pi * base_radius / gear_geometry.teeth
    start = tip - (contact_ratio - 1) * pitch
    return ProfileRelief(amount=amount, start_roll_angle_deg=math.degrees(start / base_radius))


def _relieved_case():
    """Tip relief on sun and planet of the single-pair deflection at F_0 (Harris 1958)."""
    plain = _stage_case()
    stage = plain.gearbox.stages[0]
    law = mesh_law(stage, "sun")
    force = law.table.operating_force
    amount = force / law.curve.max() / (law.mean_stiffness / law.contact_ratio)
    eps = law.transverse_contact_ratio
    return _stage_case(
        Modifications(tip_relief=_tip_relief(stage.sun.geometry, eps, amount)),
        Modifications(tip_relief=_tip_relief(stage.planet.geometry, eps, amount)),
    )


def test_load_table_interpolates_between_its_loads():
    """The relieved sun mesh's stiffness at a load between two tabulated ones lies between
    theirs at every position (linear interpolation), and the LTCA solved directly at that
    load lies between them too: the table rises with the load as the relief closes."""
    stage = _relieved_case().gearbox.stages[0]
    law = mesh_law(stage, "sun")
    table = law.table
    low, high = table.force[2], table.force[3]  # F_0 and 1.5 F_0
    middle = 0.5 * (low + high)
    k_low, k_mid, k_high = (table.secant_stiffness(f) for f in (low, middle, high))
    assert np.all(k_high >= k_low)  # the relief closes: stiffer at the higher load
    assert np.all((k_mid >= k_low) & (k_mid <= k_high))
    radii = (stage.sun.foundation_radius, stage.planet.foundation_radius)
    bodies = tooth_bodies(stage.sun_mesh, law.geometry, radii)
    direct = loaded_contact(law.geometry, bodies, [middle],
                            modifications=(stage.sun.modifications, stage.planet.modifications),
                            n_slice=20, n_position=40, driving_gear=2)  # fmt: skip
    k_direct = direct.mesh_stiffness.values[0]
    # 1e-9 relative: round-off of the active-set solve between identical separations
    assert np.all(k_direct >= k_low * (1 - 1e-9)) and np.all(k_direct <= k_high * (1 + 1e-9))


def test_te_equivalent_stiffness_carries_the_loaded_te():
    """With tip relief (delta_0 != 0): a spring k_e(s) = F_0 / (delta(s) - c) (what a mesh
    with per-tooth deviations runs) deflects
    under F_0 by the loaded TE less the constant c (exact but for one division); k_e keeps
    the LTCA's mean secant stiffness (the bisection's 1e-12); and the pair curve the
    contact table reads sums over the pairs in contact, p = s + k, to k_e at every
    tabulated position: 5e-3, the resampling of 40 positions onto 201 samples where a
    pair's share jumps at the ends of contact (measured 2.5e-3 there, 5e-5 median)."""
    law = mesh_law(_relieved_case().gearbox.stages[0], "sun")
    table = law.table
    stiffness = table.equivalent_stiffness()
    offset = table.te_offset()
    assert offset > 0  # the relief opens the flanks: the rigid offset is not zero
    loaded = table.te_loaded[list(table.force).index(table.operating_force)]
    np.testing.assert_allclose(table.operating_force / stiffness + offset, loaded,
                               rtol=1e-13, atol=0)  # fmt: skip
    assert stiffness.mean() == pytest.approx(table.mean_stiffness(table.operating_force),
                                             rel=1e-12)  # fmt: skip
    # the curve a mesh with per-tooth deviations runs (the law's mean is the secant's)
    pair = law.equivalent_curve * law.mean_stiffness / law.contact_ratio
    samples = np.linspace(0.0, law.contact_ratio, pair.size)
    total = sum(np.interp(table.position + k, samples, pair, right=0.0)
                for k in range(math.ceil(law.contact_ratio) + 1))  # fmt: skip
    np.testing.assert_allclose(total, stiffness, rtol=5e-3)


def _mesh_harmonics(run, mesh: str, frequency: float, harmonics: int = 8) -> float:
    """Root sum square of the mesh force's amplitudes at the first mesh harmonics [N]
    (Hann window over the steady part)."""
    time = run.time.values
    force = run.mesh_force.sel(mesh=mesh).values
    window = np.hanning(time.size)
    force = force - force.mean()
    return math.sqrt(sum(
        (2 * abs(np.sum(window * force * np.exp(-2j * math.pi * k * frequency * time)))
         / window.sum()) ** 2
        for k in range(1, harmonics + 1)
    ))  # fmt: skip


@pytest.mark.slow
def test_tip_relief_lowers_the_dynamic_mesh_force_at_the_mesh_harmonics():
    """Tip relief of the single-pair deflection at the design load flattens the sun
    mesh's loaded TE (11.7 to 2.0 um peak to peak; Harris 1958, Tavakoli & Houser
    1986); through the loaded_contact law the sun mesh's dynamic force at the mesh
    harmonics k f_m, f_m = Z_r n_c / 60 = 194 Hz, k = 1..8 (up to 1.55 kHz, past the
    stage's modes near the 4th harmonic), falls against the unmodified pair's.  The
    ring mesh stays on the potential-energy law in both runs.  Measured (1.7 s steady):
    the rss falls from 146 N to 62 N; asserted below two thirds."""
    frequency = 97 * 120.0 / 60.0
    plain = _stage_case(ring_law="potential_energy")
    stage = plain.gearbox.stages[0]
    law = mesh_law(stage, "sun")
    amount = law.table.operating_force / (law.curve.max() * law.mean_stiffness / law.contact_ratio)
    eps = law.transverse_contact_ratio
    relieved = _stage_case(
        Modifications(tip_relief=_tip_relief(stage.sun.geometry, eps, amount)),
        Modifications(tip_relief=_tip_relief(stage.planet.geometry, eps, amount)),
        ring_law="potential_energy",
    )
    levels = []
    for case in (plain, relieved):
        scene = _scene(case, duration=2.5)
        run = run_transient(case.for_scene(scene), scene).sel(time=slice(0.8, None))
        levels.append(_mesh_harmonics(run, "planetary.sun-planet1", frequency))
    assert levels[1] < 2 / 3 * levels[0], levels


def _sun_orders(run, signal: np.ndarray, per_turn: int = 1024) -> np.ndarray:
    """Amplitudes of ``signal`` at whole orders of the sun's rotation relative to the
    carrier, from its synchronous average over the whole turns of the record."""
    angle = np.abs(
        run.rotation_displacement.sel(rotation_dof="planetary.sun.theta_z").values
        - run.rotation_displacement.sel(rotation_dof="planetary.carrier.theta_z").values
    )
    start = math.ceil(angle[0] / (2 * math.pi)) * 2 * math.pi
    turns = int((angle[-1] - start) // (2 * math.pi))
    grid = start + np.arange(turns * per_turn) * 2 * math.pi / per_turn
    average = CubicSpline(angle, signal)(grid).reshape(turns, per_turn).mean(axis=0)
    return np.abs(np.fft.rfft(average)) / per_turn * 2


@pytest.mark.slow
def test_single_pitch_deviation_repeats_once_per_sun_turn():
    """A 5 um pitch deviation on sun tooth 0: the sun-planet mesh sees the tooth once
    per turn of the sun relative to the carrier, f_s - f_c = Z_r f_c / Z_s (6.69 Hz at
    120 rpm), so the mesh force gains the orders 1, 2, 3 of that turn, and the ring
    sensor the sidebands Z_s +- 1, Z_s +- 2 around the mesh order Z_s of that turn
    (mesh frequency +- the sun's turn; Randall 1982).  Orders from the kinematics; the
    synchronous average over the sun's turns (16 of them) keeps what repeats every turn.
    Measured: orders 1-3 rss 4.5 N healthy (5e-4 of the 9.38 kN mean), 19.6 N with the
    deviation; sidebands rss 0.44 and 1.6 m/s^2.  Asserted: the healthy orders below
    1e-3 of the mean force, and both signatures at least 3 times the healthy ones."""
    teeth = 29
    deviations = [0.0] * teeth
    deviations[0] = PITCH_DEVIATION
    pitched = Modifications(deviations=Deviations(pitch=tuple(deviations)))
    force_orders, sidebands, mean = [], [], []
    for case in (_stage_case(), _stage_case(sun_mods=pitched)):
        scene = _scene(case)
        run = run_transient(case.for_scene(scene), scene).sel(time=slice(1.0, None))
        force = run.mesh_force.sel(mesh="planetary.sun-planet1").values
        mean.append(force.mean())
        orders = _sun_orders(run, force)
        force_orders.append(math.sqrt(np.sum(orders[1:4] ** 2)))
        sensor = _sun_orders(run, run.sensor_acceleration.sel(sensor="ring_sensor").values)
        band = [teeth - 2, teeth - 1, teeth + 1, teeth + 2]
        sidebands.append(math.sqrt(np.sum(sensor[band] ** 2)))
    assert force_orders[0] < 1e-3 * mean[0], (force_orders, mean)
    assert force_orders[1] > 3 * force_orders[0], force_orders
    assert sidebands[1] > 3 * sidebands[0], sidebands


def test_pitch_deviation_gives_every_sun_tooth_its_own_curve():
    """The contact table of a sun with one pitch deviation holds a pair curve for each of
    its 29 teeth; their mean over the revolution is the mesh-periodic law's within the
    pitch deviation's share (the curves sum to the TE-equivalent stiffness of the
    revolution, whose mean is the secant stiffness'); tooth 0's differs from tooth 14's
    (far from the deviation) by more than the discretisation (1e-3)."""
    from pygear.assembly.tooth_fault_curves import deviation_curves

    deviations = [0.0] * 29
    deviations[0] = PITCH_DEVIATION
    case = _stage_case(sun_mods=Modifications(deviations=Deviations(pitch=tuple(deviations))))
    curves = deviation_curves(
        case, [("planetary", "sun", ("planetary.sun", "planetary.planet1"))], True
    )
    assert sorted(curves) == [(0, 1, tooth) for tooth in range(29)]
    stack = np.array([curves[(0, 1, tooth)] for tooth in range(29)])
    law = mesh_law(case.gearbox.stages[0], "sun")
    assert stack.mean() == pytest.approx(law.curve.mean(), rel=0.05)
    assert np.abs(stack[0] - stack[14]).max() > 1e-3


def test_gearbox_meshes_run_the_law():
    """The NREL 5 MW gearbox (two planetary stages and the helical pair) on
    ``--law loaded_contact``: every mesh keeps the potential-energy law's k-bar (perfect
    flanks; 1e-3 as above, the helical pair's 20 LTCA slices against the law's 40), and
    a short transient of the run-up scene runs with the tables."""
    from pygear.assembly.mesh_laws import stage_mesh_members, with_mesh_law

    case = load_case("nrel5mw_gearbox")
    changed = with_mesh_law(case, "loaded_contact")
    for original, stage in zip(case.gearbox.stages, changed.gearbox.stages):
        for member in stage_mesh_members(stage):
            law = mesh_law(stage, member)
            assert law.law == "loaded_contact"
            energy = mesh_law(original, member).mean_stiffness
            assert law.mean_stiffness == pytest.approx(energy, rel=1e-3), (stage.name, member)
    scene = changed.scene("runup")
    short = dataclasses.replace(scene.transient, duration=0.02, mean_window=0.01)
    scene = dataclasses.replace(scene, transient=short)
    run = run_transient(changed.for_scene(scene), scene)
    assert np.all(np.isfinite(run.mesh_force.values))


def test_loaded_contact_needs_geometry_and_one_gear_of_deviations():
    """Without gear geometry the law is refused naming the mesh; per-tooth deviations on
    both gears of a mesh are refused naming the mesh and the rule."""
    from pygear import CaseError
    from pygear.assembly.tooth_fault_curves import deviation_curves

    study = load_case("yang2016_planetary")
    stage = study.gearbox.stages[0]
    with pytest.raises(CaseError, match="sun_mesh.law 'loaded_contact'.*geometry"):
        dataclasses.replace(stage, sun_mesh=dataclasses.replace(
            stage.sun_mesh, law="loaded_contact", stiffness=None)).validate("planetary")
    runout = Modifications(deviations=Deviations(runout=2e-6))
    case = _stage_case(sun_mods=runout, planet_mods=runout)
    with pytest.raises(CaseError, match="planetary.sun_mesh: both gears carry"):
        deviation_curves(case, [("planetary", "sun", ("planetary.sun", "planetary.planet1"))],
                         True)  # fmt: skip


def test_harmonic_balance_sees_the_tip_relief():
    """cases/loaded_contact_planetary in the harmonic balance (the response reads the
    mesh stiffness from the same contact table): with the tip relief of the single-pair
    deflection the sun mesh's periodic force and dynamic TE swing less than with perfect
    flanks at every carrier speed from 40 to 240 rpm (mesh frequencies 65 to 390 Hz),
    and near quasi-static (40 rpm) by an order of magnitude, as the LTCA's loaded TE does
    (Harris 1958).  Measured: force peak to peak 5020 N against 350 N at 40 rpm (14
    times less), 2.4 to 4 times less from 120 rpm on; dynamic TE 12.9 um against 1.6 um
    at 40 rpm.  Asserted: half at every speed, a tenth (force) and a fifth (TE) at
    40 rpm."""
    from pygear.analysis.response.sweep import forced_response

    case = load_case("loaded_contact_planetary")
    speeds = np.array([40.0, 80.0, 120.0, 160.0, 200.0, 240.0])
    swing, dte = [], []
    for name in ("unmodified", "steady_sensor"):
        ds = forced_response(case, speeds, scene=case.scene(name), harmonics=32,
                             stability=False).sel(mesh="sun-planet1")  # fmt: skip
        swing.append((ds.mesh_force_max - ds.mesh_force_min).values)
        dte.append(ds.dte_peak_to_peak.values)
    assert np.all(swing[1] < swing[0] / 2), swing
    assert swing[1][0] < swing[0][0] / 10 and dte[1][0] < dte[0][0] / 5, (swing, dte)


def test_a_te_variation_of_the_deflection_itself_warns():
    """At a tenth of the load (31 N/mm, 1.8 um static deflection) a 10 um pitch deviation
    makes the revolution's TE-equivalent stiffness spread far beyond twice a spur pair's
    (measured 88): a warning names the mesh and the remedy.  At the full load and 5 um it
    spreads 1.8 and passes."""
    from pygear.assembly.tooth_fault_curves import deviation_curves

    meshes = [("planetary", "sun", ("planetary.sun", "planetary.planet1"))]
    deviations = [0.0] * 29
    deviations[0] = 10e-6
    pitched = Modifications(deviations=Deviations(pitch=tuple(deviations)))
    case = _stage_case(sun_mods=pitched)
    stage = case.gearbox.stages[0]
    light = dataclasses.replace(stage, sun_mesh=dataclasses.replace(
        stage.sun_mesh, line_load=stage.sun_mesh.line_load / 10))  # fmt: skip
    light_case = dataclasses.replace(case, gearbox=dataclasses.replace(case.gearbox,
                                                                       stages=(light,)))
    with pytest.warns(UserWarning, match="planetary.sun_mesh: .*spreads by .*line_load"):
        deviation_curves(light_case, meshes, True)
    deviations[0] = PITCH_DEVIATION
    full = _stage_case(sun_mods=Modifications(deviations=Deviations(pitch=tuple(deviations))))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        deviation_curves(full, meshes, True)
