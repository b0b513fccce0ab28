"""Rows of the DOF map: a named DOF, and the free rigid-body rotation, in reduced DOFs.

Both read only the assembled :class:`~pygear.assembly.matrices.Model`; the contact
table (mesh senses), the transient (speeds, kinematic ratios) and the output probes use
them.
"""

from __future__ import annotations

import numpy as np

from ..rigid_modes import rigid_body_mask
from .matrices import Model

__all__ = ["dof_row", "rigid_rotation"]


def dof_row(model: Model, label: str) -> np.ndarray | None:
    """Weights w with (the DOF ``label``) = w . q, from the reduction matrix; None if unknown.

    A DOF tied to another (a planet's phi, a rigid link) gets its tie's weights; a
    fixed DOF gets zeros.
    """
    try:
        index = model.full_labels.index(label)
    except ValueError:
        return None
    return np.array(model.reduction[index], dtype=np.float64)


def rigid_rotation(model: Model) -> np.ndarray | None:
    """The model's free rigid-body rotation as reduced DOF amplitudes, or None.

    The eigenvector of the lowest eigenvalue of (K0, M) when exactly one eigenvalue
    is zero (:func:`pygear.rigid_modes.rigid_body_mask`); its sign is arbitrary, so
    callers use ratios.
    """
    from ..linalg import generalized_eigh

    values, vectors = generalized_eigh(model.stiffness, model.mass)
    zero = rigid_body_mask(values)
    if zero.sum() != 1:
        return None
    return vectors[:, int(np.argmax(zero))]
