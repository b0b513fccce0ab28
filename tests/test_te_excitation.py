"""The loaded contact's transmission error as a displacement excitation.

The ``loaded_contact`` law runs the mesh force k(s) (c - delta_0(s)) along the drive
flank's compression c: k the LTCA's secant stiffness at the operating load F_0, delta_0
its unloaded TE (docs/contact.md, "The loaded contact as a mesh law").  References are
the LTCA's own output (the Fortran LTCA solver's loaded TE, secant stiffness and
unloaded TE over its 40 positions per cycle), read at the mesh position of every
sample of the run from its recorded angles, and NumPy sums.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from test_loaded_contact_law import CARRIER_TORQUE, _relieved_case

from pygear import TorqueLaw
from pygear.analysis.response.hill import mesh_signals, solve_hill
from pygear.analysis.response.system import response_system
from pygear.analysis.time.transient import run_transient
from pygear.assembly import mesh_laws
from pygear.assembly.contact_table import build_contact_table
from pygear.assembly.drivetrain_model import scene_model
from pygear.assembly.mesh_laws import mesh_law
from pygear.model.case import RayleighDamping
from pygear.model.transient_settings import Probe

MESH = "sun-planet1"

SETTLING_DAMPING = RayleighDamping(mass_coefficient=0.0, stiffness_coefficient=2e-5)
"""Stiffness-proportional damping of 1 % at the stage's 160 Hz torsional mode and 6 % at
1 kHz: the start from rest at full speed decays within a few tenths of a second (the
case's own 1e-6 s leaves it ringing for seconds), so a short run reaches the periodic
steady state the comparisons need."""


def _case(damping: RayleighDamping | None = SETTLING_DAMPING, backlash: float | None = None):
    """The sequential stage with tip relief on the sun and ring meshes' loaded_contact
    law (operating load F_0 = 9.38 kN per sun mesh), optionally heavier damped and with
    a backlash [m] on both meshes."""
    case = _relieved_case()
    if damping is not None:
        case = dataclasses.replace(case, damping=damping)
    if backlash is not None:
        stage = case.gearbox.stages[0]
        stage = dataclasses.replace(
            stage,
            sun_mesh=dataclasses.replace(stage.sun_mesh, backlash=backlash),
            ring_mesh=dataclasses.replace(stage.ring_mesh, backlash=backlash),
        )
        case = dataclasses.replace(case, gearbox=dataclasses.replace(case.gearbox, stages=(stage,)))
    return case


def _scene(case, rpm: float, duration: float, load: float = 1.0, separation: bool = False):
    """A steady run at ``rpm`` of the carrier under ``load`` times the carrier torque of
    F_0, recording the angles and the sun mesh's force and deflection."""
    scene = case.scene("steady_sensor")
    torque = CARRIER_TORQUE * load
    transient = dataclasses.replace(
        scene.transient,
        duration=duration,
        drive=TorqueLaw.constant(torque),
        load=TorqueLaw.generator(rated_drive_torque=torque, exponent=2.0),
        speed_reference_rpm=rpm,
        initial_speed_rpm=rpm,
        mean_window=duration / 4,
        probes=(
            Probe("displacement", "planetary.carrier.theta_z"),
            Probe("displacement", "planetary.sun.theta_z"),
            Probe("mesh_force", MESH),
            Probe("mesh_deflection", MESH),
        ),
    )
    effects = ("time_varying_mesh_stiffness",) + (("tooth_separation",) if separation else ())
    return dataclasses.replace(scene, transient=transient, effects=effects)


def _run(case, scene, start: float = 0.0) -> dict:
    """The run from ``start`` on: force [N], compression c = s_m delta_m [m] and mesh
    position s [mesh cycles] of the sun mesh, and its table."""
    case = case.for_scene(scene)
    run = run_transient(case, scene).sel(time=slice(start, None))
    table = build_contact_table(case, scene_model(case, scene), scene, direction=1,
                                sun_driven=True)  # fmt: skip
    index = table.names.index(MESH)
    rotation = run.rotation_displacement
    theta = (rotation.sel(rotation_dof="planetary.sun.theta_z")
             - rotation.sel(rotation_dof="planetary.carrier.theta_z")).values  # fmt: skip
    position = table.mesh_cycle(np.outer(theta, np.ones(table.size)))[:, index]
    deflection = run.mesh_deflection.values[0]
    sign = -1.0 if np.median(deflection) < 0 else 1.0  # the loaded flank's sense
    return {
        "force": run.mesh_force.values[0],
        "compression": sign * deflection,
        "position": position,
        "table": table,
        "index": index,
        "run": run,
        "law": mesh_law(case.gearbox.stages[0], "sun"),
    }


def _ltca(law, position: np.ndarray, values: np.ndarray) -> np.ndarray:
    """An LTCA quantity over its positions of one cycle, at mesh positions (periodic)."""
    return np.interp(position - np.floor(position), law.table.position, values, period=1.0)


def test_transient_reproduces_the_loaded_te():
    """At 60 rpm of the carrier (mesh frequency 97 Hz, under the stage's modes) the sun
    mesh's compression follows the LTCA's loaded TE delta(F_0, s) at every sample, to
    first order in the run's force F(t) about F_0: c = delta(F_0, s) + (F - F_0) / k(F_0, s)
    with the LTCA's secant stiffness.  The run's stiffness is the LTCA's pair shares
    resampled from 40 positions onto 201 samples per path (5e-3 of k where a pair's share
    jumps: test_loaded_contact_law), so c - delta_0 = F / k errs by up to 5e-3 F / k;
    asserted 1e-2 of the largest F / k (0.3 um; measured 0.17 um, median 0.02 um).  A
    law without the excitation would miss by delta_0 itself, up to 13 um here.  The
    case's own light damping keeps the mesh damper's share of the recorded force (its
    c_m times the TE's rate) at a few newtons, where the reference takes the force as the
    spring's; the start's ringing (F within 20 % of F_0) is what the force term follows."""
    case = _case(damping=None)
    out = _run(case, _scene(case, 60.0, 0.3), start=0.1)
    law, position = out["law"], out["position"]
    table = law.table
    f0 = table.operating_force
    loaded = table.te_loaded[list(table.force).index(f0)]
    k_ltca = _ltca(law, position, table.secant_stiffness(f0))
    reference = _ltca(law, position, loaded) + (out["force"] - f0) / k_ltca
    assert np.ptp(position) > 5  # several mesh cycles
    assert np.abs(out["force"] / f0 - 1).max() < 0.25  # near the operating load
    assert _ltca(law, position, table.te_unloaded).max() > 10e-6  # the excitation matters
    scale = (out["force"] / k_ltca).max()
    np.testing.assert_allclose(out["compression"], reference, rtol=0, atol=1e-2 * scale)


@pytest.mark.parametrize("separation", [False, True])
def test_a_zero_excitation_is_the_plain_stiffness_law(monkeypatch, separation):
    """With e = 0 carried in the contact table (the kernel's excitation path taken) the
    run equals the one without an excitation (the plain tabulated law) to round-off:
    the offset k e and the flank law's shift are then exact zeros; 1e-12 of the largest
    value allows for an operation reordered by the compiler.  With separation (2 % load,
    0.1 mm backlash) the teeth part in the short run (16 free-flight mesh steps)."""
    case = _case(backlash=0.1e-3 if separation else None)
    scene = _scene(case, 120.0, 0.03, load=0.02 if separation else 1.0, separation=separation)
    runs = []
    for excitation in (lambda law, sun_driven=True: None,
                       lambda law, sun_driven=True: np.zeros(201)):  # fmt: skip
        monkeypatch.setattr(mesh_laws.MeshLaw, "oriented_excitation", excitation)
        runs.append(_run(case, scene))
    assert runs[0]["table"].excitation is None
    assert runs[1]["table"].excitation is not None
    for name in ("force", "compression"):
        plain, zero = runs[0][name], runs[1][name]
        np.testing.assert_allclose(zero, plain, rtol=0, atol=1e-12 * np.abs(plain).max())


def test_separation_opens_where_the_compression_is_below_the_excitation():
    """At 2 % of the operating load (static F / k of 0.5 um against an unloaded TE of up
    to 13 um) and 120 rpm, with a 0.1 mm backlash and the tooth_separation effect, the
    sun mesh's teeth part: wherever the compression is below the LTCA's unloaded TE
    (c - delta_0 < -1 nm; the kernel's 201 samples of delta_0 hold the LTCA's 40
    positions, so the two agree to round-off) the mesh force is exactly 0, and that
    includes samples with c > 0, where a law without the excitation would press the
    drive flanks together."""
    case = _case(damping=None, backlash=0.1e-3)
    out = _run(case, _scene(case, 120.0, 0.5, load=0.02, separation=True))
    law = out["law"]
    gap = out["compression"] - _ltca(law, out["position"], law.table.te_unloaded)
    apart = gap < -1e-9
    assert out["run"].attrs["solver_separated"] > 0
    assert apart.sum() >= 5
    assert np.all(out["force"][apart] == 0.0)
    assert np.any(apart & (out["compression"] > 1e-9))
    # in contact the spring presses (a damper may pull a little while the teeth part)
    touching = gap > 1e-9
    k = out["run"].mesh_force.values[0][touching] / gap[touching]
    assert np.median(k) > 0


def test_harmonic_balance_equals_the_transient():
    """At 10 % of the operating load the sun mesh's TE is mostly the excitation (static
    F / k of 2.3 um against delta_0 up to 13 um); at 120 rpm the harmonic balance (64
    harmonics of the fundamental) and the transient's steady state (1 s settled, the
    last 0.5 s over whole mesh cycles) give the same mesh deflection harmonics 0 to 5 of
    the mesh frequency.  Tolerance 1e-2 of the first harmonic: the transient's time
    step puts a stiffness jump up to a step late (1/200 of a mesh period), the balance
    truncates at 64 harmonics; measured 4e-4 of the first harmonic at harmonics 1, 2,
    3e-3 at 4, 5.  Without the excitation force the balance's first harmonic would be
    off by more than a tenth (measured 0.81 um against 2.73 um).  At constant stiffness
    the balance leaves the excitation out, as the kernel does without the
    time_varying_mesh_stiffness effect."""
    case = _case()
    scene = _scene(case, 120.0, 1.5, load=0.1)
    out = _run(case, scene, start=1.0)
    table, index = out["table"], out["index"]
    position = out["position"] - table.phase[index]
    cycles = int(np.floor(abs(position[-1] - position[0])))
    keep = np.abs(position - position[0]) < cycles
    deflection, position = out["run"].mesh_deflection.values[0][keep], position[keep]
    carrier = out["run"].rotation_displacement.sel(rotation_dof="planetary.carrier.theta_z")
    rpm = float(np.polyfit(out["run"].time.values, carrier.values, 1)[0]) * 30 / math.pi

    system = response_system(case, scene)
    m = system.names.index(MESH)
    order = int(system.mesh_order[m])
    balance = mesh_signals(system, solve_hill(system, system.omega(rpm), 64))[0][:, m]
    spectrum = np.fft.fft(balance) / balance.size
    forward = np.mean(np.diff(position)) > 0

    def balanced(k: int) -> complex:
        value = spectrum[k * order]
        return value if forward else np.conj(value)

    transient = [np.mean(deflection * np.exp(-2j * math.pi * k * position)) for k in range(6)]
    first = abs(balanced(1))
    assert first > 1e-6  # microns of dynamic TE at the mesh frequency
    for k in range(6):
        assert abs(transient[k] - balanced(k)) <= 1e-2 * first, (k, transient[k], balanced(k))
    # the excitation's own share: the balance without it misses the first harmonic
    plain = dataclasses.replace(system, harmonic_force=None, excitation=None)
    plain_deflection = mesh_signals(plain, solve_hill(plain, system.omega(rpm), 64))[0][:, m]
    plain_first = abs(np.fft.fft(plain_deflection)[order] / plain_deflection.size)
    assert abs(plain_first - first) > 0.1 * first
    # at constant stiffness the excitation stays out, as in the kernel without the effect
    constant = response_system(case, scene, time_varying=False)
    assert constant.excitation is None and constant.harmonic_force is None


def test_several_frequency_groups_run_the_first_order_form():
    """The NREL 5 MW gearbox on the law has three frequency groups, whose quasi-periodic
    balance takes no periodic force: its system carries no excitation and its meshes the
    TE-equivalent stiffness (the contact table built with ``excitation=False``), and
    the excitation force refuses a table with an excitation there, naming the meshes."""
    from pygear import CaseError
    from pygear.analysis.response.mesh_excitation import mesh_excitation
    from pygear.model.case import load_case

    case = load_case("nrel5mw_loaded_contact")
    scene = case.scene("runup")
    system = response_system(case, scene, samples=2**10)
    assert system.groups == 3 and system.excitation is None and system.harmonic_force is None
    model = scene_model(case.for_scene(scene), scene)
    excited = build_contact_table(case, model, scene, sun_driven=False)
    first_order = build_contact_table(case, model, scene, sun_driven=False, excitation=False)
    assert excited.excitation is not None and first_order.excitation is None
    theta = np.zeros((4, excited.size))
    with pytest.raises(CaseError, match="stage1.*several frequency groups"):
        mesh_excitation(excited, theta, np.ones((4, excited.size)), np.ones(excited.size),
                        np.ones((excited.size, 2)), groups=3)  # fmt: skip


def test_contact_loss_balance_refuses_an_excitation():
    """The contact-loss balance tests contact at c > 0 and would report k c where the
    mesh force is k (c - e): it refuses a system with an excitation before any work,
    naming the excited meshes (the ring meshes' unloaded TE is not zero either)."""
    from pygear import CaseError
    from pygear.analysis.response.sweep import contact_loss_response

    case = _case(backlash=0.1e-3)
    scene = _scene(case, 120.0, 0.1)
    with pytest.raises(CaseError, match=r"meshes sun-planet1, .*ring-planet1.*contact-loss"):
        contact_loss_response(case, np.array([120.0]), scene=scene)
