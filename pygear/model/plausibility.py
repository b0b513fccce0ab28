"""Plausible ranges of the physical quantities a case types, in one table.

Validation has three tiers.  A value that is not a finite number, or that is
physically impossible (a negative mass, a zero length, a backlash wider than a tooth
space), is a :class:`~pygear.errors.CaseError` naming the parameter and the rule.  A
possible value outside the range of any real gearbox, most often a unit mistake (a
Young's modulus in MPa typed as Pa, a diameter in mm typed as m), is a
:class:`PlausibilityWarning` naming the parameter, the value and the range with its
unit: the run goes on, so a deliberate study of an odd design still can.

Every component's ``validate`` calls :func:`warn_if_implausible` with a quantity of
:data:`PLAUSIBLE`; docs/reliability.md lists the table.  The ranges are generous: each
spans the gears pygear is meant for, from a 0.1 mm instrument module to a multi-MW
wind-turbine gearbox (the NREL 5 MW's 45 mm module, 110 t rotor and 3.9e7 kg m^2
inertia), with a decade to spare on both sides where no physics bounds them.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

__all__ = [
    "PLAUSIBLE",
    "PlausibilityWarning",
    "PlausibleRange",
    "implausibility",
    "warn_if_implausible",
]


class PlausibilityWarning(UserWarning):
    """A possible but implausible value, most often a unit mistake; the message names
    the parameter, the value and the plausible range with its unit."""


@dataclass(frozen=True)
class PlausibleRange:
    """The plausible range of one quantity.

    Parameters
    ----------
    low, high : float
        Plausible values lie in [low, high], in ``unit``.
    unit : str
        The SI unit (or ``-`` for a ratio).
    reason : str
        Where the bounds come from, and the unit mistake a value outside most likely is.
    """

    low: float
    high: float
    unit: str
    reason: str


PLAUSIBLE: dict[str, PlausibleRange] = {
    "young_modulus": PlausibleRange(
        1e9,
        1e12,
        "Pa",
        "gear and shaft materials: polymers ~2e9, aluminium 7e10, steel 2.06e11, "
        "carbides 6e11 Pa; 2.06e5 is steel in MPa, 206 in GPa",
    ),
    "shear_modulus": PlausibleRange(
        3e8, 4e11, "Pa", "E / (2 (1 + nu)) of the materials above; 7.9e4 is steel in MPa"
    ),
    "density": PlausibleRange(
        500.0, 2e4, "kg/m^3", "wood to tungsten; steel 7850; 7.85 is steel in g/cm^3"
    ),
    "mass": PlausibleRange(
        1e-4, 1e6, "kg", "a 0.1 g instrument gear to a 1000 t rotor (NREL 5 MW: 1.1e5 kg)"
    ),
    "inertia": PlausibleRange(
        1e-12,
        1e10,
        "kg m^2",
        "a watch gear (~1e-11) to a large rotor (NREL 5 MW: 3.9e7 kg m^2); "
        "a value in g mm^2 is 1e9 times too large",
    ),
    "radius": PlausibleRange(
        5e-4,
        10.0,
        "m",
        "radii of gears and carriers from 0.5 mm to 10 m (NREL 5 MW ring: 1.2 m); "
        "a value in mm typed as m is 1000 times too large",
    ),
    "module": PlausibleRange(
        1e-4, 0.1, "m", "ISO 54 modules 0.1 .. 50 mm, the largest gears ~100 mm"
    ),
    "face_width_ratio": PlausibleRange(
        1.0,
        60.0,
        "-",
        "face width over normal module b/m_n: 6 .. 30 in practice (ISO 6336 gears; "
        "NREL 5 MW: 11 .. 26), below 1 or above 60 a unit mistake",
    ),
    "backlash_ratio": PlausibleRange(
        0.0,
        0.25,
        "-",
        "circumferential backlash over transverse module j_wt/m_t: ISO/TR 10064-2 "
        "backlash is some 0.01 .. 0.1 m, 0.25 m a worn-out gear",
    ),
    "mesh_stiffness": PlausibleRange(
        1e6,
        1e12,
        "N/m",
        "steel meshes have ~1.4e10 N/m per metre of face (ISO 6336 c_gamma = 14 to 20 "
        "N/(mm um)): 1e6 is a 0.1 mm wide steel or a polymer gear",
    ),
    "shaft_length": PlausibleRange(
        1e-4, 50.0, "m", "a section of a shaft, 0.1 mm to 50 m; mm typed as m: 1000 times"
    ),
    "shaft_diameter": PlausibleRange(
        5e-4, 5.0, "m", "shaft diameters 0.5 mm to 5 m (NREL 5 MW main shaft 0.7 m)"
    ),
}
"""Quantity name -> plausible range, the one table every component's validation reads."""


def implausibility(quantity: str, value: float) -> str | None:
    """The rule ``value`` breaks, or None when it lies in the quantity's plausible range.

    Parameters
    ----------
    quantity : str
        A key of :data:`PLAUSIBLE`.
    value : float
        A finite value in the quantity's unit.

    Returns
    -------
    str or None
        ``"outside the plausible range <low> .. <high> <unit> (<reason>)"``, or None.
    """
    limits = PLAUSIBLE[quantity]
    if not math.isfinite(value) or limits.low <= value <= limits.high:
        return None
    return (
        f"outside the plausible range {limits.low:g} .. {limits.high:g} {limits.unit} "
        f"({limits.reason})"
    )


def warn_if_implausible(path: str, quantity: str, value: float, *, zero_ok: bool = False) -> None:
    """Warn (:class:`PlausibilityWarning`) when ``value`` lies outside the plausible range
    of ``quantity``; the message names the parameter ``path``, the value and the range.

    ``zero_ok``: 0 is a valid choice of the parameter (a rigid body, no backlash), not
    a small value, so it is not warned about.  Call after the value's own rules: a
    value that is not a finite number is left alone here.
    """
    if zero_ok and value == 0:
        return
    broken = implausibility(quantity, value)
    if broken is not None:
        unit = PLAUSIBLE[quantity].unit
        shown = f"{value!r}" if unit == "-" else f"{value!r} {unit}"
        warnings.warn(f"{path} = {shown} is {broken}", PlausibilityWarning, stacklevel=3)
