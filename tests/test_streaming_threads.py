"""Threads and set-up of long runs (issue #32.3): BLAS limited to what the model needs,
and each scene's transient problem built once for its checks and its run."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from threadpoolctl import threadpool_info

from pygear import load_case
from pygear.analysis.time import transient
from pygear.cli import main
from pygear.kernel.newmark_support import SMALL_MODEL_DOFS, blas_threads

STUDY = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"


def _blas_threads_now() -> list[int]:
    return [info["num_threads"] for info in threadpool_info() if info["user_api"] == "blas"]


def test_a_small_model_runs_on_one_blas_thread_and_the_limit_is_undone(monkeypatch):
    monkeypatch.delenv("PYGEAR_BLAS_THREADS", raising=False)
    case = load_case(STUDY)
    problem = transient.transient_problem(case, case.scene("runup"))
    assert problem.model.size < SMALL_MODEL_DOFS and problem.solver.blas_threads == 1
    before = _blas_threads_now()
    during = []
    problem.solver.run(
        2000, problem.probes[:1], progress=lambda done, total: during.append(_blas_threads_now())
    )
    assert during and all(threads == [1] * len(before) for threads in during)
    assert _blas_threads_now() == before  # the caller's limits come back


def test_blas_threads_follow_the_model_size(monkeypatch):
    monkeypatch.delenv("PYGEAR_BLAS_THREADS", raising=False)
    assert blas_threads(18) == blas_threads(SMALL_MODEL_DOFS - 1) == 1
    assert blas_threads(100 * SMALL_MODEL_DOFS) >= 1
    monkeypatch.setenv("PYGEAR_BLAS_THREADS", "3")
    assert blas_threads(18) == 3


CASE_FILE = f"""
import dataclasses

from pygear import load_case

base = load_case({str(STUDY)!r})
runup = base.scene("runup")
settings = dataclasses.replace(runup.transient, duration=0.02, mean_window=0.01)
case = dataclasses.replace(
    base,
    name="twice",
    scenes=(dataclasses.replace(runup, analyses=("transient",), transient=settings),),
)
"""


def test_pygear_run_builds_each_transient_problem_once(tmp_path, monkeypatch):
    """The checks before the run build the problem; the run takes it over."""
    (tmp_path / "case").mkdir()
    (tmp_path / "case" / "case.py").write_text(CASE_FILE)
    built = []
    real = transient._new_problem

    def counting(*args, **kwargs):
        built.append(args[1].name)
        return real(*args, **kwargs)

    monkeypatch.setattr(transient, "_new_problem", counting)
    out = tmp_path / "out"
    assert main(["run", str(tmp_path / "case"), "--out", str(out), "--no-figures", "--json"]) == 0
    assert built == ["runup"]
    assert (out / "runup.nc").is_file()


def test_a_problem_is_handed_over_once_and_not_to_other_inputs():
    case = load_case(STUDY)
    scene = case.scene("runup")
    first = transient.transient_problem(case, scene)
    assert transient.transient_problem(case, scene) is not first  # only to a run
    second = transient.transient_problem(case, scene)
    assert transient.transient_problem(case, scene, reuse=True) is second  # handed over
    assert transient.transient_problem(case, scene, reuse=True) is not second  # once
    other = dataclasses.replace(
        scene, transient=dataclasses.replace(scene.transient, duration=0.5, mean_window=0.1)
    )
    transient.transient_problem(case, scene)
    assert transient.transient_problem(case, other, reuse=True).settings.duration == 0.5


def test_a_problem_built_under_another_environment_is_not_handed_over(monkeypatch):
    """The linear solver an environment variable forces is chosen as the problem is
    built: a problem built before the variable changed is not the run's."""
    case = load_case(STUDY)
    scene = case.scene("runup")
    monkeypatch.setenv("PYGEAR_LINEAR_SOLVER", "dense_inverse")
    first = transient.transient_problem(case, scene)
    monkeypatch.setenv("PYGEAR_LINEAR_SOLVER", "banded_cholesky")
    run = transient.transient_problem(case, scene, reuse=True)
    assert run is not first and run.solver.linear_solver == "banded_cholesky"
