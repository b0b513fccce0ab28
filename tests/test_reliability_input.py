"""Input that used to slip through: refused before any work, with one line naming the
parameter and the rule (exit code 2 on the command line), or run as documented.

Each test below failed before its fix: probe names that clash with the run's own
variables, tooth numbers that do not fit the base radii, averaging windows outside
the run, a negative drive torque, a case file that exits, a mesh too soft for the
deflection limit, checks that only ran when a later scene was reached, runs too large
for the machine, and NumPy scalars in a case.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest

from pygear import CaseError, Probe, Scene, TorqueLaw, load_case
from pygear.analysis.modes.modal import solve_eigenproblem
from pygear.analysis.time.transient import run_transient, transient_problem
from pygear.assembly import assemble
from pygear.cli import main
from pygear.kernel.newmark import TransientError
from pygear.model.case import replace_parameter
from pygear.model.components import Gear
from pygear.model.plausibility import PlausibilityWarning

ROOT = Path(__file__).resolve().parent.parent
STUDY = ROOT / "cases" / "yang2016_planetary"
GEARBOX = ROOT / "cases" / "yang2016_gearbox"


def _runup(study_case, **change) -> Scene:
    """The study case's run-up scene with changed transient settings (transient only)."""
    scene = study_case.scene("runup")
    return dataclasses.replace(
        scene, analyses=("transient",), transient=dataclasses.replace(scene.transient, **change)
    )


def _case_dir(tmp_path: Path, name: str, body: str) -> Path:
    """A case directory whose case.py starts from the study case (``study``)."""
    directory = tmp_path / name
    directory.mkdir()
    header = f"import dataclasses\nfrom pygear import *\nstudy = load_case({str(STUDY)!r})\n"
    (directory / "case.py").write_text(header + textwrap.dedent(body))
    return directory


def _strict_json(text: str) -> object:
    """Parse JSON refusing the NaN and Infinity tokens Python's json writes by default."""

    def refuse(token: str) -> None:
        raise AssertionError(f"non-JSON token {token} in {text[:200]!r}")

    return json.loads(text, parse_constant=refuse)


# --- 1. probe names ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "name",
    [
        "t_s",
        "equilibrium_speed",
        "planet_tangential_speed",
        "time",
        "member",
        "speed",
        "a/b",
        "__hidden",
        "",
        "1st",
        "sun speed",
    ],
)
def test_probe_name_that_clashes_or_is_not_a_netcdf_name_is_refused(study_case, name):
    scene = _runup(study_case, probes=(Probe("speed", "planetary.carrier", name=name),))
    with pytest.raises(CaseError) as error:
        dataclasses.replace(study_case, scenes=(scene,))
    message = str(error.value)
    assert "scenes.runup.transient.probes[0].name" in message
    assert "\n" not in message


def test_probe_name_refused_on_the_command_line_before_any_work(tmp_path, capsys):
    case_dir = _case_dir(
        tmp_path,
        "probe_t_s",
        """
        runup = study.scene("runup")
        settings = dataclasses.replace(
            runup.transient, probes=(Probe("speed", "planetary.sun", name="t_s"),)
        )
        case = dataclasses.replace(
            study, scenes=(dataclasses.replace(runup, transient=settings),)
        )
        """,
    )
    assert main(["run", str(case_dir), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert "probes[0].name" in err and "'t_s'" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_every_name_a_run_file_takes_is_refused_as_a_probe_name(study_case, tmp_path):
    """A run file's own names are the taken ones, whatever the file gains later."""
    from pygear.model.transient_settings import RUN_VARIABLES
    from pygear.runs.transient_outputs import write_transient

    scene = _runup(study_case, duration=0.01, mean_window=0.01, full_state=True)
    dataset, _ = write_transient(study_case, scene, tmp_path, figure=False)
    probes = {probe.variable for probe in scene.transient.probes}
    assert set(dataset.variables) - probes <= RUN_VARIABLES


# --- 2. tooth numbers against base radii ------------------------------------------------------


def test_study_and_gearbox_cases_still_load():
    # Table 1: Z_s, Z_p, Z_r = 27, 35, 96 on r_b = 38.7, 50.2, 137.5 mm (ratios agree to
    # 0.14 %); the gearbox's first ring has 97 teeth on the same radius (1.1 %)
    assert load_case(STUDY).gearbox.stages[0].ring.teeth == 96
    assert load_case(GEARBOX).gearbox.stages[0].ring.teeth == 97


@pytest.mark.parametrize(
    ("parameter", "value", "culprit"),
    [
        ("planetary.ring.teeth", 960, "planetary.ring.teeth"),  # a digit too many
        ("planetary.planet.teeth", 350, "planetary.planet.teeth"),
        ("planetary.sun.teeth", 35, "planetary.sun.teeth"),  # the planet's number
        ("planetary.ring.teeth", 92, "planetary.ring.teeth"),  # 92 for 96: 4 % off
    ],
)
def test_tooth_numbers_must_fit_the_base_radii(study_case, parameter, value, culprit):
    with pytest.raises(CaseError) as error:
        replace_parameter(study_case, parameter, value)
    message = str(error.value)
    assert message.startswith(culprit) and "base pitch" in message and "3 %" in message


def test_parallel_pair_teeth_must_fit_the_base_radii():
    gearbox = load_case(GEARBOX)  # equal gears of 34 teeth on 50 mm
    with pytest.raises(CaseError, match=r"^parallel\.output_gear\.teeth: 340 teeth"):
        replace_parameter(gearbox, "parallel.output_gear.teeth", 340)


def test_module_must_fit_base_radius_and_teeth(study_case):
    # r_b = m z cos(alpha)/2: the sun's 38.7 mm on 27 teeth is m = 3 mm at
    # alpha = acos(2 * 38.7 / (3 * 27)) = 17.2 deg, a plausible pressure angle
    accepted = replace_parameter(study_case, "planetary.sun.module", 3e-3)
    assert accepted.gearbox.stages[0].sun.module == 3e-3
    with pytest.raises(CaseError, match=r"^planetary\.sun\.module: .*pressure angle"):
        replace_parameter(study_case, "planetary.sun.module", 0.3e-3)  # x10 the teeth
    with pytest.raises(CaseError, match=r"^planetary\.sun\.module must be a positive"):
        replace_parameter(study_case, "planetary.sun.module", -3e-3)
    with pytest.raises(CaseError, match="needs its teeth"):
        Gear(mass=1.0, polar_inertia=1.0, tilt_inertia=1.0, base_radius=0.04, module=3e-3).validate(
            "g"
        )


# --- 3. averaging window and JSON --------------------------------------------------------------


@pytest.mark.parametrize(
    ("window", "rule"),
    [(1e-5, "at least one time_step"), (6.0, "at most the duration")],
)
def test_mean_window_outside_the_run_is_refused(study_case, window, rule):
    with pytest.raises(CaseError) as error:
        dataclasses.replace(study_case, scenes=(_runup(study_case, mean_window=window),))
    assert "scenes.runup.transient.mean_window" in str(error.value) and rule in str(error.value)


def test_json_text_never_writes_non_json_tokens():
    from pygear.runs.json_output import json_text

    text = json_text({"a": math.nan, "b": [math.inf, 1.5, -math.inf], "c": np.float64("nan")})
    assert _strict_json(text) == {"a": None, "b": [None, 1.5, None], "c": None}


# --- 4. negative drive torque ------------------------------------------------------------------


@pytest.fixture(scope="module")
def mirrored_runs(study_case):
    """The run-up at +10 and -10 N m with constant mesh stiffness (a linear model)."""
    runs = {}
    for torque in (10.0, -10.0):
        scene = _runup(study_case, duration=0.4, mean_window=0.1, drive=TorqueLaw.constant(torque))
        runs[torque] = run_transient(study_case, dataclasses.replace(scene, effects=()))
    return runs


def test_negative_drive_engages_the_load_as_the_mirror_image(mirrored_runs):
    forward, backward = mirrored_runs[10.0], mirrored_runs[-10.0]
    # theta -> -theta maps the linear model, the drive and the odd load law onto
    # themselves, so t_s is the same and every speed changes sign; 1e-9 allows the
    # round-off of 16000 steps of a banded solve
    assert math.isfinite(float(backward.t_s))
    assert float(backward.t_s) == pytest.approx(float(forward.t_s), rel=1e-9)
    np.testing.assert_allclose(
        backward.equilibrium_speed.values,
        -forward.equilibrium_speed.values,
        rtol=1e-9,
        atol=1e-9 * float(np.abs(forward.equilibrium_speed).max()),
    )
    # the case's sign convention: the drive probe reads the torque as given, and the
    # load brakes the actual rotation of the output (opposite signs of speed and force
    # on it: the load torque has the speed's sign and acts against it)
    assert np.all(backward.drive_torque.values == -10.0)
    late = backward.time > float(backward.t_s) + 0.05
    load = backward.load_torque.values[late]
    sun = backward.speed.sel(member="planetary.sun").values[late]
    assert np.all(load < 0) and np.all(sun < 0)
    np.testing.assert_allclose(load, -forward.load_torque.values[late], rtol=1e-9, atol=1e-9)


# --- 5. a case file that exits --------------------------------------------------------------------


@pytest.mark.parametrize(
    "body", ["import sys\nsys.exit(0)\n", "raise SystemExit\n", "raise KeyboardInterrupt\n"]
)
def test_case_file_that_exits_is_a_case_error(tmp_path, body, capsys):
    directory = tmp_path / "exits"
    directory.mkdir()
    (directory / "case.py").write_text(body)
    with pytest.raises(CaseError, match=re.escape(str(directory / "case.py"))):
        load_case(directory)
    for command in (["modal", str(directory)], ["run", str(directory), "--out", str(tmp_path)]):
        assert main(command) == 2
        assert str(directory / "case.py") in capsys.readouterr().err


def test_batch_records_a_case_that_exits_and_goes_on(tmp_path):
    from pygear.runs.batch import run_batch

    cases = tmp_path / "cases"
    (cases / "exits").mkdir(parents=True)
    (cases / "exits" / "case.py").write_text("import sys\nsys.exit(0)\n")
    _case_dir(cases, "quiet", "case = dataclasses.replace(study, name='quiet', scenes=())\n")
    table = run_batch([cases], out_dir=tmp_path / "out", workers=1, progress=False)
    rows = {row.case: row for row in table.itertuples()}
    assert rows["exits"].status == "error" and "case.py" in rows["exits"].error
    assert rows["quiet"].status == "ok"


# --- 6. a mesh too soft for the deflection limit -----------------------------------------------


def test_soft_mesh_is_named_before_the_run(study_case):
    soft = study_case
    for mesh in ("sun_mesh", "ring_mesh"):
        soft = replace_parameter(soft, f"planetary.{mesh}.stiffness", 1e4)
    with pytest.raises(CaseError) as error:
        transient_problem(soft, _runup(soft, duration=0.3, mean_window=0.1))
    message = str(error.value)
    # hand calculation: the carrier torque T = 10 N m reaches N = 3 planets at
    # r_c = 96.9 mm; each planet's sun and ring forces are equal (moment balance) and
    # their tangential parts 2 F cos(24.6 deg) carry T/(N r_c): F = 18.92 N, and
    # F / k = 1.89 mm at k = 1e4 N/m, beyond the 1 mm limit
    force = 10.0 / (2 * 3 * 96.9e-3 * math.cos(math.radians(24.6)))
    assert f"{force / 1e4 * 1e3:.3g} mm" == "1.89 mm"
    assert "scenes.runup.transient.deflection_limit" in message
    assert "1.89 mm" in message and "stiffness" in message and "predictor" not in message


def test_run_stopped_by_a_soft_mesh_names_it_not_the_predictor(study_case):
    soft = study_case
    for mesh in ("sun_mesh", "ring_mesh"):
        soft = replace_parameter(soft, f"planetary.{mesh}.stiffness", 3e4)
    # the load balances the drive from t = 0 (T_D / i, i = 1 + r_br/r_bs): the meshes
    # are loaded suddenly and overshoot their static deflection (hand calculation as
    # above: 18.92 N / 3e4 N/m = 0.631 mm) by up to twice, beyond the 1 mm limit
    ratio = 1 + 137.5 / 38.7
    scene = _runup(soft, duration=0.2, mean_window=0.1, load=TorqueLaw.constant(10.0 / ratio))
    with pytest.raises(TransientError) as error:
        run_transient(soft, scene)
    message = str(error.value)
    assert "exceeds deflection_limit" in message and "soft mesh" in message
    assert "0.631 mm" in message and "predictor" not in message


# --- 7. every scene checked before the first runs ----------------------------------------------


def test_later_scene_probe_target_is_checked_before_the_first_scene_runs(tmp_path, capsys):
    case_dir = _case_dir(
        tmp_path,
        "late_probe",
        """
        runup = study.scene("runup")
        short = dataclasses.replace(runup.transient, duration=0.2, mean_window=0.1)
        bad = dataclasses.replace(short, probes=(Probe("speed", "planetary.moon"),))
        case = dataclasses.replace(
            study,
            scenes=(
                dataclasses.replace(runup, name="first", analyses=("transient",),
                                    transient=short),
                dataclasses.replace(runup, name="second", analyses=("transient",),
                                    transient=bad),
            ),
        )
        """,
    )
    out = tmp_path / "out"
    assert main(["run", str(case_dir), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "scenes.second.transient.probes[0].target" in err
    assert not list(out.rglob("*.nc"))  # the first scene did not run


def test_signal_band_above_nyquist_is_refused_when_the_case_loads(study_case):
    scene = dataclasses.replace(
        study_case.scene("runup"),
        transient=dataclasses.replace(study_case.scene("runup").transient, sample_rate=20e3),
    )
    with pytest.raises(CaseError) as error:
        dataclasses.replace(study_case, scenes=(scene,))
    message = str(error.value)
    assert message.startswith("scenes.runup.transient.sample_rate")
    assert "Nyquist" in message and "10000 Hz" in message


# --- 8. runs too large for the machine, NumPy scalars -------------------------------------------


def test_transient_larger_than_memory_is_refused_with_the_estimate(study_case, monkeypatch):
    from pygear import resources

    monkeypatch.setattr(resources, "available_memory", lambda: 1e9)
    scene = _runup(study_case, duration=2000.0)  # 10 probes at 40 kHz for 2000 s
    with pytest.raises(CaseError) as error:
        transient_problem(study_case, scene)
    message = str(error.value)
    # 10 channels x (8e7 steps / 1 + 1) samples x 8 bytes, held twice (the kernel's
    # record and the dataset written from it): 12.8 GB
    samples = round(2000.0 / 2.5e-5) + 1
    estimate = 2 * 10 * samples * 8
    assert message.startswith("scenes.runup.transient.duration")
    shown = float(re.search(r"about ([\d.]+) GB of memory", message).group(1))
    assert shown == pytest.approx(estimate / 1e9, rel=0.01)
    assert "1 GB" in message and "\n" not in message


def test_transient_larger_than_the_disk_is_refused(study_case, tmp_path, monkeypatch):
    from pygear import resources
    from pygear.runs.transient_outputs import write_transient

    monkeypatch.setattr(resources, "available_disk", lambda path: 1e6)
    scene = _runup(study_case, duration=0.5, mean_window=0.1)  # 10 x 20001 samples: 1.6 MB
    with pytest.raises(CaseError, match=r"of disk space .* 1 MB"):
        write_transient(study_case, scene, tmp_path)
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    "argv",
    [
        [
            "sensitivity",
            str(STUDY),
            "--parameter",
            "planetary.sun_mesh.stiffness",
            "--values",
            "linspace(1e8,1e9,1e12)",
        ],
        ["sweep", str(STUDY), "--param", "planetary.sun_mesh.stiffness=linspace(1e8,1e9,1e12)"],
        ["mesh-stiffness", str(STUDY), "--duration", "1e6"],
        [
            "sweep",
            str(STUDY),
            "--param",
            "planetary.sun_mesh.stiffness=linspace(1e8,1e9,1e6)",
            "--param",
            "planetary.ring_mesh.stiffness=linspace(1e8,1e9,1e6)",
        ],  # each list fits, their grid of 1e12 points does not
    ],
    ids=["sensitivity", "sweep", "mesh-stiffness", "sweep-grid"],
)
def test_huge_commands_are_refused_with_an_estimate(argv, tmp_path, capsys):
    argv = [*argv, "--out", str(tmp_path / ("m.nc" if argv[0] == "mesh-stiffness" else "out"))]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "memory" in err and "available" in err
    assert not list(tmp_path.rglob("*.nc"))


def test_numpy_scalars_are_accepted_where_numbers_are(study_case):
    changes = {
        "planetary.sun.mass": np.float32(0.4),
        "planetary.sun.teeth": np.int64(27),
        "planetary.planets": np.int64(3),
        "planetary.sun_mesh.stiffness": np.float32(5e8),
        "damping.mass_coefficient": np.float32(0.13),
    }
    case = study_case
    for path, value in changes.items():
        case = replace_parameter(case, path, value)
    plain = study_case
    for path, value in changes.items():
        plain = replace_parameter(plain, path, value.item())
    stage = case.gearbox.stages[0]
    assert type(stage.sun.teeth) is int and type(stage.sun.mass) is float
    assert case.input_hash() == plain.input_hash()  # stored as the Python numbers they hold
    frequencies, _ = solve_eigenproblem(assemble(case))
    assert np.all(np.isfinite(frequencies))
    settings = dataclasses.replace(
        study_case.scene("runup").transient,
        duration=np.float32(1.5),
        max_iterations=np.int64(20),
        restart_at_jumps=np.bool_(False),
        mean_window=np.float64(0.25),
    )
    scene = dataclasses.replace(study_case.scene("runup"), transient=settings)
    loaded = dataclasses.replace(study_case, scenes=(scene,))
    assert type(loaded.scenes[0].transient.max_iterations) is int
    settings.validate("scenes.runup.transient")  # also before a case stores plain numbers


# --- 7. tooth faults (issue #27.4) ------------------------------------------------------------

SEQUENTIAL = ROOT / "cases" / "sequential_planetary"


def _with_fault(case, fault):
    from pygear import ToothDefect

    return dataclasses.replace(case, defects=(ToothDefect("planetary.sun", 3, fault=fault),))


def test_spall_off_the_tooth_is_refused_when_the_case_loads():
    # the sun (z 29, m 3 mm): flank from its root form circle (41.33 mm) to its tip
    # (m (z/2 + 1) = 46.5 mm); 42 typed for 42 mm is 42 m, a spall that changed nothing
    from pygear.model.tooth_faults import Spall

    case = load_case(SEQUENTIAL)
    _with_fault(case, Spall(1, 42e-3, 1e-3, 0.1e-3, 10e-3)).validate()
    rule = (
        r"^defects\[0\]\.fault\.centre_radius = 42\.0 m .* off the loaded flank: .* root form "
        r"radius 41\.33 mm .* tip radius 46\.5 mm"
    )
    with pytest.raises(CaseError, match=rule):
        _with_fault(case, Spall(1, 42.0, 1e-3, 0.1e-3, 10e-3)).validate()


def test_crack_through_the_tooth_names_its_depth():
    from pygear.model.tooth_faults import RootCrack

    with pytest.raises(CaseError, match=r"^defects\[0\]\.fault\.depth = 5\.0 m .* circular pitch"):
        _with_fault(load_case(SEQUENTIAL), RootCrack(1, 5.0, 45.0)).validate()


@pytest.mark.parametrize(
    ("spall", "named"),
    [
        ((0.031, 1e-3, 3e-3, 0.01), r"fault\.depth = 0\.003"),  # deeper than the tooth
        ((0.029, 6e-3, 1e-4, 0.01), r"fault\.length = 0\.006"),  # below the base circle
    ],
)
def test_fault_the_kernel_refuses_is_named_by_its_own_parameter(spall, named):
    # the kernel packs a spall's centre_radius, length, depth as slots a, b, c: its
    # message used to blame fault.c (or fault.a) instead of the parameter typed
    from pygear.assembly.tooth_stiffness import ToothBody, mesh_stiffness
    from pygear.model import GearGeometry, MeshGeometry
    from pygear.model.tooth_faults import Spall

    pair = MeshGeometry(GearGeometry(19, 3.2e-3, 0.016), GearGeometry(48, 3.2e-3, 0.016))
    bodies = (ToothBody(2.068e11, 0.3, 0.01), ToothBody(2.068e11, 0.3, 0.03))
    with pytest.raises(CaseError, match=named) as error:
        mesh_stiffness(pair, bodies, fault=Spall(1, *spall))
    assert not re.search(r"fault\.[abc]\b", str(error.value))


# --- 8. planet assembly (issue #27.21) ----------------------------------------------------------
# Z_s + Z_r = 27 + 96 = 123 for the study case: a planet assembles at whole multiples of
# 360/123 = 2.926829 deg from the first (sun and ring teeth both engage).


def _stage_with(study_case, **change):
    stage = dataclasses.replace(study_case.gearbox.stages[0], **change)
    return stage


def test_typed_equal_angles_that_cannot_assemble_name_the_angles_and_the_nearest(study_case):
    # 123/4 is not whole; 90 deg is 30.75 steps: the nearest assemblable angles are 31, 62
    # and 92 steps: 90.7317, 181.463, 269.268 deg
    stage = _stage_with(study_case, planets=4, planet_angles_deg=(0.0, 90.0, 180.0, 270.0))
    with pytest.raises(CaseError) as error:
        stage.validate()
    message = str(error.value)
    assert message.startswith("planetary.planet_angles_deg: 4 equally spaced planets")
    assert "(0, 90.7317, 181.463, 269.268) deg" in message
    assert "give planet_angles_deg" not in message  # they were given


def test_planet_count_without_angles_still_suggests_angles(study_case):
    with pytest.raises(CaseError, match=r"^planetary\.planets: .*give planet_angles_deg, e\.g\. "
                       r"the nearest that assemble: \(0, 90\.7317"):  # fmt: skip
        _stage_with(study_case, planets=4).validate()


def test_angles_that_cannot_assemble_warn_with_the_nearest_that_do(study_case):
    # 110 deg is 37.58 steps (0.42 of a tooth pitch off): nearest 38 steps = 111.22 deg
    stage = _stage_with(study_case, planet_angles_deg=(0.0, 110.0, 240.0))
    with pytest.warns(PlausibilityWarning, match=r"planet 2 at 110\.0 deg cannot be assembled"
                      r".*\(0, 111\.22, 240\) deg"):  # fmt: skip
        stage.validate()


def test_small_planet_position_error_is_a_study_not_a_warning(study_case):
    # the study case's scene puts planet 2 at 120.1 deg: 0.034 of a pitch off, a
    # deliberate carrier pin-hole error within ASSEMBLY_TOLERANCE
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        _stage_with(study_case, planet_angles_deg=(0.0, 120.1, 240.0)).validate()


# --- 9. time step against the mesh period (issue #27.5) ---------------------------------------


def _steady_at(case, rpm: float):
    scene = case.scene("steady_sensor")
    transient = dataclasses.replace(scene.transient, initial_speed_rpm=rpm, speed_reference_rpm=rpm)
    scene = dataclasses.replace(scene, transient=transient)
    return dataclasses.replace(case, scenes=(scene,))


def test_time_step_spanning_many_mesh_periods_is_refused():
    # Z_r = 97 ring teeth pass a held ring Z_r n_c / 60 times a second: at 1e7 rpm 1.617e7
    # Hz, so the 24.9 us step spans some 400 mesh periods (0.0025 steps per period)
    case = load_case(SEQUENTIAL)
    with pytest.raises(CaseError, match=r"^scenes\.steady_sensor\.transient\.time_step = .* "
                       r"initial_speed_rpm = 1e\+07 rpm stage planetary meshes at 1\.617e\+07 Hz, "
                       r"0\.00248 steps per mesh period; at least 10"):  # fmt: skip
        _steady_at(case, 1e7).validate()


@pytest.mark.parametrize(("steps", "refused"), [(9.5, True), (10.5, False), (207.0, False)])
def test_time_step_rule_is_ten_steps_per_mesh_period(steps, refused):
    case = load_case(SEQUENTIAL)
    dt = case.scene("steady_sensor").transient.time_step
    rpm = 60.0 / (97 * steps * dt)  # the speed at which one mesh period is `steps` steps
    if refused:
        with pytest.raises(CaseError, match="steps per mesh period"):
            _steady_at(case, rpm).validate()
    else:
        _steady_at(case, rpm).validate()


def test_mesh_events_follow_the_nrel_stages_from_the_rotor():
    # Nejad et al. (2016) Table V: ring 56 teeth on the rotor's carrier, stage 2's ring
    # (93) on the sun of stage 1 (1 + 56/19 rotor speeds), the 95-tooth wheel on stage
    # 2's sun ((1 + 56/19)(1 + 93/18)): 56, 367.1 and 2312.5 engagements per rotor turn
    from pygear.model.time_step import mesh_events_per_input_turn

    events = mesh_events_per_input_turn(load_case(ROOT / "cases" / "nrel5mw_gearbox").gearbox)
    first = 1 + 56 / 19
    assert events["stage1"] == pytest.approx(56.0, rel=1e-12)
    assert events["stage2"] == pytest.approx(93 * first, rel=1e-3)  # base radii, rounded
    assert events["parallel"] == pytest.approx(95 * first * (1 + 93 / 18), rel=1e-3)


# --- 10. probes say where the case wrote them (issue #27.21) -----------------------------------


def test_probe_error_names_the_line_of_the_case_file_that_wrote_it(tmp_path, capsys):
    # the second probe, written on line 8 of case.py (3 header lines, the body's blank
    # first line, then its 4th); the command line names the line that built the case
    case_dir = _case_dir(
        tmp_path,
        "probe_line",
        """
        runup = study.scene("runup")
        probes = (
            Probe("speed", "planetary.sun"),
            Probe("speed", "planetary.carrier", name="t_s"),
        )
        settings = dataclasses.replace(runup.transient, probes=probes)
        case = dataclasses.replace(study, scenes=(dataclasses.replace(runup, transient=settings),))
        """,
    )
    assert main(["show-case", str(case_dir)]) == 2
    err = capsys.readouterr().err.strip()
    assert "probes[1].name" in err
    assert err.endswith("(written at probe_line/case.py:8)")
    assert len(err.splitlines()) == 1


def test_probe_target_error_names_its_own_index_and_a_true_plural(study_case):
    # a scene's probes are compiled one at a time (sensors in between), so the message
    # once named every bad probe probes[0]; and listed "meshs" and "bodys"
    from pygear.analysis.time.transient import transient_problem

    runup = study_case.scene("runup")
    good = runup.transient.probes[:2]
    for bad, plural in (
        (Probe("mesh_force", "planetary.moon-planet1"), "(meshes: "),
        (Probe("speed", "planetary.moon"), "(bodies: "),
    ):
        settings = dataclasses.replace(runup.transient, probes=(*good, bad))
        scene = dataclasses.replace(runup, transient=settings)
        with pytest.raises(CaseError) as error:
            transient_problem(study_case, scene)
        message = str(error.value)
        assert f"transient.probes[{len(good)}].target" in message
        assert plural in message
        assert "meshs" not in message and "bodys" not in message
