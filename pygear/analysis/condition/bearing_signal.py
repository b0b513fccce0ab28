r"""What a housing accelerometer records from a rolling bearing's force history.

The force the elements carry (``blocked_force_x/y`` of
:func:`pygear.analysis.condition.bearing_load.defect_excitation`, in the frame the load
is fixed in) minus its mean is turned into the housing frame, projected on the sensor's
direction and passed through the path of :mod:`pygear.analysis.condition.sensor_signal`:

    a_flat(t) = g w(theta_p(t) - theta_s) [F_x cos(theta_L - theta_s) - F_y sin(theta_L - theta_s)],

theta_L(t) = theta_L0 + 2 pi f_carrier t the load direction (fixed for a bearing in the
housing; turning with the carrier for a planet bearing), theta_p(t) the planet's angle
(the same rotation), w the transmission window of a planet passing the sensor (McFadden &
Smith 1985; 1 for a bearing in the housing), g the path's gain.  The structure's modes
add their responses and white noise its share, as for a gear's sensor signal.  This is
the quasi-static synthesis of the bearing's vibration in Python; the kernel will later
integrate the same contact law per step (docs/bearings.md).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import xarray as xr

from ...errors import CaseError
from ...model.sensors import StructuralMode
from .sensor_signal import add_noise, structural_response, transmission_window

__all__ = ["bearing_sensor_signal"]


def bearing_sensor_signal(
    excitation: xr.Dataset,
    *,
    gain: float,
    sensor_angle_deg: float = 0.0,
    load_angle_deg: float = 0.0,
    carrier_hz: float = 0.0,
    window_width_deg: float | None = None,
    window_shape: str = "hann",
    modes: Sequence[StructuralMode] = (),
    snr_db: float | None = None,
    seed: int = 0,
) -> xr.DataArray:
    """A housing sensor's acceleration from a bearing's force history.

    Parameters
    ----------
    excitation : xarray.Dataset
        :func:`~pygear.analysis.condition.bearing_load.defect_excitation`'s result.
    gain : float
        Path gain g [m/s^2 per N], finite and non-zero.
    sensor_angle_deg : float
        theta_s, the sensor's direction about the axis [deg].
    load_angle_deg : float
        theta_L0, the load's direction at t = 0 (for a planet bearing, also the planet's
        angle: the mesh forces that load it turn with it) [deg].
    carrier_hz : float
        Carrier rate [Hz]: 0 for a bearing in the housing.
    window_width_deg : float, optional
        Width of the transmission window of a planet bearing [deg] (None: no window).
    window_shape : str
        ``"hann"`` or ``"rectangular"``
        (:func:`~pygear.analysis.condition.sensor_signal.transmission_window`).
    modes : sequence of StructuralMode
        Modes between the bearing and the sensor (their resonances ring at each impact).
    snr_db : float, optional
        White noise at this signal-to-noise ratio [dB]; None: none.
    seed : int
        Seed of the noise.

    Returns
    -------
    xarray.DataArray
        ``bearing_sensor_acceleration`` over ``time`` [m/s^2].
    """
    for name in ("blocked_force_x", "blocked_force_y"):
        if name not in excitation:
            raise CaseError(f"excitation must be a defect_excitation result (no {name!r})")
    if not (math.isfinite(gain) and gain != 0.0):
        raise CaseError(f"gain must be a finite, non-zero path gain in m/s^2/N (got {gain!r})")
    if window_width_deg is not None and not 0.0 < window_width_deg <= 360.0:
        raise CaseError(f"window_width_deg must be in (0, 360] (got {window_width_deg!r})")
    if window_shape not in ("hann", "rectangular"):
        raise CaseError(f"window_shape must be one of hann, rectangular (got {window_shape!r})")
    time = excitation["time"].values
    rate = float(excitation.attrs["sample_rate"])
    fx = excitation.blocked_force_x.values - np.mean(excitation.blocked_force_x.values)
    fy = excitation.blocked_force_y.values - np.mean(excitation.blocked_force_y.values)
    turn = math.radians(load_angle_deg) + 2.0 * math.pi * carrier_hz * time
    relative = turn - math.radians(sensor_angle_deg)
    flat = gain * (fx * np.cos(relative) - fy * np.sin(relative))
    if window_width_deg is not None:
        flat *= transmission_window(relative, math.radians(window_width_deg), window_shape)
    signal = add_noise(structural_response(flat, rate, tuple(modes)), snr_db, seed)
    return xr.DataArray(
        signal,
        dims="time",
        coords={"time": ("time", time, {"units": "s", "long_name": "time"})},
        name="bearing_sensor_acceleration",
        attrs={
            "units": "m/s^2",
            "long_name": f"housing sensor at {sensor_angle_deg:g} deg: bearing "
            f"{excitation.attrs.get('bearing', '')}",
            "carrier_hz": float(carrier_hz),
        },
    )
