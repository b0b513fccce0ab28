"""Bearing defects as the fault axis of a dataset (``pygear dataset --faults
outer_race_depth=A:B:N`` or ``inner_race_depth=...``).

A record's severity is the depth [m] of one spall on a race of one rolling bearing of
the case (``--bearing``; on a planet bearing, of planet ``--planet``), at ``--defect-angle``
on its ring and ``--defect-width`` wide; depth 0 is the healthy bearing.  The record's
scene gains the ``rolling_bearing_contact`` effect, so every rolling bearing of the
case is a Hertz contact in the run and the defect a depth the kernel takes off the
elements passing it (docs/bearings.md).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from ..errors import CaseError
from ..model.case import Case, Scene, replace_parameter
from ..model.rolling_bearing import BearingDefect, RollingBearing, rolling_bearings_of

__all__ = ["BEARING_FAULT_KINDS", "BearingFault", "bearing_fault", "with_bearing_defect"]

BEARING_FAULT_KINDS = {"outer_race_depth": "outer", "inner_race_depth": "inner"}
"""Dataset fault kinds on a bearing race, and the race each names."""

BEARING_EFFECT = "rolling_bearing_contact"


@dataclass(frozen=True)
class BearingFault:
    """Where a dataset's bearing defect sits and how wide it is."""

    bearing: str
    race: str
    planet: int | None
    angle_deg: float
    width: float

    def defect(self, depth: float) -> BearingDefect:
        """The defect at ``depth`` [m]."""
        return BearingDefect(
            self.race, width=self.width, depth=depth, angle_deg=self.angle_deg, planet=self.planet
        )

    def labels(self) -> dict:
        """The record labels that say where the defect is."""
        return {
            "fault_bearing": self.bearing,
            "fault_planet": self.planet or 0,
            "defect_angle_deg": self.angle_deg,
            "defect_width": self.width,
        }


def bearing_fault(
    case: Case,
    kind: str,
    severities: tuple[float, ...],
    *,
    stage: str,
    bearing: str | None,
    planet: int | None,
    angle_deg: float,
    width: float | None,
) -> BearingFault:
    """Check a bearing-fault request; raise :class:`CaseError` naming the option.

    ``bearing`` defaults to the first rolling bearing of ``stage`` (the sensor's), a
    planet bearing's ``planet`` to 1, ``width`` to a tenth of the element diameter.
    """
    bearings = rolling_bearings_of(case)
    if bearing is None:
        chosen = [b for b in bearings if b.location.partition(".")[0] == stage]
        if not chosen:
            raise CaseError(
                f"--faults {kind}: case {case.name!r} has no rolling bearing in stage "
                f"{stage!r}; give --bearing (rolling bearings: "
                f"{', '.join(b.name for b in bearings) or 'none'})"
            )
        found: RollingBearing = chosen[0]
    else:
        named = [b for b in bearings if b.name == bearing]
        if not named:
            raise CaseError(
                f"--bearing {bearing!r} is not a rolling bearing of case {case.name!r} "
                f"(rolling bearings: {', '.join(b.name for b in bearings) or 'none'})"
            )
        found = named[0]
    if any(not (math.isfinite(s) and s >= 0.0) for s in severities):
        raise CaseError(f"--faults {kind}: depths are lengths >= 0 in m")
    if planet is not None and not found.planet:
        raise CaseError(f"--planet: bearing {found.name!r} is not a planet bearing")
    if planet is not None and planet < 1:
        raise CaseError(f"--planet must be a whole number >= 1 (got {planet})")
    if not math.isfinite(angle_deg):
        raise CaseError(f"--defect-angle must be a finite angle in deg (got {angle_deg!r})")
    if width is None:
        width = 0.1 * found.element_diameter
    fault = BearingFault(
        found.name,
        BEARING_FAULT_KINDS[kind],
        (planet or 1) if found.planet else None,
        float(angle_deg),
        float(width),
    )
    for depth in severities:  # the defect's own rules (width below the element spacing)
        if depth > 0.0:
            try:
                fault.defect(depth).validate("defect", found)
            except CaseError as error:
                raise CaseError(f"--faults {kind} / --defect-width: {error}") from None
    return fault


def with_bearing_defect(
    case: Case, scene: Scene, fault: BearingFault, depth: float
) -> tuple[Case, Scene]:
    """``case`` with the bearing carrying the defect at ``depth`` (none at 0) and
    ``scene`` with the effect that puts rolling bearings into the run."""
    defects = (fault.defect(depth),) if depth > 0.0 else ()
    case = replace_parameter(case, f"rolling_bearings.{fault.bearing}.defects", defects)
    if BEARING_EFFECT not in scene.effects:
        scene = dataclasses.replace(scene, effects=(*scene.effects, BEARING_EFFECT))
    return case, scene
