"""The split of pygear/model/components.py by component family (issue #28.4).

Each family (bodies, bearings, meshes, planetary stage, tooth defects) is a module of
its own with its validation beside its fields; ``pygear.model.components`` and
``pygear`` still give every name they gave before the split, as the same objects.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import pickle
from pathlib import Path

import pytest

import pygear
from pygear.model import components

FAMILIES = {
    "pygear.model.bodies": ("Body", "Gear", "Carrier"),
    "pygear.model.bearings": ("Bearing", "PlanetBearing"),
    "pygear.model.meshes": ("Mesh",),
    "pygear.model.planetary": ("PlanetaryStage",),
    "pygear.model.defects": ("ToothDefect",),
}
"""Family module -> the component classes it holds."""

BEFORE_SPLIT = (
    "Bearing", "Body", "CaseError", "Gear", "Mesh", "PlanetBearing", "PlanetaryStage",
    "Carrier", "ToothDefect", "validate_component", "plain_numbers", "require_positive",
    "require_non_negative", "require_axial_position", "require_matching_teeth",
    "derived_record", "looks_like_radians", "is_finite_number", "is_whole_number",
    "AXIAL_LIMIT", "MAGNITUDE_LIMIT", "DEFAULT_BORE_RATIO", "MODULE_PRESSURE_ANGLE_DEG",
    "TOOTH_RATIO_TOLERANCE", "MAX_CONTACT_RATIO",
)  # fmt: skip
"""Names other modules imported from pygear.model.components before the split."""


@pytest.mark.parametrize("name", BEFORE_SPLIT)
def test_every_name_of_components_before_the_split_is_still_there(name):
    assert hasattr(components, name), name


@pytest.mark.parametrize(("module", "names"), FAMILIES.items())
def test_each_family_holds_its_classes_with_their_validation(module, names):
    family = importlib.import_module(module)
    for name in names:
        cls = getattr(family, name)
        assert cls.__module__ == module
        # the rules that name a parameter sit in the same file as the parameter
        assert inspect.getsourcefile(cls.validate) == inspect.getsourcefile(family)
        # the same object from the old module and from the package
        assert getattr(components, name) is cls
        assert getattr(pygear, name) is cls


@pytest.mark.parametrize("module", [*FAMILIES, "pygear.model.component_rules"])
def test_family_modules_stay_under_600_lines(module):
    path = Path(inspect.getsourcefile(importlib.import_module(module)))
    assert len(path.read_text().splitlines()) <= 600


def test_components_module_is_only_the_gathering_of_the_families():
    source = Path(inspect.getsourcefile(components)).read_text()
    tree = ast.parse(source)
    assert not [n for n in tree.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))]
    assert len(source.splitlines()) < 120  # was 888 lines


def test_a_pickled_case_from_the_new_modules_loads(study_case):
    gearbox = pickle.loads(pickle.dumps(study_case.gearbox))
    assert gearbox == study_case.gearbox
    assert type(gearbox.stages[0].sun) is components.Gear
