"""Tooth-contact table: time-varying mesh stiffness with phasing and tooth defects.

:func:`build_contact_table` turns a case (meshes, phasing, single-pair laws,
defects) into the flat arrays of the Fortran module ``contact_table``, which
checks them once, keeps them under a handle and evaluates every mesh at a state
(docs/model.md §5.1).  The constant-speed evaluation is
:func:`pygear.analysis.contact.mesh_stiffness.mesh_stiffness_at_constant_speed`.

Each mesh's gear 1 is the central member (sun or ring) and gear 2 the planet;
tooth numbering and phases are derived in :mod:`pygear.assembly.mesh_phasing`.
"""

from __future__ import annotations

import dataclasses
import math
import weakref
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import CaseError
from ..kernel import _kernel
from ..kernel.calls import KernelError
from ..model.case import Case, merged_defects, validate_defects
from ..model.components import PlanetaryStage, ToothDefect
from ..model.gearbox import ParallelStage
from ..model.scene_settings import SceneSettings, scene_settings
from .dof_rows import dof_row, rigid_rotation
from .matrices import Model
from .mesh_laws import LAW_CODES, mesh_law
from .mesh_phasing import stage_phasing
from .tooth_fault_curves import deviation_curves, fault_curves

if TYPE_CHECKING:  # a Scene is only resolved here (model.scene_settings), never read
    from ..model.case import Scene

# LAW_CODES: from .mesh_laws
__all__ = ["LAW_CODES", "ContactTable", "build_contact_table", "with_tooth_curves"]

_ERRORS = {
    1: "a table entry is out of range",
    2: "an unknown single-pair law code",
    3: "an array is too small for the contact ratio or the packed data",
    4: "a state is not finite or lies beyond 2**50 mesh cycles",
    5: "the table's kernel handle is not live",
    6: "the kernel holds too many tables (65535)",
}


@dataclass(frozen=True, eq=False)
class ContactTable:
    """Flat arrays of the tooth-contact table, one entry (or column) per mesh.

    Attributes
    ----------
    names : tuple of str
        Mesh names (``sun-planet1``; ``<stage>.sun-planet1`` with several stages).
    gears : tuple of (str, str)
        Gear 1 (sun or ring) and gear 2 (planet) of each mesh, as ``stage.member``.
    angles : tuple of (str, str)
        Members (a, b) with theta_rel = theta_z(a) - theta_z(b): (sun, carrier) for a
        sun-planet mesh, (carrier, ring) for a ring-planet mesh.
    teeth, tooth_offset, factor_start : ndarray of int32, shape (2, n_mesh)
        Z1 and Z2; i0 and j0; offsets of each gear's factors in ``factor`` (-1: healthy).
    cycle_sign, law, curve_start, curve_size : ndarray of int32, shape (n_mesh,)
        sigma; single-pair law code; tabulated curve offset and length.
    mean_stiffness, contact_ratio, end_to_peak, phase : ndarray of float64
        k-bar [N/m], eps, lambda, gamma [mesh cycles].
    curve, factor : ndarray of float64
        Packed unit-mean curves and per-tooth factors (each padded to length >= 1).
    max_pairs : int
        Pairs per mesh the output arrays hold: ceil(max eps) + 1.
    defects : tuple of ToothDefect
        The defects the factors come from.
    tooth_curve_block : ndarray of int32, shape (2, n_mesh), optional
        Offsets of each gear's per-tooth entries in ``tooth_curve_start`` and
        ``tooth_curve_size`` for each mesh (-1: every tooth follows the law); None: no
        tooth has a curve of its own (:func:`with_tooth_curves` fills them).
    tooth_curve_start, tooth_curve_size : ndarray of int32, optional
        Per tooth: offset of its own pair curve in ``curve`` and its samples (0: the
        tooth follows the mesh's law).  The curve is on the tabulated law's scale,
        k_pair = (k-bar / eps) c(p) at p = eps q / (n - 1) (``MeshStiffness.faulty_curve``).
    excitation_start, excitation_size : ndarray of int32, shape (n_mesh,), optional
        Offset and samples of each mesh's displacement excitation in ``excitation``
        (size 0: none); None: no mesh has one.
    excitation : ndarray of float64, optional
        Packed excitations e(s) [m] along the drive flank's compression, each one period
        over a mesh cycle at s = q / (n - 1) (first sample = last); the mesh force is
        k_m (c - e(s)) (the ``loaded_contact`` law's unloaded transmission error).
    """

    names: tuple[str, ...]
    gears: tuple[tuple[str, str], ...]
    angles: tuple[tuple[str, str], ...]
    teeth: np.ndarray
    cycle_sign: np.ndarray
    tooth_offset: np.ndarray
    mean_stiffness: np.ndarray
    contact_ratio: np.ndarray
    end_to_peak: np.ndarray
    phase: np.ndarray
    law: np.ndarray
    curve_start: np.ndarray
    curve_size: np.ndarray
    curve: np.ndarray
    factor_start: np.ndarray
    factor: np.ndarray
    max_pairs: int
    defects: tuple[ToothDefect, ...] = ()
    tooth_curve_block: np.ndarray | None = None
    tooth_curve_start: np.ndarray | None = None
    tooth_curve_size: np.ndarray | None = None
    excitation_start: np.ndarray | None = None
    excitation_size: np.ndarray | None = None
    excitation: np.ndarray | None = None

    @property
    def size(self) -> int:
        """Number of meshes."""
        return len(self.names)

    def kernel_arguments(self) -> tuple:
        """The table's arrays in the order ``contact_table_create`` takes them; without
        damaged teeth' own curves, a block of -1 (none) and one-element offsets."""
        if self.tooth_curve_block is not None:
            teeth_curves = (self.tooth_curve_block, self.tooth_curve_start, self.tooth_curve_size)
        else:
            none = np.full((2, self.size), -1, dtype=np.int32, order="F")
            teeth_curves = (none, np.zeros(1, np.int32), np.zeros(1, np.int32))
        if self.excitation is not None:
            excitation = (self.excitation_start, self.excitation_size, self.excitation)
        else:
            zero = np.zeros(self.size, dtype=np.int32)
            excitation = (zero, zero, np.zeros(1))
        return (
            self.teeth,
            self.cycle_sign,
            self.tooth_offset,
            self.mean_stiffness,
            self.contact_ratio,
            self.end_to_peak,
            self.phase,
            self.law,
            self.curve_start,
            self.curve_size,
            self.curve,
            self.factor_start,
            self.factor,
            *teeth_curves,
            *excitation,
            self.max_pairs,
        )

    @property
    def handle(self) -> int:
        """The kernel's handle of this table, created (and the table checked) on first use.

        The kernel keeps a copy of the arrays until this object is garbage collected.
        Copies and pickles of the table leave the handle behind and get their own.

        Raises
        ------
        KernelError
            The kernel's check failed; the message names the mesh at fault.
        """
        handle = self.__dict__.get("_handle")
        if handle is None:
            routine = "contact_table_create"
            handle, bad, ierr = _kernel.contact_table_create(*self.kernel_arguments())
            if ierr:
                where = f" (mesh {self.names[bad - 1]})" if bad > 0 else ""
                raise KernelError(
                    f"kernel routine {routine}: "
                    f"{_ERRORS.get(int(ierr), f'error code {ierr}')}{where}"
                )
            handle = int(handle)
            object.__setattr__(self, "_handle", handle)
            weakref.finalize(self, _kernel.contact_table_free, handle).atexit = False
        return handle

    def __getstate__(self) -> dict:
        """The fields without the kernel handle, which is valid only in this process."""
        state = dict(self.__dict__)
        state.pop("_handle", None)
        return state

    def mesh_cycle(self, theta: np.ndarray) -> np.ndarray:
        """s = sigma Z1 theta / 2 pi + gamma for relative angles ``theta`` (..., n_mesh)."""
        return self.cycle_sign * self.teeth[0] * np.asarray(theta) / (2 * np.pi) + self.phase

    def evaluate(self, theta: np.ndarray) -> dict[str, np.ndarray]:
        """Evaluate every mesh at one state.

        Parameters
        ----------
        theta : array_like, shape (n_mesh,)
            Rotation of each mesh's gear 1 relative to the carrier [rad].

        Returns
        -------
        dict
            ``stiffness`` (n_mesh) [N/m], ``pairs`` and ``loaded_pairs`` (n_mesh),
            ``position`` (n_mesh, max_pairs) [mesh cycles, -1 unused] and
            ``tooth_1``, ``tooth_2`` (n_mesh, max_pairs) [0-based, -1 unused].
        """
        theta = np.ascontiguousarray(theta, dtype=np.float64)
        stiffness, pairs, loaded, position, tooth, ierr = _kernel.contact_table_evaluate(
            handle=self.handle, max_pairs=self.max_pairs, theta=theta
        )
        self._raise(ierr, "contact_table_evaluate")
        return {
            "stiffness": stiffness,
            "pairs": pairs,
            "loaded_pairs": loaded,
            "position": position.T,
            "tooth_1": tooth[0].T,
            "tooth_2": tooth[1].T,
        }

    def series(self, theta: np.ndarray) -> dict[str, np.ndarray]:
        """Evaluate every mesh at many states in one kernel call.

        Parameters
        ----------
        theta : array_like, shape (n_state, n_mesh)
            Relative rotations of gear 1 [rad], one row per state.

        Returns
        -------
        dict
            As :meth:`evaluate`, with a leading state axis.
        """
        theta = np.asarray(theta, dtype=np.float64)
        stiffness, pairs, loaded, position, tooth, bad, ierr = _kernel.contact_table_series(
            handle=self.handle, max_pairs=self.max_pairs, theta=np.asfortranarray(theta.T)
        )
        self._raise(ierr, "contact_table_series", state=int(bad))
        return {
            "stiffness": stiffness.T,
            "pairs": pairs.T,
            "loaded_pairs": loaded.T,
            "position": position.transpose(2, 1, 0),
            "tooth_1": tooth[0].transpose(2, 1, 0),
            "tooth_2": tooth[1].transpose(2, 1, 0),
        }

    def excitation_at(self, theta: np.ndarray) -> np.ndarray:
        """The displacement excitation e_m [m] of every mesh (0 without one) along the
        drive flank's compression, at states ``theta`` (..., n_mesh) [rad]."""
        theta = np.asarray(theta, dtype=np.float64)
        if self.excitation is None:
            return np.zeros(theta.shape)
        flat = np.asfortranarray(theta.reshape(-1, self.size).T)
        values, ierr = _kernel.contact_table_excitation(handle=self.handle, theta=flat)
        self._raise(ierr, "contact_table_excitation")
        return values.T.reshape(theta.shape)

    def check(self) -> None:
        """Hand the table to the kernel, which checks it; raise :class:`KernelError` naming
        the mesh at fault."""
        self.handle  # noqa: B018 (created and checked on first access)

    def _raise(self, ierr: int, routine: str, state: int = 0) -> None:
        if ierr:
            where = f" at state {state - 1}" if state > 0 else ""
            raise KernelError(
                f"kernel routine {routine}: {_ERRORS.get(int(ierr), f'error code {ierr}')}{where}"
            )


def build_contact_table(
    case: Case,
    model: Model,
    scene: Scene | SceneSettings | None = None,
    *,
    direction: int = 1,
    sun_driven: bool = True,
    excitation: bool = True,
) -> ContactTable:
    """The tooth-contact table of an assembled model's meshes.

    Parameters
    ----------
    case : Case
        The case (stages, meshes, tooth numbers, phase overrides, defects).
    model : Model
        The assembled model; its ``meshes`` fix the order of the table.
    scene : Scene or SceneSettings, optional
        Scene whose defects apply on top of the case's (a ``Scene`` is resolved into
        its settings first, and only those are read).
    direction : int
        sigma = +1 when each sun turns in +z relative to its carrier, -1 otherwise.
    sun_driven : bool
        True when the carrier drives and the sun is the output (the seed's case);
        it decides where contact starts and so the ring-to-sun phase, and the
        direction in which a curve computed from gear geometry is read.
    excitation : bool
        False: ``loaded_contact`` meshes run their TE-equivalent stiffness without the
        displacement excitation (the first-order form, for a balance that takes no
        excitation force).

    Each mesh's law, mean stiffness, contact ratio and curve are those of
    :func:`pygear.assembly.mesh_laws.mesh_law` (resolved once per case).

    Returns
    -------
    ContactTable
        Checked by the kernel.

    Raises
    ------
    CaseError
        A tooth number is missing, or a scene defect does not fit the gearbox.
    """
    scene = scene_settings(scene)
    if scene is not None:
        validate_defects(case.gearbox, scene.defects, f"scene {scene.name!r} defects")
    defects = merged_defects(case, scene)
    several = len(case.gearbox.stages) > 1
    phasing: dict[str, dict] = {}
    rows = []
    laws = []
    parallel_sense = _parallel_senses(case, model)
    for mesh in model.meshes:
        stage = case.gearbox.stage(mesh.stage)
        prefix = f"{stage.name}." if several else ""
        if isinstance(stage, ParallelStage):
            row = _parallel_row(stage, mesh, direction * parallel_sense[stage.name])
            law = mesh_law(stage, "mesh")
        else:
            if stage.name not in phasing:
                phasing[stage.name] = stage_phasing(
                    stage, direction=direction, sun_driven=sun_driven
                )
            row = _planetary_row(stage, mesh, phasing[stage.name][mesh.name], direction)
            law = mesh_law(stage, row["central"])
        row["name"] = prefix + mesh.name
        row["member"] = "mesh" if isinstance(stage, ParallelStage) else row["central"]
        row.update(
            mean=law.mean_stiffness,
            ratio=law.contact_ratio,
            lam=law.end_to_peak,
            law=law.code,
            start=0,
            size=0,
        )
        rows.append(row)
        laws.append(law)
    meshes = [(m.stage, r["member"], r["gears"]) for m, r in zip(model.meshes, rows)]
    # teeth' own curves: per-tooth deviations on loaded-contact meshes, damaged teeth
    # (a damaged tooth's fault curve replaces its deviation curve)
    tooth_curves = deviation_curves(case, meshes, sun_driven)
    first_order = {key[0] for key in tooth_curves} if excitation else set(range(len(rows)))
    curves, excitations = _pack_curves(rows, laws, sun_driven, first_order)
    factor_start, factor = _pack_factors(case, rows, defects)
    ratios = np.array([r["ratio"] for r in rows], dtype=np.float64)
    table = ContactTable(
        names=tuple(r["name"] for r in rows),
        gears=tuple(r["gears"] for r in rows),
        angles=tuple(r["angles"] for r in rows),
        teeth=np.asfortranarray(np.array([r["teeth"] for r in rows], dtype=np.int32).T),
        cycle_sign=np.array([r["sign"] for r in rows], dtype=np.int32),
        tooth_offset=np.asfortranarray(np.array([r["offset"] for r in rows], dtype=np.int32).T),
        mean_stiffness=np.array([r["mean"] for r in rows], dtype=np.float64),
        contact_ratio=ratios,
        end_to_peak=np.array([r["lam"] for r in rows], dtype=np.float64),
        phase=np.array([r["phase"] for r in rows], dtype=np.float64),
        law=np.array([r["law"] for r in rows], dtype=np.int32),
        curve_start=np.array([r["start"] for r in rows], dtype=np.int32),
        curve_size=np.array([r["size"] for r in rows], dtype=np.int32),
        curve=curves,
        factor_start=factor_start,
        factor=factor,
        max_pairs=int(math.ceil(ratios.max())) + 1 if len(rows) else 1,
        defects=defects,
        **excitations,
    )
    table.check()
    if any(defect.fault is not None for defect in defects):
        tooth_curves.update(fault_curves(case, meshes, defects, sun_driven))
    if tooth_curves:
        table = with_tooth_curves(table, tooth_curves)
    return table


def _pack_curves(
    rows: list[dict], laws: list, sun_driven: bool, deviated: set[int]
) -> tuple[np.ndarray, dict]:
    """The packed pair curves (each row's start and size set) and the packed
    displacement excitations as ContactTable fields (empty without any).  A
    ``loaded_contact`` mesh with per-tooth deviations (index in ``deviated``) runs its
    TE-equivalent curve and no excitation (module loaded_contact_table)."""
    curves: list[np.ndarray] = []
    offset = 0
    excitations: list[np.ndarray] = []
    start = np.zeros(len(rows), dtype=np.int32)
    size = np.zeros(len(rows), dtype=np.int32)
    excited_offset = 0
    for index, (row, law) in enumerate(zip(rows, laws)):
        curve = law.oriented_curve(sun_driven)
        excitation = law.oriented_excitation(sun_driven)
        if index in deviated and law.equivalent_curve is not None:
            curve = law.equivalent_curve
            if law.mirrored and not sun_driven:
                curve = np.ascontiguousarray(curve[::-1])
            excitation = None
        if curve is not None:
            row.update(start=offset, size=len(curve))
            curves.append(curve)
            offset += len(curve)
        if excitation is not None:
            start[index], size[index] = excited_offset, excitation.size
            excitations.append(excitation)
            excited_offset += excitation.size
    packed = np.concatenate(curves + [np.zeros(1)])
    if not excitations:
        return packed, {}
    return packed, dict(
        excitation_start=start, excitation_size=size, excitation=np.concatenate(excitations)
    )


def with_tooth_curves(
    table: ContactTable, curves: dict[tuple[int, int, int], np.ndarray]
) -> ContactTable:
    """A copy of ``table`` in which damaged teeth follow their own pair curves.

    Parameters
    ----------
    table : ContactTable
        The table (its own tooth curves, if any, are replaced).
    curves : dict of (mesh, gear, tooth) to ndarray
        For mesh index ``mesh`` (0-based, the table's order), gear 1 or 2 of that mesh
        and its 0-based tooth: the pair curve while that tooth is in mesh, on the scale
        of the tabulated law (``MeshStiffness.faulty_curve()``), sampled at
        p = eps q / (n - 1) over the mesh's contact ratio eps.  A planet tooth meets the
        sun and the ring: give a curve for each mesh it is in.

    Returns
    -------
    ContactTable
        Checked by the kernel.
    """
    packed = [np.asarray(table.curve, dtype=np.float64)]
    offset = packed[0].size
    blocks = np.full((2, table.size), -1, dtype=np.int32)
    starts: list[int] = []
    sizes: list[int] = []
    for (mesh, gear, tooth), curve in sorted(curves.items()):
        if not (0 <= mesh < table.size and gear in (1, 2)):
            raise ValueError(f"tooth curve key {(mesh, gear, tooth)}: no such mesh and gear")
        teeth = int(table.teeth[gear - 1, mesh])
        if not 0 <= tooth < teeth:
            raise ValueError(
                f"tooth curve key {(mesh, gear, tooth)}: tooth not in 0 .. {teeth - 1}"
            )
        if blocks[gear - 1, mesh] < 0:
            blocks[gear - 1, mesh] = len(starts)
            starts += [0] * teeth
            sizes += [0] * teeth
        samples = np.asarray(curve, dtype=np.float64).reshape(-1)
        slot = blocks[gear - 1, mesh] + tooth
        starts[slot], sizes[slot] = offset, samples.size
        packed.append(samples)
        offset += samples.size
    changed = dataclasses.replace(
        table,
        curve=np.concatenate(packed),
        tooth_curve_block=np.asfortranarray(blocks),
        tooth_curve_start=np.array(starts or [0], dtype=np.int32),
        tooth_curve_size=np.array(sizes or [0], dtype=np.int32),
    )
    changed.check()
    return changed


def _planetary_row(stage: PlanetaryStage, mesh, phase, direction: int) -> dict:
    """Table entry of a sun or ring mesh: gear 1 the central member, gear 2 the planet,
    angle of gear 1 relative to the carrier (docs/model.md §5.1)."""
    central = mesh.name.split("-", 1)[0]
    return dict(
        central=central,
        gears=(f"{stage.name}.{central}", f"{stage.name}.planet{mesh.planet}"),
        angles=(
            (f"{stage.name}.sun", f"{stage.name}.carrier")
            if central == "sun"
            else (f"{stage.name}.carrier", f"{stage.name}.ring")
        ),
        teeth=(getattr(stage, central).teeth, stage.planet.teeth),
        offset=(phase.gear_1_offset, phase.gear_2_offset),
        phase=phase.phase,
        sign=direction,
    )


def _parallel_row(stage: ParallelStage, mesh, sign: int) -> dict:
    """Table entry of a parallel pair: gear 1 the input gear, its absolute rotation as
    the angle, first teeth in mesh at s = 0."""
    for member in stage.member_names:
        teeth = getattr(stage, member).teeth
        if not (isinstance(teeth, int) and teeth > 0):
            raise CaseError(
                f"{stage.name}.{member}.teeth must be a whole number > 0 for the "
                f"time-varying mesh stiffness (got {teeth!r})"
            )
    return dict(
        gears=(f"{stage.name}.input_gear", f"{stage.name}.output_gear"),
        angles=(f"{stage.name}.input_gear",),
        teeth=(stage.input_gear.teeth, stage.output_gear.teeth),
        offset=(0, 0),
        phase=0.0,
        sign=sign,
    )


def _parallel_senses(case: Case, model: Model) -> dict[str, int]:
    """+1 when a parallel stage's input gear turns with the first planetary stage's
    sun relative to its carrier in the gearbox's rigid-body rotation, else -1."""
    stages = [s for s in case.gearbox.stages if isinstance(s, ParallelStage)]
    if not stages:
        return {}
    rigid = rigid_rotation(model)
    reference = None
    for stage in case.gearbox.stages:
        if isinstance(stage, PlanetaryStage) and rigid is not None:
            sun = dof_row(model, f"{stage.name}.sun.theta_z")
            carrier = dof_row(model, f"{stage.name}.carrier.theta_z")
            reference = float((sun - carrier) @ rigid)
            break
    senses = {}
    for stage in stages:
        speed = dof_row(model, f"{stage.name}.input_gear.theta_z")
        own = float(speed @ rigid) if rigid is not None and speed is not None else 1.0
        senses[stage.name] = 1 if own * (reference if reference else 1.0) >= 0 else -1
    return senses


def _pack_factors(
    case: Case, rows: list[dict], defects: tuple[ToothDefect, ...]
) -> tuple[np.ndarray, np.ndarray]:
    """One block of per-tooth factors per defective gear, shared by all its meshes."""
    blocks: dict[str, np.ndarray] = {}
    for defect in defects:
        stage = case.gearbox.stage(defect.stage)
        teeth = stage.gear_teeth(defect.member)
        block = blocks.setdefault(defect.gear, np.ones(teeth))
        block[defect.tooth] = defect.factor
    offsets, packed, position = {}, [], 0
    for gear, block in blocks.items():
        offsets[gear] = position
        packed.append(block)
        position += len(block)
    start = np.array([[offsets.get(g, -1) for g in r["gears"]] for r in rows], dtype=np.int32)
    return np.asfortranarray(start.T.reshape(2, len(rows))), np.concatenate(packed + [np.ones(1)])
