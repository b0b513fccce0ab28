"""Gear rating of one mesh to ISO 6336-1/-2/-3:2019 method B, factor by factor.

:func:`rate_pair` takes a :class:`PairLoad` (the mesh's geometry, materials, load and
speed and any factor the user gave) and returns a :class:`PairRating`: every factor
with its value, the clause that gave it and whether it was given or computed, the
nominal and working stresses and the safeties of both gears.  Internally in the
standard's units (N, mm, N/mm^2, um, 1/min, m/s).
"""

from __future__ import annotations

import functools
import math
import warnings
from dataclasses import dataclass, field

from ...errors import CaseError
from ...model import gear_geometry as geo
from ...model.rating import Material
from . import factors as iso
from .tooth_form import tooth_form

__all__ = ["DENSITY", "FactorValue", "PairLoad", "PairRating", "rate_pair"]

DENSITY = 7.83e-6
"""Steel density for the reduced mass of K_v [kg/mm^3]."""

FALLBACK_SINGLE_STIFFNESS = 14.0
"""c' [N/(mm um)] ISO 6336-1 cl. 9 takes for steel pairs when method B's q' series does
not apply (profile shifts outside its range)."""


@dataclass(frozen=True)
class FactorValue:
    """A factor's value, the clause that gave it and where it came from."""

    value: float
    clause: str
    source: str  # "computed", "given", "default", "response"


@dataclass(frozen=True)
class PairLoad:
    """Everything :func:`rate_pair` needs about one mesh (gear 1 drives or is the
    planet of a ring mesh).

    Parameters
    ----------
    geometry : MeshGeometry
        Gear 1 external; gear 2 external or internal.
    materials : tuple of Material
        Of gear 1 and gear 2.
    torque1 : float
        Torque on gear 1 per mesh (a sun's torque over the planets) [N m].
    speeds : tuple of float
        Speeds of gear 1 and gear 2 relative to the carrier (a parallel pair: absolute)
        [rpm].
    contacts : tuple of int
        Tooth contacts per relative revolution of each gear (a sun or ring: the planet
        count; others 1).
    reduced_mass : float or None
        m_red [kg/mm] of K_v; None computes it from the two gears as a free pair.
    idler : tuple of bool
        Whether each gear is loaded on both flanks (a planet: Y_M = 0.7).
    rims : tuple of float or None
        Rim thickness s_R below the root [m] of each gear, None for a solid gear.
    application_factor, load_sharing : FactorValue
        K_A and K_gamma.
    given : dict of str to FactorValue
        Factors given from outside: "K_v", "K_Hbeta", "K_Halpha".
    accuracy_grade : int
        ISO 1328-1 grade.
    oil_viscosity_40 : float
        nu_40 [mm^2/s].
    service_life_h : float
        Hours of the static rating's load cycles.
    shaft_mismatch : float or None
        The model's mismatch f_sh per unit line load [um per N/mm] (from the static
        deflection, :mod:`.deflection`); None: f_sh = 0 in K_Hbeta's method C.
    """

    geometry: geo.MeshGeometry
    materials: tuple[Material, Material]
    torque1: float
    speeds: tuple[float, float]
    contacts: tuple[int, int]
    reduced_mass: float | None
    idler: tuple[bool, bool]
    rims: tuple[float | None, float | None]
    application_factor: FactorValue
    load_sharing: FactorValue
    given: dict[str, FactorValue] = field(default_factory=dict)
    accuracy_grade: int = 6
    oil_viscosity_40: float = 220.0
    service_life_h: float = 20000.0
    shaft_mismatch: float | None = None


@dataclass(frozen=True)
class PairRating:
    """The rating of one mesh: shared factors and one entry per gear."""

    mesh: dict[str, FactorValue]
    gears: tuple[dict[str, FactorValue], dict[str, FactorValue]]


def _computed(value: float, name: str, note: str = "") -> FactorValue:
    clause = iso.CLAUSES.get(name, name)
    return FactorValue(float(value), clause + (f"; {note}" if note else ""), "computed")


def _gear_mass(gear: geo.GearGeometry, bore: float) -> float:
    """m* = (pi/8) (d_m/d_b)^2 d_m^2 rho (1 - q^4) [kg/mm] per unit face width, q = d_i/d_m
    (ISO 6336-1 cl. 6.3; a ring's is not needed: it is held)."""
    d_m = 1e3 * (geo.tip_radius(gear) + geo.root_radius(gear))
    d_b = 2e3 * geo.base_radius(gear)
    q = 2e3 * bore / d_m
    return math.pi / 8.0 * (d_m / d_b) ** 2 * d_m**2 * DENSITY * (1.0 - q**4)


def free_pair_reduced_mass(mesh: geo.MeshGeometry, bores: tuple[float, float]) -> float:
    """m_red = m1* m2* / (m1* + m2*) [kg/mm] of two gears on their own shafts."""
    m1 = _gear_mass(mesh.gear1, bores[0])
    m2 = _gear_mass(mesh.gear2, bores[1])
    return m1 * m2 / (m1 + m2)


def planet_reduced_masses(
    sun: geo.GearGeometry, planet: geo.GearGeometry, bores: tuple[float, float], planets: int
) -> tuple[float, float]:
    """(sun mesh, ring mesh) m_red [kg/mm] of a planetary stage: 1/(1/m_P* + N/m_S*) and
    m_P* (ISO 6336-1 cl. 6.3, the sun shared by N planets, the ring held)."""
    m_s = _gear_mass(sun, bores[0])
    m_p = _gear_mass(planet, bores[1])
    return 1.0 / (1.0 / m_p + planets / m_s), m_p


@functools.lru_cache(maxsize=256)
def _stiffness(mesh: geo.MeshGeometry) -> tuple[float, float, str]:
    """(c', c_gamma_alpha, note) by ISO 6336-1 method B with the larger shift first (the
    q' regression's order), else ISO's c' = 14 N/(mm um); cached per mesh geometry (a
    duty cycle re-rates the same meshes once per bin)."""
    from ...assembly.mesh_stiffness_laws import iso6336_mesh_stiffness

    pair = mesh
    if not mesh.internal and mesh.gear1.profile_shift < mesh.gear2.profile_shift:
        pair = geo.MeshGeometry(
            mesh.gear2, mesh.gear1, mesh.centre_distance, mesh.working_pressure_angle_deg,
            (mesh.thickness_allowances[1], mesh.thickness_allowances[0]),
        )
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            stiffness = iso6336_mesh_stiffness(pair, line_load=1e9)
        return stiffness.single_stiffness, stiffness.mesh_stiffness_alpha, "c' by method B"
    except CaseError:
        eps = geo.transverse_contact_ratio(mesh)
        single = FALLBACK_SINGLE_STIFFNESS
        return single, single * (0.75 * eps + 0.25), "c' = 14 N/(mm um), q' out of range"


_tooth_form = functools.lru_cache(maxsize=256)(tooth_form)
"""Y_F, Y_S per (gear, eps_alpha), cached like :func:`_stiffness`."""


def _hardened(material: Material) -> bool:
    return material.kind != "through_hardened"


def rate_pair(load: PairLoad) -> PairRating:
    """ISO 6336 method B rating of one mesh (see the module docstring)."""
    mesh = load.geometry
    g1, g2 = mesh.gear1, mesh.gear2
    mat1, mat2 = load.materials
    m_n = g1.normal_module * 1e3
    b = min(g1.face_width, g2.face_width) * 1e3
    beta = math.radians(abs(g1.helix_angle_deg))
    beta_b = geo.base_helix_angle(g1)
    alpha_t = geo.transverse_pressure_angle(g1)
    alpha_wt = geo.working_pressure_angle(mesh)
    eps_a = geo.transverse_contact_ratio(mesh)
    eps_b = geo.overlap_ratio(mesh)
    eps_g = eps_a + eps_b
    d1 = 2e3 * geo.pitch_radius(g1)
    d2 = 2e3 * geo.pitch_radius(g2)
    z1, z2 = g1.teeth, g2.teeth
    u = (-z2 if mesh.internal else z2) / z1  # ISO: u < 0 for an internal pair
    out: dict[str, FactorValue] = {}

    # --- part 1: load -------------------------------------------------------------
    f_t = 2e3 * abs(load.torque1) / d1
    velocity = math.pi * d1 * abs(load.speeds[0]) / 60e3
    out["F_t"] = _computed(f_t, "F_t")
    out["v"] = _computed(velocity, "pitch line velocity (relative to the carrier) [m/s]")
    k_a = load.application_factor
    k_g = load.load_sharing
    out["K_A"], out["K_gamma"] = k_a, k_g
    single, c_ga, stiffness_note = _stiffness(mesh)
    out["c_prime"] = _computed(single, "ISO 6336-1:2019 cl. 9 (single stiffness c')",
                               stiffness_note)
    out["c_gamma_alpha"] = _computed(c_ga, "ISO 6336-1:2019 cl. 9 (mesh stiffness)")
    f_pt, f_fa, f_hb = iso.pitch_deviation(load.accuracy_grade, m_n, max(d1, d2))
    f_pb = f_pt * math.cos(alpha_t)
    s_hlim = (mat1.sigma_hlim * 1e-6, mat2.sigma_hlim * 1e-6)

    def mean_running_in(deviation: float) -> float:
        return 0.5 * sum(
            iso.running_in(deviation, s, _hardened(m), velocity)
            for s, m in zip(s_hlim, load.materials)
        )

    y_a = mean_running_in(f_pb)
    y_f = mean_running_in(f_fa)
    line_load = k_a.value * k_g.value * f_t / b
    if "K_v" in load.given:
        out["K_v"] = load.given["K_v"]
    else:
        m_red = load.reduced_mass
        if m_red is None:
            m_red = free_pair_reduced_mass(mesh, (0.0, 0.0))
        ratio = iso.resonance_ratio(abs(load.speeds[0]), z1, c_ga, m_red)
        c_ay = 0.5 * sum((s / 97.0 - 18.45) ** 2 / 18.0 + 1.5 for s in s_hlim)
        k_v = iso.dynamic_factor_method_b(
            ratio, line_load, single, max(f_pb - y_a, 0.0), max(f_fa - y_f, 0.0), c_ay, eps_g
        )
        out["N_resonance"] = _computed(ratio, "ISO 6336-1:2019 cl. 6.3 (resonance ratio N)")
        out["K_v"] = _computed(k_v, "K_v", f"N = {ratio:.3g}, grade {load.accuracy_grade}")
    k_v = out["K_v"].value
    f_m = f_t * k_a.value * k_g.value * k_v
    if "K_Hbeta" in load.given:
        out["K_Hbeta"] = load.given["K_Hbeta"]
    else:
        c_gb = 0.85 * c_ga
        # f_ma = f_Hbeta of the grade; f_sh from the model's deflection (at this line
        # load, in the adverse sense against f_ma), else 0 (no shaft data)
        f_sh = 0.0 if load.shaft_mismatch is None else abs(load.shaft_mismatch) * f_m / b
        f_bx = max(f_sh + f_hb, 0.005 * f_m / b)
        hard = all(_hardened(m) for m in load.materials)
        y_b = min(0.15 * f_bx, 6.0) if hard else min(320.0 / min(s_hlim) * f_bx,
                                                      25600.0 / min(s_hlim))
        f_by = f_bx - y_b
        ratio_h = c_gb * f_by * b / (2.0 * f_m)
        k_hb = 1.0 + ratio_h if ratio_h <= 1.0 else math.sqrt(4.0 * ratio_h)
        if load.shaft_mismatch is None:
            out["K_Hbeta"] = FactorValue(
                k_hb, "ISO 6336-1:2019 cl. 7.6 (method C: f_ma = f_Hbeta of the grade, "
                "f_sh = 0)", "computed")
        else:
            out["f_sh"] = FactorValue(f_sh, "ISO 6336-1:2019 cl. 7, Annex E (mismatch from "
                                      "the model's static deflection) [um]", "model")
            out["K_Hbeta"] = FactorValue(
                k_hb, f"ISO 6336-1:2019 cl. 7.6 (F_betax = f_sh + f_ma, f_sh = {f_sh:.3g} um "
                "from the model's static deflection, f_ma = f_Hbeta of the grade)", "model")
    k_hb = out["K_Hbeta"].value
    depth = 1e3 * min(
        abs(geo.tip_radius(g) - geo.root_radius(g)) for g in (g1, g2)
    )
    out["K_Fbeta"] = _computed(iso.face_load_factor_root(k_hb, b, depth), "K_Fbeta")
    z_eps = iso.contact_ratio_factor(eps_a, eps_b)
    if "K_Halpha" in load.given:
        out["K_Halpha"] = load.given["K_Halpha"]
        out["K_Falpha"] = FactorValue(out["K_Halpha"].value, out["K_Halpha"].clause,
                                      out["K_Halpha"].source)
    else:
        k_ha, k_fa = iso.transverse_load_factors(
            eps_g, eps_a, c_ga, max(f_pb - y_a, 0.0), f_m * k_hb / b, z_eps
        )
        out["K_Halpha"] = _computed(k_ha, "K_Halpha")
        out["K_Falpha"] = _computed(k_fa, "K_Falpha")

    # --- part 2: contact ----------------------------------------------------------
    z_h = iso.zone_factor(beta_b, alpha_t, alpha_wt)
    z_e = iso.elasticity_factor(mat1.young_modulus * 1e-6, mat1.poisson_ratio,
                                mat2.young_modulus * 1e-6, mat2.poisson_ratio)
    z_beta = iso.helix_angle_factor_contact(beta)
    sigma_h0 = z_h * z_e * z_eps * z_beta * math.sqrt(f_t / (d1 * b) * (u + 1.0) / u)
    for name, value in (("Z_H", z_h), ("Z_E", z_e), ("Z_eps", z_eps), ("Z_beta", z_beta)):
        out[name] = _computed(value, name)
    out["sigma_H0"] = _computed(sigma_h0, "ISO 6336-2:2019 cl. 5 (nominal contact stress)")
    soft = min(s_hlim)
    z_l, z_v = iso.lubrication_factors(soft, load.oil_viscosity_40, velocity)
    r_b = (1e3 * geo.base_radius(g1), 1e3 * geo.base_radius(g2))
    rho1 = r_b[0] * math.tan(alpha_wt)
    rho2 = r_b[1] * math.tan(alpha_wt) * (-1.0 if mesh.internal else 1.0)
    rho_red = rho1 * rho2 / (rho1 + rho2)
    rz = 0.5e6 * (mat1.flank_roughness_rz + mat2.flank_roughness_rz)
    z_r = iso.roughness_factor(rz, rho_red, soft)
    out["Z_L"] = _computed(z_l, "Z_L")
    out["Z_v"] = _computed(z_v, "Z_v")
    out["Z_R"] = _computed(z_r, "Z_R")
    tip_ratios = tuple(geo.tip_radius(g) / geo.base_radius(g) for g in (g1, g2))
    z_bd = iso.single_pair_factors(alpha_wt, tip_ratios, (z1, z2), eps_a, eps_b, mesh.internal)
    loads_h = k_a.value * k_g.value * k_v * k_hb * out["K_Halpha"].value
    loads_f = k_a.value * k_g.value * k_v * out["K_Fbeta"].value * out["K_Falpha"].value
    hardened = (_hardened(mat1), _hardened(mat2))
    gears = []
    for k, (gear, material) in enumerate(zip((g1, g2), load.materials)):
        entry: dict[str, FactorValue] = {}
        cycles = (60.0 * abs(load.speeds[k]) * load.contacts[k] * load.service_life_h)
        entry["N_L"] = _computed(cycles, "load cycles over the service life")
        entry["Z_BD"] = _computed(z_bd[k], "Z_B" if k == 0 else "Z_D")
        entry["Z_NT"] = _computed(iso.life_factor(material.kind, cycles, root=False), "Z_NT")
        z_w = iso.work_hardening_factor(
            material.hardness_hb if not hardened[k] else None, hardened[1 - k]
        )
        entry["Z_W"] = _computed(z_w, "Z_W")
        entry["Z_X"] = _computed(1.0, "Z_X")
        sigma_h = z_bd[k] * sigma_h0 * math.sqrt(loads_h)
        strength_h = material.sigma_hlim * 1e-6 * z_l * z_v * z_r * z_w
        entry["sigma_H"] = _computed(sigma_h, "ISO 6336-2:2019 cl. 5 (contact stress)")
        entry["sigma_HG_ref"] = _computed(strength_h, "contact strength at Z_NT = 1 [MPa]")
        entry["S_H"] = _computed(strength_h * entry["Z_NT"].value / sigma_h,
                                 "ISO 6336-2:2019 cl. 5 (S_H = sigma_HG / sigma_H)")
        # --- part 3: root --------------------------------------------------------
        form = _tooth_form(gear, eps_a)
        entry["Y_F"] = _computed(form.Y_F, "Y_F")
        entry["Y_S"] = _computed(form.Y_S, "Y_S")
        entry["Y_beta"] = _computed(iso.helix_angle_factor_root(eps_b, beta), "Y_beta")
        rim = load.rims[k]
        entry["Y_B"] = _computed(
            iso.rim_thickness_factor(None if rim is None else rim * 1e3, m_n, depth,
                                     gear.internal), "Y_B")
        entry["Y_DT"] = _computed(iso.deep_tooth_factor(eps_a / math.cos(beta_b) ** 2,
                                                        load.accuracy_grade), "Y_DT")
        entry["Y_NT"] = _computed(iso.life_factor(material.kind, cycles, root=True), "Y_NT")
        entry["Y_delta_relT"] = _computed(
            iso.notch_sensitivity_factor(form.q_s, material.slip_layer_mm), "Y_delta_relT")
        entry["Y_R_relT"] = _computed(
            iso.root_surface_factor(material.kind, material.root_roughness_rz * 1e6), "Y_R_relT")
        entry["Y_X"] = _computed(iso.size_factor_root(material.kind, m_n), "Y_X")
        entry["Y_M"] = _computed(0.7 if load.idler[k] else 1.0, "Y_M")
        sigma_f0 = (f_t / (b * m_n) * form.Y_F * form.Y_S * entry["Y_beta"].value
                    * entry["Y_B"].value * entry["Y_DT"].value)
        sigma_f = sigma_f0 * loads_f
        strength_f = (material.sigma_flim * 1e-6 * 2.0 * entry["Y_delta_relT"].value
                      * entry["Y_R_relT"].value * entry["Y_X"].value * entry["Y_M"].value)
        entry["sigma_F0"] = _computed(sigma_f0, "ISO 6336-3:2019 cl. 5 (nominal root stress)")
        entry["sigma_F"] = _computed(sigma_f, "ISO 6336-3:2019 cl. 5 (root stress)")
        entry["sigma_FG_ref"] = _computed(strength_f, "root strength at Y_NT = 1 [MPa]")
        entry["S_F"] = _computed(strength_f * entry["Y_NT"].value / sigma_f,
                                 "ISO 6336-3:2019 cl. 5 (S_F = sigma_FG / sigma_F)")
        gears.append(entry)
    return PairRating(out, (gears[0], gears[1]))
