"""Transient scenes of a plain rotor: a speed profile, unbalances at discs, a time step.

A :class:`RotorScene` of a :class:`~pygear.model.rotor_case.RotorCase` runs the rotor's
equations of motion in time, with every shaft element's and disc's gyroscopic term
at the prescribed speed and the unbalances' forces m e (Omega^2 cos psi + Omega' sin
psi, Omega^2 sin psi - Omega' cos psi) turning with the shaft (docs/rotors.md).  The
speed is a profile of time: a constant speed (one sample), a run-up or a coast-down
(linear between the samples, held beyond them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import CaseError
from .components import require_non_negative, require_positive
from .transient_settings import INTEGRATORS, steps_per_sample

__all__ = ["DiscUnbalance", "RotorRun", "RotorScene"]


@dataclass(frozen=True)
class DiscUnbalance:
    """An unbalance at a disc.

    Parameters
    ----------
    disc : str
        The disc's name.
    mass_eccentricity : float
        m e [kg m], >= 0.
    phase_deg : float
        Angle of the unbalance from x at t = 0 [deg].
    """

    disc: str
    mass_eccentricity: float
    phase_deg: float = 0.0

    def validate(self, path: str) -> None:
        """Raise :class:`CaseError` on a non-finite or negative value."""
        require_non_negative(f"{path}.mass_eccentricity", self.mass_eccentricity)
        if not (isinstance(self.phase_deg, int | float) and math.isfinite(self.phase_deg)):
            raise CaseError(f"{path}.phase_deg must be a finite number (got {self.phase_deg!r})")


@dataclass(frozen=True)
class RotorRun:
    """Settings of a rotor transient.

    Parameters
    ----------
    duration : float
        Simulated time [s], > 0.
    time_step : float
        Delta t [s], > 0; at most 1/20 of the period of the highest frequency of
        interest (the trapezoidal rule's phase error is (w dt)^2 / 12 per radian).
    times : tuple of float
        Instants of the speed profile [s], increasing.
    speeds_rpm : tuple of float
        The rotor's speed at those instants [rpm]; linear between, held beyond.
    unbalances : tuple of DiscUnbalance
        Unbalances turning with their discs' shafts.
    sample_rate : float, optional
        Output rate [Hz]; 1/(sample_rate time_step) must be whole.  Default 1/time_step.
    integrator : str
        ``newmark`` (average acceleration, energy-conserving), ``hht`` or
        ``generalized-alpha``.
    tolerance : float
        Relative change of the gyroscopic force at which a step's iteration stops [-].
    """

    duration: float
    time_step: float
    times: tuple[float, ...] = (0.0,)
    speeds_rpm: tuple[float, ...] = (0.0,)
    unbalances: tuple[DiscUnbalance, ...] = ()
    sample_rate: float | None = None
    integrator: str = "newmark"
    tolerance: float = 1e-8

    @property
    def steps(self) -> int:
        """Time steps of the run."""
        return int(round(self.duration / self.time_step))

    @property
    def decimation(self) -> int:
        """Steps per recorded sample."""
        return steps_per_sample(self.sample_rate, self.time_step)

    def validate(self, path: str) -> None:
        """Raise :class:`CaseError` naming the first wrong setting."""
        require_positive(f"{path}.duration", self.duration)
        require_positive(f"{path}.time_step", self.time_step)
        if self.time_step > self.duration:
            raise CaseError(f"{path}.time_step must not exceed duration ({self.duration} s)")
        if len(self.times) != len(self.speeds_rpm) or not self.times:
            raise CaseError(f"{path}.times and speeds_rpm must hold as many values, at least one")
        for name in ("times", "speeds_rpm"):
            values = getattr(self, name)
            if not all(isinstance(v, int | float) and math.isfinite(v) for v in values):
                raise CaseError(f"{path}.{name} must hold finite numbers (got {values!r})")
        if any(b <= a for a, b in zip(self.times, self.times[1:])):
            raise CaseError(f"{path}.times must increase strictly (got {self.times!r})")
        if self.sample_rate is not None:
            require_positive(f"{path}.sample_rate", self.sample_rate)
            ratio = 1.0 / (self.sample_rate * self.time_step)
            if ratio < 1.0 - 1e-9 or abs(ratio - round(ratio)) > 1e-6 * ratio:
                raise CaseError(
                    f"{path}.sample_rate {self.sample_rate:g} Hz: 1/(sample_rate time_step) = "
                    f"{ratio:.6g} must be a whole number of steps"
                )
        if self.integrator not in INTEGRATORS:
            raise CaseError(
                f"{path}.integrator must be one of {', '.join(INTEGRATORS)} "
                f"(got {self.integrator!r})"
            )
        require_positive(f"{path}.tolerance", self.tolerance)
        for k, unbalance in enumerate(self.unbalances):
            unbalance.validate(f"{path}.unbalances[{k}]")


@dataclass(frozen=True)
class RotorScene:
    """A transient scene of a plain rotor (``pygear run``).

    Parameters
    ----------
    name : str
        Scene name (output files are named after it).
    run : RotorRun
        The speed profile, the unbalances and the time step.
    description : str
        One line on what the scene shows.
    analyses : tuple of str
        ``("transient",)``, the one analysis a rotor scene runs.
    parameters : tuple
        Empty: a rotor scene changes no case parameter.
    transient : None
        None: a rotor scene's settings are ``run``.
    """

    name: str
    run: RotorRun
    description: str = ""
    analyses: tuple[str, ...] = ("transient",)
    parameters: tuple[tuple[str, object], ...] = ()
    transient: None = None

    @property
    def dof_set(self) -> str:
        """A rotor transient runs on every DOF of the shaft nodes."""
        return "spatial"

    def validate(self, path: str) -> None:
        """Raise :class:`CaseError` naming the first wrong setting."""
        if self.analyses != ("transient",):
            raise CaseError(f"{path}.analyses must be ('transient',) (got {self.analyses!r})")
        if self.parameters:
            raise CaseError(f"{path}.parameters: a rotor scene changes no case parameter")
        if not isinstance(self.run, RotorRun):
            raise CaseError(f"{path}.run must be a RotorRun (got {self.run!r})")
        self.run.validate(f"{path}.run")
