"""Bodies of a gearbox: a rigid body, a gear and the planet carrier, each with its
validation beside its fields (SI values; see :mod:`pygear.model.components`)."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from ..errors import CaseError
from . import gear_geometry as geo
from .component_rules import (
    derived_record,
    is_whole_number,
    require_non_negative,
    require_positive,
)
from .gear_geometry import GearGeometry
from .geometry_inputs import check_gear, fill_gear
from .micro_geometry import Modifications, check_modifications
from .plausibility import PlausibilityWarning, warn_if_implausible

__all__ = [
    "DEFAULT_BORE_RATIO",
    "FOUNDATION_RATIO_RANGE",
    "MODULE_PRESSURE_ANGLE_DEG",
    "TOOTH_RATIO_TOLERANCE",
    "Body",
    "Carrier",
    "Gear",
    "check_foundation_bore",
    "foundation_bore_radius",
    "require_matching_teeth",
    "ring_rim_ratio",
]


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
        warn_if_implausible(f"{path}.mass", "mass", self.mass)
        for name in ("polar_inertia", "tilt_inertia"):
            warn_if_implausible(f"{path}.{name}", "inertia", getattr(self, name))


MODULE_PRESSURE_ANGLE_DEG = 45.0
"""The pressure angle a gear's module implies, acos(2 r_b / (m Z)), must lie below this
(the range :class:`Mesh` accepts for ``pressure_angle_deg``)."""


@dataclass(frozen=True)
class Gear(Body):
    """A gear: a body with a base radius and (optionally) a tooth number, a module and
    its involute geometry.

    Parameters
    ----------
    base_radius : float or None
        Base-circle radius r_b [m], > 0; derived from ``geometry`` when left out (None;
        a typed value must agree with it within 0.5 %, and a typed NaN is an error).
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
        body).  None takes half the root radius (:data:`DEFAULT_BORE_RATIO`).  h_fi = r_f /
        r_int outside :data:`FOUNDATION_RATIO_RANGE` warns and is taken at the range's
        edge.  Unused for a ring (see ``rim_radius``).
    rim_radius : float or None
        A ring's rim: the outer radius r_o [m] where the housing holds it, above the root
        radius, for the rim's fillet-foundation term of the ``potential_energy`` law
        (:mod:`pygear.assembly.ring_rim`): where the rim is known, the ring's teeth sit
        on a compliant rim.  None or 0 keeps the rim rigid (the ring mesh then comes out
        some 30 to 50 % stiffer: docs/potential_energy.md).  Only a ring (an internal
        ``geometry``) takes it.
    modifications : Modifications or None
        Flank micro-geometry, deviations and axis misalignment for the loaded tooth
        contact analysis (:mod:`pygear.model.micro_geometry`); None: a perfect gear.
    """

    base_radius: float | None = None
    teeth: int | None = None
    module: float | None = None
    geometry: GearGeometry | None = None
    bore_radius: float | None = None
    rim_radius: float | None = None
    modifications: Modifications | None = None

    def __post_init__(self) -> None:
        fill_gear(self)

    def validate(self, path: str) -> None:
        super().validate(path)
        check_gear(self, path)
        check_modifications(f"{path}.modifications", self.modifications)
        if self.bore_radius is not None:
            require_non_negative(f"{path}.bore_radius", self.bore_radius)
            warn_if_implausible(f"{path}.bore_radius", "radius", self.bore_radius, zero_ok=True)
            if self.bore_radius and getattr(self.geometry, "internal", False) is True:
                warnings.warn(
                    f"{path}.bore_radius is not read for a ring (internal geometry): the "
                    f"outer radius of its rim is rim_radius",
                    PlausibilityWarning,
                    stacklevel=3,
                )
        if self.rim_radius is not None:
            require_non_negative(f"{path}.rim_radius", self.rim_radius)
            self._check_rim(path)
        if self.base_radius is None:
            raise CaseError(
                f"{path}.base_radius must be given, or derived: give the gear a geometry "
                "(GearGeometry)"
            )
        require_positive(f"{path}.base_radius", self.base_radius)
        warn_if_implausible(f"{path}.base_radius", "radius", self.base_radius)
        if self.teeth is not None and (not is_whole_number(self.teeth) or self.teeth < 3):
            raise CaseError(f"{path}.teeth must be a whole number >= 3 (got {self.teeth!r})")
        if self.module is None:
            return
        require_positive(f"{path}.module", self.module)
        warn_if_implausible(f"{path}.module", "module", self.module)
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

    def _check_rim(self, path: str) -> None:
        """A typed rim radius belongs to a ring and lies outside its root circle."""
        if self.rim_radius == 0 or not isinstance(self.geometry, GearGeometry):
            return
        if not self.geometry.internal:
            raise CaseError(
                f"{path}.rim_radius is the outer radius of a ring's rim; this gear is external: "
                "leave it out (its body is given by bore_radius)"
            )
        root = geo.root_radius(self.geometry)
        if not self.rim_radius > root:
            raise CaseError(
                f"{path}.rim_radius must exceed the ring's root radius r_f = {root * 1e3:.4g} mm "
                f"(got {self.rim_radius * 1e3:.4g} mm): the rim lies outside the tooth roots"
            )
        warn_if_implausible(f"{path}.rim_radius", "radius", self.rim_radius)

    @property
    def foundation_radius(self) -> float:
        """The radius the ``potential_energy`` law's fillet-foundation term uses [m]: an
        external gear's bore r_int (typed, else :data:`DEFAULT_BORE_RATIO` r_f, within
        :data:`FOUNDATION_RATIO_RANGE`), a ring's rim radius r_o; 0 for a rigid body (a
        ring whose rim is not given) or a gear without geometry."""
        geometry = self.geometry
        if not isinstance(geometry, GearGeometry):
            return float(self.bore_radius or 0.0)
        root = geo.root_radius(geometry)
        if geometry.internal:
            return float(self.rim_radius or 0.0)
        bore = DEFAULT_BORE_RATIO * root if self.bore_radius is None else float(self.bore_radius)
        return foundation_bore_radius(root, bore)[0]


def check_foundation_bore(path: str, gear: Gear) -> None:
    """Rules of a gear's bore for the ``potential_energy`` law (gear geometry known):
    an error for a bore at or beyond the root circle, a warning (the range's edge is
    taken) for h_fi = r_f / r_int outside :data:`FOUNDATION_RATIO_RANGE`."""
    geometry, bore = gear.geometry, gear.bore_radius
    if not isinstance(geometry, GearGeometry) or geometry.internal or not bore:
        return
    root = geo.root_radius(geometry)
    if not bore < root:
        raise CaseError(
            f"{path}.bore_radius must lie below the root radius r_f = {root * 1e3:.4g} mm "
            f"(got {bore * 1e3:.4g} mm): the bore would cut the tooth roots"
        )
    reason = foundation_bore_radius(root, bore)[1]
    if reason is not None:
        warnings.warn(
            f"{path}.bore_radius = {bore!r} m {reason}", PlausibilityWarning, stacklevel=3
        )


DEFAULT_BORE_RATIO = 0.5
"""Bore radius over root radius of a gear whose ``bore_radius`` is left out: h_fi = r_f /
r_int = 2, a gear body on a shaft or a planet on its bearing (Tian's 2004 pair has 2.4
and 2.6).  The fillet foundation is the largest compliance of a tooth pair
(docs/potential_energy.md), so a case that knows its bores should type them."""

FOUNDATION_RATIO_RANGE = (1.4, 7.0)
"""The range of h_fi = r_f / r_int taken as valid for the fillet-foundation polynomials
(L*, M*, P*, Q*) that Sainsot, Velex & Duverger (2004) fitted to finite-element results.
The fit is quadratic in h_fi: beyond the upper edge it does not level off as a gear body
does but grows as h_fi^2 (P* from 12.5 at h_fi = 7 to 310 at 40), so a bore of a few
millimetres under a 40 mm root makes the tooth pair 10^2 .. 10^5 times too soft; Q*
passes its minimum near h_fi = 8 already.  The coefficient ranges that ROSS (petrobras/
ross, ``GearElementTVMS``) checks for the same fit put the upper edge at 6.8 .. 7.3
over theta_f = 0.03 .. 0.15 rad; the lower edge is the thin-rim end, where the fit stays
bounded.  A bore outside the range is taken at the range's edge
(:func:`foundation_bore_radius`), with a warning naming the parameter."""


def foundation_bore_radius(root_radius: float, bore_radius: float) -> tuple[float, str | None]:
    """The bore radius the fillet-foundation term uses, and why it differs from the typed one.

    Parameters
    ----------
    root_radius : float
        Root radius r_f [m], > 0.
    bore_radius : float
        Typed bore radius r_int [m], >= 0; 0 leaves the term out (returned unchanged).

    Returns
    -------
    bore : float
        ``bore_radius`` when h_fi = r_f / r_int lies in :data:`FOUNDATION_RATIO_RANGE`
        (or the bore is 0), else the bore at the range's nearer edge.
    reason : str or None
        None, or the rule the typed bore breaks and the value taken instead.
    """
    if bore_radius <= 0:
        return bore_radius, None
    low, high = FOUNDATION_RATIO_RANGE
    ratio = root_radius / bore_radius
    if low * (1 - 1e-9) <= ratio <= high * (1 + 1e-9):  # round-off of a bore typed as r_f/7
        return bore_radius, None
    edge = high if ratio > high else low
    taken = root_radius / edge
    return taken, (
        f"gives h_fi = r_f / r_int = {root_radius * 1e3:.4g} mm / {bore_radius * 1e3:.4g} mm = "
        f"{ratio:.3g}, outside the range {low:g} .. {high:g} of Sainsot et al.'s (2004) "
        f"fillet-foundation fit; the potential_energy law takes r_int = "
        f"{taken * 1e3:.4g} mm (h_fi = {edge:g}) instead"
    )


def ring_rim_ratio(root_radius: float, rim_radius: float) -> float:
    """h of a ring's rim for the fillet-foundation fit: r_o / r_f, the rim annulus's outer
    over its inner radius, as h_fi = r_f / r_int is a gear body's (clamped where the
    housing holds it, as the gear body at its bore), taken no lower than the fit's
    lower edge :data:`FOUNDATION_RATIO_RANGE` and no higher than its upper edge."""
    low, high = FOUNDATION_RATIO_RANGE
    return min(max(rim_radius / root_radius, low), high)


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
    radius : float or None
        Carrier radius r_c: the distance from the stage axis to each planet centre [m],
        > 0; derived from the gear geometry when left out (None; a typed NaN is an
        error).
    """

    radius: float | None = None

    def validate(self, path: str) -> None:
        super().validate(path)
        if self.radius is None:
            raise CaseError(
                f"{path}.radius must be given, or derived: give the sun and the planet a "
                "geometry (GearGeometry)"
            )
        require_positive(f"{path}.radius", self.radius)
        warn_if_implausible(f"{path}.radius", "radius", self.radius)
