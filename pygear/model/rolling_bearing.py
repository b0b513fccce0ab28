"""Rolling-element bearings as geometry: elements, diameters, contact angle, clearance,
material, and the defects a bearing may carry.

:class:`RollingBearing` describes one bearing (Harris & Kotzalas, *Rolling Bearing
Analysis*, 5th ed., 2007): ball or roller, ``elements`` Z of diameter d on the pitch
diameter D, contact angle alpha, diametral clearance P_d (negative: preload), and which
ring turns with the body it carries.  Its load-deflection law, load distribution and
characteristic frequencies are computed in :mod:`pygear.analysis.condition.bearing_load`
and :mod:`pygear.analysis.condition.bearing_kinematics`.

:class:`BearingDefect` is a localized defect (a spall on the outer or inner race or on
one rolling element: angular position, width, depth, entry/exit profile);
:class:`DistributedFault` a distributed one (race waviness, wear clearance).

Validation follows :mod:`pygear.model.plausibility`: an impossible value is a
:class:`~pygear.errors.CaseError` naming the parameter and the rule; a possible value
outside any real bearing (most often mm typed as m) is a
:class:`~pygear.model.plausibility.PlausibilityWarning`.  The bearing ranges live in
:data:`BEARING_PLAUSIBLE` beside the class until they join the shared table.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from ..errors import CaseError
from .component_rules import require_non_negative, require_positive
from .plausibility import PlausibilityWarning, PlausibleRange
from .values import is_finite_number, is_whole_number

__all__ = [
    "BEARING_PLAUSIBLE",
    "BEARING_TYPES",
    "DEFECT_LOCATIONS",
    "DEFECT_PROFILES",
    "RING_TURNING",
    "BearingDefect",
    "DistributedFault",
    "RollingBearing",
    "rolling_bearings_of",
]

BEARING_TYPES = ("ball", "roller")
"""Point contact (load-deflection exponent 3/2) or line contact (10/9)."""
RING_TURNING = ("inner", "outer")
"""The ring that turns with the body a bearing carries: ``inner`` for a shaft in a
housing, ``outer`` for a planet on its pin (the pin is the inner ring, fixed to the
carrier)."""
DEFECT_LOCATIONS = ("outer", "inner", "element")
DEFECT_PROFILES = ("rectangular", "cosine")
"""``rectangular``: the element drops the full depth at the entry edge and climbs out at
the exit edge (a step, the impulsive spall of Randall & Antoni 2011); ``cosine``: a
smooth dent, depth ``h (1 + cos(2 pi s / w)) / 2`` over its width ``w``."""

BEARING_PLAUSIBLE: dict[str, PlausibleRange] = {
    "pitch_diameter": PlausibleRange(
        2e-3,
        5.0,
        "m",
        "miniature bearings 3 mm to slewing rings ~4 m (NREL 5 MW planet "
        "bearing 0.5 m); a value in mm typed as m is 1000 times too large",
    ),
    "element_ratio": PlausibleRange(
        0.05, 0.45, "-", "d / D of catalogue bearings 0.1 .. 0.35 (SKF 6205: 0.203)"
    ),
    "clearance_ratio": PlausibleRange(
        0.0,
        5e-3,
        "-",
        "|P_d| / D: ISO 5753 radial clearances are 1e-4 .. 2e-3 of the "
        "pitch diameter; above 5e-3 a worn-out bearing or a unit mistake",
    ),
    "elements": PlausibleRange(4, 100, "-", "catalogue bearings hold 6 .. 60 elements"),
}
"""Quantity -> plausible range of the bearing's geometry (same form as
:data:`pygear.model.plausibility.PLAUSIBLE`)."""


def _warn_if_implausible(path: str, quantity: str, value: float) -> None:
    limits = BEARING_PLAUSIBLE[quantity]
    if limits.low <= value <= limits.high:
        return
    shown = f"{value!r}" if limits.unit == "-" else f"{value!r} {limits.unit}"
    warnings.warn(
        f"{path} = {shown} is outside the plausible range {limits.low:g} .. {limits.high:g} "
        f"{limits.unit} ({limits.reason})",
        PlausibilityWarning,
        stacklevel=4,
    )


def _require_choice(path: str, value: object, choices: tuple[str, ...]) -> None:
    if value not in choices:
        raise CaseError(f"{path} must be one of {', '.join(choices)} (got {value!r})")


@dataclass(frozen=True)
class RollingBearing:
    """A rolling-element bearing's geometry and material.

    Parameters
    ----------
    name : str
        Bearing name (``"PL-A"``).
    type : str
        ``"ball"`` (point contact, Q = K delta^(3/2)) or ``"roller"`` (line contact,
        Q = K delta^(10/9)).
    elements : int
        Number of rolling elements Z per row, >= 3.
    pitch_diameter : float
        D, diameter of the element centres [m].
    element_diameter : float
        d, ball or roller diameter [m], 0 < d < D.
    contact_angle_deg : float
        alpha [deg], 0 <= alpha < 90 (0 for a radial bearing).
    diametral_clearance : float
        P_d [m]: the free radial play of the inner ring is P_d / 2 each way; negative
        for a preload (interference).  |P_d| < d.
    roller_length : float or None
        Effective roller length l [m]; required for rollers, None for balls.
    inner_conformity, outer_conformity : float
        Groove radius over ball diameter f = r / d of a ball bearing's races [-], > 0.5
        (Harris: 0.515 .. 0.53 typical).
    rows : int
        Rows of elements sharing the load (a double-row bearing: 2).
    young_modulus : float
        Elastic modulus of rings and elements [Pa] (bearing steel 2.075e11).
    poisson_ratio : float
        Poisson's ratio [-], 0 <= nu < 0.5 (steel 0.3).
    location : str
        The body it carries: ``"<stage>.planet"`` for a planet bearing (outer ring the
        planet's bore, inner ring the carrier's pin) or a member such as
        ``"parallel.output_gear"`` (inner ring on the shaft, outer in the housing).
    turning_ring : str or None
        The ring that turns with that body (:data:`RING_TURNING`); default ``"outer"``
        for a planet bearing, ``"inner"`` otherwise.
    defects : tuple of BearingDefect
        Localized defects the bearing carries in a transient run with the
        ``rolling_bearing_contact`` effect (race spalls; the kernel takes their
        rectangular depth).
    faults : tuple of DistributedFault
        Distributed faults (race waviness, wear) it carries in such a run.
    contact_damping : float
        c_c, viscous damping of each rolling-element contact [N s/m], >= 0: the
        lubricant film and the contact's hysteresis, acting on the contact's approach
        rate only while that element is loaded (kernel runs with the
        ``rolling_bearing_contact`` effect).  0 (default): undamped contacts.  For a
        damping ratio zeta of a contact of linearised stiffness k_c carrying a mass m:
        c_c = 2 zeta sqrt(k_c m) (docs/bearings.md).
    """

    name: str
    type: str
    elements: int
    pitch_diameter: float
    element_diameter: float
    contact_angle_deg: float = 0.0
    diametral_clearance: float = 0.0
    roller_length: float | None = None
    inner_conformity: float = 0.52
    outer_conformity: float = 0.52
    rows: int = 1
    young_modulus: float = 2.075e11
    poisson_ratio: float = 0.3
    location: str = ""
    turning_ring: str | None = None
    defects: tuple[BearingDefect, ...] = ()
    faults: tuple[DistributedFault, ...] = ()
    contact_damping: float = 0.0

    def __post_init__(self) -> None:
        self.validate(f"rolling_bearings[{self.name!r}]")

    @property
    def planet(self) -> bool:
        """True for a planet bearing (``location`` ``"<stage>.planet"``)."""
        return self.location.endswith(".planet")

    @property
    def turning(self) -> str:
        """The ring turning with the carried body (``turning_ring`` or its default)."""
        if self.turning_ring is not None:
            return self.turning_ring
        return "outer" if self.planet else "inner"

    @property
    def load_exponent(self) -> float:
        """n of Q = K delta^n: 3/2 for point contact, 10/9 for line contact."""
        return 1.5 if self.type == "ball" else 10.0 / 9.0

    @property
    def gamma(self) -> float:
        """gamma = d cos(alpha) / D."""
        return (
            self.element_diameter
            * math.cos(math.radians(self.contact_angle_deg))
            / self.pitch_diameter
        )

    def validate(self, path: str) -> None:
        """Raise :class:`CaseError` naming the first parameter that breaks its rule;
        warn (:class:`PlausibilityWarning`) for a value outside any real bearing."""
        if not isinstance(self.name, str) or not self.name:
            raise CaseError(f"{path}.name must be a non-empty string (got {self.name!r})")
        _require_choice(f"{path}.type", self.type, BEARING_TYPES)
        if not is_whole_number(self.elements) or self.elements < 3:
            raise CaseError(f"{path}.elements must be a whole number >= 3 (got {self.elements!r})")
        if not is_whole_number(self.rows) or self.rows < 1:
            raise CaseError(f"{path}.rows must be a whole number >= 1 (got {self.rows!r})")
        require_positive(f"{path}.pitch_diameter", self.pitch_diameter)
        require_positive(f"{path}.element_diameter", self.element_diameter)
        if self.element_diameter >= self.pitch_diameter:
            raise CaseError(
                f"{path}.element_diameter must be below pitch_diameter "
                f"(got d = {self.element_diameter!r} m >= D = {self.pitch_diameter!r} m)"
            )
        angle = self.contact_angle_deg
        if not is_finite_number(angle) or not 0.0 <= angle < 90.0:
            raise CaseError(f"{path}.contact_angle_deg must be in [0, 90) degrees (got {angle!r})")
        clearance = self.diametral_clearance
        if not is_finite_number(clearance) or abs(clearance) >= self.element_diameter:
            raise CaseError(
                f"{path}.diametral_clearance must be finite with |P_d| below the element "
                f"diameter {self.element_diameter!r} m (got {clearance!r})"
            )
        if self.type == "roller":
            if self.roller_length is None:
                raise CaseError(f"{path}.roller_length must be given for a roller bearing")
            require_positive(f"{path}.roller_length", self.roller_length)
        elif self.roller_length is not None:
            raise CaseError(f"{path}.roller_length must be None for a ball bearing")
        for name in ("inner_conformity", "outer_conformity"):
            value = getattr(self, name)
            if not is_finite_number(value) or not 0.5 < value <= 5.0:
                raise CaseError(
                    f"{path}.{name} must be in (0.5, 5] (groove radius over ball diameter, "
                    f"got {value!r})"
                )
        require_positive(f"{path}.young_modulus", self.young_modulus)
        nu = self.poisson_ratio
        if not is_finite_number(nu) or not 0.0 <= nu < 0.5:
            raise CaseError(f"{path}.poisson_ratio must be in [0, 0.5) (got {nu!r})")
        if not isinstance(self.location, str):
            raise CaseError(f"{path}.location must be a string (got {self.location!r})")
        if self.turning_ring is not None:
            _require_choice(f"{path}.turning_ring", self.turning_ring, RING_TURNING)
        damping = self.contact_damping
        if not is_finite_number(damping) or damping < 0.0:
            raise CaseError(
                f"{path}.contact_damping must be finite and >= 0 N s/m (got {damping!r})"
            )
        for n, defect in enumerate(self.defects or ()):
            if not isinstance(defect, BearingDefect):
                raise CaseError(f"{path}.defects[{n}] must be a BearingDefect (got {defect!r})")
            defect.validate(f"{path}.defects[{n}]", self)
        for n, fault in enumerate(self.faults or ()):
            if not isinstance(fault, DistributedFault):
                raise CaseError(f"{path}.faults[{n}] must be a DistributedFault (got {fault!r})")
            fault.validate(f"{path}.faults[{n}]")
        _warn_if_implausible(f"{path}.pitch_diameter", "pitch_diameter", self.pitch_diameter)
        _warn_if_implausible(
            f"{path}.element_diameter / pitch_diameter",
            "element_ratio",
            self.element_diameter / self.pitch_diameter,
        )
        _warn_if_implausible(
            f"{path}.|diametral_clearance| / pitch_diameter",
            "clearance_ratio",
            abs(clearance) / self.pitch_diameter,
        )
        _warn_if_implausible(f"{path}.elements", "elements", self.elements)


@dataclass(frozen=True)
class BearingDefect:
    """A localized defect (spall) on a race or a rolling element.

    Parameters
    ----------
    location : str
        ``"outer"`` race, ``"inner"`` race or rolling ``"element"``.
    width : float
        Extent along the rolling direction [m] (arc length on the race, or on the
        element's surface), > 0 and below the element spacing pi D / Z.
    depth : float
        Depth [m], > 0.  An element of diameter d drops into a defect of width w at
        most d/2 - sqrt(d^2/4 - w^2/4) (it spans the gap): the smaller value acts.
    angle_deg : float
        Position of the defect's centre on its ring [deg], in the ring's own frame,
        measured from the load direction at t = 0 (a race defect); the element's spin
        angle at t = 0 (an element defect, 0: touching the outer race).
    element : int
        The element carrying an ``element`` defect (0 .. Z - 1).
    profile : str
        Entry/exit profile, :data:`DEFECT_PROFILES`.
    planet : int or None
        For a planet bearing in a transient run: the planet (1-based) whose bearing
        carries the defect; None, every planet's.
    """

    location: str
    width: float
    depth: float
    angle_deg: float = 0.0
    element: int = 0
    profile: str = "rectangular"
    planet: int | None = None

    def __post_init__(self) -> None:
        self.validate("defect")

    def validate(self, path: str, bearing: RollingBearing | None = None) -> None:
        """Raise :class:`CaseError` naming the first parameter that breaks its rule
        (with ``bearing``: also the rules relative to its geometry)."""
        _require_choice(f"{path}.location", self.location, DEFECT_LOCATIONS)
        _require_choice(f"{path}.profile", self.profile, DEFECT_PROFILES)
        require_positive(f"{path}.width", self.width)
        require_positive(f"{path}.depth", self.depth)
        if not is_finite_number(self.angle_deg):
            raise CaseError(f"{path}.angle_deg must be a finite angle (got {self.angle_deg!r})")
        if not is_whole_number(self.element) or self.element < 0:
            raise CaseError(f"{path}.element must be a whole number >= 0 (got {self.element!r})")
        if self.planet is not None and (not is_whole_number(self.planet) or self.planet < 1):
            raise CaseError(
                f"{path}.planet must be a whole number >= 1 or None (got {self.planet!r})"
            )
        if bearing is None:
            return
        spacing = math.pi * bearing.pitch_diameter / bearing.elements
        if self.width >= spacing:
            raise CaseError(
                f"{path}.width must be below the element spacing pi D / Z = {spacing:.4g} m "
                f"(got {self.width!r}): a wider defect is a distributed fault"
            )
        if self.location == "element" and self.element >= bearing.elements:
            raise CaseError(
                f"{path}.element must be below the bearing's {bearing.elements} elements "
                f"(got {self.element!r})"
            )
        if self.depth > 0.5 * bearing.element_diameter:
            raise CaseError(
                f"{path}.depth must be at most half the element diameter "
                f"{0.5 * bearing.element_diameter:.4g} m (got {self.depth!r})"
            )


@dataclass(frozen=True)
class DistributedFault:
    """A distributed fault of a race: waviness and wear.

    Parameters
    ----------
    race : str
        ``"outer"`` or ``"inner"``.
    waviness_order : int
        Lobes around the race (0: none).  Order Z (and its multiples) on the race a
        load zone passes excites the varying-compliance line (Harris & Kotzalas,
        vol. 2, ch. 8).
    waviness_amplitude : float
        Radial amplitude of the waviness [m], >= 0.
    waviness_phase_deg : float
        Angle of a crest from the load direction at t = 0, in the race's frame [deg].
    wear : float
        Uniform wear of the race's radius [m], >= 0: adds 2 wear to the diametral
        clearance.
    """

    race: str
    waviness_order: int = 0
    waviness_amplitude: float = 0.0
    waviness_phase_deg: float = 0.0
    wear: float = 0.0

    def __post_init__(self) -> None:
        self.validate("fault")

    def validate(self, path: str) -> None:
        """Raise :class:`CaseError` naming the first parameter that breaks its rule."""
        _require_choice(f"{path}.race", self.race, RING_TURNING)
        if not is_whole_number(self.waviness_order) or self.waviness_order < 0:
            raise CaseError(
                f"{path}.waviness_order must be a whole number >= 0 (got {self.waviness_order!r})"
            )
        require_non_negative(f"{path}.waviness_amplitude", self.waviness_amplitude)
        require_non_negative(f"{path}.wear", self.wear)
        phase = self.waviness_phase_deg
        if not is_finite_number(phase):
            raise CaseError(f"{path}.waviness_phase_deg must be a finite angle (got {phase!r})")


def rolling_bearings_of(case: object) -> tuple[RollingBearing, ...]:
    """The rolling bearings a case carries: its ``rolling_bearings`` attribute (a
    sequence of :class:`RollingBearing`), empty when it has none.

    Raises
    ------
    CaseError
        An item that is not a :class:`RollingBearing`, or two with one name.
    """
    bearings = tuple(getattr(case, "rolling_bearings", None) or ())
    for n, bearing in enumerate(bearings):
        if not isinstance(bearing, RollingBearing):
            raise CaseError(
                f"rolling_bearings[{n}] must be a RollingBearing (got {type(bearing).__name__})"
            )
    names = [b.name for b in bearings]
    if len(set(names)) != len(names):
        raise CaseError(f"rolling_bearings: names must be unique (got {names})")
    return bearings
