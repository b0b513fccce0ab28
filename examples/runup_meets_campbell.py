"""The study case's wide run-up against its Campbell diagram, in one figure.

    python examples/runup_meets_campbell.py [OUT] [--figure PATH]

Runs the scene ``runup_wide`` of ``cases/yang2016_planetary`` (carrier 0 -> 240 rpm in
4 s), its order tracking against the carrier and its Campbell diagram, all through the
``pygear`` commands (files in OUT, default ``out/runup_meets_campbell``), then draws the
order-speed map of the sun's rotational acceleration with the Campbell analysis on top:
each rotational mode as the curve order = 60 f / n, and each crossing of a mesh harmonic
with a rotational mode as a circle whose size is the mesh's share of the mode's strain
energy.  The figure goes to PATH (default OUT/runup_meets_campbell.png);
docs/campbell.md explains what it shows.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402

from pygear.io import open_dataset  # noqa: E402

CASE = "yang2016_planetary"
SCENE = "runup_wide"
CHANNEL = "acceleration:planetary.sun.theta_z"
WINDOW_REVOLUTIONS = 0.25
MAX_ORDER = 1100.0  # past the 10th ring-mesh harmonic, 960
HARMONICS = 10


def compute(out: Path) -> tuple[xr.Dataset, xr.Dataset]:
    """Run the scene, its order tracking and the Campbell diagram; return both results."""
    commands = [
        ["run", CASE, "--scene", SCENE, "--out", str(out)],
        ["analyze", str(out / f"{SCENE}.nc"), "--orders", "planetary.carrier",
         "--channel", CHANNEL, "--max-order", f"{MAX_ORDER:g}",
         "--window-revolutions", f"{WINDOW_REVOLUTIONS:g}", "--out", str(out / "orders")],
        ["campbell", CASE, "--scene", SCENE, "--speeds", "0:240:97",
         "--harmonics", str(HARMONICS), "--out", str(out / "campbell")],
    ]  # fmt: skip
    for argv in commands:  # each as its own process, as typed at a shell
        code = subprocess.run([sys.executable, "-m", "pygear.cli", *argv]).returncode
        if code:
            sys.exit(code)
    with open_dataset(out / "orders" / "orders.nc") as orders:
        orders = orders.load()
    with open_dataset(out / "campbell" / "campbell.nc") as campbell:
        campbell = campbell.load()
    return orders, campbell


def draw(orders: xr.Dataset, campbell: xr.Dataset, path: Path) -> None:
    """The order map (log colour) with the rotational modes and their mesh crossings."""
    amplitude = orders["order_map_amplitude"]
    map_order = orders["map_order"].values
    speed = orders["speed"].values
    values = np.asarray(amplitude.values, dtype=float)
    fig, ax = plt.subplots(figsize=(9, 5.5))
    top = values.max()
    norm = LogNorm(vmin=top * 1e-4, vmax=top)
    mesh = ax.pcolormesh(map_order, speed, np.maximum(values, norm.vmin), norm=norm)
    fig.colorbar(mesh, ax=ax, label=f"{CHANNEL} [{amplitude.attrs['units']}]")
    rotational = [
        k
        for k, mode in enumerate(campbell.mode.values)
        if str(campbell.mode_class.values[0, k]).startswith("rotational")
        and float(campbell.frequency.values[0, k]) > 0
    ]
    grid = campbell.speed.values
    running = grid >= speed.min()
    for k in rotational:
        frequency = campbell.frequency.values[running, k]
        ax.plot(60.0 * frequency / grid[running], grid[running], color="white", lw=0.6,
                ls=":", alpha=0.8)  # fmt: skip
        label_speed = speed.max() * 0.97
        label_order = 60.0 * frequency[-1] / label_speed
        if label_order < MAX_ORDER:
            ax.annotate(f"{frequency[-1]:.0f} Hz", (label_order, label_speed), color="white",
                        fontsize=7, ha="left", va="top")  # fmt: skip
    kind = dict(zip(campbell.excitation.values, campbell.excitation_kind.values))
    modes = list(campbell.mode.values)
    for k in range(campbell.sizes["crossing"]):
        mode_index = modes.index(int(campbell.crossing_mode.values[k]))
        order = float(campbell.crossing_order.values[k])
        at = float(campbell.crossing_speed.values[k])
        share = float(campbell.crossing_excitability.values[k])
        if (
            kind[str(campbell.crossing_excitation.values[k])] != "mesh"
            or mode_index not in rotational
            or order > MAX_ORDER
            or at < speed.min()
        ):
            continue
        ax.scatter(order, at, s=20 + 4000 * share, facecolors="none", edgecolors="red", lw=1.0)
    ax.set_xlim(0, MAX_ORDER)
    ax.set_ylim(speed.min(), speed.max())
    ax.set_xlabel("order of the carrier")
    ax.set_ylabel("carrier speed [rpm] (window mean)")
    ax.set_title(
        f"{CASE} {SCENE}: order map, windows of {WINDOW_REVOLUTIONS:g} rev\n"
        "rotational modes (dotted) and their mesh crossings (circles, size = the mesh's "
        "strain-energy share)",
        fontsize=8,
    )
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", type=Path, default=Path("out/runup_meets_campbell"))
    parser.add_argument("--figure", type=Path, default=None)
    args = parser.parse_args(argv)
    orders, campbell = compute(args.out)
    figure = args.figure or args.out / "runup_meets_campbell.png"
    draw(orders, campbell, figure)
    print(f"wrote {figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
