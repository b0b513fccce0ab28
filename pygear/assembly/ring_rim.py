"""The fillet-foundation compliance of a ring's rim, added to the potential-energy pair.

The Fortran module ``tooth_potential_energy`` takes an internal gear's rim as rigid.
A ring held in its housing at the rim's outer radius r_o deflects under a tooth load
as an external gear's body held at its bore does, so its tooth gets the same
fillet-foundation term of Sainsot, Velex & Duverger (2004),

    1/k_f = cos(beta)^2 / (E L) [L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan(beta)^2)],

mirrored onto the internal tooth: the load line crosses the tooth's centre line at
x_p + y_p tan(beta) (towards the ring's root, outwards), u_f = r_f - x_p - y_p tan(beta)
is its distance from the root circle, S_f = 2 r_f theta_f the root thickness, and the
rim annulus's r_o / r_f stands for the gear body's h_fi = r_f / r_int
(:func:`pygear.model.bodies.ring_rim_ratio`).  The kernel's compliances, its load angle
beta = alpha_c + psi_c and its half angles psi = psi_b + inv(alpha) of the internal tooth
are used unchanged; this module adds the rim term in series with each tooth pair.
"""

from __future__ import annotations

import math

import numpy as np

from ..model import gear_geometry as geo
from ..model.bodies import ring_rim_ratio

__all__ = ["SAINSOT_COEFFICIENTS", "rim_compliance", "sainsot_coefficients", "with_rim"]

SAINSOT_COEFFICIENTS = np.array(
    [
        [-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045],
        [60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086],
        [-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236],
        [-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904],
    ]
)
"""A .. F of L*, M*, P*, Q* (Sainsot et al. 2004; the kernel's table)."""


def sainsot_coefficients(ratio: float, theta_f: float) -> np.ndarray:
    """L*, M*, P*, Q* = A/theta_f^2 + B h^2 + C h/theta_f + D/theta_f + E h + F."""
    terms = np.array([1 / theta_f**2, ratio**2, ratio / theta_f, 1 / theta_f, ratio, 1.0])
    return SAINSOT_COEFFICIENTS @ terms


def _involute(angle: np.ndarray) -> np.ndarray:
    return np.tan(angle) - angle


def rim_compliance(
    gear: geo.GearGeometry,
    half_angle_base: float,
    rim_radius: float,
    young_modulus: float,
    width: float,
    contact_radius: np.ndarray,
) -> np.ndarray:
    """Fillet-foundation compliance [m/N] of a ring tooth loaded at ``contact_radius``.

    Parameters
    ----------
    gear : GearGeometry
        The internal gear.
    half_angle_base : float
        psi_b of the kernel's gear column (thickness allowance included) [rad].
    rim_radius : float
        Outer radius of the rim r_o [m], > r_f.
    young_modulus : float
        E [Pa].
    width : float
        Loaded face width L [m].
    contact_radius : ndarray
        Contact radii on the ring tooth [m], between its tip and root circles.
    """
    r_b, r_f = geo.base_radius(gear), geo.root_radius(gear)
    theta_f = half_angle_base + math.tan(math.acos(r_b / r_f)) - math.acos(r_b / r_f)
    l_star, m_star, p_star, q_star = sainsot_coefficients(ring_rim_ratio(r_f, rim_radius), theta_f)
    radius = np.asarray(contact_radius, dtype=float)
    alpha = np.arccos(r_b / radius)
    psi = half_angle_base + _involute(alpha)
    beta = alpha + psi  # the kernel's load angle of an internal tooth
    u_f = r_f - radius * np.cos(psi) - radius * np.sin(psi) * np.tan(beta)
    ratio = u_f / (2 * r_f * theta_f)
    return (
        np.cos(beta) ** 2
        / (young_modulus * width)
        * (l_star * ratio**2 + m_star * ratio + p_star * (1 + q_star * np.tan(beta) ** 2))
    )


def ring_contact_radius(
    mesh: geo.MeshGeometry, base_pitch: float, position: np.ndarray, external_drives: bool
) -> np.ndarray:
    """Radius of the contact on the ring (gear 2) at transverse pair positions [m].

    ``position`` is in mesh cycles from the start of contact of the driving gear: the
    external gear's root (ring tip) when it drives, its tip (ring root) when the ring
    drives.  The external gear's roll distance runs from sqrt(r_a2^2 - r_b2^2) - a sin(
    alpha_w) to sqrt(r_a1^2 - r_b1^2); the ring's is a sin(alpha_w) longer.
    """
    gear1, gear2 = mesh.gear1, mesh.gear2
    span = geo.centre_distance(mesh) * math.sin(geo.working_pressure_angle(mesh))
    start = math.sqrt(geo.tip_radius(gear2) ** 2 - geo.base_radius(gear2) ** 2) - span
    end = math.sqrt(geo.tip_radius(gear1) ** 2 - geo.base_radius(gear1) ** 2)
    eps_alpha = (end - start) / base_pitch
    p = np.asarray(position, dtype=float)
    computed = p if external_drives else eps_alpha - p
    roll = start + np.clip(computed, 0.0, eps_alpha) * base_pitch + span
    return np.sqrt(geo.base_radius(gear2) ** 2 + roll**2)


def with_rim(
    pair: np.ndarray,
    transverse_compliance: np.ndarray,
    rim: np.ndarray,
    eps_alpha: float,
    eps_beta: float,
    n_slice: int,
) -> np.ndarray:
    """A pair curve with the rim compliance in series with every slice.

    Parameters
    ----------
    pair : ndarray
        The kernel's pair curve over [0, eps_alpha + eps_beta] [N/m].
    transverse_compliance : ndarray
        Sum of the kernel's whole-face compliances over [0, eps_alpha] [m/N].
    rim : ndarray
        The rim compliance on the same transverse samples [m/N].
    eps_alpha, eps_beta : float
        Contact and overlap ratios.
    n_slice : int
        Face slices of a helical pair (1 for spur).

    Returns
    -------
    ndarray
        ``pair`` times the ratio of the rimmed to the rigid-rim slice sum: on a spur
        pair exactly 1 / (1/k + c_rim); on a helical pair each slice of width L/n is
        the whole-face transverse pair at its shifted position, scaled by 1/n, as in
        the kernel, interpolated linearly between the transverse samples.
    """
    rigid = 1.0 / transverse_compliance
    compliant = 1.0 / (transverse_compliance + rim)
    if eps_beta <= 0:
        return pair * compliant / rigid
    transverse = np.linspace(0.0, eps_alpha, rigid.size)
    position = np.linspace(0.0, eps_alpha + eps_beta, pair.size)
    shifts = (np.arange(n_slice) + 0.5) * eps_beta / n_slice
    points = position[:, None] - shifts[None, :]
    rigid_sum = np.interp(points, transverse, rigid, left=0.0, right=0.0).sum(axis=1)
    compliant_sum = np.interp(points, transverse, compliant, left=0.0, right=0.0).sum(axis=1)
    ratio = np.divide(compliant_sum, rigid_sum, out=np.ones_like(pair), where=rigid_sum > 0)
    return pair * ratio
