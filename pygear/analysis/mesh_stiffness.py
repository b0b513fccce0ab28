"""Mesh stiffness along the ideal kinematics of a constant carrier speed.

:func:`mesh_stiffness_at_constant_speed` runs the tooth-contact table of
:mod:`pygear.assembly.contact_table` along the rigid-body kinematics of a constant
carrier speed with the ring held, and returns every mesh's stiffness, loaded pairs
and contact positions as a Dataset.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import xarray as xr

from ..assembly.contact_table import build_contact_table
from ..assembly.matrices import assemble
from ..errors import CaseError
from ..model.case import Case, Scene
from ..model.gearbox import ParallelStage
from ..resources import FLOAT_BYTES, require_memory

__all__ = ["DEFAULT_CYCLES", "ContactLossWarning", "mesh_stiffness_at_constant_speed"]

DEFAULT_CYCLES = 5
"""Mesh cycles the constant-speed run covers by default (without defects)."""


class ContactLossWarning(UserWarning):
    """A mesh has stretches where no tooth pair carries load (missing teeth)."""


def _relative_speeds(stage, carrier_speed: float) -> dict[str, float]:
    """d theta_rel / dt of sun and ring meshes at carrier speed [rad/s], ring held,
    from base radii (PHYSICS.md 2): theta_s - theta_c = (r_br / r_bs) omega_c t,
    theta_c - theta_r = omega_c t.  A parallel pair's input gear turns at the speed
    given, in the sense of the suns relative to their carriers."""
    if isinstance(stage, ParallelStage):
        return {"input": abs(carrier_speed)}
    return {
        "sun": stage.ring.base_radius / stage.sun.base_radius * carrier_speed,
        "ring": carrier_speed,
    }


def mesh_stiffness_at_constant_speed(
    case: Case,
    *,
    carrier_speed_rpm: float = 120.0,
    duration: float | None = None,
    samples_per_cycle: int = 200,
    scene: Scene | None = None,
    formulation: str | None = None,
    sun_driven: bool = True,
) -> xr.Dataset:
    """Mesh stiffness of every mesh along the ideal kinematics of a constant carrier speed.

    Each stage's carrier turns at ``carrier_speed_rpm`` with its ring held, so
    theta_rel = (r_br/r_bs) omega_c t for the sun meshes and omega_c t for the ring
    meshes (mesh frequency Z_r omega_c / 2 pi); a parallel pair's input gear turns
    at ``carrier_speed_rpm`` too.  A negative speed runs the mirror
    image (sigma = -1).

    Parameters
    ----------
    case : Case
        The case.
    carrier_speed_rpm : float
        Carrier speed [rpm], non-zero.
    duration : float, optional
        Length of the run [s].  Default: 5 cycles of the slowest mesh; with defects,
        two revolutions of the largest defective gear relative to the carrier plus
        the contact ratio.
    samples_per_cycle : int
        Samples per cycle of the fastest mesh.
    scene : Scene, optional
        Scene whose defects (and formulation) apply.
    formulation : str, optional
        Formulation of the model whose meshes are listed (the kinematics are the same).
    sun_driven : bool
        Power flow, see :func:`build_contact_table`.

    Returns
    -------
    xarray.Dataset
        ``mesh_stiffness(time, mesh)`` [N/m], ``pairs_in_contact(time, mesh)`` (pairs
        carrying load), ``mesh_cycle(time, mesh)``, ``contact_position``, ``tooth_1``
        and ``tooth_2`` over ``(time, mesh, pair)``; per-mesh coordinates ``gear_1``,
        ``gear_2``, ``mean_stiffness``, ``contact_ratio``, ``phase``, ``mesh_frequency``.
    """
    if not (math.isfinite(carrier_speed_rpm) and carrier_speed_rpm != 0):
        raise CaseError(
            f"--speed must be a finite non-zero carrier speed (got {carrier_speed_rpm!r})"
        )
    if not isinstance(samples_per_cycle, int) or samples_per_cycle < 4:
        raise CaseError(
            f"samples_per_cycle must be a whole number >= 4 (got {samples_per_cycle!r})"
        )
    model = assemble(case, scene, formulation=formulation)
    direction = 1 if carrier_speed_rpm > 0 else -1
    table = build_contact_table(case, model, scene, direction=direction, sun_driven=sun_driven)
    omega_c = carrier_speed_rpm * math.pi / 30
    parallel = {s.name for s in case.gearbox.stages if isinstance(s, ParallelStage)}
    speeds = np.array(
        [
            _relative_speeds(case.gearbox.stage(m.stage), omega_c)[m.name.split("-", 1)[0]]
            * (table.cycle_sign[i] if m.stage in parallel else 1)
            for i, m in enumerate(model.meshes)
        ]
    )
    frequency = table.teeth[0] * np.abs(speeds) / (2 * np.pi)
    if duration is None:
        cycles = DEFAULT_CYCLES
        if table.defects:
            largest = max(case.gearbox.stage(d.stage).gear_teeth(d.member) for d in table.defects)
            cycles = max(cycles, 2 * largest + math.ceil(table.contact_ratio.max()))
        duration = cycles / frequency.min()
    if not (math.isfinite(duration) and duration > 0):
        raise CaseError(f"--duration must be a positive number of seconds (got {duration!r})")
    step = 1.0 / (frequency.max() * samples_per_cycle)
    samples = int(math.floor(duration / step + 1e-9)) + 1
    per_sample = 1 + len(speeds) * (4 + 3 * table.max_pairs)  # time, theta + 3 per mesh, 3 per pair
    require_memory(
        "--duration",
        samples * per_sample * FLOAT_BYTES,
        f"{samples} samples x {per_sample} values x {FLOAT_BYTES} bytes",
        "shorten --duration",
    )
    time = np.arange(samples) * step
    theta = np.outer(time, speeds)
    result = table.series(theta)
    pairs = np.arange(table.max_pairs)
    position = np.where(result["position"] < 0, np.nan, result["position"])
    dataset = xr.Dataset(
        data_vars={
            "mesh_stiffness": (
                ("time", "mesh"),
                result["stiffness"],
                {"units": "N/m", "long_name": "time-varying mesh stiffness k_m"},
            ),
            "pairs_in_contact": (
                ("time", "mesh"),
                result["loaded_pairs"],
                {"units": "1", "long_name": "tooth pairs in contact carrying load"},
            ),
            "mesh_cycle": (
                ("time", "mesh"),
                table.mesh_cycle(theta),
                {"units": "1", "long_name": "mesh cycle s = sigma Z1 theta_rel / 2 pi + gamma"},
            ),
            "contact_position": (
                ("time", "mesh", "pair"),
                position,
                {
                    "units": "1",
                    "long_name": "relative contact position p_k "
                    "from the start of contact (mesh cycles)",
                },
            ),
            "tooth_1": (
                ("time", "mesh", "pair"),
                result["tooth_1"],
                {
                    "units": "1",
                    "long_name": "0-based tooth of gear 1 (sun or ring) in pair k, -1 none",
                },
            ),
            "tooth_2": (
                ("time", "mesh", "pair"),
                result["tooth_2"],
                {"units": "1", "long_name": "0-based tooth of gear 2 (planet) in pair k, -1 none"},
            ),
        },
        coords={
            "time": ("time", time, {"units": "s", "long_name": "time"}),
            "mesh": ("mesh", list(table.names), {"long_name": "mesh"}),
            "pair": ("pair", pairs, {"units": "1", "long_name": "tooth pair k, 0 the newest"}),
            "gear_1": ("mesh", [g[0] for g in table.gears], {"long_name": "gear 1 (sun or ring)"}),
            "gear_2": ("mesh", [g[1] for g in table.gears], {"long_name": "gear 2 (planet)"}),
            "mean_stiffness": (
                "mesh",
                table.mean_stiffness,
                {"units": "N/m", "long_name": "mean mesh stiffness k-bar"},
            ),
            "contact_ratio": (
                "mesh",
                table.contact_ratio,
                {"units": "1", "long_name": "transverse contact ratio"},
            ),
            "phase": ("mesh", table.phase, {"units": "1", "long_name": "mesh phase gamma"}),
            "mesh_frequency": ("mesh", frequency, {"units": "Hz", "long_name": "mesh frequency"}),
        },
        attrs={
            "case": case.name,
            "carrier_speed_rpm": float(carrier_speed_rpm),
            "formulation": model.formulation,
            "power_flow": "carrier to sun" if sun_driven else "sun to carrier",
            "defects": "; ".join(
                f"{d.gear} tooth {d.tooth} factor {d.factor:g}" for d in table.defects
            )
            or "none",
            "tooth_numbering": (
                "0-based, in the order teeth come into mesh (pygear.assembly.mesh_phasing)"
            ),
        },
    )
    _warn_contact_loss(dataset)
    return dataset


def _warn_contact_loss(dataset: xr.Dataset) -> None:
    lost = (dataset.pairs_in_contact == 0).mean("time")
    for name, share in zip(dataset.mesh.values, lost.values, strict=True):
        if share > 0:
            warnings.warn(
                f"mesh {name}: no tooth pair carries load during {100 * share:.3g} % "
                f"of the run (missing teeth); its stiffness is zero there",
                ContactLossWarning,
                stacklevel=3,
            )
