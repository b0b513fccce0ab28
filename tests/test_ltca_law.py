"""The loaded contact as a mesh law (pygear.analysis.contact.ltca_law)."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from pygear import load_case
from pygear.analysis.contact.ltca_law import with_loaded_contact_law
from pygear.analysis.contact.mesh_stiffness import mesh_stiffness_at_constant_speed
from pygear.assembly.mesh_laws import mesh_law, with_mesh_law
from pygear.errors import CaseError
from pygear.model.micro_geometry import Modifications, ProfileRelief


@pytest.fixture(scope="module")
def nrel():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_case("nrel5mw_gearbox")


def _curve(law) -> np.ndarray:
    """k_pair at 101 equal steps over the law's span [N/m]."""
    values = law.oriented_curve(True) * law.mean_stiffness / law.contact_ratio
    return np.interp(np.linspace(0, 1, 101), np.linspace(0, 1, values.size), values)


def test_perfect_flanks_give_the_potential_energy_law(nrel):
    """Without modifications the loaded pair curve is the potential-energy law's: the
    LTCA's pairs at 1/50 of a cycle, interpolated, against the law's 201 samples
    (second-order interpolation error, ~1e-4 of k near the curve's peak)."""
    changed = with_loaded_contact_law(nrel, {"stage1.sun-planet1": 1e5,
                                             "stage1.ring-planet1": 3e5})  # fmt: skip
    reference = with_mesh_law(nrel, "potential_energy")
    for member in ("sun", "ring"):
        law = mesh_law(changed.gearbox.stage("stage1"), member)
        own = mesh_law(reference.gearbox.stage("stage1"), member)
        assert law.law == "tabulated"
        assert law.mean_stiffness == pytest.approx(own.mean_stiffness, rel=1e-3)
        np.testing.assert_allclose(_curve(law), _curve(own), rtol=1e-3)


def test_tip_relief_makes_the_law_load_dependent(nrel):
    """A 30 um tip relief on the stage 1 sun from its pitch circle: at a low torque the
    relieved ends carry nothing (k-bar below the perfect pair's); a torque that closes
    more of the relief brings k-bar nearer the perfect pair's, never above it."""
    stage = nrel.gearbox.stage("stage1")
    sun = stage.sun
    relief = ProfileRelief(30e-6, start_diameter=sun.geometry.teeth * sun.geometry.normal_module)
    gear = dataclasses.replace(sun, modifications=Modifications(tip_relief=relief))
    stages = tuple(dataclasses.replace(s, sun=gear) if s.name == "stage1" else s
                   for s in nrel.gearbox.stages)  # fmt: skip
    relieved = dataclasses.replace(nrel, gearbox=dataclasses.replace(nrel.gearbox, stages=stages))
    perfect = mesh_law(with_loaded_contact_law(nrel, {"stage1.sun-planet1": 1e5})
                       .gearbox.stage("stage1"), "sun").mean_stiffness  # fmt: skip
    means = [
        mesh_law(with_loaded_contact_law(relieved, {"stage1.sun-planet1": torque})
                 .gearbox.stage("stage1"), "sun").mean_stiffness  # fmt: skip
        for torque in (2e4, 4e5)
    ]
    assert means[0] < 0.97 * perfect
    assert means[0] < means[1] <= perfect * (1 + 1e-9)


def test_the_contact_table_runs_the_loaded_law():
    """The study case (no gear geometry: its parabola law on a relative face) through
    the tooth-contact table of a constant-speed run: the table's mean mesh stiffness is
    the parabola's k-bar = 5e8 N/m (Table 1), which the loaded law reproduces (the
    parabola sampled at 1/50 of a cycle: ~1e-4)."""
    case = load_case("yang2016_planetary")
    changed = with_loaded_contact_law(case, {"sun-planet1": 50.0, "ring-planet1": 150.0})
    ds = mesh_stiffness_at_constant_speed(changed, duration=0.05)
    np.testing.assert_allclose(ds.mean_stiffness.values, 5e8, rtol=1e-3)
    assert set(np.unique(ds.mesh.values)) >= {"sun-planet1", "ring-planet3"}


def test_unknown_mesh_is_refused():
    case = load_case("yang2016_planetary")
    with pytest.raises(CaseError, match="sun-planet2 name no stage's first planet mesh"):
        with_loaded_contact_law(case, {"sun-planet2": 10.0})
