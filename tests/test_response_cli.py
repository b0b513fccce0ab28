"""``pygear response``: options checked before any work, one-line errors, the JSON keys,
the dataset's CF attributes, every gear case kind and the plain rotor's answer."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from pygear.cli import main
from pygear.io import open_dataset

ROOT = Path(__file__).resolve().parent.parent
CASE = str(ROOT / "cases" / "yang2016_planetary")


@pytest.mark.parametrize(
    ("argv", "flag"),
    [
        (["--speeds", "100:200:0"], "--speeds"),
        (["--speeds", "100:200:-3"], "--speeds"),
        (["--speeds", "100:200:2.5"], "--speeds"),
        (["--speeds", "a:200:3"], "--speeds"),
        (["--speeds", "100:200"], "--speeds"),
        (["--speeds=-100:200:3"], "--speeds"),
        (["--speeds", "0:200:3"], "--speeds"),
        (["--speeds", "300:200:3"], "--speeds"),
        (["--speeds", "100:200:3", "--harmonics", "many"], "--harmonics"),
        (["--speeds", "100:200:3", "--harmonics", "-1"], "--harmonics"),
        (["--speeds", "100:200:3", "--tolerance", "0"], "--tolerance"),
        (["--speeds", "100:200:3", "--pin-error", "planet1"], "--pin-error"),
    ],
)
def test_bad_option_is_one_line_exit_2_naming_it(argv, flag, capsys, monkeypatch):
    """Checked before the case is even loaded: a case that does not exist is never
    reached."""
    monkeypatch.setattr("pygear.model.case.load_case", _no_case)
    assert main(["response", "no-such-case", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert err.startswith("pygear response: error:") and flag in err


def _no_case(*args, **kwargs):
    raise AssertionError("the case was loaded before the options were checked")


KEYS = ("speeds_rpm", "dynamic_factor", "load_sharing", "dte_rms_m", "separation", "stable",
        "harmonics", "residual")


@pytest.mark.parametrize(
    ("case", "extra", "stages"),
    [("yang2016_gearbox", [], ["stage1", "stage2"]),
     ("nrel5mw_drivetrain", ["--no-stability"], ["stage1", "stage2"])],
)
def test_multistage_cases_answer_with_every_key(case, extra, stages, capsys, tmp_path):
    """A gearbox and a drivetrain of several stages (meshes at incommensurate frequencies)
    go through the multi-frequency balance: every key per speed, every mesh named with
    its stage, K_gamma for each planetary stage, and the dataset says which method ran."""
    speeds = "800:1000:2" if case.startswith("yang") else "9:12:2"
    code = main(["response", str(ROOT / "cases" / case), "--speeds", speeds, "--harmonics", "8",
                 "--json", "--no-figures", "--out", str(tmp_path), *extra])  # fmt: skip
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    for key in KEYS:
        assert key in summary
    assert len(summary["speeds_rpm"]) == 2
    assert list(summary["load_sharing"]) == stages
    assert "parallel.input-output" in summary["dynamic_factor"]
    assert any(m.startswith("stage2.sun-planet") for m in summary["dynamic_factor"])
    for values in summary["dynamic_factor"].values():
        assert len(values) == 2 and all(v > 1 for v in values)  # peak above the mean
    assert summary["harmonics"] == [8, 8]
    assert all(r >= 0 for r in summary["residual"])
    assert summary["stable"] == ([None, None] if extra else [True, True])
    with open_dataset(tmp_path / "response.nc") as dataset:
        assert dataset.attrs["method"].startswith("multi-frequency")
        assert dataset.attrs["frequency_groups"] == 3


def test_rotor_case_names_the_unbalance_command(capsys, tmp_path):
    """A plain rotor has no mesh: one line naming pygear frf, exit 2, no file."""
    code = main(["response", str(ROOT / "cases" / "friswell_rotor"), "--speeds", "100:200:2",
                 "--out", str(tmp_path)])  # fmt: skip
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and "pygear frf" in err
    assert not list(tmp_path.iterdir())


def test_json_keys_and_dataset(capsys, tmp_path):
    """The JSON holds one value per speed under every key the issue names; the dataset
    has speed x mesh x harmonic, CF units and long names on every variable, and agrees
    with the JSON."""
    code = main(["response", CASE, "--speeds", "600:900:3", "--harmonics", "16", "--json",
                 "--out", str(tmp_path), "--no-figures"])  # fmt: skip
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    for key in KEYS:
        assert key in summary
    assert summary["speeds_rpm"] == [600.0, 750.0, 900.0]
    assert set(summary["dynamic_factor"]) == {
        f"{m}-planet{n}" for m in ("sun", "ring") for n in (1, 2, 3)
    }
    assert list(summary["load_sharing"]) == ["planetary"]
    assert summary["harmonics"] == [16, 16, 16]
    assert all(len(v) == 3 for v in summary["dte_rms_m"].values())
    assert all(isinstance(s, bool) for s in summary["stable"])
    files = [Path(f) for f in summary["files"]]
    assert files == [tmp_path / "response.nc"]
    with open_dataset(files[0]) as dataset:
        assert {"speed", "mesh", "harmonic"} <= set(dataset.dims)
        assert dataset.attrs["Conventions"].startswith("CF")
        for name, variable in {**dataset.data_vars, **dataset.coords}.items():
            assert "long_name" in variable.attrs, name
            if variable.dtype.kind in "fiu":
                assert "units" in variable.attrs, name
        kv = dataset.dynamic_factor.sel(mesh="sun-planet1").values
        assert np.allclose(kv, summary["dynamic_factor"]["sun-planet1"], rtol=1e-12)
        assert (kv > 1).all()


def test_figures_written(tmp_path, capsys):
    code = main(["response", CASE, "--speeds", "700:700:1", "--harmonics", "8",
                 "--out", str(tmp_path)])  # fmt: skip
    assert code == 0
    out = capsys.readouterr().out
    names = {"response.nc", "response_dynamic_factor.png", "response_load_sharing.png",
             "response_stability.png"}  # fmt: skip
    assert {p.name for p in tmp_path.iterdir()} == names
    assert "sun-planet1" in out
