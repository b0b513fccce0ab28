"""Order-domain bands of a time-synchronous average (TSA): regular, residual, difference.

A TSA is one revolution of a shaft sampled at ``N`` uniform angle steps.  Being one
period of a periodic signal, its discrete Fourier transform holds its content exactly
at the integer shaft orders ``0 .. N/2`` (order ``n`` is the component
``cos(n * theta)`` of the revolution), so band filtering here keeps or zeroes orders of
an rFFT of the whole revolution: exact, with no leakage and no filter transients.  The
*mesh order* ``Z`` is the tooth count of the gear on the shaft.

The bands follow the definitions collected by Lebold, McClintic, Campbell, Byington &
Maynard (2000), "Review of vibration analysis methods for gearbox diagnostics and
prognostics", Proc. 54th MFPT, 623-634, and by Zakrajsek, Townsend & Decker (1993),
"An analysis of gear fault detection methods as applied to pitting fatigue failure
data", NASA TM-105950:

- regular signal: the shaft orders ``1 .. S``, the mesh harmonics ``k Z``
  (``k = 1 .. K``) and their first-order sidebands ``k Z +/- 1``;
- residual signal: the TSA less the shaft orders and the mesh harmonics;
- difference signal: the TSA less the regular signal.

The mean (order 0) carries no gear information and is left out of all three, so
``tsa == mean + regular + difference`` to round-off.  The published definitions leave
``S`` and ``K`` to the user; the defaults here are ``S = 3`` (once-, twice- and
three-per-revolution: unbalance, misalignment, looseness) and every mesh harmonic whose
upper sideband ``k Z + 1`` lies below the Nyquist order ``N / 2``.  The indicators
built on these bands are in :mod:`pygear.analysis.condition.gear_indicators`; the equations and
their sources in ``docs/condition_monitoring.md``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..signals.signal import SignalError

__all__ = [
    "DEFAULT_SHAFT_HARMONICS",
    "MIN_TSA_LENGTH",
    "difference_signal",
    "mesh_band_envelope",
    "regular_signal",
    "residual_signal",
]

#: Shaft orders ``1 .. S`` taken as the shaft's own content (unbalance, misalignment).
DEFAULT_SHAFT_HARMONICS: int = 3
#: Fewest samples a TSA may have.
MIN_TSA_LENGTH: int = 16


# --------------------------------------------------------------------------- input checks


def check_tsa(tsa: Any) -> np.ndarray:
    """The TSA as a finite float 1-D array of at least :data:`MIN_TSA_LENGTH` samples."""
    values = np.asarray(tsa)
    if values.ndim != 1:
        raise SignalError(f"tsa: must be one revolution as a 1-D array, got shape {values.shape}")
    if not np.issubdtype(values.dtype, np.number) or np.iscomplexobj(values):
        raise SignalError(f"tsa: values must be real numbers, got dtype {values.dtype}")
    if values.size < MIN_TSA_LENGTH:
        raise SignalError(
            f"tsa: only {values.size} samples; one revolution needs at least {MIN_TSA_LENGTH}"
        )
    values = values.astype(float)
    bad = int(np.count_nonzero(~np.isfinite(values)))
    if bad:
        raise SignalError(f"tsa: contains {bad} NaN or inf values")
    return values


def is_integer(value: Any) -> bool:
    """True for a Python or NumPy integer (not a bool)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def _highest_order(length: int) -> int:
    """Highest order strictly below the Nyquist order ``length / 2``."""
    return (length - 1) // 2


@dataclass(frozen=True)
class Orders:
    """Validated order sets of a TSA of ``length`` samples."""

    length: int
    mesh_order: int
    shaft_harmonics: int
    mesh_harmonics: int

    def shaft(self) -> np.ndarray:
        """Shaft orders ``1 .. S``."""
        return np.arange(1, self.shaft_harmonics + 1)

    def mesh(self) -> np.ndarray:
        """Mesh harmonics ``k Z``, ``k = 1 .. K``."""
        return self.mesh_order * np.arange(1, self.mesh_harmonics + 1)

    def sidebands(self) -> np.ndarray:
        """First-order sidebands ``k Z - 1`` and ``k Z + 1``."""
        return np.concatenate([self.mesh() - 1, self.mesh() + 1])

    def mask(self, *orders: np.ndarray) -> np.ndarray:
        """Boolean mask over the rFFT bins ``0 .. length // 2`` that are in ``orders``."""
        keep = np.zeros(self.length // 2 + 1, dtype=bool)
        for group in orders:
            keep[group] = True
        return keep


def check_orders(length: int, mesh_order: Any, shaft_harmonics: Any, mesh_harmonics: Any) -> Orders:
    """Check the order parameters against a TSA of ``length`` samples (one-line errors)."""
    highest = _highest_order(length)
    if not is_integer(mesh_order) or mesh_order < 2:
        raise SignalError(f"mesh_order: must be an integer tooth count >= 2, got {mesh_order!r}")
    if mesh_order + 1 > highest:
        raise SignalError(
            f"mesh_order: {mesh_order} and its upper sideband {mesh_order + 1} must lie below "
            f"the Nyquist order {length / 2:g} of a {length}-sample TSA (highest usable order "
            f"{highest}); use a TSA with more samples per revolution"
        )
    if not is_integer(shaft_harmonics) or not 0 <= shaft_harmonics <= highest:
        raise SignalError(
            f"shaft_harmonics: must be an integer in 0..{highest} (below the Nyquist order "
            f"of a {length}-sample TSA), got {shaft_harmonics!r}"
        )
    most = (highest - 1) // mesh_order
    if mesh_harmonics is None:
        mesh_harmonics = most
    elif not is_integer(mesh_harmonics) or not 1 <= mesh_harmonics <= most:
        raise SignalError(
            f"mesh_harmonics: must be an integer in 1..{most} (harmonic k and its sideband "
            f"k*{mesh_order}+1 below the Nyquist order {length / 2:g}), got {mesh_harmonics!r}"
        )
    return Orders(length, int(mesh_order), int(shaft_harmonics), int(mesh_harmonics))


def check_sidebands(orders: Orders, sidebands: Any) -> int:
    """Half-width in shaft orders of the NB4 band about the mesh order."""
    mesh, highest = orders.mesh_order, _highest_order(orders.length)
    widest = min(mesh - 1, highest - mesh)
    if sidebands is None:
        return min(mesh // 2, widest)
    if not is_integer(sidebands) or not 1 <= sidebands <= widest:
        raise SignalError(
            f"sidebands: must be an integer in 1..{widest} (the band {mesh} +/- sidebands must "
            f"hold neither order 0 nor the Nyquist order {orders.length / 2:g}), "
            f"got {sidebands!r}"
        )
    return int(sidebands)


# --------------------------------------------------------------------------- band filtering


def keep_orders(spectrum: np.ndarray, keep: np.ndarray, length: int) -> np.ndarray:
    """The revolution holding only the orders where ``keep`` is true."""
    return np.fft.irfft(np.where(keep, spectrum, 0.0), n=length)


def regular_band(spectrum: np.ndarray, orders: Orders) -> np.ndarray:
    """Regular signal from the rFFT ``spectrum`` of the revolution."""
    keep = orders.mask(orders.shaft(), orders.mesh(), orders.sidebands())
    return keep_orders(spectrum, keep, orders.length)


def residual_band(spectrum: np.ndarray, orders: Orders) -> np.ndarray:
    """Residual signal from the rFFT ``spectrum`` of the revolution."""
    keep = ~orders.mask(np.array([0]), orders.shaft(), orders.mesh())
    return keep_orders(spectrum, keep, orders.length)


def difference_band(spectrum: np.ndarray, orders: Orders) -> np.ndarray:
    """Difference signal from the rFFT ``spectrum`` of the revolution."""
    keep = ~orders.mask(np.array([0]), orders.shaft(), orders.mesh(), orders.sidebands())
    return keep_orders(spectrum, keep, orders.length)


def envelope_band(spectrum: np.ndarray, orders: Orders, sidebands: int) -> np.ndarray:
    """Magnitude of the analytic signal of the band ``Z - s .. Z + s``."""
    low, high = orders.mesh_order - sidebands, orders.mesh_order + sidebands
    analytic = np.zeros(orders.length, dtype=complex)
    analytic[low : high + 1] = 2.0 * spectrum[low : high + 1]
    return np.abs(np.fft.ifft(analytic))


def prepare(
    tsa: Any, mesh_order: Any, shaft_harmonics: Any = 0, mesh_harmonics: Any = None
) -> tuple[np.ndarray, np.ndarray, Orders]:
    """Checked TSA, its rFFT (orders ``0 .. N // 2``) and its checked order sets."""
    values = check_tsa(tsa)
    orders = check_orders(values.size, mesh_order, shaft_harmonics, mesh_harmonics)
    return values, np.fft.rfft(values), orders


def regular_signal(
    tsa: Any,
    mesh_order: int,
    *,
    shaft_harmonics: int = DEFAULT_SHAFT_HARMONICS,
    mesh_harmonics: int | None = None,
) -> np.ndarray:
    """The regular signal: shaft orders, mesh harmonics and their first-order sidebands.

    Keeps the orders ``1 .. shaft_harmonics``, ``k Z`` and ``k Z +/- 1`` for
    ``k = 1 .. mesh_harmonics`` of the TSA and zeroes every other order, the mean
    included (Lebold et al. 2000).

    Parameters
    ----------
    tsa : array_like
        One revolution, ``N >= 16`` samples uniform in angle.
    mesh_order : int
        Tooth count ``Z`` of the gear on the shaft (mesh cycles per revolution); ``Z + 1``
        must lie below the Nyquist order ``N / 2``.
    shaft_harmonics : int, optional
        Shaft orders kept, ``1 .. S`` (default 3).
    mesh_harmonics : int, optional
        Mesh harmonics kept, ``K``; default every ``k`` with ``k Z + 1 < N / 2``.

    Returns
    -------
    numpy.ndarray
        The regular signal, ``N`` samples.
    """
    _, spectrum, orders = prepare(tsa, mesh_order, shaft_harmonics, mesh_harmonics)
    return regular_band(spectrum, orders)


def residual_signal(
    tsa: Any,
    mesh_order: int,
    *,
    shaft_harmonics: int = DEFAULT_SHAFT_HARMONICS,
    mesh_harmonics: int | None = None,
) -> np.ndarray:
    """The residual signal: the TSA less its mean, shaft orders and mesh harmonics.

    Zeroes the orders ``0``, ``1 .. shaft_harmonics`` and ``k Z`` for
    ``k = 1 .. mesh_harmonics`` and keeps the rest, the mesh sidebands included
    (Zakrajsek et al. 1993; Lebold et al. 2000).  Parameters as :func:`regular_signal`.
    """
    _, spectrum, orders = prepare(tsa, mesh_order, shaft_harmonics, mesh_harmonics)
    return residual_band(spectrum, orders)


def difference_signal(
    tsa: Any,
    mesh_order: int,
    *,
    shaft_harmonics: int = DEFAULT_SHAFT_HARMONICS,
    mesh_harmonics: int | None = None,
) -> np.ndarray:
    """The difference signal: the TSA less its mean and its regular signal.

    Zeroes the orders ``0``, ``1 .. shaft_harmonics``, ``k Z`` and ``k Z +/- 1`` for
    ``k = 1 .. mesh_harmonics`` and keeps the rest (Stewart 1977; Lebold et al. 2000).
    Parameters as :func:`regular_signal`.
    """
    _, spectrum, orders = prepare(tsa, mesh_order, shaft_harmonics, mesh_harmonics)
    return difference_band(spectrum, orders)


def mesh_band_envelope(tsa: Any, mesh_order: int, *, sidebands: int | None = None) -> np.ndarray:
    """Envelope of the TSA band-passed about the mesh order, as NB4 uses it.

    The orders ``Z - s .. Z + s`` are kept, the rest zeroed, and the envelope is the
    magnitude of the analytic signal ``b + i H[b]`` of that band ``b`` (Hilbert
    transform ``H`` by FFT: the band's positive orders doubled, the negative ones
    zeroed).  Zakrajsek, Handschuh & Decker (1994) leave the bandwidth to the user; the
    default half-width ``s = floor(Z / 2)`` reaches half way to order 0 and to the
    second mesh harmonic, so the band holds every sideband of the fundamental that
    belongs to it alone (capped below the Nyquist order).

    Parameters
    ----------
    tsa : array_like
        One revolution, ``N >= 16`` samples uniform in angle.
    mesh_order : int
        Tooth count ``Z``.
    sidebands : int, optional
        Half-width ``s`` of the band in shaft orders, ``1 <= s <= Z - 1`` and
        ``Z + s < N / 2``.

    Returns
    -------
    numpy.ndarray
        The envelope, ``N`` samples.
    """
    _, spectrum, orders = prepare(tsa, mesh_order)
    return envelope_band(spectrum, orders, check_sidebands(orders, sidebands))
