"""Tooth form factor Y_F and stress correction factor Y_S by ISO 6336-3:2019 method B.

External gears: the critical section touches the root fillet where its tangent is
inclined 30 degrees to the tooth centreline, the load acts at the outer point of single
tooth contact of the virtual spur gear (z_n, d_en).  Internal gears: the tooth is taken
as the basic rack tooth of the ring's own dedendum and root fillet (z -> infinity), the
critical section at the 60 degree tangent, the load at the ring's own outer point of
single contact.  Lengths in mm, angles in radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...model import gear_geometry as geo

__all__ = ["ToothForm", "tooth_form"]


@dataclass(frozen=True)
class ToothForm:
    """Root geometry and the two factors of one gear in one mesh."""

    Y_F: float
    Y_S: float
    h_fe: float  # bending lever [mm]
    s_fn: float  # tooth root chord [mm]
    rho_f: float  # root fillet radius at the critical section [mm]
    alpha_fen: float  # load direction angle [rad]
    q_s: float  # notch parameter s_Fn / (2 rho_F) [-]


def _stress_correction(s_fn: float, h_fe: float, rho_f: float) -> tuple[float, float]:
    """Y_S = (1.2 + 0.13 L) q_s^(1 / (1.21 + 2.3 / L)), L = s_Fn/h_Fe, q_s = s_Fn/(2 rho_F)."""
    big_l = s_fn / h_fe
    q_s = s_fn / (2.0 * rho_f)
    return (1.2 + 0.13 * big_l) * q_s ** (1.0 / (1.21 + 2.3 / big_l)), q_s


def _virtual(gear: geo.GearGeometry) -> tuple[float, float, float]:
    """(z_n, beta_b, beta) of the virtual spur gear."""
    beta = math.radians(abs(gear.helix_angle_deg))
    beta_b = geo.base_helix_angle(gear)
    return gear.teeth / (math.cos(beta_b) ** 2 * math.cos(beta)), beta_b, beta


def tooth_form(gear: geo.GearGeometry, contact_ratio: float) -> ToothForm:
    """Y_F and Y_S of ``gear`` meshing with transverse contact ratio ``contact_ratio``.

    Parameters
    ----------
    gear : GearGeometry
        The gear (cut by its basic rack: h_fP, rho_fP, alpha_n; no protuberance).
    contact_ratio : float
        eps_alpha of the mesh; eps_alpha_n = eps_alpha / cos^2(beta_b) places the load.
    """
    m = gear.normal_module * 1e3
    alpha_n = math.radians(gear.normal_pressure_angle_deg)
    h_fp = gear.dedendum_factor * m
    rho_fp = gear.tip_root_radius_factor * m
    x = gear.profile_shift
    z_n, beta_b, beta = _virtual(gear)
    eps_an = contact_ratio / math.cos(beta_b) ** 2
    d = 2e3 * geo.pitch_radius(gear)
    d_a = 2e3 * geo.tip_radius(gear)
    d_n = d / math.cos(beta_b) ** 2
    d_bn = d_n * math.cos(alpha_n)
    p_bn = math.pi * m * math.cos(alpha_n)
    if gear.internal:
        return _internal(gear, m, alpha_n, h_fp, rho_fp, x, d, d_a, d_n, d_bn, p_bn, eps_an)
    # external: ISO 6336-3 method B
    e = math.pi * m / 4.0 - h_fp * math.tan(alpha_n) - (1.0 - math.sin(alpha_n)) * rho_fp / (
        math.cos(alpha_n)
    )
    g = rho_fp / m - h_fp / m + x
    h = 2.0 / z_n * (math.pi / 2.0 - e / m) - math.pi / 3.0
    theta = math.pi / 6.0
    for _ in range(100):
        updated = 2.0 * g / z_n * math.tan(theta) - h
        if abs(updated - theta) < 1e-13:
            theta = updated
            break
        theta = updated
    s_fn = m * (z_n * math.sin(math.pi / 3.0 - theta) + math.sqrt(3.0) * (g / math.cos(theta)
                                                                         - rho_fp / m))
    rho_f = m * (rho_fp / m + 2.0 * g * g / (math.cos(theta) * (z_n * math.cos(theta) ** 2
                                                                - 2.0 * g)))
    d_an = d_n + d_a - d
    roll = math.sqrt((d_an / 2.0) ** 2 - (d_bn / 2.0) ** 2) - (eps_an - 1.0) * p_bn
    d_en = 2.0 * math.sqrt(roll**2 + (d_bn / 2.0) ** 2)
    alpha_en = math.acos(d_bn / d_en)
    gamma_e = (0.5 * math.pi + 2.0 * x * math.tan(alpha_n)) / z_n + geo.involute(
        alpha_n
    ) - geo.involute(alpha_en)
    alpha_fen = alpha_en - gamma_e
    h_fe = 0.5 * m * (
        (math.cos(gamma_e) - math.sin(gamma_e) * math.tan(alpha_fen)) * d_en / m
        - z_n * math.cos(math.pi / 3.0 - theta)
        - g / math.cos(theta)
        + rho_fp / m
    )
    y_f = 6.0 * (h_fe / m) * math.cos(alpha_fen) / ((s_fn / m) ** 2 * math.cos(alpha_n))
    y_s, q_s = _stress_correction(s_fn, h_fe, rho_f)
    return ToothForm(y_f, y_s, h_fe, s_fn, rho_f, alpha_fen, q_s)


def _internal(gear, m, alpha_n, h_fp, rho_fp, x, d, d_a, d_n, d_bn, p_bn, eps_an) -> ToothForm:
    """The ring's tooth as a rack tooth of its own dedendum and fillet (60 deg tangent).

    Coordinates: y up the tooth from the root line, half width from the centreline.
    The fillet centre lies rho_fP above the root line and rho_fP off the flank; the
    critical section touches the fillet where its tangent is 60 deg to the centreline.
    """
    dedendum = h_fp - x * m  # reference line to root line (ISO 21771 sign for rings)
    half_ref = m * (math.pi / 4.0 + x * math.tan(alpha_n))
    centre_x = half_ref + (dedendum - rho_fp) * math.tan(alpha_n) + rho_fp / math.cos(alpha_n)
    section_x = centre_x - rho_fp * math.cos(math.radians(60.0))
    section_y = rho_fp * (1.0 - math.sin(math.radians(60.0)))
    s_fn = 2.0 * section_x
    # load at the ring's outer point of single contact (nearest its tip): one base pitch
    # from the far end of the path, i.e. (eps_an - 1) p_bn past its tip's roll length
    d_an = d_n - (d - d_a)  # the ring's tip lies inside its reference circle
    roll = math.sqrt((d_an / 2.0) ** 2 - (d_bn / 2.0) ** 2) + (eps_an - 1.0) * p_bn
    r_en = math.sqrt(roll**2 + (d_bn / 2.0) ** 2)
    r_fn = d_n / 2.0 + dedendum
    load_y = r_fn - r_en
    load_half = half_ref + (dedendum - load_y) * math.tan(alpha_n)
    h_fe = load_y - load_half * math.tan(alpha_n) - section_y
    alpha_fen = alpha_n
    y_f = 6.0 * (h_fe / m) * math.cos(alpha_fen) / ((s_fn / m) ** 2 * math.cos(alpha_n))
    y_s, q_s = _stress_correction(s_fn, h_fe, rho_fp)
    return ToothForm(y_f, y_s, h_fe, s_fn, rho_fp, alpha_fen, q_s)
