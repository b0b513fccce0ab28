"""On-the-fly reductions of a streamed run (issue #32.2): each one, counted block by
block with its state carried, equals the count of the whole record.

Rainflow cycles and the histograms are compared exactly: they are the same operations
on the same numbers (the cycle list of ``rainflow.extract_cycles``; bin indices floor(x
/ 2^e), exact in binary).  Sums of floats (statistics, time-at-level weights, the FIR
outputs) are compared to 1e-12 relative: the same terms added in another grouping.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
import rainflow
from scipy.signal import chirp

from pygear import load_case
from pygear.analysis.time.reductions import (
    Decimator,
    Pow2Histogram,
    RunningStatistics,
    StreamingRainflow,
    decimation_factor,
    lowpass_taps,
)
from pygear.errors import CaseError
from pygear.io import open_dataset
from pygear.model.reduction_settings import Reductions
from pygear.runs import streaming
from pygear.runs.transient_outputs import write_transient

STUDY = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"
RTOL = 1e-12  # float sums regrouped (see the module docstring)


def _blocks(values: np.ndarray, rng, pieces: int) -> list[np.ndarray]:
    """``values`` cut at random places, empty and one-sample blocks among them."""
    cuts = np.sort(rng.integers(0, values.shape[-1], pieces))
    cuts = np.concatenate([cuts, [cuts[0], cuts[0] + 1]])  # an empty and a single one
    return np.split(values, np.sort(cuts), axis=-1)


def _signal(rng, n: int = 20_000) -> np.ndarray:
    """A random walk with plateaus (equal neighbours) and repeated levels: what trips a
    reversal detector."""
    x = np.round(np.cumsum(rng.normal(size=n)), 1)
    x[100:130] = x[100]
    x[-20:] = x[-20]
    return x


def _whole_cycles(x: np.ndarray) -> np.ndarray:
    return np.array([(r, m, c) for r, m, c, *_ in rainflow.extract_cycles(x)])


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_streamed_rainflow_cycles_are_the_packages_whole_record_cycles(seed):
    rng = np.random.default_rng(seed)
    x = _signal(rng)
    counter = StreamingRainflow()
    parts = [counter.update(block) for block in _blocks(x, rng, 40)]
    parts.append(counter.finish())
    streamed = np.concatenate(parts)
    np.testing.assert_array_equal(streamed, _whole_cycles(x))  # same cycles, same order


def test_rainflow_residue_survives_a_checkpoint():
    """The carried state (stack, last point, slope) through state()/restore() resumes
    the count exactly."""
    rng = np.random.default_rng(5)
    x = _signal(rng)
    first = StreamingRainflow()
    head = first.update(x[:7000])
    resumed = StreamingRainflow()
    resumed.restore({k: np.array(v) for k, v in first.state().items()})
    rest = np.concatenate([resumed.update(x[7000:]), resumed.finish()])
    np.testing.assert_array_equal(np.concatenate([head, rest]), _whole_cycles(x))


def test_rainflow_matrix_in_blocks_equals_the_whole_record_matrix():
    rng = np.random.default_rng(3)
    x = _signal(rng) * 1e3 + 5e4  # a mesh force: offset, large
    cycles = _whole_cycles(x)
    whole = Pow2Histogram(2, 32)
    whole.update(cycles[:, :2], cycles[:, 2])
    counter, streamed = StreamingRainflow(), Pow2Histogram(2, 32)
    for block in _blocks(x, rng, 25):
        part = counter.update(block)
        streamed.update(part[:, :2], part[:, 2])
    part = counter.finish()
    streamed.update(part[:, :2], part[:, 2])
    (counts, edges), (counts_w, edges_w) = streamed.result(), whole.result()
    np.testing.assert_array_equal(edges, edges_w)
    np.testing.assert_array_equal(counts, counts_w)
    # the matrix is the plain 2-D histogram of the cycles over those edges
    reference, _, _ = np.histogram2d(
        cycles[:, 0], cycles[:, 1], bins=(edges[0], edges[1]), weights=cycles[:, 2]
    )
    np.testing.assert_array_equal(counts[..., 0], reference)
    assert counts.sum() == cycles[:, 2].sum()  # no cycle outside the bins
    widths = np.diff(edges, axis=1)
    assert np.all(np.log2(widths) == np.round(np.log2(widths)))  # powers of two


def test_statistics_in_blocks_equal_the_whole_record():
    rng = np.random.default_rng(4)
    x = rng.normal(3.0, 2.0, size=(3, 10_001))
    statistics = RunningStatistics(3)
    for block in _blocks(x, rng, 30):
        statistics.update(block)
    expected = np.stack(
        [x.min(1), x.max(1), x.mean(1), np.sqrt(np.mean(np.square(x), axis=1))], axis=1
    )
    np.testing.assert_allclose(statistics.result(), expected, rtol=RTOL)


def test_decimator_in_blocks_equals_filtering_the_whole_record():
    rng = np.random.default_rng(6)
    factor = decimation_factor(40_000.0, 1000.0)
    taps = lowpass_taps(factor, 40_000.0, 1000.0, 80.0)
    x = rng.normal(size=(2, 50_001))
    decimator = Decimator(taps, factor, 2)
    parts = [decimator.update(block) for block in _blocks(x, rng, 37)]
    streamed = np.concatenate([*parts, decimator.finish()], axis=1)
    delay = (len(taps) - 1) // 2
    for row in range(2):  # zero-phase filter of the whole record, every factor-th sample
        whole = np.convolve(x[row], taps)[delay : delay + x.shape[1]][::factor]
        np.testing.assert_allclose(streamed[row], whole, rtol=1e-9, atol=1e-13)
    assert streamed.shape[1] == (x.shape[1] - 1) // factor + 1


def test_decimated_chirp_keeps_the_band_within_01_db_and_aliases_nothing():
    """A unit chirp 0 .. fs/2 through the decimator: below keep_frequency it comes out
    within 0.1 dB; where it would alias into [0, keep_frequency] (above
    fs/D - keep_frequency) nothing comes through above the stop band's -80 dB."""
    rate, keep, stop_db = 8000.0, 200.0, 80.0
    factor = decimation_factor(rate, keep)
    assert factor == 16 and rate / factor >= 2.5 * keep
    duration = 80.0  # 50 Hz/s: the filter (about 400 taps, 50 ms) sees a steady tone
    t = np.arange(int(duration * rate)) / rate
    x = chirp(t, 0.0, duration, rate / 2, method="linear")
    frequency = rate / 2 * t / duration
    decimator = Decimator(lowpass_taps(factor, rate, keep, stop_db), factor, 1)
    parts = [decimator.update(b) for b in np.array_split(x, 9)]
    y = np.concatenate([*parts, decimator.finish()], axis=1).ravel()
    f = frequency[::factor]
    # zero phase, unit gain: in the band the output is the chirp itself, sample by
    # sample, to within 0.1 dB of its unit amplitude (stricter than an envelope: a
    # phase error counts too; a Hilbert envelope of the decimated chirp would measure
    # its own end effects, 0.2 dB, more than the filter's)
    band = (f > 1.0) & (f < keep)
    error = np.abs(y[band] - x[::factor][band]).max()
    assert error < 10 ** (0.1 / 20) - 1, error
    taps = lowpass_taps(factor, rate, keep, stop_db)
    inside = np.arange(y.size) * factor + len(taps) // 2 < x.size  # not the cut at the end
    aliasing = (f > rate / factor - keep + 5.0) & inside  # 5 Hz: a filter length of sweep
    assert 20 * np.log10(np.abs(y[aliasing]).max()) < -stop_db + 3.0


# --- in a run ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def reduced_runs(tmp_path_factory):
    """The study case's run-up with every reduction, whole and streamed in 1024-sample
    blocks."""
    case = load_case(STUDY)
    scene = case.scene("runup")
    reductions = Reductions(
        keep_frequency=2000.0,
        statistics=True,
        rainflow=("mesh_force",),
        load_duration=("drive_torque", "load_torque"),
        bins=32,
    )
    settings = dataclasses.replace(
        scene.transient, duration=1.0, mean_window=0.2, reductions=reductions
    )
    scene = dataclasses.replace(scene, transient=settings, analyses=("transient",))
    out = tmp_path_factory.mktemp("reduced")
    write_transient(case, scene, out / "whole", figure=False, stream=False)
    saved = streaming.BUFFER_BYTES
    streaming.BUFFER_BYTES = 1024 * 8 * 10
    try:
        write_transient(case, scene, out / "streamed", figure=False, stream=True)
    finally:
        streaming.BUFFER_BYTES = saved
    with (
        open_dataset(out / "whole" / "runup.nc") as w,
        open_dataset(out / "streamed" / "runup.nc") as s,
    ):
        yield w.load(), s.load()


def test_streamed_reductions_equal_the_whole_record_ones(reduced_runs):
    whole, streamed = reduced_runs
    names = [n for n in whole.variables if n.endswith(("_decimated", "_statistics", "_edges"))]
    names += [n for n in whole.variables if n.startswith(("rainflow_", "load_duration_"))]
    names += ["time_decimated"]
    assert "rainflow_mesh_force" in names and "speed_decimated" in names
    for name in names:
        np.testing.assert_allclose(
            streamed[name].values, whole[name].values, rtol=RTOL, atol=0, err_msg=name
        )
        assert streamed[name].attrs == whole[name].attrs, name


def test_file_rainflow_matrix_is_the_package_count_of_the_file_channel(reduced_runs):
    _, run = reduced_runs
    for mesh in run.mesh.values:
        force = run.mesh_force.sel(mesh=mesh).values
        cycles = _whole_cycles(force)
        range_edges = run.rainflow_mesh_force_range_edges.sel(mesh=mesh).values
        mean_edges = run.rainflow_mesh_force_mean_edges.sel(mesh=mesh).values
        reference, _, _ = np.histogram2d(
            cycles[:, 0], cycles[:, 1], bins=(range_edges, mean_edges), weights=cycles[:, 2]
        )
        np.testing.assert_array_equal(run.rainflow_mesh_force.sel(mesh=mesh).values, reference)


def test_load_duration_counts_every_sample_and_every_revolution(reduced_runs):
    _, run = reduced_runs
    interval = 1.0 / run.attrs["sample_rate"]
    time_at_level = run.load_duration_time.sum("load_level").values
    # 40 001 weights added one by one: n eps = 4e-12 of rounding at most
    np.testing.assert_allclose(time_at_level, run.sizes["time"] * interval, rtol=1e-10)
    for torque, member in (
        ("drive_torque", run.attrs["input"]),
        ("load_torque", run.attrs["output"]),
    ):
        speed = np.abs(run.speed.sel(member=member.removesuffix(".theta_z")).values)
        revolutions = run.load_duration_revolutions.sel(torque=torque).sum().item()
        np.testing.assert_allclose(revolutions, speed.sum() * interval / 60, rtol=1e-10)
        # each level holds the samples whose torque lies in it
        edges = run.load_duration_edges.sel(torque=torque).values
        counts, _ = np.histogram(run[torque].values, bins=edges)
        np.testing.assert_allclose(
            run.load_duration_time.sel(torque=torque).values, counts * interval, rtol=1e-10
        )


def test_statistics_in_the_file_are_those_of_its_channels(reduced_runs):
    _, run = reduced_runs
    force = run.mesh_force.values
    expected = np.stack(
        [force.min(1), force.max(1), force.mean(1), np.sqrt(np.mean(force**2, axis=1))], axis=1
    )
    np.testing.assert_allclose(run.mesh_force_statistics.values, expected, rtol=1e-10)


def test_a_reduction_of_an_unrecorded_variable_is_refused_before_the_run(tmp_path):
    case = load_case(STUDY)
    scene = case.scene("runup")
    settings = dataclasses.replace(
        scene.transient,
        duration=0.1,
        mean_window=0.05,
        reductions=Reductions(rainflow=("bearing_force",)),
    )
    scene = dataclasses.replace(scene, transient=settings, analyses=("transient",))
    with pytest.raises(CaseError, match=r"reductions\.rainflow: the run records no variable"):
        write_transient(case, scene, tmp_path, figure=False, stream=True)
    assert not list(tmp_path.iterdir())


def test_keep_frequency_above_what_the_rate_allows_is_refused(tmp_path):
    case = load_case(STUDY)
    scene = case.scene("runup")
    settings = dataclasses.replace(scene.transient, reductions=Reductions(keep_frequency=20e3))
    with pytest.raises(CaseError, match=r"reductions\.keep_frequency"):
        settings.validate("scenes.runup.transient")
