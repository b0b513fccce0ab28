"""Compressed NetCDF output (pygear.io.write_netcdf) and the disk estimate of a run.

Compression must be lossless (every value read back bit for bit), apply to the large
numeric variables only, and the disk a run is checked against before it starts must
bound what it writes (the estimate counts the files uncompressed).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import xarray as xr

from pygear.analysis.signals.channels import channel_names
from pygear.analysis.time.transient_checks import signal_footprint, transient_footprint
from pygear.io import COMPRESSED_SIZE, COMPRESSION_LEVEL, write_netcdf
from pygear.runs.outputs import write_run_signals
from pygear.runs.transient_outputs import write_transient


def _dataset(samples: int) -> xr.Dataset:
    rng = np.random.default_rng(3)
    time = np.arange(samples) * 2.5e-5
    return xr.Dataset(
        {
            "noise": ("time", rng.standard_normal(samples), {"units": "m/s^2"}),
            "ramp": ("time", np.minimum(time, 0.1) * 1200.0, {"units": "rpm"}),
            "count": ("time", np.arange(samples, dtype=np.int32), {"units": "1"}),
            "small": ("mode", np.linspace(1.0, 2.0, 8), {"units": "Hz"}),
            "label": ("mode", np.array([f"m{i}" for i in range(8)], dtype=object)),
        },
        coords={"time": ("time", time, {"units": "s"})},
    )


def test_large_variables_are_compressed_losslessly(tmp_path):
    original = _dataset(3 * COMPRESSED_SIZE)
    path = write_netcdf(original, tmp_path / "c.nc", title="test")
    with xr.open_dataset(path, decode_times=False) as read:  # time as stored: seconds
        for name in ("noise", "ramp", "count", "time"):
            encoding = read[name].encoding
            assert encoding["zlib"] and encoding["shuffle"], name
            assert encoding["complevel"] == COMPRESSION_LEVEL
            np.testing.assert_array_equal(read[name].values, original[name].values)
        assert not read["small"].encoding["zlib"]  # 8 values: not worth a filter
        assert read["label"].values.tolist() == original["label"].values.tolist()


def test_level_zero_writes_raw_and_compression_only_shrinks(tmp_path):
    original = _dataset(3 * COMPRESSED_SIZE)
    raw = write_netcdf(original, tmp_path / "raw.nc", title="test", compression=0)
    packed = write_netcdf(original, tmp_path / "packed.nc", title="test")
    with xr.open_dataset(raw) as read:
        assert not read["noise"].encoding["zlib"]
    # the ramp and the counter compress well, the noise hardly: the file shrinks
    assert packed.stat().st_size < raw.stat().st_size


@pytest.mark.parametrize("level", [-1, 10, True, 1.5])
def test_compression_level_is_checked(tmp_path, level):
    with pytest.raises(ValueError, match="zlib level"):
        write_netcdf(_dataset(10), tmp_path / "x.nc", title="test", compression=level)
    assert not list(tmp_path.iterdir())


def test_run_files_stay_within_the_disk_estimate(study_case, tmp_path):
    """A 1.25 s run-up with its signal analysis writes no more than the estimate the
    scene checks refuse a too-small disk with (record and spectra counted raw)."""
    scene = study_case.scene("runup")
    scene = dataclasses.replace(
        scene, transient=dataclasses.replace(scene.transient, duration=1.25, mean_window=0.1)
    )
    case = study_case.for_scene(scene)
    dataset, files = write_transient(case, scene, tmp_path, figure=False)
    spectra = write_run_signals(case, None, dataset, tmp_path, scene.name, figures=False)
    channels = len(channel_names(dataset))
    _, record, _ = transient_footprint(scene.transient, channels)
    analyses, _ = signal_footprint(scene.transient)
    assert len(spectra) == 2 and len(files) == 1
    assert files[0].stat().st_size <= record
    assert sum(p.stat().st_size for p in spectra) <= analyses
    with xr.open_dataset(files[0]) as read:
        assert read["speed"].encoding["zlib"]
