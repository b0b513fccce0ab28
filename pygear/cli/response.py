"""``pygear response``: the periodic steady state over a speed range (dynamic factors,
load sharing, stability) by harmonic balance.

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

__all__ = [
    "HANDLERS",
    "add_parsers",
    "parse_harmonics",
    "parse_pin_errors",
    "parse_torque",
]

MAX_HARMONICS = 1024
"""Largest harmonic count --harmonics takes."""

MAX_BRANCH_HARMONICS = 128
"""Largest harmonic count with --contact-loss: the branch's Jacobian is dense in
n_mesh (2H + 1) unknowns (1542 for six meshes at 128)."""


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``response`` subcommand."""
    response = commands.add_parser(
        "response",
        help="periodic steady state over speed: dynamic factor, load sharing, stability",
    )
    response.add_argument("case", metavar="CASE", help="case directory or case name under cases/")
    response.add_argument(
        "--scene", help="scene whose parameters, model choices and input/output members apply"
    )
    response.add_argument(
        "--speeds",
        required=True,
        metavar="START:STOP:COUNT",
        help="input member speeds [rpm]: COUNT equally spaced from START to STOP, START > 0",
    )
    response.add_argument(
        "--harmonics",
        default="auto",
        help="harmonics of the mesh frequency balanced: auto (chosen per speed by "
        "--tolerance) or a whole number (default auto)",
    )
    response.add_argument(
        "--tolerance",
        default="5e-3",
        help="residual the automatic harmonic count reaches (default 5e-3)",
    )
    response.add_argument(
        "--pin-error",
        action="append",
        default=[],
        metavar="PLANET=METRES",
        help="tangential pin position error of a planet, e.g. planetary.planet1=10e-6 (repeatable)",
    )
    response.add_argument(
        "--torque",
        metavar="T",
        help="drive torque on the input member [N m], > 0 (default the scene's drive torque)",
    )
    response.add_argument(
        "--contact-loss",
        action="store_true",
        help="where the linear sweep separates the teeth, continue the response with the "
        "backlash flank law in speed through its folds: response_backlash.nc, its figure "
        "and the jump speeds (harmonics: --harmonics when a number, else 16)",
    )
    response.add_argument(
        "--no-stability", action="store_true", help="skip the Floquet multipliers"
    )
    response.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    response.add_argument(
        "--out", type=Path, help="directory of response.nc and its figures (default out/<case>)"
    )
    response.add_argument("--no-figures", action="store_true", help="write the dataset only")


def parse_harmonics(text: str) -> int | str:
    """``auto`` or a whole number 0..:data:`MAX_HARMONICS`."""
    if str(text).strip().lower() == "auto":
        return "auto"
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value == int(value) and 0 <= value <= MAX_HARMONICS):
        raise CaseError(
            f"--harmonics must be auto or a whole number from 0 to {MAX_HARMONICS} (got {text!r})"
        )
    return int(value)


def _tolerance(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and 0 < value < 1):
        raise CaseError(f"--tolerance must be a number between 0 and 1 (got {text!r})")
    return value


def parse_pin_errors(items: list[str]) -> dict[str, float]:
    """``PLANET=METRES`` items as a dict."""
    errors: dict[str, float] = {}
    for item in items:
        name, sep, value = str(item).partition("=")
        try:
            metres = float(value)
        except ValueError:
            metres = math.nan
        if not (sep and name and math.isfinite(metres)):
            raise CaseError(
                f"--pin-error must read PLANET=METRES, e.g. planetary.planet1=10e-6 (got {item!r})"
            )
        errors[name] = metres
    return errors


def parse_torque(text: str | None) -> float | None:
    """``--torque``: a finite number > 0 [N m], or None when not given."""
    if text is None:
        return None
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise CaseError(f"--torque must be a finite number > 0 [N m] (got {text!r})")
    return value


def _print_jumps(summary: dict, branch) -> None:
    if branch is None:
        print("contact loss: no mesh separates in the linear sweep, no branch")
        return
    for mesh in summary["jump_up_rpm"]:
        up, down = summary["jump_up_rpm"][mesh], summary["jump_down_rpm"][mesh]
        if up or down:
            ups = ", ".join(f"{v:.1f}" for v in up) or "-"
            downs = ", ".join(f"{v:.1f}" for v in down) or "-"
            print(f"{mesh}: up-sweep jumps at {ups} rpm, down-sweep jumps at {downs} rpm")
    print(f"contact-loss branch: {branch.sizes['point']} points, "
          f"{branch.attrs['harmonics']} harmonics, {branch.attrs['wall_s']:.1f} s")  # fmt: skip


def _print_table(response, summary: dict) -> None:
    attrs = response.attrs
    speeds = response.speed.values
    print(
        f"{attrs['case']}: {attrs['formulation']} formulation, {attrs['dof_set']} DOF set, "
        f"{attrs['input']} {speeds[0]:g} to {speeds[-1]:g} rpm ({speeds.size} speeds), "
        f"{attrs['wall_s']:.2f} s"
    )
    if int(attrs.get("frequency_groups", 1)) > 1:
        print(f"multi-frequency balance: {attrs['frequency_groups']} frequency groups of "
              "meshes at incommensurate mesh frequencies; stability per group")  # fmt: skip
    print(f"{'mesh':<28} {'max K_v':>8} {'at rpm':>10} {'max DTE rms [m]':>16}  separation")
    for i, mesh in enumerate(response.mesh.values):
        kv = response.dynamic_factor.values[:, i]
        k = int(kv.argmax())
        separated = speeds[response.separation.values[:, i] > 0]
        where = f"from {separated[0]:g} rpm" if separated.size else "none"
        print(f"{str(mesh):<28} {kv[k]:>8.3f} {speeds[k]:>10.1f} "
              f"{response.dte_rms.values[:, i].max():>16.3e}  {where}")  # fmt: skip
    for stage, values in summary["load_sharing"].items():
        print(f"K_gamma {stage}: {min(values):.4f} to {max(values):.4f}")
    if "stable" in response:
        unstable = speeds[response.stable.values == 0]
        print(f"unstable at {unstable.size} speeds" + (
            f" ({unstable[0]:g} to {unstable[-1]:g} rpm)" if unstable.size else ""))  # fmt: skip
    print(f"harmonics {min(summary['harmonics'])} to {max(summary['harmonics'])}, "
          f"largest residual {max(summary['residual']):.2e}")  # fmt: skip


def _response(args: argparse.Namespace) -> int:
    start, stop, count = parse_range(args.speeds, single=True)
    harmonics = parse_harmonics(args.harmonics)
    tolerance = _tolerance(args.tolerance)
    pin_errors = parse_pin_errors(args.pin_error)
    torque = parse_torque(args.torque)
    if args.contact_loss and harmonics != "auto" and not 1 <= harmonics <= MAX_BRANCH_HARMONICS:
        raise CaseError(f"--harmonics must be auto or 1-{MAX_BRANCH_HARMONICS} with "
                        f"--contact-loss (got {args.harmonics!r})")  # fmt: skip
    if args.out is not None and args.out.exists() and not args.out.is_dir():
        raise CaseError(f"--out {str(args.out)!r} is a file: response writes into a directory")
    from ..model.case import load_case  # NumPy and the model load only when the command runs

    case = load_case(args.case)
    if case.gearbox is None:
        raise CaseError(
            f"case {case.name!r} is a plain rotor (no gear mesh): its response over speed "
            f"is the unbalance response, pygear frf {args.case} --speeds {args.speeds} "
            "--unbalance DISC:ME:PHASE"
        )
    scene = case.scene(args.scene) if args.scene is not None else None

    import numpy as np

    from ..analysis.response import contact_loss_response, forced_response, response_summary
    from ..runs.json_output import json_text
    from ..runs.progress import ProgressBar
    from ..runs.response_outputs import write_response

    options = dict(
        scene=scene,
        harmonics=harmonics,
        tolerance=tolerance,
        stability=not args.no_stability,
        pin_errors=pin_errors or None,
        torque=torque,
        progress=ProgressBar("response", enabled=not args.json),
    )
    speeds = np.linspace(start, stop, count)
    branch = None
    if args.contact_loss:
        response, branch = contact_loss_response(case, speeds, **options)
    else:
        response = forced_response(case, speeds, **options)
    out = args.out or Path("out") / case.name
    paths = write_response(case, response, out, figures=not args.no_figures, branch=branch)
    summary = response_summary(response, branch, contact_loss=args.contact_loss)
    if args.json:
        print(json_text({**summary, "files": [str(p) for p in paths]}))
        return 0
    _print_table(response, summary)
    if args.contact_loss:
        _print_jumps(summary, branch)
    print("wrote " + ", ".join(str(p) for p in paths))
    return 0


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {"response": _response}
"""Handlers of the commands :func:`add_parsers` adds; each returns the exit code."""
