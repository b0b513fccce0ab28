"""Checks of transient runs before any of them starts.

What the settings alone cannot tell needs the assembled model: a mesh so soft that its
static deflection under the drive torque already exceeds the run's deflection limit
(the run would stop as "diverged" for no numerical reason), and a record larger than
the machine's memory or disk.  :func:`pygear.runs.scene_checks.check_scenes` runs
every check of every scene a command will run, so a bad later scene is refused before
the first one starts.
"""

from __future__ import annotations

import os
import re

import numpy as np

from ...assembly.matrices import Model
from ...errors import CaseError
from ...kernel.newmark_support import TransientError
from ...model.transient_settings import TorqueLaw, Transient
from ...resources import FLOAT_BYTES, require_disk, require_memory

__all__ = [
    "FOOTPRINT_HINT",
    "SOFT_MESH_SHARE",
    "check_static_deflection",
    "check_transient_disk",
    "check_transient_memory",
    "mesh_stiffness_parameter",
    "peak_torque",
    "signal_footprint",
    "transient_footprint",
    "with_soft_mesh_cause",
]

SOFT_MESH_SHARE = 0.5
"""A run that stops at the deflection limit is blamed on a soft mesh, not on the
integrator, when the static deflection under the drive torque is at least this share
of the limit: a suddenly applied load overshoots its static deflection by up to a
factor of two (an undamped step response), which then reaches the limit."""


def peak_torque(law: TorqueLaw | None) -> float:
    """The largest magnitude of torque a law applies [N m] (0 without a law; the rated
    drive torque T_D of the generator law, which its load reaches at equilibrium)."""
    if law is None:
        return 0.0
    if law.kind == "table":
        return max(abs(t) for t in law.torques)
    return abs(law.torque)


def mesh_stiffness_parameter(mesh) -> str:
    """The case parameter of a model mesh's stiffness (``planetary.sun_mesh.stiffness``)."""
    member = {"sun": "sun_mesh", "ring": "ring_mesh"}.get(mesh.name.split("-", 1)[0], "mesh")
    return f"{mesh.stage}.{member}.stiffness"


def check_static_deflection(
    model: Model, settings: Transient, deflection_per_torque: np.ndarray, path: str
) -> np.ndarray:
    """Refuse a run whose static mesh deflection under the drive reaches its limit.

    Parameters
    ----------
    model : Model
        The assembled model.
    settings : Transient
        The run's settings (drive and ``deflection_limit``).
    deflection_per_torque : ndarray, shape (n_mesh,)
        Static mesh deflections under 1 N m of drive [m/(N m)]
        (:func:`pygear.analysis.time.transient.static_mesh_deflections`).
    path : str
        Parameter path of the settings.

    Returns
    -------
    ndarray, shape (n_mesh,)
        The size of each mesh's static deflection under the peak drive torque [m].

    Raises
    ------
    CaseError
        The static deflection of a mesh exceeds ``deflection_limit``.
    """
    deflections = np.abs(np.asarray(deflection_per_torque, dtype=float))
    deflections *= peak_torque(settings.drive)
    if not deflections.size or not deflections.max() > settings.deflection_limit:
        return deflections
    worst = int(np.argmax(deflections))
    mesh = model.meshes[worst]
    raise CaseError(
        f"{path}.deflection_limit: under the peak drive torque of "
        f"{peak_torque(settings.drive):g} N m the static deflection of mesh "
        f"{mesh.stage}.{mesh.name} is {deflections[worst] * 1e3:.3g} mm, beyond "
        f"deflection_limit = {settings.deflection_limit * 1e3:.3g} mm, so the run would stop as "
        f"diverged: the mesh is too soft for this torque ({mesh_stiffness_parameter(mesh)} = "
        f"{mesh.mean_stiffness:.3g} N/m) or the limit is too tight"
    )


def with_soft_mesh_cause(
    error: TransientError, model: Model, static: np.ndarray, settings: Transient
) -> TransientError:
    """``error`` with its likely cause replaced by a soft mesh when the run stopped at the
    deflection limit and the static deflection of that mesh under the drive torque
    (``static``, per mesh [m]) is at least :data:`SOFT_MESH_SHARE` of the limit."""
    limit = settings.deflection_limit
    found = re.search(r"the deflection of mesh (\S+) exceeds deflection_limit", str(error))
    # a growth diagnostic (PhysicalInstabilityError) included: a suddenly loaded soft
    # mesh rings up within a few periods, which looks like growth but is its overshoot
    if not isinstance(error, TransientError) or found is None or not len(static):
        return error
    # the kernel names meshes without their stage: take the softest of that name
    candidates = [m for m, mesh in enumerate(model.meshes) if mesh.name == found.group(1)]
    if not candidates:
        return error
    worst = max(candidates, key=lambda m: static[m])
    mesh, deflection = model.meshes[worst], float(static[worst])
    if deflection < SOFT_MESH_SHARE * limit:
        return error
    stopped = str(error).split("; likely cause", 1)[0]
    return TransientError(
        f"{stopped}; likely cause: a soft mesh, not the integrator: the static deflection "
        f"of mesh {mesh.stage}.{mesh.name} under the drive torque is already "
        f"{deflection * 1e3:.3g} mm ({deflection / limit:.0%} of deflection_limit = "
        f"{limit * 1e3:.3g} mm) and the dynamic response overshoots it; raise "
        f"{mesh_stiffness_parameter(mesh)} or deflection_limit"
    )


def transient_footprint(settings: Transient, channels: int) -> tuple[float, float, str]:
    """Memory and disk of a run's record [bytes], and how they are counted.

    The kernel records ``channels`` float64 channels at every output sample; the dataset
    built from the record and written to NetCDF holds them again (memory: twice), and
    the file holds them once with the time coordinate.  The file's channels are
    compressed (:data:`pygear.io.COMPRESSION_LEVEL`), by a ratio no one can know before
    the run (0.67 on the study case's run-up, nearly 1 for noise), so the disk figure
    is their uncompressed size: an upper bound.
    """
    samples = settings.steps // settings.decimation + 1
    record = max(channels, 1) * samples * FLOAT_BYTES
    what = f"{max(channels, 1)} channels x {samples} samples x {FLOAT_BYTES} bytes"
    return 2.0 * record, float(record + samples * FLOAT_BYTES), what


def signal_footprint(settings: Transient) -> tuple[float, str]:
    """Disk of a run's signal analysis files [bytes], an upper bound, and how it is counted.

    The ``signal`` analysis writes one file per acceleration probe: the frequency
    coordinate and three spectra (amplitude, envelope, DRA) of at most
    ``samples // 2 + 1`` lines each (the start-up it skips makes them shorter), float64
    and counted uncompressed.
    """
    channels = sum(probe.quantity == "acceleration" for probe in settings.probes)
    lines = (settings.steps // settings.decimation + 1) // 2 + 1
    what = f"{channels} spectra files x 4 x {lines} lines x {FLOAT_BYTES} bytes"
    return float(channels * 4 * lines * FLOAT_BYTES), what


FOOTPRINT_HINT = "shorten duration, lower sample_rate or keep fewer probes"
"""What to change when a record does not fit in memory or on disk."""


def check_transient_memory(settings: Transient, channels: int, path: str) -> None:
    """Refuse a run whose record does not fit in the memory available."""
    memory, _, what = transient_footprint(settings, channels)
    require_memory(f"{path}.duration", memory, f"{what}, held twice", FOOTPRINT_HINT)


def check_transient_disk(
    settings: Transient, channels: int, directory: str | os.PathLike, path: str
) -> None:
    """Refuse a run whose result file does not fit on the disk of ``directory``."""
    _, disk, what = transient_footprint(settings, channels)
    require_disk(f"{path}.duration", disk, directory, f"{what}, uncompressed", FOOTPRINT_HINT)
