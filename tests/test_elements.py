"""Element checks: rigid-body motions give zero deflection, K and M have the right
structure.  The rigid motions are built here from geometry, not from the code."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
from conftest import case_of, consistent_stage

from pygear.assembly import assemble
from pygear.kernel.calls import call

FORMULATIONS = ("improved", "consistent", "lin-parker")


def rigid_motion(model, stage, translation, rotation) -> np.ndarray:
    """Full DOF vector of a rigid motion u(X) = t + Theta x X of the whole gearbox."""
    translation, rotation = np.asarray(translation, float), np.asarray(rotation, float)
    q = np.zeros(len(model.full_labels))
    index = {label: i for i, label in enumerate(model.full_labels)}
    lin_parker = model.formulation == "lin-parker"

    def put(name, values):
        for dof, value in values.items():
            key = f"{name}.{dof}"
            if key in index:
                q[index[key]] = value

    centre = np.array([0.0, 0.0, stage.axial_position])
    u_centre = translation + np.cross(rotation, centre)
    central = dict(zip(("x", "y", "z"), u_centre)) | dict(
        zip(("theta_x", "theta_y", "theta_z"), rotation)
    )
    put(
        "housing",
        dict(zip(("x", "y", "z"), translation))
        | dict(zip(("theta_x", "theta_y", "theta_z"), rotation)),
    )
    for member in ("carrier", "ring", "sun"):
        put(f"{stage.name}.{member}", central)
    for n, psi in enumerate(stage.planet_angles, start=1):
        radial = np.array([math.cos(psi), math.sin(psi), 0.0])
        tangential = np.array([-math.sin(psi), math.cos(psi), 0.0])
        position = centre + stage.carrier.radius * radial
        u = translation + np.cross(rotation, position)
        values = {"z": u[2], "theta_zeta": rotation @ radial, "theta_eta": rotation @ tangential}
        if lin_parker:  # carrier-fixed frame: absolute displacements and spin
            values |= {"zeta": u @ radial, "eta": u @ tangential, "theta_z": rotation[2]}
        else:  # the revolution phi carries the turning about the stage axis
            u_in_plane = u - np.cross([0, 0, rotation[2]], position)
            values |= {
                "zeta": u_in_plane @ radial,
                "eta": u_in_plane @ tangential,
                "theta_z": 0.0,
                "phi": rotation[2],
            }
        put(f"{stage.name}.planet{n}", values)
    return q


RIGID_MOTIONS = [
    ([1e-3, 0, 0], [0, 0, 0]),
    ([0, 1e-3, 0], [0, 0, 0]),
    ([0, 0, 1e-3], [0, 0, 0]),
    ([0, 0, 0], [1e-3, 0, 0]),
    ([0, 0, 0], [0, 1e-3, 0]),
    ([0, 0, 0], [0, 0, 1e-3]),
    ([2e-4, -3e-4, 5e-4], [4e-4, -1e-4, 7e-4]),
]


@pytest.mark.parametrize("formulation", FORMULATIONS)
@pytest.mark.parametrize("helix_deg", [0.0, 18.0])
@pytest.mark.parametrize("motion", RIGID_MOTIONS)
def test_rigid_body_motion_gives_zero_deflection(formulation, helix_deg, motion):
    stage = consistent_stage(
        4, helix_deg=helix_deg, axial_position=0.35, planet_angles_deg=(0.0, 85.0, 181.0, 273.0)
    )
    model = assemble(case_of(stage), formulation=formulation, dof_set="spatial")
    q = rigid_motion(model, stage, *motion)
    scale = np.abs(q).max()
    for spring in model.springs:
        deflection = spring.deflection.T @ q[spring.dofs]
        assert np.all(np.abs(deflection) <= 1e-12 * scale), (spring.name, deflection)


def test_rigid_body_check_can_fail():
    """A wrong motion (the sun turned alone) must deflect the sun meshes."""
    stage = consistent_stage(3)
    model = assemble(case_of(stage), formulation="improved", dof_set="spatial")
    q = np.zeros(len(model.full_labels))
    q[model.full_labels.index("stage.sun.theta_z")] = 1e-3
    deflected = [s.name for s in model.springs if np.any(np.abs(s.deflection.T @ q[s.dofs]) > 0)]
    assert "stage.sun-planet1" in deflected and "stage.sun_bearing" in deflected


@pytest.mark.parametrize("helix_deg", [0.0, -15.0])
def test_parallel_mesh_rigid_motions(helix_deg):
    """Fixed-axis pair: gear 2 at gear 1 + c (cos a, sin a) with c = (r1 + r2)/cos(alpha)."""
    alpha, r1, r2, angle = math.radians(21.173), 0.05, 0.08, math.radians(30.0)
    (b,) = call("parallel_mesh_vector", angle, alpha, r1, r2, math.radians(helix_deg))
    centre_2 = (r1 + r2) / math.cos(alpha) * np.array([math.cos(angle), math.sin(angle), 0.2])
    centre_2[2] = 0.0
    for translation, rotation in RIGID_MOTIONS:
        t, w = np.array(translation), np.array(rotation)
        q = np.concatenate([t, w, t + np.cross(w, centre_2), w])
        assert abs(b @ q) <= 1e-12 * np.abs(q).max()
    # the spur pair's in-plane part: delta = d.(u1 - u2) + r1 theta1 + r2 theta2
    if helix_deg == 0.0:
        assert b[5] == pytest.approx(r1) and b[11] == pytest.approx(r2)


@pytest.mark.parametrize("formulation", FORMULATIONS)
@pytest.mark.parametrize("dof_set", ["spatial", "planar", "torsional"])
def test_matrices_structure(study_case, formulation, dof_set):
    model = assemble(study_case, formulation=formulation, dof_set=dof_set)
    for matrix in (model.mass, model.stiffness, model.damping):
        assert np.array_equal(matrix, matrix.T)
    assert scipy.linalg.eigvalsh(model.mass).min() > 0
    stiffness_eigenvalues = scipy.linalg.eigvalsh(model.stiffness)
    scale = stiffness_eigenvalues.max()
    assert stiffness_eigenvalues.min() > -1e-12 * scale
    # one free rigid rotation of the gear train: carrier and sun turn freely, ring held
    assert np.sum(np.abs(stiffness_eigenvalues) < 1e-10 * scale) == 1


@pytest.mark.parametrize("formulation", ["improved", "consistent"])
def test_null_space_is_the_kinematic_rotation(study_case, formulation):
    """Carrier 1, sun 1 + r_br/r_bs, planet spin -r_br/r_bp relative to the carrier."""
    stage = study_case.gearbox.stages[0]
    model = assemble(study_case, formulation=formulation, dof_set="planar")
    mode = np.zeros(model.size)
    ratio = {"carrier": 1.0, "sun": 1.0 + stage.ring.base_radius / stage.sun.base_radius}
    for j, label in enumerate(model.dof_labels):
        member, dof = label.split(".")[1:]
        if dof == "theta_z" and member in ratio:
            mode[j] = ratio[member]
        elif dof == "theta_z" and member.startswith("planet"):
            mode[j] = -stage.ring.base_radius / stage.planet.base_radius
    residual = model.stiffness @ mode
    assert np.abs(residual).max() < 1e-12 * np.abs(model.stiffness).max()


def test_planet_mass_formulations_kinetic_energy():
    """The consistent planet mass is the exact kinetic energy of docs/model.md §3.1."""
    m, i_t, i_p, r_c = 0.66, 0.7e-3, 1.53e-3, 0.0969
    (
        translation,
        rotation,
    ) = call("planet_mass_matrix", 2, m, i_t, i_p, r_c)
    rate = np.array([0.3, -0.7, 0.2, 0.5, -0.4, 1.1, 2.3])  # zeta, eta, z, tilts, spin, phi
    zeta, eta, z, t1, t2, spin, phi = rate
    energy = (
        0.5 * m * (zeta**2 + (eta + r_c * phi) ** 2 + z**2)
        + 0.5 * i_p * (spin + phi) ** 2
        + 0.5 * i_t * (t1**2 + t2**2)
    )
    assert 0.5 * rate @ (translation + rotation) @ rate == pytest.approx(energy, rel=1e-14)
    improved = sum(call("planet_mass_matrix", 1, m, i_t, i_p, r_c))
    assert np.allclose(improved, np.diag([m, m, m, i_t, i_t, i_p, m * r_c**2]), rtol=0, atol=0)


def test_speed_dependent_planet_terms():
    from pygear.kernel.calls import _kernel

    gyroscopic, centrifugal = _kernel.planet_speed_matrices(0.66, 12.0)
    assert np.allclose(gyroscopic + gyroscopic.T, 0)
    assert gyroscopic[1, 0] == pytest.approx(2 * 0.66 * 12.0)
    assert np.allclose(np.diag(centrifugal)[:2], -0.66 * 144.0)
