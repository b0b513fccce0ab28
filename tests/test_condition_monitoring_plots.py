"""Tests of pygear.plots.condition_monitoring: the figures built from small inputs made
here, their panels and labels, where the drawn data land (checked against closed forms:
a sine's difference signal, dB of known amplitudes, seed means of known values), the
damaged-tooth spans, the kurtogram's outline, and the sideband labels (present for the
strong stems, absent for the weak, no two overlapping)."""

from __future__ import annotations

import math
import re
from itertools import combinations

import numpy as np
import pytest
import xarray as xr
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from pygear.analysis.condition.spectral_kurtosis import fast_kurtogram
from pygear.analysis.signals.signal import SignalError
from pygear.io import save_figure
from pygear.plots.condition_monitoring import (
    LABEL_RANGE_DB,
    plot_gear_average,
    plot_indicator_trends,
    plot_kurtogram,
    plot_sensor_orders,
)

TRANSFORM = 1e-9
"""Tolerance on data coordinates read back through Matplotlib's display transforms
(data -> pixels -> data in double precision on a figure about 1000 pixels wide: round-off
near 1e-13 of the axis range, far below 1e-9)."""

SIDEBAND_LABEL = r"^\(\d+, -?\d+\)$"


def _png(figure: Figure, path) -> None:
    save_figure(figure, path, dpi=figure.dpi)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _x_extent(ax, patch) -> tuple[float, float]:
    """A patch's left and right edge in ``ax``'s data coordinates."""
    box = patch.get_window_extent().transformed(ax.transData.inverted())
    return box.x0, box.x1


# --------------------------------------------------------------------------- gear average

TEETH = 20
STEPS = TEETH * 32


def _average() -> xr.DataArray:
    """One revolution: the mesh tone (order Z), a weaker order 7 (not a shaft order
    1..3, nor Z or Z +/- 1), so the difference signal is exactly cos(7 theta)."""
    angle = np.arange(STEPS) * (2.0 * np.pi / STEPS)
    values = 2.0 * np.cos(TEETH * angle) + np.cos(7.0 * angle)
    return xr.DataArray(
        values,
        dims="angle",
        coords={"angle": ("angle", angle, {"units": "rad"})},
        attrs={
            "gear": "planetary.planet1",
            "teeth": TEETH,
            "units": "m/s^2",
            "long_name": "time-synchronous average",
            "revolutions": 12,
        },
    )


def test_gear_average_figure(tmp_path) -> None:
    figure = plot_gear_average(_average(), damaged_teeth=(5, (11.25, 12.75), 0))
    assert isinstance(figure, Figure)
    top, bottom = figure.axes
    assert len(figure.axes) == 2
    assert top.get_ylabel() == "average [m/s^2]"
    assert bottom.get_ylabel() == "difference [m/s^2]"
    assert "[tooth periods]" in bottom.get_xlabel()
    assert bottom.get_xlim() == pytest.approx((0.0, TEETH), abs=TRANSFORM)
    assert "planetary.planet1" in figure.get_suptitle()
    assert "12 revolutions" in figure.get_suptitle()
    # the difference signal drawn is cos(7 theta), theta = 2 pi x / Z at tooth period x
    (drawn,) = [c for c in bottom.collections if isinstance(c, PolyCollection)]
    x, y = drawn.get_paths()[0].vertices.T
    assert x.max() == pytest.approx(TEETH, abs=TRANSFORM)
    # FFT round-off of a unit-amplitude order over 640 samples: ~1e-15
    np.testing.assert_allclose(y, np.cos(7.0 * 2.0 * np.pi * x / TEETH), atol=1e-12)
    # shaded spans: tooth k covers k +/- 1/2, a pair as given, tooth 0 wraps to both ends
    expected = {
        "damaged tooth 5": [(4.5, 5.5)],
        "damaged 11.25 to 12.75": [(11.25, 12.75)],
        "damaged tooth 0": [(0.0, 0.5), (TEETH - 0.5, TEETH)],
    }
    figure.canvas.draw()
    for ax in (top, bottom):
        for label, spans in expected.items():
            drawn = sorted(_x_extent(ax, p) for p in ax.patches if p.get_label() == label)
            assert drawn == [pytest.approx(span, abs=TRANSFORM) for span in sorted(spans)]
    legend = [t.get_text() for t in top.get_legend().get_texts()]
    assert legend == ["damaged: tooth 5, 11.25 to 12.75, tooth 0"]
    _png(figure, tmp_path / "gear_average.png")


@pytest.mark.parametrize(
    ("damaged", "message"),
    [
        ((20,), "damaged_teeth: tooth 20 is not a tooth number 0..19"),
        (((3.0, 2.0),), "damaged_teeth: span"),
        (("a",), "damaged_teeth: 'a' is neither"),
    ],
)
def test_gear_average_rejects_bad_damaged_teeth(damaged, message) -> None:
    with pytest.raises(SignalError, match=message):
        plot_gear_average(_average(), damaged_teeth=damaged)


def test_gear_average_needs_the_tooth_count() -> None:
    average = _average()
    del average.attrs["teeth"]
    with pytest.raises(SignalError, match="teeth"):
        plot_gear_average(average)


# --------------------------------------------------------------------------- trends

SEVERITIES = (0.0, 0.5)
SPEEDS = (10.0, 15.0)
SEEDS = (1, 2)


def _trend_dataset() -> xr.Dataset:
    """2 severities x 2 speeds x 2 seeds; each indicator ``base + 4 severity + speed / 10
    + seed / 10``, so the seed mean at (s, v) is ``base + 4 s + v / 10 + 0.15`` and the
    seeds span +/- 0.05 about it."""
    rows = [(s, v, seed) for s in SEVERITIES for v in SPEEDS for seed in SEEDS]
    severity, speed, seed = (np.array(column) for column in zip(*rows))
    bases = {"fm4": 3.0, "na4": 3.0, "fm0": 2.0, "energy_ratio": 0.1}
    data = {
        name: ("record", base + 4.0 * severity + speed / 10.0 + seed / 10.0)
        for name, base in bases.items()
    }
    count = len(rows)
    return xr.Dataset(
        data,
        coords={
            "severity": ("record", severity, {"units": "1"}),
            "speed_rpm": ("record", speed),
            "load_nm": ("record", np.full(count, 2.0e6)),
            "seed": ("record", seed),
            "fault_kind": ("record", np.array(["stiffness_factor"] * count)),
        },
        attrs={"case": "study", "gear": "planetary.planet1", "tooth": 3},
    )


def test_indicator_trends_figure(tmp_path) -> None:
    names = ("fm4", "na4", "fm0", "energy_ratio")
    figure = plot_indicator_trends(_trend_dataset())
    assert isinstance(figure, Figure)
    assert len(figure.axes) == len(names)
    title = figure.get_suptitle()
    assert "study" in title and "stiffness_factor" in title and "planetary.planet1" in title
    for ax, name, reference in zip(figure.axes, names, (3.0, 3.0, None, None)):
        assert ax.get_xlabel() == "severity (stiffness_factor) [-]"
        assert ax.get_ylabel().endswith("[-]")
        base = {"fm4": 3.0, "na4": 3.0, "fm0": 2.0, "energy_ratio": 0.1}[name]
        assert len(ax.containers) == len(SPEEDS)  # one line per operating point
        for container, speed in zip(ax.containers, SPEEDS):
            line = container.lines[0]
            np.testing.assert_allclose(line.get_xdata(), SEVERITIES)
            # seed means by hand; sums of a few tenths: round-off ~1e-15
            expected = [base + 4.0 * s + speed / 10.0 + 0.15 for s in SEVERITIES]
            np.testing.assert_allclose(line.get_ydata(), expected, atol=1e-12)
            # bars from the seeds' minimum to maximum: +/- 0.05
            (bars,) = container.lines[2]
            for segment, mean in zip(bars.get_segments(), expected):
                np.testing.assert_allclose(segment[:, 1], (mean - 0.05, mean + 0.05), atol=1e-12)
        flat = [
            line
            for line in ax.get_lines()
            if np.allclose(line.get_ydata(), line.get_ydata()[0])
            and line.get_linestyle() == ":"
            and len(line.get_ydata()) == 2
        ]
        assert [line.get_ydata()[0] for line in flat] == ([reference] if reference else [])
    legend = [t.get_text() for t in figure.legends[0].get_texts()]
    assert "10 rpm, 2e+06 N m" in legend and "15 rpm, 2e+06 N m" in legend
    assert "FM4 = 3: Gaussian difference signal" in legend
    _png(figure, tmp_path / "trends.png")


def test_indicator_trends_rejects_unknown_indicator() -> None:
    with pytest.raises(SignalError, match="indicators: 'fm9'"):
        plot_indicator_trends(_trend_dataset(), indicators=("fm4", "fm9"))


# --------------------------------------------------------------------------- kurtogram


def test_kurtogram_figure(tmp_path) -> None:
    rate, burst_hz = 10_000.0, 3_000.0
    rng = np.random.default_rng(11)
    signal = rng.standard_normal(8192)
    ring = np.arange(80) / rate
    for start in range(300, 8000, 700):  # decaying 3 kHz bursts, 70 ms apart
        signal[start : start + ring.size] += (
            6.0 * np.sin(2 * np.pi * burst_hz * ring) * np.exp(-400.0 * ring)
        )
    kurtogram, best = fast_kurtogram(signal, rate)
    figure = plot_kurtogram(kurtogram, best)
    assert isinstance(figure, Figure)
    image, colour_bar = figure.axes
    assert len(figure.axes) == 2
    assert image.get_xlabel() == "frequency [Hz]"
    assert image.get_ylabel().endswith("[-]")
    assert colour_bar.get_ylabel().endswith("[-]")
    assert "Antoni 2007" in image.get_title()
    # rows labelled as Antoni labels them: level log2(3) = 1.58 reads 1.6
    ticks = [t.get_text() for t in image.get_yticklabels()]
    assert ticks[:4] == ["0", "1", "1.6", "2"]
    assert image.get_xlim() == pytest.approx((0.0, rate / 2), abs=TRANSFORM)
    # the bursts' band is the best, outlined where the band lies
    assert best.low <= burst_hz <= best.high
    (outline,) = [p for p in image.patches if isinstance(p, Rectangle)]
    assert outline.get_x() == pytest.approx(best.low, rel=TRANSFORM)
    assert outline.get_width() == pytest.approx(best.bandwidth, rel=TRANSFORM)
    row = int(np.argmin(np.abs(kurtogram["level"].values - best.level)))
    assert outline.get_y() == pytest.approx(row - 0.5, abs=TRANSFORM)
    assert outline.get_edgecolor() == to_rgba("red")
    (note,) = image.texts
    assert f"{best.centre_frequency:.4g} Hz" in note.get_text()
    assert f"{best.kurtosis:.3g}" in note.get_text()
    _png(figure, tmp_path / "kurtogram.png")


# --------------------------------------------------------------------------- sensor orders

RING_TEETH = 20
PLANETS = 4


def _labels(ax) -> dict[str, object]:
    return {t.get_text(): t for t in ax.texts if re.match(SIDEBAND_LABEL, t.get_text())}


def _stems(ax) -> dict[tuple, np.ndarray]:
    """Stem segments of ``ax`` by colour (RGBA)."""
    found = {}
    for collection in ax.collections:
        if isinstance(collection, LineCollection) and collection.get_segments():
            found[tuple(collection.get_colors()[0])] = np.array(collection.get_segments())
    return found


def test_sensor_orders_label_strong_stems_only(tmp_path) -> None:
    orders = np.arange(0, 61)
    amplitude = np.full(orders.size, 1e-3)  # -60 dB re 1 m/s^2: weak
    strong = {1: {-8, -4, 0, 4, 8}, 2: {-4, 0, 4}}
    for m, sidebands in strong.items():
        for n in sidebands:
            amplitude[m * RING_TEETH + n] = 2.0 / m  # 6.02 and 0 dB
    amplitude[RING_TEETH + 1] = 2.0 * 10 ** (-19.5 / 20)  # 19.5 dB below: labelled
    amplitude[RING_TEETH - 1] = 2.0 * 10 ** (-20.5 / 20)  # 20.5 dB below: not
    strong[1].add(1)
    figure = plot_sensor_orders(
        orders, amplitude, ring_teeth=RING_TEETH, planets=PLANETS, harmonics=(1, 2), span=10
    )
    assert isinstance(figure, Figure)
    assert len(figure.axes) == 2
    assert LABEL_RANGE_DB == 20.0
    for ax, m in zip(figure.axes, (1, 2)):
        assert ax.get_ylabel() == "amplitude [dB re 1 m/s^2]"
        assert "[per carrier revolution]" in ax.get_xlabel()
        assert f"m = {m}" in ax.get_title()
        assert set(_labels(ax)) == {f"({m}, {n})" for n in strong[m]}
        stems = _stems(ax)
        passed, other = stems[to_rgba("tab:red")], stems[to_rgba("tab:blue")]
        # every order m Z_r +/- 10 drawn once, the multiples of N in their own colour
        tops = {int(round(s[0, 0])): s[1, 1] for s in np.concatenate([passed, other])}
        assert sorted(tops) == list(range(m * RING_TEETH - 10, m * RING_TEETH + 11))
        assert all(int(round(s[0, 0])) % PLANETS == 0 for s in passed)
        assert all(int(round(s[0, 0])) % PLANETS != 0 for s in other)
        # stem tops at 20 log10(amplitude / 1 m/s^2); log10 round-off ~1e-15
        for order, top in tops.items():
            assert top == pytest.approx(20 * math.log10(amplitude[order]), abs=1e-9)
    legend = " ".join(t.get_text() for t in figure.legends[0].get_texts())
    assert f"multiple of N = {PLANETS}" in legend and "McFadden & Smith 1985" in legend
    _png(figure, tmp_path / "sensor_orders.png")


def test_sensor_order_labels_do_not_overlap(tmp_path) -> None:
    # 41 equally strong sidebands a panel: too many for one row of labels
    span = 20
    orders = np.arange(0, 3 * RING_TEETH + span + 1)
    amplitude = np.ones(orders.size)
    figure = plot_sensor_orders(
        orders, amplitude, ring_teeth=RING_TEETH, planets=PLANETS, harmonics=(1, 2), span=span
    )
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    (title,) = [t for t in figure.texts if t.get_text() == figure.get_suptitle()]
    boxes = [title.get_window_extent(renderer)]
    labels = []
    for ax in figure.axes:
        shown = _labels(ax)
        assert len(shown) == 2 * span + 1
        rows = {round(t.get_window_extent(renderer).y0, 3) for t in shown.values()}
        assert len(rows) > 1  # staggered
        area = ax.get_window_extent(renderer)
        for text in shown.values():
            box = text.get_window_extent(renderer)
            # inside the panel: clear of its title and of the panel above
            assert area.x0 <= box.x0 and box.x1 <= area.x1
            assert area.y0 <= box.y0 and box.y1 <= area.y1
            labels.append(box)
        # the stems end below the lowest label
        heads = np.concatenate([s[:, 1] for s in _stems(ax).values()])
        top_pixel = ax.transData.transform(heads)[:, 1].max()
        assert top_pixel < min(t.get_window_extent(renderer).y0 for t in shown.values())
        boxes.append(ax.title.get_window_extent(renderer))
    for first, second in combinations(labels + boxes, 2):
        assert not first.overlaps(second)
    _png(figure, tmp_path / "sensor_orders_dense.png")


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"orders": np.arange(5) + 0.5}, "orders: must be whole carrier orders"),
        ({"amplitude": -np.ones(5)}, "amplitude: must be finite and >= 0"),
        ({"planets": 0}, "planets: must be an integer >= 1"),
        ({"harmonics": ()}, "harmonics"),
        ({"span": -1}, "span: must be an integer >= 0"),
    ],
)
def test_sensor_orders_rejects_bad_input(change, message) -> None:
    arguments = {
        "orders": np.arange(5),
        "amplitude": np.ones(5),
        "ring_teeth": 3,
        "planets": 3,
        "harmonics": (1,),
        "span": 1,
    } | change
    orders, amplitude = arguments.pop("orders"), arguments.pop("amplitude")
    with pytest.raises(SignalError, match=message):
        plot_sensor_orders(orders, amplitude, **arguments)
