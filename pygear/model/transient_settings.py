"""Transient settings of a scene: time stepping, drive and load laws, output probes.

These are descriptions only (frozen dataclasses checked by ``validate``); the run
itself lives in :mod:`pygear.analysis.time.transient`.  A case file writes, for the seed's run-up
(docs/model.md §6.3)::

    Transient(
        duration=5.0, time_step=2.5e-5, sample_rate=40e3,
        input="planetary.carrier.theta_z", output="planetary.sun.theta_z",
        drive=TorqueLaw.constant(10.0),
        load=TorqueLaw.generator(rated_drive_torque=10.0, exponent=2.0),
        speed_reference_rpm=120.0,
        probes=(Probe("speed", "planetary.carrier"), Probe("speed", "planetary.sun")),
    )
"""

from __future__ import annotations

import math
import re
import sys
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import CaseError
from .components import is_finite_number, is_whole_number, require_non_negative, require_positive
from .reduction_settings import Reductions

__all__ = [
    "EQUIVALENT_LOAD_MODES",
    "INTEGRATORS",
    "LAW_KINDS",
    "PROBE_QUANTITIES",
    "RUN_VARIABLES",
    "Probe",
    "TorqueLaw",
    "Transient",
]

INTEGRATORS = ("newmark", "hht", "generalized-alpha")
"""Average-acceleration Newmark, HHT-alpha and generalized-alpha (docs/model.md §6.1)."""

EQUIVALENT_LOAD_MODES = ("predictor", "iterate", "refactor")
"""How the mesh-stiffness variation enters a step (docs/model.md §6.2)."""

LAW_KINDS = ("constant", "ramp", "table", "generator")
"""Torque laws; ``generator`` is the paper's speed-squared load law (eq. 31)."""

PROBE_QUANTITIES = {
    "displacement": "a DOF label, e.g. planetary.ring.y",
    "velocity": "a DOF label",
    "acceleration": "a DOF label",
    "speed": "a body, e.g. planetary.sun (its theta_z speed in rpm)",
    "mesh_deflection": "a mesh name, e.g. sun-planet1",
    "mesh_force": "a mesh name",
    "mesh_stiffness": "a mesh name",
    "bearing_force": "a bearing spring, e.g. planetary.ring_bearing.y",
    "drive_torque": "nothing (the input member's drive)",
    "load_torque": "nothing (the output member's load)",
    "sensor": "a sensor of the case, e.g. ring_sensor (its acceleration in m/s^2)",
}
"""Quantities a probe can keep, and what its target names."""

RUN_VARIABLES = frozenset(
    {
        # coordinates and results of the run (pygear.analysis.time.transient), its grouped
        # channels and their label dimensions (pygear.analysis.time.run_layout)
        "time",
        "scene",
        "body",
        "planet",
        "equilibrium_speed",
        "planet_tangential_speed",
        "t_s",
        "member",
        "translation_dof",
        "rotation_dof",
        "mesh",
        "bearing",
        "bearing_rotation",
        "sensor",
        "sensor_gear",
        "sensor_planet",
        "sensor_stage",
        "sensor_angle",
        "sensor_direction",
        "sensor_window",
        "sensor_window_width",
        "sensor_mesh_gain",
        "sensor_bearing_gain",
        "sensor_structure_modes",
        "sensor_noise_snr",
        "sensor_noise_seed",
        "sensor_planet_angle",
        "sensor_teeth",
        "speed",
        "translation_displacement",
        "translation_velocity",
        "translation_acceleration",
        "rotation_displacement",
        "rotation_velocity",
        "rotation_acceleration",
        "mesh_force",
        "mesh_deflection",
        "mesh_stiffness",
        "bearing_force",
        "bearing_moment",
        "sensor_acceleration",
        "drive_torque",
        "load_torque",
        # the frequencies a run file carries for its signal analysis (pygear.runs.outputs)
        "natural_frequency",
        "mode",
        "mode_class",
        "mesh_frequency",
        "mesh_stage",
        "mesh_teeth",
        # <scene>_<channel> files would replace the scene's own <scene>_<suffix> files
        "speeds",
        "sensitivity",
        "energy",
        "mode_shape",
    }
)
"""Names a run takes for its own coordinates, variables and files; a probe of the same
name would be overwritten, clash with them, or overwrite a file."""

PROBE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
"""A probe name: a letter, then letters, digits and underscores.  That is a valid NetCDF
(and CF) variable name and a safe file-name part; ``__`` names the full state's
internal channels."""

_TIME_TOLERANCE = 1e-9


@dataclass(frozen=True)
class TorqueLaw:
    """A torque as a function of time (drive) or of the output speed (load).

    Build one with :meth:`constant`, :meth:`ramp`, :meth:`table` or :meth:`generator`.

    Parameters
    ----------
    kind : str
        One of :data:`LAW_KINDS`.
    torque : float
        Constant torque, final torque of a ramp, or the rated drive torque T_D of the
        generator law [N m].  As a drive, positive turns the input member along +theta
        of its DOF and negative the other way (see ``Transient.drive``); the generator
        law takes T_D > 0 and always brakes the output's actual rotation.
    start, ramp_time : float
        Ramp start and length [s]; the length is > 0.
    times, torques : tuple of float
        Table samples [s], [N m], as many of each (at least one), the times strictly
        increasing; linear interpolation, held at the ends.
    exponent : float
        n of the generator law [-], > 0.
    ratio : float or None
        i of the generator law [-], > 0; None takes the kinematic ratio of the stage.
    """

    kind: str = "constant"
    torque: float = 0.0
    start: float = 0.0
    ramp_time: float = 1.0
    times: tuple[float, ...] = ()
    torques: tuple[float, ...] = ()
    exponent: float = 2.0
    ratio: float | None = None

    @classmethod
    def constant(cls, torque: float) -> TorqueLaw:
        """T(t) = torque."""
        return cls("constant", torque=torque)

    @classmethod
    def ramp(cls, torque: float, ramp_time: float, start: float = 0.0) -> TorqueLaw:
        """T = torque min(max((t - start) / ramp_time, 0), 1)."""
        return cls("ramp", torque=torque, start=start, ramp_time=ramp_time)

    @classmethod
    def table(cls, times: Iterable[float], torques: Iterable[float]) -> TorqueLaw:
        """Linear interpolation of (time, torque) samples, held beyond the ends."""
        return cls(
            "table",
            times=tuple(float(t) for t in times),
            torques=tuple(float(t) for t in torques),
        )

    @classmethod
    def generator(
        cls, rated_drive_torque: float, exponent: float = 2.0, ratio: float | None = None
    ) -> TorqueLaw:
        """The paper's load law (eq. 31): zero until t_s, then
        T_L = (T_D / i) (omega_out / (i omega_0))^n."""
        return cls("generator", torque=rated_drive_torque, exponent=exponent, ratio=ratio)

    def validate(self, path: str) -> None:
        """Raise :class:`CaseError` naming the first bad field."""
        if self.kind not in LAW_KINDS:
            raise CaseError(
                f"{path}.kind must be one of {', '.join(LAW_KINDS)} (got {self.kind!r})"
            )
        if not _is_finite(self.torque):
            raise CaseError(f"{path}.torque must be a finite number (got {self.torque!r})")
        if self.kind == "ramp":
            require_positive(f"{path}.ramp_time", self.ramp_time)
            if not _is_finite(self.start):
                raise CaseError(f"{path}.start must be a finite time (got {self.start!r})")
        if self.kind == "table":
            if len(self.times) < 1 or len(self.times) != len(self.torques):
                raise CaseError(
                    f"{path}: times and torques must hold the same number (>= 1) of samples "
                    f"(got {len(self.times)} and {len(self.torques)})"
                )
            if not all(_is_finite(v) for v in self.times + self.torques):
                raise CaseError(f"{path}: times and torques must be finite numbers")
            for k in range(1, len(self.times)):
                if not self.times[k] > self.times[k - 1]:
                    raise CaseError(
                        f"{path}.times must increase strictly: times[{k}] = {self.times[k]!r} "
                        f"follows times[{k - 1}] = {self.times[k - 1]!r}"
                    )
        if self.kind == "generator":
            require_positive(f"{path}.exponent", self.exponent)
            if self.ratio is not None:
                require_positive(f"{path}.ratio", self.ratio)

    def describe(self) -> str:
        """One line for file attributes."""
        if self.kind == "constant":
            return f"constant {self.torque:g} N m"
        if self.kind == "ramp":
            return (
                f"ramp to {self.torque:g} N m from t = {self.start:g} s over {self.ramp_time:g} s"
            )
        if self.kind == "table":
            return f"table of {len(self.times)} samples, linear interpolation"
        ratio = "kinematic ratio" if self.ratio is None else f"i = {self.ratio:g}"
        return (
            f"generator: 0 until t_s, then (T_D/i)(omega_out/(i omega_0))^{self.exponent:g}, "
            f"T_D = {self.torque:g} N m, {ratio}"
        )

    def direction(self) -> int:
        """+1 or -1: the sign of the torque this law mostly applies (for a drive)."""
        if self.kind == "table":
            total = sum(self.torques)
            return -1 if total < 0 else 1
        return -1 if self.torque < 0 else 1


_PACKAGE = Path(__file__).resolve().parent.parent
"""pygear's own directory: frames inside it are not where a case wrote something."""


def written_at() -> str:
    """``<directory>/<file>:<line>`` of the innermost caller outside pygear (and outside
    the standard library's dataclasses), or "" when there is none."""
    frame = sys._getframe(1)
    while frame is not None:
        filename = frame.f_code.co_filename
        path = Path(filename)
        inside = path.is_relative_to(_PACKAGE) if path.is_absolute() else False
        if not inside and not filename.startswith("<") and path.name != "dataclasses.py":
            return f"{path.parent.name}/{path.name}:{frame.f_lineno}"
        frame = frame.f_back
    return ""


def where_written(item: object) -> str:
    """`` (written at <file>:<line>)`` for an item that knows its origin, else ""."""
    origin = getattr(item, "origin", "")
    return f" (written at {origin})" if origin else ""


@dataclass(frozen=True)
class Probe:
    """One output channel, sampled at the scene's sample rate.

    Parameters
    ----------
    quantity : str
        One of :data:`PROBE_QUANTITIES`.
    target : str
        What it measures (a DOF label, a body, a mesh or a bearing spring).
    name : str, optional
        A variable of this name in the output file, over ``time`` alone.  Without a
        name the probe joins its kind's grouped variable (``speed(member, time)``,
        ``mesh_force(mesh, time)``, ...; docs/data_model.md).
    """

    quantity: str
    target: str = ""
    name: str | None = None
    _origin: str = field(default="", repr=False, compare=False, init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_origin", written_at())

    @property
    def origin(self) -> str:
        """Where the probe was written, ``<case dir>/case.py:<line>`` (the first caller
        outside pygear), or "" when pygear made it; error messages about the probe end
        with it."""
        return self._origin

    @property
    def variable(self) -> str:
        """The NetCDF variable name."""
        if self.name:
            return self.name
        if self.quantity == "sensor":
            return f"{self.target}_acceleration"
        target = self.target.replace(".", "_").replace("-", "_")
        return f"{target}_{self.quantity}" if target else self.quantity

    def validate(self, path: str) -> None:
        """Raise :class:`CaseError` for an unknown quantity, a missing target, or a name
        that is not a NetCDF variable name or is taken by the run (:data:`RUN_VARIABLES`)."""
        if self.name is not None:
            if not isinstance(self.name, str) or not PROBE_NAME.match(self.name):
                raise CaseError(
                    f"{path}.name must be a letter followed by letters, digits or underscores "
                    f"(a NetCDF variable name; got {self.name!r})"
                )
            if self.name in RUN_VARIABLES:
                raise CaseError(
                    f"{path}.name {self.name!r} is taken by the run's own output (taken: "
                    f"{', '.join(sorted(RUN_VARIABLES))}); choose another name"
                )
        if self.quantity not in PROBE_QUANTITIES:
            raise CaseError(
                f"{path}.quantity must be one of {', '.join(PROBE_QUANTITIES)} "
                f"(got {self.quantity!r})"
            )
        if self.quantity not in ("drive_torque", "load_torque") and not self.target:
            raise CaseError(
                f"{path}.target must name {PROBE_QUANTITIES[self.quantity]} "
                f"for a {self.quantity} probe"
            )


def steps_per_sample(sample_rate: float | None, time_step: float) -> int:
    """Steps per recorded sample: every step without a sample rate [-]."""
    if sample_rate is None:
        return 1
    return int(round(1.0 / (sample_rate * time_step)))


@dataclass(frozen=True)
class Transient:
    """Settings of a transient analysis (docs/model.md §6).

    Parameters
    ----------
    duration : float
        Simulated time [s], > 0 and at least one time step.
    time_step : float
        Constant step Delta t [s], > 0.
    sample_rate : float, optional
        Output rate [Hz]; 1/(sample_rate time_step) must be whole.  Default 1/time_step.
    integrator : str
        ``newmark`` (average acceleration), ``hht`` or ``generalized-alpha``.
    spectral_radius : float, optional
        rho_inf [-] of HHT (0.5 .. 1, default 0.9) or generalized-alpha (0 .. 1, default 0.8).
    equivalent_load : str
        ``predictor``, ``iterate`` or ``refactor`` (:data:`EQUIVALENT_LOAD_MODES`).
    tolerance : float
        Iteration stops when the mesh loads change by less than ``tolerance`` times
        the largest mean-stiffness mesh force [-], > 0.
    max_iterations : int
        Iterations per step before ``iterate`` fails (``refactor`` then refactors), >= 1.
    refactor_threshold : float
        ``refactor``: refactor when a mesh stiffness moved by more than this share of
        its mean from the stiffness in the factor [-], >= 0.  Also the jump that
        ``restart_at_jumps`` reacts to.
    restart_at_jumps : bool
        Restart the acceleration from the equation of motion when a mesh stiffness
        jumps between two steps (a tooth pair enters or leaves contact): second order
        when the steps land on the switching instants (docs/stability.md).  Average
        acceleration (``newmark``) only, and not with tooth separation.
    input, output : str, optional
        DOF labels of the driven and the loaded member (default: the first stage's
        carrier and sun theta_z).
    drive : TorqueLaw, optional
        Torque on the input member [N m].  Sign convention: a positive torque acts
        along +theta of the input DOF (``planetary.carrier.theta_z``: counter-clockwise
        seen from +z, right-hand rule) and a negative torque the other way.  The drive's
        sense (the sign of its torque; of the sum of a table's torques) sets the running
        direction: the contact signs, the tooth-contact table and t_s follow it, so a
        negative drive runs the mirror image of the positive one.
    load : TorqueLaw, optional
        Torque against the output member's actual rotation (the generator law has the
        sign of the output speed and brakes it in either sense).
    speed_reference_rpm : float, optional
        omega_0 > 0: t_s is the first instant the input speed reaches it in the drive's
        sense; the generator law needs it [rpm].
    probes : tuple of Probe
        Output channels; nothing else is stored.
    full_state : bool
        Also keep every DOF's displacement, velocity and acceleration.
    mean_window : float
        Equilibrium speeds are means over the last ``mean_window`` seconds [s]; at
        least one time step and at most the duration.
    deflection_limit : float
        A mesh deflection beyond this stops the run as diverged [m], > 0.
    contact_sign : tuple of int, optional
        s_m per mesh (+1 or -1); default from a static solution under the drive.
    initial_speed_rpm : float
        Speed of the input member at t = 0 [rpm], signed like its DOF; every member
        starts on the rigid-body rotation at that speed (steady operation without a
        run-up from rest).  0: from rest.
    start_loaded : bool
        Start in the static deflection under the torques at t = 0, the rigid-body
        rotation taking the net torque as acceleration (inertia relief), instead of
        undeflected: a steady operating point then starts without the torsional swing
        of loads applied at once.  The deflection is that of the mean mesh stiffness.
    reductions : Reductions, optional
        What a streamed run reduces on the fly (decimated channels, statistics, load
        duration distributions, rainflow matrices; :mod:`pygear.model.reduction_settings`).
    """

    duration: float
    time_step: float
    sample_rate: float | None = None
    integrator: str = "newmark"
    spectral_radius: float | None = None
    equivalent_load: str = "predictor"
    tolerance: float = 1e-8
    max_iterations: int = 50
    refactor_threshold: float = 0.1
    restart_at_jumps: bool = False
    input: str | None = None
    output: str | None = None
    drive: TorqueLaw | None = None
    load: TorqueLaw | None = None
    speed_reference_rpm: float | None = None
    probes: tuple[Probe, ...] = ()
    full_state: bool = False
    mean_window: float = 1.0
    deflection_limit: float = 1e-3
    contact_sign: tuple[int, ...] | None = None
    initial_speed_rpm: float = 0.0
    start_loaded: bool = False
    reductions: Reductions | None = None

    def __post_init__(self) -> None:
        if isinstance(self.probes, list):
            object.__setattr__(self, "probes", tuple(self.probes))

    @property
    def steps(self) -> int:
        """Number of steps: the duration in whole steps."""
        return int(math.floor(self.duration / self.time_step * (1 + _TIME_TOLERANCE)))

    @property
    def decimation(self) -> int:
        """Steps per output sample."""
        return steps_per_sample(self.sample_rate, self.time_step)

    def validate(self, path: str) -> None:
        """Raise :class:`CaseError` naming the first bad setting."""
        require_positive(f"{path}.time_step", self.time_step)
        require_positive(f"{path}.duration", self.duration)
        if self.duration < self.time_step * (1 - _TIME_TOLERANCE):
            raise CaseError(
                f"{path}.duration {self.duration!r} s is shorter than one time step "
                f"({path}.time_step = {self.time_step!r} s)"
            )
        if self.steps >= 2**31 - 1:
            raise CaseError(
                f"{path}: {self.steps} steps are more than one run can count (2**31 - 1); "
                f"shorten {path}.duration or lengthen {path}.time_step"
            )
        if self.sample_rate is not None:
            require_positive(f"{path}.sample_rate", self.sample_rate)
            ratio = 1.0 / (self.sample_rate * self.time_step)
            if ratio < 1 - _TIME_TOLERANCE:
                raise CaseError(
                    f"{path}.sample_rate {self.sample_rate:g} Hz is above the step rate "
                    f"1/time_step = {1 / self.time_step:g} Hz"
                )
            if abs(ratio - round(ratio)) > 1e-6 * ratio:
                raise CaseError(
                    f"{path}.sample_rate {self.sample_rate:g} Hz is not reachable: "
                    f"1/(sample_rate time_step) = {ratio:.6g} must be a whole number of steps"
                )
        if self.integrator not in INTEGRATORS:
            raise CaseError(
                f"{path}.integrator must be one of {', '.join(INTEGRATORS)} "
                f"(got {self.integrator!r})"
            )
        if self.spectral_radius is not None:
            low = 0.5 if self.integrator == "hht" else 0.0
            if not (_is_finite(self.spectral_radius) and low <= self.spectral_radius <= 1):
                raise CaseError(
                    f"{path}.spectral_radius must lie in [{low:g}, 1] for {self.integrator} "
                    f"(got {self.spectral_radius!r})"
                )
        if self.equivalent_load not in EQUIVALENT_LOAD_MODES:
            raise CaseError(
                f"{path}.equivalent_load must be one of {', '.join(EQUIVALENT_LOAD_MODES)} "
                f"(got {self.equivalent_load!r})"
            )
        require_positive(f"{path}.tolerance", self.tolerance)
        if not (is_whole_number(self.max_iterations) and self.max_iterations >= 1):
            raise CaseError(f"{path}.max_iterations must be a whole number >= 1")
        require_non_negative(f"{path}.refactor_threshold", self.refactor_threshold)
        if not isinstance(self.restart_at_jumps, (bool, np.bool_)):
            raise CaseError(f"{path}.restart_at_jumps must be True or False")
        if self.restart_at_jumps and self.integrator != "newmark":
            raise CaseError(
                f"{path}.restart_at_jumps needs integrator 'newmark' (average acceleration): "
                f"a restart solves the equation of motion at a step instant, which "
                f"{self.integrator} does not enforce (got integrator {self.integrator!r})"
            )
        require_positive(f"{path}.mean_window", self.mean_window)
        if self.mean_window < self.time_step * (1 - _TIME_TOLERANCE):
            raise CaseError(
                f"{path}.mean_window {self.mean_window!r} s must be at least one time_step "
                f"({self.time_step!r} s): the equilibrium speeds average over it"
            )
        if self.mean_window > self.duration * (1 + _TIME_TOLERANCE):
            raise CaseError(
                f"{path}.mean_window {self.mean_window!r} s must be at most the duration "
                f"({self.duration!r} s): the equilibrium speeds average over the run's end"
            )
        require_positive(f"{path}.deflection_limit", self.deflection_limit)
        for name in ("drive", "load"):
            law = getattr(self, name)
            if law is not None:
                if not isinstance(law, TorqueLaw):
                    raise CaseError(f"{path}.{name} must be a TorqueLaw (got {law!r})")
                law.validate(f"{path}.{name}")
        if self.drive is not None and self.drive.kind == "generator":
            raise CaseError(f"{path}.drive: the generator law is a load law (use it as load)")
        if self.speed_reference_rpm is not None:
            require_positive(f"{path}.speed_reference_rpm", self.speed_reference_rpm)
        elif self.load is not None and self.load.kind == "generator":
            raise CaseError(
                f"{path}.speed_reference_rpm (omega_0) is needed by the generator load law"
            )
        for k, probe in enumerate(self.probes):
            if not isinstance(probe, Probe):
                raise CaseError(f"{path}.probes[{k}] must be a Probe (got {probe!r})")
            try:
                probe.validate(f"{path}.probes[{k}]")
            except CaseError as error:
                raise CaseError(f"{error}{where_written(probe)}") from None
        names = [p.variable for p in self.probes]
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise CaseError(f"{path}.probes: variable names must be unique ({duplicates})")
        if self.contact_sign is not None and any(s not in (1, -1) for s in self.contact_sign):
            raise CaseError(f"{path}.contact_sign entries must be +1 or -1")
        if not _is_finite(self.initial_speed_rpm):
            raise CaseError(
                f"{path}.initial_speed_rpm must be a finite speed in rpm "
                f"(got {self.initial_speed_rpm!r})"
            )
        if not isinstance(self.start_loaded, bool):
            raise CaseError(
                f"{path}.start_loaded must be True or False (got {self.start_loaded!r})"
            )
        if self.reductions is not None:
            if not isinstance(self.reductions, Reductions):
                raise CaseError(f"{path}.reductions must be a Reductions (got {self.reductions!r})")
            rate = 1.0 / (self.decimation * self.time_step)
            self.reductions.validate(f"{path}.reductions", rate)

    def describe(self) -> str:
        """One line for logs."""
        return (
            f"{self.duration:g} s in steps of {self.time_step:g} s, {self.integrator}, "
            f"{self.equivalent_load}"
        )


_is_finite = is_finite_number
