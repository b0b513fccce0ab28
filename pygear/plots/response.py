"""Figures of the periodic steady state over speed (plotting only; nothing here computes).

- :func:`plot_dynamic_factor`: K_v of every mesh against the input speed, the speeds at
  which the mesh frequency meets a natural frequency marked (darker for modes storing
  more of their energy in the meshes), and ISO 6336-1's resonance ranges of the main
  mesh mode shaded: subcritical N <= 0.85, main resonance 0.85 < N <= 1.15,
  intermediate 1.15 < N < 1.5, supercritical N >= 1.5;
- :func:`plot_load_sharing`: K_gamma of every planetary stage (mean and peak forces);
- :func:`plot_stability`: the largest Floquet multiplier modulus, unstable speeds shaded;
- :func:`plot_contact_loss`: the contact-loss branch (peak-to-peak DTE of every mesh
  along it, stable solid, unstable dashed), the linear response faint, and the jump
  speeds of up and down sweeps;
- :func:`plot_harmonics_accuracy`: the accuracy ladder's frequency-domain rung, mesh-force
  error against the harmonic count and against wall time.
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from .layout import new_figure, result_title

__all__ = [
    "ISO_RANGES",
    "plot_contact_loss",
    "plot_dynamic_factor",
    "plot_harmonics_accuracy",
    "plot_load_sharing",
    "plot_stability",
]

DPI = 130
"""Resolution the figures are drawn at [pixels per inch]; save them at the same."""

ISO_RANGES = (
    ("subcritical", 0.0, 0.85, "#e8f1fb"),
    ("main resonance", 0.85, 1.15, "#fde3d9"),
    ("intermediate", 1.15, 1.5, "#f6f0dc"),
    ("supercritical", 1.5, np.inf, "#eef7e8"),
)
"""ISO 6336-1 (method B) ranges of the resonance ratio N = n / n_E1, and their shading;
the lower limit of the main resonance is N_S = 0.85 (the standard's value for line loads
of 100 N/mm and more; lighter loads lower it)."""

MARKED_SHARE = 0.01
"""Resonance speeds of modes with at least this mesh energy share are marked."""

MESH_MODE_SHARE = 0.5
MARKED_HARMONICS = 8
"""Modes with at least this mesh energy share are mesh modes; the speeds where mesh
harmonics up to this one meet them are marked too."""


def _shade_iso(axes, response: xr.Dataset) -> None:
    speed = response.speed.values
    ratio = response.resonance_ratio.values
    per_ratio = speed[-1] / ratio[-1]  # speed is proportional to N
    for name, low, high, colour in ISO_RANGES:
        start, stop = max(low * per_ratio, speed[0]), min(high * per_ratio, speed[-1])
        if start < stop:
            axes.axvspan(start, stop, color=colour, zorder=0, lw=0)
            axes.text(0.5 * (start + stop), 1.0, f"ISO {name}", ha="center", va="bottom",
                      transform=axes.get_xaxis_transform(), fontsize=7, color="0.35")  # fmt: skip


def _mark_resonances(axes, response: xr.Dataset) -> None:
    """Dotted: the mesh frequency meets a mode with some mesh energy; faint dash-dot: a
    mesh harmonic 2..:data:`MARKED_HARMONICS` meets a mesh mode (the stiffness jumps
    ring those)."""
    speed = response.speed.values
    per_hz = speed[-1] / response.fundamental_frequency.values[-1]
    orders = sorted({int(o) for o in response.mesh_order.values})
    for frequency, share in zip(response.natural_frequency.values,
                                response.mesh_energy_share.values):  # fmt: skip
        if share < MARKED_SHARE:
            continue
        for order in orders:
            for harmonic in range(1, MARKED_HARMONICS + 1):
                if harmonic > 1 and share < MESH_MODE_SHARE:
                    break
                where = frequency / (order * harmonic) * per_hz
                if speed[0] <= where <= speed[-1]:
                    style = (":", 0.3 + 0.7 * share) if harmonic == 1 else ("-.", 0.25)
                    axes.axvline(where, color="0.3", lw=0.7, ls=style[0], alpha=style[1])


def _speed_axis(axes, speed: np.ndarray) -> None:
    """The speed range on x (5 % either side of a single speed), points for one speed."""
    if speed[-1] > speed[0]:
        axes.set_xlim(speed[0], speed[-1])
        return
    axes.set_xlim(0.95 * speed[0], 1.05 * speed[0])
    for line in axes.get_lines():
        if np.size(line.get_xdata()) == 1 and line.get_marker() in ("None", None, ""):
            line.set_marker("o")


def plot_dynamic_factor(response: xr.Dataset) -> Figure:
    """Dynamic factor of every mesh against the input speed.

    Parameters
    ----------
    response : xarray.Dataset
        A :func:`pygear.analysis.response.forced_response` result.
    """
    figure = new_figure(8.0, 4.6, DPI)
    axes = figure.add_axes((0.09, 0.12, 0.66, 0.72))
    _shade_iso(axes, response)
    _mark_resonances(axes, response)
    speed = response.speed.values
    for i, mesh in enumerate(response.mesh.values):
        axes.plot(speed, response.dynamic_factor.values[:, i], lw=1.0, label=str(mesh))
    separated = response.separation.values.any(axis=1)
    if separated.any():
        axes.plot(speed[separated], np.full(separated.sum(), 1.0), "v", color="tab:red",
                  ms=3, label="tooth separation")  # fmt: skip
    _speed_axis(axes, speed)
    axes.set_xlabel(f"{response.attrs.get('input', 'input')} speed [rpm]")
    axes.set_ylabel("dynamic factor K_v [-]")
    axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    figure.suptitle(
        f"Dynamic factor over speed (dotted: mesh frequency = natural frequency; "
        f"dash-dot: a mesh harmonic = a mesh mode)\n"
        f"{result_title(response.attrs)}",
        fontsize=9,
    )
    return figure


def plot_load_sharing(response: xr.Dataset) -> Figure:
    """Planet load-sharing factor K_gamma of every planetary stage against speed."""
    figure = new_figure(7.0, 4.0, DPI)
    axes = figure.add_axes((0.1, 0.13, 0.62, 0.7))
    speed = response.speed.values
    for i, stage in enumerate(response.stage.values):
        line = axes.plot(speed, response.load_sharing.values[:, i], lw=1.2,
                         label=f"{stage}: mean forces")[0]  # fmt: skip
        axes.plot(speed, response.load_sharing_peak.values[:, i], lw=0.8, ls="--",
                  color=line.get_color(), label=f"{stage}: peak forces")  # fmt: skip
    axes.axhline(1.0, color="0.5", lw=0.6)
    _speed_axis(axes, speed)
    axes.set_xlabel(f"{response.attrs.get('input', 'input')} speed [rpm]")
    axes.set_ylabel("load-sharing factor K_gamma [-]")
    if response.sizes["stage"]:
        axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    else:
        axes.text(0.5, 0.5, "no planetary stage", transform=axes.transAxes, ha="center")
    figure.suptitle(f"Planet load sharing over speed\n{result_title(response.attrs)}", fontsize=9)
    return figure


def plot_stability(response: xr.Dataset) -> Figure:
    """Largest Floquet multiplier modulus against speed, unstable speeds shaded."""
    figure = new_figure(7.0, 3.6, DPI)
    axes = figure.add_axes((0.1, 0.15, 0.85, 0.65))
    speed = response.speed.values
    if "floquet_multiplier" in response:
        multiplier = response.floquet_multiplier.values
        axes.plot(speed, multiplier, lw=1.0, color="tab:blue")
        unstable = multiplier >= 1.0
        axes.fill_between(speed, 0, 1, where=unstable, color="tab:red", alpha=0.2,
                          transform=axes.get_xaxis_transform(), lw=0, label="unstable")  # fmt: skip
        axes.axhline(1.0, color="tab:red", lw=0.6)
        if unstable.any():
            axes.legend(loc="lower right", fontsize=7, frameon=False)
    else:
        axes.text(0.5, 0.5, "stability not computed", transform=axes.transAxes, ha="center")
    _speed_axis(axes, speed)
    axes.set_xlabel(f"{response.attrs.get('input', 'input')} speed [rpm]")
    axes.set_ylabel("largest |Floquet multiplier| [-]")
    figure.suptitle(f"Stability of the periodic steady state\n{result_title(response.attrs)}",
                    fontsize=9)  # fmt: skip
    return figure


def plot_contact_loss(branch: xr.Dataset, linear: xr.Dataset | None = None) -> Figure:
    """Peak-to-peak DTE of every mesh along the contact-loss branch against speed.

    Stable points are joined by solid lines, unstable ones by dashed lines (no flag
    computed: solid, and the title says so); the up-sweep jumps are marked by red
    upward-pointing and the down-sweep jumps by blue downward-pointing triangles on
    vertical lines.  ``linear`` (the linear sweep) is drawn faint and dotted.

    Parameters
    ----------
    branch : xarray.Dataset
        A :func:`pygear.analysis.response.continue_response` result.
    linear : xarray.Dataset, optional
        The linear sweep over the same range.
    """
    figure = new_figure(8.0, 4.6, DPI)
    axes = figure.add_axes((0.09, 0.12, 0.66, 0.72))
    speed = branch.speed.values
    stable = branch.stable.values > 0 if "stable" in branch else np.ones(speed.size, bool)
    # a segment joins two points and takes the stability of both (either unstable: dashed)
    both = stable[:-1] & stable[1:]
    for i, mesh in enumerate(branch.mesh.values):
        value = branch.dte_peak_to_peak.values[:, i] * 1e6
        solid = np.where(np.r_[both, False] | np.r_[False, both], value, np.nan)
        dashed = np.where(np.r_[~both, False] | np.r_[False, ~both], value, np.nan)
        line = axes.plot(speed, solid, lw=1.1, label=f"{mesh} (stable)")[0]
        axes.plot(speed, dashed, lw=0.9, ls="--", color=line.get_color(),
                  label=f"{mesh} (unstable)" if (~both).any() else None)  # fmt: skip
        if linear is not None and str(mesh) in [str(m) for m in linear.mesh.values]:
            axes.plot(linear.speed.values, linear.dte_peak_to_peak.sel(mesh=mesh).values * 1e6,
                      lw=0.6, ls=":", color=line.get_color(), alpha=0.6)  # fmt: skip
    for key, colour, marker, label in (("up_sweep_jumps", "tab:red", "^", "up-sweep jump"),
                                       ("down_sweep_jumps", "tab:blue", "v",
                                        "down-sweep jump")):  # fmt: skip
        for k, where in enumerate(np.atleast_1d(branch.attrs.get(key, []))):
            axes.axvline(float(where), color=colour, lw=0.7, alpha=0.7)
            axes.plot([float(where)], [1.0], marker, color=colour, ms=7, clip_on=False,
                      transform=axes.get_xaxis_transform(),
                      label=f"{label} {float(where):.1f} rpm" if k < 4 else None)  # fmt: skip
    low, high = float(np.min(speed)), float(np.max(speed))
    if high > low:
        axes.set_xlim(low, high)
    axes.set_xlabel(f"{branch.attrs.get('input', 'input')} speed [rpm]")
    axes.set_ylabel("DTE peak to peak [um]")
    axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    note = "" if "stable" in branch else " (stability not computed)"
    figure.suptitle(
        f"Contact loss with backlash: branch in speed{note}; dotted: linear response\n"
        f"{result_title(branch.attrs)}",
        fontsize=9,
    )
    return figure


def plot_harmonics_accuracy(ladder: xr.Dataset) -> Figure:
    """Mesh-force error against the harmonic count (every judged speed faint, the
    largest bold) and the largest error against wall time, the tolerance and the
    recommended count marked.

    Parameters
    ----------
    ladder : xarray.Dataset
        A judged ladder (:func:`pygear.analysis.response.harmonics.recommend_harmonics`).
    """
    figure = new_figure(9.0, 4.0, DPI)
    left = figure.add_axes((0.08, 0.14, 0.38, 0.68))
    right = figure.add_axes((0.58, 0.14, 0.38, 0.68))
    counts = ladder.harmonics.values
    judged = ladder.judged.values > 0
    errors = ladder.mesh_force_error.values
    floor = 1e-16  # an exact zero cannot be drawn on log axes
    for j in np.flatnonzero(judged):
        left.loglog(counts, np.maximum(errors[:, j], floor), color="0.7", lw=0.5)
    worst = np.maximum(ladder.max_judged_error.values, floor)
    left.loglog(counts, worst, "o-", color="tab:blue", lw=1.4, label="largest over judged speeds")
    right.loglog(ladder.wall_time.values, worst, "o-", color="tab:blue", lw=1.4)
    for count, wall, error in zip(counts, ladder.wall_time.values, worst):
        right.annotate(f"H={int(count)}", (wall, error), fontsize=6, xytext=(3, 3),
                       textcoords="offset points")  # fmt: skip
    tolerance = ladder.attrs["tolerance"]
    best = ladder.attrs["recommended_harmonics"]
    for axes in (left, right):
        axes.axhline(tolerance, color="tab:red", lw=0.8, ls="--", label="tolerance")
        axes.set_ylabel("mesh-force error [-]")
    if best > 0:
        i = int(np.flatnonzero(counts == best)[0])
        left.plot([best], [worst[i]], "*", color="tab:red", ms=11, label=f"recommended H={best}")
        right.plot([ladder.wall_time.values[i]], [worst[i]], "*", color="tab:red", ms=11)
    left.set_xlabel("harmonics H")
    right.set_xlabel("wall time over the speeds [s]")
    left.legend(fontsize=7, frameon=False)
    figure.suptitle(
        f"Harmonic balance: error against the H = {ladder.attrs['reference_harmonics']} "
        f"reference and against cost\n{result_title(ladder.attrs)}",
        fontsize=9,
    )
    return figure
