"""Rolling bearings in the kernel: what the nonlinear planet bearings cost a run-up.

``python benchmarks/bench_bearing.py`` runs the NREL 5 MW gearbox's ``runup`` scene (the
rotor's run-up under the rated torque, time-varying mesh stiffness) three ways and
reports medians of repeats:

* ``linear``: the scene as the case file gives it, planet bearings as linear springs;
* ``bearings``: the same run with the ``rolling_bearing_contact`` effect, every planet
  bearing of both planetary stages (4 bearings x 3 planets) a Hertz contact with
  clearance in the scene's equivalent-load mode;
* ``linear_iterate``, ``bearings_iterate``: both with the equivalent load iterated to
  convergence every step (the meshes' too).

The ratios bearings / linear at the same mode are the claim (the target: under 3).  Both runs do the
same steps on the same factorization; the difference is the bearings' element sums
(24 or 28 rollers each) and, with ``iterate``, the iterations they need.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from timing import median_seconds  # noqa: E402

from pygear import load_case  # noqa: E402
from pygear.analysis.time.transient import run_transient, transient_problem  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--duration", type=float, default=0.5, help="run-up length [s]")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    case = load_case("nrel5mw_gearbox")
    scene = case.scene("runup")
    settings = dataclasses.replace(
        scene.transient, duration=args.duration, mean_window=min(0.5, args.duration)
    )
    linear = dataclasses.replace(scene, transient=settings)
    bearings = dataclasses.replace(linear, effects=(*linear.effects, "rolling_bearing_contact"))
    iterated = dataclasses.replace(settings, equivalent_load="iterate")
    linear_iterate = dataclasses.replace(linear, transient=iterated)
    iterate = dataclasses.replace(bearings, transient=iterated)
    times = {}
    runs = (
        ("linear", linear),
        ("bearings", bearings),
        ("linear_iterate", linear_iterate),
        ("bearings_iterate", iterate),
    )
    for name, chosen in runs:
        problem = transient_problem(case, chosen)  # the set-up is not what is compared
        times[name] = median_seconds(
            lambda p=problem, s=chosen: run_transient(case, s, problem=p),
            args.repeats,
            warm_up=True,
        )
        print(f"{name:18s} {times[name]:8.2f} s (median of {args.repeats})")
    print(f"bearings / linear (predictor): {times['bearings'] / times['linear']:.2f}")
    iterate_ratio = times["bearings_iterate"] / times["linear_iterate"]
    print(f"bearings / linear (iterate):   {iterate_ratio:.2f}")


if __name__ == "__main__":
    main()
