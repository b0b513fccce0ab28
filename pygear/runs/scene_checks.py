"""Checks of every scene of a run before the first one starts."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

from ..analysis.time.transient import transient_problem
from ..analysis.time.transient_checks import FOOTPRINT_HINT, signal_footprint, transient_footprint
from ..assembly.drivetrain_model import scene_model
from ..model.case import Case, Scene
from ..resources import require_disk

__all__ = ["check_scenes"]


def check_scenes(
    case: Case,
    scenes: Sequence[Scene],
    *,
    formulation: str | None = None,
    out: str | os.PathLike | None = None,
) -> dict[str, float]:
    """Every check of every scene that needs the assembled model, before any runs.

    Each scene's model is assembled and each transient set up (probe targets, members,
    contact signs, static deflections, memory); the result files of all transient
    scenes together, with their signal analyses, must fit on the disk of ``out`` (counted
    uncompressed: an upper bound of the compressed files).

    Returns
    -------
    dict
        Each transient scene's result files [bytes], uncompressed: what the run will
        write at most, known before it starts.

    Raises
    ------
    CaseError
        Naming the scene's parameter and the rule, for the first scene that fails.
    """
    files, counted, sizes = 0.0, [], {}
    from ..model.rotor_transient import RotorScene

    for scene in scenes:
        if isinstance(scene, RotorScene):  # its model and integrator set up, not run
            from ..analysis.time.rotor_transient import rotor_transient_problem

            rotor_transient_problem(case, scene)
            continue
        scene_case = case.for_scene(scene)
        model = scene_model(scene_case, scene, formulation=formulation)
        if "transient" not in scene.analyses or scene.transient is None:
            continue
        # a run too long to hold twice in memory streams to its file: write_transient
        # checks the memory of the path it takes
        problem = transient_problem(
            scene_case, scene, formulation=formulation, model=model, check_memory=False
        )
        _, disk, what = transient_footprint(problem.settings, len(problem.probes))
        if "signal" in scene.analyses:
            spectra, spectra_what = signal_footprint(problem.settings)
            disk += spectra
            what = f"{what} and {spectra_what}"
        files += disk
        sizes[scene.name] = disk
        counted.append(f"{scene.name}: {what}, uncompressed")
    if out is not None and files:
        hint = FOOTPRINT_HINT
        if len(counted) > 1:
            hint = f"run fewer scenes (--scene) or {FOOTPRINT_HINT}"
        first = next(s for s in scenes if "transient" in s.analyses and s.transient is not None)
        require_disk(
            f"scenes.{first.name}.transient.duration" if len(counted) == 1 else "scenes",
            files,
            Path(out),
            "; ".join(counted) if len(counted) < 4 else f"{len(counted)} transient scenes",
            hint,
        )
    return sizes
