"""The dynamic factor of every mesh at one operating speed, for other analyses (a rating's
K_v from the dynamic model instead of ISO 6336-1 method B).

:func:`dynamic_factors_at` balances one speed of any gear case: a planetary stage or gear
pair (one mesh frequency, Hill's method), a gearbox or drivetrain of several stages (the
multi-frequency balance), and returns K_v = peak over mean mesh force over the
steady state, by mesh.
"""

from __future__ import annotations

import math

from ...errors import CaseError
from ...model.case import Case, Scene
from .sweep import DEFAULT_TOLERANCE, forced_response

__all__ = ["dynamic_factors_at", "rating_mesh_name"]


def rating_mesh_name(stage: str, mesh: str) -> str:
    """The rating's name of a response mesh: ``stage1.sun_mesh`` for ``stage1.sun-planet2``,
    ``stage1.ring_mesh`` for a ring-planet mesh, ``parallel.mesh`` for a parallel pair."""
    kind = mesh.split(".")[-1]
    if kind.startswith("sun-"):
        return f"{stage}.sun_mesh"
    if kind.startswith("ring-"):
        return f"{stage}.ring_mesh"
    return f"{stage}.mesh"


def dynamic_factors_at(
    case: Case,
    speed_rpm: float,
    torque: float | None = None,
    *,
    scene: Scene | None = None,
    harmonics: int | str = "auto",
    tolerance: float = DEFAULT_TOLERANCE,
    keys: str = "mesh",
) -> dict[str, float]:
    """Dynamic factor K_v of every mesh at one input speed.

    K_v = max_t F_m(t) / mean_t F_m(t) over the steady state at constant speed (the
    ``dynamic_factor`` of :func:`~pygear.analysis.response.forced_response`: the linear
    model, tooth separation not resolved).

    Parameters
    ----------
    case : Case
        A gear case: planetary stage, gear pair, gearbox or drivetrain.
    speed_rpm : float
        Input member speed [rpm], > 0.
    torque : float, optional
        Drive torque on the input member [N m], > 0; default the scene's drive torque.
        K_v of the linear model does not depend on it (only a pin error's share does).
    scene : Scene, optional
        Scene whose parameters and model choices apply.
    harmonics : int or "auto"
        Harmonic count, or chosen by ``tolerance``.
    tolerance : float
        Residual the automatic count reaches.
    keys : {"mesh", "rating"}
        ``mesh``: by response mesh (``stage1.sun-planet1``, or ``sun-planet1`` in a
        single-stage case); ``rating``: by the rating's mesh (``stage1.sun_mesh``,
        ``stage1.ring_mesh``, ``parallel.mesh``), the largest K_v over the stage's planets.

    Returns
    -------
    dict of str to float

    Raises
    ------
    CaseError
        A speed or torque out of range, an unknown ``keys``, a case without meshes.
    """
    if keys not in ("mesh", "rating"):
        raise CaseError(f"keys must be 'mesh' or 'rating' (got {keys!r})")
    if not (isinstance(speed_rpm, int | float) and math.isfinite(speed_rpm) and speed_rpm > 0):
        raise CaseError(f"speed_rpm must be a finite number > 0 (got {speed_rpm!r})")
    if torque is not None and not (math.isfinite(torque) and torque > 0):
        raise CaseError(f"torque must be a finite number > 0 [N m] (got {torque!r})")
    dataset = forced_response(
        case,
        [float(speed_rpm)],
        scene=scene,
        harmonics=harmonics,
        tolerance=tolerance,
        stability=False,
        torque=torque,
    )
    values = dataset.dynamic_factor.values[0]
    meshes = [str(m) for m in dataset.mesh.values]
    if keys == "mesh":
        return {m: float(v) for m, v in zip(meshes, values)}
    stages = [str(s) for s in dataset.attrs["mesh_stages"].split(",")]
    out: dict[str, float] = {}
    for stage, mesh, value in zip(stages, meshes, values):
        name = rating_mesh_name(stage, mesh)
        out[name] = max(out.get(name, -math.inf), float(value))
    return out
