"""Post-process a sweep's results with xarray: a Campbell-style plot and a map.

    python examples/postprocess_sweep.py [SWEEP]

SWEEP is a sweep's combined file (``sweep_<hash>.nc``, printed by ``pygear sweep``) or
its ``--out`` directory, whose newest combined file is taken (several sweeps may share
a directory).  Without it a small sweep of the study case over the sun-planet and
ring-planet mesh stiffnesses is run first (``out/postprocess_example``).  Writes
``campbell.png`` and ``map.png`` beside the combined file.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from pygear.io import open_dataset, open_mfdataset  # noqa: E402

COLOURS = {"rotational": "tab:red", "translational": "tab:blue", "planet": "tab:green"}


def open_sweep(target: Path) -> xr.Dataset:
    """The combined dataset: the file given, or a directory's newest ``sweep_*.nc``; the
    point files of a directory holding one grid sweep give the same with open_mfdataset."""
    if target.is_file():
        return open_dataset(target).load()
    combined = sorted(target.glob("sweep_*.nc"), key=lambda p: p.stat().st_mtime)
    if combined:
        return open_dataset(combined[-1]).load()
    directory = target
    # an interrupted sweep has no combined file yet: combine the points done so far
    files = sorted(directory.glob("point_*.nc"))
    return open_mfdataset(
        files, combine="by_coords", data_vars="all", coords="different",
        compat="no_conflicts", join="outer",
    ).load()  # fmt: skip


def swept(sweep: xr.Dataset) -> list[str]:
    """The swept parameters' dimensions (each path with ``.`` as ``__``), in the order
    given to the sweep."""
    return sweep.attrs["sweep_dimensions"].split()


def campbell(sweep: xr.Dataset, path: Path) -> None:
    """Natural frequency against the first swept parameter, a line per mode, the
    points coloured by mode class (other parameters at their middle value)."""
    x_name, *others = swept(sweep)
    cut = sweep.isel({name: sweep.sizes[name] // 2 for name in others})
    x = cut[x_name].values
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for mode in cut.mode.values[1:]:  # mode 1 is the rigid-body rotation (0 Hz)
        line = cut.sel(mode=mode)
        ax.plot(x, line.frequency, color="0.7", lw=0.8, zorder=1)
        for family, colour in COLOURS.items():
            chosen = line.mode_class.values == family
            ax.scatter(x[chosen], line.frequency.values[chosen], s=8, color=colour, zorder=2)
    ax.set(xscale="log", yscale="log", ylabel="natural frequency [Hz]")
    ax.set_xlabel(f"{x_name} [{sweep[x_name].attrs.get('units', '')}]")
    ax.set_title(", ".join(f"{n} = {float(cut[n]):.3g}" for n in others) or sweep.attrs["case"])
    present = set(np.ravel(cut.mode_class.values))
    ax.legend(
        handles=[plt.Line2D([], [], color=c, label=k) for k, c in COLOURS.items() if k in present]
    )
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def metric(sweep: xr.Dataset) -> xr.DataArray:
    """The quantity mapped over two parameters."""
    if "frequency" in sweep:  # a modal sweep: the second rotational frequency
        second = (sweep.mode_class == "rotational") & (sweep.class_index == 2)
        values = sweep.frequency.where(second).max("mode")
        return values.assign_attrs(long_name="second rotational frequency", units="Hz")
    # ------------------------------------------------------------------------------
    # TRANSIENT SWEEPS: return the dynamic mesh-force metric here, e.g. the largest
    # dynamic factor of the sun-planet meshes once the transient points provide it:
    #     return sweep["dynamic_mesh_force_factor"].sel(mesh=...).max("mesh")
    # ------------------------------------------------------------------------------
    raise KeyError("no metric defined for this sweep's variables")


def metric_map(sweep: xr.Dataset, path: Path) -> None:
    """The metric over the first two swept parameters."""
    x_name, y_name = swept(sweep)[:2]
    values = metric(sweep).transpose(y_name, x_name, ...)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    mesh = ax.pcolormesh(sweep[x_name], sweep[y_name], values, shading="nearest")
    fig.colorbar(mesh, label=f"{values.attrs['long_name']} [{values.attrs['units']}]")
    ax.set(xscale="log", yscale="log", xlabel=x_name, ylabel=y_name)
    failed = values.isnull().values  # failed points, or points not run yet
    if failed.any():
        y_index, x_index = np.nonzero(failed)
        ax.scatter(sweep[x_name].values[x_index], sweep[y_name].values[y_index], marker="x",
                   color="k", label="no result")  # fmt: skip
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    if len(sys.argv) > 1:
        target = Path(sys.argv[1])
    else:
        from pygear.runs.sweep import run_sweep

        case = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"
        params = [
            ("planetary.sun_mesh.stiffness", "logspace(7,10,13)"),
            ("planetary.ring_mesh.stiffness", "logspace(7,10,9)"),
        ]
        result = run_sweep(
            case, params, scene="modal", out_dir="out/postprocess_example", workers=2
        )
        target = Path(result.attrs["path"])
    sweep = open_sweep(target)
    directory = target.parent if target.is_file() else target
    campbell(sweep, directory / "campbell.png")
    written = [directory / "campbell.png"]
    if len(swept(sweep)) >= 2:
        metric_map(sweep, directory / "map.png")
        written.append(directory / "map.png")
    print("wrote " + " and ".join(str(p) for p in written))


if __name__ == "__main__":
    main()
