"""Sparse assembly of flexible drivetrain structures: shafts, discs, bearings, couplings.

A :class:`Structure` holds named nodes of six DOFs each (:data:`NODE_DOFS`) and the
elements placed on them (:class:`~pygear.assembly.shaft_elements.ElementMatrices`);
:meth:`Structure.assemble` adds the element matrices through COO triplets into SciPy
CSC matrices, never forming a dense n x n matrix, so that models of tens of thousands of
DOFs assemble in a fraction of a second.  Equations and conventions:
docs/shaft_elements.md.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..errors import CaseError
from ..model.components import require_positive
from .shaft_elements import ElementMatrices, shaft_element

__all__ = ["NODE_DOFS", "Structure", "StructureMatrices"]

NODE_DOFS = ("x", "y", "z", "theta_x", "theta_y", "theta_z")
"""The DOFs of every node, in order; a DOF's label is ``f"{node}.{dof}"``."""

_MATRIX_NAMES = ("mass", "stiffness", "damping", "gyroscopic")


@dataclass(frozen=True)
class StructureMatrices:
    """Assembled matrices of a structure: ``M q'' + (C + Omega G) q' + K q = F``.

    Attributes
    ----------
    labels : tuple of str
        One label ``"node.dof"`` per row and column.
    mass, stiffness, damping, gyroscopic : scipy.sparse.csc_matrix
        n x n matrices [SI]; G per unit spin speed [kg m^2].
    """

    labels: tuple[str, ...]
    mass: sp.csc_matrix
    stiffness: sp.csc_matrix
    damping: sp.csc_matrix
    gyroscopic: sp.csc_matrix

    @property
    def size(self) -> int:
        """Number of DOFs n."""
        return len(self.labels)

    def indices(self, dof: str) -> np.ndarray:
        """Positions of every DOF named ``dof`` (one of :data:`NODE_DOFS`), in node order."""
        if dof not in NODE_DOFS:
            raise CaseError(f"dof must be one of {', '.join(NODE_DOFS)} (got {dof!r})")
        suffix = "." + dof
        return np.array([i for i, label in enumerate(self.labels) if label.endswith(suffix)])

    def select(self, keep: Sequence[int] | np.ndarray) -> StructureMatrices:
        """The rows and columns ``keep`` (positions, or a boolean mask of length n).

        Dropping a DOF clamps it (its value held at zero); keeping a subset is exact for
        the dynamics only when nothing couples it to the DOFs left out.
        """
        keep = np.asarray(keep)
        if keep.dtype == bool:
            if keep.shape != (self.size,):
                raise CaseError(f"keep as a mask must have {self.size} entries (got {keep.shape})")
            keep = np.flatnonzero(keep)
        if keep.size and (keep.min() < 0 or keep.max() >= self.size):
            raise CaseError(f"keep must hold DOF positions in [0, {self.size})")
        matrices = {name: getattr(self, name)[keep][:, keep].tocsc() for name in _MATRIX_NAMES}
        return StructureMatrices(tuple(self.labels[i] for i in keep), **matrices)

    def torsional(self) -> StructureMatrices:
        """Only the theta_z rows and columns: the torsional model.

        Exact when nothing couples torsion to the other DOFs
        (:meth:`torsion_is_decoupled`), as for shafts, discs, diagonal bearings and
        couplings on one axis; otherwise the other DOFs are clamped.
        """
        return self.select(self.indices("theta_z"))

    def torsion_is_decoupled(self) -> bool:
        """True when no matrix has an entry between a theta_z DOF and any other DOF."""
        torsion = np.zeros(self.size, dtype=bool)
        torsion[self.indices("theta_z")] = True
        for name in _MATRIX_NAMES:
            coo = getattr(self, name).tocoo()
            if np.any((torsion[coo.row] != torsion[coo.col]) & (coo.data != 0)):
                return False
        return True


class Structure:
    """Named nodes of six DOFs and the elements placed on them.

    Examples
    --------
    >>> from pygear.assembly.shaft_elements import bearing_element
    >>> structure = Structure()
    >>> shaft = structure.add_shaft("rotor", length=2.0, outer_diameter=0.1, elements=8)
    >>> structure.add_ground_element(shaft[0], bearing_element([1e8] * 6))
    >>> matrices = structure.assemble()
    """

    def __init__(self) -> None:
        self._names: list[str] = []
        self._index: dict[str, int] = {}
        self._placed: dict[int, tuple[list[np.ndarray], list[ElementMatrices]]] = {
            6: ([], []),
            12: ([], []),
        }

    @property
    def node_count(self) -> int:
        """Number of nodes."""
        return len(self._names)

    @property
    def dof_count(self) -> int:
        """Number of DOFs, six per node."""
        return 6 * len(self._names)

    @property
    def node_names(self) -> tuple[str, ...]:
        """Node names in index order."""
        return tuple(self._names)

    @property
    def labels(self) -> tuple[str, ...]:
        """DOF labels ``"node.dof"`` in assembly order."""
        return tuple(f"{name}.{dof}" for name in self._names for dof in NODE_DOFS)

    def node(self, name: str) -> int:
        """Index of the node called ``name``."""
        try:
            return self._index[name]
        except KeyError:
            raise CaseError(f"node {name!r} is not in the structure") from None

    def add_node(self, name: str) -> int:
        """Add a node of six DOFs and return its index.

        Parameters
        ----------
        name : str
            Unique, non-empty, without '.' (the DOF labels are ``f"{name}.{dof}"``).
        """
        if not isinstance(name, str) or not name or "." in name or name != name.strip():
            raise CaseError(f"node name must be a non-empty string without '.' (got {name!r})")
        if name in self._index:
            raise CaseError(f"node name {name!r} is already in the structure")
        self._index[name] = len(self._names)
        self._names.append(name)
        return self._index[name]

    def add_element(self, nodes: Sequence[int] | int, element: ElementMatrices) -> None:
        """Place an element on one node (6 x 6) or two distinct nodes (12 x 12).

        Parameters
        ----------
        nodes : sequence of int, or int
            Node indices, in the order of the element's DOFs.
        element : ElementMatrices
            Its size must be 6 times the number of nodes.
        """
        nodes = [nodes] if isinstance(nodes, (int, np.integer)) else list(nodes)
        if not isinstance(element, ElementMatrices):
            raise CaseError(f"element must be an ElementMatrices (got {type(element).__name__})")
        if len(nodes) not in (1, 2):
            raise CaseError(f"nodes must name 1 or 2 nodes (got {len(nodes)})")
        for node in nodes:
            self._check_node("nodes", node)
        if len(nodes) == 2 and nodes[0] == nodes[1]:
            raise CaseError(f"nodes must be two different nodes (got {nodes[0]} twice)")
        if element.size != 6 * len(nodes):
            raise CaseError(
                f"element must be {6 * len(nodes)} x {6 * len(nodes)} for {len(nodes)} node(s) "
                f"(got {element.size} x {element.size})"
            )
        dofs = (6 * np.asarray(nodes, dtype=np.int64)[:, None] + np.arange(6)).ravel()
        positions, elements = self._placed[element.size]
        positions.append(dofs)
        elements.append(element)

    def add_ground_element(self, node: int, element: ElementMatrices) -> None:
        """Place a 6 x 6 element between a node and the ground (a bearing, a disc)."""
        if not isinstance(element, ElementMatrices) or element.size != 6:
            raise CaseError("element must be a 6 x 6 ElementMatrices to connect a node to ground")
        self.add_element([node], element)

    def add_shaft(
        self,
        name: str,
        length: float,
        outer_diameter: float,
        inner_diameter: float = 0.0,
        elements: int = 4,
        youngs_modulus: float = 2.1e11,
        shear_modulus: float | None = None,
        density: float = 7850.0,
        shear_deformation: bool = True,
        shear_coefficient: float | None = None,
        rotary_inertia: bool = True,
        start_node: int | None = None,
    ) -> list[int]:
        """Add a uniform shaft along z of ``elements`` equal Timoshenko elements.

        Parameters
        ----------
        name : str
            New nodes are called ``f"{name}_{i}"``, i = 0 .. elements (0 is skipped when
            ``start_node`` is given).
        length : float
            Shaft length [m].
        outer_diameter, inner_diameter, youngs_modulus, shear_modulus, density,
        shear_deformation, shear_coefficient, rotary_inertia
            As :func:`~pygear.assembly.shaft_elements.shaft_element`.
        elements : int
            Number of elements >= 1.
        start_node : int, optional
            An existing node the shaft starts at (a coupling or gear node).

        Returns
        -------
        list of int
            The elements + 1 node indices from start to end.
        """
        if (
            isinstance(elements, bool)
            or not isinstance(elements, (int, np.integer))
            or elements < 1
        ):
            raise CaseError(f"elements must be a whole number >= 1 (got {elements!r})")
        if start_node is not None:
            self._check_node("start_node", start_node)
        require_positive("length", length)
        element = shaft_element(
            length / elements,
            outer_diameter,
            inner_diameter,
            youngs_modulus=youngs_modulus,
            shear_modulus=shear_modulus,
            density=density,
            shear_deformation=shear_deformation,
            shear_coefficient=shear_coefficient,
            rotary_inertia=rotary_inertia,
        )
        new_names = [f"{name}_{i}" for i in range(0 if start_node is None else 1, elements + 1)]
        taken = [n for n in new_names if n in self._index]
        if taken:
            raise CaseError(f"name {name!r} gives node {taken[0]!r}, already in the structure")
        nodes = [] if start_node is None else [int(start_node)]
        nodes += [self.add_node(node_name) for node_name in new_names]
        pairs = np.column_stack([nodes[:-1], nodes[1:]]).astype(np.int64)
        dofs = (6 * pairs[:, :, None] + np.arange(6)).reshape(len(pairs), 12)
        positions, placed = self._placed[12]
        positions.extend(dofs)
        placed.extend([element] * len(pairs))
        return nodes

    def assemble(self) -> StructureMatrices:
        """Sum every element into n x n CSC matrices (COO triplets, duplicates added).

        Returns
        -------
        StructureMatrices
            Zero entries of the element matrices are not stored; a sum that cancels (the
            w-psi terms at the inner nodes of a uniform shaft) stays a stored zero, so
            the pattern of each matrix is the structural one, whatever the values.
        """
        n = self.dof_count
        triplets: dict[str, list[tuple[np.ndarray, np.ndarray, np.ndarray]]] = {
            name: [] for name in _MATRIX_NAMES
        }
        for size, (positions, placed) in self._placed.items():
            if not placed:
                continue
            dofs = np.stack(positions)
            rows = np.broadcast_to(dofs[:, :, None], (len(dofs), size, size))
            cols = np.broadcast_to(dofs[:, None, :], (len(dofs), size, size))
            distinct, order = _distinct_elements(placed)
            for name in _MATRIX_NAMES:
                values = np.stack([getattr(element, name) for element in distinct])[order]
                nonzero = values != 0
                triplets[name].append((values[nonzero], rows[nonzero], cols[nonzero]))
        matrices = {name: _csc(parts, n) for name, parts in triplets.items()}
        return StructureMatrices(self.labels, **matrices)

    def _check_node(self, name: str, node: object) -> None:
        if (
            isinstance(node, bool)
            or not isinstance(node, (int, np.integer))
            or not 0 <= node < len(self._names)
        ):
            raise CaseError(
                f"{name} must be node indices in [0, {len(self._names)}) (got {node!r})"
            )


def _distinct_elements(placed: list[ElementMatrices]) -> tuple[list[ElementMatrices], np.ndarray]:
    """The distinct element objects of ``placed`` (a shaft places one element many times)
    and, for each placed element, its position among them."""
    position: dict[int, int] = {}
    distinct: list[ElementMatrices] = []
    order = np.empty(len(placed), dtype=np.int64)
    for i, element in enumerate(placed):
        k = position.get(id(element))
        if k is None:
            k = position[id(element)] = len(distinct)
            distinct.append(element)
        order[i] = k
    return distinct, order


def _csc(parts: list[tuple[np.ndarray, np.ndarray, np.ndarray]], n: int) -> sp.csc_matrix:
    if parts:
        data, rows, cols = (np.concatenate(column) for column in zip(*parts))
    else:
        data, rows, cols = np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    matrix = sp.csc_matrix((data, (rows, cols)), shape=(n, n))
    matrix.sum_duplicates()
    return matrix
