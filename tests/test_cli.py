"""The command line: JSON output, files written, clear errors."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pygear.cli import main

CASE = str(Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary")


def test_modal_json(capsys):
    assert main(["modal", CASE, "--formulation", "lin-parker", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    frequencies = result["frequencies_hz"]
    assert frequencies == sorted(frequencies) and len(frequencies) == 18
    assert len(result["mode_class"]) == 18 and result["formulation"] == "lin-parker"
    assert abs(frequencies[5] / 1477.4 - 1) < 0.005  # Table 2, Lin-Parker rotational 2


def test_modal_by_case_name(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(Path(CASE).parent.parent)
    assert main(["modal", "yang2016_planetary", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "1334.0" in out and "rotational 2" in out
    assert (tmp_path / "modal_improved.nc").is_file()


def test_matrices(tmp_path):
    target = tmp_path / "m.npz"
    assert main(["matrices", CASE, "--formulation", "consistent", "--out", str(target)]) == 0
    data = np.load(target)
    assert data["M"].shape == (18, 18) == data["K"].shape == data["C"].shape
    assert len(data["dof_labels"]) == 18
    # Rayleigh damping of the case file: C = 0.13 M + 1e-6 K
    np.testing.assert_allclose(data["C"], 0.13 * data["M"] + 1e-6 * data["K"], rtol=1e-12)


def test_sensitivity_sweep(tmp_path, capsys):
    assert (
        main(
            [
                "sensitivity",
                CASE,
                "--parameter",
                "planetary.sun_mesh.stiffness",
                "--values",
                "logspace(7,10,4)",
                "--formulation",
                "improved",
                "lin-parker",
                "--out",
                str(tmp_path),
                "--json",
            ]
        )
        == 0
    )
    result = json.loads(capsys.readouterr().out)
    assert result["values"] == pytest.approx([1e7, 1e8, 1e9, 1e10])
    sweep = xr.open_dataset(result["files"][0])
    assert dict(sweep.sizes) == {"formulation": 2, "value": 4, "mode": 18}
    assert sweep.frequency.attrs["units"] == "Hz"
    # stiffer meshes never lower a natural frequency
    assert np.all(np.diff(sweep.frequency.values, axis=1) >= -1e-6)
    sweep.close()


def test_run_writes_netcdf_and_figures(tmp_path, capsys):
    assert main(["run", CASE, "--scene", "modal", "--out", str(tmp_path), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["scenes"]["modal"]["dof_set"] == "planar"
    with xr.open_dataset(tmp_path / "modal.nc") as modal:
        assert modal.frequency.attrs["units"] == "Hz"
        assert modal.attrs["formulation"] == "improved"
        assert modal.attrs["Conventions"].startswith("CF")
        assert "input_hash" in modal.attrs
    assert (tmp_path / "modal_energy.png").stat().st_size > 1000
    assert (tmp_path / "modal_mode_shape.png").stat().st_size > 1000
    assert not list(tmp_path.glob(".*part"))


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["modal", "no_such_case"], "no case.py found"),
        (
            ["sensitivity", CASE, "--parameter", "planetary.sun.mass", "--values", "1"],
            "is not a stiffness of this model",
        ),
        (
            [
                "sensitivity",
                CASE,
                "--parameter",
                "planetary.sun_mesh.stiffness",
                "--values",
                "logspace(7,x,3)",
            ],
            "--values",
        ),
        (
            ["sensitivity", CASE, "--parameter", "planetary.sun_mesh.stiffness", "--values", "-1"],
            "planetary.sun_mesh.stiffness must be a positive",
        ),
        (["run", CASE, "--scene", "nothing"], "has no scene 'nothing'"),
    ],
)
def test_errors_name_the_parameter(argv, message, capsys, tmp_path):
    assert main([*argv]) == 2
    assert message in capsys.readouterr().err


def test_console_script_runs():
    result = subprocess.run(
        [sys.executable, "-m", "pygear.cli", "modal", CASE, "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert json.loads(result.stdout)["mode_class"][0] == "rotational"


def test_version_names_the_kernel_blas(capsys):
    """``pygear --version`` says which OpenBLAS the kernel links and which CPU kernels
    it chose (a generic fallback would show as Prescott/Katmai)."""
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith("pygear ")
    assert "kernel BLAS: OpenBLAS" in out and "core" in out and "unknown" not in out
