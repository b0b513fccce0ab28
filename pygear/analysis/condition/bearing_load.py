r"""Loads inside a rolling bearing: Hertzian contacts, the static load distribution, the
linearised stiffness, the varying compliance and the force history of defects.

Contact law (Harris & Kotzalas 2007, ch. 6-7): element j at angle psi_j from the load
direction deflects by

    delta_j = (x cos psi_j + y sin psi_j - P_d / 2) cos(alpha) - h_j(t),

(x, y) the inner ring's displacement relative to the outer, P_d the diametral
clearance, h_j the depth of a defect or waviness under it, and carries
Q_j = K_n <delta_j>_+^n (n = 3/2 point, 10/9 line contact).  K_n joins the inner and
outer contacts in series: for balls from Hertz's elliptical contact (Johnson, *Contact
Mechanics*, 1985, sec. 4.2, the ellipse's eccentricity from the curvature ratio by the
complete elliptic integrals), for rollers from Palmgren's delta = 3.84e-5 Q^0.9 / l^0.8
(mm, N; steel), scaled to other materials as (E'_steel / E')^0.9.

:func:`element_loads` is that law for one instant and any number of instants at once:
what the time-integration kernel needs per step (displacement, element angles, defect
depths in; element loads, force and tangent stiffness out).  Everything else here
calls it: :func:`load_distribution` solves sum_j Q_j cos(alpha) (cos psi_j, sin psi_j)
= (F_r, 0) for (x, y) by Newton's method on the convex contact energy,
:func:`varying_compliance` repeats that as the cage turns, and :func:`defect_excitation`
adds defect depths for a quasi-static history at a given speed and load.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import xarray as xr
from scipy import integrate, optimize, special

from ...errors import CaseError
from ...model.rolling_bearing import BearingDefect, DistributedFault, RollingBearing

__all__ = [
    "PALMGREN_STEEL_MODULUS",
    "contact_constant",
    "defect_depths",
    "defect_excitation",
    "element_loads",
    "hertz_point_compliance",
    "load_distribution",
    "radial_integral",
    "varying_compliance",
]

PALMGREN_STEEL_MODULUS: float = 2.075e11 / (1.0 - 0.3**2)
"""E' = E / (1 - nu^2) of the bearing steel Palmgren's line-contact formula is for [Pa]."""
_PALMGREN_SI: float = 3.84e-5 * 1e-3 * 1e3**-0.8
"""Palmgren's 3.84e-5 mm N^-0.9 mm^0.8 in m N^-0.9 m^0.8."""
NEWTON_TOLERANCE: float = 1e-10
"""Newton stops when the force residual is below this fraction of the load."""


# --------------------------------------------------------------------------- Hertz contact


def hertz_point_compliance(a_curvature: float, b_curvature: float, e_star: float) -> float:
    """c of delta = c Q^(2/3) for an elliptical Hertz contact.

    The gap is A x^2 + B y^2 (A <= B, A + B half the curvature sum); Johnson (1985,
    eqs. 3.64, 4.37-4.39): B/A = (E(e)/(1 - e^2) - K(e)) / (K(e) - E(e)) fixes the
    eccentricity e of the ellipse (K, E complete elliptic integrals, m = e^2), then
    a^3 = 3 Q (K - E) / (2 pi E* e^2 A) and delta = A e^2 a^2 K / (K - E).

    Parameters
    ----------
    a_curvature, b_curvature : float
        A and B [1/m], 0 < A <= B.
    e_star : float
        Contact modulus E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2) [Pa].
    """
    a, b = float(a_curvature), float(b_curvature)
    if not (a > 0 and b >= a and e_star > 0):
        raise CaseError(f"Hertz contact: need 0 < A <= B and E* > 0 (got {a}, {b}, {e_star})")
    ratio = b / a
    if ratio - 1.0 < 1e-9:  # a circle: a^3 = 3 Q R / (4 E*), delta = a^2 / R, R = 1 / 2A
        return 2.0 * a * (3.0 / (8.0 * e_star * a)) ** (2.0 / 3.0)

    def integrals(log_m1: float) -> tuple[float, float, float, float]:
        m1 = math.exp(log_m1)  # m1 = 1 - e^2 = (b / a)^2
        return 1.0 - m1, m1, float(special.ellipkm1(m1)), float(special.ellipe(1.0 - m1))

    def mismatch(log_m1: float) -> float:
        _, m1, k, e = integrals(log_m1)
        return (e / m1 - k) / (k - e) - ratio

    log_m1 = optimize.brentq(mismatch, math.log(1e-300), math.log(1.0 - 1e-10), xtol=1e-14)
    m, _, k, e = integrals(log_m1)
    semi_axis3 = 3.0 * (k - e) / (2.0 * math.pi * e_star * m * a)
    return a * m * k / (k - e) * semi_axis3 ** (2.0 / 3.0)


def _ball_curvatures(bearing: RollingBearing) -> list[tuple[float, float]]:
    """(A, B) of the inner and the outer contact (Harris & Kotzalas, ch. 2)."""
    d, g = bearing.element_diameter, bearing.gamma
    pairs = []
    for f, term in ((bearing.inner_conformity, 2 * g / (1 - g)),
                    (bearing.outer_conformity, -2 * g / (1 + g))):  # fmt: skip
        total = (4.0 - 1.0 / f + term) / d
        difference = (1.0 / f + term) / (4.0 - 1.0 / f + term)
        pairs.append((total * (1.0 - difference) / 4.0, total * (1.0 + difference) / 4.0))
    return pairs


def contact_constant(bearing: RollingBearing) -> float:
    """K_n of Q = K_n delta^n for one angular position (inner and outer contacts in
    series; ``rows`` elements side by side) [N/m^n]."""
    e_prime = bearing.young_modulus / (1.0 - bearing.poisson_ratio**2)
    if bearing.type == "ball":
        e_star = 0.5 * e_prime
        compliance = sum(hertz_point_compliance(a, b, e_star) for a, b in _ball_curvatures(bearing))
        single = compliance**-1.5
    else:
        per_contact = (
            _PALMGREN_SI * bearing.roller_length**-0.8 * (PALMGREN_STEEL_MODULUS / e_prime) ** 0.9
        )
        single = (2.0 * per_contact) ** (-10.0 / 9.0)
    return bearing.rows * single


def radial_integral(epsilon: float, exponent: float = 1.5) -> float:
    """Harris's radial integral J_r(epsilon) = F_r / (Z Q_max) of a continuous load zone,

    J_r = (1 / 2 pi) int_{-psi_l}^{psi_l} [1 - (1 - cos psi) / (2 epsilon)]^n cos psi d psi,

    with cos psi_l = 1 - 2 epsilon (a load zone of 180 deg at epsilon = 0.5, zero
    clearance; the whole ring beyond epsilon = 1, preload).
    """
    if not (math.isfinite(epsilon) and epsilon > 0):
        raise CaseError(f"epsilon must be a positive load-zone factor (got {epsilon!r})")
    limit = math.pi if epsilon >= 1.0 else math.acos(1.0 - 2.0 * epsilon)

    def integrand(psi: float) -> float:
        base = 1.0 - (1.0 - math.cos(psi)) / (2.0 * epsilon)
        return max(base, 0.0) ** exponent * math.cos(psi)

    value, _ = integrate.quad(integrand, -limit, limit, epsabs=1e-13, epsrel=1e-12)
    return value / (2.0 * math.pi)


# --------------------------------------------------------------------------- the contact law


def element_loads(
    bearing: RollingBearing,
    x: np.ndarray | float,
    y: np.ndarray | float,
    angles: np.ndarray,
    depths: np.ndarray | float = 0.0,
    *,
    constant: float | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The contact law at one or many instants: element loads, force and stiffness.

    Parameters
    ----------
    bearing : RollingBearing
        Geometry, clearance and material.
    x, y : float or ndarray
        Inner ring displacement relative to the outer ring [m], x along the load; shape
        ``S`` (instants).
    angles : ndarray
        Element angles psi_j from x [rad], shape ``S + (Z,)``.
    depths : float or ndarray
        Depth taken off each element's deflection [m] (defects, waviness, wear),
        broadcast to ``angles``.
    constant : float, optional
        K_n (:func:`contact_constant`, computed when not given).

    Returns
    -------
    loads : ndarray
        Q_j [N], shape of ``angles``.
    force : ndarray
        (F_x, F_y) the elements exert on the inner ring, negated: the load they carry
        [N], shape ``S + (2,)``.
    stiffness : ndarray
        Tangent stiffness d force / d (x, y) [N/m], shape ``S + (2, 2)``.
    deflection : ndarray
        delta_j [m] (negative: no contact).
    """
    k_n = contact_constant(bearing) if constant is None else constant
    n = bearing.load_exponent
    cos_a = math.cos(math.radians(bearing.contact_angle_deg))
    angles = np.asarray(angles, dtype=float)
    c, s = np.cos(angles), np.sin(angles)
    x = np.asarray(x, dtype=float)[..., None]
    y = np.asarray(y, dtype=float)[..., None]
    deflection = (x * c + y * s - 0.5 * bearing.diametral_clearance) * cos_a - depths
    positive = np.maximum(deflection, 0.0)
    loads = k_n * positive**n
    radial = loads * cos_a
    force = np.stack([np.sum(radial * c, axis=-1), np.sum(radial * s, axis=-1)], axis=-1)
    slope = np.where(deflection > 0.0, n * k_n * positive ** (n - 1.0), 0.0) * cos_a**2
    kxx = np.sum(slope * c * c, axis=-1)
    kxy = np.sum(slope * c * s, axis=-1)
    kyy = np.sum(slope * s * s, axis=-1)
    stiffness = np.stack([np.stack([kxx, kxy], -1), np.stack([kxy, kyy], -1)], -2)
    return loads, force, stiffness, deflection


def _energy(bearing: RollingBearing, k_n: float, deflection: np.ndarray) -> np.ndarray:
    n = bearing.load_exponent
    return k_n / (n + 1.0) * np.sum(np.maximum(deflection, 0.0) ** (n + 1.0), axis=-1)


def _solve(
    bearing: RollingBearing,
    load: float,
    angles: np.ndarray,
    depths: np.ndarray | float = 0.0,
    start: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) where the elements carry (load, 0), at every instant of ``angles``.

    Newton's method on U(x, y) = sum K_n/(n+1) <delta_j>^(n+1) - load x, convex, with
    step halving until U decreases; a first guess from the rigid shift that gives the
    most loaded element Stribeck's 5 F / Z.
    """
    k_n = contact_constant(bearing)
    shape = angles.shape[:-1]
    cos_a = math.cos(math.radians(bearing.contact_angle_deg))
    if start is None:
        guess = (5.0 * load / (bearing.elements * k_n)) ** (1.0 / bearing.load_exponent) / cos_a
        x = np.full(shape, guess + 0.5 * bearing.diametral_clearance + np.max(depths))
        y = np.zeros(shape)
    else:
        x, y = (np.array(v, dtype=float) for v in start)
    target = np.array([load, 0.0])
    scale = max(load, 1e-30)
    for _ in range(200):
        _, force, stiffness, deflection = element_loads(bearing, x, y, angles, depths, constant=k_n)
        residual = force - target
        if np.max(np.abs(residual)) < NEWTON_TOLERANCE * scale:
            return x, y
        regular = 1e-12 * (np.trace(stiffness, axis1=-2, axis2=-1) + 1.0)
        stiffness = stiffness + regular[..., None, None] * np.eye(2)
        step = np.linalg.solve(stiffness, residual[..., None])[..., 0]
        energy = _energy(bearing, k_n, deflection) - load * x
        factor = np.ones(shape)
        for _ in range(40):
            trial_x, trial_y = x - factor * step[..., 0], y - factor * step[..., 1]
            trial = element_loads(bearing, trial_x, trial_y, angles, depths, constant=k_n)[3]
            worse = _energy(bearing, k_n, trial) - load * trial_x > energy + 1e-14 * (
                np.abs(energy) + scale * 1e-12
            )
            if not np.any(worse):
                break
            factor = np.where(worse, 0.5 * factor, factor)
        x, y = x - factor * step[..., 0], y - factor * step[..., 1]
    raise CaseError(
        f"bearing {bearing.name!r}: no equilibrium under F_r = {load:g} N within 200 "
        "Newton steps (a load far beyond the bearing's range?)"
    )


def _check_load(load: float) -> float:
    if not (isinstance(load, (int, float, np.number)) and math.isfinite(load) and load > 0):
        raise CaseError(f"radial_load must be a positive finite force in N (got {load!r})")
    return float(load)


def _element_angles(bearing: RollingBearing, cage_angle: np.ndarray | float) -> np.ndarray:
    spacing = 2.0 * math.pi * np.arange(bearing.elements) / bearing.elements
    return np.asarray(cage_angle, dtype=float)[..., None] + spacing


# --------------------------------------------------------------------------- static load


def load_distribution(
    bearing: RollingBearing, radial_load: float, *, cage_angle_deg: float = 0.0
) -> xr.Dataset:
    """Static load distribution under a radial load (Harris & Kotzalas, ch. 7).

    Solves sum_j Q_j cos(alpha) (cos psi_j, sin psi_j) = (F_r, 0) for the inner ring's
    displacement, element 0 at ``cage_angle_deg`` from the load direction.

    Returns
    -------
    xarray.Dataset
        ``element_load`` Q_j [N] and ``element_angle`` [deg] over ``element``;
        ``displacement`` (x, y) [m]; ``stiffness`` the linearised 2 x 2 matrix [N/m]
        over (``direction``, ``direction_to``); attributes ``max_element_load`` [N],
        ``radial_deflection`` delta_r [m], ``epsilon`` = (1 - P_d / (2 delta_r)) / 2
        and ``load_zone_deg`` = 2 arccos(P_d / (2 delta_r)) (Harris's epsilon method,
        360 deg with preload), ``loaded_elements``.
    """
    load = _check_load(radial_load)
    angles = _element_angles(bearing, math.radians(cage_angle_deg))
    x, y = _solve(bearing, load, angles)
    loads, _, stiffness, _ = element_loads(bearing, x, y, angles)
    delta_r = float(np.hypot(x, y))
    ratio = bearing.diametral_clearance / (2.0 * delta_r)
    zone = 360.0 if ratio <= -1.0 else 2.0 * math.degrees(math.acos(min(1.0, max(-1.0, ratio))))
    element = np.arange(bearing.elements)
    direction = ["x", "y"]
    return xr.Dataset(
        {
            "element_load": (("element",), loads, {"units": "N", "long_name": "element load Q_j"}),
            "element_angle": (
                ("element",),
                np.degrees(angles) % 360.0,
                {"units": "deg", "long_name": "element angle psi_j from the load direction"},
            ),
            "displacement": (
                ("direction",),
                np.array([float(x), float(y)]),
                {"units": "m", "long_name": "inner ring displacement relative to the outer"},
            ),
            "stiffness": (
                ("direction", "direction_to"),
                stiffness,
                {"units": "N/m", "long_name": "linearised bearing stiffness matrix"},
            ),
        },
        coords={
            "element": (("element",), element, {"units": "1", "long_name": "rolling element"}),
            "direction": (("direction",), direction, {"units": "1", "long_name": "x: load"}),
            "direction_to": (("direction_to",), direction, {"units": "1", "long_name": "x: load"}),
        },
        attrs={
            "bearing": bearing.name,
            "radial_load": load,
            "max_element_load": float(np.max(loads)),
            "radial_deflection": delta_r,
            "epsilon": 0.5 * (1.0 - ratio),
            "load_zone_deg": zone,
            "loaded_elements": int(np.count_nonzero(loads > 0.0)),
        },
    )


def varying_compliance(
    bearing: RollingBearing, radial_load: float, *, points: int = 181
) -> xr.Dataset:
    """Stiffness and displacement as the cage turns one element spacing under a load.

    The pattern repeats every 2 pi / Z of cage angle relative to the load: in time, at
    Z |f_c - f_L| (the BPFO of a bearing with its outer ring and load in the housing),
    the varying-compliance vibration (Harris & Kotzalas; Sunnersjo 1978).

    Returns
    -------
    xarray.Dataset
        ``stiffness_xx``, ``stiffness_yy``, ``stiffness_xy`` [N/m] and ``displacement_x``,
        ``displacement_y`` [m] over ``cage_angle`` [deg] (0 .. 360 / Z).
    """
    load = _check_load(radial_load)
    if not (isinstance(points, int) and points >= 2):
        raise CaseError(f"points must be an integer >= 2 (got {points!r})")
    cage = np.linspace(0.0, 2.0 * math.pi / bearing.elements, points)
    angles = _element_angles(bearing, cage)
    x, y = _solve(bearing, load, angles)
    _, _, stiffness, _ = element_loads(bearing, x, y, angles)
    return _history(
        "cage_angle",
        np.degrees(cage),
        {"units": "deg", "long_name": "cage angle from the load direction"},
        x,
        y,
        stiffness,
        attrs={"bearing": bearing.name, "radial_load": load},
    )


def _history(
    dim: str,
    values: np.ndarray,
    coord_attrs: dict,
    x: np.ndarray,
    y: np.ndarray,
    stiffness: np.ndarray,
    extra: dict | None = None,
    *,
    attrs: dict,
) -> xr.Dataset:
    variables = {
        "displacement_x": (x, "m", "inner ring displacement along the load"),
        "displacement_y": (y, "m", "inner ring displacement across the load"),
        "stiffness_xx": (stiffness[..., 0, 0], "N/m", "bearing stiffness along the load"),
        "stiffness_yy": (stiffness[..., 1, 1], "N/m", "bearing stiffness across the load"),
        "stiffness_xy": (stiffness[..., 0, 1], "N/m", "bearing cross stiffness"),
        **(extra or {}),
    }
    return xr.Dataset(
        {k: ((dim,), v, {"units": u, "long_name": n}) for k, (v, u, n) in variables.items()},
        coords={dim: ((dim,), values, coord_attrs)},
        attrs=attrs,
    )


# --------------------------------------------------------------------------- defects


def _wrap(angle: np.ndarray) -> np.ndarray:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def _profile(arc: np.ndarray, defect: BearingDefect, drop: float) -> np.ndarray:
    inside = np.abs(arc) < 0.5 * defect.width
    if defect.profile == "rectangular":
        return np.where(inside, drop, 0.0)
    return np.where(inside, drop * 0.5 * (1.0 + np.cos(2.0 * math.pi * arc / defect.width)), 0.0)


def defect_depths(
    bearing: RollingBearing,
    time: np.ndarray,
    element_angles: np.ndarray,
    rates: dict[str, float],
    defects: Sequence[BearingDefect] = (),
    faults: Sequence[DistributedFault] = (),
) -> np.ndarray:
    """Depth h_j(t) taken off each element's deflection by defects and faults [m].

    ``rates`` gives the ring speeds relative to the load frame [Hz]: ``inner``,
    ``outer`` and the element ``spin`` relative to the cage.  A race defect at angle
    phi (its ring's frame) lies at phi + 2 pi f_ring t from the load direction; element
    j's centre is ``arc = wrap(psi_j - that) R_race`` from it along the race (R_race =
    (D +- d cos alpha) / 2).  An element defect meets the outer race when the element's
    spin angle is 0 and the inner race at pi.  Waviness adds A cos(N (psi_j - phi_ring -
    phi_0)) (a crest closes the clearance); wear takes its depth off every element.
    """
    d, pitch = bearing.element_diameter, bearing.pitch_diameter
    cos_a = math.cos(math.radians(bearing.contact_angle_deg))
    radius = {"outer": 0.5 * (pitch + d * cos_a), "inner": 0.5 * (pitch - d * cos_a)}
    depths = np.zeros_like(element_angles)
    t = np.asarray(time, dtype=float)[:, None]
    for n, defect in enumerate(defects):
        defect.validate(f"defects[{n}]", bearing)
        half = 0.5 * min(defect.width, d)
        drop = min(defect.depth, 0.5 * d - math.sqrt(max(0.25 * d * d - half * half, 0.0)))
        phase = math.radians(defect.angle_deg)
        if defect.location in ("outer", "inner"):
            where = phase + 2.0 * math.pi * rates[defect.location] * t
            arc = _wrap(element_angles - where) * radius[defect.location]
            depths += _profile(arc, defect, drop)
        else:
            spin = phase + 2.0 * math.pi * rates["spin"] * t[:, 0]
            outer = _profile(_wrap(spin) * 0.5 * d, defect, drop)
            inner = _profile(_wrap(spin - math.pi) * 0.5 * d, defect, drop)
            depths[:, defect.element] += outer + inner
    for n, fault in enumerate(faults):
        fault.validate(f"faults[{n}]")
        depths += fault.wear
        if fault.waviness_order and fault.waviness_amplitude:
            ring = 2.0 * math.pi * rates[fault.race] * t + math.radians(fault.waviness_phase_deg)
            depths -= fault.waviness_amplitude * np.cos(
                fault.waviness_order * (element_angles - ring)
            )
    return depths


def defect_excitation(
    bearing: RollingBearing,
    radial_load: float,
    *,
    inner_hz: float,
    outer_hz: float = 0.0,
    load_frame_hz: float = 0.0,
    duration: float,
    sample_rate: float,
    defects: Sequence[BearingDefect] = (),
    faults: Sequence[DistributedFault] = (),
    cage_angle_deg: float = 0.0,
) -> xr.Dataset:
    """Quasi-static excitation history of a bearing at a given speed and load.

    At every sample the elements sit at psi_j(t) = psi_0 + 2 pi (f_c - f_L) t + 2 pi j / Z
    and each defect takes its depth off the deflection of the element crossing it
    (:func:`defect_depths`).  Two histories follow from :func:`element_loads`:

    * load-controlled: (x, y) in equilibrium with the constant radial load, the
      displacement excitation (varying compliance plus the defect's drops);
    * displacement-controlled (blocked): the force the elements carry with the inner
      ring held at the healthy bearing's mean displacement, the force excitation a
      defect's impacts put into the housing (to be passed through a transfer path to a
      sensor, :mod:`pygear.analysis.condition.sensor_signal`).

    Parameters
    ----------
    bearing : RollingBearing
        The bearing.
    radial_load : float
        F_r [N], fixed in the load frame, along x.
    inner_hz, outer_hz, load_frame_hz : float
        Ring speeds and the load frame's speed [Hz] in one frame.
    duration, sample_rate : float
        Length [s] and rate [Hz] of the history.
    defects, faults : sequence
        Localized defects and distributed faults.
    cage_angle_deg : float
        psi_0 of element 0 at t = 0 [deg].

    Returns
    -------
    xarray.Dataset
        Over ``time`` [s]: ``displacement_x/y`` [m], ``stiffness_xx/yy/xy`` [N/m],
        ``blocked_force_x/y`` [N], ``max_element_load`` [N].
    """
    load = _check_load(radial_load)
    for label, value in (("duration", duration), ("sample_rate", sample_rate)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise CaseError(f"{label} must be a positive finite number (got {value!r})")
    count = int(round(duration * sample_rate))
    if count < 2:
        raise CaseError(f"duration * sample_rate must give at least 2 samples (got {count})")
    gamma = bearing.gamma
    cage = 0.5 * ((1.0 - gamma) * inner_hz + (1.0 + gamma) * outer_hz)
    rates = {
        "inner": inner_hz - load_frame_hz,
        "outer": outer_hz - load_frame_hz,
        "spin": bearing.pitch_diameter
        / (2.0 * bearing.element_diameter)
        * (inner_hz - outer_hz)
        * (1.0 - gamma**2),
    }
    time = np.arange(count) / float(sample_rate)
    angles = _element_angles(
        bearing, math.radians(cage_angle_deg) + 2.0 * math.pi * (cage - load_frame_hz) * time
    )
    healthy_x, healthy_y = _solve(bearing, load, angles)
    depths = defect_depths(bearing, time, angles, rates, defects, faults)
    x, y = _solve(bearing, load, angles, depths, start=(healthy_x, healthy_y))
    loads, _, stiffness, _ = element_loads(bearing, x, y, angles, depths)
    held = np.full(count, float(np.mean(healthy_x))), np.full(count, float(np.mean(healthy_y)))
    _, blocked, _, _ = element_loads(bearing, *held, angles, depths)
    extra = {
        "blocked_force_x": (blocked[:, 0], "N", "force the elements carry, ring held (x)"),
        "blocked_force_y": (blocked[:, 1], "N", "force the elements carry, ring held (y)"),
        "max_element_load": (np.max(loads, axis=-1), "N", "largest element load"),
    }
    return _history(
        "time",
        time,
        {"units": "s", "long_name": "time"},
        x,
        y,
        stiffness,
        extra,
        attrs={
            "bearing": bearing.name,
            "radial_load": load,
            "cage_hz": cage,
            "sample_rate": float(sample_rate),
            "defects": "; ".join(repr(d) for d in (*defects, *faults)) or "none",
        },
    )
