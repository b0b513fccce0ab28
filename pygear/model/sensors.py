"""Accelerometers on the ring or housing of a planetary stage, as a case describes them.

A sensor sits at a fixed angle on the ring's outside (or on the housing next to it)
and records one direction, radial or tangential.  Every planet's ring mesh reaches it
through a path whose gain depends on the angle between the sensor and the planet: a
window that is largest when the planet passes the sensor and zero on the far side
(McFadden & Smith 1985), so that each planet's mesh is heard in turn as the carrier
turns (Inalpolat & Kahraman 2009).  The ring's bearing force reaches it with a fixed
gain.  The structure between the contact and the sensor is a sum of lightly damped
modes (a given frequency response), or a flat gain.  Measurement noise is off unless a
scene sets a signal-to-noise ratio.  :mod:`pygear.analysis.condition.sensor_signal` turns the
simulated forces into the recorded acceleration (docs/condition_monitoring.md).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from ..errors import CaseError
from .values import is_finite_number, is_whole_number

__all__ = ["SENSOR_DIRECTIONS", "SENSOR_WINDOWS", "Sensor", "StructuralMode"]

SENSOR_DIRECTIONS = ("radial", "tangential")
"""Directions a sensor records: along the ring's radius or its circumference."""

SENSOR_WINDOWS = ("hann", "rectangular")
"""Shapes of the transmission window over the planet's angle from the sensor."""

SENSOR_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


@dataclass(frozen=True)
class StructuralMode:
    """One mode of the structure between the ring mesh and the sensor.

    The mode responds to the flat path's acceleration a_flat (the gains of
    :class:`Sensor`) with H(w) = gain (-w^2) / (w_n^2 - w^2 + 2 j zeta w_n w): ``gain``
    far above f_n, gain / (2 zeta) at f_n, falling as (f / f_n)^2 below it.  The sensor
    records a_flat plus every mode's response.

    Parameters
    ----------
    frequency : float
        Natural frequency f_n [Hz], below the Nyquist frequency of the run's samples.
    damping_ratio : float
        Viscous damping ratio zeta [-], in (0, 1).
    gain : float
        The mode's share of the flat path far above f_n [-]; may be negative.
    """

    frequency: float
    damping_ratio: float
    gain: float

    def validate(self, path: str) -> None:
        if not is_finite_number(self.frequency) or self.frequency <= 0:
            raise CaseError(
                f"{path}.frequency must be a finite frequency > 0 Hz (got {self.frequency!r})"
            )
        if not is_finite_number(self.damping_ratio) or not 0 < self.damping_ratio < 1:
            raise CaseError(f"{path}.damping_ratio must lie in (0, 1) (got {self.damping_ratio!r})")
        if not is_finite_number(self.gain):
            raise CaseError(f"{path}.gain must be a finite number (got {self.gain!r})")


@dataclass(frozen=True)
class Sensor:
    """An accelerometer on the ring (or housing) of one planetary stage.

    Parameters
    ----------
    name : str
        Sensor name: a probe ``Probe("sensor", name)`` records it into
        ``sensor_acceleration(sensor, time)`` at ``sensor=name`` (a named probe: into a
        variable of its own name).
    stage : str
        The planetary stage it listens to.
    angle_deg : float
        Angular position of the sensor about the stage axis [deg], measured like the
        planet angles (from +x toward +y; planet 1 sits at ``planet_angles_deg[0]``
        when the carrier angle is zero).
    direction : str
        ``radial`` or ``tangential`` (:data:`SENSOR_DIRECTIONS`): a radial sensor
        receives the radial part of each ring-mesh force, F sin(alpha_r), a tangential one
        F cos(alpha_r), alpha_r the ring mesh's pressure angle.
    window : str
        Shape of the path's angular window, ``hann`` or ``rectangular``.
    window_width_deg : float or None
        Width of the window [deg]: a planet is heard while its angle from the sensor lies
        within half of it either side.  None: 720/N for N planets, the width at which the
        Hann windows of equally spaced planets, 360/N apart, add up to one (a rectangular
        window does at 360/N): the sensor then hears no planet pass.
    mesh_gain : float
        Gain of the ring-mesh path at the window's centre [(m/s^2)/N]: the acceleration per
        newton of force into the ring, before the structure's modes.
    bearing_gain : float
        Gain of the ring's bearing force in the sensor's direction [(m/s^2)/N]; 0 leaves
        that path out.
    structure : tuple of StructuralMode
        Modes of the path; empty for a flat path (acceleration = gain x force).
    noise_snr_db : float or None
        Signal-to-noise ratio of white measurement noise [dB], from the recorded
        signal's power; None (the default) records no noise.  Scenes turn it on with
        ``parameters={"sensors.<name>.noise_snr_db": 20.0}``.
    noise_seed : int
        Seed of the noise generator (a run with the same seed records the same noise).
    """

    name: str
    stage: str
    angle_deg: float = 90.0
    direction: str = "radial"
    window: str = "hann"
    window_width_deg: float | None = None
    mesh_gain: float = 1.0
    bearing_gain: float = 0.0
    structure: tuple[StructuralMode, ...] = ()
    noise_snr_db: float | None = None
    noise_seed: int = 0

    def __post_init__(self) -> None:
        if isinstance(self.structure, list):
            object.__setattr__(self, "structure", tuple(self.structure))

    def validate(self, path: str) -> None:
        """Raise :class:`CaseError` naming the first parameter that breaks its rule."""
        if not isinstance(self.name, str) or not SENSOR_NAME.match(self.name):
            raise CaseError(
                f"{path}.name must be a letter followed by letters, digits or "
                f"underscores (it labels the output's sensor; got {self.name!r})"
            )
        if not is_finite_number(self.angle_deg):
            raise CaseError(
                f"{path}.angle_deg must be a finite angle in degrees (got {self.angle_deg!r})"
            )
        if self.direction not in SENSOR_DIRECTIONS:
            raise CaseError(
                f"{path}.direction must be one of {', '.join(SENSOR_DIRECTIONS)} "
                f"(got {self.direction!r})"
            )
        if self.window not in SENSOR_WINDOWS:
            raise CaseError(
                f"{path}.window must be one of {', '.join(SENSOR_WINDOWS)} (got {self.window!r})"
            )
        width = self.window_width_deg
        if width is not None and (not is_finite_number(width) or not 0 < width <= 360):
            raise CaseError(
                f"{path}.window_width_deg must lie in (0, 360] degrees or be None "
                f"(None: 720/N for N planets; got {width!r})"
            )
        for name in ("mesh_gain", "bearing_gain"):
            if not is_finite_number(getattr(self, name)):
                raise CaseError(
                    f"{path}.{name} must be a finite number in (m/s^2)/N "
                    f"(got {getattr(self, name)!r})"
                )
        if not isinstance(self.structure, tuple):
            raise CaseError(f"{path}.structure must be a tuple of StructuralMode")
        for n, mode in enumerate(self.structure):
            if not isinstance(mode, StructuralMode):
                raise CaseError(f"{path}.structure[{n}] must be a StructuralMode (got {mode!r})")
            mode.validate(f"{path}.structure[{n}]")
        snr = self.noise_snr_db
        if snr is not None and not is_finite_number(snr):
            raise CaseError(
                f"{path}.noise_snr_db must be a finite ratio in dB or None "
                f"(None: no noise; got {snr!r})"
            )
        if not is_whole_number(self.noise_seed) or self.noise_seed < 0:
            raise CaseError(
                f"{path}.noise_seed must be a whole number >= 0 (got {self.noise_seed!r})"
            )

    def width_rad(self, planets: int) -> float:
        """The window's width [rad]: the given one, or 4 pi / planets."""
        if self.window_width_deg is None:
            return 4 * math.pi / planets
        return math.radians(self.window_width_deg)


def validate_sensors(sensors: tuple, stages: dict[str, object], path: str = "sensors") -> None:
    """Check a case's sensors: each a :class:`Sensor` on a planetary stage, names unique.

    ``stages`` maps stage names to stages; a sensor's stage must have a ring
    (``planets`` attribute).
    """
    if not isinstance(sensors, tuple):
        raise CaseError(f"{path} must be a tuple of Sensor (got {type(sensors).__name__})")
    seen = set()
    for n, sensor in enumerate(sensors):
        where = f"{path}[{n}]"
        if not isinstance(sensor, Sensor):
            raise CaseError(f"{where} must be a Sensor (got {sensor!r})")
        sensor.validate(where)
        where = f"{path}.{sensor.name}"  # a valid name now: the path a scene sets it by
        stage = stages.get(sensor.stage)
        if stage is None or not hasattr(stage, "planets"):
            planetary = ", ".join(name for name, s in stages.items() if hasattr(s, "planets"))
            raise CaseError(
                f"{where}.stage {sensor.stage!r} is not a planetary stage of the "
                f"gearbox (planetary stages: {planetary or 'none'})"
            )
        if sensor.name in seen:
            raise CaseError(f"{where}.name {sensor.name!r} is used twice; sensor names are unique")
        seen.add(sensor.name)
