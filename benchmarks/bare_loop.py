"""The references of ``bench_newmark.py``: the kernel's step as plain arrays, a fused
NumPy loop over them, and the bare Fortran loop ``bare_newmark.f90.in``.

:func:`loop_arrays` takes a run-up problem of :mod:`pygear.analysis.time.transient` (average
acceleration, equivalent load at the predictor, parabola or helical contact law, a
constant drive and the speed-power load) and returns what one step needs, in the
kernel's DOF order, including the fused operator X = s Khat^-1 [-C, -K0, w_in, -w_out,
-B^T] of the kernel's dense path.

:class:`BareLoop` compiles the Fortran program with gfortran at the kernel's
optimisation (``-O3``, no ``-march``), links it against the OpenBLAS the kernel links
(the scipy-openblas32 wheel, found by ``get_lib_dir()`` and its pkg-config symbol
prefix), feeds it the arrays and runs it; the program times its own loop, so each call
gives microseconds per step (wall clock and CPU time) and the channels.
"""

from __future__ import annotations

import math
import os
import re
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.linalg

SOURCE = Path(__file__).resolve().parent / "bare_newmark.f90.in"
CHOLMOD_SHIM = Path(__file__).resolve().parent.parent / "fortran" / "cholmod_shim.c"
SUITESPARSE_INCLUDE = Path("/usr/include/suitesparse")
"""Where Debian's libsuitesparse-dev puts cholmod.h (as meson.build looks for it)."""
VARIANTS = ("band", "inverse", "dense_blas", "dense_loop", "refined", "dense_cholesky", "sparse")
"""Linear solves of the bare loop (see bare_newmark.f90.in)."""


@dataclass
class LoopArrays:
    """One run-up problem as the arrays of a step, kernel DOF order (see the module)."""

    n: int
    bandwidth: int
    time_step: float
    beta: float
    gamma: float
    damping_band: np.ndarray
    stiffness_band: np.ndarray
    factor: np.ndarray  # banded Cholesky factor of Khat
    inverse: np.ndarray  # Khat^-1
    pattern: tuple  # CSC lower triangle (0-based pointers, rows) of M, C, K0 together
    pattern_values: tuple  # C, K0 and Khat on the pattern
    fused: np.ndarray  # X, n x (2n + M + 2)
    right_side: np.ndarray  # S = s [-C, -K0, w_in, -w_out, -B^T], X = Khat^-1 S
    restoring: np.ndarray  # [-C; -K0], 2n x n
    khat: np.ndarray  # Khat, dense
    arguments: dict  # the kernel's packed sparse rows of meshes, angles and members
    deflection: np.ndarray  # B, M x n
    angle: np.ndarray  # angle rows, M x n
    w_in: np.ndarray
    w_out: np.ndarray
    mean_stiffness: np.ndarray
    contact_sign: np.ndarray
    mesh_damping: np.ndarray  # c_m, in the mesh-force channels: F = s (k b.q + c_m b.v)
    teeth: np.ndarray  # Z1 per mesh
    cycle_sign: np.ndarray
    phase: np.ndarray
    contact_ratio: np.ndarray
    end_to_peak: np.ndarray
    helical: np.ndarray  # bool per mesh: helical contact-line law, else parabola
    max_pairs: int
    drive: float  # constant drive torque [N m]
    load: tuple[float, float, float]  # T = p1 |w / p2|^p3 sign(w) after t_s
    speed_reference: float  # omega_0 [rad/s]
    linear: list  # (name, "velocity" or "acceleration", weights in kernel order)
    forces: list  # (name, mesh index)
    initial_acceleration: np.ndarray

    @property
    def names(self) -> list[str]:
        """Channel order of both references: linear probes, mesh forces, torques."""
        return [p[0] for p in self.linear] + [p[0] for p in self.forces] + [
            "drive_torque",
            "load_torque",
        ]


def loop_arrays(problem) -> LoopArrays:
    """The arrays of ``problem`` (a TransientProblem of a run-up, see the module)."""
    solver = problem.solver
    n, kd = solver.n, solver.bandwidth
    arguments = solver.arguments
    mass, damping, stiffness = (_dense(solver.bands[k]) for k in ("mass", "damping", "stiffness"))
    c = solver.coefficients
    dt, beta, gamma = solver.time_step, c["beta"], c["gamma"]
    if c["alpha_m"] or c["alpha_f"] or solver.equivalent_load != "predictor":
        raise ValueError("the references are the average-acceleration rule with 'predictor'")
    s = 1.0 / (beta * dt * dt)
    khat = stiffness + s * mass + gamma / (beta * dt) * damping
    inverse = scipy.linalg.cho_solve(scipy.linalg.cho_factor(khat, lower=True), np.eye(n))
    w_in, w_out = _rows(*(arguments[f"load_{k}"] for k in ("ptr", "index", "value")), n)
    deflection = _rows(*(arguments[f"mesh_{k}"] for k in ("ptr", "index", "value")), n)
    angle = _rows(*(arguments[f"angle_{k}"] for k in ("ptr", "index", "value")), n)
    right_side = s * np.hstack(
        [-damping, -stiffness, np.column_stack([w_in, -w_out, -deflection.T])]
    )
    fused = inverse @ right_side
    table = solver.table
    drive, load = (arguments["law_param"][:, k] for k in range(2))
    lower = np.tril((mass != 0) | (damping != 0) | (stiffness != 0))
    columns, rows = np.nonzero(lower.T)  # column by column, rows ascending
    column_start = np.concatenate([[0], np.cumsum(np.bincount(columns, minlength=n))])
    return LoopArrays(
        n=n,
        bandwidth=kd,
        time_step=dt,
        beta=beta,
        gamma=gamma,
        damping_band=solver.bands["damping"],
        stiffness_band=solver.bands["stiffness"],
        factor=scipy.linalg.cholesky_banded(_band(khat, kd), lower=True),
        inverse=inverse,
        pattern=(column_start.astype(np.int32), rows.astype(np.int32)),
        pattern_values=(damping[rows, columns], stiffness[rows, columns], khat[rows, columns]),
        fused=fused,
        right_side=right_side,
        restoring=np.vstack([-damping, -stiffness]),
        khat=khat,
        arguments=arguments,
        deflection=deflection,
        angle=angle,
        w_in=w_in,
        w_out=w_out,
        mean_stiffness=np.asarray(arguments["mean_stiffness"], dtype=np.float64),
        contact_sign=np.asarray(arguments["contact_sign"], dtype=np.float64),
        mesh_damping=np.asarray(arguments["mesh_damping"], dtype=np.float64),
        teeth=table.teeth[0].astype(np.float64),
        cycle_sign=table.cycle_sign.astype(np.float64),
        phase=np.asarray(table.phase, dtype=np.float64),
        contact_ratio=np.asarray(table.contact_ratio, dtype=np.float64),
        end_to_peak=np.asarray(table.end_to_peak, dtype=np.float64),
        helical=np.asarray(table.law) == 3,
        max_pairs=int(table.max_pairs),
        drive=float(drive[0]),
        load=(float(load[0]), float(load[1]), float(load[2])),
        speed_reference=float(solver.rparam[8]),
        linear=[
            (p.name, p.kind, np.asarray(p.weights, dtype=np.float64)[solver.order])
            for p in problem.probes
            if p.kind in ("velocity", "acceleration")
        ],
        forces=[(p.name, p.mesh) for p in problem.probes if p.kind == "mesh_force"],
        initial_acceleration=solver.start()["a"],
    )


def numpy_fused(
    arrays: LoopArrays, steps: int, checks: bool = True
) -> tuple[np.ndarray, float]:
    """The kernel's step as a plain fused NumPy loop; the channels (``arrays.names`` by
    steps) and t_s [s].

    One matrix-vector product a step and, besides it, only the work the kernel does:

    * the dense path's a = X x, x = [vt; qt; drive; load; g], gives the new state
      q = qt + beta dt^2 a, v = vt + gamma dt a, and everything a step reads from the
      state is linear in it: so one operator W = R U takes x to the next step's vt and
      qt (straight into x), the channels, the input speed (for t_s), the next predictor's
      tooth-passing cycles Z A qt / 2 pi, deflections B qt and output speed, and the two
      runaway bounds that the kernel checks every step (|a| and the mesh deflections
      B q, each row scaled by its bound, so that one slice holds both checks;
      ``checks=False`` leaves them out, a loop that does less than the kernel);
    * each mesh runs its own contact law, the parabola for spur meshes and the
      contact-line law for helical ones (meshes ordered by law, so each law reads a
      slice), never both.
    """
    n, dt, beta, gamma = arrays.n, arrays.time_step, arrays.beta, arrays.gamma
    n_mesh = len(arrays.mean_stiffness)
    shift = dt * dt * (0.5 - beta)  # qt = q + dt v + shift a
    lag = dt * (1.0 - gamma)  # vt = v + lag a
    b_dt2, g_dt = beta * dt * dt, gamma * dt
    # meshes by law: spur (parabola) first, then helical; positions of each mesh there
    order = np.concatenate([np.flatnonzero(~arrays.helical), np.flatnonzero(arrays.helical)])
    n_spur = int(np.count_nonzero(~arrays.helical))
    position = np.argsort(order)
    deflection, angle = arrays.deflection[order], arrays.angle[order]
    kbar = arrays.mean_stiffness[order]
    eps, lam = arrays.contact_ratio[order], arrays.end_to_peak[order]
    cycles_per_rad = (arrays.cycle_sign * arrays.teeth)[order] / (2 * math.pi)
    phase = arrays.phase[order]
    # parabola: peak (1 - (1 - lam) u^2), u = 2 p / eps - 1
    spur, helical = slice(0, n_spur), slice(n_spur, n_mesh)
    eps_spur, eps_helical = eps[spur], eps[helical]
    peak = (3 * kbar / (eps * (2 + lam)))[spur]
    curvature = peak * (1 - lam[spur])
    slope = 2 / eps_spur
    # contact-line law: kbar min(p, eps - p, min(eps_a, lam)) / (eps_a lam), eps_a = eps - lam
    transverse = (eps - lam)[helical]
    cap = np.minimum(transverse, lam[helical])
    line_scale = kbar[helical] / (transverse * lam[helical])
    offsets = np.arange(arrays.max_pairs)[:, None]
    p1, p2, p3 = arrays.load
    omega_0 = arrays.speed_reference

    zero, eye = np.zeros(n), np.eye(n)

    def row(q=zero, v=zero, a=zero):
        return np.concatenate([q, v, a])

    def predicted(w):  # w . qt of the next step, qt = q + dt v + shift a
        return row(q=w, v=dt * w, a=shift * w)

    # R: what a step reads from the new state [q; v; a], in this order
    rows = [row(v=e, a=lag * e) for e in eye] + [predicted(e) for e in eye]  # next vt, qt
    channels = slice(len(rows), len(rows) + len(arrays.linear) + len(arrays.forces))
    rows += [row(v=w) if kind == "velocity" else row(a=w) for _, kind, w in arrays.linear]
    rows += [row(q=arrays.contact_sign[m] * arrays.deflection[m]) for _, m in arrays.forces]
    dampers = slice(len(rows), len(rows) + len(arrays.forces))  # s c_m b.v of each force
    rows += [
        row(v=arrays.contact_sign[m] * arrays.mesh_damping[m] * arrays.deflection[m])
        for _, m in arrays.forces
    ]
    speed_in = len(rows)
    rows += [row(v=arrays.w_in)]  # input speed
    cycles = slice(len(rows), len(rows) + n_mesh)  # next tooth-passing cycles Z A qt / 2 pi
    rows += [predicted(w) for w in cycles_per_rad[:, None] * angle]
    deflections = slice(len(rows), len(rows) + n_mesh)  # next delta_t = B qt
    rows += [predicted(w) for w in deflection]
    speed_out = len(rows)
    rows += [row(v=arrays.w_out, a=lag * arrays.w_out)]  # next output speed w_out . vt
    check = len(rows)  # the kernel's runaway bounds, as |row . state| <= 1
    rows += [row(a=e / 1e15) for e in eye] + [row(q=w / 1e-3) for w in deflection]
    readout = np.array(rows)
    # U: [q; v; a] = [E_qt + b X; E_vt + g X; X] x; the step's operator W = R U
    fused = arrays.fused.copy()
    fused[:, 2 * n + 2 :] = arrays.fused[:, 2 * n + 2 :][:, order]
    update = np.vstack([fused * b_dt2, fused * g_dt, fused])
    update[np.arange(n), n + np.arange(n)] += 1.0  # q = qt + ...
    update[n + np.arange(n), np.arange(n)] += 1.0  # v = vt + ...
    step_operator = readout @ update
    n_channels = channels.stop - channels.start
    force_rows = slice(len(arrays.linear), n_channels)
    force_mesh = position[[m for _, m in arrays.forces]]

    state = np.concatenate([np.zeros(2 * n), arrays.initial_acceleration])
    out = readout @ state
    samples = np.empty((n_channels + 2, steps))
    samples[n_channels] = arrays.drive
    x = np.empty(step_operator.shape[1])
    x[2 * n] = arrays.drive
    k = np.empty(n_mesh)
    load, load_on, t_s = 0.0, False, math.nan
    for step in range(steps):
        x[: 2 * n] = out[: 2 * n]
        delta_t = out[deflections]
        if load_on:
            speed = out[speed_out]
            load = math.copysign(p1 * abs(speed / p2) ** p3, speed)
        x[2 * n + 1] = load
        cycle = out[cycles] + phase
        p = (cycle - np.floor(cycle)) + offsets  # pairs at frac(s) + j while < eps
        if n_spur:
            ps = p[:, spur]
            pair = peak - curvature * (slope * ps - 1) ** 2
            k[spur] = np.where(ps < eps_spur, pair, 0.0).sum(axis=0)
        if n_spur < n_mesh:
            ph = p[:, helical]
            pair = line_scale * np.minimum(np.minimum(ph, eps_helical - ph), cap)
            k[helical] = np.where(ph < eps_helical, pair, 0.0).sum(axis=0)
        x[2 * n + 2 :] = (k - kbar) * delta_t
        speed_old = out[speed_in]
        out = step_operator @ x
        if checks and not np.abs(out[check:]).max() <= 1.0:
            raise FloatingPointError(f"the NumPy loop ran away at step {step + 1}")
        if not load_on and out[speed_in] >= omega_0:
            load_on = True
            speed = out[speed_in]
            t_s = step * dt + dt * (omega_0 - speed_old) / (speed - speed_old)
        samples[:n_channels, step] = out[channels]
        samples[force_rows, step] *= k[force_mesh]
        samples[force_rows, step] += out[dampers]
        samples[n_channels + 1, step] = load
    return samples, t_s


def openblas() -> tuple[str, str, str]:
    """Library directory, library name and symbol prefix of the scipy-openblas32 wheel."""
    import scipy_openblas32

    prefix = re.search(r"-DBLAS_SYMBOL_PREFIX=(\w*)", scipy_openblas32.get_pkg_config())
    return (
        scipy_openblas32.get_lib_dir(),
        scipy_openblas32.get_library(),
        prefix.group(1) if prefix else "",
    )


def build(directory: Path) -> Path:
    """Compile the bare loop into ``directory``; the executable's path."""
    lib_dir, library, prefix = openblas()
    source = directory / "bare_newmark.f90"
    source.write_text(SOURCE.read_text().replace("@BLAS_SYMBOL_PREFIX@", prefix))
    program = directory / "bare_newmark"
    # the kernel's CHOLMOD shim, at the kernel's optimisation; without the headers it
    # compiles to stubs that report "not available" and only the sparse variant fails
    with_cholmod = (SUITESPARSE_INCLUDE / "cholmod.h").is_file()
    shim = directory / "cholmod_shim.o"
    subprocess.run(
        ["gcc", "-O3", "-c", str(CHOLMOD_SHIM), "-o", str(shim)]
        + (["-DPYGEAR_HAVE_CHOLMOD", f"-I{SUITESPARSE_INCLUDE}"] if with_cholmod else []),
        check=True, capture_output=True, text=True, cwd=directory,
    )
    subprocess.run(
        ["gfortran", "-O3", "-o", str(program), str(source), str(shim), f"-L{lib_dir}",
         f"-l{library}", f"-Wl,-rpath,{lib_dir}"] + (["-lcholmod"] if with_cholmod else []),
        check=True, capture_output=True, text=True, cwd=directory,
    )
    return program


@dataclass
class BareRun:
    """One run of the bare loop: microseconds per step (wall clock and CPU time), t_s [s]
    and the channels (``LoopArrays.names`` by steps)."""

    us_per_step: float
    cpu_us_per_step: float
    t_s: float
    samples: np.ndarray


class BareLoop:
    """The bare loop compiled once (in a temporary directory) and fed one problem."""

    def __init__(self, arrays: LoopArrays, steps: int) -> None:
        self._directory = tempfile.TemporaryDirectory(prefix="bare_newmark_")
        directory = Path(self._directory.name)
        self.program = build(directory)
        self.input = directory / "problem.bin"
        self.output = directory / "samples.bin"
        self.steps = steps
        self._write(arrays, steps)

    def _write(self, arrays: LoopArrays, steps: int) -> None:
        arguments = arrays.arguments
        ptr, index, value = [0], [], []
        for _, _, weights in arrays.linear:
            nz = np.nonzero(weights)[0]
            index.extend(nz + 1)
            value.extend(weights[nz])
            ptr.append(len(index))
        int32 = np.int32
        sizes = [arrays.n, arrays.bandwidth, len(arrays.mean_stiffness), steps,
                 len(arrays.linear), len(arrays.forces)]
        settings = [arrays.time_step, arrays.beta, arrays.gamma, arrays.drive, *arrays.load,
                    arrays.speed_reference]
        s = 1.0 / (arrays.beta * arrays.time_step**2)
        with open(self.input, "wb") as handle:
            for block in (
                np.array(sizes, int32),
                np.array(settings),
                arrays.damping_band, arrays.stiffness_band, arrays.factor, arrays.inverse,
                arrays.fused.T,
                arguments["mesh_ptr"], arguments["mesh_index"], arguments["mesh_value"],
                arguments["angle_ptr"], arguments["angle_index"], arguments["angle_value"],
                arrays.w_in, arrays.w_out, arrays.mean_stiffness, arrays.contact_sign,
                arrays.teeth, arrays.cycle_sign, arrays.phase, arrays.contact_ratio,
                arrays.end_to_peak, np.where(arrays.helical, 3, 1).astype(int32),
                np.array([2 if kind == "velocity" else 3 for _, kind, _ in arrays.linear], int32),
                np.array(ptr, int32), np.array(index or [1], int32), np.array(value or [0.0]),
                np.array([m + 1 for _, m in arrays.forces], int32),
                arrays.initial_acceleration,
                np.array([len(arrays.pattern[1])], int32),
                *arrays.pattern,
                *arrays.pattern_values,
                arrays.restoring,
                -arrays.khat / s,
                s * arrays.inverse.T,
                arrays.right_side.T,
                np.linalg.cholesky(arrays.khat),
                arrays.mesh_damping,
            ):
                np.asarray(block).ravel(order="F").tofile(handle)

    def run(self, variant: str) -> BareRun:
        """Run the loop once with the linear solve ``variant`` (see :data:`VARIANTS`)."""
        # one OpenBLAS thread: products this small never run threaded, and an idle pool
        # spins for a while after start-up, taking a core from the loop on a small machine
        output = subprocess.run(
            [str(self.program), variant, str(self.input), str(self.output)],
            check=True, capture_output=True, text=True,
            env={**os.environ, "OPENBLAS_NUM_THREADS": "1"},
        ).stdout.split()
        samples = np.fromfile(self.output, dtype=np.float64).reshape(self.steps, -1).T
        t_s = float(output[2])
        return BareRun(float(output[0]), float(output[1]), t_s if t_s >= 0 else math.nan,
                       samples)


def _dense(band: np.ndarray) -> np.ndarray:
    """The symmetric matrix of a LAPACK lower band."""
    kd, n = band.shape[0] - 1, band.shape[1]
    matrix = np.zeros((n, n))
    for d in range(kd + 1):
        diagonal = band[d, : n - d]
        matrix += np.diag(diagonal, -d)
        if d:
            matrix += np.diag(diagonal, d)
    return matrix


def _band(matrix: np.ndarray, kd: int) -> np.ndarray:
    """LAPACK lower band storage of a symmetric matrix."""
    n = matrix.shape[0]
    band = np.zeros((kd + 1, n))
    for d in range(kd + 1):
        band[d, : n - d] = np.diagonal(matrix, -d)
    return band


def _rows(ptr, index, value, n: int) -> np.ndarray:
    """Dense rows (kernel order) of packed sparse rows (1-based indices)."""
    rows = np.zeros((len(ptr) - 1, n))
    for r in range(len(ptr) - 1):
        for e in range(ptr[r], ptr[r + 1]):
            rows[r, index[e] - 1] += value[e]
    return rows
