r"""The linear time-periodic model of a gearbox at constant speed, in elastic modal form.

At a constant input speed Omega the gearbox turns as its free rigid-body rotation
Phi Omega t, and the elastic deflection q(t) relative to that rotation obeys

    M q'' + C q' + K(t) q = F,   K(t) = K0 + sum_m (k_m(t) - kbar_m) b_m b_m^T,

with K0 the stiffness at the mean mesh stiffnesses kbar_m, b_m the mesh deflection
vectors (:class:`pygear.assembly.matrices.MeshElement`) and k_m(t) each mesh's
stiffness along the rigid-body kinematics, read from the same tooth-contact table the
transient kernel evaluates (:func:`pygear.assembly.contact_table.build_contact_table`,
phases between meshes included).  F is the static load: the drive torque T on the
input member and the load torque on the output member that balances it through the
rigid rotation (T_out = T (w_in . Phi) / (w_out . Phi), power in = power out).

The rigid rotation is taken out by writing q in the elastic modes of (K0, M): q = Psi y,
Psi^T M Psi = I, Psi^T K0 Psi = Lambda.  Every mesh and bearing deflects nothing in a
rigid rotation (b_m . Phi = 0), and Rayleigh damping C = alpha M + beta K0 does not
couple Phi to Psi, so the elastic equations

    y'' + C_r y' + (Lambda + B^T diag(dk(t)) B) y = f,   B = [b_m^T Psi],  f = Psi^T F,

are exact; a damping that couples them (a coupling's dashpot) is projected the same
way, which leaves out the torque the rigid rotation's own damping carries.

The mesh stiffness depends on time only through the mesh cycles, so it is sampled once
per case over one period of the fundamental, as a function of the phase tau in [0, 1);
at a speed Omega the fundamental is omega_0 = 2 pi nu_0 Omega.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field, replace
from fractions import Fraction

import numpy as np

from ...assembly.contact_table import build_contact_table
from ...assembly.dof_rows import dof_row
from ...assembly.drivetrain_model import scene_model
from ...assembly.matrices import Model
from ...errors import CaseError
from ...linalg import generalized_eigh
from ...model.case import Case, Scene
from ...rigid_modes import rigid_body_mask
from .mesh_excitation import mesh_excitation

_log = logging.getLogger("pygear")

__all__ = [
    "DEFAULT_SAMPLES",
    "MAX_MESH_ORDER",
    "ResponseSystem",
    "frequency_groups",
    "response_system",
]

DEFAULT_SAMPLES = 2**14
"""Samples of the mesh stiffness per period of the fundamental.  A stiffness jump (a
pair entering or leaving contact) between two samples aliases its Fourier coefficients
by about dk / N: 6e-5 of the jump here, below the accuracy asked of the balance."""

MAX_MESH_ORDER = 8
"""Largest mesh order (mesh frequency over its group's fundamental): meshes whose common
period holds more cycles of the fastest mesh form separate frequency groups, balanced
together by the multi-frequency (quasi-periodic) balance of :mod:`.quasi`."""

SNAP_DENOMINATOR = 64
SNAP_TOLERANCE = 2e-3
"""Mesh-frequency ratios within this relative distance of a fraction with a denominator
up to :data:`SNAP_DENOMINATOR` are taken as that fraction: the tooth counts fix the
ratio, while a model's base radii may round it (the study case's sun mesh runs at
Z_s r_br / r_bs = 95.93 carrier orders against the ring's 96)."""

STAGE_SNAP_TOLERANCE = 2e-2
"""Snapping tolerance between the meshes of one stage, which share a mesh frequency by
their tooth counts even where the model's base radii set them further apart."""


@dataclass
class ResponseSystem:
    """A gearbox's linear time-periodic model at constant speed, elastic modal form.

    Attributes
    ----------
    eigenvalues : ndarray, shape (n,)
        Lambda, squared elastic natural frequencies [rad^2/s^2].
    damping : ndarray, shape (n, n)
        C_r = Psi^T C Psi [1/s].
    mesh_rows : ndarray, shape (n_mesh, n)
        B: mesh deflection per modal coordinate [m].
    force : ndarray, shape (n,)
        f = Psi^T F, the static load in modal coordinates.
    mean_stiffness : ndarray, shape (n_mesh,)
        kbar_m, the stiffness inside K0 [N/m].
    stiffness : ndarray, shape (samples, n_mesh)
        k_m(tau) over one period of the fundamental [N/m].
    contact_sign : ndarray, shape (n_mesh,)
        s_m = +-1: s_m delta_m > 0 presses the loaded flanks together.
    mesh_order : ndarray of int, shape (n_mesh,)
        Mesh frequency over the fundamental.
    fundamental_per_rad_s : float
        nu_0: the fundamental [Hz] per rad/s of the input member.
    names, stages, planets : list
        Mesh names, their stage, their planet (0 for a parallel mesh).
    modes : ndarray, shape (n_full, n)
        Psi over the model's reduced DOFs (for bearing forces).
    model : Model
        The assembled model.
    attrs : dict
        What the dataset records (input, output, torque, snapping of mesh ratios).
    harmonic_force : ndarray, complex, shape (K, n), optional
        f_k, k = 1..K, of a periodic force f + sum_k (f_k e^{i k omega t} + c.c.) in
        modal coordinates (a transmission-error excitation); None: the static load alone.
    mesh_group : ndarray of int, shape (n_mesh,), optional
        Frequency group of every mesh when the meshes run at several fundamentals (a
        gearbox of several stages); ``stiffness[:, m]`` is then sampled over one period
        of mesh m's group fundamental, and ``mesh_order`` counts in it.  None: one group.
    group_fundamentals : ndarray, shape (groups,), optional
        nu_g: every group's fundamental [Hz] per rad/s of the input member.
    excitation : ndarray, shape (samples, n_mesh), optional
        s_m e_m(tau), the meshes' displacement excitation along their deflections [m]
        (:mod:`.mesh_excitation`); the mesh force is k_m (delta_m - s_m e_m).
    """

    eigenvalues: np.ndarray
    damping: np.ndarray
    mesh_rows: np.ndarray
    force: np.ndarray
    mean_stiffness: np.ndarray
    stiffness: np.ndarray
    contact_sign: np.ndarray
    mesh_order: np.ndarray
    fundamental_per_rad_s: float
    names: list[str]
    stages: list[str]
    planets: list[int]
    modes: np.ndarray
    model: Model | None = None
    attrs: dict = field(default_factory=dict)
    harmonic_force: np.ndarray | None = None
    mesh_group: np.ndarray | None = None
    group_fundamentals: np.ndarray | None = None
    excitation: np.ndarray | None = None

    @property
    def groups(self) -> int:
        """Frequency groups: 1 when every mesh frequency is a small multiple of one
        fundamental, else one per set of stages whose meshes share one."""
        return 1 if self.group_fundamentals is None else int(self.group_fundamentals.size)

    def group_omegas(self, speed_rpm: float) -> np.ndarray:
        """Fundamental angular frequency of every frequency group at an input speed [rad/s]."""
        if self.group_fundamentals is None:
            return np.array([self.omega(speed_rpm)])
        rate = abs(speed_rpm) * math.pi / 30
        return 2 * math.pi * self.group_fundamentals * rate

    def mesh_frequencies(self, speed_rpm: float) -> np.ndarray:
        """Mesh frequency of every mesh at an input speed [Hz]."""
        per_group = self.group_omegas(speed_rpm) / (2 * math.pi)
        group = np.zeros(self.mesh_order.size, int) if self.mesh_group is None else self.mesh_group
        return per_group[group] * self.mesh_order

    def group_system(self, group: int) -> ResponseSystem:
        """The single-frequency system in which only the meshes of ``group`` vary, at the
        group's fundamental; every other mesh keeps its mean stiffness."""
        if self.group_fundamentals is None:
            return self
        mine = self.mesh_group == group
        stiffness = np.where(mine[None, :], self.stiffness, self.mean_stiffness[None, :])
        return replace(
            self,
            stiffness=stiffness,
            fundamental_per_rad_s=float(self.group_fundamentals[group]),
            mesh_order=np.where(mine, self.mesh_order, 1),
            mesh_group=None,
            group_fundamentals=None,
        )

    @property
    def size(self) -> int:
        """Elastic modal coordinates."""
        return self.eigenvalues.size

    @property
    def stiffness_variation(self) -> np.ndarray:
        """dk_m(tau) = k_m(tau) - kbar_m, shape (samples, n_mesh) [N/m]."""
        return self.stiffness - self.mean_stiffness

    @property
    def natural_frequencies(self) -> np.ndarray:
        """Elastic natural frequencies at mean mesh stiffness [Hz]."""
        return np.sqrt(np.maximum(self.eigenvalues, 0.0)) / (2 * math.pi)

    def mesh_energy_share(self) -> np.ndarray:
        """Share of each mode's strain energy stored in the meshes [-]."""
        strain = self.mean_stiffness[:, None] * self.mesh_rows**2
        return strain.sum(axis=0) / np.maximum(self.eigenvalues, 1e-300)

    def static_deflection(self) -> np.ndarray:
        """Mesh deflections under the static load at mean stiffness [m]."""
        return self.mesh_rows @ (self.force / self.eigenvalues)

    def omega(self, speed_rpm: float) -> float:
        """Fundamental angular frequency at an input speed [rad/s]."""
        return 2 * math.pi * self.fundamental_per_rad_s * abs(speed_rpm) * math.pi / 30

    def constant_stiffness(self) -> ResponseSystem:
        """The same system with every mesh at its mean stiffness."""
        return replace(self, stiffness=np.broadcast_to(self.mean_stiffness, self.stiffness.shape))


def _input_output(case: Case, scene: Scene | None) -> tuple[str, str | None, float]:
    """Input and output members and the drive torque: the scene's transient settings,
    else the first transient scene's, else the gearbox's input and output at 1 N m (the
    response is linear in the torque)."""
    settings = scene.transient if scene is not None else None
    if settings is None:
        settings = next((s.transient for s in case.scenes if s.transient is not None), None)
    torque = 1.0
    if settings is not None and settings.drive is not None:
        law = settings.drive
        values = [abs(t) for t in law.torques] if law.kind == "table" else [abs(law.torque)]
        torque = max(values) or 1.0
    if settings is not None and settings.input:
        return settings.input, settings.output, torque
    return case.gearbox.input, case.gearbox.output, torque


def _snap(ratio: float, tolerance: float = SNAP_TOLERANCE) -> Fraction:
    # a looser tolerance goes with smaller denominators, or it would snap to anything
    denominator = SNAP_DENOMINATOR if tolerance <= SNAP_TOLERANCE else MAX_MESH_ORDER
    snapped = Fraction(ratio).limit_denominator(denominator)
    if abs(float(snapped) - ratio) > tolerance * ratio:
        raise CaseError(f"mesh frequency ratio {ratio:.8g} is no ratio of small whole numbers")
    return snapped


def mesh_orders(
    frequencies: np.ndarray, tolerance: float = SNAP_TOLERANCE
) -> tuple[np.ndarray, float, float]:
    """Whole mesh orders over a common fundamental.

    Parameters
    ----------
    frequencies : ndarray
        Mesh frequencies (any common unit), positive.
    tolerance : float
        Largest relative change snapping may make to a ratio.

    Returns
    -------
    orders : ndarray of int
        n_m with f_m = n_m f_0 (after snapping the ratios to small fractions).
    fundamental : float
        f_0, in the unit given.
    snap : float
        Largest relative change snapping made to a ratio.
    """
    slowest = float(frequencies.min())
    ratios = [_snap(f / slowest, tolerance) for f in frequencies]
    lcm_den = 1
    for r in ratios:
        lcm_den = lcm_den * r.denominator // math.gcd(lcm_den, r.denominator)
    whole = [int(r * lcm_den) for r in ratios]
    common = 0
    for w in whole:
        common = math.gcd(common, w)
    orders = np.array([w // common for w in whole], dtype=np.int64)
    fundamental = slowest * common / lcm_den
    snap = max(abs(float(r) * slowest - f) / f for r, f in zip(ratios, frequencies))
    return orders, fundamental, snap


def frequency_groups(
    frequencies: np.ndarray, stages: list[str]
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Meshes gathered into groups that share one fundamental.

    All meshes form one group when their frequencies are whole multiples of one
    fundamental with orders up to :data:`MAX_MESH_ORDER`.  Otherwise the meshes are taken
    stage by stage, each into the first group whose union with it keeps such orders, else
    into a new group: a stage's meshes share their mesh frequency and form one group,
    unless the model's base radii set its sun and ring meshes apart by more than the
    snapping tolerance: those meshes share a mesh frequency by their tooth counts,
    so within a stage ratios are snapped up to :data:`STAGE_SNAP_TOLERANCE`, with a
    warning (the balance then runs the stage at one mesh frequency, the transient at
    the model's two).

    Parameters
    ----------
    frequencies : ndarray
        Mesh frequencies per rad/s of the input [Hz s/rad].
    stages : list of str
        Each mesh's stage.

    Returns
    -------
    group : ndarray of int
        Each mesh's group, numbered in the order of first appearance.
    orders : ndarray of int
        Each mesh's frequency over its group's fundamental.
    fundamentals : ndarray
        Every group's fundamental [Hz s/rad].
    snap : float
        Largest relative change snapping made to a ratio.

    """

    def orders_of(members: list[int], tolerance: float = SNAP_TOLERANCE) -> tuple | None:
        try:
            found = mesh_orders(frequencies[members], tolerance)
        except CaseError:
            return None
        return found if found[0].max() <= MAX_MESH_ORDER else None

    everything = list(range(frequencies.size))
    sets: list[list[int]] = []
    if orders_of(everything) is not None:
        sets = [everything]
    else:
        for stage in dict.fromkeys(stages):  # stage by stage, into the first group it fits
            members = [i for i in everything if stages[i] == stage]
            tolerance = SNAP_TOLERANCE
            if orders_of(members) is None and orders_of(members, STAGE_SNAP_TOLERANCE):
                tolerance = STAGE_SNAP_TOLERANCE
                _, _, off = orders_of(members, tolerance)
                _log.warning(
                    f"response: stage {stage!r}'s meshes run {100 * off:.2f} % apart in "
                    "the model's kinematics (base radii against tooth counts); the "
                    "balance runs them at one mesh frequency"
                )
            for existing in sets:
                if orders_of(existing + members, tolerance) is not None:
                    existing.extend(members)
                    break
            else:
                if orders_of(members, tolerance) is not None:
                    sets.append(members)
                else:  # meshes of a stage at unrelated frequencies: one group each
                    sets.extend([m] for m in members)
    group = np.zeros(frequencies.size, np.int64)
    orders = np.zeros(frequencies.size, np.int64)
    fundamentals = np.zeros(len(sets))
    snap = 0.0
    for g, members in enumerate(sets):
        n, f0, s = orders_of(sorted(members)) or orders_of(sorted(members), STAGE_SNAP_TOLERANCE)
        group[sorted(members)] = g
        orders[sorted(members)] = n
        fundamentals[g] = f0
        snap = max(snap, s)
    return group, orders, fundamentals, snap


def _refuse_once_per_revolution(table) -> None:
    """Refuse meshes whose stiffness repeats once per gear revolution, not per mesh cycle.

    A tooth fault or a per-tooth deviation (pitch error, runout) gives one tooth its own
    stiffness: the mesh is then periodic over a revolution of that gear, and a balance
    sampled over one mesh period would miss it without a sign.
    """
    faulted = np.any(np.asarray(table.factor_start) >= 0, axis=0)
    if table.tooth_curve_block is not None:
        faulted |= np.any(np.asarray(table.tooth_curve_block) >= 0, axis=0)
    if np.any(faulted):
        names = [name for name, bad in zip(table.names, faulted) if bad]
        which = f"{'meshes' if len(names) > 1 else 'mesh'} {', '.join(names)}"
        raise CaseError(
            f"{which}: a tooth of its own (a tooth fault, pitch deviation or runout) "
            "repeats once per gear revolution, which the harmonic balance over one mesh "
            "period cannot hold; run it in time (pygear run) or drop the defect from the "
            "response scene"
        )


def response_system(
    case: Case,
    scene: Scene | None = None,
    *,
    time_varying: bool = True,
    samples: int = DEFAULT_SAMPLES,
    pin_errors: dict[str, float] | None = None,
    torque: float | None = None,
) -> ResponseSystem:
    """Build the constant-speed linear time-periodic model of a case.

    Parameters
    ----------
    case : Case
        The case (a gearbox or a drivetrain).
    scene : Scene, optional
        Scene whose parameters, formulation, DOF set, defects and transient members apply.
    time_varying : bool
        False holds every mesh at its mean stiffness.
    samples : int
        Samples of the mesh stiffness per period of the fundamental (>= 64).
    pin_errors : dict of str to float, optional
        Tangential position errors of planet pins, by planet node name
        (``planetary.planet1``) [m]: the planet bearing spring is pre-deflected by it,
        which loads the pin with k_p e along the tangential direction.
    torque : float, optional
        Drive torque on the input member [N m]; default the scene's drive torque.

    Raises
    ------
    CaseError
        No meshes, no single rigid rotation through the input member, a mesh that
        does not turn with the input member, or a mesh with a tooth of its own (a
        fault or per-tooth deviation, periodic over a gear revolution).
    """
    if not (isinstance(samples, int) and samples >= 64):
        raise CaseError(f"samples must be a whole number >= 64 (got {samples!r})")
    if scene is not None:
        case = case.for_scene(scene)
    model = scene_model(case, scene)
    if not model.meshes:
        raise CaseError(f"case {case.name!r} has no gear mesh to balance")
    input_label, output_label, drive = _input_output(case, scene)
    drive = drive if torque is None else float(torque)
    values, vectors = generalized_eigh(model.stiffness, model.mass)
    rigid = rigid_body_mask(values)
    w_in = dof_row(model, input_label)
    if w_in is None or not np.any(w_in):
        raise CaseError(f"input member {input_label!r} is not a free DOF of the model")
    if rigid.sum() != 1:
        raise CaseError(
            f"the model of {case.name!r} has {int(rigid.sum())} rigid-body "
            "rotations; the steady state at constant speed needs exactly one"
        )
    phi = vectors[:, rigid][:, 0]
    phi = phi / float(w_in @ phi)  # rad/s of every DOF per rad/s of the input
    force = drive * w_in
    w_out = dof_row(model, output_label) if output_label else None
    if w_out is not None and abs(w_out @ phi) > 1e-9 * np.abs(phi).max():
        force = force - drive * (w_in @ phi) / (w_out @ phi) * w_out
    mass_phi = model.mass @ phi
    force = force - mass_phi * (phi @ force) / (phi @ mass_phi)  # round-off of the balance
    psi = vectors[:, ~rigid]
    eigenvalues = values[~rigid]
    deflection = np.array([m.deflection for m in model.meshes])
    rows = deflection @ psi
    damping = psi.T @ model.damping @ psi
    # the loaded flank is the one the torque presses: a pin error that pulls a mesh
    # the other way shows as a negative force (separation), not as a flank change
    static = rows @ ((psi.T @ force) / eigenvalues)
    sign = np.where(static < 0, -1, 1).astype(np.int64)
    force = force + _pin_forces(model, pin_errors or {})

    table = build_contact_table(
        case, model, scene, direction=1, sun_driven=".sun." not in input_label
    )
    if time_varying:
        _refuse_once_per_revolution(table)
    rates = np.zeros(len(model.meshes))
    for m, members in enumerate(table.angles):
        for member, s in zip(members, (1.0, -1.0)):
            row = dof_row(model, f"{member}.theta_z")
            if row is not None:
                rates[m] += s * float(row @ phi)
    frequency = table.teeth[0] * np.abs(rates) / (2 * math.pi)  # Hz per rad/s of the input
    if np.any(frequency <= 0):
        raise CaseError("a mesh does not turn in the rigid rotation of the input member")
    stages_of = [m.stage for m in model.meshes]
    group, orders, fundamentals, snapped = frequency_groups(frequency, stages_of)
    fundamental = float(fundamentals[0])
    if fundamentals.size > 1 and table.excitation is not None:  # see .mesh_excitation
        table = build_contact_table(case, model, scene, direction=1, excitation=False,
                                    sun_driven=".sun." not in input_label)  # fmt: skip
    mean = np.array([m.mean_stiffness for m in model.meshes])
    tau = np.arange(samples) / samples
    # theta_rel of each mesh along the snapped kinematics: n_m cycles per period
    theta = np.outer(tau, np.sign(rates) * 2 * math.pi * orders / table.teeth[0])
    if time_varying:
        stiffness = np.array(table.series(theta)["stiffness"], dtype=np.float64)
    else:
        stiffness = np.broadcast_to(mean, (samples, mean.size)).copy()
    te = None  # the excitation is part of the varying mesh, as in the kernel
    if time_varying:
        te = mesh_excitation(table, theta, stiffness, sign, rows, groups=fundamentals.size)
    several = len(case.gearbox.stages) > 1
    names = [f"{m.stage}.{m.name}" if several else m.name for m in model.meshes]
    return ResponseSystem(
        eigenvalues=eigenvalues,
        damping=0.5 * (damping + damping.T),
        mesh_rows=rows,
        force=psi.T @ force + (te.mean_force if te else 0.0),
        harmonic_force=te.harmonic_force if te else None,
        excitation=te.excitation if te else None,
        mean_stiffness=mean,
        stiffness=stiffness,
        contact_sign=sign,
        mesh_order=orders,
        fundamental_per_rad_s=fundamental,
        mesh_group=group if fundamentals.size > 1 else None,
        group_fundamentals=fundamentals if fundamentals.size > 1 else None,
        names=names,
        stages=[m.stage for m in model.meshes],
        planets=[int(m.planet) for m in model.meshes],
        modes=psi,
        model=model,
        attrs={
            "case": case.name,
            "scene": scene.name if scene is not None else "",
            "formulation": model.formulation,
            "dof_set": model.dof_set,
            "input": input_label,
            "output": output_label or "",
            "drive_torque": drive,
            "time_varying_mesh_stiffness": int(time_varying),
            "mesh_ratio_snap": snapped,
            "stiffness_samples": samples,
            "mesh_stages": ",".join(stages_of),
            "frequency_groups": int(fundamentals.size),
        },
    )


def _pin_forces(model: Model, errors: dict[str, float]) -> np.ndarray:
    """k_p b_eta e over the reduced DOFs for tangential pin errors e by planet name."""
    force_full = np.zeros(len(model.full_labels))
    springs = {s.name: s for s in model.springs if s.kind == "planet_bearing"}
    for planet, error in errors.items():
        spring = springs.get(f"{planet}_bearing")
        if spring is None:
            known = ", ".join(sorted(n.removesuffix("_bearing") for n in springs)) or "none"
            raise CaseError(f"pin error: {planet!r} is no planet of the model (planets: {known})")
        # column 1 is the tangential (eta) spring of the planet bearing
        force_full[spring.dofs] += spring.stiffness[1] * spring.deflection[:, 1] * float(error)
    return model.reduction.T @ force_full
