"""Shared fixtures: the seed's study case and stages built for a test."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from pygear import (
    Bearing,
    Carrier,
    Case,
    Gear,
    Gearbox,
    Mesh,
    PlanetaryStage,
    PlanetBearing,
    load_case,
)
from pygear.assembly.contact_table import LAW_CODES, ContactTable

CASES = Path(__file__).resolve().parent.parent / "cases"


@pytest.fixture(scope="session")
def study_case() -> Case:
    """The seed paper's planetary study case (Table 1)."""
    return load_case(CASES / "yang2016_planetary")


def consistent_stage(
    planets: int,
    *,
    helix_deg: float = 0.0,
    axial_position: float = 0.0,
    planet_angles_deg: tuple[float, ...] | None = None,
    name: str = "stage",
) -> PlanetaryStage:
    """A stage whose radii satisfy r_bs + r_bp = r_c cos(alpha_s) and
    r_br - r_bp = r_c cos(alpha_r) exactly, with room for up to 8 planets."""
    alpha = math.radians(22.0)
    sun, planet = 0.060, 0.020
    carrier = (sun + planet) / math.cos(alpha)
    ring = planet + carrier * math.cos(alpha)
    # a helical stage needs its overlap ratio (the helical contact-line law); 1.2 is a
    # plausible value, and the matrices these stages are built for do not depend on it
    overlap = 1.2 if helix_deg else None
    return PlanetaryStage(
        name=name,
        carrier=Carrier(mass=6.0, polar_inertia=0.07, tilt_inertia=0.04, radius=carrier),
        ring=Gear(mass=3.0, polar_inertia=0.06, tilt_inertia=0.03, base_radius=ring),
        sun=Gear(mass=0.8, polar_inertia=2.0e-3, tilt_inertia=1.1e-3, base_radius=sun),
        planet=Gear(mass=0.3, polar_inertia=1.0e-4, tilt_inertia=0.6e-4, base_radius=planet),
        planets=planets,
        carrier_bearing=Bearing(radial=2e8, axial=1.5e8, tilt=3e6, torsional=0.0),
        ring_bearing=Bearing(radial=3e8, axial=2e8, tilt=4e6, torsional=5e7),
        sun_bearing=Bearing(radial=1e8, axial=1e8, tilt=2e6, torsional=0.0),
        planet_bearing=PlanetBearing(radial=1.2e8, axial=0.9e8, tilt=1.5e6),
        sun_mesh=Mesh(
            stiffness=4e8, pressure_angle_deg=22.0, contact_ratio=1.5, overlap_ratio=overlap
        ),
        ring_mesh=Mesh(
            stiffness=6e8,
            pressure_angle_deg=22.0,
            contact_ratio=1.6,
            end_to_peak=0.7,
            overlap_ratio=overlap,
        ),
        planet_angles_deg=planet_angles_deg,
        base_helix_angle_deg=helix_deg,
        axial_position=axial_position,
    )


def case_of(*stages: PlanetaryStage, formulation: str = "consistent") -> Case:
    """A case holding the given stages and no scenes of its own."""
    return Case(name="test", gearbox=Gearbox(stages=stages), formulation=formulation)


# --------------------------------------------------------------------------- round-off

DOUBLE_EPSILON = 2.0**-52
"""Unit round-off of float64 [-]."""


def rigid_to_elastic_ratio(
    base_radius: float, angle: float, mesh_force: float, mesh_stiffness: float
) -> float:
    """How much a mesh deflection amplifies round-off in the state.

    The deflection delta = b . q is a small difference of rigid-body displacements of
    size r_b * theta (theta the gear's turned angle [rad], r_b its base radius [m]), so a
    rounding of relative size eps in q becomes eps * r_b theta / delta in delta, with
    delta = F / k (F a typical mesh force [N], k the mean mesh stiffness [N/m]).
    """
    return base_radius * angle / (mesh_force / mesh_stiffness)


def roundoff_tolerance(steps: int, amplification: float, safety: float = 10.0) -> float:
    """Relative difference two equivalent computations of a transient may show.

    Two code paths that are equal in exact arithmetic (a pruned DOF set and the full one;
    two BLAS kernels summing in a different order) round differently at every step: by
    eps per operation, amplified by ``amplification`` (see :func:`rigid_to_elastic_ratio`).
    The average-acceleration rule neither damps nor amplifies what a step adds (spectral
    radius 1), so the differences accumulate; independent roundings add like a random
    walk, sqrt(steps) (Higham, *Accuracy and Stability of Numerical Algorithms*, 2002,
    sec. 2.8), and ``safety`` covers the constant of the growth.

    This is an upper estimate: the study case's planar and spatial runs, computed with
    OpenBLAS's generic (Prescott) and Haswell kernels, differ by 1e-14 to 1e-8 where it
    allows 5e-6 to 8e-5. It is kept because it follows from the run's magnitudes alone,
    and it stays four orders of magnitude below what a missing coupling would change.
    """
    return safety * math.sqrt(steps) * DOUBLE_EPSILON * amplification


def short_scene(case, name: str, duration: float, **changes):
    """Scene ``name`` of ``case`` cut to ``duration`` seconds (transient only)."""
    scene = case.scene(name)
    changes.setdefault("mean_window", min(scene.transient.mean_window, duration))
    settings = dataclasses.replace(scene.transient, duration=duration, **changes)
    return dataclasses.replace(scene, transient=settings, analyses=("transient",))


def run_on_paths(monkeypatch, case, scene, paths) -> dict:
    """The scene run once on each of the kernel's linear-solver paths, forced by the
    environment variable; each run must say it ran on that path and why."""
    from pygear.analysis.time.transient import run_transient
    from pygear.kernel.newmark_support import LINEAR_SOLVER_VARIABLE

    runs = {}
    for path in paths:
        monkeypatch.setenv(LINEAR_SOLVER_VARIABLE, path)
        runs[path] = run_transient(case, scene)
        assert runs[path].attrs["linear_solver"] == path
        assert LINEAR_SOLVER_VARIABLE in runs[path].attrs["linear_solver_reason"]
    return runs


def study_roundoff(study_case, run) -> float:
    """Round-off of the study run-up: the sun-planet deflection against the sun's turn."""
    stage = study_case.gearbox.stages[0]
    turn = float(np.abs(run.speed.sel(member="planetary.sun")).max()) * math.pi / 30  # rad/s
    angle = turn * run.attrs["duration"]
    force = float(np.sqrt(np.mean(run.mesh_force.sel(mesh="planetary.sun-planet1").values ** 2)))
    amplification = rigid_to_elastic_ratio(
        stage.sun.base_radius, angle, force, stage.sun_mesh.stiffness
    )
    return roundoff_tolerance(run.attrs["steps"], amplification)


def study_steady_rotation(study_case, carrier_rpm: float, drive_torque: float) -> dict:
    """The study case turning steadily at ``carrier_rpm`` under ``drive_torque`` on the
    carrier, derived from its matrices (not from a run): the rigid mode through the
    stiffness's null space, the load torque that balances the drive and the mass
    damping's drag (r' F = alpha omega J_eq), and the static deflection under both.

    Returns the model, the steady scene (constant drive and load, no probes), the rigid
    mode per rad/s of the carrier, omega, alpha, J_eq at the carrier, the load torque on
    the sun, the static state and each mesh's static deflection."""
    import scipy.linalg

    from pygear import TorqueLaw
    from pygear.analysis.time.transient import transient_problem
    from pygear.assembly.dof_rows import dof_row

    base = study_case.scene("runup")
    scene = dataclasses.replace(base, name="steady", effects=(), analyses=("transient",))
    settings = dataclasses.replace(
        base.transient,
        duration=1.0,
        sample_rate=None,
        drive=TorqueLaw.constant(drive_torque),
        load=TorqueLaw.constant(0.0),
        speed_reference_rpm=None,
        probes=(),
    )
    model = transient_problem(study_case, dataclasses.replace(scene, transient=settings)).model
    carrier = dof_row(model, "planetary.carrier.theta_z")
    sun = dof_row(model, "planetary.sun.theta_z")
    null = scipy.linalg.null_space(model.stiffness, rcond=1e-12)
    assert null.shape[1] == 1
    rigid = null[:, 0] / (carrier @ null[:, 0])  # carrier turns at 1 rad/s
    omega = carrier_rpm * math.pi / 30
    alpha = study_case.damping.mass_coefficient
    inertia = float(rigid @ model.mass @ rigid)  # J_eq at the carrier
    load = (drive_torque - alpha * omega * inertia) / float(sun @ rigid)
    force = drive_torque * carrier - load * sun - alpha * omega * (model.mass @ rigid)
    static = np.linalg.lstsq(model.stiffness, force, rcond=None)[0]
    settings = dataclasses.replace(settings, load=TorqueLaw.constant(load))
    return {
        "model": model,
        "scene": dataclasses.replace(scene, transient=settings),
        "rigid": rigid,
        "omega": omega,
        "alpha": alpha,
        "inertia": inertia,
        "load": load,
        "static": static,
        "deflection": np.array([mesh.deflection @ static for mesh in model.meshes]),
    }


def assert_channels_agree(reference, other, tolerance: float, round_off_only: dict) -> None:
    """Every time channel of two runs within tolerance of its scale; a channel that is
    zero in exact arithmetic is measured against the channel ``round_off_only`` names."""
    from pygear.analysis.signals.channels import channel_names, channel_series

    channels = channel_names(reference)
    assert channels
    for name in channels:
        scale = float(
            np.abs(channel_series(reference, round_off_only.get(name, name)).values).max()
        )
        difference = float(
            np.abs(
                channel_series(other, name).values - channel_series(reference, name).values
            ).max()
        )
        assert difference <= tolerance * max(scale, 1e-300), name


def single_mesh_table(
    mean_stiffness: float,
    contact_ratio: float,
    law: str,
    end_to_peak: float = 1.0,
    curve: np.ndarray | None = None,
    angles: tuple[str, str] = ("rotor", "ground"),
) -> ContactTable:
    """Tooth-contact table of one mesh with Z1 = Z2 = 1: the mesh cycle is s = theta / 2 pi.

    ``law`` is a contact-table law name (``parabola``, ``tabulated``, ...), ``curve`` the
    samples of a tabulated law, ``angles`` the labels of the two angles the mesh reads.
    """
    samples = np.zeros(1) if curve is None else np.asarray(curve, dtype=np.float64)
    return ContactTable(
        names=("mesh",),
        gears=(("pinion", "wheel"),),
        angles=(angles,),
        teeth=np.ones((2, 1), dtype=np.int32, order="F"),
        cycle_sign=np.ones(1, dtype=np.int32),
        tooth_offset=np.zeros((2, 1), dtype=np.int32, order="F"),
        mean_stiffness=np.array([mean_stiffness]),
        contact_ratio=np.array([contact_ratio]),
        end_to_peak=np.array([end_to_peak]),
        phase=np.zeros(1),
        law=np.array([LAW_CODES[law]], dtype=np.int32),
        curve_start=np.zeros(1, dtype=np.int32),
        curve_size=np.array([0 if curve is None else samples.size], dtype=np.int32),
        curve=samples,
        factor_start=np.full((2, 1), -1, dtype=np.int32, order="F"),
        factor=np.ones(1),
        max_pairs=int(math.ceil(contact_ratio)) + 1,
    )


@pytest.fixture(scope="module")
def scheduler():
    """One 2-worker cluster of threads (no processes, no dashboard) for a test module."""
    import distributed

    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
    )
    yield cluster.scheduler_address
    cluster.close()
