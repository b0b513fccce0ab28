"""Rotor transients from case files: run-ups through critical speeds with gyroscopics.

The reference of the run-up is independent of pygear's assembly and kernel: the
rigid-disc overhung rotor written in complex coordinates (z = x + i y, phi = theta_y -
i theta_x) and integrated by SciPy's ``solve_ivp``; its forward critical speed comes
from the closed-form frequency equation at w = Omega.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import solve_ivp

from pygear.analysis.time.rotor_transient import run_rotor_transient
from pygear.cli.parser import main
from pygear.errors import CaseError
from pygear.model.drivetrain import Drivetrain, Shaft, ShaftBearing, ShaftSection
from pygear.model.rotor import Disc
from pygear.model.rotor_case import RotorCase
from pygear.model.rotor_transient import DiscUnbalance, RotorRun, RotorScene

FRISWELL = str(Path(__file__).resolve().parents[1] / "cases" / "friswell_rotor")

# overhung disc at the free end of a cantilever of negligible mass (clamp: 1e12 springs)
YOUNG, LENGTH, DIAMETER = 211e9, 0.5, 0.025
MASS, DISC_DIAMETER = 20.0, 0.7
POLAR = MASS * DISC_DIAMETER**2 / 8
DIAMETRAL = POLAR / 2
BENDING = YOUNG * math.pi * DIAMETER**4 / 64
K11, K12, K22 = 12 * BENDING / LENGTH**3, -6 * BENDING / LENGTH**2, 4 * BENDING / LENGTH
BETA = 5e-4  # shaft Rayleigh stiffness damping [s]: zeta = beta w / 2 = 2 % at 80 rad/s
UNBALANCE = 1e-4  # m e [kg m]
ACCELERATION = 5.0  # [rad/s^2]
END_SPEED = 120.0  # [rad/s]


def overhung_case(acceleration: float = ACCELERATION) -> RotorCase:
    shaft = Shaft(
        "shaft",
        (ShaftSection(LENGTH, DIAMETER),),
        young_modulus=YOUNG,
        shear_modulus=81.2e9,
        density=1.0,  # a shaft of 2.5 g against a 20 kg disc: the rigid-disc model
        elements_per_section=1,  # exact static stiffness of a uniform Euler-Bernoulli beam
        shear_deformation=False,
        rayleigh_stiffness=BETA,
    )
    disc = Disc("disc", "shaft", LENGTH, mass=MASS, polar_inertia=POLAR,
                diametral_inertia=DIAMETRAL)  # fmt: skip
    clamp = ShaftBearing("clamp", "shaft", 0.0, radial=1e12, axial=1e12, tilt=1e12)
    duration = END_SPEED / acceleration
    run = RotorRun(
        duration=duration,
        time_step=5e-4,
        times=(0.0, duration),
        speeds_rpm=(0.0, END_SPEED * 30 / math.pi),
        unbalances=(DiscUnbalance("disc", UNBALANCE),),
        sample_rate=200.0,
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the shaft's density is implausible on purpose
        case = RotorCase(
            name="overhung",
            drivetrain=Drivetrain(shafts=(shaft,), discs=(disc,), bearings=(clamp,)),
            scenes=(RotorScene("runup", run),),
        )
        case.validate()
    return case


def forward_critical_speed() -> float:
    """w = Omega in (k11 - m w^2)(k22 - I_d w^2 + I_p Omega w) = k12^2 (forward whirl):
    (k11 - m W^2)(k22 + (I_p - I_d) W^2) = k12^2, a quadratic in W^2."""
    quadratic = np.polymul([-MASS, K11], [POLAR - DIAMETRAL, K22])
    quadratic[-1] -= K12**2
    return float(np.sqrt(max(np.roots(quadratic).real)))


def standstill_frequency() -> float:
    """The lowest root of (k11 - m w^2)(k22 - I_d w^2) = k12^2 [rad/s]."""
    quartic = np.polymul([-MASS, 0.0, K11], [-DIAMETRAL, 0.0, K22])
    quartic[-1] -= K12**2
    return float(min(abs(np.roots(quartic))))


def reference_runup(times: np.ndarray) -> np.ndarray:
    """|z| of m z'' + beta (k11 z' + k12 phi') + k11 z + k12 phi = m e (W^2 - i W') e^(i psi),
    I_d phi'' - i W I_p phi' + beta (k12 z' + k22 phi') + k12 z + k22 phi = 0 with
    W = a t, psi = a t^2 / 2, by solve_ivp (DOP853, rtol 1e-9)."""
    stiffness = np.array([[K11, K12], [K12, K22]])

    def rate(t, y):
        x = y[0:2] + 1j * y[2:4]
        dx = y[4:6] + 1j * y[6:8]
        speed = ACCELERATION * t
        force = np.array([UNBALANCE * (speed**2 - 1j * ACCELERATION) * np.exp(0.5j * speed * t),
                          0.0])  # fmt: skip
        gyroscopic = np.array([0.0, -1j * speed * POLAR * dx[1]])
        ddx = (force - gyroscopic - BETA * stiffness @ dx - stiffness @ x) / [MASS, DIAMETRAL]
        return np.concatenate([dx.real, dx.imag, ddx.real, ddx.imag])

    solution = solve_ivp(rate, (0.0, times[-1]), np.zeros(8), method="DOP853", t_eval=times,
                         rtol=1e-9, atol=1e-14)  # fmt: skip
    return np.hypot(solution.y[0], solution.y[2])


def test_runup_peaks_at_the_forward_critical_speed_not_at_standstill():
    """(d) The disc's gyroscopic moment lifts its forward whirl from 61.2 rad/s at rest
    to the 80.2 rad/s critical speed; the run-up's orbit follows the independent
    integration and peaks at the critical speed, delayed by the passage (Lewis 1932)."""
    case = overhung_case()
    run = run_rotor_transient(case, case.scenes[0])
    radius = run.orbit_radius.sel(disc="disc").values
    speed = run.speed.values * math.pi / 30
    reference = reference_runup(run.time.values)
    # the trapezoidal rule's phase error, (w h)^2 / 12 per radian, accumulates on the free
    # whirl the passage starts: measured 0.5 % of the peak at h = 5e-4 and 0.13 % at
    # 2.5e-4 (second order); the shaft's 2.5 g and the clamp's 1e12 springs add ~1e-4
    assert abs(radius - reference).max() <= 1e-2 * reference.max()
    peak, reference_peak = speed[radius.argmax()], speed[reference.argmax()]
    assert abs(peak - reference_peak) <= 0.005 * reference_peak
    critical, at_rest = forward_critical_speed(), standstill_frequency()
    assert at_rest < 0.8 * critical
    # the peak comes after the critical speed, by about 2 sqrt(a) (the Jeffcott rotor's
    # passage; tests/test_newmark_gyroscopic.py), never near the standstill frequency
    assert critical < peak < critical + 3 * math.sqrt(ACCELERATION)
    assert peak - at_rest > 5 * (peak - critical)


def test_rotor_scene_runs_from_the_case_file(tmp_path, capsys):
    """``pygear run`` on the rotor case writes the run's dataset: disc displacements over
    time, the orbit radius and the speed, with units."""
    out = tmp_path / "out"
    assert main(["run", FRISWELL, "--scene", "whirl_4000rpm", "--out", str(out),
                 "--no-figures", "--json"]) == 0  # fmt: skip
    summary = json.loads(capsys.readouterr().out)
    entry = summary["scenes"]["whirl_4000rpm"]
    with xr.open_dataset(out / "whirl_4000rpm.nc") as run:
        # the usual run layout: translations over their DOF labels (docs/data_model.md)
        assert run.translation_displacement.attrs["units"] == "m"
        assert set(run.translation_dof_label.values) == {
            "disc_left.x", "disc_left.y", "disc_right.x", "disc_right.y"
        }  # fmt: skip
        assert run.speed.attrs["units"] == "rpm" and np.all(run.speed.values == 4000.0)
        right = list(run.disc_label.values).index("disc_right")
        radius = run.orbit_radius.isel(disc=right).values
        assert entry["peaks"]["disc_right"]["radius_m"] == pytest.approx(radius.max())
        assert radius[0] == 0.0 and radius.max() > 0.0


def test_unbalance_at_an_unknown_disc_is_refused():
    case = overhung_case()
    scene = RotorScene("bad", RotorRun(1.0, 1e-3, unbalances=(DiscUnbalance("rim", 1e-4),)))
    with pytest.raises(CaseError, match=r"unbalances\[0\]\.disc 'rim' is not a disc"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the shaft's density, as above
            RotorCase(name="x", drivetrain=case.drivetrain, scenes=(scene,)).validate()
    with pytest.raises(CaseError, match="times must increase strictly"):
        RotorRun(1.0, 1e-3, times=(0.0, 0.0), speeds_rpm=(0.0, 1.0)).validate("run")


def test_a_varying_speed_with_a_speed_dependent_bearing_is_refused_before_any_run():
    """A bearing table that changes with speed cannot follow a run-up: the checks
    ``pygear run`` makes before its first scene refuse it, naming the scene's speeds."""
    from pygear.model.rotor import BearingCoefficients
    from pygear.runs.scene_checks import check_scenes

    case = overhung_case()
    table = BearingCoefficients(speeds=(0.0, 1000.0), k_xx=(1e7, 2e7), k_yy=(1e7, 2e7))
    bearing = ShaftBearing("oil", "shaft", LENGTH, coefficients=table)
    drivetrain = Drivetrain(
        shafts=case.drivetrain.shafts,
        discs=case.drivetrain.discs,
        bearings=(*case.drivetrain.bearings, bearing),
    )
    steady = RotorScene("steady", RotorRun(0.01, 1e-3, speeds_rpm=(500.0,)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the shaft's density, as above
        oiled = RotorCase(name="oiled", drivetrain=drivetrain, scenes=(steady, case.scenes[0]))
        oiled.validate()
        check_scenes(oiled, [steady])  # one speed: the table at 500 rpm
        with pytest.raises(CaseError, match=r"scenes\.runup\.run\.speeds_rpm: bearing 'oil'"):
            check_scenes(oiled, list(oiled.scenes))
