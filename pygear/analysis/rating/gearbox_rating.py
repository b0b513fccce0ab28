"""Rating of a whole gearbox: the torque through its stages, every mesh rated to ISO
6336, the gears' damage under a duty cycle (ISO 6336-6) and the bearings' life (ISO 281).

Torque flow: the stages are rated in the gearbox's order, the rated input torque and
speed entering the first gear stage.  A planetary stage is taken as pygear builds it
(ring held, carrier in, sun out: T_sun = T_c / (1 + z_r/z_s)); a parallel stage from
its input gear to its output gear.  Losses are neglected.

:func:`rate_gearbox` returns a :class:`GearboxRating` (the mesh ratings and bearing
lives in plain Python); :mod:`.dataset` turns it into an ``xarray.Dataset``.  Factors
known from elsewhere enter as given: the rating's own tables, and ``dynamic_factors``
per mesh from outside (the dynamic factor of ``pygear response``, say).  A K_gamma the
model computes from planet position errors is solved at the rated torque and kept for
every duty-cycle bin (the errors' extra load is fixed, so a light bin's true K_gamma is
higher: the damage of light bins is then underestimated, which they rarely decide).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

from ...errors import CaseError
from ...model import gear_geometry as geo
from ...model.geometry_inputs import parallel_mesh_geometry, planetary_mesh_geometry
from ...model.rating import Rating, RollingBearingData
from . import bearing_life as iso281
from . import factors as iso
from .duty import cycles_to_failure
from .gear_rating import FactorValue, PairLoad, PairRating, planet_reduced_masses, rate_pair

__all__ = ["GearboxRating", "MeshEntry", "load_sharing_from_forces", "model_dynamic_factors",
           "rate_gearbox"]

ISO_KV = "ISO 6336-1:2019 method B (cl. 6.3)"

MESH_MEMBERS = {"sun_mesh": ("sun", "planet"), "ring_mesh": ("planet", "ring"),
                "mesh": ("input_gear", "output_gear")}


@dataclass(frozen=True)
class MeshEntry:
    """One rated mesh: its name, its gears' names and the rating."""

    name: str
    gears: tuple[str, str]
    stage: str
    pair: PairLoad
    rating: PairRating


@dataclass
class GearboxRating:
    """Every mesh's rating, the gears' damage and the bearings' lives."""

    meshes: list[MeshEntry]
    damage: dict[str, dict[str, float]] = field(default_factory=dict)
    bearings: dict[str, dict[str, float]] = field(default_factory=dict)
    spectrum_hours: float | None = None
    dynamic_factor_method: str = ISO_KV


def load_sharing_from_forces(forces: Sequence[float]) -> float:
    """K_gamma = max F_i / mean F_i of the planets' mesh forces (static or time means),
    the definition of ISO 6336-1 cl. 5; feed it back as ``Rating(load_sharing=...)``."""
    values = [abs(float(f)) for f in forces]
    if not values or sum(values) <= 0.0:
        raise CaseError("forces must hold at least one non-zero planet mesh force")
    return max(values) / (sum(values) / len(values))


class _Records(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


def model_dynamic_factors(case, rating: Rating, scene=None) -> tuple[dict[str, float], str]:
    """K_v per rated mesh from the dynamic model's steady state at the rated input speed
    and torque (:func:`pygear.analysis.response.dynamic_factors_at`), and how K_v was
    found.  Where the response cannot give it (a case it cannot balance, or a balance
    that misses its tolerance) the dict is empty and the text says why: the rating then
    takes ISO 6336-1 method B."""
    from ..response import dynamic_factors_at

    speed = rating.rated_speed_rpm
    records = _Records()
    logger = logging.getLogger("pygear")
    logger.addHandler(records)
    try:
        values = dynamic_factors_at(case, speed, rating.rated_torque, scene=scene,
                                    keys="rating")
    except CaseError as error:
        return {}, f"{ISO_KV}: the response analysis cannot balance this case ({error})"
    finally:
        logger.removeHandler(records)
    missed = [m for m in records.messages if "residual" in m]
    if missed:
        return {}, (f"{ISO_KV}: the response analysis at {speed:g} rpm misses its "
                    f"tolerance ({missed[0].removeprefix('response: ')})")
    return values, (f"response analysis (harmonic balance, peak over mean mesh force) at "
                    f"the rated {speed:g} rpm")


def _material(rating: Rating, gear: str):
    try:
        return rating.materials[gear]
    except KeyError:
        raise CaseError(
            f"rating.materials has no entry for {gear!r}: add {gear!r}: Material(...) "
            "(or iso6336_5_material(...))"
        ) from None


def _given(table: Mapping[str, float], key: str, name: str) -> FactorValue | None:
    if key not in table:
        return None
    return FactorValue(float(table[key]), f"given in the case (rating.{name})", "given")


def _stage_meshes(stage, torque: float, speed: float) -> tuple[list, float, float]:
    """[(mesh name, members, geometry, torque1, speeds, contacts, m_red, idler, rims)],
    output torque and speed of one stage."""
    name = stage.name
    if hasattr(stage, "planets"):
        z_s, z_p, z_r = stage.sun.geometry.teeth, stage.planet.geometry.teeth, \
            stage.ring.geometry.teeth
        planets = stage.planets
        t_sun = torque / (1.0 + z_r / z_s)
        n_sun = speed * (1.0 + z_r / z_s)
        n_sun_rel = n_sun - speed
        n_planet_rel = -n_sun_rel * z_s / z_p
        bores = (stage.sun.bore_radius or 0.0, stage.planet.bore_radius or 0.0)
        m_sun, m_ring = planet_reduced_masses(stage.sun.geometry, stage.planet.geometry,
                                              bores, planets)
        sun_geometry = planetary_mesh_geometry(stage, "sun")
        ring_geometry = planetary_mesh_geometry(stage, "ring")
        f_t = (t_sun / planets) / geo.pitch_radius(stage.sun.geometry)
        t_planet = f_t * geo.pitch_radius(stage.planet.geometry)
        ring_rim = None
        if stage.ring.rim_radius is not None:
            ring_rim = stage.ring.rim_radius - geo.root_radius(stage.ring.geometry)
        meshes = [
            (f"{name}.sun_mesh", (f"{name}.sun", f"{name}.planet"), sun_geometry,
             t_sun / planets, (n_sun_rel, n_planet_rel), (planets, 1), m_sun, (False, True),
             (None, None)),
            (f"{name}.ring_mesh", (f"{name}.planet", f"{name}.ring"), ring_geometry,
             t_planet, (n_planet_rel, -speed), (1, planets), m_ring, (True, False),
             (None, ring_rim)),
        ]
        return meshes, t_sun, n_sun
    z_in, z_out = stage.input_gear.geometry.teeth, stage.output_gear.geometry.teeth
    geometry = parallel_mesh_geometry(stage)
    meshes = [(f"{name}.mesh", (f"{name}.input_gear", f"{name}.output_gear"), geometry,
               torque, (speed, speed * z_in / z_out), (1, 1), None, (False, False),
               (None, None))]
    return meshes, torque * z_out / z_in, speed * z_in / z_out


def _gear_stages(case) -> list:
    stages = [s for s in case.gearbox.stages if hasattr(s, "planets") or hasattr(s, "mesh")]
    for stage in stages:
        members = ("sun", "planet", "ring") if hasattr(stage, "planets") else (
            "input_gear", "output_gear")
        for member in members:
            if getattr(stage, member).geometry is None:
                raise CaseError(
                    f"{stage.name}.{member}.geometry is needed for a rating (give the gear a "
                    "GearGeometry: ISO 6336 rates the tooth, not a stiffness)"
                )
    if not stages:
        raise CaseError("case.gearbox has no gear stage to rate")
    return stages


def pair_loads(case, rating: Rating, torque: float, speed: float, application_factor: float,
               dynamic_factors: Mapping[str, float] | None = None,
               model_sharing: Mapping[str, float] | None = None) -> list[tuple]:
    """(mesh name, gear names, stage, PairLoad) of every mesh at input ``torque`` [N m]
    and ``speed`` [rpm]; ``model_sharing`` holds K_gamma the model computed per stage."""
    dynamic_factors = dict(dynamic_factors or {})
    for key, value in dynamic_factors.items():
        if not (math.isfinite(value) and value >= 1.0):
            raise CaseError(f"dynamic_factors[{key!r}] must be a finite number >= 1 "
                            f"(got {value})")
    out = []
    k_a = FactorValue(application_factor, iso.CLAUSES["K_A"] + "; given in the case", "given")
    for stage in _gear_stages(case):
        planets = getattr(stage, "planets", 1)
        k_g = _given(rating.load_sharing, stage.name, "load_sharing")
        if k_g is None and model_sharing and stage.name in model_sharing:
            k_g = FactorValue(
                model_sharing[stage.name],
                "static model with rating.planet_position_errors at the rated torque "
                "(ISO 6336-1:2019 cl. 5: max / mean planet force)", "model")
        if k_g is None and not hasattr(stage, "planets"):
            k_g = FactorValue(1.0, "one load path (a parallel stage)", "default")
        if k_g is None:
            k_g = FactorValue(
                iso.planet_load_sharing_default(planets),
                f"IEC 61400-4:2012 default for {planets} planet(s) (no load-sharing device)",
                "default")
        meshes, torque, speed = _stage_meshes(stage, torque, speed)
        for name, gears, geometry, t1, speeds, contacts, m_red, idler, rims in meshes:
            given = {}
            for factor, table, label in (("K_v", rating.dynamic_factor, "dynamic_factor"),
                                         ("K_Hbeta", rating.face_load_factor, "face_load_factor"),
                                         ("K_Halpha", rating.transverse_load_factor,
                                          "transverse_load_factor")):
                value = _given(table, name, label)
                if value is not None:
                    given[factor] = value
            if name in dynamic_factors:
                given["K_v"] = FactorValue(float(dynamic_factors[name]),
                                           "dynamic factor from the dynamic model", "response")
            load = PairLoad(
                geometry=geometry,
                materials=(_material(rating, gears[0]), _material(rating, gears[1])),
                torque1=t1, speeds=speeds, contacts=contacts, reduced_mass=m_red,
                idler=idler, rims=rims, application_factor=k_a, load_sharing=k_g,
                given=given, accuracy_grade=rating.accuracy_grade,
                oil_viscosity_40=rating.oil_viscosity_40,
                service_life_h=rating.service_life_h,
            )
            out.append((name, gears, stage.name, load))
    meshes = [entry[0] for entry in out]
    gears = {gear for entry in out for gear in entry[1]}
    stages = {entry[2] for entry in out if entry[0].endswith("sun_mesh")}
    for label, keys, known in (
        ("dynamic_factors", dynamic_factors, meshes),
        ("rating.dynamic_factor", rating.dynamic_factor, meshes),
        ("rating.face_load_factor", rating.face_load_factor, meshes),
        ("rating.transverse_load_factor", rating.transverse_load_factor, meshes),
        ("rating.load_sharing", rating.load_sharing, sorted(stages)),
        ("rating.materials", rating.materials, sorted(gears)),
    ):
        unknown = sorted(set(keys) - set(known))
        if unknown:
            raise CaseError(f"{label} names {unknown}, which the case does not have; "
                            f"it has {known}")
    return out


def _constant_load_damage(entry: MeshEntry, side: int, hours: float) -> tuple[float, float]:
    """(pitting, bending) damage over ``hours`` at the rated load (K_A included)."""
    values = entry.rating.gears[side]
    kind = entry.pair.materials[side].kind
    per_hour = values["N_L"].value / entry.pair.service_life_h
    out = []
    for stress, reference, root in (("sigma_H", "sigma_HG_ref", False),
                                    ("sigma_F", "sigma_FG_ref", True)):
        life = cycles_to_failure(kind, values[stress].value, values[reference].value, root)
        out.append(per_hour * hours / life)
    return out[0], out[1]


def rate_gearbox(case, rating: Rating, *, dynamic_factors: Mapping[str, float] | None = None,
                 duty_cycle=None, matrices: Sequence | None = None,
                 record_s: float | None = None,
                 record_speed_rpm: float | None = None,
                 dynamic_factor_method: str | None = None) -> GearboxRating:
    """Rate every mesh at the rated point, then the damage and the bearings.

    Parameters
    ----------
    case : Case
        The case (gear geometry on every gear of its gear stages).
    rating : Rating
        Materials, factors, safeties, life, bearings.
    dynamic_factors : dict of str to float, optional
        K_v per mesh ("stage1.sun_mesh", ...) from outside; used instead of method B.
    duty_cycle : DutyCycle, optional
        Overrides ``rating.duty_cycle``.
    matrices : sequence of CycleMatrix, optional
        Rainflow matrices of recorded mesh forces (a run's, :mod:`.run_damage`): the
        damage of the meshes they cover comes from them, over ``record_s`` seconds.
    record_s : float, optional
        Duration [s] the ``matrices`` count.
    record_speed_rpm : float, optional
        Mean input speed of that record [rpm] (default the rated speed): the tooth
        contacts the matrices' cycles share out.
    dynamic_factor_method : str, optional
        How ``dynamic_factors`` were found, for the output.
    """
    duty = duty_cycle if duty_cycle is not None else rating.duty_cycle
    sharing = None
    if rating.planet_position_errors:
        from .load_sharing import load_sharing_from_model

        sharing = load_sharing_from_model(case, rating.planet_position_errors,
                                          rating.rated_torque)
    loads = pair_loads(case, rating, rating.rated_torque, rating.rated_speed_rpm,
                       rating.application_factor, dynamic_factors, sharing)
    mismatch, contact = _shaft_mismatch(case, rating, loads) if rating.face_load_from_model \
        else ({}, {})
    loads = [(n, g, s, _face_load(p, mismatch.get(n), contact.get(n)))
             for n, g, s, p in loads]
    meshes = [MeshEntry(name, gears, stage, load, rate_pair(load))
              for name, gears, stage, load in loads]
    result = GearboxRating(meshes)
    if dynamic_factor_method is not None:
        result.dynamic_factor_method = dynamic_factor_method
    elif dynamic_factors:
        result.dynamic_factor_method = "given to rate_gearbox (dynamic_factors)"
    life = rating.service_life_h
    speed_scale = (record_speed_rpm or rating.rated_speed_rpm) / rating.rated_speed_rpm
    recorded = _recorded(case, meshes, matrices, record_s, life, result, speed_scale)
    if duty is None:
        for entry in meshes:
            if entry.name in recorded:
                continue
            for side in (0, 1):
                pitting, bending = _constant_load_damage(entry, side, life)
                _add_damage(result.damage, entry.gears[side], entry.name, pitting, bending,
                            "rated load (K_A included) over the service life")
    else:
        result.spectrum_hours = duty.period_h or sum(duty.hours)
        scale = life / result.spectrum_hours
        speeds = duty.speed_rpm or (rating.rated_speed_rpm,) * len(duty.torque)
        totals: dict[tuple[str, str, int], list[float]] = {}
        for torque, hours, speed in zip(duty.torque, duty.hours, speeds):
            if hours <= 0.0:
                continue
            # ISO 6336-6: the spectrum replaces K_A, the other factors at each bin's load
            binned = pair_loads(case, rating, torque, speed, 1.0, dynamic_factors, sharing)
            binned = [(n, g, s, _face_load(p, mismatch.get(n), contact.get(n)))
                      for n, g, s, p in binned]
            for name, gears, _, load in binned:
                if name in recorded:
                    continue
                rated = rate_pair(replace(load, service_life_h=hours))
                for side in (0, 1):
                    entry = MeshEntry(name, gears, "", replace(load, service_life_h=hours), rated)
                    pitting, bending = _constant_load_damage(entry, side, hours)
                    slot = totals.setdefault((name, gears[side], side), [0.0, 0.0])
                    slot[0] += pitting
                    slot[1] += bending
        for (name, gear, _), (pitting, bending) in totals.items():
            _add_damage(result.damage, gear, name, pitting * scale, bending * scale,
                        "duty cycle (ISO 6336-6 load spectrum)")
    result.bearings = _bearings(case, rating, meshes, duty)
    return result


def _face_load(load: PairLoad, mismatch: float | None, contact: FactorValue | None
               ) -> PairLoad:
    """``load`` with the model's mismatch, and the LTCA's K_Hbeta where it has one."""
    if contact is not None:
        return replace(load, given={**load.given, "K_Hbeta": contact})
    return replace(load, shaft_mismatch=mismatch)


def _shaft_mismatch(case, rating: Rating, loads: list[tuple]
                    ) -> tuple[dict[str, float], dict[str, FactorValue]]:
    """f_sh per unit line load [um per N/mm] of every rated mesh from the model's static
    deflection at the rated torque (:mod:`.deflection`): the largest over a stage's
    planets; and K_Hbeta of the LTCA with that mismatch for meshes whose gears carry
    micro-geometry (at the rated F_m, kept for every duty-cycle bin).  Meshes with a
    given K_Hbeta are left out."""
    from .deflection import has_micro_geometry, ltca_face_load_factor, mesh_misalignments
    from .run_damage import mesh_for_label

    slopes = mesh_misalignments(case, rating.rated_torque)
    names = [entry[0] for entry in loads]
    worst: dict[str, tuple[float, str]] = {}
    for label, slope in slopes.items():
        mesh = mesh_for_label(label, names)
        if mesh is not None and abs(slope) >= worst.get(mesh, (-1.0, ""))[0]:
            worst[mesh] = (abs(slope), label)
    out, contact = {}, {}
    for name, _, _, load in loads:
        if name in rating.face_load_factor or name not in worst:
            continue
        slope, label = worst[name]
        g1, g2 = load.geometry.gear1, load.geometry.gear2
        b = min(g1.face_width, g2.face_width)  # m
        line_load = abs(load.torque1) / geo.pitch_radius(g1) / (b * 1e3)  # N/mm, nominal
        out[name] = slope * b * 1e6 / line_load
        if has_micro_geometry(case, label):
            mesh = rate_pair(replace(load, shaft_mismatch=out[name])).mesh
            f_m = (mesh["F_t"].value * mesh["K_A"].value * mesh["K_gamma"].value
                   * mesh["K_v"].value)
            force = f_m / math.cos(geo.transverse_pressure_angle(g1))  # transverse LOA
            k_hb = ltca_face_load_factor(case, label, force, slope)
            contact[name] = FactorValue(
                k_hb, f"ISO 6336-1:2019 cl. 7 (K_Hbeta as the face load's peak over its "
                f"mean): loaded tooth contact analysis of {label} with its micro-geometry "
                f"and the model's mismatch {slope * b * 1e6:.3g} um, at the rated F_m",
                "model")
    return out, contact


def check_record_meshes(case, rating: Rating | None, matrices,
                        names: Sequence[str] | None = None) -> dict:
    """The record's matrices by rated mesh; a CaseError names labels of meshes the case
    does not have."""
    from .run_damage import matrices_by_mesh

    if names is None:
        names = [entry[0] for entry in pair_loads(case, rating, rating.rated_torque,
                                                  rating.rated_speed_rpm, 1.0)]
    grouped, unknown = matrices_by_mesh(matrices, names)
    if unknown:
        raise CaseError(f"the duty-cycle record's meshes {unknown} are not meshes of the "
                        f"case's rating ({list(names)})")
    return grouped


def _recorded(case, meshes: list[MeshEntry], matrices, record_s, life: float,
              result: GearboxRating, speed_scale: float) -> set[str]:
    """Damage of the meshes the recorded ``matrices`` cover (added to ``result``); their
    names."""
    if not matrices:
        return set()
    from .run_damage import run_planets, spectrum_damage

    grouped = check_record_meshes(case, None, matrices, [m.name for m in meshes])
    planets = {s.name: getattr(s, "planets", 1) for s in _gear_stages(case)}
    for entry in meshes:
        if entry.name not in grouped:
            continue
        damage = spectrum_damage(entry.pair, run_planets(planets, entry.name),
                                 grouped[entry.name], float(record_s or 0.0), life,
                                 speed_scale)
        for side, (pitting, bending) in enumerate(damage):
            _add_damage(result.damage, entry.gears[side], entry.name, pitting, bending,
                        "run's mesh forces (rainflow, ISO 6336-6)")
    return set(grouped)


def _add_damage(table: dict, gear: str, mesh: str, pitting: float, bending: float,
                source: str) -> None:
    slot = table.setdefault(gear, {"pitting": 0.0, "bending": 0.0, "mesh": mesh,
                                   "source": source})
    # a planet's two flanks (sun side, ring side) are different surfaces; its root sees
    # both meshes' bending, which Y_M already accounts for: the worse of each counts
    if max(pitting, bending) > max(slot["pitting"], slot["bending"]):
        slot["mesh"] = mesh
        slot["source"] = source
    slot["pitting"] = max(slot["pitting"], pitting)
    slot["bending"] = max(slot["bending"], bending)


def _bearing_load(bearing: RollingBearingData, meshes: list[MeshEntry], scale: float,
                  speed: float, rated_speed: float) -> tuple[float, float, float]:
    """(F_r, F_a, bearing speed [rpm]) at ``scale`` times the rated torque and input
    ``speed`` (the meshes were rated at ``rated_speed``)."""
    if bearing.location.endswith(".planet"):
        stage = bearing.location.rsplit(".", 1)[0]
        sun = [m for m in meshes if m.name == f"{stage}.sun_mesh"]
        if not sun:
            raise CaseError(f"bearings[{bearing.name!r}].location {bearing.location!r} names "
                            "no planetary stage of the case")
        f_t = sun[0].rating.mesh["F_t"].value
        # the pin carries the sun's and the ring's tangential forces on the planet
        radial = 2.0 * f_t * scale * bearing.share
        return radial, 0.0, abs(sun[0].pair.speeds[1]) * speed / rated_speed
    radial = (bearing.radial_load or 0.0) * scale
    axial = (bearing.axial_load or 0.0) * scale
    return radial, axial, bearing.speed_factor * speed


def _bearings(case, rating: Rating, meshes: list[MeshEntry], duty) -> dict:
    out = {}
    base = rating.rated_speed_rpm
    for bearing in rating.bearings:
        if duty is None:
            bins = [(1.0, base, rating.service_life_h)]
        else:
            speeds = duty.speed_rpm or (base,) * len(duty.torque)
            bins = [(t / rating.rated_torque, n, h)
                    for t, n, h in zip(duty.torque, speeds, duty.hours) if h > 0.0]
        loads, revolutions, speeds_used = [], [], []
        for scale, speed, hours in bins:
            radial, axial, n = _bearing_load(bearing, meshes, scale, speed, base)
            loads.append(iso281.equivalent_load(radial, axial, bearing.e, bearing.X,
                                                bearing.Y, bearing.Y1))
            revolutions.append(60.0 * n * hours)
            speeds_used.append(n)
        p_m = iso281.mean_load(loads, revolutions, bearing.kind)
        hours = sum(h for *_, h in bins)
        if duty is not None and duty.period_h:  # idle hours: no load, no revolutions
            hours = duty.period_h
        speed = sum(revolutions) / (60.0 * hours)
        l10 = iso281.basic_life(bearing.C, p_m, bearing.kind)
        d_m = bearing.pitch_diameter * 1e3
        kappa = bearing.viscosity / iso281.reference_viscosity(speed, d_m)
        c_u = bearing.fatigue_load_limit or iso281.fatigue_load_limit(bearing.C0, bearing.kind,
                                                                      d_m)
        a = iso281.a_iso(bearing.kind, kappa, bearing.contamination, c_u, p_m)
        l10_h = l10 * 1e6 / (60.0 * speed)
        out[bearing.name] = {"P": p_m, "speed": speed, "L10": l10, "L10_h": l10_h,
                             "a_ISO": a, "kappa": kappa, "C_u": c_u, "L10m_h": a * l10_h}
    return out
