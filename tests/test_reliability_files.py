"""Reliability of the files pygear reads and writes.

* Reading a run file never runs code: ``pygear analyze`` takes the natural and mesh
  frequencies it names peaks with from the run file itself, never from the case
  directory its ``case`` attribute names; a run file without them is refused.
* A checkpoint resumes only the run that wrote it: a probe retargeted under the same
  name, a changed case input or another code version refuses it.
* Every file is written under a temporary name and renamed when whole (matrices,
  figures), and no command writes one kind of file over another.
* SIGTERM while the result is written keeps the finished run in its checkpoint and
  leaves no temporary file behind.
"""

from __future__ import annotations

import dataclasses
import json
import os
import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pygear.cli import main
from pygear.io import open_dataset
from pygear.kernel.newmark import TransientError
from pygear.runs.transient_outputs import write_transient

STUDY = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"
RING_TEETH = 96  # Z_r of the study case (Yang, Jiang & Han 2016, Table 1)
ROTATIONAL_2_HZ = 1334.0  # improved model, rotational mode 2 (the same paper, Table 2)
SCENE = "short"
DURATION = 0.5  # s of the paper's run-up: past t_s = 0.156 s, enough for a 0.2 s mean
SHORT_CASE = f"""
import dataclasses

from pygear import load_case

base = load_case({str(STUDY)!r})
runup = base.scene("runup")
settings = dataclasses.replace(runup.transient, duration={DURATION}, mean_window=0.2)
case = dataclasses.replace(
    base,
    name="short_runup",
    scenes=(dataclasses.replace(runup, name={SCENE!r}, analyses=("transient",),
                                transient=settings),),
)
"""
MARKER_CASE = """
from pathlib import Path

Path({marker!r}).write_text("executed")
"""


def _hidden(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.rglob(".*"))


def _visible(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir() if not p.name.startswith("."))


@pytest.fixture(scope="module")
def short_case(tmp_path_factory) -> Path:
    """A case directory with a 0.5 s run-up of the study case."""
    directory = tmp_path_factory.mktemp("short_case")
    (directory / "case.py").write_text(SHORT_CASE)
    return directory


@pytest.fixture(scope="module")
def run_file(short_case, tmp_path_factory) -> Path:
    """The short run-up written by ``pygear run``."""
    out = tmp_path_factory.mktemp("short_run")
    assert main(["run", str(short_case), "--out", str(out), "--json"]) == 0
    return out / f"{SCENE}.nc"


def test_run_states_the_most_it_will_write_before_it_starts(short_case, tmp_path, capsys):
    """Before a transient scene runs, ``pygear run`` says how much its files take at most:
    every channel and spectrum counted uncompressed, so the compressed files never exceed
    it, and no less than the channels' own samples."""
    assert main(["run", str(short_case), "--out", str(tmp_path), "--no-figures"]) == 0
    stderr = capsys.readouterr().err
    stated = re.search(rf"{SCENE}: result files of at most ([\d.]+) (kB|MB|GB)", stderr)
    assert stated, stderr
    estimate = float(stated[1]) * {"kB": 1e3, "MB": 1e6, "GB": 1e9}[stated[2]]
    written = sum(p.stat().st_size for p in tmp_path.rglob("*.nc"))
    with xr.open_dataset(tmp_path / f"{SCENE}.nc", decode_times=False) as run:
        samples = sum(v.nbytes for v in run.data_vars.values() if "time" in v.dims)
    assert samples <= estimate * 1.005  # the estimate is printed to three digits
    assert written <= estimate


def _copy_naming_case(run_file: Path, target: Path, case_reference: str) -> Path:
    """``run_file`` copied to ``target`` with its ``case`` attribute set to ``case_reference``."""
    with xr.open_dataset(run_file, decode_times=False) as opened:  # time as stored
        run = opened.load()
    run.attrs["case"] = case_reference
    run.to_netcdf(target)
    return target


# --- 1. reading a run file never runs code --------------------------------------------------


@pytest.mark.parametrize("reference", ["absolute", "cases_dir"])
def test_analyze_never_executes_the_case_a_run_file_names(
    run_file, tmp_path, monkeypatch, capsys, reference
):
    """A run file naming a case directory (by absolute path, or by a name found under
    ./cases/) is analysed without executing that directory's case.py."""
    marker = tmp_path / "executed.txt"
    case_dir = tmp_path / "cases" / "hostile"
    case_dir.mkdir(parents=True)
    (case_dir / "case.py").write_text(MARKER_CASE.format(marker=str(marker)))
    monkeypatch.chdir(tmp_path)
    name = str(case_dir) if reference == "absolute" else "hostile"
    copied = _copy_naming_case(run_file, tmp_path / "run.nc", name)
    assert main(["analyze", str(copied), "--after", "0.1", "--json"]) == 0
    assert not marker.exists()
    result = json.loads(capsys.readouterr().out)
    with xr.open_dataset(copied) as run, xr.open_dataset(result["files"][0]) as spectra:
        # the spectra are labelled with the mesh frequency the run file carries
        assert float(spectra.attrs["mesh_frequency_hz"]) == run.mesh_frequency.item()


def test_run_file_carries_the_frequencies_analyze_needs(short_case, run_file, tmp_path, capsys):
    """The run holds the scene model's natural frequencies and its mesh frequency, so
    it is analysed with every peak reference after its case directory is gone."""
    with open_dataset(run_file) as opened:
        run = opened.load()
    assert run.natural_frequency.attrs["units"] == "Hz"
    assert run.mesh_frequency.attrs["units"] == "Hz"
    rotational = np.sort(run.natural_frequency.values[run.mode_class.values == "rotational"])
    # the paper's Table 2; pygear's model is within 0.25 % of it (0.5 % allowed)
    assert rotational[1] == pytest.approx(ROTATIONAL_2_HZ, rel=5e-3)
    carrier = float(run.equilibrium_speed.sel(body="planetary.carrier"))
    ring = float(run.equilibrium_speed.sel(body="planetary.ring"))
    # planetary mesh frequency Z_r |n_c - n_r| / 60; only round-off differs
    assert run.mesh_frequency.item() == pytest.approx(
        RING_TEETH * abs(carrier - ring) / 60.0, rel=1e-12
    )
    assert run.mesh_teeth.item() == RING_TEETH

    moved = tmp_path / "kept.nc"
    shutil.copy(run_file, moved)
    gone = tmp_path / "gone"
    shutil.copytree(short_case, gone)
    with xr.open_dataset(moved, decode_times=False) as opened:  # time as stored
        run = opened.load()
    run.attrs["case"] = str(gone)
    run.to_netcdf(moved, mode="w")
    shutil.rmtree(gone)
    assert main(["analyze", str(moved), "--after", "0.1", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    named = [p["near_natural_frequency"] for p in result["spectrum"]]
    assert any("rotational" in n or "translational" in n for n in named), named


def test_analyze_refuses_an_old_run_file_without_its_frequencies(tmp_path, capsys):
    """A pygear run file written before the frequencies were stored: one line, exit 2,
    saying to rerun; its case is not executed."""
    marker = tmp_path / "executed.txt"
    case_dir = tmp_path / "old_case"
    case_dir.mkdir()
    (case_dir / "case.py").write_text(MARKER_CASE.format(marker=str(marker)))
    time = np.arange(0, 1.0, 1 / 40e3)
    old = xr.Dataset(
        {"ring_y_acceleration": ("time", np.sin(2 * np.pi * 7000 * time), {"units": "m/s^2"})},
        coords={"time": ("time", time, {"units": "s"})},
        attrs={"case": str(case_dir), "formulation": "improved", "source": "pygear 0.1.0"},
    )
    old.to_netcdf(tmp_path / "old.nc")
    assert main(["analyze", str(tmp_path / "old.nc"), "--after", "0.1"]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1
    assert "rerun" in error and "old.nc" in error
    assert not marker.exists()
    assert _visible(tmp_path) == ["old.nc", "old_case"]


# --- 2. a checkpoint resumes only the run that wrote it -------------------------------------


def _short_scene(case, **changes):
    scene = case.scene("runup")
    settings = dataclasses.replace(scene.transient, duration=0.2, mean_window=0.1, **changes)
    return dataclasses.replace(scene, name=SCENE, analyses=("transient",), transient=settings)


def _interrupted_checkpoint(case, scene, out: Path) -> Path:
    """Stop ``scene`` after its first chunk, leaving its checkpoint in ``out``."""
    checkpoint = out / f"{SCENE}.checkpoint.npz"

    def stop(done, total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_transient(case, scene, out, progress=stop, checkpoint=checkpoint)
    with np.load(checkpoint) as saved:
        assert 0 < int(saved["istate"][0]) < 8000  # stopped mid-run
    return checkpoint


def _retarget_probe(case):
    from pygear.model.transient_settings import Probe

    scene = _short_scene(case)
    probes = (Probe("speed", "planetary.carrier", name="watched"),)
    before = dataclasses.replace(
        scene, transient=dataclasses.replace(scene.transient, probes=probes)
    )
    probes = (Probe("speed", "planetary.sun", name="watched"),)
    after = dataclasses.replace(
        scene, transient=dataclasses.replace(scene.transient, probes=probes)
    )
    return (case, before), (case, after)


def _change_tooth_numbers(case):
    # constant mesh stiffness: the tooth numbers shape the mesh frequency written, not
    # the state integrated.  30/39/105 keep the base-radius ratios of the study case
    # (ring/sun 3.553, planet/sun 1.297) within 2 % and (Z_s + Z_r)/3 whole.
    scene = dataclasses.replace(_short_scene(case), effects=())
    stage = case.gearbox.stages[0]
    stage = dataclasses.replace(
        stage,
        sun=dataclasses.replace(stage.sun, teeth=30),
        planet=dataclasses.replace(stage.planet, teeth=39),
        ring=dataclasses.replace(stage.ring, teeth=105),
    )
    changed = dataclasses.replace(case, gearbox=dataclasses.replace(case.gearbox, stages=(stage,)))
    return (case, scene), (changed, scene)


@pytest.mark.parametrize("change", [_retarget_probe, _change_tooth_numbers])
def test_resume_refuses_a_checkpoint_of_other_outputs(study_case, tmp_path, change):
    (case, scene), (changed_case, changed_scene) = change(study_case)
    checkpoint = _interrupted_checkpoint(case, scene, tmp_path)
    with pytest.raises(TransientError, match="written by different settings or inputs"):
        write_transient(
            changed_case, changed_scene, tmp_path, checkpoint=checkpoint, resume=checkpoint
        )
    assert _visible(tmp_path) == [checkpoint.name] and not _hidden(tmp_path)


def test_resume_refuses_a_checkpoint_of_another_code_version(study_case, tmp_path, monkeypatch):
    import pygear.io

    scene = _short_scene(study_case)
    checkpoint = _interrupted_checkpoint(study_case, scene, tmp_path)
    monkeypatch.setattr(pygear.io, "source_identity", lambda: "0123456789abcdef")
    with pytest.raises(TransientError, match="written by different settings or inputs"):
        write_transient(study_case, scene, tmp_path, checkpoint=checkpoint, resume=checkpoint)


def test_resume_accepts_its_own_checkpoint(study_case, tmp_path):
    """The key is stable: the same case and scene resume (to the full length)."""
    scene = _short_scene(study_case)
    checkpoint = _interrupted_checkpoint(study_case, scene, tmp_path)
    dataset, _ = write_transient(
        study_case, scene, tmp_path, checkpoint=checkpoint, resume=checkpoint, figure=False
    )
    assert dataset.sizes["time"] == 8001  # 0.2 s at 40 kHz, both ends
    assert not checkpoint.exists()


# --- 3. atomic writes, and no file of another kind overwritten --------------------------------


def _disk_full(*args, **kwargs):
    target = args[0]
    if hasattr(target, "write"):
        target.write(b"PK\x03\x04" + b"\0" * 64)
    else:
        Path(target).write_bytes(b"PK\x03\x04" + b"\0" * 64)
    raise OSError(28, "No space left on device")


def test_matrices_keeps_the_previous_file_when_the_disk_is_full(tmp_path, monkeypatch, capsys):
    """A full disk is no bad input: exit 1 with the error in one line, the old file kept."""
    target = tmp_path / "m.npz"
    np.savez(target, M=np.eye(2))
    monkeypatch.setattr(np, "savez", _disk_full)
    assert main(["matrices", str(STUDY), "--out", str(target)]) == 1
    error = capsys.readouterr().err.strip()
    assert "No space left" in error and "\n" not in error
    monkeypatch.undo()
    assert _visible(tmp_path) == ["m.npz"] and not _hidden(tmp_path)
    with np.load(target) as kept:
        assert kept["M"].tolist() == [[1.0, 0.0], [0.0, 1.0]]


def test_a_figure_that_fails_leaves_no_file(tmp_path, monkeypatch, capsys):
    """``pygear modal --out``: a figure whose writing fails is not left half written."""
    from matplotlib.figure import Figure

    monkeypatch.setattr(Figure, "savefig", lambda self, target, **kw: _disk_full(target))
    assert main(["modal", str(STUDY), "--out", str(tmp_path)]) == 1
    error = capsys.readouterr().err.strip()
    assert "No space left" in error and "\n" not in error
    monkeypatch.undo()
    assert not any(name.endswith(".png") for name in _visible(tmp_path))
    assert not _hidden(tmp_path)


@pytest.mark.parametrize(
    ("command", "target", "rule"),
    [
        (["mesh-stiffness", str(STUDY)], "stiffness.png", "--out"),
        (["mesh-stiffness", str(STUDY)], "stiffness.npz", "--out"),
        (["matrices", str(STUDY)], "matrices.nc", "--out"),
        (["matrices", str(STUDY)], "matrices.png", "--out"),
    ],
)
def test_out_of_another_kind_is_refused(tmp_path, capsys, command, target, rule):
    path = tmp_path / target
    path.write_bytes(b"someone else's file")
    assert main([*command, "--out", str(path)]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and rule in error and path.suffix in error
    assert path.read_bytes() == b"someone else's file"
    assert _visible(tmp_path) == [target]


def test_mesh_stiffness_writes_netcdf_and_figure_beside(tmp_path):
    target = tmp_path / "stiffness.nc"
    assert main(["mesh-stiffness", str(STUDY), "--out", str(target)]) == 0
    assert _visible(tmp_path) == ["stiffness.nc", "stiffness.png"]
    with xr.open_dataset(target) as written:
        assert "mesh" in written.dims
    assert target.with_suffix(".png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_analyze_never_writes_over_its_run_file(run_file, tmp_path, capsys):
    copied = tmp_path / "run.nc"
    shutil.copy(run_file, copied)
    before = copied.read_bytes()
    assert main(["analyze", str(copied), "--after", "0.1", "--out", str(copied)]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and "--out" in error
    assert copied.read_bytes() == before
    assert _visible(tmp_path) == ["run.nc"]


# --- 4. SIGTERM while the result is written --------------------------------------------------

TERMINATE_IN_WRITE = """
import os, signal, sys

import xarray as xr

from pygear.cli import main

real_to_netcdf = xr.Dataset.to_netcdf


def to_netcdf(self, path, *args, **kwargs):
    real_to_netcdf(self, path, *args, **kwargs)  # the whole file, under its temporary name
    if os.path.basename(str(path)).startswith(sys.argv[2]):
        os.kill(os.getpid(), signal.SIGTERM)  # what a scheduler sends at its time limit


xr.Dataset.to_netcdf = to_netcdf
sys.exit(main(sys.argv[3:]))
"""


def _terminated_in_write(stem: str, argv: list[str]) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", TERMINATE_IN_WRITE, "-", f".{stem}", *argv],
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_sigterm_while_writing_the_result_keeps_the_finished_run(short_case, tmp_path):
    """The run finished; SIGTERM arrives while ``short.nc`` is written.  The temporary
    file is removed, the checkpoint holds the finished state, and ``--resume`` writes
    the result from it without integrating again."""
    out = tmp_path / "out"
    checkpoint = out / f"{SCENE}.checkpoint.npz"
    steps = round(DURATION / 2.5e-5)
    run = ["run", str(short_case), "--out", str(out), "--checkpoint-every", "1e9"]
    stopped = _terminated_in_write(f"{SCENE}.nc", run)
    assert stopped.returncode == 128 + signal.SIGTERM, stopped.stderr
    assert "Traceback" not in stopped.stderr
    message = stopped.stderr.strip().splitlines()[-1]  # after the progress bar
    assert message.startswith("pygear run: scene short: interrupted by SIGTERM while writing")
    assert f"kept in {checkpoint}" in message and "--resume" in message
    assert not _hidden(out)
    assert _visible(out) == [checkpoint.name]
    with np.load(checkpoint) as saved:
        assert int(saved["istate"][0]) == steps  # the finished run
        samples = saved["samples"]

    assert main([*run[:4], "--resume", "--json"]) == 0
    assert _visible(out) == [f"{SCENE}.nc", f"{SCENE}_speeds.png"] and not _hidden(out)
    with open_dataset(out / f"{SCENE}.nc") as resumed:
        assert int(resumed.attrs["steps"]) == steps
        assert resumed.sizes["time"] == samples.shape[1] == steps + 1  # 40 kHz = every step
        # the probes as the finished run recorded them, not a second integration
        carrier = resumed.speed.sel(member="planetary.carrier")
        assert np.array_equal(carrier.values, samples[0])
        assert np.array_equal(resumed.load_torque.values, samples[9])


def test_sigterm_while_writing_a_modal_file_leaves_no_temporary(tmp_path):
    stopped = _terminated_in_write(
        "modal_improved.nc", ["modal", str(STUDY), "--out", str(tmp_path)]
    )
    assert stopped.returncode == 128 + signal.SIGTERM, stopped.stderr
    assert "SIGTERM" in stopped.stderr and len(stopped.stderr.strip().splitlines()) == 1
    assert os.listdir(tmp_path) == []
