"""On-the-fly reductions of a streamed run (issue #32.2), block by block with carried state.

A scene's :class:`pygear.model.reduction_settings.Reductions` asks for them;
:func:`scene_reductions` turns it into a consumer of the blocks a streamed run
(:mod:`pygear.runs.streaming`) writes, which adds its results to the file at the end.
Each piece gives what the whole record would give:

* :class:`Decimator`: a linear-phase FIR low-pass (Kaiser window) evaluated at every
  D-th sample, the last ``taps - 1`` samples carried: the same sums as filtering the
  whole record (zero before the start and after the end) and keeping every D-th.
* :class:`RunningStatistics`: minimum, maximum, sum and sum of squares.
* :class:`StreamingRainflow`: the reversals and the ASTM E1049 stack of the ``rainflow``
  package (``rainflow.extract_cycles``), the stack (the residue) and the last point
  carried from block to block; the residue's half cycles are counted at the end.  The
  cycles are those of ``rainflow.extract_cycles`` on the whole record, in the same order.
* :class:`Pow2Histogram`: histograms (rainflow range x mean, load duration) whose bin
  width is a power of two (in the channel's unit), the smallest that fits the data's
  extent into ``bins`` bins, with edges at multiples of it.  Coarsening merges bins
  exactly (floor(floor(x / w) / 2) = floor(x / 2w)), so the matrix of a record counted
  in blocks is the one of the whole record, whatever the blocks.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import CaseError

__all__ = [
    "Decimator",
    "Pow2Histogram",
    "ReductionConsumer",
    "RunningStatistics",
    "StreamingRainflow",
    "decimation_factor",
    "lowpass_taps",
    "scene_reductions",
]

STATISTICS = ("minimum", "maximum", "mean", "rms")
"""The running statistics of every channel, in the order of the ``statistic`` axis."""

_START_EXPONENT = -100
"""log2 of the finest bin width; the data coarsen it (2^-100: below any channel's ulp)."""


_RESOLUTION_BITS = 36
"""The finest bin is 2^-36 of the largest magnitude counted (16 bits above a double's ulp)."""


def decimation_factor(sample_rate: float, keep_frequency: float) -> int:
    """The largest D whose rate sample_rate / D is at least 2.5 keep_frequency: the band
    up to keep_frequency kept, a transition band to sample_rate / D - keep_frequency, what
    lies beyond it (which would alias into the kept band) stopped."""
    return max(1, int(math.floor(sample_rate / (2.5 * keep_frequency) * (1 + 1e-12))))


def lowpass_taps(factor: int, sample_rate: float, keep_frequency: float, stop_db: float):
    """Kaiser-window low-pass taps (odd count, linear phase) for decimation by ``factor``:
    pass band to ``keep_frequency`` (ripple 10^(-stop_db/20), far below 0.1 dB), stop band
    from ``sample_rate / factor - keep_frequency`` (attenuation ``stop_db``)."""
    from scipy.signal import firwin, kaiserord

    if factor == 1:
        return np.ones(1)
    new_rate = sample_rate / factor
    stop = new_rate - keep_frequency
    width = (stop - keep_frequency) / (sample_rate / 2)
    taps, beta = kaiserord(stop_db, width)
    taps += 1 - taps % 2  # odd: a whole-sample delay
    cutoff = 0.5 * (keep_frequency + stop)
    return firwin(taps, cutoff, window=("kaiser", beta), fs=sample_rate)


class Decimator:
    """Low-pass and keep every ``factor``-th sample of rows streamed in blocks.

    Output m is y(m factor) with y = h * x centred (delay (taps - 1) / 2 removed) and x
    zero outside the record, so the decimated channel has no delay and its times are
    m factor / sample_rate; :meth:`finish` gives the last outputs once the record ends.
    """

    def __init__(self, taps: np.ndarray, factor: int, rows: int) -> None:
        self.taps = np.asarray(taps, dtype=np.float64)
        self.factor = int(factor)
        self.delay = (len(self.taps) - 1) // 2
        self.tail = np.zeros((rows, len(self.taps) - 1))  # x before the block
        self.received = 0  # samples of x seen
        self.emitted = 0  # outputs given

    def update(self, block: np.ndarray) -> np.ndarray:
        """The outputs whose inputs ``block`` (rows, samples) completes."""
        block = np.asarray(block, dtype=np.float64).reshape(self.tail.shape[0], -1)
        joined = np.concatenate([self.tail, block], axis=1)
        self.received += block.shape[1]
        out = self._outputs(joined, self.received)
        self.tail = joined[:, joined.shape[1] - self.tail.shape[1] :]
        return out

    def finish(self) -> np.ndarray:
        """The last outputs (x zero past the record's end)."""
        total = self.received
        joined = np.concatenate([self.tail, np.zeros((self.tail.shape[0], self.delay))], axis=1)
        return self._outputs(joined, total + self.delay, last=(total - 1) // self.factor)

    def _outputs(self, joined: np.ndarray, end: int, last: int | None = None) -> np.ndarray:
        # joined holds x[end - joined.shape[1] .. end - 1]; output m needs x up to
        # m factor + delay
        n = len(self.taps)
        first_m = self.emitted
        last_m = (end - 1 - self.delay) // self.factor
        if last is not None:
            last_m = min(last_m, last)
        if last_m < first_m:
            return np.zeros((joined.shape[0], 0))
        start = end - joined.shape[1]
        ends = np.arange(first_m, last_m + 1) * self.factor + self.delay  # newest input
        windows = np.lib.stride_tricks.sliding_window_view(joined, n, axis=1)
        out = windows[:, ends - (n - 1) - start, :] @ self.taps[::-1]
        self.emitted = last_m + 1
        return out

    def state(self) -> dict:
        return {"tail": self.tail, "counters": np.array([self.received, self.emitted])}

    def restore(self, state: dict) -> None:
        self.tail = np.array(state["tail"], dtype=np.float64)
        self.received, self.emitted = (int(v) for v in state["counters"])


class RunningStatistics:
    """Minimum, maximum, mean and RMS of rows streamed in blocks."""

    def __init__(self, rows: int) -> None:
        self.values = np.array([[math.inf, -math.inf, 0.0, 0.0]] * rows).reshape(rows, 4)
        self.count = 0

    def update(self, block: np.ndarray) -> None:
        block = np.asarray(block, dtype=np.float64).reshape(self.values.shape[0], -1)
        if block.shape[1] == 0:
            return
        self.values[:, 0] = np.minimum(self.values[:, 0], block.min(axis=1))
        self.values[:, 1] = np.maximum(self.values[:, 1], block.max(axis=1))
        self.values[:, 2] += block.sum(axis=1)
        self.values[:, 3] += np.square(block).sum(axis=1)
        self.count += block.shape[1]

    def result(self) -> np.ndarray:
        """(rows, 4): minimum, maximum, mean, RMS (NaN for a row of NaN)."""
        out = self.values.copy()
        count = max(self.count, 1)
        out[:, 2] /= count
        out[:, 3] = np.sqrt(out[:, 3] / count)
        return out

    def state(self) -> dict:
        return {"values": self.values, "count": np.array(self.count)}

    def restore(self, state: dict) -> None:
        self.values = np.array(state["values"], dtype=np.float64)
        self.count = int(state["count"])


class StreamingRainflow:
    """Rainflow counting (ASTM E1049, as ``rainflow.extract_cycles``) of one channel
    streamed in blocks: the last distinct value, the last slope and the stack of
    reversals not yet closed (the residue) are carried."""

    def __init__(self) -> None:
        self.started = False
        self.last = 0.0
        self.slope = 0.0
        self.stack: list[float] = []

    def update(self, block: np.ndarray) -> np.ndarray:
        """Cycles (range, mean, count) closed by ``block``, shape (n, 3)."""
        x = np.asarray(block, dtype=np.float64).ravel()
        if x.size == 0:
            return np.zeros((0, 3))
        if not self.started:  # the record's first point is its first reversal
            self.started = True
            self.last, self.slope = float(x[0]), 0.0
            self.stack = [float(x[0])]
            x = x[1:]
        u = np.concatenate([[self.last], x])
        u = u[np.concatenate([[True], np.diff(u) != 0])]  # plateaus: their first point
        if u.size < 2:
            return np.zeros((0, 3))
        d = np.diff(u)
        before = np.concatenate([[self.slope], d[:-1]])
        reversals = u[:-1][before * d < 0]
        self.last, self.slope = float(u[-1]), float(d[-1])
        return self._push(reversals)

    def finish(self) -> np.ndarray:
        """The cycles the record's last point closes, and the residue as half cycles."""
        if not self.started:
            return np.zeros((0, 3))
        cycles = self._push(np.array([self.last]))
        stack = self.stack
        half = [(abs(a - b), 0.5 * (a + b), 0.5) for a, b in zip(stack[:-1], stack[1:])]
        self.stack = stack[-1:]
        return np.concatenate([cycles, np.array(half).reshape(-1, 3)])

    def _push(self, reversals: np.ndarray) -> np.ndarray:
        stack = self.stack
        out = []
        for point in reversals.tolist():
            stack.append(point)
            while len(stack) >= 3:
                x1, x2, x3 = stack[-3], stack[-2], stack[-1]
                if abs(x3 - x2) < abs(x2 - x1):
                    break
                if len(stack) == 3:  # the range holds the start: half a cycle
                    out.append((abs(x1 - x2), 0.5 * (x1 + x2), 0.5))
                    stack.pop(0)
                else:
                    out.append((abs(x1 - x2), 0.5 * (x1 + x2), 1.0))
                    del stack[-3:-1]
        return np.array(out, dtype=np.float64).reshape(-1, 3)

    def state(self) -> dict:
        return {
            "scalars": np.array([float(self.started), self.last, self.slope]),
            "stack": np.array(self.stack, dtype=np.float64),
        }

    def restore(self, state: dict) -> None:
        started, self.last, self.slope = (float(v) for v in state["scalars"])
        self.started = bool(started)
        self.stack = [float(v) for v in np.atleast_1d(state["stack"])]


class Pow2Histogram:
    """A histogram over ``axes`` dimensions, ``bins`` bins each, of weighted points
    streamed in blocks; bin widths 2^e (per axis) grow with the data's extent.

    Bin k of an axis covers [(first + k) 2^e, (first + k + 1) 2^e).  The counts are
    kept sparse (a bin per occupied index), so memory is the occupied bins.
    """

    def __init__(self, axes: int, bins: int, weights: int = 1) -> None:
        self.axes, self.bins, self.weights = axes, bins, weights
        self.exponent = np.full(axes, _START_EXPONENT, dtype=np.int64)
        self.low = np.full(axes, math.inf)
        self.high = np.full(axes, -math.inf)
        self.keys = np.zeros((0, axes))
        self.sums = np.zeros((0, weights))

    def update(self, points: np.ndarray, weights: np.ndarray) -> None:
        points = np.asarray(points, dtype=np.float64).reshape(-1, self.axes)
        weights = np.asarray(weights, dtype=np.float64).reshape(len(points), self.weights)
        finite = np.all(np.isfinite(points), axis=1)
        points, weights = points[finite], weights[finite]
        if not len(points):
            return
        # a bin at least 2^-RESOLUTION_BITS of the largest magnitude wide: its edges
        # stay distinct floats (a constant channel fills one bin, not a zero-width one)
        magnitude = np.abs(points).max(axis=0)
        finest = np.where(
            magnitude > 0,
            np.floor(np.log2(np.where(magnitude > 0, magnitude, 1.0))) - _RESOLUTION_BITS,
            _START_EXPONENT,
        ).astype(np.int64)
        shift = np.maximum(finest - self.exponent, 0)
        if shift.any():
            self.low = np.where(
                np.isfinite(self.low), np.floor(np.ldexp(self.low, -shift)), self.low
            )
            self.high = np.where(
                np.isfinite(self.high), np.floor(np.ldexp(self.high, -shift)), self.high
            )
            self.keys = np.floor(np.ldexp(self.keys, -shift))
            self.exponent += shift
        index = np.floor(np.ldexp(points, -self.exponent))
        self.low = np.minimum(self.low, index.min(axis=0))
        self.high = np.maximum(self.high, index.max(axis=0))
        shift = np.zeros(self.axes, dtype=np.int64)
        while True:
            wide = self.high - self.low + 1 > self.bins
            if not wide.any():
                break
            shift += wide
            self.low = np.where(wide, np.floor(self.low / 2), self.low)
            self.high = np.where(wide, np.floor(self.high / 2), self.high)
        if shift.any():
            self.exponent += shift
            index = np.floor(np.ldexp(index, -shift))
            self.keys = np.floor(np.ldexp(self.keys, -shift))
        keys = np.concatenate([self.keys, index])
        sums = np.concatenate([self.sums, weights])
        self.keys, inverse = np.unique(keys, axis=0, return_inverse=True)
        inverse = inverse.reshape(-1)
        self.sums = np.stack(
            [
                np.bincount(inverse, sums[:, w], minlength=len(self.keys))
                for w in range(self.weights)
            ],
            axis=1,
        )

    def result(self) -> tuple[np.ndarray, np.ndarray]:
        """Counts (bins,) * axes + (weights,) and edges (axes, bins + 1)."""
        low = np.where(np.isfinite(self.low), self.low, 0.0)
        counts = np.zeros((self.bins,) * self.axes + (self.weights,))
        if len(self.keys):
            where = tuple((self.keys - low).astype(np.int64).T)
            counts[where] = self.sums
        edges = np.ldexp(low[:, None] + np.arange(self.bins + 1), self.exponent[:, None])
        return counts, edges

    def state(self) -> dict:
        return {
            "exponent": self.exponent,
            "extent": np.stack([self.low, self.high]),
            "keys": self.keys,
            "sums": self.sums,
        }

    def restore(self, state: dict) -> None:
        self.exponent = np.array(state["exponent"], dtype=np.int64)
        self.low, self.high = (np.array(v, dtype=np.float64) for v in state["extent"])
        self.keys = np.array(state["keys"], dtype=np.float64).reshape(-1, self.axes)
        self.sums = np.array(state["sums"], dtype=np.float64).reshape(-1, self.weights)


def scene_reductions(problem) -> list:
    """The reductions the scene asks for, as consumers of a run's blocks (none without
    ``Transient.reductions``).

    Raises
    ------
    CaseError
        A variable to reduce that the run does not record.
    """
    reductions = getattr(problem.settings, "reductions", None)
    if reductions is None or not reductions.any:
        return []
    return [ReductionConsumer(problem, reductions)]


class ReductionConsumer:
    """Every reduction of one run: fed each block of its variables (as the file holds
    them: ``{name: values}``, time last) by :meth:`update`, its results as a dataset
    by :meth:`variables`.  A noisy sensor's channel is left out (its noise is added
    after the run, from the whole record's power)."""

    def __init__(self, problem, reductions) -> None:
        from .run_dataset import channel_variables

        settings = problem.settings
        path = f"scenes.{problem.scene.name}.transient.reductions"
        self.reductions = reductions
        self.interval = settings.decimation * settings.time_step
        self.rate = 1.0 / self.interval
        data_vars, coords = channel_variables(problem, np.zeros((max(len(problem.probes), 1), 1)))
        noisy = any(plan.sensor.noise_snr_db is not None for plan in problem.sensors)
        self.layout = {
            name: (dims, attrs, list(coords[dims[0]][1]) if len(dims) == 2 else None)
            for name, (dims, _, attrs) in data_vars.items()
            if not (noisy and attrs.get("quantity") == "sensor")
        }

        def rows(name: str) -> int:
            labels = self.layout[name][2]
            return 1 if labels is None else len(labels)

        def known(name: str, what: str) -> None:
            if name not in self.layout:
                raise CaseError(
                    f"{path}.{what}: the run records no variable {name!r} "
                    f"(variables over time: {', '.join(self.layout) or 'none'})"
                )

        self.decimators: dict[str, Decimator] = {}
        self.decimated: dict[str, list] = {}
        if reductions.keep_frequency is not None:
            self.factor = decimation_factor(self.rate, reductions.keep_frequency)
            self.taps = lowpass_taps(
                self.factor, self.rate, reductions.keep_frequency, reductions.stopband_db
            )
            for name in reductions.decimate or tuple(self.layout):
                known(name, "decimate")
                self.decimators[name] = Decimator(self.taps, self.factor, rows(name))
                self.decimated[name] = []
        self.statistics = (
            {name: RunningStatistics(rows(name)) for name in self.layout}
            if reductions.statistics
            else {}
        )
        self.rainflow: dict[str, list] = {}
        for name in reductions.rainflow:
            known(name, "rainflow")
            self.rainflow[name] = [
                (StreamingRainflow(), Pow2Histogram(2, reductions.bins)) for _ in range(rows(name))
            ]
        self.load_duration: dict[str, tuple] = {}
        for torque in reductions.load_duration:
            known(torque, "load_duration")
            member = problem.input_label if torque == "drive_torque" else problem.output_label
            member = member.removesuffix(".theta_z")
            speeds = self.layout.get("speed", (None, None, []))[2] or []
            if member not in speeds:
                raise CaseError(
                    f"{path}.load_duration: revolutions at {torque} need the speed of "
                    f"{member!r}: add Probe('speed', {member!r}) to the probes"
                )
            histogram = Pow2Histogram(1, reductions.bins, weights=2)
            self.load_duration[torque] = (speeds.index(member), histogram)

    def update(self, first: int, columns: dict) -> None:
        """Take samples ``first ..`` of every variable."""
        for name, decimator in self.decimators.items():
            self.decimated[name].append(decimator.update(_rows(columns[name])))
        for name, statistics in self.statistics.items():
            statistics.update(_rows(columns[name]))
        for name, channels in self.rainflow.items():
            for values, (counter, histogram) in zip(_rows(columns[name]), channels):
                cycles = counter.update(values)
                histogram.update(cycles[:, :2], cycles[:, 2])
        for torque, (row, histogram) in self.load_duration.items():
            speed = np.abs(_rows(columns["speed"])[row])
            weights = np.stack([np.full(speed.shape, self.interval), speed * self.interval / 60])
            histogram.update(_rows(columns[torque])[0], weights.T)

    def variables(self):
        """The results as an ``xarray.Dataset`` (the residues counted, the filters run
        to the record's end)."""
        import xarray as xr

        data_vars, coords = {}, {}
        for name, decimator in self.decimators.items():
            values = np.concatenate([*self.decimated[name], decimator.finish()], axis=1)
            dims, attrs, _ = self.layout[name]
            attrs = {
                **attrs,
                "long_name": f"{attrs.get('long_name', name)}, low-pass filtered and decimated",
                "decimation_factor": self.factor,
                "keep_frequency": self.reductions.keep_frequency,
                "stopband_db": self.reductions.stopband_db,
                "filter_taps": len(self.taps),
            }
            decimated_dims = (*dims[:-1], "time_decimated")
            data_vars[f"{name}_decimated"] = (decimated_dims, _shaped(values, dims), attrs)
            count = values.shape[1]
            coords["time_decimated"] = (
                "time_decimated",
                np.arange(count) * self.factor * self.interval,
                {"units": "s", "long_name": "time of the decimated channels"},
            )
        if self.statistics:
            coords["statistic"] = ("statistic", np.array(STATISTICS, dtype=object), {})
        for name, statistics in self.statistics.items():
            dims, attrs, _ = self.layout[name]
            data_vars[f"{name}_statistics"] = (
                (*dims[:-1], "statistic"),
                _shaped(statistics.result(), dims),
                {"units": attrs.get("units", "1"), "long_name": f"statistics of {name}"},
            )
        for name, channels in self.rainflow.items():
            dims, attrs, _ = self.layout[name]
            counts, range_edges, mean_edges = [], [], []
            for counter, histogram in channels:
                cycles = counter.finish()
                histogram.update(cycles[:, :2], cycles[:, 2])
                matrix, edges = histogram.result()
                counts.append(matrix[..., 0])
                range_edges.append(edges[0])
                mean_edges.append(edges[1])
            label = dims[:-1]
            units = attrs.get("units", "1")
            data_vars[f"rainflow_{name}"] = (
                (*label, "rainflow_range", "rainflow_mean"),
                np.array(counts).reshape((-1,) * len(label) + counts[0].shape),
                {
                    "units": "1",
                    "long_name": f"rainflow cycles of {name} by range and mean (ASTM E1049; "
                    "residue as half cycles)",
                },
            )
            for axis, edges in (("range", range_edges), ("mean", mean_edges)):
                data_vars[f"rainflow_{name}_{axis}_edges"] = (
                    (*label, f"rainflow_{axis}_edge"),
                    np.array(edges).reshape((-1,) * len(label) + edges[0].shape),
                    {"units": units, "long_name": f"edges of the cycle {axis} bins of {name}"},
                )
        if self.load_duration:
            torques = list(self.load_duration)
            results = [histogram.result() for _, histogram in self.load_duration.values()]
            coords["torque"] = ("torque", np.array(torques, dtype=object), {})
            data_vars["load_duration_time"] = (
                ("torque", "load_level"),
                np.array([counts[:, 0] for counts, _ in results]),
                {"units": "s", "long_name": "time at each torque level"},
            )
            data_vars["load_duration_revolutions"] = (
                ("torque", "load_level"),
                np.array([counts[:, 1] for counts, _ in results]),
                {"units": "1", "long_name": "revolutions of the torque's member at each level"},
            )
            data_vars["load_duration_edges"] = (
                ("torque", "load_level_edge"),
                np.array([edges[0] for _, edges in results]),
                {"units": "N m", "long_name": "edges of the torque levels"},
            )
        return xr.Dataset(data_vars, coords)

    def state(self) -> dict:
        """Everything carried, as arrays for a checkpoint."""
        state = {}
        for name, decimator in self.decimators.items():
            for key, value in decimator.state().items():
                state[f"decimate.{name}.{key}"] = value
            done = [np.zeros((decimator.tail.shape[0], 0))] + self.decimated[name]
            state[f"decimate.{name}.out"] = np.concatenate(done, axis=1)
        for name, statistics in self.statistics.items():
            for key, value in statistics.state().items():
                state[f"statistics.{name}.{key}"] = value
        for name, channels in self.rainflow.items():
            for k, (counter, histogram) in enumerate(channels):
                for part, item in (("counter", counter), ("histogram", histogram)):
                    for key, value in item.state().items():
                        state[f"rainflow.{name}.{k}.{part}.{key}"] = value
        for torque, (_, histogram) in self.load_duration.items():
            for key, value in histogram.state().items():
                state[f"load.{torque}.{key}"] = value
        return state

    def restore(self, state: dict) -> None:
        """Take back what :meth:`state` gave."""

        def part(prefix: str) -> dict:
            return {k.removeprefix(prefix): v for k, v in state.items() if k.startswith(prefix)}

        for name, decimator in self.decimators.items():
            saved = part(f"decimate.{name}.")
            decimator.restore(saved)
            self.decimated[name] = [np.array(saved["out"], dtype=np.float64)]
        for name, statistics in self.statistics.items():
            statistics.restore(part(f"statistics.{name}."))
        for name, channels in self.rainflow.items():
            for k, (counter, histogram) in enumerate(channels):
                counter.restore(part(f"rainflow.{name}.{k}.counter."))
                histogram.restore(part(f"rainflow.{name}.{k}.histogram."))
        for torque, (_, histogram) in self.load_duration.items():
            histogram.restore(part(f"load.{torque}."))


def _rows(values: np.ndarray) -> np.ndarray:
    """A variable's block as (rows, samples)."""
    values = np.asarray(values, dtype=np.float64)
    return values.reshape(1, -1) if values.ndim == 1 else values


def _shaped(values: np.ndarray, dims: tuple) -> np.ndarray:
    """(rows, n) results back to the variable's shape: one row of a (time,) variable
    as (n,)."""
    return values[0] if len(dims) == 1 else values
