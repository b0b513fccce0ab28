"""The case of a plain rotor: shafts, discs, bearings and couplings without a gearbox.

:class:`RotorCase` is a :class:`~pygear.model.case.Case` whose ``gearbox`` is None and
whose drivetrain has no gearbox, mounts, rotor or generator: ``pygear modal``,
``pygear campbell`` and ``pygear frf`` take it (docs/rotors.md).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from ..errors import CaseError
from .case import Case, RayleighDamping, Scene, require_file_name
from .drivetrain import Drivetrain

__all__ = ["RotorCase"]


@dataclass(frozen=True)
class RotorCase(Case):
    """A plain rotor: a :class:`~pygear.model.case.Case` whose drivetrain has no gearbox.

    Parameters
    ----------
    name : str
        Case name (the directory's).
    gearbox : None
        No gearbox; must stay None.
    drivetrain : Drivetrain
        The shafts, discs, bearings and couplings; its ``gearbox`` is None.
    scenes : tuple of Scene
        None by default: a rotor's analyses are commands (``pygear modal --speed``,
        ``pygear campbell``, ``pygear frf``), not scenes; ``pygear run`` refuses one.
    """

    gearbox: None = None
    formulation: str = "consistent"
    damping: RayleighDamping = dataclasses.field(default_factory=RayleighDamping)
    scenes: tuple[Scene, ...] = ()
    drivetrain: Drivetrain | None = None

    def validate(self) -> None:
        """Check the name, the damping and the drivetrain; raise :class:`CaseError`."""
        require_file_name("name", self.name)
        if self.gearbox is not None:
            raise CaseError("gearbox must be None for a RotorCase (use Case for a gearbox)")
        self.damping.validate("damping")
        if not isinstance(self.drivetrain, Drivetrain):
            raise CaseError(f"drivetrain must be a Drivetrain (got {self.drivetrain!r})")
        if self.drivetrain.gearbox is not None:
            raise CaseError("drivetrain.gearbox must be None in a RotorCase")
        self.drivetrain.validate("drivetrain")
