"""Speed sweeps of a rotor: a 50-speed Campbell diagram and a 500-speed unbalance
response, pygear against ROSS doing the same work.

The rotor is Friswell et al.'s Example 5.9.1 (cases/friswell_rotor) with
``--elements`` Timoshenko elements in each of its three sections (22 give 67 nodes,
402 DOFs; 66 give 1194).  Both programs build the same rotor (six DOFs per node,
isotropic 1e6 N/m bearings, the two discs from their geometry):

* Campbell, ``--campbell-speeds`` speeds from 0 to 4000 rpm, the 12 lowest modes per
  speed: pygear's :func:`~pygear.analysis.modes.sparse_gyroscopic.rotor_campbell`
  (sparse solver, modes tracked by their shapes, critical speeds) against ROSS's
  ``Rotor.run_campbell(speeds, frequencies=12)``;
* unbalance response, ``--unbalance-speeds`` speeds from 100 to 4000 rpm, 1e-4 kg m on
  the left disc: pygear's :func:`~pygear.analysis.response.rotor.unbalance_response`
  (one sparse LU per speed) against ROSS's ``Rotor.run_unbalance_response(node,
  1e-4, 0, speeds)`` (all modes: no modal truncation, the same exact response).

pygear: medians of ``--repeats`` in this process; ROSS: one run in ``--ross-python``
after a warm-up call (its first call compiles), each sweep at speeds shifted by
1e-9 rad/s from the warm-up's (ROSS caches per speed).  Printed: the times, their
ratio, and the largest relative difference of the Campbell frequencies at the top
speed and of the disc's response amplitude.

Run: ``.venv/bin/python benchmarks/bench_rotor_sweeps.py --ross-python PATH
[--elements 22] [--repeats 3]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from functools import partial
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from timing import median_seconds, run_peer  # noqa: E402

from pygear.analysis.modes.sparse_gyroscopic import rotor_campbell  # noqa: E402
from pygear.analysis.response.rotor import Unbalance, unbalance_response  # noqa: E402
from pygear.assembly.drivetrain import assemble_drivetrain  # noqa: E402
from pygear.model.case import load_case  # noqa: E402

ROSS_SCRIPT = """
import json, sys, time
import numpy as np
import ross as rs
elements = int(sys.argv[1])
campbell_rpm, unbalance_rpm = json.loads(sys.argv[2]), json.loads(sys.argv[3])
steel = rs.Material(name="friswell_steel", rho=7810, E=211e9, G_s=81.2e9)
n = 3 * elements
shaft = [rs.ShaftElement(L=1.5 / n, idl=0, odl=0.05, material=steel, n=i) for i in range(n)]
disks = [
    rs.DiskElement.from_geometry(n=elements, material=steel, width=0.07, i_d=0.05, o_d=0.28),
    rs.DiskElement.from_geometry(n=2 * elements, material=steel, width=0.07, i_d=0.05, o_d=0.35),
]
bearings = [rs.BearingElement(n=0, kxx=1e6, cxx=0), rs.BearingElement(n=n, kxx=1e6, cxx=0)]
rotor = rs.Rotor(shaft, disks, bearings)
rotor.run_campbell(np.array([1.0, 2.0]), frequencies=12)  # warm-up
rotor.run_unbalance_response(elements, 1e-4, 0.0, np.array([10.0, 20.0]))
campbell_rad = np.asarray(campbell_rpm) * np.pi / 30 + 1e-9
start = time.perf_counter()
campbell = rotor.run_campbell(campbell_rad, frequencies=12)
campbell_s = time.perf_counter() - start
unbalance_rad = np.asarray(unbalance_rpm) * np.pi / 30 + 1e-9
start = time.perf_counter()
response = rotor.run_unbalance_response(elements, 1e-4, 0.0, unbalance_rad)
unbalance_s = time.perf_counter() - start
disc_x = np.abs(np.asarray(response.forced_resp)[6 * elements, :])
print(json.dumps({
    "dofs": rotor.ndof,
    "campbell_s": campbell_s,
    "unbalance_s": unbalance_s,
    "top_hz": (np.asarray(campbell.wd)[-1] / (2 * np.pi)).tolist(),
    "disc_x": disc_x.tolist(),
}))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=22, help="elements per section")
    parser.add_argument("--campbell-speeds", type=int, default=50)
    parser.add_argument("--unbalance-speeds", type=int, default=500)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--ross-python", default=sys.executable, help="a Python with ross")
    args = parser.parse_args()
    case = load_case("friswell_rotor")
    shaft = dataclasses.replace(case.drivetrain.shafts[0], elements_per_section=args.elements)
    case = dataclasses.replace(
        case, drivetrain=dataclasses.replace(case.drivetrain, shafts=(shaft,))
    )
    model = assemble_drivetrain(case)
    campbell_rpm = np.linspace(0.0, 4000.0, args.campbell_speeds)
    unbalance_rpm = np.linspace(100.0, 4000.0, args.unbalance_speeds)
    results: dict = {}

    def campbell() -> None:
        results["campbell"] = rotor_campbell(model, campbell_rpm, 12, solver="sparse")

    def unbalance() -> None:
        results["unbalance"] = unbalance_response(
            model, case.drivetrain, [Unbalance("disc_left", 1e-4, 0.0)], unbalance_rpm
        )

    ours = {
        "campbell": median_seconds(partial(campbell), args.repeats),
        "unbalance": median_seconds(partial(unbalance), args.repeats),
    }
    ross = run_peer(
        args.ross_python,
        ROSS_SCRIPT,
        str(args.elements),
        json.dumps(campbell_rpm.tolist()),
        json.dumps(unbalance_rpm.tolist()),
    )
    print(
        f"Friswell rotor, {args.elements} elements per section: {model.size} DOFs"
        + (f" (ROSS {ross['dofs']})" if ross else "")
    )
    print(f"{'sweep':<22} {'pygear [s]':>11} {'ROSS [s]':>9} {'ROSS / pygear':>14}")
    for name, label in (
        ("campbell", f"Campbell, {campbell_rpm.size} speeds"),
        ("unbalance", f"unbalance, {unbalance_rpm.size} speeds"),
    ):
        theirs = ross[f"{name}_s"] if ross else float("nan")
        print(f"{label:<22} {ours[name]:>11.2f} {theirs:>9.2f} {theirs / ours[name]:>14.1f}")
    if ross:
        top = np.sort(results["campbell"].frequency.values[-1])
        their_top = np.sort(np.asarray(ross["top_hz"]))[: top.size]
        print(
            f"Campbell at 4000 rpm, largest relative difference "
            f"{np.max(np.abs(top - their_top) / their_top):.1e}"
        )
        disc = results["unbalance"].x_amplitude.sel(location="disc_left").values
        theirs = np.asarray(ross["disc_x"])
        print(
            f"disc_left |x|, largest relative difference "
            f"{np.max(np.abs(disc - theirs) / theirs):.1e}"
        )


if __name__ == "__main__":
    main()
