"""Assembly: the DOF map, element placement, constraints, mesh phasing and the
tooth-contact table, from a model description to matrices the kernel integrates.

The assembled :class:`Model` and :func:`assemble` are re-exported from
:mod:`pygear.assembly.matrices`.
"""

from .matrices import (
    CENTRAL_DOFS,
    PLANET_DOFS,
    MassPart,
    MeshElement,
    Model,
    SpringElement,
    assemble,
    choose_dof_set,
)

__all__ = [
    "CENTRAL_DOFS",
    "PLANET_DOFS",
    "MassPart",
    "MeshElement",
    "Model",
    "SpringElement",
    "assemble",
    "choose_dof_set",
]
