"""Shaft, disc, bearing and coupling elements and the sparse structure assembler.

References are closed forms derived here, never the code's output: Euler-Bernoulli
frequency equations (cos bL cosh bL = -1 clamped-free, = 1 free-free; Blevins 1979,
"Formulas for Natural Frequency and Mode Shape", table 8-1), the simply-supported
Timoshenko frequency equation (Han, Benaroya & Wei 1999, "Dynamics of transversely
vibrating beams using four engineering theories", J. Sound Vib. 225, eq. for the
pinned-pinned beam), bar and shaft wave solutions, cantilever statics and a 2-DOF
complex whirl model of an overhung disc (Friswell et al. 2010, chapter 3).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp
from scipy.optimize import brentq

from pygear.assembly.shaft_elements import (
    bearing_element,
    coupling_element,
    disc_element,
    shaft_element,
    shear_coefficient,
)
from pygear.assembly.structure import NODE_DOFS, Structure, StructureMatrices
from pygear.errors import CaseError

E, RHO, NU = 2.1e11, 7850.0, 0.3
G_SHEAR = E / (2 * (1 + NU))


def section(outer: float, inner: float = 0.0) -> tuple[float, float]:
    """Area and second moment of area of a hollow circle [m^2, m^4]."""
    return math.pi / 4 * (outer**2 - inner**2), math.pi / 64 * (outer**4 - inner**4)


def shaft(length: float, outer: float, inner: float = 0.0, elements: int = 20, **options):
    """A structure holding one shaft along z and its matrices."""
    structure = Structure()
    structure.add_shaft("s", length, outer, inner, elements=elements, **options)
    return structure, structure.assemble()


def keep(matrices: StructureMatrices, dofs: tuple[str, ...], clamped_nodes=()) -> np.ndarray:
    """Positions of the DOFs named ``dofs`` on nodes not in ``clamped_nodes``."""
    return np.array(
        [
            i
            for i, label in enumerate(matrices.labels)
            if label.split(".")[1] in dofs and label.split(".")[0] not in clamped_nodes
        ]
    )


def frequencies(matrices: StructureMatrices, dofs) -> np.ndarray:
    """Undamped natural frequencies [rad/s] of the DOFs ``dofs`` (others clamped)."""
    reduced = matrices.select(dofs)
    values = scipy.linalg.eigh(
        reduced.stiffness.toarray(), reduced.mass.toarray(), eigvals_only=True
    )
    return np.sqrt(np.clip(values, 0.0, None))


def clamped_free(b):
    return math.cos(b) * math.cosh(b) + 1.0


def free_free(b):
    return math.cos(b) * math.cosh(b) - 1.0


CANTILEVER_ROOTS = np.array([brentq(clamped_free, a, a + 1.0) for a in (1.5, 4.2, 7.5)])
FREE_FREE_ROOTS = np.array([brentq(free_free, a, a + 1.0) for a in (4.2, 7.5, 10.5)])


# --- the element itself -------------------------------------------------------------------


def test_element_is_symmetric_with_skew_gyroscopics_and_six_rigid_modes():
    """M and K symmetric, G skew, M positive definite and K with exactly six zero
    eigenvalues, its null space the rigid motions built from geometry."""
    length, outer, inner = 0.3, 0.2, 0.08
    element = shaft_element(length, outer, inner)
    m, k, g = element.mass, element.stiffness, element.gyroscopic
    assert np.array_equal(m, m.T) and np.array_equal(k, k.T)
    assert np.array_equal(g, -g.T) and np.abs(g).max() > 0
    assert np.linalg.eigvalsh(m).min() > 0
    scale = np.abs(k).max()
    values = np.linalg.eigvalsh(k)
    # six round-off zeros (1e-16 relative, 144 terms), then the elastic eigenvalues
    assert np.all(np.abs(values[:6]) < 1e-12 * scale) and values[6] > 1e-6 * scale
    # rigid motions u = t + Theta x (0, 0, z) at z = 0 and z = L
    for t, theta in [
        ((1, 0, 0), (0, 0, 0)),
        ((0, 1, 0), (0, 0, 0)),
        ((0, 0, 1), (0, 0, 0)),
        ((0, 0, 0), (1, 0, 0)),
        ((0, 0, 0), (0, 1, 0)),
        ((0, 0, 0), (0, 0, 1)),
    ]:
        q = np.concatenate(
            [np.concatenate([np.add(t, np.cross(theta, (0, 0, z))), theta]) for z in (0.0, length)]
        )
        assert np.abs(k @ q).max() < 1e-12 * scale


def test_element_mass_and_gyroscopics_of_a_rigid_motion_are_the_rigid_cylinder():
    """Projected on rigid motions, M gives the cylinder's mass and inertias (about its
    centre: rho I L + rho A L^3 / 12 diametral, rho J L polar) and G its I_p with the
    disc's sign, G(theta_x, theta_y) = +I_p."""
    length, outer, inner = 0.4, 0.15, 0.05
    area, inertia = section(outer, inner)
    element = shaft_element(length, outer, inner, youngs_modulus=E, density=RHO)
    half = 0.5 * length

    def tilt(axis: int) -> np.ndarray:
        theta = np.eye(3)[axis]
        return np.concatenate(
            [np.concatenate([np.cross(theta, (0, 0, z)), theta]) for z in (-half, half)]
        )

    translation = np.zeros(12)
    translation[[0, 6]] = 1.0
    mass = RHO * area * length
    diametral = RHO * inertia * length + mass * length**2 / 12
    polar = RHO * 2 * inertia * length
    # 1e-12: a few hundred rounded products of order one, relative
    assert translation @ element.mass @ translation == pytest.approx(mass, rel=1e-12)
    assert tilt(0) @ element.mass @ tilt(0) == pytest.approx(diametral, rel=1e-12)
    assert tilt(1) @ element.mass @ tilt(1) == pytest.approx(diametral, rel=1e-12)
    assert tilt(2) @ element.mass @ tilt(2) == pytest.approx(polar, rel=1e-12)
    assert tilt(0) @ element.gyroscopic @ tilt(1) == pytest.approx(polar, rel=1e-12)
    assert tilt(1) @ element.gyroscopic @ tilt(0) == pytest.approx(-polar, rel=1e-12)
    disc = disc_element(3.0, polar_inertia=0.2, diametral_inertia=0.1)
    assert disc.gyroscopic[3, 4] == 0.2 and disc.gyroscopic[4, 3] == -0.2
    assert np.array_equal(np.diag(disc.mass), [3.0, 3.0, 3.0, 0.1, 0.1, 0.2])


def test_shear_coefficient_is_hutchinsons_hollow_circle():
    """Solid: 6 (1 + nu)^2 / (7 + 12 nu + 4 nu^2); thin tube (b -> a): the formula's
    limit 24 (1 + nu)^2 / (48 + 72 nu + 24 nu^2) = (1 + nu) / (2 + nu)."""
    assert shear_coefficient(0.1, 0.0, NU) == pytest.approx(
        6 * (1 + NU) ** 2 / (7 + 12 * NU + 4 * NU**2), rel=1e-14
    )
    # d/D = 0.9999: the thin-wall limit to O((1 - d/D)^2) = 1e-8
    assert shear_coefficient(1.0, 0.9999, NU) == pytest.approx((1 + NU) / (2 + NU), rel=1e-7)


# --- statics: the cantilever and the sign of the bending planes ---------------------------


@pytest.mark.parametrize("shear", [False, True])
def test_cantilever_tip_load_gives_closed_form_deflection_and_right_handed_rotation(shear):
    """Tip load F: deflection F L^3/(3 E I) (+ F L/(kappa G A)), slope F L^2/(2 E I);
    along x the tip turns by +theta_y, along y by -theta_x (right-handed frame).  The
    interdependent Timoshenko element is exact for nodal loads on a uniform beam, so
    only round-off separates code and closed form."""
    length, outer, inner, force = 1.2, 0.12, 0.04, 1.0e4
    area, inertia = section(outer, inner)
    kappa = shear_coefficient(outer, inner, NU)
    structure, matrices = shaft(length, outer, inner, elements=5, shear_deformation=shear)
    free = keep(matrices, NODE_DOFS, clamped_nodes=("s_0",))
    reduced = matrices.select(free)
    index = {label: i for i, label in enumerate(reduced.labels)}
    bending = force * length**3 / (3 * E * inertia)
    if shear:
        bending += force * length / (kappa * G_SHEAR * area)
    slope = force * length**2 / (2 * E * inertia)
    stiffness = reduced.stiffness.toarray()
    for load, deflected, turned, sign in [("x", "x", "theta_y", 1.0), ("y", "y", "theta_x", -1.0)]:
        f = np.zeros(len(free))
        f[index[f"s_5.{load}"]] = force
        q = np.linalg.solve(stiffness, f)
        # 1e-10: a 30-DOF solve with condition number ~1e8 on double round-off
        assert q[index[f"s_5.{deflected}"]] == pytest.approx(bending, rel=1e-10)
        assert q[index[f"s_5.{turned}"]] == pytest.approx(sign * slope, rel=1e-10)
        other = "theta_x" if turned == "theta_y" else "theta_y"
        assert abs(q[index[f"s_5.{other}"]]) < 1e-12 * slope
    torque = np.zeros(len(free))
    torque[index["s_5.theta_z"]] = force
    axial = np.zeros(len(free))
    axial[index["s_5.z"]] = force
    twist = np.linalg.solve(stiffness, torque)[index["s_5.theta_z"]]
    stretch = np.linalg.solve(stiffness, axial)[index["s_5.z"]]
    assert twist == pytest.approx(force * length / (G_SHEAR * 2 * inertia), rel=1e-10)
    assert stretch == pytest.approx(force * length / (E * area), rel=1e-10)


# --- bending frequencies ------------------------------------------------------------------


def euler_bernoulli(length, outer, roots):
    area, inertia = section(outer)
    return roots**2 * math.sqrt(E * inertia / (RHO * area * length**4))


def test_cantilever_bending_frequencies_match_euler_bernoulli_in_both_planes():
    """Slender shaft (L/D = 40), shear and rotary inertia off, 20 elements: the first
    three of each bending plane within 0.1 % of (beta_n L)^2 sqrt(E I / (rho A L^4)), and
    the two planes equal (their sign conventions mirror each other exactly)."""
    length, outer = 2.0, 0.05
    _, matrices = shaft(length, outer, shear_deformation=False, rotary_inertia=False)
    xz = frequencies(matrices, keep(matrices, ("x", "theta_y"), ("s_0",)))[:3]
    yz = frequencies(matrices, keep(matrices, ("y", "theta_x"), ("s_0",)))[:3]
    reference = euler_bernoulli(length, outer, CANTILEVER_ROOTS)
    # discretisation error of cubic elements, 20 per length: measured 5e-8, 2e-6, 1.6e-5
    assert xz == pytest.approx(reference, rel=1e-3)
    # the y-z plane is the x-z plane with theta_x = -theta_y: S K S with S = diag(1, -1)
    xz_dofs = keep(matrices, ("x", "theta_y"), ("s_0",))
    yz_dofs = keep(matrices, ("y", "theta_x"), ("s_0",))
    signs = np.where(np.arange(len(xz_dofs)) % 2 == 0, 1.0, -1.0)
    for name in ("mass", "stiffness"):
        matrix = getattr(matrices, name).toarray()
        np.testing.assert_array_equal(
            matrix[np.ix_(yz_dofs, yz_dofs)],
            np.outer(signs, signs) * matrix[np.ix_(xz_dofs, xz_dofs)],
        )
    # eigh's round-off is relative to the largest eigenvalue, ~1e7 times the first
    np.testing.assert_allclose(yz, xz, rtol=1e-8)


def test_free_free_bending_frequencies_match_euler_bernoulli():
    """Free-free: two rigid modes per plane, then cos bL cosh bL = 1 within 0.1 %."""
    length, outer = 2.0, 0.05
    _, matrices = shaft(length, outer, shear_deformation=False, rotary_inertia=False)
    values = frequencies(matrices, keep(matrices, ("x", "theta_y")))
    reference = euler_bernoulli(length, outer, FREE_FREE_ROOTS)
    assert np.all(values[:2] < 1e-4 * reference[0])  # round-off of two zero eigenvalues
    assert values[2:5] == pytest.approx(reference, rel=1e-3)


def timoshenko_simply_supported(mode, length, outer, inner, kappa):
    """Lowest root of the pinned-pinned Timoshenko frequency equation for w ~ sin(k z),
    k = n pi / L: (kappa G A k^2 - rho A w^2)(rho I w^2 - E I k^2 - kappa G A)
    + (kappa G A k)^2 = 0, a concave quadratic in w^2 negative at 0, so its lower root
    lies between 0 and the vertex."""
    area, inertia = section(outer, inner)
    k = mode * math.pi / length
    shear = kappa * G_SHEAR * area

    def determinant(s):
        return (shear * k**2 - RHO * area * s) * (
            RHO * inertia * s - E * inertia * k**2 - shear
        ) + (shear * k) ** 2

    a = -RHO * area * RHO * inertia
    b = RHO * area * (E * inertia * k**2 + shear) + shear * k**2 * RHO * inertia
    vertex = -b / (2 * a)
    return math.sqrt(brentq(determinant, 0.0, vertex, xtol=1e-14 * vertex, rtol=1e-15))


def test_thick_shaft_matches_the_timoshenko_frequency_equation():
    """L/D = 4, hollow: shear deformation and rotary inertia on, pinned ends (x held at
    both ends, theta_y free), 40 elements against the closed-form Timoshenko roots.  The
    Euler-Bernoulli values lie 9 to 60 % higher, so the test sees both effects."""
    length, outer, inner = 0.8, 0.2, 0.1
    kappa = 0.8
    _, matrices = shaft(length, outer, inner, elements=40, shear_coefficient=kappa)
    dofs = [
        i
        for i, label in enumerate(matrices.labels)
        if label.endswith(".theta_y") or (label.endswith(".x") and label not in ("s_0.x", "s_40.x"))
    ]
    values = frequencies(matrices, np.array(dofs))[:3]
    reference = np.array(
        [timoshenko_simply_supported(n, length, outer, inner, kappa) for n in (1, 2, 3)]
    )
    area, inertia = section(outer, inner)
    euler = (np.arange(1, 4) * math.pi / length) ** 2 * math.sqrt(E * inertia / (RHO * area))
    assert np.all(euler > 1.08 * reference)
    # h = L/40 with Phi_e ~ 300 per element: the O(h^2) error of shear-dominated elements
    # (test_thick_shaft_frequency_error_falls_as_h_squared), measured 3e-5, 3.5e-4, 1.2e-3
    assert values == pytest.approx(reference, rel=2e-3)


def test_bending_frequency_error_falls_as_h_to_the_fourth():
    """Cubic Hermite elements with consistent mass: eigenvalue error O(h^(2(p+1-m))) =
    O(h^4) for p = 3, m = 2 (Strang & Fix 1973, "An Analysis of the Finite Element
    Method", chapter 6), so the frequency error halves 16-fold per halving of h.  The
    observed order from 4, 8 and 16 elements (mode 2, errors 1.2e-3, 8e-5, 5e-6, far
    above round-off) lies in [3.5, 4.5]."""
    length, outer = 2.0, 0.05
    reference = euler_bernoulli(length, outer, CANTILEVER_ROOTS)[1]
    errors = []
    for elements in (4, 8, 16):
        _, matrices = shaft(
            length, outer, elements=elements, shear_deformation=False, rotary_inertia=False
        )
        value = frequencies(matrices, keep(matrices, ("x", "theta_y"), ("s_0",)))[1]
        errors.append(value / reference - 1)
    assert all(error > 0 for error in errors)  # consistent mass bounds from above
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all((orders > 3.5) & (orders < 4.5)), orders


def test_thick_shaft_frequency_error_falls_as_h_squared():
    """With shear deformation the shape functions depend on the element's
    Phi_e = 12 E I / (kappa G A h^2), which grows as h^-2: N_w = linear + O(1/Phi_e) =
    linear + O(h^2), so on a fine mesh of a thick shaft the consistent mass is that of
    linear interpolation of w up to O(h^2), and the eigenvalue error of linear elements
    is O(h^2) (Strang & Fix 1973, chapter 6, p = 1, m = 1).  Observed order from 10, 20
    and 40 elements of the L/D = 4 shaft (Phi_e 19 .. 300): within [1.8, 2.2]."""
    length, outer, inner, kappa = 0.8, 0.2, 0.1, 0.8
    reference = timoshenko_simply_supported(2, length, outer, inner, kappa)
    errors = []
    for elements in (10, 20, 40):
        _, matrices = shaft(length, outer, inner, elements=elements, shear_coefficient=kappa)
        pinned = ("s_0.x", f"s_{elements}.x")
        dofs = [
            i
            for i, label in enumerate(matrices.labels)
            if label.endswith(".theta_y") or (label.endswith(".x") and label not in pinned)
        ]
        errors.append(frequencies(matrices, np.array(dofs))[1] / reference - 1)
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all((orders > 1.8) & (orders < 2.2)), orders


# --- torsion and axial --------------------------------------------------------------------


@pytest.mark.parametrize(("dof", "modulus"), [("theta_z", G_SHEAR), ("z", E)])
def test_torsional_and_axial_fixed_free_frequencies(dof, modulus):
    """Fixed-free bar: w_n = (2n - 1) pi / (2L) sqrt(modulus / rho).  Linear elements
    with consistent mass on a uniform mesh give exactly
    w_h^2 = (modulus / rho)(6 / h^2)(1 - cos kh)/(2 + cos kh) for the same k (the
    three-point stencil of sin(k z)), so the discrete values are checked to round-off and
    the continuum values to the (kh)^2 / 24 error of that formula."""
    length, elements = 1.5, 20
    _, matrices = shaft(length, 0.1, 0.02, elements=elements)
    values = frequencies(matrices, keep(matrices, (dof,), ("s_0",)))[:3]
    k = (2 * np.arange(1, 4) - 1) * math.pi / (2 * length)
    h = length / elements
    continuum = k * math.sqrt(modulus / RHO)
    discrete = np.sqrt(modulus / RHO * 6 / h**2 * (1 - np.cos(k * h)) / (2 + np.cos(k * h)))
    np.testing.assert_allclose(values, discrete, rtol=1e-11)  # eigh round-off
    np.testing.assert_allclose(values, continuum, rtol=1.1 * (k[-1] * h) ** 2 / 24)


# --- gyroscopics --------------------------------------------------------------------------


def whirl_directions(vectors: np.ndarray, x: int, y: int) -> np.ndarray:
    """+1 forward (x + i y turning with the spin), -1 backward, from the positive-frequency
    eigenvectors' components x and y."""
    forward = np.abs(vectors[x] + 1j * vectors[y])
    backward = np.abs(vectors[x] - 1j * vectors[y])
    return np.where(forward > backward, 1, -1)


def test_overhung_disc_whirl_frequencies_split_as_the_independent_model():
    """Disc at the tip of a massless cantilever spinning at Omega.  Independent model:
    r = x + i y, phi = theta_y - i theta_x, the tip stiffness the inverse of the
    flexibility [L^3/3EI, L^2/2EI; L^2/2EI, L/EI], and I_d phi'' - i I_p Omega phi'
    from the disc's angular momentum I_p Omega (theta_y, -theta_x, 1); its positive
    roots are forward whirl, its negative roots backward whirl.  The FE model (4
    elements, density 1e-6 of steel) must give the same frequencies with the same
    whirl directions."""
    length, outer, spin = 0.5, 0.04, 400.0
    disc_mass, polar, diametral = 20.0, 0.25, 0.13
    area, inertia = section(outer)
    structure = Structure()
    nodes = structure.add_shaft(
        "s", length, outer, elements=4, density=RHO * 1e-6, shear_deformation=False
    )
    structure.add_element(nodes[-1], disc_element(disc_mass, polar, diametral))
    matrices = structure.assemble()
    reduced = matrices.select(keep(matrices, ("x", "y", "theta_x", "theta_y"), ("s_0",)))
    m = reduced.mass.toarray()
    damping = spin * reduced.gyroscopic.toarray()
    n = m.shape[0]
    state = np.block(
        [
            [np.zeros((n, n)), np.eye(n)],
            [-np.linalg.solve(m, reduced.stiffness.toarray()), -np.linalg.solve(m, damping)],
        ]
    )
    values, vectors = np.linalg.eig(state)
    positive = values.imag > 0
    order = np.argsort(values.imag[positive])
    fe = values.imag[positive][order][:4]
    tip = {label: i for i, label in enumerate(reduced.labels) if label.startswith("s_4.")}
    fe_direction = whirl_directions(
        vectors[:, positive][:, order][:, :4], tip["s_4.x"], tip["s_4.y"]
    )

    flexibility = np.array([[length**3 / 3, length**2 / 2], [length**2 / 2, length]]) / (
        E * inertia
    )
    k2 = np.linalg.inv(flexibility)
    m2 = np.diag([disc_mass, diametral])
    d2 = np.diag([0.0, -1j * polar * spin])
    complex_state = np.block(
        [[np.zeros((2, 2)), np.eye(2)], [-np.linalg.solve(m2, k2), -np.linalg.solve(m2, d2)]]
    )
    roots = (np.linalg.eigvals(complex_state) / 1j).real  # lambda = i w
    reference_direction = np.sign(roots)[np.argsort(np.abs(roots))]
    reference = np.sort(np.abs(roots))
    static = np.sqrt(np.linalg.eigvals(np.linalg.solve(m2, k2)).real)
    assert np.abs(np.diff(reference)).min() > 0.05 * reference.min()  # a real split
    assert reference.max() > 1.05 * static.max()  # forward whirl stiffened
    # the shaft (1e-6 of steel's density) weighs 2.5e-7 of the disc and lowers the
    # frequencies by about that much (measured 2e-8 .. 7e-8); eig round-off is far below
    np.testing.assert_allclose(fe, reference, rtol=1e-6)
    np.testing.assert_array_equal(fe_direction, reference_direction)


# --- the structure ------------------------------------------------------------------------


def two_shafts() -> tuple[Structure, dict[str, float]]:
    """Shaft a (bearing at its start), a coupling, shaft b (radial bearing at its end),
    a disc on a."""
    values = {"bearing_torsion": 5e6, "coupling": 2e5, "length_a": 1.0, "length_b": 0.6}
    structure = Structure()
    a = structure.add_shaft("a", values["length_a"], 0.1, elements=4)
    b = structure.add_shaft("b", values["length_b"], 0.08, 0.02, elements=3)
    structure.add_element([a[-1], b[0]], coupling_element(values["coupling"], 1e8, 1e8, 1e5, 10.0))
    structure.add_ground_element(
        a[0], bearing_element([1e9, 1e9, 1e9, 1e7, 1e7, values["bearing_torsion"]], [1e3] * 6)
    )
    structure.add_ground_element(b[-1], bearing_element([1e9, 1e9, 0, 0, 0, 0]))
    structure.add_element(a[2], disc_element(50.0, 2.0, 1.1))
    return structure, values


def test_structure_assembles_symmetric_labelled_matrices_and_its_torsional_part():
    structure, values = two_shafts()
    matrices = structure.assemble()
    assert matrices.labels[:7] == (
        "a_0.x", "a_0.y", "a_0.z", "a_0.theta_x", "a_0.theta_y", "a_0.theta_z", "a_1.x",
    )  # fmt: skip
    assert matrices.size == 6 * 9 and structure.node_names[5] == "b_0"
    for name in ("mass", "stiffness", "damping"):
        matrix = getattr(matrices, name)
        assert isinstance(matrix, sp.csc_matrix)
        assert abs(matrix - matrix.T).max() == 0.0
    assert abs(matrices.gyroscopic + matrices.gyroscopic.T).max() == 0.0
    assert matrices.damping.nnz > 0

    torsional = matrices.torsional()
    index = [i for i, label in enumerate(matrices.labels) if label.endswith(".theta_z")]
    assert torsional.labels == tuple(matrices.labels[i] for i in index)
    for name in ("mass", "stiffness", "damping", "gyroscopic"):
        full = getattr(matrices, name).toarray()
        np.testing.assert_array_equal(
            getattr(torsional, name).toarray(), full[np.ix_(index, index)]
        )
    assert matrices.torsion_is_decoupled()

    # series springs: a torque at b's free end twists bearing, shaft a, coupling, shaft b
    torque = np.zeros(torsional.size)
    torque[-1] = 1.0e3
    twist = np.linalg.solve(torsional.stiffness.toarray(), torque)[-1]
    polar_a = math.pi / 32 * 0.1**4
    polar_b = math.pi / 32 * (0.08**4 - 0.02**4)
    compliance = (
        1 / values["bearing_torsion"]
        + values["length_a"] / (G_SHEAR * polar_a)
        + 1 / values["coupling"]
        + values["length_b"] / (G_SHEAR * polar_b)
    )
    assert twist == pytest.approx(1.0e3 * compliance, rel=1e-10)  # solve round-off


def test_cross_coupled_bearing_is_placed_as_given_and_breaks_torsional_decoupling():
    structure = Structure()
    nodes = structure.add_shaft("s", 1.0, 0.1, elements=2)
    stiffness = np.diag([1e8, 1e8, 1e8, 1e6, 1e6, 1e6])
    stiffness[0, 1], stiffness[1, 0] = 3e7, -3e7  # fluid-film cross-coupling, not symmetric
    stiffness[5, 0] = 1e4  # torsion pulled by x
    housing = structure.add_node("housing")
    structure.add_element([nodes[1], housing], bearing_element(stiffness, nodes=2))
    matrices = structure.assemble()
    k = matrices.stiffness.toarray()
    shaft_only = Structure()
    shaft_only.add_shaft("s", 1.0, 0.1, elements=2)
    k_shaft = shaft_only.assemble().stiffness.toarray()
    bearing_rows = np.arange(6, 12)
    housing_rows = np.arange(18, 24)
    np.testing.assert_array_equal(
        k[np.ix_(bearing_rows, bearing_rows)] - k_shaft[6:12, 6:12], stiffness
    )
    np.testing.assert_array_equal(k[np.ix_(bearing_rows, housing_rows)], -stiffness)
    np.testing.assert_array_equal(k[np.ix_(housing_rows, housing_rows)], stiffness)
    assert not matrices.torsion_is_decoupled()


def test_shaft_from_an_existing_node_shares_it():
    structure = Structure()
    hub = structure.add_node("hub")
    nodes = structure.add_shaft("s", 1.0, 0.1, elements=3, start_node=hub)
    assert nodes == [0, 1, 2, 3]
    assert structure.node_names == ("hub", "s_1", "s_2", "s_3")
    matrices = structure.assemble()
    # total translational mass along x: the x rows of M summed over all x columns
    x = matrices.indices("x")
    area = math.pi / 4 * 0.1**2
    assert matrices.mass[x][:, x].sum() == pytest.approx(RHO * area * 1.0, rel=1e-12)


def test_twenty_thousand_dofs_assemble_sparse_with_the_structural_pattern():
    """3333 elements, 20 004 DOFs.  Per bending plane each node has a 2 x 2 block and each
    element two 2 x 2 off-diagonal blocks: 4 (N + 1) + 8 N entries; axial and torsion
    (N + 1) + 2 N each; so nnz(K) = nnz(M) = 30 N + 10.  G couples the two planes both
    ways: 2 (4 (N + 1) + 8 N) = 24 N + 8.  Cancelling sums stay stored."""
    elements = 3333
    structure = Structure()
    structure.add_shaft("s", 30.0, 0.3, 0.1, elements=elements)
    matrices = structure.assemble()
    assert matrices.size == 20004
    for name in ("mass", "stiffness"):
        matrix = getattr(matrices, name)
        assert isinstance(matrix, sp.csc_matrix)
        assert matrix.nnz == 30 * elements + 10
    assert matrices.gyroscopic.nnz == 24 * elements + 8
    assert matrices.damping.nnz == 0


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: shaft_element(-1.0, 0.1), "length"),
        (lambda: shaft_element(1.0, 0.1, 0.1), "inner_diameter"),
        (lambda: shaft_element(1.0, 0.1, shear_coefficient=1.5), "shear_coefficient"),
        (lambda: shaft_element(1.0, 0.1, shear_modulus=1e10), "shear_modulus"),
        (lambda: disc_element(0.0, 1.0, 1.0), "mass"),
        (lambda: bearing_element([1.0] * 5), "stiffness"),
        (lambda: bearing_element([1.0] * 6, [-1.0] * 6), "damping"),
        (lambda: bearing_element([1.0] * 6, nodes=3), "nodes"),
        (lambda: coupling_element(1.0, radial=-2.0), "radial"),
        (lambda: Structure().add_shaft("s", 1.0, 0.1, elements=0), "elements"),
        (lambda: Structure().add_node("a.b"), "node name"),
    ],
)
def test_bad_input_is_a_one_line_error_naming_the_parameter(build, message):
    with pytest.raises(CaseError, match=message) as caught:
        build()
    assert "\n" not in str(caught.value)


def test_structure_refuses_misplaced_elements():
    structure = Structure()
    nodes = structure.add_shaft("s", 1.0, 0.1, elements=2)
    with pytest.raises(CaseError, match="element must be 6 x 6"):
        structure.add_element([nodes[0]], shaft_element(0.5, 0.1))
    with pytest.raises(CaseError, match="nodes must be"):
        structure.add_element([nodes[0], 7], coupling_element(1.0))
    with pytest.raises(CaseError, match="two different nodes"):
        structure.add_element([nodes[0], nodes[0]], coupling_element(1.0))
    with pytest.raises(CaseError, match="6 x 6"):
        structure.add_ground_element(nodes[0], coupling_element(1.0))
    with pytest.raises(CaseError, match="already"):
        structure.add_shaft("s", 1.0, 0.1, elements=2)
