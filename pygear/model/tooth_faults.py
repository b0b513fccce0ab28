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

__all__ = ["ChippedTooth", "RootCrack", "Spall", "ToothFault"]


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
