"""Rolling bearing life to ISO 281:2007.

* basic rating life L10 = (C/P)^p million revolutions, p = 3 (ball), 10/3 (roller);
* dynamic equivalent load P = X F_r + Y F_a (F_a/F_r > e), F_r + Y1 F_a otherwise;
* variable load: P_m = (sum P_i^p N_i / sum N_i)^(1/p) over the revolutions N_i;
* modified life L10m = a1 a_ISO L10 with a_ISO of ISO 281 cl. 9.3 (the viscosity ratio
  kappa = nu/nu_1, nu_1 from the speed and pitch diameter, and e_C C_u / P), a1 = 1.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ...errors import CaseError

__all__ = [
    "a_iso",
    "basic_life",
    "equivalent_load",
    "fatigue_load_limit",
    "life_exponent",
    "mean_load",
    "reference_viscosity",
]


def life_exponent(kind: str) -> float:
    """p = 3 for ball bearings, 10/3 for roller bearings."""
    if kind == "ball":
        return 3.0
    if kind == "roller":
        return 10.0 / 3.0
    raise CaseError(f"kind must be 'ball' or 'roller' (got {kind!r})")


def basic_life(c: float, p_load: float, kind: str) -> float:
    """L10 = (C/P)^p [million revolutions]; infinite at P = 0."""
    if p_load <= 0.0:
        return math.inf
    return (c / p_load) ** life_exponent(kind)


def equivalent_load(radial: float, axial: float, e: float, x: float, y: float,
                    y1: float = 0.0) -> float:
    """P = X F_r + Y F_a when F_a/F_r > e, else F_r + Y1 F_a [N]."""
    if radial <= 0.0 or axial / radial > e:
        return x * radial + y * axial
    return radial + y1 * axial


def mean_load(loads: Sequence[float], revolutions: Sequence[float], kind: str) -> float:
    """P_m = (sum P_i^p N_i / sum N_i)^(1/p) [N]."""
    p = life_exponent(kind)
    total = sum(revolutions)
    if total <= 0.0:
        raise CaseError("revolutions must add up to more than 0")
    return (sum(load**p * n for load, n in zip(loads, revolutions)) / total) ** (1.0 / p)


def reference_viscosity(speed_rpm: float, pitch_diameter_mm: float) -> float:
    """nu_1 [mm^2/s] (ISO 281 cl. 9.3.3): 45000 n^-0.83 d_m^-0.5 below 1000 rpm, 4500
    n^-0.5 d_m^-0.5 from 1000 rpm."""
    n = max(speed_rpm, 1e-9)
    if n < 1000.0:
        return 45000.0 * n**-0.83 * pitch_diameter_mm**-0.5
    return 4500.0 * n**-0.5 * pitch_diameter_mm**-0.5


def fatigue_load_limit(c0: float, kind: str, pitch_diameter_mm: float) -> float:
    """C_u estimated from C0 (ISO 281 Annex B, simplified): C0/8.2 roller, C0/27 ball,
    times (100/d_m)^0.3 above d_m = 100 mm [N]."""
    base = c0 / (8.2 if kind == "roller" else 27.0)
    return base * (100.0 / pitch_diameter_mm) ** 0.3 if pitch_diameter_mm > 100.0 else base


def a_iso(kind: str, kappa: float, contamination: float, c_u: float, p_load: float) -> float:
    """Life modification factor a_ISO of ISO 281:2007 cl. 9.3 (radial bearings), at most
    50; kappa is taken in 0.1..4.

    roller: 0.1 [1 - (2.5671 - 1.2777/kappa^0.071739)^0.83 (e_C C_u/P)^0.4]^-9.185 for
    1 <= kappa <= 4 (0.19087 for 0.4 <= kappa < 1; 1.5859 - 1.3993/kappa^0.054381 below
    0.4); ball: 0.1 [1 - (2.5671 - 1.9987/kappa^0.071739)^0.83 (e_C C_u/P)^(1/3)]^-9.3
    (0.19087 for 0.4..1; 2.5671 - 2.2649/kappa^0.054381 below 0.4).
    """
    if p_load <= 0.0:
        return 50.0
    kappa = min(max(kappa, 0.1), 4.0)
    load_term = contamination * c_u / p_load
    if kind == "roller":
        if kappa < 0.4:
            inner = 1.5859 - 1.3993 / kappa**0.054381
        elif kappa < 1.0:
            inner = 2.5671 - 1.2777 / kappa**0.19087
        else:
            inner = 2.5671 - 1.2777 / kappa**0.071739
        base = 1.0 - inner**0.83 * load_term**0.4
        exponent = -9.185
    else:
        if kappa < 0.4:
            inner = 2.5671 - 2.2649 / kappa**0.054381
        elif kappa < 1.0:
            inner = 2.5671 - 1.9987 / kappa**0.19087
        else:
            inner = 2.5671 - 1.9987 / kappa**0.071739
        base = 1.0 - inner**0.83 * load_term ** (1.0 / 3.0)
        exponent = -9.3
    if base <= 0.0:
        return 50.0
    return min(0.1 * base**exponent, 50.0)
