"""A scene resolved into the plain settings that assembly and the kernel receive.

A :class:`~pygear.model.case.Scene` says what to run (analyses, parameters to change,
transient settings).  Assembly and the kernel need only a few of its values: the
formulation and DOF set it asks for, its effects, the carrier speed of the
speed-dependent terms, its tooth defects (on top of the case's, for the contact table)
and its output probes.  :func:`scene_settings` copies those once, so nothing below the
analysis layer reads a ``Scene``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from .components import ToothDefect
from .transient_settings import Probe

if TYPE_CHECKING:
    from .case import Scene

__all__ = ["SceneSettings", "scene_settings"]


@dataclass(frozen=True)
class SceneSettings:
    """What assembly and the kernel take from a scene.

    Attributes
    ----------
    name : str
        The scene's name, for messages (``set by scene 'runup'``).
    formulation : str or None
        The formulation the scene asks for; None leaves the case's.
    dof_set : str or None
        The DOF set the scene asks for; None lets assembly choose.
    effects : tuple of str
        Effects the scene calls for (``time_varying_mesh_stiffness``, ...).
    carrier_speed_rpm : float
        Carrier speed of the speed-dependent terms [rpm].
    defects : tuple of ToothDefect
        The scene's own tooth defects; a defect on a tooth the case's defects also
        name replaces the case's (:func:`pygear.model.case.merged_defects`).
    probes : tuple of Probe
        Output probes of the scene's transient (empty without one).
    """

    name: str
    formulation: str | None = None
    dof_set: str | None = None
    effects: tuple[str, ...] = ()
    carrier_speed_rpm: float = 0.0
    defects: tuple[ToothDefect, ...] = ()
    probes: tuple[Probe, ...] = ()


def scene_settings(scene: Scene | SceneSettings | None) -> SceneSettings | None:
    """The settings of ``scene`` (None stays None, settings stay as they are)."""
    if scene is None or isinstance(scene, SceneSettings):
        return scene
    return SceneSettings(
        name=scene.name,
        formulation=scene.formulation,
        dof_set=scene.dof_set,
        effects=tuple(scene.effects),
        carrier_speed_rpm=scene.carrier_speed_rpm,
        defects=tuple(scene.defects),
        probes=tuple(scene.transient.probes) if scene.transient is not None else (),
    )
