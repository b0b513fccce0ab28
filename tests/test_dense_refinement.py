"""The refined dense path keeps a long run's rigid rotation; the bare inverse does not.

1e6 steps (25 s) of the study case in its exact steady state at 2000 rpm, as
tests/test_long_runs.py builds it: a rigid rotation at omega on top of the static
deflections, the drive balancing the load and the mass-proportional damping exactly, so
that every speed stays at omega r (r the rigid rotation, carrier 1) and every mesh
deflection at the static one.  The reference is derived by linear algebra on M and K0
(a null vector and a least-squares static solve), not by the integrator.

The bound.  The rigid mode's speed error e (relative to omega) obeys
J de/dt = tau / omega - alpha J e: each step's torque error tau enters, and the damping
alpha (C = alpha M + ...) takes it out with time constant 1 / alpha (3e5 steps here).
A backward stable step leaves a residual of order eps |K0| |q| (eps = 2^-52, q up to
the 16 rad at which pygear rebases the rotation), so |tau| <= tau_eps = eps r^T |K0| |q|,
and these roundings change sign from step to step: e is a damped random walk of steps
dt tau_eps / (J omega) over the min(steps, 1 / (2 alpha dt)) steps it remembers
(Higham, Accuracy and Stability of Numerical Algorithms, 2002, sec. 2.8), safety 10.
A product with a computed inverse X = s Khat^-1 [..] instead makes a fixed error: X_K r
and X_C r are not 0 but of order kappa(Khat) eps |X| |r|, the same every step at a
constant speed, so e grows steadily towards that error over alpha.

The random walk is what the band factor and, with an optimised BLAS, the refined path
give; with a generic BLAS kernel (OPENBLAS_CORETYPE=Prescott) the refined path's
residual roundings keep their sign for long stretches (2.1e-9 measured, against 7e-11).
The refined path is therefore held to the worst case of the same rounding, each step's
error adding with one sign over the 1 / alpha steps the damping remembers, and to being
at least 10 times closer than the bare inverse, whose error is the kappa(Khat)-amplified
one the refinement removes (measured 500 times with an optimised BLAS, 24 times with
the generic one).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from conftest import DOUBLE_EPSILON, study_steady_rotation

from pygear import Probe
from pygear.analysis.time.transient import transient_problem
from pygear.kernel.newmark_rebase import REBASE_ANGLE
from pygear.kernel.newmark_support import LINEAR_SOLVER_VARIABLE

CARRIER_RPM = 2000.0
DRIVE_TORQUE = 1000.0  # N m on the carrier
STEPS = 1_000_000
DECIMATION = 10_000
SAFETY = 10.0


@pytest.fixture(scope="module")
def steady(study_case):
    """The exact steady state of the study case and its problem on each path."""
    state = study_steady_rotation(study_case, CARRIER_RPM, DRIVE_TORQUE)
    probes = tuple(Probe("mesh_deflection", mesh.name) for mesh in state["model"].meshes)
    transient = dataclasses.replace(state["scene"].transient, probes=probes)
    state["scene"] = dataclasses.replace(state["scene"], transient=transient)
    return state


def _run(study_case, steady: dict, path: str, monkeypatch) -> dict:
    """STEPS steps from the steady state on ``path``: the largest speed error of any DOF
    relative to omega at the end, and the largest mesh deflection error of the samples
    relative to the largest static deflection."""
    monkeypatch.setenv(LINEAR_SOLVER_VARIABLE, path)
    problem = transient_problem(study_case, steady["scene"])
    assert problem.solver.linear_solver == path
    omega, rigid = steady["omega"], steady["rigid"]
    result = problem.solver.run(
        STEPS, problem.probes, decimation=DECIMATION, q0=steady["static"], v0=omega * rigid
    )
    error = np.abs(result.samples - steady["deflection"][:, None]).max()
    return {
        "speed": float(np.abs(result.v - omega * rigid).max() / omega),
        "deflection": float(error / np.abs(steady["deflection"]).max()),
        "time_step": problem.solver.time_step,
    }


def _per_step(steady: dict, time_step: float) -> float:
    """A backward stable step's rigid speed rounding, tau_eps dt / (J omega) (module
    docstring) [relative to omega]."""
    model, rigid, omega = steady["model"], steady["rigid"], steady["omega"]
    angle = steady["static"] + REBASE_ANGLE / np.abs(rigid).max() * rigid  # q before a rebase
    torque = DOUBLE_EPSILON * np.abs(rigid) @ (np.abs(model.stiffness) @ np.abs(angle))
    return time_step * torque / (steady["inertia"] * omega)


def _speed_bound(steady: dict, time_step: float) -> float:
    """SAFETY times the damped random walk of a backward stable step's rigid torque
    rounding (module docstring) [relative to omega]."""
    remembered = min(STEPS, 1.0 / (2.0 * steady["alpha"] * time_step))
    return SAFETY * _per_step(steady, time_step) * math.sqrt(remembered)


def _worst_case_bound(steady: dict, time_step: float) -> float:
    """The same rounding adding with one sign every step over the steps the damping
    remembers, sum_k (1 - alpha dt)^k <= 1 / (alpha dt) [relative to omega]."""
    remembered = min(STEPS, 1.0 / (steady["alpha"] * time_step))
    return _per_step(steady, time_step) * remembered


def test_refined_dense_path_keeps_the_rigid_rotation(study_case, steady, monkeypatch):
    """Over 1e6 steps the band factor keeps every speed within the random walk of a
    backward stable step (about 8e-10 of omega), the refined dense path (the automatic
    choice for the study case) within that rounding's worst case and at least 10 times
    closer than the bare inverse (module docstring), and every mesh deflection within
    1e-9 of the static one."""
    refined = _run(study_case, steady, "dense_refined", monkeypatch)
    banded = _run(study_case, steady, "banded_cholesky", monkeypatch)
    inverse = _run(study_case, steady, "dense_inverse", monkeypatch)
    bound = _speed_bound(steady, refined["time_step"])
    print(
        f"\nspeed error after {STEPS:.0e} steps, relative to omega: refined "
        f"{refined['speed']:.2g}, band factor {banded['speed']:.2g}, bare inverse "
        f"{inverse['speed']:.2g}; bound {bound:.2g}"
    )
    assert bound < 1e-9
    assert banded["speed"] <= bound  # the random walk holds for the band factor
    assert refined["speed"] <= _worst_case_bound(steady, refined["time_step"])
    assert refined["deflection"] <= 1e-9
    assert inverse["speed"] > 10.0 * refined["speed"]  # refinement removes the drift
