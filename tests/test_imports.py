"""Each ``pygear`` command loads only what it uses: checked in fresh processes.

``pygear --help`` loads no numerical library; the ``pygear modal`` table loads NumPy
alone (xarray, NetCDF and Matplotlib only with ``--out``); a run loads no Dask (it
computes without it), neither ``scipy.signal`` nor ``scipy.linalg`` and, with
``--no-figures``, no Matplotlib, and draws its figures only after every NetCDF file of
the scene is written.  Module
sets, never wall times: what a command imports is the same on any machine.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

STUDY = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"

NUMERICS = {
    "numpy",
    "scipy",
    "pandas",
    "xarray",
    "netCDF4",
    "matplotlib",
    "pyfftw",
    "dask",
    "distributed",
}
"""Libraries that cost a command time and memory when imported."""

RUNNER = """
import json, sys
from pygear.cli import main
sys.argv[0] = "pygear"
try:
    code = main()  # as the console script calls it: the command line from sys.argv
except SystemExit as stop:
    code = stop.code
loaded = sorted(name for name, module in sys.modules.items() if module is not None)
print(json.dumps({"code": code, "modules": loaded}))
"""
"""Runs one command in a fresh interpreter, as ``pygear`` does, and prints the modules
it left loaded."""

SHORT_RUNUP = f"""
import dataclasses

from pygear import load_case

base = load_case({str(STUDY)!r})
runup = base.scene("runup")
# 1.25 s: the signal analysis skips the first second and needs samples after it
settings = dataclasses.replace(runup.transient, duration=1.25, mean_window=0.1)
case = dataclasses.replace(
    base, name="short", scenes=(dataclasses.replace(runup, transient=settings),)
)
"""


def _loaded(*argv: str, cwd: Path | None = None) -> set[str]:
    """Modules loaded by ``pygear ARGV`` in a fresh process (its output discarded)."""
    result = subprocess.run(
        [sys.executable, "-c", RUNNER, *argv], capture_output=True, text=True, cwd=cwd
    )
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout.strip().splitlines()[-1])
    assert report["code"] in (0, None), result.stderr
    return set(report["modules"])


def _top_level(modules: set[str]) -> set[str]:
    return {name.split(".", 1)[0] for name in modules}


def test_help_loads_no_numerical_library():
    assert _top_level(_loaded("--help")) & NUMERICS == set()


@pytest.mark.parametrize("command", ["run", "modal", "batch", "sweep", "campbell", "analyze"])
def test_command_help_loads_no_numerical_library(command):
    assert _top_level(_loaded(command, "--help")) & NUMERICS == set()


def test_modal_table_loads_numpy_alone():
    assert _top_level(_loaded("modal", str(STUDY))) & NUMERICS == {"numpy"}


@pytest.fixture(scope="module")
def short_case(tmp_path_factory) -> Path:
    directory = tmp_path_factory.mktemp("short")
    (directory / "case.py").write_text(SHORT_RUNUP)
    return directory


def test_run_without_figures_loads_no_plotting_and_no_dask(short_case, tmp_path):
    modules = _loaded("run", str(short_case), "--no-figures", "--out", str(tmp_path), "--json")
    top = _top_level(modules)
    assert {"xarray", "netCDF4", "pyfftw"} <= top  # it did run, analyse and write
    assert top & {"matplotlib", "dask", "distributed"} == set()
    assert {"scipy.signal", "scipy.fftpack", "scipy.linalg"} & modules == set()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["runup.nc", "spectra"]
    assert sorted(p.name for p in (tmp_path / "spectra").iterdir()) == [
        "runup_acceleration_planetary.ring.y.nc",
        "runup_acceleration_planetary.sun.theta_z.nc",
    ]


def test_run_draws_figures_after_every_netcdf_file(short_case, tmp_path):
    top = _top_level(_loaded("run", str(short_case), "--out", str(tmp_path), "--json"))
    assert "matplotlib" in top and top & {"dask", "distributed"} == set()
    data = [p.stat().st_mtime_ns for p in tmp_path.rglob("*.nc")]
    figures = [p.stat().st_mtime_ns for p in tmp_path.rglob("*.png")]
    assert len(data) == 3 and len(figures) == 3  # run file, two spectra; speeds, two spectra
    # every figure is renamed into place after the last NetCDF file (equal on a coarse clock)
    assert min(figures) >= max(data)


def test_main_called_from_python_leaves_dask_visible(tmp_path):
    """Dask is hidden only from a command that is the whole process: ``main([...])``
    called from Python (a notebook, a test) builds its datasets as xarray always does."""
    script = f"""
import sys
from pygear.cli import main
assert main(["mesh-stiffness", {str(STUDY)!r}, "--duration", "0.01",
             "--out", {str(tmp_path / "mesh.nc")!r}, "--json"]) == 0
assert "dask.array" in sys.modules  # imported by xarray, as without pygear
"""
    result = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, cwd=tmp_path
    )
    assert result.returncode == 0, result.stderr


def test_hidden_dask_leaves_no_trace_in_the_process(tmp_path):
    """After a command run as the process (``main()``), ``sys.modules`` holds no
    placeholder for Dask: an import of Dask at exit (an atexit hook, a plugin) works."""
    script = f"""
import sys
from pygear.cli import main
sys.argv = ["pygear", "mesh-stiffness", {str(STUDY)!r}, "--duration", "0.01",
            "--out", {str(tmp_path / "mesh.nc")!r}, "--json"]
assert main() == 0
assert "dask" not in sys.modules  # hidden while xarray built and wrote the datasets
import dask
"""
    result = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, cwd=tmp_path
    )
    assert result.returncode == 0, result.stderr
