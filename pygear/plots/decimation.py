"""Long series cut down to what the pixels of a plot can show.

A run-up's channel holds 200 000 samples and its spectrum 80 000 lines, drawn into
axes some 800 pixels wide: every pixel column would carry hundreds of segments, which
Agg strokes one by one.  What a column shows of them is the span from their lowest to
their highest value, so :func:`pixel_envelope` keeps that span per column and
:func:`plot_envelope` fills it (edged with the line's width, so a flat stretch still
shows as a line).  The figure then looks as the full series does and costs the same
for any record length.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["axes_columns", "pixel_envelope", "plot_envelope"]


def axes_columns(axes: Axes) -> int:
    """Width of ``axes`` in pixels at its figure's resolution (create the figure with the
    ``dpi`` it is saved at)."""
    return max(1, math.ceil(axes.get_window_extent().width))


def pixel_envelope(
    x: np.ndarray, y: np.ndarray, columns: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The lowest and highest value of ``y`` in each of ``columns`` equal runs.

    Parameters
    ----------
    x, y : (n,) arrays
        A uniformly sampled series (time or frequency, ascending) and its values.
    columns : int
        Pixel columns the series spans; at least 1.

    Returns
    -------
    (x, lower, upper) : arrays
        The series itself (``lower`` and ``upper`` both ``y``) when it has at most
        ``2 columns`` samples; otherwise one entry per run of ``ceil(n / columns)``
        consecutive samples: the ``x`` midway between the run's first and last sample,
        and the run's minimum and maximum.
    """
    x = np.asarray(x)
    y = np.asarray(y)
    if x.shape != y.shape or y.ndim != 1:
        raise ValueError(f"x and y must be 1-D of one length (got {x.shape} and {y.shape})")
    if columns < 1:
        raise ValueError(f"columns must be >= 1 (got {columns})")
    count = y.size
    if count <= 2 * columns:
        return x, y, y
    run = math.ceil(count / columns)
    runs = math.ceil(count / run)
    padded = np.empty(runs * run, dtype=y.dtype)
    padded[:count] = y
    padded[count:] = y[-1]  # repeats the last sample: no run gains a new extreme
    blocks = padded.reshape(runs, run)
    first = np.arange(runs) * run
    last = np.minimum(first + run - 1, count - 1)
    return 0.5 * (x[first] + x[last]), blocks.min(axis=1), blocks.max(axis=1)


def plot_envelope(
    axes: Axes, x: np.ndarray, y: np.ndarray, *, linewidth: float, color: str = "C0"
) -> None:
    """Draw ``y`` against ``x`` as its per-pixel-column span (:func:`pixel_envelope`),
    filled and edged in ``color``; set the x limits before (the columns are the
    pixels of the axes' whole width)."""
    middle, lower, upper = pixel_envelope(x, y, axes_columns(axes))
    axes.fill_between(middle, lower, upper, facecolor=color, edgecolor=color, linewidth=linewidth)
