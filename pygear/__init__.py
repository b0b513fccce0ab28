"""pygear: gearbox dynamics for wind-turbine drivetrains.

Rigid multibody models of planetary and parallel gear stages (the improved model of
Yang, Jiang & Han 2016, a kinetically consistent variant, and Lin & Parker 1999),
assembled from Fortran element matrices, with modal analysis and sensitivities.
"""

# first: loads the kernel's OpenBLAS so that the extension finds it wherever installed
from . import _blas  # noqa: F401  isort: skip
from ._version import __version__ as __version__
from .errors import CaseError
from .model.case import Case, RayleighDamping, Scene, load_case
from .model.components import (
    Bearing,
    Body,
    Carrier,
    Gear,
    Mesh,
    PlanetaryStage,
    PlanetBearing,
    ToothDefect,
)
from .model.gear_geometry import GearGeometry
from .model.gearbox import Gearbox, ParallelStage, RigidLink, ShaftInertia, TorsionalSpring
from .model.transient_settings import Probe, TorqueLaw, Transient

__all__ = [
    "Bearing",
    "Body",
    "Carrier",
    "Case",
    "CaseError",
    "Gear",
    "GearGeometry",
    "Gearbox",
    "Mesh",
    "ParallelStage",
    "RigidLink",
    "ShaftInertia",
    "TorsionalSpring",
    "PlanetBearing",
    "PlanetaryStage",
    "Probe",
    "RayleighDamping",
    "Scene",
    "ToothDefect",
    "TorqueLaw",
    "Transient",
    "load_case",
]
