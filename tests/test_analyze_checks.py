"""What every ``pygear analyze`` path checks before any work (issue #27, items 5, 6, 10,
11, 20): damaged files and files of other commands named in one line, a record uniform
in time on every path, a gear mesh below the file's Nyquist frequency, and defaults
that follow the file.

The run files are 0.1 s of the study case's sensor scene (Yang, Jiang & Han 2016; the
carrier at 120 rpm, a 96-tooth ring: mesh at 192 Hz, sampled at 13 248 Hz): every check
runs before the averaging, so the record need not hold a full revolution.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pygear.analysis.condition.gear_average import check_tsa_sampling
from pygear.cli import main
from pygear.io import open_dataset, write_netcdf

SMALL = """
import dataclasses

from pygear import load_case

base = load_case("yang2016_planetary")
scene = base.scene("steady_sensor")
settings = dataclasses.replace(scene.transient, duration=0.1, mean_window=0.05)
case = dataclasses.replace(
    base,
    name="checks",
    scenes=(base.scene("modal"), dataclasses.replace(scene, transient=settings)),
)
"""

MESH_HZ = 192.0  # 96 teeth x 2 Hz
SUN_TEETH = 27

MODES = {
    "spectra": [],
    "tsa": ["--tsa", "sun", "--indicators", "--no-figures"],
    "orders": ["--orders", "planetary.carrier"],
}


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> Path:
    case = tmp_path_factory.mktemp("checks_case")
    (case / "case.py").write_text(SMALL)
    out = tmp_path_factory.mktemp("checks")
    assert main(["run", str(case), "--out", str(out), "--no-figures", "--json"]) == 0
    return out


def _plain(dataset: xr.Dataset) -> xr.Dataset:
    """``dataset`` without the storage settings it was read with (chunk sizes of the
    longer record)."""
    for variable in dataset.variables.values():
        variable.encoding = {}
    return dataset


def _derived(files: Path, name: str, change) -> Path:
    """The sensor run changed by ``change`` (a Dataset -> Dataset), written as pygear
    writes (same title and attributes)."""
    with open_dataset(files / "steady_sensor.nc") as run:
        changed = _plain(change(run.load()))
    path = files / name
    write_netcdf(changed, path, title=run.attrs["title"])
    return path


def _refused(argv: list[str], capsys) -> str:
    assert main(argv) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1, error
    assert "internal error" not in error and "Traceback" not in error
    return error


# --- item 10: damaged files -----------------------------------------------------------------


def _damaged(directory: Path, kind: str, files: Path) -> Path:
    path = directory / f"{kind}.nc"
    if kind == "empty":
        path.write_bytes(b"")
    elif kind == "text":
        path.write_text("time,acceleration\n0,1\n")
    elif kind == "random":
        path.write_bytes(np.random.default_rng(3).bytes(6000))
    elif kind == "flipped":  # a real run, one byte in every 997 inverted
        data = bytearray((files / "steady_sensor.nc").read_bytes())
        for index in range(2048, len(data), 997):
            data[index] ^= 0xFF
        path.write_bytes(bytes(data))
    else:  # zero samples: the run's layout, no time step
        with open_dataset(files / "steady_sensor.nc") as run:
            empty = _plain(run.load().isel(time=slice(0, 0)))
        write_netcdf(empty, path, title=run.attrs["title"], compression=0)
    return path


@pytest.mark.parametrize("mode", sorted(MODES))
@pytest.mark.parametrize("kind", ["empty", "text", "random", "flipped", "zero"])
def test_a_damaged_file_is_named_in_one_line(files, tmp_path, capsys, kind, mode):
    path = _damaged(tmp_path, kind, files)
    error = _refused(["analyze", str(path), *MODES[mode], "--out", str(tmp_path / "o")], capsys)
    assert f"RUN.nc {str(path)!r}" in error
    expected = {
        "empty": "is empty (0 bytes)",
        "text": "cannot be read as NetCDF",
        "random": "cannot be read as NetCDF",
        "flipped": "cannot be read as NetCDF",
        "zero": "holds no samples",
    }
    assert expected[kind] in error
    assert not (tmp_path / "o").exists() and not list(tmp_path.glob("o_*"))


# --- item 11: files of other commands -------------------------------------------------------


def _other_kind(directory: Path, files: Path, kind: str) -> Path:
    """A file of another command: the modal file and a mesh-stiffness file as written,
    the others with their writers' titles over a layout like theirs."""
    if kind == "modal":
        return files / "modal.nc"
    path = directory / f"{kind}.nc"
    if kind == "mesh-stiffness":
        argv = ["mesh-stiffness", "yang2016_planetary", "--duration", "0.01", "--out", str(path)]
        assert main([*argv, "--json"]) == 0
        return path
    titles = {
        "campbell": "Campbell diagram of yang2016_planetary over the speed of planetary.carrier",
        "dataset": "Fault dataset of sequential_planetary: crack_depth on planetary.sun tooth 0",
        "record": "Fault record 0123456789abcdef of sequential_planetary",
    }
    data = xr.Dataset(
        {"fm4": ("record", np.array([3.0, 3.2]), {"units": "1", "long_name": "FM4"})},
        attrs={"case": "sequential_planetary", "scene": "sun_crack"},
    )
    write_netcdf(data, path, title=titles[kind])
    return path


@pytest.mark.parametrize("mode", sorted(MODES))
@pytest.mark.parametrize(
    ("kind", "command"),
    [
        ("modal", "`pygear run` for a modal scene"),
        ("mesh-stiffness", "`pygear mesh-stiffness`"),
        ("campbell", "`pygear campbell`"),
        ("dataset", "`pygear dataset`"),
        ("record", "`pygear dataset`"),
    ],
)
def test_a_file_of_another_command_says_what_it_is(files, tmp_path, capsys, kind, command, mode):
    path = _other_kind(tmp_path, files, kind)
    error = _refused(["analyze", str(path), *MODES[mode], "--out", str(tmp_path / "o")], capsys)
    assert f"written by {command}" in error and "not a run" in error
    assert "older pygear" not in error
    assert "needs a transient's result" in error  # what analyze wants instead


# --- item 6: one uniform-time check on every path -------------------------------------------


@pytest.mark.parametrize("mode", sorted(MODES))
def test_a_gap_in_time_is_refused_on_every_path(files, tmp_path, capsys, mode):
    """10 ms of samples missing at t = 0.07 s (after every default start-up): each path
    refuses the record instead of averaging or resampling across the gap."""
    path = _derived(
        files,
        f"gap_{mode}.nc",
        lambda run: run.isel(time=~((run.time > 0.07) & (run.time < 0.08)).values),
    )
    error = _refused(["analyze", str(path), *MODES[mode], "--out", str(tmp_path / "o")], capsys)
    assert "time is not uniformly sampled" in error and "--after" in error
    last = np.floor(0.07 * 13248.0) / 13248.0  # the last sample before the gap
    assert f"at t = {last:.6g} s" in error and "a step of 0.0100" in error


def test_a_gap_before_after_is_no_concern(files, tmp_path, capsys):
    """The check applies to the analysed record: a gap before --after passes it."""
    path = _derived(
        files,
        "early_gap.nc",
        lambda run: run.isel(time=~((run.time > 0.01) & (run.time < 0.02)).values),
    )
    argv = ["analyze", str(path), "--after", "0.03", "--json", "--out", str(tmp_path / "s")]
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["files"]


# --- item 5: the mesh below the Nyquist frequency --------------------------------------------


@pytest.mark.parametrize(("every", "refused"), [(30, False), (40, True)])
def test_tsa_refuses_a_mesh_above_nyquist(files, tmp_path, capsys, every, refused):
    """Every 30th sample (441.6 Hz, Nyquist 220.8 Hz) still resolves the sun's mesh
    at 192 Hz and its first sideband at 192 x 28/27 = 199.1 Hz; every 40th (331.2 Hz,
    Nyquist 165.6 Hz) does not, and --tsa refuses before averaging aliases."""
    path = _derived(files, f"every_{every}.nc", lambda run: run.isel(time=slice(None, None, every)))
    needed = MESH_HZ * (1 + 1 / SUN_TEETH)
    with open_dataset(path) as run:
        rate = 13248.0 / every
        if not refused:  # the check passes and says what it needs
            got = check_tsa_sampling(run.load(), "sun", "ring_sensor", "RUN.nc")
            assert got == pytest.approx(needed, rel=1e-3)  # the angle's slope: 120.02 rpm
            return
    error = _refused(["analyze", str(path), *MODES["tsa"], "--out", str(tmp_path / "o")], capsys)
    assert error.startswith("pygear analyze: error: --tsa sun:")
    assert "Nyquist frequency" in error and f"{rate / 2:.6g} Hz" in error
    assert not list(tmp_path.iterdir())


# --- item 20: defaults that follow the file, messages that name the flags --------------------


def _short_run(path: Path, rate: float, duration: float) -> Path:
    """A run sampled at ``rate``: a resonance at a fifth of the sample rate, amplitude
    modulated at 60 Hz, with the frequencies pygear stores."""
    time = np.arange(0, duration, 1 / rate)
    carrier = np.sin(2 * np.pi * rate / 5 * time)
    signal = (1 + 0.5 * np.cos(2 * np.pi * 60.0 * time)) * carrier
    run = xr.Dataset(
        {
            "ring_y_acceleration": ("time", signal, {"units": "m/s^2"}),
            "natural_frequency": ("mode", [rate / 5], {"units": "Hz"}),
            "mesh_frequency": ("mesh_stage", [60.0], {"units": "Hz", "gearbox_stages": 1}),
        },
        coords={
            "time": ("time", time, {"units": "s"}),
            "mode_class": ("mode", ["rotational"]),
            "mesh_stage": ("mesh_stage", ["planetary"]),
        },
        attrs={"case": "a_case"},
    )
    run.to_netcdf(path)
    return path


def test_defaults_follow_a_short_20_khz_run(tmp_path, capsys):
    """0.5 s at 20 kHz: the study case's defaults (1 s, 5-10 kHz) fit neither; the file's
    own are half the run and a quarter to a half of its 10 kHz Nyquist frequency."""
    path = _short_run(tmp_path / "run.nc", 20e3, 0.5)
    assert main(["analyze", str(path), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    with xr.open_dataset(result["files"][0]) as spectra:
        # half the record: its last sample lies at 0.5 s - 50 us
        assert spectra.attrs["after_s"] == pytest.approx((0.5 - 5e-5) / 2, rel=1e-12)
        # from the mean step: equal to the nominal rate but for round-off
        assert list(spectra.attrs["band_hz"]) == pytest.approx([2500.0, 5000.0], rel=1e-9)
    dra = result["dra_spectrum"][0]  # the 4 kHz resonance lies in the band: 60 Hz AM found
    assert dra["frequency_hz"] == pytest.approx(60.0, abs=4.0)  # one bin: 1 / 0.25 s


def test_default_start_is_never_before_the_run_settles(tmp_path, capsys):
    """A run whose input reaches its speed at t_s = 0.4 s: the spectra start there."""
    path = _short_run(tmp_path / "run.nc", 40e3, 2.0)
    with xr.open_dataset(path) as run:
        settled = run.load().assign(t_s=((), 1.4, {"units": "s"}))
    settled.to_netcdf(tmp_path / "settled.nc")
    assert main(["analyze", str(tmp_path / "settled.nc"), "--json"]) == 0
    with xr.open_dataset(json.loads(capsys.readouterr().out)["files"][0]) as spectra:
        assert spectra.attrs["after_s"] == 1.4
        # the paper's at 40 kHz (from the mean step: equal but for round-off)
        assert list(spectra.attrs["band_hz"]) == pytest.approx([5000.0, 10000.0], rel=1e-9)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--after", "0.5"], "--after 0.5 s must lie within the run"),
        (["--after", "0.49952"], "--after 0.49952 s leaves 9 samples"),
        (["--band", "5000", "10000"], "--band 5000 10000: the band must satisfy"),
    ],
)
def test_messages_name_the_flags(tmp_path, capsys, argv, message):
    path = _short_run(tmp_path / "run.nc", 20e3, 0.5)
    error = _refused(["analyze", str(path), *argv], capsys)
    assert message in error
    if "--band" in argv:
        assert "Nyquist = 10000 Hz" in error


def test_checks_never_change_a_clean_study_run(files, tmp_path, capsys):
    """The sensor run as written passes every path's checks (and the spectra use the
    file's defaults: the 13 248 Hz record's band is 1656-3312 Hz)."""
    out = tmp_path / "s"
    assert main(["analyze", str(files / "steady_sensor.nc"), "--json", "--out", str(out)]) == 0
    with xr.open_dataset(json.loads(capsys.readouterr().out)["files"][0]) as spectra:
        # the sample rate from the mean step: equal to 13 248 Hz but for round-off
        assert list(spectra.attrs["band_hz"]) == pytest.approx([1656.0, 3312.0], rel=1e-9)
        # half the run: its last sample lies within one step (75 us) of 0.1 s
        assert spectra.attrs["after_s"] == pytest.approx(0.05, abs=1e-4)
