"""Sweep reruns reuse points by their values and their code, never by their place in the
list; a sweep never deletes another sweep's files; bad point files are run again."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pygear import CaseError, load_case
from pygear import io as pygear_io
from pygear.analysis.modes.modal import modal_analysis
from pygear.assembly import assemble
from pygear.cli import batch
from pygear.model.case import replace_parameter
from pygear.runs import sweep
from pygear.runs.sweep_points import dimension_name

ROOT = Path(__file__).resolve().parent.parent
PLANETARY = ROOT / "cases" / "yang2016_planetary"
SUN = "planetary.sun_mesh.stiffness"
RING = "planetary.ring_mesh.stiffness"

# Pairs of (sun-planet, ring-planet) mesh stiffness [N/m]; their lowest elastic
# frequencies differ by tens of per cent, so a result placed on the wrong pair shows.
PAIRS = [(1e8, 3e8), (4e8, 6e8), (9e8, 2e8)]

# A point read back from its file holds the numbers written (NetCDF float64 round
# trip is exact); against a fresh eigen-solution in this process, 1e-10 allows the
# round-off of LAPACK's symmetric eigensolver between two calls on the same matrices.
RTOL = 1e-10


@pytest.fixture
def fresh_source_identity():
    """Forget the cached source identity before and after a test that fakes it."""
    pygear_io.source_identity.cache_clear()
    yield
    pygear_io.source_identity.cache_clear()


def direct_frequencies(sun: float, ring: float) -> np.ndarray:
    """The point's natural frequencies [Hz] from a modal analysis run here, not swept."""
    case = load_case(PLANETARY)
    changed = replace_parameter(replace_parameter(case, SUN, sun), RING, ring)
    return modal_analysis(assemble(changed, case.scene("modal"))).frequency.values


def zipped(pairs, out, scheduler):
    return sweep.run_sweep(
        PLANETARY,
        [(SUN, [p[0] for p in pairs]), (RING, [p[1] for p in pairs])],
        zip_params=True,
        scene="modal",
        out_dir=out,
        scheduler=scheduler,
        progress=False,
    )


def grid(params, out, scheduler):
    return sweep.run_sweep(
        PLANETARY, params, scene="modal", out_dir=out, scheduler=scheduler, progress=False
    )


def assert_on_their_values(result: xr.Dataset, pairs) -> None:
    for index, (sun, ring) in enumerate(pairs):
        point = result.sel(point=index)
        assert float(point[dimension_name(SUN)]) == sun
        assert float(point[dimension_name(RING)]) == ring
        np.testing.assert_allclose(point.frequency.values, direct_frequencies(sun, ring), rtol=RTOL)


def point_files(directory: Path) -> dict[str, float]:
    """Every point file and its modification time."""
    return {p.name: p.stat().st_mtime_ns for p in directory.glob("point_*.nc")}


def test_zipped_rerun_reordered_and_fewer_values_reuses_by_value(tmp_path, scheduler):
    first = zipped(PAIRS, tmp_path, scheduler)
    assert first.attrs["points_computed"] == 3
    assert_on_their_values(first, PAIRS)
    # the same pairs in reverse order: every point comes from its file, on its values
    reordered = PAIRS[::-1]
    again = zipped(reordered, tmp_path, scheduler)
    assert list(again.point_status.values) == ["reused"] * 3
    assert_on_their_values(again, reordered)
    # one pair left out
    fewer = [PAIRS[2], PAIRS[0]]
    second = zipped(fewer, tmp_path, scheduler)
    assert second.attrs["points_reused"] == 2 and second.attrs["points_computed"] == 0
    assert list(second.point_status.values) == ["reused", "reused"]
    assert np.isfinite(second.frequency.values).all()  # no reused point without numbers
    assert_on_their_values(second, fewer)
    # a new pair in the middle: only it runs
    more = [PAIRS[1], (2e8, 8e8), PAIRS[2]]
    third = zipped(more, tmp_path, scheduler)
    assert list(third.point_status.values) == ["reused", "computed", "reused"]
    assert_on_their_values(third, more)


def test_grid_points_reused_by_a_zipped_sweep(tmp_path, scheduler):
    """A point's file serves any sweep that reaches the same inputs, whatever its layout."""
    grid([(SUN, [1e8, 9e8]), (RING, [3e8, 2e8])], tmp_path, scheduler)
    result = zipped([PAIRS[2], PAIRS[0]], tmp_path, scheduler)
    assert list(result.point_status.values) == ["reused", "reused"]
    assert_on_their_values(result, [PAIRS[2], PAIRS[0]])


def test_error_record_or_nan_results_are_run_again(tmp_path, scheduler):
    first = zipped(PAIRS[:2], tmp_path, scheduler)
    hashes = [str(h) for h in first.point_hash.values]
    assert len(set(hashes)) == 2 and all(len(h) == 16 for h in hashes)
    # point 0: an error record beside its file (a point that failed after it was written)
    error_path = tmp_path / f"point_{hashes[0]}.error.json"
    error_path.write_text(json.dumps({"error": "worker lost"}))
    # point 1: its file holds NaN where the frequencies were
    path = tmp_path / f"point_{hashes[1]}.nc"
    with xr.open_dataset(path) as opened:
        damaged = opened.load()
    damaged["frequency"][:] = np.nan
    damaged.to_netcdf(path)
    second = zipped(PAIRS[:2], tmp_path, scheduler)
    assert list(second.point_status.values) == ["computed", "computed"]
    assert_on_their_values(second, PAIRS[:2])
    assert not error_path.exists()  # the point ran cleanly
    third = zipped(PAIRS[:2], tmp_path, scheduler)
    assert list(third.point_status.values) == ["reused", "reused"]


def test_source_identity_follows_every_source_file(tmp_path, fresh_source_identity, monkeypatch):
    listed = pygear_io._source_files()
    names = {p.name for p in listed}
    assert {"sweep.py", "sweep_points.py", "calls.py", "__init__.py"} <= names
    assert any(p.name.startswith("_kernel") for p in listed)  # the compiled kernel
    if (ROOT / "fortran").is_dir():  # an editable install: the Fortran sources too
        assert ROOT / "fortran" / "elements.f90" in listed
    python_file, fortran_file = tmp_path / "a.py", tmp_path / "b.f90"
    python_file.write_text("x = 1\n")
    fortran_file.write_text("module b\nend module b\n")
    monkeypatch.setattr(pygear_io, "_source_files", lambda: [python_file, fortran_file])
    pygear_io.source_identity.cache_clear()
    before = pygear_io.source_identity()
    assert pygear_io.source_identity() == before  # cached
    fortran_file.write_text("module b\nimplicit none\nend module b\n")
    assert pygear_io.source_identity() == before  # computed once per process
    pygear_io.source_identity.cache_clear()
    assert pygear_io.source_identity() != before


def test_code_change_runs_every_point_again(
    tmp_path, scheduler, fresh_source_identity, monkeypatch
):
    source = tmp_path / "src" / "elements.f90"
    source.parent.mkdir()
    source.write_text("module elements\nend module elements\n")
    monkeypatch.setattr(pygear_io, "_source_files", lambda: [source])
    pygear_io.source_identity.cache_clear()
    out = tmp_path / "sweep"
    assert zipped(PAIRS[:2], out, scheduler).attrs["points_computed"] == 2
    assert zipped(PAIRS[:2], out, scheduler).attrs["points_reused"] == 2
    source.write_text("module elements\nimplicit none\nend module elements\n")
    pygear_io.source_identity.cache_clear()  # a new process after the edit
    changed = zipped(PAIRS[:2], out, scheduler)
    assert changed.attrs["points_computed"] == 2 and changed.attrs["points_reused"] == 0


def test_second_sweep_keeps_the_first_sweeps_files(tmp_path, scheduler):
    first = grid([(SUN, [1e8, 4e8])], tmp_path, scheduler)
    first_files = point_files(tmp_path)
    assert len(first_files) == 2
    first_combined = Path(first.attrs["path"])
    second = grid([(RING, [2e8, 6e8, 8e8])], tmp_path, scheduler)
    assert second.attrs["points_computed"] == 3
    after = point_files(tmp_path)
    assert {k: after[k] for k in first_files} == first_files  # untouched
    assert len(after) == 5
    assert Path(second.attrs["path"]) != first_combined
    with xr.open_dataset(first_combined) as kept:  # the first sweep's dataset is still there
        np.testing.assert_allclose(kept.frequency.values, first.frequency.values, rtol=0)
    again = grid([(SUN, [1e8, 4e8])], tmp_path, scheduler)
    assert again.attrs["points_reused"] == 2 and point_files(tmp_path) == after


def test_out_must_be_a_directory(tmp_path):
    out = tmp_path / "results.nc"
    out.write_text("not a sweep")
    parser = argparse.ArgumentParser(prog="pygear")
    batch.add_parsers(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(["sweep", str(PLANETARY), "--param", f"{SUN}=1e8", "--out", str(out)])
    with pytest.raises(CaseError, match="--out .* is a file"):
        batch.HANDLERS["sweep"](args)
    assert out.read_text() == "not a sweep"


def test_nan_is_trusted_only_where_it_is_an_answer(tmp_path):
    """A run-up that never reaches its speed has t_s = NaN: its file is reused; NaN in
    a mesh force is no answer, and that file runs again."""
    digest = "0123456789abcdef"
    point = xr.Dataset(
        {"t_s": ((), np.nan), "sun_mesh_force_rms": ((), 12.5)},
        attrs={"point_hash": digest, "point_parameters": json.dumps({SUN: 1e8})},
    )
    point.to_netcdf(tmp_path / f"point_{digest}.nc")
    reused = sweep._reusable_point(tmp_path, digest)
    assert reused is not None and np.isnan(float(reused.t_s))
    assert sweep._reusable_point(tmp_path, "fedcba9876543210") is None  # no such file
    point["sun_mesh_force_rms"] = ((), np.nan)
    point.to_netcdf(tmp_path / f"point_{digest}.nc")
    assert sweep._reusable_point(tmp_path, digest) is None
