"""Rotor torque and speed read from OpenFAST output files (pygear.io_openfast).

``tests/data/nrel5mw_short.out`` is a text output file in OpenFAST's layout (blank line,
two lines naming the program, the description line, channel names and units in
parentheses, tab-separated rows) with ramps whose values are known: row i has
Time = 0.05 i s, RotSpeed = 12.1 + 0.01 i rpm and RotTorq = 3900 + 10 i kN-m, written
with four significant digits, exactly representable at the precision the file prints.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pygear.errors import CaseError
from pygear.io_openfast import read_openfast_output

DATA = Path(__file__).parent / "data"
SAMPLE = DATA / "nrel5mw_short.out"
ROWS = np.arange(11)


def _rewrite(tmp_path: Path, old: str, new: str, line: int) -> Path:
    lines = SAMPLE.read_text().splitlines()
    lines[line] = lines[line].replace(old, new)
    out = tmp_path / "changed.out"
    out.write_text("\n".join(lines) + "\n")
    return out


def test_torque_in_newton_metres_and_speed_in_rpm():
    ds = read_openfast_output(SAMPLE)
    # the file's kN-m times 1000; the printed values are exact to 4 digits, so the only
    # error is the decimal-to-binary round-off of the parsed numbers (relative 1e-15)
    np.testing.assert_allclose(ds.time.values, 0.05 * ROWS, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ds.rotor_torque.values, (3900.0 + 10.0 * ROWS) * 1e3, rtol=1e-14)
    np.testing.assert_allclose(ds.rotor_speed.values, 12.1 + 0.01 * ROWS, rtol=1e-14)
    assert ds.rotor_torque.attrs["units"] == "N m"
    assert ds.rotor_speed.attrs["units"] == "rpm"
    assert ds.time.attrs["units"] == "s"
    assert ds.attrs["source_name"] == "nrel5mw_short.out"
    assert "NREL 5.0 MW" in ds.attrs["source_description"]
    assert ds.rotor_torque.attrs["openfast_channel"] == "RotTorq [kN-m]"


def test_low_speed_shaft_torque_channel_and_newton_metre_unit(tmp_path):
    path = _rewrite(tmp_path, "RotTorq ", "LSShftTq", 6)
    lines = path.read_text().splitlines()
    lines[7] = lines[7].replace("(kN-m)", "(N-m)  ")
    path.write_text("\n".join(lines) + "\n")
    ds = read_openfast_output(path)
    # N-m: the column's numbers are taken as they are
    np.testing.assert_allclose(ds.rotor_torque.values, 3900.0 + 10.0 * ROWS, rtol=1e-14)
    assert ds.rotor_torque.attrs["openfast_channel"] == "LSShftTq [N-m]"


def test_speed_in_radians_per_second_is_converted(tmp_path):
    path = _rewrite(tmp_path, "(rpm) ", "(rad/s)", 7)
    ds = read_openfast_output(path)
    np.testing.assert_allclose(
        ds.rotor_speed.values, (12.1 + 0.01 * ROWS) * 30.0 / np.pi, rtol=1e-14
    )


def test_missing_torque_channel_is_one_line_error(tmp_path):
    path = _rewrite(tmp_path, "RotTorq ", "GenTq   ", 6)
    with pytest.raises(CaseError, match=r"missing channel\(s\) RotTorq or LSShftTq") as info:
        read_openfast_output(path)
    assert "\n" not in str(info.value)


def test_unknown_torque_unit_is_refused(tmp_path):
    path = _rewrite(tmp_path, "(kN-m)", "(kW)  ", 7)
    with pytest.raises(CaseError, match="channel RotTorq has unit 'kW'"):
        read_openfast_output(path)


def test_missing_file_names_the_path(tmp_path):
    with pytest.raises(CaseError, match="no such file"):
        read_openfast_output(tmp_path / "absent.out")


def test_binary_output_reads_like_the_text_one(tmp_path):
    # an .outb in OpenFAST's uncompressed layout without a time channel (file format 3:
    # first time and step, then the channels as float64), written here field by field
    import struct

    rows = np.arange(5)
    speed, torque = 12.1 + 0.01 * rows, 3900.0 + 10.0 * rows
    names = [f"{n:<10s}".encode() for n in ("Time", "RotSpeed", "RotTorq")]
    units = [f"{u:<10s}".encode() for u in ("(s)", "(rpm)", "(kN-m)")]
    description = b"binary sample"
    blob = struct.pack("<hii", 3, 2, rows.size) + struct.pack("<dd", 0.0, 0.05)
    blob += struct.pack("<i", len(description)) + description + b"".join(names + units)
    blob += np.column_stack([speed, torque]).astype("<f8").tobytes()
    path = tmp_path / "sample.outb"
    path.write_bytes(blob)
    ds = read_openfast_output(path)
    np.testing.assert_allclose(ds.time.values, 0.05 * rows, rtol=0, atol=1e-15)
    # float64 stored as written; kN-m x 1000 rounds once (1e-15 relative)
    np.testing.assert_allclose(ds.rotor_torque.values, torque * 1e3, rtol=1e-15)
    np.testing.assert_allclose(ds.rotor_speed.values, speed, rtol=1e-15)
