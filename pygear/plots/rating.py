"""Figure of a rating: safety factors S_H and S_F per gear against the required ones."""

from __future__ import annotations

from pathlib import Path

import xarray as xr

__all__ = ["plot_safety_factors"]


def plot_safety_factors(ds: xr.Dataset, path: str | Path) -> Path:
    """Bars of S_H and S_F per gear with the required safeties as lines; saved to ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    gears = [str(g) for g in ds.gear.values]
    x = np.arange(len(gears))
    figure, axes = plt.subplots(figsize=(max(6.0, 0.9 * len(gears)), 4.0))
    axes.bar(x - 0.2, ds.S_H.values, 0.4, label="S_H (pitting)")
    axes.bar(x + 0.2, ds.S_F.values, 0.4, label="S_F (bending)")
    axes.axhline(float(ds.attrs["required_sh"]), color="C0", linestyle="--", label="S_Hmin")
    axes.axhline(float(ds.attrs["required_sf"]), color="C1", linestyle="--", label="S_Fmin")
    axes.set_xticks(x, gears, rotation=30, ha="right")
    axes.set_ylabel("safety factor [-]")
    axes.set_title(str(ds.attrs.get("title", "rating")))
    axes.legend(fontsize="small")
    figure.tight_layout()
    target = Path(path)
    figure.savefig(target, dpi=120)
    plt.close(figure)
    return target
