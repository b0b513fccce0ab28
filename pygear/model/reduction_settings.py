"""What a long run reduces on the fly (:class:`Reductions`, a scene's
``Transient(reductions=...)``): decimated channels, running statistics, load duration
distributions and rainflow matrices, computed block by block while the run streams
(:mod:`pygear.analysis.time.reductions`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import CaseError

__all__ = ["Reductions", "LOAD_DURATION_TORQUES"]

LOAD_DURATION_TORQUES = ("drive_torque", "load_torque")
"""The torques a load duration distribution can count, each at its member's speed."""


@dataclass(frozen=True)
class Reductions:
    """On-the-fly reductions of a transient run, written into its file.

    Parameters
    ----------
    keep_frequency : float, optional
        Highest frequency the decimated channels keep [Hz]: each channel is low-pass
        filtered (linear phase, within 0.1 dB up to it) and decimated by the largest
        whole factor whose new sample rate is at least 2.5 times it; nothing above it
        aliases into [0, keep_frequency] (attenuated by ``stopband_db``).  None: no
        decimated channels.
    decimate : tuple of str
        The variables decimated (default: every variable over time).
    stopband_db : float
        Attenuation of what would alias into the kept band [dB], >= 40.
    statistics : bool
        Running minimum, maximum, mean and RMS of every channel.
    rainflow : tuple of str
        Variables counted into rainflow matrices (range x mean), e.g. ``("mesh_force",
        "bearing_force")``: every label of each.
    load_duration : tuple of str
        Torques (:data:`LOAD_DURATION_TORQUES`) counted into time-at-level and
        revolutions-at-torque histograms; the run must record the speed of the torque's
        member (``Probe("speed", <member>)``).
    bins : int
        Bins of every histogram along each axis, >= 4.  Their widths are powers of two
        (in the channel's unit) chosen by the data's extent, so that the same record
        gives the same matrix whether it is counted whole or in blocks.
    """

    keep_frequency: float | None = None
    decimate: tuple[str, ...] = ()
    stopband_db: float = 80.0
    statistics: bool = False
    rainflow: tuple[str, ...] = ()
    load_duration: tuple[str, ...] = ()
    bins: int = 64

    def __post_init__(self) -> None:
        for name in ("decimate", "rainflow", "load_duration"):
            value = getattr(self, name)
            if isinstance(value, (list, str)):
                value = (value,) if isinstance(value, str) else tuple(value)
                object.__setattr__(self, name, value)

    @property
    def any(self) -> bool:
        """Whether anything is reduced."""
        return bool(
            self.keep_frequency is not None
            or self.statistics
            or self.rainflow
            or self.load_duration
        )

    def validate(self, path: str, sample_rate: float) -> None:
        """Raise :class:`CaseError` naming the first bad setting."""
        if self.keep_frequency is not None:
            f = self.keep_frequency
            if not (isinstance(f, (int, float)) and math.isfinite(f) and f > 0):
                raise CaseError(f"{path}.keep_frequency must be a frequency > 0 Hz (got {f!r})")
            if 2.5 * f > sample_rate:
                raise CaseError(
                    f"{path}.keep_frequency {f:g} Hz needs a sample rate of at least 2.5 times "
                    f"it; the run samples at {sample_rate:g} Hz (lower keep_frequency)"
                )
        if not (math.isfinite(self.stopband_db) and self.stopband_db >= 40):
            raise CaseError(f"{path}.stopband_db must be >= 40 dB (got {self.stopband_db!r})")
        if not (isinstance(self.bins, int) and self.bins >= 4):
            raise CaseError(f"{path}.bins must be a whole number >= 4 (got {self.bins!r})")
        for torque in self.load_duration:
            if torque not in LOAD_DURATION_TORQUES:
                raise CaseError(
                    f"{path}.load_duration: {torque!r} is not one of "
                    f"{', '.join(LOAD_DURATION_TORQUES)}"
                )
        for name in ("decimate", "rainflow"):
            for variable in getattr(self, name):
                if not isinstance(variable, str) or not variable:
                    raise CaseError(f"{path}.{name} entries must be variable names")
        if not isinstance(self.statistics, bool):
            raise CaseError(f"{path}.statistics must be True or False")
