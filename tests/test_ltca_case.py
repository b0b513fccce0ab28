"""The LTCA's case side: micro-geometry in the case, the separations it makes, the
``pygear contact`` command on shipped cases."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

from pygear import Gear
from pygear.analysis.contact.ltca import loaded_contact
from pygear.analysis.contact.ltca_geometry import lead_gap, profile_gap
from pygear.assembly.tooth_stiffness import ToothBody
from pygear.cli.parser import main
from pygear.errors import CaseError
from pygear.model import gear_geometry as geo
from pygear.model.micro_geometry import (
    Deviations,
    EndRelief,
    Misalignment,
    Modifications,
    ProfileRelief,
)

GEAR = geo.GearGeometry(teeth=19, normal_module=3.2e-3, face_width=16e-3)
RING = geo.GearGeometry(teeth=96, normal_module=3.2e-3, face_width=16e-3, internal=True)


def _roll(gear: geo.GearGeometry, radius: float) -> float:
    return math.sqrt(radius**2 - geo.base_radius(gear) ** 2)


@pytest.mark.parametrize("shape, middle", [("linear", 0.5), ("parabolic", 0.25)])
@pytest.mark.parametrize("gear", [GEAR, RING])
def test_tip_relief_grows_from_its_start_to_the_amount_at_the_tip(gear, shape, middle):
    """C_a at the tip circle, 0 at the start, C_a/2 (linear) or C_a/4 (parabolic) halfway
    in roll length; a ring's tip is its smallest radius, so its relief grows inwards."""
    r_b, r_tip = geo.base_radius(gear), geo.tip_radius(gear)
    start = r_b + 0.5 * (r_tip - r_b) if not gear.internal else r_tip + 2e-3
    mods = Modifications(tip_relief=ProfileRelief(10e-6, start_diameter=2 * start, shape=shape))
    rolls = np.array([_roll(gear, start), _roll(gear, r_tip)])
    rolls = np.append(rolls, rolls.mean())
    gap = profile_gap(gear, mods, rolls)
    np.testing.assert_allclose(gap, [0.0, 10e-6, middle * 10e-6], atol=1e-18)


def test_root_relief_and_profile_slope_deviation():
    """Root relief C_f at the root form circle, 0 at its start; a profile slope deviation
    f_Halpha adds f/2 of material at the tip and removes f/2 at the root form circle
    (ISO 1328-1: positive is material added towards the tip)."""
    r_b = geo.base_radius(GEAR)
    form, tip = geo.root_form_radius(GEAR), geo.tip_radius(GEAR)
    start = 0.5 * (form + tip)
    mods = Modifications(root_relief=ProfileRelief(6e-6, start_diameter=2 * start),
                         deviations=Deviations(profile_slope=4e-6))  # fmt: skip
    rolls = np.array([_roll(GEAR, max(form, r_b)), _roll(GEAR, start), _roll(GEAR, tip)])
    gap = profile_gap(GEAR, mods, rolls)
    slope_at_start = -4e-6 * ((rolls[1] - rolls[0]) / (rolls[2] - rolls[0]) - 0.5)
    np.testing.assert_allclose(gap, [6e-6 + 2e-6, slope_at_start, -2e-6], atol=1e-18)


def test_pitch_deviations_need_one_per_tooth():
    mesh = geo.MeshGeometry(GEAR, geo.GearGeometry(teeth=48, normal_module=3.2e-3,
                                                   face_width=16e-3))  # fmt: skip
    bodies = (ToothBody(206e9, 0.3, 10e-3), ToothBody(206e9, 0.3, 30e-3))
    mods = (Modifications(deviations=Deviations(pitch=(1e-6, 2e-6))), None)
    with pytest.raises(CaseError, match=r"deviations.pitch must hold one deviation per tooth"):
        loaded_contact(mesh, bodies, 1000.0, modifications=mods)


def test_lead_modifications_at_the_face_ends_and_middle():
    """Crowning C_beta at both ends, 0 in the middle; an end relief adds its amount at the
    ends; a helix slope modification removes +H/2 at y = b and -H/2 at y = 0."""
    width = 16e-3
    face = np.array([0.0, width / 2, width])
    mods = Modifications(crowning=8e-6, end_relief=EndRelief(3e-6, 2e-3), helix_slope=4e-6)
    expected = [8e-6 + 3e-6 - 2e-6, 0.0, 8e-6 + 3e-6 + 2e-6]
    np.testing.assert_allclose(lead_gap(mods, face, width), expected, atol=1e-18)


def test_misalignment_in_the_plane_of_action():
    """A tilt in the plane of the axes opens the gap by gamma sin(alpha_wt) per face
    length, one out of it by gamma cos(alpha_wt) (ISO 6336-1's f_Sigma_delta and
    f_Sigma_beta terms)."""
    alpha = math.radians(21.0)
    assert Misalignment(in_plane=1e-4).separation_slope(alpha) == pytest.approx(
        1e-4 * math.sin(alpha)
    )
    assert Misalignment(out_of_plane=1e-4).separation_slope(alpha) == pytest.approx(
        1e-4 * math.cos(alpha)
    )


@pytest.mark.parametrize(
    ("modifications", "message"),
    [
        ("tip", "planet.modifications must be a Modifications or None"),
        (Modifications(crowning=1.0), "planet.modifications.crowning must be a finite length"),
        (Modifications(tip_relief=ProfileRelief(1e-5, start_diameter=-1.0)),
         "planet.modifications.tip_relief.start_diameter must be a positive"),
        (Modifications(misalignment=Misalignment(in_plane=1.0)),
         "planet.modifications.misalignment.in_plane must be a tilt in radians"),
    ],
)  # fmt: skip
def test_gear_refuses_bad_modifications(modifications, message):
    gear = Gear(mass=1.0, polar_inertia=1.0, tilt_inertia=1.0, base_radius=0.05,
                modifications=modifications)  # fmt: skip
    with pytest.raises(CaseError) as error:
        gear.validate("planet")
    assert message in str(error.value)


def test_contact_json_of_a_ring_mesh_without_geometry(capsys):
    """yang2016_planetary has no gear geometry: the mesh's parabola law on a relative face.
    F = T / r_b of the ring (137.5 mm, Table 1); the TE of a perfect mesh is F / k(s) with
    the parabola's pair curve, k_pk = 3 k-bar / (eps (2 + lambda)) (docs/model.md 5.2)."""
    code = main(["contact", "yang2016_planetary", "--mesh", "ring-planet1",
                 "--torques", "50:100:2", "--json"])  # fmt: skip
    assert code == 0
    result = json.loads(capsys.readouterr().out)
    assert set(result) >= {"torques_nm", "force_n", "mean_te_m", "te_peak_to_peak_m",
                           "te_harmonics_m", "k_h_beta", "k_h_alpha",
                           "max_contact_pressure_pa"}  # fmt: skip
    np.testing.assert_allclose(result["force_n"], np.array([50.0, 100.0]) / 137.5e-3)
    eps, lam, mean = 1.24, 0.7, 5e8
    peak = 3 * mean / (eps * (2 + lam))
    s = np.arange(20) / 20

    def pair(p):
        inside = (p >= 0) & (p <= eps)
        return np.where(inside, peak * (1 - (1 - lam) * (2 * p / eps - 1) ** 2), 0.0)

    k = pair(s) + pair(s + 1) + pair(s + 2)
    te = result["force_n"][1] / k
    assert result["te_peak_to_peak_m"][1] == pytest.approx(np.ptp(te), rel=1e-9)
    assert result["mean_te_m"][1] == pytest.approx(te.mean(), rel=1e-9)
    assert result["k_h_beta"] == pytest.approx([1.0, 1.0], rel=1e-12)
    assert result["max_contact_pressure_pa"] == [None, None]  # no geometry: no radii


def test_contact_of_a_helical_mesh_writes_its_files(tmp_path, capsys):
    """The NREL gearbox's parallel helical stage, with geometry: files written, the
    stored TE in metres, K_Hbeta of a perfect pair near 1 (the slices sample the cycle
    at 20 positions: a few per cent)."""
    code = main(["contact", "nrel5mw_gearbox", "--mesh", "parallel.input-output",
                 "--torque", "2e5", "--out", str(tmp_path)])  # fmt: skip
    assert code == 0
    assert "K_Hbeta" in capsys.readouterr().out
    for name in ("contact.nc", "contact.md", "contact.png"):
        assert (tmp_path / name).stat().st_size > 0
    with xr.open_dataset(tmp_path / "contact.nc") as ds:
        assert ds.te_loaded.attrs["units"] == "m"
        assert 1.0 <= float(ds.k_h_beta[0]) < 1.1
        assert float(ds.te_peak_to_peak[0]) < 0.5 * float(ds.mean_te[0])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--mesh", "sun-planet9", "--torque", "10"],
         "is not a mesh of case 'yang2016_planetary'; its meshes are: sun-planet1"),
        (["--mesh", "sun-planet1"], "give exactly one of --torque T and --torques A:B:N"),
        (["--mesh", "sun-planet1", "--torque", "-3"], "--torque values must be positive"),
        (["--mesh", "sun-planet1", "--torques", "1:2"], "--torques must be A:B:N"),
        (["--mesh", "sun-planet1", "--torque", "1", "--slices", "0"],
         "--slices must be a whole number in [1, 400]"),
    ],
)  # fmt: skip
def test_contact_bad_input_is_one_line(argv, message, capsys):
    assert main(["contact", "yang2016_planetary", *argv]) == 2
    error = capsys.readouterr().err
    assert message in error
    assert error.count("\n") == 1
