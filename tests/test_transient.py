"""Tests of the banded Newmark transient (fortran/newmark.f90, pygear.kernel.newmark,
pygear.analysis.time.transient).

References: Chopra's Examples 5.3/5.4 (*Dynamics of Structures*) and the textbook
properties of average acceleration (Newmark 1959), closed-form solutions of a single
oscillator, Table 3 of Yang, Jiang & Han (2016), and the run-up time and equilibrium
speed of each formulation derived here from its inertias and kinematics
(docs/model.md §6.3).
Nothing is compared with the code's own earlier output.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import signal

import numpy as np
import pytest
import xarray as xr

from pygear import CaseError, Probe, Scene, TorqueLaw
from pygear.analysis.signals.channels import channel_names
from pygear.analysis.time.transient import run_transient, static_mesh_deflections, transient_problem
from pygear.assembly import assemble
from pygear.assembly.dof_rows import dof_row
from pygear.cli import main
from pygear.io import open_dataset
from pygear.kernel.newmark import (
    BandedNewmark,
    KernelProbe,
    LawArrays,
    MeshTerms,
    TransientError,
    TransientInterrupted,
)

CASE = "yang2016_planetary"
SCENES = {"improved": "runup", "lin-parker": "runup_lin_parker", "consistent": "runup_consistent"}


def oscillator(m: float, k: float, c: float, dt: float, **options) -> BandedNewmark:
    return BandedNewmark([[m]], [[c]], [[k]], dt, **options)


def displacement_probe(n: int, i: int = 0) -> KernelProbe:
    row = np.zeros(n)
    row[i] = 1.0
    return KernelProbe(f"u{i}", "displacement", row)


# --- integrator checks (Chopra; Newmark 1959) ---------------------------------------------


def test_chopra_average_acceleration_example():
    """Chopra, Examples 5.3/5.4: u at t = 0.1 ... 1.0 s to 1e-4."""
    m, k, zeta = 0.2533, 10.0, 0.05
    t = np.round(np.arange(0.0, 1.05, 0.1), 10)
    p = np.where(t <= 0.6, 10.0 * np.sin(np.pi * t / 0.6), 0.0)
    solver = oscillator(
        m,
        k,
        2 * zeta * math.sqrt(k * m),
        0.1,
        drive=LawArrays("table", times=t, torques=p),
        input_weights=np.array([1.0]),
    )
    result = solver.run(10, [displacement_probe(1)])
    reference = [0.0437, 0.2326, 0.6121, 1.0825, 1.4309, 1.4231, 0.9622, 0.1908, -0.6044, -1.1442]
    np.testing.assert_allclose(result.time[1:], np.arange(1, 11) * 0.1, atol=1e-12)
    np.testing.assert_allclose(result.samples[0, 1:], reference, atol=1e-4)


def test_undamped_linear_run_keeps_energy():
    """Average acceleration conserves E = v'Mv/2 + q'Kq/2 of a free undamped system."""
    rng = np.random.default_rng(7)
    n = 6
    mass = np.diag(rng.uniform(0.5, 2.0, n))
    springs = rng.uniform(1e3, 1e5, n)
    stiffness = np.diag(springs + np.r_[springs[1:], 0.0])
    stiffness -= np.diag(springs[1:], 1) + np.diag(springs[1:], -1)
    solver = BandedNewmark(mass, np.zeros((n, n)), stiffness, 1e-3)
    probes = [displacement_probe(n, i) for i in range(n)]
    probes += [KernelProbe(f"v{i}", "velocity", np.eye(n)[i]) for i in range(n)]
    q0 = rng.normal(size=n) * 1e-3
    result = solver.run(5000, probes, q0=q0)
    q, v = result.samples[:n], result.samples[n:]
    energy = 0.5 * np.einsum("it,ij,jt->t", v, mass, v) + 0.5 * np.einsum(
        "it,ij,jt->t", q, stiffness, q
    )
    assert np.max(np.abs(energy / energy[0] - 1)) < 1e-10


def _free_vibration_error(dt: float, integrator: str) -> float:
    m, k, zeta, u0 = 1.0, (2 * np.pi) ** 2, 0.05, 1.0
    omega = math.sqrt(k / m)
    omega_d = omega * math.sqrt(1 - zeta**2)
    solver = oscillator(m, k, 2 * zeta * omega * m, dt, integrator=integrator)
    steps = int(round(2.0 / dt))
    result = solver.run(steps, [displacement_probe(1)], q0=np.array([u0]))
    t = result.time
    exact = (
        np.exp(-zeta * omega * t)
        * u0
        * (np.cos(omega_d * t) + zeta * omega / omega_d * np.sin(omega_d * t))
    )
    return float(np.max(np.abs(result.samples[0] - exact)))


@pytest.mark.parametrize("integrator", ["newmark", "hht", "generalized-alpha"])
def test_second_order_convergence(integrator):
    """Halving the step divides the error by 4 (observed order 1.9 .. 2.1)."""
    errors = [_free_vibration_error(dt, integrator) for dt in (1 / 100, 1 / 200, 1 / 400)]
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all((orders > 1.9) & (orders < 2.1)), orders


@pytest.mark.parametrize("omega_h", [0.3, 1.0, 2.5])
def test_period_elongation(omega_h):
    """Undamped average acceleration: Tbar/T = Omega h / (2 atan(Omega h / 2))."""
    dt = 1e-3
    k = (omega_h / dt) ** 2
    result = oscillator(1.0, k, 0.0, dt).run(400, [displacement_probe(1)], q0=np.array([1.0]))
    u = result.samples[0]
    # the discrete solution is u_n = cos(n phi): u_(n+1) + u_(n-1) = 2 cos(phi) u_n
    use = np.abs(u[1:-1]) > 0.5
    cos_phi = np.mean((u[2:] + u[:-2])[use] / (2 * u[1:-1][use]))
    measured = omega_h / math.acos(cos_phi)
    expected = omega_h / (2 * math.atan(omega_h / 2))
    assert measured == pytest.approx(expected, rel=1e-9)
    assert np.max(np.abs(u)) == pytest.approx(1.0, abs=1e-12)  # no amplitude decay


def _amplification(omega_h: float, integrator: str, rho: float) -> np.ndarray:
    """Amplification matrix of x = (u, v dt, a dt^2) for an undamped oscillator, derived
    from the schemes' definitions: M a_(n+1-am) + K u_(n+1-af) = 0 (Chung & Hulbert 1993;
    HHT is am = 0, af = (1 - rho)/(1 + rho); average acceleration am = af = 0)."""
    if integrator == "generalized-alpha":
        am, af = (2 * rho - 1) / (rho + 1), rho / (rho + 1)
    else:
        am, af = 0.0, (1 - rho) / (1 + rho)
    gamma, beta = 0.5 - am + af, 0.25 * (1 - am + af) ** 2
    w2 = omega_h**2
    matrix = np.zeros((3, 3))
    for j, (u0, v0, a0) in enumerate(np.eye(3)):
        ut, vt = u0 + v0 + (0.5 - beta) * a0, v0 + (1 - gamma) * a0
        a1 = -(am * a0 + w2 * ((1 - af) * ut + af * u0)) / (1 - am + w2 * (1 - af) * beta)
        matrix[:, j] = [ut + beta * a1, vt + gamma * a1, a1]
    return matrix


@pytest.mark.parametrize(
    ("integrator", "rho"), [("newmark", 1.0), ("hht", 0.7), ("generalized-alpha", 0.5)]
)
def test_numerical_damping_follows_the_spectral_radius(integrator, rho):
    """The kernel's steps are the scheme's amplification matrix, whose spectral radius
    tends to rho_inf far above 1/dt (numerical damping of the highest modes)."""
    for omega_h in (0.5, 5.0, 1e3):
        dt = 1.0
        solver = oscillator(1.0, omega_h**2, 0.0, dt, integrator=integrator, spectral_radius=rho)
        u = solver.run(20, [displacement_probe(1)], q0=np.array([1.0])).samples[0]
        matrix = _amplification(omega_h, integrator, rho)
        x = np.array([1.0, 0.0, -(omega_h**2)])  # a0 from the equation of motion
        expected = [x[0]]
        for _ in range(20):
            x = matrix @ x
            expected.append(x[0])
        np.testing.assert_allclose(u, expected, rtol=1e-9, atol=1e-12)
    assert max(abs(np.linalg.eigvals(_amplification(1e8, integrator, rho)))) == pytest.approx(
        rho, rel=1e-4
    )


# --- the seed's run-up (Yang, Jiang & Han 2016, Table 3; docs/model.md §6.3) --------------


@pytest.fixture(scope="module")
def runups(study_case):
    """The case's three run-up scenes (5 s, time-varying mesh stiffness, predictor)."""
    return {f: run_transient(study_case, study_case.scene(s)) for f, s in SCENES.items()}


def _sun_mesh(dataset: xr.Dataset) -> xr.DataArray:
    return dataset.mesh_force.sel(mesh="planetary.sun-planet1")


def _speed(dataset: xr.Dataset, member: str) -> float:
    return float(dataset.equilibrium_speed.sel(body=f"planetary.{member}"))


@pytest.mark.parametrize(
    ("formulation", "t_s", "carrier", "sun"),
    [("improved", 0.158, 118.8, 541.058), ("lin-parker", 0.132, 119.0, 541.9)],
)
def test_table3(runups, study_case, formulation, t_s, carrier, sun):
    """Seed Table 3: t_s to 1 %, speeds to 0.2 %, sun/carrier within 0.1 % of 1 + r_br/r_bs."""
    run = runups[formulation]
    stage = study_case.gearbox.stages[0]
    assert run.attrs["effects"] == "time_varying_mesh_stiffness"
    assert float(run.t_s) == pytest.approx(t_s, rel=0.01)
    assert _speed(run, "carrier") == pytest.approx(carrier, rel=0.002)
    assert _speed(run, "sun") == pytest.approx(sun, rel=0.002)
    ratio = 1 + stage.ring.base_radius / stage.sun.base_radius
    assert _speed(run, "sun") / _speed(run, "carrier") == pytest.approx(ratio, rel=0.001)


def test_planet_tangential_speed(runups):
    """Lin-Parker's planet moves at r_c omega_c in its frame (1.207 m/s); improved: 0."""
    assert float(runups["lin-parker"].planet_tangential_speed[0]) == pytest.approx(1.207, rel=0.002)
    assert abs(float(runups["improved"].planet_tangential_speed[0])) < 1e-4


def _equivalent_inertia(case, formulation: str) -> tuple[float, float]:
    """J_eq reduced to the carrier and the sun/carrier ratio, from docs/model.md §3.1 and §6.3."""
    stage = case.gearbox.stages[0]
    m, i_p, r_c = stage.planet.mass, stage.planet.polar_inertia, stage.carrier.radius
    r_bs, r_br, r_bp = stage.sun.base_radius, stage.ring.base_radius, stage.planet.base_radius
    if formulation == "lin-parker":  # eta = r_c theta_c; meshes fix theta_p and theta_s
        ratio = 2 * r_c * math.cos(stage.ring_mesh.pressure_angle) / r_bs
        spin = r_c * math.cos(stage.ring_mesh.pressure_angle) / r_bp
    else:  # relative spin -(r_br/r_bp) theta_c; consistent: absolute spin enters I_p
        ratio = 1 + r_br / r_bs
        spin = r_br / r_bp - (1.0 if formulation == "consistent" else 0.0)
    planets = stage.planets * (m * r_c**2 + i_p * spin**2)
    return stage.carrier.polar_inertia + stage.sun.polar_inertia * ratio**2 + planets, ratio


@pytest.mark.parametrize("formulation", ["improved", "lin-parker", "consistent"])
def test_runup_follows_each_formulations_inertia(runups, study_case, formulation):
    """t_s = -ln(1 - alpha J w0 / T_D)/alpha and T_D (1 - (w/w0)^2) = alpha J w."""
    j_eq, _ = _equivalent_inertia(study_case, formulation)
    alpha = study_case.damping.mass_coefficient
    settings = study_case.scene(SCENES[formulation]).transient
    torque, omega_0 = settings.drive.torque, settings.speed_reference_rpm * math.pi / 30
    t_s = -math.log(1 - alpha * j_eq * omega_0 / torque) / alpha
    a, b = torque / omega_0**2, alpha * j_eq
    omega = (-b + math.sqrt(b * b + 4 * a * torque)) / (2 * a)
    run = runups[formulation]
    assert float(run.t_s) == pytest.approx(t_s, rel=0.005)
    assert _speed(run, "carrier") == pytest.approx(omega * 30 / math.pi, rel=0.002)


def test_static_mesh_load_and_contact_sign(study_case):
    """10 N m on the carrier, sun held: 18.9 N and -3.78e-8 m per mesh (docs/model.md §3.4)."""
    model = assemble(study_case, study_case.scene("runup"))
    stage = study_case.gearbox.stages[0]
    force = 10.0 / stage.speed_ratio / (stage.planets * stage.sun.base_radius)
    deflection = static_mesh_deflections(
        model,
        dof_row(model, "planetary.carrier.theta_z"),
        dof_row(model, "planetary.sun.theta_z"),
        10.0,
    )
    np.testing.assert_allclose(deflection, -force / stage.sun_mesh.stiffness, rtol=1e-3)
    assert force == pytest.approx(18.9, abs=0.05)
    problem = transient_problem(study_case, study_case.scene("runup"))
    assert np.all(problem.contact_sign == -1)


def test_cli_run_writes_transient_file(study_case, tmp_path, capsys):
    argv = ["run", CASE, "--scene", "runup_lin_parker", "--out", str(tmp_path), "--json"]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    entry = summary["scenes"]["runup_lin_parker"]
    assert entry["t_s"] == pytest.approx(0.132, rel=0.01)
    assert set(entry["equilibrium_speed_rpm"]) >= {"carrier", "sun", "planet1"}
    assert entry["planet_tangential_speed"] == pytest.approx(1.207, rel=0.002)
    assert entry["steps"] == 200000
    assert 0 < entry["solver_wall_s"] < entry["wall_s"] <= summary["wall_s"]
    with open_dataset(tmp_path / "runup_lin_parker.nc") as run:
        assert run.attrs["formulation"] == "lin-parker"
        assert run.attrs["Conventions"].startswith("CF")
        assert run.sizes["time"] == 200001  # 40 kHz over 5 s, with t = 0
        assert run.time.values[1] == pytest.approx(2.5e-5)
        for name, variable in run.variables.items():
            assert "long_name" in variable.attrs, name
            if variable.dtype.kind not in "OUS":  # labels are text: no units
                assert "units" in variable.attrs, name
        assert "translation_displacement" not in run  # no full state unless asked
        ring = run.translation_acceleration.sel(translation_dof="planetary.ring.y")
        assert ring.attrs["units"] == "m/s^2"
    assert (tmp_path / "runup_lin_parker_speeds.png").stat().st_size > 1000
    assert not list(tmp_path.glob(".*part"))


# --- equivalent-load modes -----------------------------------------------------------------


def _short_scene(case, time_step: float, mode: str, duration: float = 0.3, **extra) -> Scene:
    settings = dataclasses.replace(
        case.scene("runup").transient,
        duration=duration,
        time_step=time_step,
        sample_rate=None,
        equivalent_load=mode,
        mean_window=min(0.05, duration),
        **extra,
    )
    return dataclasses.replace(
        case.scene("runup"), name=f"short_{mode}", transient=settings, analyses=("transient",)
    )


@pytest.fixture(scope="module")
def modes(study_case):
    return {
        mode: run_transient(study_case, _short_scene(study_case, 2.5e-5, mode))
        for mode in ("predictor", "iterate", "refactor")
    }


def test_modes_agree_where_all_converge(modes):
    force = {m: _sun_mesh(d).sel(time=slice(0.25, 0.3)) for m, d in modes.items()}
    carrier = {m: _speed(d, "carrier") for m, d in modes.items()}
    # iterate and refactor solve the same implicit step
    assert np.max(np.abs(force["iterate"] - force["refactor"])) < 1e-4
    assert carrier["refactor"] == pytest.approx(carrier["iterate"], rel=1e-9)
    # the predictor's explicit mesh term only adds high-frequency error
    assert carrier["predictor"] == pytest.approx(carrier["iterate"], rel=1e-4)
    assert float(force["predictor"].mean()) == pytest.approx(
        float(force["iterate"].mean()), rel=0.01
    )
    assert float(modes["predictor"].t_s) == pytest.approx(float(modes["iterate"].t_s), rel=1e-3)
    assert modes["iterate"].attrs["solver_iterations"] > modes["iterate"].attrs["steps"]
    assert modes["refactor"].attrs["solver_refactors"] > 0


def test_iterate_converges_where_predictor_diverges(study_case, modes):
    """At twice the paper's step the explicit mesh term diverges; iteration does not."""
    with pytest.raises(TransientError, match=r"at t = .* s .*mesh .*predictor.*iterate"):
        run_transient(study_case, _short_scene(study_case, 5e-5, "predictor"))
    coarse = run_transient(study_case, _short_scene(study_case, 5e-5, "iterate"))
    fine = modes["iterate"]
    assert _speed(coarse, "carrier") == pytest.approx(_speed(fine, "carrier"), rel=1e-3)
    assert float(coarse.t_s) == pytest.approx(float(fine.t_s), rel=2e-3)


def test_unstable_run_fails_clearly_and_writes_nothing(study_case, tmp_path, capsys, monkeypatch):
    unstable = _short_scene(study_case, 1e-4, "predictor")
    case = dataclasses.replace(study_case, scenes=(unstable,))
    monkeypatch.setattr("pygear.model.case.load_case", lambda reference: case)
    assert main(["run", CASE, "--out", str(tmp_path)]) == 2
    error = capsys.readouterr().err
    assert "at t = " in error and "likely cause" in error and "mesh" in error
    assert not list(tmp_path.glob("*.nc")) and not list(tmp_path.glob(".*part"))


def test_ctrl_c_stops_between_chunks_and_resumes(study_case, tmp_path):
    scene = _short_scene(study_case, 2.5e-5, "predictor", duration=0.2)
    problem = transient_problem(study_case, scene)
    checkpoint = tmp_path / "state.npz"

    def interrupt(done, total):
        raise KeyboardInterrupt

    with pytest.raises(TransientInterrupted, match="no result file"):
        run_transient(study_case, scene, problem=problem, progress=interrupt, checkpoint=checkpoint)
    assert checkpoint.is_file()
    resumed = run_transient(study_case, scene, resume=checkpoint)
    whole = run_transient(study_case, scene)
    np.testing.assert_array_equal(_sun_mesh(resumed), _sun_mesh(whole))
    assert float(resumed.t_s) == float(whole.t_s)


def test_sigint_is_honoured_between_chunks(study_case):
    """A real Ctrl-C (SIGINT) during a run stops it after the current chunk."""
    scene = _short_scene(study_case, 2.5e-5, "predictor", duration=0.2)
    calls = []

    def send_sigint(done, total):
        calls.append(done)
        if len(calls) == 1:
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(TransientInterrupted, match=r"interrupted at t = .* \(step \d+ of 8000\)"):
        run_transient(study_case, scene, progress=send_sigint)
    assert len(calls) == 1
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_ctrl_c_in_cli_leaves_no_file(study_case, tmp_path, capsys, monkeypatch):
    class Interrupting:
        def __init__(self, *args, **kwargs):
            pass

        def __call__(self, done, total):
            raise KeyboardInterrupt

    monkeypatch.setattr("pygear.cli.run.ProgressBar", Interrupting)
    assert main(["run", CASE, "--scene", "runup", "--out", str(tmp_path)]) == 130
    assert "interrupted" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_cli_checkpoint_and_resume(study_case, tmp_path, capsys, monkeypatch):
    """Ctrl-C with --checkpoint-every leaves only the checkpoint; --resume finishes the run
    exactly as an uninterrupted one and removes it."""
    scene = _short_scene(study_case, 2.5e-5, "predictor", duration=0.2)
    case = dataclasses.replace(study_case, scenes=(scene,))
    monkeypatch.setattr("pygear.model.case.load_case", lambda reference: case)
    interrupting = {"on": True}

    class Bar:
        def __init__(self, *args, **kwargs):
            pass

        def __call__(self, done, total):
            if interrupting["on"]:
                raise KeyboardInterrupt

    monkeypatch.setattr("pygear.cli.run.ProgressBar", Bar)
    argv = ["run", CASE, "--out", str(tmp_path), "--checkpoint-every", "1000"]
    assert main(argv) == 130
    assert [p.name for p in tmp_path.iterdir()] == [f"{scene.name}.checkpoint.npz"]
    interrupting["on"] = False
    assert main([*argv, "--resume", "--json"]) == 0
    assert not (tmp_path / f"{scene.name}.checkpoint.npz").exists()
    whole = run_transient(study_case, scene)
    with open_dataset(tmp_path / f"{scene.name}.nc") as resumed:
        np.testing.assert_array_equal(_sun_mesh(resumed), _sun_mesh(whole))
    capsys.readouterr()


def test_tooth_separation_is_an_elastic_impact():
    """Two equal masses meet through a contact-only spring and leave with swapped speeds."""
    m, k, dt = 1.0, 1e6, 1e-5
    meshes = MeshTerms(
        deflection=np.array([[1.0, -1.0]]),
        mean_stiffness=np.array([k]),
        contact_sign=np.array([1]),  # compressed when x1 > x2
        angle=np.zeros((1, 2)),
        separation=True,
        names=["contact"],
    )
    stiffness = k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    solver = BandedNewmark(
        np.eye(2) * m, np.zeros((2, 2)), stiffness, dt, meshes=meshes, equivalent_load="refactor"
    )
    probes = [KernelProbe("force", "mesh_force", mesh=0)]
    result = solver.run(2000, probes, q0=np.array([-1e-3, 0.0]), v0=np.array([1.0, 0.0]))
    assert result.v == pytest.approx([0.0, 1.0], abs=0.01)
    assert np.all(result.samples[0] >= 0)  # contact pushes, never pulls
    assert result.samples[0, 0] == 0 and result.samples[0, -1] == 0
    assert result.counters["separated"] > 0


# --- bad input refused before the run ------------------------------------------------------


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"time_step": 0.0}, "time_step must be a positive"),
        ({"time_step": -1e-5}, "time_step must be a positive"),
        ({"duration": 1e-5}, "duration 1e-05 s is shorter than one time step"),
        ({"sample_rate": 80e3}, "sample_rate 80000 Hz is above the step rate"),
        ({"sample_rate": 30e3}, "sample_rate 30000 Hz is not reachable"),
        ({"drive": TorqueLaw.table([0.0, 1.0, 1.0], [1.0, 2.0, 3.0])}, "times must increase"),
        ({"equivalent_load": "guess"}, "equivalent_load must be one of"),
        ({"integrator": "euler"}, "integrator must be one of"),
    ],
)
def test_bad_settings_name_the_parameter(study_case, change, message):
    settings = dataclasses.replace(study_case.scene("runup").transient, **change)
    with pytest.raises(CaseError, match=message) as error:
        Scene("bad", analyses=("transient",), transient=settings).validate("scenes.bad")
    assert "scenes.bad.transient." in str(error.value)


@pytest.mark.parametrize(
    ("probe", "message"),
    [
        (Probe("acceleration", "planetary.sun.theta_q"), "is not a DOF of this model"),
        (Probe("mesh_force", "sun-planet7"), "is not a mesh of this model"),
        (Probe("speed", "planetary.moon"), "is not a body of this model"),
        (Probe("bearing_force", "planetary.ring_bearing.w"), "is not a bearing spring"),
    ],
)
def test_probe_targets_are_checked_before_the_run(study_case, probe, message):
    settings = dataclasses.replace(study_case.scene("runup").transient, probes=(probe,))
    scene = dataclasses.replace(study_case.scene("runup"), transient=settings)
    with pytest.raises(CaseError, match=message) as error:
        transient_problem(study_case, scene)
    assert "scenes.runup.transient.probes[0].target" in str(error.value)


def test_members_are_checked(study_case):
    settings = dataclasses.replace(study_case.scene("runup").transient, input="planetary.sun.z")
    scene = dataclasses.replace(study_case.scene("runup"), transient=settings)
    with pytest.raises(CaseError, match=r"transient.input: 'planetary.sun.z' is a DOF held fixed"):
        transient_problem(study_case, scene)


def test_transient_scene_needs_settings():
    with pytest.raises(CaseError, match="scenes.x.transient: the transient analysis needs"):
        Scene("x", analyses=("transient",)).validate("scenes.x")


def test_probes_keep_only_what_is_asked(study_case):
    """Memory grows with the probes kept: one row per probe, one column per sample."""
    probes = (Probe("speed", "planetary.sun"), Probe("bearing_force", "planetary.ring_bearing.y"))
    scene = _short_scene(study_case, 2.5e-5, "predictor", duration=0.01, probes=probes)
    run = run_transient(study_case, scene)
    assert channel_names(run) == ["speed:planetary.sun", "bearing_force:planetary.ring_bearing.y"]
    assert run.speed.dims == ("member", "time") and run.bearing_force.sizes["bearing"] == 1
    assert run.bearing_force.attrs["units"] == "N"
    full = run_transient(
        study_case,
        _short_scene(study_case, 2.5e-5, "predictor", duration=0.01, full_state=True),
    )
    # the planar model's 18 DOFs: x, y, theta_z of the carrier, ring and sun, zeta, eta,
    # theta_z of each of 3 planets; translations and rotations apart (one unit each)
    assert full.translation_acceleration.dims == ("translation_dof", "time")
    assert full.sizes["translation_dof"] == 12 and full.sizes["rotation_dof"] == 6
