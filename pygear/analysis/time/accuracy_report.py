"""The grid of an accuracy study as a Dataset, its recommendation and its table.

Split from :mod:`pygear.analysis.time.accuracy` (which computes): :func:`grid_dataset` packs the
arrays with units and long names, :func:`recommendation` picks the cheapest setting
within the tolerance, :func:`accuracy_table_text` formats the table.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import xarray as xr

__all__ = ["accuracy_table_text", "grid_dataset", "quantity_recommendations", "recommendation"]


def grid_dataset(
    case, scene, study, formulations, ladder, steps, metrics, a: dict, sampled_kinds: tuple
) -> xr.Dataset:
    """The study's arrays ``a`` as a Dataset with units, long names and recommendations."""
    units = {
        "t_s": "s",
        "equilibrium_speed": "rpm",
        "mesh_force_rms": "N",
        "mesh_force_peak": "N",
        "peak_frequency": "Hz",
        "natural_frequency": "Hz",
    }
    kind = [m.split(":", 1)[0] for m in metrics]
    grid = ("formulation", "fidelity", "time_step")
    # judged metrics only: a channel carrying round-off (the symmetric study case's ring
    # acceleration) has an "order" that is a random number of the build and the BLAS
    orders = np.where(a["judged"][:, None, :], a["order"], np.nan)
    sampled = orders[..., np.isin(kind, sampled_kinds)]
    order_median = np.array(
        [[np.nanmedian(r) if np.isfinite(r).any() else np.nan for r in per_f] for per_f in sampled]
    )
    ds = xr.Dataset(
        {
            "value": (
                (*grid, "metric"),
                a["value"],
                {"units": "see metric_units", "long_name": "metric value"},
            ),
            "error": (
                (*grid, "metric"),
                a["error"],
                {"units": "1", "long_name": "error against the reference over the metric's scale"},
            ),
            "max_error": (
                grid,
                a["max_error"],
                {"units": "1", "long_name": "largest error of the judged metrics"},
            ),
            "wall_time": (
                grid,
                a["wall"],
                {"units": "s", "long_name": "median wall time of a run"},
            ),
            "status": (grid, a["status"].astype(str), {"long_name": "ok, diverged or refused"}),
            "message": (grid, a["message"].astype(str), {"long_name": "why a run failed"}),
            "contact_evaluations": (
                grid,
                a["contact"],
                {"units": "1", "long_name": "tooth-contact table evaluations of a run"},
            ),
            "dof_count": (
                ("formulation", "fidelity"),
                a["dofs"],
                {"units": "1", "long_name": "reduced DOFs"},
            ),
            "observed_order": (
                ("formulation", "fidelity", "metric"),
                a["order"],
                {"units": "1", "long_name": "observed order from the three finest time steps"},
            ),
            "observed_order_median": (
                ("formulation", "fidelity"),
                order_median,
                {
                    "units": "1",
                    "long_name": "median observed order of the judged metrics of the samples",
                },
            ),
            "discretisation_error": (
                ("formulation", "fidelity", "metric"),
                a["estimate"],
                {"units": "1", "long_name": "Richardson estimate of the finest run's error"},
            ),
            "judged": (
                ("formulation", "metric"),
                a["judged"].astype(np.int8),
                {"units": "1", "long_name": "1 where the reference is converged to the tolerance"},
            ),
        },
        coords={
            "formulation": ("formulation", list(formulations), {"long_name": "formulation"}),
            "fidelity": ("fidelity", [f.name for f in ladder], {"long_name": "fidelity rung"}),
            "time_step": ("time_step", steps, {"units": "s", "long_name": "time step"}),
            "metric": ("metric", metrics, {"long_name": "quantity users read"}),
            "dof_set": ("fidelity", [f.dof_set for f in ladder], {"long_name": "DOF set"}),
            "stiffness": (
                "fidelity",
                ["time-varying" if f.time_varying else "constant" for f in ladder],
                {"long_name": "mesh stiffness"},
            ),
            "equivalent_load": (
                "fidelity",
                [f.equivalent_load for f in ladder],
                {"long_name": "equivalent-load mode"},
            ),
            "metric_kind": ("metric", kind, {"long_name": "kind of metric"}),
            "metric_units": (
                "metric",
                [units.get(k, "m/s^2 or rad/s^2") for k in kind],
                {"long_name": "units of the metric"},
            ),
        },
        attrs={
            "case": case.name,
            "scene": scene.name,
            "tolerance": study.tolerance,
            "repeats": study.repeats,
            "reference": f"{ladder[-1].name} at dt = {steps[-1]:g} s, per formulation",
        },
    )
    for formulation in formulations:
        best = recommendation(ds, formulation)
        for key, val in best.items():
            ds.attrs[f"recommendation_{formulation}_{key}"] = val
    return ds


def recommendation(ds: xr.Dataset, formulation: str, kind: str | None = None) -> dict:
    """The cheapest setting whose judged metrics (of ``kind``, or all) meet the tolerance."""
    sub = ds.sel(formulation=formulation)
    judged = sub.judged.values.astype(bool)
    if kind is not None:
        judged &= sub.metric_kind.values == kind
    if not judged.any():
        return {"fidelity": "", "time_step": math.nan, "wall_time": math.nan, "max_error": math.nan}
    errors = np.nan_to_num(sub.error.values[..., judged], nan=np.inf).max(-1)
    wall = np.where(errors <= ds.attrs["tolerance"], sub.wall_time.values, np.inf)
    j, k = np.unravel_index(np.argmin(wall), wall.shape)
    if not np.isfinite(wall[j, k]):
        return {"fidelity": "", "time_step": math.nan, "wall_time": math.nan, "max_error": math.nan}
    return {
        "fidelity": str(sub.fidelity.values[j]),
        "time_step": float(sub.time_step.values[k]),
        "wall_time": float(wall[j, k]),
        "max_error": float(errors[j, k]),
    }


def accuracy_table_text(ds: xr.Dataset, formulations: Sequence[str] | None = None) -> str:
    """Per formulation: each fidelity's largest judged error and wall time per time step."""
    lines = [f"accuracy of {ds.attrs['case']} / {ds.attrs['scene']}: {ds.attrs['study_note']}"]
    tolerance = ds.attrs["tolerance"]
    for f in formulations or ds.formulation.values.tolist():
        sub = ds.sel(formulation=f)
        skipped = [str(m) for m, j in zip(sub.metric.values, sub.judged.values) if not j]
        lines.append("")
        lines.append(
            f"{f}: largest error of {int(sub.judged.sum())} judged metrics / median wall time "
            f"(tolerance {tolerance:.3g}; not judged, reference not converged: "
            f"{len(skipped)})"
        )
        header = f"{'fidelity':<34}{'DOFs':>5}" + "".join(
            f"{'dt=' + format(dt, '.3g'):>20}" for dt in sub.time_step.values
        )
        lines.append(header)
        best = recommendation(ds, f)
        for j, fid in enumerate(sub.fidelity.values):
            cells = []
            for k, dt in enumerate(sub.time_step.values):
                if sub.status.values[j, k] != "ok":
                    cells.append(f"{sub.status.values[j, k]:>20}")
                    continue
                mark = "*" if (fid == best["fidelity"] and dt == best["time_step"]) else " "
                err = sub.max_error.values[j, k]
                cells.append(
                    f"{err * 100:>9.3g}% {sub.wall_time.values[j, k] * 1e3:>6.0f} ms{mark}"
                )
            lines.append(f"{fid:<34}{int(sub.dof_count.values[j]):>5}" + "".join(cells))
        orders = ", ".join(
            f"{fid}: {o:.2f}"
            for fid, o in zip(sub.fidelity.values, sub.observed_order_median.values)
        )
        lines.append(f"observed order (median over judged metrics): {orders}")
        if best["fidelity"]:
            lines.append(
                f"recommendation (*): {best['fidelity']} at dt = {best['time_step']:g} s, "
                f"{best['wall_time'] * 1e3:.0f} ms, largest error {best['max_error'] * 100:.3g} %"
            )
        else:
            lines.append("recommendation: no setting meets the tolerance")
        lines.append("cheapest setting per quantity (the quantities a study reads decide):")
        lines += [f"  {kind:<18} {text}" for kind, text in quantity_recommendations(ds, f)]
    return "\n".join(lines)


def quantity_recommendations(ds: xr.Dataset, formulation: str) -> list[tuple[str, str]]:
    """(metric kind, its cheapest setting within the tolerance, as text) per kind."""
    rows = []
    for kind in dict.fromkeys(ds.metric_kind.values.tolist()):
        pick = recommendation(ds, formulation, kind)
        if pick["fidelity"]:
            text = (
                f"{pick['fidelity']} at dt = {pick['time_step']:g} s, "
                f"{pick['wall_time'] * 1e3:.0f} ms, error {pick['max_error'] * 100:.2g} %"
            )
        else:
            text = "not judged, or no setting meets the tolerance"
        rows.append((kind, text))
    return rows
