"""Figures of long series cut to the pixels that show them (pygear.plots.decimation).

The span kept per pixel column is checked against the runs' own minima and maxima
computed here, and the drawn outline against the axes' width: a figure of a million
samples carries no more vertices than one of a thousand.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pygear.plots.decimation import axes_columns, pixel_envelope, plot_envelope  # noqa: E402


def test_short_series_is_drawn_as_it_is():
    x = np.arange(10.0)
    y = np.sin(x)
    middle, lower, upper = pixel_envelope(x, y, columns=5)
    np.testing.assert_array_equal(middle, x)
    np.testing.assert_array_equal(lower, y)
    np.testing.assert_array_equal(upper, y)


@pytest.mark.parametrize("count", [1000, 1001, 1234])
def test_each_column_spans_its_runs_extremes(count):
    rng = np.random.default_rng(count)
    x = np.arange(count) * 0.25
    y = rng.standard_normal(count)
    columns = 100
    middle, lower, upper = pixel_envelope(x, y, columns)
    run = -(-count // columns)  # ceil: samples per column
    assert len(middle) == -(-count // run) <= columns
    for k in range(len(middle)):
        part = slice(k * run, min((k + 1) * run, count))
        assert lower[k] == y[part].min() and upper[k] == y[part].max()
        assert middle[k] == 0.5 * (x[part][0] + x[part][-1])
    assert lower.min() == y.min() and upper.max() == y.max()  # no extreme is lost


def test_fast_oscillation_fills_every_column():
    """A tone of many periods per column spans its full amplitude in every column, as the
    full series drawn as a line covers those pixels."""
    sample_rate, frequency, amplitude = 200_000.0, 12_000.0, 3.0
    time = np.arange(200_001) / sample_rate
    tone = amplitude * np.sin(2 * np.pi * frequency * time)
    _, lower, upper = pixel_envelope(time, tone, 800)
    # 251 samples per column hold 15 periods; the sample nearest a crest lies at most
    # half a step from it, a phase of pi f / f_s, so it reads at least A cos(pi f / f_s)
    # (less 1e-12 of it: the round-off of sin near a crest)
    reach = amplitude * np.cos(np.pi * frequency / sample_rate) * (1 - 1e-12)
    assert np.all(upper >= reach) and np.all(lower <= -reach)


def test_drawn_outline_is_bounded_by_the_axes_width(tmp_path):
    figure, axes = plt.subplots(figsize=(6, 2), dpi=100)
    time = np.linspace(0.0, 5.0, 1_000_001)
    axes.set_xlim(time[0], time[-1])
    plot_envelope(axes, time, np.sin(2 * np.pi * 50 * time), linewidth=0.5)
    columns = axes_columns(axes)
    assert columns <= 600  # 6 in at 100 dpi
    (band,) = axes.collections
    vertices = sum(len(path.vertices) for path in band.get_paths())
    # fill_between's outline: the upper and lower edges, one point per column each,
    # plus the closing points
    assert vertices <= 2 * columns + 5
    figure.savefig(tmp_path / "envelope.png")
    plt.close(figure)


def test_refuses_mismatched_input():
    with pytest.raises(ValueError, match="one length"):
        pixel_envelope(np.arange(3), np.arange(4), 2)
    with pytest.raises(ValueError, match="columns"):
        pixel_envelope(np.arange(3), np.arange(3), 0)
