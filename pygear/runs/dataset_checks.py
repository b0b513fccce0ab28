"""Checks of a fault dataset's plan before any record runs (:mod:`.fault_dataset`).

Everything a record would refuse on a Dask worker is refused here, in one line naming
the option, with exit code 2 and before a cluster starts: a gear that cannot carry the
fault, repeated values, a record too short for one carrier revolution, operating
points the transient refuses (tried on the corners of the grid), and a plan whose
memory (per worker) or disk (all records and the combined file) would not fit.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence

from ..errors import CaseError
from ..resources import FLOAT_BYTES, format_bytes, require_disk, require_memory

__all__ = [
    "RECORD_OVERHEAD",
    "check_distinct",
    "check_footprint",
    "check_gear",
    "check_record_length",
    "fault_gears",
    "record_start",
]

RECORD_OVERHEAD = 100_000
"""Bytes of a record file beyond its time series: NetCDF4/HDF5 metadata, the case as
JSON, the gear average and the indicators."""

SAMPLES_PER_TOOTH = 32
"""Angle steps a tooth period of the gear average (its default)."""

AVERAGE_COPIES = 3
"""Arrays of the resampled signal the gear average holds at once (angle grid, values,
the revolutions' stack)."""


def record_start(duration: float) -> float:
    """The start-up a record's average skips [s]: a quarter of the run, at most 0.5 s."""
    return min(0.5, 0.25 * duration)


def fault_gears(case, stage_name: str, kind: str) -> list[str]:
    """The gears of the sensor's stage that can carry a fault of ``kind``: the sun, the
    ring and the planets with a tooth number, and for ``crack_depth`` only the
    external ones with a geometry (a root crack is placed on the tooth's profile)."""
    stage = case.gearbox.stage(stage_name)
    gears = []
    for member in getattr(stage, "member_names", ()):
        if member == "carrier":
            continue
        try:
            teeth = stage.gear_teeth(member)
        except (KeyError, AttributeError):
            continue
        if teeth is None:
            continue
        if kind == "crack_depth":
            body = stage.planet if member.startswith("planet") else getattr(stage, member, None)
            geometry = getattr(body, "geometry", None)
            if geometry is None or geometry.internal:
                continue
        gears.append(f"{stage.name}.{member}")
    return gears


def check_gear(case, stage_name: str, gear: str, kind: str) -> None:
    """Refuse a ``--gear`` that is not one of :func:`fault_gears`."""
    gears = fault_gears(case, stage_name, kind)
    if gear in gears:
        return
    if not gears:
        raise CaseError(
            f"--gear {gear!r}: no gear of stage {stage_name!r} (the sensor's) can carry a "
            f"{kind} fault"
        )
    which = "external gears with a geometry" if kind == "crack_depth" else "gears with teeth"
    raise CaseError(
        f"--gear {gear!r} cannot carry a {kind} fault; the {which} of the sensor's stage "
        f"can: {', '.join(gears)}"
    )


def check_distinct(option: str, values: Sequence[float]) -> None:
    """Refuse a value given twice: its records would be the same records twice."""
    seen = set()
    for value in values:
        if value in seen:
            raise CaseError(
                f"{option}: {value:g} is given twice ({', '.join(f'{v:g}' for v in values)}); "
                "each value makes its own records"
            )
        seen.add(value)


def check_record_length(duration: float, speeds: Sequence[float], given: bool) -> None:
    """Refuse a run whose averaged part is shorter than one carrier revolution at the
    slowest speed: the gear average would hold less than one revolution."""
    slowest = min(speeds)
    revolution = 60.0 / slowest
    averaged = duration - record_start(duration)
    if averaged >= revolution:
        return
    needed = revolution / 0.75 if revolution / 0.75 <= 2.0 else revolution + 0.5
    option = "--duration" if given else "--duration (the scene's transient.duration)"
    raise CaseError(
        f"{option} {duration:g} s: a record averages {averaged:g} s after its start-up, "
        f"less than one carrier revolution at {slowest:g} rpm ({revolution:g} s); give "
        f"--duration {needed:.4g} or more, or faster --speeds"
    )


def check_footprint(
    *,
    records: int,
    simulations: int,
    samples: int,
    channels: int,
    mesh_passes: float,
    workers: int,
    out: str | os.PathLike | None = None,
    most: str = "--seeds",
) -> None:
    """Refuse a plan whose memory or disk would not fit, with the estimate.

    Parameters
    ----------
    records, simulations : int
        Records of the plan (every seed) and the runs that make them.
    samples, channels : int
        Output samples and recorded channels of the longest run.
    mesh_passes : float
        Tooth passes in the averaged part of the fastest run: the gear average
        resamples the sensor to :data:`SAMPLES_PER_TOOTH` steps a pass.
    workers : int
        Runs held in memory at once (one a worker).
    out : path, optional
        The dataset's directory; its disk is checked when given.
    most : str
        The option with the most values, which the disk check names.
    """
    run = 2.0 * channels * samples * FLOAT_BYTES  # the kernel's record and its dataset
    average = AVERAGE_COPIES * mesh_passes * SAMPLES_PER_TOOTH * FLOAT_BYTES
    at_once = max(1, min(workers, simulations))
    if math.isfinite(average) and average > run:
        parameter, hint = "--speeds", "lower --speeds or shorten --duration"
    else:
        parameter, hint = "--duration", "shorten --duration"
    require_memory(
        parameter,
        at_once * (run + average),
        f"{at_once} run{'s' if at_once > 1 else ''} at once, each {format_bytes(run)} for "
        f"{channels} channels x {samples:,} samples and {format_bytes(average)} for the "
        f"gear average over {mesh_passes:.3g} tooth passes",
        hint,
    )
    if out is None:
        return
    record = RECORD_OVERHEAD + 3.0 * samples * FLOAT_BYTES  # sensor, tachometer, time
    require_disk(
        most,
        2.0 * records * record,
        out,
        f"{records:,} records of about {format_bytes(record)} each and the combined "
        "dataset, uncompressed",
        "fewer severities, speeds, loads or seeds, or a shorter --duration",
    )
