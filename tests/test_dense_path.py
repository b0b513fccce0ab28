"""The kernel's dense linear solvers of the Newmark step (fortran/newmark_dense.f90).

The dense path multiplies by s Khat^-1 [-C, -K0, w_in, w_out, B^T, -M], formed once per
problem and updated by the Woodbury identity on refactors; the refined dense path
follows the product with one step of iterative refinement against Khat; the banded path
multiplies by the band matrices and solves with the banded Cholesky factor.  All compute
the same step in exact arithmetic, so their runs may differ by round-off only: the bound
is conftest.roundoff_tolerance with the mesh deflection's rigid-to-elastic ratio, never
bit-identity.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import (
    assert_channels_agree,
    rigid_to_elastic_ratio,
    roundoff_tolerance,
    run_on_paths,
    short_scene,
    study_roundoff,
)

from pygear import load_case
from pygear.analysis.time.transient import run_transient
from pygear.kernel.newmark import BandedNewmark, KernelProbe
from pygear.kernel.newmark_support import LINEAR_SOLVER_VARIABLE, choose_linear_solver

GEARBOX = Path(__file__).resolve().parent.parent / "cases" / "yang2016_gearbox"
PATHS = ("banded_cholesky", "dense_inverse", "dense_refined")


def _both_paths(monkeypatch, case, scene) -> dict:
    """The scene run once on each path, forced by the environment variable."""
    return run_on_paths(monkeypatch, case, scene, PATHS)


def _assert_channels_agree(runs: dict, tolerance: float, round_off_only: dict) -> None:
    """Every channel of each dense run within tolerance of the banded run's."""
    for dense in PATHS[1:]:
        assert_channels_agree(runs[PATHS[0]], runs[dense], tolerance, round_off_only)


def test_dense_and_banded_study_runup_agree_to_round_off(study_case, monkeypatch):
    """The study run-up (18 DOFs, time-varying stiffness, predictor) on both paths over
    0.2 s, past t_s (0.158 s, the load law switches on): every channel within
    conftest.roundoff_tolerance (about 1e-5), where a wrong column of the dense operator
    would move the speeds and mesh forces by percents."""
    scene = short_scene(study_case, "runup", 0.2, mean_window=0.05)
    runs = _both_paths(monkeypatch, study_case, scene)
    tolerance = study_roundoff(study_case, runs["banded_cholesky"])
    assert tolerance < 1e-4  # tight enough to see a wrong term
    # in-phase, equally spaced planets excite no ring translation: round-off on both
    _assert_channels_agree(
        runs, tolerance, {"acceleration:planetary.ring.y": "acceleration:planetary.sun.theta_z"}
    )
    banded = runs[PATHS[0]]
    for dense in (runs[path] for path in PATHS[1:]):
        assert dense.t_s.item() == pytest.approx(banded.t_s.item(), rel=tolerance)
        assert dense.attrs["solver_iterations"] == banded.attrs["solver_iterations"]


def test_dense_and_banded_gearbox_runup_agree_to_round_off(monkeypatch):
    """The gearbox run-up (50 DOFs, 15 meshes, the helical parallel pair) on both paths:
    every channel within conftest.roundoff_tolerance; the parallel pair, the fastest,
    turns furthest against its deflection and sets the amplification."""
    gearbox = load_case(GEARBOX)
    scene = short_scene(gearbox, "runup_tv", 0.05, mean_window=0.01)
    runs = _both_paths(monkeypatch, gearbox, scene)
    banded = runs["banded_cholesky"]
    assert banded.attrs["dof_count"] == 50
    pair = gearbox.gearbox.stages[2]
    turned = float(np.abs(banded.speed.sel(member="parallel.input_gear")).max()) * math.pi / 30
    turned *= 0.05
    force = banded.mesh_force.sel(mesh="parallel.input-output").values
    force = float(np.sqrt(np.mean(force**2)))
    tolerance = roundoff_tolerance(
        banded.attrs["steps"],
        rigid_to_elastic_ratio(pair.input_gear.base_radius, turned, force, pair.mesh.stiffness),
    )
    assert tolerance < 1e-5
    _assert_channels_agree(runs, tolerance, {})


@pytest.mark.parametrize(
    "changes",
    [
        {"equivalent_load": "refactor"},
        {"integrator": "generalized-alpha", "equivalent_load": "refactor"},
        {"equivalent_load": "iterate", "restart_at_jumps": True},
    ],
    ids=["refactor", "generalized-alpha-refactor", "iterate-restart"],
)
def test_dense_and_banded_agree_in_the_iterated_modes(study_case, monkeypatch, changes):
    """The iterated equivalent loads: the dense path's refactor is a Woodbury update of
    its mean-stiffness operator, the banded path's a new factorization; the generalized-
    alpha scheme adds the alpha_m and alpha_f terms, which the dense path carries in its
    operator's mass block and load coefficients.  Each iteration stops once the lagged
    loads move less than the tolerance (1e-8 of the largest mesh force), so the two may
    also differ by that much per step, accumulating like round-off (a random walk over
    the steps, safety 10): the bound is the larger of that and the round-off bound."""
    scene = short_scene(study_case, "runup", 0.05, mean_window=0.02, **changes)
    runs = _both_paths(monkeypatch, study_case, scene)
    banded = runs["banded_cholesky"]
    if changes["equivalent_load"] == "refactor":
        assert banded.attrs["solver_refactors"] > 0  # the update is exercised
    if changes.get("restart_at_jumps"):
        assert banded.attrs["solver_restarts"] > 0
    iteration = 10.0 * math.sqrt(banded.attrs["steps"]) * banded.attrs["tolerance"]
    tolerance = max(study_roundoff(study_case, banded), iteration)
    _assert_channels_agree(
        runs, tolerance, {"acceleration:planetary.ring.y": "acceleration:planetary.sun.theta_z"}
    )


def test_automatic_choice_is_a_backward_stable_path_and_recorded(study_case, monkeypatch):
    """Without a forced path the study run-up (18 DOFs, band half-width 13 of 17) runs on
    the refined dense path (the dense inverse with one step of iterative refinement),
    never on the bare inverse (faster, but it drifts over long runs,
    tests/test_dense_refinement.py).  The run's attributes say which path ran and why."""
    monkeypatch.delenv(LINEAR_SOLVER_VARIABLE, raising=False)
    run = run_transient(study_case, short_scene(study_case, "runup", 0.005))
    assert run.attrs["linear_solver"] == "dense_refined"
    reason = run.attrs["linear_solver_reason"]
    assert reason.startswith("automatic") and "18 DOFs" in reason
    # the half-width itself (13 of 17 here) is counted from the assembled matrices'
    # non-zeros, and a product that is exactly 0 on one BLAS core is 1e-20 on another
    # (14 under Prescott): the reason must name it, not one core's count
    assert "band half-width" in reason and "iterative refinement" in reason


def test_automatic_choice_leaves_larger_models_to_the_factors(monkeypatch):
    """The 50-DOF gearbox is beyond the refined dense path's range: the automatic choice
    compares CHOLMOD's sparse factor with the band (both counts in the reason) when the
    build has CHOLMOD, else takes the band.  Below the range, too, a factor's solve costs
    less than three dense products (a 4-DOF chain)."""
    from pygear.kernel.sparse_cholesky import sparse_cholesky_available

    monkeypatch.delenv(LINEAR_SOLVER_VARIABLE, raising=False)
    gearbox = load_case(GEARBOX)
    run = run_transient(gearbox, short_scene(gearbox, "runup_tv", 0.001))
    assert run.attrs["dof_count"] == 50
    assert run.attrs["linear_solver"] in ("sparse_cholesky", "banded_cholesky")
    if sparse_cholesky_available():
        assert "CHOLMOD factor" in run.attrs["linear_solver_reason"]
    n = 4
    stiffness = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    small = BandedNewmark(np.eye(n), np.zeros((n, n)), stiffness, 1e-3)
    assert small.linear_solver != "dense_refined"
    assert "4 DOFs" in small.linear_solver_reason


def test_automatic_choice_is_banded_for_a_long_narrow_band(monkeypatch):
    """A chain of 400 masses (band half-width 1): the dense operator would hold 1200 x 400
    numbers and cost 2 n^2 per step against a few n for the band, so the automatic
    choice is the banded path; forcing either path is honoured."""
    monkeypatch.delenv(LINEAR_SOLVER_VARIABLE, raising=False)
    n = 400
    stiffness = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    solver = BandedNewmark(np.eye(n), np.zeros((n, n)), stiffness, 1e-3)
    assert solver.bandwidth == 1
    assert solver.linear_solver == "banded_cholesky"
    assert "400 DOFs" in solver.linear_solver_reason
    forced = BandedNewmark(
        np.eye(n), np.zeros((n, n)), stiffness, 1e-3, linear_solver="dense_inverse"
    )
    assert forced.linear_solver == "dense_inverse"
    assert forced.linear_solver_reason.startswith("forced")


def test_unknown_forced_solver_is_refused_naming_the_variable(monkeypatch):
    """A misspelt path in the environment variable is an error naming it and the choices,
    not a silent fall-back to the automatic choice."""
    monkeypatch.setenv(LINEAR_SOLVER_VARIABLE, "dense")
    with pytest.raises(ValueError, match=rf"{LINEAR_SOLVER_VARIABLE} must be one of"):
        choose_linear_solver(18, 13)


@pytest.mark.parametrize("path", ["dense_inverse", "dense_refined"])
def test_dense_path_matches_the_closed_form_oscillator(monkeypatch, path):
    """One mass on a spring (omega^2 = k/m), started at x0 on a dense path: the average-
    acceleration rule advances a phase of 2 atan(omega dt / 2) per step with unit
    amplitude (Newmark's discrete cosine), so x_n = x0 cos(n phi) to the recurrence's
    round-off (about n eps x0 = 1e-15 m; the bound, 1e-12 m, is a thousand times that)."""
    monkeypatch.delenv(LINEAR_SOLVER_VARIABLE, raising=False)
    mass, stiffness, time_step, x0, steps = 2.0, 8.0e4, 1.0e-3, 1.0e-3, 4000
    solver = BandedNewmark(
        np.array([[mass]]),
        np.zeros((1, 1)),
        np.array([[stiffness]]),
        time_step,
        linear_solver=path,
    )
    assert solver.linear_solver == path
    probe = KernelProbe("x", "displacement", weights=np.ones(1))
    result = solver.run(steps, [probe], q0=np.array([x0]))
    phase = 2.0 * math.atan(math.sqrt(stiffness / mass) * time_step / 2.0)
    expected = x0 * np.cos(phase * np.arange(steps + 1))
    np.testing.assert_allclose(result.samples[0], expected, rtol=0, atol=1e-12)
