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
* ``chipped_fraction``: the tip chipped off down to severity x the tooth height.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from ..errors import CaseError
from ..io import index_labels, source_identity, write_netcdf
from ..model.case import Case, Scene, load_case, validate_defects
from ..model.case_json import case_json
from ..model.components import ToothDefect
from ..model.gear_geometry import base_half_thickness
from ..model.tooth_faults import ChippedTooth, RootCrack
from ..model.transient_settings import Probe, TorqueLaw
from .dataset_card import data_card
from .progress import ProgressBar

__all__ = ["FAULT_KINDS", "DatasetPlan", "plan_dataset", "run_dataset"]

FAULT_KINDS = ("crack_depth", "stiffness_factor", "chipped_fraction")
"""Severity axes a dataset may sweep (module docstring)."""

CRACK_ANGLE_DEG = 45.0
"""Angle of the root crack to the tooth's centre line [deg] (Tian 2004)."""

DATASET_FORMAT = "2"
"""Changes when a record file's content changes meaning (part of every record hash)."""

LABEL_ATTRS = {
    "fault_kind": {"long_name": "kind of tooth fault"},
    "fault_gear": {"long_name": "gear with the damaged tooth (stage.member)"},
    "fault_tooth": {"units": "1", "long_name": "damaged tooth number"},
    "severity": {"units": "1", "long_name": "fault severity (its kind's own measure)"},
    "speed_rpm": {"units": "rpm", "long_name": "carrier speed"},
    "load_nm": {"units": "N m", "long_name": "carrier torque"},
    "snr_db": {"units": "1", "long_name": "signal-to-noise ratio of the sensor noise in dB"},
    "seed": {"units": "1", "long_name": "seed of the sensor noise"},
}
"""CF attributes of a record's labels (coordinates along ``record`` in the dataset)."""

RECORD_SENSOR = "sensor_acceleration"
"""A record's noisy sensor series over ``time`` (its attributes: the sensor's settings)."""

INDICATORS = (
    "fm0",
    "fm4",
    "na4",
    "nb4",
    "m6a",
    "m8a",
    "energy_ratio",
    "sideband_level_factor",
    "kurtosis",
    "crest_factor",
    "rms",
)


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
) -> DatasetPlan:
    """Check a dataset request before any work; raise :class:`CaseError` naming the option."""
    case = case_ref if isinstance(case_ref, Case) else load_case(case_ref)
    kind, _, values = faults.partition("=")
    if kind not in FAULT_KINDS or not values:
        raise CaseError(
            f"--faults {faults!r}: give KIND=VALUES with KIND one of {', '.join(FAULT_KINDS)}"
        )
    severities = parse_values(values, "--faults")
    if any(not 0.0 <= s < 1.0 for s in severities) and kind == "crack_depth":
        raise CaseError("--faults crack_depth: severities lie in [0, 1) (depth over h_b)")
    if any(not 0.0 <= s <= 1.0 for s in severities):
        raise CaseError(f"--faults {kind}: severities lie in [0, 1]")
    speed_values = parse_values(speeds, "--speeds")
    load_values = parse_values(loads, "--loads")
    if any(not (math.isfinite(s) and s > 0) for s in speed_values):
        raise CaseError("--speeds: carrier speeds are positive, in rpm")
    if any(not (math.isfinite(v) and v > 0) for v in load_values):
        raise CaseError("--loads: carrier torques are positive, in N m")
    if isinstance(seeds, bool) or not isinstance(seeds, int) or seeds < 1:
        raise CaseError(f"--seeds must be a whole number >= 1 (got {seeds!r})")
    if not math.isfinite(snr_db):
        raise CaseError(f"--snr must be a finite ratio in dB (got {snr_db!r})")
    chosen, sensor = _sensor_scene(case, scene)
    stage = next(s for s in case.sensors if s.name == sensor).stage
    gear = gear or f"{stage}.sun"
    plan = DatasetPlan(
        case,
        chosen,
        kind,
        severities,
        speed_values,
        load_values,
        tuple(range(seeds)),
        gear,
        int(tooth),
        sensor,
        float(snr_db),
        duration,
    )
    for labels in _grid(plan):  # every record's case and scene, checked before any run
        _record_case(plan, labels)
    return plan


def _grid(plan: DatasetPlan) -> list[dict]:
    return [
        {"severity": s, "speed_rpm": v, "load_nm": t}
        for s in plan.severities
        for v in plan.speeds
        for t in plan.loads
    ]


def _defect(plan: DatasetPlan, case: Case, severity: float) -> ToothDefect | None:
    if severity == 0.0:
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
        plan.scene,
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
            labels = {
                **labels,
                "fault_kind": plan.kind,
                "fault_gear": plan.gear,
                "fault_tooth": plan.tooth,
                "snr_db": plan.snr_db,
            }
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


def _sensor_channel(scene: Scene, sensor: str) -> str:
    """The channel name of the sensor's probe (:mod:`pygear.analysis.signals.channels`)."""
    probe = next(
        p for p in scene.transient.probes if p.quantity == "sensor" and p.target == sensor
    )
    return probe.name or f"sensor_acceleration:{sensor}"


def _record(task: RecordTask, run: xr.Dataset, seed: int, digest: str) -> xr.Dataset:
    """One record: the noisy sensor channel, the tachometer, the gear's average, the
    indicators and the labels."""
    from ..analysis.condition.gear_average import gear_average, gear_indicator_values, member_angle
    from ..analysis.condition.sensor_signal import add_noise
    from ..analysis.condition.synchronous_average import synthetic_tachometer
    from ..analysis.signals.channels import channel_series

    channel = _sensor_channel(task.scene, task.sensor)
    clean = channel_series(run, channel)
    noisy = clean.copy(data=add_noise(clean.values, task.snr_db, seed)).rename(RECORD_SENSOR)
    noisy.attrs.update(
        sensor_noise_snr_db=task.snr_db, sensor_noise_seed=seed, channel=RECORD_SENSOR
    )
    stage = task.gear.partition(".")[0]
    carrier = member_angle(run, stage, "carrier")
    view = run.assign({RECORD_SENSOR: noisy})
    start = float(run.time[0]) + min(0.5, 0.25 * float(run.time[-1] - run.time[0]))
    average = gear_average(view.sel(time=slice(start, None)), task.gear, RECORD_SENSOR)
    indicators = gear_indicator_values(average)
    pulses = synthetic_tachometer(run.time.values, carrier.values, 1)
    data = xr.Dataset(
        {
            RECORD_SENSOR: noisy,
            "tachometer_angle": carrier.assign_attrs(
                long_name="carrier angle (the tachometer's shaft)", units="rad"
            ),
            "tachometer_pulse_time": (
                ("pulse",),
                pulses,
                {"units": "s", "long_name": "once-per-turn pulses of the carrier"},
            ),
            "gear_average": average.rename(angle="angle_step").drop_vars(
                "weight_sum", errors="ignore"
            ),
        },
        coords={
            "pulse": ("pulse", np.arange(pulses.size), {"units": "1", "long_name": "pulse number"})
        },
    )
    unit = noisy.attrs.get("units", "m/s^2")
    units = {"rms": unit, "residual_variance": f"({unit})^2", "envelope_variance": f"({unit})^2"}
    for name in (*INDICATORS, "residual_variance", "envelope_variance"):
        attrs = {"long_name": f"{name} of the gear average", "units": units.get(name, "1")}
        data[name] = ((), float(indicators[name]), attrs)
    labels = {**task.labels, "seed": seed}
    data = data.assign_coords({k: ((), v, LABEL_ATTRS.get(k, {})) for k, v in labels.items()})
    data.attrs.update(
        record_hash=digest,
        case=task.case.name,
        scene=task.scene.name,
        gear=task.gear,
        sensor_channel=channel,
        labels=json.dumps(labels),
    )
    return data


def run_record_task(task: RecordTask) -> list[dict]:
    """Simulate one (severity, speed, load) and write a record per seed; never raises."""
    from ..analysis.time.transient import run_transient
    from ..io import atomic_path
    from .cluster import task_files

    started = time.perf_counter()
    try:
        run = run_transient(task.case, task.scene)
        record_case_json = case_json(task.case)
        for seed, digest, path in zip(task.seeds, task.hashes, task.paths):
            record = _record(task, run, seed, digest)
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
        message = str(error) if isinstance(error, CaseError) else f"{type(error).__name__}: {error}"
        for path in task.paths:
            with atomic_path(Path(path).with_suffix(".error.json")) as temporary:
                Path(temporary).write_text(json.dumps({"labels": task.labels, "error": message}))
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
    from .cluster import dask_client

    started = time.perf_counter()
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise CaseError(f"--out {str(out)!r} is a file: a dataset writes into a directory")
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
                for record in future.result():
                    outcome[record["hash"]] = record
                done += len(future.result())
                bar(done, len(hashes))
    failed = [r for r in outcome.values() if r["status"] == "failed"]
    complete = [h for h in hashes if h not in {r["hash"] for r in failed}]
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
        _trend_figure(combined, out / f"dataset_{digest}_trends.png", plan)
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


def _trend_figure(combined: xr.Dataset, path: Path, plan: DatasetPlan) -> None:
    """FM4, the NA4 trend, FM0 and ER against severity, drawn after the files are safe."""
    from ..io import save_figure
    from ..plots.condition_monitoring import plot_indicator_trends

    figure = plot_indicator_trends(
        combined,
        indicators=("fm4", "na4_trend", "fm0", "energy_ratio"),
        title=f"{plan.case.name}: {plan.kind} on {plan.gear} tooth {plan.tooth}",
    )
    save_figure(figure, path, dpi=figure.dpi, release=True)  # atomic: no half-written figure


def combine_records(paths: Sequence[Path]) -> xr.Dataset:
    """The records on one ``record`` dimension, with the NA4 and NB4 trends: each
    record's fourth moment over the mean variance of the records of its operating point
    and seed up to its severity (Zakrajsek et al. 1993's running average)."""
    records = []
    for path in paths:
        with xr.open_dataset(path, decode_times=False) as data:
            records.append(index_labels(data.load()))
    if not records:
        return xr.Dataset()
    combined = xr.concat(
        [r.expand_dims("record") for r in records],
        dim="record",
        join="outer",  # the pulse counts differ between speeds: NaN-padded
        combine_attrs="override",  # the variables keep their units and long names
        coords="all",
        compat="override",
    )
    combined.attrs = {}  # the first record's own: the dataset sets its own
    combined["record"] = ("record", np.arange(len(records)), {"units": "1", "long_name": "record"})
    combined["record_hash"] = (
        "record",
        [r.attrs["record_hash"] for r in records],
        {"long_name": "input hash: the record's file is record_<hash>.nc"},
    )
    point = np.stack([combined[k].values for k in ("speed_rpm", "load_nm", "seed")], axis=1)
    severity = combined.severity.values
    # record j is in record i's trend: same operating point and seed, severity up to i's
    member = (point[:, None, :] == point[None, :, :]).all(axis=2)
    member &= severity[None, :] <= severity[:, None]
    for indicator, variance in (("na4", "residual_variance"), ("nb4", "envelope_variance")):
        own = combined[variance].values
        mean = (member * own[None, :]).sum(axis=1) / member.sum(axis=1)
        trend = combined[indicator].values * own**2 / mean**2
        combined[f"{indicator}_trend"] = (
            "record",
            trend,
            {
                "units": "1",
                "long_name": f"{indicator.upper()} normalised by the mean {variance} of the "
                "records of the same speed, load and seed up to this severity",
            },
        )
    return combined
