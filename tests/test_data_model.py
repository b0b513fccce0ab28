"""The output data model (docs/data_model.md): every file kind clean under both CF
checkers, a batch read back with ``open_mfdataset`` and selected by scene, member and
mesh names, the case JSON of ``pygear show-case``, and grouped channels that hold what
the probes asked for.

The runs are short versions of the study case's scenes (Yang, Jiang & Han 2016), cut
with ``dataclasses.replace``: what is checked is the layout and its metadata, and a
run's length changes neither.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pygear import Probe, load_case
from pygear.analysis.signals.channels import channel_names, channel_series
from pygear.analysis.time.transient import run_transient
from pygear.cli import main
from pygear.io import index_labels, open_dataset, open_mfdataset
from pygear.runs import batch, sweep
from pygear.runs.fault_dataset import plan_dataset, run_dataset

CASES = Path(__file__).resolve().parent.parent / "cases"
STUDY = CASES / "yang2016_planetary"

SHORT_CASE = f"""
import dataclasses

from pygear import load_case

base = load_case({str(STUDY)!r})


def short(name, duration, **changes):
    scene = base.scene(name)
    settings = dataclasses.replace(
        scene.transient, duration=duration, mean_window=min(0.2, duration)
    )
    return dataclasses.replace(scene, transient=settings, **changes)


case = dataclasses.replace(
    base,
    name="short_study",
    scenes=(
        base.scene("modal"),
        short("runup", 1.5),  # with its signal analysis; 2.8 carrier turns for orders
        short("runup_lin_parker", 0.05, analyses=("transient",)),
        short("runup_consistent", 0.05, analyses=("transient",)),
        short("steady_sensor", 1.0),
    ),
)
"""

PROVENANCE = ("case", "scene", "formulation", "input_hash", "case_json")

SECONDS_NOT_TIME = "Coordinate variable 'time' should have standard_name='time', found: 'None'"
"""The one compliance-checker message a pygear file draws, and why it is no CF fault.
``time`` holds seconds from the run's start (units "s"): CF 4.4 requires a reference
instant ("since") of a variable with ``standard_name: time``, which cfchecker and the
compliance checker's own §4.4 enforce, and a simulation has none (an epoch made xarray
decode 1970 datetimes).  Without that standard name ``time`` is an ordinary coordinate
in seconds, which CF 5.1 allows; the compliance checker's §5.1 check, however, wants
``standard_name: time`` on any dimension called ``time``, a rule of that checker, not
of CF.  Only this message is let through; any other §5.1 message still fails."""


# --- the checkers -----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def cf_checks(tmp_path_factory):
    """``check(path) -> list of messages``: the FATAL, ERROR and WARN messages of
    cfchecker and every failed check of the IOOS compliance checker (cf:1.10).

    cfchecker 4.1 (the newest on PyPI) knows CF up to 1.8 and reads the standard-name,
    area-type and region tables from the web.  Here it runs every rule it has (all of
    them gated on versions up to 1.8) on files that declare CF-1.10, with the
    standard-name table the compliance checker ships and empty area-type and region
    tables: the files use neither area types nor regions, so those tables are never
    consulted.
    """
    try:
        from cfchecker import cfchecks
        from compliance_checker.runner import CheckSuite, ComplianceChecker
    except Exception as error:  # noqa: BLE001 - e.g. cfunits without the UDUNITS-2 library
        pytest.skip(f"the CF checkers are not installed (scripts/setup.sh installs them): {error}")
    import compliance_checker

    version = cfchecks.CFVersion((1, 10))
    if all(str(v) != str(version) for v in cfchecks.cfVersions):
        cfchecks.cfVersions.append(version)
    tables = tmp_path_factory.mktemp("cf_tables")
    areas, regions = tables / "area_types.xml", tables / "regions.xml"
    areas.write_text(
        '<?xml version="1.0"?><area_type_table><version_number>0</version_number>'
        "<date>none</date></area_type_table>"
    )
    regions.write_text(
        '<?xml version="1.0"?><standardized_region_list><version_number>0</version_number>'
        "<date>none</date></standardized_region_list>"
    )
    names = Path(compliance_checker.__file__).parent / "data" / "cf-standard-name-table.xml"
    CheckSuite.load_all_available_checkers()

    def check(path: Path) -> list[str]:
        checker = cfchecks.CFChecker(
            version=version,
            cfStandardNamesXML=str(names),
            cfAreaTypesXML=str(areas),
            cfRegionNamesXML=str(regions),
            silent=True,
            cacheTables=False,
        )
        results = checker.checker(str(path))
        messages = []
        for level in ("FATAL", "ERROR", "WARN"):
            messages += [f"cfchecks global {level}: {m}" for m in results["global"][level]]
            for variable, found in results["variables"].items():
                messages += [f"cfchecks {variable} {level}: {m}" for m in found[level]]
        report = tables / f"{path.stem}.json"
        ComplianceChecker.run_checker(
            str(path), ["cf:1.10"], 0, "lenient", output_filename=str(report),
            output_format="json",
        )  # fmt: skip
        result = json.loads(report.read_text())["cf:1.10"]
        for check in result["all_priorities"]:
            passed, total = check["value"]
            found = [m for m in check["msgs"] if m != SECONDS_NOT_TIME]
            if passed < total and found:
                messages.append(f"compliance-checker {check['name']}: {found}")
        if result.get("errors"):
            messages.append(f"compliance-checker exceptions: {result['errors']}")
        return messages

    return check


def _assert_described(path: Path) -> None:
    """Every variable has a long name, and units unless it holds text (labels)."""
    with xr.open_dataset(path, decode_times=False) as data:
        for name, variable in data.variables.items():
            assert "long_name" in variable.attrs, (path.name, name)
            if variable.dtype.kind not in "OUS":
                assert "units" in variable.attrs, (path.name, name)
            assert "_FillValue" not in variable.encoding or name not in data.coords, name


# --- the files --------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def short_case(tmp_path_factory) -> Path:
    directory = tmp_path_factory.mktemp("short_study")
    (directory / "case.py").write_text(SHORT_CASE)
    return directory


@pytest.fixture(scope="module")
def run_dir(short_case, tmp_path_factory) -> Path:
    """``pygear run`` of the short case: modal, three transients, the spectra of the
    run-up, its order tracking and the sun's synchronous average at the sensor."""
    out = tmp_path_factory.mktemp("run")
    assert main(["run", str(short_case), "--out", str(out), "--no-figures", "--json"]) == 0
    orders = ["analyze", str(out / "runup.nc"), "--orders", "planetary.carrier", "--json"]
    orders += ["--channel", "acceleration:planetary.sun.theta_z", "--max-order", "150"]
    assert main([*orders, "--out", str(out / "orders")]) == 0
    tsa = ["analyze", str(out / "steady_sensor.nc"), "--tsa", "sun", "--indicators"]
    assert main([*tsa, "--no-figures", "--json"]) == 0
    return out


@pytest.fixture(scope="module")
def batch_dir(short_case, tmp_path_factory, scheduler) -> Path:
    out = tmp_path_factory.mktemp("batch")
    table = batch.run_batch(
        [short_case], out_dir=out, workers=2, scheduler=scheduler, progress=False, figures=False
    )
    assert list(table.status) == ["ok"] * 5, list(table.error)
    return out / short_case.name


@pytest.fixture(scope="module")
def sweep_dir(short_case, tmp_path_factory, scheduler) -> Path:
    out = tmp_path_factory.mktemp("sweep")
    for scene in ("modal", "runup_lin_parker"):
        swept = sweep.run_sweep(
            short_case,
            [("planetary.sun_mesh.stiffness", "4e8,6e8")],
            scene=scene,
            out_dir=out / scene,
            scheduler=scheduler,
            progress=False,
        )
        assert swept.attrs["points_failed"] == 0
    return out


@pytest.fixture(scope="module")
def dataset_dir(tmp_path_factory, scheduler) -> Path:
    out = tmp_path_factory.mktemp("dataset")
    plan = plan_dataset(
        "sequential_planetary", "crack_depth=0:0.2:2", speeds="120", loads="500", duration=1.0
    )
    data = run_dataset(plan, out, scheduler=scheduler, progress=False, figures=False)
    assert data.attrs["records_failed"] == 0
    return out


def test_run_files_pass_both_checkers(run_dir, cf_checks):
    files = sorted(run_dir.rglob("*.nc"))
    kinds = {p.relative_to(run_dir).as_posix() for p in files}
    assert {"modal.nc", "runup.nc", "steady_sensor.nc", "orders/orders.nc"} <= kinds
    assert "steady_sensor_tsa_planetary_sun.nc" in kinds
    assert {"spectra/runup_acceleration_planetary.sun.theta_z.nc"} <= kinds
    for path in files:
        assert cf_checks(path) == [], path.name
        _assert_described(path)


def test_sweep_files_pass_both_checkers(sweep_dir, cf_checks):
    files = sorted(sweep_dir.rglob("*.nc"))
    assert len([p for p in files if p.name.startswith("sweep_")]) == 2
    for path in files:
        assert cf_checks(path) == [], path.name
        _assert_described(path)


def test_batch_files_pass_both_checkers(batch_dir, cf_checks):
    for path in sorted(batch_dir.rglob("*.nc")):
        assert cf_checks(path) == [], path.name
        _assert_described(path)


def test_dataset_files_pass_both_checkers(dataset_dir, cf_checks):
    files = sorted(dataset_dir.glob("*.nc"))
    assert {p.name.split("_")[0] for p in files} == {"dataset", "record"}
    for path in files:
        assert cf_checks(path) == [], path.name
        _assert_described(path)


def test_every_file_names_the_inputs_that_made_it(run_dir, batch_dir, sweep_dir, dataset_dir):
    """Spectra, orders and averages carry the run's case, scene, formulation, input hash
    and case JSON; every file carries the case JSON, and it parses as JSON alone."""
    with open_dataset(run_dir / "runup.nc") as run:
        source = {key: run.attrs[key] for key in PROVENANCE}
    derived = [
        run_dir / "spectra" / "runup_acceleration_planetary.sun.theta_z.nc",
        run_dir / "orders" / "orders.nc",
    ]
    for path in derived:
        with xr.open_dataset(path, decode_times=False) as data:
            assert {key: data.attrs[key] for key in PROVENANCE} == source, path.name
    with xr.open_dataset(run_dir / "steady_sensor_tsa_planetary_sun.nc") as average:
        assert average.attrs["scene"] == "steady_sensor"
        assert average.attrs["formulation"] == "improved"
    for directory in (run_dir, batch_dir, sweep_dir, dataset_dir):
        for path in directory.rglob("*.nc"):
            with xr.open_dataset(path, decode_times=False) as data:
                document = json.loads(data.attrs["case_json"])
                assert document["format"] == "pygear-case-json-1", path.name
                assert document["input_hash"] == data.attrs["input_hash"] or path.name.startswith(
                    ("record_", "dataset_")
                ), path.name


# --- reading a batch back ---------------------------------------------------------------------


def test_a_batch_opens_as_one_dataset_and_selects_by_name(batch_dir):
    """The run-ups of three formulations stacked along ``scene``: one scene's sun speed
    and sun-planet mesh force are those of its own file."""
    pattern = str(batch_dir / "runup*.nc")
    with xr.open_mfdataset(
        pattern,
        combine="nested",
        concat_dim="scene",
        preprocess=index_labels,
        decode_times=False,
        join="outer",  # the run-up lasts longer than the others: NaN past their end
        data_vars="all",
        coords="different",
    ) as stacked:
        assert sorted(stacked.scene.values.tolist()) == [
            "runup",
            "runup_consistent",
            "runup_lin_parker",
        ]
        for scene in stacked.scene.values.tolist():
            with open_dataset(batch_dir / f"{scene}.nc") as alone:
                own = stacked.sel(scene=scene, time=alone.time.values)  # longer runs: NaN
                speed = own.speed.sel(member="planetary.sun")
                np.testing.assert_array_equal(
                    speed.values, alone.speed.sel(member="planetary.sun").values
                )
                force = own.mesh_force.sel(mesh="planetary.sun-planet1")
                np.testing.assert_array_equal(
                    force.values, alone.mesh_force.sel(mesh="planetary.sun-planet1").values
                )
    with open_mfdataset(pattern) as stacked:  # the same through pygear.io
        assert stacked.sizes["scene"] == 3
        assert stacked.t_s.sel(scene="runup_lin_parker").values.shape == ()
        assert stacked.time.attrs["units"] == "s"


def test_plain_xarray_reads_the_labels_as_coordinates(batch_dir):
    """Without pygear: CF's auxiliary label coordinates, which ``set_xindex`` indexes,
    and time in seconds (no epoch for xarray to decode into 1970 datetimes)."""
    with xr.open_dataset(batch_dir / "runup.nc") as run:
        assert run.time.dtype.kind == "f" and run.time.attrs["units"] == "s"
        assert run.time.values[0] == 0.0 and "standard_name" not in run.time.attrs
        labelled = run.set_xindex("member_label")
        sun = labelled.speed.sel(member_label="planetary.sun")
        assert sun.dims == ("time",)
        assert run.scene.item() == "runup"


# --- show-case --------------------------------------------------------------------------------


def test_show_case_json_round_trips(capsys):
    """The JSON parses, prints back the same, and holds the inputs of Yang et al.'s
    Table 1 with the values pygear derives from them (the stage's ratio 1 + r_br / r_bs,
    the sun mesh's pressure angle in radians)."""
    assert main(["show-case", "yang2016_planetary", "--json"]) == 0
    text = capsys.readouterr().out
    document = json.loads(text)
    assert json.loads(json.dumps(document)) == document
    assert "NaN" not in text.replace('"NaN"', "")  # strict JSON: no bare NaN literals
    case = load_case("yang2016_planetary")
    assert document["input_hash"] == case.input_hash()
    stage = document["case"]["gearbox"]["stages"][0]
    assert stage["type"] == "PlanetaryStage" and stage["planets"] == 3
    assert (stage["ring"]["teeth"], stage["sun"]["teeth"], stage["planet"]["teeth"]) == (96, 27, 35)
    # Table 1 base radii: r_br = 0.1375 m, r_bs = 0.0387 m; 1 + 0.1375 / 0.0387 = 4.5530
    assert stage["derived"]["speed_ratio"] == pytest.approx(1 + 0.1375 / 0.0387, rel=1e-12)
    assert stage["sun_mesh"]["derived"]["pressure_angle"] == pytest.approx(
        math.radians(24.6), rel=1e-12
    )
    scenes = {scene["name"]: scene for scene in document["case"]["scenes"]}
    runup = scenes["runup"]["transient"]
    assert runup["type"] == "Transient" and runup["integrator"] == "newmark"  # a default


def test_show_case_applies_a_scene_and_prints_lines(capsys):
    argv = ["show-case", "yang2016_planetary", "--scene", "runup_planet_error"]
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "case.gearbox.stages[0].planet_angles_deg = [0.0, 120.1, 240.0]" in lines
    assert main(["show-case", "yang2016_planetary", "--scene", "nosuch"]) == 2
    assert "no scene 'nosuch'" in capsys.readouterr().err


def test_a_run_file_stores_the_case_show_case_prints(run_dir, short_case, capsys):
    assert main(["show-case", str(short_case), "--scene", "runup", "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    with xr.open_dataset(run_dir / "runup.nc", decode_times=False) as run:
        assert json.loads(run.attrs["case_json"]) == printed


# --- grouped channels -------------------------------------------------------------------------


@pytest.fixture(scope="module")
def probed(study_case):
    """0.02 s of the run-up with the full state and probes of every grouped kind, one of
    them named."""
    import dataclasses

    scene = study_case.scene("runup")
    probes = (
        Probe("speed", "planetary.sun"),
        Probe("displacement", "planetary.carrier.theta_z"),
        Probe("acceleration", "planetary.sun.theta_z"),
        Probe("velocity", "planetary.planet1.eta"),
        Probe("acceleration", "planetary.ring.y", name="ring_y"),
        Probe("acceleration", "planetary.ring.y"),
        Probe("mesh_force", "sun-planet1"),
        Probe("mesh_deflection", "planetary.ring-planet1"),
        Probe("bearing_force", "planetary.ring_bearing.y"),
        Probe("drive_torque"),
    )
    settings = dataclasses.replace(
        scene.transient, duration=0.02, mean_window=0.01, probes=probes, full_state=True
    )
    return run_transient(study_case, dataclasses.replace(scene, transient=settings))


def test_grouped_channels_hold_what_the_probes_asked_for(probed):
    """Each grouped series equals the full state's DOF it reads: a speed is the
    theta_z velocity times 30/pi rpm per rad/s, a DOF quantity its own state row.  The
    kernel evaluates each probe as a dot product of its weights with the state, so two
    series of one DOF differ by at most the round-off of that product (1e-12 of the
    series' scale allows it with margin)."""
    run = probed

    def close(a, b) -> None:
        a, b = np.asarray(a), np.asarray(b)
        assert np.abs(a - b).max() <= 1e-12 * max(np.abs(b).max(), 1e-300)

    velocity = run.rotation_velocity.sel(rotation_dof="planetary.sun.theta_z")
    close(run.speed.sel(member="planetary.sun"), velocity * 30 / math.pi)
    assert run.speed.attrs["units"] == "rpm" and run.speed.dims == ("member", "time")
    close(
        run.translation_acceleration.sel(translation_dof="planetary.ring.y"),
        channel_series(run, "ring_y"),
    )
    assert run.ring_y.dims == ("time",) and run.ring_y.attrs["target"] == "planetary.ring.y"
    assert run.translation_acceleration.attrs["units"] == "m/s^2"
    assert run.rotation_acceleration.attrs["units"] == "rad/s^2"
    # the mesh given by its short name is labelled with its stage; mesh_force and
    # mesh_deflection share the dimension of every mesh some quantity was probed at
    assert run.mesh.values.tolist() == ["planetary.sun-planet1", "planetary.ring-planet1"]
    assert np.isnan(run.mesh_force.sel(mesh="planetary.ring-planet1").values).all()
    assert run.bearing_force.sel(bearing="planetary.ring_bearing.y").attrs["units"] == "N"
    assert run.drive_torque.dims == ("time",)
    names = channel_names(run)
    assert "mesh_force:planetary.sun-planet1" in names
    assert "mesh_force:planetary.ring-planet1" not in names  # NaN: not recorded


def test_channel_names_resolve_as_the_cli_reads_them(probed):
    run = probed
    by_kind = channel_series(run, "acceleration:planetary.sun.theta_z")
    by_variable = channel_series(run, "rotation_acceleration:planetary.sun.theta_z")
    np.testing.assert_array_equal(by_kind.values, by_variable.values)
    assert by_kind.attrs["channel"] == "acceleration:planetary.sun.theta_z"
    assert by_kind.attrs["units"] == "rad/s^2"
    speed = channel_series(run, "planetary.sun")  # a label that one channel has
    assert speed.attrs["channel"] == "speed:planetary.sun"
    # a label alone names a channel only where one has it: the full state records the
    # ring's displacement, velocity and acceleration
    assert channel_series(run, "planetary.ring.y") is None
    assert channel_series(run, "acceleration:planetary.moon.theta_z") is None


def test_files_stack_labels_of_the_full_state_in_si_units(probed, tmp_path, cf_checks):
    """The full state in a file: translations and rotations apart, each in one unit,
    and the file read back equals the run."""
    from pygear.io import write_netcdf

    path = write_netcdf(probed, tmp_path / "state.nc", title="state")
    assert cf_checks(path) == []
    with open_dataset(path) as read:
        for name in ("rotation_velocity", "translation_acceleration", "speed", "mesh_force"):
            np.testing.assert_array_equal(read[name].values, probed[name].values)
            assert read[name].dims == probed[name].dims
        assert read.translation_displacement.attrs["units"] == "m"
        assert read.rotation_displacement.attrs["units"] == "rad"
        np.testing.assert_array_equal(read.time.values, probed.time.values)
    assert os.path.getsize(path) > 0
