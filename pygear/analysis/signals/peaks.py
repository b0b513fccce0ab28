"""Peak picking in spectra and identification against known frequencies.

Computing (:func:`find_peaks`) and formatting (:func:`peak_table_text`) are
kept apart; nothing here plots.  Both are re-exported by
:mod:`pygear.analysis.signals.signal`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from .signal import SignalError

__all__ = ["PEAK_COLUMNS", "find_peaks", "local_maxima", "peak_table_text"]

#: Columns of the table returned by :func:`find_peaks` (the first is renamed
#: ``order`` for order spectra).
PEAK_COLUMNS = (
    "frequency_hz",
    "amplitude",
    "identification",
    "kind",
    "reference",
    "relative_deviation",
    "near_natural_frequency",
)
_KIND_PRIORITY = {"mesh harmonic": 0, "natural frequency": 1, "sideband": 2}
_MINUS = "\u2212"


@dataclass(frozen=True)
class _Reference:
    label: str
    value: float
    kind: str


def _natural_references(natural_frequencies: Any) -> list[_Reference]:
    """Labelled natural frequencies from a mapping or a modal Dataset."""
    if natural_frequencies is None:
        return []
    if isinstance(natural_frequencies, xr.Dataset):
        if "frequency" not in natural_frequencies or "mode_class" not in natural_frequencies:
            raise SignalError(
                "natural_frequencies: a Dataset needs 'frequency' and 'mode_class' variables"
            )
        frequencies = np.asarray(natural_frequencies["frequency"].values, dtype=float).ravel()
        classes = np.asarray(natural_frequencies["mode_class"].values).astype(str).ravel()
        if frequencies.shape != classes.shape:
            raise SignalError("natural_frequencies: 'frequency' and 'mode_class' differ in shape")
        return _number_modes(frequencies, classes)
    if isinstance(natural_frequencies, Mapping):
        references = []
        for label, value in natural_frequencies.items():
            value = float(value)
            if not np.isfinite(value) or value < 0.0:
                raise SignalError(
                    f"natural_frequencies: {label!r} must be a finite frequency >= 0, got {value}"
                )
            references.append(_Reference(f"{label} ({value:.1f} Hz)", value, "natural frequency"))
        return references
    raise SignalError(
        "natural_frequencies: must be a mapping label -> Hz or a Dataset with 'frequency' "
        f"and 'mode_class', got {type(natural_frequencies).__name__}"
    )


def _number_modes(frequencies: np.ndarray, classes: np.ndarray) -> list[_Reference]:
    """Label modes "<class> <k>", k counting distinct frequencies within a class.

    Repeated (degenerate) frequencies, such as the translational pairs of a
    planetary stage, share one number.
    """
    references = []
    for mode_class in dict.fromkeys(classes):
        members = np.sort(frequencies[classes == mode_class])
        number, previous = 0, None
        for value in members:
            if previous is None or abs(value - previous) > 1e-6 * max(abs(value), 1.0):
                number += 1
                previous = value
                references.append(
                    _Reference(
                        f"{mode_class} {number} ({value:.1f} Hz)", float(value), "natural frequency"
                    )
                )
    return references


def _mesh_references(
    mesh_frequency: float | Mapping[str, float] | None,
    mesh_harmonics: int,
    sideband_frequency: float | None,
    sideband_orders: int,
    sideband_name: str,
) -> list[_Reference]:
    if mesh_frequency is None:
        if sideband_frequency is not None:
            raise SignalError(
                "sideband_frequency: needs mesh_frequency (sidebands are around mesh harmonics)"
            )
        return []
    meshes = dict(mesh_frequency) if isinstance(mesh_frequency, Mapping) else {"": mesh_frequency}
    named = [
        (f"mesh_frequency[{key!r}]" if key else "mesh_frequency", f) for key, f in meshes.items()
    ]
    for name, value in (*named, ("sideband_frequency", sideband_frequency)):
        if value is not None and not (np.isfinite(value) and value > 0.0):
            raise SignalError(f"{name}: must be a finite frequency > 0, got {value!r}")
    for name, count in (("mesh_harmonics", mesh_harmonics), ("sideband_orders", sideband_orders)):
        if not isinstance(count, (int, np.integer)) or isinstance(count, bool) or count < 1:
            raise SignalError(f"{name}: must be an integer >= 1, got {count!r}")
    references = []
    for key, frequency in meshes.items():
        prefix = f"{key} " if key else ""
        for harmonic in range(1, mesh_harmonics + 1):
            centre = harmonic * frequency
            label = f"{prefix}mesh harmonic {harmonic}"
            references.append(_Reference(label, centre, "mesh harmonic"))
            if sideband_frequency is None:
                continue
            for order in range(1, sideband_orders + 1):
                for sign, symbol in ((-1, _MINUS), (1, "+")):
                    value = centre + sign * order * sideband_frequency
                    if value > 0.0:
                        sideband = f"{label} {symbol} {order}\u00d7{sideband_name}"
                        references.append(_Reference(sideband, value, "sideband"))
    return references


def _matches(value: float, references: list[_Reference], rel_tol: float) -> list[tuple]:
    """References within ``rel_tol`` of ``value``, best first."""
    found = []
    for reference in references:
        if reference.value > 0.0 and abs(value - reference.value) <= rel_tol * reference.value:
            deviation = (value - reference.value) / reference.value
            found.append((abs(deviation), _KIND_PRIORITY[reference.kind], deviation, reference))
    found.sort(key=lambda match: match[:2])
    return found


def local_maxima(values: np.ndarray) -> np.ndarray:
    """Indices of the local maxima of a 1-D series, ascending.

    A sample is a maximum when it exceeds both neighbours; a plateau of equal samples
    is one maximum when it exceeds the samples on both sides, placed at its middle
    (the left one of two middles).  The first and last samples never are, nor is a
    plateau that reaches either end.  These are the rules of
    ``scipy.signal.find_peaks`` without conditions, in NumPy so that a run's signal
    analysis does not load ``scipy.signal`` (0.5 s and 40 MB of imports).
    """
    values = np.asarray(values)
    if values.ndim != 1:
        raise ValueError(f"values must be 1-D (got shape {values.shape})")
    if values.size < 3:
        return np.empty(0, dtype=np.intp)
    changes = np.flatnonzero(values[1:] != values[:-1])
    first = np.concatenate(([0], changes + 1))  # first sample of each run of equal values
    last = np.concatenate((changes, [values.size - 1]))  # and its last
    level = values[first]
    inner = np.arange(1, first.size - 1)
    higher = (level[inner] > level[inner - 1]) & (level[inner] > level[inner + 1])
    runs = inner[higher]
    return (first[runs] + last[runs]) // 2


def find_peaks(
    spectrum: xr.DataArray,
    n: int = 10,
    *,
    natural_frequencies: Mapping[str, float] | xr.Dataset | None = None,
    mesh_frequency: float | Mapping[str, float] | None = None,
    mesh_harmonics: int = 20,
    sideband_frequency: float | None = None,
    sideband_orders: int = 3,
    sideband_name: str = "carrier",
    rel_tol: float = 0.01,
    min_frequency: float = 0.0,
) -> pd.DataFrame:
    """The ``n`` largest local maxima of a spectrum, each identified.

    A peak at ``f`` matches a reference ``f_ref`` when
    ``|f - f_ref| <= rel_tol * f_ref``.  Its identification is the closest
    match in relative terms (ties: mesh harmonic, then natural frequency, then
    sideband) or "unidentified"; the closest matching natural frequency is also
    reported when the identification is something else.

    Parameters
    ----------
    spectrum : xarray.DataArray
        1-D amplitude spectrum (e.g. from
        :func:`pygear.analysis.signals.signal.amplitude_spectrum`).
        References are in the units of its coordinate (Hz for ``frequency``).
    n : int, default 10
        Number of peaks to return, largest first.
    natural_frequencies : mapping or xarray.Dataset, optional
        Label -> frequency, e.g. ``{"rotational 2": 1334.0}``, or a modal Dataset
        with ``frequency`` and ``mode_class`` (labelled "<class> <k>", k counting
        distinct frequencies of that class upwards from 1).
    mesh_frequency : float or mapping of str to float, optional
        Mesh frequency, or one per stage (``{"stage2": 428.1}``, labels
        "stage2 mesh harmonic 1"); harmonics 1 .. ``mesh_harmonics`` are references.
    mesh_harmonics : int, default 20
        Highest mesh harmonic considered.
    sideband_frequency : float, optional
        Sideband spacing (e.g. the carrier's rotation frequency); sidebands
        ``k f_mesh +/- j f_sb`` for ``j = 1 .. sideband_orders`` are references.
    sideband_orders : int, default 3
        Most sideband orders on each side.
    sideband_name : str, default "carrier"
        Name of the sideband spacing in labels ("mesh harmonic 7 − 1×carrier").
    rel_tol : float, default 0.01
        Relative tolerance of a match.
    min_frequency : float, default 0
        Ignore peaks below this value.  Spectra keep their mean by default, and
        the DC bin's window lobe (bin 1 for Hann) is then a local maximum: pass
        a few bin widths here to skip it.

    Returns
    -------
    pandas.DataFrame
        Columns :data:`PEAK_COLUMNS`; ``attrs`` holds the amplitude and axis units.
    """
    if not isinstance(spectrum, xr.DataArray) or spectrum.ndim != 1:
        raise SignalError("spectrum: must be a 1-D xarray.DataArray (select one channel first)")
    axis = spectrum.dims[0]
    if axis not in spectrum.coords:
        raise SignalError(f"spectrum: its dimension {axis!r} needs a coordinate")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise SignalError(f"n: must be an integer >= 1, got {n!r}")
    if not (np.isfinite(rel_tol) and 0.0 < rel_tol < 1.0):
        raise SignalError(f"rel_tol: must lie in (0, 1), got {rel_tol!r}")
    amplitude = np.asarray(spectrum.values, dtype=float)
    if not np.all(np.isfinite(amplitude)):
        raise SignalError("spectrum: contains NaN or inf values")
    references = _natural_references(natural_frequencies) + _mesh_references(
        mesh_frequency, mesh_harmonics, sideband_frequency, sideband_orders, sideband_name
    )
    positions = np.asarray(spectrum[axis].values, dtype=float)
    indices = local_maxima(amplitude)
    indices = indices[positions[indices] >= min_frequency]
    indices = indices[np.argsort(amplitude[indices], kind="stable")[::-1][:n]]
    rows = []
    for index in indices:
        value = float(positions[index])
        matches = _matches(value, references, rel_tol)
        best = matches[0] if matches else None
        natural = next((m[3] for m in matches if m[3].kind == "natural frequency"), None)
        rows.append(
            {
                "frequency_hz": value,
                "amplitude": float(amplitude[index]),
                "identification": best[3].label if best else "unidentified",
                "kind": best[3].kind if best else "unidentified",
                "reference": best[3].value if best else np.nan,
                "relative_deviation": best[2] if best else np.nan,
                "near_natural_frequency": natural.label
                if natural and natural is not best[3]
                else "",
            }
        )
    table = pd.DataFrame(rows, columns=list(PEAK_COLUMNS))
    axis_units = spectrum[axis].attrs.get("units", "")
    if axis != "frequency":
        table = table.rename(columns={"frequency_hz": str(axis)})
    table.attrs.update(
        axis=str(axis), axis_units=axis_units, amplitude_units=spectrum.attrs.get("units", "")
    )
    return table


def peak_table_text(peaks: pd.DataFrame, *, title: str | None = None) -> str:
    """Format a :func:`find_peaks` table as fixed-width text for printing.

    Parameters
    ----------
    peaks : pandas.DataFrame
        The table from :func:`find_peaks`.
    title : str, optional
        A line printed above the table.

    Returns
    -------
    str
        The table, one peak per line, largest first.
    """
    axis = peaks.attrs.get("axis", "frequency")
    axis_column = "frequency_hz" if "frequency_hz" in peaks.columns else axis
    axis_units = peaks.attrs.get("axis_units", "Hz")
    amplitude_units = peaks.attrs.get("amplitude_units", "")
    headers = [
        "#",
        f"{axis} [{axis_units}]",
        f"amplitude [{amplitude_units}]",
        "identification",
        "near natural frequency",
    ]
    body = [
        [
            str(rank),
            f"{row[axis_column]:.2f}",
            f"{row['amplitude']:.4g}",
            str(row["identification"]),
            str(row["near_natural_frequency"]),
        ]
        for rank, (_, row) in enumerate(peaks.iterrows(), start=1)
    ]
    widths = [max(len(line[col]) for line in [headers, *body]) for col in range(len(headers))]
    right = (True, True, True, False, False)

    def line(cells: list[str]) -> str:
        return "  ".join(
            cell.rjust(width) if align else cell.ljust(width)
            for cell, width, align in zip(cells, widths, right, strict=True)
        ).rstrip()

    lines = [title] if title else []
    lines += [line(headers), "  ".join("-" * width for width in widths)]
    lines += [line(cells) for cells in body] or ["(no peaks)"]
    return "\n".join(lines)
