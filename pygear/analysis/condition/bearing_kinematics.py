r"""Characteristic frequencies of a rolling bearing from its geometry and ring speeds.

With gamma = d cos(alpha) / D, ring speeds f_i, f_o (inner, outer) and f_L of the frame
the radial load is fixed in (the housing for a shaft bearing, the carrier for a planet
bearing), all in Hz of one frame, the cage turns at (Harris & Kotzalas 2007, ch. 8;
Randall & Antoni 2011, eq. 1-4)

    f_c = ((1 - gamma) f_i + (1 + gamma) f_o) / 2,

and with the relative ring speed f_r = |f_i - f_o|::

    FTF  = |f_c - f_o| = (1/2) f_r (1 - gamma)        cage rate relative to the outer ring
    BPFO = Z |f_c - f_o| = (Z/2) f_r (1 - gamma)       elements passing an outer-race point
    BPFI = Z |f_i - f_c| = (Z/2) f_r (1 + gamma)       elements passing an inner-race point
    BSF  = (D / 2d) f_r (1 - gamma^2)                  element spin (a defect on it strikes
                                                       both races: lines at 2 BSF)

Slip (1-2 %, Randall & Antoni 2011) makes the real lines wander about these values.
A defect's impacts are modulated by the load zone at the rate its carrier passes the
load: an outer-race defect at |f_o - f_L|, an inner-race defect at |f_i - f_L| (the
shaft rate of a shaft bearing), an element defect at |f_c - f_L| (the cage rate).  A
planet bearing turns with the carrier past a housing sensor: its lines carry sidebands
at the carrier rate as well (the transmission path, McFadden & Smith 1985).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ...errors import CaseError
from ...model.rolling_bearing import RollingBearing

__all__ = [
    "BEARING_LINES",
    "BearingFrequencies",
    "bearing_frequencies",
    "frequency_table",
    "read_frequency_table",
    "run_frequencies",
]

BEARING_LINES = ("FTF", "BPFO", "BPFI", "BSF")
"""The characteristic lines, in the order datasets list them."""


@dataclass(frozen=True)
class BearingFrequencies:
    """Characteristic frequencies of one bearing at one speed [Hz]."""

    name: str
    relative_speed: float
    """f_r = |f_i - f_o|, the relative ring speed."""
    cage: float
    """f_c, the cage's speed in the frame the ring speeds were given in (signed)."""
    lines: dict[str, float]
    """``{"FTF", "BPFO", "BPFI", "BSF"}`` -> frequency."""
    modulation: dict[str, float]
    """Line -> rate at which the load zone modulates a defect of that kind: BPFO at
    |f_o - f_L|, BPFI at |f_i - f_L|, BSF (element) and FTF at |f_c - f_L|."""
    carrier: float = 0.0
    """Carrier rate |f_L| of a planet bearing seen from the housing (transmission-path
    sidebands); 0 for a bearing in the housing."""


def bearing_frequencies(
    bearing: RollingBearing,
    inner_hz: float,
    outer_hz: float = 0.0,
    *,
    load_frame_hz: float = 0.0,
    carrier_hz: float = 0.0,
) -> BearingFrequencies:
    """Cage rate, FTF, BPFO, BPFI and BSF of ``bearing`` at the given ring speeds.

    Parameters
    ----------
    bearing : RollingBearing
        Geometry (Z, d, D, alpha).
    inner_hz, outer_hz : float
        Speeds of the inner and the outer ring [Hz], signed, in any one frame (for a
        planet bearing the carrier frame: inner 0, outer the planet's spin).
    load_frame_hz : float
        Speed of the frame the radial load is fixed in, in that frame [Hz] (0 when the
        speeds are given in it).
    carrier_hz : float
        Carrier rate seen from the housing [Hz] (planet bearings; 0 otherwise).

    Returns
    -------
    BearingFrequencies
    """
    for label, value in (("inner_hz", inner_hz), ("outer_hz", outer_hz),
                         ("load_frame_hz", load_frame_hz), ("carrier_hz", carrier_hz)):  # fmt: skip
        if not math.isfinite(value):
            raise CaseError(f"{label} must be a finite speed in Hz (got {value!r})")
    gamma = bearing.gamma
    z = bearing.elements
    cage = 0.5 * ((1.0 - gamma) * inner_hz + (1.0 + gamma) * outer_hz)
    relative = abs(inner_hz - outer_hz)
    ftf = abs(cage - outer_hz)
    lines = {
        "FTF": ftf,
        "BPFO": z * ftf,
        "BPFI": z * abs(inner_hz - cage),
        "BSF": bearing.pitch_diameter
        / (2.0 * bearing.element_diameter)
        * relative
        * (1.0 - gamma**2),
    }
    modulation = {
        "FTF": abs(cage - load_frame_hz),
        "BPFO": abs(outer_hz - load_frame_hz),
        "BPFI": abs(inner_hz - load_frame_hz),
        "BSF": abs(cage - load_frame_hz),
    }
    return BearingFrequencies(bearing.name, relative, cage, lines, modulation, abs(carrier_hz))


def frequency_table(found: list[BearingFrequencies]) -> xr.Dataset:
    """Characteristic frequencies of several bearings as a Dataset (run files store it).

    Variables over (``rolling_bearing``, ``bearing_line``): ``bearing_frequency`` and
    ``bearing_modulation`` [Hz]; over ``rolling_bearing``: ``bearing_shaft_frequency``
    (f_r) and ``bearing_carrier_frequency`` [Hz].  The dimension is not ``bearing``,
    which names a run's bearing-force channels (the springs), not the rolling bearings.
    """
    names = [f.name for f in found]
    lines = list(BEARING_LINES)
    shape = (len(found), len(lines))
    frequency = np.array([[f.lines[k] for k in lines] for f in found], dtype=float).reshape(shape)
    modulation = np.array([[f.modulation[k] for k in lines] for f in found], dtype=float).reshape(
        shape
    )
    return xr.Dataset(
        {
            "bearing_frequency": (
                ("rolling_bearing", "bearing_line"),
                frequency,
                {
                    "units": "Hz",
                    "long_name": "bearing characteristic frequency (FTF, BPFO, BPFI, BSF) "
                    "at the equilibrium speeds",
                },
            ),
            "bearing_modulation": (
                ("rolling_bearing", "bearing_line"),
                modulation,
                {
                    "units": "Hz",
                    "long_name": "rate at which the load zone modulates a defect's line "
                    "(its shaft-rate sidebands)",
                },
            ),
            "bearing_shaft_frequency": (
                ("rolling_bearing",),
                np.array([f.relative_speed for f in found], dtype=float),
                {"units": "Hz", "long_name": "relative ring speed f_r of the bearing"},
            ),
            "bearing_carrier_frequency": (
                ("rolling_bearing",),
                np.array([f.carrier for f in found], dtype=float),
                {
                    "units": "Hz",
                    "long_name": "carrier rate of a planet bearing seen from the housing "
                    "(0 for a bearing in the housing)",
                },
            ),
        },
        coords={
            "rolling_bearing": (
                ("rolling_bearing",),
                names,
                {"units": "1", "long_name": "rolling bearing"},
            ),
            "bearing_line": (
                ("bearing_line",),
                lines,
                {"units": "1", "long_name": "bearing characteristic line"},
            ),
        },
    )


def run_frequencies(
    bearings: tuple[RollingBearing, ...] | list[RollingBearing], speeds_rpm: dict[str, float]
) -> list[BearingFrequencies]:
    """Characteristic frequencies of a case's bearings at a run's equilibrium speeds.

    A planet bearing (``location`` ``"<stage>.planet"``) turns with the stage's first
    planet, whose speed a run gives relative to the carrier (its theta_z DOF): in the
    carrier frame the pin (inner ring) and the load stand still, the planet's bore
    (outer ring) turns at the planet's speed, and the carrier's own rate becomes the
    transmission-path sideband.  Any other bearing turns its ``turning`` ring with the
    body ``location`` names, the other ring and the load in the housing.  Bearings whose
    body the run does not hold are left out.

    Parameters
    ----------
    bearings : sequence of RollingBearing
        The case's rolling bearings.
    speeds_rpm : dict
        Body name -> equilibrium speed [rpm] (a run's ``equilibrium_speed``).
    """
    found = []
    for bearing in bearings:
        if bearing.planet:
            stage = bearing.location[: -len(".planet")]
            planets = sorted(k for k in speeds_rpm if k.startswith(f"{stage}.planet"))
            if not planets:
                continue
            body_hz = speeds_rpm[planets[0]] / 60.0
            carrier_hz = speeds_rpm.get(f"{stage}.carrier", 0.0) / 60.0
        elif bearing.location in speeds_rpm:
            body_hz, carrier_hz = speeds_rpm[bearing.location] / 60.0, 0.0
        else:
            continue
        if not (math.isfinite(body_hz) and math.isfinite(carrier_hz)):
            continue
        inner, outer = (0.0, body_hz) if bearing.turning == "outer" else (body_hz, 0.0)
        found.append(bearing_frequencies(bearing, inner, outer, carrier_hz=carrier_hz))
    return found


def read_frequency_table(dataset: xr.Dataset) -> list[BearingFrequencies]:
    """The bearing frequencies a run file stores (:func:`frequency_table`); empty when
    it stores none."""
    if "bearing_frequency" not in dataset:
        return []
    lines = [str(k) for k in dataset["bearing_line"].values]
    found = []
    for n, name in enumerate(dataset["rolling_bearing"].values):
        frequency = dataset["bearing_frequency"].values[n]
        modulation = dataset["bearing_modulation"].values[n]
        found.append(
            BearingFrequencies(
                str(name),
                float(dataset["bearing_shaft_frequency"].values[n]),
                math.nan,
                {k: float(v) for k, v in zip(lines, frequency)},
                {k: float(v) for k, v in zip(lines, modulation)},
                float(dataset["bearing_carrier_frequency"].values[n]),
            )
        )
    return found
