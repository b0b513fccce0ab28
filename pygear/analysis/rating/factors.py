"""The influence factors of ISO 6336-1/-2/-3:2019 as plain functions (ISO units).

Units follow the standard: forces N, lengths mm, stresses N/mm^2 (MPa), deviations and
stiffnesses um and N/(mm um), speeds 1/min, velocities m/s.  Each function names the
part and clause it implements; :mod:`.gear_rating` strings them together.
"""

from __future__ import annotations

import math

__all__ = [
    "CLAUSES",
    "dynamic_factor_method_b",
    "elasticity_factor",
    "contact_ratio_factor",
    "deep_tooth_factor",
    "face_load_factor_root",
    "helix_angle_factor_contact",
    "helix_angle_factor_root",
    "life_factor",
    "lubrication_factors",
    "notch_sensitivity_factor",
    "pitch_deviation",
    "planet_load_sharing_default",
    "resonance_ratio",
    "rim_thickness_factor",
    "roughness_factor",
    "root_surface_factor",
    "running_in",
    "single_pair_factors",
    "size_factor_root",
    "transverse_load_factors",
    "work_hardening_factor",
    "zone_factor",
]

CLAUSES = {
    "F_t": "ISO 6336-1:2019 cl. 5 (nominal tangential load at the reference circle)",
    "K_A": "ISO 6336-1:2019 Annex B (application factor)",
    "K_gamma": "ISO 6336-1:2019 cl. 5 (mesh load factor, planets' load sharing)",
    "K_v": "ISO 6336-1:2019 cl. 6.3 (dynamic factor, method B)",
    "K_Hbeta": "ISO 6336-1:2019 cl. 7 (face load factor, contact)",
    "K_Fbeta": "ISO 6336-1:2019 cl. 7 (K_Fbeta = K_Hbeta^N_F)",
    "K_Halpha": "ISO 6336-1:2019 cl. 8.3 (transverse load factor, method B)",
    "K_Falpha": "ISO 6336-1:2019 cl. 8.3 (transverse load factor, method B)",
    "Z_H": "ISO 6336-2:2019 cl. 6.1 (zone factor)",
    "Z_B": "ISO 6336-2:2019 cl. 6.2 (single pair tooth contact factor, pinion)",
    "Z_D": "ISO 6336-2:2019 cl. 6.2 (single pair tooth contact factor, wheel)",
    "Z_E": "ISO 6336-2:2019 cl. 7 (elasticity factor)",
    "Z_eps": "ISO 6336-2:2019 cl. 8 (contact ratio factor)",
    "Z_beta": "ISO 6336-2:2019 cl. 9 (helix angle factor)",
    "Z_NT": "ISO 6336-2:2019 cl. 10, Table 2 (life factor, contact)",
    "Z_L": "ISO 6336-2:2019 cl. 11 (lubricant factor, method B)",
    "Z_v": "ISO 6336-2:2019 cl. 11 (velocity factor, method B)",
    "Z_R": "ISO 6336-2:2019 cl. 11 (roughness factor, method B)",
    "Z_W": "ISO 6336-2:2019 cl. 12 (work hardening factor)",
    "Z_X": "ISO 6336-2:2019 cl. 13 (size factor, 1 without data)",
    "Y_F": "ISO 6336-3:2019 cl. 6.2 (tooth form factor, method B)",
    "Y_S": "ISO 6336-3:2019 cl. 7.2 (stress correction factor, method B)",
    "Y_beta": "ISO 6336-3:2019 cl. 8 (helix angle factor)",
    "Y_B": "ISO 6336-3:2019 cl. 9 (rim thickness factor)",
    "Y_DT": "ISO 6336-3:2019 cl. 10 (deep tooth factor)",
    "Y_NT": "ISO 6336-3:2019 cl. 11, Table 4 (life factor, root)",
    "Y_delta_relT": "ISO 6336-3:2019 cl. 12 (relative notch sensitivity, method B)",
    "Y_R_relT": "ISO 6336-3:2019 cl. 13 (relative surface factor, method B)",
    "Y_X": "ISO 6336-3:2019 cl. 14 (size factor)",
    "Y_ST": "ISO 6336-3:2019 cl. 5 (stress correction of the reference test gear, 2)",
    "Y_M": "ISO 6336-3:2019 Annex (mean stress factor, 0.7 for alternating bending)",
    "sigma_hlim": "ISO 6336-5:2016 (endurance limit, contact)",
    "sigma_flim": "ISO 6336-5:2016 (nominal stress number, bending)",
}
"""The clause that gives each factor (ISO 6336:2019 parts 1-3, ISO 6336-5:2016)."""


# ----------------------------------------------------------------------------------
# Part 1: loads
# ----------------------------------------------------------------------------------

_PLANET_LOAD_SHARING = {3: 1.10, 4: 1.25, 5: 1.35, 6: 1.44, 7: 1.47}


def planet_load_sharing_default(planets: int) -> float:
    """K_gamma for ``planets`` planets without load-sharing devices: 1.10, 1.25, 1.35,
    1.44, 1.47 for 3..7 planets (the wind-turbine gearbox table of IEC 61400-4:2012,
    also in the planetary rating of ISO 6336 practice); 1 for one or two planets."""
    if planets <= 2:
        return 1.0
    return _PLANET_LOAD_SHARING.get(planets, 1.47)


def pitch_deviation(grade: int, module: float, diameter: float) -> tuple[float, float, float]:
    """(f_pt, f_falpha, f_Hbeta) [um] of ISO 1328-1:1995 for accuracy ``grade``.

    Grade 5 values f_pt = 0.3 (m + 0.4 sqrt d) + 4, f_falpha = 2.5 sqrt m + 0.17 sqrt d
    + 0.5 and f_Hbeta = 0.07 sqrt d + 0.45 sqrt b + 3 (b = 0.4 d here, the face width
    class), each step of one grade a factor sqrt 2.
    """
    step = 2.0 ** ((grade - 5) / 2.0)
    f_pt = (0.3 * (module + 0.4 * math.sqrt(diameter)) + 4.0) * step
    f_fa = (2.5 * math.sqrt(module) + 0.17 * math.sqrt(diameter) + 0.5) * step
    f_hb = (0.07 * math.sqrt(diameter) + 0.45 * math.sqrt(0.4 * diameter) + 3.0) * step
    return f_pt, f_fa, f_hb


def running_in(deviation: float, sigma_hlim: float, hardened: bool, velocity: float) -> float:
    """Running-in allowance y_alpha (= y_p, y_f) [um] of a deviation [um]
    (ISO 6336-1:2019 cl. 8.3): 0.075 f, at most 3 um, for surface-hardened steel;
    160/sigma_hlim f, at most 12800/sigma_hlim (v <= 5 m/s) or 6400/sigma_hlim
    (5 < v <= 10 m/s) um, for through-hardened steel."""
    if hardened:
        return min(0.075 * deviation, 3.0)
    value = 160.0 / sigma_hlim * deviation
    if velocity <= 5.0:
        return min(value, 12800.0 / sigma_hlim)
    if velocity <= 10.0:
        return min(value, 6400.0 / sigma_hlim)
    return value


def resonance_ratio(speed: float, teeth: int, mesh_stiffness: float, reduced_mass: float) -> float:
    """N = n_1 / n_E1, n_E1 = 30000/(pi z_1) sqrt(c_gamma_alpha / m_red) (ISO 6336-1
    cl. 6.3; speed in 1/min, c in N/(mm um), m_red in kg/mm)."""
    n_e1 = 30000.0 / (math.pi * teeth) * math.sqrt(mesh_stiffness / reduced_mass)
    return speed / n_e1


def dynamic_factor_method_b(
    ratio: float,
    line_load: float,
    single_stiffness: float,
    f_pb_eff: float,
    f_fa_eff: float,
    tip_relief: float,
    total_contact_ratio: float,
) -> float:
    """K_v by ISO 6336-1:2019 cl. 6.3 (method B) in every speed range.

    Parameters
    ----------
    ratio : float
        Resonance ratio N.
    line_load : float
        K_A K_gamma F_t / b [N/mm].
    single_stiffness : float
        c' [N/(mm um)].
    f_pb_eff, f_fa_eff : float
        Effective base pitch and profile form deviations after running-in [um].
    tip_relief : float
        C_a [um] (the running-in amount C_ay when the flanks are not relieved).
    total_contact_ratio : float
        eps_gamma.
    """
    eps = total_contact_ratio
    c_v1, c_v5 = 0.32, 0.47
    if eps <= 2.0:
        c_v2, c_v3, c_v4, c_v6 = 0.34, 0.23, 0.90, 0.47
    else:
        c_v2 = 0.57 / (eps - 0.3)
        c_v3 = 0.096 / (eps - 1.56)
        c_v4 = (0.57 - 0.05 * eps) / (eps - 1.44)
        c_v6 = 0.12 / (eps - 1.74)
    if eps <= 1.5:
        c_v7 = 0.75
    elif eps <= 2.5:
        c_v7 = 0.125 * math.sin(math.pi * (eps - 2.0)) + 0.875
    else:
        c_v7 = 1.0
    b_p = single_stiffness * f_pb_eff / line_load
    b_f = single_stiffness * f_fa_eff / line_load
    b_k = abs(1.0 - single_stiffness * tip_relief / line_load)
    n_s = 0.85 if line_load >= 100.0 else 0.5 + 0.35 * math.sqrt(line_load / 100.0)
    main = c_v1 * b_p + c_v2 * b_f + c_v4 * b_k + 1.0
    super_ = c_v5 * b_p + c_v6 * b_f + c_v7
    if ratio <= n_s:
        return ratio * (c_v1 * b_p + c_v2 * b_f + c_v3 * b_k) + 1.0
    if ratio <= 1.15:
        return main
    if ratio < 1.5:
        return super_ + (main - super_) * (1.5 - ratio) / 0.35
    return super_


def face_load_factor_root(k_hbeta: float, face_width: float, tooth_depth: float) -> float:
    """K_Fbeta = K_Hbeta^N_F, N_F = (b/h)^2 / (1 + b/h + (b/h)^2), b/h >= 3
    (ISO 6336-1:2019 cl. 7)."""
    ratio = max(face_width / tooth_depth, 3.0)
    return k_hbeta ** (ratio**2 / (1.0 + ratio + ratio**2))


def transverse_load_factors(
    eps_gamma: float,
    eps_alpha: float,
    mesh_stiffness: float,
    f_pb_eff: float,
    line_load_h: float,
    z_eps: float,
) -> tuple[float, float]:
    """(K_Halpha, K_Falpha) by ISO 6336-1:2019 cl. 8.3 (method B).

    ``line_load_h`` = F_tH / b = K_A K_gamma K_v K_Hbeta F_t / b [N/mm]; ``f_pb_eff``
    = f_pb - y_alpha [um].
    """
    term = mesh_stiffness * f_pb_eff / line_load_h
    if eps_gamma <= 2.0:
        value = eps_gamma / 2.0 * (0.9 + 0.4 * term)
    else:
        value = 0.9 + 0.4 * math.sqrt(2.0 * (eps_gamma - 1.0) / eps_gamma) * term
    k_h = min(max(value, 1.0), eps_gamma / (eps_alpha * z_eps**2))
    k_f = min(max(value, 1.0), eps_gamma / (0.25 * eps_alpha + 0.75))
    return k_h, k_f


# ----------------------------------------------------------------------------------
# Part 2: contact
# ----------------------------------------------------------------------------------


def zone_factor(beta_b: float, alpha_t: float, alpha_wt: float) -> float:
    """Z_H = sqrt(2 cos beta_b cos alpha_wt / (cos^2 alpha_t sin alpha_wt))."""
    return math.sqrt(
        2.0 * math.cos(beta_b) * math.cos(alpha_wt) / (math.cos(alpha_t) ** 2 * math.sin(alpha_wt))
    )


def elasticity_factor(e1: float, nu1: float, e2: float, nu2: float) -> float:
    """Z_E = sqrt(1 / (pi ((1 - nu1^2)/E1 + (1 - nu2^2)/E2))) [sqrt(N/mm^2)], E in N/mm^2."""
    return math.sqrt(1.0 / (math.pi * ((1.0 - nu1**2) / e1 + (1.0 - nu2**2) / e2)))


def contact_ratio_factor(eps_alpha: float, eps_beta: float) -> float:
    """Z_eps: sqrt((4 - eps_a)/3) spur; sqrt((4 - eps_a)(1 - eps_b)/3 + eps_b/eps_a) for
    eps_b < 1; sqrt(1/eps_a) for eps_b >= 1."""
    if eps_beta >= 1.0:
        return math.sqrt(1.0 / eps_alpha)
    return math.sqrt((4.0 - eps_alpha) * (1.0 - eps_beta) / 3.0 + eps_beta / eps_alpha)


def helix_angle_factor_contact(beta: float) -> float:
    """Z_beta = 1 / sqrt(cos beta)."""
    return 1.0 / math.sqrt(math.cos(beta))


def single_pair_factors(
    alpha_wt: float,
    tip_ratios: tuple[float, float],
    teeth: tuple[int, int],
    eps_alpha: float,
    eps_beta: float,
    internal: bool,
) -> tuple[float, float]:
    """(Z_B, Z_D) of pinion and wheel (ISO 6336-2:2019 cl. 6.2).

    M_1 = tan alpha_wt / sqrt((sqrt(r_a1^2/r_b1^2 - 1) - 2 pi/z_1)
    (sqrt(r_a2^2/r_b2^2 - 1) - (eps_a - 1) 2 pi/z_2)), M_2 likewise with 1 and 2
    swapped; spur: Z = M if M > 1 else 1; eps_b >= 1: 1; 0 < eps_b < 1: M - eps_b (M - 1).
    Internal meshes: Z_B = Z_D = 1 (the standard's rule for the wheel, and the
    pinion's inner point of single contact lies on its flank's stronger side).
    """
    if internal or eps_beta >= 1.0:
        return 1.0, 1.0
    roll = [math.sqrt(k * k - 1.0) for k in tip_ratios]
    z1, z2 = teeth
    m1 = math.tan(alpha_wt) / math.sqrt(
        (roll[0] - 2.0 * math.pi / z1) * (roll[1] - (eps_alpha - 1.0) * 2.0 * math.pi / z2)
    )
    m2 = math.tan(alpha_wt) / math.sqrt(
        (roll[1] - 2.0 * math.pi / z2) * (roll[0] - (eps_alpha - 1.0) * 2.0 * math.pi / z1)
    )
    values = []
    for m in (m1, m2):
        value = m - eps_beta * (m - 1.0)
        values.append(max(value, 1.0))
    return values[0], values[1]


def lubrication_factors(
    sigma_hlim: float, viscosity_40: float, velocity: float
) -> tuple[float, float]:
    """(Z_L, Z_v) by ISO 6336-2:2019 cl. 11 (method B), sigma_hlim of the softer gear.

    C_ZL = 0.83 (sigma_hlim < 850), 0.91 (> 1200), linear between; Z_L = C_ZL +
    4 (1 - C_ZL) / (1.2 + 134/nu_40)^2; C_Zv = C_ZL + 0.02; Z_v = C_Zv + 2 (1 - C_Zv) /
    sqrt(0.8 + 32/v).
    """
    if sigma_hlim < 850.0:
        c_zl = 0.83
    elif sigma_hlim > 1200.0:
        c_zl = 0.91
    else:
        c_zl = 0.83 + 0.08 * (sigma_hlim - 850.0) / 350.0
    z_l = c_zl + 4.0 * (1.0 - c_zl) / (1.2 + 134.0 / viscosity_40) ** 2
    c_zv = c_zl + 0.02
    z_v = c_zv + 2.0 * (1.0 - c_zv) / math.sqrt(0.8 + 32.0 / velocity)
    return z_l, z_v


def roughness_factor(rz_mean: float, rho_red: float, sigma_hlim: float) -> float:
    """Z_R = (3 / R_z10)^C_ZR, R_z10 = R_z (10/rho_red)^(1/3) (ISO 6336-2 cl. 11); C_ZR
    = 0.15 (sigma_hlim < 850), 0.08 (> 1200), 0.32 - 0.0002 sigma_hlim between; R_z in
    um, rho_red in mm."""
    rz10 = rz_mean * (10.0 / rho_red) ** (1.0 / 3.0)
    if sigma_hlim < 850.0:
        c_zr = 0.15
    elif sigma_hlim > 1200.0:
        c_zr = 0.08
    else:
        c_zr = 0.32 - 0.0002 * sigma_hlim
    return (3.0 / rz10) ** c_zr


def work_hardening_factor(soft_hb: float | None, partner_hardened: bool) -> float:
    """Z_W = 1.2 - (HB - 130)/1700 (HB clamped to 130..470) for a through-hardened gear
    meshing with a surface-hardened one; 1 otherwise (ISO 6336-2 cl. 12, the
    hardness-only form)."""
    if soft_hb is None or not partner_hardened:
        return 1.0
    return 1.2 - (min(max(soft_hb, 130.0), 470.0) - 130.0) / 1700.0


_CONTACT_LIFE = {
    # kind: knees (N, Z_NT) of ISO 6336-2 Table 2, log-log straight lines between
    "case_carburized": ((1e5, 1.6), (5e7, 1.0), (1e10, 0.85)),
    "through_hardened": ((1e5, 1.6), (5e7, 1.0), (1e10, 0.85)),
    "nitrided": ((1e5, 1.3), (2e6, 1.0), (1e10, 0.85)),
}
_ROOT_LIFE = {
    # kind: knees (N, Y_NT) of ISO 6336-3 Table 4
    "case_carburized": ((1e3, 2.5), (3e6, 1.0), (1e10, 0.85)),
    "through_hardened": ((1e4, 2.5), (3e6, 1.0), (1e10, 0.85)),
    "nitrided": ((1e3, 1.6), (3e6, 1.0), (1e10, 0.85)),
}


def life_factor(kind: str, cycles: float, root: bool) -> float:
    """Z_NT (contact) or Y_NT (``root``) at ``cycles`` load cycles: the standard's knee
    points joined by straight lines in log-log; constant before the first knee, and
    beyond 1e10 the last line continued (ISO 6336-6's S-N curve for damage sums)."""
    knees = (_ROOT_LIFE if root else _CONTACT_LIFE)[kind]
    if cycles <= knees[0][0]:
        return knees[0][1]
    for (n0, y0), (n1, y1) in zip(knees[:-1], knees[1:]):
        if cycles <= n1 or (n1, y1) == knees[-1]:
            slope = math.log(y1 / y0) / math.log(n1 / n0)
            return y0 * (cycles / n0) ** slope
    raise AssertionError("unreachable")


def life_knees(kind: str, root: bool) -> tuple[tuple[float, float], ...]:
    """The (N, factor) knee points of :func:`life_factor`."""
    return (_ROOT_LIFE if root else _CONTACT_LIFE)[kind]


# ----------------------------------------------------------------------------------
# Part 3: root
# ----------------------------------------------------------------------------------


def helix_angle_factor_root(eps_beta: float, beta: float) -> float:
    """Y_beta = 1 - eps_beta beta / 120 deg, eps_beta taken at most 1 and beta at most
    30 deg."""
    return 1.0 - min(eps_beta, 1.0) * min(math.degrees(beta), 30.0) / 120.0


def rim_thickness_factor(rim: float | None, module: float, tooth_depth: float,
                         internal: bool) -> float:
    """Y_B (ISO 6336-3 cl. 9): 1 for a solid gear (``rim`` None) or a thick rim;
    external: s_R/h_t < 1.2 gives 1.6 ln(2.242 h_t/s_R); internal: s_R/m_n < 3.5 gives
    1.15 ln(8.324 m_n/s_R)."""
    if rim is None:
        return 1.0
    if internal:
        return 1.0 if rim / module >= 3.5 else 1.15 * math.log(8.324 * module / rim)
    return 1.0 if rim / tooth_depth >= 1.2 else 1.6 * math.log(2.242 * tooth_depth / rim)


def deep_tooth_factor(eps_alpha_n: float, grade: int) -> float:
    """Y_DT (ISO 6336-3 cl. 10): 1 unless eps_alpha_n > 2.05 with grade Q <= 4, then
    2.366 - 0.666 eps_alpha_n up to eps_alpha_n = 2.5 and 0.9 beyond."""
    if eps_alpha_n <= 2.05 or grade > 4:
        return 1.0
    return 2.366 - 0.666 * eps_alpha_n if eps_alpha_n <= 2.5 else 0.9


def notch_sensitivity_factor(q_s: float, slip_layer: float) -> float:
    """Y_delta rel T = (1 + sqrt(rho' chi*)) / (1 + sqrt(rho' chi*_T)), chi* = (1 + 2
    q_s)/5, chi*_T = 1.2 [1/mm] (ISO 6336-3 cl. 12, method B)."""
    chi = (1.0 + 2.0 * q_s) / 5.0
    return (1.0 + math.sqrt(slip_layer * chi)) / (1.0 + math.sqrt(slip_layer * 1.2))


def root_surface_factor(kind: str, rz: float) -> float:
    """Y_R rel T (ISO 6336-3 cl. 13, method B; R_z in um, 1..40): 1.674 - 0.529 (R_z +
    1)^0.1 for through- and case-hardened steel, 4.3 - 3.259 (R_z + 1)^0.0058 for
    nitrided; R_z < 1: 1.12 and 1.025."""
    if kind == "nitrided":
        return 1.025 if rz < 1.0 else 4.3 - 3.259 * (rz + 1.0) ** 0.0058
    return 1.12 if rz < 1.0 else 1.674 - 0.529 * (rz + 1.0) ** 0.1


def size_factor_root(kind: str, module: float) -> float:
    """Y_X (ISO 6336-3 cl. 14): through-hardened 1.03 - 0.006 m_n in 5..30 mm (0.85
    above); surface-hardened 1.05 - 0.01 m_n in 5..25 mm (0.8 above); 1 up to 5 mm."""
    if module <= 5.0:
        return 1.0
    if kind == "through_hardened":
        return max(1.03 - 0.006 * module, 0.85)
    return max(1.05 - 0.01 * module, 0.8)
