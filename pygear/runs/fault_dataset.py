"""Labelled fault datasets: a grid of fault severities x operating points x noise seeds,
one record per run, run on Dask, resumable, combined into one NetCDF file with a data card.

A record is a transient of a scene with a sensor: one tooth of one gear carries the
fault at the record's severity, the carrier turns steadily at the record's speed under
the record's torque, and the sensor's measurement noise uses the record's seed.  The
seeds of one (severity, speed, load) share one simulation: noise is added after the run
exactly as :func:`pygear.analysis.condition.sensor_signal.add_noise` adds it during one.  Each
record is written as ``record_<hash>.nc``, named by the hash of everything it depends on
(the modified case and scene, the seed, pygear's sources), so a rerun, or a larger grid
into the same directory, reuses every record already there.  ``dataset_<hash>.nc`` holds
all records on a ``record`` dimension (labels as coordinates, indicators as variables),
and ``dataset_<hash>.md`` is its data card.

Fault kinds (``--faults KIND=VALUES``):

* ``crack_depth``: a root crack at 45 degrees (Tian 2004) whose depth q gives
  q sin(45) = severity x h_b, h_b the tooth's half thickness at its base circle (0: none);
* ``stiffness_factor``: the tooth's pair stiffness times (1 - severity) (1: missing);
* ``chipped_fraction``: the tip chipped off down to severity x the tooth height;
* ``outer_race_depth``, ``inner_race_depth``: a spall of that depth [m] on a race of one
  rolling bearing (``--bearing``, ``--planet``, ``--defect-angle``, ``--defect-width``;
  :mod:`.bearing_faults`), the run with the bearings as Hertz contacts.  The gear
  average and its indicators are still those of ``--gear``.
"""

from __future__ import annotations

import dataclasses
import errno
import hashlib
import json
import math
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from ..errors import CaseError
from ..io import source_identity, write_netcdf
from ..model.case import Case, Scene, load_case, validate_defects
from ..model.case_json import case_json
from ..model.components import ToothDefect
from ..model.gear_geometry import base_half_thickness
from ..model.tooth_faults import ChippedTooth, RootCrack
from ..model.transient_settings import Probe, TorqueLaw
from .bearing_faults import BEARING_FAULT_KINDS, BearingFault, bearing_fault, with_bearing_defect
from .dataset_card import data_card
from .dataset_checks import (
    check_distinct,
    check_footprint,
    check_gear,
    check_record_length,
    record_start,
)
from .dataset_records import (
    INDICATORS,
    combine_records,
    record_dataset,
    trend_figure,
)
from .plan_checks import disk_full
from .progress import ProgressBar

__all__ = ["FAULT_KINDS", "DatasetError", "DatasetPlan", "plan_dataset", "run_dataset"]

FAULT_KINDS = ("crack_depth", "stiffness_factor", "chipped_fraction", *BEARING_FAULT_KINDS)
"""Severity axes a dataset may sweep (module docstring)."""

CRACK_ANGLE_DEG = 45.0
"""Angle of the root crack to the tooth's centre line [deg] (Tian 2004)."""

DATASET_FORMAT = "2"
"""Changes when a record file's content changes meaning (part of every record hash)."""


@dataclass(frozen=True)
class DatasetPlan:
    """A checked dataset request."""

    case: Case
    scene: Scene
    kind: str
    severities: tuple[float, ...]
    speeds: tuple[float, ...]
    loads: tuple[float, ...]
    seeds: tuple[int, ...]
    gear: str
    tooth: int
    sensor: str
    snr_db: float
    duration: float | None
    footprint: tuple = ()
    """What :func:`.dataset_checks.check_footprint` estimates memory and disk from."""
    bearing: BearingFault | None = None
    """The bearing defect's place and width for a bearing fault kind."""


@dataclass(frozen=True)
class RecordTask:
    """One simulation: a (severity, speed, load) and the seeds it serves."""

    case: Case
    scene: Scene
    labels: dict
    seeds: tuple[int, ...]
    hashes: tuple[str, ...]
    paths: tuple[str, ...]
    sensor: str
    snr_db: float
    gear: str


def parse_values(text: str, name: str) -> tuple[float, ...]:
    """``a:b:n`` (n values from a to b) or a comma list."""
    try:
        if ":" in text:
            start, stop, count = text.split(":")
            if int(count) < 1:
                raise ValueError
            values = np.linspace(float(start), float(stop), int(count))
            return tuple(float(f"{v:.12g}") for v in values)  # 0.3, not 0.30000000000000004
        return tuple(float(v) for v in text.split(","))
    except ValueError:
        raise CaseError(
            f"{name} {text!r}: give START:STOP:COUNT (COUNT >= 1) or a comma list of numbers"
        ) from None


def _sensor_scene(case: Case, scene_name: str | None) -> tuple[Scene, str]:
    scenes = [case.scene(scene_name)] if scene_name else list(case.scenes)
    for scene in scenes:
        if scene.transient is None:
            continue
        probes = [p for p in scene.transient.probes if p.quantity == "sensor"]
        if probes:
            return scene, probes[0].target
    where = f"scene {scene_name!r}" if scene_name else f"case {case.name!r}"
    raise CaseError(f"--scene: {where} has no transient with a sensor probe to record")


def plan_dataset(
    case_ref: str | os.PathLike | Case,
    faults: str,
    *,
    speeds: str,
    loads: str,
    seeds: int = 1,
    gear: str | None = None,
    tooth: int = 0,
    scene: str | None = None,
    snr_db: float = 20.0,
    duration: float | None = None,
    workers: int = 2,
    out: str | os.PathLike | None = None,
    bearing: str | None = None,
    planet: int | None = None,
    defect_angle: float = 0.0,
    defect_width: float | None = None,
) -> DatasetPlan:
    """Check a dataset request before any work; raise :class:`CaseError` naming the option.

    Memory is estimated for ``workers`` runs at once, and disk, when ``out`` is given,
    for every record and the combined file (:func:`.dataset_checks.check_footprint`;
    :func:`run_dataset` checks both again with its own workers and directory).
    """
    case = case_ref if isinstance(case_ref, Case) else load_case(case_ref)
    kind, _, values = faults.partition("=")
    if kind not in FAULT_KINDS or not values:
        raise CaseError(
            f"--faults {faults!r}: give KIND=VALUES with KIND one of {', '.join(FAULT_KINDS)}"
        )
    severities = parse_values(values, "--faults")
    check_distinct(f"--faults {kind}", severities)
    if any(not 0.0 <= s < 1.0 for s in severities) and kind == "crack_depth":
        raise CaseError("--faults crack_depth: severities lie in [0, 1) (depth over h_b)")
    if kind not in BEARING_FAULT_KINDS and any(not 0.0 <= s <= 1.0 for s in severities):
        raise CaseError(f"--faults {kind}: severities lie in [0, 1]")
    speed_values = parse_values(speeds, "--speeds")
    load_values = parse_values(loads, "--loads")
    if any(not (math.isfinite(s) and s > 0) for s in speed_values):
        raise CaseError("--speeds: carrier speeds are positive, in rpm")
    if any(not (math.isfinite(v) and v > 0) for v in load_values):
        raise CaseError("--loads: carrier torques are positive, in N m")
    check_distinct("--speeds", speed_values)
    check_distinct("--loads", load_values)
    if isinstance(seeds, bool) or not isinstance(seeds, int) or seeds < 1:
        raise CaseError(f"--seeds must be a whole number >= 1 (got {seeds!r})")
    if not math.isfinite(snr_db):
        raise CaseError(f"--snr must be a finite ratio in dB (got {snr_db!r})")
    if duration is not None and not (math.isfinite(duration) and duration > 0):
        raise CaseError(f"--duration must be a positive time in s (got {duration!r})")
    chosen, sensor = _sensor_scene(case, scene)
    stage = next(s for s in case.sensors if s.name == sensor).stage
    gear = gear or f"{stage}.sun"
    fault = None
    if kind in BEARING_FAULT_KINDS:  # the averaged gear only needs teeth
        fault = bearing_fault(
            case, kind, severities, stage=stage, bearing=bearing, planet=planet,
            angle_deg=defect_angle, width=defect_width,
        )  # fmt: skip
    check_gear(case, stage, gear, "stiffness_factor" if fault else kind)
    check_record_length(duration or chosen.transient.duration, speed_values, duration is not None)
    plan = DatasetPlan(
        case,
        chosen,
        kind,
        severities,
        speed_values,
        load_values,
        range(seeds),  # not a tuple: a million seeds take no memory until they run
        gear,
        int(tooth),
        sensor,
        float(snr_db),
        duration,
        bearing=fault,
    )
    plan = dataclasses.replace(plan, footprint=_footprint(plan))  # tries the grid's corners
    check_footprint(**dict(plan.footprint), workers=workers, out=out)
    # every severity's and every operating point's case and scene, before any run
    for speed in plan.speeds:  # the operating points' whole case and scene
        for load in plan.loads:
            _record_case(plan, {"severity": severities[0], "speed_rpm": speed, "load_nm": load})
    where = f"--gear {plan.gear!r} --tooth {plan.tooth}"
    # the severities' tooth faults alone (they change no more); a bearing's are checked
    for severity in severities[1:] if fault is None else ():
        defect = _defect(plan, case, severity)
        validate_defects(case.gearbox, (defect,) if defect else (), f"{where} --faults {kind}")
    return plan


def _footprint(plan: DatasetPlan) -> tuple:
    """The transient set up (not run) on the corners of the grid, the slowest and the
    fastest speed under the least and the largest load at the largest severity: what
    the kernel refuses there (a load too large for the meshes) is refused before any
    run.  Returns :func:`.dataset_checks.check_footprint`'s inputs."""
    from ..analysis.time.transient import transient_problem
    from .plan_checks import check_drivetrain_memory

    check_drivetrain_memory(plan.case, dense=True, dof_set=plan.scene.dof_set)  # before assembly
    samples = channels = 0
    for speed in sorted({min(plan.speeds), max(plan.speeds)}):
        for load in sorted({min(plan.loads), max(plan.loads)}):
            labels = {"severity": max(plan.severities), "speed_rpm": speed, "load_nm": load}
            case, scene = _record_case(plan, labels)
            problem = transient_problem(case, scene)
            settings = problem.settings
            samples = max(samples, settings.steps // settings.decimation + 1)
            channels = max(channels, len(problem.probes))
    stage = plan.case.gearbox.stage(plan.gear.partition(".")[0])
    ring = stage.gear_teeth("ring") if "ring" in getattr(stage, "member_names", ()) else None
    duration = plan.duration or plan.scene.transient.duration
    averaged = duration - record_start(duration)
    passes = (ring or 0) * max(plan.speeds) / 60.0 * averaged  # fixed ring: Z_r turns
    grid = len(plan.severities) * len(plan.speeds) * len(plan.loads)
    counts = {
        "--faults": len(plan.severities),
        "--speeds": len(plan.speeds),
        "--loads": len(plan.loads),
        "--seeds": len(plan.seeds),
    }
    return (
        ("most", max(counts, key=counts.get)),  # the option the disk check names
        ("records", grid * len(plan.seeds)),
        ("simulations", grid),
        ("samples", samples),
        ("channels", channels),
        ("mesh_passes", float(passes)),
    )


def _grid(plan: DatasetPlan) -> list[dict]:
    return [
        {"severity": s, "speed_rpm": v, "load_nm": t}
        for s in plan.severities
        for v in plan.speeds
        for t in plan.loads
    ]


def _defect(plan: DatasetPlan, case: Case, severity: float) -> ToothDefect | None:
    if severity == 0.0 or plan.bearing is not None:
        return None
    if plan.kind == "stiffness_factor":
        return ToothDefect(plan.gear, plan.tooth, factor=1.0 - severity)
    if plan.kind == "chipped_fraction":
        return ToothDefect(plan.gear, plan.tooth, fault=ChippedTooth(1, severity))
    stage_name, _, member = plan.gear.partition(".")
    stage = case.gearbox.stage(stage_name)
    body = stage.planet if member.startswith("planet") else getattr(stage, member, None)
    if body is None or body.geometry is None or body.geometry.internal:
        raise CaseError(
            f"--faults crack_depth needs an external gear with geometry "
            f"(--gear {plan.gear!r} has none)"
        )
    angle = math.radians(CRACK_ANGLE_DEG)
    depth = severity * base_half_thickness(body.geometry) / math.sin(angle)
    return ToothDefect(plan.gear, plan.tooth, fault=RootCrack(1, depth, CRACK_ANGLE_DEG))


def _angle_probes(case: Case, sensor: str) -> tuple[Probe, ...]:
    stage = case.gearbox.stage(next(s for s in case.sensors if s.name == sensor).stage)
    members = ["carrier", "sun", *(f"planet{n}" for n in range(1, stage.planets + 1))]
    return tuple(Probe("displacement", f"{stage.name}.{m}.theta_z") for m in members)


def _record_case(plan: DatasetPlan, labels: dict) -> tuple[Case, Scene]:
    """The case and scene of one (severity, speed, load), without noise (added per seed)."""
    case = plan.case.for_scene(plan.scene)
    sensors = tuple(
        dataclasses.replace(s, noise_snr_db=None) if s.name == plan.sensor else s
        for s in case.sensors
    )
    case = dataclasses.replace(case, sensors=sensors)
    scene = plan.scene
    if plan.bearing is not None:
        case, scene = with_bearing_defect(case, scene, plan.bearing, labels["severity"])
    transient = plan.scene.transient
    if transient.load is None or transient.load.kind != "generator":
        raise CaseError(
            f"--scene {plan.scene.name!r}: its load must be the generator law, "
            "which --speeds and --loads set to balance the drive"
        )
    load = labels["load_nm"]
    kept = {p.variable for p in transient.probes}
    probes = transient.probes + tuple(
        p for p in _angle_probes(case, plan.sensor) if p.variable not in kept
    )
    transient = dataclasses.replace(
        transient,
        drive=TorqueLaw.constant(load),
        load=dataclasses.replace(transient.load, torque=load),
        speed_reference_rpm=labels["speed_rpm"],
        initial_speed_rpm=labels["speed_rpm"],
        probes=probes,
        duration=plan.duration or transient.duration,
        mean_window=min(transient.mean_window, plan.duration or transient.duration),
    )
    defect = _defect(plan, case, labels["severity"])
    defects = tuple(d for d in plan.scene.defects if (d.gear, d.tooth) != (plan.gear, plan.tooth))
    scene = dataclasses.replace(
        scene,
        transient=transient,
        defects=defects + ((defect,) if defect else ()),
        parameters=(),
    )
    scene.validate(f"scenes.{scene.name}")
    validate_defects(case.gearbox, scene.defects, f"--gear {plan.gear!r} --tooth {plan.tooth}")
    return case, scene


def record_hash(case: Case, scene: Scene, seed: int, plan: DatasetPlan) -> str:
    """Hash of one record's inputs: the modified case and scene, the seed and noise, the
    averaged gear, pygear's sources and the record format."""
    text = "\n".join(
        [
            repr(case),
            repr(scene),
            str(seed),
            repr(plan.snr_db),
            plan.sensor,
            plan.gear,
            str(plan.tooth),
            plan.kind,
            DATASET_FORMAT,
            source_identity(),
        ]
    )
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _record_path(out: Path, digest: str) -> Path:
    return out / f"record_{digest}.nc"


def _sound(path: Path, digest: str) -> bool:
    """True when ``path`` is a complete record of ``digest`` (written atomically)."""
    try:
        with xr.open_dataset(path) as data:
            return data.attrs.get("record_hash") == digest
    except (OSError, ValueError):
        return False


def _tasks(plan: DatasetPlan, out: Path) -> tuple[list[RecordTask], list[str], int]:
    """The simulations still needed, every record's hash in grid order, and the count
    of records found complete."""
    tasks, hashes, found = [], [], 0
    for labels in _grid(plan):
        case, scene = _record_case(plan, labels)
        digests = [record_hash(case, scene, seed, plan) for seed in plan.seeds]
        hashes += digests
        missing = [
            (seed, d) for seed, d in zip(plan.seeds, digests) if not _sound(_record_path(out, d), d)
        ]
        found += len(plan.seeds) - len(missing)
        if missing:
            where = (
                {"fault_gear": plan.gear, "fault_tooth": plan.tooth}
                if plan.bearing is None
                else plan.bearing.labels()
            )
            labels = {**labels, "fault_kind": plan.kind, **where, "snr_db": plan.snr_db}
            tasks.append(
                RecordTask(
                    case,
                    scene,
                    labels,
                    tuple(s for s, _ in missing),
                    tuple(d for _, d in missing),
                    tuple(str(_record_path(out, d)) for _, d in missing),
                    plan.sensor,
                    plan.snr_db,
                    plan.gear,
                )
            )
    return tasks, hashes, found


def run_record_task(task: RecordTask) -> list[dict]:
    """Simulate one (severity, speed, load) and write a record per seed; never raises."""
    from ..analysis.time.transient import run_transient
    from ..io import atomic_path
    from .cluster import task_files

    started = time.perf_counter()
    path = task.paths[0]
    try:
        run = run_transient(task.case, task.scene)
        record_case_json = case_json(task.case)
        for seed, digest, path in zip(task.seeds, task.hashes, task.paths):
            record = record_dataset(task, run, seed, digest)
            with task_files():  # HDF5 is not thread-safe: one writer per worker process
                write_netcdf(
                    record,
                    path,
                    title=f"Fault record {digest} of {task.case.name}",
                    input_hash=digest,
                    case_json=record_case_json,
                )
            Path(path).with_suffix(".error.json").unlink(missing_ok=True)
        wall = time.perf_counter() - started
        return [{"hash": d, "status": "computed", "wall_s": wall} for d in task.hashes]
    except Exception as error:  # noqa: BLE001 - one record's failure must not stop the rest
        if disk_full(error):  # the dataset stops: no other record can be written either
            failed = {"status": "failed", "error": f"no space left on device writing {path}"}
            return [{"hash": d, **failed, "disk_full": 1} for d in task.hashes]
        message = str(error) if isinstance(error, CaseError) else f"{type(error).__name__}: {error}"
        for path in task.paths:
            target = Path(path).with_suffix(".error.json")
            try:
                with atomic_path(target) as temporary:
                    Path(temporary).write_text(
                        json.dumps({"labels": task.labels, "error": message})
                    )
            except OSError as written:
                if not disk_full(written):
                    raise
                failed = {"status": "failed", "error": f"no space left on device writing {target}"}
                return [{"hash": d, **failed, "disk_full": 1} for d in task.hashes]
        return [{"hash": d, "status": "failed", "error": message} for d in task.hashes]


def run_dataset(
    plan: DatasetPlan,
    out_dir: str | os.PathLike,
    *,
    workers: int = 2,
    scheduler: str | None = None,
    progress: bool = True,
    figures: bool = True,
) -> xr.Dataset:
    """Run every record of ``plan`` still missing in ``out_dir`` on Dask and combine all.

    Returns
    -------
    xarray.Dataset
        Every record on ``record`` (labels as coordinates), with attributes
        ``records``, ``records_computed``, ``records_reused``, ``records_failed`` and
        ``path`` (the combined file; the data card beside it has the suffix ``.md``).
    """
    from .cluster import dask_client, validate_cluster_options
    from .plan_checks import check_out_dir

    started = time.perf_counter()
    out = Path(out_dir)
    check_out_dir("--out", out, "a dataset")
    validate_cluster_options(workers, scheduler)
    if plan.footprint:
        check_footprint(**dict(plan.footprint), workers=workers, out=out)
    out.mkdir(parents=True, exist_ok=True)
    tasks, hashes, found = _tasks(plan, out)
    bar = ProgressBar(f"dataset {plan.case.name}", enabled=progress)
    outcome: dict[str, dict] = {}
    done = found
    if tasks:
        bar(done, len(hashes))
        with dask_client(workers=workers, scheduler=scheduler) as client:
            from distributed import as_completed

            futures = client.map(run_record_task, tasks, pure=False)
            for future in as_completed(futures, loop=client.loop):
                records = future.result()
                full = next((r for r in records if r.get("disk_full")), None)
                if full is not None:
                    raise OSError(errno.ENOSPC, _disk_full_message(full, plan, len(outcome)))
                for record in records:
                    outcome[record["hash"]] = record
                done += len(records)
                bar(done, len(hashes))
    failed = [r for r in outcome.values() if r["status"] == "failed"]
    complete = [h for h in hashes if h not in {r["hash"] for r in failed}]
    if not complete:  # no record: no dataset, no card (the error records say why)
        raise DatasetError(
            f"every one of the {len(hashes)} records failed, so no dataset was written; "
            f"the first: {failed[0]['error'] if failed else 'unknown'}"
        )
    combined = combine_records([_record_path(out, h) for h in complete])
    digest = hashlib.sha256(" ".join(hashes).encode()).hexdigest()[:16]
    combined.attrs.update(
        case=plan.case.name,
        scene=plan.scene.name,
        fault_kind=plan.kind,
        gear=plan.gear,
        tooth=plan.tooth,
        sensor=plan.sensor,
        snr_db=plan.snr_db,
        records=len(hashes),
        records_computed=sum(r["status"] == "computed" for r in outcome.values()),
        records_reused=found,
        records_failed=len(failed),
    )
    path = write_netcdf(
        combined,
        out / f"dataset_{digest}.nc",
        title=f"Fault dataset of {plan.case.name}: {plan.kind} on {plan.gear} tooth {plan.tooth}",
        input_hash=digest,
        case_json=case_json(plan.case.for_scene(plan.scene)),
    )
    card = out / f"dataset_{digest}.md"
    from ..io import atomic_path

    with atomic_path(card) as temporary:
        Path(temporary).write_text(data_card(plan, combined, path.name, INDICATORS))
    combined.attrs["path"] = str(path)
    if figures and combined.sizes.get("record", 0):
        trend_figure(combined, out / f"dataset_{digest}_trends.png", plan)
    combined.attrs["wall_s"] = time.perf_counter() - started
    if progress:
        print(
            f"dataset {plan.case.name}: {len(hashes)} records "
            f"({combined.attrs['records_computed']} computed, {found} reused, "
            f"{len(failed)} failed) -> {path}",
            file=sys.stderr,
        )
        for record in failed:
            print(f"  failed: {record['error']}", file=sys.stderr)
    return combined


class DatasetError(RuntimeError):
    """Every record of a dataset failed (exit code 1: the input was sound)."""


def _disk_full_message(record: dict, plan: DatasetPlan, written: int) -> str:
    """One line: the file that did not fit and what the rest of the plan needs."""
    from ..resources import format_bytes
    from .dataset_checks import RECORD_OVERHEAD

    footprint = dict(plan.footprint)
    size = RECORD_OVERHEAD + 3.0 * footprint.get("samples", 0) * 8
    left = max(footprint.get("records", 0) - written, 1)
    return (
        f"{record['error']} (a record takes about {format_bytes(size)}; the {left:,} records "
        f"left and the combined dataset need about {format_bytes(2 * left * size)}); "
        "no partial file is left"
    )
