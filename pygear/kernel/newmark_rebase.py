"""Keeping rotation angles small in long runs: rebasing the rigid-body rotation.

A drivetrain turns without bound (2000 rpm for 250 s is 5e4 rad), while its mesh
deflections stay near 1e-6 m.  Every deflection is a difference b . q of large
rotations, and the kernel's K0 q cancels the rigid motion the same way, so a double
holding 1e5 rad keeps only about 1e-11 rad: relative errors of 1e-6 in the
deflections.  Between two kernel calls, :class:`RigidRebase` takes the rigid-body part
Phi c (c = Phi^T M q, Phi the mass-normalised null space of K0) out of q and adds it to
an offset, so q stays within a few radians.  Nothing physical changes: K0 Phi = 0 and
b . Phi = 0, the velocities are untouched, and each mesh's phase gamma takes up the
rotation it lost (tooth counts keep their integer part), so the tooth-contact table
sees the same mesh cycle.  Displacement probes and the final state get the offset back.
"""

from __future__ import annotations

import math

import numpy as np

from ..linalg import generalized_eigh
from ..rigid_modes import rigid_body_mask

__all__ = ["RigidRebase"]

REBASE_ANGLE = 16.0
"""Rebase when the rigid-body part of q exceeds this in any DOF [rad or m].  Short runs
then never rebase, and two runs that differ only in decoupled DOFs (planar against
spatial) stay bit-identical; the rounding of q at 16 rad still keeps 1e-9."""

REBASE_STEPS = 1000
"""Rebasing is considered only at multiples of this many steps, and no kernel call
crosses one: the result then does not depend on how a run was cut into calls (a
resumed run stays bit-identical).  At 2000 rpm and 2.5e-5 s that is 5.2 rad between
rebases.  The position update rounds at eps |q| every step; with q this small the
deflections of the study case keep 3e-10 of their value over 1e7 steps, against
5e-9 with 10 000 steps between rebases and 4e-6 without rebasing."""


class RigidRebase:
    """Rigid-body rebasing of a kernel state between chunks (see the module docstring).

    Parameters
    ----------
    mass, stiffness : ndarray, shape (n, n)
        M and K0 in the caller's DOF order.
    order : ndarray
        The kernel's DOF order (the state holds ``x[order]``).
    angle : ndarray, shape (n_mesh, n), optional
        Mesh angle rows (caller's order) when the tooth-contact table is in use.
    cycle_sign, teeth : ndarray, optional
        The table's sign and tooth numbers (2, n_mesh) for the phase bookkeeping.
    """

    def __init__(
        self,
        mass: np.ndarray,
        stiffness: np.ndarray,
        order: np.ndarray,
        *,
        angle: np.ndarray | None = None,
        cycle_sign: np.ndarray | None = None,
        teeth: np.ndarray | None = None,
    ) -> None:
        n = mass.shape[0]
        self.modes = np.zeros((n, 0))
        if type(mass).__module__.startswith("scipy.sparse"):
            rigid = _sparse_rigid_modes(mass, stiffness)
            if rigid is None:
                return
            self.mass = mass.tocsr()[order][:, order]
        else:
            try:
                values, vectors = generalized_eigh(stiffness, mass)
            except (np.linalg.LinAlgError, ValueError):
                return  # M not positive definite: no rebasing
            rigid = vectors[:, rigid_body_mask(values)]
            self.mass = mass[np.ix_(order, order)]
        self.modes = rigid[order]  # kernel order
        self.cycles_per_unit = None
        if angle is not None and cycle_sign is not None and teeth is not None and rigid.size:
            # mesh-cycle change per unit modal coordinate: sigma Z1 (angle . phi) / 2 pi
            self.cycles_per_unit = (
                (cycle_sign * teeth[0])[:, None] * (np.asarray(angle) @ rigid) / (2 * math.pi)
            )
            self.teeth = np.asarray(teeth)

    @property
    def active(self) -> bool:
        """True when the model has a free rigid-body motion to take out."""
        return self.modes.shape[1] > 0

    def initial_state(self, arguments: dict) -> dict:
        """The extra state a run carries: the offset and the table's phase bookkeeping."""
        return {
            "rigid_offset": np.zeros(self.modes.shape[1]),
            "phase": np.array(arguments["phase"], dtype=np.float64),
            "tooth_offset": np.asfortranarray(arguments["tooth_offset"], dtype=np.int32),
        }

    def aligned_steps(self, step: int, steps: int) -> int:
        """``steps`` from ``step``, cut so that a call never crosses a multiple of
        :data:`REBASE_STEPS` (it may end on one)."""
        if not self.active:
            return steps
        return int(min(steps, (step // REBASE_STEPS + 1) * REBASE_STEPS - step))

    def apply(self, state: dict, step: int) -> bool:
        """Take the rigid-body part out of ``state["q"]`` when it is large and ``step`` is
        a multiple of :data:`REBASE_STEPS`; True if done."""
        if not self.active or step % REBASE_STEPS:
            return False
        coordinates = self.modes.T @ (self.mass @ state["q"])
        shift = self.modes @ coordinates
        if not np.abs(shift).max() > REBASE_ANGLE:
            return False
        state["q"] = state["q"] - shift
        state["rigid_offset"] = state["rigid_offset"] + coordinates
        if self.cycles_per_unit is not None:
            phase = state["phase"] + self.cycles_per_unit @ coordinates
            whole = np.floor(phase)
            state["phase"] = phase - whole
            count = whole.astype(np.int64)
            offsets = np.array(state["tooth_offset"], dtype=np.int64)
            offsets = np.mod(offsets + count[None, :], self.teeth.astype(np.int64))
            state["tooth_offset"] = np.asfortranarray(offsets, dtype=np.int32)
        return True

    def probe_offsets(self, weights: np.ndarray, state: dict) -> float:
        """What a displacement probe (weights in kernel order) lost to the rebasing:
        (w . Phi) c.  A probe that the rigid motion leaves unchanged (a mesh deflection,
        w . Phi zero but for rounding) gets exactly nothing."""
        if not self.active:
            return 0.0
        gains = weights @ self.modes
        scale = np.abs(weights) @ np.abs(self.modes)
        gains = np.where(np.abs(gains) <= 1e-12 * scale, 0.0, gains)
        return float(gains @ state["rigid_offset"])

    def displacement(self, state: dict) -> np.ndarray:
        """The rigid-body displacement taken out so far (kernel order)."""
        if not self.active:
            return np.zeros(0)
        return self.modes @ state["rigid_offset"]


RIGID_MODES_SOUGHT = 6
"""Lowest modes a sparse model is searched for rigid-body motions (a free body has 6)."""


def _sparse_rigid_modes(mass, stiffness) -> np.ndarray | None:
    """Mass-normalised rigid-body modes of a large sparse model, or None.

    Shift-invert Lanczos (SciPy ``eigsh``) for the :data:`RIGID_MODES_SOUGHT` lowest
    modes of (K0, M), shifted below zero so that K0 - sigma M is positive definite; a
    mode is rigid by :func:`pygear.rigid_modes.rigid_body_mask` with the largest
    diagonal ratio K_ii / M_ii as the scale (a lower bound of the largest eigenvalue).
    """
    import scipy.sparse
    import scipy.sparse.linalg

    n = mass.shape[0]
    stiffness = scipy.sparse.csc_matrix(stiffness)
    mass = scipy.sparse.csc_matrix(mass)
    diagonal_mass = mass.diagonal()
    if n < 3 or not np.all(diagonal_mass > 0):
        return None
    ratios = np.abs(stiffness.diagonal()) / diagonal_mass
    scale = max(float(ratios.max()), 1e-300)
    shift = -1e-6 * max(float(np.median(ratios[ratios > 0])) if np.any(ratios > 0) else 1.0, 1e-300)
    try:
        values, vectors = scipy.sparse.linalg.eigsh(
            stiffness, k=min(RIGID_MODES_SOUGHT, n - 2), M=mass, sigma=shift, which="LM"
        )
    except (RuntimeError, ValueError, scipy.sparse.linalg.ArpackError):
        return None
    rigid = vectors[:, rigid_body_mask(values, scale)]
    # eigsh's vectors are M-orthonormal; orthonormalise again against rounding
    if rigid.shape[1] > 1:
        gram = rigid.T @ (mass @ rigid)
        rigid = rigid @ np.linalg.inv(np.linalg.cholesky(gram)).T
    return rigid
