"""``pygear analyze RUN.nc --orders MEMBER``: computed order tracking of one channel of a
run against a member's angle (``orders.nc`` and three figures).

The run file is read as data (NetCDF), never the case it names: the member's angle or
speed channel and the stages' mesh frequencies come from the file itself.  Every check
runs before the resampling starts, and a bad request exits with code 2.
"""

from __future__ import annotations

import argparse

__all__ = ["ORDERS_AFTER_DEFAULT", "analyze_orders"]

ORDERS_AFTER_DEFAULT = 0.0
"""``--after`` of an order tracking: a run-up is analysed from its start (the record
begins where the reference reaches a tenth of its top speed)."""


NEEDS = (
    "--orders needs a transient's result with the member's angle or speed over time "
    "(`pygear run` of a scene with a 'transient' analysis)"
)
"""What ``--orders`` asks of RUN.nc (ends the message of a file of another kind)."""


def analyze_orders(args: argparse.Namespace) -> int:
    """Handler of ``pygear analyze --orders``; returns the exit code."""
    from ..analysis.signals.order_plan import plan_order_tracking
    from ..analysis.signals.order_tracking import order_summary
    from ..analysis.signals.record_checks import check_record_time
    from ..runs.json_output import json_text
    from ..runs.order_outputs import order_directory, write_order_tracking
    from ..runs.outputs import read_run_file

    directory = order_directory(args.run, args.out)
    run = read_run_file(args.run, NEEDS)
    after = ORDERS_AFTER_DEFAULT if args.after is None else args.after
    check_record_time(run, f"RUN.nc {str(args.run)!r}", after)  # as every analyze path
    plan = plan_order_tracking(
        run,
        args.orders,
        args.channel,
        after=after,
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
