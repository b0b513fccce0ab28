"""Mesh stiffness laws from gear geometry: ISO 6336-1:2019 method B.

The arithmetic runs in the Fortran kernel (module ``iso6336_stiffness``); this module
checks the arguments, derives the geometry the standard needs from a
:class:`pygear.model.MeshGeometry` and returns every factor.  Equations, sources and
limits: docs/gear_geometry.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import CaseError
from ..kernel import _kernel
from ..model import gear_geometry as geo
from ..model.components import is_finite_number

__all__ = ["IsoMeshStiffness", "iso6336_mesh_stiffness", "ISO_REFERENCE_LINE_LOAD"]

ISO_REFERENCE_LINE_LOAD = 100.0
"""K_A F_t / b [N/mm] at and above which ISO's single stiffness needs no load correction."""


@dataclass(frozen=True)
class IsoMeshStiffness:
    """ISO 6336-1 method B stiffness of one gear pair, with its factors.

    Per-width values are in N/(mm um) (ISO's unit); totals are for the common face
    width, in N/m.  ``mesh_stiffness_alpha_total`` is the mean mesh stiffness that
    :class:`pygear.Mesh` takes as ``stiffness``.
    """

    virtual_teeth: tuple[float, float]  # z_n1, z_n2 (inf for an internal gear)
    minimum_flexibility: float  # q' [mm um/N]
    theoretical_single_stiffness: float  # c'_th [N/(mm um)]
    correction_factor: float  # C_M [-]
    gear_blank_factor: float  # C_R [-]
    basic_rack_factor: float  # C_B [-]
    load_factor: float  # (K_A F_t/b / 100)^0.25 below 100 N/mm, else 1 [-]
    single_stiffness: float  # c' [N/(mm um)]
    mesh_stiffness_alpha: float  # c_gamma_alpha [N/(mm um)]
    mesh_stiffness_beta: float  # c_gamma_beta [N/(mm um)]
    single_stiffness_total: float  # c' b [N/m]
    mesh_stiffness_alpha_total: float  # c_gamma_alpha b [N/m]
    mesh_stiffness_beta_total: float  # c_gamma_beta b [N/m]
    face_width: float  # common face width b [m]
    contact_ratio: float  # eps_alpha used [-]


def iso6336_mesh_stiffness(
    mesh: geo.MeshGeometry,
    *,
    line_load: float = ISO_REFERENCE_LINE_LOAD,
    web_width_ratio: float = 1.0,
    rim_thickness_ratio: float = 1.0,
    path: str = "mesh",
) -> IsoMeshStiffness:
    """Single stiffness c' and mesh stiffness c_gamma of ``mesh`` by ISO 6336-1 method B.

    Parameters
    ----------
    mesh : MeshGeometry
        The gear pair; validated first (a pointed tip only warns).  Gear 1 is the
        pinion of ISO's q' series (x1 >= x2 is required for external pairs).
    line_load : float
        K_A F_t / b [N/mm]; below 100 N/mm ISO reduces c' by (line_load/100)^0.25.
    web_width_ratio : float
        b_s / b of a webbed blank; 1 for a solid disc (C_R = 1).
    rim_thickness_ratio : float
        s_R / m_n of a webbed blank (unused for a solid disc).
    path : str
        Name of the mesh in error messages.

    Raises
    ------
    CaseError
        For bad geometry (the message names the rule) or profile shifts outside the
        range of ISO's regression (x1 >= x2 for external pairs, -0.5 <= x1 + x2 <= 2).

    Notes
    -----
    For an internal pair ISO puts z_n2 = infinity in q', which the standard itself
    flags as an approximation: use ring-planet values with care.
    """
    for name, value in (
        ("line_load", line_load),
        ("web_width_ratio", web_width_ratio),
        ("rim_thickness_ratio", rim_thickness_ratio),
    ):
        if not is_finite_number(value) or value <= 0.0:
            raise CaseError(f"{path}.{name} must be a positive finite number (got {value!r})")
    mesh.validate(path)
    gear1, gear2 = mesh.gear1, mesh.gear2
    contact_ratio = geo.transverse_contact_ratio(mesh)
    face_width = min(gear1.face_width, gear2.face_width)
    result = _kernel.iso6336_mesh_stiffness(
        float(gear1.teeth),
        float(gear2.teeth),
        1 if mesh.internal else 0,
        float(gear1.profile_shift),
        float(gear2.profile_shift),
        abs(float(gear1.helix_angle_deg)),
        math.degrees(geo.base_helix_angle(gear1)),
        float(gear1.normal_pressure_angle_deg),
        float(gear1.dedendum_factor),
        float(gear2.dedendum_factor),
        float(web_width_ratio),
        float(rim_thickness_ratio),
        float(line_load),
        contact_ratio,
        face_width,
    )
    *values, ierr = result
    if ierr == 3:
        raise CaseError(
            f"{path}: profile shifts x1 = {gear1.profile_shift!r}, x2 = {gear2.profile_shift!r} "
            "lie outside ISO 6336-1 method B's range (x1 >= x2 for external pairs, "
            "-0.5 <= x1 + x2 <= 2)"
        )
    if ierr != 0:
        raise CaseError(
            f"{path}: ISO 6336-1 stiffness refused its arguments (kernel error {int(ierr)}); "
            f"contact ratio {contact_ratio:.4g}, face width {face_width!r} m"
        )
    (zn1, zn2, flexibility, theoretical, blank, rack, load, single, alpha, beta,
     single_total, alpha_total, beta_total) = (float(v) for v in values)  # fmt: skip
    return IsoMeshStiffness(
        virtual_teeth=(zn1, math.inf if mesh.internal else zn2),
        minimum_flexibility=flexibility,
        theoretical_single_stiffness=theoretical,
        correction_factor=0.8,
        gear_blank_factor=blank,
        basic_rack_factor=rack,
        load_factor=load,
        single_stiffness=single,
        mesh_stiffness_alpha=alpha,
        mesh_stiffness_beta=beta,
        single_stiffness_total=single_total,
        mesh_stiffness_alpha_total=alpha_total,
        mesh_stiffness_beta_total=beta_total,
        face_width=face_width,
        contact_ratio=contact_ratio,
    )
