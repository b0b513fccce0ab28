"""The loaded contact as a mesh law for the dynamics.

:func:`loaded_pair_curve` turns an LTCA over a mesh cycle into a single-pair stiffness
curve: pair k at position s carries F_k(s) of the force, and the mesh's approach under
load is delta(s) - delta_0(s) (loaded minus unloaded TE), so its secant stiffness is

    k_pair(p) = F_k(s) / (delta(s) - delta_0(s)),     p = s + k,

which sums over the pairs to the LTCA's mesh stiffness F / (delta - delta_0).  For
perfect flanks it is the potential-energy law's pair curve; modifications, deviations
and misalignment make it load-dependent (a relieved tip takes no load until the load
closes the relief).  :func:`with_loaded_contact_law` gives every mesh of a case this
curve at a torque, as the ``tabulated`` law (k-bar its integral over the path), so
transients, modes and the contact table run the loaded contact; it also serves meshes
without gear geometry (their own law spread over a unit face).  A mesh with gear
geometry runs its loaded contact better as ``Mesh(law="loaded_contact")``
(:mod:`pygear.assembly.loaded_contact_table`): tabulated over position and load when
the model is assembled, the loaded TE carried by the TE-equivalent stiffness, per-tooth
deviations tooth by tooth.  This secant curve leaves out the unloaded TE and takes the
first mesh cycle's pairs for all teeth.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np
import xarray as xr

from ...assembly.mesh_laws import stage_mesh_members
from ...errors import CaseError
from ...model.case import Case
from ...model.gearbox import ParallelStage
from .ltca_case import case_loaded_contact

__all__ = ["loaded_pair_curve", "with_loaded_contact_law"]


def loaded_pair_curve(ds: xr.Dataset, index: int = 0, samples: int = 201) -> np.ndarray:
    """Secant stiffness of one tooth pair [N/m] along its path, at force ``index`` of an
    LTCA over whole mesh cycles, sampled at ``samples`` equal steps over [0, eps_alpha +
    eps_beta] (linear interpolation between the LTCA's positions)."""
    eps = float(ds.attrs["eps_alpha"] + ds.attrs["eps_beta"])
    first = ds.position.values < 1.0
    line = ds.line_load.isel(force=index).values[first]  # (position, pair, face)
    width = float(ds.attrs["face_width"])
    pair_force = line.sum(axis=2) * width / ds.face.size  # (position, pair)
    approach = (ds.te_loaded.isel(force=index).values - ds.te_unloaded.values)[first]
    stiffness = pair_force / approach[:, None]
    p = (ds.position.values[first][:, None] + np.arange(pair_force.shape[1])[None, :]).ravel()
    inside = p <= eps * (1 + 1e-12)  # the path's own samples
    order = np.argsort(p[inside])
    p, k = p[inside][order], stiffness.ravel()[inside][order]
    if p[-1] < eps and p.size > 1:  # the last step to the end: extrapolated linearly
        end = k[-1] + (k[-1] - k[-2]) * (eps - p[-1]) / (p[-1] - p[-2])
        p, k = np.append(p, eps), np.append(k, max(end, 0.0))
    return np.interp(np.linspace(0.0, eps, samples), p, k)


def _member_mesh_name(case: Case, stage: object, member: str) -> str:
    several = sum(1 for s in case.gearbox.stages if stage_mesh_members(s)) > 1
    own = "input-output" if isinstance(stage, ParallelStage) else f"{member}-planet1"
    return f"{stage.name}.{own}" if several else own


def with_loaded_contact_law(
    case: Case,
    torques: Mapping[str, float],
    *,
    n_slice: int = 40,
    n_position: int = 50,
) -> Case:
    """A copy of ``case`` whose named meshes run their loaded contact at a torque.

    Parameters
    ----------
    case : Case
        The case; its gears' modifications shape the contact.
    torques : mapping of str to float
        Torque [N m] on the first-named gear of each mesh to convert, by mesh name
        (``sun-planet1`` stands for the stage's sun meshes, ``ring-planet1`` for its
        ring meshes, ``input-output`` for a parallel stage; the prefix ``<stage>.`` as
        :func:`.ltca_case.case_mesh_names` gives them).
    n_slice, n_position : int
        Slices and positions per mesh cycle of each LTCA.

    Returns
    -------
    Case
        The copy, each converted mesh on the ``tabulated`` law with the loaded pair curve
        and its mean stiffness.

    Raises
    ------
    CaseError
        A mesh name that is not a mesh's first planet (or the parallel pair), or what
        the LTCA refuses.
    """
    case.validate()
    wanted = dict(torques)
    stages = []
    for stage in case.gearbox.stages:
        changes = {}
        for member in stage_mesh_members(stage):
            name = _member_mesh_name(case, stage, member)
            if name not in wanted:
                continue
            ds = case_loaded_contact(case, name, wanted.pop(name), n_slice=n_slice,
                                     n_position=n_position)  # fmt: skip
            curve = loaded_pair_curve(ds)
            eps = float(ds.attrs["eps_alpha"] + ds.attrs["eps_beta"])
            trapezoid = (curve.sum() - 0.5 * (curve[0] + curve[-1])) / (curve.size - 1)
            attribute = "mesh" if member == "mesh" else f"{member}_mesh"
            mesh = getattr(stage, attribute)
            changes[attribute] = dataclasses.replace(
                mesh, law="tabulated", stiffness=float(eps * trapezoid),
                stiffness_curve=tuple(float(c) for c in curve),
            )  # fmt: skip
        stages.append(dataclasses.replace(stage, **changes) if changes else stage)
    if wanted:
        raise CaseError(
            f"loaded_contact torques: {', '.join(sorted(wanted))} name no stage's first "
            "planet mesh or parallel pair; choose among "
            + ", ".join(
                _member_mesh_name(case, s, m)
                for s in case.gearbox.stages
                for m in stage_mesh_members(s)
            )
        )
    changed = dataclasses.replace(case, gearbox=dataclasses.replace(case.gearbox,
                                                                    stages=tuple(stages)))
    changed.validate()
    return changed
