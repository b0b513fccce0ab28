"""Effects as the scene's contract (docs/model.md §7): pruning is exact, an effect
left out costs nothing, every output records what was in force, contradictions are refused."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import (
    CASES,
    case_of,
    consistent_stage,
    rigid_to_elastic_ratio,
    roundoff_tolerance,
)

from pygear import CaseError, Scene
from pygear.analysis.modes.modal import modal_analysis
from pygear.analysis.signals.channels import channel_names, channel_series
from pygear.analysis.time.transient import run_transient
from pygear.assembly import assemble
from pygear.cli import main

TV = "time_varying_mesh_stiffness"


def _short(scene: Scene, **changes) -> Scene:
    """The run-up shortened to 0.2 s (8000 steps at the paper's 2.5e-5 s)."""
    transient = dataclasses.replace(scene.transient, duration=0.2, mean_window=0.05)
    return dataclasses.replace(scene, transient=transient, **changes)


@pytest.fixture(scope="module")
def planar_and_spatial(study_case):
    runup = _short(study_case.scene("runup"))
    planar = run_transient(study_case, dataclasses.replace(runup, dof_set="planar"))
    spatial = run_transient(study_case, dataclasses.replace(runup, dof_set="spatial"))
    return planar, spatial


def planar_spatial_tolerance(study_case, run) -> float:
    """Round-off the planar and spatial runs may differ by (conftest.roundoff_tolerance):
    the sun-planet deflection against the sun's rigid turn over the run."""
    stage = study_case.gearbox.stages[0]
    sun_mesh, sun = stage.sun_mesh, stage.sun
    turn = float(np.abs(run.speed.sel(member="planetary.sun")).max()) * np.pi / 30
    angle = turn * run.attrs["duration"]
    force = float(np.sqrt(np.mean(run.mesh_force.sel(mesh="planetary.sun-planet1").values ** 2)))
    amplification = rigid_to_elastic_ratio(sun.base_radius, angle, force, sun_mesh.stiffness)
    return roundoff_tolerance(run.attrs["steps"], amplification)


def test_planar_run_equals_spatial_run_in_plane(study_case, planar_and_spatial):
    """A spur stage's out-of-plane DOFs are decoupled (docs/model.md §7): the planar run's
    in-plane answers equal the spatial run's to round-off, with time-varying stiffness on.

    The two runs solve different systems, so they round differently: the bound is
    conftest.roundoff_tolerance (about 5e-6 here), while a missing coupling would show at
    the level of the coupling itself (1e-3 and more)."""
    planar, spatial = planar_and_spatial
    assert planar.attrs["dof_count"] == 18 and spatial.attrs["dof_count"] == 36
    tolerance = planar_spatial_tolerance(study_case, spatial)
    assert tolerance < 1e-5  # still tight enough to see a coupling
    channels = channel_names(planar)
    assert len(channels) == 10
    for name in channels:
        a, b = channel_series(planar, name).values, channel_series(spatial, name).values
        scale = max(np.abs(b).max(), 1e-300)
        if name == "acceleration:planetary.ring.y":
            # in phase, equally spaced planets excite no translation: round-off on both
            # sides; compare against the sun's acceleration scale instead
            sun = channel_series(spatial, "acceleration:planetary.sun.theta_z")
            scale = np.abs(sun.values).max()
        assert np.abs(a - b).max() <= tolerance * scale, name
    speeds = planar.equilibrium_speed.values
    np.testing.assert_allclose(
        speeds, spatial.equilibrium_speed.values, rtol=0, atol=tolerance * 540
    )
    assert float(planar.t_s) == pytest.approx(float(spatial.t_s), rel=tolerance)


def test_constant_stiffness_never_evaluates_the_contact_table(study_case):
    """Counted in the kernel: the predictor evaluates the table once at the start and
    once per step with time-varying stiffness, never at constant stiffness."""
    runup = _short(study_case.scene("runup"))
    steps = runup.transient.steps
    varying = run_transient(study_case, runup)
    constant = run_transient(study_case, dataclasses.replace(runup, effects=()))
    assert varying.attrs["solver_contact_evaluations"] == steps + 1
    assert constant.attrs["solver_contact_evaluations"] == 0
    assert constant.attrs["equivalent_load"] == "linear"
    assert "table never evaluated" in constant.attrs["effects_in_force"]


def test_every_output_records_dof_set_count_and_effects(study_case, planar_and_spatial):
    planar, _ = planar_and_spatial
    for attrs in (planar.attrs, modal_analysis(assemble(study_case)).attrs):
        assert attrs["dof_set"] == "planar"
        assert attrs["dof_count"] == 18 and attrs["dof_count_spatial"] == 36
        for effect in ("time_varying_mesh_stiffness", "tooth_separation", "helical_coupling"):
            assert effect in attrs["effects_in_force"]
    assert "time_varying_mesh_stiffness: on" in planar.attrs["effects_in_force"]
    assert "equivalent_load: predictor" in planar.attrs["effects_in_force"]


def test_open_dof_set_picks_planar_for_spur_and_says_why(study_case):
    """Left open, a spur stage is planar (the smallest exact set); torsional only on request."""
    model = assemble(study_case, Scene("open", analyses=("modal",), formulation="improved"))
    assert model.dof_set == "planar" and "spur" in model.dof_set_reason
    asked = Scene("t", analyses=("modal",), dof_set="torsional")
    assert assemble(study_case, asked).dof_set == "torsional"


def test_helical_coupling_is_kept_by_the_gearbox_pick():
    from pygear import load_case

    gearbox = load_case(CASES / "yang2016_gearbox")
    model = assemble(gearbox, Scene("h", analyses=("modal",), effects=("helical_coupling",)))
    assert model.dof_set == "per-stage"
    assert "helical_coupling: on (parallel)" in modal_analysis(model).attrs["effects_in_force"]


@pytest.mark.parametrize(
    "scene, message",
    [
        (Scene("s", effects=("gyroscopic",)), "scenes.s.effects must be one of"),
        (
            Scene("s", dof_set="torsional", effects=("helical_coupling",)),
            "'helical_coupling' couples in-plane and out-of-plane DOFs",
        ),
        (
            Scene("s", dof_set="planar", effects=("helical_coupling",)),
            "scenes.s.dof_set must be 'spatial' or left open",
        ),
        (
            Scene(
                "s",
                dof_set="torsional",
                effects=("speed_dependent_planet_terms",),
                carrier_speed_rpm=120.0,
            ),
            "which the torsional DOF set drops",
        ),
        (
            Scene("s", effects=("speed_dependent_planet_terms",)),
            "scenes.s.carrier_speed_rpm must be non-zero",
        ),
        (Scene("s", effects=(TV, TV)), "each effect may be listed once"),
    ],
)
def test_contradicting_effects_are_refused(scene, message):
    with pytest.raises(CaseError, match=message.replace("(", r"\(").replace(")", r"\)")):
        scene.validate("scenes.s")


def test_helical_coupling_needs_a_helical_stage():
    with pytest.raises(CaseError, match="'helical_coupling' needs a helical stage"):
        dataclasses.replace(
            case_of(consistent_stage(3)),
            scenes=(Scene("s", effects=("helical_coupling",)),),
        )


def test_cli_refuses_a_bad_tolerance(capsys):
    for bad in ("0", "-1%", "abc"):
        assert main(["accuracy", str(CASES / "yang2016_planetary"), f"--tolerance={bad}"]) == 2
        assert "--tolerance" in capsys.readouterr().err


_GENERIC_CORE_PAIR = """
import dataclasses, json, sys
import numpy as np
from pygear import load_case
from pygear._blas import kernel_blas
from pygear.analysis.signals.channels import channel_names, channel_series
from pygear.analysis.time.transient import run_transient

case = load_case(sys.argv[1])
scene = case.scene("runup")
scene = dataclasses.replace(
    scene, transient=dataclasses.replace(scene.transient, duration=0.05, mean_window=0.01)
)
runs = {
    dof_set: run_transient(case, dataclasses.replace(scene, dof_set=dof_set))
    for dof_set in ("planar", "spatial")
}
channels = channel_names(runs["planar"])
series = {k: {n: channel_series(r, n).values for n in channels} for k, r in runs.items()}
difference = {
    n: float(np.abs(series["planar"][n] - series["spatial"][n]).max()) for n in channels
}
scale = {n: float(np.abs(series["spatial"][n]).max()) for n in channels}
print(json.dumps({"core": kernel_blas()["core"], "difference": difference, "scale": scale,
                  "steps": runs["spatial"].attrs["steps"]}))
"""


def _cpu_has(*flags: str) -> bool:
    try:
        with open("/proc/cpuinfo") as info:
            words = set(info.read().split())
    except OSError:
        return False
    return all(flag in words for flag in flags)


@pytest.mark.parametrize("core", ["Prescott", "Haswell"])
def test_planar_spatial_pair_under_a_forced_blas_core(study_case, core, tmp_path):
    """The same pair as above, 0.05 s, in a child process whose OpenBLAS is forced to a
    core type (Prescott is the generic fallback an older OpenBLAS takes on a CPU it does
    not know): the bound holds whatever kernels BLAS runs, and the kernel reports them."""
    import json
    import os
    import subprocess
    import sys

    if core == "Haswell" and not _cpu_has("avx2", "fma"):
        pytest.skip("this CPU cannot run OpenBLAS's Haswell kernels (no AVX2/FMA)")
    env = {**os.environ, "OPENBLAS_CORETYPE": core}
    script = tmp_path / "pair.py"
    script.write_text(_GENERIC_CORE_PAIR)
    result = subprocess.run(
        [sys.executable, str(script), str(CASES / "yang2016_planetary")],
        env=env, capture_output=True, text=True, check=True,
    )
    report = json.loads(result.stdout.strip().splitlines()[-1])
    # OpenBLAS names the forced core (Prescott's generic kernels report as Katmai, its
    # oldest x86-64 target); on other CPU families the name may differ but is reported
    assert report["core"] not in ("", "unknown")
    angle = 541.0 * np.pi / 30 * 0.05  # the sun cannot have turned further than this
    stage = study_case.gearbox.stages[0]
    force = 0.1 * 10.0 / stage.sun.base_radius / 3  # a tenth of the static share: generous
    tolerance = roundoff_tolerance(
        report["steps"],
        rigid_to_elastic_ratio(stage.sun.base_radius, angle, force, stage.sun_mesh.stiffness),
    )
    for name, difference in report["difference"].items():
        scale = report["scale"][name]
        if name == "acceleration:planetary.ring.y":
            scale = report["scale"]["acceleration:planetary.sun.theta_z"]  # round-off only
        assert difference <= tolerance * max(scale, 1e-300), name
