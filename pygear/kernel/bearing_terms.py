"""Rolling bearings as the Newmark kernel takes them (``fortran/rolling_bearing.f90``).

:class:`BearingTerms` holds, for every bearing, the element count, the constants of its
Hertz law, the linear spring it replaces, four rows over the DOFs (the inner ring's
displacement relative to the outer one, x and y, and the two rings' angles) and its
defects.  :func:`bearing_arguments` packs them for ``transient_problem_bearings``.
Nothing here knows about gearboxes: :mod:`pygear.analysis.time.bearing_element`
builds the terms from a case's rolling bearings.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["BearingTerms", "BEARING_PARAM_LAYOUT", "DEFECT_KINDS", "RINGS", "bearing_arguments"]

BEARING_PARAM_LAYOUT = (
    "constant",  # K_n [N/m^n]
    "exponent",  # n [-]
    "clearance",  # P_d [m]
    "cos_alpha",  # [-]
    "cage_inner",  # (1 - gamma) / 2 [-]
    "cage_outer",  # (1 + gamma) / 2 [-]
    "spring",  # k_r, the radial spring inside K0 [N/m]
    "damping",  # c_c, viscous damping per loaded contact [N s/m]
)
"""Order of the constants per bearing (the kernel's ``bp_*``)."""

RINGS = {"outer": 1, "inner": 2}
"""Kernel codes of the ring a defect lies on."""

DEFECT_KINDS = {"spall": 1, "waviness": 2}
"""Kernel codes of the defect kinds."""


@dataclass(frozen=True)
class BearingTerms:
    """The rolling bearings of a transient problem, in the caller's DOF order.

    Parameters
    ----------
    names : tuple of str
        One name per bearing, for messages.
    elements : ndarray of int, shape (n_bearing,)
        Rolling elements per row Z.
    param : ndarray, shape (8, n_bearing)
        Constants in :data:`BEARING_PARAM_LAYOUT` order [SI].
    rows : ndarray, shape (4 n_bearing, n)
        x, y [m/m] and theta_inner, theta_outer [rad/rad] rows of each bearing.
    defects : ndarray of int, shape (3, n_defect)
        Bearing (1-based), ring (:data:`RINGS`) and kind (:data:`DEFECT_KINDS`).
    defect_values : ndarray, shape (3, n_defect)
        Angle on the ring [rad]; angular width [rad] (spall) or order [-] (waviness);
        depth or amplitude [m].
    """

    names: tuple[str, ...]
    elements: np.ndarray
    param: np.ndarray
    rows: np.ndarray
    defects: np.ndarray
    defect_values: np.ndarray

    @property
    def size(self) -> int:
        """Number of bearings."""
        return len(self.names)

    def row_sets(self, index: int) -> np.ndarray:
        """The four rows (x, y, theta_inner, theta_outer) of bearing ``index``."""
        return self.rows[4 * index : 4 * index + 4]


def bearing_arguments(terms: BearingTerms, position: np.ndarray) -> dict:
    """Keyword arguments of ``transient_problem_bearings`` (rows in the kernel's order:
    ``position[i]`` is the kernel's place of the caller's DOF i)."""
    pointers, index, value = [0], [], []
    for row in terms.rows:
        nz = np.nonzero(row)[0]
        index.extend(position[nz] + 1)
        value.extend(np.asarray(row)[nz])
        pointers.append(len(index))
    n_defect = terms.defects.shape[1]
    defects = terms.defects if n_defect else np.ones((3, 1), dtype=np.int32)
    values = terms.defect_values if n_defect else np.zeros((3, 1))
    return {
        "elements": np.asarray(terms.elements, dtype=np.int32),
        "param": np.asfortranarray(terms.param, dtype=np.float64),
        "rows_ptr": np.array(pointers, dtype=np.int32),
        "rows_index": np.array(index or [1], dtype=np.int32),
        "rows_value": np.array(value or [0.0], dtype=np.float64),
        "n_defect": n_defect,
        "defect": np.asfortranarray(defects, dtype=np.int32),
        "defect_value": np.asfortranarray(values, dtype=np.float64),
    }
