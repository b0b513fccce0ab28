"""Hostile and first-time use of the command line (#27): bad input refused in one line
with exit code 2 before any work and before Dask, estimates of memory and disk before
long work, a full disk and Ctrl-C in one line with no partial file and no process left,
a closed pipe ending quietly, and what a user reads (help, tables, warnings)."""

from __future__ import annotations

import errno
import json
import os
import signal
import socket
import subprocess
import sys
import time
import warnings
from pathlib import Path
from types import SimpleNamespace

import pytest

from pygear import resources
from pygear.cli import main
from pygear.cli import modal as modal_cli
from pygear.cli.parser import build_parser

ROOT = Path(__file__).resolve().parent.parent
CASES = ROOT / "cases"
PLANETARY = str(CASES / "yang2016_planetary")
DRIVETRAIN = str(CASES / "nrel5mw_drivetrain")
SENSOR_CASE = "sequential_planetary"
SUN = "planetary.sun_mesh.stiffness"
NOWHERE = "tcp://127.0.0.1:1"
"""A scheduler no one runs: a command that got as far as Dask would fail to connect."""


def _one_line_error(capsys, option: str) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert option in err, err
    return err


# --- item 3: modal --formulation of a drivetrain ------------------------------------------


def _drivetrain_modes(capsys, *extra: str) -> dict:
    assert main(["modal", DRIVETRAIN, "--modes", "40", "--json", *extra]) == 0
    return json.loads(capsys.readouterr().out)


def test_drivetrain_modal_assembles_its_gearbox_in_the_formulation_asked(capsys):
    """improved and consistent differ in a planet's inertia (docs/model.md §4), which
    moves some of the NREL drivetrain's 40 lowest modes; lin-parker is refused."""
    improved = _drivetrain_modes(capsys, "--formulation", "improved")
    consistent = _drivetrain_modes(capsys, "--formulation", "consistent")
    assert improved["formulation"] == "improved" and consistent["formulation"] == "consistent"
    moved = [
        abs(a / b - 1)
        for a, b in zip(improved["frequencies_hz"], consistent["frequencies_hz"])
        if b > 1.0
    ]
    assert max(moved) > 1e-3  # the same frequencies for both: --formulation ignored
    assert main(["modal", DRIVETRAIN, "--formulation", "lin-parker"]) == 2
    err = _one_line_error(capsys, "--formulation 'lin-parker'")
    assert "'improved' or 'consistent'" in err


def test_drivetrain_modes_up_to_its_dofs_say_why_one_is_missing(capsys):
    assert main(["modal", DRIVETRAIN, "--modes", "144"]) == 0
    captured = capsys.readouterr()
    assert "143 lowest modes" in captured.out
    assert "--modes 144" in captured.err and "at most 143" in captured.err


# --- item 9: a drivetrain too large, refused before it is assembled -----------------------


def test_a_drivetrain_too_large_is_refused_from_its_element_count(tmp_path, monkeypatch, capsys):
    case_dir = tmp_path / "big_drivetrain"
    case_dir.mkdir()
    text = (Path(DRIVETRAIN) / "case.py").read_text()
    assert "elements_per_section=4," in text
    (case_dir / "case.py").write_text(
        text.replace("elements_per_section=4,", "elements_per_section=20000,")
    )
    (tmp_path / "nrel5mw_gearbox").symlink_to(CASES / "nrel5mw_gearbox")
    monkeypatch.setattr(resources, "available_memory", lambda: 100e6)

    def never(*args, **kwargs):
        raise AssertionError("the drivetrain was assembled")

    monkeypatch.setattr("pygear.assembly.drivetrain.assemble_drivetrain", never)
    started = time.perf_counter()
    assert main(["modal", str(case_dir), "--modes", "3"]) == 2
    assert time.perf_counter() - started < 30
    err = _one_line_error(capsys, "drivetrain.shafts[1].elements_per_section")
    assert "40,001 shaft elements" in err and "400 MB" in err and "100 MB" in err


# --- item 10 and 14: dataset input refused before Dask ------------------------------------


def _dataset(*extra: str, out: Path) -> int:
    return main(
        ["dataset", SENSOR_CASE, "--speeds", "120", "--loads", "500", "--out", str(out)]
        + ["--scheduler", NOWHERE, "--no-figures", *extra]
    )


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        (
            ["--gear", "planetary.carrier", "--faults", "crack_depth=0.1"],
            ["--gear 'planetary.carrier'", "planetary.sun, planetary.planet1"],
        ),
        (
            ["--gear", "planetary.ring", "--faults", "crack_depth=0.1"],
            ["--gear 'planetary.ring'", "external gears"],
        ),
        (["--faults", "stiffness_factor=0.1,0.2,0.1"], ["--faults stiffness_factor", "twice"]),
        (["--faults", "stiffness_factor=0.1", "--duration", "0.2"], ["--duration 0.2", "0.5 s"]),
        (["--faults", "stiffness_factor=0.1", "--loads", "1e9"], ["deflection_limit", "1e+09"]),
        (["--faults", "stiffness_factor=0.1", "--speeds", "1e7"], ["--speeds", "of memory"]),
        (["--faults", "stiffness_factor=0.1", "--seeds", "100000000"], ["--seeds", "of disk"]),
    ],
)
def test_dataset_input_is_refused_before_dask(tmp_path, capsys, extra, words):
    out = tmp_path / "dataset"
    assert _dataset(*extra, out=out) == 2
    err = _one_line_error(capsys, words[0])
    assert all(word in err for word in words), err
    assert "connect" not in err  # refused before the scheduler was asked
    assert not out.exists()


@pytest.mark.parametrize("out", ["y.nc", "a_file"])
def test_an_out_that_is_no_directory_is_refused_before_any_work(tmp_path, capsys, out):
    (tmp_path / "a_file").write_text("mine")
    target = tmp_path / out
    commands = [
        ["sweep", PLANETARY, "--param", f"{SUN}=1e8", "--scheduler", NOWHERE],
        ["batch", PLANETARY, "--scheduler", NOWHERE],
        ["modal", PLANETARY],
        ["sensitivity", PLANETARY, "--parameter", SUN, "--values", "1e8"],
        ["campbell", PLANETARY, "--speeds", "0:100:3"],
        ["accuracy", PLANETARY],
    ]
    for argv in commands:
        assert main([*argv, "--out", str(target)]) == 2, argv
        err = _one_line_error(capsys, f"--out '{target}'")
        assert "connect" not in err
        assert not (tmp_path / "y.nc").exists()
        assert (tmp_path / "a_file").read_text() == "mine"
    assert _dataset("--faults", "stiffness_factor=0.1", out=target) == 2
    _one_line_error(capsys, f"--out '{target}'")
    (tmp_path / "m.npz").mkdir()
    assert main(["matrices", PLANETARY, "--out", str(tmp_path / "m.npz")]) == 2  # a directory
    _one_line_error(capsys, "is a directory")


# --- item 17: swept values checked by the model before the cluster -------------------------


def test_a_swept_value_the_case_refuses_is_bad_input_before_dask(tmp_path, capsys):
    out = tmp_path / "sweep"
    argv = ["sweep", PLANETARY, "--param", f"{SUN}=1e8,-1", "--scheduler", NOWHERE]
    assert main([*argv, "--out", str(out)]) == 2
    err = _one_line_error(capsys, f"--param {SUN}=-1.0")
    assert "positive" in err and "connect" not in err
    assert not out.exists()  # no error record of a point: there is no point


# --- item 13: disk estimate before a sweep, and a disk that fills -------------------------


def test_a_sweep_that_would_not_fit_on_the_disk_is_refused_with_its_estimate(
    tmp_path, capsys, monkeypatch
):
    monkeypatch.setattr(resources, "available_disk", lambda path: 1e6)
    out = tmp_path / "sweep"
    argv = ["sweep", PLANETARY, "--param", f"{SUN}=logspace(7,10,20)", "--scheduler", NOWHERE]
    assert main([*argv, "--out", str(out)]) == 2
    err = _one_line_error(capsys, "--param")
    assert "20 point files" in err and "disk space" in err and "1 MB free" in err
    assert not out.exists()


def _no_space(*args, **kwargs):
    raise OSError(errno.ENOSPC, "No space left on device")


def test_a_full_disk_stops_a_sweep_in_one_line_with_no_partial_file(
    tmp_path, capsys, monkeypatch, scheduler
):
    monkeypatch.setattr("pygear.runs.sweep_points.write_netcdf", _no_space)
    out = tmp_path / "sweep"
    argv = ["sweep", PLANETARY, "--param", f"{SUN}=1e8,2e8", "--scheduler", scheduler]
    assert main([*argv, "--out", str(out), "-q"]) == 1
    err = _one_line_error(capsys, "no space left on device writing")
    assert f"{out}/point_" in err and "need about" in err
    assert sorted(p.name for p in out.iterdir()) == []  # no point, no error record, no .part


def test_a_full_disk_stops_a_dataset_in_one_line_with_no_partial_file(
    tmp_path, capsys, monkeypatch, scheduler
):
    monkeypatch.setattr("pygear.runs.fault_dataset.write_netcdf", _no_space)
    monkeypatch.setattr("pygear.analysis.time.transient.run_transient", _fake_run)
    monkeypatch.setattr("pygear.runs.fault_dataset.record_dataset", lambda *a: None)
    out = tmp_path / "dataset"
    argv = ["dataset", SENSOR_CASE, "--faults", "stiffness_factor=0.1", "--speeds", "120"]
    argv += ["--loads", "500", "--scheduler", scheduler, "--out", str(out), "-q"]
    assert main(argv) == 1
    err = _one_line_error(capsys, "no space left on device writing")
    assert f"{out}/record_" in err and "need about" in err
    assert sorted(p.name for p in out.iterdir()) == []


def _fake_run(*args, **kwargs):
    return SimpleNamespace()


def test_a_dataset_whose_every_record_failed_writes_no_dataset_and_no_card(
    tmp_path, capsys, monkeypatch, scheduler
):
    def broken(*args, **kwargs):
        raise RuntimeError("the kernel gave up")

    monkeypatch.setattr("pygear.analysis.time.transient.run_transient", broken)
    out = tmp_path / "dataset"
    argv = ["dataset", SENSOR_CASE, "--faults", "stiffness_factor=0.1,0.2", "--speeds", "120"]
    argv += ["--loads", "500", "--scheduler", scheduler, "--out", str(out), "-q"]
    assert main(argv) == 1
    err = _one_line_error(capsys, "every one of the 2 records failed")
    assert "the kernel gave up" in err and "internal error" not in err
    assert not list(out.glob("dataset_*")) and len(list(out.glob("*.error.json"))) == 2


# --- item 12: Ctrl-C during a sweep -------------------------------------------------------


def test_ctrl_c_during_a_sweep_is_one_line_130_and_stops_the_workers(tmp_path):
    """The terminal sends SIGINT to the whole process group: the workers too.  They
    must not print their tracebacks, and none may outlive the command."""
    process = subprocess.Popen(
        [sys.executable, "-m", "pygear", "sweep", PLANETARY, "--scene", "runup_wide"]
        + ["--param", f"{SUN}=logspace(8,9,40)", "--workers", "2", "--out", str(tmp_path / "s")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    group = process.pid
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:  # until the workers run: forked by the fork server
        listed = subprocess.run(
            ["ps", "-o", "args=", "-g", str(group)], capture_output=True, text=True
        )
        forked = [line for line in listed.stdout.splitlines() if "forkserver" in line]
        if len(forked) >= 3 or process.poll() is not None:  # the server and two workers
            break
        time.sleep(0.5)
    time.sleep(1.5)  # the points are running
    assert process.poll() is None, process.communicate()
    os.killpg(group, signal.SIGINT)
    out, err = process.communicate(timeout=120)
    assert _running(group) == [], err  # no worker and no fork server outlives the command
    lines = [line for line in err.splitlines() if not line.startswith("sweep ")]  # progress
    assert process.returncode == 130, err
    assert lines == ["pygear sweep: interrupted"], err
    assert not list((tmp_path / "s").glob("*.part"))


def _running(group: int) -> list[str]:
    """The processes of ``group`` still running, once multiprocessing's resource tracker
    (which ends on its own when the command's pipe to it closes) has had a moment."""
    for _ in range(20):
        listed = subprocess.run(
            ["ps", "-o", "stat=,args=", "-g", str(group)], capture_output=True, text=True
        )
        running = [line for line in listed.stdout.splitlines() if not line.startswith("Z")]
        if not any("resource_tracker" in line for line in running):
            return running
        time.sleep(0.1)
    return running


# --- item 16: a closed pipe ---------------------------------------------------------------


def test_a_closed_stdout_pipe_ends_quietly_with_141():
    process = subprocess.Popen(
        [sys.executable, "-m", "pygear", "show-case", DRIVETRAIN],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    process.stdout.close()  # `| head -0`: the reader is gone before the first line
    err = process.stderr.read().decode()
    assert process.wait(timeout=120) == 141, err
    # quiet: no error line and no traceback (the editable build may report a rebuild)
    assert "pygear show-case" not in err and "Traceback" not in err and "Broken" not in err


# --- item 22: what a user reads -----------------------------------------------------------


def test_help_has_no_markup_and_every_option_says_what_it_is():
    parser = build_parser()
    assert "``" not in parser.format_help()
    commands = parser._subparsers._group_actions[0].choices
    assert "CASE" in commands["show-case"].format_usage()
    for action in commands["sensitivity"]._actions:
        if "--dof-set" in action.option_strings:
            assert action.help and "DOF set" in action.help


def test_modal_table_columns_stay_aligned_for_long_names(capsys):
    modal = SimpleNamespace(
        attrs={"case": "c", "formulation": "improved", "dof_set": "planar", "dof_set_reason": "r"},
        frequency=SimpleNamespace(size=2),
        stages=("stage1", "a_very_long_stage_name"),
        stage_name=["stage1", "a_very_long_stage_name"],
        mode_class=["rotational", "coupled-translational-rotational"],
        class_index=[1, 12],
        multiplicity=[1, 2],
    )
    modal.frequency = _Frequencies([10.0, 2000.0])
    modal_cli._print_modal_table(modal)
    rows = capsys.readouterr().out.splitlines()[1:]
    assert len({len(row) for row in rows}) == 1, rows  # the x column ends in one place
    assert rows[0].index("class") == rows[2].index("coupled")


class _Frequencies(list):
    @property
    def size(self) -> int:
        return len(self)


def test_batch_settling_instant_of_a_steady_scene_reads_zero():
    from pygear.runs.batch import _settling_instant

    assert _settling_instant(1.4e-17) == 0.0 and str(_settling_instant(-1e-18)) == "0.0"
    assert _settling_instant(0.123456789) == 0.123456789
    assert _settling_instant(None) != _settling_instant(None)  # NaN


def test_a_busy_dashboard_port_gives_no_warning():
    from pygear.runs.cluster import dask_client

    holder = socket.socket()
    try:
        holder.bind(("127.0.0.1", 8787))
        holder.listen()
    except OSError:
        pass  # someone holds it already: the same situation
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            with dask_client(workers=1, processes=False) as client:
                assert client.submit(sum, [1, 2]).result() == 3
        assert not [w for w in caught if "8787" in str(w.message)], caught
    finally:
        holder.close()


@pytest.mark.parametrize(
    "command",
    [
        ["run", "yang2016_planetary", "--scene", "modal"],
        ["rate", "nrel5mw_gearbox"],
        ["contact", "yang2016_planetary", "--mesh", "planetary.sun-planet1", "--torque", "100"],
    ],
)
def test_out_of_a_file_is_refused_before_any_work_for_every_directory_command(
    command, tmp_path, capsys
):
    # an existing file, and a name with a file's suffix, where a command writes a directory
    existing = tmp_path / "taken"
    existing.write_text("keep me")
    for out in (existing, tmp_path / "y.nc"):
        assert main([*command, "--out", str(out)]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and "--out" in err
    assert existing.read_text() == "keep me"
    assert not (tmp_path / "y.nc").exists()


def test_mesh_stiffness_out_of_a_directory_is_refused(tmp_path, capsys):
    folder = tmp_path / "m.nc"
    folder.mkdir()
    assert main(["mesh-stiffness", "yang2016_planetary", "--out", str(folder)]) == 2
    assert "is a directory" in capsys.readouterr().err


def test_tsa_help_and_data_model_page_name_the_same_file(capsys):
    # the help once said RUN_tsa_<gear>.nc while the files (and the data-model page) are
    # RUN_tsa_<stage>_<gear>.nc, e.g. steady_sensor_tsa_planetary_sun.nc
    import re
    from pathlib import Path

    with pytest.raises(SystemExit):
        main(["analyze", "--help"])
    help_text = " ".join(capsys.readouterr().out.split())
    in_help = re.search(r"RUN_tsa_(<[a-z]+>(?:_<[a-z]+>)*)\.nc", help_text).group(1)
    page = (Path(__file__).resolve().parent.parent / "docs" / "data_model.md").read_text()
    in_page = re.search(r"<RUN>_tsa_(<[a-z]+>(?:_<[a-z]+>)*)\.nc", page).group(1)
    assert in_help == in_page == "<stage>_<gear>"


def test_a_bad_range_names_its_own_flag(capsys):
    # one range parser for every command: frf's --frequencies once blamed --speeds
    code = main(["frf", "friswell_rotor", "--frf", "a,b", "--frequencies", "50:10:5"])
    err = capsys.readouterr().err
    assert code == 2 and "--frequencies" in err and "--speeds" not in err
    assert main(["response", "yang2016_planetary", "--speeds", "0:100:3"]) == 2
    assert "0 < START <= STOP" in capsys.readouterr().err
    assert main(["campbell", "yang2016_planetary", "--speeds", "0:100:1"]) == 2
    assert "COUNT must be a whole number >= 2" in capsys.readouterr().err
