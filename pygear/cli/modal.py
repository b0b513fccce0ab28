"""``pygear modal``, ``pygear matrices`` and ``pygear sensitivity``: the modal family.

Handlers import the analysis they run when called, so ``pygear --help`` loads none of it.
"""

from __future__ import annotations

import argparse
import logging
import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import CaseError
from ..model.names import DOF_SETS, FORMULATIONS
from ..runs.progress import ProgressBar

if TYPE_CHECKING:
    from ..analysis.modes.modal import ModalResult

__all__ = ["HANDLERS", "add_parsers"]

_log = logging.getLogger(__name__)


def _add_model_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("case", metavar="CASE", help="case directory or case name under cases/")
    parser.add_argument(
        "--formulation",
        choices=FORMULATIONS,
        help="model formulation (default: the scene's, else the case's)",
    )
    parser.add_argument(
        "--dof-set",
        choices=DOF_SETS,
        help="DOF set (default: the scene's, else the smallest exact one)",
    )


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``modal``, ``matrices`` and ``sensitivity`` subcommands."""
    modal = commands.add_parser("modal", help="natural frequencies and mode classes")
    _add_model_options(modal)
    modal.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    modal.add_argument("--out", type=Path, help="also write modal.nc and figures to this directory")
    modal.add_argument(
        "--compare-stage", metavar="STAGE", help="also compare STAGE alone with it in the gearbox"
    )
    modal.add_argument(
        "--modes",
        type=int,
        default=20,
        metavar="N",
        help="a drivetrain case: the N lowest modes (sparse shift-invert; default 20)",
    )
    modal.add_argument(
        "--below",
        metavar="FREQUENCY",
        help="a drivetrain case: every mode below FREQUENCY (e.g. 3000Hz or 3000)",
    )
    modal.add_argument(
        "--speed",
        type=float,
        metavar="RPM",
        help="the modes at this speed [rpm] (a rotor or drivetrain case: the rotor's, with "
        "the shafts' and discs' gyroscopic terms and the planets' frame terms; a gearbox "
        "case: the first planetary carrier's, else the input's, with Cooley & Parker's "
        "terms), with forward/backward whirl",
    )

    matrices = commands.add_parser("matrices", help="save the reduced M, K, C and DOF labels")
    _add_model_options(matrices)
    matrices.add_argument("--out", type=Path, required=True, help="target .npz file")

    sensitivity = commands.add_parser(
        "sensitivity", help="natural frequencies against a stiffness parameter (paper Fig. 7)"
    )
    sensitivity.add_argument("case", metavar="CASE", help="case directory or case name")
    sensitivity.add_argument(
        "--parameter",
        required=True,
        help="stiffness parameter path, e.g. planetary.sun_mesh.stiffness",
    )
    sensitivity.add_argument(
        "--values",
        nargs="+",
        required=True,
        help="values: numbers, linspace(a,b,n) or logspace(a,b,n)",
    )
    sensitivity.add_argument(
        "--formulation",
        nargs="+",
        choices=FORMULATIONS,
        help="one or more formulations (default: the case's)",
    )
    sensitivity.add_argument(
        "--dof-set",
        choices=DOF_SETS,
        help="DOF set (default: the smallest exact one for the case)",
    )
    sensitivity.add_argument("--out", type=Path, help="output directory (default: out/<case>)")
    sensitivity.add_argument("--json", action="store_true", help="print one JSON object")


def _print_modal_table(modal: ModalResult) -> None:
    """One row per mode; each column as wide as its longest entry (stage names and mode
    classes of any length stay aligned)."""
    print(
        f"{modal.attrs['case']}: {modal.attrs['formulation']} formulation, "
        f"{modal.attrs['dof_set']} DOF set ({modal.attrs['dof_set_reason']}), "
        f"{modal.frequency.size} modes"
    )
    several = len(modal.stages) > 1
    classes = [f"{c} {i}" for c, i in zip(modal.mode_class, modal.class_index)]
    class_width = max([len("class"), *map(len, classes)])
    stage_width = max([len("stage"), *(len(str(st)) for st in modal.stage_name)])
    stage_header = f"{'stage':<{stage_width}}  " if several else ""
    print(f"{'mode':>4}  {'frequency [Hz]':>14}  {stage_header}{'class':<{class_width}}  {'x':>2}")
    for m, f, st, label, r in zip(
        range(1, modal.frequency.size + 1),
        modal.frequency,
        modal.stage_name,
        classes,
        modal.multiplicity,
    ):
        stage = f"{st:<{stage_width}}  " if several else ""
        print(f"{m:>4}  {f:>14.1f}  {stage}{label:<{class_width}}  {r:>2}")


def _modal(args: argparse.Namespace) -> int:
    # the table needs NumPy alone: xarray, NetCDF and the figures load only with --out
    from ..analysis.modes.modal import modal_results
    from ..assembly.matrices import assemble
    from ..model.case import load_case
    from ..runs.json_output import json_text
    from ..runs.plan_checks import check_out_dir

    check_out_dir("--out", args.out, "modal --out")
    case = load_case(args.case)
    if case.drivetrain is not None:
        if args.speed is not None:
            return _modes_at_speed(case, args)
        return _drivetrain_modal(case, args)
    if args.speed is not None:
        return _gearbox_modes_at_speed(case, args)
    if args.below is not None:
        from ..errors import CaseError

        raise CaseError("--below is for drivetrain cases; a gearbox case gives every mode")
    started = time.perf_counter()
    model = assemble(case, formulation=args.formulation, dof_set=args.dof_set)
    modal = modal_results(model)
    elapsed = time.perf_counter() - started
    if args.out:
        from ..analysis.modes.modal import modal_dataset
        from ..runs.outputs import write_modal_outputs

        dataset = modal_dataset(modal)
        write_modal_outputs(case, None, model, dataset, args.out, f"modal_{model.formulation}")
    from ..runs.scene_runner import modal_summary

    summary = {**modal_summary(modal), "wall_s": elapsed}
    if args.compare_stage:
        from ..analysis.modes.modal import stage_comparison

        comparison = stage_comparison(case, args.compare_stage, model.formulation)
        summary["stage_comparison"] = {
            str(c): {
                "in_gearbox_hz": _finite_list(comparison.in_gearbox.sel(mode_class=c).values),
                "independent_hz": _finite_list(comparison.independent.sel(mode_class=c).values),
            }
            for c in comparison.mode_class.values
        }
    if args.json:
        print(json_text(summary))
        return 0
    _log.info("assembly and eigensolution: %.1f ms", elapsed * 1e3)
    _print_modal_table(modal)
    for family, table in summary.get("stage_comparison", {}).items():
        print(f"{args.compare_stage} {family}: in gearbox / alone [Hz]")
        for a, b in zip(table["in_gearbox_hz"], table["independent_hz"]):
            change = f"{(a / b - 1) * 100:+.2f} %" if b > 0 else ""
            print(f"  {a:>10.1f} {b:>10.1f} {change}")
    return 0


def _drivetrain_modal(case, args: argparse.Namespace) -> int:
    """A drivetrain case: its lowest ``--modes`` modes, spatial unless ``--dof-set``."""
    from ..analysis.modes.drivetrain_modal import drivetrain_modes
    from ..assembly.drivetrain import assemble_drivetrain, drivetrain_formulation
    from ..errors import CaseError
    from ..runs.json_output import json_text
    from ..runs.plan_checks import check_drivetrain_memory

    if args.modes < 1:
        raise CaseError(f"--modes must be at least 1 (got {args.modes})")
    below = _frequency_hz("--below", args.below) if args.below is not None else None
    if args.out or args.compare_stage:
        raise CaseError("--out and --compare-stage are for gearbox cases, not a drivetrain")
    # improved and consistent join the shafts; lin-parker (a rotating frame) is refused
    plain = case.drivetrain.gearbox is None  # a rotor: no gearbox, no formulation
    formulation = (
        None if plain else drivetrain_formulation(case, None, args.formulation, "--formulation")
    )
    check_drivetrain_memory(case, dense=False, dof_set=args.dof_set)  # before assembling
    started = time.perf_counter()
    model = assemble_drivetrain(case, dof_set=args.dof_set, formulation=formulation)
    if below is None and args.modes >= model.size:
        _log.warning(
            "--modes %d: the sparse eigensolver finds at most %d modes of a model of %d "
            "DOFs (one fewer than its DOFs); printing %d",
            args.modes,
            model.size - 1,
            model.size,
            model.size - 1,
        )
    modes = drivetrain_modes(model, args.modes, below_hz=below)
    elapsed = time.perf_counter() - started
    if args.json:
        summary = {
            "case": case.name,
            "formulation": "none" if plain else model.gearbox.formulation,
            "dof_set": model.dof_set,
            "dofs": model.size,
            "frequencies_hz": [float(f) for f in modes.frequencies_hz],
            "dominant_dof": modes.dominant,
            "wall_s": elapsed,
        }
        print(json_text(summary))
        return 0
    _log.info("drivetrain assembly and eigensolution: %.1f ms", elapsed * 1e3)
    print(
        f"{case.name}: "
        + ("rotor, " if plain else f"drivetrain, {model.gearbox.formulation} formulation, ")
        + f"{model.dof_set} DOF set, {model.size} DOFs, "
        f"{modes.frequencies_hz.size} lowest modes"
    )
    print(f"{'mode':>4}  {'frequency [Hz]':>14}  dominant DOF")
    for m, (f, label) in enumerate(zip(modes.frequencies_hz, modes.dominant), start=1):
        print(f"{m:>4}  {f:>14.3f}  {label}")
    return 0


def _modes_at_speed(case, args: argparse.Namespace) -> int:
    """A rotor or drivetrain case at ``--speed``: its lowest ``--modes`` modes with the
    shafts' and discs' gyroscopic terms, their whirl and kind."""
    from ..analysis.modes.sparse_gyroscopic import rotor_modes
    from ..assembly.drivetrain import assemble_drivetrain
    from ..assembly.speed_terms import drivetrain_frame_terms
    from ..errors import CaseError
    from ..runs.json_output import json_text

    if args.modes < 1:
        raise CaseError(f"--modes must be at least 1 (got {args.modes})")
    if not math.isfinite(args.speed):
        raise CaseError(f"--speed must be a finite number of rpm (got {args.speed!r})")
    if args.below is not None or args.out or args.compare_stage:
        raise CaseError("--below, --out and --compare-stage do not combine with --speed")
    model = assemble_drivetrain(case, dof_set="spatial")
    frame_terms = drivetrain_frame_terms(model, case)
    modes = rotor_modes(model, args.speed, args.modes, frame_terms=frame_terms)
    if args.json:
        print(
            json_text(
                {
                    "case": case.name,
                    "speed_rpm": args.speed,
                    "dofs": model.size,
                    "solver": modes.attrs["solver"],
                    "frequencies_hz": modes.frequency.values.tolist(),
                    "damping_ratios": modes.damping_ratio.values.tolist(),
                    "whirl": [str(w) for w in modes.whirl.values],
                    "kind": [str(k) for k in modes.kind.values],
                    "gyroscopic": modes.attrs["gyroscopic"],
                }
            )
        )
        return 0
    planets = "" if frame_terms is None else ", planets in their carriers' frames"
    print(
        f"{case.name}: {model.size} DOFs at {args.speed:g} rpm (gyroscopic terms of the "
        f"shafts and discs{planets}), {modes.attrs['solver']} solver, "
        f"{modes.sizes['mode']} modes"
    )
    print(f"{'mode':>4}  {'frequency [Hz]':>14}  {'damping':>8}  {'kind':<10} whirl")
    for m in range(modes.sizes["mode"]):
        print(
            f"{m + 1:>4}  {modes.frequency.values[m]:>14.4f}  "
            f"{modes.damping_ratio.values[m]:>8.4f}  {modes.kind.values[m]:<10} "
            f"{modes.whirl.values[m]}"
        )
    return 0


def _gearbox_modes_at_speed(case, args: argparse.Namespace) -> int:
    """A gearbox case at ``--speed`` of its first planetary carrier (else its input):
    every mode with Cooley & Parker's gyroscopic and centripetal terms."""
    from ..analysis.modes.gyroscopic import speed_dependent_modes
    from ..assembly.matrices import assemble
    from ..assembly.speed_terms import reference_label
    from ..errors import CaseError
    from ..model.components import PlanetaryStage
    from ..runs.json_output import json_text

    if not math.isfinite(args.speed):
        raise CaseError(f"--speed must be a finite number of rpm (got {args.speed!r})")
    if args.below is not None or args.out or args.compare_stage:
        raise CaseError("--below, --out and --compare-stage do not combine with --speed")
    planetary = any(isinstance(s, PlanetaryStage) for s in case.gearbox.stages)
    reference = reference_label(case, "carrier" if planetary else "input")
    model = assemble(case, formulation=args.formulation, dof_set=args.dof_set)
    modes = speed_dependent_modes(model, case, args.speed, reference=reference)
    if args.json:
        print(
            json_text(
                {
                    "case": case.name,
                    "speed_rpm": args.speed,
                    "reference": reference,
                    "dofs": len(model.dof_labels),
                    "frequencies_hz": modes.frequency.values.tolist(),
                    "whirl": [str(w) for w in modes.whirl.values],
                    "mode_class": [str(c) for c in modes.mode_class.values],
                    "stability": modes.stability.values.tolist(),
                    "speed_terms": modes.attrs["speed_terms"],
                }
            )
        )
        return 0
    print(
        f"{case.name}: {len(model.dof_labels)} DOFs, {model.formulation} formulation, "
        f"{reference} at {args.speed:g} rpm ({modes.attrs['speed_terms']}); frequencies "
        "in each planetary stage's carrier frame"
    )
    print(f"{'mode':>4}  {'frequency [Hz]':>14}  {'class':<14} {'whirl':<9} stability")
    for m in range(modes.sizes["mode"]):
        print(
            f"{m + 1:>4}  {modes.frequency.values[m]:>14.4f}  {modes.mode_class.values[m]:<14} "
            f"{modes.whirl.values[m]:<9} {int(modes.stability.values[m])}"
        )
    return 0


def _frequency_hz(option: str, text: str) -> float:
    """A frequency written ``3000``, ``3000Hz``, ``3 kHz`` [Hz]; CaseError otherwise."""
    from ..errors import CaseError

    compact = text.replace(" ", "").lower()
    scale = 1e3 if compact.endswith("khz") else 1.0
    number = compact.removesuffix("khz").removesuffix("hz")
    try:
        value = float(number) * scale
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise CaseError(f"{option} must be a positive frequency such as 3000Hz (got {text!r})")
    return value


def _finite_list(values) -> list[float]:
    return [float(v) for v in values if math.isfinite(v)]


def _matrices(args: argparse.Namespace) -> int:
    import numpy as np

    from ..assembly.matrices import assemble
    from ..io import check_suffix, write_npz
    from ..model.case import load_case

    check_suffix("--out", args.out, ".npz", "a NumPy archive of M, K, C and the DOF labels")
    if args.out.is_dir():
        raise CaseError(f"--out {str(args.out)!r} is a directory: matrices writes one .npz file")
    case = load_case(args.case)
    model = assemble(case, formulation=args.formulation, dof_set=args.dof_set)
    write_npz(
        args.out,
        M=model.mass,
        K=model.stiffness,
        C=model.damping,
        dof_labels=np.array(model.dof_labels),
        formulation=model.formulation,
        dof_set=model.dof_set,
    )
    print(f"wrote {args.out}: {model.size} DOFs ({model.formulation}, {model.dof_set})")
    return 0


def _sensitivity(args: argparse.Namespace) -> int:
    import numpy as np

    from ..analysis.modes.sensitivity import frequency_sweep, parse_values
    from ..io import save_figure, write_netcdf
    from ..model.case import load_case
    from ..plots.modal import plot_frequency_sweep
    from ..runs.json_output import json_text
    from ..runs.plan_checks import check_out_dir

    check_out_dir("--out", args.out, "sensitivity")
    case = load_case(args.case)
    values = parse_values(args.values)
    sweep = frequency_sweep(
        case,
        args.parameter,
        values,
        formulations=args.formulation,
        dof_set=args.dof_set,
        progress=ProgressBar("sensitivity", enabled=not args.json),
    )
    out = args.out or Path("out") / case.name
    stem = f"sensitivity_{args.parameter.replace('.', '_')}"
    path = write_netcdf(
        sweep,
        out / f"{stem}.nc",
        input_hash=case.input_hash(),
        title=f"Natural frequencies of {case.name} against {args.parameter}",
    )
    drawing = plot_frequency_sweep(sweep)
    figure = save_figure(drawing, out / f"{stem}.png", dpi=drawing.dpi, release=True)
    if args.json:
        print(
            json_text(
                {
                    "parameter": args.parameter,
                    "values": values.tolist(),
                    "formulations": [str(f) for f in sweep.formulation.values],
                    "frequencies_hz": np.nan_to_num(sweep.frequency.values).tolist(),
                    "files": [str(path), str(figure)],
                }
            )
        )
    else:
        print(f"wrote {path} and {figure}")
    return 0


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {
    "modal": _modal,
    "matrices": _matrices,
    "sensitivity": _sensitivity,
}
"""Handlers of the commands :func:`add_parsers` adds; each returns the exit code."""
