"""Mesh stiffness along the ideal kinematics of a constant carrier speed.

:func:`mesh_stiffness_at_constant_speed` runs the tooth-contact table of
:mod:`pygear.assembly.contact_table` along the rigid-body kinematics of a constant
carrier speed with the ring held, and returns every mesh's stiffness, loaded pairs
and contact positions as a Dataset; :func:`mesh_summary` lists each mesh's law, gear
geometry and stiffness from it.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import xarray as xr

from ...assembly.contact_table import build_contact_table
from ...assembly.matrices import assemble
from ...assembly.mesh_laws import mesh_law
from ...errors import CaseError
from ...model import gear_geometry as geo
from ...model.case import Case, Scene
from ...model.gearbox import ParallelStage
from ...model.geometry_inputs import parallel_mesh_geometry, planetary_mesh_geometry
from ...resources import FLOAT_BYTES, require_memory

__all__ = [
    "DEFAULT_CYCLES",
    "ContactLossWarning",
    "mesh_stiffness_at_constant_speed",
    "mesh_summary",
]

DEFAULT_CYCLES = 5
"""Mesh cycles the constant-speed run covers by default (without defects)."""


class ContactLossWarning(UserWarning):
    """A mesh has stretches where no tooth pair carries load (missing teeth)."""


def _relative_speeds(stage, carrier_speed: float) -> dict[str, float]:
    """d theta_rel / dt of sun and ring meshes at carrier speed [rad/s], ring held,
    from base radii (docs/model.md §2): theta_s - theta_c = (r_br / r_bs) omega_c t,
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


def _gear_pair(case: Case, gear_1: str) -> tuple:
    """Stage, law member, the two gears (the table's order: sun or ring and planet, or
    input and output gear) and the mesh geometry of the mesh whose gear 1 is ``gear_1``."""
    stage_name, first = gear_1.split(".", 1)
    stage = case.gearbox.stage(stage_name)
    if isinstance(stage, ParallelStage):
        gears = (stage.input_gear, stage.output_gear)
        return stage, "mesh", gears, parallel_mesh_geometry(stage)
    gears = (getattr(stage, first), stage.planet)
    return stage, first, gears, planetary_mesh_geometry(stage, first)


def mesh_summary(case: Case, dataset: xr.Dataset) -> dict[str, dict]:
    """Each mesh's law, gear geometry and stiffness, in SI units.

    Parameters
    ----------
    case : Case
        The case the dataset was computed from (with any ``--law`` applied).
    dataset : xarray.Dataset
        Its :func:`mesh_stiffness_at_constant_speed`.

    Returns
    -------
    dict
        By mesh name (as in the dataset): ``law``; ``gears`` and ``teeth`` (gear 1 and
        gear 2: sun or ring and planet, or input and output gear); ``normal_module``
        and ``face_width`` (the common one) [m], ``profile_shift`` (pair),
        ``helix_angle_deg`` (gear 1's, signed), ``normal_pressure_angle_deg`` and
        ``centre_distance`` [m], all None without gear geometry on both gears;
        ``pressure_angle_deg`` (working, transverse), ``transverse_contact_ratio``,
        ``overlap_ratio``; ``mean_stiffness`` (the law's k-bar) and the largest and
        smallest stiffness of the run, ``max_stiffness`` and ``min_stiffness`` [N/m];
        ``backlash``, circumferential on the working pitch circle [m] (None: not given).
    """
    summary = {}
    for index, name in enumerate(dataset.mesh.values):
        gear_1, gear_2 = str(dataset.gear_1.values[index]), str(dataset.gear_2.values[index])
        stage, member, gears, geometry = _gear_pair(case, gear_1)
        law = mesh_law(stage, member)
        mesh = stage.mesh if member == "mesh" else getattr(stage, f"{member}_mesh")
        series = dataset.mesh_stiffness.values[:, index]
        entry = {
            "law": law.law,
            "gears": [gear_1, gear_2],
            "teeth": [gear.teeth for gear in gears],
            "normal_module": None,
            "face_width": None,
            "profile_shift": None,
            "helix_angle_deg": None,
            "normal_pressure_angle_deg": None,
            "centre_distance": None,
            "pressure_angle_deg": float(mesh.pressure_angle_deg),
            "transverse_contact_ratio": law.transverse_contact_ratio,
            "overlap_ratio": law.overlap_ratio,
            "mean_stiffness": law.mean_stiffness,
            "max_stiffness": float(np.max(series)),
            "min_stiffness": float(np.min(series)),
            "backlash": None if mesh.backlash is None else float(mesh.backlash),
        }
        if geometry is not None:
            first, second = (gear.geometry for gear in gears)
            entry.update(
                normal_module=float(first.normal_module),
                face_width=float(min(first.face_width, second.face_width)),
                profile_shift=[float(first.profile_shift), float(second.profile_shift)],
                helix_angle_deg=float(first.helix_angle_deg),
                normal_pressure_angle_deg=float(first.normal_pressure_angle_deg),
                centre_distance=geo.centre_distance(geometry),
            )
        summary[str(name)] = entry
    return summary
