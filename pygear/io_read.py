"""Reading pygear's NetCDF files as pygear wrote the data: text labels as indexes,
time in seconds, a streamed run's file refused until whole.

:func:`open_dataset`, :func:`open_mfdataset` (a batch of scenes of other probes and
kinds stacked along ``scene``) and the xarray backend ``engine="pygear"``
(``PygearBackendEntrypoint``, built on first use so that importing this module imports
no xarray).  :mod:`pygear.io` writes the files and re-exports all of this.
"""

from __future__ import annotations

import functools
import os
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "COMPLETE",
    "LABEL_SUFFIX",
    "LEGACY_TIME_UNITS",
    "IncompleteFileError",
    "PygearBackendEntrypoint",  # noqa: F822 - built on first access (__getattr__)
    "check_complete",
    "index_labels",
    "open_dataset",
    "open_mfdataset",
]

LEGACY_TIME_UNITS = "seconds since 1970-01-01"
"""How files written before 0.1.0's reading fixes stored ``time`` (t = 0 as the epoch)."""

LABEL_SUFFIX = "_label"
"""A label dimension ``member`` is written with its names in ``member_label(member)``."""

_COORDINATE_MARK = "pygear_coordinate"
"""Attribute :func:`open_mfdataset` puts on a coordinate it stacks as data for a while."""


COMPLETE = "complete"
"""Global attribute of a streamed file: 0 while it is written (or when its run stopped
before the end), 1 once whole.  :func:`index_labels` (so :func:`open_dataset`,
``engine="pygear"`` and ``pygear analyze``) refuses a file with ``complete = 0``."""


class IncompleteFileError(ValueError):
    """A streamed run's file that is not whole yet (``complete = 0``)."""


def check_complete(dataset: xr.Dataset, name: str = "the file") -> None:
    """Raise :class:`IncompleteFileError` for a file marked ``complete = 0``."""
    flag = dataset.attrs.get(COMPLETE)
    if flag is not None and int(flag) == 0:
        raise IncompleteFileError(
            f"{name} is an incomplete run (complete = 0: written while the run goes, "
            "stopped before its end); `pygear run --resume` completes it"
        )


def index_labels(dataset: xr.Dataset) -> xr.Dataset:
    """A pygear file as pygear computed it: every ``<dim>_label`` back as the text
    index of ``<dim>`` (so ``.sel(member="planetary.sun")`` works) and ``time`` in
    seconds from the start (also from files that stored it against the 1970 epoch).
    Pass it as ``preprocess`` to ``xarray.open_mfdataset``; :func:`open_dataset`,
    :func:`open_mfdataset` and ``engine="pygear"`` apply it."""
    import numpy as np

    check_complete(dataset)
    text = [name for name, variable in dataset.variables.items() if variable.dtype.kind in "OUS"]
    if text:  # labels are small: in memory, so Dask never chunks text (it cannot size it)
        dataset = dataset.assign_coords(
            {name: dataset[name].load() for name in text if name in dataset.coords}
        )
        for name in text:
            if name not in dataset.coords:
                dataset[name] = dataset[name].load()
    for name in list(dataset.variables):
        dimension = str(name).removesuffix(LABEL_SUFFIX)
        variable = dataset[name]
        if name != dimension and variable.dims == (dimension,) and dimension not in dataset.coords:
            values = variable.values.astype(str).astype(object)
            dataset = dataset.drop_vars(name).assign_coords(
                {dimension: (dimension, values, dict(variable.attrs))}
            )
    if "time" in dataset.variables:
        time = dataset["time"]
        units = str(time.attrs.get("units", time.encoding.get("units", "")))
        if np.issubdtype(time.dtype, np.datetime64):
            seconds = (time.values - np.datetime64("1970-01-01T00:00:00")) / np.timedelta64(1, "s")
        elif units.startswith(LEGACY_TIME_UNITS):  # an older file, read without decoding
            seconds = time.values
        else:
            return dataset
        attrs = {k: v for k, v in time.attrs.items() if k not in ("standard_name", "calendar")}
        attrs["units"] = "s"
        dataset = dataset.assign_coords(time=(time.dims, np.asarray(seconds, float), attrs))
    return dataset


def open_dataset(path: str | os.PathLike, **options) -> xr.Dataset:
    """Open a pygear NetCDF file as pygear wrote the data: labels as text indexes and
    time in seconds (:func:`index_labels`); ``options`` go to ``xarray.open_dataset``.
    The same as ``xarray.open_dataset(path, engine="pygear")``."""
    import xarray as xr

    options.setdefault("decode_times", False)
    opened = xr.open_dataset(path, **options)
    result = index_labels(opened)
    result.set_close(opened.close)  # closing the result closes the file
    return result


def _stackable(dataset: xr.Dataset, keep: frozenset = frozenset(), then=None) -> xr.Dataset:
    """``dataset`` through :func:`index_labels`, its coordinates other than indexes (and
    ``keep``) as data variables marked :data:`_COORDINATE_MARK`: xarray stacks data
    variables that some files lack (NaN there), but refuses a coordinate that some files
    lack or hold as data (a run's ``mode_class`` coordinate, a modal file's variable)."""
    dataset = index_labels(dataset)
    names = [n for n in dataset.coords if n not in dataset.indexes and n not in keep]
    dataset = dataset.reset_coords(names)
    for name in names:
        dataset[name] = dataset[name].copy().assign_attrs({_COORDINATE_MARK: 1})
    return then(dataset) if then is not None else dataset  # a caller's own preprocess


def _with_coordinates(dataset: xr.Dataset) -> xr.Dataset:
    """Undo :func:`_stackable`'s marks: the marked variables are coordinates again."""
    marked = [n for n, v in dataset.variables.items() if _COORDINATE_MARK in v.attrs]
    for name in marked:
        dataset[name].attrs.pop(_COORDINATE_MARK)
    return dataset.set_coords([n for n in marked if n in dataset.data_vars])


def open_mfdataset(paths, **options) -> xr.Dataset:
    """Open several pygear files as one dataset: by default stacked along ``scene``
    (``combine="nested", concat_dim="scene"``), each file through :func:`index_labels`,
    labels and times joined outer.  Files of scenes with other durations, probes,
    members or meshes, and files of other kinds (a modal file beside runs) stack too:
    a variable, coordinate or label a file lacks is NaN in its scene.  Coordinates other
    than the label indexes gain the ``scene`` dimension (each scene keeps its own).
    ``options`` go to ``xarray.open_mfdataset`` (``combine="by_coords"`` as there,
    with :func:`index_labels` as ``preprocess``)."""
    import functools

    import xarray as xr

    options.setdefault("decode_times", False)
    if options.get("combine", "nested") != "nested":
        options.setdefault("preprocess", index_labels)
        return xr.open_mfdataset(paths, **options)
    options["combine"] = "nested"
    options.setdefault("concat_dim", "scene")
    keep = options["concat_dim"]
    keep = frozenset([keep] if isinstance(keep, str) else [k for k in keep if isinstance(k, str)])
    options["preprocess"] = functools.partial(_stackable, keep=keep, then=options.get("preprocess"))
    defaults = {"join": "outer", "data_vars": "all", "coords": "minimal"}
    defaults["compat"] = "no_conflicts"
    for key, value in defaults.items():
        options.setdefault(key, value)
    stacked = xr.open_mfdataset(paths, **options)
    result = _with_coordinates(stacked)
    result.set_close(stacked.close)  # closing the result closes the files
    return result


class _PygearBackend:
    """``xarray.open_dataset(path, engine="pygear")``: a pygear file with its labels as
    indexes and time in seconds (:func:`index_labels`), also through
    ``xarray.open_mfdataset(..., engine="pygear")``.

    Registered in pyproject.toml under ``[project.entry-points."xarray.backends"]``.
    The file is read by xarray's netCDF4 backend; nothing in it is executed.  It never
    claims a file by itself (``guess_can_open`` is False): name the engine.
    ``pygear.io.PygearBackendEntrypoint`` is this class on xarray's ``BackendEntrypoint``,
    built when first asked for, so importing :mod:`pygear.io` imports no xarray.
    """

    description = "pygear NetCDF results: text labels as indexes, time in seconds"
    url = "https://github.com/pygear/pygear/blob/main/docs/data_model.md"
    open_dataset_parameters = (
        "filename_or_obj",
        "mask_and_scale",
        "decode_times",
        "concat_characters",
        "decode_coords",
        "drop_variables",
        "use_cftime",
        "decode_timedelta",
        "group",
    )

    def open_dataset(
        self,
        filename_or_obj,
        *,
        mask_and_scale=True,
        decode_times=False,
        concat_characters=True,
        decode_coords=True,
        drop_variables=None,
        use_cftime=None,
        decode_timedelta=None,
        group=None,
    ):
        from xarray.backends import NetCDF4BackendEntrypoint

        opened = NetCDF4BackendEntrypoint().open_dataset(
            filename_or_obj,
            mask_and_scale=mask_and_scale,
            decode_times=decode_times,
            concat_characters=concat_characters,
            decode_coords=decode_coords,
            drop_variables=drop_variables,
            use_cftime=use_cftime,
            decode_timedelta=decode_timedelta,
            group=group,
        )
        result = index_labels(opened)
        result.set_close(opened.close)
        return result

    def guess_can_open(self, filename_or_obj) -> bool:
        return False

    def open_datatree(self, filename_or_obj, **kwargs):
        raise NotImplementedError("engine='pygear' opens datasets (xarray.open_dataset)")


@functools.lru_cache(maxsize=1)
def _backend_class() -> type:
    from xarray.backends import BackendEntrypoint

    return type(
        "PygearBackendEntrypoint",
        (_PygearBackend, BackendEntrypoint),
        {"__module__": __name__, "__doc__": _PygearBackend.__doc__},
    )


def __getattr__(name: str):
    if name == "PygearBackendEntrypoint":
        return _backend_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
