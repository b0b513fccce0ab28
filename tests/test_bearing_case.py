"""A case's rolling bearings reach its run files: the NREL 5 MW gearbox's planet bearings
by geometry, their characteristic frequencies stored beside the mesh frequencies."""

from __future__ import annotations

import dataclasses
import math

import pytest

from pygear.io import open_dataset
from pygear.model.case import load_case
from pygear.runs.scene_runner import RunOptions, run_scene


@pytest.fixture(scope="module")
def nrel():
    return load_case("nrel5mw_gearbox")


def test_case_carries_its_planet_bearings(nrel):
    names = [b.name for b in nrel.rolling_bearings]
    assert names == ["PL-A", "PL-B", "IMS-PL-A", "IMS-PL-B"]


def test_a_rolling_bearing_of_another_type_is_refused(nrel):
    from pygear.errors import CaseError

    with pytest.raises(CaseError, match=r"rolling_bearings\[0\] must be a RollingBearing"):
        dataclasses.replace(nrel, rolling_bearings=("PL-A",))


def test_run_file_stores_the_planet_bearing_frequencies(nrel, tmp_path):
    scene = nrel.scene("runup")
    short = dataclasses.replace(scene.transient, duration=0.3, mean_window=0.1)
    scene = dataclasses.replace(scene, transient=short, analyses=("transient",))
    outcome = run_scene(nrel, scene, tmp_path, RunOptions(figures=False))
    with open_dataset(tmp_path / "runup.nc") as run:
        frequencies = run.bearing_frequency.load()
        speeds = dict(zip(run.body.values.tolist(), run.equilibrium_speed.values.tolist()))
    assert outcome.transient is not None
    assert sorted(frequencies.rolling_bearing.values.tolist()) == sorted(
        ["PL-A", "PL-B", "IMS-PL-A", "IMS-PL-B"]
    )
    # a planet bearing's outer ring turns with the planet, its inner ring (the pin) with
    # the carrier: the cage runs at the mean of the two in the carrier's frame, and the
    # fundamental train frequency is (1/2) f_rel (1 - d/D cos alpha), alpha = 0 (rollers)
    bearing = next(b for b in nrel.rolling_bearings if b.name == "PL-A")
    relative = abs(speeds["stage1.planet1"]) / 60.0  # the planet's own rotation [Hz]
    ratio = bearing.element_diameter / bearing.pitch_diameter
    ftf = 0.5 * relative * (1.0 + ratio)  # outer ring turning, inner ring still
    bpfo = bearing.elements * (relative - ftf)
    lines = [str(v) for v in frequencies.bearing_line.values]
    measured = frequencies.sel(rolling_bearing="PL-A").values
    found_bpfo = measured[lines.index("BPFO")]
    assert math.isfinite(found_bpfo) and found_bpfo > 0
    assert found_bpfo == pytest.approx(bpfo, rel=0.02)
