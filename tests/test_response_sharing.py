"""Planet load sharing (K_gamma) from the periodic steady state."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pygear.analysis.response import forced_response, response_system, sweep_system
from pygear.errors import CaseError
from pygear.model.case import load_case

SPEEDS = [300.0, 900.0]


@pytest.fixture(scope="module")
def study():
    return load_case("yang2016_planetary")


def _sharing(case, error: float) -> np.ndarray:
    errors = {"planetary.planet1": error} if error else None
    system = response_system(case, pin_errors=errors)
    dataset = sweep_system(system, np.array(SPEEDS), harmonics=16, stability=False)
    return dataset.load_sharing.values[:, 0]


def test_perfect_stage_shares_equally(study):
    """Equally spaced planets with Z_s / N and Z_r / N whole: every planet's meshes are
    in phase and the stage is cyclically symmetric, so the mean sun-mesh forces agree
    to round-off (1e-12) with the time-varying stiffness too."""
    assert np.abs(_sharing(study, 0.0) - 1).max() < 1e-12


def test_pin_error_raises_k_gamma_and_soft_pins_lower_it(study):
    """A tangential pin error of planet 1 (5 and 10 nm against a static mesh deflection
    of 38 nm under the study case's 10 N m) loads it unlike the others: K_gamma > 1,
    growing with the error (linear model: K_gamma - 1 proportional to it, to 1e-9);
    planet bearings ten times softer take up the error with less force, so K_gamma
    falls."""
    small, large = _sharing(study, 5e-9), _sharing(study, 10e-9)
    assert (small > 1 + 1e-3).all()
    assert (large > small).all()
    assert (large - 1) == pytest.approx(2 * (small - 1), rel=1e-9)
    stage = study.gearbox.stages[0]
    soft_bearing = dataclasses.replace(
        stage.planet_bearing, radial=stage.planet_bearing.radial / 10
    )
    soft = dataclasses.replace(
        study,
        gearbox=dataclasses.replace(
            study.gearbox, stages=(dataclasses.replace(stage, planet_bearing=soft_bearing),)
        ),
    )
    assert (_sharing(soft, 10e-9) < large).all()


def test_large_pin_error_separates_teeth(study):
    """A pin error far beyond the static mesh deflection (5 um against 38 nm) pulls one
    planet's meshes apart: the linear model's force turns negative and says so."""
    system = response_system(study, pin_errors={"planetary.planet1": 5e-6})
    dataset = sweep_system(system, np.array([300.0]), harmonics=8, stability=False)
    assert dataset.separation.values.any()


def test_unknown_planet_refused(study):
    with pytest.raises(CaseError, match="no planet"):
        response_system(study, pin_errors={"planetary.planet9": 1e-6})


def test_speeds_must_be_positive(study):
    with pytest.raises(CaseError, match="speeds"):
        forced_response(study, [0.0, 100.0])
