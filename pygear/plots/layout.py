"""What every figure of :mod:`pygear.plots` shares: a figure on its own Agg canvas, titles
that say which result they show, and labels placed where they overlap nothing.

A plot function returns its :class:`matplotlib.figure.Figure`; the caller saves it
(:func:`pygear.io.save_figure`, at the figure's own ``dpi``: the long series are cut
to the pixel columns of that resolution, :mod:`pygear.plots.decimation`).  Figures are
not registered with pyplot, so there is nothing to close, and they need no backend: the
modules that draw with these helpers select none, so a notebook keeps its own.

Labels that could collide (peak labels, excitation lines, mesh orders) are measured
with the figure's renderer as they are placed: each goes into the first free spot of
a list of candidates, clear of every text and leader line placed before it.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.text import Text
from matplotlib.transforms import Bbox

__all__ = [
    "LABEL_GAP_PX",
    "NO_SCENE",
    "fit_below_labels",
    "new_figure",
    "overlaps",
    "place_first_clear",
    "place_point_labels",
    "result_title",
    "scaled_units",
]

LABEL_GAP_PX = 3.0
"""Clearance kept between two placed labels, and between a label and a leader [pixels]."""

NO_SCENE = "no scene"
"""What a title says of a result computed from the case alone, without a scene's
settings (``pygear modal``, ``sensitivity``, ``mesh-stiffness``)."""


def new_figure(width: float, height: float, dpi: float) -> Figure:
    """A figure of ``width`` x ``height`` inches at ``dpi`` on its own Agg canvas."""
    figure = Figure(figsize=(width, height), dpi=dpi)
    FigureCanvasAgg(figure)
    return figure


def result_title(
    attrs: Mapping[str, Any],
    *,
    scene: str | None = None,
    formulation: str | None = None,
    case: bool = True,
) -> str:
    """``CASE, scene SCENE, FORMULATION formulation`` from a result's attributes.

    Parameters
    ----------
    attrs : mapping
        The result's attributes (``case``, ``scene``, ``formulation`` where known).
    scene, formulation : str, optional
        Used when the attributes do not name them (a scene ``"none"`` counts as none:
        :data:`NO_SCENE`).
    case : bool
        Whether to start with the case (False where the figure's title names it).
    """
    scene = scene or str(attrs.get("scene", "") or "")
    parts = [f"scene {scene}" if scene and scene != "none" else NO_SCENE]
    if case:
        parts.insert(0, str(attrs.get("case", "") or "unnamed case"))
    formulation = formulation or str(attrs.get("formulation", "") or "")
    if formulation:
        parts.append(f"{formulation} formulation")
    return ", ".join(parts)


def scaled_units(largest: float, units: str) -> tuple[float, str]:
    """A factor and the units of ``units`` times it: ``(1e9, "10^-9 m/s^2")`` for a
    largest value of 2e-8, so that the ticks read 0 to 999 without an offset text (which
    would sit where the panel's title is).  Values from 0.01 to 1e4 keep their units."""
    if not np.isfinite(largest) or largest <= 0.0 or 1e-2 <= largest < 1e4:
        return 1.0, units
    exponent = 3 * int(np.floor(np.log10(largest) / 3.0))
    return 10.0**-exponent, f"$10^{{{exponent}}}$ {units}"


def overlaps(box: Bbox, others: Iterable[Bbox], gap: float = LABEL_GAP_PX) -> bool:
    """Whether ``box`` comes within ``gap`` pixels of any of ``others``."""
    return any(
        not (
            box.x1 + gap <= other.x0
            or other.x1 + gap <= box.x0
            or box.y1 + gap <= other.y0
            or other.y1 + gap <= box.y0
        )
        for other in others
    )


def _inside(box: Bbox, frame: Bbox) -> bool:
    return frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1


def place_first_clear(
    ax: Axes,
    text: str,
    candidates: Iterable[dict[str, Any]],
    placed: list[Bbox],
    *,
    frame: Bbox | None = None,
    **style: Any,
) -> Text | None:
    """Write ``text`` with the keywords of the first candidate that keeps it inside
    ``frame`` (default: the axes) and clear of every box in ``placed``.

    Each candidate holds the keywords of :meth:`~matplotlib.axes.Axes.annotate` that
    differ between places (``xy``, ``xycoords``, ``ha``, ...); ``style`` holds the
    common ones.  The text's box joins ``placed``.  Returns None, writing nothing,
    when no candidate is free.
    """
    renderer = ax.figure.canvas.get_renderer()
    frame = frame if frame is not None else ax.get_window_extent(renderer)
    for candidate in candidates:
        label = ax.annotate(text, **{**style, **candidate})
        box = label.get_window_extent(renderer)
        if _inside(box, frame) and not overlaps(box, placed):
            placed.append(box)
            return label
        label.remove()
    return None


def place_point_labels(
    ax: Axes,
    labels: Sequence[tuple[float, float | None, str]],
    *,
    fontsize: float = 6.0,
    rows: int = 6,
    top: float = 0.985,
) -> float:
    """Write each ``(x, y, text)`` in rows from the top of the axes down, above its
    point ``(x, y)`` (data coordinates), in the first row where it is clear of every
    label and leader placed before it; a leader line runs from the label down to its
    point (none for ``y`` None: a label of a vertical line the caller draws).

    In each row a label is tried centred on ``x`` and then shifted to either side by a
    third of its width (its leader still leaves from under it); labels that fit in
    none of ``rows`` rows are left out.  Set the x limits first; afterwards raise the
    y limit with :func:`fit_below_labels` so that the data stay below the labels.

    Returns
    -------
    float
        Axes fraction of the lowest label's bottom edge (``top`` when none is placed).
    """
    renderer = ax.figure.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    style = {
        "textcoords": ("data", "axes fraction"),
        "ha": "center",
        "va": "top",
        "fontsize": fontsize,
        "zorder": 5,
        "bbox": {"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none"},
        "annotation_clip": False,
    }
    texts: list[Bbox] = []
    lines: list[Bbox] = []
    lowest = top
    step = 0.0
    for x, y, text in sorted(labels, key=lambda label: label[0]):
        x_px = ax.transData.transform((x, ax.get_ylim()[0]))[0]  # any y: x is separable
        if not frame.x0 <= x_px <= frame.x1:
            continue
        # the text measured once, in the first row: the other places are that box moved
        trial = ax.annotate(text, xy=(x, top), xytext=(x, top), **style)
        trial.update_positions(renderer)  # its text's transform, before measuring
        first = Text.get_window_extent(trial, renderer)
        trial.remove()
        step = step or (first.height + 2.0 * LABEL_GAP_PX) / frame.height
        spot = None
        for row in range(rows):
            for shift in (0.0, -1.0 / 3.0, 1.0 / 3.0):  # sideways, a share of the width
                box = first.translated(shift * first.width, -row * step * frame.height)
                # a leader drops from under the text to the axes' bottom (the point lies
                # somewhere on it once the y limits are set; a caller's line spans it)
                leader = Bbox.from_extents(x_px - 0.5, frame.y0, x_px + 0.5, box.y0)
                if (
                    _inside(box, frame)
                    and not overlaps(box, texts + lines)
                    and not overlaps(leader, texts, gap=1.0)
                ):
                    spot = (shift, top - row * step, box, leader)
                    break
            if spot is not None:
                break
        if spot is None:
            continue
        shift, height, box, leader = spot
        moved = ax.transData.inverted().transform((x_px + shift * box.width, frame.y0))[0]
        ax.annotate(
            text,
            xy=(x, height) if y is None else (x, y),
            xycoords=("data", "axes fraction") if y is None else "data",
            xytext=(moved, height),
            arrowprops=(
                None
                if y is None
                else {
                    "arrowstyle": "-",
                    "lw": 0.4,
                    "color": "0.45",
                    "shrinkA": 0,
                    "shrinkB": 1,
                    "relpos": (0.5 - shift, 0.0),  # from under the text, straight down
                }
            ),
            **style,
        )
        texts.append(box)
        lines.append(leader)
        lowest = min(lowest, (box.y0 - frame.y0) / frame.height)
    return lowest


def fit_below_labels(
    ax: Axes,
    data_top: float,
    lowest: float,
    *,
    bottom: float = 0.0,
    log: bool = False,
    margin: float = 0.04,
) -> None:
    """Set the y limits from ``bottom`` so that ``data_top`` lands ``margin`` (axes
    fraction) below ``lowest``, the bottom of the lowest label
    (:func:`place_point_labels`); on a log axis in decades."""
    reach = max(lowest - margin, 0.2)
    if log:
        low, high = np.log10(bottom), np.log10(max(data_top, bottom * 10.0))
        ax.set_ylim(bottom, 10.0 ** (low + (high - low) / reach))
        return
    span = data_top - bottom if data_top > bottom else 1.0
    ax.set_ylim(bottom, bottom + span / reach)
