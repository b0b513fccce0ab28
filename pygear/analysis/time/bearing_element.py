"""A case's rolling bearings as nonlinear elements of a transient run.

With the scene effect ``rolling_bearing_contact``, every rolling bearing of the case
(:class:`~pygear.model.rolling_bearing.RollingBearing`, ``Case.rolling_bearings``)
replaces the radial spring of the body it carries by its Hertz contacts
(``fortran/rolling_bearing.f90``): Z elements at the cage angle, clearance, the
defects and faults it carries.  A planet bearing (``location`` ``"<stage>.planet"``)
acts on every planet of the stage, in the carrier's frame: the pin (inner ring) stands
still there and the planet's bore (outer ring) turns with the planet's spin relative
to the carrier.  A shaft bearing (``location`` a member, ``"parallel.output_gear"``)
joins the member (inner ring) to the housing (outer ring).  Bearings sharing a body
share its spring: each replaces its share.

:func:`bearing_terms` builds the kernel's :class:`~pygear.kernel.bearing_terms.BearingTerms`
from an assembled model: the rows are the first two deflection vectors of the body's
bearing spring (radial x, y; in the carrier frame for planets) and the rotation DOFs of
the rings, so the element touches exactly the DOFs its spring touches.
"""

from __future__ import annotations

import math

import numpy as np

from ...assembly.dof_rows import dof_row
from ...assembly.matrices import Model
from ...errors import CaseError
from ...kernel.bearing_terms import DEFECT_KINDS, RINGS, BearingTerms
from ...model.rolling_bearing import RollingBearing, rolling_bearings_of

__all__ = [
    "BEARING_EFFECT",
    "bearing_constants",
    "bearing_equivalent_load",
    "bearing_terms",
    "defect_rows",
    "static_displacement",
]

BEARING_EFFECT = "rolling_bearing_contact"
"""The scene effect that puts rolling bearings into a transient run."""


def bearing_constants(bearing: RollingBearing, spring: float) -> np.ndarray:
    """The kernel's constants of ``bearing`` replacing a radial spring ``spring`` [N/m]
    (layout :data:`~pygear.kernel.bearing_terms.BEARING_PARAM_LAYOUT`)."""
    # the Hertz law's constants (SciPy's elliptic integrals) load only when a run has bearings
    from ..condition.bearing_load import contact_constant

    gamma = bearing.gamma
    clearance = bearing.diametral_clearance + 2.0 * sum(f.wear for f in bearing.faults)
    return np.array(
        [
            contact_constant(bearing),
            bearing.load_exponent,
            clearance,
            math.cos(math.radians(bearing.contact_angle_deg)),
            0.5 * (1.0 - gamma),
            0.5 * (1.0 + gamma),
            spring,
            bearing.contact_damping,
        ]
    )


def defect_rows(
    bearing: RollingBearing, index: int, planet: int | None = None
) -> list[tuple[tuple[int, int, int], tuple]]:
    """The kernel's defect entries of ``bearing`` (1-based bearing ``index``) on planet
    ``planet`` (None: a shaft bearing): race spalls (angle, angular width on the race,
    the depth the element reaches) and waviness (phase, order, amplitude).  Element
    defects are not in the kernel; a defect naming another planet is left out."""
    d, pitch = bearing.element_diameter, bearing.pitch_diameter
    cos_a = math.cos(math.radians(bearing.contact_angle_deg))
    radius = {"outer": 0.5 * (pitch + d * cos_a), "inner": 0.5 * (pitch - d * cos_a)}
    rows = []
    for n, defect in enumerate(bearing.defects):
        if defect.location == "element":
            raise CaseError(
                f"rolling_bearings[{bearing.name!r}].defects[{n}].location 'element' is not "
                "in transient runs (race defects only)"
            )
        if defect.planet is not None and planet is not None and defect.planet != planet:
            continue
        half = 0.5 * min(defect.width, d)
        drop = min(defect.depth, 0.5 * d - math.sqrt(max(0.25 * d * d - half * half, 0.0)))
        rows.append(
            (
                (index, RINGS[defect.location], DEFECT_KINDS["spall"]),
                (math.radians(defect.angle_deg), defect.width / radius[defect.location], drop),
            )
        )
    for fault in bearing.faults:
        if fault.waviness_order and fault.waviness_amplitude:
            rows.append(
                (
                    (index, RINGS[fault.race], DEFECT_KINDS["waviness"]),
                    (
                        math.radians(fault.waviness_phase_deg),
                        float(fault.waviness_order),
                        fault.waviness_amplitude,
                    ),
                )
            )
    return rows


def _spring(model: Model, name: str):
    for spring in model.springs:
        if spring.name == name:
            return spring
    return None


def _reduced(model: Model, spring, column: int) -> np.ndarray:
    full = np.zeros(len(model.full_labels))
    full[spring.dofs] = spring.deflection[:, column]
    return model.reduction.T @ full


def _bodies(model: Model, bearing: RollingBearing, path: str) -> list[tuple[str, object]]:
    """(body, its bearing spring) pairs ``bearing`` sits on."""
    if bearing.planet:
        stage = bearing.location.removesuffix(".planet")
        found = []
        n = 1
        while (spring := _spring(model, f"{stage}.planet{n}_bearing")) is not None:
            found.append((f"{stage}.planet{n}", spring))
            n += 1
    else:
        spring = _spring(model, f"{bearing.location}_bearing")
        found = [(bearing.location, spring)] if spring is not None else []
    if not found:
        raise CaseError(
            f"{path}.location {bearing.location!r} names no body with a bearing in this "
            "model ('<stage>.planet' or a member such as 'stage1.sun')"
        )
    return found


def bearing_terms(case: object, model: Model) -> BearingTerms | None:
    """The kernel's terms of the case's rolling bearings on ``model``; None without any.

    Raises
    ------
    CaseError
        A bearing whose location names no body with a bearing spring, or an element
        defect.
    """
    bearings = rolling_bearings_of(case)
    if not bearings:
        return None
    sharing: dict[str, int] = {}
    placed = []
    for n, bearing in enumerate(bearings):
        path = f"rolling_bearings[{n}]"
        bodies = _bodies(model, bearing, path)
        for k, defect in enumerate(bearing.defects):
            if defect.planet is not None and (not bearing.planet or defect.planet > len(bodies)):
                raise CaseError(
                    f"{path}.defects[{k}].planet {defect.planet} names no planet of "
                    f"{bearing.location!r} ({len(bodies) if bearing.planet else 'not'} planets)"
                )
        for body, spring in bodies:
            sharing[body] = sharing.get(body, 0) + 1
            placed.append((bearing, body, spring))
    names, elements, params, rows, defects, values = [], [], [], [], [], []
    zero = np.zeros(model.size)
    for bearing, body, spring in placed:
        x, y = (_reduced(model, spring, c) for c in (0, 1))
        label = f"{body}.{'zeta' if bearing.planet else 'x'}"
        entry = spring.dofs.tolist().index(model.full_labels.index(label))
        # rows of the inner ring relative to the outer (the planet's bore is the outer ring)
        sign = 1.0 if (spring.deflection[entry, 0] > 0) != bearing.planet else -1.0
        turning = dof_row(model, f"{body}.theta_z")
        turning = zero if turning is None else turning
        inner, outer = (turning, zero) if bearing.turning == "inner" else (zero, turning)
        index = len(names) + 1
        names.append(f"{bearing.name}@{body}")
        elements.append(bearing.elements)
        params.append(bearing_constants(bearing, spring.stiffness[0] / sharing[body]))
        rows.extend([sign * x, sign * y, inner, outer])
        planet = int(body.rpartition(".planet")[2]) if bearing.planet else None
        for ints, reals in defect_rows(bearing, index, planet):
            defects.append(ints)
            values.append(reals)
    return BearingTerms(
        names=tuple(names),
        elements=np.array(elements, dtype=np.int32),
        param=np.array(params).T,
        rows=np.array(rows),
        defects=np.array(defects, dtype=np.int32).reshape(-1, 3).T,
        defect_values=np.array(values, dtype=np.float64).reshape(-1, 3).T,
    )


def bearing_equivalent_load(terms: BearingTerms, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The bearings' equivalent load N(q) over the DOFs and its tangent dN/dq (dense,
    regularised by 1e-6 of the spring), healthy (no defect), the kernel's law in NumPy:
    for :func:`static_displacement`."""
    n = q.size
    load = np.zeros(n)
    tangent = np.zeros((n, n))
    for b in range(terms.size):
        rows = terms.row_sets(b)
        x, y, theta_i, theta_o = rows @ q
        k_n, exponent, clearance, cos_a, cage_i, cage_o, spring = terms.param[:7, b]
        z = int(terms.elements[b])
        psi = cage_i * theta_i + cage_o * theta_o + 2 * math.pi * np.arange(z) / z
        c, s = np.cos(psi), np.sin(psi)
        delta = np.maximum((x * c + y * s - 0.5 * clearance) * cos_a, 0.0)
        force = k_n * delta**exponent * cos_a
        slope = exponent * k_n * delta ** (exponent - 1.0) * cos_a**2
        block = np.array(
            [[np.sum(slope * c * c), np.sum(slope * c * s)],
             [np.sum(slope * c * s), np.sum(slope * s * s)]]
        ) - spring * np.eye(2)  # fmt: skip
        # a shaft free in its clearance has no stiffness there: 1e-6 of the spring's
        # keeps the Newton matrix regular (the residual, not the step, sets the answer)
        block += 1e-6 * max(spring, float(np.trace(block)) + 2 * spring, 1.0) * np.eye(2)
        pair = rows[:2]
        elements = np.array([np.sum(force * c), np.sum(force * s)])
        load += pair.T @ (elements - spring * np.array([x, y]))
        tangent += pair.T @ block @ pair
    return load, tangent


def static_displacement(
    terms: BearingTerms, stiffness: np.ndarray, force: np.ndarray, start: np.ndarray
) -> np.ndarray:
    """q with stiffness q + N(q) = force (``stiffness`` regular, holding the bearings'
    springs, N their equivalent load): Newton's method from ``start`` with step halving
    on the residual, to 1e-10 of the force; ``start`` back if it does not converge
    (the run then starts with the springs' deflection, as without bearings)."""
    q = np.array(start, dtype=np.float64)
    scale = max(float(np.abs(force).max()), 1e-30)

    def residual(x: np.ndarray) -> np.ndarray:
        return stiffness @ x + bearing_equivalent_load(terms, x)[0] - force

    r = residual(q)
    for _ in range(100):
        if np.abs(r).max() <= 1e-10 * scale:
            return q
        step = np.linalg.solve(stiffness + bearing_equivalent_load(terms, q)[1], r)
        factor = 1.0
        for _ in range(40):
            trial = q - factor * step
            r_trial = residual(trial)
            if np.linalg.norm(r_trial) < np.linalg.norm(r):
                break
            factor *= 0.5
        q, r = trial, r_trial
    return np.array(start, dtype=np.float64)
