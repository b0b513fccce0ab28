"""The kernel's sparse path (fortran/newmark_sparse.f90): M, C, K0 on one sparse pattern,
Khat and M factored by CHOLMOD.

The sparse path computes the same step as the banded path in exact arithmetic (the
same right-hand side, a different factorization of the same Khat), so on the study case
and the gearbox their runs may differ by round-off only: the bound is
conftest.roundoff_tolerance with the mesh deflection's rigid-to-elastic ratio.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse
from conftest import (
    CASES,
    assert_channels_agree,
    rigid_to_elastic_ratio,
    roundoff_tolerance,
    run_on_paths,
    short_scene,
    study_roundoff,
)

from pygear import load_case
from pygear.kernel.newmark import BandedNewmark, KernelProbe
from pygear.kernel.newmark_rebase import RigidRebase
from pygear.kernel.newmark_storage import SPARSE_OVERHEAD, kernel_storage
from pygear.kernel.newmark_support import LINEAR_SOLVER_VARIABLE
from pygear.kernel.sparse_cholesky import sparse_cholesky_available

PATHS = ("banded_cholesky", "sparse_cholesky")

pytestmark = pytest.mark.skipif(
    not sparse_cholesky_available(), reason="this build has no CHOLMOD (libsuitesparse-dev)"
)


def test_sparse_and_banded_study_runup_agree_to_round_off(study_case, monkeypatch):
    """The study run-up (18 DOFs, time-varying stiffness, predictor) over 0.2 s, past
    t_s: every channel within conftest.roundoff_tolerance (about 1e-5), where a wrong
    entry of the sparse pattern would move speeds and mesh forces by percents."""
    scene = short_scene(study_case, "runup", 0.2, mean_window=0.05)
    runs = run_on_paths(monkeypatch, study_case, scene, PATHS)
    banded, sparse = (runs[path] for path in PATHS)
    tolerance = study_roundoff(study_case, banded)
    assert tolerance < 1e-4
    assert_channels_agree(
        banded,
        sparse,
        tolerance,
        {"acceleration:planetary.ring.y": "acceleration:planetary.sun.theta_z"},
    )
    assert sparse.t_s.item() == pytest.approx(banded.t_s.item(), rel=tolerance)


def test_sparse_and_banded_gearbox_runup_agree_to_round_off(monkeypatch):
    """The gearbox run-up (50 DOFs, 15 meshes, the helical parallel pair): every channel
    within conftest.roundoff_tolerance set by the fastest pair's turn."""
    gearbox = load_case(CASES / "yang2016_gearbox")
    scene = short_scene(gearbox, "runup_tv", 0.05, mean_window=0.01)
    runs = run_on_paths(monkeypatch, gearbox, scene, PATHS)
    banded, sparse = (runs[path] for path in PATHS)
    pair = gearbox.gearbox.stages[2]
    turned = float(np.abs(banded.speed.sel(member="parallel.input_gear")).max()) * math.pi / 30
    force = float(np.sqrt(np.mean(banded.mesh_force.sel(mesh="parallel.input-output").values ** 2)))
    tolerance = roundoff_tolerance(
        banded.attrs["steps"],
        rigid_to_elastic_ratio(
            pair.input_gear.base_radius, turned * 0.05, force, pair.mesh.stiffness
        ),
    )
    assert tolerance < 1e-5
    assert_channels_agree(banded, sparse, tolerance, {})


@pytest.mark.parametrize(
    "changes",
    [
        {"equivalent_load": "iterate", "restart_at_jumps": True},
        {"integrator": "generalized-alpha"},
        {"equivalent_load": "refactor"},
        {"integrator": "generalized-alpha", "equivalent_load": "refactor"},
    ],
    ids=["iterate-restart", "generalized-alpha", "refactor", "generalized-alpha-refactor"],
)
def test_sparse_and_banded_agree_in_the_other_modes(study_case, monkeypatch, changes):
    """The restarts solve with M's CHOLMOD factor, the generalized-alpha scheme adds the
    alpha_m M a_n product on the sparse pattern, and a refactor adds the meshes'
    stiffness changes b_m b_m^T to Khat on the pattern and refactors numerically (the
    banded path factors anew): both paths within the round-off bound, or the iteration
    tolerance accumulated like round-off (as in tests/test_dense_path.py)."""
    scene = short_scene(study_case, "runup", 0.05, mean_window=0.02, **changes)
    runs = run_on_paths(monkeypatch, study_case, scene, PATHS)
    banded, sparse = (runs[path] for path in PATHS)
    if changes.get("restart_at_jumps"):
        assert banded.attrs["solver_restarts"] > 0 and sparse.attrs["solver_restarts"] > 0
    if changes.get("equivalent_load") == "refactor":
        assert sparse.attrs["solver_refactors"] == banded.attrs["solver_refactors"] > 0
    iteration = 10.0 * math.sqrt(banded.attrs["steps"]) * banded.attrs["tolerance"]
    tolerance = max(study_roundoff(study_case, banded), iteration)
    assert_channels_agree(
        banded,
        sparse,
        tolerance,
        {"acceleration:planetary.ring.y": "acceleration:planetary.sun.theta_z"},
    )


def _chain(n: int, spring: float = 1.0e6, mass: float = 2.0, grounded: bool = True):
    """A spring-mass chain as SciPy sparse matrices (fixed at one end when grounded)."""
    main = np.full(n, 2.0 * spring)
    main[-1] = spring
    if not grounded:
        main[0] = spring
    stiffness = scipy.sparse.diags(
        [main, np.full(n - 1, -spring), np.full(n - 1, -spring)], [0, 1, -1], format="csc"
    )
    return scipy.sparse.identity(n, format="csc") * mass, stiffness


def test_sparse_chain_free_vibration_matches_its_modal_solution(monkeypatch):
    """A fixed-free chain of 3000 masses on the sparse path (forced: a plain chain reads
    as much banded), started in its first mode: average acceleration keeps the mode's amplitude and
    stretches its period by the known factor, omega_h = (2/dt) atan(omega dt / 2)
    (Newmark's trapezoidal rule; Hughes, The Finite Element Method, 1987, sec. 9.3).
    The last mass's displacement follows A cos(omega_h t) to round-off of the solves."""
    monkeypatch.delenv(LINEAR_SOLVER_VARIABLE, raising=False)
    n, spring, mass = 3000, 1.0e6, 2.0
    mass_matrix, stiffness = _chain(n, spring, mass)
    j = np.arange(1, n + 1)
    omega = 2.0 * math.sqrt(spring / mass) * math.sin(math.pi / (2 * (2 * n + 1)))
    shape = np.sin(j * math.pi / (2 * n + 1))  # the first fixed-free mode, exactly
    dt = 0.05 / omega
    solver = BandedNewmark(
        mass_matrix, 0.0 * stiffness, stiffness, dt, linear_solver="sparse_cholesky"
    )
    assert solver.linear_solver == "sparse_cholesky"
    weights = np.zeros(n)
    weights[-1] = 1.0
    steps = 400
    run = solver.run(steps, [KernelProbe("tip", "displacement", weights)], q0=1e-3 * shape)
    omega_h = (2.0 / dt) * math.atan(omega * dt / 2.0)
    expected = 1e-3 * shape[-1] * np.cos(omega_h * run.time)
    # each solve errs by about cond(Khat) eps (Higham 2002, sec. 10.1), cond(Khat) =
    # (4 k/m + 4/dt^2) / (4/dt^2) about 4e4 here; over the steps like a random walk,
    # safety 10 (conftest.roundoff_tolerance)
    condition = (4.0 * spring / mass + 4.0 / dt**2) / (4.0 / dt**2)
    tolerance = 10.0 * math.sqrt(steps) * np.finfo(float).eps * condition
    assert tolerance < 1e-8
    assert np.abs(run.samples[0] - expected).max() <= tolerance * 1e-3 * shape[-1]


def test_automatic_choice_by_the_entries_a_step_reads(monkeypatch):
    """A spring chain reads the same count on both paths (band 2n, CHOLMOD factor and
    pattern 2n - 1 each): banded, sparse input or dense.  A chain whose every 10th mass
    is tied to mass 0 has a band as wide as the model after RCM but a factor of a few
    entries per DOF: sparse, and the reason gives the counts.  A chain of 3000 masses
    started on the sparse path is the test above."""
    monkeypatch.delenv(LINEAR_SOLVER_VARIABLE, raising=False)
    mass, stiffness = _chain(400)
    chain = kernel_storage(mass, 0 * mass, stiffness, None)
    assert chain.linear_solver == "banded_cholesky"
    assert "banded step reads less" in chain.reason
    dense = kernel_storage(mass.toarray(), np.zeros((400, 400)), stiffness.toarray(), None)
    assert dense.linear_solver == "banded_cholesky"
    ties = scipy.sparse.lil_matrix((400, 400))
    for k in range(10, 400, 10):
        ties[0, 0] += 1.0
        ties[k, k] += 1.0
        ties[0, k] = ties[k, 0] = -1.0
    storage = kernel_storage(mass, 0 * mass, stiffness + ties.tocsc(), None)
    assert storage.linear_solver == "sparse_cholesky"
    assert "CHOLMOD factor" in storage.reason and "reads" in storage.reason
    assert SPARSE_OVERHEAD > 1.0


def test_sparse_storage_holds_the_matrices_exactly(monkeypatch):
    """The values on the common pattern are the matrices' own entries (no rounding:
    each is copied or summed with zeros), for dense and for sparse input alike."""
    rng = np.random.default_rng(7)
    n = 60
    dense = {}
    for name in ("mass", "damping", "stiffness"):
        a = rng.standard_normal((n, n)) * (rng.random((n, n)) < 0.05)
        dense[name] = a + a.T + n * np.eye(n)
    for inputs in (dense, {k: scipy.sparse.csc_matrix(v) for k, v in dense.items()}):
        storage = kernel_storage(*inputs.values(), None, "sparse_cholesky")
        start = storage.sparse["sparse_column_start"]
        rows = storage.sparse["sparse_row_index"]
        columns = np.repeat(np.arange(n), np.diff(start))
        for name, matrix in dense.items():
            rebuilt = np.zeros((n, n))
            rebuilt[rows, columns] = storage.sparse[f"sparse_{name}"]
            np.testing.assert_array_equal(np.tril(rebuilt), np.tril(matrix))


def test_sparse_rigid_modes_of_a_free_chain():
    """A free chain has one rigid mode (uniform displacement, mass-normalised: 1 /
    sqrt(n m)); a grounded one has none, even with a low first mode."""
    n, mass = 2500, 2.0
    mass_matrix, stiffness = _chain(n, 1.0e9, mass, grounded=False)
    rebase = RigidRebase(mass_matrix, stiffness, np.arange(n))
    assert rebase.modes.shape == (n, 1)
    # eigsh's vector to its convergence tolerance, relative to the entries
    assert np.abs(np.abs(rebase.modes[:, 0]) - 1.0 / math.sqrt(n * mass)).max() <= 1e-6 / math.sqrt(
        n * mass
    )
    mass_matrix, stiffness = _chain(n, 1.0e9, mass, grounded=True)
    assert not RigidRebase(mass_matrix, stiffness, np.arange(n)).active


def test_ten_thousand_dof_drivetrain_modes_and_steps():
    """A 10 000-DOF synthetic drivetrain (four Timoshenko shafts of 416 elements on
    bearings, joined by couplings, their middles tied by torsional springs): its first 30
    modes by shift-invert Lanczos on a CHOLMOD factor agree with the same Lanczos on
    SciPy's SuperLU factor (another factorization) to 1e-8; and 1 000 Newmark steps on the
    sparse path, started in the first elastic mode without damping, follow Newmark's
    discrete cosine (omega_h = (2/dt) atan(omega dt/2)) to 1e-6 of the amplitude, the
    mode's own residual from Lanczos (1e-10) amplified by the period count (Hughes 1987,
    sec. 9.3).  Times: benchmarks/bench_sparse_path.py."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))
    from bench_sparse_path import drivetrain

    from pygear.analysis.modes.sparse_modal import sparse_modes

    mass, _, stiffness, n = drivetrain(10_002)
    assert n >= 9_900
    cholmod = sparse_modes(stiffness, mass, modes=30)
    splu = sparse_modes(stiffness, mass, modes=30, factorization="splu")
    assert "cholmod" in cholmod.solver and "splu" in splu.solver
    np.testing.assert_allclose(cholmod.frequencies_hz, splu.frequencies_hz, rtol=1e-8)
    elastic = int(np.argmax(cholmod.frequencies_hz > 1e-3))
    omega = 2 * math.pi * float(cholmod.frequencies_hz[elastic])
    shape = cholmod.shapes[:, elastic]
    dt = 0.02 / omega * 2 * math.pi  # 50 steps per period
    solver = BandedNewmark(mass, 0.0 * stiffness, stiffness, dt)
    assert solver.linear_solver == "sparse_cholesky"
    probe_dof = int(np.argmax(np.abs(shape)))
    weights = np.zeros(n)
    weights[probe_dof] = 1.0
    run = solver.run(1000, [KernelProbe("peak", "displacement", weights)], q0=shape)
    omega_h = (2.0 / dt) * math.atan(omega * dt / 2.0)
    expected = shape[probe_dof] * np.cos(omega_h * run.time)
    assert np.abs(run.samples[0] - expected).max() <= 1e-6 * abs(shape[probe_dof])


def test_without_cholmod_the_banded_path_carries_everything(monkeypatch):
    """A build without SuiteSparse: the automatic choice falls back to the banded path
    (and says nothing of CHOLMOD's counts), and asking for the sparse path by name is a
    one-line error naming the remedy, before any work."""
    import pygear.kernel.newmark_storage as storage

    monkeypatch.delenv(LINEAR_SOLVER_VARIABLE, raising=False)
    monkeypatch.setattr(storage, "cholmod_available", lambda: False)
    mass, stiffness = _chain(400)
    ties = scipy.sparse.lil_matrix((400, 400))
    for k in range(10, 400, 10):
        ties[0, 0] += 1.0
        ties[k, k] += 1.0
        ties[0, k] = ties[k, 0] = -1.0
    chosen = kernel_storage(mass, 0 * mass, stiffness + ties.tocsc(), None)
    assert chosen.linear_solver == "banded_cholesky"
    assert "CHOLMOD" not in chosen.reason
    with pytest.raises(ValueError, match="no CHOLMOD.*libsuitesparse-dev"):
        kernel_storage(mass, 0 * mass, stiffness, None, "sparse_cholesky")
