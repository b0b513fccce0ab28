"""The accuracy study run: every column of the ladder of
:mod:`pygear.analysis.time.accuracy`, in this process or on a local Dask cluster; for a
response scene, the frequency-domain rung (:func:`harmonics_study`: harmonic count
against error and wall time, :mod:`pygear.analysis.response.harmonics`)."""

from __future__ import annotations

import time
from collections.abc import Callable

import xarray as xr

from ..analysis.time.accuracy import (
    AccuracyStudy,
    accuracy_grid,
    fidelity_ladder,
    run_column,
)
from ..errors import CaseError
from ..model.case import FORMULATIONS, Case, Scene

__all__ = ["accuracy_study", "harmonics_study"]


def accuracy_study(
    case: Case,
    scene: Scene,
    study: AccuracyStudy | None = None,
    *,
    workers: int = 1,
    progress: Callable[[int, int], None] | None = None,
) -> xr.Dataset:
    """Run the ladder of ``scene`` and return the grid (formulation x fidelity x dt x metric).

    Parameters
    ----------
    case, scene : Case, Scene
        The case (as the scene sees it) and a scene with a ``transient`` analysis.
    study : AccuracyStudy, optional
        Settings (default :class:`AccuracyStudy()`).
    workers : int
        1 runs everything in this process; more run the (formulation, fidelity)
        columns on a local Dask cluster of that many single-threaded workers.
    progress : callable, optional
        ``progress(done, total)`` after every column.

    Raises
    ------
    CaseError
        A bad setting, or a scene without transient settings.
    """
    study = study or AccuracyStudy()
    study.validate()
    if scene.transient is None:
        raise CaseError(f"--scene {scene.name!r} has no transient settings to study")
    case = case.for_scene(scene)
    base = scene.transient
    coarsest = study.coarsest_time_step or 8 * base.time_step
    steps = [coarsest / 2**k for k in range(study.levels)]
    rate = study.sample_rate or 1.0 / coarsest
    formulations = study.formulations or tuple(
        f for f in FORMULATIONS if f != "lin-parker" or len(case.gearbox.stages) == 1
    )
    ladder = fidelity_ladder(case, scene, study)
    duration = study.duration or base.duration
    window = study.mean_window or base.mean_window
    if window >= duration:
        raise CaseError(f"accuracy.mean_window {window:g} s must be shorter than {duration:g} s")
    ladder[-1].scene(scene, steps[-1], study, rate).validate("accuracy")  # refuse early
    tasks = [(case, scene, fid, f, steps, study, rate) for f in formulations for fid in ladder]
    started = time.perf_counter()
    columns = _run_columns(tasks, workers, progress)
    wall_total = time.perf_counter() - started
    results = {(t[3], t[2]): column for t, column in zip(tasks, columns)}
    dataset = accuracy_grid(case, scene, study, formulations, ladder, steps, results)
    dataset.attrs.update(
        {
            "duration": duration,
            "mean_window": window,
            "sample_rate": rate,
            "study_wall_s": wall_total,
            "workers": workers,
            "study_note": (
                f"every run lasts {duration:g} s (the scene's {base.duration:g} s shortened "
                f"for the study), equilibrium values and mesh-force statistics over the last "
                f"{window:g} s, spectra after {study.signal_after:g} s, all sampled at "
                f"{rate:g} Hz"
            ),
        }
    )
    return dataset


def _run_columns(tasks: list, workers: int, progress) -> list[list[dict]]:
    if workers <= 1:
        columns = []
        for done, task in enumerate(tasks, start=1):
            columns.append(run_column(task))
            if progress is not None:
                progress(done, len(tasks))
        return columns
    from .cluster import dask_client  # Dask loads only when asked for

    with dask_client(workers=workers) as client:
        futures = client.map(run_column, tasks, pure=False)
        from distributed import as_completed

        for done, _ in enumerate(as_completed(futures, loop=client.loop), start=1):
            if progress is not None:
                progress(done, len(tasks))
        return client.gather(futures)


def harmonics_study(case: Case, scene: Scene, tolerance: float, levels: int = 7) -> xr.Dataset:
    """The frequency-domain rung of a response scene: its speeds balanced at H = 2, 4,
    ..., 2^levels and at 2^(levels + 1) as the reference, judged at ``tolerance``
    (:func:`pygear.analysis.response.harmonics.recommend_harmonics`).

    Parameters
    ----------
    case : Case
        The case as loaded (the scene's parameter changes are applied here).
    scene : Scene
        A scene with ``response`` settings (speeds, torque, pin errors).
    tolerance : float
        Accepted mesh-force error, a fraction of the largest mesh force.
    levels : int
        Counts in the ladder, 1-9.

    Raises
    ------
    CaseError
        A scene without response settings, or ``levels`` out of range.
    """
    from ..analysis.response import response_system
    from ..analysis.response.harmonics import harmonics_ladder, recommend_harmonics

    if scene.response is None:
        raise CaseError(f"--scene {scene.name!r} has no response settings to study")
    if not (isinstance(levels, int) and 1 <= levels <= 9):
        raise CaseError(f"--levels must be a whole number 1-9 for a response scene "
                        f"(got {levels!r})")  # fmt: skip
    settings = scene.response
    system = response_system(case, scene, pin_errors=dict(settings.pin_errors) or None,
                             torque=settings.torque)  # fmt: skip
    counts = tuple(2**k for k in range(1, levels + 1))
    ladder = harmonics_ladder(system, settings.speeds, counts)
    return recommend_harmonics(ladder, tolerance)
