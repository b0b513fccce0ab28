"""Rating a gearbox from a duty-cycle run against the run itself.

The NREL 5 MW gearbox runs loaded at its rated point (12.1 rpm, rated torque, the
run-up scene's settings: 20 kHz, five mesh-force probes) for T seconds, streamed with
rainflow matrices of the mesh forces and the drive torque's load duration.  Then the
rating of that file is timed the two ways ``pygear rate --duty-cycle RUN.nc`` takes
it: from the whole mesh-force record (rainflow counted again, then every occupied
peak level of every mesh rated) and from the streamed matrices alone (read as
written).  The run's cost grows with T; the rating's is a fixed part (one ISO rating
per occupied peak level: at most 64 x 64 per mesh) plus the counting, linear in T.
Two lengths give both slopes, and the ratio at 600 s follows from them (a 600 s run
takes over an hour on this machine, so it is extrapolated, not run).  The K_v of the
dynamic model (``--dynamic-factor model``, the default) is one harmonic balance at the
rated speed, a fixed cost, timed apart.

``python benchmarks/bench_rating_run.py [T1 T2]`` prints medians of repeats.
"""

from __future__ import annotations

import dataclasses
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from timing import median_seconds  # noqa: E402

from pygear.analysis.rating.duty_files import duty_from_dataset  # noqa: E402
from pygear.analysis.rating.gearbox_rating import (  # noqa: E402
    model_dynamic_factors,
    rate_gearbox,
)
from pygear.io import open_dataset  # noqa: E402
from pygear.model.case import load_case  # noqa: E402
from pygear.model.rating import load_rating  # noqa: E402
from pygear.model.reduction_settings import Reductions  # noqa: E402
from pygear.runs.transient_outputs import write_transient  # noqa: E402

RUN_REPEATS = 3
RATE_REPEATS = 5


def _scene(case, duration: float):
    scene = case.scene("runup")
    reductions = Reductions(rainflow=("mesh_force",), load_duration=("drive_torque",))
    settings = dataclasses.replace(scene.transient, duration=duration,
                                   mean_window=duration / 2, initial_speed_rpm=12.1,
                                   speed_reference_rpm=12.1, start_loaded=True,
                                   reductions=reductions)
    return dataclasses.replace(scene, transient=settings, analyses=("transient",))


def _rate(case, rating, data) -> None:
    found = duty_from_dataset(data, "run.nc")
    rate_gearbox(case, rating, matrices=found.matrices, record_s=found.record_s,
                 record_speed_rpm=found.speed_rpm)


def measure(duration: float, folder: Path) -> tuple[float, float, float]:
    """(run, rating from the record, rating from the matrices) [s] for one length."""
    case = load_case("nrel5mw_gearbox")
    _, rating = load_rating("nrel5mw_gearbox")
    scene = _scene(case, duration)
    runs = []
    for k in range(RUN_REPEATS):
        start = time.perf_counter()
        write_transient(case, scene, folder / f"{duration}_{k}", figure=False, stream=True)
        runs.append(time.perf_counter() - start)
    runs.sort()
    with open_dataset(folder / f"{duration}_0" / "runup.nc") as ds:
        data = ds.load()
    matrices = data.drop_vars("mesh_force")
    whole = median_seconds(lambda: _rate(case, rating, data), RATE_REPEATS, warm_up=True)
    streamed = median_seconds(lambda: _rate(case, rating, matrices), RATE_REPEATS,
                              warm_up=True)
    return runs[len(runs) // 2], whole, streamed


def main() -> None:
    lengths = [float(v) for v in sys.argv[1:3]] or [0.5, 1.0]
    with tempfile.TemporaryDirectory() as tmp:
        rows = [(t, *measure(t, Path(tmp))) for t in lengths]
    case, rating = load_rating("nrel5mw_gearbox")
    response = median_seconds(lambda: model_dynamic_factors(case, rating), 3)
    print(f"{'T [s]':>6} {'run [s]':>9} {'rate record [s]':>16} {'rate matrices [s]':>18}")
    for t, run, whole, streamed in rows:
        print(f"{t:6.2f} {run:9.2f} {whole:16.3f} {streamed:18.3f}")
    (t1, r1, w1, _), (t2, r2, w2, s2) = rows[0], rows[-1]
    run_rate = (r2 - r1) / (t2 - t1)  # s of run per s of record
    count_rate = max((w2 - w1) / (t2 - t1), 0.0)
    fixed = w1 - count_rate * t1
    run_600 = r1 + run_rate * (600.0 - t1)
    rate_600 = fixed + count_rate * 600.0
    print(f"K_v by the dynamic model (one balance at the rated speed): {response:.2f} s")
    print(f"run: {run_rate:.2f} s per second of record; rating from the record: "
          f"{fixed:.3f} s + {count_rate:.3f} s per second of record")
    print(f"extrapolated to 600 s: run {run_600:.0f} s, rating from the record "
          f"{rate_600:.1f} s (+ {response:.1f} s for K_v), from the matrices "
          f"{s2:.3f} s: rating / run = {(rate_600 + response) / run_600:.4f}")


if __name__ == "__main__":
    main()
