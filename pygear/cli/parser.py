"""The ``pygear`` command line."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from ..analysis.modal import modal_analysis
from ..analysis.signal import SignalError
from ..analysis.transient import runup_table_text, transient_summary
from ..assembly.matrices import assemble
from ..errors import CaseError
from ..io import write_netcdf
from ..kernel.calls import KernelError
from ..model.case import DOF_SETS, FORMULATIONS, Case, Scene, load_case
from ..runs.batch import HANDLERS as BATCH_HANDLERS
from ..runs.batch import add_parsers as add_batch_parsers
from ..runs.json_output import json_text
from ..runs.outputs import (
    write_modal_outputs,
    write_run_signals,
    write_signal_analysis,
)
from ..runs.progress import ProgressBar
from ..runs.scene_checks import check_scenes
from .accuracy import HANDLERS as ACCURACY_HANDLERS
from .accuracy import add_parser as add_accuracy_parser

__all__ = ["main"]


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


class _VersionAction(argparse.Action):
    """``--version``: the package and the kernel's BLAS (library, version, CPU core)."""

    def __init__(self, option_strings: list[str], dest: str, **kwargs: object) -> None:
        super().__init__(option_strings, dest, nargs=0, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None) -> None:  # noqa: ANN001
        from .._blas import kernel_blas
        from .._version import __version__

        blas = kernel_blas()
        print(f"pygear {__version__}")
        print(f"kernel BLAS: OpenBLAS {blas['version']}, core {blas['core']} ({blas['library']})")
        parser.exit(0)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every subcommand."""
    parser = argparse.ArgumentParser(prog="pygear", description=__doc__)
    parser.add_argument(
        "--version",
        action=_VersionAction,
        help="print the package version and the BLAS the kernel runs, then exit",
    )
    commands = parser.add_subparsers(dest="command", required=True)

    run = commands.add_parser("run", help="run a case's scenes and write results and figures")
    run.add_argument("case", metavar="CASE", help="case directory or case name under cases/")
    run.add_argument("--scene", action="append", help="scene to run (repeatable; default: all)")
    run.add_argument("--formulation", choices=FORMULATIONS, help="override every scene's")
    run.add_argument("--out", type=Path, help="output directory (default: out/<case>)")
    run.add_argument("--json", action="store_true", help="print a JSON summary on stdout")
    run.add_argument(
        "--checkpoint-every",
        type=float,
        metavar="S",
        help="transient scenes: save the state to DIR/<scene>.checkpoint.npz every S seconds "
        "of wall time and on Ctrl-C or SIGTERM",
    )
    run.add_argument(
        "--resume",
        action="store_true",
        help="transient scenes: continue from DIR/<scene>.checkpoint.npz when it exists "
        "(saved again on Ctrl-C or SIGTERM, removed once the result is written)",
    )

    modal = commands.add_parser("modal", help="natural frequencies and mode classes")
    _add_model_options(modal)
    modal.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    modal.add_argument("--out", type=Path, help="also write modal.nc and figures to this directory")
    modal.add_argument(
        "--compare-stage", metavar="STAGE", help="also compare STAGE alone with it in the gearbox"
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
    sensitivity.add_argument("--dof-set", choices=DOF_SETS)
    sensitivity.add_argument("--out", type=Path, help="output directory (default: out/<case>)")
    sensitivity.add_argument("--json", action="store_true", help="print one JSON object")
    analyze = commands.add_parser(
        "analyze", help="spectrum, envelope spectrum and DRA of a run's channel (Figs. 10-14)"
    )
    analyze.add_argument("run", metavar="RUN.nc", type=Path, help="a run's NetCDF file")
    analyze.add_argument("--channel", help="time series to analyse (default: an acceleration)")
    analyze.add_argument(
        "--band",
        nargs=2,
        type=float,
        default=(5000.0, 10000.0),
        metavar=("LOW", "HIGH"),
        help="DRA band [Hz] (default 5000 10000)",
    )
    analyze.add_argument("--after", type=float, default=1.0, help="skip the start-up [s]")
    analyze.add_argument("--mesh-frequency", type=float, help="mesh frequency [Hz] for labels")
    analyze.add_argument("--out", type=Path, help="output stem (default: beside RUN.nc)")
    analyze.add_argument("--json", action="store_true", help="print the peak tables as JSON")

    mesh = commands.add_parser(
        "mesh-stiffness", help="time-varying mesh stiffness at constant carrier speed (Fig. 3)"
    )
    mesh.add_argument("case", metavar="CASE", help="case directory or case name")
    mesh.add_argument("--speed", type=float, default=120.0, help="carrier speed [rpm]")
    mesh.add_argument("--duration", type=float, help="length [s] (default: 5 mesh cycles)")
    mesh.add_argument("--out", type=Path, required=True, help="target .nc file (figure beside)")
    add_batch_parsers(commands)
    add_accuracy_parser(commands)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit code (2 for bad input)."""
    args = build_parser().parse_args(argv)
    handler = {
        "run": _run,
        "modal": _modal,
        "matrices": _matrices,
        "sensitivity": _sensitivity,
        "mesh-stiffness": _mesh_stiffness,
        "analyze": _analyze,
        **BATCH_HANDLERS,
        **ACCURACY_HANDLERS,
    }[args.command]
    try:
        return handler(args)
    except (CaseError, KernelError, SignalError) as error:
        print(f"pygear {args.command}: error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as interrupt:  # Ctrl-C, or SIGTERM while a file is written
        print(f"pygear {args.command}: {interrupt or 'interrupted'}", file=sys.stderr)
        return 128 + getattr(interrupt, "signal_number", 2)  # 130 Ctrl-C, 143 SIGTERM


def _modal_summary(modal) -> dict:
    return {
        "case": modal.attrs["case"],
        "formulation": modal.attrs["formulation"],
        "dof_set": modal.attrs["dof_set"],
        "frequencies_hz": [float(f) for f in modal.frequency.values],
        "mode_class": [str(c) for c in modal.mode_class.values],
        "class_index": [int(i) for i in modal.class_index.values],
        "multiplicity": [int(m) for m in modal.multiplicity.values],
        "stage": [str(st) for st in modal.stage_name.values],
    }


def _print_modal_table(modal) -> None:
    print(
        f"{modal.attrs['case']}: {modal.attrs['formulation']} formulation, "
        f"{modal.attrs['dof_set']} DOF set ({modal.attrs['dof_set_reason']}), "
        f"{modal.sizes['mode']} modes"
    )
    several = modal.sizes["stage"] > 1
    stage_header = f"{'stage':<12} " if several else ""
    print(f"{'mode':>4}  {'frequency [Hz]':>14}  {stage_header}{'class':<22} {'x':>2}")
    for m, f, st, c, i, r in zip(
        modal.mode.values,
        modal.frequency.values,
        modal.stage_name.values,
        modal.mode_class.values,
        modal.class_index.values,
        modal.multiplicity.values,
    ):
        stage = f"{st:<12} " if several else ""
        print(f"{m:>4}  {f:>14.1f}  {stage}{c + ' ' + str(i):<22} {r:>2}")


def _modal(args: argparse.Namespace) -> int:
    case = load_case(args.case)
    started = time.perf_counter()
    model = assemble(case, formulation=args.formulation, dof_set=args.dof_set)
    modal = modal_analysis(model)
    elapsed = time.perf_counter() - started
    if args.out:
        write_modal_outputs(case, None, model, modal, args.out, f"modal_{model.formulation}")
    summary = {**_modal_summary(modal), "wall_s": elapsed}
    if args.compare_stage:
        from ..analysis.modal import stage_comparison

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
    _print_modal_table(modal)
    print(f"assembly and eigensolution: {elapsed * 1e3:.1f} ms")
    for family, table in summary.get("stage_comparison", {}).items():
        print(f"{args.compare_stage} {family}: in gearbox / alone [Hz]")
        for a, b in zip(table["in_gearbox_hz"], table["independent_hz"]):
            change = f"{(a / b - 1) * 100:+.2f} %" if b > 0 else ""
            print(f"  {a:>10.1f} {b:>10.1f} {change}")
    return 0


def _finite_list(values: np.ndarray) -> list[float]:
    return [float(v) for v in values if np.isfinite(v)]


def _matrices(args: argparse.Namespace) -> int:
    from ..io import check_suffix, write_npz

    check_suffix("--out", args.out, ".npz", "a NumPy archive of M, K, C and the DOF labels")
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
    print(
        f"wrote {args.out}: {model.size} DOFs ({model.formulation}, {model.dof_set})",
        file=sys.stderr,
    )
    return 0


def _sensitivity(args: argparse.Namespace) -> int:
    from ..analysis.sensitivity import frequency_sweep, parse_values
    from ..plots.modal import plot_frequency_sweep

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
    figure = out / f"{stem}.png"
    plot_frequency_sweep(sweep, figure)
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


def _analyze(args: argparse.Namespace) -> int:
    import xarray as xr

    from ..analysis.analyze import pick_channel
    from ..analysis.peaks import peak_table_text
    from ..runs.outputs import stored_references

    if not args.run.is_file():
        raise CaseError(f"RUN.nc {str(args.run)!r} does not exist")
    if args.out is not None and args.out.suffix.lower() in (".nc", ".png"):
        raise CaseError(
            f"--out {str(args.out)!r} is an output stem: STEM_<channel>.nc and .png are "
            f"written (drop the {args.out.suffix})"
        )
    with xr.open_dataset(args.run) as opened:
        run = opened.load()
    # the run file carries its own frequencies: nothing is loaded from the case it names
    natural, stored_mesh_frequency = stored_references(run, args.run)
    stem = args.out or args.run.with_name(args.run.stem)
    channel = pick_channel(run, args.channel)
    if stem.with_name(f"{stem.name}_{channel}.nc").resolve() == args.run.resolve():
        raise CaseError(f"--out {str(stem)!r} would write the spectra over RUN.nc itself")
    analysis, files = write_signal_analysis(
        run,
        stem,
        channel=channel,
        band=args.band,
        after=args.after,
        natural=natural,
        mesh_frequency=args.mesh_frequency or stored_mesh_frequency,
    )
    if args.json:
        print(json_text({**analysis.summary(), "files": [str(f) for f in files]}))
        return 0
    for name, table in analysis.peaks.items():
        print(peak_table_text(table, title=f"{name} of {analysis.channel}"))
    print(f"wrote {files[0]} and {files[1]}")
    return 0


def _mesh_stiffness(args: argparse.Namespace) -> int:
    from ..io import check_suffix
    from ..runs.mesh_stiffness import write_mesh_stiffness

    check_suffix("--out", args.out, ".nc", "the mesh stiffness as NetCDF (figure beside, .png)")
    if not np.isfinite(args.speed) or args.speed == 0:
        raise CaseError(
            f"--speed must be a finite non-zero carrier speed in rpm (got {args.speed})"
        )
    if args.duration is not None and not (np.isfinite(args.duration) and args.duration > 0):
        raise CaseError(f"--duration must be a positive number of seconds (got {args.duration})")
    dataset = write_mesh_stiffness(args.case, args.speed, args.duration, args.out)
    print(
        f"wrote {args.out} and {args.out.with_suffix('.png')}: "
        f"{dataset.sizes['mesh']} meshes, {dataset.sizes['time']} samples"
    )
    return 0


def _run(args: argparse.Namespace) -> int:
    case = base_case = load_case(args.case)
    scenes = [case.scene(name) for name in args.scene] if args.scene else list(case.scenes)
    out = args.out or Path("out") / case.name
    check_scenes(base_case, scenes, formulation=args.formulation, out=out)  # before any runs
    summary: dict = {"case": case.name, "scenes": {}}
    transients: dict = {}
    run_started = time.perf_counter()
    for scene in scenes:
        started = time.perf_counter()
        case = base_case.for_scene(scene)
        model = assemble(case, scene, formulation=args.formulation)
        entry: dict = {"formulation": model.formulation, "dof_set": model.dof_set, "files": []}
        if "modal" in scene.analyses:
            modal = modal_analysis(model)
            files = write_modal_outputs(case, scene, model, modal, out, scene.name)
            entry.update(_modal_summary(modal))
            entry["files"] += [str(p) for p in files]
        if "sensitivity" in scene.analyses:
            from ..analysis.sensitivity import frequency_sensitivity

            sensitivity = frequency_sensitivity(model)
            path = write_netcdf(
                sensitivity,
                out / f"{scene.name}_sensitivity.nc",
                input_hash=case.input_hash(),
                title=f"Frequency sensitivities of {case.name}",
            )
            entry["files"].append(str(path))
        if "transient" in scene.analyses:
            try:
                dataset, files = _run_transient(case, scene, model, out, args)
            except KeyboardInterrupt as interrupt:
                print(f"pygear run: scene {scene.name}: {interrupt}", file=sys.stderr)
                return 128 + getattr(interrupt, "signal_number", 2)  # 130 Ctrl-C, 143 SIGTERM
            transients[scene.name] = dataset
            entry.update(transient_summary(dataset))
            entry["files"] += [str(p) for p in files]
            if "signal" in scene.analyses:
                written = write_run_signals(case, model, dataset, out, scene.name)
                entry["files"] += [str(p) for p in written]
        entry["wall_s"] = time.perf_counter() - started
        summary["scenes"][scene.name] = entry
        if not args.json:
            print(
                f"scene {scene.name}: {model.formulation}, {model.dof_set} "
                f"({model.size} DOFs), {entry['wall_s'] * 1e3:.0f} ms"
            )
            for path in entry["files"]:
                print(f"  wrote {path}")
    if len(transients) > 1:
        summary["files"] = [str(_compare_transients(transients, out))]
    summary["wall_s"] = time.perf_counter() - run_started
    if args.json:
        print(json_text(summary))
    elif transients:
        print(runup_table_text(transients))
    return 0


def _run_transient(case: Case, scene: Scene, model, out: Path, args: argparse.Namespace):
    """One transient scene: run it with a progress bar and write ``<scene>.nc``."""
    from ..runs.transient_outputs import write_transient

    progress = ProgressBar(f"{scene.name}", enabled=not args.json)
    checkpoint = out / f"{scene.name}.checkpoint.npz"
    every = args.checkpoint_every
    if every is not None and not every > 0:
        raise CaseError(f"--checkpoint-every must be a positive number of seconds (got {every})")
    return write_transient(
        case,
        scene,
        out,
        progress=progress,
        model=model,
        # resuming keeps the file current: saved again on a signal, removed when done
        checkpoint=checkpoint if every is not None or args.resume else None,
        checkpoint_every=every if every is not None else float("inf"),
        resume=checkpoint if args.resume and checkpoint.is_file() else None,
    )


def _compare_transients(transients: dict, out: Path) -> Path:
    """The speeds of several transient scenes side by side (seed Figure 9)."""
    from ..io import atomic_path
    from ..plots.transient import plot_speeds

    target = out / "transient_speeds.png"
    with atomic_path(target) as temporary:
        plot_speeds(list(transients.values()), temporary, format="png")
    return target


if __name__ == "__main__":
    sys.exit(main())
