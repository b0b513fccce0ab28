"""Streamed transient files: a run's channels go into ``<scene>.nc`` as the run goes.

A long run (an IEC 61400 design load case: 600 s at tens of kHz) would hold every
sample in memory twice (the kernel's record and the dataset written from it) and
write its file only at the very end.  :class:`StreamedFile` is the kernel's sample sink
(:class:`pygear.kernel.newmark.SampleSink`): every chunk of samples is laid out as the
whole-record file lays it out (:func:`pygear.analysis.time.transient.channel_variables`)
and appended to the file, whose ``time`` dimension is unlimited and whose variables are
chunked along time and compressed.  Memory is O(block), whatever the run's length.

The file is written under a hidden name beside the target, ``.<scene>.nc.stream.part``,
and carries ``complete = 0`` until the run is over; then what only the end gives (the
equilibrium speeds over the mean window and t_s, from the kernel's final state; the
sensor noise, whose power is the whole record's; the frequencies of
:func:`pygear.runs.outputs.analysis_references`; the solver's counters) is added,
``complete = 1`` set and the file renamed to ``<scene>.nc``.  A reader never takes a
partial file as complete: it has another name and :func:`pygear.io.index_labels`
(``open_dataset``, ``pygear analyze``) refuses ``complete = 0``.  The file is open only
while a block is appended, so a kill between appends leaves a file HDF5 reads; a
checkpoint is written only after the file holds every sample before it, and a resumed
run continues the same file from the checkpoint's sample (what was appended after the
checkpoint is written again).  When the partial file is missing, unreadable or belongs
to another run, :func:`usable_partial` says so and the run starts over.

What needs the whole record, and how it is had here:

* t_s and the equilibrium speeds: the kernel carries them (first crossing, the mean
  window's velocity sum) in its state, never from samples.
* a sensor's structural response (IIR filters): filtered block by block, each filter's
  state carried (``scipy.signal.lfilter`` with ``zi``), in the checkpoint too.
* a sensor's noise (power = mean square of the whole record / 10^(SNR/10)): the running
  sum of squares gives the power at the end; the noise is then added reading the
  channel back from the file in blocks, drawn from the same generator in sequence
  (NumPy's draws in consecutive blocks equal one draw of the whole length).
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
from pathlib import Path

import numpy as np

from .. import io
from ..analysis.time.run_dataset import (
    channel_variables,
    sample_times,
    static_attributes,
    time_coordinate,
)
from ..analysis.time.transient import TransientProblem

__all__ = [
    "BUFFER_BYTES",
    "StreamedFile",
    "partial_path",
    "stream_wanted",
    "usable_partial",
]

BUFFER_BYTES = 16 * 2**20
"""Samples a streamed run holds at once, all channels together [bytes] (the kernel's
block and the block waiting to be appended each take about this much)."""

STREAM_RECORD_BYTES = 256 * 2**20
"""A run whose record (channels x samples x 8 bytes) exceeds this streams by default."""

TIME_CHUNK = 16384
"""Samples per HDF5 chunk along time of a streamed file (128 KiB per channel)."""

IDENTITY = "stream_identity"
"""Attribute of a partial streamed file: the run it belongs to (removed once whole)."""


FINISHING = "stream_finishing"
"""Attribute of a partial file whose end is being written (noise added in place, end
variables appended): such a file is not continued, the run starts over."""


def partial_path(target: Path) -> Path:
    """The hidden name a streamed file grows under beside ``target``."""
    target = Path(target)
    return target.with_name(f".{target.name}.stream.part")


def stream_wanted(problem: TransientProblem, requested: bool | None = None) -> bool:
    """Whether a run streams: as ``requested``, else the environment variable
    ``PYGEAR_STREAM`` (``1``/``0``), else when its record exceeds
    :data:`STREAM_RECORD_BYTES` or what memory holds twice."""
    if requested is not None:
        return bool(requested)
    forced = os.environ.get("PYGEAR_STREAM", "").strip()
    if forced in ("0", "1"):
        return forced == "1"
    from ..analysis.time.transient_checks import transient_footprint
    from ..resources import available_memory

    memory, _, _ = transient_footprint(problem.settings, len(problem.probes))
    available = available_memory()
    return memory / 2 > STREAM_RECORD_BYTES or (available is not None and memory > available)


def usable_partial(partial: Path, identity: str, written: int) -> str:
    """ "" when ``partial`` can be continued at sample ``written``, else why not."""
    import netCDF4

    if not partial.is_file():
        return f"{partial} is missing"
    try:
        with netCDF4.Dataset(partial, "r") as handle:
            attrs = handle.__dict__
            if attrs.get(IDENTITY) != identity:
                return f"{partial} belongs to another run"
            if int(attrs.get(io.COMPLETE, 1)) != 0:
                return f"{partial} is not a partial file"
            if FINISHING in attrs:  # its noise or end variables may be half written
                return f"{partial} was stopped while its end was written"
            length = len(handle.dimensions["time"])
    except (OSError, KeyError, RuntimeError) as error:
        return f"{partial} cannot be read ({error})"
    if length < written:
        return f"{partial} holds {length} samples, the checkpoint {written}"
    return ""


class StreamedFile:
    """The sample sink of a streamed run: ``<scene>.nc`` grown block by block.

    Parameters
    ----------
    problem : TransientProblem
        The run.
    target : path
        The file's final name.
    title, input_hash, case_json : str
        As :func:`pygear.io.write_netcdf` takes them.
    identity : str
        The run's checkpoint identity (a partial file of another run is not continued).
    buffer_bytes : int
        Memory of one block of samples (default :data:`BUFFER_BYTES`).
    consumers : sequence, optional
        Objects with ``update(first, variables)``, ``state()``, ``restore(state)`` and
        ``variables()`` that see every block of channel variables (the on-the-fly
        reductions of :mod:`pygear.analysis.time.reductions`) and add their results to
        the file at the end.
    """

    def __init__(
        self,
        problem: TransientProblem,
        target: Path,
        *,
        title: str,
        input_hash: str | None = None,
        case_json: str | None = None,
        identity: str = "",
        buffer_bytes: int | None = None,
        consumers=(),
    ) -> None:
        self.problem = problem
        self.target = Path(target)
        self.partial = partial_path(self.target)
        self.title, self.input_hash, self.case_json = title, input_hash, case_json
        self.identity = identity
        channels = max(len(problem.probes), 1)
        buffer_bytes = BUFFER_BYTES if buffer_bytes is None else buffer_bytes
        self.block_samples = int(min(1 << 16, max(1024, buffer_bytes // (8 * channels))))
        self.time_chunk = min(TIME_CHUNK, self.block_samples)
        self.consumers = list(consumers)
        self.length = 0  # samples in the file
        self._pending: list[tuple[int, dict]] = []
        self._pending_samples = 0
        self._created = False
        settings = problem.settings
        self.rate = 1.0 / (settings.decimation * settings.time_step)
        self._filters: list[list] = [[] for _ in problem.sensors]  # (b, a, state) per mode
        self._attrs: dict[int, dict] = {}
        self._squares = np.zeros(len(problem.sensors))
        self._counts = np.zeros(len(problem.sensors), dtype=np.int64)
        self._plan_index = {id(plan): k for k, plan in enumerate(problem.sensors)}

    # --- the sink --------------------------------------------------------------------------

    def write(self, first: int, samples: np.ndarray) -> None:
        """Lay out samples ``first ..`` (probe, sample) as the file holds them and queue
        them; append when a block is full."""
        count = samples.shape[1]
        data_vars, coords = channel_variables(self.problem, samples, sensor=self._sensor)
        columns = {name: np.array(values) for name, (_, values, _) in data_vars.items()}
        columns["time"] = sample_times(self.problem, first, count)
        for consumer in self.consumers:
            consumer.update(first, columns)
        if not self._created:
            self._create(first, data_vars, coords, columns["time"])
            return
        self._pending.append((first, columns))
        self._pending_samples += count
        if self._pending_samples >= self.block_samples:
            self._append(aligned=True)

    def flush(self) -> None:
        """Append every queued sample to the file (before a checkpoint, at the end)."""
        self._append(aligned=False)

    def _append(self, aligned: bool) -> None:
        """Append the queued samples; ``aligned``: only up to the last whole HDF5 chunk
        along time, the rest kept queued (a chunk written in pieces is compressed again
        with every piece)."""
        if not self._pending:
            return
        first = self._pending[0][0]
        names = self._pending[0][1].keys()
        joined = {
            name: np.concatenate([columns[name] for _, columns in self._pending], axis=-1)
            for name in names
        }
        end = first + self._pending_samples
        if aligned:
            end = max(first, end - end % self.time_chunk)
        count = end - first
        if count:
            io.append_streamed(
                self.partial, first, {name: values[..., :count] for name, values in joined.items()}
            )
        self.length = max(self.length, end)
        rest = self._pending_samples - count
        self._pending = (
            [(end, {n: v[..., count:].copy() for n, v in joined.items()})] if rest else []
        )
        self._pending_samples = rest

    def state(self) -> dict:
        """What the sink carries from block to block, as arrays for a checkpoint."""
        state = {"sensor_squares": self._squares.copy(), "sensor_counts": self._counts.copy()}
        for k, filters in enumerate(self._filters):
            for m, (_, _, zi) in enumerate(filters):
                state[f"sensor{k}_mode{m}"] = zi.copy()
        for c, consumer in enumerate(self.consumers):
            for name, value in consumer.state().items():
                state[f"consumer{c}_{name}"] = np.asarray(value)
        return state

    def restore(self, state: dict, written: int) -> None:
        """Continue the partial file at sample ``written`` with the carried ``state``."""
        reason = usable_partial(self.partial, self.identity, written)
        if reason:
            from ..kernel.newmark import TransientError

            raise TransientError(f"resume: the streamed file cannot be continued: {reason}")
        self._created, self.length = True, written
        self._squares = np.array(state["sensor_squares"], dtype=np.float64)
        self._counts = np.array(state["sensor_counts"], dtype=np.int64)
        for k, filters in enumerate(self._filters):
            for m, (b, a, _) in enumerate(filters):
                filters[m] = (b, a, np.array(state[f"sensor{k}_mode{m}"], dtype=np.float64))
        for c, consumer in enumerate(self.consumers):
            prefix = f"consumer{c}_"
            consumer.restore(
                {k.removeprefix(prefix): v for k, v in state.items() if k.startswith(prefix)}
            )

    # --- the end ---------------------------------------------------------------------------

    def finish(self, dataset_tail, attrs: dict) -> Path:
        """Add the end's variables (``dataset_tail``, an ``xarray.Dataset``), the noise of
        noisy sensors and the consumers' results, set ``attrs`` and ``complete = 1``,
        and rename the file to its target."""
        import netCDF4
        import xarray as xr

        self.flush()
        with netCDF4.Dataset(self.partial, "a") as handle:  # from here on not resumable
            handle.setncattr(FINISHING, 1)
        self._add_noise()
        tail = dataset_tail
        for consumer in self.consumers:
            tail = xr.merge([tail, consumer.variables()], combine_attrs="override")
        tail = io._cf_encoded(tail)
        encoding: dict = {name: {"_FillValue": None} for name in tail.coords}
        for name, variable in tail.variables.items():
            if variable.dtype.kind in "OUS":
                encoding.setdefault(name, {}).update({"dtype": "S1", "_FillValue": None})
        with netCDF4.Dataset(self.partial, "a") as handle:
            for name in (IDENTITY, FINISHING):
                if name in handle.ncattrs():
                    handle.delncattr(name)
        return io.finish_streamed(self.partial, self.target, tail, attrs, encoding)

    def discard(self) -> None:
        """Remove the partial file (a run that failed without a checkpoint to resume)."""
        with contextlib.suppress(FileNotFoundError):
            self.partial.unlink()

    # --- inside ----------------------------------------------------------------------------

    def _create(self, first: int, data_vars: dict, coords: dict, times: np.ndarray) -> None:
        import xarray as xr

        if first != 0:
            raise RuntimeError("a streamed file starts at sample 0")
        coords = dict(coords)
        coords["time"] = time_coordinate(times)
        attrs = static_attributes(self.problem)
        dataset = xr.Dataset(data_vars, coords, attrs)
        dataset, encoding = io.netcdf_layout(
            dataset, title=self.title, input_hash=self.input_hash, case_json=self.case_json
        )
        dataset.attrs[IDENTITY] = self.identity
        with contextlib.suppress(FileNotFoundError):
            self.partial.unlink()
        self.partial.parent.mkdir(parents=True, exist_ok=True)
        io.create_streamed(self.partial, dataset, encoding, self.time_chunk)
        self._created, self.length = True, len(times)

    def _sensor(self, plan, channels: dict):
        """A sensor's values over one block: the flat path, plus each structural mode's
        response with its filter state carried, noise added at the end."""
        from scipy.signal import lfilter

        from ..analysis.condition.sensor_signal import _mode_coefficients, sensor_signal

        k = self._plan_index[id(plan)]
        if k not in self._attrs:  # the first block: the sensor's checks and attributes
            _, self._attrs[k] = sensor_signal(
                plan, {n: v[:1] for n, v in channels.items()}, self.rate
            )
            if not self._filters[k]:
                for mode in plan.sensor.structure:
                    b, a = _mode_coefficients(mode, self.rate)
                    self._filters[k].append((b, a, np.zeros(max(len(a), len(b)) - 1)))
        quiet = dataclasses.replace(
            plan, sensor=dataclasses.replace(plan.sensor, structure=(), noise_snr_db=None)
        )
        flat, _ = sensor_signal(quiet, channels, self.rate)
        response = np.array(flat, dtype=np.float64)
        for m, (b, a, zi) in enumerate(self._filters[k]):
            out, zf = lfilter(b, a, flat, zi=zi)
            response += out
            self._filters[k][m] = (b, a, zf)
        self._squares[k] += float(np.sum(np.square(response)))
        self._counts[k] += response.size
        return response, self._attrs[k]

    def _add_noise(self) -> None:
        """Each noisy sensor's white noise over the whole file, block by block, with the
        power of the whole record (:func:`pygear.analysis.condition.sensor_signal.add_noise`)."""
        import netCDF4

        sensors = enumerate(self.problem.sensors)
        noisy = [(k, plan) for k, plan in sensors if plan.sensor.noise_snr_db is not None]
        if not noisy:
            return
        with netCDF4.Dataset(self.partial, "a") as handle:
            handle.set_auto_mask(False)
            labels = _labels(handle, "sensor")
            for k, plan in noisy:
                power = self._squares[k] / max(int(self._counts[k]), 1)
                deviation = math.sqrt(power / 10 ** (plan.sensor.noise_snr_db / 10))
                generator = np.random.default_rng(int(plan.sensor.noise_seed))
                if plan.named:
                    variable, row = handle[plan.variable], None
                else:
                    variable, row = handle["sensor_acceleration"], labels.index(plan.sensor.name)
                total = len(handle.dimensions["time"])
                for start in range(0, total, self.block_samples):
                    stop = min(total, start + self.block_samples)
                    if row is None:
                        values = variable[start:stop]
                        variable[start:stop] = values + generator.normal(
                            0.0, deviation, size=stop - start
                        )
                    else:
                        values = variable[row, start:stop]
                        variable[row, start:stop] = values + generator.normal(
                            0.0, deviation, size=stop - start
                        )


def _labels(handle, dimension: str) -> list[str]:
    """The text labels of ``dimension`` in an open netCDF4 file (``<dim>_label``)."""
    name = f"{dimension}{io.LABEL_SUFFIX}"
    if name not in handle.variables:
        return []
    import netCDF4

    values = handle[name][:]
    return (
        [str(v) for v in netCDF4.chartostring(values)]
        if values.dtype.kind == "S"
        else list(map(str, values))
    )
