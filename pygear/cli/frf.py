"""``pygear frf``: unbalance response of a rotor or drivetrain case over speed (Bode and
polar plots, API 684 amplification factors and separation margins), or a frequency
response function between two DOFs.

The handler checks every option before it loads the analysis.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from pathlib import Path

from ..errors import CaseError
from .ranges import parse_range

__all__ = ["HANDLERS", "add_parsers", "parse_unbalance"]


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``frf`` subcommand."""
    frf = commands.add_parser(
        "frf", help="rotor unbalance response (Bode, polar, API 684 margins) or an FRF"
    )
    frf.add_argument("case", metavar="CASE", help="case directory or case name under cases/")
    frf.add_argument(
        "--speeds",
        metavar="START:STOP:COUNT",
        help="rotor speeds [rpm] of the unbalance response: COUNT from START to STOP",
    )
    frf.add_argument(
        "--unbalance",
        action="append",
        default=[],
        metavar="DISC:ME:PHASE",
        help="unbalance m e [kg m] on a disc at PHASE [deg]; repeat for several discs",
    )
    frf.add_argument(
        "--operating",
        metavar="MIN:MAX",
        help="operating speed range [rpm] for API 684's separation margins",
    )
    frf.add_argument(
        "--frf",
        metavar="OUTPUT,INPUT",
        help="instead: the FRF between two DOF labels (shaft_3.x,shaft_3.x)",
    )
    frf.add_argument(
        "--frequencies",
        metavar="START:STOP:COUNT",
        help="frequencies [Hz] of --frf",
    )
    frf.add_argument("--speed", type=float, default=0.0, help="rotor speed of --frf [rpm]")
    frf.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    frf.add_argument("--out", type=Path, help="output directory (default out/<case>)")


def parse_unbalance(text: str) -> tuple[str, float, float]:
    """``DISC:ME:PHASE`` as (disc, m e [kg m] >= 0, phase [deg]); PHASE may be left out."""
    parts = str(text).split(":")
    rule = "--unbalance must read DISC:ME:PHASE with ME >= 0 [kg m] and PHASE [deg]"
    if len(parts) not in (2, 3) or not parts[0]:
        raise CaseError(f"{rule} (got {text!r})")
    try:
        moment = float(parts[1])
        phase = float(parts[2]) if len(parts) == 3 else 0.0
    except ValueError:
        raise CaseError(f"{rule} (got {text!r})") from None
    if not (math.isfinite(moment) and moment >= 0 and math.isfinite(phase)):
        raise CaseError(f"{rule} (got {text!r})")
    return parts[0], moment, phase


def _range(option: str, text: str) -> tuple[float, float]:
    parts = str(text).split(":")
    try:
        low, high = (float(p) for p in parts)
    except ValueError:
        raise CaseError(f"{option} must read MIN:MAX with 0 <= MIN <= MAX (got {text!r})") from None
    if not (math.isfinite(low) and math.isfinite(high) and 0 <= low <= high):
        raise CaseError(f"{option} must read MIN:MAX with 0 <= MIN <= MAX (got {text!r})")
    return low, high


def _frf(args: argparse.Namespace) -> int:
    if args.frf is None and args.speeds is None:
        raise CaseError("--speeds START:STOP:COUNT is required (or --frf with --frequencies)")
    if args.frf is not None:
        if args.frequencies is None:
            raise CaseError("--frf needs --frequencies START:STOP:COUNT [Hz]")
        f_start, f_stop, f_count = parse_range(args.frequencies, "--frequencies", unit="Hz")
        pair = args.frf.split(",")
        if len(pair) != 2:
            raise CaseError(f"--frf must read OUTPUT,INPUT (two DOF labels) (got {args.frf!r})")
    else:
        start, stop, count = parse_range(args.speeds)
        if not args.unbalance:
            raise CaseError("--unbalance DISC:ME:PHASE is required with --speeds")
        unbalances = [parse_unbalance(text) for text in args.unbalance]
    operating = _range("--operating", args.operating) if args.operating else None
    if not math.isfinite(args.speed):
        raise CaseError(f"--speed must be a finite number of rpm (got {args.speed!r})")
    from ..runs.plan_checks import check_out_dir

    check_out_dir("--out", args.out, "frf")
    import numpy as np

    from ..analysis.response.rotor import (
        Unbalance,
        amplification_factors,
        frequency_response,
        unbalance_response,
    )
    from ..assembly.drivetrain import assemble_drivetrain
    from ..assembly.speed_terms import drivetrain_frame_terms, with_frame_terms
    from ..io import save_figure, write_netcdf
    from ..model.case import load_case
    from ..runs.json_output import json_text

    case = load_case(args.case)
    if case.drivetrain is None:
        raise CaseError(f"case {case.name!r} has no shafts: frf needs a rotor or drivetrain case")
    model = assemble_drivetrain(case, dof_set="spatial")
    model = with_frame_terms(model, drivetrain_frame_terms(model, case))  # planets' terms
    out = args.out or Path("out") / case.name
    if args.frf is not None:
        result = frequency_response(
            model, pair[0], pair[1], np.linspace(f_start, f_stop, f_count), args.speed
        )
        path = write_netcdf(result, out / "frf.nc", input_hash=case.input_hash(), title="FRF")
        summary = {
            "case": case.name,
            "output": pair[0],
            "input": pair[1],
            "speed_rpm": args.speed,
            "frequencies_hz": result.frequency.values.tolist(),
            "amplitude_m_per_n": result.amplitude.values.tolist(),
            "phase_deg": result.phase.values.tolist(),
            "files": [str(path)],
        }
        if args.json:
            print(json_text(summary))
        else:
            peak = int(np.argmax(result.amplitude.values))
            print(
                f"{case.name}: FRF {pair[0]} / {pair[1]} at {args.speed:g} rpm, "
                f"largest {result.amplitude.values[peak]:.4g} m/N at "
                f"{result.frequency.values[peak]:.4g} Hz; wrote {path}"
            )
        return 0
    from ..plots.rotor import plot_unbalance_response

    response = unbalance_response(
        model,
        case.drivetrain,
        [Unbalance(*u) for u in unbalances],
        np.linspace(start, stop, count),
    )
    path = write_netcdf(
        response, out / "unbalance.nc", input_hash=case.input_hash(), title="Unbalance response"
    )
    drawing = plot_unbalance_response(response)
    figure = save_figure(drawing, out / "unbalance.png", dpi=drawing.dpi, release=True)
    peaks = {
        str(location): amplification_factors(
            response.speed.values,
            response.sel(location=location).major_axis.values,
            operating,
        )
        for location in response.location.values
    }
    if args.json:
        print(
            json_text(
                {
                    "case": case.name,
                    "unbalance": response.attrs["unbalance"],
                    "speeds_rpm": response.speed.values.tolist(),
                    "major_axis_m": {
                        str(loc): response.sel(location=loc).major_axis.values.tolist()
                        for loc in response.location.values
                    },
                    "peaks": peaks,
                    "files": [str(path), str(figure)],
                }
            )
        )
        return 0
    print(f"{case.name}: unbalance {response.attrs['unbalance']}, {start:g} to {stop:g} rpm")
    print(
        f"{'location':<16} {'N_c [rpm]':>10} {'peak [m]':>11} {'AF':>7} {'SM req %':>9} {'SM %':>7}"
    )
    for location, found in peaks.items():
        for p in found:

            def shown(value, form):
                return format(value, form) if value is not None else "-"

            print(
                f"{location:<16} {p['speed_rpm']:>10.1f} {p['peak']:>11.4g} "
                f"{shown(p['amplification_factor'], '7.2f'):>7} "
                f"{shown(p['required_margin_pct'], '9.1f'):>9} "
                f"{shown(p['actual_margin_pct'], '7.1f'):>7}"
            )
    print(f"wrote {path} and {figure}")
    return 0


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {"frf": _frf}
"""Handlers of the commands :func:`add_parsers` adds; each returns the exit code."""
