"""NetCDF output: CF-style attributes and atomic writes.

Every file is written under a temporary name in its target directory and renamed
only when complete, so a crash never leaves a file that looks whole.
"""

from __future__ import annotations

import contextlib
import datetime
import functools
import os
import subprocess
import tempfile
from pathlib import Path

import xarray as xr

from . import __version__

__all__ = ["atomic_path", "source_string", "write_netcdf"]


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
