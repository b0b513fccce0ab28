"""The BLAS the Fortran kernel links, found and reported.

The kernel is linked against the OpenBLAS of the ``scipy-openblas32`` wheel, the build
NumPy and SciPy ship, so it runs kernels for the CPU it is on instead of an older system
library's generic fallback.  An editable build finds the library through its run path;
an installed wheel may not, so :func:`preload_kernel_blas` loads it by path first (the
dynamic linker then resolves the kernel's ``libscipy_openblas.so`` by its soname).
Importing this module does that, which is why ``pygear/__init__`` imports it first.
A manylinux wheel repaired by auditwheel carries its own copy of the library (renamed,
in ``pygear.libs/`` beside the package) and the kernel links that copy.
"""

from __future__ import annotations

import ctypes
import importlib.util
import os

__all__ = ["kernel_blas", "preload_kernel_blas"]

_LIBRARY = "libscipy_openblas.so"


def _wheel_library() -> str | None:
    """Path of the scipy-openblas32 library, without importing that package."""
    spec = importlib.util.find_spec("scipy_openblas32")
    if spec is None or not spec.submodule_search_locations:
        return None
    path = os.path.join(list(spec.submodule_search_locations)[0], "lib", _LIBRARY)
    return path if os.path.exists(path) else None


def _bundled_library() -> str | None:
    """Path of the OpenBLAS auditwheel copied into ``pygear.libs/``, if any."""
    site = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    folder = os.path.join(site, "pygear.libs")
    if not os.path.isdir(folder):
        return None
    for name in sorted(os.listdir(folder)):
        if name.startswith(("libscipy_openblas", "libopenblas")):
            return os.path.join(folder, name)
    return None


def preload_kernel_blas() -> None:
    """Load the wheel's OpenBLAS globally before the kernel extension is imported."""
    path = _wheel_library()
    if path is not None:
        ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL)


def kernel_blas() -> dict[str, str]:
    """The BLAS library the kernel runs: ``library``, ``version`` and ``core`` (the CPU
    kernel set OpenBLAS chose, e.g. ``Haswell``; ``Prescott`` or ``Katmai`` mean a
    generic fallback)."""
    from threadpoolctl import threadpool_info

    from .kernel import _kernel  # noqa: F401  (loads the library the kernel links)

    wheel = _bundled_library() or _wheel_library()
    libraries = [info for info in threadpool_info() if info.get("user_api") == "blas"]
    for info in libraries:
        path = info.get("filepath", "")
        if (wheel and os.path.realpath(path) == os.path.realpath(wheel)) or (
            not wheel and "numpy.libs" not in path and "scipy.libs" not in path
        ):
            return {
                "library": path,
                "version": str(info.get("version")),
                "core": str(info.get("architecture")),
            }
    return {"library": "unknown", "version": "unknown", "core": "unknown"}


preload_kernel_blas()
