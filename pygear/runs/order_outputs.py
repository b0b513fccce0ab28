"""The files of an order tracking: ``orders.nc`` and its three figures in one directory,
each written under a temporary name and renamed when whole (:mod:`pygear.io`)."""

from __future__ import annotations

from pathlib import Path

import xarray as xr

from ..analysis.signals.order_plan import OrderPlan
from ..analysis.signals.order_tracking import track_orders
from ..errors import CaseError
from ..io import save_figure, write_netcdf

__all__ = ["ORDER_FILES", "order_directory", "write_order_tracking"]

ORDER_FILES = ("orders.nc", "orders_map.png", "orders_spectrum.png", "orders_slices.png")
"""What an order tracking writes into its directory."""


def order_directory(run_path: Path, out: Path | None) -> Path:
    """Where the order tracking of ``run_path`` goes: ``out``, else ``<run>_orders/``
    beside the run (so two runs in one directory keep their own results).

    Raises
    ------
    CaseError
        ``out`` names a file (an existing one, or a .nc/.png name), or a directory whose
        ``orders.nc`` would be the run file itself.
    """
    directory = out if out is not None else run_path.with_name(f"{run_path.stem}_orders")
    if out is not None and (out.suffix.lower() in (".nc", ".png") or out.is_file()):
        raise CaseError(
            f"--out {str(out)!r}: with --orders it is a directory (orders.nc and figures are "
            "written into it), not a file"
        )
    if (directory / ORDER_FILES[0]).resolve() == run_path.resolve():
        raise CaseError(f"--out {str(directory)!r} would write orders.nc over RUN.nc itself")
    return directory


def write_order_tracking(
    run: xr.Dataset, plan: OrderPlan, directory: Path, *, source: str = ""
) -> tuple[xr.Dataset, list[Path]]:
    """Track the plan's orders and write ``orders.nc`` and its figures into ``directory``.

    Parameters
    ----------
    run : xarray.Dataset
        The run the plan was made for.
    plan : OrderPlan
        From :func:`pygear.analysis.signals.order_plan.plan_order_tracking` (checked input).
    directory : Path
        Target directory (created if missing).
    source : str
        The run file's name, kept as an attribute.

    Returns
    -------
    (xarray.Dataset, list of Path)
        The result and the files written.
    """
    from ..plots.orders import plot_order_map, plot_order_slices, plot_order_spectrum

    result = track_orders(run, plan)
    if source:
        result.attrs["run_file"] = source
    directory.mkdir(parents=True, exist_ok=True)
    paths = [directory / name for name in ORDER_FILES]
    write_netcdf(
        result,
        paths[0],
        title=f"Order tracking of {plan.channel} against the angle of {plan.reference.member}",
        input_hash=str(run.attrs.get("input_hash", "")) or None,
        provenance=run.attrs,  # the run's case, scene, formulation and case JSON
    )
    for plot, path in zip((plot_order_map, plot_order_spectrum, plot_order_slices), paths[1:]):
        figure = plot(result, run_attrs=run.attrs)
        save_figure(figure, path, dpi=figure.dpi, release=True)  # atomic: no half-written figure
    return result, paths
