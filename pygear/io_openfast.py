"""Rotor torque and speed from an OpenFAST output file, as an xarray dataset.

An OpenFAST simulation of a turbine writes its channels to ``<root>.out`` (text) or
``<root>.outb`` (binary).  A gearbox model driven by the rotor needs two of them: the
low-speed shaft torque (ElastoDyn's ``RotTorq``, or ``LSShftTq``, which is the same
torque along the shaft) and the rotor speed ``RotSpeed``.  The file is read with
OpenFAST's own reader (:mod:`openfast_io.FAST_output_reader`, the ``openfast`` extra of
pygear) and the channels are converted to SI units from the units the file states.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import xarray as xr

from pygear.errors import CaseError

__all__ = ["read_openfast_output"]

TORQUE_CHANNELS = ("RotTorq", "LSShftTq")
"""Low-speed shaft torque channels of ElastoDyn, in the order they are preferred."""

SPEED_CHANNEL = "RotSpeed"

TORQUE_UNITS = {
    "kn-m": 1.0e3,
    "kn*m": 1.0e3,
    "knm": 1.0e3,
    "kn.m": 1.0e3,
    "kn·m": 1.0e3,
    "n-m": 1.0,
    "n*m": 1.0,
    "nm": 1.0,
    "n.m": 1.0,
    "n·m": 1.0,
    "mn-m": 1.0e6,
    "mn·m": 1.0e6,
    "mnm": 1.0e6,
}
"""Torque units OpenFAST writes (``kN-m`` in ElastoDyn), to N m."""

SPEED_UNITS = {"rpm": 1.0, "rad/s": 30.0 / np.pi, "deg/s": 1.0 / 6.0}
"""Rotor speed units, to rpm."""

TIME_UNITS = {"s": 1.0, "sec": 1.0}


def _load(path: Path) -> tuple[np.ndarray, list[str], list[str], str]:
    try:
        from openfast_io.FAST_output_reader import FASTOutputFile
    except ImportError as exc:  # pragma: no cover - the test extra installs it
        raise ImportError(
            "reading OpenFAST output needs the openfast-io package: pip install 'pygear[openfast]'"
        ) from exc
    try:
        reader = FASTOutputFile(str(path))
    except (ValueError, IndexError, OSError, UnicodeDecodeError) as exc:
        raise CaseError(
            f"openfast file {path}: not an OpenFAST .out/.outb output file ({exc})"
        ) from None
    info = reader.info
    names = [str(n).strip() for n in info["attribute_names"]]
    units = [str(u).strip() for u in info.get("attribute_units") or [""] * len(names)]
    data = np.asarray(reader.data, dtype=float)
    if data.ndim != 2 or data.shape[1] != len(names):
        raise CaseError(
            f"openfast file {path}: {len(names)} channel names but "
            f"{data.shape[-1] if data.ndim == 2 else 0} columns of data"
        )
    return data, names, units, str(info.get("description", ""))


def _column(names: list[str], wanted: str) -> int | None:
    lowered = [n.lower() for n in names]
    return lowered.index(wanted.lower()) if wanted.lower() in lowered else None


def _unit_factor(table: dict[str, float], unit: str, channel: str, path: Path) -> float:
    key = unit.strip().strip("()").replace(" ", "").lower()
    if key not in table:
        raise CaseError(
            f"openfast file {path}: channel {channel} has unit '{unit}', expected one of "
            f"{sorted(set(table))}"
        )
    return table[key]


def read_openfast_output(path: str | os.PathLike[str]) -> xr.Dataset:
    """Rotor torque and speed over time from an OpenFAST output file.

    Parameters
    ----------
    path : str or path-like
        An OpenFAST output file, text (``.out``) or binary (``.outb``), holding the
        channels ``Time``, ``RotSpeed`` and ``RotTorq`` (or ``LSShftTq``).

    Returns
    -------
    xarray.Dataset
        ``rotor_torque(time)`` [N m], the low-speed shaft torque, and
        ``rotor_speed(time)`` [rpm], with the coordinate ``time`` [s]; the attributes
        name the source file, its description line and the channels read.

    Raises
    ------
    pygear.errors.CaseError
        The file is missing or not OpenFAST output, a channel is missing, a unit is not
        one of a torque, speed or time, or the time is not increasing.
    """
    path = Path(path)
    if not path.is_file():
        raise CaseError(f"openfast file {path}: no such file")
    data, names, units, description = _load(path)
    time_col = _column(names, "Time")
    speed_col = _column(names, SPEED_CHANNEL)
    torque_name = next((c for c in TORQUE_CHANNELS if _column(names, c) is not None), None)
    missing = [
        label
        for label, col in (
            ("Time", time_col),
            (SPEED_CHANNEL, speed_col),
            ("RotTorq or LSShftTq", torque_name),
        )
        if col is None
    ]
    if missing:
        raise CaseError(
            f"openfast file {path}: missing channel(s) {', '.join(missing)}; "
            f"the file has {', '.join(names)}"
        )
    assert time_col is not None and speed_col is not None and torque_name is not None
    torque_col = _column(names, torque_name)
    assert torque_col is not None

    def unit(col: int) -> str:
        return units[col] if col < len(units) else ""

    to_s = _unit_factor(TIME_UNITS, unit(time_col), "Time", path)
    to_rpm = _unit_factor(SPEED_UNITS, unit(speed_col), SPEED_CHANNEL, path)
    to_newton_metre = _unit_factor(TORQUE_UNITS, unit(torque_col), torque_name, path)
    time = data[:, time_col] * to_s
    if time.size < 2 or np.any(np.diff(time) <= 0.0):
        raise CaseError(f"openfast file {path}: Time must increase from row to row")
    return xr.Dataset(
        {
            "rotor_torque": (
                "time",
                data[:, torque_col] * to_newton_metre,
                {
                    "units": "N m",
                    "long_name": "low-speed shaft torque",
                    "openfast_channel": f"{torque_name} [{unit(torque_col)}]",
                },
            ),
            "rotor_speed": (
                "time",
                data[:, speed_col] * to_rpm,
                {
                    "units": "rpm",
                    "long_name": "rotor speed",
                    "openfast_channel": f"{SPEED_CHANNEL} [{unit(speed_col)}]",
                },
            ),
        },
        coords={"time": ("time", time, {"units": "s", "long_name": "time"})},
        attrs={
            "source": str(path),
            "source_name": path.name,
            "source_description": description,
            "reader": "openfast_io.FAST_output_reader",
        },
    )
