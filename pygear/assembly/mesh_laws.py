"""Each mesh's single-pair stiffness law, resolved once per case.

A :class:`~pygear.model.components.Mesh` names its law (``Mesh.law``, or the default of
:func:`pygear.model.geometry_inputs.effective_law`); :func:`mesh_law` turns it into what
the element matrices and the tooth-contact table take: the mean mesh stiffness k-bar,
the contact-table law code, the contact ratio the single-pair law spans, its shape
parameter and, for a tabulated law, the unit-mean curve.

- ``parabola``: k-bar typed, the mean-preserving parabola over eps_alpha (docs/model.md §5.2).
- ``helical``: k-bar typed, the contact-line law over eps_alpha + eps_beta.
- ``tabulated``: k-bar typed, the case's ``stiffness_curve`` scaled to unit mean, over
  eps_alpha (+ eps_beta on a helical stage).
- ``iso6336``: k-bar = c_gamma_alpha b of ISO 6336-1 method B
  (:func:`pygear.assembly.mesh_stiffness_laws.iso6336_mesh_stiffness`, pinion first, at
  the mesh's ``line_load``).  On a spur stage every pair in contact has the same
  stiffness c_gamma_alpha b / eps_alpha (a rectangular pair curve, so the mean over a
  mesh cycle is c_gamma_alpha b); on a helical stage the contact-line law over
  eps_alpha + eps_beta with that mean.
- ``potential_energy``: the pair curve of
  :func:`pygear.assembly.tooth_stiffness.mesh_stiffness` (material of the mesh, bores of
  the gears, a ring's compliant rim) as a tabulated law, k-bar its mean, over its
  eps_alpha + eps_beta.  The curve runs from where the driving gear's root meets the
  other's tip with power from the carrier to the sun (or from the input gear to the
  output gear); for the other power flow the contact table takes it mirrored
  (:meth:`MeshLaw.oriented_curve`).
- ``loaded_contact``: the loaded tooth contact analysis of the pair with its gears'
  micro-geometry (:mod:`pygear.assembly.loaded_contact_table`), tabulated over mesh
  position and load once per mesh at the operating load w b (``Mesh.line_load`` w on
  the common face width b) and 0.25 to 2 times it; the dynamics take its secant
  stiffness at the operating load as a tabulated law and its unloaded transmission
  error as the mesh's displacement excitation (force k(s) (c - delta_0(s)), which
  deflects under that load by the LTCA's loaded TE), k-bar the LTCA's mean mesh
  stiffness.  Per-tooth deviations (single pitch deviations, runout) enter the contact
  table tooth by tooth as TE-equivalent stiffness curves
  (:func:`pygear.assembly.tooth_fault_curves.deviation_curves`).

Results are cached by their frozen inputs (the mesh, the mesh geometry, the bores, the
stage's helix; the gears' modifications for ``loaded_contact``), so the element
matrices, the contact table and every scene of a case share one evaluation; the time
loop only reads the table.
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass

import numpy as np

from ..errors import CaseError
from ..model.case import Case, check_choice
from ..model.components import PlanetaryStage
from ..model.gear_geometry import MeshGeometry
from ..model.gearbox import ParallelStage
from ..model.geometry_inputs import (
    GEOMETRY_LAWS,
    LAWS,
    effective_law,
    parallel_mesh_geometry,
    planetary_mesh_geometry,
)
from .loaded_contact_table import (
    LoadedContactTable,
    loaded_contact_table,
    operating_force,
)
from .mesh_stiffness_laws import iso6336_mesh_stiffness
from .tooth_stiffness import ToothBody, mesh_stiffness

__all__ = ["LAW_CODES", "MeshLaw", "mesh_law", "stage_mesh_members", "with_mesh_law"]

LAW_CODES = {"parabola": 1, "tabulated": 2, "helical": 3}
"""Single-pair law codes of the Fortran module ``contact_table``."""

RECTANGLE = np.ones(2)
"""A constant pair stiffness as a unit-mean tabulated curve (the ``iso6336`` spur law)."""


@dataclass(frozen=True, eq=False)
class MeshLaw:
    """A mesh's single-pair law as the matrices and the contact table take it.

    Attributes
    ----------
    law : str
        The law's name (``parabola``, ``tabulated``, ``helical``, ``iso6336``,
        ``potential_energy``).
    code : int
        The contact table's law code (:data:`LAW_CODES`).
    mean_stiffness : float
        k-bar, the mean mesh stiffness over a mesh cycle [N/m].
    contact_ratio : float
        The contact ratio the single-pair law spans (eps_alpha, or eps_alpha + eps_beta
        for the helical law and a helical tabulated one) [-].
    end_to_peak : float
        lambda of the parabola, eps_beta of the helical law (unused when tabulated).
    curve : ndarray or None
        Unit-mean samples of a tabulated law over [0, ``contact_ratio``], for power
        from the carrier to the sun (or from the input gear to the output gear).
    mirrored : bool
        True when the curve is mirrored for the other power flow (a curve computed
        from the geometry; a case's own curve is taken as given).
    transverse_contact_ratio, overlap_ratio : float
        eps_alpha and eps_beta of the mesh [-] (eps_beta 0 for a spur mesh).
    geometry : MeshGeometry or None
        The mesh geometry the law was derived from, if any.
    table : LoadedContactTable or None
        The ``loaded_contact`` law's table over position and load (None otherwise).
    excitation : ndarray or None
        The ``loaded_contact`` law's displacement excitation: the unloaded TE [m] at equal
        steps over one mesh cycle s = 0 .. 1 (first = last), for the power flow of
        ``curve`` (None for the other laws).
    equivalent_curve : ndarray or None
        The ``loaded_contact`` law's unit-mean TE-equivalent pair curve, which a mesh
        with per-tooth deviations runs instead of ``curve`` and the excitation.
    """

    law: str
    code: int
    mean_stiffness: float
    contact_ratio: float
    end_to_peak: float
    transverse_contact_ratio: float
    overlap_ratio: float
    curve: np.ndarray | None = None
    mirrored: bool = False
    geometry: MeshGeometry | None = None
    table: LoadedContactTable | None = None
    excitation: np.ndarray | None = None
    equivalent_curve: np.ndarray | None = None

    def __post_init__(self) -> None:
        for array in (self.curve, self.excitation, self.equivalent_curve):
            if array is not None:  # shared through the cache: nobody may change it
                array.setflags(write=False)

    def oriented_curve(self, sun_driven: bool = True) -> np.ndarray | None:
        """The tabulated curve for a power flow: as stored when the carrier (or input
        gear) drives, reversed along the path of contact otherwise when ``mirrored``."""
        if self.curve is None or sun_driven or not self.mirrored:
            return self.curve
        return np.ascontiguousarray(self.curve[::-1])

    def oriented_excitation(self, sun_driven: bool = True) -> np.ndarray | None:
        """The excitation for a power flow: as stored, or for a mirrored law read along
        the mirrored cycle, e'(s) = e(frac(eps - s)) (the mesh stiffness of the mirrored
        pair curve is k(frac(eps - s)) as well)."""
        if self.excitation is None or sun_driven or not self.mirrored:
            return self.excitation
        grid = np.linspace(0.0, 1.0, self.excitation.size)
        values = np.interp(np.mod(self.contact_ratio - grid, 1.0), grid, self.excitation)
        values[-1] = values[0]
        return values


def stage_mesh_members(stage: object) -> tuple[str, ...]:
    """The members :func:`mesh_law` takes for a stage: ``sun`` and ``ring`` of a
    planetary stage, ``mesh`` of a parallel one, none of an inertia."""
    if isinstance(stage, PlanetaryStage):
        return ("sun", "ring")
    if isinstance(stage, ParallelStage):
        return ("mesh",)
    return ()


def _mesh_of(stage: object, member: str):
    return stage.mesh if member == "mesh" else getattr(stage, f"{member}_mesh")


def _bore(gear: object) -> float:
    """The radius of the gear's fillet-foundation term for the potential-energy law [m]:
    an external gear's bore, a ring's rim (:attr:`pygear.model.bodies.Gear.foundation_radius`)."""
    return gear.foundation_radius


def tooth_bodies(
    mesh: object, geometry: MeshGeometry, radii: tuple[float, float]
) -> tuple[ToothBody, ToothBody]:
    """The potential-energy law's bodies of a mesh's two gears (geometry order): the
    mesh's material, the external gear's bore, the ring's rim (0: rigid)."""
    return tuple(
        ToothBody(mesh.young_modulus, mesh.poisson_ratio, 0.0, rim_radius=radius)
        if gear.internal
        else ToothBody(mesh.young_modulus, mesh.poisson_ratio, radius)
        for gear, radius in zip((geometry.gear1, geometry.gear2), radii)
    )


def mesh_law(stage: PlanetaryStage | ParallelStage, member: str) -> MeshLaw:
    """The resolved law of a stage's mesh (cached by its frozen inputs).

    Parameters
    ----------
    stage : PlanetaryStage or ParallelStage
        A validated stage.
    member : str
        ``sun`` or ``ring`` (the sun-planet or ring-planet mesh of a planetary stage),
        ``mesh`` (a parallel stage's).

    Raises
    ------
    CaseError
        The ISO 6336 or potential-energy evaluation refused the geometry (the message
        names the mesh).
    """
    mesh = _mesh_of(stage, member)
    if isinstance(stage, PlanetaryStage):
        geometry = planetary_mesh_geometry(stage, member)
        gears = (stage.sun, stage.planet) if member == "sun" else (stage.planet, stage.ring)
        overlap = mesh.overlap_ratio
        # carrier in, sun out: the planet drives the sun, the ring drives the planet
        driving = 2
    else:
        geometry = parallel_mesh_geometry(stage)
        gears = (stage.input_gear, stage.output_gear)
        overlap = stage.overlap_ratio
        driving = 1
    helical = stage.base_helix_angle_deg != 0.0
    law = effective_law(mesh, helical, overlap)
    # the micro-geometry shapes only the loaded contact: other laws share their cache
    mods = (
        tuple(getattr(g, "modifications", None) for g in gears)
        if law == "loaded_contact"
        else None
    )
    key = (
        law,
        mesh,
        geometry,
        tuple(_bore(g) for g in gears),
        helical,
        overlap,
        driving,
        f"{stage.name}.{'mesh' if member == 'mesh' else member + '_mesh'}",
        mods,
    )
    try:
        hash(key)
    except TypeError:  # an unhashable field value: resolve without the cache
        return _resolve.__wrapped__(key)
    return _resolve(key)


@functools.lru_cache(maxsize=256)
def _resolve(key: tuple) -> MeshLaw:
    law, mesh, geometry, bores, helical, overlap, driving, path, mods = key
    transverse = float(mesh.contact_ratio)
    eps_beta = float(overlap) if helical and overlap else 0.0
    common = dict(law=law, transverse_contact_ratio=transverse, overlap_ratio=eps_beta,
                  geometry=geometry)  # fmt: skip
    if law == "parabola":
        return MeshLaw(code=LAW_CODES["parabola"], mean_stiffness=float(mesh.stiffness),
                       contact_ratio=transverse, end_to_peak=float(mesh.end_to_peak),
                       **common)  # fmt: skip
    if law == "helical":
        return MeshLaw(code=LAW_CODES["helical"], mean_stiffness=float(mesh.stiffness),
                       contact_ratio=transverse + eps_beta, end_to_peak=eps_beta,
                       **common)  # fmt: skip
    if law == "tabulated":
        return MeshLaw(code=LAW_CODES["tabulated"], mean_stiffness=float(mesh.stiffness),
                       contact_ratio=transverse + eps_beta,
                       end_to_peak=eps_beta if eps_beta else float(mesh.end_to_peak),
                       curve=unit_mean_curve(mesh.stiffness_curve), **common)  # fmt: skip
    if geometry is None:  # validation refuses this first; kept for direct callers
        raise CaseError(f"{path}.law {law!r} needs gear geometry on both gears of the mesh")
    if law == "iso6336":
        iso = iso6336_mesh_stiffness(_pinion_first(geometry), line_load=mesh.line_load,
                                     path=path)  # fmt: skip
        mean = iso.mesh_stiffness_alpha_total
        if eps_beta:
            return MeshLaw(code=LAW_CODES["helical"], mean_stiffness=mean,
                           contact_ratio=transverse + eps_beta, end_to_peak=eps_beta,
                           **common)  # fmt: skip
        return MeshLaw(code=LAW_CODES["tabulated"], mean_stiffness=mean,
                       contact_ratio=transverse, end_to_peak=float(mesh.end_to_peak),
                       curve=RECTANGLE.copy(), **common)  # fmt: skip
    if law == "potential_energy":
        bodies = tooth_bodies(mesh, geometry, bores)
        result = mesh_stiffness(geometry, bodies, driving_gear=driving, path=path)
        curve, mean, span = result.tabulated_curve()
        return MeshLaw(code=LAW_CODES["tabulated"], mean_stiffness=float(mean),
                       contact_ratio=float(span), end_to_peak=float(mesh.end_to_peak),
                       curve=curve, mirrored=True, **common)  # fmt: skip
    if law == "loaded_contact":
        bodies = tooth_bodies(mesh, geometry, bores)
        table = loaded_contact_table(geometry, bodies, mods,
                                     operating_force(geometry, mesh.line_load),
                                     driving_gear=driving, path=path)  # fmt: skip
        secant = table.secant_pair_curve()
        return MeshLaw(code=LAW_CODES["tabulated"],
                       mean_stiffness=table.contact_ratio * _trapezoid_mean(secant),
                       contact_ratio=table.contact_ratio, end_to_peak=float(mesh.end_to_peak),
                       curve=unit_mean_curve(secant), mirrored=True, table=table,
                       excitation=table.excitation(),
                       equivalent_curve=unit_mean_curve(table.pair_curve()),
                       **common)  # fmt: skip
    raise CaseError(f"{path}.law must be one of {', '.join(LAWS)} (got {law!r})")


def _trapezoid_mean(values: np.ndarray) -> float:
    """Mean of equally spaced samples under linear interpolation."""
    return float((values.sum() - 0.5 * (values[0] + values[-1])) / (len(values) - 1))


def unit_mean_curve(curve: tuple[float, ...]) -> np.ndarray:
    """Samples scaled to unit mean over [0, eps] under linear interpolation (trapezoid rule)."""
    values = np.asarray(curve, dtype=np.float64)
    mean = (values.sum() - 0.5 * (values[0] + values[-1])) / (len(values) - 1)
    return values / mean


def gears_swapped(geometry: MeshGeometry) -> MeshGeometry:
    """The same pair with gears 1 and 2 (and their thickness allowances) exchanged."""
    first, second = geometry.thickness_allowances
    return dataclasses.replace(
        geometry,
        gear1=geometry.gear2,
        gear2=geometry.gear1,
        thickness_allowances=(second, first),
    )


def _pinion_first(geometry: MeshGeometry) -> MeshGeometry:
    """An external pair with its smaller gear as gear 1 (ISO 6336's pinion)."""
    if geometry.internal or geometry.gear1.teeth <= geometry.gear2.teeth:
        return geometry
    return gears_swapped(geometry)


def with_mesh_law(case: Case, law: str) -> Case:
    """A copy of ``case`` in which every mesh runs ``law`` (``--law``).

    A geometry law derives each mesh's stiffness (every mesh then needs gear geometry
    on both gears); another keeps the mean stiffness of the mesh's own law and changes
    only the shape (``tabulated`` takes the curve of the mesh's own law, so that law
    must have one).

    Raises
    ------
    CaseError
        An unknown law, or a mesh that cannot run it (the message names the mesh).
    """
    check_choice("--law", law, LAWS)
    case.validate()
    stages = []
    for stage in case.gearbox.stages:
        changes = {}
        for member in stage_mesh_members(stage):
            attribute = "mesh" if member == "mesh" else f"{member}_mesh"
            changes[attribute] = _overridden(stage, member, attribute, law)
        stages.append(dataclasses.replace(stage, **changes) if changes else stage)
    gearbox = dataclasses.replace(case.gearbox, stages=tuple(stages))
    changed = dataclasses.replace(case, gearbox=gearbox)
    changed.validate()
    if law in GEOMETRY_LAWS:
        # resolve now (cached for the run): a pair outside the law's range is refused
        # here, naming the mesh, not when the model is assembled
        for stage in changed.gearbox.stages:
            for member in stage_mesh_members(stage):
                mesh_law(stage, member)
    return changed


def _overridden(stage: object, member: str, attribute: str, law: str):
    mesh = _mesh_of(stage, member)
    if law in GEOMETRY_LAWS:
        return dataclasses.replace(mesh, law=law, stiffness=None, stiffness_curve=None)
    own = mesh_law(stage, member)
    curve = None
    if law == "tabulated":
        if own.curve is None:
            raise CaseError(
                f"--law tabulated: {stage.name}.{attribute} runs law {own.law!r}, which has "
                "no curve to tabulate; give it a stiffness_curve or choose a geometry law"
            )
        curve = tuple(float(c) for c in own.curve)
    return dataclasses.replace(mesh, law=law, stiffness=own.mean_stiffness, stiffness_curve=curve)
