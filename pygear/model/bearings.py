"""Bearings of a gearbox: a central member's to the housing and a planet's on the
carrier, each with its validation beside its fields."""

from __future__ import annotations

from dataclasses import dataclass, fields

from .component_rules import require_non_negative

__all__ = ["Bearing", "PlanetBearing"]


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
