"""The paper's Figure 7 as a sweep: natural frequencies of the study case against the
sun-planet mesh stiffness over five decades, improved and Lin-Parker formulations.

Two sweeps, one per formulation, on one local Dask cluster.  The formulation is a
choice of model, not a number of the case, so it is not a swept parameter: each
sweep keeps its own directory (its points reuse on a rerun) and the two combined
datasets are stacked along a ``formulation`` dimension here.  The figure is drawn
from the stacked dataset with pygear's own Figure 7 plot.

    python examples/figure7_sweep.py [--out out/figure7] [--points 41] [--workers 2]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import xarray as xr
from distributed import LocalCluster

from pygear import load_case
from pygear.analysis.modes.sensitivity import frequency_sweep
from pygear.plots.modal import plot_frequency_sweep
from pygear.runs.sweep import run_sweep

CASE = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"
PARAMETER = "planetary.sun_mesh.stiffness"
FORMULATIONS = ("improved", "lin-parker")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("out/figure7"))
    parser.add_argument("--points", type=int, default=41, help="values from 1e6 to 1e11 N/m")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()

    values = f"logspace(6,11,{args.points})"
    with LocalCluster(
        n_workers=args.workers, threads_per_worker=1, dashboard_address=None
    ) as cluster:
        sweeps = [
            run_sweep(
                CASE,
                [(PARAMETER, values)],
                scene="modal",
                formulation=formulation,
                out_dir=args.out / formulation,
                scheduler=cluster.scheduler_address,
            )
            for formulation in FORMULATIONS
        ]

    # one dataset: formulation x stiffness x mode, laid out as `pygear sensitivity` does
    stacked = xr.concat(
        [s[["frequency", "mode_class"]] for s in sweeps],
        dim=xr.DataArray(list(FORMULATIONS), dims="formulation", name="formulation"),
    ).rename({PARAMETER: "value"})
    stacked.attrs["parameter"] = PARAMETER
    figure = args.out / "figure7.png"
    plot_frequency_sweep(stacked, figure)

    # the same numbers as the serial `pygear sensitivity` computation
    case = load_case(CASE)
    serial = frequency_sweep(
        case, PARAMETER, stacked.value.values, formulations=FORMULATIONS, scene=case.scene("modal")
    )
    reference = serial.frequency.values
    difference = np.max(abs(stacked.frequency.values - reference) / np.maximum(reference, 1.0))
    print(f"largest relative difference from the serial sweep: {difference:.1e}")
    failed = int(np.sum([s.attrs["points_failed"] for s in sweeps]))
    print(f"wrote {figure} ({failed} failed points)")


if __name__ == "__main__":
    main()
