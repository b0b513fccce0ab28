"""Synthetic turbulent wind and the rotor torque it drives (design load cases).

A design load case of IEC 61400-1 ed.3 (DLC 1.2, power production in the normal
turbulence model) runs the turbine in turbulent wind at one hub wind speed for 600 s,
several seeds per speed.  Without an aeroelastic simulation, the gearbox's input is
made here in three steps:

1. :func:`kaimal_wind` draws the longitudinal wind speed at the hub from the Kaimal
   spectrum of IEC 61400-1 ed.3 annex B (normal turbulence model, eq. 11 and B.14):
   S(f) = 4 sigma^2 (L/V) / (1 + 6 f L/V)^(5/3), L = 8.1 Lambda, Lambda = 0.7 z_hub
   (42 m above 60 m), sigma = I_ref (0.75 V + 5.6 m/s).  The Fourier coefficients are
   complex Gaussian with the spectrum's variance (a Gaussian process, not fixed
   amplitudes), drawn from ``numpy.random.default_rng(seed)``.
2. The rotor follows the slow wind (a first-order low pass of time constant tau,
   ASSUMED 5 s for the rotor's inertia and the controller): below rated at the optimal
   tip-speed ratio within the speed range, above rated at rated speed and power
   (pitch control, which is not modelled beyond holding the mean power).
3. The aerodynamic torque is the quasi-steady torque of the slow wind, T_s = P_s / Omega
   with P_s = min(rho A Cp(lambda) U_f^3 / 2, P_rated), times the turbulence's fast part
   through the rotor's sensitivity at fixed speed:
   T = T_s (1 + g (U - U_f) / U_f), g = dln P / dln U = 3 - lambda Cp'(lambda) / Cp(lambda).
   The low pass keeps the mean, so the mean torque is that of the slow wind.

The rotor is the NREL 5 MW reference turbine's (Jonkman et al. 2009, NREL/TP-500-38060):
R = 63 m, rated 12.1 rpm and 5.296 MW mechanical (5 MW electrical at 94.4 %), minimum
speed 6.9 rpm, peak Cp = 0.482 at lambda = 7.55 (zero pitch).  The report draws its
Cp(lambda, pitch) surface without tabulating it: the Cp(lambda) table below is ASSUMED,
the usual Heier-type curve (Cp = 0.5176 (116/l_i - 5) exp(-21/l_i) + 0.0068 lambda,
1/l_i = 1/lambda - 0.035) moved and scaled to the report's peak.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ...errors import CaseError

__all__ = [
    "NREL5MW_ROTOR",
    "RotorAerodynamics",
    "TURBULENCE_CLASSES",
    "kaimal_spectrum",
    "kaimal_wind",
    "rotor_torque_series",
]

TURBULENCE_CLASSES = {"A": 0.16, "B": 0.14, "C": 0.12}
"""I_ref of IEC 61400-1 ed.3 Table 1 (turbulence intensity at 15 m/s)."""

NTM_B = 5.6
"""b of the normal turbulence model [m/s]: sigma_1 = I_ref (0.75 V_hub + b)."""


@dataclass(frozen=True)
class RotorAerodynamics:
    """A rotor's steady aerodynamics and its speed regulation.

    Attributes
    ----------
    radius : float
        Rotor radius [m].
    hub_height : float
        Hub height [m] (sets the turbulence scale).
    rated_power : float
        Rated mechanical (rotor) power [W].
    rated_speed_rpm, minimum_speed_rpm : float
        Speed range of the variable-speed regulation [rpm].
    tip_speed_ratios, power_coefficients : tuple of float
        Cp(lambda) at zero pitch, lambda increasing.
    air_density : float
        [kg/m^3].
    """

    radius: float
    hub_height: float
    rated_power: float
    rated_speed_rpm: float
    minimum_speed_rpm: float
    tip_speed_ratios: tuple[float, ...]
    power_coefficients: tuple[float, ...]
    air_density: float = 1.225

    @property
    def area(self) -> float:
        """Swept area [m^2]."""
        return math.pi * self.radius**2

    def cp(self, tip_speed_ratio: np.ndarray) -> np.ndarray:
        """Cp at the tip-speed ratio (linear interpolation, held at the table's ends)."""
        return np.interp(tip_speed_ratio, self.tip_speed_ratios, self.power_coefficients)

    def sensitivity(self, tip_speed_ratio: np.ndarray) -> np.ndarray:
        """g = dln P / dln U at fixed speed: 3 - lambda Cp'(lambda) / Cp(lambda)."""
        lam = np.asarray(self.tip_speed_ratios)
        slope = np.gradient(np.asarray(self.power_coefficients), lam)
        derivative = np.interp(tip_speed_ratio, lam, slope)
        cp = np.maximum(self.cp(tip_speed_ratio), 1e-3)
        return 3.0 - tip_speed_ratio * derivative / cp

    @property
    def optimal_tip_speed_ratio(self) -> float:
        """lambda of the table's largest Cp."""
        return float(self.tip_speed_ratios[int(np.argmax(self.power_coefficients))])

    def regulated(self, wind_speed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Rotor speed [rad/s] and quasi-steady aerodynamic power [W] at a slow wind
        speed: the optimal tip-speed ratio within the speed range, the power limited
        to rated."""
        wind = np.maximum(np.asarray(wind_speed, dtype=float), 0.1)
        omega_min = self.minimum_speed_rpm * math.pi / 30.0
        omega_rated = self.rated_speed_rpm * math.pi / 30.0
        omega = np.clip(self.optimal_tip_speed_ratio * wind / self.radius, omega_min, omega_rated)
        power = 0.5 * self.air_density * self.area * self.cp(omega * self.radius / wind) * wind**3
        return omega, np.minimum(power, self.rated_power)


# Cp(lambda) at zero pitch, lambda = 2, 2.5, ..., 14.  ASSUMED: the Heier-type curve
# moved and scaled to the published peak (0.482 at lambda = 7.55; NREL/TP-500-38060
# section 7.1); negative values past lambda = 12.5 are the windmilling rotor's.
_NREL5MW_CP = (
    0.017, 0.033, 0.065, 0.114, 0.175, 0.242, 0.308, 0.367, 0.416, 0.452, 0.474, 0.482,
    0.477, 0.459, 0.430, 0.390, 0.341, 0.285, 0.221, 0.152, 0.077, -0.001, -0.083, -0.168,
    -0.255,
)  # fmt: skip

NREL5MW_ROTOR = RotorAerodynamics(
    radius=63.0,  # m, NREL/TP-500-38060 Table 1-1
    hub_height=90.0,  # m, Table 1-1
    rated_power=5.296610e6,  # W mechanical, Table 7-1 (5 MW electrical at 94.4 %)
    rated_speed_rpm=12.1,  # Table 1-1
    minimum_speed_rpm=6.9,  # cut-in rotor speed, Table 1-1
    tip_speed_ratios=tuple(2.0 + 0.5 * k for k in range(len(_NREL5MW_CP))),
    power_coefficients=_NREL5MW_CP,
)
"""The NREL 5 MW reference turbine's rotor (Cp table ASSUMED, see above)."""


def _turbulence(wind_speed: float, turbulence_class: str, hub_height: float) -> tuple:
    if turbulence_class not in TURBULENCE_CLASSES:
        raise CaseError(
            f"turbulence_class must be one of {', '.join(TURBULENCE_CLASSES)} "
            f"(got {turbulence_class!r})"
        )
    if not (math.isfinite(wind_speed) and wind_speed > 0):
        raise CaseError(f"wind_speed must be > 0 m/s (got {wind_speed!r})")
    sigma = TURBULENCE_CLASSES[turbulence_class] * (0.75 * wind_speed + NTM_B)
    scale = 8.1 * (0.7 * hub_height if hub_height <= 60.0 else 42.0)
    return sigma, scale


def kaimal_spectrum(
    frequency: np.ndarray, wind_speed: float, turbulence_class: str = "B", hub_height: float = 90.0
) -> np.ndarray:
    """One-sided Kaimal spectrum of the longitudinal wind speed [m^2/s^2/Hz] (IEC
    61400-1 ed.3 eq. B.14 with the normal turbulence model's sigma_1)."""
    sigma, scale = _turbulence(wind_speed, turbulence_class, hub_height)
    ratio = scale / wind_speed
    return 4.0 * sigma**2 * ratio / (1.0 + 6.0 * np.asarray(frequency) * ratio) ** (5.0 / 3.0)


def kaimal_wind(
    wind_speed: float,
    duration: float,
    sample_rate: float,
    seed: int,
    turbulence_class: str = "B",
    hub_height: float = 90.0,
) -> np.ndarray:
    """Hub wind speed [m/s] at ``sample_rate`` over ``duration``: the mean plus a
    Gaussian process of the Kaimal spectrum (periodic over the duration).

    The Fourier coefficient at f_k = k / duration (k = 1 .. N/2 - 1) is complex Gaussian
    with E|c_k|^2 = S(f_k) df / 2, so that the periodogram's mean is S(f_k); the mean
    and the Nyquist bin get nothing.
    """
    count = int(round(duration * sample_rate))
    if count < 4:
        raise CaseError(f"duration x sample_rate must give at least 4 samples (got {count})")
    frequency = np.fft.rfftfreq(count, d=1.0 / sample_rate)
    spectrum = np.zeros_like(frequency)
    spectrum[1:] = kaimal_spectrum(frequency[1:], wind_speed, turbulence_class, hub_height)
    if count % 2 == 0:
        spectrum[-1] = 0.0
    rng = np.random.default_rng(seed)
    df = sample_rate / count
    normal = rng.standard_normal((2, frequency.size))
    coefficients = np.sqrt(spectrum * df / 4.0) * (normal[0] + 1j * normal[1])
    return wind_speed + np.fft.irfft(coefficients * count, n=count)


def rotor_torque_series(
    wind: np.ndarray,
    sample_rate: float,
    rotor: RotorAerodynamics = NREL5MW_ROTOR,
    time_constant: float = 5.0,
    mean_wind_speed: float | None = None,
) -> xr.Dataset:
    """Aerodynamic rotor torque and rotor speed driven by a hub wind speed series.

    Parameters
    ----------
    wind : ndarray
        Hub wind speed [m/s], sampled at ``sample_rate`` [Hz].
    rotor : RotorAerodynamics
        The rotor (default the NREL 5 MW).
    time_constant : float
        tau of the slow wind the rotor speed and the pitch follow [s], ASSUMED 5 s.
    mean_wind_speed : float, optional
        Where the low pass starts (default the series' mean).

    Returns
    -------
    xarray.Dataset
        ``rotor_torque(time)`` [N m], ``rotor_speed(time)`` [rpm] and
        ``wind_speed(time)`` [m/s], as :func:`pygear.io_openfast.read_openfast_output`
        returns them.
    """
    from scipy.signal import lfilter

    wind = np.asarray(wind, dtype=float)
    if not (time_constant > 0 and math.isfinite(time_constant)):
        raise CaseError(f"time_constant must be > 0 s (got {time_constant!r})")
    start = float(np.mean(wind)) if mean_wind_speed is None else float(mean_wind_speed)
    pole = math.exp(-1.0 / (sample_rate * time_constant))
    slow, _ = lfilter([1.0 - pole], [1.0, -pole], wind, zi=[pole * start])
    slow = np.maximum(slow, 0.1)
    omega, power = rotor.regulated(slow)
    gain = rotor.sensitivity(omega * rotor.radius / slow)
    torque = power / omega * (1.0 + gain * (wind - slow) / slow)
    time = np.arange(wind.size) / sample_rate
    return xr.Dataset(
        {
            "rotor_torque": ("time", torque, {"units": "N m", "long_name": "rotor torque"}),
            "rotor_speed": (
                "time",
                omega * 30.0 / math.pi,
                {"units": "rpm", "long_name": "rotor speed"},
            ),
            "wind_speed": ("time", wind, {"units": "m/s", "long_name": "hub wind speed"}),
        },
        coords={"time": ("time", time, {"units": "s", "long_name": "time"})},
        attrs={"regulation_time_constant": time_constant},
    )
