"""Loaded tooth contact analysis (LTCA) of one mesh over a mesh cycle.

The contact lines of every tooth pair in mesh are cut into slices along the face
(:mod:`.ltca_geometry`); each slice carries the compliance of the potential-energy law
per slice width (:func:`pygear.assembly.tooth_stiffness.mesh_stiffness`: bending, shear,
axial compression and fillet foundation of both teeth, plus Yang & Lin's Hertz term),
the slices of one pair are coupled as a Pasternak foundation (Ajmi & Velex 2005), and
the initial separation comes from the gears' micro-geometry, deviations and
misalignment.  The Fortran module ``ltca`` solves the contact problem with non-negative
slice loads at each position and load (Conry & Seireg 1973).  Equations, choices and
validation: the documentation's contact page.

Results are along the transverse line of action: the transmission error (TE) is the
approach of the flanks, delta = theta_1 r_b1 - theta_2 r_b2 (the driven gear's lag), the
force F the transmitted force along that line (F = T_1 / r_b1).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..errors import CaseError
from ..kernel import _kernel
from ..model import gear_geometry as geo
from ..model.component_rules import is_finite_number
from ..model.micro_geometry import Modifications, check_modifications
from .ltca_geometry import SliceGrid, contact_rolls, separation, slice_grid
from .tooth_stiffness import ToothBody, mesh_stiffness

if TYPE_CHECKING:  # xarray only where a result is built: mesh laws import this module
    import xarray as xr

__all__ = ["contact_dataset", "loaded_contact", "solve_slices", "te_harmonics"]

_KERNEL_ERRORS = {
    1: "an input is out of range",
    2: "an array size is out of range",
    3: "no slice lies on the path of contact",
    4: "a compliance block is not positive definite",
    5: "the active set did not settle",
}


def _count(path: str, value: object, low: int, high: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise CaseError(f"{path} must be a whole number in [{low}, {high}] (got {value!r})")


def _forces(path: str, force: float | Sequence[float]) -> np.ndarray:
    values = np.atleast_1d(np.asarray(force, dtype=float))
    if values.ndim != 1 or values.size == 0 or not np.all(np.isfinite(values) & (values > 0)):
        raise CaseError(f"{path} must be positive finite forces [N] (got {force!r})")
    return values


def solve_slices(
    c_struct: np.ndarray,
    c_hertz: np.ndarray,
    in_path: np.ndarray,
    gap: np.ndarray,
    coupling: float,
    force: np.ndarray,
    *,
    path: str = "mesh",
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The kernel's contact solve over (slice, pair, position) arrays.

    Returns
    -------
    te_unloaded : ndarray (position)
        Approach at first contact [m].
    te_loaded : ndarray (position, load)
        Loaded approach [m].
    load : ndarray (slice, pair, position, load)
        Slice loads [N].
    iterations : ndarray (position, load)
        Active-set iterations.
    """
    unloaded, loaded, load, iterations, bad, ierr = _kernel.ltca_mesh(
        np.asfortranarray(c_struct, dtype=float),
        np.asfortranarray(c_hertz, dtype=float),
        np.asfortranarray(in_path, dtype=np.int32),
        np.asfortranarray(gap, dtype=float),
        float(coupling),
        np.asarray(force, dtype=float),
    )
    if ierr:
        reason = _KERNEL_ERRORS.get(int(ierr), f"error code {int(ierr)}")
        where = f" at position {bad - 1}" if ierr in (3, 5) else f" (entry {bad})"
        raise CaseError(f"{path}: the contact solve failed{where}: {reason}")
    return np.array(unloaded), np.array(loaded), np.array(load), np.array(iterations)


def te_harmonics(te: np.ndarray, cycles: int, orders: int) -> np.ndarray:
    """Amplitudes [m] of mesh orders 1..``orders`` of TE sampled uniformly over
    ``cycles`` whole mesh cycles along the last axis (one-sided, 2 |X| / N)."""
    spectrum = np.fft.rfft(te, axis=-1)
    n = te.shape[-1]
    index = np.arange(1, orders + 1) * cycles
    return 2 * np.abs(spectrum[..., index]) / n


def _pressure_factor(mesh: geo.MeshGeometry, bodies, rolls) -> np.ndarray:
    """E* / (pi R) of Hertz's line contact at every slice [Pa/m]: p_H = sqrt(w E*/(pi R))
    with w the line load, R the relative radius of curvature in the normal plane."""
    e_star = 1 / sum((1 - b.poisson_ratio**2) / b.young_modulus for b in bodies)
    cos_b = math.cos(geo.base_helix_angle(mesh.gear1))
    rho1 = np.maximum(rolls[0], 1e-9) / cos_b
    rho2 = np.maximum(rolls[1], 1e-9) / cos_b
    curvature = 1 / rho1 - 1 / rho2 if mesh.internal else 1 / rho1 + 1 / rho2
    return e_star * np.abs(curvature) / math.pi


def loaded_contact(
    mesh: geo.MeshGeometry,
    bodies: tuple[ToothBody, ToothBody],
    force: float | Sequence[float],
    *,
    modifications: tuple[Modifications | None, Modifications | None] = (None, None),
    n_slice: int = 40,
    n_position: int = 20,
    cycles: int = 1,
    coupling_length: float = 0.0,
    hertz: bool = True,
    driving_gear: int = 1,
    path: str = "mesh",
) -> xr.Dataset:
    """Loaded tooth contact analysis of ``mesh`` at the forces ``force``.

    Parameters
    ----------
    mesh : MeshGeometry
        The gear pair (gear 2 may be a ring).
    bodies : (ToothBody, ToothBody)
        Material and bores of gears 1 and 2 (the potential-energy law's).
    force : float or sequence of float
        Transmitted forces along the transverse line of action [N], > 0.
    modifications : (Modifications or None, Modifications or None)
        Micro-geometry, deviations and misalignment of gears 1 and 2.
    n_slice : int
        Slices along the face (1..400).
    n_position : int
        Positions per mesh cycle (2..2000).
    cycles : int
        Mesh cycles covered (1..10000): a single pitch deviation or runout needs a
        revolution of the gear (its tooth number of cycles).
    coupling_length : float
        Decay length lambda of the Pasternak coupling of neighbouring slices [m], >= 0.
        0 (the default) leaves the slices uncoupled (a Winkler foundation, as the
        potential-energy law's slicing and ISO 6336-1's K_Hbeta take the face); the
        coupling is not calibrated and loads the face ends and the contact lines' ends
        under a varying deflection (the documentation's contact page).
    hertz : bool
        Include Yang & Lin's linear Hertz compliance (as the potential-energy law does).
    driving_gear : int
        1 or 2: the path of contact starts where the driving gear's root meets the
        other's tip (and the driving flanks carry the micro-geometry).
    path : str
        Name of the mesh in error messages.

    Returns
    -------
    xarray.Dataset
        Over ``force`` (N), ``position`` (mesh cycles), ``pair`` and ``face`` (slice
        centre y [m]): ``te_unloaded``, ``te_loaded``, ``mesh_stiffness`` (F over the
        loaded minus the unloaded TE), ``line_load`` [N/m], ``contact_pressure`` [Pa],
        ``face_load`` (line load summed over the pairs) and per force ``mean_te``,
        ``te_peak_to_peak``, ``te_harmonics`` (by mesh ``order``), ``k_h_beta`` (the
        peak of the face load's mean over the positions, over F/b), ``k_h_beta_peak``
        (the largest face load at any position over F/b), ``k_h_alpha`` (1 plus the
        largest extra share of F a tooth pair takes over perfect flanks at the same
        position) and
        ``max_contact_pressure``.

    Raises
    ------
    CaseError
        Bad input, naming the parameter and its rule.
    """
    forces = _forces(f"{path}.force", force)
    _count(f"{path}.n_slice", n_slice, 1, 400)
    _count(f"{path}.n_position", n_position, 2, 2000)
    _count(f"{path}.cycles", cycles, 1, 10_000)
    if driving_gear not in (1, 2):
        raise CaseError(f"{path}.driving_gear must be 1 or 2 (got {driving_gear!r})")
    if len(modifications) != 2:
        raise CaseError(
            f"{path}.modifications must hold one entry per gear (got {modifications!r})"
        )
    for index, (mod, gear) in enumerate(zip(modifications, (mesh.gear1, mesh.gear2))):
        check_modifications(f"{path}.modifications[{index}]", mod)
        pitch = mod.deviations.pitch if mod is not None and mod.deviations else ()
        if pitch and len(pitch) != gear.teeth:
            raise CaseError(
                f"{path}.modifications[{index}].deviations.pitch must hold one deviation per "
                f"tooth ({gear.teeth}), or none (got {len(pitch)})"
            )
    if not (is_finite_number(coupling_length) and 0 <= coupling_length < 10):
        raise CaseError(
            f"{path}.coupling_length must be a length in [0, 10) m (got {coupling_length!r})"
        )
    stiffness = mesh_stiffness(mesh, bodies, n_slice=1, driving_gear=driving_gear, path=path)
    eps_alpha, eps_beta = stiffness.contact_ratio, stiffness.overlap_ratio
    width = min(mesh.gear1.face_width, mesh.gear2.face_width)
    position = np.arange(n_position * cycles) / n_position
    grid = slice_grid(position, n_slice, width, eps_alpha, eps_beta)
    total = sum(stiffness.compliance.values())
    # the law's samples without contact (0: an end of the path a hair beyond the flank)
    known = total > 0
    c_hertz_whole = float(stiffness.compliance["hertz"][known][0])
    c_whole = np.interp(grid.path, stiffness.spur_position[known], total[known])
    c_struct = (c_whole - c_hertz_whole) * n_slice
    c_hertz = np.full_like(c_struct, c_hertz_whole * n_slice if hertz else 0.0)
    rolls = contact_rolls(mesh, grid.path, stiffness.base_pitch, driving_gear)
    gap = separation(mesh, modifications, grid, rolls)
    kappa = (coupling_length * n_slice / width) ** 2
    unloaded, loaded, load, iterations = solve_slices(
        c_struct, c_hertz, grid.in_path, gap, kappa, forces, path=path
    )
    has_gap = bool(np.any(gap != 0))
    if has_gap:
        ref = solve_slices(c_struct, c_hertz, grid.in_path, np.zeros_like(gap), kappa, forces,
                           path=path)[2]  # fmt: skip
    else:
        ref = load
    factor = np.transpose(_pressure_factor(mesh, bodies, rolls), (2, 1, 0))
    return contact_dataset(
        grid, forces, unloaded, loaded, load, ref, factor, width, cycles,
        dict(eps_alpha=eps_alpha, eps_beta=eps_beta, base_pitch=stiffness.base_pitch,
             coupling_length=coupling_length, hertz=int(hertz), driving_gear=driving_gear,
             n_slice=n_slice, mesh=path, max_iterations=int(iterations.max())),
    )  # fmt: skip


def contact_dataset(
    grid: SliceGrid,
    forces: np.ndarray,
    unloaded: np.ndarray,
    loaded: np.ndarray,
    load: np.ndarray,
    ref: np.ndarray,
    pressure_factor: np.ndarray | float,
    width: float,
    cycles: int,
    attrs: dict,
) -> xr.Dataset:
    """The LTCA's Dataset from the kernel's arrays (see :func:`loaded_contact`);
    ``pressure_factor`` is E*/(pi R) over (position, pair, slice) [Pa/m] (NaN: unknown),
    ``ref`` the slice loads of perfect flanks."""
    n_slice = grid.face.size
    te = loaded.T  # (force, position)
    line = np.moveaxis(load, 3, 0) * n_slice / width  # (force, slice, pair, position)
    line = np.transpose(line, (0, 3, 2, 1))  # (force, position, pair, slice)
    pressure = np.sqrt(line * pressure_factor)
    face_load = line.sum(axis=2)  # (force, position, slice)
    mean_line = forces / width
    # ISO 6336-1's K_Hbeta: the face load distribution over the mesh cycle's mean (every
    # transverse section sees every path position once per cycle), its peak over F/b
    k_h_beta = face_load.mean(axis=1).max(axis=1) / mean_line
    k_h_beta_peak = face_load.max(axis=(1, 2)) / mean_line
    pair_force = np.moveaxis(load.sum(axis=0), 2, 0)  # (force, pair, position)
    ref_force = np.moveaxis(ref.sum(axis=0), 2, 0)
    k_h_alpha = 1 + (pair_force - ref_force).max(axis=(1, 2)) / forces
    orders = max(1, min(10, (te.shape[1] // cycles - 1) // 2))
    harmonics = te_harmonics(te, cycles, orders)
    with np.errstate(divide="ignore", invalid="ignore"):
        stiffness = forces[:, None] / (te - unloaded[None, :])
    force_attrs = {"units": "N", "long_name": "force along the transverse line of action"}
    import xarray as xr

    return xr.Dataset(
        {
            "te_unloaded": ("position", unloaded,
                            {"units": "m", "long_name": "unloaded transmission error"}),
            "te_loaded": (("force", "position"), te,
                          {"units": "m", "long_name": "loaded transmission error"}),
            "mesh_stiffness": (("force", "position"), stiffness,
                               {"units": "N/m", "long_name": "mesh stiffness F / (TE - TE_0)"}),
            "line_load": (("force", "position", "pair", "face"), line,
                          {"units": "N/m", "long_name": "line load of each slice"}),
            "contact_pressure": (("force", "position", "pair", "face"), pressure,
                                 {"units": "Pa", "long_name": "maximum Hertzian pressure"}),
            "face_load": (("force", "position", "face"), face_load,
                          {"units": "N/m", "long_name": "line load summed over the pairs"}),
            "path_position": (("pair", "position"), (grid.position[None, :]
                              + np.arange(grid.path.shape[1])[:, None]),
                              {"units": "1", "long_name": "pair position p along the path"}),
            "mean_te": ("force", te.mean(axis=1), {"units": "m", "long_name": "mean loaded TE"}),
            "te_peak_to_peak": ("force", np.ptp(te, axis=1),
                                {"units": "m", "long_name": "peak-to-peak loaded TE"}),
            "te_harmonics": (("force", "order"), harmonics,
                             {"units": "m", "long_name": "amplitude of TE mesh harmonics"}),
            "k_h_beta": ("force", k_h_beta,
                         {"units": "1", "long_name": "face load factor: peak of the cycle's "
                          "mean face load over F/b"}),
            "k_h_beta_peak": ("force", k_h_beta_peak,
                              {"units": "1", "long_name": "largest face load at any position "
                               "over F/b"}),
            "k_h_alpha": ("force", k_h_alpha,
                          {"units": "1", "long_name": "transverse load factor: 1 + largest "
                           "extra share of F a pair takes over perfect flanks"}),
            "max_contact_pressure": ("force", pressure.max(axis=(1, 2, 3)),
                                     {"units": "Pa", "long_name": "maximum Hertzian pressure"}),
        },
        coords={
            "force": ("force", forces, force_attrs),
            "position": ("position", grid.position, {"units": "1", "long_name": "mesh cycles"}),
            "pair": ("pair", np.arange(grid.path.shape[1]), {"long_name": "tooth pair"}),
            "face": ("face", grid.face, {"units": "m", "long_name": "slice centre along the face"}),
            "order": ("order", np.arange(1, harmonics.shape[1] + 1),
                      {"units": "1", "long_name": "mesh order"}),
        },
        attrs={**attrs, "face_width": width, "cycles": cycles},
    )  # fmt: skip
