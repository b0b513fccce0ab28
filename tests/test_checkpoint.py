"""Checkpoint and resume, signals and crashes.

A real ``pygear run`` process is stopped by SIGINT or SIGTERM (what SLURM sends) and
resumed with ``--resume``: the result must be bit-identical to an uninterrupted run
(every sample, the final state of every DOF, t_s and the equilibrium speeds).  A
process killed outright (SIGKILL) or a run that raises must never leave a file that
looks complete: the final name is absent or still holds the previous complete file,
and a checkpoint is either absent or a whole one that resumes bit-identically.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pygear import load_case
from pygear.cli import main
from pygear.io import write_netcdf
from pygear.runs.transient_outputs import write_transient

STUDY = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"
SCENE = "long"
STEPS = 400_000  # 10 s of the run-up at 2.5e-5 s: about 0.5 s of kernel time
CASE_FILE = f"""
import dataclasses

from pygear import load_case

base = load_case({str(STUDY)!r})
runup = base.scene("runup")
settings = dataclasses.replace(
    runup.transient, duration={STEPS} * 2.5e-5, sample_rate=40.0, full_state=True
)
case = dataclasses.replace(
    base,
    name="checkpointed",
    scenes=(dataclasses.replace(runup, name={SCENE!r}, analyses=("transient",),
                                transient=settings),),
)
"""


def _command() -> list[str]:
    """The ``pygear`` console script of this interpreter (or the module behind it)."""
    script = Path(sys.executable).with_name("pygear")
    return [str(script)] if script.is_file() else [sys.executable, "-m", "pygear.cli"]


@pytest.fixture(scope="module")
def case_dir(tmp_path_factory) -> Path:
    """A case directory with one 10 s run-up scene keeping the full state at 40 Hz."""
    directory = tmp_path_factory.mktemp("checkpointed")
    (directory / "case.py").write_text(CASE_FILE)
    return directory


@pytest.fixture(scope="module")
def uninterrupted(case_dir, tmp_path_factory) -> xr.Dataset:
    """The scene run in one go."""
    out = tmp_path_factory.mktemp("whole")
    assert main(["run", str(case_dir), "--out", str(out), "--json"]) == 0
    with xr.open_dataset(out / f"{SCENE}.nc") as run:
        return run.load()


def _assert_bit_identical(resumed: xr.Dataset, whole: xr.Dataset) -> None:
    assert resumed.sizes["time"] == STEPS // 1000 + 1
    assert set(resumed.data_vars) == set(whole.data_vars)
    for name in whole.data_vars:
        assert np.array_equal(resumed[name].values, whole[name].values, equal_nan=True), name
    for quantity in ("displacement", "velocity", "acceleration"):  # the final state
        for kind in (f"translation_{quantity}", f"rotation_{quantity}"):
            final = resumed[kind].isel(time=-1).values
            assert np.array_equal(final, whole[kind].isel(time=-1).values), kind
    assert float(resumed.t_s) > 0  # the load law switched on in both


def _start_run(case_dir: Path, out: Path, every: str) -> tuple[subprocess.Popen, Path]:
    log = out.parent / f"{out.name}.stderr"
    with open(log, "w") as stderr:
        process = subprocess.Popen(
            [*_command(), "run", str(case_dir), "--out", str(out), "--checkpoint-every", every],
            stdout=subprocess.DEVNULL,
            stderr=stderr,
        )
    return process, log


def _wait_for(path: Path, process: subprocess.Popen, timeout: float = 120.0) -> None:
    deadline = time.monotonic() + timeout
    while not path.exists():
        if process.poll() is not None:
            pytest.fail(f"pygear run ended (code {process.returncode}) before {path.name}")
        if time.monotonic() > deadline:
            process.kill()
            pytest.fail(f"{path.name} did not appear")
        time.sleep(0.005)


def _visible(directory: Path) -> list[str]:
    """Files that look like results (hidden temporaries excluded)."""
    return sorted(p.name for p in directory.iterdir() if not p.name.startswith("."))


@pytest.mark.parametrize(("signum", "code"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signal_stops_pygear_run_and_resume_is_bit_identical(
    case_dir, uninterrupted, tmp_path, signum, code
):
    out = tmp_path / "out"
    checkpoint = out / f"{SCENE}.checkpoint.npz"
    process, log = _start_run(case_dir, out, "0.05")
    _wait_for(checkpoint, process)
    process.send_signal(signum)
    assert process.wait(timeout=120) == code
    message = log.read_text()
    name = signal.Signals(signum).name
    assert f"by {name}; state saved to {checkpoint}" in message
    assert "no result file written" in message
    assert _visible(out) == [checkpoint.name]  # no .nc, no figure
    with np.load(checkpoint) as saved:
        assert 0 < int(saved["istate"][0]) < STEPS  # stopped mid-run

    assert main(["run", str(case_dir), "--out", str(out), "--resume", "--json"]) == 0
    assert not checkpoint.exists()  # removed once the result is written
    with xr.open_dataset(out / f"{SCENE}.nc") as resumed:
        _assert_bit_identical(resumed.load(), uninterrupted)


def test_sigkill_never_leaves_a_complete_looking_file(case_dir, uninterrupted, tmp_path):
    """Killed while checkpointing after every chunk: no result file; the checkpoint, when
    there is one, is whole and resumes to the uninterrupted result."""
    out = tmp_path / "out"
    checkpoint = out / f"{SCENE}.checkpoint.npz"
    process, _ = _start_run(case_dir, out, "1e-9")
    _wait_for(checkpoint, process)
    time.sleep(0.05)  # a few more chunks and checkpoint writes
    process.kill()
    assert process.wait(timeout=60) == -signal.SIGKILL
    assert not (out / f"{SCENE}.nc").exists()
    assert _visible(out) == [checkpoint.name]
    with np.load(checkpoint) as saved:
        assert 0 < int(saved["istate"][0]) < STEPS
    assert main(["run", str(case_dir), "--out", str(out), "--resume", "--json"]) == 0
    with xr.open_dataset(out / f"{SCENE}.nc") as resumed:
        _assert_bit_identical(resumed.load(), uninterrupted)


KILL_IN_CHECKPOINT = """
import os, signal, sys
import numpy as np
from pygear import load_case
from pygear.runs.transient_outputs import write_transient

saves = []
real_savez = np.savez

def savez(handle, **arrays):
    saves.append(1)
    if len(saves) == 2:  # the second checkpoint: half written, then the power goes
        handle.write(b"PK\\x03\\x04" + b"\\0" * 4096)
        handle.flush()
        os.kill(os.getpid(), signal.SIGKILL)
    real_savez(handle, **arrays)

np.savez = savez
case = load_case(sys.argv[1])
out = sys.argv[2]
write_transient(case, case.scene(sys.argv[3]), out, checkpoint=os.path.join(out, "state.npz"),
                checkpoint_every=1e-9, figure=False)
"""


def test_sigkill_while_writing_a_checkpoint_keeps_the_previous_one(
    case_dir, uninterrupted, tmp_path
):
    out = tmp_path / "out"
    out.mkdir()
    result = subprocess.run(
        [sys.executable, "-c", KILL_IN_CHECKPOINT, str(case_dir), str(out), SCENE],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == -signal.SIGKILL, result.stderr
    assert _visible(out) == ["state.npz"]  # the half-written one kept its hidden name
    assert [p.name.endswith(".part") for p in out.iterdir() if p.name.startswith(".")] == [True]
    case = load_case(case_dir)
    dataset, _ = write_transient(
        case, case.scene(SCENE), out, checkpoint=out / "state.npz", resume=out / "state.npz"
    )
    _assert_bit_identical(dataset, uninterrupted)


KILL_IN_NETCDF = """
import os, signal, sys
import xarray as xr
from pygear.io import write_netcdf

def partial(self, path, **kwargs):
    with open(path, "wb") as handle:  # the first bytes of an HDF5 file, then the crash
        handle.write(b"\\x89HDF\\r\\n\\x1a\\n" + b"\\0" * 4096)
    os.kill(os.getpid(), signal.SIGKILL)

xr.Dataset.to_netcdf = partial
write_netcdf(xr.Dataset({"x": ("t", [2.0, 2.0])}), sys.argv[1], title="second")
"""


def test_sigkill_while_writing_netcdf_keeps_the_previous_file(tmp_path):
    target = tmp_path / "run.nc"
    write_netcdf(xr.Dataset({"x": ("t", [1.0, 1.0])}), target, title="first")
    result = subprocess.run(
        [sys.executable, "-c", KILL_IN_NETCDF, str(target)], capture_output=True, timeout=120
    )
    assert result.returncode == -signal.SIGKILL
    with xr.open_dataset(target) as kept:
        assert kept.attrs["title"] == "first" and kept.x.values.tolist() == [1.0, 1.0]
    leftovers = [p.name for p in tmp_path.iterdir() if p != target]
    assert len(leftovers) == 1 and leftovers[0].startswith(".run.nc.")
    assert leftovers[0].endswith(".part")


def test_exception_while_writing_netcdf_leaves_the_previous_file(tmp_path, monkeypatch):
    target = tmp_path / "run.nc"
    write_netcdf(xr.Dataset({"x": ("t", [1.0])}), target, title="first")

    def failing(self, path, **kwargs):
        Path(path).write_bytes(b"\x89HDF\r\n\x1a\n")
        raise OSError("disk full")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", failing)
    with pytest.raises(OSError, match="disk full"):
        write_netcdf(xr.Dataset({"x": ("t", [2.0])}), target, title="second")
    monkeypatch.undo()
    assert [p.name for p in tmp_path.iterdir()] == ["run.nc"]  # temporary removed
    with xr.open_dataset(target) as kept:
        assert kept.attrs["title"] == "first"


def test_exception_during_a_run_writes_no_result(tmp_path):
    """A run that fails mid-way (here its progress callback) writes neither a result nor
    a figure; its last checkpoint is whole."""
    case = load_case(STUDY)
    scene = case.scene("runup")
    calls = []

    def failing(done, total):
        calls.append(done)
        if len(calls) == 3:
            raise RuntimeError("monitor crashed")

    with pytest.raises(RuntimeError, match="monitor crashed"):
        write_transient(
            case,
            scene,
            tmp_path,
            progress=failing,
            checkpoint=tmp_path / "state.npz",
            checkpoint_every=1e-9,
        )
    assert [p.name for p in tmp_path.iterdir()] == ["state.npz"]
    with np.load(tmp_path / "state.npz") as saved:
        assert int(saved["istate"][0]) == calls[1]  # the one written after chunk 2


def test_sigterm_in_process_stops_between_chunks(tmp_path):
    """SIGTERM is deferred like Ctrl-C: the chunk finishes, the state is saved, the
    previous handlers come back."""
    case = load_case(STUDY)
    scene = case.scene("runup")
    before = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    calls = []

    def terminate(done, total):
        calls.append(done)
        if len(calls) == 1:
            os.kill(os.getpid(), signal.SIGTERM)

    from pygear.kernel.newmark import TransientInterrupted

    with pytest.raises(TransientInterrupted, match=r"by SIGTERM; state saved") as stopped:
        write_transient(
            case, scene, tmp_path, progress=terminate, checkpoint=tmp_path / "state.npz"
        )
    assert stopped.value.signal_number == signal.SIGTERM
    assert len(calls) == 1
    assert {s: signal.getsignal(s) for s in before} == before
    with np.load(tmp_path / "state.npz") as saved:
        assert int(saved["istate"][0]) == calls[0]
    assert [p.name for p in tmp_path.iterdir()] == ["state.npz"]


def test_resume_refuses_a_checkpoint_of_other_settings(case_dir, tmp_path, capsys):
    """A checkpoint is tied to the inputs and settings that wrote it."""
    out = tmp_path / "out"
    out.mkdir()
    study = load_case(STUDY)
    with pytest.raises(KeyboardInterrupt):
        write_transient(
            study,
            study.scene("runup"),
            out,
            progress=lambda done, total: (_ for _ in ()).throw(KeyboardInterrupt),
            checkpoint=out / f"{SCENE}.checkpoint.npz",
        )
    assert main(["run", str(case_dir), "--out", str(out), "--resume"]) == 2
    assert "was written by different settings or inputs" in capsys.readouterr().err
    assert not (out / f"{SCENE}.nc").exists()
