"""Speed-dependent terms of a turning gearbox: Coriolis (gyroscopic) and centripetal
matrices per unit reference speed, and the kinematics that scale every stage.

Cooley & Parker (J. Vib. Acoust. 134 (2012) 061014) write a planetary stage in a frame
that turns with its carrier at Omega.  Every member then gains, on the two in-plane
translations of its centre (x, y of carrier, ring and sun; zeta, eta of a planet), a
gyroscopic matrix and a centripetal softening

    Omega G_j = 2 m_j Omega [[0, -1], [1, 0]],     -Omega^2 K_Omega,j = -Omega^2 m_j I,

and rotations gain nothing.  The equation of free motion is
M q'' + (C + Omega G) q' + (K - Omega^2 K_Omega) q = 0.

pygear's assembly already writes every planetary mesh and bearing with the planets'
fixed angles psi_n, i.e. in the carrier frame; its bearings are isotropic in the plane,
so reading the central members' x, y as carrier-frame coordinates changes no stiffness,
and these terms make the description exact at constant speed.  Per formulation:

- a planet's translation is read off its own mass matrix, M_t = m A^T A with
  A = d(radial, tangential)/dq.  In ``consistent`` the tangential motion is
  eta + r_c phi, so G gains the zeta-phi coupling 2 m Omega r_c of the planet's exact
  kinetic energy; ``improved`` and ``lin-parker`` keep it on (zeta, eta);
- K_Omega acts on (zeta, eta) only: a planet's distance from the axis does not change
  when its revolving frame turns with phi.  In ``lin-parker`` eta is the planet's
  whole tangential motion, so a free rigid rotation of the carrier softens by
  sum m_p Omega^2 (the published model's linear centripetal term);
- parallel stages and shaft inertias stay in the inertial frame: no frame terms.
  Gyroscopic moments of spinning bodies on their tilts are not modelled.

Every planetary stage turns at its own carrier speed, Omega_s = ratio_s Omega_ref,
from the gearbox's one free rigid-body rotation, so G and K_Omega are returned per
rad/s (and (rad/s)^2) of a reference member: G(Omega_ref) = Omega_ref G_unit.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import CaseError
from ..model.components import PlanetaryStage

__all__ = [
    "MEMBER_CHOICES",
    "SpeedTerms",
    "TranslationPair",
    "FrameTerms",
    "apply_speed_terms",
    "drivetrain_frame_terms",
    "with_frame_terms",
    "reference_label",
    "speed_terms",
]

MEMBER_CHOICES = ("carrier", "input")
"""Reference members a speed may be given for: the first planetary stage's carrier, or
the gearbox's input DOF."""

RIGID_TOLERANCE = 1e-8
"""Eigenvalues of (K, M) below this fraction of the largest are free rigid-body motions."""


@dataclass(frozen=True)
class TranslationPair:
    """The two in-plane translations of one body's centre, as rows over reduced DOFs.

    ``first @ q`` is x (zeta for a planet) and ``second @ q`` is y (the planet's whole
    tangential motion) in the body's frame, which turns at ``frame_ratio`` times the
    reference speed (0: inertial); the body spins at ``spin_ratio`` times it.
    """

    body: str
    stage: str
    role: str
    mass: float
    first: np.ndarray
    second: np.ndarray
    frame_ratio: float
    spin_ratio: float


@dataclass(frozen=True)
class SpeedTerms:
    """Gyroscopic and centripetal matrices of a model per unit reference speed.

    Attributes
    ----------
    reference : str
        DOF label of the reference member (``planetary.carrier.theta_z``).
    members : str
        ``all`` (Cooley & Parker) or ``planets`` (the planets' terms only).
    gyroscopic : ndarray
        G_unit over reduced DOFs [kg]: the Coriolis matrix at 1 rad/s of the reference.
    centripetal : ndarray
        K_Omega,unit over reduced DOFs [kg]: the softening at 1 rad/s is -K_Omega,unit.
    pairs : tuple of TranslationPair
        Every body's in-plane translation pair (all bodies, for whirl and energy).
    speed_ratios : dict of str to float
        Each body's absolute speed over the reference's (``stage.member``).
    frame_ratios : dict of str to float
        Each planetary stage's carrier speed over the reference's.
    """

    reference: str
    members: str
    gyroscopic: np.ndarray
    centripetal: np.ndarray
    pairs: tuple[TranslationPair, ...]
    speed_ratios: dict[str, float]
    frame_ratios: dict[str, float]

    def at(self, speed_rad_s: float) -> tuple[np.ndarray, np.ndarray]:
        """(Omega G_unit, Omega^2 K_Omega,unit) at a reference speed [rad/s]."""
        return speed_rad_s * self.gyroscopic, speed_rad_s**2 * self.centripetal


def reference_label(case: Any, member: str) -> str:
    """DOF label of the reference member: ``carrier`` (the first planetary stage's
    carrier) or ``input`` (the gearbox's input DOF)."""
    if member not in MEMBER_CHOICES:
        raise CaseError(f"--member must be one of {', '.join(MEMBER_CHOICES)} (got {member!r})")
    if member == "input":
        return case.gearbox.input
    for stage in case.gearbox.stages:
        if isinstance(stage, PlanetaryStage):
            return f"{stage.name}.carrier.theta_z"
    raise CaseError(
        f"--member carrier: case {case.name!r} has no planetary stage (use --member input)"
    )


def _rigid_rotation(model: Any) -> np.ndarray:
    import scipy.linalg

    values, vectors = scipy.linalg.eigh(model.stiffness, model.mass)
    zero = np.abs(values) <= RIGID_TOLERANCE * np.abs(values).max()
    if zero.sum() != 1:
        raise CaseError(
            f"gearbox.rigid_body_modes: speed-dependent terms scale every stage by the one "
            f"free rigid-body rotation, and this model has {int(zero.sum())}"
        )
    return vectors[:, int(np.argmax(zero))]


def _row(model: Any, label: str) -> np.ndarray:
    return np.asarray(model.reduction[model.full_labels.index(label)], dtype=float)


def speed_terms(
    model: Any, case: Any, reference: str | None = None, members: str = "all"
) -> SpeedTerms:
    """G and K_Omega of an assembled model per unit reference speed.

    Parameters
    ----------
    model : Model
        The assembled model at zero speed (no speed-dependent effect in force).
    case : Case
        Its case (stages and couplings).
    reference : str, optional
        DOF label the speed refers to; default the first planetary stage's carrier.
    members : {"all", "planets"}
        Cooley & Parker's terms on every member of every planetary stage (each stage
        in its carrier's frame), or on the planets only: the carrier, ring and sun
        are then read in the inertial frame (their pairs' ``frame_ratio`` is 0), as
        the shafts of a drivetrain they sit on.

    Raises
    ------
    CaseError
        Without exactly one free rigid-body rotation, when the reference does not turn
        in it, or when a coupling ties translations of bodies in different frames.
    """
    if members not in ("all", "planets"):
        raise CaseError(f"members must be 'all' or 'planets' (got {members!r})")
    reference = reference or reference_label(case, "carrier")
    if reference not in model.full_labels:
        raise CaseError(f"reference {reference!r} is not a DOF of this model")
    rigid = _rigid_rotation(model)
    reference_speed = _row(model, reference) @ rigid
    if abs(reference_speed) <= 1e-9 * np.abs(rigid).max():
        raise CaseError(f"reference {reference!r} does not turn in the gearbox's free rotation")

    def ratio(label: str) -> float:
        if label not in model.full_labels:
            return 0.0
        return float(_row(model, label) @ rigid / reference_speed)

    frame_ratios = {
        stage.name: ratio(f"{stage.name}.carrier.theta_z")
        for stage in case.gearbox.stages
        if isinstance(stage, PlanetaryStage)
    }
    _check_couplings(case, frame_ratios)
    n_full = len(model.full_labels)
    gyroscopic = np.zeros((n_full, n_full))
    centripetal = np.zeros((n_full, n_full))
    pairs, speeds = [], {}
    for node in model.nodes:
        if node.role == "housing":
            continue
        stage = node.name.split(".", 1)[0]
        spin = ratio(f"{node.name}.theta_z") + ratio(f"{node.name}.phi")
        speeds[node.name] = spin
        part = _in_plane_translation(model, node)
        if part is None:
            continue
        first, second, mass = _pair_axes(node, part, n_full)
        frame = frame_ratios.get(stage, 0.0)
        if members == "planets" and node.role != "planet":
            frame = 0.0  # a central member read in the inertial frame, as a shaft's node
        pairs.append(
            TranslationPair(
                node.name,
                stage,
                node.role,
                mass,
                first @ model.reduction,
                second @ model.reduction,
                frame,
                spin,
            )
        )
        if frame == 0.0:
            continue
        # Coriolis: 2 m Omega (a2 a1^T - a1 a2^T); centripetal: m on the pair's own DOFs
        gyroscopic += 2.0 * mass * frame * (np.outer(second, first) - np.outer(first, second))
        for axis in _own_axes(node, n_full):
            centripetal += mass * frame**2 * np.outer(axis, axis)
    reduce = model.reduction
    return SpeedTerms(
        reference=reference,
        members=members,
        gyroscopic=reduce.T @ gyroscopic @ reduce,
        centripetal=_symmetric(reduce.T @ centripetal @ reduce),
        pairs=tuple(pairs),
        speed_ratios=speeds,
        frame_ratios=frame_ratios,
    )


def _in_plane_translation(model: Any, node: Any) -> np.ndarray | None:
    """The body's in-plane translational mass matrix over its node's DOFs, if any."""
    matrix = None
    for part in model.mass_parts:
        if part.body == node.name and part.motion == "translation" and part.plane == "in-plane":
            matrix = part.matrix if matrix is None else matrix + part.matrix
    return matrix


def _pair_axes(node: Any, part: np.ndarray, n_full: int) -> tuple[np.ndarray, np.ndarray, float]:
    """Full-DOF rows of the pair's first and second coordinate, and the body's mass.

    The second row is the body's mass-matrix row of its second DOF over its mass, so a
    consistent planet's tangential motion eta + r_c phi comes out of its own kinetic
    energy."""
    names = node.dof_names
    first_name, second_name = ("zeta", "eta") if node.role == "planet" else ("x", "y")
    i, j = names.index(first_name), names.index(second_name)
    mass = float(part[i, i])
    first = np.zeros(n_full)
    second = np.zeros(n_full)
    first[node.first + i] = 1.0
    second[node.dofs] = part[j] / mass
    return first, second, mass


def _own_axes(node: Any, n_full: int) -> list[np.ndarray]:
    names = ("zeta", "eta") if node.role == "planet" else ("x", "y")
    axes = []
    for name in names:
        axis = np.zeros(n_full)
        axis[node.first + node.dof_names.index(name)] = 1.0
        axes.append(axis)
    return axes


def _check_couplings(case: Any, frame_ratios: dict[str, float]) -> None:
    """Refuse a coupling that ties translations of bodies in frames that turn apart."""
    for coupling in case.gearbox.couplings:
        labels = (coupling.a, coupling.b)
        if all(label.rsplit(".", 1)[1] in ("theta_z", "z") for label in labels):
            continue
        frames = {frame_ratios.get(label.split(".", 1)[0], 0.0) for label in labels}
        if len(frames) > 1:
            raise CaseError(
                f"gearbox.couplings {coupling.a} - {coupling.b}: speed-dependent terms write "
                "each planetary stage in its carrier's frame, and this coupling ties motions "
                "of bodies in frames that turn at different speeds"
            )


def apply_speed_terms(model: Any, case: Any, carrier_speed_rpm: float) -> Any:
    """The model with Cooley & Parker's terms of every member at a carrier speed.

    ``carrier_speed_rpm`` is the first planetary stage's carrier speed; the other
    stages turn at theirs from the gearbox's kinematics (the ``gyroscopic_all_members``
    effect).  Returns a copy with stiffness K0 - Omega^2 K_Omega and the gyroscopic
    matrix Omega G; the damping stays the Rayleigh damping of K0.
    """
    if carrier_speed_rpm == 0.0:
        return model
    terms = speed_terms(model, case, reference_label(case, "carrier"), "all")
    gyroscopic, centripetal = terms.at(carrier_speed_rpm * math.pi / 30.0)
    if model.gyroscopic is not None:
        gyroscopic = gyroscopic + model.gyroscopic
    return dataclasses.replace(
        model, stiffness=_symmetric(model.stiffness - centripetal), gyroscopic=gyroscopic
    )


def _symmetric(matrix: np.ndarray) -> np.ndarray:
    return 0.5 * (matrix + matrix.T)


@dataclass(frozen=True)
class FrameTerms:
    """A drivetrain's gearbox-block rotating-frame terms per unit rotor speed.

    Attributes
    ----------
    gyroscopic : scipy.sparse.csc_matrix
        Coriolis matrix over the drivetrain's DOFs at 1 rad/s of the rotor [kg].
    centripetal : scipy.sparse.csc_matrix
        Centripetal softening at 1 rad/s of the rotor: K(Omega) = K - Omega^2 times it [kg].
    carrier_ratios : dict of str to float
        Each planetary stage's carrier speed over the rotor's.
    terms : SpeedTerms
        The gearbox model's terms per unit speed of the reference carrier.
    """

    gyroscopic: Any
    centripetal: Any
    carrier_ratios: dict[str, float]
    terms: SpeedTerms

    def at(self, rotor_speed_rad_s: float) -> tuple[Any, Any]:
        """(Omega G, Omega^2 K_Omega) at a rotor speed [rad/s]."""
        return rotor_speed_rad_s * self.gyroscopic, rotor_speed_rad_s**2 * self.centripetal


def drivetrain_frame_terms(model: Any, case: Any) -> FrameTerms | None:
    """The planets' Coriolis and centripetal terms of a drivetrain's gearbox block.

    A drivetrain's carrier, ring and sun share their shafts' inertial DOFs (the
    ``improved`` and ``consistent`` formulations), while each planet is written in its
    carrier's frame at the planet's fixed angle: the planets carry Cooley & Parker's
    terms (``members="planets"``) at their stage's carrier speed, and the central
    members carry none.  The terms are scaled from the gearbox's reference carrier to
    the rotor by the speed of a mounted member over its shaft's speed ratio.

    Parameters
    ----------
    model : DrivetrainModel
        The assembled drivetrain (its ``gearbox`` block and ``speed_ratios``).
    case : Case
        Its case.

    Returns
    -------
    FrameTerms or None
        None for a plain rotor or a gearbox without a planetary stage.
    """
    import scipy.sparse as sp

    gearbox = model.gearbox
    if gearbox is None or not any(isinstance(s, PlanetaryStage) for s in case.gearbox.stages):
        return None
    terms = speed_terms(gearbox, case, reference_label(case, "carrier"), "planets")
    carrier_over_rotor = None
    for mount in case.drivetrain.mounts:
        member = terms.speed_ratios.get(mount.member, 0.0)
        if abs(member) > 1e-12:
            carrier_over_rotor = model.speed_ratios[mount.at.split(".")[0]] / member
            break
    if carrier_over_rotor is None:
        raise CaseError("drivetrain.mounts: no mounted gearbox member turns with the rotor")
    offset = model.gearbox_offset

    def placed(block: np.ndarray) -> Any:
        return sp.block_diag((sp.csc_matrix((offset, offset)), sp.csc_matrix(block)), "csc")

    return FrameTerms(
        gyroscopic=placed(carrier_over_rotor * terms.gyroscopic),
        centripetal=placed(carrier_over_rotor**2 * terms.centripetal),
        carrier_ratios={k: v * carrier_over_rotor for k, v in terms.frame_ratios.items()},
        terms=terms,
    )


def with_frame_terms(model: Any, frame_terms: FrameTerms | None) -> Any:
    """The drivetrain model with its planets' frame terms folded in: ``gyroscopic``
    holds G + G_frame (per unit rotor speed) and :meth:`at_speed` subtracts
    Omega^2 K_Omega, so every analysis that reads a model at a speed (the unbalance
    response, an FRF) gets them.  ``model`` itself when ``frame_terms`` is None."""
    if frame_terms is None:
        return model

    @dataclass
    class _Spinning(type(model)):  # a DrivetrainModel (not imported: drivetrain imports us)
        centripetal: Any = None

        def at_speed(self, speed_rpm: float) -> tuple[Any, Any]:
            stiffness, damping = super().at_speed(speed_rpm)
            omega = speed_rpm * math.pi / 30.0
            return (stiffness - omega**2 * self.centripetal).tocsc(), damping

    fields = {f.name: getattr(model, f.name) for f in dataclasses.fields(model)}
    fields["gyroscopic"] = (model.gyroscopic + frame_terms.gyroscopic).tocsc()
    return _Spinning(**fields, centripetal=frame_terms.centripetal)
