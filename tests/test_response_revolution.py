"""A mesh periodic over a gear revolution is refused by the harmonic balance.

The balance samples one mesh period; a tooth fault or a per-tooth deviation makes a
mesh repeat once per revolution of its gear, so the balance must refuse it in one line
rather than answer for a mesh period it did not represent.
"""

from __future__ import annotations

import dataclasses

import pytest

from pygear.analysis.response import response_system
from pygear.errors import CaseError
from pygear.model.case import load_case


@pytest.mark.parametrize(
    ("case_name", "scene_name", "mesh"),
    [
        ("sequential_planetary", "sun_crack", "sun-planet1"),
        ("sequential_planetary", "planet_missing_tooth", "sun-planet1"),
        ("loaded_contact_planetary", "sun_pitch_error", "sun-planet1"),
    ],
)
def test_a_tooth_of_its_own_is_refused_naming_the_mesh(case_name, scene_name, mesh):
    case = load_case(case_name)
    scene = case.scene(scene_name)
    with pytest.raises(CaseError, match=rf"{mesh}.*once per gear revolution"):
        response_system(case, scene)


def test_the_same_scene_without_its_defect_is_balanced():
    case = load_case("sequential_planetary")
    scene = dataclasses.replace(case.scene("sun_crack"), defects=())
    system = response_system(case, scene)
    assert system.stiffness.shape[1] == len(system.mean_stiffness)
