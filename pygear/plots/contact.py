"""Figures of a loaded tooth contact analysis: TE over the mesh cycle, its peak-to-peak
against load (the Harris map) and the contact pattern over face and path."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

__all__ = ["contact_pattern", "plot_contact"]


def contact_pattern(ds: xr.Dataset, index: int = -1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Line load of one tooth pair as it passes the path, at force ``index``.

    Returns
    -------
    path : ndarray
        Pair positions p = s + k [mesh cycles], sorted.
    face : ndarray
        Slice centres [m].
    load : ndarray (path, face)
        Line load [N/m] (0 where the slice is out of contact).
    """
    line = ds.line_load.isel(force=index).values  # (position, pair, face)
    cycles = int(ds.attrs.get("cycles", 1))
    first = ds.position.values < 1.0 if cycles > 1 else slice(None)
    line = line[first]
    p = ds.path_position.values.T[first]  # (position, pair)
    order = np.argsort(p.ravel())
    return p.ravel()[order], ds.face.values, line.reshape(-1, line.shape[-1])[order]


def plot_contact(ds: xr.Dataset, path: str | Path) -> Path:
    """Three panels: loaded TE over the positions at every torque, TE peak-to-peak against
    torque, and the contact pattern at the largest torque; saved to ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..io import save_figure

    figure, axes = plt.subplots(1, 3, figsize=(14.0, 4.0))
    for i in range(ds.force.size):
        axes[0].plot(ds.position.values, ds.te_loaded.values[i] * 1e6,
                     label=f"{float(ds.torque[i]):.4g} N m")  # fmt: skip
    axes[0].plot(ds.position.values, ds.te_unloaded.values * 1e6, "k--", label="unloaded")
    axes[0].set_xlabel("mesh position [mesh cycles]")
    axes[0].set_ylabel("transmission error [um]")
    axes[0].legend(fontsize="x-small")
    axes[1].plot(ds.torque.values, ds.te_peak_to_peak.values * 1e6, "o-")
    axes[1].set_xlabel("torque [N m]")
    axes[1].set_ylabel("TE peak-to-peak [um]")
    axes[1].set_title("Harris map")
    p, face, load = contact_pattern(ds)
    relative = ds.face.attrs.get("units") == "1"  # a mesh without gear geometry
    scale = 1.0 if relative else 1e3
    mesh = axes[2].pcolormesh(p, face * scale, load.T / scale, shading="nearest", cmap="viridis")
    figure.colorbar(mesh, ax=axes[2], label="line load [N per b]" if relative
                    else "line load [N/mm]")  # fmt: skip
    axes[2].set_xlabel("pair position along the path [mesh cycles]")
    axes[2].set_ylabel("face [y / b]" if relative else "face [mm]")
    axes[2].set_title("contact pattern")
    figure.suptitle(f"{ds.attrs.get('case', '')} {ds.attrs.get('mesh', '')}")
    figure.tight_layout()
    target = save_figure(figure, Path(path), dpi=120, release=True)
    plt.close(figure)
    return target
