"""Where the slices of a loaded tooth contact analysis sit, and their initial separation.

The face is cut into ``n`` slices of width w = b / n at y_i = (i + 1/2) w from the end
that enters mesh first.  Pair k at mesh position s (mesh cycles) has reached
p = s + k along its path of contact; slice i of a helical pair lags by the stagger,
q_i = p - (i + 1/2) eps_beta / n, and lies on the path while 0 <= q_i <= eps_alpha
(the face-width slicing of :mod:`pygear.assembly.tooth_stiffness`).  Roll lengths of
the contact point on both gears follow from q (docs/potential_energy.md), and the
modifications, deviations and misalignment of :mod:`pygear.model.micro_geometry` turn
them into the initial separation along the transverse line of action.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model import gear_geometry as geo
from ..model.micro_geometry import Modifications

__all__ = ["SliceGrid", "flank_roll_limits", "separation", "slice_grid"]


@dataclass(frozen=True)
class SliceGrid:
    """Slices of every pair at every position (arrays over (slice, pair, position)).

    Attributes
    ----------
    position : ndarray
        Mesh positions s [mesh cycles].
    face : ndarray
        Slice centres y [m] (or [-] of b when the face width is unknown).
    path : ndarray
        q, each slice's position along the transverse path [mesh cycles], clamped to
        [0, eps_alpha]; ``in_path`` says whether it really lies there.
    in_path : ndarray of bool
    cycle : ndarray of int
        floor(s) - k: the engagement count of the teeth of pair k (tooth numbers).
    """

    position: np.ndarray
    face: np.ndarray
    path: np.ndarray
    in_path: np.ndarray
    cycle: np.ndarray


def slice_grid(
    position: np.ndarray, n_slice: int, face_width: float, eps_alpha: float, eps_beta: float
) -> SliceGrid:
    """The slices of ceil(eps_alpha + eps_beta) + 1 pairs at the positions ``position``."""
    n_pair = math.ceil(eps_alpha + eps_beta) + 1
    i = np.arange(n_slice)[:, None, None]
    k = np.arange(n_pair)[None, :, None]
    s = np.asarray(position, dtype=float)[None, None, :]
    q = s - np.floor(s) + k - (i + 0.5) * eps_beta / n_slice
    inside = (q >= 0.0) & (q <= eps_alpha)
    width = face_width / n_slice
    return SliceGrid(
        position=np.asarray(position, dtype=float),
        face=(np.arange(n_slice) + 0.5) * width,
        path=np.clip(q, 0.0, eps_alpha),
        in_path=np.broadcast_to(inside, q.shape).copy(),
        cycle=np.broadcast_to(np.floor(s).astype(int) - k, q.shape).copy(),
    )


def flank_roll_limits(gear: geo.GearGeometry) -> tuple[float, float, float]:
    """Roll lengths sqrt(r^2 - r_b^2) of the tip and root form circles, and r_b [m]."""
    r_b = geo.base_radius(gear)
    roll = [math.sqrt(max(r * r - r_b * r_b, 0.0)) for r in (geo.tip_radius(gear),
                                                               geo.root_form_radius(gear))]
    return roll[0], roll[1], r_b


def contact_rolls(mesh: geo.MeshGeometry, q: np.ndarray, base_pitch: float, driving_gear: int):
    """Roll lengths (s1, s2) [m] of the contact at path positions q [mesh cycles] on gears
    1 and 2 of ``mesh``, q = 0 where the driving gear's root meets the other's tip."""
    span = geo.centre_distance(mesh) * math.sin(geo.working_pressure_angle(mesh))
    tip1 = flank_roll_limits(mesh.gear1)[0]
    tip2 = flank_roll_limits(mesh.gear2)[0]
    travel = q * base_pitch
    if not mesh.internal:
        if driving_gear == 1:
            s1 = span - tip2 + travel
        else:
            s1 = tip1 - travel
        return s1, span - s1
    if driving_gear == 1:  # the planet drives the ring: both rolls grow
        s1 = tip2 - span + travel
    else:  # the ring drives: its contact starts at its root
        s1 = tip1 - travel
    return s1, s1 + span


def _ramp(x: np.ndarray, shape: str) -> np.ndarray:
    x = np.clip(x, 0.0, None)
    return x * x if shape == "parabolic" else x


def profile_gap(gear: geo.GearGeometry, mods: Modifications, roll: np.ndarray) -> np.ndarray:
    """Material removed (positive) or added (negative) on the profile at roll lengths
    ``roll`` [m]: tip and root relief, profile slope deviation."""
    tip, form, r_b = flank_roll_limits(gear)
    towards_tip = -1.0 if gear.internal else 1.0  # a ring's tip is its smallest radius
    gap = np.zeros_like(roll)
    relief = mods.tip_relief
    if relief is not None and relief.amount:
        start = relief.start_roll_length(r_b)
        length = (tip - start) * towards_tip
        if length > 0:
            gap += relief.amount * _ramp((roll - start) * towards_tip / length, relief.shape)
    relief = mods.root_relief
    if relief is not None and relief.amount:
        start = relief.start_roll_length(r_b)
        length = (start - form) * towards_tip
        if length > 0:
            gap += relief.amount * _ramp((start - roll) * towards_tip / length, relief.shape)
    deviation = mods.deviations
    if deviation is not None and deviation.profile_slope and tip != form:
        gap -= deviation.profile_slope * ((roll - form) / (tip - form) - 0.5)
    return gap


def lead_gap(mods: Modifications, face: np.ndarray, face_width: float) -> np.ndarray:
    """Material removed along the face at y = ``face`` [m]: crowning, end relief, helix
    slope modification and deviation."""
    u = face / face_width
    gap = mods.crowning * (2 * u - 1) ** 2 + mods.helix_slope * (u - 0.5)
    relief = mods.end_relief
    if relief is not None and relief.amount:
        ends = np.minimum(face, face_width - face)
        gap = gap + relief.amount * _ramp(1 - ends / relief.length, relief.shape)
    if mods.deviations is not None:
        gap = gap - mods.deviations.helix_slope * (u - 0.5)
    return gap


def _cumulative_pitch(pitch: tuple[float, ...], teeth: int, tooth: np.ndarray) -> np.ndarray:
    """Cumulative pitch deviation F_p of each tooth, closed around the gear [m]."""
    deviations = np.asarray(pitch, dtype=float)
    cumulative = np.cumsum(deviations) - np.arange(1, teeth + 1) * deviations.sum() / teeth
    return cumulative[np.mod(tooth, teeth)]


def separation(
    mesh: geo.MeshGeometry,
    mods: tuple[Modifications | None, Modifications | None],
    grid: SliceGrid,
    rolls: tuple[np.ndarray, np.ndarray],
) -> np.ndarray:
    """Initial separation [m] of every slice along the transverse line of action."""
    width = min(mesh.gear1.face_width, mesh.gear2.face_width)
    face = grid.face[:, None, None]
    gap = np.zeros(grid.path.shape)
    alpha_wt = geo.working_pressure_angle(mesh)
    for gear, mod, roll in zip((mesh.gear1, mesh.gear2), mods, rolls):
        if mod is None:
            continue
        gap += profile_gap(gear, mod, roll) + lead_gap(mod, face, width)
        if mod.misalignment is not None:
            tilt = mod.misalignment.separation_slope(alpha_wt) * width + mod.misalignment.mismatch
            gap += tilt * (face / width - 0.5)
        deviation = mod.deviations
        if deviation is None:
            continue
        if deviation.pitch:
            alpha_t = geo.transverse_pressure_angle(gear)
            gap -= math.cos(alpha_t) * _cumulative_pitch(deviation.pitch, gear.teeth, grid.cycle)
        if deviation.runout:
            turn = 2 * math.pi * grid.position / gear.teeth
            phase = math.radians(deviation.runout_phase_deg)
            gap -= deviation.runout * np.sin(turn + phase)[None, None, :]
    return gap
