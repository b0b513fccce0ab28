"""pygear: gearbox dynamics for wind-turbine drivetrains.

Rigid multibody models of planetary and parallel gear stages (the improved model of
Yang, Jiang & Han 2016, a kinetically consistent variant, and Lin & Parker 1999),
assembled from Fortran element matrices, with modal analysis and sensitivities.

The public names below load on first use (PEP 562), so ``import pygear`` and the
``pygear`` command's parser do not load NumPy and the model until something asks.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

# first: loads the kernel's OpenBLAS so that the extension finds it wherever installed
# (ctypes and one dlopen, a few milliseconds; NumPy is not imported)
from . import _blas  # noqa: F401  isort: skip
from ._version import __version__ as __version__
from .errors import CaseError

if TYPE_CHECKING:
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
    from .model.drivetrain import (
        Coupling,
        Drivetrain,
        GearboxMount,
        Generator,
        Rotor,
        Shaft,
        ShaftBearing,
        ShaftSection,
    )
    from .model.gear_geometry import GearGeometry
    from .model.gearbox import Gearbox, ParallelStage, RigidLink, ShaftInertia, TorsionalSpring
    from .model.micro_geometry import (
        Deviations,
        EndRelief,
        Misalignment,
        Modifications,
        ProfileRelief,
    )
    from .model.rating import DutyCycle, Material, Rating, RollingBearingData
    from .model.reduction_settings import Reductions
    from .model.response_settings import Response
    from .model.rolling_bearing import BearingDefect, DistributedFault, RollingBearing
    from .model.rotor import BearingCoefficients, Disc
    from .model.rotor_case import RotorCase
    from .model.sensors import Sensor, StructuralMode
    from .model.transient_settings import Probe, TorqueLaw, Transient

_SOURCES = {
    ".model.case": ("Case", "RayleighDamping", "Scene", "load_case"),
    ".model.components": (
        "Bearing",
        "Body",
        "Carrier",
        "Gear",
        "Mesh",
        "PlanetaryStage",
        "PlanetBearing",
        "ToothDefect",
    ),
    ".model.drivetrain": (
        "Coupling",
        "Drivetrain",
        "GearboxMount",
        "Generator",
        "Rotor",
        "Shaft",
        "ShaftBearing",
        "ShaftSection",
    ),
    ".model.gear_geometry": ("GearGeometry",),
    ".model.gearbox": ("Gearbox", "ParallelStage", "RigidLink", "ShaftInertia", "TorsionalSpring"),
    ".model.rating": ("DutyCycle", "Material", "Rating", "RollingBearingData"),
    ".model.micro_geometry": (
        "Deviations",
        "EndRelief",
        "Misalignment",
        "Modifications",
        "ProfileRelief",
    ),
    ".model.reduction_settings": ("Reductions",),
    ".model.response_settings": ("Response",),
    ".model.rolling_bearing": ("BearingDefect", "DistributedFault", "RollingBearing"),
    ".model.rotor": ("BearingCoefficients", "Disc"),
    ".model.rotor_case": ("RotorCase",),
    ".model.sensors": ("Sensor", "StructuralMode"),
    ".model.transient_settings": ("Probe", "TorqueLaw", "Transient"),
}
_MODULE_OF = {name: module for module, names in _SOURCES.items() for name in names}
"""The module each lazily loaded public name comes from."""


def __getattr__(name: str) -> object:
    module = _MODULE_OF.get(name)
    if module is None:
        raise AttributeError(f"module 'pygear' has no attribute {name!r}")
    value = getattr(importlib.import_module(module, __name__), name)
    globals()[name] = value  # the next access is a plain attribute
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_MODULE_OF))


__all__ = [
    "Bearing",
    "BearingCoefficients",
    "BearingDefect",
    "Body",
    "Carrier",
    "Case",
    "CaseError",
    "Coupling",
    "Deviations",
    "Disc",
    "DistributedFault",
    "Drivetrain",
    "DutyCycle",
    "EndRelief",
    "Gear",
    "GearGeometry",
    "Gearbox",
    "GearboxMount",
    "Generator",
    "Material",
    "Mesh",
    "Misalignment",
    "Modifications",
    "ParallelStage",
    "PlanetBearing",
    "PlanetaryStage",
    "Probe",
    "ProfileRelief",
    "Rating",
    "RayleighDamping",
    "Reductions",
    "Response",
    "RigidLink",
    "RollingBearing",
    "RollingBearingData",
    "Rotor",
    "RotorCase",
    "Scene",
    "Sensor",
    "Shaft",
    "ShaftBearing",
    "ShaftInertia",
    "ShaftSection",
    "StructuralMode",
    "ToothDefect",
    "TorqueLaw",
    "TorsionalSpring",
    "Transient",
    "load_case",
]
