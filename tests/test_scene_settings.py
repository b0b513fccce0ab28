"""A scene resolved into SceneSettings: what it keeps, and that assembly reads only that."""

from __future__ import annotations

import dataclasses

import numpy as np

from pygear import ToothDefect, load_case
from pygear.assembly import assemble
from pygear.model.scene_settings import SceneSettings, scene_settings

CASE = "yang2016_planetary"


def test_settings_keep_what_assembly_and_the_kernel_need():
    case = load_case(CASE)
    scene = dataclasses.replace(
        case.scene("runup"),
        carrier_speed_rpm=30.0,
        defects=(ToothDefect(gear="planetary.sun", tooth=3, factor=0.5),),
    )
    settings = scene_settings(scene)
    assert settings == SceneSettings(
        name="runup",
        formulation="improved",
        dof_set="planar",
        effects=("time_varying_mesh_stiffness",),
        carrier_speed_rpm=30.0,
        defects=(ToothDefect(gear="planetary.sun", tooth=3, factor=0.5),),
        probes=tuple(scene.transient.probes),
    )
    assert len(settings.probes) > 0  # the study case's runup keeps speeds and accelerations
    assert scene_settings(settings) is settings
    assert scene_settings(None) is None


def test_assembly_of_a_scene_is_assembly_of_its_settings():
    case = load_case(CASE)
    scene = case.scene("runup")
    from_scene = assemble(case, scene)
    from_settings = assemble(case, scene_settings(scene))
    # one code path on the same numbers (the Scene is resolved first either way), so
    # the matrices agree exactly
    for name in ("mass", "stiffness", "damping", "reduction"):
        np.testing.assert_array_equal(getattr(from_scene, name), getattr(from_settings, name))
    assert from_scene.dof_labels == from_settings.dof_labels
    assert from_scene.attributes == from_settings.attributes
    assert from_scene.dof_set_reason == "set by scene 'runup'"


def test_settings_alone_decide_the_model():
    # settings that no scene of the case holds: the DOF set, formulation and carrier speed
    # they name are the model's
    case = load_case(CASE)
    settings = SceneSettings(
        name="made_up", formulation="consistent", dof_set="torsional", carrier_speed_rpm=60.0
    )
    model = assemble(case, settings)
    assert model.formulation == "consistent"
    assert model.dof_set == "torsional"
    assert model.dof_set_reason == "set by scene 'made_up'"
    assert model.attributes["carrier_speed_rpm"] == 60.0
    # torsional: rotations about z only (a planet's revolution phi is tied to its carrier)
    assert all(label.endswith(("theta_z", "phi")) for label in model.dof_labels)
