"""Figures of modal results (plotting only; nothing here computes a result)."""

from __future__ import annotations

import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

from ..assembly.matrices import Model  # noqa: E402
from ..io import save_figure  # noqa: E402
from ..model.case import Case  # noqa: E402

__all__ = ["plot_frequency_sweep", "plot_modal_energy", "plot_mode_shape"]

CLASS_COLOURS = {
    "rotational": "tab:red",
    "translational": "tab:blue",
    "planet": "tab:green",
    "axial": "tab:orange",
    "tilting": "tab:purple",
}


def _distinct_modes(modal: xr.Dataset) -> list[int]:
    """Mode indices with non-zero frequency, one per repeated frequency."""
    chosen, last = [], None
    for m, f in enumerate(modal.frequency.values):
        if f <= 0 or (last is not None and abs(f - last) <= 1e-6 * f):
            continue
        chosen.append(m)
        last = f
    return chosen


def plot_modal_energy(modal: xr.Dataset, path: str | os.PathLike) -> None:
    """Bars of the four modal-energy shares for every distinct mode (paper Figs. 4, 5)."""
    modes = _distinct_modes(modal)
    columns = 4
    rows = math.ceil(len(modes) / columns)
    width, height = 2.6 * columns, 2.0 * rows
    fig, axes = plt.subplots(rows, columns, figsize=(width, height), sharey=True, squeeze=False)
    # fixed margins [in] for the tick labels and the two-line title: a layout search
    # (tight_layout) drew the figure twice and was most of its cost
    fig.subplots_adjust(
        left=0.45 / width,
        right=1 - 0.1 / width,
        bottom=0.3 / height,
        top=1 - 0.75 / height,
        wspace=0.12,
        hspace=0.5,
    )
    groups = list(modal.energy_group.values)
    for ax, m in zip(axes.flat, modes):
        shares = modal.energy_share.values[m]
        ax.bar(np.arange(1, len(groups) + 1), shares, color="tab:gray")
        cls = modal.mode_class.values[m]
        ax.set_title(
            f"{cls} {int(modal.class_index.values[m])}: {modal.frequency.values[m]:.1f} Hz",
            fontsize=8,
        )
        ax.set_xticks(np.arange(1, len(groups) + 1))
        ax.set_ylim(0, 1)
        ax.tick_params(labelsize=7)
    for ax in list(axes.flat)[len(modes) :]:
        ax.set_visible(False)
    legend = "; ".join(f"{i + 1}: {g}" for i, g in enumerate(groups))
    fig.suptitle(
        f"Modal kinetic energy, {modal.attrs.get('formulation', '')} formulation\n{legend}",
        fontsize=9,
        y=1 - 0.05 / height,  # its two lines above the first row's titles at any height
    )
    save_figure(fig, path, dpi=120)  # atomic: no half-written figure
    plt.close(fig)


def plot_mode_shape(
    case: Case, model: Model, modal: xr.Dataset, mode: int, path: str | os.PathLike
) -> None:
    """In-plane drawing of one mode of the first stage (paper Fig. 6).

    Dashed circles are the pitch circles at rest, solid ones deflected; a radial line
    on each member shows its rotation; dots mark the centres.
    """
    stage = case.gearbox.stages[0]
    shape = model.reduction @ np.asarray(modal.shape.values[:, mode], dtype=float)
    value = dict(zip(model.full_labels, shape))

    def dof(member: str, name: str) -> float:
        return float(value.get(f"{stage.name}.{member}.{name}", 0.0))

    radii = {
        "carrier": stage.carrier.radius,
        "ring": stage.ring.base_radius,
        "sun": stage.sun.base_radius,
    }
    bodies = []  # (centre at rest, displacement, rotation, radius)
    for member, radius in radii.items():
        bodies.append(
            (
                np.zeros(2),
                np.array([dof(member, "x"), dof(member, "y")]),
                dof(member, "theta_z"),
                radius,
            )
        )
    for n, psi in enumerate(stage.planet_angles, start=1):
        member = f"planet{n}"
        radial = np.array([math.cos(psi), math.sin(psi)])
        tangential = np.array([-math.sin(psi), math.cos(psi)])
        revolution = dof(member, "phi")
        displacement = (
            dof(member, "zeta") * radial
            + (dof(member, "eta") + stage.carrier.radius * revolution) * tangential
        )
        bodies.append(
            (
                stage.carrier.radius * radial,
                displacement,
                dof(member, "theta_z") + revolution,
                stage.planet.base_radius,
            )
        )
    largest = max(max(np.hypot(*d), abs(t) * r) for _, d, t, r in bodies) or 1.0
    scale = 0.12 * stage.carrier.radius / largest
    fig, ax = plt.subplots(figsize=(5.5, 5.5))
    for centre, displacement, rotation, radius in bodies:
        moved = centre + scale * displacement
        angle = scale * rotation
        ax.add_patch(Circle(tuple(centre), radius, fill=False, ls="--", lw=0.8, color="gray"))
        ax.add_patch(Circle(tuple(moved), radius, fill=False, lw=1.2, color="tab:blue"))
        ax.plot(*centre, ".", color="gray")
        ax.plot(*moved, "o", color="tab:blue", ms=3)
        tip = moved + radius * np.array([math.cos(angle), math.sin(angle)])
        ax.plot([moved[0], tip[0]], [moved[1], tip[1]], color="tab:red", lw=1)
    limit = stage.ring.base_radius * 1.15
    ax.set_xlim(-limit, limit)
    ax.set_ylim(-limit, limit)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    cls = modal.mode_class.values[mode]
    ax.set_title(
        f"{cls} {int(modal.class_index.values[mode])}, "
        f"{modal.frequency.values[mode]:.1f} Hz ({model.formulation})"
    )
    fig.tight_layout()
    save_figure(fig, path, dpi=120)  # atomic: no half-written figure
    plt.close(fig)


def plot_frequency_sweep(sweep: xr.Dataset, path: str | os.PathLike) -> None:
    """Natural frequencies against a stiffness parameter, coloured by class (paper Fig. 7)."""
    formulations = list(sweep.formulation.values) if "formulation" in sweep.dims else [None]
    fig, axes = plt.subplots(
        1, len(formulations), figsize=(5.5 * len(formulations), 4.5), sharey=True, squeeze=False
    )
    values = sweep.value.values
    for ax, formulation in zip(axes.flat, formulations):
        data = sweep.sel(formulation=formulation) if formulation is not None else sweep
        frequency = data.frequency.values
        classes = data.mode_class.values
        for m in range(frequency.shape[1]):
            ax.plot(values, frequency[:, m], color="0.75", lw=0.8, zorder=1)
        for cls, colour in CLASS_COLOURS.items():
            chosen = classes == cls
            if chosen.any():
                ax.scatter(
                    np.broadcast_to(values[:, None], frequency.shape)[chosen],
                    frequency[chosen],
                    s=6,
                    color=colour,
                    zorder=2,
                )
        ax.set_yscale("log")
        ax.set_xscale("log")
        ax.set_xlabel(
            f"{sweep.attrs.get('parameter', 'parameter')} [{sweep.value.attrs.get('units', '')}]"
        )
        ax.set_title(f"{formulation or ''} formulation")
        ax.grid(True, which="both", alpha=0.3)
    axes.flat[0].set_ylabel("natural frequency [Hz]")
    handles = [
        plt.Line2D([], [], color=c, label=k)
        for k, c in CLASS_COLOURS.items()
        if k in set(np.ravel(sweep.mode_class.values))
    ]
    axes.flat[-1].legend(handles=handles, fontsize=8)
    fig.tight_layout()
    save_figure(fig, path, dpi=120)  # atomic: no half-written figure
    plt.close(fig)
