"""pyFFTW, loaded without the drop-in interfaces it builds for SciPy and Dask.

Importing any part of pyFFTW runs its package ``__init__``, which imports
``pyfftw.interfaces``; that in turn imports ``scipy.fftpack`` and ``dask.array.fft``
whenever they are installed, to offer replacements for them (pyFFTW 0.15).  pygear
calls the :class:`pyfftw.FFTW` class itself and uses none of the interfaces, and those
two imports cost a run 0.3 s and 20 MB (``dask.array`` alone 0.23 s).  So while pyFFTW
loads, both read as not installed — a ``None`` entry in ``sys.modules`` makes their
import raise ``ImportError``, the case pyFFTW handles by leaving that interface out —
and the entries are taken back at once, so a later ``import dask.array`` works as
always.  A module already loaded is left alone, and in any thread but the main one
pyFFTW is imported as it is (another thread could be importing one of them).
"""

from __future__ import annotations

import importlib
import sys
import threading
from types import ModuleType

__all__ = ["pyfftw"]

SKIPPED = ("dask.array.fft", "scipy.fftpack")
"""Modules pyFFTW's interfaces would import, which pygear does not use."""


def _import_pyfftw() -> ModuleType:
    if "pyfftw" in sys.modules or threading.current_thread() is not threading.main_thread():
        return importlib.import_module("pyfftw")
    hidden = [name for name in SKIPPED if name not in sys.modules]
    for name in hidden:
        sys.modules[name] = None  # reads as not installed
    try:
        return importlib.import_module("pyfftw")
    finally:
        for name in hidden:
            if sys.modules.get(name, 0) is None:
                del sys.modules[name]


pyfftw = _import_pyfftw()
