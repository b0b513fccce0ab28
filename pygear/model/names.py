"""The names a case and the command line choose from: formulations, DOF sets and
mesh stiffness laws.

Plain tuples of text, importing nothing, so that the ``pygear`` parser lists its
choices without loading NumPy or the model (``pygear --help``).  The model's modules
re-export them (:mod:`pygear.model.case`, :mod:`pygear.model.geometry_inputs`).
"""

__all__ = ["DOF_SETS", "FORMULATIONS", "LAWS"]

FORMULATIONS = ("improved", "consistent", "lin-parker")
"""Model formulations (docs/model.md §3.1 and §4)."""

DOF_SETS = ("spatial", "planar", "torsional")
"""DOF sets: all six/seven DOFs, the in-plane ones, or the rotations only."""

LAWS = ("parabola", "tabulated", "helical", "iso6336", "potential_energy", "loaded_contact")
"""Single-pair stiffness laws a :class:`~pygear.model.components.Mesh` may name."""
