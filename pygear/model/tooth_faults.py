"""Faults of one tooth, as a case names them and the potential-energy method takes them.

A root crack (Tian 2004), a spall on the loaded flank (Chaari et al. 2008; Saxena et al.
2016) or a chipped tip.  :func:`pygear.assembly.tooth_stiffness.mesh_stiffness` turns one
into the damaged tooth's pair curve; a case's ``ToothDefect(fault=...)`` puts that curve
into the tooth-contact table while the tooth is in mesh.  ``packed`` is the row the
Fortran module ``tooth_potential_energy`` reads.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import CaseError
from . import gear_geometry as geo
from .values import is_finite_number

__all__ = [
    "ChippedTooth",
    "RootCrack",
    "Spall",
    "ToothFault",
    "check_fault_fields",
    "check_fault_on_tooth",
    "field_names",
]


@dataclass(frozen=True)
class RootCrack:
    """A straight crack from the root of the loaded flank (Tian 2004).

    The sections of the damaged width lose the part beyond the crack tip's distance from
    the centre line, h_q = h_root - depth sin(angle).

    Parameters
    ----------
    gear : int
        1 or 2: the gear with the cracked tooth.
    depth : float
        Crack length q [m].
    angle_deg : float
        Angle nu between the crack and the tooth centre line [deg], in (0, 90].
    face_start, face_width : float
        Where the crack lies along the face width [m], from the face end that enters the
        mesh first; ``face_width=None`` means through the whole face.
    """

    gear: int
    depth: float
    angle_deg: float
    face_start: float = 0.0
    face_width: float | None = None

    def packed(self, width: float) -> np.ndarray:
        span = width - self.face_start if self.face_width is None else self.face_width
        return np.array([1, self.gear, self.face_start, span,
                         self.depth, math.radians(self.angle_deg), 0.0, 0.0])  # fmt: skip


@dataclass(frozen=True)
class Spall:
    """A spall (or pit) on the loaded flank (Chaari et al. 2008; Saxena et al. 2016).

    Parameters
    ----------
    gear : int
        1 or 2: the gear with the spalled tooth.
    centre_radius : float
        Radius of the spall's centre on the flank [m].
    length : float
        Extent along the involute profile [m].
    depth : float
        Depth of the removed material [m].
    face_width : float
        Extent along the face width [m].
    face_start : float
        Start along the face width [m] from the end entering the mesh first.
    """

    gear: int
    centre_radius: float
    length: float
    depth: float
    face_width: float
    face_start: float = 0.0

    def packed(self, width: float) -> np.ndarray:
        return np.array([2, self.gear, self.face_start, self.face_width,
                         self.centre_radius, self.length, self.depth, 0.0])  # fmt: skip


@dataclass(frozen=True)
class ChippedTooth:
    """A tooth that lost its top: no contact beyond the chipped radius.

    Parameters
    ----------
    gear : int
        1 or 2: the gear with the chipped tooth.
    missing_fraction : float
        Lost fraction of the tooth height (tip to root circle) [-], in (0, 1]; 1 is a
        missing tooth.
    face_start, face_width : float
        Extent along the face width [m]; ``face_width=None``: the whole face.
    """

    gear: int
    missing_fraction: float
    face_start: float = 0.0
    face_width: float | None = None

    def packed(self, width: float) -> np.ndarray:
        span = width - self.face_start if self.face_width is None else self.face_width
        return np.array([3, self.gear, self.face_start, span,
                         self.missing_fraction, 0.0, 0.0, 0.0])  # fmt: skip


ToothFault = RootCrack | Spall | ChippedTooth


KERNEL_FIELDS = {
    RootCrack: ("depth", "angle_deg", None),
    Spall: ("centre_radius", "length", "depth"),
    ChippedTooth: ("missing_fraction", None, None),
}
"""The parameters a fault's packed slots a, b, c hold (the kernel's ``fp_a`` .. ``fp_c``)."""


def field_names(fault: object) -> tuple[str, ...]:
    """Names of a fault's packed slots kind, gear, face_start, face_width, a, b, c as the
    fault's own parameters (``a`` of a spall is ``centre_radius``), for error messages."""
    a, b, c = KERNEL_FIELDS.get(type(fault), ("a", "b", "c"))
    return ("kind", "gear", "face_start", "face_width", a or "a", b or "b", c or "c")


def check_fault_on_tooth(fault: object, gear: geo.GearGeometry, path: str) -> None:
    """Raise :class:`CaseError` when a fault lies off its tooth: a spall's centre off the
    involute flank (between the root form and tip circles), a crack deeper than the
    tooth is thick at its root, a face extent beyond the face width.

    ``path`` names the fault (``defects[0].fault``); the message names the fault's own
    parameter, its value in mm and the range the tooth allows.
    """
    width = gear.face_width
    start = fault.face_start
    if is_finite_number(start) and not 0 <= start < width:
        raise CaseError(
            f"{path}.face_start = {start!r} m must lie within the face width [0, {width * 1e3:.4g}"
            " mm) (a value in mm typed as m?)"
        )
    span = fault.face_width
    if span is not None and is_finite_number(span) and is_finite_number(start):
        if not 0 < span <= (width - start) * (1 + 1e-12):
            raise CaseError(
                f"{path}.face_width = {span!r} m must lie in (0, {(width - start) * 1e3:.4g} mm]: "
                "face_start + face_width within the gear's face width"
            )
    if isinstance(fault, Spall) and is_finite_number(fault.centre_radius):
        tip, form = geo.tip_radius(gear), geo.root_form_radius(gear)
        low, high = sorted((tip, form))
        if not low <= fault.centre_radius <= high:
            raise CaseError(
                f"{path}.centre_radius = {fault.centre_radius!r} m = "
                f"{fault.centre_radius * 1e3:.4g} mm is off the loaded flank: it must lie between "
                f"the {'tip' if gear.internal else 'root form'} radius {low * 1e3:.4g} mm and the "
                f"{'root form' if gear.internal else 'tip'} radius {high * 1e3:.4g} mm "
                "(a value in mm typed as m?)"
            )
    if isinstance(fault, RootCrack) and is_finite_number(fault.depth):
        pitch = math.pi * geo.transverse_module(gear)
        if fault.depth >= pitch:
            raise CaseError(
                f"{path}.depth = {fault.depth!r} m = {fault.depth * 1e3:.4g} mm must be below "
                f"the circular pitch {pitch * 1e3:.4g} mm (a crack through the whole tooth and "
                "beyond; a value in mm typed as m?)"
            )


def _require(path: str, name: str, value: object, *, zero: bool = False) -> None:
    ok = is_finite_number(value) and (value >= 0.0 if zero else value > 0.0)
    if not ok:
        rule = "a finite number >= 0" if zero else "a positive finite number"
        raise CaseError(f"{path}.{name} must be {rule} (got {value!r})")


def check_fault_fields(fault: object, path: str) -> None:
    """Raise :class:`CaseError` naming the first field of a fault that breaks its own rule
    (no tooth needed): the fault type, ``gear`` 1 or 2, face extent, crack depth and
    angle, spall radius, length and depth, the chipped fraction."""
    if not isinstance(fault, (RootCrack, Spall, ChippedTooth)):
        raise CaseError(f"{path} must be a RootCrack, Spall or ChippedTooth (got {fault!r})")
    if fault.gear not in (1, 2):
        raise CaseError(f"{path}.gear must be 1 or 2 (got {fault.gear!r})")
    _require(path, "face_start", fault.face_start, zero=True)
    if fault.face_width is not None:
        _require(path, "face_width", fault.face_width)
    if isinstance(fault, RootCrack):
        _require(path, "depth", fault.depth)
        if not (is_finite_number(fault.angle_deg) and 0.0 < fault.angle_deg <= 90.0):
            raise CaseError(f"{path}.angle_deg must lie in (0, 90] (got {fault.angle_deg!r})")
    elif isinstance(fault, Spall):
        for name in ("centre_radius", "length", "depth"):
            _require(path, name, getattr(fault, name))
    else:
        share = fault.missing_fraction
        if not (is_finite_number(share) and 0.0 < share <= 1.0):
            raise CaseError(f"{path}.missing_fraction must lie in (0, 1] (got {share!r})")
