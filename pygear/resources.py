"""Memory and disk a piece of work needs, checked against what the machine has.

A run too large for the machine is refused before it starts, with one line naming the
parameter, the estimate and what is available, instead of ending in a MemoryError
(or a full disk) after the work.  Estimates count the large arrays only (float64
samples: 8 bytes each); the figures available come from ``os.sysconf`` (physical
pages not in use) and ``shutil.disk_usage``.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from .errors import CaseError

__all__ = [
    "FLOAT_BYTES",
    "available_disk",
    "available_memory",
    "format_bytes",
    "require_disk",
    "require_memory",
]

FLOAT_BYTES = 8
"""Bytes of one float64 sample."""


def available_memory() -> float | None:
    """Physical memory not in use now [bytes], or None where the system does not say."""
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES")) * float(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


def available_disk(path: str | os.PathLike) -> float | None:
    """Free disk space [bytes] where ``path`` is or would be created, or None if unknown."""
    directory = Path(path).absolute()
    while not directory.exists() and directory != directory.parent:
        directory = directory.parent
    try:
        return float(shutil.disk_usage(directory).free)
    except OSError:
        return None


def format_bytes(size: float) -> str:
    """``12.8 GB``: decimal units, three significant digits."""
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if size >= scale:
            return f"{size / scale:.3g} {unit}"
    return f"{size:.3g} B"


def require_memory(parameter: str, needed: float, what: str, hint: str = "") -> None:
    """Raise :class:`CaseError` when ``needed`` bytes exceed the memory available.

    Parameters
    ----------
    parameter : str
        The parameter the message names first (``scenes.runup.transient.duration``).
    needed : float
        Estimated bytes.
    what : str
        How the estimate is made (``10 channels x 80000001 samples x 8 bytes, twice``).
    hint : str
        What to change.
    """
    available = available_memory()
    if available is not None and needed > available:
        raise CaseError(
            f"{parameter} needs about {format_bytes(needed)} of memory ({what}), more "
            f"than the {format_bytes(available)} available{'; ' + hint if hint else ''}"
        )


def require_disk(
    parameter: str, needed: float, directory: str | os.PathLike, what: str, hint: str = ""
) -> None:
    """Raise :class:`CaseError` when ``needed`` bytes exceed the free space of ``directory``."""
    available = available_disk(directory)
    if available is not None and needed > available:
        raise CaseError(
            f"{parameter} needs about {format_bytes(needed)} of disk space ({what}), "
            f"more than the {format_bytes(available)} free in {str(directory)!r}"
            f"{'; ' + hint if hint else ''}"
        )
