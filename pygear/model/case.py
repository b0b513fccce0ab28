"""Cases and scenes: what a case directory describes and how it is loaded.

A case is a directory holding ``case.py``, a Python file that builds a module-level
``case = Case(...)``: the gearbox, its damping and its scenes.  A scene names the
analyses to run and the effects they call for; nothing outside that list is built.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..errors import CaseError
from .case_files import find_case_dir, load_case_module
from .components import ToothDefect, is_finite_number, plain_numbers, require_non_negative
from .drivetrain import Drivetrain
from .gearbox import Gearbox
from .names import DOF_SETS, FORMULATIONS
from .response_settings import Response
from .sensors import Sensor, validate_sensors
from .time_step import check_time_step
from .tooth_faults import check_fault_on_tooth
from .transient_settings import Transient, where_written

if TYPE_CHECKING:
    from .rolling_bearing import RollingBearing

__all__ = [
    "ANALYSES",
    "DOF_SETS",
    "EFFECTS",
    "FORMULATIONS",
    "Case",
    "Gearbox",
    "RayleighDamping",
    "Scene",
    "find_case_dir",
    "load_case",
    "load_case_module",
    "replace_parameter",
    "get_parameter",
    "merged_defects",
    "validate_defects",
]

ANALYSES = ("modal", "sensitivity", "transient", "signal", "response")
"""Analyses a scene may ask for."""

SIGNAL_AFTER = 1.0
"""Start-up the 'signal' analysis of a run skips [s] (the paper analyses t > 1 s)."""

SIGNAL_BAND = (5000.0, 10000.0)
"""Resonance band the 'signal' analysis demodulates [Hz] (the paper's DRA band): it must
lie below the Nyquist frequency, half the run's sample rate."""

EFFECTS = (
    "speed_dependent_planet_terms",
    "gyroscopic_all_members",
    "time_varying_mesh_stiffness",
    "tooth_separation",
    "helical_coupling",
    "rolling_bearing_contact",
)
"""Optional effects a scene may call for (docs/model.md §7).  ``helical_coupling`` asks
that a helical stage keep its out-of-plane DOFs (the default when the DOF set is left
open); naming it refuses a DOF set that would drop them.  ``gyroscopic_all_members``
writes every planetary stage in its carrier's frame with Cooley & Parker's (2012)
gyroscopic and centripetal terms on every member (``speed_dependent_planet_terms``:
the planets only).  ``rolling_bearing_contact`` puts the case's rolling bearings into
a transient run as Hertz contacts with clearance, varying compliance and defects in
place of their linear springs (docs/bearings.md)."""


@dataclass(frozen=True)
class RayleighDamping:
    """Rayleigh damping C = alpha M + beta K0.

    Parameters
    ----------
    mass_coefficient : float
        alpha [1/s], >= 0: mass-proportional damping (it also brakes the rigid rotation).
    stiffness_coefficient : float
        beta [s], >= 0: stiffness-proportional damping.
    """

    mass_coefficient: float = 0.0
    stiffness_coefficient: float = 0.0

    def validate(self, path: str) -> None:
        require_non_negative(f"{path}.mass_coefficient", self.mass_coefficient)
        require_non_negative(f"{path}.stiffness_coefficient", self.stiffness_coefficient)


@dataclass(frozen=True)
class Scene:
    """What to compute and which effects to include.

    Parameters
    ----------
    name : str
        Scene name, unique in the case; output files are named after it, so it has no
        path separator and no leading dot.
    analyses : tuple of str
        Analyses to run, from :data:`ANALYSES`.
    formulation : str or None
        Formulation for this scene; the case's when None.
    dof_set : str or None
        DOF set from :data:`DOF_SETS`; None lets pygear pick the smallest exact one.
    effects : tuple of str
        Effects from :data:`EFFECTS`.
    carrier_speed_rpm : float
        Nominal carrier speed for speed-dependent terms [rpm], finite; non-zero with
        ``speed_dependent_planet_terms``.
    defects : tuple of ToothDefect
        Tooth defects of this scene, on top of the case's own (a scene's defect on
        the same tooth replaces the case's).  Checked against the gearbox by
        :meth:`Case.validate`.
    transient : Transient or None
        Settings of the ``transient`` analysis (time step, laws, probes).
    parameters : mapping of str to value
        Case parameters this scene changes, by path (``planetary.planet_angles_deg``):
        a scene of the same gearbox with, say, a planet position error.
    response : Response or None
        Settings of the ``response`` analysis (speeds, harmonics, contact loss).
    """

    name: str
    analyses: tuple[str, ...] = ("modal",)
    formulation: str | None = None
    dof_set: str | None = None
    effects: tuple[str, ...] = ()
    carrier_speed_rpm: float = 0.0
    defects: tuple[ToothDefect, ...] = ()
    transient: Transient | None = None
    parameters: tuple[tuple[str, object], ...] = ()
    response: Response | None = None

    def __post_init__(self) -> None:
        if isinstance(self.defects, list):
            object.__setattr__(self, "defects", tuple(self.defects))
        if isinstance(self.parameters, dict):
            object.__setattr__(self, "parameters", tuple(sorted(self.parameters.items())))

    def validate(self, path: str) -> None:
        check_choice(f"{path}.formulation", self.formulation, FORMULATIONS, allow_none=True)
        check_choice(f"{path}.dof_set", self.dof_set, DOF_SETS, allow_none=True)
        for analysis in self.analyses:
            check_choice(f"{path}.analyses", analysis, ANALYSES)
        for effect in self.effects:
            check_choice(f"{path}.effects", effect, EFFECTS)
        check_effects_against_dof_set(path, self)
        if not is_finite_number(self.carrier_speed_rpm):
            raise CaseError(
                f"{path}.carrier_speed_rpm must be a finite number (got {self.carrier_speed_rpm!r})"
            )
        if "signal" in self.analyses and "transient" not in self.analyses:
            raise CaseError(f"{path}.analyses: 'signal' analyses a run, so it needs 'transient'")
        if "signal" in self.analyses and isinstance(self.transient, Transient):
            check_signal_sample_rate(f"{path}.transient", self.transient)
            if self.transient.duration <= SIGNAL_AFTER + 0.1:
                raise CaseError(
                    f"{path}.transient.duration must exceed {SIGNAL_AFTER + 0.1:g} s for the "
                    f"'signal' analysis, which skips the first {SIGNAL_AFTER:g} s of start-up"
                )
        if "transient" in self.analyses and self.transient is None:
            raise CaseError(f"{path}.transient: the transient analysis needs its settings")
        if self.transient is not None:
            if not isinstance(self.transient, Transient):
                raise CaseError(f"{path}.transient must be a Transient (got {self.transient!r})")
            self.transient.validate(f"{path}.transient")
        if "response" in self.analyses and self.response is None:
            raise CaseError(f"{path}.response: the response analysis needs its settings, "
                            "e.g. Response(speeds_rpm=(100.0, 1500.0, 200))")  # fmt: skip
        if self.response is not None:
            if not isinstance(self.response, Response):
                raise CaseError(f"{path}.response must be a Response (got {self.response!r})")
            self.response.validate(f"{path}.response")


@dataclass(frozen=True)
class Case:
    """A gearbox with its damping, formulation and scenes.

    Parameters
    ----------
    name : str
        Case name (usually the directory name): a file name, without path separators
        or leading dot.
    gearbox : Gearbox
        The stages.
    formulation : str
        Default formulation of the case's scenes.
    damping : RayleighDamping
        Damping model.
    scenes : tuple of Scene
        The scenes ``pygear run`` executes.
    description : str
        One line for output files.
    defects : tuple of ToothDefect
        Tooth defects present in every scene (cracked or missing teeth).
    sensors : tuple of Sensor
        Accelerometers on the ring or housing of a planetary stage; a transient's
        ``Probe("sensor", name)`` records one (docs/condition_monitoring.md).
    drivetrain : Drivetrain or None
        Shafts, bearings, couplings, rotor and generator around the gearbox
        (docs/drivetrain.md); its ``gearbox`` must be this case's gearbox.
    rolling_bearings : tuple of RollingBearing
        Rolling-element bearings by geometry (docs/bearings.md): their characteristic
        frequencies are stored in every run file, so ``pygear analyze`` labels them.
    """

    name: str
    gearbox: Gearbox
    formulation: str = "consistent"
    damping: RayleighDamping = field(default_factory=RayleighDamping)
    scenes: tuple[Scene, ...] = (Scene("modal"),)
    description: str = ""
    defects: tuple[ToothDefect, ...] = ()
    sensors: tuple[Sensor, ...] = ()
    drivetrain: Drivetrain | None = None
    rolling_bearings: tuple[RollingBearing, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "scenes", tuple(self.scenes))
        for name in ("defects", "sensors", "rolling_bearings"):
            if isinstance(getattr(self, name), list):
                object.__setattr__(self, name, tuple(getattr(self, name)))
        plain_numbers(self)  # np.float32(0.4) is stored, hashed and computed as 0.4
        self.validate()

    def validate(self) -> None:
        """Check the whole case; raise :class:`CaseError` naming the first bad parameter."""
        check_choice("formulation", self.formulation, FORMULATIONS)
        self.gearbox.validate()
        self.damping.validate("damping")
        require_file_name("name", self.name)
        for n, scene in enumerate(self.scenes):
            if not isinstance(scene, Scene):
                raise CaseError(f"scenes[{n}] must be a Scene (got {scene!r})")
            require_file_name(f"scenes[{n}].name", scene.name)
        names = [s.name for s in self.scenes]
        if len(set(names)) != len(names):
            raise CaseError(f"scenes: scene names must be unique (got {names})")
        validate_defects(self.gearbox, self.defects, "defects")
        validate_sensors(self.sensors, {s.name: s for s in self.gearbox.stages})
        from .rolling_bearing import rolling_bearings_of

        for n, bearing in enumerate(rolling_bearings_of(self)):
            bearing.validate(f"rolling_bearings[{n}]")
        if self.drivetrain is not None:
            if not isinstance(self.drivetrain, Drivetrain):
                raise CaseError(f"drivetrain must be a Drivetrain (got {self.drivetrain!r})")
            self.drivetrain.validate("drivetrain")
            if self.drivetrain.gearbox != self.gearbox:
                raise CaseError("drivetrain.gearbox must be the case's gearbox")
        for scene in self.scenes:
            scene.validate(f"scenes.{scene.name}")
            validate_defects(self.gearbox, scene.defects, f"scenes.{scene.name}.defects")
            if "helical_coupling" in scene.effects and all(s.spur for s in self.gearbox.stages):
                raise CaseError(
                    f"scenes.{scene.name}.effects: 'helical_coupling' needs a helical stage "
                    "(every stage of this gearbox is spur)"
                )
            seen_by_scene = self.for_scene(scene) if scene.parameters else self
            if scene.transient is not None:
                check_time_step(
                    seen_by_scene.gearbox, scene.transient, f"scenes.{scene.name}.transient"
                )
            self._check_sensor_probes(scene)

    def _check_sensor_probes(self, scene: Scene) -> None:
        if scene.transient is None:
            return
        names = [sensor.name for sensor in self.sensors]
        for n, probe in enumerate(scene.transient.probes):
            if probe.quantity == "sensor" and probe.target not in names:
                raise CaseError(
                    f"scenes.{scene.name}.transient.probes[{n}].target: {probe.target!r} is "
                    f"not a sensor of the case (sensors: {', '.join(names) or 'none'})"
                    f"{where_written(probe)}"
                )

    def for_scene(self, scene: Scene) -> Case:
        """The case as ``scene`` sees it: its parameter changes applied and validated."""
        if not scene.parameters:
            return self
        changed = dataclasses.replace(self, scenes=())
        for path, value in scene.parameters:
            try:
                changed = replace_parameter(changed, path, value)
            except CaseError as error:
                raise CaseError(f"scenes.{scene.name}.parameters: {error}") from None
        object.__setattr__(changed, "scenes", self.scenes)  # validated above, scene by scene
        return changed

    def scene(self, name: str) -> Scene:
        """The scene called ``name``."""
        for scene in self.scenes:
            if scene.name == name:
                return scene
        known = ", ".join(s.name for s in self.scenes)
        raise CaseError(f"--scene: case {self.name!r} has no scene {name!r} (scenes: {known})")

    def input_hash(self) -> str:
        """A short hash of every input value (stable across runs)."""
        return hashlib.sha256(repr(self).encode()).hexdigest()[:16]


def check_signal_sample_rate(path: str, transient: Transient) -> None:
    """Raise :class:`CaseError` unless the run's samples resolve :data:`SIGNAL_BAND`."""
    time_step = transient.time_step
    if not (is_finite_number(time_step) and time_step > 0):
        return  # Transient.validate names it
    rate = transient.sample_rate if transient.sample_rate is not None else 1.0 / time_step
    if is_finite_number(rate) and rate > 0 and not SIGNAL_BAND[1] < rate / 2:
        name = "sample_rate" if transient.sample_rate is not None else "time_step"
        raise CaseError(
            f"{path}.{name}: the 'signal' analysis demodulates the {SIGNAL_BAND[0]:g}-"
            f"{SIGNAL_BAND[1]:g} Hz band, which must lie below the Nyquist frequency "
            f"(half the sample rate: {rate / 2:g} Hz); sample above {2 * SIGNAL_BAND[1]:g} Hz"
        )


def require_file_name(path: str, name: object) -> None:
    """Raise :class:`CaseError` unless ``name`` can name output files and directories."""
    if (
        not isinstance(name, str)
        or not name.strip()
        or name.startswith(".")
        or any(c in name for c in '/\\:*?"<>|\0')
    ):
        raise CaseError(
            f"{path} must be a non-empty name without path separators or leading dot; "
            f"output files are named after it (got {name!r})"
        )


def member_of(member: str) -> str:
    """The stage attribute of a member name: ``planet`` for ``planet<n>``."""
    return "planet" if member.startswith("planet") else member


def validate_defects(gearbox: Gearbox, defects: tuple, path: str) -> None:
    """Check tooth defects against the gearbox; raise :class:`CaseError` naming the first bad one.

    Each defect must be a :class:`ToothDefect` on a gear of the gearbox with a known
    tooth number, with a 0-based tooth index below it, and no tooth may appear twice.
    """
    if not isinstance(defects, tuple):
        raise CaseError(f"{path} must be a tuple of ToothDefect (got {type(defects).__name__})")
    seen = set()
    for n, defect in enumerate(defects):
        where = f"{path}[{n}]"
        if not isinstance(defect, ToothDefect):
            raise CaseError(f"{where} must be a ToothDefect (got {defect!r})")
        defect.validate(where)
        stage = next((s for s in gearbox.stages if s.name == defect.stage), None)
        if stage is None:
            known = ", ".join(s.name for s in gearbox.stages)
            raise CaseError(
                f"{where}.gear {defect.gear!r}: no stage named {defect.stage!r} (stages: {known})"
            )
        try:
            teeth = stage.gear_teeth(defect.member)
        except KeyError:
            gears = ", ".join(f"{stage.name}.{m}" for m in stage.member_names if m != "carrier")
            raise CaseError(
                f"{where}.gear {defect.gear!r} is not a gear of stage {stage.name!r} "
                f"(gears: {gears})"
            ) from None
        if teeth is None:
            member = "planet" if defect.member.startswith("planet") else defect.member
            raise CaseError(
                f"{where}: {stage.name}.{member}.teeth is not given, so tooth "
                f"{defect.tooth} of {defect.gear} cannot be placed"
            )
        if defect.tooth >= teeth:
            raise CaseError(
                f"{where}.tooth {defect.tooth} does not exist on {defect.gear}: teeth "
                f"are numbered 0 .. {teeth - 1} (0-based, {teeth} teeth)"
            )
        geometry = getattr(getattr(stage, member_of(defect.member), None), "geometry", None)
        if defect.fault is not None and geometry is not None:
            check_fault_on_tooth(defect.fault, geometry, f"{where}.fault")
        key = (defect.gear, int(defect.tooth))
        if key in seen:
            raise CaseError(f"{where}: tooth {defect.tooth} of {defect.gear} is listed twice")
        seen.add(key)


def check_effects_against_dof_set(path: str, scene: Scene) -> None:
    """Refuse effects a scene's DOF set cannot carry, or that are listed twice.

    ``helical_coupling`` couples in-plane and out-of-plane motion, so it needs the
    out-of-plane DOFs (``spatial``, or the DOF set left open); the speed-dependent
    planet terms act on the planets' zeta and eta, which a torsional set drops, and
    need a nominal carrier speed.
    """
    repeated = sorted({e for e in scene.effects if scene.effects.count(e) > 1})
    if repeated:
        raise CaseError(f"{path}.effects: each effect may be listed once ({repeated} repeated)")
    if "helical_coupling" in scene.effects and scene.dof_set in ("planar", "torsional"):
        raise CaseError(
            f"{path}.effects: 'helical_coupling' couples in-plane and out-of-plane DOFs, which "
            f"the {scene.dof_set} DOF set drops ({path}.dof_set must be 'spatial' or left open)"
        )
    if "speed_dependent_planet_terms" in scene.effects:
        if scene.dof_set == "torsional":
            raise CaseError(
                f"{path}.effects: 'speed_dependent_planet_terms' act on the planets' zeta and "
                f"eta, which the torsional DOF set drops ({path}.dof_set)"
            )
        if scene.carrier_speed_rpm == 0.0:
            raise CaseError(
                f"{path}.carrier_speed_rpm must be non-zero for 'speed_dependent_planet_terms' "
                "(the terms grow with the nominal carrier speed)"
            )
    if "gyroscopic_all_members" in scene.effects:
        if "speed_dependent_planet_terms" in scene.effects:
            raise CaseError(
                f"{path}.effects: 'gyroscopic_all_members' holds the planets' terms too; "
                "list one of it and 'speed_dependent_planet_terms'"
            )
        if scene.dof_set == "torsional":
            raise CaseError(
                f"{path}.effects: 'gyroscopic_all_members' acts on the members' in-plane "
                f"translations, which the torsional DOF set drops ({path}.dof_set)"
            )
        if "transient" in scene.analyses:
            raise CaseError(
                f"{path}.effects: 'gyroscopic_all_members' is for modal scenes at a fixed "
                "carrier speed: a transient drives the speed itself and integrates no "
                "Coriolis matrix"
            )


def merged_defects(case: Case, scene: Scene | None = None) -> tuple[ToothDefect, ...]:
    """The case's defects with the scene's on top (a scene's defect replaces the case's
    on the same tooth)."""
    merged = {(d.gear, int(d.tooth)): d for d in case.defects}
    if scene is not None:
        merged.update({(d.gear, int(d.tooth)): d for d in scene.defects})
    return tuple(merged.values())


def defects_json(case: Case, scene: Scene | None = None) -> str:
    """The tooth defects a scene runs with, as JSON: gear, tooth, stiffness factor and
    fault kind (for output files, which readers take as data)."""
    import json

    return json.dumps(
        [
            {
                "gear": d.gear,
                "tooth": int(d.tooth),
                "factor": float(d.factor),
                "fault": type(d.fault).__name__ if d.fault is not None else "none",
            }
            for d in merged_defects(case, scene)
        ]
    )


def check_choice(
    path: str, value: str | None, choices: Iterable[str], allow_none: bool = False
) -> None:
    """Raise :class:`CaseError` unless ``value`` is one of ``choices``."""
    choices = tuple(choices)
    if value is None and allow_none:
        return
    if value not in choices:
        raise CaseError(f"{path} must be one of {', '.join(choices)} (got {value!r})")


def get_parameter(case: Case, path: str) -> object:
    """Value of a dotted parameter path such as ``planetary.sun_mesh.stiffness``."""
    parts = path.split(".")
    if parts[0] == "sensors":
        target: object = _sensor(case, parts[1] if len(parts) > 2 else "", path)
        parts = parts[1:]
    elif parts[0] == "rolling_bearings":
        target = _rolling_bearing(case, parts[1] if len(parts) > 2 else "", path)
        parts = parts[1:]
    else:
        target = _resolve_root(case, parts[0], path)
    for part in parts if target is case else parts[1:]:
        if not dataclasses.is_dataclass(target) or not hasattr(target, part):
            raise CaseError(
                f"parameter {path!r}: {part!r} is not a field of {type(target).__name__}"
            )
        target = getattr(target, part)
    return target


def replace_parameter(case: Case, path: str, value: object) -> Case:
    """A copy of ``case`` with the parameter at ``path`` set to ``value`` (then validated)."""
    parts = path.split(".")
    current = get_parameter(case, path)
    if dataclasses.is_dataclass(current) and not isinstance(value, type(current)):
        _refuse_group(path, current)
    if parts[0] in ("damping", "formulation", "name", "description"):
        return _replace_path(case, parts, value)
    if parts[0] == "sensors":
        sensors = tuple(
            _replace_path(s, parts[2:], value) if s.name == parts[1] else s for s in case.sensors
        )
        return dataclasses.replace(case, sensors=sensors)
    if parts[0] == "rolling_bearings":
        bearings = tuple(
            _replace_path(b, parts[2:], value) if b.name == parts[1] else b
            for b in case.rolling_bearings
        )
        return dataclasses.replace(case, rolling_bearings=bearings)
    stages = tuple(
        _replace_path(s, parts[1:], value) if s.name == parts[0] else s for s in case.gearbox.stages
    )
    gearbox = dataclasses.replace(case.gearbox, stages=stages)
    drivetrain = case.drivetrain and dataclasses.replace(case.drivetrain, gearbox=gearbox)
    return dataclasses.replace(case, gearbox=gearbox, drivetrain=drivetrain)


def _refuse_group(path: str, group: object) -> None:
    """Raise :class:`CaseError`: ``path`` names a stage, a gear or another group of
    parameters, which a value cannot replace; the message lists its fields."""
    kind = type(group).__name__
    what = f"the stage {path!r} ({kind})" if getattr(group, "name", None) == path else f"a {kind}"
    fields = [f.name for f in dataclasses.fields(group) if f.init and f.name[0] != "_"]
    fields = [name for name in fields if name != "name"]
    leaves = [
        (name, child.name)
        for name in fields
        if dataclasses.is_dataclass(getattr(group, name))
        for child in dataclasses.fields(getattr(group, name))
    ]
    stiffness = [".".join(p) for p in [(f,) for f in fields] + leaves if p[-1] == "stiffness"]
    example = f"{path}.{stiffness[0] if stiffness else fields[0]}"
    raise CaseError(
        f"parameter {path!r} names {what}, not a number: give the path of one of its "
        f"fields ({', '.join(fields)}), e.g. {example}"
    )


def _sensor(case: Case, name: str, path: str) -> Sensor:
    for sensor in case.sensors:
        if sensor.name == name:
            return sensor
    known = ", ".join(s.name for s in case.sensors) or "none"
    raise CaseError(
        f"parameter {path!r} must read sensors.<sensor>.<field> with a sensor of the case "
        f"(sensors: {known})"
    )


def _rolling_bearing(case: Case, name: str, path: str) -> RollingBearing:
    for bearing in case.rolling_bearings:
        if bearing.name == name:
            return bearing
    known = ", ".join(b.name for b in case.rolling_bearings) or "none"
    raise CaseError(
        f"parameter {path!r} must read rolling_bearings.<bearing>.<field> with a rolling "
        f"bearing of the case (rolling bearings: {known})"
    )


def _resolve_root(case: Case, first: str, path: str) -> object:
    if first in ("damping", "formulation", "name", "description"):
        return case
    try:
        return case.gearbox.stage(first)
    except CaseError:
        stages = ", ".join(s.name for s in case.gearbox.stages)
        raise CaseError(
            f"parameter {path!r} must start with a stage name ({stages}) or 'damping'"
        ) from None


def _replace_path(obj: object, parts: list[str], value: object) -> object:
    if len(parts) == 1:
        return dataclasses.replace(obj, **{parts[0]: value})
    child = getattr(obj, parts[0])
    return dataclasses.replace(obj, **{parts[0]: _replace_path(child, parts[1:], value)})


def load_case(reference: str | os.PathLike) -> Case:
    """Load the ``case`` object that ``<case dir>/case.py`` defines."""
    directory, module = load_case_module(reference)
    case = getattr(module, "case", None)
    if not isinstance(case, Case):
        raise CaseError(f"{directory / 'case.py'} must define a module-level `case = Case(...)`")
    return case
