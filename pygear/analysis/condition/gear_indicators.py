"""Gear condition indicators of a time-synchronous average (TSA).

Every function takes one revolution of a shaft, sampled at ``N`` uniform angle steps,
as a 1-D array (the TSA), and the *mesh order* ``Z``, the tooth count of the gear on
that shaft.  The regular, residual and difference signals the indicators are built on
come from exact order-domain filtering of the revolution
(:mod:`pygear.analysis.condition.tsa_bands`; re-exported here).  The indicators follow the
definitions collected by Lebold, McClintic, Campbell, Byington & Maynard (2000),
"Review of vibration analysis methods for gearbox diagnostics and prognostics", Proc.
54th MFPT, 623-634, and by Zakrajsek, Townsend & Decker (1993), NASA TM-105950:
FM0 and FM4 (Stewart 1977), NA4 (Zakrajsek et al. 1993), NB4 (Zakrajsek, Handschuh &
Decker 1994), M6A and M8A (Martin 1989), the energy ratio and the sideband level
factor, with the TSA's kurtosis, crest factor and RMS.  Moments are population
moments (``1/N``), as in those definitions.  The equations are in
``docs/condition_monitoring.md``.

A ratio whose denominator is empty (a filtered signal holding nothing but round-off,
e.g. the difference signal of a pure mesh tone) is NaN, not an error: the TSA is valid,
the indicator is undefined.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import xarray as xr

from ..signals.signal import SignalError
from .tsa_bands import (
    DEFAULT_SHAFT_HARMONICS,
    MIN_TSA_LENGTH,
    Orders,
    check_orders,
    check_sidebands,
    difference_band,
    difference_signal,
    envelope_band,
    is_integer,
    mesh_band_envelope,
    prepare,
    regular_band,
    regular_signal,
    residual_band,
    residual_signal,
)

__all__ = [
    "DEFAULT_SHAFT_HARMONICS",
    "INDICATORS",
    "MIN_TSA_LENGTH",
    "crest_factor",
    "difference_signal",
    "energy_ratio",
    "fm0",
    "fm4",
    "gear_indicators",
    "gear_indicators_dataset",
    "kurtosis",
    "m6a",
    "m8a",
    "mesh_band_envelope",
    "na4",
    "nb4",
    "normalized_moment",
    "regular_signal",
    "residual_signal",
    "rms",
    "sideband_level_factor",
]

#: Largest relative deviation of an angle step from the mean step (xarray wrapper).
UNIFORM_TOLERANCE: float = 1e-6
#: A filtered signal whose standard deviation is below this many round-off units of
#: the TSA's peak is empty: its moment ratios are 0/0 and read NaN.
ROUND_OFF_UNITS: float = 64.0

INDICATORS: dict[str, str] = {
    "fm0": "FM0: TSA peak-to-peak over the sum of the mesh-harmonic amplitudes",
    "fm4": "FM4: normalized kurtosis of the difference signal",
    "na4": "NA4: residual 4th moment over the squared mean residual variance of the trend",
    "nb4": "NB4: envelope 4th moment over the squared mean envelope variance of the trend",
    "m6a": "M6A: normalized 6th moment of the difference signal",
    "m8a": "M8A: normalized 8th moment of the difference signal",
    "energy_ratio": "ER: RMS of the difference signal over RMS of the regular signal",
    "sideband_level_factor": "SLF: first-order mesh sidebands over the TSA standard deviation",
    "kurtosis": "kurtosis of the TSA",
    "crest_factor": "crest factor of the TSA (peak over RMS)",
    "rms": "RMS of the TSA",
    "residual_variance": "variance of the residual signal (NA4 trend history)",
    "envelope_variance": "variance of the mesh-band envelope (NB4 trend history)",
}
"""The keys :func:`gear_indicators` returns, each with what it is."""


def _check_history(history: Any, name: str = "history") -> np.ndarray:
    if history is None:
        return np.empty(0)
    try:
        values = np.asarray(history, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise SignalError(
            f"{name}: must be a sequence of earlier variances, got {history!r}"
        ) from None
    if not np.all(np.isfinite(values)) or np.any(values < 0.0):
        raise SignalError(f"{name}: earlier variances must be finite and >= 0, got {history!r}")
    return values


# --------------------------------------------------------------------------- statistics


def _empty(values: np.ndarray, scale: float) -> bool:
    """True when ``values`` holds nothing but round-off of a signal of peak ``scale``."""
    spread = float(np.std(values))
    return spread == 0.0 or spread <= ROUND_OFF_UNITS * np.finfo(float).eps * scale


def _central_moment(values: np.ndarray, order: int) -> float:
    return float(np.mean((values - np.mean(values)) ** order))


def normalized_moment(values: Any, order: int) -> float:
    """Central moment of ``order`` over the variance to the power ``order / 2``.

    ``N^(p/2-1) sum (x - mean)^p / [sum (x - mean)^2]^(p/2)``: 3, 15 and 105 for
    Gaussian samples at ``p = 4, 6, 8``.  NaN when the values are constant.
    """
    values = np.asarray(values, dtype=float).reshape(-1)
    if not is_integer(order) or order < 2:
        raise SignalError(f"order: must be an integer >= 2, got {order!r}")
    if values.size < 2:
        raise SignalError(f"values: need at least 2 samples, got {values.size}")
    variance = _central_moment(values, 2)
    if variance == 0.0:
        return float("nan")
    return _central_moment(values, order) / variance ** (order / 2)


def kurtosis(values: Any) -> float:
    """Normalized 4th central moment (3 for Gaussian samples, 1.5 for a sine)."""
    return normalized_moment(values, 4)


def rms(values: Any) -> float:
    """Root mean square, mean included: ``sqrt(mean(x^2))``."""
    values = np.asarray(values, dtype=float).reshape(-1)
    return float(np.sqrt(np.mean(values**2)))


def crest_factor(values: Any) -> float:
    """Peak over RMS, ``max |x| / sqrt(mean(x^2))`` (``sqrt(2)`` for a sine)."""
    values = np.asarray(values, dtype=float).reshape(-1)
    level = rms(values)
    return float(np.max(np.abs(values)) / level) if level > 0.0 else float("nan")


def _moment_of(signal: np.ndarray, order: int, scale: float) -> float:
    return float("nan") if _empty(signal, scale) else normalized_moment(signal, order)


def _trend_ratio(signal: np.ndarray, history: np.ndarray, scale: float) -> float:
    """4th central moment over the squared mean of the trend's variances."""
    if _empty(signal, scale):
        return float("nan")
    variances = np.append(history, _central_moment(signal, 2))
    return _central_moment(signal, 4) / float(np.mean(variances)) ** 2


def _peak(values: np.ndarray) -> float:
    return float(np.max(np.abs(values)))


# --------------------------------------------------------------------------- indicators


def fm0(tsa: Any, mesh_order: int, *, mesh_harmonics: int | None = None) -> float:
    """FM0: peak-to-peak of the TSA over the sum of the mesh-harmonic amplitudes.

    ``FM0 = (max x - min x) / sum_{k=1..K} P_k``, with ``P_k`` the amplitude of order
    ``k Z`` (Stewart 1977; Lebold et al. 2000).  2 for a pure mesh sine.  NaN when the
    mesh harmonics are all zero.  Parameters as :func:`regular_signal`.
    """
    return _fm0(*prepare(tsa, mesh_order, 0, mesh_harmonics))


def _fm0(values: np.ndarray, spectrum: np.ndarray, orders: Orders) -> float:
    amplitudes = 2.0 * np.abs(spectrum[orders.mesh()]) / orders.length
    total = float(np.sum(amplitudes))
    if total <= ROUND_OFF_UNITS * np.finfo(float).eps * _peak(values):
        return float("nan")
    return float(np.ptp(values)) / total


def fm4(
    tsa: Any,
    mesh_order: int,
    *,
    shaft_harmonics: int = DEFAULT_SHAFT_HARMONICS,
    mesh_harmonics: int | None = None,
) -> float:
    """FM4: normalized kurtosis of the difference signal ``d`` (Stewart 1977).

    ``FM4 = N sum (d - mean d)^4 / [sum (d - mean d)^2]^2``: about 3 for a healthy
    gear (Gaussian-like difference signal), larger for a localized tooth fault.  NaN
    when the difference signal is empty.  Parameters as :func:`regular_signal`.
    """
    values, spectrum, orders = prepare(tsa, mesh_order, shaft_harmonics, mesh_harmonics)
    return _moment_of(difference_band(spectrum, orders), 4, _peak(values))


def m6a(
    tsa: Any,
    mesh_order: int,
    *,
    shaft_harmonics: int = DEFAULT_SHAFT_HARMONICS,
    mesh_harmonics: int | None = None,
) -> float:
    """M6A: ``N^2 sum (d - mean d)^6 / [sum (d - mean d)^2]^3`` of the difference signal.

    15 for a Gaussian difference signal (Martin 1989, as collected by Lebold et al.
    2000).  Parameters as :func:`regular_signal`.
    """
    values, spectrum, orders = prepare(tsa, mesh_order, shaft_harmonics, mesh_harmonics)
    return _moment_of(difference_band(spectrum, orders), 6, _peak(values))


def m8a(
    tsa: Any,
    mesh_order: int,
    *,
    shaft_harmonics: int = DEFAULT_SHAFT_HARMONICS,
    mesh_harmonics: int | None = None,
) -> float:
    """M8A: ``N^3 sum (d - mean d)^8 / [sum (d - mean d)^2]^4`` of the difference signal.

    105 for a Gaussian difference signal (Martin 1989, as collected by Lebold et al.
    2000).  Parameters as :func:`regular_signal`.
    """
    values, spectrum, orders = prepare(tsa, mesh_order, shaft_harmonics, mesh_harmonics)
    return _moment_of(difference_band(spectrum, orders), 8, _peak(values))


def na4(
    tsa: Any,
    mesh_order: int,
    *,
    shaft_harmonics: int = DEFAULT_SHAFT_HARMONICS,
    mesh_harmonics: int | None = None,
    history: Sequence[float] | None = None,
) -> float:
    """NA4: 4th moment of the residual over the squared mean variance of a trend.

    With ``r_j`` the residual signal of record ``j`` of a run, ``M`` the current one
    (Zakrajsek, Townsend & Decker 1993; Lebold et al. 2000)::

        NA4 = N sum_i (r_iM - mean r_M)^4 / [(1/M) sum_j sum_i (r_ij - mean r_j)^2]^2
            = m4(r_M) / [mean(var(r_1), ..., var(r_M))]^2

    with population moments (``1/N``).  Without ``history`` (``M = 1``) it is the
    kurtosis of the residual.

    Parameters
    ----------
    tsa, mesh_order, shaft_harmonics, mesh_harmonics
        As :func:`regular_signal`.
    history : sequence of float, optional
        Residual variances ``var(r_1) .. var(r_{M-1})`` of the earlier records (the
        ``residual_variance`` that :func:`gear_indicators` returns).

    Returns
    -------
    float
        NA4; NaN when the residual is empty.
    """
    earlier = _check_history(history)
    values, spectrum, orders = prepare(tsa, mesh_order, shaft_harmonics, mesh_harmonics)
    return _trend_ratio(residual_band(spectrum, orders), earlier, _peak(values))


def nb4(
    tsa: Any,
    mesh_order: int,
    *,
    sidebands: int | None = None,
    history: Sequence[float] | None = None,
) -> float:
    """NB4: NA4's ratio on the envelope of the TSA band-passed about the mesh order.

    ``NB4 = m4(E_M) / [mean(var(E_1), ..., var(E_M))]^2`` with ``E_j`` the envelope of
    :func:`mesh_band_envelope` of record ``j`` (Zakrajsek, Handschuh & Decker 1994;
    Lebold et al. 2000).  Without ``history`` it is the envelope's kurtosis.

    Parameters
    ----------
    tsa, mesh_order, sidebands
        As :func:`mesh_band_envelope`.
    history : sequence of float, optional
        Envelope variances of the earlier records (the ``envelope_variance`` that
        :func:`gear_indicators` returns).
    """
    earlier = _check_history(history)
    values, spectrum, orders = prepare(tsa, mesh_order)
    envelope = envelope_band(spectrum, orders, check_sidebands(orders, sidebands))
    return _trend_ratio(envelope, earlier, _peak(values))


def energy_ratio(
    tsa: Any,
    mesh_order: int,
    *,
    shaft_harmonics: int = DEFAULT_SHAFT_HARMONICS,
    mesh_harmonics: int | None = None,
) -> float:
    """ER: RMS of the difference signal over RMS of the regular signal.

    ``ER = RMS(d) / RMS(y)`` with ``y`` the regular meshing signal of
    :func:`regular_signal` (Lebold et al. 2000).  It grows as a fault moves energy
    from the meshing components to the rest.  NaN when the regular signal is zero.
    Parameters as :func:`regular_signal`.
    """
    return _energy_ratio(*prepare(tsa, mesh_order, shaft_harmonics, mesh_harmonics))


def _energy_ratio(values: np.ndarray, spectrum: np.ndarray, orders: Orders) -> float:
    regular = regular_band(spectrum, orders)
    if _empty(regular, _peak(values)):
        return float("nan")
    return rms(difference_band(spectrum, orders)) / rms(regular)


def sideband_level_factor(tsa: Any, mesh_order: int) -> float:
    """SLF: the first-order sidebands about the mesh fundamental over the TSA's std.

    ``SLF = (P_{Z-1} + P_{Z+1}) / std(x)`` with ``P_n`` the amplitude of order ``n``
    and ``std`` the population standard deviation of the TSA (Lebold et al. 2000).
    NaN for a constant TSA.
    """
    return _sideband_level_factor(*prepare(tsa, mesh_order))


def _sideband_level_factor(values: np.ndarray, spectrum: np.ndarray, orders: Orders) -> float:
    if _empty(values, _peak(values)):
        return float("nan")
    spread = float(np.std(values))
    z = orders.mesh_order
    sidebands = 2.0 * (np.abs(spectrum[z - 1]) + np.abs(spectrum[z + 1])) / orders.length
    return float(sidebands) / spread


# --------------------------------------------------------------------------- all at once


def _history_column(history: Any, key: str) -> list[Any]:
    if history is None:
        return []
    if isinstance(history, Mapping) or not isinstance(history, Sequence):
        raise SignalError(
            "history: must be a sequence of earlier gear_indicators results, "
            f"got {type(history).__name__}"
        )
    column = []
    for index, record in enumerate(history):
        if not isinstance(record, Mapping) or key not in record:
            raise SignalError(f"history: record {index} has no {key!r} (pass earlier results)")
        column.append(record[key])
    return column


def gear_indicators(
    tsa: Any,
    mesh_order: int,
    *,
    shaft_harmonics: int = DEFAULT_SHAFT_HARMONICS,
    mesh_harmonics: int | None = None,
    sidebands: int | None = None,
    history: Sequence[Mapping[str, float]] | None = None,
) -> dict[str, float]:
    """Every indicator of one TSA, from one rFFT.

    Parameters
    ----------
    tsa, mesh_order, shaft_harmonics, mesh_harmonics
        As :func:`regular_signal`.
    sidebands : int, optional
        Half-width of NB4's band, as :func:`mesh_band_envelope`.
    history : sequence of mappings, optional
        Earlier results of this function for the same gear, oldest first: NA4 and NB4
        take their ``residual_variance`` and ``envelope_variance``.  Appending each
        result to a list and passing the list trends a run.

    Returns
    -------
    dict of str to float
        The keys of :data:`INDICATORS`: ``fm0``, ``fm4``, ``na4``, ``nb4``, ``m6a``,
        ``m8a``, ``energy_ratio``, ``sideband_level_factor``, ``kurtosis``,
        ``crest_factor`` and ``rms`` (of the TSA), and the two variances a later
        record's ``history`` needs.
    """
    residual_history = _check_history(_history_column(history, "residual_variance"))
    envelope_history = _check_history(_history_column(history, "envelope_variance"))
    values, spectrum, orders = prepare(tsa, mesh_order, shaft_harmonics, mesh_harmonics)
    half_width = check_sidebands(orders, sidebands)
    peak = _peak(values)
    residual = residual_band(spectrum, orders)
    difference = difference_band(spectrum, orders)
    envelope = envelope_band(spectrum, orders, half_width)
    return {
        "fm0": _fm0(values, spectrum, orders),
        "fm4": _moment_of(difference, 4, peak),
        "na4": _trend_ratio(residual, residual_history, peak),
        "nb4": _trend_ratio(envelope, envelope_history, peak),
        "m6a": _moment_of(difference, 6, peak),
        "m8a": _moment_of(difference, 8, peak),
        "energy_ratio": _energy_ratio(values, spectrum, orders),
        "sideband_level_factor": _sideband_level_factor(values, spectrum, orders),
        "kurtosis": float("nan") if _empty(values, peak) else kurtosis(values),
        "crest_factor": crest_factor(values),
        "rms": rms(values),
        "residual_variance": _central_moment(residual, 2),
        "envelope_variance": _central_moment(envelope, 2),
    }


def _angle_dim(tsa: xr.DataArray, dim: str | None) -> str:
    if dim is None:
        if tsa.ndim == 1:
            return str(tsa.dims[0])
        if "angle" in tsa.dims:
            return "angle"
        raise SignalError(f"dim: name the angle dimension of tsa (its dims are {tsa.dims})")
    if dim not in tsa.dims:
        raise SignalError(f"dim: {dim!r} is not a dimension of tsa (its dims are {tsa.dims})")
    return dim


def _check_angle(tsa: xr.DataArray, dim: str) -> None:
    if dim not in tsa.coords:
        return
    angle = np.asarray(tsa[dim].values)
    if not np.issubdtype(angle.dtype, np.number):
        raise SignalError(f"tsa: the {dim!r} coordinate must be numeric, got {angle.dtype}")
    steps = np.diff(angle.astype(float))
    mean_step = float(np.mean(steps)) if steps.size else 0.0
    if not np.all(np.isfinite(steps)) or mean_step <= 0.0 or np.any(steps <= 0.0):
        raise SignalError(f"tsa: the {dim!r} coordinate must be finite and strictly increasing")
    deviation = float(np.max(np.abs(steps - mean_step)) / mean_step)
    if deviation > UNIFORM_TOLERANCE:
        raise SignalError(
            f"tsa: the {dim!r} coordinate is not uniform (largest relative step deviation "
            f"{deviation:.3g} > {UNIFORM_TOLERANCE:g}); resample the revolution first"
        )


def _series_history(history: Any, template: xr.DataArray) -> list[list[dict[str, float]]]:
    """Split earlier results (datasets of this wrapper, or mappings) into one history per
    series of ``template`` (the TSA's dimensions other than the angle)."""
    count = template.size
    columns: dict[str, list[np.ndarray]] = {}
    for key in ("residual_variance", "envelope_variance"):
        rows = []
        for index, value in enumerate(_history_column(history, key)):
            try:
                if isinstance(value, xr.DataArray):
                    if set(value.dims) - set(template.dims):
                        raise ValueError
                    value = value.broadcast_like(template).transpose(*template.dims).values
                value = np.broadcast_to(np.asarray(value, dtype=float), template.shape)
            except (TypeError, ValueError):
                raise SignalError(
                    f"history: record {index} {key} does not match the TSA's series "
                    f"(dims {template.dims}, shape {template.shape})"
                ) from None
            rows.append(value.reshape(count))
        columns[key] = rows
    return [
        [
            {key: float(columns[key][record][series]) for key in columns}
            for record in range(len(columns["residual_variance"]))
        ]
        for series in range(count)
    ]


def gear_indicators_dataset(
    tsa: xr.DataArray,
    mesh_order: int,
    *,
    dim: str | None = None,
    shaft_harmonics: int = DEFAULT_SHAFT_HARMONICS,
    mesh_harmonics: int | None = None,
    sidebands: int | None = None,
    history: Sequence[Mapping[str, Any]] | None = None,
) -> xr.Dataset:
    """:func:`gear_indicators` of a DataArray, as a Dataset of the indicators.

    Parameters
    ----------
    tsa : xarray.DataArray
        One revolution along the angle dimension ``dim`` (a coordinate there, if any,
        must be uniform), with a ``units`` attribute.  Other dimensions (channels,
        records, ...) are series analysed separately.
    mesh_order, shaft_harmonics, mesh_harmonics, sidebands
        As :func:`gear_indicators`.
    dim : str, optional
        The angle dimension; default the only dimension, else ``"angle"``.
    history : sequence, optional
        Earlier results of this function (Datasets over the same other dimensions) or
        of :func:`gear_indicators` (mappings of floats, applied to every series).

    Returns
    -------
    xarray.Dataset
        One variable per key of :data:`INDICATORS` over the other dimensions, each with
        ``units`` and ``long_name``; the settings as attributes.
    """
    if not isinstance(tsa, xr.DataArray):
        raise SignalError(f"tsa: must be an xarray.DataArray, got {type(tsa).__name__}")
    if "units" not in tsa.attrs:
        raise SignalError("tsa: needs a 'units' attribute (e.g. 'm/s^2')")
    dim = _angle_dim(tsa, dim)
    _check_angle(tsa, dim)
    length = tsa.sizes[dim]
    if length < MIN_TSA_LENGTH:
        raise SignalError(
            f"tsa: only {length} samples along {dim!r}; one revolution needs at least "
            f"{MIN_TSA_LENGTH}"
        )
    orders = check_orders(length, mesh_order, shaft_harmonics, mesh_harmonics)
    half_width = check_sidebands(orders, sidebands)
    others = tuple(d for d in tsa.dims if d != dim)
    ordered = tsa.transpose(*others, dim)
    coords = {}
    for name, coord in tsa.coords.items():
        if dim not in coord.dims:
            coord = coord.copy()
            coord.attrs.setdefault("long_name", str(name))
            coord.attrs.setdefault("units", "1" if np.issubdtype(coord.dtype, np.number) else "")
            coords[name] = coord
    template = xr.DataArray(
        np.zeros(tuple(tsa.sizes[d] for d in others)), dims=others, coords=coords
    )
    histories = _series_history(history, template)
    rows = np.asarray(ordered.values).reshape(template.size, tsa.sizes[dim])
    results = [
        gear_indicators(
            row,
            mesh_order,
            shaft_harmonics=shaft_harmonics,
            mesh_harmonics=mesh_harmonics,
            sidebands=sidebands,
            history=earlier,
        )
        for row, earlier in zip(rows, histories)
    ]
    units = str(tsa.attrs["units"])
    squared = f"({units})^2"
    unit_of = {"rms": units, "residual_variance": squared, "envelope_variance": squared}
    variables = {}
    for key, meaning in INDICATORS.items():
        values = np.array([result[key] for result in results]).reshape(template.shape)
        variable = template.copy(data=values)
        variable.attrs = {"units": unit_of.get(key, "1"), "long_name": meaning}
        variables[key] = variable
    settings = {
        "mesh_order": orders.mesh_order,
        "shaft_harmonics": orders.shaft_harmonics,
        "mesh_harmonics": orders.mesh_harmonics,
        "sidebands": half_width,
        "samples_per_revolution": length,
        "source": str(tsa.attrs.get("long_name", tsa.name or "TSA")),
    }
    return xr.Dataset(variables, attrs=settings)
