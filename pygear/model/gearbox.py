"""A gearbox: stages on one housing, joined by couplings (docs/model.md §3.5).

Besides :class:`~pygear.model.components.PlanetaryStage` a gearbox holds helical or spur
:class:`ParallelStage` pairs and :class:`ShaftInertia` nodes (a rotor, a generator).
Couplings name their DOFs ``stage.member.dof`` so a case reads like the gearbox drawing:
a :class:`RigidLink` removes a DOF through a constraint, a :class:`TorsionalSpring`
adds a spring (and damper) between two rotations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import CaseError
from .components import (
    Bearing,
    Body,
    Gear,
    Mesh,
    PlanetaryStage,
    check_backlash,
    check_foundation_bore,
    derived_record,
    is_whole_number,
    require_axial_position,
    require_matching_teeth,
    require_non_negative,
    transverse_module_of,
)
from .components import is_finite_number as _finite
from .geometry_inputs import check_parallel_geometry, fill_parallel_stage

__all__ = [
    "CENTRAL_DOFS",
    "PLANET_DOFS",
    "Gearbox",
    "ParallelStage",
    "RigidLink",
    "ShaftInertia",
    "TorsionalSpring",
    "member_dofs",
]

CENTRAL_DOFS = ("x", "y", "z", "theta_x", "theta_y", "theta_z")
PLANET_DOFS = ("zeta", "eta", "z", "theta_zeta", "theta_eta", "theta_z", "phi")


@dataclass(frozen=True)
class ParallelStage:
    """An external fixed-axis gear pair (helical or spur) on two 6-DOF nodes.

    The input gear sits on the gearbox axis at ``axial_position``; the output gear's
    centre lies at the centre distance (r_b1 + r_b2)/cos(alpha) in the direction
    ``centre_angle_deg`` from the x axis.

    Parameters
    ----------
    name : str
        Stage name.
    input_gear, output_gear : Gear
        The two gears.
    input_bearing, output_bearing : Bearing
        Their bearings to the housing.
    mesh : Mesh
        The mesh (``contact_ratio`` is the transverse one).  With gear geometry on both
        gears the mesh geometry is (input gear, output gear) at the zero-backlash
        centre distance of the profile shifts.
    overlap_ratio : float or None
        Axial (overlap) contact ratio [-], >= 0; 0 for spur gears.  Left out: from the gear
        geometry, else ``mesh.overlap_ratio``, else 0 for a spur pair; a helical pair
        needs one (0 typed runs it with the parabola).
    base_helix_angle_deg : float or None
        Signed base helix angle [deg], in (-45, 45); left out: from the gear geometry
        (signed with the input gear's hand), else 0.
    centre_angle_deg : float
        Direction of the line of centres [deg], finite.
    axial_position : float
        Position along the gearbox axis [m].
    """

    name: str
    input_gear: Gear
    output_gear: Gear
    input_bearing: Bearing
    output_bearing: Bearing
    mesh: Mesh
    overlap_ratio: float | None = None
    base_helix_angle_deg: float | None = None
    centre_angle_deg: float = 0.0
    axial_position: float = 0.0
    kind: str = field(default="parallel", init=False)
    _derived: tuple = derived_record()

    member_names = ("input_gear", "output_gear")

    def __post_init__(self) -> None:
        fill_parallel_stage(self)

    @property
    def spur(self) -> bool:
        """True for a spur pair."""
        return self.base_helix_angle_deg == 0.0

    @property
    def speed_ratio(self) -> float:
        """Input over output speed: r_b2 / r_b1."""
        return self.output_gear.base_radius / self.input_gear.base_radius

    @property
    def centre_distance(self) -> float:
        """(r_b1 + r_b2)/cos(alpha) [m]."""
        return (self.input_gear.base_radius + self.output_gear.base_radius) / math.cos(
            self.mesh.pressure_angle
        )

    def position(self, member: str) -> tuple[float, float, float]:
        """Centre of a member [m]."""
        if member == "input_gear":
            return (0.0, 0.0, self.axial_position)
        angle = math.radians(self.centre_angle_deg)
        c = self.centre_distance
        return (c * math.cos(angle), c * math.sin(angle), self.axial_position)

    def gear_teeth(self, member: str) -> int | None:
        """Tooth number of a member (KeyError for an unknown member)."""
        if member not in self.member_names:
            raise KeyError(member)
        return getattr(self, member).teeth

    def validate(self, path: str | None = None) -> None:
        path = path or self.name
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise CaseError(f"stage name must be an identifier (got {self.name!r})")
        for name in ("input_gear", "output_gear"):
            getattr(self, name).validate(f"{path}.{name}")
        for name in ("base_helix_angle_deg", "centre_angle_deg"):
            if not _finite(getattr(self, name)):
                raise CaseError(f"{path}.{name} must be finite (got {getattr(self, name)!r})")
        if abs(self.base_helix_angle_deg) >= 45:
            raise CaseError(f"{path}.base_helix_angle_deg must lie in (-45, 45) degrees")
        if self.overlap_ratio is not None:
            require_non_negative(f"{path}.overlap_ratio", self.overlap_ratio)
        check_parallel_geometry(self, path)
        for name in ("input_bearing", "output_bearing", "mesh"):
            getattr(self, name).validate(f"{path}.{name}")
        require_matching_teeth(
            path, {"input_gear": self.input_gear, "output_gear": self.output_gear}
        )
        require_axial_position(f"{path}.axial_position", self.axial_position)
        if self.mesh.law in ("potential_energy", "loaded_contact"):  # both slice the tooth
            for name in ("input_gear", "output_gear"):
                check_foundation_bore(f"{path}.{name}", getattr(self, name))
        check_backlash(
            f"{path}.mesh.backlash",
            self.mesh.backlash,
            transverse_module_of(self.output_gear, self.mesh.pressure_angle_deg),
        )
        if self.spur and self.mesh.contact_ratio <= 1:
            raise CaseError(
                f"{path}.mesh.contact_ratio must exceed 1 for a spur pair "
                f"(got {self.mesh.contact_ratio})"
            )


@dataclass(frozen=True)
class ShaftInertia:
    """A plain inertia node on the gearbox axis: a rotor hub, a generator, a shaft.

    Parameters
    ----------
    name : str
        Stage name; its one member is ``body``.
    body : Body
        Mass and inertias.
    bearing : Bearing
        Bearing to the housing (torsional stiffness 0 for a free shaft).
    axial_position : float
        Position along the gearbox axis [m].
    """

    name: str
    body: Body
    bearing: Bearing
    axial_position: float = 0.0
    kind: str = field(default="inertia", init=False)

    member_names = ("body",)
    spur = True

    def position(self, member: str) -> tuple[float, float, float]:
        """Centre of the body [m]."""
        return (0.0, 0.0, self.axial_position)

    def gear_teeth(self, member: str) -> int | None:
        raise KeyError(member)

    def validate(self, path: str | None = None) -> None:
        path = path or self.name
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise CaseError(f"stage name must be an identifier (got {self.name!r})")
        self.body.validate(f"{path}.body")
        self.bearing.validate(f"{path}.bearing")
        require_axial_position(f"{path}.axial_position", self.axial_position)


@dataclass(frozen=True)
class RigidLink:
    """A constraint q_b = ratio * q_a between two DOFs (``stage.member.dof``).

    Parameters
    ----------
    a : str
        DOF label of the master, ``stage.member.dof`` (``stage1.sun.theta_z``).
    b : str
        DOF label of the tied DOF, which the constraint removes; not ``a``, and no loop
        of rigid links.
    ratio : float
        q_b / q_a [-], finite and non-zero (for rotations, the speed ratio).
    """

    a: str
    b: str
    ratio: float = 1.0


@dataclass(frozen=True)
class TorsionalSpring:
    """A spring (and damper) k (q_a - q_b) between two rotations.

    Parameters
    ----------
    name : str
        Coupling name, a Python identifier; its stiffness is the sensitivity parameter
        ``couplings.<name>.stiffness``.
    a, b : str
        DOF labels ``stage.member.dof``, two different DOFs.
    stiffness : float
        Torsional stiffness k [N m/rad], >= 0.
    damping : float
        Torsional damping, a damper beside the spring [N m s/rad], >= 0.
    """

    name: str
    a: str
    b: str
    stiffness: float
    damping: float = 0.0


def reachable(start: str, edges: list[tuple[str, str]]) -> set[str]:
    """Every name joined to ``start`` by a chain of undirected ``edges`` (start included)."""
    reached, frontier = {start}, [start]
    while frontier:
        here = frontier.pop()
        for a, b in edges:
            for x, y in ((a, b), (b, a)):
                if x == here and y not in reached:
                    reached.add(y)
                    frontier.append(y)
    return reached


def member_dofs(stage: object, member: str) -> tuple[str, ...]:
    """DOF names of a stage member (planets in their revolving frame)."""
    if member not in stage.member_names:
        raise KeyError(member)
    if isinstance(stage, PlanetaryStage) and member.startswith("planet"):
        return PLANET_DOFS
    return CENTRAL_DOFS


@dataclass(frozen=True)
class Gearbox:
    """Stages sharing one housing, and the couplings between them.

    Parameters
    ----------
    stages : tuple
        Planetary, parallel and inertia stages.
    couplings : tuple
        :class:`RigidLink` and :class:`TorsionalSpring` items.
    input_dof, output_dof : str or None
        Where the drive and the load act; by default the first stage's carrier (or
        input gear, or body) and the last stage's sun (or output gear, or body).
    rigid_body_modes : int
        Free rigid-body motions the assembled gearbox must have (1: the drivetrain
        turns); another count means a part is disconnected.
    """

    stages: tuple[PlanetaryStage | ParallelStage | ShaftInertia, ...]
    couplings: tuple[RigidLink | TorsionalSpring, ...] = ()
    input_dof: str | None = None
    output_dof: str | None = None
    rigid_body_modes: int = 1

    def __post_init__(self) -> None:
        object.__setattr__(self, "stages", tuple(self.stages))
        object.__setattr__(self, "couplings", tuple(self.couplings))

    def stage(self, name: str) -> PlanetaryStage | ParallelStage | ShaftInertia:
        """The stage called ``name``."""
        for stage in self.stages:
            if stage.name == name:
                return stage
        known = ", ".join(s.name for s in self.stages)
        raise CaseError(f"no stage named {name!r} (stages: {known})")

    @property
    def input(self) -> str:
        """DOF label of the drive."""
        if self.input_dof:
            return self.input_dof
        first = self.stages[0]
        member = {"planetary": "carrier", "parallel": "input_gear"}.get(first.kind, "body")
        return f"{first.name}.{member}.theta_z"

    @property
    def output(self) -> str:
        """DOF label of the load."""
        if self.output_dof:
            return self.output_dof
        last = self.stages[-1]
        member = {"planetary": "sun", "parallel": "output_gear"}.get(last.kind, "body")
        return f"{last.name}.{member}.theta_z"

    def check_label(self, label: str, path: str) -> tuple[str, str, str]:
        """Split ``stage.member.dof`` and check that it exists."""
        parts = label.split(".") if isinstance(label, str) else []
        if len(parts) != 3:
            raise CaseError(f"{path} must be a DOF label 'stage.member.dof' (got {label!r})")
        stage_name, member, dof = parts
        stage = next((s for s in self.stages if s.name == stage_name), None)
        if stage is None:
            known = ", ".join(s.name for s in self.stages)
            raise CaseError(f"{path} {label!r}: no stage named {stage_name!r} (stages: {known})")
        try:
            dofs = member_dofs(stage, member)
        except KeyError:
            raise CaseError(
                f"{path} {label!r}: stage {stage_name!r} has no member {member!r} "
                f"(members: {', '.join(stage.member_names)})"
            ) from None
        if dof not in dofs:
            raise CaseError(
                f"{path} {label!r}: {member} has no DOF {dof!r} (DOFs: {', '.join(dofs)})"
            )
        return stage_name, member, dof

    def validate(self, path: str = "gearbox") -> None:
        """Check stages, couplings and connectivity; raise :class:`CaseError`."""
        if not self.stages:
            raise CaseError(f"{path}.stages must hold at least one stage")
        names = [getattr(s, "name", None) for s in self.stages]
        if not all(isinstance(n, str) and n.isidentifier() for n in names):
            raise CaseError(f"{path}.stages: stage names must be identifiers (got {names!r})")
        if len(set(names)) != len(names):
            raise CaseError(f"{path}.stages: stage names must be unique (got {names})")
        for stage in self.stages:
            if not isinstance(stage, (PlanetaryStage, ParallelStage, ShaftInertia)):
                raise CaseError(f"{path}.stages: {stage!r} is not a stage")
            stage.validate(stage.name)
        if not is_whole_number(self.rigid_body_modes) or self.rigid_body_modes < 0:
            raise CaseError(f"{path}.rigid_body_modes must be a whole number >= 0")
        self.check_label(self.input, f"{path}.input_dof")
        self.check_label(self.output, f"{path}.output_dof")
        parent: dict[str, str] = {}

        def root(label: str) -> str:
            while parent.get(label, label) != label:
                label = parent[label]
            return label

        edges = []
        for n, coupling in enumerate(self.couplings):
            where = f"{path}.couplings[{n}]"
            if isinstance(coupling, RigidLink):
                if not _finite(coupling.ratio) or coupling.ratio == 0:
                    raise CaseError(f"{where}.ratio must be finite and non-zero")
            elif isinstance(coupling, TorsionalSpring):
                if not isinstance(coupling.name, str) or not coupling.name.isidentifier():
                    raise CaseError(f"{where}.name must be an identifier (got {coupling.name!r})")
                require_non_negative(f"{where}.stiffness", coupling.stiffness)
                require_non_negative(f"{where}.damping", coupling.damping)
            else:
                raise CaseError(f"{where} must be a RigidLink or a TorsionalSpring")
            a = self.check_label(coupling.a, f"{where}.a")
            b = self.check_label(coupling.b, f"{where}.b")
            if coupling.a == coupling.b:
                raise CaseError(f"{where} joins {coupling.a} to itself")
            edges.append((a[0], b[0]))
            if isinstance(coupling, RigidLink):
                ra, rb = root(coupling.a), root(coupling.b)
                if ra == rb:
                    raise CaseError(
                        f"{where}: rigid links {coupling.a} -> {coupling.b} close a loop; "
                        "a loop of rigid links with a ratio over-constrains the gearbox"
                    )
                parent[rb] = ra
        self._check_connected(path, edges)

    def _check_connected(self, path: str, edges: list[tuple[str, str]]) -> None:
        reached = reachable(self.input.split(".")[0], edges)
        lost = [s.name for s in self.stages if s.name not in reached]
        if lost:
            raise CaseError(
                f"{path}: stage {lost[0]!r} has no path to the drive at {self.input} "
                "(add a coupling to it)"
            )
