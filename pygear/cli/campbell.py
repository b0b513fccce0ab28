"""``pygear campbell``: natural frequencies over a speed range with Cooley & Parker's
gyroscopic and centripetal terms, crossings with mesh and shaft orders, instabilities.

The handler checks every option before it loads the analysis, and imports its work when
called, so ``pygear --help`` loads none of it.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from pathlib import Path

from ..errors import CaseError
from .ranges import parse_range

__all__ = ["HANDLERS", "add_parsers", "campbell_summary"]

MEMBERS = ("carrier", "input")
"""Reference members the speeds may be given for."""

SPEED_TERMS = ("all", "planets")
"""Members of a gearbox case that carry Cooley & Parker's terms."""


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``campbell`` subcommand."""
    campbell = commands.add_parser(
        "campbell",
        help="Campbell diagram: frequencies over speed, order crossings, instabilities",
    )
    campbell.add_argument("case", metavar="CASE", help="case directory or case name under cases/")
    campbell.add_argument(
        "--scene", help="scene whose formulation and DOF set apply (default: first modal scene)"
    )
    campbell.add_argument(
        "--speeds",
        metavar="START:STOP:COUNT",
        help="speeds of the reference member [rpm]: COUNT equally spaced from START to "
        "STOP (a negative START: --speeds=-100:100:21)",
    )
    campbell.add_argument(
        "--member",
        default="carrier",
        help="reference member: carrier (first planetary stage's) or input (default carrier)",
    )
    campbell.add_argument(
        "--harmonics", default="3", help="mesh harmonics to cross with (default 3)"
    )
    campbell.add_argument(
        "--damping", action="store_true", help="include the case's damping (damping ratios)"
    )
    campbell.add_argument(
        "--speed-terms",
        default="all",
        help="a gearbox case: all (every member in its carrier's frame, default) or planets "
        "(the planets' terms, carrier, ring and sun inertial: as in a drivetrain)",
    )
    campbell.add_argument(
        "--modes",
        type=int,
        default=8,
        metavar="N",
        help="a rotor or drivetrain case: the N lowest modes at each speed (default 8)",
    )
    campbell.add_argument(
        "--solver",
        default="auto",
        help="a rotor or drivetrain case: auto (dense up to 400 DOFs), sparse or dense",
    )
    campbell.add_argument(
        "--critical-speed-map",
        metavar="KMIN:KMAX:COUNT",
        help="a rotor or drivetrain case, instead of --speeds: the undamped critical speeds "
        "against every shaft bearing's radial stiffness, COUNT values spaced "
        "logarithmically from KMIN to KMAX [N/m] (critical_speed_map.nc and .png)",
    )
    campbell.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    campbell.add_argument(
        "--out", type=Path, help="directory of campbell.nc and campbell.png (default out/<case>)"
    )


def _harmonics(text: str) -> int:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value == int(value) and 0 <= value <= 100):
        raise CaseError(f"--harmonics must be a whole number from 0 to 100 (got {text!r})")
    return int(value)


def campbell_summary(campbell) -> dict:
    """The numbers ``--json`` prints for a Campbell diagram."""
    crossings = [
        {
            "speed_rpm": float(speed),
            "mode": int(mode),
            "order": float(order),
            "excitation": str(name),
            "frequency_hz": float(frequency),
            "excitability": float(share),
        }
        for speed, mode, order, name, frequency, share in zip(
            campbell.crossing_speed.values,
            campbell.crossing_mode.values,
            campbell.crossing_order.values,
            campbell.crossing_excitation.values,
            campbell.crossing_frequency.values,
            campbell.crossing_excitability.values,
        )
    ]
    return {
        "case": campbell.attrs["case"],
        "reference": campbell.attrs["reference"],
        "formulation": campbell.attrs["formulation"],
        "speeds_rpm": campbell.speed.values.tolist(),
        "frequencies_hz": campbell.frequency.values.tolist(),
        "crossings": crossings,
        "unstable": [
            [float(a), float(b)]
            for a, b in zip(campbell.unstable_start.values, campbell.unstable_stop.values)
        ],
        "unstable_kind": [str(k) for k in campbell.unstable_kind.values],
    }


def _print_table(campbell, summary: dict) -> None:
    speeds = campbell.speed.values
    print(
        f"{campbell.attrs['case']}: {campbell.attrs['formulation']} formulation, "
        f"{campbell.attrs['dof_set']} DOF set, speeds of {campbell.attrs['reference']} "
        f"{speeds[0]:g} to {speeds[-1]:g} rpm ({speeds.size} speeds)"
    )
    print(f"{'mode':>4}  {'class':<14} {'f start [Hz]':>12} {'f stop [Hz]':>12}  whirl at stop")
    for m in range(campbell.sizes["mode"]):
        print(
            f"{m + 1:>4}  {str(campbell.mode_class.values[0, m]):<14} "
            f"{campbell.frequency.values[0, m]:>12.1f} {campbell.frequency.values[-1, m]:>12.1f}"
            f"  {campbell.whirl.values[-1, m]}"
        )
    crossings = sorted(summary["crossings"], key=lambda c: -c["excitability"])
    print(f"{len(crossings)} crossings; the most excitable:")
    for c in crossings[:10]:
        print(
            f"  {c['speed_rpm']:>12.2f} rpm  mode {c['mode']:>3}  {c['excitation']:<24} "
            f"{c['frequency_hz']:>10.1f} Hz  share {c['excitability']:.3f}"
        )
    if summary["unstable"]:
        for (start, stop), kind in zip(summary["unstable"], summary["unstable_kind"]):
            print(f"unstable ({kind}): {start:.6g} to {stop:.6g} rpm")
    else:
        print("no unstable speed in the range")


def _campbell(args: argparse.Namespace) -> int:
    if args.critical_speed_map is not None:
        return _critical_speed_map(args)
    if args.speeds is None:
        raise CaseError("--speeds START:STOP:COUNT is required (or --critical-speed-map)")
    start, stop, count = parse_range(args.speeds)
    if args.member not in MEMBERS:
        raise CaseError(f"--member must be one of {', '.join(MEMBERS)} (got {args.member!r})")
    harmonics = _harmonics(args.harmonics)
    if args.speed_terms not in SPEED_TERMS:
        raise CaseError(
            f"--speed-terms must be one of {', '.join(SPEED_TERMS)} (got {args.speed_terms!r})"
        )
    from ..runs.plan_checks import check_out_dir

    check_out_dir("--out", args.out, "campbell")
    import numpy as np

    from ..model.case import load_case  # NumPy and the model load only when the command runs

    case = load_case(args.case)
    if case.drivetrain is not None:
        if args.scene is not None or args.member != "carrier" or args.speed_terms != "all":
            raise CaseError(
                "--scene, --member and --speed-terms are for gearbox cases: a rotor or "
                "drivetrain case's speeds are the rotor's, its planets carry their frame "
                "terms, and its damping is always included"
            )
        return _rotor_campbell(case, args, np.linspace(start, stop, count))
    if args.scene is not None:
        scene = case.scene(args.scene)
    else:
        scene = next((s for s in case.scenes if "modal" in s.analyses), None)

    from ..analysis.modes.campbell import campbell_diagram
    from ..assembly.speed_terms import reference_label
    from ..io import save_figure, write_netcdf
    from ..plots.campbell import plot_campbell
    from ..runs.json_output import json_text

    reference_label(case, args.member)  # a case without a planetary stage, before any work
    campbell = campbell_diagram(
        case,
        np.linspace(start, stop, count),
        scene=scene,
        member=args.member,
        harmonics=harmonics,
        damping=args.damping,
        members=args.speed_terms,
    )
    out = args.out or Path("out") / case.name
    path = write_netcdf(
        campbell,
        out / "campbell.nc",
        input_hash=case.input_hash(),
        title=f"Campbell diagram of {case.name} over the speed of {campbell.attrs['reference']}",
    )
    drawing = plot_campbell(campbell)
    figure = save_figure(drawing, out / "campbell.png", dpi=drawing.dpi, release=True)
    summary = campbell_summary(campbell)
    if args.json:
        print(json_text({**summary, "files": [str(path), str(figure)]}))
        return 0
    _print_table(campbell, summary)
    print(f"wrote {path} and {figure}")
    return 0


def _rotor_campbell(case, args: argparse.Namespace, speeds) -> int:
    """A rotor or drivetrain case: the shafts' and discs' gyroscopic terms at their own
    speed ratios, speeds of the rotor, critical speeds from the 1x crossings."""
    from ..analysis.modes.sparse_gyroscopic import SOLVERS, rotor_campbell
    from ..assembly.drivetrain import assemble_drivetrain
    from ..assembly.speed_terms import drivetrain_frame_terms
    from ..io import save_figure, write_netcdf
    from ..plots.rotor import plot_rotor_campbell
    from ..runs.json_output import json_text

    if args.solver not in SOLVERS:
        raise CaseError(f"--solver must be one of {', '.join(SOLVERS)} (got {args.solver!r})")
    if args.modes < 1:
        raise CaseError(f"--modes must be at least 1 (got {args.modes})")
    model = assemble_drivetrain(case, dof_set="spatial")
    frame_terms = drivetrain_frame_terms(model, case)
    campbell = rotor_campbell(
        model, speeds, args.modes, solver=args.solver, frame_terms=frame_terms
    )
    out = args.out or Path("out") / case.name
    path = write_netcdf(
        campbell,
        out / "campbell.nc",
        input_hash=case.input_hash(),
        title=f"Campbell diagram of {case.name} over the rotor speed",
    )
    drawing = plot_rotor_campbell(campbell)
    figure = save_figure(drawing, out / "campbell.png", dpi=drawing.dpi, release=True)
    critical = [
        {"speed_rpm": float(s), "frequency_hz": float(f), "mode": int(m), "whirl": str(w)}
        for s, f, m, w in zip(
            campbell.critical_speed.values,
            campbell.critical_frequency.values,
            campbell.critical_mode.values,
            campbell.critical_whirl.values,
        )
    ]
    if args.json:
        summary = {
            "case": case.name,
            "dofs": model.size,
            "solver": campbell.attrs["solver"],
            "speed_ratios": model.speed_ratios,
            "gyroscopic": campbell.attrs["gyroscopic"],
            "speeds_rpm": campbell.speed.values.tolist(),
            "frequencies_hz": campbell.frequency.values.tolist(),
            "whirl": campbell.whirl.values.astype(str).tolist(),
            "critical_speeds": critical,
            "files": [str(path), str(figure)],
        }
        print(json_text(summary))
        return 0
    print(
        f"{case.name}: {model.size} DOFs, {campbell.attrs['solver']} solver, rotor speed "
        f"{speeds[0]:g} to {speeds[-1]:g} rpm ({speeds.size} speeds)"
    )
    print(f"{'mode':>4}  {'kind':<10} {'f start [Hz]':>12} {'f stop [Hz]':>12}  whirl at stop")
    for m in range(campbell.sizes["mode"]):
        print(
            f"{m + 1:>4}  {str(campbell.kind.values[-1, m]):<10} "
            f"{campbell.frequency.values[0, m]:>12.3f} {campbell.frequency.values[-1, m]:>12.3f}"
            f"  {campbell.whirl.values[-1, m]}"
        )
    print(f"{len(critical)} critical speeds (1x crossings):")
    for c in critical:
        print(f"  {c['speed_rpm']:>10.1f} rpm  mode {c['mode']:>3}  {c['whirl']:<9}")
    print(f"wrote {path} and {figure}")
    return 0


def _critical_speed_map(args: argparse.Namespace) -> int:
    """The undamped critical-speed map of a rotor or drivetrain case."""
    start, stop, count = parse_range(args.critical_speed_map, "--critical-speed-map", unit="N/m")
    if start <= 0:
        raise CaseError(f"--critical-speed-map must start above 0 N/m (got {start:g})")
    if args.speeds is not None or args.scene is not None or args.member != "carrier":
        raise CaseError("--critical-speed-map takes no --speeds, --scene or --member")
    if args.modes < 1:
        raise CaseError(f"--modes must be at least 1 (got {args.modes})")
    from ..runs.plan_checks import check_out_dir

    check_out_dir("--out", args.out, "campbell")
    import numpy as np

    from ..model.case import load_case

    case = load_case(args.case)
    if case.drivetrain is None:
        raise CaseError("--critical-speed-map is for rotor and drivetrain cases (shaft bearings)")
    from ..analysis.modes.critical_speeds import critical_speed_map
    from ..io import save_figure, write_netcdf
    from ..plots.critical_map import plot_critical_speed_map
    from ..runs.json_output import json_text

    critical = critical_speed_map(case, np.geomspace(start, stop, count), args.modes)
    out = args.out or Path("out") / case.name
    path = write_netcdf(
        critical,
        out / "critical_speed_map.nc",
        input_hash=case.input_hash(),
        title=f"Undamped critical-speed map of {case.name}",
    )
    drawing = plot_critical_speed_map(critical)
    figure = save_figure(drawing, out / "critical_speed_map.png", dpi=drawing.dpi, release=True)
    table = np.where(
        np.isfinite(critical.critical_speed.values), critical.critical_speed.values, None
    )
    if args.json:
        print(
            json_text(
                {
                    "case": case.name,
                    "bearing_stiffness_n_per_m": critical.bearing_stiffness.values.tolist(),
                    "lines": critical.line.values.tolist(),
                    "critical_speeds_rpm": table.tolist(),
                    "whirl": critical.whirl.values.astype(str).tolist(),
                    "files": [str(path), str(figure)],
                }
            )
        )
        return 0
    print(
        f"{case.name}: undamped critical speeds [rpm] against the radial stiffness of "
        f"{critical.attrs['bearings']} ({critical.attrs['dofs']} DOFs)"
    )
    for j, ratio in enumerate(critical.line.values):
        print(f"1x line of {critical.line_shafts.values[j]} ({ratio:g} x rotor):")
        for i, k in enumerate(critical.bearing_stiffness.values):
            row = "  ".join(
                f"{v:>10.1f} {str(w)[:1].upper()}" if np.isfinite(v) else f"{'-':>12}"
                for v, w in zip(critical.critical_speed.values[i, j], critical.whirl.values[i, j])
            )
            print(f"  {k:>10.3g} N/m  {row}")
    print(f"wrote {path} and {figure}")
    return 0


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {"campbell": _campbell}
"""Handlers of the commands :func:`add_parsers` adds; each returns the exit code."""
