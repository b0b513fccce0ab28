"""Tests of the tooth-contact table (pygear.assembly.contact_table, pygear.assembly.mesh_phasing,
Fortran contact_table).

References come from docs/model.md §5 (the parabola, k_pk, the tooth formula), from
exact quadrature, from the kinematics of docs/model.md §2, and from contact geometry
recomputed here by intersecting circles with the line of action; never from the
code's own output.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from pygear import (
    Bearing,
    Carrier,
    Case,
    CaseError,
    Gear,
    Gearbox,
    Mesh,
    PlanetaryStage,
    PlanetBearing,
    Scene,
    ToothDefect,
)
from pygear.analysis.contact.mesh_stiffness import (
    ContactLossWarning,
    mesh_stiffness_at_constant_speed,
)
from pygear.assembly import assemble
from pygear.assembly.contact_table import build_contact_table
from pygear.assembly.mesh_phasing import ring_sun_phase, stage_phasing
from pygear.io import open_dataset
from pygear.kernel.calls import KernelError
from pygear.model.case import load_case
from pygear.runs.mesh_stiffness import write_mesh_stiffness

STUDY = "yang2016_planetary"
GAUSS_X, GAUSS_W = np.polynomial.legendre.leggauss(3)


# --- helpers -------------------------------------------------------------------------------


def make_stage(
    z_s=25,
    z_p=35,
    z_r=None,
    planets=3,
    ratio=1.24,
    lam=(0.6, 0.7),
    angles=None,
    curve=None,
    module=3e-3,
    alpha_deg=20.0,
    **extra,
) -> PlanetaryStage:
    """A geometrically consistent stage: base radii m Z cos(alpha)/2, Z_r = Z_s + 2 Z_p."""
    z_r = z_r or z_s + 2 * z_p
    cos_a = math.cos(math.radians(alpha_deg))

    def gear(mass, teeth):
        return Gear(
            mass=mass,
            polar_inertia=mass * 1e-3,
            tilt_inertia=mass * 5e-4,
            base_radius=module * teeth * cos_a / 2,
            teeth=teeth,
        )

    bearing = Bearing(radial=1e8, axial=1e8, tilt=1e6, torsional=0.0)
    return PlanetaryStage(
        name="planetary",
        carrier=Carrier(
            mass=5.0, polar_inertia=0.05, tilt_inertia=0.025, radius=module * (z_s + z_p) / 2
        ),
        ring=gear(2.0, z_r),
        sun=gear(0.4, z_s),
        planet=gear(0.6, z_p),
        planets=planets,
        carrier_bearing=bearing,
        ring_bearing=dataclasses.replace(bearing, torsional=1e7),
        sun_bearing=bearing,
        planet_bearing=PlanetBearing(radial=1e8, axial=1e8, tilt=1e6),
        sun_mesh=Mesh(
            stiffness=5e8,
            pressure_angle_deg=alpha_deg,
            contact_ratio=ratio,
            end_to_peak=lam[0],
            stiffness_curve=curve,
        ),
        ring_mesh=Mesh(
            stiffness=4e8,
            pressure_angle_deg=alpha_deg,
            contact_ratio=ratio,
            end_to_peak=lam[1],
            stiffness_curve=curve,
        ),
        planet_angles_deg=angles,
        **extra,
    )


def make_case(stage=None, defects=(), scenes=None, **stage_args) -> Case:
    stage = stage or make_stage(**stage_args)
    return Case(
        name="test",
        gearbox=Gearbox(stages=(stage,)),
        formulation="improved",
        defects=defects,
        scenes=scenes or (Scene("modal"),),
    )


def table_of(case, scene=None, **kwargs):
    return build_contact_table(case, assemble(case, scene), scene, **kwargs)


def stiffness_at(table, s: np.ndarray) -> dict:
    """Evaluate the table at prescribed mesh cycles s (n_state, n_mesh)."""
    theta = (s - table.phase) * 2 * np.pi / (table.cycle_sign * table.teeth[0])
    return table.series(theta)


def parabola(p, kbar, eps, lam):
    """The single-pair parabola of docs/model.md §5.2.

    k_pk [1 - (1 - lambda)(2p/eps - 1)^2], k_pk = 3 kbar / (eps (2 + lambda)).
    """
    k_pk = 3 * kbar / (eps * (2 + lam))
    return k_pk * (1 - (1 - lam) * (2 * p / eps - 1) ** 2)


def exact_cycle_mean(table, breakpoints, cycles=7):
    """Mean of k_m over whole mesh cycles by Gauss-Legendre between the breakpoints of frac(s)
    (exact for piecewise polynomials of degree <= 5)."""
    edges = np.unique(np.concatenate([[0.0, 1.0], np.mod(breakpoints, 1.0)]))
    a, b = edges[:-1], edges[1:]
    nodes = (0.5 * (b - a)[:, None] * GAUSS_X + 0.5 * (a + b)[:, None]).ravel()
    weights = (0.5 * (b - a)[:, None] * GAUSS_W).ravel()
    s = (np.arange(cycles)[:, None] + 3.0 + nodes).ravel()
    k = stiffness_at(table, np.repeat(s[:, None], table.size, axis=1))["stiffness"]
    return (np.tile(weights, cycles)[:, None] * k).sum(axis=0) / cycles


def geometric_pitch_points(stage, sun_driven=True):
    """p_P of both meshes from circle / line-of-action intersections, standard addenda.

    Contact starts where the driven gear's tip circle crosses the line of action
    (textbook involute gearing); when the carrier drives and the sun is the output, the
    sun is driven in the carrier frame and the planet is driven by the ring."""
    z_p = stage.planet.teeth
    out = {}
    meshes = (("sun", stage.sun, stage.sun_mesh), ("ring", stage.ring, stage.ring_mesh))
    for name, gear, mesh in meshes:
        alpha = mesh.pressure_angle
        u = np.array([math.sin(alpha), math.cos(alpha)])  # line-of-action direction
        m = 2 * stage.planet.base_radius / (z_p * math.cos(alpha))
        r_gear = gear.base_radius / math.cos(alpha)  # pitch radius of sun or ring
        r_planet = stage.planet.base_radius / math.cos(alpha)
        pitch = np.array([r_gear, 0.0])
        centre = np.array([r_gear + r_planet if name == "sun" else r_gear - r_planet, 0.0])
        gear_tip = r_gear + m if name == "sun" else r_gear - m

        def hits(c, radius, pitch=pitch, u=u):
            # |pitch + t u - c| = radius
            d = pitch - c
            return np.roots([1.0, 2 * d @ u, d @ d - radius**2]).real

        t_gear = hits(np.zeros(2), gear_tip)
        t_planet = hits(centre, r_planet + m)
        if name == "sun":  # sun tip on the planet's side (t > 0), planet tip on the sun's side
            gear_len, planet_len = t_gear.max(), -t_planet.min()
            approach, recess = (gear_len, planet_len) if sun_driven else (planet_len, gear_len)
        else:  # ring tip on the tangent-point side (t < 0), planet tip beyond P
            gear_len, planet_len = -t_gear[t_gear < 0].max(), t_planet.max()
            approach, recess = (planet_len, gear_len) if sun_driven else (gear_len, planet_len)
        out[name] = mesh.contact_ratio * approach / (approach + recess)
    return out


def windows(mask: np.ndarray) -> list[tuple[int, int]]:
    """(start, stop) sample indices of the runs of True in mask."""
    edges = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True))


def mod_distance(a, b, period=1.0):
    d = np.mod(np.asarray(a) - np.asarray(b), period)
    return np.minimum(d, period - d)


# --- mean, period, pairs -----------------------------------------------------------------


@pytest.mark.parametrize("ratio", [1.24, 1.6, 2.0, 2.35])
def test_mean_over_whole_cycles_is_kbar(ratio):
    table = table_of(make_case(ratio=ratio))
    mean = exact_cycle_mean(table, [0.0, ratio])
    assert np.allclose(mean, table.mean_stiffness, rtol=1e-10, atol=0)


def test_single_pair_law_is_the_parabola_of_physics_md():
    case = make_case(ratio=1.24, lam=(0.6, 0.7))
    table = table_of(case)
    s = np.linspace(0.3, 0.99, 17)  # frac(s) in (eps - 1, 1): one pair, at p = frac(s)
    k = stiffness_at(table, np.repeat(s[:, None], table.size, axis=1))["stiffness"]
    for m in range(table.size):
        expected = parabola(s, table.mean_stiffness[m], 1.24, table.end_to_peak[m])
        assert np.allclose(k[:, m], expected, rtol=1e-13)
    assert k.dtype == np.float64


def test_period_is_one_mesh_cycle():
    table = table_of(make_case(ratio=1.45))
    # cell midpoints: k_m jumps where frac(s) = 0 or eps - 1, so keep samples off those
    s = (np.arange(400)[:, None] + 0.5) / 400 + np.zeros(table.size) + 12.0
    k0 = stiffness_at(table, s)["stiffness"]
    assert np.allclose(stiffness_at(table, s + 1.0)["stiffness"], k0, rtol=1e-12)
    assert np.allclose(stiffness_at(table, s + 5.0)["stiffness"], k0, rtol=1e-12)
    assert np.abs(stiffness_at(table, s + 0.5)["stiffness"] - k0).max() > 0.1 * k0.max()


@pytest.mark.parametrize("ratio", [1.24, 1.7, 2.35])
def test_pairs_alternate_between_floor_and_ceil(ratio):
    table = table_of(make_case(ratio=ratio))
    n = 1000
    s = (np.arange(10 * n) + 0.5) / n + 3.0
    pairs = stiffness_at(table, np.repeat(s[:, None], table.size, axis=1))["pairs"]
    low, high = math.floor(ratio), math.ceil(ratio)
    assert set(np.unique(pairs)) == {low, high}
    expected = np.where(np.mod(s, 1.0) < ratio - low, high, low)
    assert np.array_equal(pairs, np.repeat(expected[:, None], table.size, axis=1))
    duty = np.mean(pairs[:, 0] == high)
    assert duty == pytest.approx(ratio - low, abs=1.0 / n)


def test_tooth_indices_follow_physics_md():
    table = table_of(make_case())
    s = (np.arange(4000)[:, None] + 0.5) / 50 + np.zeros(table.size)  # off the jumps
    result = stiffness_at(table, s)
    m = table.names.index("sun-planet1")  # i0 = j0 = 0 by construction
    z1, z2 = table.teeth[:, m]
    for k in range(2):
        used = result["tooth_1"][:, m, k] >= 0
        expected = np.floor(s[used, m]).astype(int) - k
        assert np.array_equal(result["tooth_1"][used, m, k], np.mod(expected, z1))
        assert np.array_equal(result["tooth_2"][used, m, k], np.mod(expected, z2))


# --- tabulated law ---------------------------------------------------------------------


@pytest.mark.parametrize("samples", [9, 17, 33])
def test_tabulated_parabola_samples_reproduce_the_parabola(samples):
    eps, lam = 1.36, 0.6
    p = np.linspace(0.0, eps, samples)
    shape = tuple(parabola(p, 1.0, eps, lam))
    tabulated = table_of(make_case(ratio=eps, lam=(lam, lam), curve=shape))
    exact = table_of(make_case(ratio=eps, lam=(lam, lam)))
    s = np.linspace(0.0, 3.0, 3001)[:, None] + np.zeros(exact.size) + 2.0
    error = np.abs(stiffness_at(tabulated, s)["stiffness"] - stiffness_at(exact, s)["stiffness"])
    # Interpolation error of f = k_pk[1 - (1 - lam)(2p/eps - 1)^2], h = eps/(n - 1):
    # |L - f| <= h^2 |f''| / 8 = k_pk (1 - lam)/(n - 1)^2; the interpolant's integral falls
    # short by eps h^2 |f''| / 12, and rescaling it to the mean k-bar multiplies it by
    # c = kbar / (kbar - that); so |c L - f| <= (c - 1) k_pk + h^2 |f''| / 8 per pair.
    for m in range(exact.size):
        kbar = exact.mean_stiffness[m]
        k_pk = 3 * kbar / (eps * (2 + lam))
        h = eps / (samples - 1)
        curvature = 8 * k_pk * (1 - lam) / eps**2
        c = kbar / (kbar - eps * h**2 * curvature / 12)
        bound = math.ceil(eps) * ((c - 1) * k_pk + h**2 * curvature / 8)
        assert error[:, m].max() <= bound * (1 + 1e-9)
        assert error[:, m].max() > 0.05 * bound  # the bound is not vacuous


def test_tabulated_law_keeps_the_mean_and_the_shape():
    eps = 1.5
    shape = (0.2, 1.0, 0.6, 0.9, 0.3)  # piecewise linear: represented exactly
    table = table_of(make_case(ratio=eps, curve=shape))
    nodes = eps * np.arange(len(shape)) / (len(shape) - 1)
    breakpoints = np.concatenate([nodes - k for k in range(2)] + [[eps]])
    mean = exact_cycle_mean(table, breakpoints)
    assert np.allclose(mean, table.mean_stiffness, rtol=1e-10, atol=0)
    # single-pair stretch: k = (kbar / eps) * shape / trapezoid mean of shape
    trapezoid = (sum(shape) - 0.5 * (shape[0] + shape[-1])) / (len(shape) - 1)
    p = np.array([nodes[2], 0.5 * (nodes[2] + nodes[3])])
    k = stiffness_at(table, np.repeat(p[:, None], table.size, axis=1) + 4.0)["stiffness"]
    expected = np.array([shape[2], 0.5 * (shape[2] + shape[3])]) / trapezoid / eps
    assert np.allclose(k / table.mean_stiffness, expected[:, None], rtol=1e-13)


# --- phasing ---------------------------------------------------------------------------


def test_equal_spacing_gives_equal_sun_and_ring_sequences():
    stage = make_stage(z_s=25, z_p=35, planets=4)  # Z_s/N = 6.25: sequential
    phases = stage_phasing(stage)
    gamma_rs = phases["ring-planet1"].phase
    for n in range(1, 5):
        gamma_sn = phases[f"sun-planet{n}"].phase
        gamma_rn = phases[f"ring-planet{n}"].phase
        assert mod_distance(gamma_rn - gamma_rs, gamma_sn) < 1e-12
    assert len({round(phases[f"sun-planet{n}"].phase, 9) for n in range(1, 5)}) == 4


def test_sun_teeth_multiple_of_planets_puts_sun_meshes_in_phase():
    case = load_case(STUDY)  # Z_s/N = 27/3 = 9
    phases = stage_phasing(case.gearbox.stages[0])
    assert all(phases[f"sun-planet{n}"].phase == 0.0 for n in (1, 2, 3))
    assert len({phases[f"ring-planet{n}"].phase for n in (1, 2, 3)}) == 1


@pytest.mark.parametrize("angles", [None, (0.0, 100.0, 230.0), (0.0, 120.1, 240.0)])
def test_phase_sequence_is_parker_lin(angles):
    stage = make_stage(z_s=25, z_p=35, planets=3, angles=angles)
    z_s, z_r = 25, 95
    psi = np.array(stage.planet_angles)
    for direction, sign in ((-1, +1), (1, -1)):  # upper sign: sun turning clockwise
        phases = stage_phasing(stage, direction=direction)
        gamma_rs = phases["ring-planet1"].phase
        for n in range(3):
            expected_s = np.mod(sign * z_s * (psi[n] - psi[0]) / (2 * np.pi), 1.0)
            expected_r = np.mod(-sign * z_r * (psi[n] - psi[0]) / (2 * np.pi), 1.0)
            assert mod_distance(phases[f"sun-planet{n + 1}"].phase, expected_s) < 1e-9
            assert mod_distance(phases[f"ring-planet{n + 1}"].phase - gamma_rs, expected_r) < 1e-9


def test_ring_to_sun_phase_flips_by_half_a_cycle_with_planet_parity():
    for p_s, p_r in ((0.61, 0.57), (0.2, 0.9), (0.5, 0.5)):
        odd = ring_sun_phase(p_s, p_r, 35)
        even = ring_sun_phase(p_s, p_r, 36)
        assert mod_distance(odd - even, 0.5) < 1e-12
    # whole stages with odd and even planets, against the geometry recomputed here
    for z_s, z_p in ((25, 35), (24, 36)):
        stage = make_stage(z_s=z_s, z_p=z_p)
        points = geometric_pitch_points(stage)
        half = 0.5 if z_p % 2 == 0 else 0.0
        expected = np.mod(points["ring"] - points["sun"] + half, 1.0)
        assert mod_distance(stage_phasing(stage)["ring-planet1"].phase, expected) < 1e-9


def test_study_case_ring_to_sun_phase_from_geometry():
    stage = load_case(STUDY).gearbox.stages[0]
    points = geometric_pitch_points(stage)
    expected = np.mod(points["ring"] - points["sun"], 1.0)  # Z_p = 35 is odd
    gamma_rs = stage_phasing(stage)["ring-planet1"].phase
    assert mod_distance(gamma_rs, expected) < 1e-9
    assert 0.01 < mod_distance(gamma_rs, 0.0)  # a real phase shift


def test_phase_overrides_are_used():
    stage = make_stage(mesh_phases={"ring-planet2": 0.25, "sun-planet3": 0.5})
    table = table_of(make_case(stage=stage))
    assert table.phase[table.names.index("ring-planet2")] == 0.25
    assert table.phase[table.names.index("sun-planet3")] == 0.5


# --- defects ---------------------------------------------------------------------------


def test_sun_tooth_defect_only_while_in_contact_once_per_revolution():
    case = load_case(STUDY)
    healthy = mesh_stiffness_at_constant_speed(case, duration=0.3)
    defect = ToothDefect("planetary.sun", 5, 0.5)
    cracked = mesh_stiffness_at_constant_speed(
        dataclasses.replace(case, defects=(defect,)), duration=0.3
    )
    difference = (healthy.mesh_stiffness - cracked.mesh_stiffness).values
    stage = case.gearbox.stages[0]
    omega_c = 120 * math.pi / 30
    revolution = 2 * math.pi / (stage.ring.base_radius / stage.sun.base_radius * omega_c)
    dt = float(healthy.time[1] - healthy.time[0])
    for m, name in enumerate(healthy.mesh.values):
        changed = np.abs(difference[:, m]) > 1e-6 * 5e8
        if name.startswith("ring"):
            assert not changed.any()
            continue
        frequency = float(healthy.mesh_frequency[m])
        in_contact = (cracked.tooth_1.values[:, m, :] == 5).any(axis=1)
        assert np.array_equal(changed, in_contact)
        runs = [r for r in windows(changed) if r[0] > 0 and r[1] < len(changed)]
        assert len(runs) >= 1
        for start, stop in runs:  # in contact for eps mesh cycles
            assert abs((stop - start) * dt * frequency - 1.24) <= 1.5 * dt * frequency
            t = healthy.time.values[start:stop] - healthy.time.values[start] + 0.5 * dt
            p = t * frequency  # the defective pair's position
            expected = 0.5 * parabola(p, 5e8, 1.24, 0.6)
            inner = slice(1, -1)
            assert np.allclose(difference[start:stop, m][inner], expected[inner], rtol=0.02)
        starts = [healthy.time.values[s] for s, _ in windows(changed)]
        for a, b in zip(starts, starts[1:], strict=False):
            assert abs(b - a - revolution) <= 2 * dt


def test_planet_tooth_defect_acts_in_both_its_meshes_half_a_turn_apart():
    for z_s, z_p in ((25, 35), (24, 36)):
        stage = make_stage(z_s=z_s, z_p=z_p)
        case = make_case(stage=stage, defects=(ToothDefect("planetary.planet2", 7, 0.0),))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ContactLossWarning)
            data = mesh_stiffness_at_constant_speed(case, samples_per_cycle=400)
        frequency = float(data.mesh_frequency.sel(mesh="ring-planet2"))
        assert frequency == pytest.approx(float(data.mesh_frequency.sel(mesh="sun-planet2")))
        dt = float(data.time[1] - data.time[0])
        starts = {}
        for name in data.mesh.values:
            lost = (data.tooth_2.sel(mesh=name) == 7).any("pair").values
            if name.endswith("planet2"):
                runs = windows(lost)
                assert len(runs) >= 2
                period = (runs[1][0] - runs[0][0]) * dt * frequency
                assert period == pytest.approx(z_p, abs=2 * dt * frequency)  # once per turn
                starts[name.split("-")[0]] = runs[0][0] * dt * frequency
                k = data.mesh_stiffness.sel(mesh=name).values
                k_healthy = (
                    mesh_stiffness_at_constant_speed(
                        make_case(stage=stage), duration=float(data.time[-1]), samples_per_cycle=400
                    )
                    .mesh_stiffness.sel(mesh=name)
                    .values
                )
                assert np.array_equal(k != k_healthy, lost)
            else:
                k = data.mesh_stiffness.sel(mesh=name).values
                assert (k > 0).all()
        points = geometric_pitch_points(stage)
        # its sun-loaded flank passes the sun pitch point, then (Z_p + 1)/2 tooth periods
        # later its ring-loaded (trailing) flank passes the ring pitch point
        expected = (z_p + 1) / 2 + points["sun"] - points["ring"]
        assert mod_distance(starts["ring"] - starts["sun"], expected, z_p) <= 2.5 * dt * frequency


def test_missing_tooth_leaves_a_stretch_without_contact():
    case = make_case(ratio=1.24, defects=(ToothDefect("planetary.ring", 3, 0.0),))
    with pytest.warns(ContactLossWarning, match="ring-planet"):
        data = mesh_stiffness_at_constant_speed(case, samples_per_cycle=500)
    for name in data.mesh.values:
        pairs = data.pairs_in_contact.sel(mesh=name).values
        k = data.mesh_stiffness.sel(mesh=name).values
        if name.startswith("sun"):
            assert pairs.min() == 1
            continue
        assert pairs.min() == 0 and np.all(k[pairs == 0] == 0.0)
        frequency = float(data.mesh_frequency.sel(mesh=name))
        dt = float(data.time[1] - data.time[0])
        for start, stop in windows(pairs == 0):
            if start > 0 and stop < len(pairs):
                # alone for 1 - (eps - 1) = 2 - eps cycles of its eps-cycle contact
                alone = (stop - start) * dt * frequency
                assert alone == pytest.approx(2 - 1.24, abs=2 * dt * frequency)


def test_scene_defect_replaces_the_case_defect():
    scene = Scene("cracked", defects=(ToothDefect("planetary.sun", 4, 0.3),))
    case = make_case(defects=(ToothDefect("planetary.sun", 4, 0.8),), scenes=(scene,))
    table = table_of(case, scene)
    sun = table.names.index("sun-planet1")
    start = table.factor_start[0, sun]
    assert table.factor[start + 4] == 0.3
    assert table_of(case).factor[start + 4] == 0.8


# --- bad input -------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (dict(ratio=1.0), ["sun_mesh.contact_ratio", "exceed 1", "spur"]),
        (dict(ratio=0.9), ["contact_ratio", "exceed 1"]),
        (dict(lam=(0.0, 0.7)), ["sun_mesh.end_to_peak", "(0, 1]"]),
        (dict(lam=(0.6, 1.2)), ["ring_mesh.end_to_peak", "(0, 1]"]),
        (dict(mesh_phases={"sun-planet4": 0.1}), ["mesh_phases", "sun-planet4", "no mesh"]),
        (dict(mesh_phases={"ring-planet1": 1.5}), ["mesh_phases", "ring-planet1", "[0, 1)"]),
        (dict(curve=(0.0, 0.0)), ["stiffness_curve"]),
    ],
)
def test_bad_stage_input_is_refused(change, words):
    with pytest.raises(CaseError) as error:
        make_case(**change)
    for word in words:
        assert word in str(error.value)


@pytest.mark.parametrize("stiffness", [0.0, -5e8])
def test_nonpositive_mean_stiffness_is_refused(stiffness):
    stage = make_stage()
    stage = dataclasses.replace(
        stage, sun_mesh=dataclasses.replace(stage.sun_mesh, stiffness=stiffness)
    )
    with pytest.raises(CaseError, match=r"planetary\.sun_mesh\.stiffness must be a positive"):
        make_case(stage=stage)


@pytest.mark.parametrize(
    ("defect", "words"),
    [
        (ToothDefect("planetary.sun", 25, 0.5), ["tooth 25 does not exist", "0 .. 24"]),
        (ToothDefect("planetary.planet1", 35, 0.5), ["tooth 35", "0 .. 34"]),
        (ToothDefect("planetary.ring", -1, 0.5), ["tooth", ">= 0"]),
        (ToothDefect("planetary.planet4", 1, 0.5), ["planet4", "not a gear"]),
        (ToothDefect("planetary.carrier", 1, 0.5), ["carrier", "not a gear"]),
        (ToothDefect("gearbox.sun", 1, 0.5), ["no stage named 'gearbox'"]),
        (ToothDefect("planetary.sun", 1, 1.5), ["factor", "[0, 1]"]),
        (ToothDefect("sun", 1, 0.5), ["<stage>.<member>"]),
    ],
)
def test_bad_defect_is_refused(defect, words):
    with pytest.raises(CaseError) as error:
        make_case(defects=(defect,))
    for word in words:
        assert word in str(error.value)
    with pytest.raises(CaseError):
        make_case(scenes=(Scene("s", defects=(defect,)),))


def test_duplicate_defect_is_refused():
    defect = ToothDefect("planetary.sun", 1, 0.5)
    with pytest.raises(CaseError, match="listed twice"):
        make_case(defects=(defect, dataclasses.replace(defect, factor=0.2)))


def test_kernel_check_names_the_mesh():
    table = table_of(make_case())
    broken = dataclasses.replace(table, max_pairs=1)
    with pytest.raises(KernelError, match="sun-planet1"):
        broken.check()
    with pytest.raises(KernelError, match="not finite"):
        table.evaluate(np.full(table.size, np.nan))


# --- study case --------------------------------------------------------------------------


def test_study_case_at_120_rpm():
    case = load_case(STUDY)
    data = mesh_stiffness_at_constant_speed(case, carrier_speed_rpm=120.0, duration=50 / 192)
    assert data.mesh_stiffness.attrs["units"] == "N/m"
    assert data.mesh_stiffness.dtype == np.float64
    assert list(data.mesh.values) == [
        "sun-planet1",
        "ring-planet1",
        "sun-planet2",
        "ring-planet2",
        "sun-planet3",
        "ring-planet3",
    ]
    # f_m = Z_r omega_c / 2 pi = 96 * 2 = 192 Hz; check the ring-planet1 spectrum peak
    k = data.mesh_stiffness.sel(mesh="ring-planet1").values
    dt = float(data.time[1] - data.time[0])
    n = int(round(50 / 192 / dt))
    spectrum = np.abs(np.fft.rfft(k[:n] - k[:n].mean()))
    peak = np.fft.rfftfreq(n, dt)[np.argmax(spectrum)]
    assert peak == pytest.approx(192.0, abs=1e-6)
    assert float(data.mesh_frequency.sel(mesh="ring-planet1")) == pytest.approx(192.0, rel=1e-12)
    # sun meshes follow the base-radius kinematics: Z_s (r_br / r_bs) omega_c / 2 pi
    stage = case.gearbox.stages[0]
    expected_sun = 27 * stage.ring.base_radius / stage.sun.base_radius * 2.0
    assert float(data.mesh_frequency.sel(mesh="sun-planet1")) == pytest.approx(expected_sun)
    # phase shift between sun-planet1 and ring-planet1: pair entries (count rises)
    entries = {}
    for name in ("sun-planet1", "ring-planet1", "sun-planet2"):
        pairs = data.pairs_in_contact.sel(mesh=name).values
        entries[name] = data.time.values[1:][np.diff(pairs) > 0][:3] * 192.0
    shift = entries["ring-planet1"] - entries["sun-planet1"]
    points = geometric_pitch_points(stage)
    expected = np.mod(points["sun"] - points["ring"], 1.0)  # 1 - gamma_rs
    assert np.all(mod_distance(shift, expected) < 2 * dt * 192.0)
    assert np.all(mod_distance(shift, 0.0) > 0.02)
    assert np.allclose(entries["sun-planet2"], entries["sun-planet1"])  # Z_s / N whole


def test_write_mesh_stiffness(tmp_path):
    out = tmp_path / "run" / "mesh.nc"
    data = write_mesh_stiffness(STUDY, 120.0, 0.01, out)
    assert out.is_file() and out.with_suffix(".png").is_file()
    assert sorted(p.name for p in out.parent.iterdir()) == ["mesh.nc", "mesh.png"]
    with open_dataset(out) as back:  # mesh names as the index of mesh
        assert back.mesh_stiffness.attrs["units"] == "N/m"
        assert back.attrs["Conventions"].startswith("CF")
        assert np.allclose(back.mesh_stiffness.values, data.mesh_stiffness.values)
        assert list(back.mesh.values)[:2] == ["sun-planet1", "ring-planet1"]


def test_helical_pair_follows_its_contact_line_length():
    """A helical pair's stiffness is proportional to its contact-line length: each pair
    contributes min(p, eps_g - p, eps_a, eps_b) / (eps_a eps_b) k-bar over the total
    contact ratio eps_g = eps_a + eps_b, so the mean stays k-bar (textbook helical
    gearing; docs/model.md §5.2)."""
    case = load_case(Path(__file__).resolve().parent.parent / "cases" / "yang2016_gearbox")
    dataset = mesh_stiffness_at_constant_speed(case, carrier_speed_rpm=60.0, duration=0.1)
    stage = case.gearbox.stages[2]
    k = dataset.mesh_stiffness.sel(mesh="parallel.input-output").values
    eps_a, eps_b = stage.mesh.contact_ratio, stage.overlap_ratio
    eps_g = eps_a + eps_b
    cycle = stage.input_gear.teeth * (60.0 * math.pi / 30) * dataset.time.values / (2 * math.pi)
    p = np.mod(cycle, 1.0)[:, None] + np.arange(math.ceil(eps_g) + 1)[None, :]
    length = np.clip(
        np.minimum.reduce([p, eps_g - p, np.full_like(p, eps_a), np.full_like(p, eps_b)]), 0, None
    )
    expected = stage.mesh.stiffness * length.sum(axis=1) / (eps_a * eps_b)
    assert np.allclose(k, expected, rtol=1e-9, atol=1e-6 * stage.mesh.stiffness)
    assert float(dataset.contact_ratio.sel(mesh="parallel.input-output")) == pytest.approx(eps_g)
    assert k.min() < 0.7 * stage.mesh.stiffness < stage.mesh.stiffness < k.max()
