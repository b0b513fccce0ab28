"""`pygear analyze` on a run file with known content (the study-case runs come with the
transient)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from pygear.analysis.signals.analyze import analyze_channel
from pygear.cli import main

SAMPLE_RATE = 40000.0  # Hz, the paper's
MESH = 192.0  # Hz, the study case's mesh frequency at 120 rpm
# natural frequencies [Hz] of the study case, improved model (Yang, Jiang & Han 2016,
# Table 2); the translational modes come in pairs
ROTATIONAL_HZ = [0.0, 1334.0, 1891.3, 2662.8, 8045.4, 11822.3]
TRANSLATIONAL_HZ = [743.2, 1102.7, 1896.5, 2276.5, 6989.0, 9651.7]


@pytest.fixture()
def run_file(tmp_path):
    """A 3 s run: a 7 kHz resonance modulated at the mesh frequency, a 1334 Hz tone
    and noise, plus a rotation speed channel that is no acceleration."""
    rng = np.random.default_rng(5)
    time = np.arange(0, 3.0, 1 / SAMPLE_RATE)
    acceleration = (
        (1 + 0.5 * np.cos(2 * np.pi * MESH * time)) * np.sin(2 * np.pi * 7000 * time)
        + 0.3 * np.sin(2 * np.pi * 1334.0 * time)
        + 0.05 * rng.standard_normal(time.size)
    )
    natural = ROTATIONAL_HZ + 2 * TRANSLATIONAL_HZ
    classes = ["rotational"] * 6 + ["translational"] * 12
    run = xr.Dataset(
        {
            "carrier_speed": ("time", np.full(time.size, 120.0), {"units": "rpm"}),
            "ring_y_acceleration": ("time", acceleration, {"units": "m/s^2"}),
            # what `pygear run` stores for the analysis: natural and mesh frequencies
            "natural_frequency": ("mode", natural, {"units": "Hz"}),
            "mesh_frequency": ("mesh_stage", [MESH], {"units": "Hz", "gearbox_stages": 1}),
            "mesh_teeth": ("mesh_stage", [96], {"units": "1"}),
        },
        coords={
            "time": ("time", time, {"units": "s"}),
            "mode_class": ("mode", classes),
            "mesh_stage": ("mesh_stage", ["planetary"]),
        },
        attrs={"case": "yang2016_planetary", "formulation": "improved", "mesh_frequency_hz": MESH},
    )
    path = tmp_path / "run.nc"
    run.to_netcdf(path)
    return path


def test_analyze_json_names_peaks(run_file, capsys):
    assert main(["analyze", str(run_file), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["channel"] == "ring_y_acceleration"  # picked: the acceleration
    dra = result["dra_spectrum"][0]
    assert dra["frequency_hz"] == pytest.approx(MESH, abs=0.5)
    assert dra["what"] == "mesh harmonic 1"
    # AM depth 0.5 on a unit carrier: the envelope line reads 0.5 (window and noise aside)
    assert dra["amplitude"] == pytest.approx(0.5, rel=0.02)
    tone = next(p for p in result["spectrum"] if abs(p["frequency_hz"] - 1334.0) < 1)
    assert tone["what"].startswith("rotational 2") and tone["amplitude"] == pytest.approx(
        0.3, rel=0.01
    )
    for path in result["files"]:
        assert (run_file.parent / path).exists() or __import__("os").path.exists(path)
    with xr.open_dataset(result["files"][0]) as spectra:
        assert spectra.dra_spectrum.attrs["units"] == "m/s^2"
        assert "strongest_peaks" in spectra.attrs


def test_after_drops_the_start(run_file):
    with xr.open_dataset(run_file) as run:
        analysis = analyze_channel(run.load(), "ring_y_acceleration", after=2.0)
    resolution = float(analysis.spectra.frequency[1])
    assert resolution == pytest.approx(1.0, rel=1e-6)  # 1 s of record left


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--channel", "sun_speed"], "--channel: 'sun_speed' is not a time series"),
        (["--band", "5000", "30000"], "band"),
        (["--after", "5"], "after"),
    ],
)
def test_bad_input(run_file, argv, message, capsys):
    assert main(["analyze", str(run_file), *argv]) == 2
    assert message in capsys.readouterr().err
