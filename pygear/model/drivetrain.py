"""A wind-turbine drivetrain: flexible shafts, their bearings and couplings, the rotor,
the generator, and a :class:`~pygear.model.gearbox.Gearbox` whose members sit on
shaft ends.

The shafts are finite-element beams along the drivetrain axis z (Timoshenko beams with
the shear deformation flag, Euler-Bernoulli without; Friswell, Penny, Garvey & Lees,
*Dynamics of Rotating Machines*, 2010, §5.4), six DOFs per node in the order
``x, y, z, theta_x, theta_y, theta_z``.  A shaft's nodes lie at its section ends and
``elements_per_section`` equal steps inside each section; ``shaft.start`` is its first
node, ``shaft.end`` its last.

``ShaftBearing`` is its own class rather than the gear stages' :class:`Bearing`: that
one is the six springs of a rigid member at the member's centre, with a torsional
stiffness for a held member; a shaft bearing sits at an axial position on a flexible
shaft (a node), has damping, and a rolling bearing carries no torque about the axis.

Nothing is checked when a component is built; :meth:`Drivetrain.validate` names the
first parameter that breaks a rule by its full path (``drivetrain.shafts[0].sections[1]
.outer_diameter``), as the gearbox's components do.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import CaseError
from .components import require_non_negative, require_positive
from .gearbox import Gearbox, member_dofs, reachable
from .plausibility import warn_if_implausible
from .rotor import BearingCoefficients, Disc
from .values import is_whole_number

__all__ = [
    "ENDS",
    "Coupling",
    "Drivetrain",
    "GearboxMount",
    "Generator",
    "Rotor",
    "Shaft",
    "ShaftBearing",
    "ShaftSection",
]

ENDS = ("start", "end")
"""The two ends of a shaft a component can sit on: ``<shaft>.start`` or ``<shaft>.end``."""

NODE_TOLERANCE = 1e-9
"""A bearing's position must lie this close to a shaft node [m] (round-off of the
section lengths' sum)."""


@dataclass(frozen=True)
class ShaftSection:
    """A length of shaft with one cross-section (a tube, or solid with bore 0).

    Parameters
    ----------
    length : float
        Length along the axis [m], > 0.
    outer_diameter : float
        Outer diameter [m], > 0.
    inner_diameter : float
        Bore diameter [m], >= 0 and below ``outer_diameter``.
    """

    length: float
    outer_diameter: float
    inner_diameter: float = 0.0

    def validate(self, path: str) -> None:
        require_positive(f"{path}.length", self.length)
        require_positive(f"{path}.outer_diameter", self.outer_diameter)
        require_non_negative(f"{path}.inner_diameter", self.inner_diameter)
        warn_if_implausible(f"{path}.length", "shaft_length", self.length)
        warn_if_implausible(f"{path}.outer_diameter", "shaft_diameter", self.outer_diameter)
        if self.inner_diameter >= self.outer_diameter:
            raise CaseError(
                f"{path}.inner_diameter must be below outer_diameter "
                f"({self.inner_diameter!r} >= {self.outer_diameter!r} m)"
            )


@dataclass(frozen=True)
class Shaft:
    """A flexible shaft of one material along the drivetrain axis.

    Parameters
    ----------
    name : str
        Shaft name, a Python identifier; its DOFs are ``<name>.n<k>.<dof>``.
    sections : tuple of ShaftSection
        The sections from the start to the end, at least one.
    young_modulus : float
        E [Pa], > 0.
    shear_modulus : float
        G [Pa], > 0 (torsion, and shear deformation).
    density : float
        Mass density [kg/m^3], > 0.
    elements_per_section : int
        Beam elements in each section, >= 1.
    shear_deformation : bool
        Timoshenko beams (True) or Euler-Bernoulli beams (False).
    torsional_damping : float
        beta [s], >= 0: a damper beside the shaft's torsion, C = beta K_torsion
        (stiffness-proportional on the twist only, so bending is not damped by it).
    shear_coefficient : float or None
        Timoshenko shear coefficient kappa [-] in (0, 1]; None takes Hutchinson's
        (2001) value for the section and nu = E / (2 G) - 1 (Cowper's
        6 (1 + nu) / (7 + 6 nu) for a solid section reproduces ROSS's default).
    rayleigh_mass : float
        alpha [1/s], >= 0: shaft damping alpha M_e of every element (all DOFs).
    rayleigh_stiffness : float
        beta [s], >= 0: shaft damping beta K_e of every element (all DOFs), viscous in
        the inertial frame (no rotating-damping circulatory term).
    """

    name: str
    sections: tuple[ShaftSection, ...]
    young_modulus: float
    shear_modulus: float
    density: float
    elements_per_section: int = 4
    shear_deformation: bool = True
    torsional_damping: float = 0.0
    shear_coefficient: float | None = None
    rayleigh_mass: float = 0.0
    rayleigh_stiffness: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.sections, list):
            object.__setattr__(self, "sections", tuple(self.sections))

    @property
    def length(self) -> float:
        """Total length [m]."""
        return float(sum(section.length for section in self.sections))

    def node_positions(self) -> list[float]:
        """Axial position of every node from the shaft's start [m]."""
        positions, start = [0.0], 0.0
        for section in self.sections:
            step = section.length / self.elements_per_section
            positions.extend(start + step * k for k in range(1, self.elements_per_section + 1))
            start += section.length
        return positions

    def validate(self, path: str) -> None:
        require_identifier(f"{path}.name", self.name)
        if not isinstance(self.sections, tuple) or not self.sections:
            raise CaseError(f"{path}.sections must hold at least one ShaftSection")
        for n, section in enumerate(self.sections):
            if not isinstance(section, ShaftSection):
                raise CaseError(f"{path}.sections[{n}] must be a ShaftSection (got {section!r})")
            section.validate(f"{path}.sections[{n}]")
        for name in ("young_modulus", "shear_modulus", "density"):
            require_positive(f"{path}.{name}", getattr(self, name))
            warn_if_implausible(f"{path}.{name}", name, getattr(self, name))
        if not is_whole_number(self.elements_per_section) or self.elements_per_section < 1:
            raise CaseError(
                f"{path}.elements_per_section must be a whole number >= 1 "
                f"(got {self.elements_per_section!r})"
            )
        if not isinstance(self.shear_deformation, bool):
            raise CaseError(
                f"{path}.shear_deformation must be True or False (got {self.shear_deformation!r})"
            )
        require_non_negative(f"{path}.torsional_damping", self.torsional_damping)
        require_non_negative(f"{path}.rayleigh_mass", self.rayleigh_mass)
        require_non_negative(f"{path}.rayleigh_stiffness", self.rayleigh_stiffness)
        kappa = self.shear_coefficient
        if kappa is not None and not (
            isinstance(kappa, (int, float)) and not isinstance(kappa, bool) and 0.0 < kappa <= 1.0
        ):
            raise CaseError(
                f"{path}.shear_coefficient must lie in (0, 1] or be None (got {kappa!r})"
            )


@dataclass(frozen=True)
class ShaftBearing:
    """A bearing between a shaft node and the ground (the bedplate).

    Parameters
    ----------
    name : str
        Bearing name, a Python identifier.
    shaft : str
        Name of the shaft it carries.
    position : float
        Axial position from the shaft's start [m]; must be a node of the shaft (a
        section end or an element boundary).
    radial : float
        Stiffness in x and y [N/m], >= 0.
    axial : float
        Stiffness in z [N/m], >= 0.
    tilt : float
        Tilting stiffness about x and y [N m/rad], >= 0.
    radial_damping : float
        Damping in x and y [N s/m], >= 0.
    axial_damping : float
        Damping in z [N s/m], >= 0.
    coefficients : BearingCoefficients or None
        The full 2 x 2 lateral stiffness and damping over the shaft's speed
        (:class:`~pygear.model.rotor.BearingCoefficients`: anisotropic, cross-coupled,
        speed-dependent, a fluid-film bearing or a seal); when given it replaces
        ``radial`` and ``radial_damping``, which must then be 0.
    """

    name: str
    shaft: str
    position: float
    radial: float = 0.0
    axial: float = 0.0
    tilt: float = 0.0
    radial_damping: float = 0.0
    axial_damping: float = 0.0
    coefficients: BearingCoefficients | None = None

    def validate(self, path: str) -> None:
        require_identifier(f"{path}.name", self.name)
        for name in ("radial", "axial", "tilt", "radial_damping", "axial_damping"):
            require_non_negative(f"{path}.{name}", getattr(self, name))
        if self.coefficients is not None:
            if not isinstance(self.coefficients, BearingCoefficients):
                raise CaseError(
                    f"{path}.coefficients must be a BearingCoefficients or None "
                    f"(got {self.coefficients!r})"
                )
            self.coefficients.validate(f"{path}.coefficients")
            if self.radial or self.radial_damping:
                raise CaseError(
                    f"{path}.radial and radial_damping must be 0 when coefficients are given "
                    "(the table holds the lateral stiffness and damping)"
                )


@dataclass(frozen=True)
class Coupling:
    """A flexible coupling between two shaft ends: springs and dampers between their
    nodes.

    Parameters
    ----------
    name : str
        Coupling name, a Python identifier.
    a, b : str
        The two shaft ends, ``<shaft>.start`` or ``<shaft>.end``; not the same end.
    torsional : float
        Torsional stiffness [N m/rad], > 0 (a coupling transmits the torque).
    radial, axial : float
        Lateral and axial stiffness [N/m], >= 0.
    angular : float
        Stiffness against a relative tilt [N m/rad], >= 0.
    torsional_damping : float
        Torsional damping [N m s/rad], >= 0.
    """

    name: str
    a: str
    b: str
    torsional: float
    radial: float = 0.0
    axial: float = 0.0
    angular: float = 0.0
    torsional_damping: float = 0.0

    def validate(self, path: str) -> None:
        require_identifier(f"{path}.name", self.name)
        require_positive(f"{path}.torsional", self.torsional)
        for name in ("radial", "axial", "angular", "torsional_damping"):
            require_non_negative(f"{path}.{name}", getattr(self, name))


@dataclass(frozen=True)
class Rotor:
    """The turbine rotor (hub and blades) as a rigid disc on a shaft end.

    Parameters
    ----------
    mass : float
        Mass [kg], > 0.
    polar_inertia : float
        Inertia about the shaft axis [kg m^2], > 0.
    diametral_inertia : float
        Inertia about a diameter [kg m^2], > 0.
    at : str
        The shaft end it sits on, ``<shaft>.start`` or ``<shaft>.end``.
    """

    mass: float
    polar_inertia: float
    diametral_inertia: float
    at: str

    def validate(self, path: str) -> None:
        _require_disc(self, path)


@dataclass(frozen=True)
class Generator:
    """The generator's rotor as a rigid disc on the high-speed shaft's end.

    Parameters
    ----------
    polar_inertia : float
        Inertia about the shaft axis [kg m^2], > 0.
    mass : float
        Mass [kg], > 0.
    diametral_inertia : float
        Inertia about a diameter [kg m^2], > 0.
    at : str
        The shaft end it sits on, ``<shaft>.start`` or ``<shaft>.end``.
    """

    polar_inertia: float
    mass: float
    diametral_inertia: float
    at: str

    def validate(self, path: str) -> None:
        _require_disc(self, path)


@dataclass(frozen=True)
class GearboxMount:
    """Where a gearbox member sits: the member moves with a shaft end's node.

    Parameters
    ----------
    member : str
        A central member of the gearbox, ``stage.member`` (``stage1.carrier``,
        ``parallel.output_gear``); not a planet.
    at : str
        The shaft end, ``<shaft>.start`` or ``<shaft>.end``.
    """

    member: str
    at: str


@dataclass(frozen=True)
class Drivetrain:
    """Shafts, bearings and couplings from the rotor through a gearbox to the generator,
    or a plain rotor: shafts, discs and bearings without a gearbox.

    Parameters
    ----------
    shafts : tuple of Shaft
        The shafts, names unique.
    gearbox : Gearbox or None
        The gear stages (the case's gearbox: :class:`~pygear.model.case.Case` checks it);
        None for a plain rotor (:class:`~pygear.model.rotor.RotorCase`).
    mounts : tuple of GearboxMount
        Where the gearbox members sit, at least one with a gearbox, none without; a
        member and a shaft end at most once each.
    rotor : Rotor or None
        The turbine rotor; required with a gearbox.
    generator : Generator or None
        The generator; required with a gearbox.
    bearings : tuple of ShaftBearing
        Bearings to the ground.
    couplings : tuple of Coupling
        Couplings between shaft ends.
    discs : tuple of Disc
        Rigid discs at shaft nodes (:class:`~pygear.model.rotor.Disc`), names unique.
    """

    shafts: tuple[Shaft, ...]
    gearbox: Gearbox | None = None
    mounts: tuple[GearboxMount, ...] = ()
    rotor: Rotor | None = None
    generator: Generator | None = None
    bearings: tuple[ShaftBearing, ...] = ()
    couplings: tuple[Coupling, ...] = ()
    discs: tuple[Disc, ...] = ()

    def __post_init__(self) -> None:
        for name in ("shafts", "mounts", "bearings", "couplings", "discs"):
            if isinstance(getattr(self, name), list):
                object.__setattr__(self, name, tuple(getattr(self, name)))

    def shaft(self, name: str) -> Shaft:
        """The shaft called ``name``."""
        for shaft in self.shafts:
            if shaft.name == name:
                return shaft
        known = ", ".join(s.name for s in self.shafts)
        raise CaseError(f"no shaft named {name!r} (shafts: {known})")

    def disc(self, name: str) -> Disc:
        """The disc called ``name``."""
        for disc in self.discs:
            if disc.name == name:
                return disc
        known = ", ".join(d.name for d in self.discs) or "none"
        raise CaseError(f"no disc named {name!r} (discs: {known})")

    def validate(self, path: str = "drivetrain") -> None:
        """Check every component and every reference; raise :class:`CaseError`."""
        for name in ("shafts", "mounts", "bearings", "couplings", "discs"):
            if not isinstance(getattr(self, name), tuple):
                raise CaseError(f"{path}.{name} must be a tuple")
        if not self.shafts:
            raise CaseError(f"{path}.shafts must hold at least one Shaft")
        for n, shaft in enumerate(self.shafts):
            if not isinstance(shaft, Shaft):
                raise CaseError(f"{path}.shafts[{n}] must be a Shaft (got {shaft!r})")
            shaft.validate(f"{path}.shafts[{n}]")
        _require_unique(f"{path}.shafts", [s.name for s in self.shafts])
        if self.gearbox is not None and not isinstance(self.gearbox, Gearbox):
            raise CaseError(f"{path}.gearbox must be a Gearbox or None (got {self.gearbox!r})")
        shafts = {s.name: s for s in self.shafts}
        for name, kind in (("rotor", Rotor), ("generator", Generator)):
            part = getattr(self, name)
            if part is None and self.gearbox is None:
                continue
            if not isinstance(part, kind):
                raise CaseError(f"{path}.{name} must be a {kind.__name__} (got {part!r})")
            part.validate(f"{path}.{name}")
            self._check_end(f"{path}.{name}.at", part.at, shafts)
        for n, bearing in enumerate(self.bearings):
            where = f"{path}.bearings[{n}]"
            if not isinstance(bearing, ShaftBearing):
                raise CaseError(f"{where} must be a ShaftBearing (got {bearing!r})")
            bearing.validate(where)
            self._check_bearing_position(where, bearing, shafts)
        _require_unique(f"{path}.bearings", [b.name for b in self.bearings])
        for n, disc in enumerate(self.discs):
            where = f"{path}.discs[{n}]"
            if not isinstance(disc, Disc):
                raise CaseError(f"{where} must be a Disc (got {disc!r})")
            disc.validate(where)
            self._check_bearing_position(where, disc, shafts)
        _require_unique(f"{path}.discs", [d.name for d in self.discs])
        for n, coupling in enumerate(self.couplings):
            where = f"{path}.couplings[{n}]"
            if not isinstance(coupling, Coupling):
                raise CaseError(f"{where} must be a Coupling (got {coupling!r})")
            coupling.validate(where)
            self._check_end(f"{where}.a", coupling.a, shafts)
            self._check_end(f"{where}.b", coupling.b, shafts)
            if coupling.a == coupling.b:
                raise CaseError(f"{where} joins {coupling.a} to itself")
        _require_unique(f"{path}.couplings", [c.name for c in self.couplings])
        if self.gearbox is None:
            if self.mounts:
                raise CaseError(f"{path}.mounts must be empty without a gearbox")
        else:
            self._check_mounts(path, shafts)
        self._check_connected(path)

    @staticmethod
    def _check_end(path: str, end: object, shafts: dict[str, Shaft]) -> None:
        parts = end.split(".") if isinstance(end, str) else []
        if len(parts) != 2 or parts[1] not in ENDS:
            raise CaseError(
                f"{path} must be a shaft end '<shaft>.start' or '<shaft>.end' (got {end!r})"
            )
        if parts[0] not in shafts:
            raise CaseError(
                f"{path} {end!r}: no shaft named {parts[0]!r} (shafts: {', '.join(shafts)})"
            )

    @staticmethod
    def _check_bearing_position(path: str, bearing: object, shafts: dict[str, Shaft]) -> None:
        shaft = shafts.get(bearing.shaft)
        if shaft is None:
            raise CaseError(
                f"{path}.shaft: no shaft named {bearing.shaft!r} (shafts: {', '.join(shafts)})"
            )
        positions = shaft.node_positions()
        if not isinstance(bearing.position, (int, float)) or not any(
            abs(bearing.position - p) <= NODE_TOLERANCE for p in positions
        ):
            nodes = ", ".join(f"{p:g}" for p in positions)
            raise CaseError(
                f"{path}.position must be a node of shaft {shaft.name!r} (nodes at {nodes} m; "
                f"split a section there) (got {bearing.position!r})"
            )

    def _check_mounts(self, path: str, shafts: dict[str, Shaft]) -> None:
        if not self.mounts:
            raise CaseError(f"{path}.mounts must place at least one gearbox member on a shaft")
        for n, mount in enumerate(self.mounts):
            where = f"{path}.mounts[{n}]"
            if not isinstance(mount, GearboxMount):
                raise CaseError(f"{where} must be a GearboxMount (got {mount!r})")
            self._check_end(f"{where}.at", mount.at, shafts)
            parts = mount.member.split(".") if isinstance(mount.member, str) else []
            if len(parts) != 2:
                raise CaseError(
                    f"{where}.member must name a gearbox member 'stage.member' "
                    f"(got {mount.member!r})"
                )
            stage = next((s for s in self.gearbox.stages if s.name == parts[0]), None)
            if stage is None:
                known = ", ".join(s.name for s in self.gearbox.stages)
                raise CaseError(
                    f"{where}.member {mount.member!r}: no stage named {parts[0]!r} "
                    f"(stages: {known})"
                )
            try:
                dofs = member_dofs(stage, parts[1])
            except KeyError:
                raise CaseError(
                    f"{where}.member {mount.member!r}: stage {parts[0]!r} has no member "
                    f"{parts[1]!r} (members: {', '.join(stage.member_names)})"
                ) from None
            if "theta_x" not in dofs:
                raise CaseError(
                    f"{where}.member {mount.member!r}: a planet revolves with its carrier "
                    "and cannot sit on a shaft; mount a central member"
                )
        _require_unique(f"{path}.mounts (members)", [m.member for m in self.mounts])
        _require_unique(f"{path}.mounts (shaft ends)", [m.at for m in self.mounts])

    def _check_connected(self, path: str) -> None:
        edges = [(c.a.split(".")[0], c.b.split(".")[0]) for c in self.couplings]
        edges += [(m.at.split(".")[0], "<gearbox>") for m in self.mounts]
        first = self.rotor.at.split(".")[0] if self.rotor is not None else self.shafts[0].name
        reached = reachable(first, edges)
        lost = [s.name for s in self.shafts if s.name not in reached]
        if lost:
            where = f"the rotor on {self.rotor.at}" if self.rotor else f"shaft {first!r}"
            raise CaseError(
                f"{path}.shafts: shaft {lost[0]!r} has no path to {where} "
                "(add a coupling or a gearbox mount on it)"
            )


def _require_disc(disc: Rotor | Generator, path: str) -> None:
    """A rotor's or generator's mass and inertias are positive."""
    for name in ("mass", "polar_inertia", "diametral_inertia"):
        require_positive(f"{path}.{name}", getattr(disc, name))


def require_identifier(path: str, name: object) -> None:
    """Raise :class:`CaseError` unless ``name`` is a Python identifier."""
    if not isinstance(name, str) or not name.isidentifier():
        raise CaseError(f"{path} must be an identifier (got {name!r})")


def _require_unique(path: str, names: list[str]) -> None:
    if len(set(names)) != len(names):
        raise CaseError(f"{path}: names must be unique (got {names})")
