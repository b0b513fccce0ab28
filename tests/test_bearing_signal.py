"""A planet bearing's defect heard by a housing sensor (bearing_signal): the contact law's
force history through a transmission window turning with the carrier and a resonance."""

from __future__ import annotations

import numpy as np
import pytest

from pygear.analysis.condition.bearing_envelope import bearing_envelope_analysis
from pygear.analysis.condition.bearing_kinematics import bearing_frequencies
from pygear.analysis.condition.bearing_load import defect_excitation
from pygear.analysis.condition.bearing_signal import bearing_sensor_signal
from pygear.errors import CaseError
from pygear.model.rolling_bearing import BearingDefect, RollingBearing
from pygear.model.sensors import StructuralMode

RATE, CARRIER, SPIN = 20000.0, 2.0, 5.0  # Hz; the planet's spin relative to the carrier
PLANET = RollingBearing("PL", "roller", elements=13, pitch_diameter=0.1, element_diameter=0.012,
                        roller_length=0.015, diametral_clearance=10e-6,
                        location="stage1.planet")  # fmt: skip
MODE = (StructuralMode(3500.0, 0.02, 1.0),)


@pytest.fixture(scope="module")
def pin_spall() -> tuple:
    """A spall on the pin (inner ring, held by the carrier) in the load zone's centre."""
    found = bearing_frequencies(PLANET, 0.0, SPIN, carrier_hz=CARRIER)
    history = defect_excitation(
        PLANET, 2e4, inner_hz=0.0, outer_hz=SPIN, duration=2.0, sample_rate=RATE,
        defects=(BearingDefect("inner", width=1e-3, depth=10e-6),),
    )  # fmt: skip
    return found, history


def _sidebands(history, found, width):
    signal = bearing_sensor_signal(history, gain=1e-3, carrier_hz=CARRIER, window_width_deg=width,
                                   modes=MODE, snr_db=10.0)  # fmt: skip
    lines = {"BPFO": found.lines["BPFO"], "BPFI": found.lines["BPFI"]}
    _, detection = bearing_envelope_analysis(signal.values, RATE, lines,
                                             modulation={"BPFI": CARRIER})  # fmt: skip
    return detection


def test_a_pin_spall_is_unmodulated_until_the_carrier_turns_it_past_the_sensor(pin_spall):
    found, history = pin_spall
    # the pin stands in the load zone: no load-zone modulation of BPFI
    assert found.modulation["BPFI"] == 0.0 and found.carrier == CARRIER
    steady = _sidebands(history, found, None)
    turning = _sidebands(history, found, 180.0)
    for detection in (steady, turning):
        assert bool(detection.detected.sel(line="BPFI"))
        assert not bool(detection.detected.sel(line="BPFO"))
    # observed: +-f_c at 1.9 and 3.8 dB without the window, 14.3 and 15.3 dB with it
    pairs = (("steady", steady), ("turning", turning))
    first = {name: d.sel(line="BPFI", harmonic=1) for name, d in pairs}
    assert not first["steady"].found.sel(sideband=[-1, 1]).any()
    assert first["turning"].found.sel(sideband=[-1, 1]).all()
    sides = first["turning"].found_frequency.sel(sideband=[-1, 1]).values
    assert np.allclose(sides, found.lines["BPFI"] + np.array([-CARRIER, CARRIER]), atol=0.5)


def test_the_window_silences_the_sensor_while_the_planet_is_away(pin_spall):
    _, history = pin_spall
    signal = bearing_sensor_signal(history, gain=1.0, carrier_hz=CARRIER, window_width_deg=90.0)
    angle = (np.degrees(2 * np.pi * CARRIER * signal.time.values) + 180.0) % 360.0 - 180.0
    assert np.all(signal.values[np.abs(angle) > 45.0 + 1e-9] == 0.0)
    assert np.any(signal.values[np.abs(angle) < 40.0] != 0.0)
    assert signal.attrs["units"] == "m/s^2"


def test_bad_path_is_one_line(pin_spall):
    _, history = pin_spall
    with pytest.raises(CaseError, match=r"^gain must be a finite, non-zero path gain"):
        bearing_sensor_signal(history, gain=0.0)
    with pytest.raises(CaseError, match=r"^window_width_deg must be in \(0, 360\]"):
        bearing_sensor_signal(history, gain=1.0, window_width_deg=0.0)
