"""The data card of a fault dataset: what it holds, how it was made, its labels
(:mod:`pygear.runs.fault_dataset` writes it beside ``dataset_<hash>.nc``)."""

from __future__ import annotations

import xarray as xr

from .._version import __version__

__all__ = ["data_card"]


def data_card(plan, combined: xr.Dataset, file_name: str, indicators: tuple[str, ...]) -> str:
    """The dataset's data card (Markdown): what it holds, how it was made, its labels."""
    lines = [
        f"# Data card: {file_name}",
        "",
        f"Simulated vibration of case `{plan.case.name}` (scene `{plan.scene.name}`), "
        f"made by pygear {__version__}.",
        "",
        "## Grid",
        f"- fault: `{plan.kind}` on {_place(plan)}, severities "
        f"{', '.join(f'{s:g}' for s in plan.severities)} ({_SEVERITY[plan.kind]})",
        f"- carrier speeds [rpm]: {', '.join(f'{s:g}' for s in plan.speeds)}; the run starts "
        "turning at that speed and the load law balances the drive there",
        f"- carrier torques [N m]: {', '.join(f'{t:g}' for t in plan.loads)}",
        f"- noise seeds: {len(plan.seeds)}, white noise at {plan.snr_db:g} dB SNR on the sensor",
        f"- records: {combined.attrs.get('records', combined.sizes.get('record', 0))}, "
        f"failed: {combined.attrs.get('records_failed', 0)}",
        "",
        "## Variables (dimension `record`)",
        f"- `{next(iter(v for v in combined.data_vars if v.endswith('_acceleration')), 'sensor')}`"
        "(record, time): the sensor channel [m/s^2]",
        "- `tachometer_angle`(record, time): the carrier's angle [rad]; "
        "`tachometer_pulse_time`(record, pulse): once-per-turn pulses [s], NaN-padded",
        f"- `gear_average`(record, angle_step): the synchronous average of `{plan.gear}`",
        f"- indicators (record): {', '.join(indicators)}, and `na4_trend`, `nb4_trend` "
        "(normalised by the records of the same operating point and seed up to the severity)",
        f"- labels (coordinates on record): fault_kind, {_place_labels(plan)}, severity, "
        "speed_rpm, load_nm, seed, snr_db; `record_hash` names each record's own file",
        "",
        "## Use",
        "```python",
        "import pygear.io",
        f"data = pygear.io.open_dataset('{file_name}')  # time in s, labels as indexes",
        "data.fm4.groupby('severity').mean()",
        "```",
        "The record files `record_<hash>.nc` open one by one or together with "
        "`pygear.io.open_mfdataset('record_*.nc', concat_dim='record', join='outer')`.",
        "",
        "## Model",
        "Rigid multibody planetary stage (pygear's improved formulation); sensor model, "
        "averages and indicators: pygear's docs/condition_monitoring.md.",
        "",
    ]
    return "\n".join(lines)


_SEVERITY = {
    "crack_depth": "root crack at 45 deg, q sin(45 deg) over the base-circle half thickness",
    "stiffness_factor": "loss of the tooth's pair stiffness",
    "chipped_fraction": "tip chipped off to this share of the tooth height",
    "outer_race_depth": "depth [m] of a spall on the outer race, bearings as Hertz contacts",
    "inner_race_depth": "depth [m] of a spall on the inner race, bearings as Hertz contacts",
}


def _place(plan) -> str:
    """Where the fault sits, in words."""
    fault = getattr(plan, "bearing", None)
    if fault is None:
        return f"tooth {plan.tooth} of `{plan.gear}`"
    planet = f" of planet {fault.planet}" if fault.planet else ""
    return (
        f"the {fault.race} race of bearing `{fault.bearing}`{planet}, at {fault.angle_deg:g} deg, "
        f"{fault.width:g} m wide (averaged gear `{plan.gear}`)"
    )


def _place_labels(plan) -> str:
    """The labels that say where the fault sits."""
    if getattr(plan, "bearing", None) is None:
        return "fault_gear, fault_tooth"
    return "fault_bearing, fault_planet, defect_angle_deg, defect_width"
