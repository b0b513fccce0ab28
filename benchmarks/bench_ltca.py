"""Benchmark: loaded tooth contact analysis of one mesh over a mesh cycle.

Target (#30): 40 slices, 20 positions, one load, under 50 ms.  Measured on the NREL
5 MW gearbox's meshes (``cases/nrel5mw_gearbox``, every gear with geometry): the stage 1
sun-planet (spur) and the parallel helical pair, each

* **whole call**: :func:`pygear.analysis.contact.ltca.loaded_contact`, including the
  potential-energy compliances (``mesh_stiffness`` with one slice), the separations and
  the Dataset, without modifications and with a tip relief plus crowning plus
  misalignment (which adds the perfect-flank reference solve for K_Halpha);
* **kernel alone**: the Fortran contact solve (``solve_slices``) on the same arrays;
* a **Harris map** of 10 loads in one call (the kernel warm-starts each load's active
  set from the previous one).

Target (#30, the ``loaded_contact`` law): the **whole NREL gearbox tabulated**, its five
meshes over one mesh cycle at five loads each (``pygear.assembly.loaded_contact_table``,
20 slices, 40 positions), under 2 s, cold (the law's cache cleared before each repeat);
beside it, as the baseline doing the meshes' law without contact, the same five meshes
on the potential-energy law (the compliances the LTCA starts from; the helical pair's
law slices its face, the LTCA takes the one-slice compliances and slices the contact).
Measured: 0.13 s for the gearbox, 0.13 of the potential-energy laws' 1.0 s.

Every figure is a median of repeats (``--repeats``).

Usage::

    PYTHONPATH=. python benchmarks/bench_ltca.py [--repeats 15]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from timing import median_seconds  # noqa: E402

from pygear import load_case  # noqa: E402
from pygear.analysis.contact.ltca_case import case_mesh  # noqa: E402
from pygear.assembly import ltca, mesh_laws  # noqa: E402
from pygear.assembly.mesh_laws import tooth_bodies  # noqa: E402
from pygear.model.micro_geometry import (  # noqa: E402
    Misalignment,
    Modifications,
    ProfileRelief,
)

TARGET = 0.050  # s: 40 slices x 20 positions, one load


def _arrays_of_kernel(geometry, bodies, force, mods):
    """Capture the kernel's arrays of one call (to time the kernel alone)."""
    captured = {}
    original = ltca.solve_slices

    def spy(*args, **kwargs):
        captured.setdefault("args", (args, kwargs))
        return original(*args, **kwargs)

    ltca.solve_slices = spy
    try:
        ltca.loaded_contact(geometry, bodies, force, modifications=mods)
    finally:
        ltca.solve_slices = original
    return captured["args"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=15)
    repeats = parser.parse_args().repeats
    case = load_case("nrel5mw_gearbox")
    print(f"{'mesh':<24}{'case':<14}{'whole ms':>10}{'kernel ms':>11}{'10 loads ms':>13}")
    worst = 0.0
    for name in ("stage1.sun-planet1", "parallel.input-output"):
        mesh = case_mesh(case, name)
        stage_mesh = mesh.stage.mesh if mesh.member == "mesh" else getattr(
            mesh.stage, f"{mesh.member}_mesh"
        )
        bodies = tooth_bodies(stage_mesh, mesh.geometry,
                              tuple(g.foundation_radius for g in mesh.gears))  # fmt: skip
        force = 1e5 / mesh.torque_radius
        tip = 2 * mesh.gears[0].geometry.teeth * mesh.gears[0].geometry.normal_module / 2
        modified = Modifications(
            tip_relief=ProfileRelief(20e-6, start_diameter=tip),
            crowning=10e-6,
            misalignment=Misalignment(in_plane=5e-5),
        )
        for label, mods in (("perfect", (None, None)), ("modified", (modified, None))):
            def whole(mods=mods, mesh=mesh, bodies=bodies, force=force):
                return ltca.loaded_contact(mesh.geometry, bodies, force, modifications=mods,
                                           n_slice=40, n_position=20,
                                           driving_gear=mesh.driving_gear)  # fmt: skip

            def harris(mods=mods, mesh=mesh, bodies=bodies, force=force):
                return ltca.loaded_contact(mesh.geometry, bodies,
                                           np.linspace(0.1, 1.0, 10) * force,
                                           modifications=mods, n_slice=40, n_position=20,
                                           driving_gear=mesh.driving_gear)  # fmt: skip

            args, kwargs = _arrays_of_kernel(mesh.geometry, bodies, force, mods)
            t_whole = median_seconds(whole, repeats, warm_up=True)
            t_kernel = median_seconds(lambda a=args, k=kwargs: ltca.solve_slices(*a, **k),
                                      repeats, warm_up=True)  # fmt: skip
            t_harris = median_seconds(harris, repeats, warm_up=True)
            worst = max(worst, t_whole)
            print(f"{name:<24}{label:<14}{t_whole * 1e3:10.1f}{t_kernel * 1e3:11.2f}"
                  f"{t_harris * 1e3:13.1f}")
    verdict = "meets" if worst < TARGET else "MISSES"
    print(f"slowest whole call {worst * 1e3:.1f} ms: {verdict} the {TARGET * 1e3:.0f} ms target")
    _gearbox_table(case, max(3, repeats // 3))


GEARBOX_TARGET = 2.0  # s: the whole NREL gearbox tabulated by the loaded_contact law


def _gearbox_table(case, repeats: int) -> None:
    """Time the loaded_contact law of every mesh of the gearbox, cold."""
    laws = {law: mesh_laws.with_mesh_law(case, law) for law in ("potential_energy",
                                                                  "loaded_contact")}

    def resolve(changed) -> None:
        mesh_laws._resolve.cache_clear()
        for stage in changed.gearbox.stages:
            for member in mesh_laws.stage_mesh_members(stage):
                mesh_laws.mesh_law(stage, member)

    times = {law: median_seconds(lambda c=c: resolve(c), repeats) for law, c in laws.items()}
    table, energy = times["loaded_contact"], times["potential_energy"]
    verdict = "meets" if table < GEARBOX_TARGET else "MISSES"
    print(f"whole gearbox, 5 meshes x 5 loads: {table:.2f} s ({table / energy:.2f} x the "
          f"potential-energy law's {energy * 1e3:.0f} ms): {verdict} the "
          f"{GEARBOX_TARGET:.0f} s target")


if __name__ == "__main__":
    main()
