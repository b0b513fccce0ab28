"""Bad input table and a fuzz of the case loader.

Every rejected input below, from case files, scenes and the command line, must be
refused with a :class:`CaseError` (exit code 2 on the command line) whose message
names the parameter path and the rule.  The fuzz mutates the study case at random
(non-finite, negative, zero, huge and wrongly typed values, unknown names): every
failure must be a ``CaseError`` naming a path, and every accepted case must give
finite natural frequencies (never a silent NaN).
"""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import CASES
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pygear import CaseError, Probe, Scene, TorqueLaw, load_case
from pygear.analysis.modes.modal import solve_eigenproblem
from pygear.assembly import assemble
from pygear.cli import main
from pygear.model.case import get_parameter, replace_parameter

CASE = str(Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary")

# --- case files -----------------------------------------------------------------------------

CASE_FILE_INPUTS = [
    (
        "planetary.sun.mass",
        math.nan,
        "planetary.sun.mass must be a positive finite number (got nan)",
    ),
    (
        "planetary.carrier.polar_inertia",
        math.inf,
        "planetary.carrier.polar_inertia must be a positive finite number (got inf)",
    ),
    (
        "planetary.sun_mesh.stiffness",
        -math.inf,
        "planetary.sun_mesh.stiffness must be a positive finite number (got -inf)",
    ),
    (
        "planetary.planet.mass",
        "0.66",
        "planetary.planet.mass must be a positive finite number (got '0.66')",
    ),
    (
        "planetary.sun.mass",
        1e300,
        "planetary.sun.mass must be a positive finite number between 1e-15 and 1e+15 "
        "in SI units (got 1e+300)",
    ),
    (
        "planetary.ring_bearing.torsional",
        math.nan,
        "planetary.ring_bearing.torsional must be a finite number >= 0 (got nan)",
    ),
    (
        "planetary.sun_mesh.pressure_angle_deg",
        math.radians(24.6),
        "planetary.sun_mesh.pressure_angle_deg must be given in degrees: 0.4293509",
    ),
    (
        "planetary.ring_mesh.pressure_angle_deg",
        math.radians(24.6),
        "looks like radians (= 24.6 deg)",
    ),
    (
        "planetary.ring_mesh.pressure_angle_deg",
        60.0,
        "planetary.ring_mesh.pressure_angle_deg must lie in (0, 45) degrees (got 60.0)",
    ),
    (
        "planetary.base_helix_angle_deg",
        math.radians(20.0),
        "planetary.base_helix_angle_deg must be given in degrees (0 for spur gears): "
        "0.3490658503988659 looks like radians (= 20 deg)",
    ),
    (
        "planetary.planet_angles_deg",
        (0.0, 2 * math.pi / 3, 4 * math.pi / 3),
        "the angles look like radians: in degrees they are (0, 120, 240)",
    ),
    (
        "planetary.planet_angles_deg",
        (0.0, math.nan, 240.0),
        "planetary.planet_angles_deg must be finite numbers",
    ),
    (
        "planetary.planet_angles_deg",
        120.0,
        "planetary.planet_angles_deg must be a sequence of angles in degrees, one per planet",
    ),
    (
        "planetary.planet_angles_deg",
        (0.0, 120.0),
        "planetary.planet_angles_deg must list one angle per planet (2 given for 3 planets)",
    ),
    (
        "planetary.carrier.radius",
        0.05,
        "planetary.carrier.radius: the geometry is impossible: sun + planet base_radius = "
        "88.9 mm must lie between cos(45 deg) r_c and r_c = 50 mm",
    ),
    (
        "planetary.carrier.radius",
        0.2,
        "planetary.carrier.radius: the geometry is impossible: sun + planet base_radius = "
        "88.9 mm must lie between cos(45 deg) r_c and r_c = 200 mm",
    ),
    (
        "planetary.ring.base_radius",
        0.2,
        "the geometry is impossible: ring - planet base_radius = 149.8 mm",
    ),
    (
        "planetary.ring.base_radius",
        0.04,
        "planetary.ring.base_radius must exceed planetary.planet.base_radius",
    ),
    (
        "planetary.sun_mesh.contact_ratio",
        0.9,
        "planetary.sun_mesh.contact_ratio must exceed 1 for a spur mesh (got 0.9)",
    ),
    (
        "planetary.ring_mesh.contact_ratio",
        1e6,
        "planetary.ring_mesh.contact_ratio must be below 10 tooth pairs (got 1000000.0)",
    ),
    (
        "planetary.sun_mesh.end_to_peak",
        1.5,
        "planetary.sun_mesh.end_to_peak must lie in (0, 1] (got 1.5)",
    ),
    ("planetary.sun.teeth", 27.5, "planetary.sun.teeth must be a whole number >= 3 (got 27.5)"),
    ("planetary.planets", 10**9, "planetary.planet_angles_deg: neighbouring planets"),
    ("planetary.planets", 4, r"(Z_s + Z_r)/N must be a whole number (got 123/4)"),
    (
        "planetary.mesh_phases",
        {"sun-planet9": 0.1},
        "planetary.mesh_phases: no mesh named 'sun-planet9' in this stage",
    ),
    (
        "planetary.mesh_phases",
        {"sun-planet1": 1.5},
        "planetary.mesh_phases['sun-planet1'] must lie in [0, 1) mesh cycles (got 1.5)",
    ),
    ("planetary.name", "planetary stage", "stage names must be identifiers"),
    ("planetary.name", [1.0], "gearbox.stages: stage names must be identifiers (got [[1.0]])"),
    (
        "planetary.axial_position",
        1e300,
        "planetary.axial_position must be a finite position within 100 m of the gearbox origin",
    ),
    (
        "damping.stiffness_coefficient",
        math.inf,
        "damping.stiffness_coefficient must be a finite number >= 0 (got inf)",
    ),
    (
        "formulation",
        "yang",
        "formulation must be one of improved, consistent, lin-parker (got 'yang')",
    ),
    (
        "planetary.sun.mass_kg",
        1.0,
        "parameter 'planetary.sun.mass_kg': 'mass_kg' is not a field of Gear",
    ),
    ("gearbox.sun.mass", 1.0, "parameter 'gearbox.sun.mass' must start with a stage name"),
]


@pytest.mark.parametrize(
    ("parameter", "value", "message"),
    CASE_FILE_INPUTS,
    ids=[f"{p}={v!r}"[:60] for p, v, _ in CASE_FILE_INPUTS],
)
def test_case_file_input_is_refused(study_case, parameter, value, message):
    with pytest.raises(CaseError) as error:
        replace_parameter(study_case, parameter, value)
    assert message in str(error.value)


GEARBOX_INPUTS = [
    (
        "parallel.axial_position",
        1e300,
        "parallel.axial_position must be a finite position within 100 m of the gearbox origin",
    ),
    (
        "parallel.axial_position",
        math.nan,
        "parallel.axial_position must be a finite position within 100 m of the gearbox origin",
    ),
    ("parallel.overlap_ratio", -0.37, "parallel.overlap_ratio must be a finite number >= 0"),
    ("parallel.input_gear.teeth", 0, "parallel.input_gear.teeth"),
]


@pytest.mark.parametrize(("parameter", "value", "message"), GEARBOX_INPUTS)
def test_gearbox_input_is_refused(parameter, value, message):
    """The gearbox case's parallel stage has the same rules as a planetary stage."""
    gearbox = load_case(CASES / "yang2016_gearbox")
    with pytest.raises(CaseError) as error:
        replace_parameter(gearbox, parameter, value)
    assert message in str(error.value)


# --- scenes ---------------------------------------------------------------------------------


def _transient(study_case, **change):
    return dataclasses.replace(study_case.scene("runup").transient, **change)


SCENE_INPUTS = [
    (lambda c: Scene("s", effects=("backlash",)), "scenes.s.effects must be one of"),
    (lambda c: Scene("s", analyses=("fft",)), "scenes.s.analyses must be one of"),
    (lambda c: Scene("s", formulation="yang"), "scenes.s.formulation must be one of"),
    (
        lambda c: Scene("s", carrier_speed_rpm=math.nan),
        "scenes.s.carrier_speed_rpm must be a finite number (got nan)",
    ),
    (
        lambda c: Scene("s", carrier_speed_rpm="120"),
        "scenes.s.carrier_speed_rpm must be a finite number (got '120')",
    ),
    (
        lambda c: Scene("../elsewhere"),
        "scenes[0].name must be a non-empty name without path separators",
    ),
    (
        lambda c: Scene("s", parameters={"planetary.sun.mass": -1.0}),
        "scenes.s.parameters: planetary.sun.mass must be a positive finite number (got -1.0)",
    ),
    (
        lambda c: Scene("s", parameters={"planetary.planet_angles_deg": (0.0, 2.0944, 4.18879)}),
        "scenes.s.parameters: planetary.planet_angles_deg: neighbouring planets",
    ),
    (
        lambda c: Scene("s", parameters={"planetary.moon.mass": 1.0}),
        "scenes.s.parameters: parameter 'planetary.moon.mass': 'moon' is not a field",
    ),
    (
        lambda c: Scene("s", analyses=("transient",), transient=_transient(c, time_step=math.nan)),
        "scenes.s.transient.time_step must be a positive finite number (got nan)",
    ),
    (
        lambda c: Scene(
            "s",
            analyses=("transient",),
            transient=_transient(c, drive=TorqueLaw.constant(math.inf)),
        ),
        "scenes.s.transient.drive.torque must be a finite number (got inf)",
    ),
    (
        lambda c: Scene(
            "s", analyses=("transient",), transient=_transient(c, speed_reference_rpm=-120.0)
        ),
        "scenes.s.transient.speed_reference_rpm must be a positive finite number (got -120.0)",
    ),
    (
        lambda c: Scene(
            "s",
            analyses=("transient",),
            transient=_transient(c, probes=(Probe("pressure", "planetary.sun"),)),
        ),
        "scenes.s.transient.probes[0].quantity must be one of",
    ),
    (
        lambda c: Scene(
            "s", analyses=("transient",), transient=_transient(c, load=TorqueLaw("brake", 1.0))
        ),
        "scenes.s.transient.load.kind must be one of constant, ramp, table, generator",
    ),
]


@pytest.mark.parametrize(("build", "message"), SCENE_INPUTS, ids=[m[:50] for _, m in SCENE_INPUTS])
def test_scene_input_is_refused(study_case, build, message):
    with pytest.raises(CaseError) as error:
        dataclasses.replace(study_case, scenes=(build(study_case),))
    assert message in str(error.value)


def test_case_name_must_name_files(study_case):
    with pytest.raises(CaseError, match="name must be a non-empty name without path separators"):
        dataclasses.replace(study_case, name="out/../x")


# --- command line ---------------------------------------------------------------------------

COMMAND_LINE_INPUTS = [
    (["modal", "no_such_case"], "pygear modal: error: CASE 'no_such_case': no case.py found"),
    (["run", CASE, "--scene", "nothing"], "case 'yang2016_planetary' has no scene 'nothing'"),
    (
        ["run", CASE, "--scene", "runup", "--checkpoint-every", "nan"],
        "--checkpoint-every must be a positive number of seconds (got nan)",
    ),
    (
        ["run", CASE, "--scene", "runup", "--checkpoint-every", "-5"],
        "--checkpoint-every must be a positive number of seconds (got -5.0)",
    ),
    (
        ["mesh-stiffness", CASE, "--speed", "inf", "--out", "{tmp}/m.nc"],
        "--speed must be a finite non-zero carrier speed in rpm (got inf)",
    ),
    (
        ["mesh-stiffness", CASE, "--duration", "-1", "--out", "{tmp}/m.nc"],
        "--duration must be a positive number of seconds (got -1.0)",
    ),
    (
        ["sensitivity", CASE, "--parameter", "planetary.sun_mesh.stiffness", "--values", "nan"],
        "--values must be finite numbers",
    ),
    (
        ["sensitivity", CASE, "--parameter", "planetary.sun_mesh.stiffness", "--values", "1e300"],
        "planetary.sun_mesh.stiffness must be a positive finite number between 1e-15 and 1e+15",
    ),
    (
        ["sensitivity", CASE, "--parameter", "planetary.sun.mass", "--values", "1"],
        "is not a stiffness of this model",
    ),
    (["analyze", "{tmp}/missing.nc"], "does not exist"),
]


@pytest.mark.parametrize(
    ("argv", "message"),
    COMMAND_LINE_INPUTS,
    ids=[" ".join(a[:2]) + "|" + m[:30] for a, m in COMMAND_LINE_INPUTS],
)
def test_command_line_input_is_refused(argv, message, tmp_path, capsys):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    if "--out" not in argv and argv[0] in ("run", "sensitivity"):
        argv += ["--out", str(tmp_path / "out")]
    assert main(argv) == 2
    assert message in capsys.readouterr().err
    assert not list(tmp_path.rglob("*.nc"))  # refused before any work


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["modal", CASE, "--formulation", "yang"], "invalid choice: 'yang'"),
        (["modal", CASE, "--dof-set", "3d"], "invalid choice: '3d'"),
        (["run", CASE, "--checkpoint-every", "soon"], "invalid float value: 'soon'"),
    ],
)
def test_command_line_syntax_is_refused(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 2
    assert message in capsys.readouterr().err


# --- fuzz of the case loader ----------------------------------------------------------------


def _leaves(obj: object, prefix: str) -> list[str]:
    paths = []
    for spec in dataclasses.fields(obj):
        if not spec.init:
            continue
        value = getattr(obj, spec.name)
        path = f"{prefix}.{spec.name}"
        paths += _leaves(value, path) if dataclasses.is_dataclass(value) else [path]
    return paths


SPECIAL = [math.nan, math.inf, -math.inf, 0, 0.0, -1.0, 1e300, -1e300, 1e-300, 2**63, 10**9]
WRONG_TYPES = ["5", None, True, [1.0], (), "nonsense", b"1", {"a": 1}]


def _mutations(study_case, path: str) -> st.SearchStrategy:
    original = get_parameter(study_case, path)
    strategy = st.sampled_from(SPECIAL + WRONG_TYPES)
    if isinstance(original, (int, float)) and not isinstance(original, bool):
        strategy |= st.floats(allow_nan=True, allow_infinity=True)
        strategy |= st.floats(1e-3, 1e3).map(lambda f: original * f) | st.just(-original)
        if isinstance(original, int):
            strategy |= st.integers(-10, 10**6)
    if path.endswith("planet_angles_deg"):
        strategy |= st.just((0.0, 2 * math.pi / 3, 4 * math.pi / 3))
        strategy |= st.lists(st.floats(allow_nan=True), min_size=0, max_size=5).map(tuple)
        strategy |= st.lists(st.floats(-720, 720), min_size=3, max_size=3).map(tuple)
    if path.endswith("stiffness_curve"):
        strategy |= st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=4).map(tuple)
    if path.endswith("mesh_phases"):
        names = st.sampled_from(["sun-planet1", "ring-planet3", "sun-planet9", "", "x"])
        strategy |= st.dictionaries(names, st.floats(allow_nan=True, allow_infinity=True))
    if path.endswith("name") or path == "formulation":
        strategy |= st.text(max_size=12) | st.sampled_from(["consistent", "lin-parker"])
    return strategy


@pytest.fixture(scope="module")
def fuzz_base(study_case):
    """The study case without scenes (their run-up settings are checked above)."""
    case = dataclasses.replace(study_case, scenes=(Scene("modal"),))
    paths = _leaves(case.gearbox.stages[0], "planetary")
    paths += ["damping.mass_coefficient", "damping.stiffness_coefficient", "formulation"]
    return case, paths


PATH_PATTERN = re.compile(r"\b[A-Za-z_]\w*\.[A-Za-z_]\w*")


@settings(
    max_examples=150,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(data=st.data())
def test_fuzzed_case_fails_clearly_or_gives_finite_frequencies(fuzz_base, data):
    case, paths = fuzz_base
    tried = []
    try:
        for _ in range(data.draw(st.integers(1, 3), label="mutations")):
            path = data.draw(st.sampled_from(paths), label="path")
            value = data.draw(_mutations(case, path), label="value")
            tried.append(path)
            case = replace_parameter(case, path, value)
        model = assemble(case)
        frequencies, _ = solve_eigenproblem(model)
    except CaseError as error:
        message = str(error)
        field_name = tried[-1].rsplit(".", 1)[-1]
        assert field_name in message or PATH_PATTERN.search(message), message
        return
    assert frequencies.shape == (model.size,)
    assert np.all(np.isfinite(frequencies)), (tried, frequencies)
    assert frequencies.min() > -1e-3 * frequencies.max()
