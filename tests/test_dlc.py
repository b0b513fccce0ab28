"""Design load case batches (pygear.model.dlc_settings, pygear.runs.dlc, dlc_spectrum).

References: the Rayleigh (Weibull k = 2) bin probabilities in closed form,
P(a < V < b) = exp(-(pi/4)(a/V_mean)^2) - exp(-(pi/4)(b/V_mean)^2); the combined
histograms against a bare NumPy histogram of the weighted samples on the same edges;
a load case's drive against the torque series it was given.
"""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pygear.analysis.time.reductions import Pow2Histogram
from pygear.errors import CaseError
from pygear.model.dlc_settings import DesignLoadCases, load_design_load_cases
from pygear.runs.dlc_spectrum import combine_histograms

SMALL_CASE = """
import dataclasses

from pygear.model.case_files import load_case_module

_, _base = load_case_module("nrel5mw_gearbox")
case = dataclasses.replace(_base.case, name="{name}")
design_load_cases = dataclasses.replace(
    _base.design_load_cases, wind_speeds={speeds}, seeds={seeds}, duration={duration},
    input_rate=200.0,
)
"""


def small_case(root: Path, name: str, speeds, seeds, duration: float) -> Path:
    """A case directory: the NREL 5 MW gearbox with a short design load case table."""
    directory = root / name
    directory.mkdir(parents=True)
    text = SMALL_CASE.format(name=name, speeds=tuple(speeds), seeds=tuple(seeds),
                             duration=duration)  # fmt: skip
    (directory / "case.py").write_text(text)
    return directory


def _rayleigh(a: float, b: float, mean: float) -> float:
    return math.exp(-math.pi / 4 * (a / mean) ** 2) - math.exp(-math.pi / 4 * (b / mean) ** 2)


def test_hours_per_year_follow_the_rayleigh_distribution():
    table = DesignLoadCases(scene="runup", wind_speeds=(4.0, 6.0, 8.0), seeds=(1, 2), duration=10.0)
    table.validate()
    assert table.bin_edges() == (3.0, 5.0, 7.0, 9.0)
    cases = table.load_cases()
    assert [c.name for c in cases] == [
        "dlc_4ms_seed1", "dlc_4ms_seed2", "dlc_6ms_seed1", "dlc_6ms_seed2",
        "dlc_8ms_seed1", "dlc_8ms_seed2",
    ]  # fmt: skip
    for case in cases:
        lo = case.wind_speed - 1.0
        expected = 8766.0 * _rayleigh(lo, lo + 2.0, 10.0) / 2  # two seeds share a bin
        # Gamma(1.5) = sqrt(pi)/2 in the scale: equal to round-off (1e-12 relative)
        assert case.hours_per_year == pytest.approx(expected, rel=1e-12)


def test_the_shipped_table_covers_cut_in_to_cut_out():
    case, table, _ = load_design_load_cases("nrel5mw_gearbox")
    assert table.bin_edges()[0] == 3.0 and table.bin_edges()[-1] == 25.0
    hours = sum(c.hours_per_year for c in table.load_cases())
    assert hours == pytest.approx(8766.0 * _rayleigh(3.0, 25.0, 10.0), rel=1e-12)
    assert len(table.load_cases()) == 11 * 6


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"wind_speeds": (8.0, 6.0)}, "wind_speeds must increase strictly"),
        ({"seeds": (1, 1)}, "seeds must be distinct"),
        ({"duration": 0.0}, "duration must be > 0"),
        ({"source": "hawc2"}, "source must be one of kaimal, openfast"),
        ({"source": "openfast"}, "openfast_files must name one file per load case"),
        ({"turbulence_class": "D"}, "turbulence_class must be A, B or C"),
        ({"wind_bin_edges": (3.0, 5.0)}, "wind_bin_edges must be 3 increasing edges"),
        ({"duration": 0.1, "input_rate": 20.0}, "at least 4 samples"),
    ],
)
def test_bad_table_is_one_line_error(change, message):
    settings = {"scene": "runup", "wind_speeds": (6.0, 8.0), "seeds": (1,), **change}
    with pytest.raises(CaseError, match=message) as info:
        DesignLoadCases(**settings).validate()
    assert "\n" not in str(info.value)


def test_combined_histograms_equal_one_histogram_of_the_weighted_samples():
    # two records of different extents count into bins of different widths (2^e); their
    # weighted sum re-binned must equal np.histogram of all samples with the weights on
    # the result's edges: each part's bin lies whole in one of them (exact but for the
    # weights' round-off, 1e-12 relative)
    rng = np.random.default_rng(3)
    small = rng.normal(0.0, 1.0, 5000)
    large = rng.normal(40.0, 30.0, 7000)
    parts = []
    for values, weight in ((small, 3.0), (large, 0.25)):
        histogram = Pow2Histogram(1, 32, 1)
        histogram.update(values[:, None], np.ones((values.size, 1)))
        counts, edges = histogram.result()
        parts.append((counts, edges, weight))
    assert parts[0][1][0][1] - parts[0][1][0][0] < parts[1][1][0][1] - parts[1][1][0][0]
    counts, edges = combine_histograms(parts, bins=32)
    samples = np.concatenate([small, large])
    weights = np.concatenate([np.full(small.size, 3.0), np.full(large.size, 0.25)])
    expected, _ = np.histogram(samples, bins=edges[0], weights=weights)
    np.testing.assert_allclose(counts[:, 0], expected, rtol=1e-12)
    assert counts.sum() == pytest.approx(3.0 * small.size + 0.25 * large.size, rel=1e-12)


def test_missing_table_names_what_to_add(tmp_path):
    directory = tmp_path / "plain"
    directory.mkdir()
    (directory / "case.py").write_text(
        "from pygear.model.case_files import load_case_module\n"
        "_, base = load_case_module('nrel5mw_gearbox')\ncase = base.case\n"
    )
    with pytest.raises(CaseError, match="has no design load cases: add a module-level"):
        load_design_load_cases(directory)


def _pygear(*args: str) -> list[str]:
    return [sys.executable, "-m", "pygear", *args]


@pytest.mark.slow
def test_dlc_batch_writes_a_file_per_load_case_and_the_weighted_spectrum(tmp_path):
    from pygear.runs.dlc import load_case_series

    directory = small_case(tmp_path, "dlc_two", (8.0, 14.0), (1,), 0.1)
    out = tmp_path / "out"
    done = subprocess.run(
        _pygear("batch", str(directory), "--dlc", "--out", str(out), "--workers", "2"),
        capture_output=True, text=True, timeout=900,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    _, table, _ = load_design_load_cases(directory)
    loads = table.load_cases()
    runs = {}
    for load in loads:
        run = xr.open_dataset(out / "dlc_two" / "dlc" / f"{load.name}.nc")
        assert int(run.attrs["complete"]) == 1
        runs[load.name] = run
        # the drive is the load case's torque series (linear interpolation of the table;
        # the kernel evaluates it at each step: equal to round-off, 1e-9 relative)
        series = load_case_series(table, load)
        expected = np.interp(run.time.values, series.time.values, series.rotor_torque.values)
        np.testing.assert_allclose(run.drive_torque.values, expected, rtol=1e-9)
    spectrum = xr.open_dataset(out / "dlc_two" / "load_spectrum.nc")
    weights = {load.name: 3600.0 * load.hours_per_year / 0.1 for load in loads}
    for name in ("rainflow_mesh_force", "rainflow_bearing_force"):
        total = sum(weights[k] * float(r[name].sum()) for k, r in runs.items())
        assert float(spectrum[name].sum()) == pytest.approx(total, rel=1e-12)
        per_label = sum(weights[k] * r[name].sum(("rainflow_range", "rainflow_mean")).values
                        for k, r in runs.items())  # fmt: skip
        np.testing.assert_allclose(
            spectrum[name].sum(("rainflow_range", "rainflow_mean")).values, per_label, rtol=1e-12
        )
    # time at level a year: each load case's seconds times its weight (hours x 3600 s
    # over the duration)
    total_time = sum(weights[k] * r.load_duration_time.sum("load_level").values
                     for k, r in runs.items())  # fmt: skip
    np.testing.assert_allclose(
        spectrum.load_duration_time.sum("load_level").values, total_time, rtol=1e-12
    )
    assert spectrum.attrs["period"] == "one year"
    journal = (out / "dlc_two" / "dlc" / "dlc_journal.log").read_text().splitlines()
    stamps = {p: (out / "dlc_two" / "dlc" / f"{p}.nc").stat().st_mtime_ns for p in runs}
    # run again: every load case is complete, none runs, the spectrum is written again
    again = subprocess.run(
        _pygear("batch", str(directory), "--dlc", "--out", str(out), "--json"),
        capture_output=True, text=True, timeout=900,
    )  # fmt: skip
    assert again.returncode == 0, again.stderr[-2000:]
    statuses = {
        r["load_case"]: r["status"] for r in json.loads(again.stdout)["dlc"][0]["load_cases"]
    }
    assert set(statuses.values()) == {"reused"}
    assert (out / "dlc_two" / "dlc" / "dlc_journal.log").read_text().splitlines() == journal
    for name, stamp in stamps.items():
        assert (out / "dlc_two" / "dlc" / f"{name}.nc").stat().st_mtime_ns == stamp


def _journal(path: Path) -> list[list[str]]:
    return [line.split() for line in path.read_text().splitlines()] if path.is_file() else []


def _wait(predicate, process, limit: float = 600.0) -> None:
    started = time.monotonic()
    while not predicate():
        assert process.poll() is None or predicate(), "the batch ended before the event"
        assert time.monotonic() - started < limit, "the event did not come"
        time.sleep(0.2)


@pytest.mark.slow
def test_batch_resumed_after_a_killed_worker_runs_no_load_case_twice(tmp_path):
    directory = small_case(tmp_path, "dlc_kill", (6.0, 10.0, 14.0), (1, 2), 0.4)
    out = tmp_path / "out"
    journal = out / "dlc_kill" / "dlc" / "dlc_journal.log"
    command = _pygear("batch", str(directory), "--dlc", "--out", str(out), "--workers", "2")
    log = open(tmp_path / "first.log", "w")
    batch = subprocess.Popen(command, stdout=log, stderr=log, start_new_session=True)
    try:
        # a worker killed half way through a load case
        def running():
            done = {e[1] for e in _journal(journal) if e[0] == "completed"}
            return [e for e in _journal(journal) if e[0] == "started" and e[1] not in done]

        _wait(lambda: bool(running()), batch)
        _, victim, pid = running()[0][:3]
        os.kill(int(pid), signal.SIGKILL)
        # then the whole batch killed once another load case has completed
        completed_before = sum(e[0] == "completed" for e in _journal(journal))
        _wait(lambda: sum(e[0] == "completed" for e in _journal(journal)) > completed_before
              or batch.poll() is not None, batch)  # fmt: skip
        if batch.poll() is None:
            os.killpg(batch.pid, signal.SIGKILL)
    finally:
        if batch.poll() is None:
            os.killpg(batch.pid, signal.SIGKILL)
        batch.wait()
        log.close()
    first = _journal(journal)
    finished_first = {e[1] for e in first if e[0] == "completed"}
    assert ["completed", victim, pid] not in [e[:3] for e in first]  # it was killed
    resumed = subprocess.run(command + ["--json"], capture_output=True, text=True, timeout=900)
    assert resumed.returncode == 0, resumed.stderr[-2000:]
    entries = _journal(journal)
    report = json.loads(resumed.stdout)["dlc"][0]
    statuses = {r["load_case"]: r["status"] for r in report["load_cases"]}
    assert report["load_spectrum"] is not None
    _, table, _ = load_design_load_cases(directory)
    for load in table.load_cases():
        completions = [k for k, e in enumerate(entries) if e[:2] == ["completed", load.name]]
        starts = [k for k, e in enumerate(entries) if e[:2] == ["started", load.name]]
        assert len(completions) == 1, (load.name, entries)  # completed once, never again
        assert max(starts) < completions[0]  # no start after its completion
        # the resumed batch ran exactly those the first did not complete
        assert statuses[load.name] == ("reused" if load.name in finished_first else "ok")
    assert len([e for e in entries if e[:2] == ["started", victim]]) >= 2  # redone
    assert (out / "dlc_kill" / "load_spectrum.nc").is_file()
    assert not list((out / "dlc_kill" / "dlc").glob(".*.part"))


def test_openfast_load_case_drives_the_scene_with_the_file_torque():
    from pygear.model.case import load_case
    from pygear.runs.dlc import load_case_scene, load_case_series

    data = Path(__file__).parent / "data"
    table = DesignLoadCases(
        scene="runup", wind_speeds=(12.0,), seeds=(1,), duration=0.4, source="openfast",
        openfast_files=("nrel5mw_short.out",),
    )  # fmt: skip
    table.validate()
    (load,) = table.load_cases()
    series = load_case_series(table, load, data)
    # the file's first 0.4 s (rows 0..8 at 0.05 s), RotTorq 3900 + 10 i kN-m in N m
    rows = np.arange(9)
    np.testing.assert_allclose(series.time.values, 0.05 * rows, atol=1e-12)
    np.testing.assert_allclose(series.rotor_torque.values, (3900.0 + 10 * rows) * 1e3, rtol=1e-14)
    scene = load_case_scene(load_case("nrel5mw_gearbox"), table, load, series)
    transient = scene.transient
    assert transient.drive.kind == "table"
    np.testing.assert_allclose(transient.drive.torques, (3900.0 + 10 * rows) * 1e3, rtol=1e-14)
    # the generator law balances the mean torque at the mean speed, from that speed
    assert transient.load.torque == pytest.approx(np.mean((3900.0 + 10 * rows) * 1e3), rel=1e-14)
    assert transient.speed_reference_rpm == pytest.approx(np.mean(12.1 + 0.01 * rows), rel=1e-14)
    assert transient.initial_speed_rpm == transient.speed_reference_rpm
    assert transient.duration == 0.4 and scene.name == "dlc_12ms_seed1"
    longer = DesignLoadCases(
        scene="runup", wind_speeds=(12.0,), seeds=(1,), duration=5.0, source="openfast",
        openfast_files=("nrel5mw_short.out",),
    )  # fmt: skip
    with pytest.raises(CaseError, match="holds 0.5 s, less than the duration 5 s"):
        load_case_series(longer, longer.load_cases()[0], data)


@pytest.mark.slow
def test_load_case_runs_on_the_whole_drivetrain(tmp_path):
    # the flexible NREL 5 MW drivetrain (shafts as beam elements) under the same kind of
    # table: the load case's file holds its series as the drive and its reductions
    from pygear.runs.dlc import load_case_series, run_load_case

    directory = tmp_path / "drivetrain_dlc"
    directory.mkdir()
    (directory / "case.py").write_text(
        "import dataclasses\n"
        "from pygear.model.case_files import load_case_module\n"
        "from pygear.model.dlc_settings import DesignLoadCases\n"
        "from pygear.model.reduction_settings import Reductions\n"
        "_, base = load_case_module('nrel5mw_drivetrain')\n"
        "case = dataclasses.replace(base.case, name='drivetrain_dlc')\n"
        "design_load_cases = DesignLoadCases(scene='runup', wind_speeds=(14.0,), seeds=(1,),\n"
        "    duration=0.1, input_rate=200.0, reductions=Reductions(rainflow=('mesh_force',),\n"
        "    load_duration=('drive_torque', 'load_torque')))\n"
    )
    row = run_load_case(str(directory), "dlc_14ms_seed1", str(tmp_path / "out"))
    assert row["status"] == "ok", row["error"]
    _, table, _ = load_design_load_cases(directory)
    series = load_case_series(table, table.load_cases()[0])
    with xr.open_dataset(row["file"]) as run:
        assert int(run.attrs["complete"]) == 1 and int(run.attrs["whole_drivetrain"]) == 1
        expected = np.interp(run.time.values, series.time.values, series.rotor_torque.values)
        np.testing.assert_allclose(run.drive_torque.values, expected, rtol=1e-9)
        assert float(run.rainflow_mesh_force.sum()) > 0
        assert float(run.load_duration_time.sum()) > 0


def test_batch_dlc_refuses_bad_input_before_any_work(tmp_path, capsys):
    from pygear.cli import main

    (tmp_path / "a_file").write_text("mine")
    # a case without a table, an --out that is a file, a cluster option without
    # --cluster, and --cluster on a plain batch: exit 2, one line, nothing written
    runs = [
        (["batch", "yang2016_planetary", "--dlc", "--out", str(tmp_path / "o")],
         "has no design load cases"),
        (["batch", "nrel5mw_gearbox", "--dlc", "--out", str(tmp_path / "a_file")],
         "is a file"),
        (["batch", "nrel5mw_gearbox", "--dlc", "--queue", "q", "--out", str(tmp_path / "o")],
         "--queue applies to a job-queue cluster"),
        (["batch", "nrel5mw_gearbox", "--cluster", "slurm", "--out", str(tmp_path / "o")],
         "--cluster applies to design load cases and sweeps"),
    ]  # fmt: skip
    for argv, words in runs:
        assert main(argv) == 2, argv
        err = capsys.readouterr().err.strip()
        assert words in err and "\n" not in err, (argv, err)
    assert not (tmp_path / "o").exists()
    assert (tmp_path / "a_file").read_text() == "mine"
