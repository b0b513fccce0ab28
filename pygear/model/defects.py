"""A weakened or missing tooth of a case or a scene, with its validation beside its
fields."""

from __future__ import annotations

import dataclasses
import numbers
from dataclasses import dataclass

from ..errors import CaseError
from .component_rules import is_finite_number
from .tooth_faults import ChippedTooth, RootCrack, Spall, check_fault_fields

__all__ = ["ToothDefect"]

_finite = is_finite_number


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
        if self.fault is not None:
            # the fault's own gear index is not read here: ``gear`` names the tooth
            check_fault_fields(dataclasses.replace(self.fault, gear=1), f"{path}.fault")
