"""Rotor cases: Friswell et al.'s Example 5.9.1, gyroscopic modes (sparse and dense),
unbalance response and FRF of a Jeffcott rotor against its closed form, bearing
coefficient tables, and the rules of the rotor components."""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest

from pygear.analysis.modes.sparse_gyroscopic import modes_at_speed, rotor_modes, solve
from pygear.analysis.response.rotor import (
    Unbalance,
    amplification_factors,
    frequency_response,
    required_separation_margin,
    unbalance_response,
)
from pygear.assembly.drivetrain import assemble_drivetrain
from pygear.errors import CaseError
from pygear.model.case import load_case
from pygear.model.drivetrain import Drivetrain, Shaft, ShaftBearing, ShaftSection
from pygear.model.plausibility import PlausibilityWarning
from pygear.model.rotor import BearingCoefficients, Disc
from pygear.model.rotor_case import RotorCase

RPM = math.pi / 30.0

# Friswell, Penny, Garvey & Lees (2010), Example 5.9.1 (six Timoshenko elements), the
# natural frequencies at 0 and 4000 rev/min as printed [rad/s] by ROSS's documentation
# of that example (petrobras/ross, docs/examples/example_05_09_01).
FRISWELL_0RPM_RAD_S = (86.65811435, 274.31285391, 716.78631221)
FRISWELL_4000RPM_RAD_S = (
    85.389467,
    87.7958637,
    251.78460413,
    294.71333087,
    600.17936195,
    827.07536193,
)
# Backward and forward whirl alternate at 4000 rev/min (the book's Campbell diagram).
FRISWELL_WHIRL = ("backward", "forward") * 3


@pytest.fixture(scope="module")
def friswell():
    case = load_case("friswell_rotor")
    return case, assemble_drivetrain(case)


def _lateral(dataset):
    keep = dataset.kind.values == "lateral"
    return dataset.frequency.values[keep], dataset.whirl.values[keep]


def test_friswell_example_at_0_rpm(friswell):
    """Pairs of equal frequencies (isotropic bearings, no spin) at the book's values;
    7 significant figures printed, the same element formulation: 1e-7."""
    _, model = friswell
    frequency, whirl = _lateral(rotor_modes(model, 0.0, 10))
    expected = np.repeat(np.array(FRISWELL_0RPM_RAD_S) / (2 * math.pi), 2)
    np.testing.assert_allclose(frequency[:6], expected, rtol=1e-7)
    assert set(whirl[:6]) == {"planar"}


def test_friswell_example_at_4000_rpm_splits_into_backward_and_forward(friswell):
    """The gyroscopic couple of the discs splits every pair: backward below, forward
    above (values printed to 9 figures: 1e-7)."""
    _, model = friswell
    frequency, whirl = _lateral(rotor_modes(model, 4000.0, 10))
    np.testing.assert_allclose(
        frequency[:6], np.array(FRISWELL_4000RPM_RAD_S) / (2 * math.pi), rtol=1e-7
    )
    assert tuple(whirl[:6]) == FRISWELL_WHIRL


def _big_rotor(elements: int = 25):
    """Friswell's rotor with ``elements`` per section, anisotropic damped bearings with
    symmetric cross-coupling (stable), non-proportional damping; 25 elements per
    section give 456 DOFs."""
    case = load_case("friswell_rotor")
    drivetrain = case.drivetrain
    shaft = dataclasses.replace(drivetrain.shafts[0], elements_per_section=elements)
    table = BearingCoefficients(
        speeds=(0.0,),
        k_xx=(1e6,),
        k_yy=(0.8e6,),
        k_xy=(2e5,),
        k_yx=(2e5,),
        c_xx=(300.0,),
        c_yy=(250.0,),
        c_xy=(20.0,),
        c_yx=(20.0,),
    )
    bearings = tuple(
        dataclasses.replace(b, radial=0.0, coefficients=table) for b in drivetrain.bearings
    )
    return dataclasses.replace(
        case, drivetrain=dataclasses.replace(drivetrain, shafts=(shaft,), bearings=bearings)
    )


@pytest.mark.parametrize("speed", [0.0, 4000.0])
def test_sparse_and_dense_solvers_agree(speed):
    """Shift-invert Arnoldi on a sparse LU and the dense state space give the same
    eigenvalues to 1e-9 (relative to |lambda|) on the modes both return."""
    model = assemble_drivetrain(_big_rotor(8))  # 150 DOFs: the dense solve stays short
    stiffness, damping = model.at_speed(speed)
    first = damping + speed * RPM * model.gyroscopic
    sparse = solve(model.mass, stiffness, first, 12, "sparse")
    dense = solve(model.mass, stiffness, first, 12, "dense")
    relative = np.abs(sparse.eigenvalues - dense.eigenvalues) / np.abs(dense.eigenvalues)
    assert relative.max() < 1e-9
    # the bearings damp the lateral modes; the torsional one keeps Re = 0 (round-off)
    assert np.all(dense.eigenvalues.real <= 1e-9 * np.abs(dense.eigenvalues))
    assert np.sum(dense.eigenvalues.real < -1e-3) >= 10


def test_auto_solver_picks_dense_for_small_and_sparse_for_large(friswell):
    _, model = friswell
    assert rotor_modes(model, 100.0, 4).attrs["solver"] == "dense"
    big = assemble_drivetrain(_big_rotor())
    assert big.size > 400  # above DENSE_LIMIT
    assert rotor_modes(big, 100.0, 4).attrs["solver"] == "sparse"


def test_speed_dependent_bearing_table_is_interpolated_linearly():
    """Between the table's speeds each coefficient is the straight line through them;
    outside it keeps the end values."""
    table = BearingCoefficients(speeds=(1000.0, 3000.0), k_xx=(1e6, 3e6), c_xy=(10.0, -10.0))
    stiffness, damping = table.at(2500.0)
    assert stiffness[0, 0] == pytest.approx(2.5e6, rel=1e-15)
    assert damping[0, 1] == pytest.approx(-5.0, rel=1e-15)
    assert table.at(0.0)[0][0, 0] == 1e6 and table.at(9000.0)[0][0, 0] == 3e6
    assert table.at(2000.0)[0][1, 1] == 0.0  # k_yy left out: zero


def test_a_constant_table_is_the_isotropic_bearing(friswell):
    """radial = 1 MN/m and a one-row table k_xx = k_yy = 1 MN/m give the same modes."""
    case, model = friswell
    table = BearingCoefficients(speeds=(0.0,), k_xx=(1e6,), k_yy=(1e6,))
    bearings = tuple(
        dataclasses.replace(b, radial=0.0, coefficients=table) for b in case.drivetrain.bearings
    )
    tabled = dataclasses.replace(
        case, drivetrain=dataclasses.replace(case.drivetrain, bearings=bearings)
    )
    a = modes_at_speed(model, 3000.0, 8)
    b = modes_at_speed(assemble_drivetrain(tabled), 3000.0, 8)
    np.testing.assert_allclose(b.eigenvalues, a.eigenvalues, rtol=1e-10)


# --------------------------------------------------------------------------- Jeffcott

JEFFCOTT_MASS = 10.0  # kg
LENGTH, DIAMETER, YOUNG = 1.0, 0.02, 2.1e11
JEFFCOTT_STIFFNESS = 48 * YOUNG * math.pi * DIAMETER**4 / 64 / LENGTH**3  # N/m, midspan
ZETA = 0.05
JEFFCOTT_DAMPING = 2 * ZETA * math.sqrt(JEFFCOTT_STIFFNESS * JEFFCOTT_MASS)  # N s/m


def _jeffcott():
    """A disc at midspan of a massless Euler-Bernoulli shaft on rigid bearings, a
    damper at the disc: m x'' + c x' + k x = m e Omega^2 cos(Omega t).  The shaft's
    density is 1e-6 kg/m^3 (its mass 3e-10 kg) and the bearings 1e13 N/m (k / k_b =
    8e-9): the closed form holds to 1e-7."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        shaft = Shaft(
            name="shaft",
            sections=(ShaftSection(LENGTH / 2, DIAMETER),) * 2,
            young_modulus=YOUNG,
            shear_modulus=YOUNG / 2.6,
            density=1e-6,
            elements_per_section=1,
            shear_deformation=False,
        )
        drivetrain = Drivetrain(
            shafts=(shaft,),
            discs=(Disc("disc", "shaft", 0.5, JEFFCOTT_MASS, 0.02, 0.01),),
            bearings=(
                ShaftBearing("a", "shaft", 0.0, radial=1e13),
                ShaftBearing("b", "shaft", 1.0, radial=1e13),
                ShaftBearing("damper", "shaft", 0.5, radial_damping=JEFFCOTT_DAMPING),
            ),
        )
        case = RotorCase(name="jeffcott", drivetrain=drivetrain)
    return case, assemble_drivetrain(case)


def test_jeffcott_unbalance_response_and_phase_through_the_critical_speed():
    """|X| = m e W^2 / |k - m W^2 + i c W| and phase -atan2(c W, k - m W^2): the lag
    passes 90 deg at the critical speed sqrt(k/m)."""
    case, model = _jeffcott()
    critical_rpm = math.sqrt(JEFFCOTT_STIFFNESS / JEFFCOTT_MASS) / RPM
    speeds = np.linspace(0.2, 2.0, 37) * critical_rpm
    result = unbalance_response(
        model, case.drivetrain, [Unbalance("disc", 1e-4, 30.0)], speeds
    ).sel(location="disc")
    omega = speeds * RPM
    exact = (
        1e-4
        * omega**2
        * np.exp(1j * math.radians(30.0))
        / (JEFFCOTT_STIFFNESS - JEFFCOTT_MASS * omega**2 + 1j * JEFFCOTT_DAMPING * omega)
    )
    np.testing.assert_allclose(result.x_amplitude.values, np.abs(exact), rtol=1e-6)
    np.testing.assert_allclose(result.y_amplitude.values, np.abs(exact), rtol=1e-6)
    np.testing.assert_allclose(result.x_phase.values, np.degrees(np.angle(exact)), atol=1e-5)
    lag = 30.0 - result.x_phase.values
    lag = np.mod(lag, 360.0)
    at_critical = np.interp(critical_rpm, speeds, lag)
    assert at_critical == pytest.approx(90.0, abs=0.5)  # linear between grid speeds
    assert lag[0] < 10.0 and lag[-1] > 170.0


def test_jeffcott_frf_is_the_single_degree_of_freedom_receptance():
    _, model = _jeffcott()
    label = model.node_label(
        Shaft("shaft", (ShaftSection(0.5, 0.02),) * 2, 1.0, 1.0, 1.0, 1), 0.5, "x"
    )
    frequencies = np.linspace(1.0, 30.0, 30)
    frf = frequency_response(model, label, label, frequencies)
    w = 2 * math.pi * frequencies
    exact = 1 / (JEFFCOTT_STIFFNESS - JEFFCOTT_MASS * w**2 + 1j * JEFFCOTT_DAMPING * w)
    np.testing.assert_allclose(frf.h_real.values + 1j * frf.h_imag.values, exact, rtol=1e-6)


def test_jeffcott_amplification_factor_and_api684_margin():
    """Half-power AF of the unbalance response ~ 1/(2 zeta) = 10 (the W^2 factor and a
    0.5 % grid move it by a few per cent); API 684's SM = 17 (1 - 1/(AF - 1.5))."""
    case, model = _jeffcott()
    critical_rpm = math.sqrt(JEFFCOTT_STIFFNESS / JEFFCOTT_MASS) / RPM
    speeds = np.linspace(0.5, 1.5, 401) * critical_rpm
    result = unbalance_response(model, case.drivetrain, [Unbalance("disc", 1e-4)], speeds)
    peaks = amplification_factors(
        speeds, result.sel(location="disc").major_axis.values, (0.0, 0.5 * critical_rpm)
    )
    assert len(peaks) == 1
    assert peaks[0]["speed_rpm"] == pytest.approx(critical_rpm, rel=0.01)
    assert peaks[0]["amplification_factor"] == pytest.approx(1 / (2 * ZETA), rel=0.05)
    assert required_separation_margin(3.5) == pytest.approx(8.5)
    assert required_separation_margin(2.0) == 0.0
    assert peaks[0]["actual_margin_pct"] == pytest.approx(
        100.0 * (peaks[0]["speed_rpm"] / (0.5 * critical_rpm) - 1)
    )


# --------------------------------------------------------------------------- rules


def test_rotor_component_rules_name_the_parameter():
    case = load_case("friswell_rotor")
    drivetrain = case.drivetrain
    off_node = dataclasses.replace(drivetrain.discs[0], position=0.3)
    with pytest.raises(CaseError, match=r"drivetrain.discs\[0\].position must be a node"):
        dataclasses.replace(drivetrain, discs=(off_node,)).validate()
    short = BearingCoefficients(speeds=(0.0, 10.0), k_xx=(1.0,))
    with pytest.raises(CaseError, match=r"coefficients.k_xx must hold one value per speed"):
        dataclasses.replace(drivetrain.bearings[0], radial=0.0, coefficients=short).validate("b")
    with pytest.raises(CaseError, match=r"shaft.shear_coefficient must lie in \(0, 1\]"):
        dataclasses.replace(drivetrain.shafts[0], shear_coefficient=1.5).validate("shaft")
    with pytest.raises(CaseError, match=r"speeds must increase strictly"):
        BearingCoefficients(speeds=(10.0, 0.0), k_xx=(1.0, 2.0)).validate("t")
    with pytest.raises(CaseError, match=r"mounts must be empty without a gearbox"):
        dataclasses.replace(drivetrain, mounts=("x",)).validate()
    with pytest.raises(CaseError, match=r"no disc named 'nope'"):
        drivetrain.disc("nope")


def test_shaft_rayleigh_damping_gives_the_proportional_damping_ratios():
    """A free shaft with C = alpha M + beta K (element by element, so globally): every
    elastic mode has zeta = alpha / (2 w) + beta w / 2 with w its undamped frequency
    (Rayleigh damping keeps the undamped shapes; 1e-9 for round-off)."""
    alpha, beta = 2.0, 1e-5
    shaft = Shaft(
        "shaft",
        (ShaftSection(1.0, 0.05),),
        young_modulus=2.1e11,
        shear_modulus=8.1e10,
        density=7800.0,
        elements_per_section=6,
        rayleigh_mass=alpha,
        rayleigh_stiffness=beta,
    )
    model = assemble_drivetrain(RotorCase("free", drivetrain=Drivetrain(shafts=(shaft,))))
    damped = solve(model.mass, model.stiffness, model.damping, 6, "dense")
    undamped = solve(model.mass, model.stiffness, 0 * model.damping, 6, "dense")
    w = np.abs(undamped.eigenvalues)
    zeta = alpha / (2 * w) + beta * w / 2
    np.testing.assert_allclose(damped.damping_ratios, zeta, rtol=1e-9)
    np.testing.assert_allclose(np.abs(damped.eigenvalues), w, rtol=1e-9)  # |lambda| = w


def test_a_speed_dependent_table_enters_at_the_shaft_speed(friswell):
    """k_xx = k_yy rising linearly from 1 MN/m at 0 rpm to 2 MN/m at 4000 rpm is, at
    2000 rpm, the 1.5 MN/m isotropic bearing: the same eigenvalues (1e-10)."""
    case, _ = friswell
    table = BearingCoefficients(speeds=(0.0, 4000.0), k_xx=(1e6, 2e6), k_yy=(1e6, 2e6))
    tabled = dataclasses.replace(
        case,
        drivetrain=dataclasses.replace(
            case.drivetrain,
            bearings=tuple(
                dataclasses.replace(b, radial=0.0, coefficients=table)
                for b in case.drivetrain.bearings
            ),
        ),
    )
    fixed = dataclasses.replace(
        case,
        drivetrain=dataclasses.replace(
            case.drivetrain,
            bearings=tuple(dataclasses.replace(b, radial=1.5e6) for b in case.drivetrain.bearings),
        ),
    )
    a = modes_at_speed(assemble_drivetrain(tabled), 2000.0, 8)
    b = modes_at_speed(assemble_drivetrain(fixed), 2000.0, 8)
    np.testing.assert_allclose(a.eigenvalues, b.eigenvalues, rtol=1e-10)
    c = modes_at_speed(assemble_drivetrain(tabled), 0.0, 8)
    assert np.all(np.abs(c.eigenvalues[:2].imag) < np.abs(b.eigenvalues[:2].imag))  # softer
