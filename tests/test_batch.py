"""Batch runs and parameter sweeps on Dask: same numbers as serial runs, reruns that skip
finished points, failures that stay local, validation before any work, the commands."""

from __future__ import annotations

import argparse
import dataclasses
import json
import signal
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from pygear import CaseError, Scene, load_case
from pygear.analysis.modes.modal import modal_analysis
from pygear.analysis.time.transient import run_transient
from pygear.assembly import assemble
from pygear.assembly.drivetrain_model import scene_model
from pygear.cli import batch as batch_cli
from pygear.model.case import replace_parameter
from pygear.model.rotor_case import RotorCase
from pygear.runs import batch, sweep
from pygear.runs.cluster import jobqueue_cluster, validate_cluster_options

ROOT = Path(__file__).resolve().parent.parent
CASES = ROOT / "cases"
PLANETARY = CASES / "yang2016_planetary"
SUN = "planetary.sun_mesh.stiffness"
RING = "planetary.ring_mesh.stiffness"
# the sweep's dimensions: each path with its dots as "__", a keyword .sel() takes
SUN_DIM, RING_DIM = "planetary__sun_mesh__stiffness", "planetary__ring_mesh__stiffness"


def reference(case, assignments, scene="modal"):
    """The point computed by hand, one call after another."""
    for path, value in assignments.items():
        case = replace_parameter(case, path, value)
    return modal_analysis(assemble(case, case.scene(scene)))


def sweep_6(case_ref, out, scheduler, **kwargs):
    return sweep.run_sweep(
        case_ref,
        [(SUN, "1e8,3e8,9e8"), (RING, [2e8, 7e8])],
        out_dir=out,
        scheduler=scheduler,
        progress=False,
        **kwargs,
    )


def test_grid_sweep_matches_serial_runs(tmp_path, scheduler):
    case = load_case(PLANETARY)
    result = sweep_6(PLANETARY, tmp_path, scheduler)
    assert result.sizes[SUN_DIM] == 3 and result.sizes[RING_DIM] == 2
    np.testing.assert_array_equal(result[SUN_DIM].values, [1e8, 3e8, 9e8])
    np.testing.assert_array_equal(result[RING_DIM].values, [2e8, 7e8])
    assert result.frequency.dims == (SUN_DIM, RING_DIM, "mode")
    assert result.attrs["points"] == 6 and result.attrs["points_computed"] == 6
    for sun in (1e8, 3e8, 9e8):
        for ring in (2e8, 7e8):
            expected = reference(case, {SUN: sun, RING: ring})
            point = result.sel({SUN_DIM: sun, RING_DIM: ring})
            np.testing.assert_allclose(
                point.frequency.values, expected.frequency.values, rtol=1e-10
            )
            assert list(point.mode_class.values) == list(expected.mode_class.values)
    # the point files combine by themselves, and the combined file holds the same
    files = sorted(tmp_path.glob("point_*.nc"))
    assert len(files) == 6
    with xr.open_mfdataset(
        files,
        combine="by_coords",
        data_vars="all",
        coords="different",
        compat="no_conflicts",
        join="outer",
    ) as opened:
        assert opened.sizes[SUN_DIM] == 3 and opened.sizes[RING_DIM] == 2
        np.testing.assert_allclose(opened.frequency.values, result.frequency.values, rtol=1e-12)
    combined = Path(result.attrs["path"])
    assert combined.parent == tmp_path and combined.name.startswith("sweep_")
    with xr.open_dataset(combined) as written:
        np.testing.assert_allclose(written.frequency.values, result.frequency.values, rtol=1e-12)
        assert written[SUN_DIM].attrs["units"] == "N/m"
        assert written[SUN_DIM].attrs["parameter_path"] == SUN
        assert written.frequency.attrs["units"] == "Hz"  # the points' attributes kept


def test_zipped_sweep_pairs_values(tmp_path, scheduler):
    case = load_case(PLANETARY)
    result = sweep.run_sweep(
        case,
        [(SUN, [1e8, 4e8]), (RING, "3e8, 6e8")],
        zip_params=True,
        formulation="lin-parker",
        out_dir=tmp_path,
        scheduler=scheduler,
        progress=False,
    )
    assert dict(result.sizes)["point"] == 2
    np.testing.assert_array_equal(result[RING_DIM].values, [3e8, 6e8])
    expected = modal_analysis(
        assemble(
            replace_parameter(replace_parameter(case, SUN, 4e8), RING, 6e8),
            case.scene("modal"),
            formulation="lin-parker",
        )
    )
    np.testing.assert_allclose(
        result.frequency.sel(point=1).values, expected.frequency.values, rtol=1e-10
    )


def test_scene_parameters_apply_under_the_swept_ones(tmp_path, scheduler):
    """A scene's own parameter changes hold at every point, as in `pygear run`; a swept
    parameter of the same path wins."""
    base = load_case(PLANETARY)
    scene = Scene(
        "stiff_ring",
        analyses=("modal", "sensitivity"),
        dof_set="planar",
        parameters={RING: 9e8, SUN: 2e8},
    )
    case = dataclasses.replace(base, scenes=(scene,))
    result = sweep.run_sweep(
        case, [(SUN, [1e8, 4e8])], out_dir=tmp_path, scheduler=scheduler, progress=False
    )
    for sun in (1e8, 4e8):
        changed = replace_parameter(replace_parameter(base, RING, 9e8), SUN, sun)
        expected = modal_analysis(assemble(changed, scene))
        np.testing.assert_allclose(
            result.frequency.sel({SUN_DIM: sun}).values, expected.frequency.values, rtol=1e-10
        )
    assert result.strain_energy_fraction.dims == (SUN_DIM, "mode", "parameter")


def test_rerun_computes_only_missing_points(tmp_path, scheduler):
    first = sweep_6(PLANETARY, tmp_path, scheduler)
    files = sorted(tmp_path.glob("point_*.nc"))
    for path in files[1], files[4]:
        path.unlink()
    second = sweep_6(PLANETARY, tmp_path, scheduler)
    assert second.attrs["points_computed"] == 2 and second.attrs["points_reused"] == 4
    assert sorted(p.name for p in tmp_path.glob("point_*.nc")) == [p.name for p in files]
    np.testing.assert_allclose(second.frequency.values, first.frequency.values, rtol=1e-12)
    assert (second.point_status.values == "computed").sum() == 2

    # a changed input of the case changes every point's hash: all six run again
    edited = tmp_path / "edited" / "yang2016_planetary"
    edited.mkdir(parents=True)
    text = (PLANETARY / "case.py").read_text()
    assert "BEARING_STIFFNESS = 1e8" in text
    (edited / "case.py").write_text(
        text.replace("BEARING_STIFFNESS = 1e8", "BEARING_STIFFNESS = 2e8")
    )
    third = sweep_6(edited, tmp_path, scheduler)
    assert third.attrs["points_computed"] == 6 and third.attrs["points_reused"] == 0
    # the first sweep's files stay beside the new ones: nothing is deleted
    assert len(list(tmp_path.glob("point_*.nc"))) == 12
    assert not np.allclose(third.frequency.values, first.frequency.values)


def test_failing_points_fail_alone(tmp_path, scheduler):
    # a torsional sun bearing leaves the planetary stage without its rigid-body mode,
    # refused when the point's model is assembled on a worker; the others go on (a value
    # the case refuses by itself is bad input, refused before any point: see
    # test_cli_hardening.py)
    result = sweep.run_sweep(
        PLANETARY,
        [(SUN, [2e8, 5e8]), ("planetary.sun_bearing.torsional", [0.0, 1e6])],
        out_dir=tmp_path,
        scheduler=scheduler,
        progress=False,
    )
    status = result.point_status.values
    assert list(status.ravel()) == ["computed", "failed", "computed", "failed"]
    assert result.attrs["points_failed"] == 2 and result.attrs["points_computed"] == 2
    assert np.isfinite(result.frequency.values[0, 0]).all()
    assert np.isnan(result.frequency.values[0, 1]).all()
    assert np.isnan(result.frequency.values[1, 1]).all()
    hashes = result.point_hash.values
    worker_side = json.loads((tmp_path / f"point_{hashes[1, 1]}.error.json").read_text())
    assert worker_side["parameters"] == {SUN: 5e8, "planetary.sun_bearing.torsional": 1e6}
    assert worker_side["error"] == str(result.point_error.values[1, 1]) != ""
    with xr.open_dataset(result.attrs["path"]) as written:
        assert written.point_status.values[1, 0] == "computed"


@pytest.mark.parametrize(
    ("params", "kwargs", "message"),
    [
        ([("planetary.sun_mesh.stifness", "1e8")], {}, "stifness"),
        ([("planetary.gear.stiffness", "1e8")], {}, "planetary.gear.stiffness"),
        ([("nostage.sun_mesh.stiffness", "1e8")], {}, "nostage"),
        ([(SUN, "abc")], {}, "--param planetary.sun_mesh.stiffness"),
        ([(SUN, ["1e8", "x"])], {}, "'x' is not a number"),
        ([("planetary.sun", "1")], {}, "only numbers can be swept"),
        ([(SUN, "1e8,2e8"), (RING, "1e8")], {"zip_params": True}, RING + " has 1"),
        ([(SUN, "1e8,1e8")], {}, "given twice"),
        ([(SUN, "1e8")], {"workers": 0}, "--workers"),
        ([(SUN, "1e8")], {"cluster": "sge"}, "--cluster must be one of slurm, pbs"),
        ([(SUN, "1e8")], {"scene": "nosuch"}, "no scene 'nosuch'"),
        ([(SUN, "1e8")], {"formulation": "exact"}, "--formulation"),
        ([(SUN, "1e8")], {"cluster_options": {"walltime": "1h"}}, "--cluster slurm|pbs"),
        (
            [(SUN, "1e8")],
            {"cluster": "slurm", "cluster_options": {"walltime": "1h"}},
            "--walltime",
        ),
        ([(SUN, "1e8")], {"cluster": "pbs", "cluster_options": {"memory": "lots"}}, "--memory"),
        ([], {}, "at least one"),
    ],
)
def test_sweep_validation_before_any_work(tmp_path, params, kwargs, message):
    out = tmp_path / "never"
    with pytest.raises(CaseError) as raised:
        sweep.run_sweep(PLANETARY, params, out_dir=out, progress=False, **kwargs)
    assert message in str(raised.value)
    assert not out.exists()


def test_scene_with_an_analysis_a_sweep_cannot_run(tmp_path, monkeypatch):
    monkeypatch.delitem(sweep.POINT_ANALYSES, "modal")
    with pytest.raises(CaseError, match="cannot run yet"):
        sweep.run_sweep(PLANETARY, [(SUN, "1e8")], out_dir=tmp_path / "x", progress=False)


def test_missing_dask_jobqueue_is_named(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "dask_jobqueue", None)
    with pytest.raises(CaseError, match="needs dask-jobqueue"):
        sweep.run_sweep(
            PLANETARY, [(SUN, "1e8")], cluster="slurm", out_dir=tmp_path, progress=False
        )


@pytest.mark.filterwarnings("ignore:Port 8787 is already in use")
def test_job_queue_scripts_carry_the_options():
    handler = signal.getsignal(signal.SIGINT)
    pytest.importorskip("dask_jobqueue")
    signal.signal(signal.SIGINT, handler)  # importorskip imported it: undo its handler
    for name in [m for m in sys.modules if m.split(".")[0] == "dask_jobqueue"]:
        del sys.modules[name]  # so that pygear imports it again
    options = {"queue": "long", "walltime": "02:30:00", "memory": "8GB", "cores": 2}
    slurm = jobqueue_cluster("slurm", validate_cluster_options(2, None, "slurm", options))
    try:
        script = slurm.job_script()
    finally:
        slurm.close()
    assert "#SBATCH -p long" in script and "#SBATCH -t 02:30:00" in script
    assert "--nthreads 1" in script and "--nworkers 2" in script
    pbs = jobqueue_cluster("pbs", validate_cluster_options(2, None, "pbs", options))
    try:
        script = pbs.job_script()
    finally:
        pbs.close()
    assert "#PBS -q long" in script and "walltime=02:30:00" in script
    assert signal.getsignal(signal.SIGINT) is handler  # Ctrl-C still raises KeyboardInterrupt


def test_parse_param():
    path, values = sweep.parse_param("planetary.sun_mesh.stiffness=logspace(7,9,3)")
    assert path == SUN
    np.testing.assert_allclose(values, [1e7, 1e8, 1e9])
    with pytest.raises(CaseError, match="stage.member.parameter=VALUES"):
        sweep.parse_param("planetary.sun_mesh.stiffness")


def expected_runs() -> list[tuple[str, str, tuple]]:
    runs = []
    for directory in sorted(p.parent for p in CASES.glob("*/case.py")):
        case = load_case(directory)
        # a case without scenes gets one row
        runs += [(directory.name, s.name, s.analyses) for s in case.scenes] or [
            (directory.name, "", ())
        ]
    return runs


def test_batch_runs_every_case(tmp_path, scheduler):
    table = batch.run_batch(
        [CASES], out_dir=tmp_path, workers=2, scheduler=scheduler, progress=False
    )
    runs = expected_runs()
    assert [(r.case, r.scene) for r in table.itertuples()] == [(c, s) for c, s, _ in runs]
    for (case_name, scene_name, analyses), row in zip(runs, table.itertuples()):
        if not analyses:
            assert row.status == "ok" and row.error == "no scenes"
        elif "response" in analyses:  # the steady state over speed, as `pygear run` writes it
            assert row.status == "ok", row.error
            assert all(Path(f).is_file() for f in row.files)
            assert any(Path(f).name.endswith("response.nc") for f in row.files)
        elif set(analyses) <= {"modal", "sensitivity"}:
            assert row.status == "ok", row.error
            case = load_case(CASES / case_name)
            scene = case.scene(scene_name)
            modal = modal_analysis(scene_model(case.for_scene(scene), scene))
            lowest = modal.frequency.values[modal.frequency.values > 0].min()
            assert row.lowest_hz == pytest.approx(lowest, rel=1e-10)
            assert (tmp_path / case_name / f"{scene_name}.nc").is_file()
            assert all(Path(f).is_file() for f in row.files)
        elif isinstance(load_case(CASES / case_name), RotorCase):  # a rotor's transient
            assert row.status == "ok", row.error
            assert (tmp_path / case_name / f"{scene_name}.nc").is_file()
        else:  # a transient: the same t_s as the scene run on its own (run-to-run identical;
            # NaN for a scene without a speed reference, such as a torque reversal)
            assert row.status == "ok", row.error
            case = load_case(CASES / case_name)
            scene = case.scene(scene_name)
            alone = run_transient(case.for_scene(scene), scene)
            # the summary keeps t_s to the nanosecond (a steady scene's 1e-17 s reads 0)
            np.testing.assert_allclose(row.t_s, float(alone.t_s), rtol=0.0, atol=5e-10)
            assert (tmp_path / case_name / f"{scene_name}.nc").is_file()
    assert (tmp_path / "batch_summary.csv").is_file()


def test_find_case_dirs_errors(tmp_path):
    with pytest.raises(CaseError, match="does not exist"):
        batch.find_case_dirs([tmp_path / "missing"])
    with pytest.raises(CaseError, match="holds no case directory"):
        batch.find_case_dirs([tmp_path])
    assert batch.find_case_dirs([PLANETARY, CASES])[0] == PLANETARY


def command(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="pygear")
    batch_cli.add_parsers(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(argv)
    return batch_cli.HANDLERS[args.command](args)


def small_cases(tmp_path: Path) -> Path:
    """A broken case and a one-scene copy of the study case (a batch runs in a second)."""
    cases = tmp_path / "cases"
    (cases / "broken").mkdir(parents=True)
    (cases / "broken" / "case.py").write_text("raise RuntimeError('bad case file')\n")
    (cases / "good").mkdir()
    (cases / "good" / "case.py").write_text(
        "import dataclasses, importlib.util\n"
        f"spec = importlib.util.spec_from_file_location('p', {str(PLANETARY / 'case.py')!r})\n"
        "module = importlib.util.module_from_spec(spec)\n"
        "spec.loader.exec_module(module)\n"
        "scene = module.case.scene('modal_lin_parker')\n"
        "case = dataclasses.replace(module.case, name='good', scenes=(scene,))\n"
    )
    return cases


def test_commands(tmp_path, scheduler, capsys):
    argv = ["sweep", str(PLANETARY), "--param", f"{SUN}=linspace(2e8,6e8,3)"]
    argv += ["--out", str(tmp_path / "s"), "--scheduler", scheduler, "--json"]
    assert command(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["points"] == 3 and summary["points_computed"] == 3
    assert summary["parameters"] == {SUN: [2e8, 4e8, 6e8]}
    argv[3] = f"{SUN}=-1,1e8"  # a value the case refuses: bad input, before any point
    with pytest.raises(CaseError, match=f"--param {SUN}=-1.0: .* positive"):
        command(argv)
    argv[3] = "planetary.sun_bearing.torsional=0,1e6"  # the second fails on its worker
    assert command(argv) == 1
    assert json.loads(capsys.readouterr().out)["failures"][0]["index"] == 1
    with pytest.raises(CaseError, match="--queue applies to a job-queue cluster"):
        command([*argv, "--queue", "long"])

    good = small_cases(tmp_path) / "good"
    argv = ["batch", str(good), "--out", str(tmp_path / "b"), "--scheduler", scheduler, "--json"]
    assert command(argv) == 0
    runs = json.loads(capsys.readouterr().out)["runs"]
    assert [(r["case"], r["scene"], r["status"]) for r in runs] == [
        ("good", "modal_lin_parker", "ok")
    ]
    assert runs[0]["lowest_hz"] > 0 and len(runs[0]["files"]) == 3


def test_batch_records_a_broken_case_and_goes_on(tmp_path, scheduler, capsys):
    cases = small_cases(tmp_path)
    out = tmp_path / "out"
    assert command(["batch", str(cases), "--out", str(out), "--scheduler", scheduler]) == 1
    printed = capsys.readouterr().out
    assert "broken" in printed and "modal_lin_parker" in printed and "1 error" in printed
    table = pd.read_csv(out / "batch_summary.csv", keep_default_na=False)
    broken = table[table.case == "broken"]
    assert len(broken) == 1 and broken.status.iloc[0] == "error"
    assert "bad case file" in broken.error.iloc[0]
    good = table[table.case == "good"]
    assert list(good.status) == ["ok"] and (out / "good" / "modal_lin_parker.nc").is_file()
