"""A fault dataset's records: one record's dataset from its run, all records on one
``record`` dimension with the NA4/NB4 trends, and the indicator-trend figure
(:mod:`.fault_dataset` plans and runs them)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from ..io import index_labels

if TYPE_CHECKING:
    from ..model.case import Scene

__all__ = ["INDICATORS", "LABEL_ATTRS", "RECORD_SENSOR", "combine_records", "record_dataset"]

LABEL_ATTRS = {
    "fault_kind": {"long_name": "kind of tooth fault"},
    "fault_gear": {"long_name": "gear with the damaged tooth (stage.member)"},
    "fault_tooth": {"units": "1", "long_name": "damaged tooth number"},
    "severity": {"units": "1", "long_name": "fault severity (its kind's own measure)"},
    "fault_bearing": {"long_name": "rolling bearing with the race defect"},
    "fault_planet": {"units": "1", "long_name": "planet carrying it (0: not a planet bearing)"},
    "defect_angle_deg": {"units": "deg", "long_name": "defect's angle on its ring"},
    "defect_width": {"units": "m", "long_name": "defect's width along the race"},
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


def _sensor_channel(scene: Scene, sensor: str) -> str:
    """The channel name of the sensor's probe (:mod:`pygear.analysis.signals.channels`)."""
    probe = next(p for p in scene.transient.probes if p.quantity == "sensor" and p.target == sensor)
    return probe.name or f"sensor_acceleration:{sensor}"


def record_dataset(task, run: xr.Dataset, seed: int, digest: str) -> xr.Dataset:
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


def trend_figure(combined: xr.Dataset, path: Path, plan) -> None:
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
