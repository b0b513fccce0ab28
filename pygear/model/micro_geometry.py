"""Micro-geometry of a gear's flanks: intended modifications, manufacturing deviations and
the misalignment of its axis in its meshes, for the loaded tooth contact analysis
(:mod:`pygear.analysis.contact.ltca`; the documentation's contact page).

Every amount is a length [m] along the transverse line of action (normal to the involute
in the transverse plane), where ISO 1328-1 measures profile and helix deviations.
Signs: a *modification* removes material (a positive amount opens the gap); a
*deviation* follows ISO 1328-1/ISO 21771: positive means material added (a positive
profile slope deviation f_Halpha adds material towards the tip, a positive helix slope
deviation f_Hbeta towards the face end at y = b, a positive single pitch deviation
f_pt moves the flank towards its mate).  The face coordinate y runs from 0 to b from
the end of the face that enters mesh first.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import CaseError
from .component_rules import is_finite_number

__all__ = [
    "Deviations",
    "EndRelief",
    "Misalignment",
    "Modifications",
    "ProfileRelief",
    "check_modifications",
]

SHAPES = ("linear", "parabolic")
"""Shapes of a relief: the amount grows linearly or as a square from its start."""

MAX_AMOUNT = 1e-3
"""Largest amount of any modification or deviation [m]: micro-geometry is micrometres;
1 mm is a typed unit error (micrometres given as metres times 1e3)."""


def _length(path: str, value: object, *, signed: bool = False, limit: float = MAX_AMOUNT) -> None:
    ok = is_finite_number(value) and (signed or value >= 0) and abs(value) <= limit
    if not ok:
        rule = f"|value| <= {limit:g} m" if signed else f"0 <= value <= {limit:g} m"
        raise CaseError(f"{path} must be a finite length with {rule} (got {value!r})")


def _shape(path: str, value: object) -> None:
    if value not in SHAPES:
        raise CaseError(f"{path} must be one of {', '.join(SHAPES)} (got {value!r})")


@dataclass(frozen=True)
class ProfileRelief:
    """Tip or root relief of the profile.

    Parameters
    ----------
    amount : float
        C_a (tip) or C_f (root) [m]: material removed at the tip (root form) circle.
    start_diameter : float or None
        Diameter where the relief starts [m] (tip relief: towards the tip from here; root
        relief: towards the root).
    start_roll_angle_deg : float or None
        The start as a roll angle xi = s / r_b [deg] instead (exactly one of the two).
    shape : str
        ``linear`` or ``parabolic`` in the roll length from the start.
    """

    amount: float
    start_diameter: float | None = None
    start_roll_angle_deg: float | None = None
    shape: str = "linear"

    def validate(self, path: str) -> None:
        _length(f"{path}.amount", self.amount)
        _shape(f"{path}.shape", self.shape)
        if (self.start_diameter is None) == (self.start_roll_angle_deg is None):
            raise CaseError(
                f"{path}: give exactly one of start_diameter and start_roll_angle_deg "
                f"(got {self.start_diameter!r} and {self.start_roll_angle_deg!r})"
            )
        if self.start_diameter is not None:
            if not (is_finite_number(self.start_diameter) and self.start_diameter > 0):
                raise CaseError(
                    f"{path}.start_diameter must be a positive finite diameter [m] "
                    f"(got {self.start_diameter!r})"
                )
        elif not (is_finite_number(self.start_roll_angle_deg) and self.start_roll_angle_deg >= 0):
            raise CaseError(
                f"{path}.start_roll_angle_deg must be a finite angle >= 0 deg "
                f"(got {self.start_roll_angle_deg!r})"
            )

    def start_roll_length(self, base_radius: float) -> float:
        """Roll length s = sqrt(r^2 - r_b^2) (or r_b xi) where the relief starts [m]."""
        if self.start_roll_angle_deg is not None:
            return base_radius * math.radians(self.start_roll_angle_deg)
        radius = self.start_diameter / 2
        return math.sqrt(max(radius * radius - base_radius * base_radius, 0.0))


@dataclass(frozen=True)
class EndRelief:
    """Relief of both face ends.

    Parameters
    ----------
    amount : float
        C_I = C_II [m] removed at each end of the face.
    length : float
        Length along the face over which it grows from 0 [m], > 0.
    shape : str
        ``linear`` or ``parabolic``.
    """

    amount: float
    length: float
    shape: str = "linear"

    def validate(self, path: str) -> None:
        _length(f"{path}.amount", self.amount)
        _shape(f"{path}.shape", self.shape)
        if not (is_finite_number(self.length) and 0 < self.length <= 10.0):
            raise CaseError(f"{path}.length must be a length in (0, 10] m (got {self.length!r})")


@dataclass(frozen=True)
class Deviations:
    """Manufacturing deviations of one gear (ISO 1328-1 signs: positive adds material).

    Parameters
    ----------
    pitch : tuple of float
        Single pitch deviations f_pt [m] of teeth 0, 1, ... (cumulated along the gear to
        each tooth's position; an empty tuple: none).  Either empty or one per tooth.
    runout : float
        Eccentricity e of the pitch circle [m] (radial runout F_r ~ 2 e).
    runout_phase_deg : float
        Angle of the eccentricity from tooth 0 [deg].
    profile_slope : float
        f_Halpha [m] over the active profile, positive adding material towards the tip.
    helix_slope : float
        f_Hbeta [m] over the face, positive adding material towards y = b.
    """

    pitch: tuple[float, ...] = ()
    runout: float = 0.0
    runout_phase_deg: float = 0.0
    profile_slope: float = 0.0
    helix_slope: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.pitch, list):
            object.__setattr__(self, "pitch", tuple(self.pitch))

    def validate(self, path: str) -> None:
        if not isinstance(self.pitch, tuple):
            raise CaseError(f"{path}.pitch must be a sequence of lengths [m] (got {self.pitch!r})")
        for index, value in enumerate(self.pitch):
            _length(f"{path}.pitch[{index}]", value, signed=True)
        _length(f"{path}.runout", self.runout)
        if not is_finite_number(self.runout_phase_deg):
            raise CaseError(
                f"{path}.runout_phase_deg must be a finite angle [deg] "
                f"(got {self.runout_phase_deg!r})"
            )
        _length(f"{path}.profile_slope", self.profile_slope, signed=True)
        _length(f"{path}.helix_slope", self.helix_slope, signed=True)


@dataclass(frozen=True)
class Misalignment:
    """Tilt of this gear's axis relative to its mate's in every mesh it takes part in.

    Parameters
    ----------
    in_plane : float
        Tilt in the plane of the axes [rad] (ISO 6336-1's f_Sigma_delta / b).
    out_of_plane : float
        Tilt out of the plane of the axes [rad] (f_Sigma_beta / b).
    mismatch : float
        A mismatch f_ma over the face in the plane of action [m], added to the tilts'
        b (gamma_in sin(alpha_wt) + gamma_out cos(alpha_wt)).
    """

    in_plane: float = 0.0
    out_of_plane: float = 0.0
    mismatch: float = 0.0

    def validate(self, path: str) -> None:
        for name in ("in_plane", "out_of_plane"):
            value = getattr(self, name)
            if not (is_finite_number(value) and abs(value) <= 0.05):
                raise CaseError(
                    f"{path}.{name} must be a tilt in radians with |value| <= 0.05 "
                    f"(got {value!r})"
                )
        _length(f"{path}.mismatch", self.mismatch, signed=True)

    def separation_slope(self, pressure_angle: float) -> float:
        """Gap change per face length in the plane of action [m/m] from the tilts."""
        return self.in_plane * math.sin(pressure_angle) + self.out_of_plane * math.cos(
            pressure_angle
        )


@dataclass(frozen=True)
class Modifications:
    """Micro-geometry of one gear's working flanks (``Gear(modifications=...)``).

    Parameters
    ----------
    tip_relief, root_relief : ProfileRelief or None
        Profile reliefs.
    crowning : float
        C_beta [m]: parabolic, removing C_beta at each face end relative to the middle.
    end_relief : EndRelief or None
        Relief of both face ends.
    helix_slope : float
        Intended helix slope modification f_Hbeta [m] over the face: material removed
        at y = b relative to y = 0 (a negative value removes it at y = 0).
    deviations : Deviations or None
        Manufacturing deviations.
    misalignment : Misalignment or None
        Tilt of this gear's axis in its meshes.
    """

    tip_relief: ProfileRelief | None = None
    root_relief: ProfileRelief | None = None
    crowning: float = 0.0
    end_relief: EndRelief | None = None
    helix_slope: float = 0.0
    deviations: Deviations | None = None
    misalignment: Misalignment | None = None

    def validate(self, path: str) -> None:
        kinds = {
            "tip_relief": ProfileRelief,
            "root_relief": ProfileRelief,
            "end_relief": EndRelief,
            "deviations": Deviations,
            "misalignment": Misalignment,
        }
        for name, kind in kinds.items():
            value = getattr(self, name)
            if value is None:
                continue
            if not isinstance(value, kind):
                raise CaseError(
                    f"{path}.{name} must be a {kind.__name__} or None (got {value!r})"
                )
            value.validate(f"{path}.{name}")
        _length(f"{path}.crowning", self.crowning)
        _length(f"{path}.helix_slope", self.helix_slope, signed=True)


def check_modifications(path: str, value: object) -> None:
    """Raise :class:`CaseError` unless ``value`` is None or a valid :class:`Modifications`."""
    if value is None:
        return
    if not isinstance(value, Modifications):
        raise CaseError(f"{path} must be a Modifications or None (got {value!r})")
    value.validate(path)
