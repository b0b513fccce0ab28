"""Bearing defects as a dataset's fault axis (``pygear dataset --faults
outer_race_depth=...``): the records carry the spall where the options put it, the
labels say so, and bad requests are refused before any run."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pygear.cli.parser import main
from pygear.errors import CaseError
from pygear.model.case import load_case
from pygear.model.rolling_bearing import RollingBearing
from pygear.runs.fault_dataset import _record_case, plan_dataset, run_dataset

CASE = "sequential_planetary"
PIN = RollingBearing(
    "PB", "roller", elements=14, pitch_diameter=0.05, element_diameter=0.008,
    roller_length=0.008, diametral_clearance=5e-6, location="planetary.planet",
)  # fmt: skip
"""A roller bearing on each planet pin (its size chosen for the test, not a case's)."""


@pytest.fixture(scope="module")
def case():
    return dataclasses.replace(load_case(CASE), rolling_bearings=(PIN,))


def test_records_carry_the_spall_where_the_options_put_it(case):
    plan = plan_dataset(
        case, "outer_race_depth=0,4e-6", speeds="120", loads="500", duration=0.7,
        planet=2, defect_angle=30.0, defect_width=1e-3,
    )  # fmt: skip
    healthy, spalled = (
        _record_case(plan, {"severity": s, "speed_rpm": 120.0, "load_nm": 500.0})
        for s in (0.0, 4e-6)
    )
    for _, scene in (healthy, spalled):
        assert "rolling_bearing_contact" in scene.effects
    assert healthy[0].rolling_bearings[0].defects == ()
    (defect,) = spalled[0].rolling_bearings[0].defects
    assert (defect.location, defect.depth, defect.width) == ("outer", 4e-6, 1e-3)
    assert (defect.angle_deg, defect.planet) == (30.0, 2)


def test_bearing_dataset_labels_and_its_records_differ(case, tmp_path):
    """Two depths, one operating point: two records labelled with the bearing, the
    planet, the defect's place and size; the spall changes what the sensor records."""
    plan = plan_dataset(
        case, "outer_race_depth=0,4e-6", speeds="120", loads="500", duration=0.7, planet=2
    )
    data = run_dataset(plan, tmp_path, workers=1, progress=False, figures=False)
    assert data.attrs["records"] == 2 and data.attrs["records_failed"] == 0
    assert set(data.severity.values) == {0.0, 4e-6}
    assert set(data.fault_kind.values) == {"outer_race_depth"}
    assert set(data.fault_bearing.values) == {"PB"} and set(data.fault_planet.values) == {2}
    assert set(data.defect_width.values) == {0.1 * PIN.element_diameter}
    first, second = (data.sensor_acceleration.isel(record=r).values for r in (0, 1))
    assert not np.allclose(first, second)
    card = (tmp_path / data.attrs["path"].split("/")[-1]).with_suffix(".md").read_text()
    assert "outer race of bearing `PB` of planet 2" in card


@pytest.mark.parametrize(
    "options, words",
    [
        ({"bearing": "NOPE"}, ["--bearing 'NOPE'", "PB"]),
        ({"planet": 0}, ["--planet", ">= 1"]),
        ({"defect_width": 0.5}, ["--defect-width", "element spacing"]),
    ],
)
def test_bad_bearing_requests_are_refused(case, options, words):
    with pytest.raises(CaseError) as error:
        plan_dataset(case, "outer_race_depth=0,4e-6", speeds="120", loads="500", **options)
    assert all(word in str(error.value) for word in words), str(error.value)


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--faults", "outer_race_depth=0,4e-6"], ["no rolling bearing", "--bearing"]),
        (["--faults", "inner_race_depth=0:1e-5:2", "--bearing", "X"], ["--bearing 'X'"]),
    ],
)
def test_dataset_cli_refuses_bearing_faults_in_one_line(tmp_path, capsys, argv, words):
    """The study case has no rolling bearings: one line, exit 2, nothing written."""
    argv = [*argv, "--speeds", "120", "--loads", "500", "--out", str(tmp_path / "d")]
    assert main(["dataset", CASE, *argv]) == 2
    error = capsys.readouterr().err.strip()
    assert "\n" not in error and all(word in error for word in words), error
    assert not (tmp_path / "d").exists()
