"""Rotor components: discs anywhere on a shaft, bearing coefficient tables, and a case
that is a plain rotor (shafts, discs and bearings without a gearbox).

A :class:`Disc` is a rigid body at a node of a shaft (Friswell, Penny, Garvey & Lees,
*Dynamics of Rotating Machines*, 2010, §5.3): its mass in x, y, z, its diametral
inertia about x and y, its polar inertia about z, and the gyroscopic couple of its
polar inertia.  :class:`BearingCoefficients` gives a bearing (or a seal) the full 2 x 2
stiffness and damping of the shaft's lateral motion, cross-coupling included, as a
table over the shaft's speed: at any speed each coefficient is interpolated linearly
between the table's speeds and held at the end values outside them (one row gives
constant coefficients).  A plain rotor's case is a
:class:`~pygear.model.rotor_case.RotorCase`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import CaseError
from .components import require_non_negative, require_positive

__all__ = ["COEFFICIENTS", "BearingCoefficients", "Disc", "require_identifier"]

COEFFICIENTS = ("k_xx", "k_yy", "k_xy", "k_yx", "c_xx", "c_yy", "c_xy", "c_yx")
"""The coefficient columns of a :class:`BearingCoefficients` table."""


@dataclass(frozen=True)
class Disc:
    """A rigid disc at a node of a shaft.

    Parameters
    ----------
    name : str
        Disc name, a Python identifier (``--unbalance NAME:ME:PHASE`` names it).
    shaft : str
        Name of the shaft it sits on.
    position : float
        Axial position from the shaft's start [m]; must be a node of the shaft.
    mass : float
        Mass [kg], > 0.
    polar_inertia : float
        Inertia about the shaft axis [kg m^2], >= 0.
    diametral_inertia : float
        Inertia about a diameter through its centre [kg m^2], >= 0.
    """

    name: str
    shaft: str
    position: float
    mass: float
    polar_inertia: float
    diametral_inertia: float

    @classmethod
    def from_geometry(
        cls,
        name: str,
        shaft: str,
        position: float,
        density: float,
        width: float,
        outer_diameter: float,
        inner_diameter: float = 0.0,
    ) -> Disc:
        """A uniform annular disc: m = rho pi (D^2 - d^2) w / 4, I_p = m (D^2 + d^2) / 8,
        I_d = I_p / 2 + m w^2 / 12 (Friswell et al. 2010, eq. 5.2)."""
        for label, value in (
            ("density", density),
            ("width", width),
            ("outer_diameter", outer_diameter),
        ):
            require_positive(f"disc {name!r} {label}", value)
        require_non_negative(f"disc {name!r} inner_diameter", inner_diameter)
        if inner_diameter >= outer_diameter:
            raise CaseError(f"disc {name!r} inner_diameter must be below outer_diameter")
        mass = density * math.pi * (outer_diameter**2 - inner_diameter**2) * width / 4.0
        polar = mass * (outer_diameter**2 + inner_diameter**2) / 8.0
        return cls(name, shaft, position, mass, polar, polar / 2.0 + mass * width**2 / 12.0)

    def validate(self, path: str) -> None:
        require_identifier(f"{path}.name", self.name)
        require_positive(f"{path}.mass", self.mass)
        require_non_negative(f"{path}.polar_inertia", self.polar_inertia)
        require_non_negative(f"{path}.diametral_inertia", self.diametral_inertia)


@dataclass(frozen=True)
class BearingCoefficients:
    """Lateral stiffness and damping of a bearing or seal over the shaft's speed.

    Every coefficient is a tuple with one value per entry of ``speeds``; a coefficient
    left empty is zero at every speed.  Force on the shaft: ``-K (x, y) - C (x', y')``
    with ``K = [[k_xx, k_xy], [k_yx, k_yy]]`` and C alike.

    Parameters
    ----------
    speeds : tuple of float
        Speeds of the bearing's shaft [rpm], increasing, at least one.
    k_xx, k_yy : tuple of float
        Direct stiffness [N/m], each >= 0.
    k_xy, k_yx : tuple of float
        Cross-coupled stiffness [N/m], any sign.
    c_xx, c_yy : tuple of float
        Direct damping [N s/m], each >= 0.
    c_xy, c_yx : tuple of float
        Cross-coupled damping [N s/m], any sign.
    """

    speeds: tuple[float, ...]
    k_xx: tuple[float, ...] = ()
    k_yy: tuple[float, ...] = ()
    k_xy: tuple[float, ...] = ()
    k_yx: tuple[float, ...] = ()
    c_xx: tuple[float, ...] = ()
    c_yy: tuple[float, ...] = ()
    c_xy: tuple[float, ...] = ()
    c_yx: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        for name in ("speeds", *COEFFICIENTS):
            value = getattr(self, name)
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                value = (value,)
            if isinstance(value, (list, np.ndarray)):
                value = tuple(float(v) for v in value)
            object.__setattr__(self, name, value)

    def validate(self, path: str) -> None:
        speeds = self._column(path, "speeds", self.speeds)
        if speeds.size < 1:
            raise CaseError(f"{path}.speeds must hold at least one speed [rpm]")
        if np.any(np.diff(speeds) <= 0):
            raise CaseError(f"{path}.speeds must increase strictly (got {self.speeds!r})")
        for name in COEFFICIENTS:
            values = self._column(path, name, getattr(self, name))
            if values.size not in (0, speeds.size):
                raise CaseError(
                    f"{path}.{name} must hold one value per speed ({speeds.size}) or none "
                    f"(got {values.size})"
                )
            if name in ("k_xx", "k_yy", "c_xx", "c_yy") and np.any(values < 0):
                raise CaseError(f"{path}.{name} must be >= 0 (got {getattr(self, name)!r})")

    @staticmethod
    def _column(path: str, name: str, value: object) -> np.ndarray:
        try:
            array = np.asarray(value, dtype=float).ravel()
        except (TypeError, ValueError):
            raise CaseError(f"{path}.{name} must be a tuple of numbers (got {value!r})") from None
        if not np.all(np.isfinite(array)):
            raise CaseError(f"{path}.{name} must hold finite numbers (got {value!r})")
        return array

    def at(self, speed_rpm: float) -> tuple[np.ndarray, np.ndarray]:
        """The 2 x 2 stiffness [N/m] and damping [N s/m] at a speed [rpm] (linear between
        the table's speeds, the end values outside them)."""
        speeds = np.asarray(self.speeds, dtype=float)
        value = {}
        for name in COEFFICIENTS:
            column = np.asarray(getattr(self, name), dtype=float)
            value[name] = 0.0 if column.size == 0 else float(np.interp(speed_rpm, speeds, column))
        stiffness = np.array([[value["k_xx"], value["k_xy"]], [value["k_yx"], value["k_yy"]]])
        damping = np.array([[value["c_xx"], value["c_xy"]], [value["c_yx"], value["c_yy"]]])
        return stiffness, damping

    @property
    def speed_dependent(self) -> bool:
        """True when some coefficient changes over the table."""
        return any(len(set(getattr(self, name))) > 1 for name in COEFFICIENTS)


def require_identifier(path: str, name: object) -> None:
    """Raise :class:`CaseError` unless ``name`` is a Python identifier."""
    if not isinstance(name, str) or not name.isidentifier():
        raise CaseError(f"{path} must be an identifier (got {name!r})")
