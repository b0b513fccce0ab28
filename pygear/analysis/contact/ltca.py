"""Loaded tooth contact analysis of one mesh (:mod:`pygear.assembly.ltca`).

The solver lives in the assembly layer because the ``loaded_contact`` mesh law
(:mod:`pygear.assembly.mesh_laws`) tabulates it when a case's model is assembled; this
module keeps its names where the analysis topics look for them.
"""

from ...assembly.ltca import (
    _count,
    contact_dataset,
    loaded_contact,
    solve_slices,
    te_harmonics,
)

__all__ = ["_count", "contact_dataset", "loaded_contact", "solve_slices", "te_harmonics"]
