"""``pygear analyze RUN.nc --bearing-envelope``: the bearing lines an envelope analysis
finds in a run's channel, with their SNRs.

The lines are the bearing frequencies the run file stores (``pygear run`` writes them
when the case has rolling bearings) or those given with ``--bpfo`` / ``--bpfi``; the
file is read as data, no case file runs.
"""

from __future__ import annotations

import argparse

import numpy as np

from ..errors import CaseError

__all__ = ["BEARING_NEEDS", "analyze_bearing_envelope", "bearing_lines"]

BEARING_NEEDS = (
    "--bearing-envelope needs a transient's result with series over time "
    "(`pygear run` of a scene with a 'transient' analysis)"
)
"""What ``--bearing-envelope`` asks of RUN.nc."""
SEARCHED = ("BPFO", "BPFI", "BSF")
"""Stored lines looked for (a cage fault's FTF lies below the envelope's resolution of
most records and is left out)."""


def bearing_lines(run, args: argparse.Namespace) -> tuple[dict, dict]:
    """``({label: Hz}, {label: modulation Hz})`` from ``--bpfo``/``--bpfi`` when given,
    else from the run file's stored bearing frequencies."""
    from ..analysis.condition.bearing_kinematics import read_frequency_table

    for flag in ("bpfo", "bpfi", "shaft_frequency"):
        value = getattr(args, flag)
        if value is not None and not (np.isfinite(value) and value > 0):
            raise CaseError(f"--{flag.replace('_', '-')} must be a positive frequency in Hz "
                            f"(got {value})")  # fmt: skip
    given = {k: v for k, v in (("BPFO", args.bpfo), ("BPFI", args.bpfi)) if v is not None}
    if given:
        shaft = args.shaft_frequency or 0.0
        return given, {"BPFI": shaft, "BPFO": 0.0}
    stored = read_frequency_table(run)
    if not stored:
        raise CaseError(
            f"RUN.nc {str(args.run)!r} stores no bearing frequencies (its case has no rolling "
            "bearings, or an older pygear wrote it): give --bpfo and/or --bpfi"
        )
    lines, modulation = {}, {}
    for bearing in stored:
        for line in SEARCHED:
            if not bearing.lines[line] > 0:  # a bearing that does not turn in this run
                continue
            label = f"{bearing.name}:{line}"
            lines[label] = bearing.lines[line]
            # a defect standing in the load zone of a planet bearing is still carried
            # past the sensor by the carrier
            modulation[label] = bearing.modulation[line] or bearing.carrier
    if not lines:
        raise CaseError(
            f"RUN.nc {str(args.run)!r}: none of its rolling bearings turns at the run's "
            "equilibrium speeds (all bearing frequencies are 0): give --bpfo and/or --bpfi"
        )
    return lines, modulation


def analyze_bearing_envelope(args: argparse.Namespace) -> int:
    """Pre-whitening, the kurtogram's band, the squared envelope spectrum, the lines."""
    from ..analysis.condition.bearing_envelope import bearing_envelope_analysis
    from ..analysis.signals.analyze import pick_channel
    from ..analysis.signals.channels import channel_series
    from ..analysis.signals.record_checks import (
        check_band,
        check_record_time,
        default_after,
        record_sample_rate,
    )
    from ..model.case import SIGNAL_AFTER
    from ..runs.json_output import json_text
    from ..runs.outputs import read_run_file

    run = read_run_file(args.run, BEARING_NEEDS)
    source = f"RUN.nc {str(args.run)!r}"
    lines, modulation = bearing_lines(run, args)
    after = default_after(run, SIGNAL_AFTER) if args.after is None else args.after
    kept = check_record_time(run, source, after)
    rate = record_sample_rate(kept)
    band = None
    if args.band is not None:
        band = tuple(args.band)
        check_band(band, rate, kept.size, source)
    channel = pick_channel(run, args.channel)
    series = channel_series(run, channel)
    values = np.asarray(series.values[series["time"].values >= after], dtype=float)
    spectrum, found = bearing_envelope_analysis(
        values, rate, lines, modulation=modulation, band=band, separate=args.drs
    )
    rows = []
    for label in found.line.values:
        line = found.sel(line=label)
        rows.append(
            {
                "line": str(label),
                "expected_hz": float(line.expected_frequency.sel(harmonic=1, sideband=0)),
                "detected": bool(line.detected),
                "snr_db": float(line.snr_fundamental),
                "harmonics": [
                    {
                        "k": int(k),
                        "found_hz": float(line.found_frequency.sel(harmonic=k, sideband=0)),
                        "snr_db": float(line.snr.sel(harmonic=k, sideband=0)),
                    }
                    for k in found.harmonic.values
                ],
                "sidebands": [
                    {
                        "m": int(m),
                        "found_hz": float(line.found_frequency.sel(harmonic=1, sideband=m)),
                        "snr_db": float(line.snr.sel(harmonic=1, sideband=m)),
                    }
                    for m in found.sideband.values
                    if m != 0 and np.isfinite(line.expected_frequency.sel(harmonic=1, sideband=m))
                ],
            }
        )
    summary = {
        "channel": channel,
        "band_hz": [found.attrs["band_low"], found.attrs["band_high"]],
        "band_kurtosis": spectrum.attrs["band_kurtosis"],
        "prewhitened": True,
        "discrete_random_separation": bool(args.drs),
        "threshold_db": found.attrs["threshold_db"],
        "bin_width_hz": found.attrs["bin_width"],
        "lines": rows,
    }
    if args.json:
        print(json_text(summary))
        return 0
    low, high = summary["band_hz"]
    steps = "discrete-random separated, pre-whitened" if args.drs else "pre-whitened"
    print(f"bearing envelope of {channel}: {steps}, band {low:.0f} .. {high:.0f} Hz, "
          f"lines above {summary['threshold_db']:g} dB")  # fmt: skip
    print(f"{'line':<24} {'expected Hz':>11} {'found Hz':>9} {'SNR dB':>7} {'x2 dB':>6} "
          f"{'x3 dB':>6}  detected")  # fmt: skip
    for row in rows:
        snrs = [h["snr_db"] for h in row["harmonics"]] + [float("nan")] * 3
        print(
            f"{row['line']:<24} {row['expected_hz']:>11.2f} "
            f"{row['harmonics'][0]['found_hz']:>9.2f} {snrs[0]:>7.1f} {snrs[1]:>6.1f} "
            f"{snrs[2]:>6.1f}  {'yes' if row['detected'] else 'no'}"
        )
    return 0
