"""``pygear dataset`` (labelled fault datasets) and ``pygear analyze RUN.nc --tsa GEAR``
(a gear's synchronous average, its condition indicators and the sensor's kurtogram).

The run file is read as data: the sensor channel's attributes hold the sensor, the
planets' positions and the tooth counts, so no case file runs.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import CaseError
from ..runs.progress import progress_wanted

__all__ = ["HANDLERS", "TSA_AFTER", "add_parsers", "analyze_tsa", "damaged_teeth"]

TSA_AFTER = 0.5
"""``--after`` of ``--tsa`` when the run has no settling instant ``t_s`` (at most half
the run): the start-up a steady run sheds before its average."""

TSA_NEEDS = (
    "--tsa needs a transient's result with a sensor channel and the gears' angles "
    "(`pygear run` of a scene with a sensor probe and theta_z displacement probes)"
)
"""What ``--tsa`` asks of RUN.nc (ends the message of a file of another kind)."""


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``dataset`` subcommand."""
    dataset = commands.add_parser(
        "dataset",
        help="labelled fault dataset: fault severities x speeds x loads x noise seeds (Dask)",
        description="One record per run, record_<hash>.nc, named by the hash of its inputs: "
        "a rerun or a larger grid into the same --out reuses every record already there.  "
        "All records are combined into dataset_<hash>.nc with a data card dataset_<hash>.md.  "
        "Exit code 0 when every record ran, 1 when some failed, 2 for bad input.",
    )
    dataset.add_argument("case", metavar="CASE", help="case directory or case name under cases/")
    dataset.add_argument(
        "--faults",
        required=True,
        metavar="KIND=VALUES",
        help="crack_depth, stiffness_factor, chipped_fraction, or a bearing race spall's depth "
        "[m] outer_race_depth or inner_race_depth = START:STOP:COUNT or a list, "
        "e.g. crack_depth=0:0.5:6, outer_race_depth=0:20e-6:3",
    )
    dataset.add_argument("--gear", help="faulty gear, e.g. planetary.planet1 (default: the sun)")
    dataset.add_argument("--tooth", type=int, default=0, help="faulty tooth (0-based, default 0)")
    dataset.add_argument(
        "--bearing", help="bearing with the race defect (default: the sensor stage's first)"
    )
    dataset.add_argument(
        "--planet", type=int, help="planet whose bearing has it (planet bearings, default 1)"
    )
    dataset.add_argument(
        "--defect-angle", type=float, default=0.0, help="defect's angle on its ring [deg]"
    )
    dataset.add_argument("--defect-width", type=float, help="defect's width [m] (default: d / 10)")
    dataset.add_argument("--speeds", required=True, help="carrier speeds [rpm], e.g. 60,120")
    dataset.add_argument("--loads", required=True, help="carrier torques [N m], e.g. 250,500")
    dataset.add_argument("--seeds", type=int, default=1, help="noise seeds per point (default 1)")
    dataset.add_argument(
        "--snr", type=float, default=20.0, help="sensor noise [dB SNR] (default 20)"
    )
    dataset.add_argument("--scene", help="scene with a sensor (default: the first)")
    dataset.add_argument("--duration", type=float, help="override the scene's duration [s]")
    dataset.add_argument("--out", type=Path, help="directory (default: out/<case>/dataset)")
    dataset.add_argument("--workers", type=int, default=2, help="local Dask workers (default 2)")
    dataset.add_argument("--scheduler", metavar="ADDRESS", help="use a running Dask scheduler")
    dataset.add_argument(
        "--no-figures", action="store_true", help="no indicator-trend figure beside the dataset"
    )
    dataset.add_argument("--json", action="store_true", help="print a JSON summary on stdout")


def _dataset(args: argparse.Namespace) -> int:
    from ..runs.fault_dataset import plan_dataset, run_dataset
    from ..runs.json_output import json_text

    if args.duration is not None and not args.duration > 0:
        raise CaseError(f"--duration must be a positive time in s (got {args.duration!r})")
    if args.workers < 1:
        raise CaseError(f"--workers must be >= 1 (got {args.workers})")
    plan = plan_dataset(
        args.case,
        args.faults,
        speeds=args.speeds,
        loads=args.loads,
        seeds=args.seeds,
        gear=args.gear,
        tooth=args.tooth,
        scene=args.scene,
        snr_db=args.snr,
        duration=args.duration,
        bearing=args.bearing,
        planet=args.planet,
        defect_angle=args.defect_angle,
        defect_width=args.defect_width,
    )
    out = args.out or Path("out") / plan.case.name / "dataset"
    result = run_dataset(
        plan,
        out,
        workers=args.workers,
        scheduler=args.scheduler,
        progress=not args.json and progress_wanted(),  # -q: none
        figures=not args.no_figures,
    )
    if args.json:
        keys = ("records", "records_computed", "records_reused", "records_failed", "path")
        print(json_text({key: result.attrs[key] for key in keys}))
    return 1 if result.attrs["records_failed"] else 0


def analyze_tsa(args: argparse.Namespace) -> int:
    """Handler of ``pygear analyze RUN.nc --tsa GEAR [--indicators] [--json]``."""
    import xarray as xr

    from ..analysis.condition.gear_average import (
        check_tsa_sampling,
        gear_average,
        gear_indicator_values,
    )
    from ..analysis.condition.spectral_kurtosis import fast_kurtogram
    from ..analysis.signals.channels import channel_series, run_channels
    from ..analysis.signals.record_checks import check_record_time, default_after
    from ..io import write_netcdf
    from ..runs.json_output import json_text
    from ..runs.outputs import read_run_file

    if args.tachometer is not None and args.tachometer < 1:
        raise CaseError(
            f"--tachometer must be a whole number of pulses >= 1 (got {args.tachometer})"
        )
    if not args.jitter >= 0:
        raise CaseError(f"--jitter must be a time >= 0 s (got {args.jitter!r})")
    run = read_run_file(args.run, TSA_NEEDS)
    source = f"RUN.nc {str(args.run)!r}"
    sensors = [
        n for n, (v, _, _) in run_channels(run).items() if run[v].attrs.get("quantity") == "sensor"
    ]
    channel = args.channel or next(iter(sensors), None)
    if channel is None:
        raise CaseError(f"{source} holds no sensor channel: {TSA_NEEDS}")
    after = default_after(run, TSA_AFTER) if args.after is None else args.after
    # the checks every analyze path makes: the record from --after is uniform in time
    check_record_time(run, source, after)
    late = run.sel(time=slice(after, None))
    # and the mesh, with its first sideband, lies below the record's Nyquist frequency
    check_tsa_sampling(late, args.tsa, channel, source)
    average = gear_average(late, args.tsa, channel, tachometer=args.tachometer, jitter=args.jitter)
    gear = average.attrs["gear"]
    stem = args.out or args.run.with_name(f"{args.run.stem}_tsa_{gear.replace('.', '_')}")
    summary: dict = {
        "gear": gear,
        "channel": channel,
        "revolutions": average.attrs["revolutions"],
        "angles": average.attrs["angles"],
    }
    kurtogram = None
    result = xr.Dataset({"gear_average": average.drop_vars("weight_sum", errors="ignore")})
    if args.indicators:
        indicators = gear_indicator_values(average)
        summary["indicators"] = indicators
        rate = (late.sizes["time"] - 1) / float(late.time[-1] - late.time[0])  # uniform
        kurtogram = fast_kurtogram(channel_series(late, channel).values, rate)
        best = kurtogram[1]
        summary["kurtogram"] = {
            "centre_frequency_hz": best.centre_frequency,
            "bandwidth_hz": best.bandwidth,
            "level": best.level,
            "kurtosis": best.kurtosis,
        }
        unit = str(average.attrs.get("units", "1"))  # the sensor's: rms, variances squared
        squared = f"({unit})^2"
        units = {"rms": unit, "residual_variance": squared, "envelope_variance": squared}
        for name, value in indicators.items():
            attrs = {"units": units.get(name, "1"), "long_name": f"{name} of the gear average"}
            result[name] = ((), value, attrs)
    path = write_netcdf(
        result,
        stem.with_suffix(".nc"),
        title=f"Synchronous average of {gear} in {channel}",
        provenance=run.attrs,
    )
    files = [str(path)]
    if not args.no_figures:
        files += _figures(average, stem, summary, run, kurtogram if args.indicators else None)
    summary["files"] = files
    if args.json:
        print(json_text(summary))
        return 0
    print(f"synchronous average of {gear} in {channel}: {average.attrs['revolutions']} revolutions")
    for name, value in summary.get("indicators", {}).items():
        print(f"  {name:24s} {value:.6g}")
    if "kurtogram" in summary:
        band = summary["kurtogram"]
        print(
            f"  kurtogram best band      {band['centre_frequency_hz']:.6g} Hz "
            f"+- {band['bandwidth_hz'] / 2:.6g} Hz (level {band['level']:g})"
        )
    print("wrote " + ", ".join(files))
    return 0


def damaged_teeth(run, gear: str, teeth: int) -> list:
    """Where the run's damaged teeth of ``gear`` show in its average, in tooth periods.

    A tooth k of the sun or the ring sits at k.  A planet's tooth meets the sun at k and
    the ring (Z_p + 1) / 2 tooth periods later when the carrier drives (half a turn, and
    the ring loads the other flank), (Z_p - 1) / 2 when the sun drives; a ring sensor
    hears mostly the latter, so its contact, about two periods long, is shaded too.
    """
    import json

    try:
        defects = json.loads(run.attrs.get("tooth_defects", "[]"))
    except ValueError:
        return []
    marks: list = []
    for defect in defects:
        if defect.get("gear") != gear:
            continue
        tooth = int(defect["tooth"])
        marks.append(tooth)
        if ".planet" in gear:
            carrier_driven = str(run.attrs.get("input", "")).endswith("carrier.theta_z")
            start = (tooth + (teeth + (1 if carrier_driven else -1)) / 2) % teeth
            marks.append((start, start + 2.0))
    return marks


def _figures(average, stem: Path, summary: dict, run, kurtogram=None) -> list[str]:
    from ..io import save_figure
    from ..plots.condition_monitoring import plot_gear_average, plot_kurtogram
    from ..plots.layout import result_title

    damaged = damaged_teeth(run, summary["gear"], int(average.attrs["teeth"]))
    source = result_title(run.attrs)
    figures = {
        stem.with_suffix(".png"): plot_gear_average(
            average,
            damaged_teeth=damaged,
            title=f"{summary['gear']} in {summary['channel']}: {source}",
        )
    }
    if kurtogram is not None:
        figures[stem.with_name(f"{stem.name}_kurtogram.png")] = plot_kurtogram(
            *kurtogram, title=f"kurtogram of {summary['channel']}: {source}"
        )
    for path, figure in figures.items():
        save_figure(figure, path, dpi=figure.dpi, release=True)  # atomic: no half-written figure
    return [str(path) for path in figures]


HANDLERS = {"dataset": _dataset}
