"""Loaded tooth contact analysis (pygear.analysis.contact.ltca) against closed forms,
the potential-energy law it builds on, Harris's tip relief and ISO 6336-1's K_Hbeta."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pygear.analysis.contact.ltca import loaded_contact, solve_slices, te_harmonics
from pygear.analysis.contact.ltca_geometry import contact_rolls
from pygear.assembly.tooth_stiffness import ToothBody, mesh_stiffness
from pygear.errors import CaseError
from pygear.model import gear_geometry as geo
from pygear.model.micro_geometry import (
    Deviations,
    Misalignment,
    Modifications,
    ProfileRelief,
)

# Tian's (2004) pair: z = 19/48, m = 3.2 mm, b = 16 mm (docs/potential_energy.md)
WIDTH = 16e-3
PINION = geo.GearGeometry(teeth=19, normal_module=3.2e-3, face_width=WIDTH)
WHEEL = geo.GearGeometry(teeth=48, normal_module=3.2e-3, face_width=WIDTH)
SPUR = geo.MeshGeometry(PINION, WHEEL)
BODIES = (ToothBody(206.8e9, 0.3, 10e-3), ToothBody(206.8e9, 0.3, 30e-3))
FORCE = 2000.0  # N along the line of action: 125 N/mm, a moderate design load


def _pair_stiffness_at(stiffness, s: np.ndarray) -> np.ndarray:
    """k_m(s) = sum_k k_pair(s + k) from the potential-energy law's own pair curve."""
    return sum(
        np.interp(s + k, stiffness.position, stiffness.pair, left=0.0, right=0.0)
        for k in range(math.ceil(stiffness.total_contact_ratio) + 1)
    )


def test_perfect_spur_pair_is_the_potential_energy_law():
    """(a) No modification: TE = F / k(s) pointwise, k the potential-energy mesh stiffness
    (same compliances, Hertz included in both), and the mean stiffness is the law's."""
    ds = loaded_contact(SPUR, BODIES, [FORCE, 2 * FORCE], n_position=20)
    law = mesh_stiffness(SPUR, BODIES)
    k = _pair_stiffness_at(law, ds.position.values)
    # The LTCA interpolates the compliance between the law's 201 samples, the reference
    # its stiffness: both are second-order accurate, (dp)^2 k''/8 ~ 1e-5 of k.
    np.testing.assert_allclose(ds.te_loaded.values, ds.force.values[:, None] / k, rtol=1e-4)
    np.testing.assert_allclose(ds.te_unloaded.values, 0.0, atol=1e-15)
    np.testing.assert_allclose(ds.k_h_beta.values, 1.0, rtol=1e-12)
    np.testing.assert_allclose(ds.k_h_alpha.values, 1.0, rtol=1e-12)
    fine = loaded_contact(SPUR, BODIES, FORCE, n_position=400)
    # The sampled mean of a curve that jumps by Delta k ~ 1.4e8 N/m twice per cycle
    # differs from its integral by at most Delta k / 400 per jump: ~1e-3 of k-bar.
    assert float(fine.mesh_stiffness.mean()) == pytest.approx(law.mean_stiffness, rel=2e-3)


def test_coupling_carries_nothing_under_a_uniform_deflection():
    """The Pasternak shear springs between slices of an unmodified spur pair stay
    unstretched: TE = F / k(s) with the coupling as without it (to round-off)."""
    coupled = loaded_contact(SPUR, BODIES, FORCE, n_position=20, coupling_length=3.2e-3)
    plain = loaded_contact(SPUR, BODIES, FORCE, n_position=20)
    np.testing.assert_allclose(coupled.te_loaded.values, plain.te_loaded.values, rtol=1e-9)


def test_kernel_solves_the_contact_problem_of_two_coupled_slices():
    """Two slices of stiffness k coupled by k_c, the first one 1 um away.  Below the load
    that closes that gap only the second carries: delta = C_22 F with C = K^-1,
    C_22 = (k + k_c) / (k (k + 2 k_c)), and the first slice's deflection C_12 F must stay
    below its gap; above it both carry and delta = (F + k g) / (2 k) (the shear spring
    stretched by the gap g between them: sum of loads = k (2 delta - g))."""
    k, k_c, g = 1e8, 5e7, 1e-6
    c_struct = np.full((2, 1, 1), 1 / k)
    gap = np.array([g, 0.0]).reshape(2, 1, 1)
    kappa = k_c / k  # k_c = kappa 2 / (c_1 + c_2) with equal compliances
    small = 10.0
    closing = g / ((k + k_c) / (k * (k + 2 * k_c)) - k_c / (k * (k + 2 * k_c)))
    unloaded, loaded, load, _ = solve_slices(c_struct, np.zeros_like(c_struct),
                                             np.ones((2, 1, 1), dtype=np.int32), gap, kappa,
                                             np.array([small, 3 * closing]))  # fmt: skip
    assert unloaded[0] == 0.0
    assert loaded[0, 0] == pytest.approx((k + k_c) / (k * (k + 2 * k_c)) * small, rel=1e-12)
    np.testing.assert_allclose(load[:, 0, 0, 0], [0.0, small], atol=1e-12 * small)
    assert loaded[0, 1] == pytest.approx((3 * closing + k * g) / (2 * k), rel=1e-12)
    assert load[:, 0, 0, 1].sum() == pytest.approx(3 * closing, rel=1e-12)


def test_perfect_helical_pair_without_coupling_is_the_sliced_law():
    """(a) A helical pair with uncoupled slices is the potential-energy law's slicing."""
    pinion = geo.GearGeometry(teeth=19, normal_module=3e-3, face_width=20e-3, helix_angle_deg=15)
    wheel = geo.GearGeometry(teeth=48, normal_module=3e-3, face_width=20e-3, helix_angle_deg=-15)
    mesh = geo.MeshGeometry(pinion, wheel)
    ds = loaded_contact(mesh, BODIES, FORCE, n_slice=40, n_position=20, coupling_length=0.0)
    law = mesh_stiffness(mesh, BODIES, n_slice=40, n_cycle=20)
    np.testing.assert_allclose(ds.mesh_stiffness.values[0], law.mesh, rtol=1e-4)


def _tip_relief(amount: float) -> tuple[Modifications, Modifications]:
    """Linear tip relief on both gears from their highest point of single tooth contact:
    the pinion's at path position 1 (the next pair enters behind it), the wheel's at
    eps_alpha - 1 (the previous pair has just left)."""
    law = mesh_stiffness(SPUR, BODIES)
    s1, _ = contact_rolls(SPUR, np.array([1.0]), law.base_pitch, 1)
    _, s2 = contact_rolls(SPUR, np.array([law.contact_ratio - 1]), law.base_pitch, 1)
    d1 = 2 * math.hypot(geo.base_radius(PINION), s1[0])
    d2 = 2 * math.hypot(geo.base_radius(WHEEL), s2[0])
    return (
        Modifications(tip_relief=ProfileRelief(amount, start_diameter=d1)),
        Modifications(tip_relief=ProfileRelief(amount, start_diameter=d2)),
    )


def test_tip_relief_of_the_design_deflection_flattens_te_at_design_load():
    """(b) Harris (1958), Tavakoli & Houser (1986): a linear tip relief equal to the
    single-pair deflection at the design load, from the highest point of single contact,
    leaves a small fraction of the unmodified TE ripple at that load, more at half and
    double the load."""
    forces = [FORCE / 2, FORCE, 2 * FORCE]
    plain = loaded_contact(SPUR, BODIES, forces, n_position=40)
    law = mesh_stiffness(SPUR, BODIES)
    deflection = FORCE / law.min_stiffness  # single tooth contact at the design load
    relieved = loaded_contact(SPUR, BODIES, forces, modifications=_tip_relief(deflection),
                              n_position=40)  # fmt: skip
    ratio = relieved.te_peak_to_peak.values / plain.te_peak_to_peak.values
    # Not zero: the single pair's stiffness itself varies by some +-3 % over the
    # single-contact zone, and the linear relief does not follow the curved loaded TE.
    assert ratio[1] < 0.25
    assert relieved.te_peak_to_peak.values[0] > 2 * relieved.te_peak_to_peak.values[1]
    assert relieved.te_peak_to_peak.values[2] > 2 * relieved.te_peak_to_peak.values[1]
    # unloaded TE: 0 in single contact, the flanks' relief where the pairs hand over
    assert float(relieved.te_unloaded.min()) == pytest.approx(0.0, abs=1e-15)
    assert 0.1 * deflection < float(relieved.te_unloaded.max()) < deflection


def _parabola_peak(force: float, stiffness: float, crowning: float, mismatch: float) -> float:
    """Peak line load [N/m] of a parabolic separation g(u) = C u^2 + (f/2) u on a face
    u = 2y/b - 1 in [-1, 1] with uniform stiffness c' = k / b per face length: the load
    w = c' (d - g) where positive, sum w dy = F, solved for d with the integral in closed
    form (the vertex u0 = -f/(4C) lies on the face, so the peak is c' (d - g(u0)))."""
    c_face = stiffness / WIDTH
    u0 = -mismatch / (4 * crowning)
    g0 = -(mismatch**2) / (16 * crowning)

    def load(depth: float) -> float:
        half = math.sqrt(depth / crowning)
        lo, hi = max(-1.0, u0 - half), min(1.0, u0 + half)

        def antiderivative(u):
            return depth * u - crowning * (u - u0) ** 3 / 3

        return c_face * WIDTH / 2 * (antiderivative(hi) - antiderivative(lo)) - force

    depth = brentq(load, 1e-15, 1e-2)
    assert -1 < u0 < 1
    return c_face * depth, g0


def test_crowning_under_misalignment_moves_the_pattern_and_matches_the_closed_form():
    """(c) Crowning C_beta = 10 um with a 15 um mismatch over the face: the pattern's
    peak moves to the end the mismatch closes and its line load is the closed form of a
    parabolic load distribution (uncoupled slices: the closed form is a Winkler face)."""
    crowning, mismatch = 10e-6, 15e-6
    mods = (Modifications(crowning=crowning, misalignment=Misalignment(mismatch=mismatch)), None)
    ds = loaded_contact(SPUR, BODIES, FORCE, modifications=mods, n_slice=40, n_position=20,
                        coupling_length=0.0)  # fmt: skip
    plain = loaded_contact(SPUR, BODIES, FORCE, n_position=20, coupling_length=0.0)
    face = ds.face.values
    for j in range(ds.position.size):
        stiffness = float(plain.mesh_stiffness[0, j])
        peak, _ = _parabola_peak(FORCE, stiffness, crowning, mismatch)
        loads = ds.face_load.values[0, j]
        # midpoint rule on 40 slices against the integral, with the kinks of the
        # contact zone's edges inside a slice: O((2/40)^2) ~ 3e-3 of the peak
        assert loads.max() == pytest.approx(peak, rel=5e-3)
        assert face[np.argmax(loads)] < WIDTH / 2  # the gap closes towards y = 0
        u0 = -mismatch / (4 * crowning)
        assert abs(face[np.argmax(loads)] - WIDTH * (u0 + 1) / 2) <= WIDTH / 40


def _iso_k_h_beta(mismatch: float, stiffness_per_width: float, line_load: float) -> float:
    """ISO 6336-1 (eq. 41/42): K_Hbeta = 1 + F_by c / (2 F_m/b) while that is <= 2, else
    sqrt(2 F_by c / (F_m/b)), with F_by = mismatch (no running-in)."""
    x = mismatch * stiffness_per_width / (2 * line_load)
    return 1 + x if x <= 1 else math.sqrt(4 * x)


def test_k_h_beta_of_a_misaligned_pair_against_iso_6336():
    """(c) A straight 15 um mismatch with full face contact: at each position the face
    load is linear, w(y) = (F/b) (1 + x(s) (1 - 2y/b)), x(s) = f c'(s) / (2 F/b) with c'
    the local mesh stiffness per face width; its mean over the cycle is ISO 6336-1's
    distribution with c_gamma the mean mesh stiffness per width, so K_Hbeta = 1 +
    x-bar, read at the slice centre nearest the end: 1 + x-bar (1 - 1/n).  The peak at
    one position (k_h_beta_peak) exceeds ISO's: it comes where two pairs share the load,
    stiffer than the mean."""
    mismatch = 15e-6
    mods = (Modifications(misalignment=Misalignment(mismatch=mismatch)), None)
    force = 8000.0  # full face contact at every position
    ds = loaded_contact(SPUR, BODIES, force, modifications=mods, n_slice=40, n_position=20,
                        coupling_length=0.0)  # fmt: skip
    plain = loaded_contact(SPUR, BODIES, force, n_position=20, coupling_length=0.0)
    k = plain.mesh_stiffness.values[0]
    x = mismatch * (k / WIDTH) / (2 * force / WIDTH)
    assert np.all(x <= 1)
    local = ds.face_load.values[0].max(axis=1) / (force / WIDTH)
    np.testing.assert_allclose(local, 1 + x * (1 - 1 / 40), rtol=1e-9)  # exact: linear
    iso = _iso_k_h_beta(mismatch, k.mean() / WIDTH, force / WIDTH)
    assert float(ds.k_h_beta[0]) == pytest.approx(1 + (iso - 1) * (1 - 1 / 40), rel=1e-9)
    assert float(ds.k_h_beta_peak[0]) > iso


def _helical_ripple(overlap: float, coupling_length: float) -> float:
    beta, module = 15.0, 3e-3
    probe = geo.GearGeometry(teeth=19, normal_module=module, face_width=0.01,
                             helix_angle_deg=beta)  # fmt: skip
    width = overlap * geo.transverse_base_pitch(probe) / math.tan(geo.base_helix_angle(probe))
    pinion = geo.GearGeometry(teeth=19, normal_module=module, face_width=width,
                              helix_angle_deg=beta)  # fmt: skip
    wheel = geo.GearGeometry(teeth=48, normal_module=module, face_width=width,
                             helix_angle_deg=-beta)  # fmt: skip
    mesh = geo.MeshGeometry(pinion, wheel)
    assert geo.overlap_ratio(mesh) == pytest.approx(overlap)
    # 37 positions against 30 slices: the positions do not fall on the slices' stagger
    ds = loaded_contact(mesh, BODIES, 100e3 * width, n_slice=30, n_position=37,
                        coupling_length=coupling_length)  # fmt: skip
    return float(ds.te_peak_to_peak[0] / ds.mean_te[0])


@pytest.mark.parametrize("coupling_length", [0.0, 3e-3])
def test_helical_te_ripple_falls_as_the_overlap_ratio_nears_an_integer(coupling_length):
    """(d) The total contact line length of a helical pair is constant at integer
    eps_beta, so the TE ripple falls from eps_beta = 0.5 to 1 (uncoupled slices, and
    coupled over a decay length of the normal module)."""
    ripple = [_helical_ripple(e, coupling_length) for e in (0.5, 0.75, 0.9, 1.0)]
    assert ripple[0] > ripple[1] > ripple[2] > ripple[3]
    assert ripple[3] < 0.3 * ripple[0]


def test_pitch_deviation_loads_one_pair_more():
    """A +5 um single pitch deviation on one pinion tooth (material added) makes its pair
    carry more than with perfect flanks (K_Halpha > 1), and the unloaded TE dips by its
    cumulative pitch deviation on the line of action: F_p = f (1 - 4/19) for the fourth
    tooth (the deviations closed around the gear), times cos(alpha_t)."""
    pitch = [0.0] * PINION.teeth
    pitch[3] = 5e-6
    mods = (Modifications(deviations=Deviations(pitch=tuple(pitch))), None)
    ds = loaded_contact(SPUR, BODIES, FORCE, modifications=mods, n_position=10,
                        cycles=PINION.teeth)  # fmt: skip
    assert float(ds.k_h_alpha[0]) > 1.05
    alpha_t = geo.transverse_pressure_angle(PINION)
    closing = 5e-6 * (1 - 4 / PINION.teeth) * math.cos(alpha_t)
    assert float(ds.te_unloaded.min()) == pytest.approx(-closing, rel=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"force": -1.0}, "mesh.force must be positive"),
        ({"n_slice": 0}, "mesh.n_slice must be a whole number"),
        ({"coupling_length": -1.0}, "mesh.coupling_length must be a length"),
        ({"modifications": (Modifications(crowning=-1e-6), None)},
         "mesh.modifications[0].crowning must be a finite length"),
        ({"modifications": (Modifications(tip_relief=ProfileRelief(1e-5)), None)},
         "give exactly one of start_diameter and start_roll_angle_deg"),
    ],
)  # fmt: skip
def test_bad_input_names_the_parameter(kwargs, message):
    arguments = {"force": FORCE, **kwargs}
    force = arguments.pop("force")
    with pytest.raises(CaseError, match=None) as error:
        loaded_contact(SPUR, BODIES, force, **arguments)
    assert message in str(error.value)
    assert "\n" not in str(error.value)


def test_te_harmonics_are_one_sided_amplitudes_of_mesh_orders():
    """A TE of 1 um at mesh order 2 and 0.5 um at order 3, over 3 mesh cycles of 20
    positions each: the amplitudes come back at orders 2 and 3 (exact for a sampled
    sinusoid below the Nyquist order)."""
    s = np.arange(60) / 20
    te = 5e-6 + 1e-6 * np.cos(2 * np.pi * 2 * s + 0.3) + 0.5e-6 * np.sin(2 * np.pi * 3 * s)
    np.testing.assert_allclose(te_harmonics(te, 3, 4), [0.0, 1e-6, 0.5e-6, 0.0], atol=1e-18)
