"""Benchmark: mesh-stiffness laws from gear geometry, built once and read per step.

On the NREL 5 MW gearbox (``cases/nrel5mw_gearbox``: every gear carries its geometry)
this measures, in one run:

* **table build**: the time to resolve one mesh's single-pair law from its geometry,
  for a spur mesh (stage 1 sun-planet) and the helical pair (the parallel stage, whose
  potential-energy law cuts the face width into slices), for the ``parabola`` law
  (nothing to build: k-bar is typed), ISO 6336-1 method B (``iso6336``) and the
  potential-energy method (``potential_energy``).  ``mesh_law`` caches its results
  (``functools.lru_cache`` on ``_resolve``): the *uncached* column clears that cache
  before every call, so each call builds the law afresh; the *kernel call* column
  times the underlying function alone (``mesh_stiffness`` or
  ``iso6336_mesh_stiffness``); the *cache hit* column is a repeated ``mesh_law`` call.
  A slice sweep shows what the helical pair's face-width slices cost;
* **run-up cost per step**: the case's ``runup`` scene, cut to ``--duration`` seconds,
  with every mesh on the ``parabola`` law, on the ``potential_energy`` law
  (``with_mesh_law``) and on ISO 6336 (``with_mesh_law``, or the case's own ISO 6336
  mesh set of its ``modal_iso6336`` scene when pygear's ``iso6336`` law refuses a
  mesh), in microseconds per step inside the Newmark kernel (its own clock) and over
  the whole ``run`` call.  The contact table is built before the run, so the kernel's
  cost per step should not depend on the law.  The set-up (``transient_problem`` with
  the law cache cleared: assembly plus every mesh's law) is timed too.

Every figure is a median of repeats; within a repeat the laws take turns (each repeat
starting with the next law), so that the load of the machine falls on all of them
alike.  Ratios of run costs are medians of the ratios within each repeat.  The study case
``cases/yang2016_planetary`` gives its gears no geometry, so it cannot take a
geometry law; the benchmark says so and runs the NREL gearbox only.

Usage::

    PYTHONPATH=. python benchmarks/bench_mesh_laws.py [--duration 0.5] [--run-repeats 9]
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
from collections.abc import Callable

import numpy as np
from timing import median_seconds

from pygear import load_case
from pygear.analysis.time.transient import TransientProblem, transient_problem
from pygear.assembly.mesh_laws import _bore, _resolve, gears_swapped, mesh_law, with_mesh_law
from pygear.assembly.mesh_stiffness_laws import iso6336_mesh_stiffness
from pygear.assembly.tooth_stiffness import ToothBody, mesh_stiffness
from pygear.errors import CaseError
from pygear.model.case import Case
from pygear.model.components import PlanetaryStage

CASE = "nrel5mw_gearbox"
SCENE = "runup"
ISO_SCENE = "modal_iso6336"  # the case's own ISO 6336 mesh set, if pygear's law refuses
STUDY_CASE = "yang2016_planetary"
LAWS = ("parabola", "potential_energy", "iso6336")
MESHES = {"spur": ("stage1", "sun"), "helical": ("parallel", "mesh")}
HELICAL_SLICES = 100
"""Face-width slices ``mesh_stiffness`` takes for a helical pair by default (n_slice=None)."""
SLICE_SWEEP = (1, 10, 25, 50, 100, 200)
TARGET_SECONDS = 0.02
"""Timed calls per build figure are chosen so that one figure lasts about this long."""


# ----------------------------------------------------------------------------------
# table build
# ----------------------------------------------------------------------------------


def stage_named(case: Case, name: str):
    return next(stage for stage in case.gearbox.stages if stage.name == name)


def mesh_of(stage, member: str):
    """The stage's ``sun`` or ``ring`` mesh, or a parallel stage's ``mesh``."""
    return stage.mesh if member == "mesh" else getattr(stage, f"{member}_mesh")


def bodies_of(stage, member: str) -> tuple[ToothBody, ToothBody]:
    """Material and bores of the mesh's two gears, as ``mesh_law`` hands them on."""
    mesh = mesh_of(stage, member)
    if isinstance(stage, PlanetaryStage):
        gears = (stage.sun, stage.planet) if member == "sun" else (stage.planet, stage.ring)
    else:
        gears = (stage.input_gear, stage.output_gear)
    return tuple(ToothBody(mesh.young_modulus, mesh.poisson_ratio, _bore(g)) for g in gears)


def driving_gear(stage) -> int:
    """The gear of the mesh geometry that drives, as ``mesh_law`` takes it (carrier in,
    sun out: the planet drives the sun; a parallel stage's input gear drives)."""
    return 2 if isinstance(stage, PlanetaryStage) else 1


def larger_shift_first(geometry):
    """The pair with the larger profile shift as gear 1 (ISO 6336-1's q' needs x1 >= x2
    for an external pair)."""
    if geometry.internal or geometry.gear1.profile_shift >= geometry.gear2.profile_shift:
        return geometry
    return gears_swapped(geometry)


def rotated(items: list, repeat: int) -> list:
    """``items`` starting at ``repeat`` (modulo their number): no item always goes first."""
    shift = repeat % len(items)
    return items[shift:] + items[:shift]


def calls_for(function: Callable[[], object]) -> int:
    """Calls per timed figure: enough for ``TARGET_SECONDS``, at least one."""
    once = median_seconds(function, 1, warm_up=True)
    return max(1, min(10_000, round(TARGET_SECONDS / max(once, 1e-9))))


@dataclasses.dataclass(frozen=True)
class BuildItem:
    """One law of one mesh and the calls that build it."""

    kind: str
    law: str
    slices: int | str
    resolve: Callable[[], object] | None  # mesh_law, cache cleared first
    cached: Callable[[], object] | None  # mesh_law, a cache hit
    kernel: Callable[[], object] | None  # the underlying function alone
    note: str = ""


def build_items(case: Case) -> list[BuildItem]:
    items = []
    for kind, (stage_name, member) in MESHES.items():
        for law in LAWS:
            stage = stage_named(with_mesh_law(case, law), stage_name)
            path = f"{stage_name}.{member}"
            helical = stage.base_helix_angle_deg != 0.0
            slices: int | str = "-"
            notes = []

            def resolve(stage=stage, member=member):
                _resolve.cache_clear()
                return mesh_law(stage, member)

            def cached(stage=stage, member=member):
                return mesh_law(stage, member)

            try:
                resolved = resolve()
            except CaseError as error:
                resolve = cached = None
                notes.append(f"mesh_law refused: {error}")
                resolved = None
            geometry = resolved.geometry if resolved is not None else _geometry_of(case, path)
            kernel = None
            if law == "potential_energy":
                slices = HELICAL_SLICES if helical else 1
                bodies, driving = bodies_of(stage, member), driving_gear(stage)

                def kernel(geometry=geometry, bodies=bodies, driving=driving, path=path):
                    return mesh_stiffness(geometry, bodies, driving_gear=driving, path=path)

            elif law == "iso6336":
                ordered = larger_shift_first(geometry)
                line_load = mesh_of(stage, member).line_load
                if ordered is not geometry:
                    notes.append("kernel call with the larger profile shift as gear 1")

                def kernel(ordered=ordered, line_load=line_load, path=path):
                    return iso6336_mesh_stiffness(ordered, line_load=line_load, path=path)

            items.append(BuildItem(kind, law, slices, resolve, cached, kernel, "; ".join(notes)))
    return items


def _geometry_of(case: Case, path: str):
    """The mesh geometry of ``path`` from the case's own law (when a law refuses it)."""
    stage_name, member = path.split(".")
    return mesh_law(stage_named(case, stage_name), member).geometry


def time_builds(items: list[BuildItem], repeats: int) -> dict[tuple[str, str, str], float]:
    """Median seconds per call of every item's calls; the items take turns per repeat."""
    plan = []
    for item in items:
        for column in ("resolve", "kernel", "cached"):
            function = getattr(item, column)
            if function is not None:
                plan.append(((item.kind, item.law, column), function, calls_for(function)))
    samples: dict[tuple[str, str, str], list[float]] = {key: [] for key, _, _ in plan}
    for repeat in range(repeats):
        for key, function, calls in rotated(plan, repeat):
            samples[key].append(median_seconds(function, calls))
    return {key: statistics.median(values) for key, values in samples.items()}


def time_slices(case: Case, repeats: int) -> dict[int, float]:
    """Median seconds of the helical pair's potential-energy curve per slice count."""
    stage_name, member = MESHES["helical"]
    stage = stage_named(case, stage_name)
    geometry = _geometry_of(case, f"{stage_name}.{member}")
    bodies, driving = bodies_of(stage, member), driving_gear(stage)
    default = mesh_stiffness(geometry, bodies, driving_gear=driving)
    explicit = mesh_stiffness(geometry, bodies, driving_gear=driving, n_slice=HELICAL_SLICES)
    if not np.array_equal(default.pair, explicit.pair):
        print(f"note: the helical default is not {HELICAL_SLICES} slices (curves differ)")
    samples: dict[int, list[float]] = {n: [] for n in SLICE_SWEEP}
    for repeat in range(repeats):
        for n in rotated(list(SLICE_SWEEP), repeat):
            samples[n].append(
                median_seconds(
                    lambda n=n: mesh_stiffness(geometry, bodies, driving_gear=driving, n_slice=n),
                    1,
                )
            )
    return {n: statistics.median(values) for n, values in samples.items()}


# ----------------------------------------------------------------------------------
# run-up cost per step
# ----------------------------------------------------------------------------------


def law_cases(case: Case, scene) -> dict[str, tuple[Case, str]]:
    """Every law's case and how it was made; ``iso6336`` falls back to the case's own
    ISO 6336 mesh set when pygear's law refuses a mesh."""
    cases = {}
    for law in LAWS:
        changed = with_mesh_law(case, law)
        try:
            _resolve.cache_clear()
            transient_problem(changed, scene)
            cases[law] = (changed, f"with_mesh_law(case, {law!r})")
        except CaseError as error:
            if law != "iso6336":
                raise
            print(f"note: with_mesh_law(case, 'iso6336') refused at assembly: {error}")
            cases[law] = (case.for_scene(case.scene(ISO_SCENE)), f"scene {ISO_SCENE!r} meshes")
    return cases


def law_summary(problem: TransientProblem) -> str:
    """The contact table's single-pair laws, counted (``3 parabola + 2 tabulated``)."""
    names = {1: "parabola", 2: "tabulated", 3: "helical"}
    codes = [names[int(code)] for code in problem.solver.meshes.table.law]
    return " + ".join(f"{codes.count(name)} {name}" for name in dict.fromkeys(codes))


def time_runs(
    cases: dict[str, tuple[Case, str]], scene, repeats: int, setup_repeats: int
) -> dict[str, dict]:
    """Per law: kernel and whole-run microseconds per step (median and least of the
    repeats), the set-up seconds (median) and the kernel's ratio to ``parabola`` (the
    median of the ratios within each repeat, which share the machine's load)."""
    settings = scene.transient
    problems = {}
    for law, (changed, _) in cases.items():
        problem = transient_problem(changed, scene)
        problem.solver.run(1000, problem.probes, decimation=problem.settings.decimation)
        problems[law] = problem
    steps = round(settings.duration / settings.time_step)
    names = ("kernel", "wall", "setup", "evaluations")
    samples = {law: {name: [] for name in names} for law in cases}
    for repeat in range(repeats):
        for law in rotated(list(cases), repeat):
            problem = problems[law]
            started = time.perf_counter()
            result = problem.solver.run(steps, problem.probes, decimation=settings.decimation)
            wall = time.perf_counter() - started
            samples[law]["kernel"].append(result.solver_wall_s / result.steps * 1e6)
            samples[law]["wall"].append(wall / result.steps * 1e6)
            samples[law]["evaluations"].append(result.counters["contact_evaluations"])
    for repeat in range(setup_repeats):
        for law in rotated(list(cases), repeat):
            _resolve.cache_clear()
            changed = cases[law][0]
            samples[law]["setup"].append(
                median_seconds(lambda changed=changed: transient_problem(changed, scene), 1)
            )
    reference = samples["parabola"]
    figures = {}
    for law, values in samples.items():
        figures[law] = {name: statistics.median(v) for name, v in values.items()}
        figures[law]["kernel_least"] = min(values["kernel"])
        figures[law]["wall_least"] = min(values["wall"])
        for name in ("kernel", "wall"):
            paired = [a / b for a, b in zip(values[name], reference[name], strict=True)]
            figures[law][f"{name}_ratio"] = statistics.median(paired)
        figures[law]["steps"] = steps
        figures[law]["table"] = law_summary(problems[law])
    return figures


# ----------------------------------------------------------------------------------
# report
# ----------------------------------------------------------------------------------


def print_builds(items: list[BuildItem], figures: dict, repeats: int) -> None:
    print(
        f"\ntable build, one mesh (median of {repeats} repeats; uncached = mesh_law after "
        "_resolve.cache_clear(), the clear included)"
    )
    header = (
        f"{'mesh':<8} {'law':<17} {'slices':>6} {'uncached mesh_law':>18} "
        f"{'kernel call':>12} {'cache hit':>10}"
    )
    print(header)
    print("-" * len(header))

    def cell(key, width):
        value = figures.get(key)
        return f"{'refused':>{width}}" if value is None else f"{value * 1e3:>{width - 3}.3f} ms"

    notes = []
    for item in items:
        key = (item.kind, item.law)
        hit = figures.get((*key, "cached"))
        hit_text = f"{'-':>10}" if hit is None else f"{hit * 1e6:>7.2f} us"
        kernel = figures.get((*key, "kernel"))
        kernel_text = f"{'-':>12}" if kernel is None else cell((*key, "kernel"), 12)
        print(
            f"{item.kind:<8} {item.law:<17} {item.slices!s:>6} "
            f"{cell((*key, 'resolve'), 18)} {kernel_text} {hit_text}"
        )
        if item.note:
            notes.append(f"  {item.kind} {item.law}: {item.note}")
    for kind in MESHES:
        parabola = figures.get((kind, "parabola", "resolve"))
        for law in ("iso6336", "potential_energy"):
            column = "resolve" if (kind, law, "resolve") in figures else "kernel"
            built = figures.get((kind, law, column))
            if parabola and built:
                which = "uncached mesh_law" if column == "resolve" else "kernel call"
                print(f"ratio {kind:<7} {law:<16} / parabola: {built / parabola:>8.0f} x ({which})")
    if notes:
        print("notes:")
        print("\n".join(notes))


def print_slices(figures: dict[int, float], repeats: int) -> None:
    print(
        f"\nhelical pair, potential-energy curve against face-width slices "
        f"(mesh_stiffness, median of {repeats}; default {HELICAL_SLICES})"
    )
    print(f"{'slices':>6} {'time':>12} {'per slice':>12}")
    for n, seconds in figures.items():
        print(f"{n:>6} {seconds * 1e3:>9.3f} ms {seconds / n * 1e6:>9.1f} us")


def print_runs(cases: dict, figures: dict, repeats: int, setup_repeats: int, scene) -> None:
    steps = next(iter(figures.values()))["steps"]
    settings = scene.transient
    print(
        f"\n{CASE} {SCENE}: {steps} steps ({steps * settings.time_step:g} s at dt = "
        f"{settings.time_step:g} s), {repeats} runs per law, laws taking turns; us/step as "
        f"median (least); set-up: transient_problem, law cache cleared, median of "
        f"{setup_repeats}"
    )
    header = (
        f"{'law':<17} {'kernel us/step':>17} {'run us/step':>17} {'set-up':>10} "
        f"{'table evals':>11}  contact table"
    )
    print(header)
    print("-" * len(header))
    for law, values in figures.items():
        kernel = f"{values['kernel']:.2f} ({values['kernel_least']:.2f})"
        wall = f"{values['wall']:.2f} ({values['wall_least']:.2f})"
        print(
            f"{law:<17} {kernel:>17} {wall:>17} {values['setup'] * 1e3:>7.1f} ms "
            f"{values['evaluations']:>11.0f}  {values['table']}"
        )
    print("sources: " + "; ".join(f"{law}: {source}" for law, (_, source) in cases.items()))
    print("ratio to parabola, median of the per-repeat ratios:")
    for law in ("potential_energy", "iso6336"):
        values = figures[law]
        print(
            f"  {law:<17} kernel {values['kernel_ratio']:.3f}, whole run "
            f"{values['wall_ratio']:.3f} (ratio of medians: kernel "
            f"{values['kernel'] / figures['parabola']['kernel']:.3f})"
        )
    parabola = figures["parabola"]
    extra = figures["potential_energy"]["setup"] - parabola["setup"]
    print(
        f"set-up, law cache cleared: potential_energy - parabola = {extra * 1e3:.1f} ms, "
        f"the kernel's cost of {extra / (parabola['kernel'] * 1e-6):.0f} steps"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=0.5, help="simulated run-up [s]")
    parser.add_argument(
        "--build-repeats", type=int, default=7, help="build and set-up repeats (median)"
    )
    parser.add_argument("--run-repeats", type=int, default=9, help="run repeats (median)")
    args = parser.parse_args()

    started = time.perf_counter()
    case = load_case(CASE)
    try:
        with_mesh_law(load_case(STUDY_CASE), "potential_energy")
        print(f"note: {STUDY_CASE} takes a geometry law, but this benchmark runs {CASE} only")
    except CaseError as error:
        print(f"{STUDY_CASE} left out: {error}")

    items = build_items(case)
    print_builds(items, time_builds(items, args.build_repeats), args.build_repeats)
    print_slices(time_slices(case, args.build_repeats), args.build_repeats)

    scene = case.scene(SCENE)
    settings = dataclasses.replace(
        scene.transient, duration=args.duration, mean_window=scene.transient.time_step
    )
    scene = dataclasses.replace(scene, transient=settings)
    cases = law_cases(case, scene)
    figures = time_runs(cases, scene, args.run_repeats, args.build_repeats)
    print_runs(cases, figures, args.run_repeats, args.build_repeats, scene)
    print(f"\nwhole benchmark: {time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
