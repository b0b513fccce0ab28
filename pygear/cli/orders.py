"""``pygear analyze RUN.nc --orders MEMBER``: computed order tracking of one channel of a
run against a member's angle (``orders.nc`` and three figures).

The run file is read as data (NetCDF), never the case it names: the member's angle or
speed channel and the stages' mesh frequencies come from the file itself.  Every check
runs before the resampling starts, and a bad request exits with code 2.
"""

from __future__ import annotations

import argparse

from ..errors import CaseError

__all__ = ["ORDERS_AFTER_DEFAULT", "analyze_orders"]

ORDERS_AFTER_DEFAULT = 0.0
"""``--after`` of an order tracking: a run-up is analysed from its start (the record
begins where the reference reaches a tenth of its top speed)."""


def _read_run(path) -> object:
    import xarray as xr

    from ..io import index_labels

    try:
        with xr.open_dataset(path, decode_times=False) as opened:
            return index_labels(opened.load())  # labels as indexes, time in s
    except (OSError, ValueError) as error:
        raise CaseError(
            f"RUN.nc {str(path)!r} is not a NetCDF file pygear can read ({error})"
        ) from None


def analyze_orders(args: argparse.Namespace) -> int:
    """Handler of ``pygear analyze --orders``; returns the exit code."""
    from ..analysis.signals.order_plan import plan_order_tracking
    from ..analysis.signals.order_tracking import order_summary
    from ..runs.json_output import json_text
    from ..runs.order_outputs import order_directory, write_order_tracking

    if not args.run.is_file():
        raise CaseError(f"RUN.nc {str(args.run)!r} does not exist")
    directory = order_directory(args.run, args.out)
    run = _read_run(args.run)
    plan = plan_order_tracking(
        run,
        args.orders,
        args.channel,
        after=ORDERS_AFTER_DEFAULT if args.after is None else args.after,
        max_order=args.max_order,
        window_revolutions=args.window_revolutions,
    )
    result, files = write_order_tracking(run, plan, directory, source=str(args.run))
    summary = {**order_summary(result), "files": [str(f) for f in files]}
    if args.json:
        print(json_text(summary))
        return 0
    print(
        f"orders of {summary['channel']} against {summary['reference']} "
        f"({summary['angle_source']}): {summary['revolutions']:.4g} revolutions, "
        f"{summary['speed_range_rpm'][0]:.4g}-{summary['speed_range_rpm'][1]:.4g} rpm, "
        f"orders up to {summary['max_order']:.4g} in steps of {summary['order_resolution']:.3g}"
    )
    for stage, order in summary["mesh_orders"].items():
        print(f"  mesh order of {stage}: {order:.6g}")
    print(f"{'order':>12} {'amplitude [' + summary['units'] + ']':>24}")
    for peak in summary["orders"]:
        print(f"{peak['order']:>12.4f} {peak['amplitude']:>24.6g}")
    print(f"wrote {', '.join(str(f) for f in files)}")
    return 0
