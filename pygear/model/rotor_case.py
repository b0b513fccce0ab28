"""The case of a plain rotor: shafts, discs, bearings and couplings without a gearbox.

:class:`RotorCase` is a :class:`~pygear.model.case.Case` whose ``gearbox`` is None and
whose drivetrain has no gearbox, mounts, rotor or generator: ``pygear modal``,
``pygear campbell`` and ``pygear frf`` take it, and ``pygear run`` its transient
scenes (:class:`~pygear.model.rotor_transient.RotorScene`: run-ups through critical
speeds, constant-speed runs; docs/rotors.md).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from ..errors import CaseError
from .case import Case, RayleighDamping, require_file_name
from .drivetrain import Drivetrain
from .rotor_transient import RotorScene

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
    scenes : tuple of RotorScene
        Transient scenes (``pygear run``): a speed profile, unbalances at discs.  The
        rotor's other analyses are commands (``pygear modal --speed``, ``pygear
        campbell``, ``pygear frf``).
    """

    gearbox: None = None
    formulation: str = "consistent"
    damping: RayleighDamping = dataclasses.field(default_factory=RayleighDamping)
    scenes: tuple[RotorScene, ...] = ()
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
        names = [scene.name for scene in self.scenes]
        discs = {disc.name for disc in self.drivetrain.discs}
        for k, scene in enumerate(self.scenes):
            path = f"scenes[{k}]"
            if not isinstance(scene, RotorScene):
                raise CaseError(f"{path} must be a RotorScene (got {type(scene).__name__})")
            require_file_name(f"{path}.name", scene.name)
            if names.count(scene.name) > 1:
                raise CaseError(f"{path}.name {scene.name!r} is not unique")
            scene.validate(f"scenes.{scene.name}")
            for u, unbalance in enumerate(scene.run.unbalances):
                if unbalance.disc not in discs:
                    raise CaseError(
                        f"scenes.{scene.name}.run.unbalances[{u}].disc {unbalance.disc!r} is "
                        f"not a disc of the drivetrain (discs: {', '.join(sorted(discs))})"
                    )
