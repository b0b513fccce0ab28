"""Reading pygear's files back (issue #27, items 8, 18, 19): time in seconds for every
reader, labels as indexes through ``engine="pygear"``, batches of scenes with other
probes and of other kinds stacked by :func:`pygear.io.open_mfdataset`, and the git
revision a file records being the package's own.

The batch is a short version of the study case (Yang, Jiang & Han 2016): 0.05 s of
three run-ups (two with a translation probe, one without), a sensor scene and the modal
scene, which is what the stacking has to cope with; their length changes nothing.
"""

from __future__ import annotations

import importlib.metadata
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import tomllib
import xarray as xr

import pygear
from pygear.cli import main
from pygear.io import open_dataset, open_mfdataset, write_netcdf

ROOT = Path(__file__).resolve().parent.parent

SMALL_BATCH = """
import dataclasses

from pygear import load_case

base = load_case("yang2016_planetary")


def short(name):
    scene = base.scene(name)
    settings = dataclasses.replace(scene.transient, duration=0.05, mean_window=0.05)
    return dataclasses.replace(scene, transient=settings, analyses=("transient",))


case = dataclasses.replace(
    base,
    name="small_batch",
    scenes=(
        base.scene("modal"),
        short("runup"),
        short("runup_consistent"),
        short("runup_wide"),  # no translation probe
        short("steady_sensor"),  # a sensor, angles, no acceleration
    ),
)
"""


@pytest.fixture(scope="module")
def batch(tmp_path_factory) -> Path:
    case = tmp_path_factory.mktemp("small_batch")
    (case / "case.py").write_text(SMALL_BATCH)
    out = tmp_path_factory.mktemp("out")
    assert main(["run", str(case), "--out", str(out), "--no-figures", "--json"]) == 0
    return out


def _labelled_run(path: Path) -> xr.Dataset:
    """A run as pygear computes it (time in s, text labels), written by write_netcdf."""
    time = np.arange(0, 0.01, 1 / 7e3)  # a step of no whole number of nanoseconds
    members = ["planetary.carrier", "planetary.sun"]
    speed = np.vstack([np.full(time.size, 120.0), np.linspace(0, 546.0, time.size)])
    run = xr.Dataset(
        {"speed": (("member", "time"), speed, {"units": "rpm", "long_name": "speed"})},
        coords={
            "time": ("time", time, {"units": "s", "long_name": "time since the start"}),
            "member": ("member", members, {"long_name": "member"}),
        },
        attrs={"scene": "steady"},
    )
    write_netcdf(run, path, title="a run")
    return run


# --- item 19: time in seconds, labels as indexes -------------------------------------------


def test_plain_xarray_reads_time_in_seconds(tmp_path):
    """No epoch in the file: plain xarray gives the very seconds written, not 1970
    datetimes rounded to whole nanoseconds."""
    written = _labelled_run(tmp_path / "run.nc")
    with xr.open_dataset(tmp_path / "run.nc") as plain:
        assert plain.time.dtype == np.float64
        np.testing.assert_array_equal(plain.time.values, written.time.values)
        assert plain.time.attrs["units"] == "s"
        assert "since" not in plain.time.attrs["units"]


def test_backend_indexes_the_labels(tmp_path):
    """``engine=`` the backend class: ``.sel(member=...)`` works on plain xarray."""
    from pygear.io import PygearBackendEntrypoint

    written = _labelled_run(tmp_path / "run.nc")
    with xr.open_dataset(tmp_path / "run.nc", engine=PygearBackendEntrypoint) as run:
        sun = run.speed.sel(member="planetary.sun")
        np.testing.assert_array_equal(sun.values, written.speed.sel(member="planetary.sun"))
        np.testing.assert_array_equal(run.time.values, written.time.values)
    with xr.open_mfdataset(
        [tmp_path / "run.nc"],
        engine=PygearBackendEntrypoint,
        combine="nested",
        concat_dim="scene",
    ) as stacked:
        assert stacked.speed.sel(scene="steady", member="planetary.carrier").values[0] == 120.0


def test_engine_pygear_is_registered_for_xarray(tmp_path):
    """pyproject.toml declares the entry point; where the installed metadata has it
    (an install after that declaration), ``engine="pygear"`` reads by name, also a file
    of an older pygear whose time was stored against the 1970 epoch."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    backends = project["entry-points"]["xarray.backends"]
    assert backends == {"pygear": "pygear.io:PygearBackendEntrypoint"}
    # what xarray does with the declared entry point once installed: load it and check
    # the class's parameters
    from xarray.backends.plugins import backends_dict_from_pkg, set_missing_parameters

    declared = importlib.metadata.EntryPoint(
        name="pygear", value=backends["pygear"], group="xarray.backends"
    )
    engines = backends_dict_from_pkg([declared])
    set_missing_parameters(engines)
    assert "decode_times" in engines["pygear"].open_dataset_parameters
    installed = importlib.metadata.entry_points(group="xarray.backends")
    if "pygear" not in installed.names:
        pytest.skip("the installed metadata predates the entry point: reinstall pygear")
    time = np.arange(4) / 4.0
    old = xr.Dataset(
        {"x": ("time", np.arange(4.0), {"units": "m"})},
        coords={"time": ("time", time, {"units": "seconds since 1970-01-01 00:00:00"})},
    )
    old.to_netcdf(tmp_path / "old.nc")
    with xr.open_dataset(tmp_path / "old.nc", engine="pygear") as read:
        np.testing.assert_array_equal(read.time.values, time)
        assert read.time.attrs["units"] == "s"


# --- item 18: batches of other probes and other kinds ---------------------------------------


def test_runups_with_other_probes_stack(batch):
    """Two run-ups record ``translation_dof``, the third does not: the stack holds it,
    NaN for that scene, and each scene's values are its own file's."""
    with open_mfdataset(str(batch / "runup*.nc")) as stacked:
        assert sorted(stacked.scene.values.tolist()) == [
            "runup",
            "runup_consistent",
            "runup_wide",
        ]
        ring = stacked.translation_acceleration.sel(translation_dof="planetary.ring.y")
        assert np.isnan(ring.sel(scene="runup_wide").values).all()
        for scene in stacked.scene.values.tolist():
            with open_dataset(batch / f"{scene}.nc") as alone:
                own = stacked.sel(scene=scene, time=alone.time.values)
                np.testing.assert_array_equal(
                    own.speed.sel(member="planetary.carrier").values,
                    alone.speed.sel(member="planetary.carrier").values,
                )
                if "translation_acceleration" in alone:
                    np.testing.assert_array_equal(
                        own.translation_acceleration.values,
                        alone.translation_acceleration.values,
                    )


def test_files_of_other_kinds_stack(batch):
    """``*.nc`` of a batch: the modal file (``mode_class`` a variable there, a
    coordinate in the runs) and a sensor run (its own coordinates over ``sensor``)
    stack with the run-ups; each scene keeps its own values."""
    with open_mfdataset(str(batch / "*.nc")) as stacked:
        assert set(stacked.scene.values.tolist()) == {
            "modal",
            "runup",
            "runup_consistent",
            "runup_wide",
            "steady_sensor",
        }
        with open_dataset(batch / "modal.nc") as modal:
            np.testing.assert_array_equal(
                stacked.frequency.sel(scene="modal").values, modal.frequency.values
            )
        with open_dataset(batch / "steady_sensor.nc") as sensor:
            own = stacked.sel(scene="steady_sensor", time=sensor.time.values)
            np.testing.assert_array_equal(
                own.sensor_acceleration.values, sensor.sensor_acceleration.values
            )
            assert "sensor_angle" in stacked.coords  # a coordinate again after stacking
            assert own.sensor_angle.values.tolist() == sensor.sensor_angle.values.tolist()
        assert np.isnan(stacked.frequency.sel(scene="runup").values).all()


# --- item 8: the git revision a file records ------------------------------------------------


def _user_repository(path: Path) -> str:
    """A git repository with one commit; returns its commit hash."""
    path.mkdir(parents=True, exist_ok=True)
    env = {k: v for k, v in os.environ.items() if not k.startswith("GIT_")}
    git = ["git", "-c", "user.name=u", "-c", "user.email=u@example.org", "-C", str(path)]
    subprocess.run([*git, "init", "-q"], check=True, env=env)
    (path / "notes.txt").write_text("the user's own work\n")
    subprocess.run([*git, "add", "notes.txt"], check=True, env=env)
    subprocess.run([*git, "commit", "-q", "-m", "user"], check=True, env=env)
    return subprocess.run(
        [*git, "rev-parse", "HEAD"], check=True, env=env, capture_output=True, text=True
    ).stdout.strip()


def test_an_installed_copy_inside_a_repository_records_its_build_revision(tmp_path):
    """pygear installed into a virtual environment inside the user's repository, run
    from there: the file's ``source`` names the revision written at build time, never
    the user's commit (io.py, io_read.py and _version.py as installed, without
    site-packages)."""
    repository = tmp_path / "user"
    commit = _user_repository(repository)
    package = repository / ".venv" / "site-packages" / "pygear"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    for name in ("io.py", "io_read.py", "_version.py"):
        shutil.copy(ROOT / "pygear" / name, package / name)
    (package / "_git_revision.py").write_text('GIT_REVISION = "0123456789ab"\n')
    env = {**os.environ, "PYTHONPATH": str(package.parent)}
    result = subprocess.run(
        [sys.executable, "-S", "-c", "from pygear.io import source_string; print(source_string())"],
        cwd=repository,
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    assert result.stdout.strip() == f"pygear {pygear.__version__} (git 0123456789ab)"
    assert commit[:7] not in result.stdout


def test_a_repository_around_the_working_directory_changes_no_revision(tmp_path):
    """This pygear, run inside another repository as its git hook would (GIT_DIR set):
    ``source`` and ``--version`` name pygear's revision, not that repository's commit."""
    repository = tmp_path / "user"
    commit = _user_repository(repository)
    env = {**os.environ, "GIT_DIR": str(repository / ".git"), "GIT_WORK_TREE": str(repository)}
    before = _head()
    result = subprocess.run(
        [sys.executable, "-c", "from pygear.io import source_string; print(source_string())"],
        cwd=repository,
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    assert commit[:7] not in result.stdout
    assert result.stdout.startswith(f"pygear {pygear.__version__} (git ")
    # a checkout: the revision it is built from; other developers may commit meanwhile
    heads = {before, _head()} - {""}
    assert not heads or any(head[:12] in result.stdout for head in heads), (heads, result.stdout)


def _head() -> str:
    """pygear's own HEAD, asked of its checkout alone ("" when it is none)."""
    return subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "HEAD"],
        capture_output=True,
        text=True,
        env={k: v for k, v in os.environ.items() if not k.startswith("GIT_")},
    ).stdout.strip()
