"""Drawing of one mode shape of a gear stage (plotting only; nothing here computes).

A stage is drawn as its bodies, each a disc: a planetary stage's carrier (the circle
through the planet centres), ring, sun and planets at their base radii, a parallel
stage's two gears at theirs, each at its centre (:meth:`ParallelStage.position`).  A
mode moves every disc by its centre's translation and turns it by its rotation, both
taken from the full DOF vector (``q_full = T q``) and put into the inertial frame
(docs/model.md, section 1): a planet's ``zeta`` and ``eta`` along its radial and
tangential unit vectors, plus its revolution ``r_c phi``; its tilts ``theta_zeta`` and
``theta_eta`` about the same vectors; its spin ``theta_z`` relative to the carrier,
plus ``phi``.

The transverse plane (x-y, seen from +z) shows the in-plane motion, as the seed's
Figure 6 does.  A stage whose model keeps out-of-plane DOFs (a helical stage, whose
mesh forces have an axial part and tilt the gears) is also drawn in the two axial
planes, where each disc shows edge-on: in the x-z plane (seen from +y) its axial
motion and its tilt about y, in the y-z plane (seen from -x) its tilt about x.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle

from ..assembly.matrices import Model
from ..model.case import Case
from .layout import new_figure, result_title

__all__ = ["OUT_OF_PLANE_DOFS", "plot_mode_shape", "stage_mode"]

DPI = 120
"""Resolution the figure is drawn at [pixels per inch]; save it at the same."""

OUT_OF_PLANE_DOFS = frozenset({"z", "theta_x", "theta_y", "theta_zeta", "theta_eta"})
"""DOF names that move a body out of its stage's transverse plane."""

DEFLECTION_SHARE = 0.12
"""The largest in-plane motion of a drawn mode, as a share of the transverse view's
half-width: neither a centre's translation nor a rim's travel by its rotation about z
exceeds it."""

EDGE_SHARE = 0.4
"""The largest motion seen in the axial planes (a centre's translation, a rim's travel
by a tilt), as a share of their half-width along z.  The axial planes have a scale of
their own: a helical stage's axial motion and tilts are often much smaller than its
rotation, and would not show at the transverse view's scale."""

PANEL_INCH, LEFT_INCH, GAP_INCH, TOP_INCH, BOTTOM_INCH = 4.2, 0.8, 0.75, 0.9, 1.05
"""Fixed layout [in]: the transverse view's square panel (the axial views are half as
wide), the y label's margin, the gap between panels (the next panel's y label), the
figure's two-line title, the x label and the key."""


@dataclass(frozen=True)
class _Disc:
    """A body drawn as a disc normal to the gearbox axis, and its motion in a mode."""

    name: str
    centre: np.ndarray  # (x, y, z) at rest [m]
    radius: float  # [m]
    translation: np.ndarray  # (x, y, z) of the centre, mode units
    rotation: np.ndarray  # (about x, about y, about z), mode units


def _planetary_discs(stage, dof: Callable[[str, str], float]) -> list[_Disc]:
    z = float(stage.axial_position)
    discs = []
    for member, radius in (
        ("carrier", stage.carrier.radius),
        ("ring", stage.ring.base_radius),
        ("sun", stage.sun.base_radius),
    ):
        discs.append(
            _Disc(
                f"{stage.name}.{member}",
                np.array([0.0, 0.0, z]),
                radius,
                np.array([dof(member, "x"), dof(member, "y"), dof(member, "z")]),
                np.array([dof(member, "theta_x"), dof(member, "theta_y"), dof(member, "theta_z")]),
            )
        )
    r_c = stage.carrier.radius
    for n, psi in enumerate(stage.planet_angles, start=1):
        member = f"planet{n}"
        radial = np.array([math.cos(psi), math.sin(psi), 0.0])
        tangential = np.array([-math.sin(psi), math.cos(psi), 0.0])
        axial = np.array([0.0, 0.0, 1.0])
        revolution = dof(member, "phi")
        translation = (
            dof(member, "zeta") * radial
            + (dof(member, "eta") + r_c * revolution) * tangential
            + dof(member, "z") * axial
        )
        rotation = (
            dof(member, "theta_zeta") * radial
            + dof(member, "theta_eta") * tangential
            + (dof(member, "theta_z") + revolution) * axial
        )
        centre = r_c * radial + z * axial
        discs.append(
            _Disc(f"{stage.name}.{member}", centre, stage.planet.base_radius, translation, rotation)
        )
    return discs


def _parallel_discs(stage, dof: Callable[[str, str], float]) -> list[_Disc]:
    return [
        _Disc(
            f"{stage.name}.{member}",
            np.array(stage.position(member), dtype=float),
            getattr(stage, member).base_radius,
            np.array([dof(member, "x"), dof(member, "y"), dof(member, "z")]),
            np.array([dof(member, "theta_x"), dof(member, "theta_y"), dof(member, "theta_z")]),
        )
        for member in stage.member_names
    ]


def _discs(stage, model: Model, shape: np.ndarray) -> list[_Disc]:
    """The stage's bodies moved by ``shape`` (over the reduced DOFs)."""
    value = dict(zip(model.full_labels, model.reduction @ shape))

    def dof(member: str, name: str) -> float:
        return float(value.get(f"{stage.name}.{member}.{name}", 0.0))

    if stage.kind == "planetary":
        return _planetary_discs(stage, dof)
    if stage.kind == "parallel":
        return _parallel_discs(stage, dof)
    raise ValueError(f"stage {stage.name!r} ({stage.kind}) has no gears to draw")


def _front_view(ax: Axes, discs: list[_Disc], scale: float, colours: list[str]) -> None:
    """Transverse plane: rest circles dashed, moved ones solid with a radius turned by
    the disc's rotation about z."""
    for disc, colour in zip(discs, colours):
        centre = disc.centre[:2]
        moved = centre + scale * disc.translation[:2]
        angle = scale * disc.rotation[2]
        ax.add_patch(Circle(tuple(centre), disc.radius, fill=False, ls="--", lw=0.7, color="0.6"))
        ax.add_patch(Circle(tuple(moved), disc.radius, fill=False, lw=1.2, color=colour))
        tip = moved + disc.radius * np.array([math.cos(angle), math.sin(angle)])
        ax.plot([moved[0], tip[0]], [moved[1], tip[1]], color=colour, lw=1.4)
        ax.plot(*moved, "o", color=colour, ms=3)


def _edge_view(ax: Axes, discs: list[_Disc], scale: float, colours: list[str], across: int) -> None:
    """An axial plane: each disc edge-on, as a segment through its centre along the
    in-plane axis ``across`` (0: x, 1: y) drawn against z, turned by its tilt about
    the other in-plane axis."""
    for disc, colour in zip(discs, colours):
        z0, c0 = disc.centre[2], disc.centre[across]
        ax.plot([z0, z0], [c0 - disc.radius, c0 + disc.radius], ls="--", lw=0.7, color="0.6")
        z1 = z0 + scale * disc.translation[2]
        c1 = c0 + scale * disc.translation[across]
        # a rim point at +r along x turns about y to z = -r sin(theta_y); along y about
        # x to z = +r sin(theta_x)
        tilt = scale * (disc.rotation[0] if across == 1 else -disc.rotation[1])
        dz, dc = disc.radius * math.sin(tilt), disc.radius * math.cos(tilt)
        ax.plot([z1 - dz, z1 + dz], [c1 - dc, c1 + dc], lw=1.4, color=colour)
        ax.plot(z1, c1, "o", color=colour, ms=3)


def stage_mode(modal: xr.Dataset, stage: str) -> int | None:
    """The mode drawn for ``stage``: the lowest of non-zero frequency that holds most of
    its energy in the stage (``modal.stage_name``), a rotational one (its meshes
    deflect) where there is one; None when no mode lives in the stage."""
    if "stage_name" not in modal:
        return None
    own = [
        m
        for m, (name, frequency) in enumerate(zip(modal.stage_name.values, modal.frequency.values))
        if str(name) == stage and frequency > 0
    ]
    rotational = [m for m in own if str(modal.mode_class.values[m]) == "rotational"]
    return (rotational or own or [None])[0]


def plot_mode_shape(
    case: Case,
    model: Model,
    modal: xr.Dataset,
    mode: int,
    *,
    stage: str | None = None,
    scene: str | None = None,
) -> Figure:
    """One mode of one stage, in the transverse plane and, for a stage with
    out-of-plane DOFs in the model (a helical stage), in the two axial planes too.

    Parameters
    ----------
    case : Case
        The case the model was assembled from.
    model : Model
        The assembled model (its reduction gives the full DOF vector).
    modal : xarray.Dataset
        From :func:`pygear.analysis.modes.modal.modal_analysis` of ``model``.
    mode : int
        Position of the mode along ``modal.mode`` (0 is the lowest).
    stage : str, optional
        Stage to draw; default the stage that holds most of the mode's energy
        (``modal.stage_name``), else the first.
    scene : str, optional
        The scene the model was assembled for, for the title when the attributes of
        ``modal`` do not name one.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per plane; dashed: at rest, solid: the moved discs with a radius
        turned by the rotation about the axis, the in-plane motion scaled so the
        largest is :data:`DEFLECTION_SHARE` of the view's half-width, that of the
        axial planes by :data:`EDGE_SHARE`.
    """
    stages = {s.name: s for s in case.gearbox.stages}
    if stage is None:
        stage = str(modal.stage_name.values[mode]) if "stage_name" in modal else None
        stage = stage if stage in stages else case.gearbox.stages[0].name
    if stage not in stages:
        raise ValueError(f"stage {stage!r} is not a stage of {case.name} ({', '.join(stages)})")
    chosen = stages[stage]
    discs = _discs(chosen, model, np.asarray(modal.shape.values[:, mode], dtype=float))
    spatial = any(
        label.startswith(f"{stage}.") and label.rsplit(".", 1)[1] in OUT_OF_PLANE_DOFS
        for label in model.dof_labels
    )
    low = np.min([d.centre - d.radius for d in discs], axis=0)
    high = np.max([d.centre + d.radius for d in discs], axis=0)
    middle = 0.5 * (low + high)
    half = 0.5 * float(np.max(high[:2] - low[:2])) * 1.2  # half the side of a panel [m]
    in_plane = max(
        max(float(np.max(np.abs(d.translation[:2]))), abs(float(d.rotation[2])) * d.radius)
        for d in discs
    )
    axial = max(
        max(float(np.max(np.abs(d.translation))), float(np.max(np.abs(d.rotation[:2]))) * d.radius)
        for d in discs
    )
    scale = DEFLECTION_SHARE * half / in_plane if in_plane > 0 else 0.0
    edge_scale = EDGE_SHARE * 0.5 * half / axial if axial > 0 else 0.0
    colours = [f"C{n % 10}" for n in range(len(discs))]

    widths = [PANEL_INCH] + ([0.5 * PANEL_INCH] * 2 if spatial else [])
    width = LEFT_INCH + sum(widths) + (len(widths) - 1) * GAP_INCH + 0.2
    height = TOP_INCH + PANEL_INCH + BOTTOM_INCH
    figure = new_figure(width, height, DPI)
    axes = []
    left = LEFT_INCH
    for panel_width in widths:
        axes.append(
            figure.add_axes(
                (left / width, BOTTOM_INCH / height, panel_width / width, PANEL_INCH / height)
            )
        )
        left += panel_width + GAP_INCH
    _front_view(axes[0], discs, scale, colours)
    axes[0].set_xlim(middle[0] - half, middle[0] + half)
    axes[0].set_ylim(middle[1] - half, middle[1] + half)
    axes[0].set_xlabel("x [m]")
    axes[0].set_ylabel("y [m]")
    axes[0].set_title("(a) transverse plane, seen from +z", fontsize=9, loc="left")
    if spatial:
        for ax, across, name, title in (
            (axes[1], 0, "x", "(b) x-z plane, from +y\ntilt about y"),
            (axes[2], 1, "y", "(c) y-z plane, from -x\ntilt about x"),
        ):
            _edge_view(ax, discs, edge_scale, colours, across)
            ax.set_xlim(middle[2] - 0.5 * half, middle[2] + 0.5 * half)
            ax.set_ylim(middle[across] - half, middle[across] + half)
            ax.set_xlabel("z [m]")
            ax.set_ylabel(f"{name} [m]")
            ax.set_title(title, fontsize=9, loc="left")
    for ax in axes:
        ax.set_aspect("equal")
        ax.tick_params(labelsize=8)
        ax.grid(alpha=0.25, lw=0.4)
    handles = [Line2D([], [], color=c, lw=1.4, label=d.name) for d, c in zip(discs, colours)]
    handles.append(Line2D([], [], color="0.6", ls="--", lw=0.7, label="at rest"))
    key = "solid: moved, dashed: at rest; a radius shows the rotation about z"
    if spatial:
        key += ",\na segment's slope the tilt; (b) and (c) drawn to a larger scale than (a)"
    figure.legend(
        handles=handles,
        loc="lower center",
        ncol=min(len(handles), 6 if spatial else 4),
        fontsize=7,
        frameon=False,
        title=key,
        title_fontsize=7,
    )
    number = int(modal.mode.values[mode]) if "mode" in modal.coords else mode + 1
    figure.suptitle(
        f"Mode {number} of {stage}: {modal.mode_class.values[mode]} "
        f"{int(modal.class_index.values[mode])}, {float(modal.frequency.values[mode]):.1f} Hz\n"
        f"{result_title(modal.attrs, scene=scene, formulation=model.formulation)}",
        fontsize=10,
        y=1 - 0.08 / height,
    )
    return figure
