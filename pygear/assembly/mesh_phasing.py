r"""Mesh phasing of a planetary stage (Parker & Lin 2004) and the tooth-index offsets.

Conventions (docs/model.md §5.1)
--------------------------------
Every mesh has gear 1 = the central member (sun or ring) and gear 2 = the planet.
Its mesh cycle is s = sigma Z1 theta_rel / 2 pi + gamma, with theta_rel = theta_s -
theta_c (sun-planet) or theta_c - theta_r (ring-planet) and sigma = +1 when the sun
turns in +z relative to the carrier (the carrier driven forward with the ring held:
the seed's case), -1 for the mirror image.  With that sign s grows while the gears
run; the pairs in contact sit at p_k = frac(s) + k < eps, measured in base pitches
along the path of contact from where contact starts.  Pair k joined the mesh at the
unwrapped count n_k = floor(s) - k and is tooth i = (i0 + n_k) mod Z1 of gear 1 and
tooth j = (j0 + n_k) mod Z2 of the planet.  Teeth of every gear are numbered 0 ..
Z - 1 in the order in which they come into mesh, i.e. against the gear's rotation
relative to the carrier; a planet's teeth come into its sun mesh and its ring mesh
in that same order (one rotation sense serves both).

Reference state (all rotations zero): gamma_s1 = 0 and i0 = j0 = 0 for sun-planet1,
so sun tooth 0 and planet-1 tooth 0 form the pair that has just entered contact.
Ring tooth 0 is in the newest ring-planet1 pair (i0 = 0).  Planet n's tooth 0 is in
the newest sun-planet n pair (j0 = 0 for every sun mesh).

Sun-planet and ring-planet phases (Parker & Lin 2004)
-----------------------------------------------------
Turning the whole stage by -psi_n brings planet n onto planet 1 and the sun from
theta to theta - psi_n, and a sun-planet mesh state depends only on the sun's tooth
position seen from its planet.  Hence s_sn(theta) = s_s1(theta - psi_n), i.e. the
unwrapped phase g_sn = -sigma Z_s (psi_n - psi_1) / 2 pi.  The ring turns the other
way relative to the carrier, so g_rn = gamma_rs + sigma Z_r (psi_n - psi_1) / 2 pi.
The phase is gamma = frac(g); the whole part is the tooth offset of gear 1,
i0 = floor(g) mod Z1 (the sun or ring tooth that planet n meets at count 0 is
floor(g) teeth after the one planet 1 meets).  This is Parker & Lin's
gamma_sn = frac(+-Z_s psi_n / 2 pi), gamma_rn = frac(-+Z_r psi_n / 2 pi), the upper
signs for a sun turning clockwise (sigma = -1).  Equally spaced planets that can be
assembled have (Z_s + Z_r)/N whole, so gamma_rn - gamma_rs = gamma_sn (mod 1); Z_s/N
whole puts every sun-planet mesh in phase.  Unequal spacing is allowed; a planet
position error (off the assembly condition) simply enters both formulas.

Ring-to-sun phase of one planet
-------------------------------
Both pitch points of a planet lie on the line through the stage axis and the planet
centre, diametrically opposite on the planet: half a planet revolution, Z_p / 2
tooth periods, apart.  An idler loads opposite flanks in its two meshes.  In the
carrier frame power flows ring -> planet -> sun when the carrier drives and the sun
is the output (``sun_driven``, sigma_L = +1: the planet drives the sun with the
flank facing its motion, and is driven by the ring on the trailing flank), and the
other way (sigma_L = -1) when the sun drives.  With standard teeth (tooth thickness
half the circular pitch on the pitch circle, no backlash; exact when alpha_s =
alpha_r) the trailing flank of a tooth follows its leading flank by half a tooth
period.  So a planet tooth whose sun-loaded flank passes the sun pitch point P_s
passes the ring pitch point P_r with its ring-loaded flank

    Delta_c = (Z_p + sigma_L) / 2   tooth periods (mesh cycles) later.

A flank passes a pitch point when its pair is at p = p_P, the distance from the
start of contact to the pitch point in base pitches.  Planet tooth j (j0 = 0 in
the sun mesh) is at P_s when s_s = n + p_Ps with n = j (mod Z_p), and at P_r when
s_r = n' + p_Pr.  Both meshes advance one cycle per planet tooth period and
s_r - s_s = gamma_rn - gamma_sn = Delta, so n' = n + p_Ps - p_Pr + Delta_c + Delta
must be whole.  Hence

    gamma_rs = frac(p_Pr - p_Ps - (Z_p + sigma_L) / 2),
    j0 (ring mesh) = -round(p_Ps - p_Pr + Delta_c + Delta)  mod Z_p.

Z_p odd makes (Z_p + sigma_L)/2 whole, Z_p even makes it a half: gamma_rs flips by
half a cycle between odd and even Z_p (docs/model.md §5.3).  The rounding in j0 only
matters when an override or a planet position error moves Delta off its
geometric value.

Where contact starts (p_P)
--------------------------
Contact starts where the driven gear's tip circle crosses the line of action (the
driving flank meets it near its own root) and moves toward the driving gear's tip.
From the tangent point T of a gear with base radius r_b the pitch point lies
r_b tan(alpha) along the line of action and the tip circle r_a crosses it at
sqrt(r_a^2 - r_b^2) (external gear; for the internal ring the tip circle is the
inner one, on the same side of T as P, so its distance to P is r_b tan(alpha) -
sqrt(r_a^2 - r_b^2)).  The part of the path on the driven gear's side of P is the
approach length L_a, the rest the recess L_r:

    external tip:  L = sqrt(r_a^2 - r_b^2) - r_b tan(alpha),  r_a = r_b / cos(alpha) + h m
    ring tip:      L = r_b tan(alpha) - sqrt(r_a^2 - r_b^2),  r_a = r_b / cos(alpha) - h m

with the module m = 2 r_bp / (Z_p cos(alpha)) of the planet (pitch circles at the
operating pressure angle) and addendum coefficient h = 1 (standard teeth, assumed).
sigma_L = +1: the sun mesh starts at the sun's tip, the ring mesh at the planet's
tip; sigma_L = -1 swaps approach and recess in both.  The case's contact ratio eps
is kept (the seed's 1.24 is smaller than standard addenda give): the geometry only
splits it, p_P = eps L_a / (L_a + L_r).  For the study case p_Ps = 0.612,
p_Pr = 0.569 and Z_p = 35, so gamma_rs = 0.957.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import CaseError
from ..model.components import PlanetaryStage

__all__ = [
    "MeshPhase",
    "PitchPoints",
    "parker_lin_phases",
    "pitch_points",
    "ring_sun_phase",
    "stage_phasing",
]


@dataclass(frozen=True)
class MeshPhase:
    """Phase and tooth offsets of one mesh.

    Attributes
    ----------
    phase : float
        gamma in [0, 1) mesh cycles.
    gear_1_offset, gear_2_offset : int
        i0 and j0: the 0-based teeth of gear 1 (sun or ring) and gear 2 (planet) in
        the pair that enters contact at the count n = 0.
    overridden : bool
        True when the phase comes from the case's ``mesh_phases``.
    """

    phase: float
    gear_1_offset: int
    gear_2_offset: int
    overridden: bool = False


@dataclass(frozen=True)
class PitchPoints:
    """Where the pitch point lies on each path of contact of a planet.

    Attributes
    ----------
    sun, ring : float
        p_P of the sun-planet and ring-planet mesh: distance from the start of
        contact to the pitch point [mesh cycles, i.e. base pitches].
    sun_geometric_ratio, ring_geometric_ratio : float
        The contact ratios that standard addenda would give (for information).
    """

    sun: float
    ring: float
    sun_geometric_ratio: float
    ring_geometric_ratio: float


SNAP = 1e-9
"""Phases within this many mesh cycles of a whole number are taken as whole (planet
angles given in degrees, 2 pi n / N, never land exactly on a tooth)."""


def _snap(value: float) -> float:
    nearest = round(value)
    return float(nearest) if abs(value - nearest) < SNAP else value


def _frac(value: float) -> float:
    result = value - math.floor(value)
    return 0.0 if result >= 1.0 else result


def _required_teeth(stage: PlanetaryStage, path: str) -> tuple[int, int, int]:
    for member in ("sun", "ring", "planet"):
        if getattr(stage, member).teeth is None:
            raise CaseError(
                f"{path}.{member}.teeth is needed for mesh phasing and the tooth-contact table"
            )
    return stage.sun.teeth, stage.ring.teeth, stage.planet.teeth


def pitch_points(
    stage: PlanetaryStage, *, sun_driven: bool = True, addendum_coefficient: float = 1.0
) -> PitchPoints:
    """Distance from the start of contact to the pitch point, for both meshes of a planet.

    Parameters
    ----------
    stage : PlanetaryStage
        The stage (base radii, pressure angles, tooth numbers and contact ratios).
    sun_driven : bool
        True when the carrier drives and the sun is the output (power flows ring ->
        planet -> sun in the carrier frame); False when the sun drives.
    addendum_coefficient : float
        Tooth addendum over the module (1 for standard teeth).

    Returns
    -------
    PitchPoints
        p_P of each mesh, the case's contact ratio split in the proportion of the
        approach and recess lengths of standard teeth (see the module docstring).
    """
    _, _, z_p = _required_teeth(stage, stage.name)
    r_bs, r_br, r_bp = stage.sun.base_radius, stage.ring.base_radius, stage.planet.base_radius
    base_pitch = 2 * math.pi * r_bp / z_p
    results = {}
    for name, mesh, r_b in (("sun", stage.sun_mesh, r_bs), ("ring", stage.ring_mesh, r_br)):
        alpha = mesh.pressure_angle
        addendum = addendum_coefficient * 2 * r_bp / (z_p * math.cos(alpha))
        planet_tip = r_bp / math.cos(alpha) + addendum
        planet_part = math.sqrt(planet_tip**2 - r_bp**2) - r_bp * math.tan(alpha)
        if name == "sun":
            tip = r_b / math.cos(alpha) + addendum
            central_part = math.sqrt(tip**2 - r_b**2) - r_b * math.tan(alpha)
            # sun driven: contact starts on the sun's tip
            approach, recess = central_part, planet_part
        else:
            tip = r_b / math.cos(alpha) - addendum
            if tip <= r_b:
                raise CaseError(
                    f"{stage.name}.ring: the ring's tip circle ({tip:.6g} m) falls inside its "
                    f"base circle ({r_b:.6g} m); the mesh geometry is not involute"
                )
            central_part = r_b * math.tan(alpha) - math.sqrt(tip**2 - r_b**2)
            # carrier driving: the ring drives the planet, contact starts on the planet's tip
            approach, recess = planet_part, central_part
        if not sun_driven:
            approach, recess = recess, approach
        if approach <= 0 or recess <= 0:
            raise CaseError(
                f"{stage.name}.{name}_mesh: the path of contact does not straddle the pitch "
                f"point (approach {approach:.4g} m, recess {recess:.4g} m)"
            )
        share = approach / (approach + recess)
        results[name] = (mesh.contact_ratio * share, (approach + recess) / base_pitch)
    return PitchPoints(
        sun=results["sun"][0],
        ring=results["ring"][0],
        sun_geometric_ratio=results["sun"][1],
        ring_geometric_ratio=results["ring"][1],
    )


def ring_sun_phase(
    sun_pitch_point: float, ring_pitch_point: float, planet_teeth: int, *, sun_driven: bool = True
) -> float:
    """gamma_rs = frac(p_Pr - p_Ps - (Z_p + sigma_L)/2) of one planet (module docstring)."""
    sigma_load = 1 if sun_driven else -1
    return _frac(ring_pitch_point - sun_pitch_point - (planet_teeth + sigma_load) / 2)


def parker_lin_phases(
    teeth: int, angles: tuple[float, ...], *, direction: int = 1, member: str = "sun"
) -> tuple[float, ...]:
    """Unwrapped phases relative to planet 1 (before frac and the ring-to-sun phase).

    Parameters
    ----------
    teeth : int
        Z_s for ``member='sun'``, Z_r for ``member='ring'``.
    angles : tuple of float
        Planet angles psi_n [rad].
    direction : int
        sigma: +1 when the sun turns in +z relative to the carrier, -1 otherwise.
    member : str
        ``sun`` (g = -sigma Z_s dpsi / 2 pi) or ``ring`` (g = +sigma Z_r dpsi / 2 pi).
    """
    sign = -direction if member == "sun" else direction
    return tuple(_snap(sign * teeth * (psi - angles[0]) / (2 * math.pi)) for psi in angles)


def stage_phasing(
    stage: PlanetaryStage, *, direction: int = 1, sun_driven: bool = True
) -> dict[str, MeshPhase]:
    """Phase and tooth offsets of every mesh of a stage, by mesh name.

    Parameters
    ----------
    stage : PlanetaryStage
        The stage; its ``mesh_phases`` override the computed phases.
    direction : int
        sigma = +1 when the sun turns in +z relative to the carrier (carrier driven
        forward, ring held), -1 for the mirror image.
    sun_driven : bool
        True when the carrier drives and the sun is the output (the seed's wind
        turbine); False when the sun drives.

    Returns
    -------
    dict
        ``{"sun-planet1": MeshPhase, ..., "ring-planetN": MeshPhase}``.
    """
    if direction not in (1, -1):
        raise CaseError(f"direction must be +1 or -1 (got {direction!r})")
    z_s, z_r, z_p = _required_teeth(stage, stage.name)
    points = pitch_points(stage, sun_driven=sun_driven)
    gamma_rs = ring_sun_phase(points.sun, points.ring, z_p, sun_driven=sun_driven)
    delta_c = (z_p + (1 if sun_driven else -1)) / 2
    overrides = stage.phase_overrides
    angles = stage.planet_angles
    sun = parker_lin_phases(z_s, angles, direction=direction, member="sun")
    ring = parker_lin_phases(z_r, angles, direction=direction, member="ring")
    phases: dict[str, MeshPhase] = {}
    for n in range(stage.planets):
        # whole and fractional parts kept apart so that planets in phase get equal phases
        whole = math.floor(ring[n])
        combined = _snap(gamma_rs + (ring[n] - whole))
        carry = math.floor(combined)
        sun_name, ring_name = f"sun-planet{n + 1}", f"ring-planet{n + 1}"
        gamma_s = overrides.get(sun_name, _frac(sun[n]))
        gamma_r = overrides.get(ring_name, _frac(combined - carry))
        planet_offset = -round(points.sun - points.ring + delta_c + (gamma_r - gamma_s))
        phases[sun_name] = MeshPhase(gamma_s, math.floor(sun[n]) % z_s, 0, sun_name in overrides)
        phases[ring_name] = MeshPhase(
            gamma_r, (whole + carry) % z_r, planet_offset % z_p, ring_name in overrides
        )
    return phases
