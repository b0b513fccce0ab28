"""The load spectrum of a design load case batch: the load cases' rainflow matrices and
load duration distributions summed per year (``load_spectrum.nc``).

Each load case stands for ``hours_per_year`` hours a year (its wind speed's Weibull
probability shared among its seeds) and ran ``duration`` seconds, so its counts enter
the spectrum times w = 3600 hours_per_year / duration.  The variables are those of a
single run's reductions (:mod:`pygear.analysis.time.reductions`), counted per year:

* ``rainflow_<variable>(<label>, rainflow_range, rainflow_mean)`` [cycles a year] with
  ``rainflow_<variable>_range_edges`` and ``..._mean_edges``;
* ``load_duration_time(torque, load_level)`` [s a year], ``load_duration_revolutions``
  [revolutions a year], ``load_duration_edges`` [N m].

A run's histogram bins are 2^e wide with edges at multiples of the width, so the bins
of two runs are either nested or disjoint: the sum re-bins every load case onto the
widest width among them (each of its bins falls whole into one bin there) and widens
further, by powers of two, until the union fits into the runs' bin count.  No count is
split between bins, so the sum is exact up to the weights' round-off.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from ..analysis.time.reductions import Pow2Histogram
from ..errors import CaseError
from ..io import atomic_path
from ..model.dlc_settings import HOURS_PER_YEAR, DesignLoadCases, LoadCase

__all__ = ["combine_histograms", "load_spectrum", "write_load_spectrum"]


def _exponent(edges: np.ndarray) -> int:
    width = float(edges[1] - edges[0])
    exponent = int(round(math.log2(width)))
    if not math.isclose(width, 2.0**exponent, rel_tol=1e-12):
        raise CaseError(f"histogram edges {edges[:2]} are not a power-of-two width apart")
    return exponent


def combine_histograms(
    parts: Sequence[tuple[np.ndarray, Sequence[np.ndarray], float]], bins: int
) -> tuple[np.ndarray, list[np.ndarray]]:
    """The weighted sum of power-of-two histograms with different bins.

    Parameters
    ----------
    parts : sequence of (counts, edges, weight)
        ``counts`` of shape (bins,) * axes + (weights,), ``edges`` one array of
        bins + 1 edges per axis, and the factor the counts are multiplied by.
    bins : int
        Bins of the result along each axis.

    Returns
    -------
    (ndarray, list of ndarray)
        The summed counts and the edges of each axis.
    """
    axes = len(parts[0][1])
    weights = parts[0][0].shape[-1]
    histogram = Pow2Histogram(axes, bins, weights)
    # the widest bins among the parts: every part's bin then lies in one bin of the sum
    histogram.exponent = np.array(
        [max(_exponent(edges[a]) for _, edges, _ in parts) for a in range(axes)], dtype=np.int64
    )
    points, sums = [], []
    for counts, edges, weight in parts:
        occupied = np.nonzero(np.any(counts != 0, axis=-1))
        if not occupied[0].size:
            continue
        points.append(np.stack([edges[a][occupied[a]] for a in range(axes)], axis=1))
        sums.append(counts[occupied] * weight)
    if points:
        histogram.update(np.concatenate(points), np.concatenate(sums))
    counts, edges = histogram.result()
    return counts, list(edges)


def load_spectrum(
    runs: Sequence[tuple[xr.Dataset, LoadCase]], table: DesignLoadCases
) -> xr.Dataset:
    """The load spectrum per year of the load cases' reductions (see the module)."""
    first = runs[0][0]
    weights = [3600.0 * load.hours_per_year / table.duration for _, load in runs]
    data_vars: dict = {}
    coords: dict = {}
    names = sorted(
        n
        for n in first.data_vars
        if n.startswith("rainflow_") and not n.endswith(("_range_edges", "_mean_edges"))
    )
    for name in names:
        matrix = first[name]
        label = matrix.dims[0]
        labels = first[f"{label}_label"] if f"{label}_label" in first else None
        if labels is not None:
            coords[f"{label}_label"] = ((label,), labels.values, dict(labels.attrs))
        bins = matrix.shape[-1]
        summed, range_edges, mean_edges = [], [], []
        for k in range(matrix.shape[0]):
            parts = []
            for (run, _), weight in zip(runs, weights):
                counts = run[name].values[k][..., None]
                edges = (run[f"{name}_range_edges"].values[k], run[f"{name}_mean_edges"].values[k])
                parts.append((counts, edges, weight))
            counts, edges = combine_histograms(parts, bins)
            summed.append(counts[..., 0])
            range_edges.append(edges[0])
            mean_edges.append(edges[1])
        variable = name[len("rainflow_") :]
        units = first[f"{name}_range_edges"].attrs.get("units", "1")
        data_vars[name] = (
            matrix.dims,
            np.array(summed),
            {
                "units": "1",
                "long_name": f"rainflow cycles of {variable} a year by range and "
                "mean, summed over the design load cases",
            },
        )
        for axis, edges in (("range", range_edges), ("mean", mean_edges)):
            data_vars[f"{name}_{axis}_edges"] = (
                (label, f"rainflow_{axis}_edge"),
                np.array(edges),
                {"units": units, "long_name": f"edges of the cycle {axis} bins of {variable}"},
            )
    if "load_duration_time" in first:
        torques = first["load_duration_time"].dims[0]
        if f"{torques}_label" in first:
            labels = first[f"{torques}_label"]
            coords[f"{torques}_label"] = ((torques,), labels.values, dict(labels.attrs))
        bins = first["load_duration_time"].shape[-1]
        times, revolutions, level_edges = [], [], []
        for k in range(first["load_duration_time"].shape[0]):
            parts = [
                (
                    np.stack(
                        [
                            run["load_duration_time"].values[k],
                            run["load_duration_revolutions"].values[k],
                        ],
                        axis=-1,
                    ),
                    (run["load_duration_edges"].values[k],),
                    weight,
                )
                for (run, _), weight in zip(runs, weights)
            ]
            counts, edges = combine_histograms(parts, bins)
            times.append(counts[:, 0])
            revolutions.append(counts[:, 1])
            level_edges.append(edges[0])
        dims = first["load_duration_time"].dims
        data_vars["load_duration_time"] = (
            dims,
            np.array(times),
            {"units": "s", "long_name": "time a year at each torque level"},
        )
        data_vars["load_duration_revolutions"] = (
            dims,
            np.array(revolutions),
            {"units": "1", "long_name": "revolutions a year of the torque's member at each level"},
        )
        data_vars["load_duration_edges"] = (
            (torques, "load_level_edge"),
            np.array(level_edges),
            {"units": "N m", "long_name": "edges of the torque levels"},
        )
    if not data_vars:
        raise CaseError(
            "design_load_cases.reductions: the load cases hold no rainflow matrix or load "
            "duration distribution (set rainflow=... or load_duration=...)"
        )
    coords["load_case"] = ("load_case", [load.name for _, load in runs], {})
    data_vars["load_case_wind_speed"] = (
        "load_case",
        [load.wind_speed for _, load in runs],
        {"units": "m/s", "long_name": "hub wind speed"},
    )
    data_vars["load_case_seed"] = (
        "load_case",
        [load.seed for _, load in runs],
        {"units": "1", "long_name": "turbulence seed"},
    )
    data_vars["load_case_hours"] = (
        "load_case",
        [load.hours_per_year for _, load in runs],
        {"units": "h", "long_name": "hours a year each load case stands for"},
    )
    data_vars["load_case_weight"] = (
        "load_case",
        weights,
        {"units": "1", "long_name": "factor of each load case's counts (3600 hours / duration)"},
    )
    return xr.Dataset(
        data_vars,
        coords,
        attrs={
            "title": "Load spectrum of design load cases",
            "period": "one year",
            "hours_per_year": HOURS_PER_YEAR,
            "hours_covered": float(sum(load.hours_per_year for _, load in runs)),
            "load_case_duration_s": table.duration,
            "scene": table.scene,
            "source": table.source,
            "turbulence_class": table.turbulence_class,
            "weibull_shape": table.weibull_shape,
            "weibull_mean_m_per_s": table.weibull_mean,
        },
    )


def write_load_spectrum(
    files: Sequence[tuple[str | os.PathLike, LoadCase]],
    table: DesignLoadCases,
    path: str | os.PathLike,
    case_name: str = "",
) -> Path:
    """Combine the load case files into the load spectrum written to ``path``."""
    from ..io_read import check_complete

    runs = []
    try:
        for file, load in files:
            run = xr.open_dataset(file, decode_times=False)  # labels as <dim>_label
            runs.append((run, load))
            check_complete(run, str(file))
        spectrum = load_spectrum(runs, table)
    finally:
        for run, _ in runs:
            run.close()
    spectrum.attrs["case"] = case_name
    path = Path(path)
    with atomic_path(path) as temporary:
        spectrum.to_netcdf(temporary)
    return path
