"""Figure of the time-varying mesh stiffness (plotting only; nothing here computes)."""

from __future__ import annotations

import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

__all__ = ["DEFAULT_PANELS", "plot_mesh_stiffness"]

DEFAULT_PANELS = ("sun-planet1", "sun-planet2", "ring-planet1")
"""The seed's Figure 3: (a) sun-first planet, (b) sun-second planet, (c) ring-first planet."""


def _find(dataset: xr.Dataset, name: str) -> str | None:
    """The mesh called ``name``, also as ``<stage>.<name>`` (first stage wins)."""
    for mesh in dataset.mesh.values:
        if mesh == name or str(mesh).endswith(f".{name}"):
            return str(mesh)
    return None


def plot_mesh_stiffness(
    dataset: xr.Dataset,
    path: str | os.PathLike,
    meshes: tuple[str, ...] | None = None,
    *,
    format: str | None = None,
) -> None:
    """Stacked panels of mesh stiffness against time, like the seed's Figure 3.

    Dotted vertical lines mark where a new tooth pair enters the first panel's
    mesh (its mesh cycle crosses a whole number) in every panel, so the phase shift
    of the other meshes shows against them.

    Parameters
    ----------
    dataset : xarray.Dataset
        From :func:`pygear.analysis.mesh_stiffness.mesh_stiffness_at_constant_speed`.
    path : str or path
        Target image file.
    meshes : tuple of str, optional
        Meshes to draw, one panel each; default :data:`DEFAULT_PANELS` (those present).
    format : str, optional
        Image format when ``path`` has no telling suffix.
    """
    wanted = meshes or DEFAULT_PANELS
    chosen = [m for m in (_find(dataset, n) for n in wanted) if m is not None]
    if not chosen:
        chosen = [str(m) for m in dataset.mesh.values[:3]]
    time_ms = dataset.time.values * 1e3
    reference = dataset.mesh_cycle.sel(mesh=chosen[0]).values
    entries = time_ms[1:][np.floor(reference[1:]) != np.floor(reference[:-1])]
    fig, axes = plt.subplots(
        len(chosen), 1, figsize=(7.0, 1.9 * len(chosen) + 0.6), sharex=True, squeeze=False
    )
    for n, (ax, name) in enumerate(zip(axes[:, 0], chosen, strict=True)):
        stiffness = dataset.mesh_stiffness.sel(mesh=name).values
        ax.plot(time_ms, stiffness / 1e8, color="tab:blue", lw=1.0)
        for t in entries:
            ax.axvline(t, color="0.6", lw=0.6, ls=":")
        phase = float(dataset.phase.sel(mesh=name))
        ax.set_title(f"({chr(ord('a') + n)}) {name}, phase {phase:.3f}", fontsize=9, loc="left")
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
    axes[-1, 0].set_xlabel("time [ms]", fontsize=8)
    speed = dataset.attrs.get("carrier_speed_rpm")
    title = "Time-varying mesh stiffness"
    if speed is not None:
        title += f" at {speed:g} rpm carrier speed"
    fig.suptitle(f"{title}; dotted: a pair enters {chosen[0]}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=150, format=format)
    plt.close(fig)
