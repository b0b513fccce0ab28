"""Figure of the time-varying mesh stiffness (plotting only; nothing here computes)."""

from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from .layout import new_figure, result_title

__all__ = ["DEFAULT_PANELS", "plot_mesh_stiffness"]

DEFAULT_PANELS = ("sun-planet1", "sun-planet2", "ring-planet1")
"""The seed's Figure 3: (a) sun-first planet, (b) sun-second planet, (c) ring-first planet."""

DPI = 150
"""Resolution the figure is drawn at [pixels per inch]; save it at the same."""

PANEL_INCH, GAP_INCH, TOP_INCH, BOTTOM_INCH = 1.5, 0.4, 0.75, 0.5
"""Fixed layout [in]: each panel's height, the gap between panels (each panel's title),
the figure's two-line title, the time axis."""


def _find(dataset: xr.Dataset, name: str) -> str | None:
    """The mesh called ``name``, also as ``<stage>.<name>`` (first stage wins)."""
    for mesh in dataset.mesh.values:
        if mesh == name or str(mesh).endswith(f".{name}"):
            return str(mesh)
    return None


def _staged(dataset: xr.Dataset, mesh: str) -> str:
    """``stage.mesh``: a mesh name with its stage, taken from its first gear's name
    (``planetary.sun``) when the name does not hold it."""
    if "." in mesh or "gear_1" not in dataset.coords:
        return mesh
    stage = str(dataset["gear_1"].sel(mesh=mesh).values).split(".")[0]
    return f"{stage}.{mesh}"


def plot_mesh_stiffness(
    dataset: xr.Dataset, meshes: tuple[str, ...] | None = None, *, scene: str | None = None
) -> Figure:
    """Stacked panels of mesh stiffness against time, like the seed's Figure 3.

    Dotted vertical lines mark where a new tooth pair enters the first panel's
    mesh (its mesh cycle crosses a whole number) in every panel, so the phase shift
    of the other meshes shows against them.

    Parameters
    ----------
    dataset : xarray.Dataset
        From :func:`pygear.analysis.contact.mesh_stiffness.mesh_stiffness_at_constant_speed`.
    meshes : tuple of str, optional
        Meshes to draw, one panel each; default :data:`DEFAULT_PANELS` (those present).
    scene : str, optional
        The scene whose parameters the dataset was computed with, for the title when
        its attributes do not name one.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per mesh, titled with the mesh's stage and phase; shaded where no
        tooth pair is in contact.
    """
    wanted = meshes or DEFAULT_PANELS
    chosen = [m for m in (_find(dataset, n) for n in wanted) if m is not None]
    if not chosen:
        chosen = [str(m) for m in dataset.mesh.values[:3]]
    time_ms = dataset.time.values * 1e3
    reference = dataset.mesh_cycle.sel(mesh=chosen[0]).values
    entries = time_ms[1:][np.floor(reference[1:]) != np.floor(reference[:-1])]
    height = TOP_INCH + BOTTOM_INCH + len(chosen) * PANEL_INCH + (len(chosen) - 1) * GAP_INCH
    figure = new_figure(7.0, height, DPI)
    axes = figure.subplots(len(chosen), 1, sharex=True, squeeze=False)
    figure.subplots_adjust(
        left=0.1,
        right=0.97,
        bottom=BOTTOM_INCH / height,
        top=1 - TOP_INCH / height,
        hspace=GAP_INCH / PANEL_INCH,
    )
    for n, (ax, name) in enumerate(zip(axes[:, 0], chosen, strict=True)):
        stiffness = dataset.mesh_stiffness.sel(mesh=name).values
        ax.plot(time_ms, stiffness / 1e8, color="tab:blue", lw=1.0)
        for t in entries:
            ax.axvline(t, color="0.6", lw=0.6, ls=":")
        phase = float(dataset.phase.sel(mesh=name))
        ax.set_title(
            f"({chr(ord('a') + n)}) {_staged(dataset, name)}, phase {phase:.3f}",
            fontsize=9,
            loc="left",
        )
        ax.set_ylabel(r"$k_m$ [$10^8$ N/m]", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3, lw=0.4)
        lost = dataset.pairs_in_contact.sel(mesh=name).values == 0
        if lost.any():
            ax.fill_between(
                time_ms,
                0,
                1,
                where=lost,
                color="tab:red",
                alpha=0.15,
                transform=ax.get_xaxis_transform(),
                label="no pair in contact",
            )
            ax.legend(fontsize=7, loc="upper right")
    axes[-1, 0].set_xlim(time_ms[0], time_ms[-1])
    axes[-1, 0].set_xlabel("time [ms]", fontsize=8)
    speed = dataset.attrs.get("carrier_speed_rpm")
    title = "Time-varying mesh stiffness"
    if speed is not None:
        title += f" at {speed:g} rpm carrier speed"
    figure.suptitle(
        f"{title}; dotted: a pair enters {_staged(dataset, chosen[0])}\n"
        f"{result_title(dataset.attrs, scene=scene)}",
        fontsize=9,
        y=1 - 0.08 / height,
    )
    return figure
