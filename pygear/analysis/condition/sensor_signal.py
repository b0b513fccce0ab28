r"""What an accelerometer on the ring records: the planets' ring-mesh forces through
angle-dependent paths, the ring's bearing force, the structure's modes and noise.

The model (docs/condition_monitoring.md, "Sensors") follows McFadden & Smith (1985):
planet n, at the angle theta_c(t) + psi_n about the stage axis, reaches a sensor at
theta_s through a window w of the angle between them,

    a_flat(t) = g_m c sum_n w(theta_c + psi_n - theta_s) F_n(t) + g_b F_b(t),

with F_n the force of mesh ring-planet n (compression positive), c = sin(alpha_r) for a
radial sensor and cos(alpha_r) for a tangential one, F_b the ring's bearing force in the
sensor's direction, and g_m, g_b the paths' gains.  The model's element matrices keep
planet n at psi_n, so its in-plane axes turn with the carrier: the bearing force is
turned by theta_c into the sensor's fixed frame.  The structure's modes add to a_flat
their responses g_k s^2 / (s^2 + 2 zeta_k w_k s + w_k^2) to it, discretised by the
bilinear transform pre-warped at w_k (the resonance's frequency and peak are exact).
Noise, when asked, is white with the power of the recorded signal over 10^(SNR/10).

For N equally spaced, identical planets in a periodic steady state, F_n(t) =
F_1(t - (n-1) T_c / N) (T_c the carrier period), so the sum is a sum of N copies of one
T_c-periodic signal shifted by T_c / N: only carrier orders that are multiples of N
survive (McFadden & Smith 1985; Inalpolat & Kahraman 2009), whatever the mesh phasing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...assembly.matrices import Model
from ...errors import CaseError
from ...kernel.newmark import KernelProbe
from ...model.case import Case
from ...model.components import PlanetaryStage
from ...model.sensors import Sensor, StructuralMode
from ...model.transient_settings import Probe
from ..signals.probes import compile_probes

__all__ = [
    "SensorPlan",
    "add_noise",
    "compile_scene_probes",
    "sensor_carrier_orders",
    "sensor_plan",
    "sensor_signal",
    "structural_response",
    "transmission_window",
]

AUXILIARY_PREFIX = "_sensor_"
"""Kernel channels a sensor needs; they feed the sensor's channel and are not written."""


@dataclass(frozen=True)
class SensorPlan:
    """A sensor probe compiled for one model: which kernel channels feed it and how."""

    sensor: Sensor
    variable: str
    planet_angles: tuple[float, ...]  # psi_n [rad]
    force_component: float  # sin or cos of the ring mesh's pressure angle [-]
    carrier_channel: str
    mesh_channels: tuple[str, ...]
    bearing_channels: tuple[str, str] | None
    window_width: float  # [rad]
    teeth: tuple[int, int, int]  # sun, planet, ring (0: not given)
    named: bool = False  # the probe has a name: its own variable, not sensor_acceleration

    @property
    def channels(self) -> tuple[str, ...]:
        """Every auxiliary channel the plan reads."""
        return (self.carrier_channel, *self.mesh_channels, *(self.bearing_channels or ()))


def transmission_window(angle_from_sensor: np.ndarray, width: float, shape: str) -> np.ndarray:
    """Gain of the path from a planet at ``angle_from_sensor`` [rad] (any turn) to the sensor.

    ``hann``: cos^2(pi d / width) for |d| < width / 2, d the angle wrapped to [-pi, pi);
    ``rectangular``: 1 there.  Zero elsewhere.
    """
    wrapped = np.mod(np.asarray(angle_from_sensor, dtype=np.float64) + math.pi, 2 * math.pi)
    wrapped -= math.pi
    inside = np.abs(wrapped) < width / 2
    if shape == "rectangular":
        return inside.astype(np.float64)
    return np.where(inside, np.cos(math.pi * wrapped / width) ** 2, 0.0)


def _mode_coefficients(mode: StructuralMode, sample_rate: float) -> tuple[np.ndarray, np.ndarray]:
    """Bilinear-transform coefficients (b, a) of g s^2 / (s^2 + 2 zeta w s + w^2),
    pre-warped at w."""
    omega = 2 * math.pi * mode.frequency
    warp = omega / math.tan(omega / (2 * sample_rate))
    two_zeta = 2 * mode.damping_ratio * omega * warp
    a = np.array(
        [warp**2 + two_zeta + omega**2, 2 * (omega**2 - warp**2), warp**2 - two_zeta + omega**2]
    )
    b = mode.gain * warp**2 * np.array([1.0, -2.0, 1.0])
    return b / a[0], a / a[0]


def structural_response(
    flat: np.ndarray, sample_rate: float, modes: tuple[StructuralMode, ...]
) -> np.ndarray:
    """The flat path's acceleration plus the responses of the structure's modes to it.

    Parameters
    ----------
    flat : ndarray
        a_flat at the sample rate [m/s^2].
    sample_rate : float
        [Hz]; every mode must lie below its Nyquist frequency.
    modes : tuple of StructuralMode
        The path's modes; their responses add.
    """
    response = np.array(flat, dtype=np.float64)
    if not modes:
        return response
    from scipy.signal import lfilter

    for mode in modes:
        if not mode.frequency < sample_rate / 2:
            raise CaseError(
                f"structure: a mode at {mode.frequency:g} Hz lies above the Nyquist frequency "
                f"{sample_rate / 2:g} Hz of the sample rate"
            )
        b, a = _mode_coefficients(mode, sample_rate)
        response += lfilter(b, a, flat)
    return response


def add_noise(signal: np.ndarray, snr_db: float | None, seed: int) -> np.ndarray:
    """``signal`` plus white Gaussian noise of power mean(signal^2) / 10^(snr_db / 10);
    unchanged when ``snr_db`` is None."""
    if snr_db is None:
        return signal
    power = float(np.mean(np.square(signal)))
    deviation = math.sqrt(power / 10 ** (snr_db / 10))
    return signal + np.random.default_rng(seed).normal(0.0, deviation, size=signal.shape)


def sensor_plan(
    case: Case, model: Model, probe: Probe, index: int, path: str
) -> tuple[SensorPlan, list[KernelProbe]]:
    """Compile ``Probe("sensor", name)``: the plan and the kernel channels it reads.

    Raises
    ------
    CaseError
        An unknown sensor, or a path the model's DOF set cannot carry (the bearing
        path needs the ring's in-plane DOFs).
    """
    sensor = next((s for s in case.sensors if s.name == probe.target), None)
    if sensor is None:
        known = ", ".join(s.name for s in case.sensors) or "none"
        raise CaseError(
            f"{path}.target: {probe.target!r} is not a sensor of the case (sensors: {known})"
        )
    stage: PlanetaryStage = case.gearbox.stage(sensor.stage)
    prefix = f"{AUXILIARY_PREFIX}{index}_"
    name = sensor.stage
    auxiliary = [Probe("displacement", f"{name}.carrier.theta_z", name=prefix + "carrier")]
    meshes = tuple(f"{prefix}mesh{n}" for n in range(1, stage.planets + 1))
    auxiliary += [
        Probe("mesh_force", f"{name}.ring-planet{n}", name=meshes[n - 1])
        for n in range(1, stage.planets + 1)
    ]
    bearing = None
    if sensor.bearing_gain != 0.0:
        bearing = (prefix + "bearing_x", prefix + "bearing_y")
        auxiliary += [
            Probe("bearing_force", f"{name}.ring_bearing.{axis}", name=channel)
            for axis, channel in zip("xy", bearing)
        ]
    try:
        kernel = compile_probes(model, auxiliary, f"{path}.target")
    except CaseError as error:
        raise CaseError(f"{error} (needed by sensor {sensor.name!r})") from None
    angle = stage.ring_mesh.pressure_angle
    plan = SensorPlan(
        sensor=sensor,
        variable=probe.variable,
        planet_angles=stage.planet_angles,
        force_component=math.sin(angle) if sensor.direction == "radial" else math.cos(angle),
        carrier_channel=prefix + "carrier",
        mesh_channels=meshes,
        bearing_channels=bearing,
        window_width=sensor.width_rad(stage.planets),
        teeth=tuple(int(stage.gear_teeth(m) or 0) for m in ("sun", "planet1", "ring")),
        named=bool(probe.name),
    )
    return plan, kernel


def compile_scene_probes(
    case: Case, model: Model, probes: tuple[Probe, ...], path: str
) -> tuple[list[KernelProbe], tuple]:
    """Kernel channels of a scene's probes, each sensor replaced by the channels it reads,
    and the sensors' plans (in probe order)."""
    compiled: list[KernelProbe] = []
    sensors = []
    for k, probe in enumerate(probes):
        if probe.quantity == "sensor":
            plan, channels = sensor_plan(case, model, probe, k, f"{path}[{k}]")
            sensors.append(plan)
            compiled += channels
        else:
            compiled += compile_probes(model, (probe,), path, first_index=k)
    return compiled, tuple(sensors)


def sensor_signal(
    plan: SensorPlan, channels: dict[str, np.ndarray], sample_rate: float
) -> tuple[np.ndarray, dict[str, object]]:
    """The sensor's acceleration from the auxiliary channels, and its attributes."""
    sensor = plan.sensor
    sensor_angle = math.radians(sensor.angle_deg)
    carrier = channels[plan.carrier_channel]
    flat = np.zeros_like(carrier)
    for psi, channel in zip(plan.planet_angles, plan.mesh_channels):
        window = transmission_window(carrier + psi - sensor_angle, plan.window_width, sensor.window)
        flat += window * channels[channel]
    flat *= sensor.mesh_gain * plan.force_component
    if plan.bearing_channels is not None:
        # the model's in-plane axes turn with the carrier (its matrices keep planet n at
        # psi_n): the sensor's direction in them is theta_s - theta_c
        fx, fy = (channels[c] for c in plan.bearing_channels)
        relative = sensor_angle - carrier
        c, s = np.cos(relative), np.sin(relative)
        along = c * fx + s * fy if sensor.direction == "radial" else -s * fx + c * fy
        flat += sensor.bearing_gain * along
    recorded = structural_response(flat, sample_rate, sensor.structure)
    recorded = add_noise(recorded, sensor.noise_snr_db, int(sensor.noise_seed))
    attrs = {
        "quantity": "sensor",
        "target": sensor.name,
        "units": "m/s^2",
        "long_name": f"{sensor.direction} acceleration at sensor {sensor.name}",
        "sensor_stage": sensor.stage,
        "sensor_angle_deg": float(sensor.angle_deg),
        "sensor_direction": sensor.direction,
        "sensor_window": sensor.window,
        "sensor_window_width_deg": math.degrees(plan.window_width),
        "sensor_mesh_gain": float(sensor.mesh_gain),
        "sensor_bearing_gain": float(sensor.bearing_gain),
        "sensor_structure_modes": len(sensor.structure),
        "sensor_noise_snr_db": "none" if sensor.noise_snr_db is None else sensor.noise_snr_db,
        "sensor_noise_seed": int(sensor.noise_seed),
        # what a gear's synchronous average needs, so that reading the file is enough
        "sensor_planet_angles_deg": [math.degrees(a) for a in plan.planet_angles],
        "sensor_teeth_sun_planet_ring": list(plan.teeth),
    }
    return recorded, attrs


def sensor_carrier_orders(
    run, channel: str, revolutions: int | None = None, steps_per_revolution: int = 4096
) -> tuple[np.ndarray, np.ndarray, int]:
    """Amplitude of a sensor channel at whole carrier orders over the run's last whole
    carrier revolutions (resampled at uniform carrier angle).

    Parameters
    ----------
    run : xarray.Dataset
        A run with the sensor channel and its stage's carrier angle (the displacement
        of ``<stage>.carrier.theta_z``).
    channel : str
        The sensor channel (``sensor_acceleration:<sensor>``, the sensor's name, or a
        named sensor probe's variable).
    revolutions : int, optional
        Revolutions analysed (default: every whole one in the second half of the run).
    steps_per_revolution : int
        Angle steps per revolution (orders up to half of it).

    Returns
    -------
    orders, amplitude, revolutions
        Whole orders 0 .. steps/2, their one-sided amplitudes [the channel's unit] and
        the number of revolutions used.
    """
    from ..signals.angle_resampling import crossing_times, local_cubic, monotone_slopes
    from ..signals.channels import channel_series, find_channel

    signal = channel_series(run, channel)
    if signal is None or "sensor_stage" not in signal.attrs:
        raise CaseError(f"{channel!r} is not a sensor channel of the run")
    target = f"{signal.attrs['sensor_stage']}.carrier.theta_z"
    carrier = find_channel(run, "displacement", target)
    if carrier is None:
        raise CaseError(f"the run has no carrier angle {target!r} for the sensor's carrier orders")
    time = run.time.values
    values = carrier.values
    angle = values * (1.0 if values[-1] >= values[0] else -1.0)
    turns = (angle[-1] - angle[0]) / (2 * math.pi)
    available = int(math.floor(turns / 2)) if revolutions is None else int(revolutions)
    if available < 1 or available > turns:
        raise CaseError(
            f"{channel}: the run covers {turns:.3g} carrier revolutions; "
            "its carrier orders need at least 2"
        )
    end = math.floor(angle[-1] / (2 * math.pi)) * 2 * math.pi
    targets = end - 2 * math.pi * (
        available - np.arange(available * steps_per_revolution) / steps_per_revolution
    )
    crossings = crossing_times(time, angle, monotone_slopes(time, angle), targets)
    resampled = local_cubic(time, signal.values, crossings)
    spectrum = np.abs(np.fft.rfft(resampled)) / resampled.size * 2
    amplitude = spectrum[::available]
    amplitude[0] /= 2  # the mean
    return np.arange(amplitude.size), amplitude, available
