"""Tooth-pair and mesh stiffness from gear geometry by the potential-energy method.

The arithmetic runs once per mesh, before a run, in the Fortran module
``tooth_potential_energy``: each tooth is a non-uniform cantilever (bending, shear,
axial compression; Tian 2004, Wu et al. 2008) on an elastic foundation (Sainsot,
Velex & Duverger 2004), the pair adds the Hertz compliance of Yang & Lin (1987),
helical gears are cut into face-width slices staggered along the path of contact, and
one tooth may carry a root crack, a spall or a chipped tip.  Equations and sources:
docs/potential_energy.md.

Positions p along the path of contact are in mesh cycles (transverse base pitches)
from the start of contact of the driving gear (its root meets the other gear's tip).
:meth:`MeshStiffness.tabulated_curve` turns the single-pair curve into the unit-mean
samples of the contact table's ``law_tabulated``.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import CaseError
from ..kernel import _kernel
from ..model import gear_geometry as geo
from ..model.bodies import foundation_bore_radius
from ..model.components import is_finite_number
from ..model.plausibility import PlausibilityWarning
from ..model.tooth_faults import (
    ChippedTooth,
    RootCrack,
    Spall,
    ToothFault,
    check_fault_fields,
    check_fault_on_tooth,
    field_names,
)
from .ring_rim import rim_compliance, ring_contact_radius, with_rim

__all__ = [
    "ChippedTooth",
    "MeshStiffness",
    "RootCrack",
    "Spall",
    "ToothBody",
    "mesh_stiffness",
    "tooth_compliance",
]

_GEAR_NAMES = (
    "teeth", "base radius", "tip radius", "root radius", "root form radius",
    "tooth thickness (half angle at the base circle)", "base helix angle", "face_width",
    "bore_radius", "young_modulus", "poisson_ratio", "internal",
)  # fmt: skip
_ERRORS = {
    1: "a parameter is out of range",
    2: "the gears cannot mesh as given (contact off the involute, or eps_alpha < 1)",
    3: "a sample count is out of range",
    4: "the fault does not fit the tooth",
}


@dataclass(frozen=True)
class ToothBody:
    """Material and body of one gear.

    Parameters
    ----------
    young_modulus : float
        Young's modulus E [Pa].
    poisson_ratio : float
        Poisson's ratio nu [-], 0 <= nu < 0.5.
    bore_radius : float
        Radius r_int of the bore (or of the hub that holds the rim) [m], entering the
        fillet-foundation term through h_fi = r_f / r_int (Sainsot et al. 2004).  0 leaves
        the foundation term out (a rigid body, as in Tian 2004).  h_fi outside the fit's
        range :data:`pygear.model.bodies.FOUNDATION_RATIO_RANGE` warns and is taken at the
        range's edge.  Ignored for a ring.
    rim_radius : float
        A ring's rim: its outer radius r_o [m], above the root circle, where the housing
        holds it; the ring tooth then gets the rim's fillet-foundation term
        (:mod:`pygear.assembly.ring_rim`).  0 (the default) keeps the rim rigid.  Ignored
        for an external gear.
    """

    young_modulus: float
    poisson_ratio: float
    bore_radius: float
    rim_radius: float = 0.0


@dataclass(frozen=True)
class MeshStiffness:
    """Potential-energy stiffness of one mesh.

    Attributes
    ----------
    contact_ratio, overlap_ratio : float
        eps_alpha and eps_beta; the pair curves span [0, eps_alpha + eps_beta].
    base_pitch : float
        Transverse base pitch p_bt [m].
    position : ndarray
        Pair positions p [mesh cycles] of ``pair`` and ``faulty_pair``.
    pair, faulty_pair : ndarray
        Single-pair stiffness [N/m]: healthy, and the pair holding the damaged tooth
        (equal to ``pair`` without a fault).
    spur_position : ndarray
        Positions [0, eps_alpha] of ``compliance``.
    compliance : dict of str to ndarray
        Compliances [m/N] of the whole-face transverse pair (one slice): ``hertz``, then
        ``bending1``, ``shear1``, ``axial1``, ``foundation1`` and the same for gear 2.
    cycle_position, mesh : ndarray
        Mesh stiffness k_m [N/m] over one healthy mesh cycle, s in [0, 1).
    window_position, faulty_mesh : ndarray
        k_m while the damaged tooth passes, its pair entering at s = 0.
    mean_stiffness : float
        Mean mesh stiffness over a cycle, the integral of the pair curve [N/m].
    """

    contact_ratio: float
    overlap_ratio: float
    base_pitch: float
    position: np.ndarray
    pair: np.ndarray
    faulty_pair: np.ndarray
    spur_position: np.ndarray
    compliance: dict[str, np.ndarray]
    cycle_position: np.ndarray
    mesh: np.ndarray
    window_position: np.ndarray
    faulty_mesh: np.ndarray
    mean_stiffness: float
    fault: ToothFault | None = field(default=None)

    @property
    def total_contact_ratio(self) -> float:
        """eps_alpha + eps_beta: the span of the pair curves."""
        return self.contact_ratio + self.overlap_ratio

    @property
    def max_stiffness(self) -> float:
        """Largest mesh stiffness over a healthy cycle [N/m]."""
        return float(self.mesh.max())

    @property
    def min_stiffness(self) -> float:
        """Smallest mesh stiffness over a healthy cycle [N/m]."""
        return float(self.mesh.min())

    def tabulated_curve(self) -> tuple[np.ndarray, float, float]:
        """Samples for the contact table's ``law_tabulated``.

        Returns
        -------
        curve : ndarray
            Unit-mean samples c(p) at p = eps (q - 1) / (n - 1) (trapezoid mean 1).
        mean_stiffness : float
            k-bar [N/m], so that k_pair = (k-bar / eps) c(p).
        contact_ratio : float
            eps = eps_alpha + eps_beta.
        """
        trapezoid = _trapezoid_mean(self.pair)
        eps = self.total_contact_ratio
        return self.pair / trapezoid, eps * trapezoid, eps

    def faulty_curve(self) -> np.ndarray:
        """The damaged tooth's pair on the scale of :meth:`tabulated_curve` (not unit
        mean): k_pair = (k-bar / eps) c_faulty(p) while that tooth is in mesh."""
        return self.faulty_pair / _trapezoid_mean(self.pair)


def _trapezoid_mean(samples: np.ndarray) -> float:
    return float((samples.sum() - 0.5 * (samples[0] + samples[-1])) / (samples.size - 1))


def _positive(path: str, name: str, value: object, *, zero: bool = False) -> None:
    ok = is_finite_number(value) and (value >= 0.0 if zero else value > 0.0)
    if not ok:
        rule = "a finite number >= 0" if zero else "a positive finite number"
        raise CaseError(f"{path}.{name} must be {rule} (got {value!r})")


def _check_body(body: ToothBody, path: str) -> None:
    _positive(path, "young_modulus", body.young_modulus)
    _positive(path, "bore_radius", body.bore_radius, zero=True)
    _positive(path, "rim_radius", body.rim_radius, zero=True)
    nu = body.poisson_ratio
    if not (is_finite_number(nu) and 0.0 <= nu < 0.5):
        raise CaseError(f"{path}.poisson_ratio must lie in [0, 0.5) (got {nu!r})")


def _check_count(name: str, value: object, low: int, high: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise CaseError(f"{name} must be a whole number in [{low}, {high}] (got {value!r})")


def _check_fault(
    fault: ToothFault, width: float, path: str, gears: tuple[geo.GearGeometry, geo.GearGeometry]
) -> None:
    """Rules of a fault, before the kernel: its own ranges, then its place on the tooth of
    ``gears[fault.gear - 1]`` (:func:`pygear.model.tooth_faults.check_fault_on_tooth`)."""
    check_fault_fields(fault, path)
    if fault.face_start >= width:
        raise CaseError(f"{path}.face_start must lie within the face width {width!r} m")
    if fault.face_width is not None and fault.face_start + fault.face_width > width * (1 + 1e-12):
        raise CaseError(
            f"{path}: face_start + face_width must not exceed the face width {width!r} m"
        )
    check_fault_on_tooth(fault, gears[fault.gear - 1], path)


def _foundation_bore(gear: geo.GearGeometry, body: ToothBody, path: str) -> float:
    """The bore the kernel takes: 0 for a ring, else the typed bore within the fit's range
    of h_fi (a warning names the bore taken instead); a bore at or beyond the root circle
    is an error."""
    if gear.internal or body.bore_radius == 0:
        return 0.0
    root = geo.root_radius(gear)
    if not body.bore_radius < root:
        raise CaseError(
            f"{path}.bore_radius must lie below the root radius r_f = {root * 1e3:.4g} mm "
            f"(got {body.bore_radius * 1e3:.4g} mm)"
        )
    bore, reason = foundation_bore_radius(root, body.bore_radius)
    if reason is not None:
        message = f"{path}.bore_radius = {body.bore_radius!r} m {reason}"
        warnings.warn(message, PlausibilityWarning, stacklevel=3)
    return bore


def _check_rim(gear: geo.GearGeometry, body: ToothBody, path: str) -> None:
    if gear.internal and body.rim_radius and not body.rim_radius > geo.root_radius(gear):
        raise CaseError(
            f"{path}.rim_radius must exceed the ring's root radius r_f = "
            f"{geo.root_radius(gear) * 1e3:.4g} mm (got {body.rim_radius * 1e3:.4g} mm)"
        )


def _gear_column(gear: geo.GearGeometry, body: ToothBody, allowance: float) -> np.ndarray:
    """The kernel's derived transverse geometry of one gear (``body.bore_radius`` as the
    kernel takes it: see :func:`_foundation_bore`)."""
    alpha_n = math.radians(gear.normal_pressure_angle_deg)
    alpha_t = geo.transverse_pressure_angle(gear)
    helix = math.radians(abs(gear.helix_angle_deg))
    thickness = geo.transverse_module(gear) * (
        math.pi / 2 + 2 * gear.profile_shift * math.tan(alpha_n)
    ) + allowance / math.cos(helix)
    half = thickness / (2 * geo.pitch_radius(gear))
    half += -geo.involute(alpha_t) if gear.internal else geo.involute(alpha_t)
    return np.array([
        gear.teeth, geo.base_radius(gear), geo.tip_radius(gear), geo.root_radius(gear),
        geo.root_form_radius(gear), half, geo.base_helix_angle(gear), gear.face_width,
        0.0 if gear.internal else body.bore_radius, body.young_modulus, body.poisson_ratio,
        1.0 if gear.internal else 0.0,
    ], dtype=float)  # fmt: skip


def _raise_kernel(
    path: str, routine: str, ierr: int, bad: int, fault: ToothFault | None = None
) -> None:
    reason = _ERRORS.get(int(ierr), f"error code {int(ierr)}")
    if 100 < bad < 300:
        where = f"gear{bad // 100}.{_GEAR_NAMES[bad % 100 - 1]}"
    elif 300 < bad < 303:
        where = ("centre distance", "working pressure angle")[bad - 301]
    elif 1000 < bad < 1008:
        name = field_names(fault)[bad - 1001]
        value = getattr(fault, name, None)
        shown = f" = {value!r}" if value is not None else ""
        where = f"fault.{name}{shown}"
    elif bad > 2000:
        where = f"contact_radius[{bad - 2001}]"
    else:
        where = "arguments"
    raise CaseError(f"{path}: {routine} refused {where}: {reason}")


def mesh_stiffness(
    mesh: geo.MeshGeometry,
    bodies: tuple[ToothBody, ToothBody],
    *,
    fault: ToothFault | None = None,
    n_sample: int = 201,
    n_cycle: int = 200,
    n_slice: int | None = None,
    n_quad: int = 24,
    driving_gear: int = 1,
    path: str = "mesh",
) -> MeshStiffness:
    """Single-pair curves and mesh stiffness of ``mesh`` by the potential-energy method.

    Parameters
    ----------
    mesh : MeshGeometry
        The gear pair (gear 2 may be a ring); validated first.  Its centre distance and
        thickness allowances are used; tip relief is not modelled.
    bodies : (ToothBody, ToothBody)
        Material and bore of gears 1 and 2.
    fault : RootCrack, Spall, ChippedTooth or None
        Damage of one tooth; ``faulty_pair`` and ``faulty_mesh`` show it.
    n_sample : int
        Samples of the pair curves over [0, eps].
    n_cycle : int
        Samples per mesh cycle of the mesh stiffness.
    n_slice : int or None
        Face-width slices of a helical pair (None: 1 for spur, 100 for helical).
    n_quad : int
        Gauss-Legendre points per integration segment (1..256).
    driving_gear : int
        1 or 2: p = 0 where the driving gear's root meets the other gear's tip.
    path : str
        Name of the mesh in error messages.

    Raises
    ------
    CaseError
        For bad input, before any work; the message names the parameter.
    """
    mesh.validate(path, pointed_tip="ignore")
    if len(bodies) != 2:
        raise CaseError(f"{path}.bodies must hold one ToothBody per gear (got {len(bodies)})")
    for index, body in enumerate(bodies, start=1):
        _check_body(body, f"{path}.bodies[{index - 1}]")
    bodies = tuple(
        dataclasses.replace(body, bore_radius=_foundation_bore(gear, body, f"{path}.bodies[{i}]"))
        for i, (gear, body) in enumerate(zip((mesh.gear1, mesh.gear2), bodies))
    )
    _check_rim(mesh.gear2, bodies[1], f"{path}.bodies[1]")
    _check_count(f"{path}.n_sample", n_sample, 2, 100_000)
    _check_count(f"{path}.n_cycle", n_cycle, 1, 100_000)
    _check_count(f"{path}.n_quad", n_quad, 1, 256)
    helical = mesh.gear1.helix_angle_deg != 0.0
    slices = (100 if helical else 1) if n_slice is None else n_slice
    _check_count(f"{path}.n_slice", slices, 1, 10_000)
    if driving_gear not in (1, 2):
        raise CaseError(f"{path}.driving_gear must be 1 or 2 (got {driving_gear!r})")
    width = min(mesh.gear1.face_width, mesh.gear2.face_width)
    packed = np.zeros(8)
    if fault is not None:
        _check_fault(fault, width, f"{path}.fault", (mesh.gear1, mesh.gear2))
        packed = fault.packed(width)
    columns = [
        _gear_column(mesh.gear1, bodies[0], mesh.thickness_allowances[0]),
        _gear_column(mesh.gear2, bodies[1], mesh.thickness_allowances[1]),
    ]
    if driving_gear == 2:
        # the kernel starts the path at its gear 1's root: hand it the driving gear first
        columns.reverse()
        if fault is not None:
            packed[1] = 3 - fault.gear
    gears = np.asfortranarray(np.column_stack(columns))
    operating = np.array([geo.centre_distance(mesh), geo.working_pressure_angle(mesh)])
    summary, bad, ierr = _kernel.pe_mesh_geometry(gears, operating)
    if ierr:
        _raise_kernel(path, "the potential-energy geometry", ierr, bad)
    eps_alpha, eps_beta, base_pitch = (float(v) for v in summary[:3])
    eps = eps_alpha + eps_beta
    n_window = math.ceil(eps)
    pair, faulty, breakdown, cycle, window, bad, ierr = _kernel.pe_mesh_stiffness(
        gears, operating, packed, n_sample, n_cycle, n_window, slices, n_quad
    )
    if ierr:
        _raise_kernel(path, "the potential-energy stiffness", ierr, bad, fault)
    spur_position = np.linspace(0.0, eps_alpha, n_sample)
    if driving_gear == 2:
        breakdown = breakdown[[0, 5, 6, 7, 8, 1, 2, 3, 4]]
    names = ("hertz", "bending1", "shear1", "axial1", "foundation1",
             "bending2", "shear2", "axial2", "foundation2")  # fmt: skip
    compliance = {name: np.array(breakdown[row]) for row, name in enumerate(names)}
    pair, faulty = np.array(pair), np.array(faulty)
    cycle, window = np.array(cycle), np.array(window)
    if mesh.gear2.internal and bodies[1].rim_radius > 0:
        rim = rim_compliance(
            mesh.gear2,
            float(columns[0 if driving_gear == 2 else 1][5]),
            bodies[1].rim_radius,
            bodies[1].young_modulus,
            width,
            ring_contact_radius(mesh, base_pitch, spur_position, driving_gear == 1),
        )
        transverse = sum(compliance.values())
        pair = with_rim(pair, transverse, rim, eps_alpha, eps_beta, slices)
        if eps_beta > 0:
            faulty = with_rim(faulty, transverse, rim, eps_alpha, eps_beta, slices)
        else:  # one slice: the rim in series with the damaged pair itself (0: no contact)
            faulty = np.divide(
                faulty, 1.0 + faulty * rim, out=np.zeros_like(faulty), where=faulty > 0
            )
        compliance["foundation2"] = rim
        cycle, window = _summed(pair, faulty, eps, n_cycle, n_window)
    return MeshStiffness(
        contact_ratio=eps_alpha,
        overlap_ratio=eps_beta,
        base_pitch=base_pitch,
        position=np.linspace(0.0, eps, n_sample),
        pair=pair,
        faulty_pair=faulty,
        spur_position=spur_position,
        compliance=compliance,
        cycle_position=np.arange(n_cycle) / n_cycle,
        mesh=cycle,
        window_position=np.arange(n_cycle * n_window) / n_cycle,
        faulty_mesh=window,
        mean_stiffness=eps * _trapezoid_mean(pair),
        fault=fault,
    )


def _summed(
    pair: np.ndarray, faulty: np.ndarray, eps: float, n_cycle: int, n_window: int
) -> tuple[np.ndarray, np.ndarray]:
    """Mesh stiffness over a healthy cycle and over the damaged tooth's window, summed
    from pair curves sampled over [0, eps] (linear interpolation between samples)."""
    position = np.linspace(0.0, eps, pair.size)
    n_pair = math.ceil(eps) + 1

    def at(curve: np.ndarray, p: np.ndarray) -> np.ndarray:
        return np.interp(p, position, curve, left=0.0, right=0.0)

    s = np.arange(n_cycle) / n_cycle
    cycle = sum(at(pair, s + m) for m in range(n_pair + 1))
    s = np.arange(n_cycle * n_window) / n_cycle
    window = at(faulty, s) + sum(at(pair, s - m) for m in range(-n_pair, n_pair + 1) if m)
    return cycle, window


def tooth_compliance(
    gear: geo.GearGeometry,
    body: ToothBody,
    contact_radius: np.ndarray,
    *,
    fault: ToothFault | None = None,
    thickness_allowance: float = 0.0,
    n_quad: int = 24,
    path: str = "gear",
) -> dict[str, np.ndarray]:
    """Compliances of one tooth (its whole face width) for a unit load at given radii.

    Returns
    -------
    dict of str to ndarray
        ``bending``, ``shear``, ``axial``, ``foundation`` [m/N] and ``load_angle`` [rad]
        (angle between the load and the normal to the tooth centre line).
    """
    gear.validate(path)
    _check_body(body, f"{path}.body")
    body = dataclasses.replace(body, bore_radius=_foundation_bore(gear, body, f"{path}.body"))
    _check_rim(gear, body, f"{path}.body")
    _check_count(f"{path}.n_quad", n_quad, 1, 256)
    radii = np.atleast_1d(np.asarray(contact_radius, dtype=float))
    if radii.size == 0 or not np.all(np.isfinite(radii)):
        raise CaseError(f"{path}.contact_radius must be finite radii [m] (got {contact_radius!r})")
    packed = np.zeros(8)
    if fault is not None:
        _check_fault(fault, gear.face_width, f"{path}.fault", (gear, gear))
        packed = fault.packed(gear.face_width)
    column = _gear_column(gear, body, thickness_allowance)
    values, angle, bad, ierr = _kernel.pe_tooth_compliance(column, packed, radii, n_quad)
    if ierr:
        _raise_kernel(path, "the potential-energy tooth", ierr, bad, fault)
    names = ("bending", "shear", "axial", "foundation")
    result = {name: np.array(values[row]) for row, name in enumerate(names)}
    if gear.internal and body.rim_radius > 0:
        result["foundation"] = rim_compliance(
            gear, float(column[5]), body.rim_radius, body.young_modulus, gear.face_width, radii
        )
    result["load_angle"] = np.array(angle)
    return result
