"""``dynamic_factors_at``: the K_v per mesh at one speed that a rating takes."""

import numpy as np
import pytest

from pygear.analysis.response import dynamic_factors_at, forced_response
from pygear.errors import CaseError
from pygear.model.case import load_case


@pytest.fixture(scope="module")
def planetary():
    return load_case("yang2016_planetary")


def test_equals_the_sweep_at_that_speed(planetary):
    """The value at one speed is the sweep's at that speed (same balance, same count);
    the rating's keys take the largest over the planets."""
    factors = dynamic_factors_at(planetary, 1000.0, harmonics=32)
    sweep = forced_response(planetary, np.array([700.0, 1000.0]), harmonics=32, stability=False)
    for i, mesh in enumerate(sweep.mesh.values):
        # both solve the same 6 x 65 real system: LU round-off only
        assert factors[str(mesh)] == pytest.approx(sweep.dynamic_factor.values[1, i], rel=1e-9)
    rating = dynamic_factors_at(planetary, 1000.0, harmonics=32, keys="rating")
    assert set(rating) == {"planetary.sun_mesh", "planetary.ring_mesh"}
    sun = max(v for k, v in factors.items() if k.startswith("sun-"))
    assert rating["planetary.sun_mesh"] == pytest.approx(sun, rel=1e-12)
    assert all(v > 1.0 for v in rating.values())  # time-varying stiffness: peak above mean


@pytest.mark.parametrize(
    "kwargs, word",
    [({"speed_rpm": 0.0}, "speed_rpm"), ({"speed_rpm": 100.0, "torque": -1.0}, "torque"),
     ({"speed_rpm": 100.0, "keys": "gear"}, "keys")],
)
def test_refusals(planetary, kwargs, word):
    with pytest.raises(CaseError, match=word):
        dynamic_factors_at(planetary, **kwargs)
