"""Components of a gearbox: bodies, bearings, meshes and planetary stages.

Every component is a frozen dataclass holding SI values (m, kg, s, N, rad); only
parameters whose name says so are in degrees (``pressure_angle_deg``).  Nothing is
checked when a component is built: :func:`validate` walks a whole gearbox and names
the first parameter that breaks a rule by its full path (``planetary.sun.mass``),
before any work starts.

This module is longer than 600 lines because each component keeps its validation
rules beside its fields, so a parameter and the rule that names it are read together.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field, fields, is_dataclass

import numpy as np

from ..errors import CaseError  # re-exported: pygear.errors.CaseError
from .gear_geometry import GearGeometry
from .geometry_inputs import (
    GEOMETRY_LAWS,
    LAWS,
    check_gear,
    check_planetary_geometry,
    fill_gear,
    fill_planetary_stage,
)
from .tooth_faults import ChippedTooth, RootCrack, Spall
from .values import is_finite_number, is_whole_number  # re-exported

__all__ = [
    "Bearing",
    "Body",
    "CaseError",
    "Gear",
    "Mesh",
    "PlanetBearing",
    "PlanetaryStage",
    "Carrier",
    "ToothDefect",
    "validate_component",
]


def plain_numbers(value: object) -> object:
    """``value`` with every NumPy scalar replaced by the Python int, float or bool it holds.

    Dataclasses (frozen or not) are updated in place, field by field; tuples, lists and
    dicts are rebuilt only where an item changed.  A case so holds the same numbers,
    the same ``repr`` (input hash) and the same double-precision arithmetic whether a
    value was written as ``0.4`` or as ``np.float32(0.4)``.
    """
    if isinstance(value, (np.number, np.bool_)):
        return value.item()
    if is_dataclass(value) and not isinstance(value, type):
        for spec in fields(value):
            current = getattr(value, spec.name, None)
            converted = plain_numbers(current)
            if converted is not current:
                object.__setattr__(value, spec.name, converted)
        return value
    if isinstance(value, (tuple, list)):
        items = [plain_numbers(v) for v in value]
        if all(a is b for a, b in zip(items, value)):
            return value
        return type(value)(items) if type(value) in (tuple, list) else value
    if isinstance(value, dict):
        pairs = [(plain_numbers(k), plain_numbers(v)) for k, v in value.items()]
        if all(a is k and b is v for (a, b), (k, v) in zip(pairs, value.items())):
            return value
        return dict(pairs)
    return value


_finite = is_finite_number

AXIAL_LIMIT = 100.0
"""Stages sit within this distance of the gearbox origin along its axis [m]."""


def require_axial_position(path: str, value: object) -> None:
    """Raise :class:`CaseError` unless ``value`` is a finite position within
    :data:`AXIAL_LIMIT` of the gearbox origin."""
    if not is_finite_number(value) or abs(value) > AXIAL_LIMIT:
        raise CaseError(
            f"{path} must be a finite position within {AXIAL_LIMIT:g} m of the "
            f"gearbox origin (got {value!r})"
        )


MAGNITUDE_LIMIT = 1e15
"""No SI value of a gearbox (kg, kg m^2, m, N/m, s) comes near 1e15 or 1e-15: beyond,
the assembled matrices overflow or lose every digit, so such a value is a typo."""


def require_positive(path: str, value: float) -> None:
    """Raise :class:`CaseError` unless ``value`` is a finite number > 0 (within
    1e-15 .. 1e15, :data:`MAGNITUDE_LIMIT`)."""
    if not _finite(value) or value <= 0:
        raise CaseError(f"{path} must be a positive finite number (got {value!r})")
    if not 1 / MAGNITUDE_LIMIT <= value <= MAGNITUDE_LIMIT:
        raise CaseError(
            f"{path} must be a positive finite number between {1 / MAGNITUDE_LIMIT:g} and "
            f"{MAGNITUDE_LIMIT:g} in SI units (got {value!r})"
        )


def require_non_negative(path: str, value: float) -> None:
    """Raise :class:`CaseError` unless ``value`` is a finite number >= 0 (at most 1e15)."""
    if not _finite(value) or value < 0:
        raise CaseError(f"{path} must be a finite number >= 0 (got {value!r})")
    if value > MAGNITUDE_LIMIT:
        raise CaseError(
            f"{path} must be a finite number >= 0 and at most {MAGNITUDE_LIMIT:g} in SI units "
            f"(got {value!r})"
        )


def derived_record() -> tuple:
    """The ``_derived`` field of a component whose values gear geometry may fill in: the
    (name, value) pairs filled so far (:mod:`pygear.model.geometry_inputs`), keyword-only
    and left out of ``repr`` and comparisons."""
    return field(default=(), repr=False, compare=False, kw_only=True)


def looks_like_radians(value: float) -> bool:
    """True for a non-zero angle in degrees below 1 in size: no gear angle of a
    ``_deg`` parameter is that small, a value in radians often is."""
    return _finite(value) and 0 < abs(value) < 1


@dataclass(frozen=True)
class Body:
    """A rigid body on the stage axis (a rotor or generator inertia, a shaft).

    Parameters
    ----------
    mass : float
        Mass [kg], > 0.
    polar_inertia : float
        Moment of inertia about the axis [kg m^2], > 0.
    tilt_inertia : float
        Moment of inertia about a diameter (bending, x and y) [kg m^2], > 0.
    """

    mass: float
    polar_inertia: float
    tilt_inertia: float
    _derived: tuple = derived_record()

    def validate(self, path: str) -> None:
        for name in ("mass", "polar_inertia", "tilt_inertia"):
            require_positive(f"{path}.{name}", getattr(self, name))


MODULE_PRESSURE_ANGLE_DEG = 45.0
"""The pressure angle a gear's module implies, acos(2 r_b / (m Z)), must lie below this
(the range :class:`Mesh` accepts for ``pressure_angle_deg``)."""


@dataclass(frozen=True)
class Gear(Body):
    """A gear: a body with a base radius and (optionally) a tooth number, a module and
    its involute geometry.

    Parameters
    ----------
    base_radius : float
        Base-circle radius r_b [m], > 0; derived from ``geometry`` when left out (a typed
        value must agree with it within 0.5 %).
    teeth : int or None
        Number of teeth Z, a whole number >= 3; needed for phasing and the tooth-contact
        table.  The tooth numbers of meshing gears must fit their base radii
        (:data:`TOOTH_RATIO_TOLERANCE`).
        Derived from ``geometry`` when left out.
    module : float or None
        Transverse module m_t [m] (the normal module over cos(beta) for a helical
        gear), optional and used only as a check: r_b = m_t Z cos(alpha_t) / 2, so
        2 r_b / (m_t Z) must be the cosine of a pressure angle in (0, 45) degrees.
    geometry : GearGeometry or None
        The gear's involute geometry (ISO 21771); with it the stage derives its meshes'
        pressure angles, contact and overlap ratios and backlash, and the mesh laws
        ``iso6336`` and ``potential_energy`` their stiffness (docs/gear_geometry.md).
    bore_radius : float or None
        Radius of the bore or hub seat r_int [m], for the fillet-foundation term of the
        ``potential_energy`` law (Sainsot et al. 2004); 0 leaves the term out (a rigid
        body).  None takes half the root radius (:data:`DEFAULT_BORE_RATIO`).  Unused
        for a ring, whose rim the law takes as rigid.
    """

    base_radius: float = float("nan")
    teeth: int | None = None
    module: float | None = None
    geometry: GearGeometry | None = None
    bore_radius: float | None = None

    def __post_init__(self) -> None:
        fill_gear(self)

    def validate(self, path: str) -> None:
        super().validate(path)
        check_gear(self, path)
        if self.bore_radius is not None:
            require_non_negative(f"{path}.bore_radius", self.bore_radius)
        require_positive(f"{path}.base_radius", self.base_radius)
        if self.teeth is not None and (not is_whole_number(self.teeth) or self.teeth < 3):
            raise CaseError(f"{path}.teeth must be a whole number >= 3 (got {self.teeth!r})")
        if self.module is None:
            return
        require_positive(f"{path}.module", self.module)
        if self.teeth is None:
            raise CaseError(
                f"{path}.module needs its teeth: r_b = m Z cos(alpha) / 2 checks the module "
                f"against {path}.teeth, which is not given"
            )
        cosine = 2 * self.base_radius / (self.module * self.teeth)
        if not math.cos(math.radians(MODULE_PRESSURE_ANGLE_DEG)) < cosine < 1:
            implied = f"{math.degrees(math.acos(cosine)):.3g} deg" if cosine < 1 else "none"
            raise CaseError(
                f"{path}.module: m = {self.module * 1e3:.4g} mm and Z = {self.teeth} do not fit "
                f"base_radius = {self.base_radius * 1e3:.4g} mm: r_b = m Z cos(alpha) / 2 needs "
                f"a pressure angle alpha in (0, {MODULE_PRESSURE_ANGLE_DEG:g}) deg "
                f"(implied pressure angle: {implied})"
            )


DEFAULT_BORE_RATIO = 0.5
"""Bore radius over root radius of a gear whose ``bore_radius`` is left out: h_fi = r_f /
r_int = 2, a gear body on a shaft or a planet on its bearing (Tian's 2004 pair has 2.4
and 2.6).  The fillet foundation is the largest compliance of a tooth pair
(docs/potential_energy.md), so a case that knows its bores should type them."""


TOOTH_RATIO_TOLERANCE = 0.03
"""How far the tooth-number ratio of two meshing gears may stray from their base-radius
ratio [-].  Meshing gears share one base pitch 2 pi r_b / Z (r_b = m Z cos(alpha) / 2 with
the same m and alpha), so Z_2 / Z_1 = r_b2 / r_b1 exactly.  A case still differs from
that by the rounding of published radii (three significant digits are off by up to
0.5 % each, so a ratio by up to 1 %: Table 1's 38.7, 50.2 and 137.5 mm with 27, 35 and
96 teeth agree to 0.14 %) and by a tooth number moved by one for assembly (one tooth
in 50 or more: 2 %; the gearbox case's 97-tooth ring on Table 1's 96-tooth radius is
1.1 % off).  3 % allows both; a wrong digit (960 teeth for 96) or another gear's tooth
number is far beyond."""


def require_matching_teeth(path: str, gears: dict[str, Gear]) -> None:
    """Raise :class:`CaseError` unless the tooth numbers of gears that share one base
    pitch fit their base radii (:data:`TOOTH_RATIO_TOLERANCE`).

    ``gears`` maps member names to gears; gears without a tooth number are skipped.
    The message names the gear that disagrees with every other (or the pair).
    """
    known = {name: gear for name, gear in gears.items() if gear.teeth is not None}
    names = list(known)
    failed = []
    for i, first in enumerate(names):
        for second in names[i + 1 :]:
            a, b = known[first], known[second]
            teeth_ratio = b.teeth / a.teeth
            radius_ratio = b.base_radius / a.base_radius
            if abs(teeth_ratio / radius_ratio - 1) > TOOTH_RATIO_TOLERANCE:
                failed.append((first, second, teeth_ratio, radius_ratio))
    if not failed:
        return
    common = set.intersection(*({f[0], f[1]} for f in failed))
    first, second, teeth_ratio, radius_ratio = failed[0]
    culprit = common.pop() if len(common) == 1 else second
    other = first if culprit == second else second
    gear, reference = known[culprit], known[other]
    implied = reference.teeth * gear.base_radius / reference.base_radius
    raise CaseError(
        f"{path}.{culprit}.teeth: {gear.teeth} teeth do not fit the base radii: "
        f"Z_{culprit}/Z_{other} = {gear.teeth}/{reference.teeth} = "
        f"{gear.teeth / reference.teeth:.4g} but r_b {culprit}/{other} = "
        f"{gear.base_radius / reference.base_radius:.4g} (about {implied:.1f} teeth); meshing "
        f"gears share one base pitch 2 pi r_b/Z, so the ratios must agree within "
        f"{TOOTH_RATIO_TOLERANCE * 100:g} %"
    )


@dataclass(frozen=True)
class Carrier(Body):
    """The planet carrier.

    Parameters
    ----------
    radius : float
        Carrier radius r_c: the distance from the stage axis to each planet centre [m],
        > 0.
    """

    radius: float = float("nan")

    def validate(self, path: str) -> None:
        super().validate(path)
        require_positive(f"{path}.radius", self.radius)


@dataclass(frozen=True)
class Bearing:
    """Bearing of a central member to the housing: six independent springs.

    Parameters
    ----------
    radial : float
        Stiffness in x and y [N/m], >= 0.
    axial : float
        Stiffness in z [N/m], >= 0.
    tilt : float
        Tilting stiffness about x and y [N m/rad], >= 0.
    torsional : float
        Torsional stiffness about z [N m/rad], >= 0; 0 for a member that turns freely.
    """

    radial: float
    axial: float
    tilt: float
    torsional: float = 0.0

    def validate(self, path: str) -> None:
        for spec in fields(self):
            require_non_negative(f"{path}.{spec.name}", getattr(self, spec.name))


@dataclass(frozen=True)
class PlanetBearing:
    """Bearing between the carrier and each planet, in the planet's revolving frame.

    Parameters
    ----------
    radial : float
        Stiffness in the radial and tangential directions [N/m], >= 0.
    axial : float
        Axial stiffness [N/m], >= 0.
    tilt : float
        Tilting stiffness [N m/rad], >= 0.
    """

    radial: float
    axial: float
    tilt: float

    def validate(self, path: str) -> None:
        for spec in fields(self):
            require_non_negative(f"{path}.{spec.name}", getattr(self, spec.name))


MAX_CONTACT_RATIO = 10.0
"""Involute gears mesh with fewer than ~3 transverse (~5 total) tooth pairs; the
tooth-contact table evaluates ceil(contact_ratio) pairs per mesh and step."""


@dataclass(frozen=True)
class Mesh:
    """A gear mesh: one spring on the line of action, with its single-pair law.

    With gear geometry on both gears of the mesh (``Gear.geometry``) the stage derives
    ``pressure_angle_deg``, ``contact_ratio``, ``overlap_ratio`` and ``backlash``
    (typed values must agree: :mod:`pygear.model.geometry_inputs`).

    Parameters
    ----------
    stiffness : float or None
        Mean (synthesizing) mesh stiffness k-bar [N/m], > 0.  Derived by the laws
        ``iso6336`` and ``potential_energy`` (typing it then is an error); required
        by the others.
    pressure_angle_deg : float or None
        Transverse operating pressure angle [deg], in (0, 45); derived from gear geometry
        when left out, else required.
    contact_ratio : float or None
        Transverse contact ratio epsilon_alpha [-], > 0 and below 10, above 1 on a spur
        stage; derived from gear geometry when left out, else required.
    end_to_peak : float
        Single-pair stiffness at the ends of contact over the peak, lambda [-], in (0, 1]
        (the parabola of docs/model.md §5.2).
    stiffness_curve : tuple of float or None
        The ``tabulated`` single-pair law [-]: the shape of the stiffness of one tooth
        pair at equally spaced relative contact positions from the start (0) to the
        end of contact (``contact_ratio``, plus ``overlap_ratio`` on a helical stage),
        at least two samples, all >= 0.  Only the shape counts: the curve is scaled so
        that the mean mesh stiffness over a mesh cycle is ``stiffness``; linear
        interpolation between samples.
    law : str or None
        Single-pair law: ``parabola`` (docs/model.md §5.2), ``tabulated``
        (``stiffness_curve``), ``helical`` (contact-line length over eps_alpha +
        eps_beta), ``iso6336`` (ISO 6336-1 method B mean c_gamma_alpha b; a constant
        pair stiffness on a spur stage, the helical law on a helical one) or
        ``potential_energy`` (the pair curve of :mod:`pygear.assembly.tooth_stiffness`).
        None: ``tabulated`` with a curve, ``helical`` on a helical stage, else
        ``parabola``.
    overlap_ratio : float or None
        Overlap ratio epsilon_beta of a helical mesh [-], >= 0 and below 10 (derived
        from geometry).  A helical
        stage needs it, typed or derived.
    line_load : float
        K_A F_t / b [N/mm] of the ``iso6336`` law, > 0 (below 100 it lowers the
        stiffness).
    young_modulus, poisson_ratio : float
        Material of both gears [Pa, -], for the ``potential_energy`` law: Young's
        modulus > 0, Poisson's ratio in [0, 0.5).
    backlash : float or None
        Circumferential backlash j_wt at the working pitch circle [m], >= 0: derived from the
        geometry (centre distance and ``thickness_allowances``) when left out.  With the
        ``tooth_separation`` effect the teeth part within it (on the flank normal,
        j_wt cos(alpha_wt) cos(beta_b)) and meet again on the coast flanks; that effect
        refuses a mesh with no backlash, typed or derived; 0 is a two-sided contact.
    thickness_allowances : tuple of float
        Normal tooth thickness allowances (A_sn1, A_sn2) [m] of the mesh geometry's
        gears in its order: (sun, planet), (planet, ring) or (input, output gear);
        negative thins a tooth; each below 1 m in size.
    """

    stiffness: float | None = None
    pressure_angle_deg: float | None = None
    contact_ratio: float | None = None
    end_to_peak: float = 0.6
    stiffness_curve: tuple[float, ...] | None = None
    law: str | None = None
    overlap_ratio: float | None = None
    line_load: float = 100.0
    young_modulus: float = 206e9
    poisson_ratio: float = 0.3
    backlash: float | None = None
    thickness_allowances: tuple[float, float] = (0.0, 0.0)
    _derived: tuple = derived_record()

    def __post_init__(self) -> None:
        for name in ("stiffness_curve", "thickness_allowances"):
            value = getattr(self, name)
            if value is not None and not isinstance(value, tuple):
                try:
                    object.__setattr__(self, name, tuple(value))
                except TypeError:
                    pass  # validate() names it

    @property
    def pressure_angle(self) -> float:
        """Pressure angle [rad]."""
        return math.radians(self.pressure_angle_deg)

    def validate(self, path: str) -> None:
        if self.law is not None and self.law not in LAWS:
            raise CaseError(
                f"{path}.law must be one of {', '.join(LAWS)} or None (got {self.law!r})"
            )
        if self.law in GEOMETRY_LAWS:
            if self.stiffness is not None:
                raise CaseError(
                    f"{path}.stiffness must be left out with law {self.law!r}, which derives it "
                    f"from the gear geometry (got {self.stiffness!r})"
                )
        elif self.stiffness is None:
            raise CaseError(
                f"{path}.stiffness must be given (or choose law 'iso6336' or "
                "'potential_energy' with gear geometry on both gears)"
            )
        else:
            require_positive(f"{path}.stiffness", self.stiffness)
        for name in ("pressure_angle_deg", "contact_ratio"):
            if getattr(self, name) is None:
                raise CaseError(
                    f"{path}.{name} must be given, or derived: give both gears of the mesh a "
                    "geometry (GearGeometry)"
                )
        if not _finite(self.pressure_angle_deg) or not 0 < self.pressure_angle_deg < 45:
            raise CaseError(
                f"{path}.pressure_angle_deg must lie in (0, 45) degrees "
                f"(got {self.pressure_angle_deg!r})"
            )
        if looks_like_radians(self.pressure_angle_deg):
            raise CaseError(
                f"{path}.pressure_angle_deg must be given in degrees: "
                f"{self.pressure_angle_deg!r} looks like radians "
                f"(= {math.degrees(self.pressure_angle_deg):.4g} deg)"
            )
        require_positive(f"{path}.contact_ratio", self.contact_ratio)
        if self.contact_ratio >= MAX_CONTACT_RATIO:
            raise CaseError(
                f"{path}.contact_ratio must be below {MAX_CONTACT_RATIO:g} tooth pairs "
                f"(got {self.contact_ratio!r})"
            )
        if not _finite(self.end_to_peak) or not 0 < self.end_to_peak <= 1:
            raise CaseError(f"{path}.end_to_peak must lie in (0, 1] (got {self.end_to_peak!r})")
        if self.stiffness_curve is not None:
            curve = self.stiffness_curve
            if (
                not isinstance(curve, tuple)
                or len(curve) < 2
                or not all(_finite(c) and c >= 0 for c in curve)
                or not sum(curve) > 0
            ):
                raise CaseError(
                    f"{path}.stiffness_curve must be a sequence of at least two finite numbers "
                    f">= 0, not all zero (got {curve!r})"
                )
            if self.law not in (None, "tabulated"):
                raise CaseError(
                    f"{path}.stiffness_curve is the shape of law 'tabulated', not of law "
                    f"{self.law!r}: drop one of them"
                )
        elif self.law == "tabulated":
            raise CaseError(f"{path}.law 'tabulated' needs a stiffness_curve")
        self._validate_geometry_inputs(path)

    def _validate_geometry_inputs(self, path: str) -> None:
        """The overlap ratio, the laws' material and load, backlash and allowances."""
        if self.overlap_ratio is not None:
            require_non_negative(f"{path}.overlap_ratio", self.overlap_ratio)
            if self.overlap_ratio >= MAX_CONTACT_RATIO:
                raise CaseError(
                    f"{path}.overlap_ratio must be below {MAX_CONTACT_RATIO:g} "
                    f"(got {self.overlap_ratio!r})"
                )
        require_positive(f"{path}.line_load", self.line_load)
        require_positive(f"{path}.young_modulus", self.young_modulus)
        if not _finite(self.poisson_ratio) or not 0 <= self.poisson_ratio < 0.5:
            raise CaseError(
                f"{path}.poisson_ratio must lie in [0, 0.5) (got {self.poisson_ratio!r})"
            )
        if self.backlash is not None:
            require_non_negative(f"{path}.backlash", self.backlash)
        allowances = self.thickness_allowances
        if (
            not isinstance(allowances, tuple)
            or len(allowances) != 2
            or not all(_finite(a) and abs(a) < 1.0 for a in allowances)
        ):
            raise CaseError(
                f"{path}.thickness_allowances must be two lengths (A_sn1, A_sn2) in metres "
                f"(got {allowances!r})"
            )


@dataclass(frozen=True)
class PlanetaryStage:
    """A planetary stage: carrier, ring, sun and N identical planets.

    The carrier, ring and sun live in the inertial frame; each planet in a frame
    revolving with it (docs/model.md §1-3).

    Parameters
    ----------
    name : str
        Stage name, the first part of every DOF and parameter path: a Python
        identifier, unique in the gearbox.
    carrier, ring, sun, planet : Carrier, Gear, Gear, Gear
        The members; ``planet`` describes each of the N planets.  With gear geometry
        the carrier radius is the centre distance of both meshes: left out, it is the
        sun-planet geometry's zero-backlash centre distance; typed, it must agree with
        both meshes' within 0.5 %.
    planets : int
        Number of planets N >= 1.
    carrier_bearing, ring_bearing, sun_bearing : Bearing
        Bearings of the central members to the housing.
    planet_bearing : PlanetBearing
        Bearing of each planet on the carrier.
    sun_mesh, ring_mesh : Mesh
        Sun-planet and ring-planet meshes (the same for every planet).
    planet_angles_deg : tuple of float or None
        Angle psi_n of each planet from the x axis [deg], one per planet; equal spacing
        when None.  Neighbouring planets must not touch.
    base_helix_angle_deg : float or None
        Signed base helix angle beta_b [deg], in (-45, 45); 0 for spur gears.  Left out: from the
        gear geometry (signed with the sun's hand), else 0.  A helical stage needs an
        overlap ratio on both meshes (typed or from geometry).
    axial_position : float
        Position of the stage centre along the gearbox z axis [m], within 100 m of the
        origin.
    mesh_phases : dict of str to float or None
        Overrides of the mesh phases gamma [mesh cycles], each in [0, 1), keyed by mesh name
        (``sun-planet1`` ... ``sun-planetN``, ``ring-planet1`` ... ``ring-planetN``);
        the others follow Parker & Lin's phasing (:mod:`pygear.assembly.mesh_phasing`).  Stored
        as sorted (name, phase) pairs; :attr:`phase_overrides` gives the dict.
    """

    name: str
    carrier: Carrier
    ring: Gear
    sun: Gear
    planet: Gear
    planets: int
    carrier_bearing: Bearing
    ring_bearing: Bearing
    sun_bearing: Bearing
    planet_bearing: PlanetBearing
    sun_mesh: Mesh
    ring_mesh: Mesh
    planet_angles_deg: tuple[float, ...] | None = None
    base_helix_angle_deg: float | None = None
    axial_position: float = 0.0
    mesh_phases: dict[str, float] | None = None
    kind: str = field(default="planetary", init=False)
    _derived: tuple = derived_record()

    def __post_init__(self) -> None:
        phases = self.mesh_phases
        if isinstance(phases, dict):
            try:
                object.__setattr__(self, "mesh_phases", tuple(sorted(phases.items())))
            except TypeError:
                object.__setattr__(self, "mesh_phases", tuple(phases.items()))
        fill_planetary_stage(self)

    @property
    def phase_overrides(self) -> dict[str, float]:
        """Phase overrides by mesh name (empty when none are given)."""
        return dict(self.mesh_phases or ())

    @property
    def mesh_names(self) -> tuple[str, ...]:
        """Mesh names: sun-planet1..N, then ring-planet1..N."""
        planets = range(1, self.planets + 1)
        return tuple(f"{gear}-planet{n}" for gear in ("sun", "ring") for n in planets)

    def gear_teeth(self, member: str) -> int | None:
        """Tooth number of ``sun``, ``ring`` or ``planet<n>``; KeyError for anything else."""
        if member in ("sun", "ring"):
            return getattr(self, member).teeth
        if member in self.member_names[3:]:
            return self.planet.teeth
        raise KeyError(member)

    @property
    def planet_angles(self) -> tuple[float, ...]:
        """Planet angles psi_n [rad] (equal spacing unless given)."""
        if self.planet_angles_deg is None:
            return tuple(2 * math.pi * n / self.planets for n in range(self.planets))
        return tuple(math.radians(a) for a in self.planet_angles_deg)

    @property
    def equally_spaced(self) -> bool:
        """True when the planets sit at 360/N degree intervals from the first."""
        first = self.planet_angles[0]
        return all(
            abs(math.remainder(a - first - 2 * math.pi * n / self.planets, 2 * math.pi)) < 1e-12
            for n, a in enumerate(self.planet_angles)
        )

    @property
    def base_helix_angle(self) -> float:
        """Base helix angle [rad]."""
        return math.radians(self.base_helix_angle_deg)

    @property
    def spur(self) -> bool:
        """True for a spur stage (no helix angle)."""
        return self.base_helix_angle_deg == 0.0

    @property
    def speed_ratio(self) -> float:
        """Ideal ratio with the ring held, carrier in and sun out: 1 + r_br/r_bs."""
        return 1.0 + self.ring.base_radius / self.sun.base_radius

    @property
    def member_names(self) -> tuple[str, ...]:
        """Node names in DOF order: carrier, ring, sun, planet1..planetN."""
        return ("carrier", "ring", "sun") + tuple(f"planet{n + 1}" for n in range(self.planets))

    def validate(self, path: str | None = None) -> None:
        """Check every parameter; raise :class:`CaseError` naming the first bad one."""
        path = path or self.name
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise CaseError(f"stage name must be an identifier (got {self.name!r})")
        if not is_whole_number(self.planets) or self.planets < 1:
            raise CaseError(f"{path}.planets must be a whole number >= 1 (got {self.planets!r})")
        for name in ("ring", "sun", "planet"):
            validate_component(getattr(self, name), f"{path}.{name}")
        for name in ("carrier", "sun_mesh", "ring_mesh"):
            validate_component(getattr(self, name), f"{path}.{name}", validate=False)
        if not _finite(self.base_helix_angle_deg) or abs(self.base_helix_angle_deg) >= 45:
            raise CaseError(
                f"{path}.base_helix_angle_deg must lie in (-45, 45) degrees "
                f"(got {self.base_helix_angle_deg!r})"
            )
        if looks_like_radians(self.base_helix_angle_deg):
            raise CaseError(
                f"{path}.base_helix_angle_deg must be given in degrees (0 for spur gears): "
                f"{self.base_helix_angle_deg!r} looks like radians "
                f"(= {math.degrees(self.base_helix_angle_deg):.4g} deg)"
            )
        check_planetary_geometry(self, path)
        for name in (
            "carrier",
            "carrier_bearing",
            "ring_bearing",
            "sun_bearing",
            "planet_bearing",
            "sun_mesh",
            "ring_mesh",
        ):
            getattr(self, name).validate(f"{path}.{name}")
        require_axial_position(f"{path}.axial_position", self.axial_position)
        if self.ring.base_radius <= self.planet.base_radius:
            raise CaseError(
                f"{path}.ring.base_radius must exceed {path}.planet.base_radius "
                f"({self.ring.base_radius} <= {self.planet.base_radius})"
            )
        self._validate_radii(path)
        self._validate_angles(path)
        self._validate_teeth(path)
        self._validate_contact(path)

    def _validate_radii(self, path: str) -> None:
        """The base radii and the carrier radius fix each mesh's line of action:
        r_bs + r_bp = r_c cos(alpha_s) and r_br - r_bp = r_c cos(alpha_r) (docs/model.md §2),
        so both sums over r_c must be cosines of a pressure angle in (0, 45) degrees."""
        r_c = self.carrier.radius
        for mesh, value, formula in (
            ("sun_mesh", self.sun.base_radius + self.planet.base_radius, "sun + planet"),
            ("ring_mesh", self.ring.base_radius - self.planet.base_radius, "ring - planet"),
        ):
            cosine = value / r_c
            if not math.cos(math.pi / 4) < cosine < 1:
                angle = f"{math.degrees(math.acos(cosine)):.3g} deg" if cosine < 1 else "none"
                raise CaseError(
                    f"{path}.carrier.radius: the geometry is impossible: {formula} base_radius = "
                    f"{value * 1e3:.4g} mm must lie between cos(45 deg) r_c and r_c = "
                    f"{r_c * 1e3:.4g} mm (r_c cos(alpha) of the {mesh}; implied pressure "
                    f"angle: {angle})"
                )

    def _validate_angles(self, path: str) -> None:
        if self.planet_angles_deg is not None:
            angles = self.planet_angles_deg
            if not isinstance(angles, (tuple, list)):
                raise CaseError(
                    f"{path}.planet_angles_deg must be a sequence of angles in degrees, one per "
                    f"planet (got {angles!r})"
                )
            if len(angles) != self.planets:
                raise CaseError(
                    f"{path}.planet_angles_deg must list one angle per planet "
                    f"({len(angles)} given for {self.planets} planets)"
                )
            if not all(_finite(a) for a in angles):
                raise CaseError(f"{path}.planet_angles_deg must be finite numbers (got {angles!r})")
        if self.planets < 2:
            return
        pitch = self.planet.base_radius / math.cos(self.sun_mesh.pressure_angle)
        module = 2 * pitch / self.planet.teeth if self.planet.teeth else 0.0
        tip_radius = pitch + module
        if self.planet_angles_deg is None:  # equal spacing (no list: N may be absurd)
            smallest = 2 * math.pi / self.planets
        else:
            ordered = sorted(a % (2 * math.pi) for a in self.planet_angles)
            gaps = [b - a for a, b in zip(ordered, ordered[1:])] + [
                ordered[0] + 2 * math.pi - ordered[-1]
            ]
            smallest = min(gaps)
        centre_distance = 2 * self.carrier.radius * math.sin(smallest / 2)
        if centre_distance <= 2 * tip_radius:
            hint = ""
            angles = self.planet_angles_deg
            if angles is not None and max(abs(a) for a in angles) <= 2 * math.pi + 1e-9:
                degrees = ", ".join(f"{math.degrees(a):.4g}" for a in angles)
                hint = f"; the angles look like radians: in degrees they are ({degrees})"
            raise CaseError(
                f"{path}.planet_angles_deg: neighbouring planets {math.degrees(smallest):.3g} deg "
                f"apart collide (centres {centre_distance * 1e3:.4g} mm apart, the planet tip "
                f"circles need more than {2 * tip_radius * 1e3:.4g} mm){hint}"
            )

    def _validate_teeth(self, path: str) -> None:
        require_matching_teeth(path, {"sun": self.sun, "planet": self.planet, "ring": self.ring})
        teeth = (self.sun.teeth, self.ring.teeth)
        if None in teeth or not self.equally_spaced:
            return
        if (self.sun.teeth + self.ring.teeth) % self.planets:
            raise CaseError(
                f"{path}.planets: {self.planets} equally spaced planets cannot be assembled with "
                f"sun.teeth = {self.sun.teeth} and ring.teeth = {self.ring.teeth}: "
                f"(Z_s + Z_r)/N must be a whole number (got {self.sun.teeth + self.ring.teeth}"
                f"/{self.planets}); give planet_angles_deg or other tooth numbers"
            )

    def _validate_contact(self, path: str) -> None:
        if self.spur:
            for name in ("sun_mesh", "ring_mesh"):
                ratio = getattr(self, name).contact_ratio
                if ratio <= 1:
                    raise CaseError(
                        f"{path}.{name}.contact_ratio must exceed 1 for a spur mesh "
                        f"(got {ratio!r}): at most one tooth pair would be in contact, "
                        f"with gaps of none"
                    )
        if self.mesh_phases is None:
            return
        pairs = self.mesh_phases
        if not isinstance(pairs, tuple) or not all(
            isinstance(p, tuple) and len(p) == 2 for p in pairs
        ):
            raise CaseError(
                f"{path}.mesh_phases must be a dict of mesh name to phase (got {pairs!r})"
            )
        known = self.mesh_names
        for name, phase in pairs:
            if name not in known:
                raise CaseError(
                    f"{path}.mesh_phases: no mesh named {name!r} in this stage "
                    f"(meshes: {', '.join(known)})"
                )
            if not _finite(phase) or not 0 <= phase < 1:
                raise CaseError(
                    f"{path}.mesh_phases[{name!r}] must lie in [0, 1) mesh cycles (got {phase!r})"
                )


def validate_component(component: object, path: str, *, validate: bool = True) -> None:
    """Validate any component that has a ``validate(path)`` method (``validate=False``:
    only check that it is one)."""
    if not is_dataclass(component) or not hasattr(component, "validate"):
        raise CaseError(f"{path} is not a pygear component (got {type(component).__name__})")
    if validate:
        component.validate(path)


@dataclass(frozen=True)
class ToothDefect:
    """A weakened or missing tooth, given in a case or a scene.

    Parameters
    ----------
    gear : str
        The gear as ``<stage>.<member>``: ``planetary.sun``, ``planetary.ring`` or
        ``planetary.planet2`` (planets numbered from 1, as in the DOF labels).  A planet
        tooth meets the sun and the ring, so its defect acts in both of its meshes.
    tooth : int
        0-based tooth index, 0 .. Z - 1.  Teeth are numbered in the order in which
        they come into mesh (against the gear's rotation relative to the carrier in
        the running direction).  Tooth 0 is the one in the newest tooth pair at the
        reference state (all rotations zero): of sun-planet1 for the sun, of
        ring-planet1 for the ring, and of sun-planet<n> for planet n
        (:mod:`pygear.assembly.mesh_phasing` gives the derivation).
    factor : float
        Stiffness factor of the tooth [-], in [0, 1]: 1 healthy, below 1 a crack or
        spall, 0 a missing tooth.  It multiplies the stiffness of every tooth pair
        the tooth is part of.
    fault : RootCrack, Spall, ChippedTooth or None
        A geometric fault (:mod:`pygear.model.tooth_faults`): while the tooth is in mesh
        its pair follows the potential-energy pair curve of the damaged tooth
        (:func:`pygear.assembly.tooth_stiffness.mesh_stiffness`), scaled to the mesh's
        mean stiffness, instead of the mesh's law.  Needs gear geometry on both gears of
        every mesh the tooth meets; the fault's own ``gear`` index is not read (``gear``
        above names the tooth).
    """

    gear: str
    tooth: int
    factor: float = 1.0
    fault: RootCrack | Spall | ChippedTooth | None = None

    @property
    def stage(self) -> str:
        """Stage part of :attr:`gear`."""
        return self.gear.split(".", 1)[0]

    @property
    def member(self) -> str:
        """Member part of :attr:`gear` (sun, ring, planet<n>)."""
        return self.gear.split(".", 1)[1]

    def validate(self, path: str) -> None:
        if not isinstance(self.gear, str) or self.gear.count(".") != 1:
            raise CaseError(
                f"{path}.gear must name a gear as '<stage>.<member>', e.g. 'planetary.sun' "
                f"(got {self.gear!r})"
            )
        if (
            not isinstance(self.tooth, numbers.Integral)
            or isinstance(self.tooth, bool)
            or self.tooth < 0
        ):
            raise CaseError(
                f"{path}.tooth must be a whole number >= 0 (0-based; got {self.tooth!r})"
            )
        if not _finite(self.factor) or not 0 <= self.factor <= 1:
            raise CaseError(
                f"{path}.factor must lie in [0, 1] (1 healthy, 0 missing tooth; "
                f"got {self.factor!r})"
            )
        if self.fault is not None and not isinstance(self.fault, (RootCrack, Spall, ChippedTooth)):
            raise CaseError(
                f"{path}.fault must be a RootCrack, Spall or ChippedTooth "
                f"(got {type(self.fault).__name__})"
            )
