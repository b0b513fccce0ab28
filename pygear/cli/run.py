"""``pygear run``, ``pygear analyze`` and ``pygear mesh-stiffness``: running scenes and
reading their results.

Handlers import the analyses and writers they use when called, so ``pygear --help``
loads none of them.
"""

from __future__ import annotations

import argparse
import logging
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path

from ..errors import CaseError
from ..model.names import FORMULATIONS, LAWS
from ..resources import format_bytes
from ..runs.progress import ProgressBar, progress_wanted

__all__ = ["HANDLERS", "add_parsers"]

_log = logging.getLogger(__name__)


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``run``, ``analyze`` and ``mesh-stiffness`` subcommands."""
    run = commands.add_parser("run", help="run a case's scenes and write results and figures")
    run.add_argument("case", metavar="CASE", help="case directory or case name under cases/")
    run.add_argument("--scene", action="append", help="scene to run (repeatable; default: all)")
    run.add_argument("--formulation", choices=FORMULATIONS, help="override every scene's")
    run.add_argument("--out", type=Path, help="output directory (default: out/<case>)")
    run.add_argument("--json", action="store_true", help="print a JSON summary on stdout")
    run.add_argument(
        "--no-figures",
        action="store_true",
        help="write the NetCDF results only (figures are otherwise drawn after them)",
    )
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

    analyze = commands.add_parser(
        "analyze", help="spectrum, envelope spectrum and DRA of a run's channel (Figs. 10-14)"
    )
    analyze.add_argument("run", metavar="RUN.nc", type=Path, help="a run's NetCDF file")
    analyze.add_argument(
        "--channel",
        help="time series to analyse: KIND:LABEL (acceleration:planetary.sun.theta_z, "
        "speed:planetary.carrier), a label one channel has, or a variable's name "
        "(default: the first acceleration)",
    )
    analyze.add_argument(
        "--band",
        nargs=2,
        type=float,
        metavar=("LOW", "HIGH"),
        help="DRA band [Hz] (default: a quarter to a half of the file's Nyquist frequency, "
        "5000 10000 at 40 kHz)",
    )
    analyze.add_argument(
        "--after",
        type=float,
        help="skip the start-up [s] (default: 1 s, 0.5 s with --tsa, at most half the run "
        "and never before its settling instant t_s; 0 with --orders)",
    )
    analyze.add_argument("--mesh-frequency", type=float, help="mesh frequency [Hz] for labels")
    analyze.add_argument(
        "--out",
        type=Path,
        help="output stem (default: beside RUN.nc); with --orders a directory "
        "(default: RUN_orders/ beside RUN.nc)",
    )
    analyze.add_argument("--json", action="store_true", help="print the peak tables as JSON")
    analyze.add_argument(
        "--orders",
        metavar="MEMBER",
        help="computed order tracking against MEMBER's angle (e.g. planetary.carrier): "
        "order spectrum, order-speed map and order slices in orders.nc and figures",
    )
    analyze.add_argument(
        "--max-order",
        type=float,
        help="--orders: highest order kept (default: the highest the time sampling resolves)",
    )
    analyze.add_argument(
        "--tsa",
        metavar="GEAR",
        help="synchronous average of GEAR (sun, ring, planet<n>) in a sensor channel, "
        "McFadden's windowed averages for the sun and the planets: RUN_tsa_<stage>_<gear>.nc "
        "and .png",
    )
    analyze.add_argument(
        "--indicators",
        action="store_true",
        help="--tsa: also FM0, FM4, NA4, NB4, M6A, M8A, ER, SLF, kurtosis, crest factor and "
        "the sensor's kurtogram (best band)",
    )
    analyze.add_argument(
        "--no-figures", action="store_true", help="--tsa: write the NetCDF file only"
    )
    analyze.add_argument(
        "--tachometer",
        type=int,
        metavar="PULSES",
        help="--tsa: average on the angles of a synthetic carrier tachometer with PULSES "
        "marks a turn (the sun's and planets' from the kinematics) instead of the simulated",
    )
    analyze.add_argument(
        "--jitter", type=float, default=0.0, help="--tachometer: timing jitter [s] (default 0)"
    )
    analyze.add_argument(
        "--bearing-envelope",
        action="store_true",
        help="bearing diagnostics: pre-whitening, the kurtogram's band, the squared envelope "
        "spectrum; lists the bearing lines found (BPFO, BPFI, BSF the run file stores, or "
        "--bpfo/--bpfi) with harmonics, sidebands and SNRs",
    )
    analyze.add_argument("--bpfo", type=float, metavar="HZ", help="--bearing-envelope: BPFO [Hz]")
    analyze.add_argument("--bpfi", type=float, metavar="HZ", help="--bearing-envelope: BPFI [Hz]")
    analyze.add_argument(
        "--shaft-frequency",
        type=float,
        metavar="HZ",
        help="--bpfi: shaft rate whose sidebands about BPFI are looked for [Hz]",
    )
    analyze.add_argument(
        "--drs",
        action="store_true",
        help="--bearing-envelope: remove the gears' discrete components by discrete-random "
        "separation before the pre-whitening",
    )
    analyze.add_argument(
        "--window-revolutions",
        type=float,
        default=1.0,
        help="--orders: revolutions per order-map window; order resolution 1/W (default 1)",
    )

    mesh = commands.add_parser(
        "mesh-stiffness",
        help="each mesh's law and time-varying stiffness at constant carrier speed (Fig. 3)",
    )
    mesh.add_argument("case", metavar="CASE", help="case directory or case name")
    mesh.add_argument("--scene", help="scene whose parameters and tooth defects apply")
    mesh.add_argument(
        "--law", choices=LAWS, help="run every mesh with this single-pair stiffness law"
    )
    mesh.add_argument("--speed", type=float, default=120.0, help="carrier speed [rpm]")
    mesh.add_argument("--duration", type=float, help="length [s] (default: 5 mesh cycles)")
    mesh.add_argument("--out", type=Path, help="also write this .nc file (figure beside)")
    mesh.add_argument(
        "--json", action="store_true", help='print {"meshes": {NAME: {...}}} in SI units'
    )


def _analyze(args: argparse.Namespace) -> int:
    from ..analysis.signals.analyze import pick_channel
    from ..analysis.signals.channels import channel_file_part
    from ..analysis.signals.peaks import peak_table_text
    from ..analysis.signals.record_checks import (
        check_band,
        check_record_time,
        default_after,
        default_band,
        record_sample_rate,
    )
    from ..model.case import SIGNAL_AFTER
    from ..runs.json_output import json_text
    from ..runs.outputs import read_run_file, stored_references, write_signal_analysis

    if args.orders is not None:
        from .orders import analyze_orders

        return analyze_orders(args)
    if args.tsa is not None:
        from .condition import analyze_tsa

        return analyze_tsa(args)
    if args.bearing_envelope:
        from .bearing import analyze_bearing_envelope

        return analyze_bearing_envelope(args)
    if args.bpfo is not None or args.bpfi is not None or args.drs:
        raise CaseError(
            "--bpfo/--bpfi/--drs: ask for the bearing envelope with --bearing-envelope"
        )
    if args.indicators:
        raise CaseError("--indicators: name the gear to average with --tsa GEAR")
    if args.out is not None and args.out.suffix.lower() in (".nc", ".png"):
        raise CaseError(
            f"--out {str(args.out)!r} is an output stem: STEM_<channel>.nc and .png are "
            f"written (drop the {args.out.suffix})"
        )
    run = read_run_file(
        args.run,
        "analyze needs a transient's result with series over time "
        "(`pygear run` of a scene with a 'transient' analysis)",
    )
    source = f"RUN.nc {str(args.run)!r}"
    # defaults follow the file: its settling instant, its Nyquist frequency
    after = default_after(run, SIGNAL_AFTER) if args.after is None else args.after
    kept = check_record_time(run, source, after)
    rate = record_sample_rate(kept)
    band = default_band(rate) if args.band is None else tuple(args.band)
    check_band(band, rate, kept.size, source)
    # the run file carries its own frequencies: nothing is loaded from the case it names
    natural, stored_mesh_frequency = stored_references(run, args.run)
    stem = args.out or args.run.with_name(args.run.stem)
    channel = pick_channel(run, args.channel)
    spectra = stem.with_name(f"{stem.name}_{channel_file_part(channel)}.nc")
    if spectra.resolve() == args.run.resolve():
        raise CaseError(f"--out {str(stem)!r} would write the spectra over RUN.nc itself")
    analysis, files = write_signal_analysis(
        run,
        stem,
        channel=channel,
        band=band,
        after=after,
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
    from ..runs.json_output import json_text
    from ..runs.mesh_stiffness import mesh_stiffness_report

    if args.out is not None:
        check_suffix("--out", args.out, ".nc", "the mesh stiffness as NetCDF (figure beside, .png)")
        if args.out.is_dir():
            raise CaseError(f"--out {str(args.out)!r} is a directory: name the .nc file to write")
    if not math.isfinite(args.speed) or args.speed == 0:
        raise CaseError(
            f"--speed must be a finite non-zero carrier speed in rpm (got {args.speed})"
        )
    if args.duration is not None and not (math.isfinite(args.duration) and args.duration > 0):
        raise CaseError(f"--duration must be a positive number of seconds (got {args.duration})")
    dataset, summary = mesh_stiffness_report(
        args.case, args.speed, args.duration, args.out, scene=args.scene, law=args.law
    )
    if args.json:
        print(json_text({"meshes": summary}))
        return 0
    print(f"{'mesh':<24} {'law':<17} {'mean N/m':>10} {'max N/m':>10} {'eps_a':>6} {'eps_b':>6}")
    for name, entry in summary.items():
        print(
            f"{name:<24} {entry['law']:<17} {entry['mean_stiffness']:>10.4g} "
            f"{entry['max_stiffness']:>10.4g} {entry['transverse_contact_ratio']:>6.3f} "
            f"{entry['overlap_ratio']:>6.3f}"
        )
    if args.out is not None:
        print(
            f"wrote {args.out} and {args.out.with_suffix('.png')}: "
            f"{dataset.sizes['mesh']} meshes, {dataset.sizes['time']} samples"
        )
    return 0


def _run(args: argparse.Namespace) -> int:
    from ..analysis.time.transient import runup_table_text
    from ..model.case import load_case
    from ..runs.json_output import json_text
    from ..runs.plan_checks import check_out_dir
    from ..runs.scene_checks import check_scenes
    from ..runs.scene_runner import RunOptions, run_scene

    every = args.checkpoint_every
    if every is not None and not every > 0:
        raise CaseError(f"--checkpoint-every must be a positive number of seconds (got {every})")
    check_out_dir("--out", args.out, "run")
    case = load_case(args.case)
    scenes = [case.scene(name) for name in args.scene] if args.scene else list(case.scenes)
    out = args.out or Path("out") / case.name
    # before any runs; the result files each transient scene will write at most
    file_sizes = check_scenes(case, scenes, formulation=args.formulation, out=out)
    summary: dict = {"case": case.name, "scenes": {}}
    transients: dict = {}
    run_started = time.perf_counter()
    for scene in scenes:
        if scene.name in file_sizes and not args.json and progress_wanted():
            print(
                f"{scene.name}: result files of at most {format_bytes(file_sizes[scene.name])}"
                " (counted uncompressed; they are written compressed)",
                file=sys.stderr,
            )
        options = RunOptions(
            formulation=args.formulation,
            figures=not args.no_figures,
            progress=ProgressBar(scene.name, enabled=not args.json),
            checkpoint_every=every,
            resume=args.resume,
        )
        try:
            outcome = run_scene(case, scene, out, options)
        except KeyboardInterrupt as interrupt:
            print(f"pygear run: scene {scene.name}: {interrupt}", file=sys.stderr)
            return 128 + getattr(interrupt, "signal_number", 2)  # 130 Ctrl-C, 143 SIGTERM
        entry = outcome.summary
        if outcome.transient is not None:
            transients[scene.name] = outcome.transient
        summary["scenes"][scene.name] = entry
        _log.info("scene %s: %.0f ms", scene.name, entry["wall_s"] * 1e3)
        if not args.json:
            model = outcome.model
            print(f"scene {scene.name}: {model.formulation}, {model.dof_set} ({model.size} DOFs)")
            for path in entry["files"]:
                print(f"  wrote {path}")
    if len(transients) > 1 and not args.no_figures:
        summary["files"] = [str(_compare_transients(transients, out))]
    summary["wall_s"] = time.perf_counter() - run_started
    if args.json:
        print(json_text(summary))
    elif transients:
        print(runup_table_text(transients))
    return 0


def _compare_transients(transients: dict, out: Path) -> Path:
    """The speeds of several transient scenes side by side (seed Figure 9)."""
    from ..io import save_figure
    from ..plots.transient import plot_speeds

    figure = plot_speeds(list(transients.values()))
    return save_figure(figure, out / "transient_speeds.png", dpi=figure.dpi, release=True)


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {
    "run": _run,
    "analyze": _analyze,
    "mesh-stiffness": _mesh_stiffness,
}
"""Handlers of the commands :func:`add_parsers` adds; each returns the exit code."""
