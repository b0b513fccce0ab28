"""ISO 6336-1:2019 method B single and mesh stiffness (Fortran module iso6336_stiffness,
called through pygear.assembly.mesh_stiffness_laws).

References are hand calculations from the standard's equations, carried out step by
step below to 7 significant digits (rel 1e-6 covers that rounding), and the typical
values ISO 6336-1 quotes for solid steel spur gears with the standard basic rack,
c' ~ 14 N/(mm um) and c_gamma ~ 20 N/(mm um) (docs/gear_geometry.md).
"""

from __future__ import annotations

import math

import pytest

from pygear.assembly.mesh_stiffness_laws import iso6336_mesh_stiffness
from pygear.kernel.calls import _kernel
from pygear.model import GearGeometry, MeshGeometry, transverse_contact_ratio
from pygear.model.components import CaseError

MM = 1e-3
HAND = 1e-6  # hand calculations carry 7 significant digits


def gear(teeth: int, module_mm: float = 4.0, **options: object) -> GearGeometry:
    return GearGeometry(teeth=teeth, normal_module=module_mm * MM, face_width=0.04, **options)


def test_standard_spur_pair_by_hand() -> None:
    """z 30/60, m 4 mm, x = 0, solid, K_A F_t/b >= 100 N/mm.

    q'    = 0.04723 + 0.15551/30 + 0.25791/60 = 0.05671217 mm um/N
    c'_th = 1/q' = 17.63290;  C_B = 1 + 0.5 (1.2 - 1.25) = 0.975;  C_M = 0.8
    c'    = 17.63290 x 0.8 x 0.975 = 13.75366 N/(mm um)
    eps_alpha = (30.28399 + 51.57983 - 61.56363) / 11.80856 = 1.719114
    c_ga  = 13.75366 (0.75 x 1.719114 + 0.25) = 21.17150;  c_gb = 0.85 c_ga = 17.99578
    totals for b = 40 mm: c_ga b = 21.17150 x 40 N/um = 8.468600e8 N/m
    """
    result = iso6336_mesh_stiffness(MeshGeometry(gear(30), gear(60)), line_load=150.0)
    assert result.virtual_teeth == (30.0, 60.0)
    assert result.minimum_flexibility == pytest.approx(0.05671217, rel=HAND)
    assert result.theoretical_single_stiffness == pytest.approx(17.63290, rel=HAND)
    assert result.basic_rack_factor == pytest.approx(0.975, rel=1e-12)
    assert result.gear_blank_factor == 1.0 and result.load_factor == 1.0
    assert result.single_stiffness == pytest.approx(13.75366, rel=HAND)
    assert result.contact_ratio == pytest.approx(1.719114, rel=HAND)
    assert result.mesh_stiffness_alpha == pytest.approx(21.17150, rel=HAND)
    assert result.mesh_stiffness_beta == pytest.approx(17.99578, rel=HAND)
    assert result.mesh_stiffness_alpha_total == pytest.approx(8.468600e8, rel=HAND)
    assert result.single_stiffness_total == pytest.approx(13.75366 * 40e6, rel=HAND)


def test_helical_shifted_webbed_lightly_loaded_pair_by_hand() -> None:
    """z 21/73, m_n 4 mm, beta 12 deg, x 0.3/0.1, b_s/b = 0.5, s_R/m_n = 3, 40 N/mm.

    alpha_t = atan(tan 20/cos 12) = 20.41031 deg;  beta_b = atan(tan 12 cos alpha_t) = 11.26652
    z_n = z / (cos^2 beta_b cos beta): 22.32117, 77.59262
    q'  = 0.04723 + 0.15551/22.32117 + 0.25791/77.59262 - 0.00635 x 0.3
          - 0.11654 x 0.3/22.32117 - 0.00193 x 0.1 - 0.24188 x 0.1/77.59262
          + 0.00529 x 0.09 + 0.00182 x 0.01 = 0.05403908
    C_R = 1 + ln(0.5) / (5 e^(3/5)) = 0.9239186;  load factor (40/100)^0.25 = 0.7952707
    c'  = (1/0.05403908) x 0.8 x 0.9239186 x 0.975 x cos 12 x 0.7952707 = 10.37384
    """
    mesh = MeshGeometry(
        gear(21, helix_angle_deg=12.0, profile_shift=0.3),
        gear(73, helix_angle_deg=-12.0, profile_shift=0.1),
    )
    result = iso6336_mesh_stiffness(
        mesh, line_load=40.0, web_width_ratio=0.5, rim_thickness_ratio=3.0
    )
    assert result.virtual_teeth == pytest.approx((22.32117, 77.59262), rel=HAND)
    assert result.minimum_flexibility == pytest.approx(0.05403908, rel=HAND)
    assert result.gear_blank_factor == pytest.approx(0.9239186, rel=HAND)
    assert result.load_factor == pytest.approx(0.7952707, rel=HAND)
    assert result.single_stiffness == pytest.approx(10.37384, rel=HAND)
    eps = transverse_contact_ratio(mesh)
    assert result.mesh_stiffness_alpha == pytest.approx(10.37384 * (0.75 * eps + 0.25), rel=HAND)
    assert result.mesh_stiffness_beta == pytest.approx(
        0.85 * result.mesh_stiffness_alpha, rel=1e-12
    )


def test_internal_pair_takes_zn2_infinite() -> None:
    """Planet 35, ring 97, x = 0: q' = 0.04723 + 0.15551/35 = 0.05167314 (the ring's
    terms vanish), c' = 0.78/q' = 15.09488 N/(mm um)."""
    mesh = MeshGeometry(gear(35), gear(97, internal=True, tip_alteration=-0.1))
    result = iso6336_mesh_stiffness(mesh)
    assert result.virtual_teeth == (35.0, math.inf)
    assert result.minimum_flexibility == pytest.approx(0.05167314, rel=HAND)
    assert result.single_stiffness == pytest.approx(15.09488, rel=HAND)
    # an internal mesh is stiffer than the external one with the same pinion
    external = iso6336_mesh_stiffness(MeshGeometry(gear(35), gear(97)))
    assert result.single_stiffness > external.single_stiffness


@pytest.mark.parametrize(("pinion", "wheel"), [(20, 40), (25, 75), (30, 60), (40, 120), (30, 90)])
def test_standard_spur_pairs_sit_near_iso_typical_values(pinion: int, wheel: int) -> None:
    """ISO 6336-1's typical values for solid steel spur gears with the standard basic
    rack, c' ~ 14 and c_gamma ~ 20 N/(mm um): the q' series stays within 10 % of 14 for
    20 to 40 pinion teeth at x = 0, and c_gamma_alpha = c' (0.75 eps_alpha + 0.25) within
    20 % of 20 as eps_alpha runs from 1.63 to 1.79 (without C_M = 0.8, c' would exceed 14
    by 13 to 31 %)."""
    result = iso6336_mesh_stiffness(MeshGeometry(gear(pinion), gear(wheel)))
    assert result.single_stiffness == pytest.approx(14.0, rel=0.10)
    assert result.mesh_stiffness_alpha == pytest.approx(20.0, rel=0.20)


def test_basic_rack_blank_and_load_factors() -> None:
    """C_B = mean of the two gears' [1 + 0.5 (1.2 - h_fP/m_n)] [1 - 0.02 (20 - alpha)]:
    1.0 at h_fP = 1.2; (0.975 + 0.9)/2 = 0.9375 for 1.25 with 1.4.  C_R holds b_s/b at
    0.2 below it.  Loads at or above 100 N/mm leave c' unchanged, 50 N/mm scales it by
    0.5^0.25 = 0.8408964."""
    reference = iso6336_mesh_stiffness(MeshGeometry(gear(30), gear(60)))
    rack = iso6336_mesh_stiffness(
        MeshGeometry(gear(30, dedendum_factor=1.2), gear(60, dedendum_factor=1.2))
    )
    assert rack.basic_rack_factor == pytest.approx(1.0, abs=1e-12)
    mixed = iso6336_mesh_stiffness(MeshGeometry(gear(30), gear(60, dedendum_factor=1.4)))
    assert mixed.basic_rack_factor == pytest.approx(0.9375, abs=1e-12)
    narrow = iso6336_mesh_stiffness(MeshGeometry(gear(30), gear(60)), web_width_ratio=0.1)
    floor = iso6336_mesh_stiffness(MeshGeometry(gear(30), gear(60)), web_width_ratio=0.2)
    assert narrow.gear_blank_factor == floor.gear_blank_factor < 1.0
    heavy = iso6336_mesh_stiffness(MeshGeometry(gear(30), gear(60)), line_load=400.0)
    light = iso6336_mesh_stiffness(MeshGeometry(gear(30), gear(60)), line_load=50.0)
    assert heavy.single_stiffness == reference.single_stiffness
    ratio = light.single_stiffness / reference.single_stiffness
    assert ratio == pytest.approx(0.8408964, rel=HAND)


def test_refuses_inputs_outside_the_method() -> None:
    with pytest.raises(CaseError, match=r"stage.sun_mesh: profile shifts .*\(x1 >= x2"):
        iso6336_mesh_stiffness(
            MeshGeometry(gear(30), gear(60, profile_shift=0.2)), path="stage.sun_mesh"
        )
    with pytest.raises(CaseError, match=r"-0.5 <= x1 \+ x2 <= 2"):
        iso6336_mesh_stiffness(
            MeshGeometry(
                gear(60, profile_shift=-0.2, tip_alteration=-0.1),
                gear(80, profile_shift=-0.4, tip_alteration=-0.1),
            )
        )
    with pytest.raises(CaseError, match="mesh.line_load must be a positive"):
        iso6336_mesh_stiffness(MeshGeometry(gear(30), gear(60)), line_load=0.0)
    with pytest.raises(CaseError, match="gear2.normal_module"):
        iso6336_mesh_stiffness(MeshGeometry(gear(30), gear(60, 5.0)))


def test_kernel_reports_bad_arguments_with_an_error_code() -> None:
    """The Fortran entry point checks before computing: eps_alpha < 1 is error 1,
    x1 < x2 error 3, and the outputs stay zero."""
    good = (30.0, 60.0, 0, 0.0, 0.0, 0.0, 0.0, 20.0, 1.25, 1.25, 1.0, 1.0, 150.0, 1.7, 0.04)
    *outputs, ierr = _kernel.iso6336_mesh_stiffness(*good)
    assert ierr == 0 and outputs[7] == pytest.approx(13.75366, rel=HAND)
    *outputs, ierr = _kernel.iso6336_mesh_stiffness(*good[:13], 0.9, 0.04)
    assert ierr == 1 and all(value == 0.0 for value in outputs)
    *outputs, ierr = _kernel.iso6336_mesh_stiffness(*good[:3], 0.0, 0.1, *good[5:])
    assert ierr == 3 and all(value == 0.0 for value in outputs)
