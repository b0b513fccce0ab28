"""Figures of gear condition monitoring, plotting only: a gear's synchronous average
with its difference signal (:mod:`pygear.analysis.condition.gear_average`), indicator trends
against fault severity (the fault datasets' records), the fast kurtogram (Antoni 2007;
:mod:`pygear.analysis.condition.spectral_kurtosis`) and a ring sensor's spectrum in carrier orders
with its sidebands labelled (McFadden & Smith 1985).

Every function returns a :class:`matplotlib.figure.Figure` on an Agg canvas, not
registered with pyplot (nothing to close; save it with :func:`pygear.io.save_figure`).
Long lines are cut to what the pixels show (:mod:`pygear.plots.decimation`) and the
panels sit at fixed margins, so the figures cost the same for any record length.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle
from matplotlib.ticker import MaxNLocator

from ..analysis.condition.gear_indicators import difference_signal
from ..analysis.condition.spectral_kurtosis import KurtogramBand
from ..analysis.signals.signal import SignalError
from .decimation import plot_envelope

__all__ = [
    "HEALTHY_REFERENCES",
    "LABEL_RANGE_DB",
    "plot_gear_average",
    "plot_indicator_trends",
    "plot_kurtogram",
    "plot_sensor_orders",
]

DPI = 110
"""Resolution the figures are drawn at [pixels per inch]; save them at the same."""

HEALTHY_REFERENCES: dict[str, tuple[float, str]] = {
    "fm4": (3.0, "FM4 = 3: Gaussian difference signal"),
    "na4": (3.0, "NA4 = 3: Gaussian residual signal"),
    "m6a": (15.0, "M6A = 15: Gaussian difference signal"),
    "m8a": (105.0, "M8A = 105: Gaussian difference signal"),
}
"""Indicator values of a healthy gear, drawn as reference lines: the normalized 4th, 6th
and 8th moments of Gaussian samples, E[x^p] / E[x^2]^(p/2) = (p - 1)!! = 3, 15, 105
(Stewart 1977; Martin 1989; Zakrajsek, Townsend & Decker 1993)."""

LABEL_RANGE_DB = 20.0
"""A sideband stem is labelled when it stands within this many dB of its panel's largest."""

_SHORT_NAMES = ("fm0", "fm4", "na4", "nb4", "m6a", "m8a", "rms")
"""Indicators written in capitals (their names in the literature); the rest in words."""
_LABEL_GAP_PX = 3.0
"""Clearance kept between two sideband labels [pixels]."""


def _figure(width: float, height: float) -> Figure:
    """A figure of ``width`` x ``height`` inches at :data:`DPI` on its own Agg canvas."""
    figure = Figure(figsize=(width, height), dpi=DPI)
    FigureCanvasAgg(figure)
    return figure


def _indicator_name(name: str) -> str:
    """``fm4`` -> ``FM4``, ``energy_ratio`` -> ``energy ratio``."""
    return name.upper() if name in _SHORT_NAMES else name.replace("_", " ")


def _units(attrs: dict, default: str = "-") -> str:
    """An attribute's ``units``, dimensionless ``1`` shown as ``-``."""
    units = str(attrs.get("units", default)) or default
    return "-" if units == "1" else units


# --------------------------------------------------------------------------- gear average


def _tooth_spans(damaged_teeth: Iterable[Any], teeth: int) -> list[tuple[float, float, str]]:
    """Each damaged tooth as a span in tooth periods and its name: tooth ``k`` sits at
    ``k`` (the convention of :mod:`pygear.analysis.condition.synchronous_average`), so it covers
    ``[k - 1/2, k + 1/2]``; a pair is a span ``(start, end)`` as given."""
    spans = []
    for item in damaged_teeth:
        if isinstance(item, (int, np.integer)) and not isinstance(item, bool):
            if not 0 <= int(item) < teeth:
                raise SignalError(
                    f"damaged_teeth: tooth {item} is not a tooth number 0..{teeth - 1}"
                )
            spans.append((int(item) - 0.5, int(item) + 0.5, f"tooth {int(item)}"))
            continue
        try:
            start, end = (float(value) for value in item)
        except (TypeError, ValueError):
            raise SignalError(
                f"damaged_teeth: {item!r} is neither a tooth number nor a (start, end) span "
                "in tooth periods"
            ) from None
        if not (math.isfinite(start) and math.isfinite(end) and start < end <= start + teeth):
            raise SignalError(
                f"damaged_teeth: span {item!r} needs finite start < end <= start + {teeth}"
            )
        spans.append((start, end, f"{start:g} to {end:g}"))
    return spans


def _wrapped(start: float, end: float, teeth: int) -> list[tuple[float, float]]:
    """The span ``[start, end]`` folded onto one revolution ``[0, teeth]`` (one or two
    pieces): tooth 0's span ``[-1/2, 1/2]`` shows at both ends of the axis."""
    shift = math.floor(start / teeth) * teeth
    start, end = start - shift, end - shift
    if end <= teeth:
        return [(start, end)]
    return [(start, float(teeth)), (0.0, end - teeth)]


def plot_gear_average(
    average: xr.DataArray,
    *,
    damaged_teeth: Sequence[int | tuple[float, float]] = (),
    title: str | None = None,
) -> Figure:
    """A gear's synchronous average and its difference signal against the tooth periods.

    Parameters
    ----------
    average : xarray.DataArray
        One revolution along ``angle`` [rad] from 0 to 2 pi, with the attributes
        ``teeth`` (the mesh order of the difference signal) and ``units``, and
        ``gear``, ``revolutions`` and ``long_name`` where known
        (:func:`pygear.analysis.condition.gear_average.gear_average`).
    damaged_teeth : sequence, optional
        Teeth to shade: a tooth number ``k`` (the span ``k +/- 1/2``) or a
        ``(start, end)`` span in tooth periods; spans past the revolution's end wrap.
    title : str, optional
        Figure title; default names the gear, its teeth and the revolutions averaged.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels sharing the x axis, angle x teeth / 2 pi (tick ``k`` is tooth ``k``):
        the average, and its difference signal
        (:func:`pygear.analysis.condition.gear_indicators.difference_signal`: the mean, the
        shaft orders, the mesh harmonics and their first sidebands removed).
    """
    if not isinstance(average, xr.DataArray) or "angle" not in average.dims:
        raise SignalError("average: must be an xarray.DataArray along 'angle' [rad]")
    teeth = average.attrs.get("teeth")
    if not isinstance(teeth, (int, np.integer)) or isinstance(teeth, bool) or teeth < 1:
        raise SignalError(f"average: attribute 'teeth' must be an integer >= 1, got {teeth!r}")
    teeth = int(teeth)
    spans = _tooth_spans(damaged_teeth, teeth)
    values = np.asarray(average.values, dtype=float)
    difference = difference_signal(values, teeth)
    position = np.asarray(average["angle"].values, dtype=float) * teeth / (2.0 * np.pi)
    # one revolution is periodic: close it at 2 pi with its first sample
    position = np.append(position, float(teeth))
    values = np.append(values, values[0])
    difference = np.append(difference, difference[0])
    units = _units(average.attrs)
    gear = average.attrs.get("gear", average.name or "gear")
    revolutions = average.attrs.get("revolutions")
    if title is None:
        over = f" over {revolutions} revolutions" if revolutions is not None else ""
        title = f"synchronous average of {gear} ({teeth} teeth){over}"

    figure = _figure(9.0, 5.6)
    figure.subplots_adjust(left=0.1, right=0.97, bottom=0.1, top=0.88, hspace=0.38)
    axes = figure.subplots(2, 1, sharex=True)
    panels = (
        (values, "C0", f"average [{units}]", "(a) synchronous average"),
        (difference, "C1", f"difference [{units}]", "(b) difference signal"),
    )
    for ax, (series, colour, ylabel, panel_title) in zip(axes, panels):
        ax.set_xlim(0.0, float(teeth))
        plot_envelope(ax, position, series, linewidth=0.7, color=colour)
        ax.set_ylabel(ylabel)
        ax.set_title(panel_title, fontsize=9, loc="left")
        ax.grid(True, axis="x", lw=0.3, alpha=0.5)
        for start, end, name in spans:
            for low, high in _wrapped(start, end, teeth):
                ax.axvspan(low, high, color="tab:red", alpha=0.18, lw=0, label=f"damaged {name}")
    axes[1].xaxis.set_major_locator(MaxNLocator(nbins=24, integer=True))
    axes[1].set_xlabel("angle [tooth periods] (tick k: tooth k)")
    if spans:
        shaded = Patch(
            color="tab:red", alpha=0.18, label="damaged: " + ", ".join(s[2] for s in spans)
        )
        axes[0].legend(
            handles=[shaded],
            fontsize=7,
            loc="lower right",
            bbox_to_anchor=(1.0, 1.0),
            frameon=False,
        )
    figure.suptitle(title, fontsize=10)
    return figure


# --------------------------------------------------------------------------- trends


def _check_trend_dataset(dataset: Any, indicators: Sequence[str]) -> list[str]:
    if not isinstance(dataset, xr.Dataset) or "record" not in dataset.dims:
        raise SignalError("dataset: must be an xarray.Dataset with a 'record' dimension")
    missing = [name for name in ("severity", "speed_rpm", "load_nm", "seed") if name not in dataset]
    if missing:
        raise SignalError(f"dataset: needs the record coordinates {', '.join(missing)}")
    if isinstance(indicators, str) or not len(indicators):
        raise SignalError("indicators: must be a non-empty sequence of indicator names")
    names = [str(name) for name in indicators]
    for name in names:
        if name not in dataset.data_vars or dataset[name].dims != ("record",):
            known = sorted(v for v in dataset.data_vars if dataset[v].dims == ("record",))
            raise SignalError(
                f"indicators: {name!r} is not a variable on 'record' (have: {', '.join(known)})"
            )
    return names


def _operating_points(dataset: xr.Dataset) -> list[tuple]:
    """Each record's (fault kind, speed [rpm], load [N m]); kind "" when not given."""
    kinds = dataset["fault_kind"].values.astype(str) if "fault_kind" in dataset else None
    speeds, loads = (dataset[name].values.astype(float) for name in ("speed_rpm", "load_nm"))
    count = dataset.sizes["record"]
    return [("" if kinds is None else kinds[i], speeds[i], loads[i]) for i in range(count)]


def _seed_statistics(
    severity: np.ndarray, values: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per severity (ascending) the mean, minimum and maximum over the seeds, leaving
    out undefined (NaN) values and severities with none."""
    rows = []
    for level in np.unique(severity):
        defined = values[(severity == level) & np.isfinite(values)]
        if defined.size:
            rows.append((level, defined.mean(), defined.min(), defined.max()))
    table = np.array(rows, dtype=float).reshape(-1, 4)
    return table[:, 0], table[:, 1], table[:, 2], table[:, 3]


def plot_indicator_trends(
    dataset: xr.Dataset,
    indicators: Sequence[str] = ("fm4", "na4", "fm0", "energy_ratio"),
    title: str | None = None,
) -> Figure:
    """Condition indicators against fault severity, one line per operating point.

    Parameters
    ----------
    dataset : xarray.Dataset
        Records on dimension ``record`` with the coordinates ``severity``,
        ``speed_rpm``, ``load_nm``, ``seed`` (and ``fault_kind``) and the indicators as
        variables on ``record`` (:mod:`pygear.runs.fault_dataset`).
    indicators : sequence of str, optional
        Variables to draw, one panel each.
    title : str, optional
        Figure title; default names the case, the fault and the gear where the
        dataset's attributes give them.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per indicator (two columns), each line the mean over the seeds of one
        (fault kind, speed, load) with bars from the seeds' minimum to maximum; dotted
        lines at the healthy values of :data:`HEALTHY_REFERENCES`.
    """
    names = _check_trend_dataset(dataset, indicators)
    keys = _operating_points(dataset)
    points = sorted(set(keys))
    kinds = sorted({point[0] for point in points})
    columns = 1 if len(names) == 1 else 2
    rows = math.ceil(len(names) / columns)
    entries = len(points) + len(
        {HEALTHY_REFERENCES[n][1] for n in names if n in HEALTHY_REFERENCES}
    )
    legend_columns = min(4 if columns == 2 else 2, entries)
    bottom = 0.75 + 0.17 * math.ceil(entries / legend_columns)  # x label, legend [inch]
    height = 3.0 * rows + bottom + 0.45
    figure = _figure(5.0 * columns + 0.6, height)
    figure.subplots_adjust(
        left=0.1 if columns == 2 else 0.16,
        right=0.97,
        top=1.0 - 0.55 / height,
        bottom=bottom / height,
        hspace=0.5,
        wspace=0.3,
    )
    axes = [figure.add_subplot(rows, columns, index + 1) for index in range(len(names))]
    severity = np.asarray(dataset["severity"].values, dtype=float)
    severity_units = _units(dataset["severity"].attrs)
    kind_label = kinds[0] if len(kinds) == 1 and kinds[0] else "fault"
    handles: dict[str, Line2D] = {}
    for ax, name in zip(axes, names):
        values = np.asarray(dataset[name].values, dtype=float)
        for colour, point in enumerate(points):
            chosen = np.array([key == point for key in keys])
            level, mean, low, high = _seed_statistics(severity[chosen], values[chosen])
            style = {"color": f"C{colour % 10}", "ls": ("-", "--", ":")[kinds.index(point[0]) % 3]}
            ax.errorbar(
                level, mean, yerr=(mean - low, high - mean), marker="o", ms=4, capsize=3, **style
            )
            label = f"{point[1]:g} rpm, {point[2]:g} N m" + (
                f" ({point[0]})" if len(kinds) > 1 else ""
            )
            handles[label] = Line2D([], [], marker="o", ms=4, label=label, **style)
        if name in HEALTHY_REFERENCES:
            value, label = HEALTHY_REFERENCES[name]
            ax.axhline(value, color="0.35", ls=":", lw=1.2)
            handles[label] = Line2D([], [], color="0.35", ls=":", lw=1.2, label=label)
        ax.set_xlabel(f"severity ({kind_label}) [{severity_units}]")
        ax.set_ylabel(f"{_indicator_name(name)} [{_units(dataset[name].attrs)}]")
        ax.set_title(_indicator_name(name), fontsize=9)
        ax.grid(True, lw=0.3, alpha=0.5)
    seeds = np.unique(dataset["seed"].values).size
    figure.legend(
        handles=list(handles.values()),
        loc="lower center",
        ncol=legend_columns,
        fontsize=7,
        title=f"operating points (mean of {seeds} seeds, bars: min to max)",
        title_fontsize=7,
        frameon=False,
    )
    if title is None:
        attrs = dataset.attrs
        where = f" on {attrs['gear']}" if "gear" in attrs else ""
        tooth = f" tooth {attrs['tooth']}" if "tooth" in attrs else ""
        case = f"{attrs['case']}: " if "case" in attrs else ""
        title = f"{case}indicators against {kind_label} severity{where}{tooth}"
    figure.suptitle(title, fontsize=10)
    return figure


# --------------------------------------------------------------------------- kurtogram


def plot_kurtogram(kurtogram: xr.Dataset, best: KurtogramBand, title: str | None = None) -> Figure:
    """The fast kurtogram as an image of kurtosis over frequency and level.

    Parameters
    ----------
    kurtogram : xarray.Dataset
        ``kurtosis`` over (``level``, ``frequency``) as
        :func:`pygear.analysis.condition.spectral_kurtosis.fast_kurtogram` returns it (frequency
        cells across ``[0, sample_rate / 2]``), with the ``sample_rate`` attribute.
    best : KurtogramBand
        The band to outline and annotate (the function's second result).
    title : str, optional
        Figure title; default names the method and the deepest level.

    Returns
    -------
    matplotlib.figure.Figure
        The image (level 0 at the top, rows labelled as Antoni (2007) labels them: 0, 1,
        1.6, 2, ...) and its colour bar.
    """
    if not isinstance(kurtogram, xr.Dataset) or "kurtosis" not in kurtogram:
        raise SignalError("kurtogram: must be the Dataset fast_kurtogram returns")
    if kurtogram["kurtosis"].dims != ("level", "frequency") or "sample_rate" not in kurtogram.attrs:
        raise SignalError(
            "kurtogram: needs 'kurtosis' over (level, frequency) and a 'sample_rate' attribute"
        )
    levels = np.asarray(kurtogram["level"].values, dtype=float)
    row = int(np.argmin(np.abs(levels - float(best.level))))
    if not math.isclose(levels[row], float(best.level), abs_tol=1e-9):
        raise SignalError(f"best: level {best.level!r} is not a level of the kurtogram")
    rate = float(kurtogram.attrs["sample_rate"])
    cells = kurtogram.sizes["frequency"]
    edges = np.arange(cells + 1) * (rate / (2.0 * cells))
    rows = np.arange(levels.size + 1) - 0.5

    figure = _figure(9.0, 5.0)
    figure.subplots_adjust(left=0.1, right=0.98, bottom=0.12, top=0.88)
    ax = figure.add_subplot(1, 1, 1)
    image = ax.pcolormesh(edges, rows, kurtogram["kurtosis"].values, cmap="viridis")
    figure.colorbar(image, ax=ax, label="kurtosis of the band's envelope [-]", pad=0.02)
    ax.set_ylim(rows[-1], rows[0])  # level 0 (the whole band) at the top
    ax.set_yticks(np.arange(levels.size), [f"{round(level, 1):g}" for level in levels])
    ax.set_xlim(0.0, rate / 2.0)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("level (bandwidth fs / 2^(level+1)) [-]")
    ax.add_patch(
        Rectangle(
            (best.low, row - 0.5), best.bandwidth, 1.0, fill=False, ec="red", lw=2.0, zorder=3
        )
    )
    # the note sits in the image corner farthest from the band, over a white box
    note_left = best.centre_frequency > rate / 4.0
    note_top = row >= levels.size / 2.0
    ax.annotate(
        f"best band: level {round(best.level, 1):g}\ncentre {best.centre_frequency:.4g} Hz, "
        f"bandwidth {best.bandwidth:.4g} Hz\nkurtosis {best.kurtosis:.3g}",
        xy=(best.low if note_left else best.high, row),
        xytext=(0.03 if note_left else 0.97, 0.95 if note_top else 0.05),
        textcoords="axes fraction",
        ha="left" if note_left else "right",
        va="top" if note_top else "bottom",
        fontsize=8,
        bbox={"boxstyle": "round", "fc": "white", "ec": "red", "alpha": 0.9},
        arrowprops={"arrowstyle": "->", "color": "red", "lw": 1.0},
        zorder=4,
    )
    if title is None:
        title = (
            f"fast kurtogram (Antoni 2007), levels 0 to {kurtogram.attrs.get('max_level', '?')}, "
            f"fs = {rate:g} Hz"
        )
    ax.set_title(title, fontsize=10)
    return figure


# --------------------------------------------------------------------------- sensor orders


def _whole_number(value: Any, name: str, minimum: int) -> int:
    if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < minimum:
        raise SignalError(f"{name}: must be an integer >= {minimum}, got {value!r}")
    return int(value)


def _check_spectrum(orders: Any, amplitude: Any) -> tuple[np.ndarray, np.ndarray]:
    try:
        order_values = np.asarray(orders, dtype=float)
        amplitudes = np.asarray(amplitude, dtype=float)
    except (TypeError, ValueError):
        raise SignalError("orders, amplitude: must be arrays of real numbers") from None
    if order_values.ndim != 1 or order_values.shape != amplitudes.shape:
        raise SignalError(
            f"orders, amplitude: must be 1-D of one length, got {order_values.shape} and "
            f"{amplitudes.shape}"
        )
    if not np.all(np.isfinite(order_values)) or np.any(order_values != np.round(order_values)):
        raise SignalError("orders: must be whole carrier orders (finite integers)")
    if not np.all(np.isfinite(amplitudes)) or np.any(amplitudes < 0.0):
        raise SignalError("amplitude: must be finite and >= 0")
    return np.round(order_values).astype(int), amplitudes


def _place_labels(ax, labels: list[tuple[float, str]], renderer) -> float:
    """Write each ``(order, text)`` near the axes' top, centred on its order, in the
    highest row where it keeps :data:`_LABEL_GAP_PX` clear of every label already
    written (rows a label's height and a gap apart); return the axes fraction of the
    lowest label's bottom (1 when there are none)."""
    axes_box = ax.get_window_extent(renderer)
    placed = []
    lowest = 1.0
    step = 0.0
    for order, text in sorted(labels):
        row = 0
        while True:
            label = ax.annotate(
                text,
                (order, 0.97 - row * step),
                xycoords=("data", "axes fraction"),
                ha="center",
                va="top",
                fontsize=7,
                zorder=4,
                bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none"},
            )
            box = label.get_window_extent(renderer)
            step = step or (box.height + 2.0 * _LABEL_GAP_PX) / axes_box.height
            clear = all(
                box.x1 + _LABEL_GAP_PX < other.x0
                or other.x1 + _LABEL_GAP_PX < box.x0
                or box.y1 + _LABEL_GAP_PX < other.y0
                or other.y1 + _LABEL_GAP_PX < box.y0
                for other in placed
            )
            if clear:
                placed.append(box)
                lowest = min(lowest, (box.y0 - axes_box.y0) / axes_box.height)
                break
            label.remove()
            row += 1
    return lowest


def plot_sensor_orders(
    orders: Any,
    amplitude: Any,
    *,
    ring_teeth: int,
    planets: int,
    harmonics: Sequence[int] = (1, 2),
    span: int = 10,
    units: str = "m/s^2",
    title: str | None = None,
) -> Figure:
    """A sensor's spectrum in carrier orders about each mesh harmonic, sidebands labelled.

    A sensor on the ring of a stage with ``N`` equally spaced planets hears the mesh
    harmonic ``m`` at the carrier orders ``m Z_r + n``; where all planets mesh alike,
    only the orders that are multiples of ``N`` survive the sum over the planets
    (McFadden & Smith 1985), so those are coloured apart from the others.

    Parameters
    ----------
    orders, amplitude : array_like
        Whole carrier orders and their amplitudes [``units``], 1-D, one length.
    ring_teeth : int
        Teeth of the ring, ``Z_r`` (the mesh order in carrier orders).
    planets : int
        Number of planets ``N``.
    harmonics : sequence of int, optional
        Mesh harmonics ``m`` to show, one panel each.
    span : int, optional
        Sidebands ``n`` shown on each side, ``|n| <= span``.
    units : str, optional
        Units of ``amplitude``; the stems are in dB re 1 of these.
    title : str, optional
        Figure title; default names the stage's ring teeth and planets.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per harmonic, stems at the orders ``m Z_r +/- span`` present in
        ``orders``, each stem within :data:`LABEL_RANGE_DB` of its panel's largest
        labelled ``(m, n)``, labels stacked in rows so that none overlaps another.
    """
    order_values, amplitudes = _check_spectrum(orders, amplitude)
    teeth = _whole_number(ring_teeth, "ring_teeth", 1)
    count = _whole_number(planets, "planets", 1)
    reach = _whole_number(span, "span", 0)
    if isinstance(harmonics, (str, bytes)) or not len(harmonics):
        raise SignalError("harmonics: must be a non-empty sequence of integers >= 1")
    mesh_harmonics = [_whole_number(m, "harmonics", 1) for m in harmonics]

    panel_height, top_margin, gap, bottom_margin = 2.5, 0.8, 0.9, 1.05  # inches
    height = top_margin + bottom_margin + len(mesh_harmonics) * panel_height
    height += (len(mesh_harmonics) - 1) * gap
    figure = _figure(9.0, height)
    renderer = figure.canvas.get_renderer()
    passed, other = "tab:red", "tab:blue"
    for index, m in enumerate(mesh_harmonics):
        bottom = bottom_margin + (len(mesh_harmonics) - 1 - index) * (panel_height + gap)
        ax = figure.add_axes((0.1, bottom / height, 0.87, panel_height / height))
        centre = m * teeth
        margin = 0.8 + 0.03 * reach  # room for the outermost labels [orders]
        ax.set_xlim(centre - reach - margin, centre + reach + margin)
        ax.set_xlabel("order [per carrier revolution]")
        ax.set_ylabel(f"amplitude [dB re 1 {units}]")
        ax.set_title(f"mesh harmonic m = {m}: orders {m} \u00d7 {teeth} \u00b1 {reach}", fontsize=9)
        ax.axvline(centre, color="0.7", lw=0.6, ls="--", zorder=0)
        shown = (np.abs(order_values - centre) <= reach) & (amplitudes > 0.0)
        if not np.any(shown):
            ax.text(0.5, 0.5, "no orders in range", transform=ax.transAxes, ha="center")
            continue
        level = 20.0 * np.log10(amplitudes[shown])
        strongest = float(level.max())
        floor = 10.0 * math.floor(max(float(level.min()) - 6.0, strongest - 100.0) / 10.0)
        multiple = order_values[shown] % count == 0
        for keep, colour in ((multiple, passed), (~multiple, other)):
            ax.vlines(order_values[shown][keep], floor, level[keep], colors=colour, lw=1.4)
            ax.plot(order_values[shown][keep], level[keep], "o", ms=3.5, color=colour)
        labels = [
            (float(order), f"({m}, {int(order) - centre})")
            for order, value in zip(order_values[shown], level)
            if value >= strongest - LABEL_RANGE_DB
        ]
        lowest = _place_labels(ax, labels, renderer)
        # the strongest stem ends just below the lowest label row
        reach_fraction = max(lowest - 0.05, 0.25)
        ax.set_ylim(floor, floor + (strongest - floor) / reach_fraction)
        ax.xaxis.set_major_locator(MaxNLocator(nbins=12, integer=True))
        ax.grid(True, axis="y", lw=0.3, alpha=0.5)
    figure.legend(
        handles=[
            Line2D([], [], color=colour, marker="o", ms=3.5, label=label)
            for colour, label in (
                (
                    passed,
                    f"order a multiple of N = {count}: passed by equally spaced planets "
                    "(McFadden & Smith 1985)",
                ),
                (other, "other orders"),
            )
        ],
        loc="lower center",
        ncol=2,
        fontsize=7,
        frameon=False,
        title=f"labels (m, n): order m Z_r + n, stems within {LABEL_RANGE_DB:g} dB of the "
        "panel's largest",
        title_fontsize=7,
    )
    if title is None:
        title = f"sensor spectrum in carrier orders: ring of {teeth} teeth, {count} planets"
    figure.suptitle(title, fontsize=10, y=1.0 - 0.2 / height, va="top")
    return figure
