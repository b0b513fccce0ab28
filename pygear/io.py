"""NetCDF output: CF-style attributes, compressed channels and atomic writes.

Every file is written under a temporary name in its target directory and renamed
only when complete, so a crash never leaves a file that looks whole.  xarray is
imported by :func:`write_netcdf` when it writes, so the atomic helpers cost no import.

Reading the files back (labels as indexes, time in seconds, the ``pygear`` xarray
engine, a streamed file refused until whole) is :mod:`pygear.io_read`, re-exported here.
"""

from __future__ import annotations

import contextlib
import datetime
import functools
import hashlib
import importlib
import os
import signal
import tempfile
import threading
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from ._version import __version__
from .io_read import (
    COMPLETE,
    LABEL_SUFFIX,
    LEGACY_TIME_UNITS,
    IncompleteFileError,
    check_complete,
    index_labels,
    open_dataset,
    open_mfdataset,
)

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "CONVENTIONS",
    "LABEL_SUFFIX",
    "LEGACY_TIME_UNITS",
    "PygearBackendEntrypoint",  # noqa: F822 - built on first access (__getattr__)
    "TIME_UNITS",
    "index_labels",
    "open_dataset",
    "open_mfdataset",
    "PROVENANCE",
    "COMPRESSION_LEVEL",
    "COMPRESSED_SIZE",
    "COMPLETE",
    "IncompleteFileError",
    "append_streamed",
    "check_complete",
    "create_streamed",
    "finish_streamed",
    "netcdf_layout",
    "WriteInterrupted",
    "atomic_path",
    "check_suffix",
    "save_figure",
    "signals_interrupt",
    "source_identity",
    "source_string",
    "stable_digest",
    "write_netcdf",
    "write_npz",
]


COMPRESSION_LEVEL = 1
"""zlib level of the compressed variables (with HDF5's byte shuffle before it).

On a study-case run-up (10 channels of 200 001 float64 samples, 17.6 MB raw) level 1
writes 11.8 MB, levels 2-4 between 11.80 and 11.72 MB in the same time, and level 9
11.66 MB in 2.7 times as long: past level 1 the time buys almost nothing.  The noisy
accelerations and mesh forces keep 77-86 % of their size, speeds and torques 64 % or
less, the time coordinate 4 %."""

COMPRESSED_SIZE = 4096
"""Numeric variables with at least this many values are compressed (the channels,
their time coordinate, spectra); smaller ones are not worth a filter."""


def source_string() -> str:
    """``pygear <version> (git <revision>)``: the revision the package was built from
    (:func:`pygear._version.git_revision`), never one git finds around it at run time."""
    from ._version import git_revision

    return f"pygear {__version__} (git {git_revision() or 'unknown'})"


def _source_files() -> list[Path]:
    """The files whose content decides pygear's numbers: the package's Python sources,
    the compiled kernel, and the Fortran sources when the source tree is installed
    (an editable install; a wheel carries only the compiled kernel)."""
    package = Path(__file__).resolve().parent
    files = sorted(p for p in package.rglob("*.py") if "__pycache__" not in p.parts)
    kernel = importlib.import_module("pygear.kernel._kernel").__file__
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


def stable_digest(value: object) -> str:
    """Hash (16 hex digits) of ``value``, the same in every process.

    Dataclasses are taken field by field, mappings in key order, arrays by dtype,
    shape and every byte (a repr would elide the middle of a long array), floats by
    their exact repr.
    """
    return hashlib.sha256(repr(_canonical(value)).encode()).hexdigest()[:16]


def _canonical(value: object) -> object:
    import dataclasses

    import numpy as np

    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return (
            type(value).__name__,
            tuple((f.name, _canonical(getattr(value, f.name))) for f in dataclasses.fields(value)),
        )
    if isinstance(value, np.ndarray):
        data = np.ascontiguousarray(value)
        return ("ndarray", data.dtype.str, data.shape, hashlib.sha256(data.tobytes()).hexdigest())
    if isinstance(value, dict):
        return ("dict", tuple(sorted((repr(k), _canonical(v)) for k, v in value.items())))
    if isinstance(value, (list, tuple)):
        return (type(value).__name__, tuple(_canonical(v) for v in value))
    if isinstance(value, (set, frozenset)):
        return ("set", tuple(sorted(repr(_canonical(v)) for v in value)))
    if isinstance(value, (float, np.floating)):
        return float(value).hex()
    return repr(value)


class WriteInterrupted(KeyboardInterrupt):
    """SIGTERM or Ctrl-C arrived while a file was written; its temporary was removed.

    Attributes
    ----------
    signal_number : int
        The signal (SIGTERM, or SIGINT for Ctrl-C).
    """

    def __init__(self, message: str = "", signal_number: int = signal.SIGINT) -> None:
        super().__init__(message)
        self.signal_number = int(signal_number)


_DEFAULT_HANDLERS = {signal.SIGINT: signal.default_int_handler, signal.SIGTERM: signal.SIG_DFL}


@contextlib.contextmanager
def signals_interrupt():
    """Turn SIGTERM and Ctrl-C into :class:`WriteInterrupted` while the block runs.

    SIGTERM's default action ends the process at once, past every ``finally``: a file
    being written would stay behind under its temporary name.  Raised as an exception
    instead, the writer's clean-up runs.  Only signals still at their default handler
    are taken (a handler a run installed, such as the deferred interrupt of
    :mod:`pygear.kernel.newmark`, stays in force), and only in the main thread.  A second
    signal while the first unwinds is ignored, so the clean-up completes.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    raised: list[int] = []

    def handler(signum, frame):
        if raised:
            return
        raised.append(signum)
        name = signal.Signals(signum).name
        raise WriteInterrupted(f"interrupted by {name}; the file being written was removed", signum)

    previous = {
        number: signal.getsignal(number)
        for number, default in _DEFAULT_HANDLERS.items()
        if signal.getsignal(number) is default
    }
    for number in previous:
        signal.signal(number, handler)
    try:
        yield
    finally:
        for number, restored in previous.items():
            signal.signal(number, restored)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike):
    """Yield a temporary path beside ``path``; rename it to ``path`` on success only.

    The temporary (``.<name>.<random>.part``) is flushed to disk before the rename, so
    a full disk fails the write instead of leaving a short file under the final name,
    and it is removed on any exception, Ctrl-C or SIGTERM (see :func:`signals_interrupt`).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with signals_interrupt():
        temporary = None
        try:
            handle, temporary = tempfile.mkstemp(
                prefix=f".{path.name}.", suffix=".part", dir=path.parent
            )
            os.close(handle)
            yield Path(temporary)
            os.chmod(temporary, 0o666 & ~_umask())  # mkstemp makes files private
            _flush_to_disk(temporary)
            os.replace(temporary, path)
        finally:
            if temporary is not None:
                with contextlib.suppress(FileNotFoundError):
                    os.remove(temporary)


def _flush_to_disk(path: str) -> None:
    """fsync ``path``: a delayed write error (no space left) surfaces here, not later."""
    descriptor = os.open(path, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)


def check_suffix(option: str, path: str | os.PathLike, suffix: str, what: str) -> None:
    """Raise :class:`~pygear.errors.CaseError` unless ``path`` ends in ``suffix``.

    A command writes one kind of file; a target named as another kind (a figure name
    for NetCDF data) is refused before any work, so no file is overwritten by a
    file of another kind.
    """
    from .errors import CaseError

    path = Path(path)
    if path.suffix.lower() != suffix:
        raise CaseError(
            f"{option} {str(path)!r} must end in {suffix}: {what} is written there "
            f"(got {path.suffix or 'no suffix'})"
        )


def write_npz(path: str | os.PathLike, **arrays) -> Path:
    """Write ``arrays`` to an ``.npz`` file atomically (see :func:`atomic_path`)."""
    import numpy as np

    path = Path(path)
    with atomic_path(path) as temporary, open(temporary, "wb") as handle:
        np.savez(handle, **arrays)
    return path


def save_figure(figure, path: str | os.PathLike, *, release: bool = False, **options) -> Path:
    """Save a matplotlib ``figure`` atomically; the format follows ``path``'s suffix.

    With ``release`` the figure is emptied once saved and its canvas drops the renderer
    that holds the pixels, so their memory is freed now rather than when the garbage
    collector next finds the figure's reference cycles: the four figures of a study-case
    run-up otherwise hold 13 MiB to the end of the process, and the run's peak memory
    with them.  The commands release every figure they save (about 20 ms a figure).
    """
    path = Path(path)
    options.setdefault("format", path.suffix.lstrip(".").lower() or "png")
    with atomic_path(path) as temporary:
        figure.savefig(temporary, **options)
    if release:
        figure.clear()
        vars(figure.canvas).pop("renderer", None)  # Agg's last renderer holds the pixels
    return path


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


CONVENTIONS = "CF-1.10"
"""The CF version every file follows (docs/data_model.md)."""

PROVENANCE = ("case", "scene", "formulation", "input_hash", "case_json")
"""Global attributes that say which inputs made a file; a file computed from another
(spectra, orders, averages of a run file) takes them from it (``provenance``)."""


TIME_UNITS = "s"
"""Units of a file's ``time``: seconds from the run's start, as plain floats.  A
simulation has no date, and CF (4.4) gives a variable with ``standard_name: time`` or
units ``<unit> since <epoch>`` a reference instant, which xarray decodes to datetimes
(1970 dates, rounded to whole nanoseconds); so ``time`` is a coordinate in seconds with
a ``long_name`` and neither, and every reader (plain xarray, netCDF4, ncdump) reads the
seconds.  Files written before (``seconds since 1970-01-01``) are read back in seconds
by :func:`index_labels`."""

def _cf_encoded(dataset: xr.Dataset) -> xr.Dataset:
    """The dataset as a CF file holds it: ``time`` in seconds (:data:`TIME_UNITS`,
    without an epoch or ``standard_name``), and each dimension labelled by text
    (``member``) written without a coordinate variable of its own and with its names in
    the auxiliary coordinate ``member_label`` (CF 1.3: a coordinate variable is numeric;
    CF 5: an auxiliary coordinate is not named after its dimension).
    :func:`index_labels` (or ``engine="pygear"``) turns the labels back into indexes."""
    if "time" in dataset.variables and dataset["time"].attrs.get("units") == "s":
        attrs = {
            k: v for k, v in dataset["time"].attrs.items() if k not in ("standard_name", "calendar")
        }
        attrs.setdefault("long_name", "time from the start of the run")
        dataset = dataset.assign_coords(time=dataset["time"].copy().assign_attrs(attrs))
    labelled = [
        name
        for name in dataset.dims
        if name in dataset.coords and dataset[name].dtype.kind in "OUS"
    ]
    for name in labelled:
        label = dataset[name].variable.to_base_variable()
        dataset = dataset.drop_vars(name).assign_coords({f"{name}{LABEL_SUFFIX}": label})
    return dataset


def write_netcdf(
    dataset: xr.Dataset,
    path: str | os.PathLike,
    *,
    title: str,
    input_hash: str | None = None,
    compression: int = COMPRESSION_LEVEL,
    case_json: str | None = None,
    provenance: Mapping | None = None,
) -> Path:
    """Write ``dataset`` to NetCDF4 atomically, with CF global attributes.

    ``Conventions``, ``title``, ``source`` (pygear's version and git revision), ``history``
    and, when given, ``input_hash`` and ``case_json`` join the dataset's own attributes;
    the file appears under its name only when complete (:func:`atomic_path`).  Numeric
    variables of at least :data:`COMPRESSED_SIZE` values are stored shuffled and
    zlib-compressed (lossless; HDF5 keeps a chunk raw where compression would not shrink
    it, so the file is never larger than uncompressed but for a few bytes of chunk
    index).  Coordinates are written without ``_FillValue`` (CF: a coordinate has no
    missing values), and a file of one scene (a ``scene`` attribute) carries it as a
    scalar ``scene`` coordinate, so that ``xarray.open_mfdataset(files,
    combine="nested", concat_dim="scene")`` stacks scenes along it.

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
    compression : int
        zlib level 1-9 of the large variables; 0 stores every variable raw.
    case_json : str, optional
        The resolved case as JSON (:func:`pygear.model.case_json.case_json`).
    provenance : mapping, optional
        Attributes of the file this one was computed from: its :data:`PROVENANCE`
        entries are kept where the dataset has none of its own.
    """
    if isinstance(compression, bool) or compression not in range(10):
        raise ValueError(f"compression must be a zlib level 0-9 (got {compression!r})")
    dataset, encoding = netcdf_layout(
        dataset,
        title=title,
        input_hash=input_hash,
        compression=compression,
        case_json=case_json,
        provenance=provenance,
    )
    path = Path(path)
    with atomic_path(path) as temporary:
        dataset.to_netcdf(temporary, engine="netcdf4", encoding=encoding)
    return path


def netcdf_layout(
    dataset: xr.Dataset,
    *,
    title: str,
    input_hash: str | None = None,
    compression: int = COMPRESSION_LEVEL,
    case_json: str | None = None,
    provenance: Mapping | None = None,
) -> tuple[xr.Dataset, dict]:
    """The dataset :func:`write_netcdf` writes (global attributes, CF encoding of time
    and labels, the ``scene`` coordinate) and its encoding; the streamed writer of
    :mod:`pygear.runs.streaming` lays its file out with it too."""
    if isinstance(compression, bool) or compression not in range(10):
        raise ValueError(f"compression must be a zlib level 0-9 (got {compression!r})")
    stamp = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    dataset = dataset.copy()
    for key in PROVENANCE:
        if provenance is not None and key in provenance and key not in dataset.attrs:
            dataset.attrs[key] = provenance[key]
    dataset.attrs.update(
        {
            "Conventions": CONVENTIONS,
            "title": title,
            "source": source_string(),
            "history": f"{stamp} written by {source_string()}",
        }
    )
    if input_hash:
        dataset.attrs["input_hash"] = input_hash
    if case_json:
        dataset.attrs["case_json"] = case_json
    scene = dataset.attrs.get("scene")
    if isinstance(scene, str) and "scene" not in dataset.variables and "scene" not in dataset.dims:
        dataset = dataset.assign_coords(scene=((), scene, {"long_name": "scene of the case"}))
    dataset = _cf_encoded(dataset)
    encoding: dict[str, dict] = {name: {"_FillValue": None} for name in dataset.coords}
    for name, variable in dataset.variables.items():
        if variable.dtype.kind in "OUS":  # text as character arrays (CF 2.2)
            encoding.setdefault(name, {}).update({"dtype": "S1", "_FillValue": None})
    if compression:
        for name, variable in dataset.variables.items():
            if variable.dtype.kind in "iuf" and variable.size >= COMPRESSED_SIZE:
                encoding.setdefault(name, {}).update(
                    {"zlib": True, "complevel": compression, "shuffle": True}
                )
    return dataset, encoding


def create_streamed(
    path: Path,
    dataset: xr.Dataset,
    encoding: dict,
    time_chunk: int,
    compression: int = COMPRESSION_LEVEL,
) -> None:
    """Write ``dataset`` (laid out by :func:`netcdf_layout`) to ``path`` with ``time``
    unlimited, every numeric variable over time chunked by ``time_chunk`` samples and
    compressed as :func:`write_netcdf` compresses a long one, and ``complete = 0``: the
    start of a streamed file, grown by :func:`append_streamed`."""
    encoding = {name: dict(value) for name, value in encoding.items()}
    for name, variable in dataset.variables.items():
        if "time" in variable.dims and variable.dtype.kind in "iuf":
            chunks = tuple(time_chunk if d == "time" else n for d, n in variable.sizes.items())
            entry = encoding.setdefault(name, {})
            entry["chunksizes"] = chunks
            if compression:
                entry.update({"zlib": True, "complevel": compression, "shuffle": True})
    dataset = dataset.copy()
    dataset.attrs[COMPLETE] = 0
    dataset.to_netcdf(path, engine="netcdf4", encoding=encoding, unlimited_dims=["time"])
    _flush_to_disk(str(path))


def append_streamed(path: Path, first: int, columns: Mapping) -> None:
    """Write ``columns`` ({variable: values over time, time last}) at samples ``first ..``
    of the streamed file ``path``; the file is open only while it writes (a kill between
    two appends leaves a file HDF5 reads)."""
    import netCDF4

    with netCDF4.Dataset(path, "a") as handle:
        for name, values in columns.items():
            count = values.shape[-1]
            handle[name][..., first : first + count] = values


def finish_streamed(
    path: Path, target: Path, tail: xr.Dataset | None, attrs: Mapping, encoding: dict
) -> Path:
    """Add ``tail`` (what only the end of a run gives) and ``attrs`` to the streamed file
    ``path``, mark it ``complete = 1``, flush it and rename it to ``target``."""
    import netCDF4

    if tail is not None and tail.variables:
        tail.to_netcdf(path, mode="a", engine="netcdf4", encoding=encoding)
    with netCDF4.Dataset(path, "a") as handle:
        for key, value in attrs.items():
            handle.setncattr(key, value)
        handle.setncattr(COMPLETE, 1)
    os.chmod(path, 0o666 & ~_umask())
    _flush_to_disk(str(path))
    os.replace(path, target)
    return target


def __getattr__(name: str):
    if name == "PygearBackendEntrypoint":  # the xarray backend, built when first asked for
        from .io_read import _backend_class

        return _backend_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
