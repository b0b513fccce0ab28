"""Forced response of a rotor or drivetrain model: unbalance response over speed and
frequency response functions, with API 684's amplification factors and separation
margins.

Unbalance
    A disc's unbalance m e [kg m] at phase phi turns with its shaft (speed Omega_s =
    ratio x Omega): F_x + i F_y = m e Omega_s^2 e^(i (Omega_s t + phi)), i.e. the complex
    amplitudes F_x = m e Omega_s^2 e^(i phi) and F_y = -i F_x on the disc's node.  At
    each rotor speed Omega the response solves
    ``(K(Omega) - Omega_s^2 M + i Omega_s (C(Omega) + Omega G)) X = F`` with one sparse
    LU; x(t) = Re(X e^(i Omega_s t)).  Phase is arg X [deg]: the response leads the
    unbalance by it (a Jeffcott rotor lags by 90 deg at its critical speed).
FRF
    ``H_ij(omega) = [K - omega^2 M + i omega (C + Omega G)]^-1_ij`` at a rotor speed
    Omega [m/N or rad/(N m)].
API 684 (2005, §2.8 / API 617 §2.6.2.10)
    At a peak of the response (a critical speed N_c) the amplification factor is
    AF = N_c / (N_2 - N_1) with N_1, N_2 the half-power (peak / sqrt 2) speeds; a
    separation margin is required when AF >= 2.5, SM = 17 (1 - 1 / (AF - 1.5)) % (at
    most 26 %), and the actual margin is how far N_c lies outside the operating range
    [N_min, N_max]: 100 (N_min - N_c)/N_min below, 100 (N_c - N_max)/N_max above.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import xarray as xr

from ...errors import CaseError

__all__ = [
    "Unbalance",
    "amplification_factors",
    "frequency_response",
    "required_separation_margin",
    "unbalance_response",
]


@dataclass(frozen=True)
class Unbalance:
    """An unbalance on a disc: ``moment`` m e [kg m] >= 0 at ``phase`` [deg]."""

    disc: str
    moment: float
    phase_deg: float = 0.0


def _speeds(values: Sequence[float], name: str) -> np.ndarray:
    array = np.asarray(values, dtype=float).ravel()
    if array.size < 1 or not np.all(np.isfinite(array)):
        raise CaseError(f"{name} must be one or more finite numbers")
    return array


def _dynamic(model, speed_rpm: float, frequency: float) -> sp.csc_matrix:
    """K(Omega) - w^2 M + i w (C(Omega) + Omega G) at rotor speed and response w [rad/s]."""
    omega = speed_rpm * math.pi / 30.0
    stiffness, damping = model.at_speed(speed_rpm)
    first = damping + omega * model.gyroscopic
    return sp.csc_matrix(stiffness - frequency**2 * model.mass + 1j * frequency * first)


def _nodes(model, drivetrain) -> list[tuple[str, str, str]]:
    """(name, x label, y label) of every disc and bearing node."""
    out = []
    for part in (*drivetrain.discs, *drivetrain.bearings):
        shaft = drivetrain.shaft(part.shaft)
        out.append(
            (
                part.name,
                model.node_label(shaft, part.position, "x"),
                model.node_label(shaft, part.position, "y"),
            )
        )
    return out


def unbalance_response(
    model, drivetrain, unbalances: Sequence[Unbalance], speeds_rpm: Sequence[float]
) -> xr.Dataset:
    """Steady response to disc unbalances at every rotor speed.

    Parameters
    ----------
    model : DrivetrainModel
        The assembled model (spatial DOF set).
    drivetrain : Drivetrain
        Its drivetrain (the discs, bearings and shafts by name).
    unbalances : sequence of Unbalance
        At least one; all on shafts at one speed ratio.
    speeds_rpm : sequence of float
        Rotor speeds [rpm].

    Returns
    -------
    xarray.Dataset
        Over (``speed``, ``location``), the discs' and bearings' nodes:
        ``x_amplitude``, ``y_amplitude`` [m], ``x_phase``, ``y_phase`` [deg],
        ``major_axis`` [m] (the orbit's semi-major axis).
    """
    speeds = _speeds(speeds_rpm, "--speeds")
    if not unbalances:
        raise CaseError("--unbalance: give at least one DISC:ME:PHASE")
    ratios = set()
    force = np.zeros(model.size, complex)
    for item in unbalances:
        try:
            disc = drivetrain.disc(item.disc)
        except CaseError as error:
            raise CaseError(f"--unbalance: {error}") from None
        if not (math.isfinite(item.moment) and item.moment >= 0):
            raise CaseError(f"--unbalance {item.disc}: ME must be >= 0 kg m (got {item.moment!r})")
        shaft = drivetrain.shaft(disc.shaft)
        ratios.add(model.speed_ratios.get(shaft.name, 1.0))
        amplitude = item.moment * np.exp(1j * math.radians(item.phase_deg))
        force[model.index(model.node_label(shaft, disc.position, "x"))] += amplitude
        force[model.index(model.node_label(shaft, disc.position, "y"))] += -1j * amplitude
    if len(ratios) != 1:
        raise CaseError("--unbalance: the discs must turn at one speed (one shaft group)")
    (ratio,) = ratios
    locations = _nodes(model, drivetrain)
    rows_x = [model.index(x) for _, x, _ in locations]
    rows_y = [model.index(y) for _, _, y in locations]
    response_x = np.zeros((speeds.size, len(locations)), complex)
    response_y = np.zeros_like(response_x)
    for k, speed in enumerate(speeds):
        spin = abs(ratio * speed) * math.pi / 30.0
        if spin == 0.0:
            continue
        solution = spla.splu(_dynamic(model, speed, spin)).solve(force * spin**2)
        response_x[k], response_y[k] = solution[rows_x], solution[rows_y]
    forward = np.abs(response_x + 1j * response_y) / 2
    backward = np.abs(response_x - 1j * response_y) / 2
    dims = ("speed", "location")

    def var(values, units, long_name):
        return dims, values, {"units": units, "long_name": long_name}

    return xr.Dataset(
        {
            "x_amplitude": var(np.abs(response_x), "m", "amplitude of x"),
            "y_amplitude": var(np.abs(response_y), "m", "amplitude of y"),
            "x_phase": var(np.degrees(np.angle(response_x)), "deg", "phase of x (lead)"),
            "y_phase": var(np.degrees(np.angle(response_y)), "deg", "phase of y (lead)"),
            "major_axis": var(forward + backward, "m", "semi-major axis of the orbit"),
        },
        coords={
            "speed": ("speed", speeds, {"units": "rpm", "long_name": "rotor speed"}),
            "location": (
                "location",
                np.array([name for name, _, _ in locations], object),
                {"units": "1", "long_name": "disc or bearing"},
            ),
        },
        attrs={
            "case": model.case_name,
            "unbalance": "; ".join(f"{u.disc}:{u.moment:g}:{u.phase_deg:g}" for u in unbalances),
            "unbalance_speed_ratio": float(ratio),
        },
    )


def frequency_response(
    model, output: str, input_: str, frequencies_hz: Sequence[float], speed_rpm: float = 0.0
) -> xr.Dataset:
    """H(output, input) over frequency at a rotor speed: the receptance [m/N].

    ``output`` and ``input_`` are DOF labels of the model (``shaft_3.x``)."""
    frequencies = _speeds(frequencies_hz, "frequencies")
    i, j = model.index(output), model.index(input_)
    unit = np.zeros(model.size, complex)
    unit[j] = 1.0
    values = np.array(
        [spla.splu(_dynamic(model, speed_rpm, 2 * math.pi * f)).solve(unit)[i] for f in frequencies]
    )
    return xr.Dataset(
        {
            "amplitude": ("frequency", np.abs(values), {"units": "m/N", "long_name": "|H|"}),
            "phase": (
                "frequency",
                np.degrees(np.angle(values)),
                {"units": "deg", "long_name": "arg H"},
            ),
            "h_real": ("frequency", values.real, {"units": "m/N", "long_name": "Re H"}),
            "h_imag": ("frequency", values.imag, {"units": "m/N", "long_name": "Im H"}),
        },
        coords={"frequency": ("frequency", frequencies, {"units": "Hz", "long_name": "frequency"})},
        attrs={"case": model.case_name, "output": output, "input": input_, "speed_rpm": speed_rpm},
    )


def required_separation_margin(amplification: float) -> float:
    """API 684's required separation margin [%] for an amplification factor (0 below
    2.5, at most 26)."""
    if amplification < 2.5:
        return 0.0
    return min(17.0 * (1.0 - 1.0 / (amplification - 1.5)), 26.0)


def amplification_factors(
    speeds_rpm: np.ndarray,
    amplitude: np.ndarray,
    operating_rpm: tuple[float, float] | None = None,
) -> list[dict]:
    """Every peak of an amplitude over speed: its speed N_c [rpm], the half-power speeds,
    AF = N_c / (N_2 - N_1) (None when a half-power point lies outside the range), and
    API 684's required and actual separation margins [%]."""
    speeds = np.asarray(speeds_rpm, dtype=float)
    values = np.asarray(amplitude, dtype=float)
    peaks = []
    for k in range(1, values.size - 1):
        if not (values[k] > values[k - 1] and values[k] >= values[k + 1]):
            continue
        half = values[k] / math.sqrt(2.0)
        lower = _crossing(speeds[: k + 1][::-1], values[: k + 1][::-1], half)
        upper = _crossing(speeds[k:], values[k:], half)
        factor = None if lower is None or upper is None else speeds[k] / (upper - lower)
        required = None if factor is None else required_separation_margin(factor)
        actual = None
        if operating_rpm is not None:
            low, high = operating_rpm
            if speeds[k] < low:
                actual = 100.0 * (low - speeds[k]) / low
            elif speeds[k] > high:
                actual = 100.0 * (speeds[k] - high) / high
            else:
                actual = 0.0
        peaks.append(
            {
                "speed_rpm": float(speeds[k]),
                "peak": float(values[k]),
                "half_power_rpm": [lower, upper],
                "amplification_factor": factor,
                "required_margin_pct": required,
                "actual_margin_pct": actual,
                "meets_api684": None if required is None or actual is None else actual >= required,
            }
        )
    return peaks


def _crossing(speeds: np.ndarray, values: np.ndarray, level: float) -> float | None:
    """The first speed from ``speeds[0]`` on where ``values`` falls to ``level`` (linear)."""
    for k in range(1, values.size):
        if values[k] <= level:
            weight = (values[k - 1] - level) / (values[k - 1] - values[k])
            return float(speeds[k - 1] + weight * (speeds[k] - speeds[k - 1]))
    return None
