"""Streamed transient files (issue #32.1): samples appended to ``<scene>.nc`` as the run
goes, O(block) memory, never a partial file that looks complete, resumable.

The reference of every comparison is the whole-record write of the same run (the
kernel's record held in memory and written at the end, today's path).  Channels are
compared to 1e-12 relative: the kernel is the same code on the same state, so the
samples are bit-identical, and only what is summed differently may differ by rounding
(a sensor's structural filter run block by block with its state carried, its noise
power summed block by block: a few ulp).
"""

from __future__ import annotations

import dataclasses
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pygear import Probe, load_case
from pygear.io import IncompleteFileError, open_dataset
from pygear.model.reduction_settings import Reductions
from pygear.runs import streaming
from pygear.runs.transient_outputs import write_transient

STUDY = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"
VOLATILE = {"history", "source", "wall_s", "solver_wall_s", "complete"}  # time, git revision
RTOL = 1e-12  # summation order only (see the module docstring)


def _assert_same_attrs(a: dict, b: dict, where: str, skip=frozenset()) -> None:
    assert set(a) - skip == set(b) - skip, where
    for key in set(b) - skip:
        x, y = np.asarray(a[key]), np.asarray(b[key])
        if x.dtype.kind == "f":
            np.testing.assert_allclose(x, y, rtol=RTOL, equal_nan=True, err_msg=f"{where} {key}")
        else:
            assert np.array_equal(x, y), f"{where} {key}"


def _assert_same_file(streamed: Path, whole: Path) -> None:
    """Every variable, coordinate and attribute of two run files equal (to RTOL), read
    both through pygear and through plain xarray."""
    for opener in (open_dataset, lambda p: xr.open_dataset(p, decode_times=False)):
        with opener(streamed) as a, opener(whole) as b:
            assert set(a.variables) == set(b.variables)
            assert a.sizes == b.sizes
            for name in b.variables:
                x, y = a[name].values, b[name].values
                assert x.dtype == y.dtype, name
                if x.dtype.kind == "f":
                    np.testing.assert_allclose(
                        x, y, rtol=RTOL, atol=0, equal_nan=True, err_msg=name
                    )
                else:
                    assert np.array_equal(x, y), name
                _assert_same_attrs(a[name].attrs, b[name].attrs, name)
            _assert_same_attrs(a.attrs, b.attrs, "global", skip=VOLATILE)
    with xr.open_dataset(streamed) as plain:
        assert int(plain.attrs["complete"]) == 1
        assert "stream_identity" not in plain.attrs
        assert plain.time.encoding["zlib"]  # chunked along time and compressed
        assert "time" in plain.encoding.get("unlimited_dims", set())


@pytest.fixture(scope="module")
def study():
    return load_case(STUDY)


def _short(case, name: str, duration: float, **changes):
    scene = case.scene(name)
    settings = dataclasses.replace(scene.transient, duration=duration, **changes)
    return dataclasses.replace(scene, transient=settings, analyses=("transient",))


def test_streamed_file_equals_the_whole_record_write(study, tmp_path, monkeypatch):
    """The run-up streamed in blocks of 1024 samples (many appends, HDF5 chunks written
    in pieces) gives the file the whole-record write gives."""
    scene = _short(study, "runup", 1.0, mean_window=0.2)
    write_transient(study, scene, tmp_path / "whole", figure=False, stream=False)
    monkeypatch.setattr(streaming, "BUFFER_BYTES", 1024 * 8 * 10)  # 1024 samples a block
    dataset, files = write_transient(study, scene, tmp_path / "streamed", figure=False, stream=True)
    assert [f.name for f in files] == ["runup.nc"]
    assert sorted(p.name for p in (tmp_path / "streamed").iterdir()) == ["runup.nc"]
    _assert_same_file(tmp_path / "streamed" / "runup.nc", tmp_path / "whole" / "runup.nc")
    assert dataset.sizes["time"] == 40001 and float(dataset.t_s) == float(dataset.t_s)


def test_streamed_sensor_with_structure_and_noise_equals_the_whole_record(study, tmp_path):
    """A sensor's structural mode (an IIR filter, state carried over blocks) and its
    noise (power of the whole record, added from the file after the run) as the whole
    record gives them: grouped and as a named variable."""
    sensor = dataclasses.replace(study.sensors[0], noise_snr_db=10.0, noise_seed=7)
    case = dataclasses.replace(study, sensors=(sensor,))
    scene = _short(case, "steady_sensor", 0.3, mean_window=0.1)
    probes = (*scene.transient.probes, Probe("sensor", "ring_sensor", name="named_sensor"))
    scene = dataclasses.replace(
        scene, transient=dataclasses.replace(scene.transient, probes=probes)
    )
    write_transient(case, scene, tmp_path / "whole", figure=False, stream=False)
    streaming_buffer = streaming.BUFFER_BYTES
    try:
        streaming.BUFFER_BYTES = 1024 * 8 * 20
        write_transient(case, scene, tmp_path / "streamed", figure=False, stream=True)
    finally:
        streaming.BUFFER_BYTES = streaming_buffer
    _assert_same_file(
        tmp_path / "streamed" / "steady_sensor.nc", tmp_path / "whole" / "steady_sensor.nc"
    )
    with open_dataset(tmp_path / "whole" / "steady_sensor.nc") as whole:
        grouped = whole.sensor_acceleration.sel(sensor="ring_sensor").values
        # the same sensor with the same seed twice: the noise is drawn per sensor in order
        np.testing.assert_array_equal(grouped, whole.named_sensor.values)


KILLED_RUN = """
import dataclasses, sys
from pygear import load_case
from pygear.model.reduction_settings import Reductions
from pygear.runs import streaming
from pygear.runs.transient_outputs import write_transient

import pygear.io

streaming.BUFFER_BYTES = 1024 * 8 * 10
# the code's identity pinned: sources edited between the killed and the resumed process
# (a working tree others edit) would otherwise make the resumed run refuse the partial
pygear.io.source_identity = lambda: "pinned"
case = load_case(sys.argv[1])
scene = case.scene("runup")
reductions = Reductions(keep_frequency=2000.0, statistics=True, rainflow=("mesh_force",),
                        load_duration=("drive_torque",), bins=32)
scene = dataclasses.replace(scene, analyses=("transient",), transient=dataclasses.replace(
    scene.transient, duration=float(sys.argv[3]), mean_window=0.2, reductions=reductions))
write_transient(case, scene, sys.argv[2], checkpoint=sys.argv[2] + "/state.npz",
                checkpoint_every=float(sys.argv[4]), figure=False, stream=True,
                resume=sys.argv[2] + "/state.npz" if len(sys.argv) > 5 else None)
"""


def _killed_scene(case, duration):
    """The killed run's scene, with every reduction (their state crosses the resume)."""
    reductions = Reductions(
        keep_frequency=2000.0,
        statistics=True,
        rainflow=("mesh_force",),
        load_duration=("drive_torque",),
        bins=32,
    )
    return _short(case, "runup", duration, mean_window=0.2, reductions=reductions)


def test_sigkill_half_way_leaves_no_complete_file_and_resume_completes_it(study, tmp_path):
    duration = 4.0
    whole = tmp_path / "whole"
    write_transient(study, _killed_scene(study, duration), whole, figure=False, stream=False)
    out = tmp_path / "out"
    out.mkdir()
    partial = out / ".runup.nc.stream.part"
    process = subprocess.Popen(
        [sys.executable, "-c", KILLED_RUN, str(STUDY), str(out), str(duration), "0.05"],
        stderr=subprocess.PIPE,
    )
    deadline = time.monotonic() + 300
    total = round(duration / 2.5e-5)
    while True:  # kill once the checkpoint is past a quarter of the run
        if process.poll() is not None:
            pytest.fail(f"the run ended first: {process.stderr.read().decode()}")
        state = out / "state.npz"
        if state.is_file():
            try:
                with np.load(state) as saved:
                    step = int(saved["istate"][0])
            except (OSError, ValueError, KeyError):
                step = 0
            if step > total // 4:
                break
        if time.monotonic() > deadline:
            process.kill()
            pytest.fail("no checkpoint past a quarter of the run")
        time.sleep(0.02)
    process.send_signal(signal.SIGKILL)
    assert process.wait(timeout=60) == -signal.SIGKILL
    assert not (out / "runup.nc").exists()
    assert partial.is_file()
    with xr.open_dataset(partial, decode_times=False) as plain:  # plain xarray: marked
        assert int(plain.attrs["complete"]) == 0
        assert 0 < plain.sizes["time"] < total + 1
    with pytest.raises(IncompleteFileError, match="incomplete run"):
        open_dataset(partial)
    from pygear.runs.outputs import read_run_file  # what `pygear analyze` reads a run with

    with pytest.raises(Exception, match="incomplete run"):
        read_run_file(partial, "a run")
    with np.load(out / "state.npz") as saved:
        assert 0 < int(saved["istate"][0]) < total
    result = subprocess.run(
        [sys.executable, "-c", KILLED_RUN, str(STUDY), str(out), str(duration), "1e9", "resume"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stderr
    assert "running runup.nc from the start" not in result.stderr  # continued, not restarted
    assert sorted(p.name for p in out.iterdir()) == ["runup.nc"]
    _assert_same_file(out / "runup.nc", whole / "runup.nc")  # reductions included
    with open_dataset(out / "runup.nc") as resumed:
        assert "rainflow_mesh_force" in resumed and "speed_decimated" in resumed


MEMORY_RUN = """
import dataclasses, json, sys
from pygear import load_case
from pygear.runs.transient_outputs import write_transient

case = load_case(sys.argv[1])
scene = case.scene("runup")
scene = dataclasses.replace(scene, analyses=("transient",), transient=dataclasses.replace(
    scene.transient, duration=float(sys.argv[3]), mean_window=0.2))
write_transient(case, scene, sys.argv[2], figure=False, stream=sys.argv[4] == "1")
# VmHWM: this process's own peak; ru_maxrss keeps the parent's across fork and exec, so
# a large pytest process would set the floor of every measurement
peak = next(line for line in open("/proc/self/status") if line.startswith("VmHWM"))
print(json.dumps(int(peak.split()[1])))
"""


def _peak_rss_mib(tmp_path: Path, duration: float, stream: bool) -> float:
    out = tmp_path / f"{duration}_{int(stream)}"
    result = subprocess.run(
        [sys.executable, "-c", MEMORY_RUN, str(STUDY), str(out), str(duration), str(int(stream))],
        capture_output=True,
        text=True,
        timeout=900,
        env={**os.environ, "OPENBLAS_NUM_THREADS": "1"},
    )
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout.strip().splitlines()[-1]) / 1024


@pytest.mark.slow
def test_peak_memory_does_not_grow_with_the_run_length(tmp_path):
    """Peak RSS of a streamed run 4x longer is the same to within 15 MiB (allocator
    noise; each the least of two processes), while the whole-record run's grows by about
    its record held twice (10 channels x 3e5 more samples x 8 bytes x 2 = 48 MB): the
    test sees the difference."""
    short, long = 2.5, 10.0

    def least_of_two(duration: float, stream: bool) -> float:
        # a process's peak can catch a passing allocation burst: the least of two runs
        return min(_peak_rss_mib(tmp_path / f"r{k}", duration, stream) for k in range(2))

    streamed = [least_of_two(d, True) for d in (short, long)]
    whole = [least_of_two(d, False) for d in (short, long)]
    assert streamed[1] - streamed[0] < 15.0, streamed
    assert whole[1] - whole[0] > 40.0, whole  # the measurement can tell


def test_a_run_stopped_while_its_end_is_written_starts_over_on_resume(study, tmp_path, monkeypatch):
    """Stopped after the last step, while the file's end is written (its noise is added in
    place): the partial file is marked and not continued; --resume runs the scene again
    and gives the whole-record file."""
    scene = _short(study, "runup", 0.3, mean_window=0.1)
    write_transient(study, scene, tmp_path / "whole", figure=False, stream=False)
    out, checkpoint = tmp_path / "out", tmp_path / "out" / "state.npz"

    def stopped(self):
        raise RuntimeError("stopped while finishing")

    monkeypatch.setattr(streaming.StreamedFile, "_add_noise", stopped)
    with pytest.raises(RuntimeError, match="stopped while finishing"):
        write_transient(study, scene, out, figure=False, stream=True, checkpoint=checkpoint)
    monkeypatch.undo()
    assert not (out / "runup.nc").exists() and checkpoint.is_file()
    with xr.open_dataset(out / ".runup.nc.stream.part", decode_times=False) as partial:
        assert int(partial.attrs["complete"]) == 0 and partial.attrs["stream_finishing"] == 1
    with pytest.warns(UserWarning, match="stopped while its end was written"):
        write_transient(
            study, scene, out, figure=False, stream=True, checkpoint=checkpoint, resume=checkpoint
        )
    assert sorted(p.name for p in out.iterdir()) == ["runup.nc"]
    _assert_same_file(out / "runup.nc", tmp_path / "whole" / "runup.nc")


class _CollectingSink:
    """A sink that keeps what it is given (a test's view of a streamed kernel run)."""

    def __init__(self, block_samples: int) -> None:
        self.block_samples = block_samples
        self.blocks: list = []

    def write(self, first, samples):
        self.blocks.append((first, samples.copy()))

    def flush(self):
        pass

    def state(self):
        return {}

    def restore(self, state, written):
        pass


def test_a_streamed_run_that_grows_physically_is_diagnosed_from_its_last_samples(monkeypatch):
    """The divergence diagnostic of a streamed run sees its last samples (not the whole
    record, which it no longer holds) and still names a parametric resonance with the
    Floquet rate (to 1 %, as tests/test_stability.py asks of the whole record)."""
    import functools

    import test_stability

    from pygear.kernel.newmark import BandedNewmark, PhysicalInstabilityError

    sink = _CollectingSink(8192)
    monkeypatch.setattr(BandedNewmark, "run", functools.partialmethod(BandedNewmark.run, sink=sink))
    mesh_frequency = 2 * test_stability.PARAM_FREQUENCY
    with pytest.raises(PhysicalInstabilityError, match="grew physically") as error:
        test_stability.parametric_run(mesh_frequency, 100)
    rate = test_stability.floquet_growth_rate(mesh_frequency)
    assert error.value.diagnostic.rate == pytest.approx(rate, rel=0.01)
    firsts = [first for first, _ in sink.blocks]
    counts = [block.shape[1] for _, block in sink.blocks]
    assert firsts == list(np.cumsum([0, *counts[:-1]]))  # every sample once, in order
    assert max(counts) <= 8192
