"""Speed-dependent modes of a rotor of about 1200 DOFs: the sparse shift-invert solver
against the dense state space, and against ROSS when it is importable.

The rotor is Friswell et al.'s Example 5.9.1 (cases/friswell_rotor) with
``elements_per_section`` Timoshenko elements in each of its three sections: 66 elements
per section give 199 nodes, 1194 DOFs.  Per speed (0 and 4000 rpm), in this process:

* ``sparse``: :func:`pygear.analysis.modes.sparse_gyroscopic.solve` with 12 modes
  (one splu of sigma^2 M + sigma D + K, ARPACK on the first-order operator);
* ``dense``: the same call with ``solver="dense"`` (the state space of 2388 rows);
* ``ross``: ``rs.Rotor(...).run_modal(speed, num_modes=24)`` on the same rotor (ROSS
  2.3: six DOFs per node, the same 1194), when ``--ross-python`` imports ross; after
  one warm-up call, each repeat at a speed 1e-9 rad/s apart (ROSS caches per speed).

Medians of repeats (benchmarks/timing.py); the largest relative difference of the 12
eigenvalues between the sparse and the dense solver is printed beside the times.

Run: ``.venv/bin/python benchmarks/bench_rotor.py [--elements 66] [--repeats 3]``;
with ROSS in another environment, ``--ross-python PATH`` runs its part there.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
from functools import partial
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from timing import median_seconds, run_peer  # noqa: E402

from pygear.analysis.modes.sparse_gyroscopic import solve  # noqa: E402
from pygear.assembly.drivetrain import assemble_drivetrain  # noqa: E402
from pygear.model.case import load_case  # noqa: E402

ROSS_SCRIPT = """
import json, sys, time
import numpy as np
import ross as rs
elements, speeds, repeats = int(sys.argv[1]), json.loads(sys.argv[2]), int(sys.argv[3])
steel = rs.Material(name="friswell_steel", rho=7810, E=211e9, G_s=81.2e9)
n = 3 * elements
shaft = [rs.ShaftElement(L=1.5 / n, idl=0, odl=0.05, material=steel, n=i) for i in range(n)]
disks = [
    rs.DiskElement.from_geometry(n=elements, material=steel, width=0.07, i_d=0.05, o_d=0.28),
    rs.DiskElement.from_geometry(n=2 * elements, material=steel, width=0.07, i_d=0.05, o_d=0.35),
]
bearings = [rs.BearingElement(n=0, kxx=1e6, cxx=0), rs.BearingElement(n=n, kxx=1e6, cxx=0)]
rotor = rs.Rotor(shaft, disks, bearings)
out = {}
rotor.run_modal(1.0, num_modes=24)  # warm-up: ROSS's first call compiles and caches
for speed in speeds:
    times = []
    for r in range(repeats):
        # run_modal caches its result per speed: a new speed (1e-9 rad/s apart) each time
        start = time.perf_counter()
        modal = rotor.run_modal(speed * np.pi / 30 + 1e-9 * (r + 1), num_modes=24)
        times.append(time.perf_counter() - start)
    out[str(speed)] = {"seconds": sorted(times)[len(times) // 2],
                       "hz": (np.asarray(modal.wd) / (2 * np.pi))[:12].tolist()}
print(json.dumps({"dofs": rotor.ndof, "runs": out}))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=66, help="elements per section")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--ross-python", default=sys.executable, help="a Python with ross")
    parser.add_argument(
        "--skip-dense", action="store_true", help="leave out the dense solver (minutes)"
    )
    args = parser.parse_args()
    case = load_case("friswell_rotor")
    shaft = dataclasses.replace(case.drivetrain.shafts[0], elements_per_section=args.elements)
    case = dataclasses.replace(
        case, drivetrain=dataclasses.replace(case.drivetrain, shafts=(shaft,))
    )
    model = assemble_drivetrain(case)
    speeds = [0.0, 4000.0]
    ross = run_peer(
        args.ross_python, ROSS_SCRIPT, str(args.elements), json.dumps(speeds), str(args.repeats)
    )
    print(f"Friswell rotor, {args.elements} elements per section: {model.size} DOFs")
    print(f"{'speed':>6} {'sparse [s]':>11} {'dense [s]':>10} {'ross [s]':>9} {'max rel diff':>13}")
    for speed in speeds:
        first = model.damping + speed * math.pi / 30 * model.gyroscopic
        results: dict = {}

        def run(name: str, first=first, results=results) -> None:
            results[name] = solve(model.mass, model.stiffness, first, 12, name)

        sparse = median_seconds(partial(run, "sparse"), args.repeats)
        dense, difference = float("nan"), float("nan")
        if not args.skip_dense:
            dense = median_seconds(partial(run, "dense"), 1)
            a, b = results["sparse"].eigenvalues, results["dense"].eigenvalues
            difference = float(np.max(np.abs(a - b) / np.abs(b)))
        ross_time = ross["runs"][str(speed)]["seconds"] if ross else float("nan")
        if ross and speed == speeds[0]:
            print(f"       ROSS's model: {ross['dofs']} DOFs")
        print(f"{speed:>6g} {sparse:>11.3f} {dense:>10.2f} {ross_time:>9.3f} {difference:>13.2e}")
        if ross:
            lateral = results["sparse"].frequencies[:6]
            print(f"       pygear Hz {np.round(lateral, 4).tolist()}")
            print(f"       ROSS   Hz {np.round(ross['runs'][str(speed)]['hz'][:6], 4).tolist()}")
            theirs = np.array(ross["runs"][str(speed)]["hz"][:6])
            largest = np.max(np.abs(lateral - theirs) / theirs)
            print(f"       largest relative difference {largest:.1e}")


if __name__ == "__main__":
    main()
