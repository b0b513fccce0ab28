"""The ``response`` scene analysis: its settings and their refusals, ``pygear run``
through the scene runner, and ``pygear sweep`` over a planet pin error, each against
direct :func:`forced_response` calls."""

from __future__ import annotations

import dataclasses
import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from pygear import Scene, load_case
from pygear.analysis.response import forced_response
from pygear.cli import main
from pygear.errors import CaseError
from pygear.io import open_dataset
from pygear.model.response_settings import Response

ROOT = Path(__file__).resolve().parent.parent
PLANETARY = ROOT / "cases" / "yang2016_planetary"
SPEEDS = (600.0, 900.0, 3)
PIN = "scene.response.pin_errors.planetary.planet1"
PIN_DIM = "scene__response__pin_errors__planetary__planet1"

CASE_FILE = textwrap.dedent(
    f"""
    import dataclasses
    from pygear import Scene, load_case
    from pygear.model.response_settings import Response

    base = load_case(r"{PLANETARY}")
    scene = Scene("resp", analyses=("response",), formulation="improved", dof_set="planar",
                  effects=("time_varying_mesh_stiffness",),
                  response=Response(speeds_rpm={SPEEDS!r}, harmonics=16))
    case = dataclasses.replace(base, scenes=base.scenes + (scene,))
    """
)
"""The study case with a short response scene (3 speeds, 16 harmonics)."""


@pytest.fixture(scope="module")
def case_dir(tmp_path_factory) -> Path:
    directory = tmp_path_factory.mktemp("cases") / "planetary_response"
    directory.mkdir()
    (directory / "case.py").write_text(CASE_FILE)
    return directory


def _scene(**response) -> Scene:
    settings = {"speeds_rpm": SPEEDS, "harmonics": 16, **response}
    return Scene("resp", analyses=("response",), dof_set="planar",
                 effects=("time_varying_mesh_stiffness",),
                 response=Response(**settings))  # fmt: skip


@pytest.mark.parametrize(
    ("settings", "parameter"),
    [
        ({"speeds_rpm": (0.0, 900.0, 3)}, "speeds_rpm"),
        ({"speeds_rpm": (900.0, 600.0, 3)}, "speeds_rpm"),
        ({"speeds_rpm": (600.0, 900.0, 2.5)}, "speeds_rpm"),
        ({"speeds_rpm": (600.0, 600.0, 3)}, "speeds_rpm"),
        ({"speeds_rpm": (600.0, 900.0)}, "speeds_rpm"),
        ({"harmonics": -1}, "harmonics"),
        ({"harmonics": 2000}, "harmonics"),
        ({"harmonics": 0, "contact_loss": True}, "harmonics"),
        ({"tolerance": 0.0}, "tolerance"),
        ({"torque": -10.0}, "torque"),
        ({"torque": float("nan")}, "torque"),
        ({"contact_loss": "yes"}, "contact_loss"),
        ({"pin_errors": {"planetary.planet1": "big"}}, "pin_errors"),
    ],
)
def test_bad_settings_are_refused_naming_the_parameter(settings, parameter):
    with pytest.raises(CaseError, match=rf"scenes\.resp\.response\.{parameter}") as error:
        _scene(**settings).validate("scenes.resp")
    assert "\n" not in str(error.value)


def test_response_analysis_needs_its_settings():
    with pytest.raises(CaseError, match=r"scenes\.resp\.response: the response analysis needs"):
        Scene("resp", analyses=("response",)).validate("scenes.resp")


def test_study_case_response_scene():
    """The shipped scene validates and spans the range the response page documents."""
    scene = load_case(PLANETARY).scene("response")
    assert scene.response.speeds_rpm == (250.0, 1500.0, 200)
    assert scene.response.speeds[1] - scene.response.speeds[0] == pytest.approx(1250 / 199)


def test_run_writes_what_forced_response_gives(case_dir, tmp_path, capsys):
    """``pygear run --scene resp`` writes resp_response.nc and its figures; its values
    are those of a direct forced_response with the scene's settings (the same
    computation: to 1e-12 relative)."""
    assert main(["run", str(case_dir), "--scene", "resp", "--out", str(tmp_path)]) == 0
    capsys.readouterr()
    case = load_case(case_dir)
    direct = forced_response(case, np.linspace(*SPEEDS[:2], SPEEDS[2]), scene=case.scene("resp"),
                             harmonics=16)  # fmt: skip
    with open_dataset(tmp_path / "resp_response.nc") as written:
        np.testing.assert_allclose(written.speed.values, [600.0, 750.0, 900.0])
        for name in ("dynamic_factor", "load_sharing", "dte_rms", "floquet_multiplier"):
            np.testing.assert_allclose(written[name].values, direct[name].values, rtol=1e-12)
    for figure in ("dynamic_factor", "load_sharing", "stability"):
        assert (tmp_path / f"resp_response_{figure}.png").stat().st_size > 10_000


def test_sweep_pin_error_map_equals_direct_calls(case_dir, tmp_path, capsys, scheduler):
    """``pygear sweep --param scene.response.pin_errors.planetary.planet1=0,10e-9`` over
    the response scene: a (pin error x speed) K_gamma map whose every row equals
    forced_response with that pin error (to 1e-12: the same balance).  Independently of
    the code: the perfect stage shares exactly (K_gamma = 1 to 1e-9, its planets equally
    spaced with Z_s/N and Z_r/N whole), and 10 nm breaks the symmetry (K_gamma > 1.001;
    the floating sun takes up most of it, so far less than the 10/38 of the static mesh
    deflection; tests/test_response_sharing.py checks its linearity in the error)."""
    code = main(["sweep", str(case_dir), "--param", f"{PIN}=0,10e-9", "--scene", "resp",
                 "--scheduler", scheduler, "--out", str(tmp_path), "--json"])  # fmt: skip
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    case = load_case(case_dir)
    assert summary["points_computed"] == 2 and not summary["failures"]
    with open_dataset(summary["file"]) as swept:
        sharing = swept.load_sharing.sel(stage="planetary")
        assert sharing.dims == (PIN_DIM, "speed")
        assert swept[PIN_DIM].attrs["units"] == "m"
        for error in (0.0, 10e-9):
            direct = forced_response(case, np.linspace(*SPEEDS[:2], SPEEDS[2]),
                                     scene=case.scene("resp"), harmonics=16,
                                     pin_errors={"planetary.planet1": error})  # fmt: skip
            np.testing.assert_allclose(sharing.sel({PIN_DIM: error}).values,
                                       direct.load_sharing.values[:, 0], rtol=1e-12)  # fmt: skip
            np.testing.assert_allclose(swept.dynamic_factor.sel({PIN_DIM: error}).values,
                                       direct.dynamic_factor.values, rtol=1e-12)  # fmt: skip
        assert np.abs(sharing.sel({PIN_DIM: 0.0}).values - 1.0).max() < 1e-9
        assert sharing.sel({PIN_DIM: 10e-9}).values.min() > 1.001


def test_pin_error_needs_a_response_scene(case_dir, tmp_path, capsys):
    code = main(["sweep", str(case_dir), "--param", f"{PIN}=0,10e-9", "--scene", "modal",
                 "--out", str(tmp_path)])  # fmt: skip
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1
    assert PIN in err and "'response' analysis" in err


def test_scene_parameters_apply_once(case_dir):
    """A scene parameter changes the response: a stiffer sun mesh (scene parameter)
    shifts the dynamic factor, and the runner's case already holds it."""
    case = load_case(case_dir)
    scene = dataclasses.replace(case.scene("resp"),
                                parameters={"planetary.sun_mesh.stiffness": 9e8})  # fmt: skip
    from pygear.analysis.response import scene_response

    stiff, _ = scene_response(case.for_scene(scene), scene)
    plain, _ = scene_response(case, case.scene("resp"))
    assert not np.allclose(stiff.dynamic_factor.values, plain.dynamic_factor.values, rtol=1e-3)
