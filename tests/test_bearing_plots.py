"""Bearing figures drawn from small inputs made here: the stems land on the element
loads, the dashed lines on the expected harmonics, a dot on each harmonic found."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from pygear.analysis.condition.bearing_envelope import detect_lines
from pygear.analysis.condition.bearing_load import load_distribution
from pygear.analysis.signals.signal import SignalError
from pygear.io import save_figure
from pygear.model.rolling_bearing import RollingBearing
from pygear.plots.bearing import plot_bearing_envelope, plot_load_distribution


def test_load_distribution_stems_are_the_element_loads(tmp_path):
    bearing = RollingBearing("B", "ball", elements=12, pitch_diameter=0.1,
                             element_diameter=0.012, diametral_clearance=10e-6)  # fmt: skip
    distribution = load_distribution(bearing, 5e3)
    figure = plot_load_distribution(distribution)
    ax = figure.axes[0]
    stems = ax.collections[0].get_segments()
    tops = sorted(segment[1][1] for segment in stems)
    assert np.allclose(tops, np.sort(distribution.element_load.values), rtol=1e-12)
    assert "load zone" in ax.get_legend_handles_labels()[1][1]
    save_figure(figure, tmp_path / "load.png", dpi=figure.dpi)
    assert (tmp_path / "load.png").read_bytes()[:4] == b"\x89PNG"


def test_envelope_figure_marks_expected_and_found_harmonics():
    frequency = np.arange(0, 500.0, 0.5)
    values = np.full(frequency.size, 1e-3)
    for k in (1, 2, 3):  # lines at k 87.5 Hz, far above the 1e-3 floor
        values[int(k * 87.5 / 0.5)] = 1.0
    spectrum = xr.DataArray(values, dims="frequency", coords={"frequency": frequency})
    found = detect_lines(spectrum, {"BPFO": 87.5, "BPFI": 140.0})
    figure = plot_bearing_envelope(spectrum, found)
    ax = figure.axes[0]
    dashed = [line for line in ax.lines if line.get_linestyle() == "--"]
    assert len(dashed) == 6  # 3 harmonics of 2 lines
    assert sorted(float(line.get_xdata()[0]) for line in dashed[:3]) == [87.5, 175.0, 262.5]
    dots = [line for line in ax.lines if line.get_marker() == "o"]
    assert len(dots) == 3 and all(float(d.get_ydata()[0]) == 1.0 for d in dots)
    labels = ax.get_legend_handles_labels()[1]
    assert labels == ["BPFO (found)", "BPFI (not found)"]


def test_envelope_figure_refuses_other_data():
    with pytest.raises(SignalError, match=r"^spectrum and detection: need"):
        plot_bearing_envelope(xr.DataArray([1.0], dims="time"), xr.Dataset())
