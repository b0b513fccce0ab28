"""A planetary stage: carrier, ring, sun and N identical planets, with the stage's
validation (geometry, planet spacing and assembly, contact) beside its fields."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

from ..errors import CaseError
from .bearings import Bearing, PlanetBearing
from .bodies import Carrier, Gear, check_foundation_bore, require_matching_teeth
from .component_rules import (
    check_backlash,
    derived_record,
    is_finite_number,
    is_whole_number,
    looks_like_radians,
    require_axial_position,
    transverse_module_of,
    validate_component,
)
from .geometry_inputs import check_planetary_geometry, fill_planetary_stage
from .meshes import Mesh
from .plausibility import PlausibilityWarning

__all__ = ["ASSEMBLY_TOLERANCE", "PlanetaryStage"]

ASSEMBLY_TOLERANCE = 0.05
"""How far (Z_s + Z_r) psi / 360 deg may stray from a whole number for a planet at psi
(relative to the first) [tooth pitches] before validation warns that the planet cannot
be assembled.  A planet within 5 % of a pitch of an assemblable angle is taken as a
position error on purpose (a carrier pin-hole study: the study case's 120.1 deg is 0.034
of a pitch off); beyond, the teeth of sun, planet and ring cannot all engage at once."""

_finite = is_finite_number


@dataclass(frozen=True)
class PlanetaryStage:
    """A planetary stage: carrier, ring, sun and N identical planets.

    The carrier, ring and sun live in the inertial frame; each planet in a frame
    revolving with it (docs/model.md §1-3).

    Parameters
    ----------
    name : str
        Stage name, the first part of every DOF and parameter path: a Python
        identifier, unique in the gearbox.
    carrier, ring, sun, planet : Carrier, Gear, Gear, Gear
        The members; ``planet`` describes each of the N planets.  With gear geometry
        the carrier radius is the centre distance of both meshes: left out, it is the
        sun-planet geometry's zero-backlash centre distance; typed, it must agree with
        both meshes' within 0.5 %.
    planets : int
        Number of planets N >= 1.
    carrier_bearing, ring_bearing, sun_bearing : Bearing
        Bearings of the central members to the housing.
    planet_bearing : PlanetBearing
        Bearing of each planet on the carrier.
    sun_mesh, ring_mesh : Mesh
        Sun-planet and ring-planet meshes (the same for every planet).
    planet_angles_deg : tuple of float or None
        Angle psi_n of each planet from the x axis [deg], one per planet; equal spacing
        when None.  Neighbouring planets must not touch.
    base_helix_angle_deg : float or None
        Signed base helix angle beta_b [deg], in (-45, 45); 0 for spur gears.  Left out: from the
        gear geometry (signed with the sun's hand), else 0.  A helical stage needs an
        overlap ratio on both meshes (typed or from geometry).
    axial_position : float
        Position of the stage centre along the gearbox z axis [m], within 100 m of the
        origin.
    mesh_phases : dict of str to float or None
        Overrides of the mesh phases gamma [mesh cycles], each in [0, 1), keyed by mesh name
        (``sun-planet1`` ... ``sun-planetN``, ``ring-planet1`` ... ``ring-planetN``);
        the others follow Parker & Lin's phasing (:mod:`pygear.assembly.mesh_phasing`).  Stored
        as sorted (name, phase) pairs; :attr:`phase_overrides` gives the dict.
    """

    name: str
    carrier: Carrier
    ring: Gear
    sun: Gear
    planet: Gear
    planets: int
    carrier_bearing: Bearing
    ring_bearing: Bearing
    sun_bearing: Bearing
    planet_bearing: PlanetBearing
    sun_mesh: Mesh
    ring_mesh: Mesh
    planet_angles_deg: tuple[float, ...] | None = None
    base_helix_angle_deg: float | None = None
    axial_position: float = 0.0
    mesh_phases: dict[str, float] | None = None
    kind: str = field(default="planetary", init=False)
    _derived: tuple = derived_record()

    def __post_init__(self) -> None:
        phases = self.mesh_phases
        if isinstance(phases, dict):
            try:
                object.__setattr__(self, "mesh_phases", tuple(sorted(phases.items())))
            except TypeError:
                object.__setattr__(self, "mesh_phases", tuple(phases.items()))
        fill_planetary_stage(self)

    @property
    def phase_overrides(self) -> dict[str, float]:
        """Phase overrides by mesh name (empty when none are given)."""
        return dict(self.mesh_phases or ())

    @property
    def mesh_names(self) -> tuple[str, ...]:
        """Mesh names: sun-planet1..N, then ring-planet1..N."""
        planets = range(1, self.planets + 1)
        return tuple(f"{gear}-planet{n}" for gear in ("sun", "ring") for n in planets)

    def gear_teeth(self, member: str) -> int | None:
        """Tooth number of ``sun``, ``ring`` or ``planet<n>``; KeyError for anything else."""
        if member in ("sun", "ring"):
            return getattr(self, member).teeth
        if member in self.member_names[3:]:
            return self.planet.teeth
        raise KeyError(member)

    @property
    def planet_angles(self) -> tuple[float, ...]:
        """Planet angles psi_n [rad] (equal spacing unless given)."""
        if self.planet_angles_deg is None:
            return tuple(2 * math.pi * n / self.planets for n in range(self.planets))
        return tuple(math.radians(a) for a in self.planet_angles_deg)

    @property
    def equally_spaced(self) -> bool:
        """True when the planets sit at 360/N degree intervals from the first."""
        first = self.planet_angles[0]
        return all(
            abs(math.remainder(a - first - 2 * math.pi * n / self.planets, 2 * math.pi)) < 1e-12
            for n, a in enumerate(self.planet_angles)
        )

    @property
    def base_helix_angle(self) -> float:
        """Base helix angle [rad]."""
        return math.radians(self.base_helix_angle_deg)

    @property
    def spur(self) -> bool:
        """True for a spur stage (no helix angle)."""
        return self.base_helix_angle_deg == 0.0

    @property
    def speed_ratio(self) -> float:
        """Ideal ratio with the ring held, carrier in and sun out: 1 + r_br/r_bs."""
        return 1.0 + self.ring.base_radius / self.sun.base_radius

    @property
    def member_names(self) -> tuple[str, ...]:
        """Node names in DOF order: carrier, ring, sun, planet1..planetN."""
        return ("carrier", "ring", "sun") + tuple(f"planet{n + 1}" for n in range(self.planets))

    def validate(self, path: str | None = None) -> None:
        """Check every parameter; raise :class:`CaseError` naming the first bad one."""
        path = path or self.name
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise CaseError(f"stage name must be an identifier (got {self.name!r})")
        if not is_whole_number(self.planets) or self.planets < 1:
            raise CaseError(f"{path}.planets must be a whole number >= 1 (got {self.planets!r})")
        for name in ("ring", "sun", "planet"):
            validate_component(getattr(self, name), f"{path}.{name}")
        for name in ("carrier", "sun_mesh", "ring_mesh"):
            validate_component(getattr(self, name), f"{path}.{name}", validate=False)
        if not _finite(self.base_helix_angle_deg) or abs(self.base_helix_angle_deg) >= 45:
            raise CaseError(
                f"{path}.base_helix_angle_deg must lie in (-45, 45) degrees "
                f"(got {self.base_helix_angle_deg!r})"
            )
        if looks_like_radians(self.base_helix_angle_deg):
            raise CaseError(
                f"{path}.base_helix_angle_deg must be given in degrees (0 for spur gears): "
                f"{self.base_helix_angle_deg!r} looks like radians "
                f"(= {math.degrees(self.base_helix_angle_deg):.4g} deg)"
            )
        check_planetary_geometry(self, path)
        for name in (
            "carrier",
            "carrier_bearing",
            "ring_bearing",
            "sun_bearing",
            "planet_bearing",
            "sun_mesh",
            "ring_mesh",
        ):
            getattr(self, name).validate(f"{path}.{name}")
        require_axial_position(f"{path}.axial_position", self.axial_position)
        if self.ring.base_radius <= self.planet.base_radius:
            raise CaseError(
                f"{path}.ring.base_radius must exceed {path}.planet.base_radius "
                f"({self.ring.base_radius} <= {self.planet.base_radius})"
            )
        self._validate_radii(path)
        laws = (self.sun_mesh.law, self.ring_mesh.law)
        bodied = ("potential_energy", "loaded_contact")  # laws whose compliance has the bore
        if any(law in bodied for law in laws):
            members = ("sun", "planet") if laws[0] in bodied else ("planet",)
            for member in members:
                check_foundation_bore(f"{path}.{member}", getattr(self, member))
        for name in ("sun_mesh", "ring_mesh"):
            mesh = getattr(self, name)
            module = transverse_module_of(self.planet, mesh.pressure_angle_deg)
            check_backlash(f"{path}.{name}.backlash", mesh.backlash, module)
        self._validate_angles(path)
        self._validate_teeth(path)
        self._validate_contact(path)

    def _validate_radii(self, path: str) -> None:
        """The base radii and the carrier radius fix each mesh's line of action:
        r_bs + r_bp = r_c cos(alpha_s) and r_br - r_bp = r_c cos(alpha_r) (docs/model.md §2),
        so both sums over r_c must be cosines of a pressure angle in (0, 45) degrees."""
        r_c = self.carrier.radius
        for mesh, value, formula in (
            ("sun_mesh", self.sun.base_radius + self.planet.base_radius, "sun + planet"),
            ("ring_mesh", self.ring.base_radius - self.planet.base_radius, "ring - planet"),
        ):
            cosine = value / r_c
            if not math.cos(math.pi / 4) < cosine < 1:
                angle = f"{math.degrees(math.acos(cosine)):.3g} deg" if cosine < 1 else "none"
                raise CaseError(
                    f"{path}.carrier.radius: the geometry is impossible: {formula} base_radius = "
                    f"{value * 1e3:.4g} mm must lie between cos(45 deg) r_c and r_c = "
                    f"{r_c * 1e3:.4g} mm (r_c cos(alpha) of the {mesh}; implied pressure "
                    f"angle: {angle})"
                )

    def _validate_angles(self, path: str) -> None:
        if self.planet_angles_deg is not None:
            angles = self.planet_angles_deg
            if not isinstance(angles, (tuple, list)):
                raise CaseError(
                    f"{path}.planet_angles_deg must be a sequence of angles in degrees, one per "
                    f"planet (got {angles!r})"
                )
            if len(angles) != self.planets:
                raise CaseError(
                    f"{path}.planet_angles_deg must list one angle per planet "
                    f"({len(angles)} given for {self.planets} planets)"
                )
            if not all(_finite(a) for a in angles):
                raise CaseError(f"{path}.planet_angles_deg must be finite numbers (got {angles!r})")
        if self.planets < 2:
            return
        pitch = self.planet.base_radius / math.cos(self.sun_mesh.pressure_angle)
        module = 2 * pitch / self.planet.teeth if self.planet.teeth else 0.0
        tip_radius = pitch + module
        if self.planet_angles_deg is None:  # equal spacing (no list: N may be absurd)
            smallest = 2 * math.pi / self.planets
        else:
            ordered = sorted(a % (2 * math.pi) for a in self.planet_angles)
            gaps = [b - a for a, b in zip(ordered, ordered[1:])] + [
                ordered[0] + 2 * math.pi - ordered[-1]
            ]
            smallest = min(gaps)
        centre_distance = 2 * self.carrier.radius * math.sin(smallest / 2)
        if centre_distance <= 2 * tip_radius:
            hint = ""
            angles = self.planet_angles_deg
            if angles is not None and max(abs(a) for a in angles) <= 2 * math.pi + 1e-9:
                degrees = ", ".join(f"{math.degrees(a):.4g}" for a in angles)
                hint = f"; the angles look like radians: in degrees they are ({degrees})"
            raise CaseError(
                f"{path}.planet_angles_deg: neighbouring planets {math.degrees(smallest):.3g} deg "
                f"apart collide (centres {centre_distance * 1e3:.4g} mm apart, the planet tip "
                f"circles need more than {2 * tip_radius * 1e3:.4g} mm){hint}"
            )

    def _validate_teeth(self, path: str) -> None:
        require_matching_teeth(path, {"sun": self.sun, "planet": self.planet, "ring": self.ring})
        if self.sun.teeth is None or self.ring.teeth is None:
            return
        total = self.sun.teeth + self.ring.teeth
        if self.equally_spaced and total % self.planets:
            typed = self.planet_angles_deg is not None
            nearest = ", ".join(f"{a:.6g}" for a in self.assemblable_angles_deg())
            remedy = (
                f"the nearest angles that assemble are ({nearest}) deg"
                if typed
                else f"give planet_angles_deg, e.g. the nearest that assemble: ({nearest}) deg"
            )
            raise CaseError(
                f"{path}.{'planet_angles_deg' if typed else 'planets'}: {self.planets} equally "
                f"spaced planets cannot be assembled with sun.teeth = {self.sun.teeth} and "
                f"ring.teeth = {self.ring.teeth}: (Z_s + Z_r)/N must be a whole number (got "
                f"{total}/{self.planets}); {remedy}, or other tooth numbers"
            )
        if self.planet_angles_deg is None:
            return
        first = self.planet_angles_deg[0]
        off = [
            ((a - first) * total / 360.0 - round((a - first) * total / 360.0))
            for a in self.planet_angles_deg
        ]
        worst = max(range(len(off)), key=lambda n: abs(off[n]))
        if abs(off[worst]) > ASSEMBLY_TOLERANCE:
            nearest = ", ".join(f"{a:.6g}" for a in self.assemblable_angles_deg())
            warnings.warn(
                f"{path}.planet_angles_deg: planet {worst + 1} at "
                f"{self.planet_angles_deg[worst]!r} deg cannot be assembled with sun.teeth = "
                f"{self.sun.teeth} and ring.teeth = {self.ring.teeth}: (Z_s + Z_r) psi / 360 deg "
                f"must be a whole number (is {off[worst]:+.3f} tooth pitches off one); the "
                f"nearest angles that assemble are ({nearest}) deg",
                PlausibilityWarning,
                stacklevel=4,
            )

    def assemblable_angles_deg(self) -> tuple[float, ...]:
        """The planet angles nearest to this stage's that assemble [deg]: the first planet
        where it is, each other at a whole number of 360/(Z_s + Z_r) degrees from it
        (equal spacing when no angles are given).  Needs both tooth numbers."""
        total = self.sun.teeth + self.ring.teeth
        step = 360.0 / total
        angles = self.planet_angles_deg
        if angles is None:
            angles = tuple(360.0 * n / self.planets for n in range(self.planets))
        first = angles[0]
        return tuple(first + step * round((a - first) / step) for a in angles)

    def _validate_contact(self, path: str) -> None:
        if self.spur:
            for name in ("sun_mesh", "ring_mesh"):
                ratio = getattr(self, name).contact_ratio
                if ratio <= 1:
                    raise CaseError(
                        f"{path}.{name}.contact_ratio must exceed 1 for a spur mesh "
                        f"(got {ratio!r}): at most one tooth pair would be in contact, "
                        f"with gaps of none"
                    )
        if self.mesh_phases is None:
            return
        pairs = self.mesh_phases
        if not isinstance(pairs, tuple) or not all(
            isinstance(p, tuple) and len(p) == 2 for p in pairs
        ):
            raise CaseError(
                f"{path}.mesh_phases must be a dict of mesh name to phase (got {pairs!r})"
            )
        known = self.mesh_names
        for name, phase in pairs:
            if name not in known:
                raise CaseError(
                    f"{path}.mesh_phases: no mesh named {name!r} in this stage "
                    f"(meshes: {', '.join(known)})"
                )
            if not _finite(phase) or not 0 <= phase < 1:
                raise CaseError(
                    f"{path}.mesh_phases[{name!r}] must lie in [0, 1) mesh cycles (got {phase!r})"
                )
