"""``pygear rate``: the JSON keys and units, the files of --out, a duty-cycle file, and
the one-line errors of a case without rating data or a bad duty-cycle file."""

from __future__ import annotations

import json
import math

import pytest
import xarray as xr

from pygear.cli.parser import main


def _json(capsys, *argv: str) -> dict:
    # ISO's K_v: these tests are about the files and the JSON, not the dynamic model
    assert main(["rate", *argv, "--dynamic-factor", "iso", "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_json_of_the_nrel_gearbox(capsys):
    doc = _json(capsys, "nrel5mw_gearbox")
    assert set(doc) >= {"gears", "meshes", "bearings", "limiting"}
    assert set(doc["gears"]) == {f"stage{k}.{m}" for k in (1, 2) for m in
                                 ("sun", "planet", "ring")} | {"parallel.input_gear",
                                                                "parallel.output_gear"}
    for values in doc["gears"].values():
        assert set(values) >= {"sigma_F0", "sigma_F", "sigma_H", "S_H", "S_F", "damage",
                               "life_h"}
    sun = doc["meshes"]["stage1.sun_mesh"]
    # F_t in N: 2 T_sun / (3 d_sun) at 5 MW and 12.1 rpm, by hand
    t_sun = 5e6 / (12.1 * math.pi / 30.0) / (1.0 + 56.0 / 19.0)
    assert sun["F_t"] == pytest.approx(2.0 * t_sun / (3.0 * 0.855), rel=1e-9)
    # stresses in MPa: a carburized sun's contact stress is of order 1000 MPa, not 1e9
    assert 500.0 < doc["gears"]["stage1.sun"]["sigma_H"] < 2000.0
    assert {"K_v", "K_Hbeta", "K_gamma", "sigma_H0"} <= set(sun)
    assert "K_Hbeta" in sun["given"] and "K_v" not in sun["given"]
    assert set(doc["bearings"]) == {"PL-A", "PL-B", "IMS-PL-A", "IMS-PL-B", "HS-A", "HS-B",
                                    "HS-C"}
    assert doc["limiting"].startswith("stage1.ring ")


def test_out_writes_the_dataset_the_report_and_the_figure(tmp_path, capsys):
    assert main(["rate", "nrel5mw_gearbox", "--dynamic-factor", "iso", "--out",
                 str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    assert "limiting: stage1.ring " in printed
    with xr.open_dataset(tmp_path / "rating.nc", engine="pygear") as ds:  # labels indexed
        assert ds.S_H.attrs["units"] == "1" and ds.sigma_H.attrs["units"] == "MPa"
        assert "ISO 6336-1:2019" in ds.K_v.attrs["clause"]
        assert ds.K_Hbeta_source.sel(mesh="stage1.sun_mesh").item() == "given"
        method = ds.attrs["K_v_method"]
        assert method.endswith("asked for with --dynamic-factor iso")
        assert ds.attrs["limiting"].startswith("stage1.ring")
    report = (tmp_path / "rating.md").read_text()
    assert "## Factors per mesh" in report and "(given)" in report and "FAIL" in report
    assert f"- K_v: {method}" in report and "| damage from |" in report
    assert (tmp_path / "rating.png").stat().st_size > 0


@pytest.mark.slow
def test_k_v_comes_from_the_dynamic_model_by_default(tmp_path, capsys):
    # one harmonic balance of the whole gearbox at the rated speed (10-60 s here): its
    # K_v, or ISO's method B with the reason where the balance misses its tolerance
    assert main(["rate", "nrel5mw_gearbox", "--out", str(tmp_path)]) == 0
    capsys.readouterr()
    with xr.open_dataset(tmp_path / "rating.nc", engine="pygear") as ds:
        method = ds.attrs["K_v_method"]
        sources = set(ds.K_v_source.values.tolist())
    if method.startswith("response analysis"):
        assert sources == {"response"}
    else:
        assert method.startswith("ISO 6336-1:2019 method B (cl. 6.3): the response")
        assert sources == {"computed"}
    assert f"- K_v: {method}" in (tmp_path / "rating.md").read_text()


def test_a_duty_cycle_file_lowers_the_damage(tmp_path, capsys):
    # half the rated torque for the whole life: the damage of every gear falls
    rated = _json(capsys, "nrel5mw_gearbox")
    spectrum = tmp_path / "ldd.csv"
    torque = 5e6 / (12.1 * math.pi / 30.0)
    spectrum.write_text(f"torque,hours\n{0.5 * torque},175200\n")
    light = _json(capsys, "nrel5mw_gearbox", "--duty-cycle", str(spectrum))
    for gear, values in light["gears"].items():
        assert values["damage"] < rated["gears"][gear]["damage"], gear
    series = tmp_path / "series.csv"
    series.write_text("time,torque\n0,3e6\n1,4e6\n2,3.5e6\n3,4e6\n")
    assert "gears" in _json(capsys, "nrel5mw_gearbox", "--duty-cycle", str(series))


def test_a_case_without_rating_data_says_what_to_add(capsys):
    assert main(["rate", "yang2016_planetary"]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1
    assert "has no rating data: add a module-level `rating = Rating(" in error


def test_a_bad_duty_cycle_file_is_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("load,duration\n1,2\n")
    assert main(["rate", "nrel5mw_gearbox", "--duty-cycle", str(bad)]) == 2
    error = capsys.readouterr().err.strip()
    assert "needs columns 'torque' and 'hours'" in error and len(error.splitlines()) == 1
