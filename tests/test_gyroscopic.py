"""Modes of a turning gearbox: Cooley & Parker's (J. Vib. Acoust. 134 (2012) 061014)
gyroscopic and centripetal terms and the quadratic eigenproblem's state-space solver.

References are closed forms (a rotor in its rotating frame), hand derivations (the
planet's kinetic energy), theorems on gyroscopic systems (energy; the sign of the
characteristic polynomial at zero) and the structure of the published model for
equally spaced planets, never this code's own earlier output.
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np
import pytest
import scipy.linalg
from conftest import case_of, consistent_stage

from pygear import Scene
from pygear.analysis.modes.gyroscopic import (
    quadratic_modes,
    solve_at_speed,
    speed_dependent_modes,
    whirl_ratios,
)
from pygear.analysis.modes.modal import modal_analysis
from pygear.assembly.effects import effects_in_force
from pygear.assembly.matrices import assemble
from pygear.assembly.speed_terms import SpeedTerms, TranslationPair, speed_terms
from pygear.errors import CaseError

FORMULATIONS = ("improved", "consistent", "lin-parker")
RPM = math.pi / 30.0  # rad/s per rpm


def rotor_terms(mass: float) -> SpeedTerms:
    """A single body in a frame turning with it (frame and spin ratio 1)."""
    pair = TranslationPair(
        "rotor.body", "rotor", "central", mass, np.array([1.0, 0.0]), np.array([0.0, 1.0]), 1, 1
    )
    gyroscopic = 2 * mass * np.array([[0.0, -1.0], [1.0, 0.0]])
    return SpeedTerms("rotor.body.theta_z", "all", gyroscopic, mass * np.eye(2), (pair,), {}, {})


# --------------------------------------------------------------------------- zero speed


@pytest.mark.parametrize("formulation", FORMULATIONS)
@pytest.mark.parametrize("dof_set", ["planar", "spatial"])
def test_zero_speed_is_todays_modal_analysis(study_case, formulation, dof_set):
    model = assemble(study_case, formulation=formulation, dof_set=dof_set)
    reference = modal_analysis(model).frequency.values
    for method in ("auto", "state-space"):
        modes = speed_dependent_modes(model, study_case, 0.0, method=method)
        found = modes.frequency.values
        assert found.shape == reference.shape
        np.testing.assert_array_equal(found == 0, reference == 0)
        # the state-space path scales both blocks to omega_max, so its eigenvalues carry
        # round-off of a few eps * omega_max: 1e-14 of the lowest frequency here (the
        # spread is 16:1); 1e-9 leaves five orders of margin
        np.testing.assert_allclose(found[reference > 0], reference[reference > 0], rtol=1e-9)
        assert np.all(modes.stability.values[reference == 0] == 3)
        assert np.all(modes.stability.values[reference > 0] == 0)


# --------------------------------------------------------------------------- the matrices


@pytest.mark.parametrize("formulation", FORMULATIONS)
def test_speed_terms_are_cooley_parker_on_every_member(study_case, formulation):
    model = assemble(study_case, formulation=formulation, dof_set="planar")
    terms = speed_terms(model, study_case)
    g, k = terms.gyroscopic, terms.centripetal
    assert np.array_equal(g, -g.T)  # skew by construction: a2 a1^T - a1 a2^T
    assert np.array_equal(k, k.T)
    assert np.linalg.eigvalsh(k).min() >= -1e-12 * np.abs(k).max()
    labels = model.dof_labels
    stage = study_case.gearbox.stages[0]
    for member, mass in (
        ("carrier", stage.carrier.mass),
        ("ring", stage.ring.mass),
        ("sun", stage.sun.mass),
    ):
        x, y = labels.index(f"planetary.{member}.x"), labels.index(f"planetary.{member}.y")
        assert g[y, x] == pytest.approx(2 * mass, rel=1e-14)  # G_j = 2 m_j [[0,-1],[1,0]]
        assert k[x, x] == pytest.approx(mass, rel=1e-14) and k[x, y] == 0.0
    for n in (1, 2, 3):
        zeta = labels.index(f"planetary.planet{n}.zeta")
        eta = labels.index(f"planetary.planet{n}.eta")
        assert g[eta, zeta] == pytest.approx(2 * stage.planet.mass, rel=1e-14)
        assert k[zeta, zeta] == k[eta, eta] == pytest.approx(stage.planet.mass, rel=1e-14)
    rotations = [i for i, label in enumerate(labels) if label.endswith("theta_z")]
    assert not np.any(k[np.ix_(rotations, rotations)])
    # the carrier's speed in the gearbox's free rotation is the reference's; the sun's
    # is the stage ratio 1 + r_br/r_bs with the ring held (base radii of Table 1)
    assert terms.frame_ratios["planetary"] == pytest.approx(1.0, rel=1e-12)
    expected = 1 + stage.ring.base_radius / stage.sun.base_radius
    rigid_ratio_tolerance = 1e-4 if formulation == "lin-parker" else 1e-9
    # lin-parker's planets have no revolution DOF: their eta follows the carrier through
    # the meshes' lines of action, and with Table 1's rounded radii (r_bs + r_bp differs
    # from r_c cos alpha by 0.1 %) its free rotation sits 6e-5 off the ideal ratio; the
    # other formulations tie the revolution to the carrier and hold it to round-off
    assert terms.speed_ratios["planetary.sun"] == pytest.approx(expected, rel=rigid_ratio_tolerance)


def test_planet_terms_match_the_kernel_element(study_case):
    """members='planets' in the improved formulation is the Fortran planet_speed_terms
    element the existing effect assembles (2 m Omega on zeta-eta, -m Omega^2 on both)."""
    scene = Scene(
        "spinning",
        formulation="improved",
        dof_set="planar",
        effects=("speed_dependent_planet_terms",),
        carrier_speed_rpm=30.0 / math.pi,  # 1 rad/s
    )
    still = assemble(study_case, formulation="improved", dof_set="planar")
    spinning = assemble(study_case, scene)
    terms = speed_terms(still, study_case, members="planets")
    np.testing.assert_allclose(spinning.gyroscopic, terms.gyroscopic, rtol=0, atol=1e-15)
    # K0 - K_Omega against K0: the difference of two 1e9-sized matrices keeps 1e-7 of
    # round-off, far below the 0.66 kg planet mass it must show
    np.testing.assert_allclose(still.stiffness - spinning.stiffness, terms.centripetal, atol=1e-6)


def test_consistent_planet_coriolis_reaches_the_revolution(study_case):
    """In the consistent formulation a planet's tangential motion is eta + r_c phi (its
    exact kinetic energy), so 2 m Omega [[0,-1],[1,0]] on (zeta, eta + r_c phi) couples
    zeta with phi = the carrier's theta_z: G[zeta, theta_c] = -2 m r_c per planet."""
    model = assemble(study_case, formulation="consistent", dof_set="planar")
    g = speed_terms(model, study_case).gyroscopic
    labels = model.dof_labels
    stage = study_case.gearbox.stages[0]
    carrier = labels.index("planetary.carrier.theta_z")
    for n in (1, 2, 3):
        zeta = labels.index(f"planetary.planet{n}.zeta")
        expected = -2 * stage.planet.mass * stage.carrier.radius
        assert g[zeta, carrier] == pytest.approx(expected, rel=1e-12)
        assert g[carrier, zeta] == pytest.approx(-expected, rel=1e-12)


# --------------------------------------------------------------------------- a rotor


@pytest.mark.parametrize("speed", [30.0, 150.0, 199.0, 260.0, 500.0])
def test_rotor_in_its_rotating_frame_forward_and_backward_whirl(speed):
    """m q'' + 2 m Omega J q' + (k - m Omega^2) q = 0 has the eigenvalues
    i(omega_n - Omega) and i(omega_n + Omega): a circle turning with the frame at
    omega_n - Omega (forward whirl, omega_n from the housing) and one against it at
    omega_n + Omega (backward, -omega_n from the housing), at any speed."""
    mass, stiffness = 2.0, 8.0e4
    natural = math.sqrt(stiffness / mass)  # 200 rad/s
    terms = rotor_terms(mass)
    gyroscopic, centripetal = terms.at(speed)
    modes = quadratic_modes(mass * np.eye(2), stiffness * np.eye(2) - centripetal, gyroscopic)
    found = np.abs(modes.eigenvalues.imag)
    # undamped and conservative: |Re| is round-off, a few eps times omega_s (~700 rad/s)
    assert np.abs(modes.eigenvalues.real).max() < 1e-9 * natural
    ratio, translating = whirl_ratios(terms, modes, speed / RPM)
    assert translating.all()
    forward = found[ratio > 0.99]
    backward = found[ratio < -0.99]
    assert forward.size == backward.size == 1  # circular orbits: the ratio is +-1
    assert forward[0] == pytest.approx(abs(natural - speed), rel=1e-12)
    assert backward[0] == pytest.approx(natural + speed, rel=1e-12)


def test_rotor_damping_ratios_match_the_closed_form():
    """With damping c in the rotating frame, z = x + i y obeys
    m z'' + (c + 2 i m Omega) z' + (k - m Omega^2) z = 0: two roots in closed form."""
    mass, stiffness, damping, speed = 2.0, 8.0e4, 12.0, 60.0
    terms = rotor_terms(mass)
    gyroscopic, centripetal = terms.at(speed)
    modes = quadratic_modes(
        mass * np.eye(2),
        stiffness * np.eye(2) - centripetal,
        gyroscopic + damping * np.eye(2),
    )
    b = damping + 2j * mass * speed
    c = stiffness - mass * speed**2
    roots = (-b + np.array([1, -1]) * np.sqrt(b * b - 4 * mass * c)) / (2 * mass)
    # each real mode is a conjugate pair: the roots of z and their conjugates (those of
    # z-bar) are the four eigenvalues; the representatives have Im > 0
    expected = np.sort_complex(np.where(roots.imag > 0, roots, roots.conj()))
    found = np.sort_complex(modes.eigenvalues)
    np.testing.assert_allclose(found, expected, rtol=1e-12)
    np.testing.assert_allclose(
        np.sort(modes.damping_ratios), np.sort(-expected.real / np.abs(expected)), rtol=1e-10
    )


# --------------------------------------------------------------------------- theorems


def definiteness_lost(model, terms, high: float) -> float:
    """The lowest reference speed [rad/s] where K - Omega^2 K_Omega gets a negative
    eigenvalue, by bisection on its eigenvalues (the rigid rotation's zero aside)."""

    def negative(speed: float) -> bool:
        values = np.linalg.eigvalsh(model.stiffness - speed**2 * terms.centripetal)
        return values.min() < -1e-9 * np.abs(values).max()

    low = 0.0
    assert negative(high)
    for _ in range(200):
        middle = 0.5 * (low + high)
        low, high = (low, middle) if negative(middle) else (middle, high)
    return high


@pytest.mark.parametrize("formulation", ["improved", "consistent"])
def test_frequencies_stay_real_while_the_stiffness_is_definite(study_case, formulation):
    """Energy: with G skew and K_eff = K - Omega^2 K_Omega symmetric, E = q'^T M q'/2 +
    q^T K_eff q/2 is conserved; while K_eff >= 0 (apart from the free rotation, which
    K_Omega does not touch in these formulations) E bounds the motion, so every
    eigenvalue is imaginary: the frequencies stay real and nothing grows."""
    model = assemble(study_case, formulation=formulation, dof_set="planar")
    terms = speed_terms(model, study_case)
    critical = definiteness_lost(model, terms, 2e5 * RPM)
    for speed in np.linspace(0.0, 0.999 * critical, 40) / RPM:
        modes = solve_at_speed(model, terms, speed, method="state-space")
        # imaginary to round-off: |Re| below 1e-9 of omega_s (measured 1e-15 .. 1e-14)
        assert np.abs(modes.eigenvalues.real).max() < 1e-9 * modes.scale
        assert np.all(modes.stability[~modes.rigid] == 0)


@pytest.mark.parametrize("formulation", FORMULATIONS)
def test_odd_negative_count_means_divergence(formulation):
    """det(lambda^2 M + lambda G + K_eff) is positive for large real lambda and has the
    sign (-1)^(negative eigenvalues of K_eff) near lambda = 0 (the free rotation's
    double zero divided out), so an odd count forces a real positive eigenvalue:
    divergence.  Checked over 0..200 000 rpm on four equally spaced planets."""
    case = case_of(consistent_stage(4))
    model = assemble(case, formulation=formulation, dof_set="planar")
    terms = speed_terms(model, case)
    odd = 0
    for speed in np.linspace(500.0, 2.0e5, 60):
        values = np.linalg.eigvalsh(model.stiffness - (speed * RPM) ** 2 * terms.centripetal)
        negative = int(np.sum(values < -1e-9 * np.abs(values).max()))
        modes = solve_at_speed(model, terms, speed, method="state-space")
        if negative % 2:
            odd += 1
            assert np.any(modes.stability == 1), speed
    assert odd > 0  # the grid does reach odd counts


def test_lin_parker_free_rotation_softens_into_divergence(study_case):
    """In Lin & Parker's coordinates a planet's eta carries the carrier's rigid turning
    (eta = r_c theta_c), so K_Omega acts on the free rotation v: lambda^2 v^T M v =
    Omega^2 v^T K_Omega v (v^T G v = 0), a real pair +-sigma at any speed.  This is the
    published model's linear centripetal term; the improved and consistent frames keep
    the revolution out of zeta, eta and the free rotation at zero."""
    model = assemble(study_case, formulation="lin-parker", dof_set="planar")
    terms = speed_terms(model, study_case)
    values, vectors = scipy.linalg.eigh(model.stiffness, model.mass)
    rigid = vectors[:, np.argmin(np.abs(values))]
    speed = 120.0
    expected = speed * RPM * math.sqrt(
        (rigid @ terms.centripetal @ rigid) / (rigid @ model.mass @ rigid)
    )
    modes = solve_at_speed(model, terms, speed, method="state-space")
    divergent = modes.eigenvalues[modes.stability == 1]
    assert divergent.size == 1
    # Rayleigh's quotient is exact to second order in Omega/omega_1 (12.6 against
    # 4670 rad/s: 1e-5), the coupling to the flexible modes through G and K_Omega
    assert divergent[0].real == pytest.approx(expected, rel=1e-4)
    for formulation in ("improved", "consistent"):
        other = assemble(study_case, formulation=formulation, dof_set="planar")
        modes = solve_at_speed(other, speed_terms(other, study_case), speed, method="state-space")
        assert modes.rigid.sum() == 1 and not np.any(modes.stability == 1)


# --------------------------------------------------------------------------- structure


@pytest.mark.parametrize("formulation", FORMULATIONS)
@pytest.mark.parametrize("planets", [3, 4, 5, 6])
def test_mode_families_survive_speed(formulation, planets):
    """Equally spaced planets: G and K_Omega are the same for every planet and act on
    each body's own translation, so the cyclic structure of Lin & Parker's modes holds at
    speed (Cooley & Parker 2012): 6 rotational modes without central translation, 12
    translational ones without central rotation, the zero-speed pairs split (no repeated
    translational frequency), and 3 planet frequencies N - 3 times each, without central
    motion."""
    case = case_of(consistent_stage(planets))
    model = assemble(case, formulation=formulation, dof_set="planar")
    modes = speed_dependent_modes(model, case, 6000.0)
    flexible = modes.stability.values != 3
    if formulation == "lin-parker":  # its free rotation diverges (test above)
        flexible &= modes.stability.values != 1
    classes = Counter(modes.mode_class.values[flexible])
    assert classes["rotational"] == 5  # 6 less the free rotation
    assert classes["translational"] == 12
    assert classes.get("planet", 0) == 3 * (planets - 3)
    translational = np.sort(modes.frequency.values[modes.mode_class.values == "translational"])
    assert np.diff(translational).min() > 1.0  # Hz: every pair split (by ~Omega/2 pi)
    if planets > 3:
        planet = np.sort(modes.frequency.values[modes.mode_class.values == "planet"])
        groups = planet.reshape(3, planets - 3)
        # a repeated eigenvalue of the state matrix: round-off of eps * omega_s / gap
        np.testing.assert_allclose(groups, np.repeat(groups[:, :1], planets - 3, 1), rtol=1e-8)


# --------------------------------------------------------------------------- the effect


def test_gyroscopic_all_members_effect_in_a_modal_scene(study_case):
    scene = Scene(
        "spinning",
        formulation="improved",
        dof_set="planar",
        effects=("gyroscopic_all_members",),
        carrier_speed_rpm=3000.0,
    )
    spinning = assemble(study_case, scene)
    still = assemble(study_case, formulation="improved", dof_set="planar")
    terms = speed_terms(still, study_case)
    gyroscopic, centripetal = terms.at(3000.0 * RPM)
    np.testing.assert_allclose(spinning.gyroscopic, gyroscopic, rtol=1e-14, atol=0)
    # K0 - Omega^2 K_Omega: round-off of the 1e9-sized K0 only
    np.testing.assert_allclose(spinning.stiffness, still.stiffness - centripetal, atol=1e-5)
    modal = modal_analysis(spinning).frequency.values
    direct = speed_dependent_modes(still, study_case, 3000.0).frequency.values
    # modal.py solves the unscaled M^-1 K state space: round-off of eps * omega_max^2 /
    # omega_min, 3e-10 relative here; 1e-8 allows for it
    np.testing.assert_allclose(np.sort(modal), np.sort(direct), rtol=1e-8, atol=1e-6)
    record = effects_in_force(spinning)
    assert record["gyroscopic_all_members"].startswith("on at 3000 rpm")
    assert record["speed_dependent_planet_terms"] == "off"


@pytest.mark.parametrize(
    "changes, message",
    [
        (dict(dof_set="torsional"), "torsional DOF set drops"),
        (
            dict(effects=("gyroscopic_all_members", "speed_dependent_planet_terms")),
            "list one of it",
        ),
        (dict(analyses=("transient",)), "a transient drives the speed itself"),
    ],
)
def test_gyroscopic_all_members_refusals(study_case, changes, message):
    settings = dict(
        analyses=("modal",),
        effects=("gyroscopic_all_members",),
        carrier_speed_rpm=100.0,
    )
    settings.update(changes)
    with pytest.raises(CaseError, match=message):
        Scene("s", **settings).validate("scenes.s")
