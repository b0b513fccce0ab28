"""What a duty-cycle file holds, as the rating takes it.

:func:`duty_from_dataset` reads, in this order of preference:

1. a pygear run's ``mesh_force`` record (``mesh``, ``time``): the rainflow matrices of
   the whole record (:func:`.run_damage.cycle_matrix`);
2. a streamed run's reductions ``rainflow_mesh_force`` with its ``_range_edges`` and
   ``_mean_edges`` (or a batch's combined spectrum in the same variables,
   :mod:`pygear.runs.dlc_spectrum`, counted per year: attribute ``period`` "one year",
   so the record is the year, idle hours included): the matrices as written, not
   counted again;
3. a load duration distribution ``load_duration_time`` / ``load_duration_revolutions``
   / ``load_duration_edges`` of the ``drive_torque``: a :class:`DutyCycle` (each
   level at its upper edge, the speed from its revolutions);
4. a rotor record ``rotor_torque`` [N m], ``rotor_speed`` [rpm] over ``time`` [s] (an
   OpenFAST output as :func:`pygear.io_openfast.read_openfast_output` gives it) or a
   run's ``drive_torque`` and input speed: binned at level into a :class:`DutyCycle`
   (:func:`load_duration_from_series`), the gear torques following through the
   stages' ratios, and its rainflow cycles noted.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...errors import CaseError
from ...model.rating import DutyCycle
from .duty import rainflow_cycles
from .run_damage import DEFAULT_BINS, CycleMatrix, cycle_matrix

__all__ = ["DutyInput", "duty_from_dataset", "load_duration_from_series"]


@dataclass
class DutyInput:
    """A duty-cycle file's content: a load spectrum of the input torque, or the cycle
    matrices of the meshes' forces over ``record_s`` seconds at a mean input speed of
    ``speed_rpm`` (None: unknown, the rated speed is taken); ``notes`` for the report
    (what was read and how)."""

    duty_cycle: DutyCycle | None = None
    matrices: list[CycleMatrix] = field(default_factory=list)
    record_s: float = 0.0
    speed_rpm: float | None = None
    notes: dict = field(default_factory=dict)


def load_duration_from_series(time, torque, speed_rpm, bins: int = DEFAULT_BINS
                              ) -> DutyCycle:
    """A load duration distribution of an input torque record with its speed: |torque|
    binned into ``bins`` levels (each at its upper edge), each sample standing for half
    the interval to each neighbour; a level's speed is its revolutions over its time."""
    t = np.asarray(time, dtype=float)
    q = np.abs(np.asarray(torque, dtype=float))
    n = np.abs(np.asarray(speed_rpm, dtype=float))
    if not (t.ndim == 1 and t.shape == q.shape == n.shape and t.size >= 2):
        raise CaseError("time, torque and speed must be 1-D records of the same length >= 2")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(q)) and np.all(np.isfinite(n))):
        raise CaseError("time, torque and speed must be finite")
    if np.any(np.diff(t) <= 0.0):
        raise CaseError("time must increase strictly")
    step = np.empty_like(t)
    step[1:-1] = 0.5 * (t[2:] - t[:-2])
    step[0] = 0.5 * (t[1] - t[0])
    step[-1] = 0.5 * (t[-1] - t[-2])
    edges = np.linspace(0.0, float(q.max()) * (1.0 + 1e-12) or 1.0, bins + 1)
    index = np.clip(np.searchsorted(edges, q, side="left") - 1, 0, bins - 1)
    seconds = np.bincount(index, weights=step, minlength=bins)
    revolutions = np.bincount(index, weights=step * n / 60.0, minlength=bins)
    keep = seconds > 0.0
    speed = np.where(keep, 60.0 * revolutions / np.where(keep, seconds, 1.0), 0.0)
    return DutyCycle(tuple(edges[1:][keep]), tuple(seconds[keep] / 3600.0),
                     tuple(np.maximum(speed[keep], 1e-9)))


def _yearly(ds) -> float | None:
    """Hours of the year a batch's load spectrum counts per (``period`` "one year"),
    else None."""
    if ds.attrs.get("period") == "one year":
        return float(ds.attrs.get("hours_per_year", 8766.0))
    return None


def _ldd_seconds(ds) -> float | None:
    """Seconds the drive torque's load duration counts (every sample one interval)."""
    names = _names(ds, "torque")
    if "load_duration_time" in ds and "drive_torque" in names:
        return float(np.atleast_2d(ds["load_duration_time"].values)[
            names.index("drive_torque")].sum())
    return None


def _record_seconds(ds) -> float:
    """The time a file's matrices count: a batch spectrum's year; else the span the
    load duration counts, the same samples' (every sample one interval); else the
    run's duration."""
    if _yearly(ds) is not None:
        return _yearly(ds) * 3600.0
    if _ldd_seconds(ds):
        return _ldd_seconds(ds)
    if "duration" in ds.attrs:
        return float(ds.attrs["duration"])
    raise CaseError("the duty-cycle file's rainflow matrices need the record's length: "
                    "a 'duration' attribute [s] or load_duration_time of drive_torque")


def _names(ds, dim: str) -> list[str]:
    """Labels along ``dim``: its ``<dim>_label`` variable as pygear writes it, or the
    index :func:`pygear.io.open_dataset` makes of it; [] without either."""
    if f"{dim}_label" in ds.variables:
        return [str(v) for v in ds[f"{dim}_label"].values]
    if dim in ds.coords:
        return [str(v) for v in ds[dim].values]
    return []


def _labels(ds) -> list[str]:
    return _names(ds, "mesh")


def duty_from_dataset(ds, source: str, bins: int | None = None) -> DutyInput:
    """The duty input a dataset holds (see the module docstring); ``source`` names the
    file in errors and notes.

    Raises
    ------
    CaseError
        A dataset holding none of the four forms.
    """
    if "mesh_force" in ds and "time" in ds["mesh_force"].dims:
        force = ds["mesh_force"].transpose("mesh", "time").values
        count = bins or (ds.sizes.get("rainflow_range") or DEFAULT_BINS)
        matrices = [cycle_matrix(label, row, count) for label, row in zip(_labels(ds), force)]
        time = ds["time"].values
        return DutyInput(matrices=matrices, record_s=float(time[-1] - time[0]),
                         speed_rpm=_mean_speed(ds), notes={
            "source": f"{source}: mesh forces of the run, rainflow counted (ASTM E1049-85)",
            "record_s": float(time[-1] - time[0]), "bins": count,
            "rainflow_cycles": float(sum(m.counts.sum() for m in matrices))})
    if "rainflow_mesh_force" in ds:
        counts = ds["rainflow_mesh_force"].values.reshape(-1, *ds["rainflow_mesh_force"].shape[-2:])
        ranges = ds["rainflow_mesh_force_range_edges"].values.reshape(counts.shape[0], -1)
        means = ds["rainflow_mesh_force_mean_edges"].values.reshape(counts.shape[0], -1)
        matrices = [CycleMatrix(label, c, r, m)
                    for label, c, r, m in zip(_labels(ds), counts, ranges, means)]
        record = _record_seconds(ds)
        return DutyInput(matrices=matrices, record_s=record, speed_rpm=_mean_speed(ds), notes={
            "source": f"{source}: rainflow matrices of the mesh forces as written "
                      "(streamed reductions or a batch's combined spectrum)",
            "record_s": record, "bins": counts.shape[-1],
            "rainflow_cycles": float(counts.sum())})
    if "load_duration_time" in ds:
        names = _names(ds, "torque")
        which = {v: i for i, v in enumerate(names)} if names else {"drive_torque": 0}
        if "drive_torque" not in which:
            raise CaseError(f"--duty-cycle {source!r}: its load duration distribution has no "
                            "drive_torque level set (the input torque the rating needs)")
        k = which["drive_torque"]
        seconds = np.atleast_2d(ds["load_duration_time"].values)[k]
        revolutions = np.atleast_2d(ds["load_duration_revolutions"].values)[k]
        edges = np.atleast_2d(ds["load_duration_edges"].values)[k]
        upper = np.maximum(np.abs(edges[1:]), np.abs(edges[:-1]))  # a level's largest |T|
        keep = seconds > 0.0
        if not keep.any():
            raise CaseError(f"--duty-cycle {source!r}: its load duration distribution is empty")
        speed = 60.0 * revolutions[keep] / seconds[keep]
        duty = DutyCycle(tuple(upper[keep]), tuple(seconds[keep] / 3600.0),
                         tuple(np.maximum(speed, 1e-9)), period_h=_yearly(ds))
        return DutyInput(duty_cycle=duty, notes={
            "source": f"{source}: load duration distribution of the input torque as written",
            "record_s": float(seconds.sum()), "levels": int(keep.sum())})
    series = _torque_series(ds, source)
    if series is not None:
        time, torque, speed, what = series
        duty = load_duration_from_series(time, torque, speed, bins or DEFAULT_BINS)
        cycles = rainflow_cycles(torque)
        return DutyInput(duty_cycle=duty, notes={
            "source": f"{source}: {what}, binned at level into a load duration distribution",
            "record_s": float(time[-1] - time[0]), "rainflow_cycles": len(cycles),
            "largest_range": max((c[0] for c in cycles), default=0.0)})
    raise CaseError(
        f"--duty-cycle {source!r} holds no duty cycle: it needs mesh_force over time (a "
        "pygear run), rainflow_mesh_force (streamed reductions), load_duration_time, or "
        "rotor_torque and rotor_speed over time (an OpenFAST output)")


def _mean_speed(ds) -> float | None:
    """The record's mean input speed [rpm]: of the input member's speed record, else
    from the drive torque's load duration (revolutions over time), else None."""
    member = str(ds.attrs.get("input", "")).removesuffix(".theta_z")
    if "speed" in ds and "time" in ds["speed"].dims and "member" in ds["speed"].dims:
        labels = _names(ds, "member")
        if member in labels:
            return float(np.abs(ds["speed"].transpose("member", "time").values[
                labels.index(member)]).mean())
    names = _names(ds, "torque")
    if "load_duration_revolutions" in ds and names:
        if "drive_torque" in names:
            k = names.index("drive_torque")
            seconds = float(np.atleast_2d(ds["load_duration_time"].values)[k].sum())
            turns = float(np.atleast_2d(ds["load_duration_revolutions"].values)[k].sum())
            if _yearly(ds) is not None:  # a year's revolutions over the whole year
                seconds = _yearly(ds) * 3600.0
            if seconds > 0.0:
                return 60.0 * turns / seconds
    return None


def _torque_series(ds, source: str):
    if "rotor_torque" in ds and "rotor_speed" in ds:
        return (ds["time"].values, ds["rotor_torque"].values, ds["rotor_speed"].values,
                "rotor torque and speed")
    if "drive_torque" in ds and "time" in ds["drive_torque"].dims and "speed" in ds:
        member = str(ds.attrs.get("input", "")).removesuffix(".theta_z")
        labels = _names(ds, "member")
        if member not in labels:
            raise CaseError(f"--duty-cycle {source!r}: the run records drive_torque but not "
                            f"the speed of its input member {member!r}")
        speed = ds["speed"].transpose("member", "time").values[labels.index(member)]
        return (ds["time"].values, ds["drive_torque"].values, speed,
                "drive torque and input speed of the run")
    return None
