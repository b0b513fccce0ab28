"""The loaded tooth contact analysis of a case's mesh, by the mesh's name.

Mesh names are pygear's: ``sun-planet1``, ``ring-planet2`` of a planetary stage,
``input-output`` of a parallel stage, prefixed ``<stage>.`` when the gearbox has more
than one geared stage (the prefixed form is always accepted).  The torque is the one
this mesh carries on its first-named gear (the sun, the ring, the input gear), so the
force along the transverse line of action is F = T / r_b of that gear.

With gear geometry on both gears the analysis is :func:`.ltca.loaded_contact` with the
mesh's material, the gears' bores and modifications, and the potential-energy law's
power flow (the planet drives the sun, the ring the planet, the input gear the
output).  A mesh without gear geometry runs its own single-pair law (parabola or
tabulated on a spur stage, the contact-line law on a helical one) on a face of unit
relative width, without Hertz and modifications:
TE, stiffness and K_Hbeta come out, pressures do not.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ...assembly.mesh_laws import LAW_CODES, mesh_law, stage_mesh_members, tooth_bodies
from ...errors import CaseError
from ...model.case import Case
from ...model.gear_geometry import MeshGeometry
from ...model.gearbox import ParallelStage
from ...model.geometry_inputs import parallel_mesh_geometry, planetary_mesh_geometry
from .ltca import _count, contact_dataset, loaded_contact, solve_slices
from .ltca_geometry import slice_grid

__all__ = ["CaseMesh", "case_loaded_contact", "case_mesh", "case_mesh_names"]


@dataclass(frozen=True)
class CaseMesh:
    """One mesh of a case as the LTCA takes it.

    Attributes
    ----------
    name : str
        The mesh's name.
    stage, member : object, str
        Its stage and the stage's member (``sun``, ``ring`` or ``mesh``).
    geometry : MeshGeometry or None
        Gear geometry of the pair (None when a gear has none).
    gears : tuple
        The two Gear objects in the geometry's order.
    driving_gear : int
        The driving gear of the geometry's pair (1 or 2).
    torque_radius : float
        Base radius of the mesh name's first gear [m]: F = T / r_b.
    """

    name: str
    stage: object
    member: str
    geometry: MeshGeometry | None
    gears: tuple
    driving_gear: int
    torque_radius: float


def _geared(case: Case) -> list:
    gearbox = getattr(case, "gearbox", None)
    return [s for s in getattr(gearbox, "stages", ()) if stage_mesh_members(s)]


def case_mesh_names(case: Case) -> tuple[str, ...]:
    """Names of every mesh of ``case`` (prefixed with the stage with several stages)."""
    stages = _geared(case)
    names = []
    for stage in stages:
        prefix = f"{stage.name}." if len(stages) > 1 else ""
        own = ("input-output",) if isinstance(stage, ParallelStage) else stage.mesh_names
        names += [prefix + name for name in own]
    return tuple(names)


def case_mesh(case: Case, name: str) -> CaseMesh:
    """The mesh ``name`` of ``case``; a one-line CaseError lists the meshes otherwise."""
    stages = _geared(case)
    for stage in stages:
        own = ("input-output",) if isinstance(stage, ParallelStage) else stage.mesh_names
        for mesh_name in own:
            if name not in (mesh_name, f"{stage.name}.{mesh_name}") or (
                name == mesh_name and len(stages) > 1
            ):
                continue
            if isinstance(stage, ParallelStage):
                gears = (stage.input_gear, stage.output_gear)
                return CaseMesh(name, stage, "mesh", parallel_mesh_geometry(stage), gears, 1,
                                float(stage.input_gear.base_radius))  # fmt: skip
            member = mesh_name.split("-", 1)[0]
            geometry = planetary_mesh_geometry(stage, member)
            gears = (stage.sun, stage.planet) if member == "sun" else (stage.planet, stage.ring)
            radius = float(getattr(stage, member).base_radius)
            # the potential-energy law's power flow: carrier in, sun out
            return CaseMesh(name, stage, member, geometry, gears, 2, radius)
    names = case_mesh_names(case)
    if not names:
        raise CaseError(f"--mesh {name!r}: case {case.name!r} has no gear meshes")
    raise CaseError(
        f"--mesh {name!r} is not a mesh of case {case.name!r}; its meshes are: "
        + ", ".join(names)
    )


def _forces(path: str, torques: Sequence[float], radius: float) -> np.ndarray:
    values = np.atleast_1d(np.asarray(torques, dtype=float))
    if values.ndim != 1 or values.size == 0 or not np.all(np.isfinite(values) & (values > 0)):
        raise CaseError(f"{path} must be positive finite torques [N m] (got {torques!r})")
    return values / radius


def case_loaded_contact(
    case: Case,
    name: str,
    torques: float | Sequence[float],
    *,
    n_slice: int = 40,
    n_position: int = 20,
    cycles: int = 1,
    coupling_length: float = 0.0,
) -> xr.Dataset:
    """LTCA of the mesh ``name`` of ``case`` at the torques ``torques`` [N m] on the mesh
    name's first gear (carried by this mesh).

    Returns
    -------
    xarray.Dataset
        :func:`.ltca.loaded_contact`'s Dataset with a ``torque`` coordinate along
        ``force`` and the case and mesh names in its attributes.
    """
    _count(f"{name}.n_slice", n_slice, 1, 400)
    _count(f"{name}.n_position", n_position, 2, 2000)
    _count(f"{name}.cycles", cycles, 1, 10_000)
    case.validate()
    mesh = case_mesh(case, name)
    forces = _forces("--torque", torques, mesh.torque_radius)
    mods = tuple(getattr(g, "modifications", None) for g in mesh.gears)
    if mesh.geometry is not None:
        stage_mesh = mesh.stage.mesh if mesh.member == "mesh" else getattr(
            mesh.stage, f"{mesh.member}_mesh"
        )
        bodies = tooth_bodies(stage_mesh, mesh.geometry,
                              tuple(g.foundation_radius for g in mesh.gears))  # fmt: skip
        ds = loaded_contact(mesh.geometry, bodies, forces, modifications=mods, n_slice=n_slice,
                            n_position=n_position, cycles=cycles,
                            coupling_length=coupling_length, driving_gear=mesh.driving_gear,
                            path=name)  # fmt: skip
        ds.attrs["source"] = "potential-energy slice compliances, gear geometry"
    else:
        if any(m is not None for m in mods):
            raise CaseError(
                f"{name}: the gears' modifications need gear geometry on both gears "
                "(Gear(geometry=GearGeometry(...)))"
            )
        ds = _law_contact(mesh, forces, n_slice, n_position, cycles)
    torque = forces * mesh.torque_radius
    ds = ds.assign_coords(torque=("force", torque, {"units": "N m", "long_name": "mesh torque"}))
    ds.attrs.update(case=case.name, mesh=name)
    return ds


def _law_contact(mesh: CaseMesh, forces: np.ndarray, n_slice: int, n_position: int,
                 cycles: int) -> xr.Dataset:  # fmt: skip
    """The mesh's own single-pair law spread evenly over a face of unit relative width."""
    law = mesh_law(mesh.stage, mesh.member)
    eps, eps_beta = law.transverse_contact_ratio, law.overlap_ratio
    if eps_beta and law.code != LAW_CODES["helical"]:
        raise CaseError(
            f"{mesh.name}: a helical mesh without gear geometry needs the helical law for "
            f"the LTCA (it runs {law.law!r})"
        )
    position = np.arange(n_position * cycles) / n_position
    grid = slice_grid(position, n_slice, 1.0, eps, eps_beta)
    if eps_beta:  # the contact-line law: the same stiffness per contact-line length
        pair = np.full(grid.path.shape, law.mean_stiffness / eps)
    elif law.curve is not None:
        samples = np.linspace(0.0, eps, law.curve.size)
        pair = law.mean_stiffness / eps * np.interp(grid.path, samples, law.curve)
    else:  # the parabola of docs/model.md section 5.2
        lam = law.end_to_peak
        peak = 3 * law.mean_stiffness / (eps * (2 + lam))
        pair = peak * (1 - (1 - lam) * (2 * grid.path / eps - 1) ** 2)
    if not np.all(pair > 0):
        raise CaseError(f"{mesh.name}: the single-pair law is not positive along the path")
    c_struct = n_slice / pair
    zeros = np.zeros_like(c_struct)
    unloaded, loaded, load, iterations = solve_slices(c_struct, zeros, grid.in_path, zeros, 0.0,
                                                      forces, path=mesh.name)  # fmt: skip
    ds = contact_dataset(
        grid, forces, unloaded, loaded, load, load, math.nan, 1.0, cycles,
        dict(eps_alpha=eps, eps_beta=eps_beta, coupling_length=0.0, hertz=0, n_slice=n_slice,
             mesh=mesh.name, max_iterations=int(iterations.max()),
             source=f"the mesh's {law.law} law on a unit relative face (no gear geometry)"),
    )  # fmt: skip
    ds["face"].attrs.update(units="1", long_name="slice centre over the face width")
    for name in ("line_load", "face_load"):
        ds[name].attrs["units"] = "N"
    return ds
