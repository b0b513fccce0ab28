"""Modal analysis of a drivetrain model: its lowest modes by shift-invert Lanczos.

A drivetrain model is sparse and larger than a gearbox's, so only the lowest ``modes``
are computed, by :func:`pygear.analysis.modes.sparse_modal.sparse_modes`: shift-invert
Lanczos (Ericsson & Ruhe 1980) with a negative shift, so that the free rotation is
found and K - sigma M stays positive definite.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...assembly.drivetrain import DrivetrainModel
from .sparse_modal import sparse_modes

__all__ = ["DrivetrainModes", "drivetrain_modes", "modal_damping_ratios"]

ZERO_FREQUENCY = 1e-3
"""Frequencies below this [Hz] are rigid-body motions, reported as 0 Hz."""


@dataclass(frozen=True)
class DrivetrainModes:
    """The lowest modes of a drivetrain model.

    Attributes
    ----------
    frequencies_hz : ndarray
        Natural frequencies [Hz], ascending; rigid-body motions as 0.
    shapes : ndarray
        Mass-normalised mode shapes, one column per mode.
    dominant : list of str
        The DOF label holding the largest kinetic-energy share of each mode.
    solves : int
        Solves with the factor of K - sigma M the Lanczos iterations made (0 when the
        model was small enough for the dense solver): tens for tens of modes.
    """

    frequencies_hz: np.ndarray
    shapes: np.ndarray
    dominant: list[str]
    solves: int = 0


def drivetrain_modes(
    model: DrivetrainModel, modes: int = 20, *, below_hz: float | None = None
) -> DrivetrainModes:
    """The ``modes`` lowest modes of ``model`` (all of them when it has fewer DOFs), or,
    with ``below_hz``, exactly the modes below that frequency [Hz]."""
    result = sparse_modes(
        model.stiffness, model.mass, modes=min(int(modes), model.size - 1), below_hz=below_hz
    )
    frequencies = np.array(result.frequencies_hz, dtype=float)
    frequencies[frequencies < ZERO_FREQUENCY] = 0.0
    shapes = result.shapes
    energy = shapes * (model.mass @ shapes)
    dominant = [model.labels[i] for i in np.argmax(energy, axis=0)]
    return DrivetrainModes(frequencies, shapes, dominant, result.solves)


def modal_damping_ratios(model: DrivetrainModel, modes: DrivetrainModes) -> np.ndarray:
    """zeta = phi^T C phi / (2 omega) of every elastic mode (mass-normalised shapes);
    exact for classically damped modes, a first-order estimate otherwise.  NaN for the
    rigid-body modes."""
    omega = 2.0 * np.pi * modes.frequencies_hz
    damping = np.einsum("im,im->m", modes.shapes, model.damping @ modes.shapes)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(omega > 0, damping / (2.0 * omega), np.nan)
