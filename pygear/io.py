"""NetCDF output: CF-style attributes and atomic writes.

Every file is written under a temporary name in its target directory and renamed
only when complete, so a crash never leaves a file that looks whole.
"""

from __future__ import annotations

import contextlib
import datetime
import functools
import hashlib
import importlib
import os
import subprocess
import tempfile
from pathlib import Path

import xarray as xr

from . import __version__

__all__ = ["atomic_path", "source_identity", "source_string", "write_netcdf"]


@functools.lru_cache(maxsize=1)
def source_string() -> str:
    """``pygear <version>`` plus the git revision of the source tree when known."""
    root = Path(__file__).resolve().parent.parent
    try:
        revision = subprocess.run(
            ["git", "-C", str(root), "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            timeout=5,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        revision = "unknown"
    return f"pygear {__version__} (git {revision})"


def _source_files() -> list[Path]:
    """The files whose content decides pygear's numbers: the package's Python sources,
    the compiled kernel, and the Fortran sources when the source tree is installed
    (an editable install; a wheel carries only the compiled kernel)."""
    package = Path(__file__).resolve().parent
    files = sorted(p for p in package.rglob("*.py") if "__pycache__" not in p.parts)
    kernel = importlib.import_module("pygear._kernel").__file__
    if kernel:
        files.append(Path(kernel).resolve())
    fortran = package.parent / "fortran"
    if fortran.is_dir():
        files += sorted(p for p in fortran.iterdir() if p.is_file() and p.name[0] != ".")
    return files


@functools.lru_cache(maxsize=1)
def source_identity() -> str:
    """Hash (16 hex digits) of the names and contents of :func:`_source_files`.

    Computed once per process (5 ms here): any edit of a Python or Fortran source,
    or a rebuilt kernel, gives another identity, which sweeps fold into every point's
    input hash so that results of other code are never reused.
    """
    digest = hashlib.sha256()
    for path in _source_files():
        digest.update(path.name.encode() + b"\0")
        digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()[:16]


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike):
    """Yield a temporary path beside ``path``; rename it to ``path`` on success only."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    os.close(handle)
    try:
        yield Path(temporary)
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp makes files private
        os.replace(temporary, path)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_netcdf(
    dataset: xr.Dataset, path: str | os.PathLike, *, title: str, input_hash: str | None = None
) -> Path:
    """Write ``dataset`` to NetCDF4 atomically with the global attributes of ARCHITECTURE.md.

    Parameters
    ----------
    dataset : xarray.Dataset
        The result; its own attributes are kept.
    path : path-like
        Target file.
    title : str
        One line saying what the file holds.
    input_hash : str, optional
        Hash of the case inputs that produced it.
    """
    stamp = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    dataset = dataset.copy()
    dataset.attrs.update(
        {
            "Conventions": "CF-1.8",
            "title": title,
            "source": source_string(),
            "history": f"{stamp} written by {source_string()}",
        }
    )
    if input_hash:
        dataset.attrs["input_hash"] = input_hash
    path = Path(path)
    with atomic_path(path) as temporary:
        dataset.to_netcdf(temporary, engine="netcdf4")
    return path
