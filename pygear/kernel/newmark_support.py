"""Support of :mod:`pygear.kernel.newmark`: kernel codes and layouts, error messages, Ctrl-C
handling and checkpoints of a run."""

from __future__ import annotations

import contextlib
import functools
import os
import signal
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .calls import KernelError

__all__ = [
    "EQUIVALENT_LOAD_CODES",
    "IPARAM_LAYOUT",
    "ISTATE_LAYOUT",
    "LAW_CODES",
    "LINEAR_SOLVER_CODES",
    "LINEAR_SOLVER_VARIABLE",
    "PROBE_CODES",
    "RPARAM_LAYOUT",
    "requested_linear_solver",
    "INTERRUPT_SIGNALS",
    "GrowthDiagnostic",
    "PhysicalInstabilityError",
    "TransientError",
    "TransientInterrupted",
    "SMALL_MODEL_DOFS",
    "blas_threads",
    "checkpoint_key",
    "limited_blas",
    "choose_linear_solver",
    "DENSE_REFINED_DOFS",
    "dense_refined_fits",
    "deferred_interrupt",
    "growth_diagnostic",
    "kernel_error",
    "load_checkpoint",
    "save_checkpoint",
    "scheme_coefficients",
]

EQUIVALENT_LOAD_CODES = {"linear": 0, "predictor": 1, "iterate": 2, "refactor": 3}
"""Kernel codes of the equivalent-load modes (``linear``: no mesh terms at all)."""

LINEAR_SOLVER_CODES = {
    "banded_cholesky": 0,
    "dense_inverse": 1,
    "sparse_cholesky": 2,
    "dense_refined": 3,
}
"""Kernel codes of the linear solvers of Khat a = rhs (``fortran/newmark_dense.f90``)."""

LAW_CODES = {"none": 0, "constant": 1, "ramp": 2, "table": 3, "speed_power": 4}
"""Kernel codes of the torque laws."""

PROBE_CODES = {
    "displacement": 1,
    "velocity": 2,
    "acceleration": 3,
    "mesh_force": 4,
    "mesh_stiffness": 5,
    "drive_torque": 6,
    "load_torque": 7,
}
"""Kernel codes of the probe kinds (linear probes carry a weight vector)."""

RPARAM_LAYOUT = (
    "dt",
    "beta",
    "gamma",
    "alpha_m",
    "alpha_f",
    "tolerance",
    "refactor_threshold",
    "deflection_limit",
    "speed_reference",
    "acceleration_limit",
)
IPARAM_LAYOUT = (
    "mode",
    "max_iterations",
    "time_varying",
    "separation",
    "max_refactors",
    "restart_at_jumps",
    "linear_solver",
)
ISTATE_LAYOUT = (
    "step",
    "load_on",
    "iterations",
    "refactors",
    "max_iterations",
    "window",
    "separated",
    "contact_evaluations",
    "restarts",
    "coast",
)


LINEAR_SOLVER_VARIABLE = "PYGEAR_LINEAR_SOLVER"
"""Environment variable that forces the kernel's linear solver (``dense_refined``,
``banded_cholesky``, ``sparse_cholesky`` or ``dense_inverse``) over the automatic choice,
e.g. to compare the paths."""

DENSE_REFINED_DOFS = (10, 40)
"""Models the automatic choice puts on the refined dense path: from the first to the
second DOF count, inclusive [DOFs]; see :func:`choose_linear_solver`."""


def dense_refined_fits(n: int) -> bool:
    """Whether the automatic choice takes the refined dense path for ``n`` DOFs."""
    return DENSE_REFINED_DOFS[0] <= n <= DENSE_REFINED_DOFS[1]


def choose_linear_solver(n: int, bandwidth: int, requested: str = "auto") -> tuple[str, str]:
    """The kernel's linear solver for Khat a = rhs on band storage and the reason, in words.

    ``dense_refined`` keeps s Khat^-1 times the step's matrices and load vectors, spends
    one dense matrix-vector product per solve, and follows it with one step of iterative
    refinement against Khat (the residual from C, K0, the loads and Khat, corrected with
    s Khat^-1): four dense products per solve, about n (6 n + M + 2) multiplications for
    M meshes, and a step as backward stable as a factorization's
    (``fortran/newmark_dense.f90``).
    ``dense_inverse`` is the same product without the refinement, the fastest step but
    not backward stable: over 1e6 steps of the study case at 2000 rpm its speeds drift
    to 3.6e-8 of their value, against 7e-11 refined and 4e-11 on the band factor
    (``tests/test_dense_refinement.py``); it runs only on request.  ``banded_cholesky``
    multiplies by the band matrices and solves with the banded Cholesky factor, about
    n (kd + 1) multiplications per product or triangular solve.  On the 2-core AVX2
    machine of ``benchmarks/bench_newmark.py`` (docs/performance.md) the refined dense
    path was the fastest stable one on the study case (0.85 times CHOLMOD's sparse step)
    and on spring lattices of 12 to 40 DOFs with half-widths 2 to 20 (0.66 to 0.91
    times), within 10 % of CHOLMOD either way on narrow bands at 24 to 30 DOFs (the NREL
    drivetrain, a lattice of half-width 2), and slower below 10 DOFs (its four BLAS
    calls cost more than a small factor's solve: 1.2 times at 4 DOFs) and on the 50- and
    54-DOF gearboxes (1.13 and 1.2 times), so ``auto`` takes it within
    :data:`DENSE_REFINED_DOFS` and leaves other models to the band and sparse factors
    (:func:`~pygear.kernel.newmark_storage.kernel_storage`).  ``requested`` (or the
    environment variable :data:`LINEAR_SOLVER_VARIABLE`, which wins) forces a path.
    """
    choice, forced = requested_linear_solver(requested)
    shape = f"{n} DOFs, band half-width {bandwidth}, band fill {_band_fill(n, bandwidth):.0%}"
    if choice != "auto":
        source = f"{LINEAR_SOLVER_VARIABLE}={forced}" if forced else f"linear_solver={choice!r}"
        return choice, f"forced by {source} ({shape})"
    low, high = DENSE_REFINED_DOFS
    if dense_refined_fits(n):
        return "dense_refined", (
            f"automatic: {shape}; from {low} to {high} DOFs the dense inverse with one step "
            "of iterative refinement is the fastest backward stable step"
        )
    return "banded_cholesky", (
        f"automatic: {shape}; outside {low} to {high} DOFs the band factor costs less "
        "than the refined dense inverse"
    )


def requested_linear_solver(requested: str) -> tuple[str, str]:
    """The path asked for, by the environment variable :data:`LINEAR_SOLVER_VARIABLE`
    (which wins) or by ``requested``, and the variable's value ("" when unset).

    Raises
    ------
    ValueError
        Neither ``auto`` nor a path, naming where it was asked for.
    """
    forced = os.environ.get(LINEAR_SOLVER_VARIABLE, "").strip()
    choice = forced or requested
    if choice not in (*LINEAR_SOLVER_CODES, "auto"):
        where = f"environment variable {LINEAR_SOLVER_VARIABLE}" if forced else "linear_solver"
        raise ValueError(
            f"{where} must be one of {', '.join((*LINEAR_SOLVER_CODES, 'auto'))} (got {choice!r})"
        )
    return choice, forced


def _band_fill(n: int, bandwidth: int) -> float:
    """Share of the lower triangle (diagonal included) inside the band [-]."""
    inside = n * (bandwidth + 1) - bandwidth * (bandwidth + 1) // 2
    return inside / (n * (n + 1) / 2)


def scheme_coefficients(integrator: str, spectral_radius: float | None = None) -> dict:
    """beta, gamma, alpha_m, alpha_f of a scheme.

    ``newmark``: average acceleration (1/4, 1/2, 0, 0).  ``hht``: alpha_f =
    (1 - rho)/(1 + rho) (HHT's alpha = -alpha_f), gamma = 1/2 + alpha_f, beta =
    (1 + alpha_f)^2 / 4.  ``generalized-alpha`` (Chung & Hulbert 1993): alpha_m =
    (2 rho - 1)/(rho + 1), alpha_f = rho/(rho + 1), gamma = 1/2 - alpha_m + alpha_f,
    beta = (1 - alpha_m + alpha_f)^2 / 4.  In the kernel's convention alpha_f
    weights the old state, so Chung & Hulbert's alpha_m, alpha_f enter as given.
    """
    if integrator == "newmark":
        return {"beta": 0.25, "gamma": 0.5, "alpha_m": 0.0, "alpha_f": 0.0, "rho_inf": 1.0}
    if integrator == "hht":
        rho = 0.9 if spectral_radius is None else spectral_radius
        alpha_f = (1 - rho) / (1 + rho)
        return {
            "beta": 0.25 * (1 + alpha_f) ** 2,
            "gamma": 0.5 + alpha_f,
            "alpha_m": 0.0,
            "alpha_f": alpha_f,
            "rho_inf": rho,
        }
    if integrator == "generalized-alpha":
        rho = 0.8 if spectral_radius is None else spectral_radius
        alpha_m = (2 * rho - 1) / (rho + 1)
        alpha_f = rho / (rho + 1)
        return {
            "beta": 0.25 * (1 - alpha_m + alpha_f) ** 2,
            "gamma": 0.5 - alpha_m + alpha_f,
            "alpha_m": alpha_m,
            "alpha_f": alpha_f,
            "rho_inf": rho,
        }
    raise ValueError(f"unknown integrator {integrator!r}")


class TransientError(KernelError):
    """A transient run stopped: the message names the time, the DOF or mesh and the cause."""


@dataclass(frozen=True)
class GrowthDiagnostic:
    """Exponential growth of a recorded response (see :func:`growth_diagnostic`).

    Attributes
    ----------
    channel : int
        Row of the samples that grew most.
    rate : float
        Growth rate sigma of the envelope, exp(sigma t) [1/s].
    frequency : float
        Frequency of the growing oscillation [Hz].
    steps_per_period : float
        Time steps per period of that oscillation [-].
    physical : bool
        True when the growth is resolved by the time step (at least
        ``RESOLVED_STEPS_PER_PERIOD`` steps per period, fewer than one e-fold per
        period): the model's own (e.g. parametric) instability, which a smaller time
        step does not remove.  False: an unresolved, numerical growth.
    """

    channel: int
    rate: float
    frequency: float
    steps_per_period: float
    physical: bool


RESOLVED_STEPS_PER_PERIOD = 10.0
"""Steps per period from which a growing oscillation counts as resolved (Omega h < 0.63)."""


class PhysicalInstabilityError(TransientError):
    """The response grew physically (resolved by the time step) until it crossed a limit:
    an instability of the model, such as a parametric resonance of the mesh stiffness,
    not a failure of the integrator.  ``diagnostic`` holds the measured growth."""

    def __init__(self, message: str, diagnostic: GrowthDiagnostic) -> None:
        super().__init__(message)
        self.diagnostic = diagnostic


def growth_diagnostic(
    samples: np.ndarray, sample_interval: float, time_step: float
) -> GrowthDiagnostic | None:
    """Growth rate and frequency of the channel that grew most over a record.

    The second half of the record is cut at the zero crossings of the channel; the
    largest ``|x|`` of each half cycle, fitted by a straight line in log scale, gives
    the growth rate and the crossing spacing the frequency.

    Parameters
    ----------
    samples : ndarray, shape (n_channel, n_sample)
        Recorded channels (probe samples).
    sample_interval : float
        Time between samples [s].
    time_step : float
        Integrator step [s].

    Returns
    -------
    GrowthDiagnostic or None
        None when no channel grows through at least 6 zero crossings.
    """
    samples = np.atleast_2d(np.asarray(samples, dtype=np.float64))
    best = None
    for channel, series in enumerate(samples):
        tail = series[series.size // 2 :]
        if not np.isfinite(tail).all():
            tail = tail[: np.argmin(np.isfinite(tail))]
        signs = np.sign(tail)
        crossings = np.nonzero(signs[:-1] * signs[1:] < 0)[0] + 1
        if crossings.size < 6:
            continue
        peaks = [np.max(np.abs(tail[a:b])) for a, b in zip(crossings[:-1], crossings[1:])]
        times = 0.5 * (crossings[:-1] + crossings[1:]) * sample_interval
        rate = float(np.polyfit(times, np.log(peaks), 1)[0])
        period = 2.0 * float(np.mean(np.diff(crossings))) * sample_interval
        if best is None or rate > best.rate:
            steps = period / time_step
            physical = rate > 0 and steps >= RESOLVED_STEPS_PER_PERIOD and rate * period < 1
            best = GrowthDiagnostic(channel, rate, 1.0 / period, steps, bool(physical))
    return best


INTERRUPT_SIGNALS = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM") if hasattr(signal, name)
)
"""Signals that stop a run cleanly between chunks: Ctrl-C, and SIGTERM (what a batch
scheduler such as SLURM sends before it kills a job)."""


class TransientInterrupted(KeyboardInterrupt):
    """Ctrl-C or SIGTERM stopped a run between two chunks; no result was written.

    Attributes
    ----------
    signal_number : int
        The signal that stopped the run (SIGINT for Ctrl-C or a KeyboardInterrupt).
    """

    def __init__(self, message: str = "", signal_number: int = signal.SIGINT) -> None:
        super().__init__(message)
        self.signal_number = int(signal_number)


def kernel_error(
    ierr: int,
    bad: int,
    step: int,
    phase: str,
    *,
    time_step: float,
    labels: Sequence[str],
    order: np.ndarray,
    mesh_names: Sequence[str],
    mode: str,
    max_iterations: int,
    deflection_limit: float,
) -> TransientError:
    """A message naming the time, the DOF or mesh and the likely cause."""
    when = f"at t = {step * time_step:.6g} s (step {step})" if step else "at t = 0"
    dof = labels[order[bad - 1]] if 1 <= bad <= len(labels) else None
    mesh = mesh_names[bad - 1] if 1 <= bad <= len(mesh_names) else None
    if ierr == 1:
        if 1 <= bad <= len(RPARAM_LAYOUT):
            setting = RPARAM_LAYOUT[bad - 1]
        elif 101 <= bad <= 100 + len(IPARAM_LAYOUT):
            setting = IPARAM_LAYOUT[bad - 101]
        else:
            setting = f"entry {bad}"
        return TransientError(f"transient {phase}: setting {setting} is out of range")
    if ierr == 2:
        return TransientError(
            f"transient {phase} {when}: the effective matrix Khat is not positive definite "
            f"at DOF {dof}; likely cause: a negative stiffness or mass, or a mesh stiffness "
            f"far below its mean in the refactored matrix"
        )
    if ierr == 3:
        return TransientError(
            f"transient {phase}: the mass matrix is not positive definite at DOF {dof}; "
            f"every DOF needs mass to start from rest"
        )
    cause = (
        "the explicit mesh-stiffness variation of equivalent_load='predictor' is "
        "unstable at this time step: use equivalent_load='iterate' or 'refactor', or a "
        "smaller time_step"
        if mode == "predictor"
        else "the time step is too large for the stiffness variation, or the loads or "
        "matrices are not physical: reduce time_step and check the case"
    )
    if ierr == 4:
        return TransientError(
            f"transient {phase} {when}: the state is not finite or exploded at DOF {dof}; "
            f"likely cause: {cause}"
        )
    if ierr == 5:
        return TransientError(
            f"transient {phase} {when}: the deflection of mesh {mesh} exceeds "
            f"deflection_limit = {deflection_limit:g} m (the solution is diverging); "
            f"likely cause: {cause}"
        )
    if ierr == 6 and bad == 0:  # the gyroscopic force's iteration (newmark_gyroscopic)
        return TransientError(
            f"transient {phase} {when}: the gyroscopic force did not converge in "
            f"{max_iterations} iterations; likely cause: a time step too long for the "
            f"speed (the iteration contracts by about time_step x speed): reduce time_step"
        )
    if ierr == 6:
        return TransientError(
            f"transient {phase} {when}: equivalent_load={mode!r} did not converge in "
            f"{max_iterations} iterations (mesh {mesh} changes most); likely cause: a "
            f"stiffness change too large for one factor: use equivalent_load='refactor', "
            f"more max_iterations or a smaller time_step"
        )
    if ierr == 7:
        return TransientError(
            f"transient {phase} {when}: the tooth-contact table failed (a mesh angle is not "
            f"finite or beyond 2**50 mesh cycles); likely cause: {cause}"
        )
    if ierr == 10:
        return TransientError(
            f"transient {phase}: the kernel's handle of the problem or of its tooth-contact "
            f"table is not live"
        )
    if ierr == 11:
        return TransientError(f"transient {phase}: the kernel holds too many problems (65535)")
    if ierr == 12:
        return TransientError(
            f"transient {phase}: linear_solver 'sparse_cholesky' needs CHOLMOD, and this "
            "build of pygear has none: install SuiteSparse (Debian: libsuitesparse-dev) and "
            "rebuild, or use linear_solver='banded_cholesky'"
        )
    return TransientError(f"transient {phase} {when}: kernel error code {ierr}")


@contextlib.contextmanager
def deferred_interrupt():
    """Turn Ctrl-C and SIGTERM into a flag checked between chunks (main thread only); a
    KeyboardInterrupt raised anyway (e.g. by a progress callback) sets it too.

    The flag's ``signal_number`` names the signal that set it (SIGINT by default); a
    second signal stops at once, without a checkpoint.
    """
    flag = threading.Event()
    flag.signal_number = int(signal.SIGINT)
    previous = {}
    main = threading.current_thread() is threading.main_thread()
    if main:

        def handler(signum, frame):
            if flag.is_set():  # a second signal: stop now
                raise TransientInterrupted(
                    f"interrupted again by {signal.Signals(signum).name}; stopped at once, "
                    "no checkpoint and no result file written",
                    signum,
                )
            flag.signal_number = int(signum)
            flag.set()

        for number in INTERRUPT_SIGNALS:
            previous[number] = signal.getsignal(number)
            signal.signal(number, handler)
    try:
        try:
            yield flag
        except KeyboardInterrupt as error:
            if isinstance(error, TransientInterrupted):
                raise
            raise TransientInterrupted(
                "interrupted; no result file written", flag.signal_number
            ) from None
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)


def checkpoint_key(
    arrays: Sequence, settings: tuple, probes: Sequence, probe_arrays: Sequence
) -> str:
    """Hash (16 hex digits) of everything that shapes a run's state and its samples.

    Parameters
    ----------
    arrays : sequence of array-like
        The solver's matrices, parameters and mesh arrays.
    settings : tuple
        Steps, decimation, averaging window and the caller's identity string.
    probes : sequence of KernelProbe
        The channels: each one's name, kind, mesh and attributes (units, target).
    probe_arrays : sequence of array-like
        The kernel's probe arrays (kinds, weights and the DOFs they act on) and any
        initial state given, so a probe retargeted under the same name differs.
    """
    import hashlib

    digest = hashlib.sha256()
    for array in (*arrays, *probe_arrays):
        array = np.ascontiguousarray(array)
        digest.update(f"{array.dtype.str}{array.shape}".encode())
        digest.update(array.tobytes())
    channels = [(p.name, p.kind, p.mesh, sorted(p.attrs.items())) for p in probes]
    digest.update(repr((settings, channels)).encode())
    return digest.hexdigest()[:16]


SMALL_MODEL_DOFS = 300
"""Below this many DOFs a step's solve is a few microseconds of work: BLAS threads only
cost (waking them, and on a loaded machine waiting for cores others hold: a 144 x 144
solve measured 225 ms instead of 1.8 ms with every OpenBLAS thread on a busy host)."""


def blas_threads(n: int) -> int:
    """BLAS threads for a model of ``n`` DOFs: 1 below :data:`SMALL_MODEL_DOFS`, else one
    per ``SMALL_MODEL_DOFS`` DOFs up to the cores this process may use; the environment
    variable ``PYGEAR_BLAS_THREADS`` overrides it."""
    given = os.environ.get("PYGEAR_BLAS_THREADS", "").strip()
    if given.isdigit() and int(given) >= 1:
        return int(given)
    if n < SMALL_MODEL_DOFS:
        return 1
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cores = os.cpu_count() or 1
    return max(1, min(cores, n // SMALL_MODEL_DOFS))


@functools.lru_cache(maxsize=1)
def _blas_controller():
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()  # a search of the loaded libraries: once


def limited_blas(threads: int):
    """A context in which every loaded BLAS (NumPy's, the kernel's) runs ``threads``
    threads; the previous limits come back after it."""
    return _blas_controller().limit(limits=int(threads), user_api="blas")


SINK_PREFIX = "sink__"
"""Prefix of a streamed run's sink state in a checkpoint (filters, statistics, residues)."""


def save_checkpoint(
    path, key: str, state: dict, samples: np.ndarray, written: int, extra: dict | None = None
) -> None:
    """Write the state (and the samples so far, or a streamed run's sink state as
    ``extra``) to ``path`` atomically."""
    from ..io import atomic_path

    path = Path(path)
    kept = {f"{SINK_PREFIX}{name}": value for name, value in (extra or {}).items()}
    streamed = int(extra is not None)
    with atomic_path(path) as temporary, open(temporary, "wb") as handle:
        np.savez(
            handle, key=key, written=written, samples=samples, streamed=streamed, **state, **kept
        )


def load_checkpoint(path, key: str, samples: np.ndarray | None):
    """The state and the number of samples written; the samples go into ``samples``.

    With ``samples`` None (a streamed run) returns ``(state, written, sink_state)``: the
    samples are in the sink's file, and a checkpoint of a run that kept them in memory
    is refused (its file would miss them)."""
    with np.load(path) as data:
        if str(data["key"]) != key:
            raise TransientError(
                f"resume: checkpoint {path} was written by different settings or inputs"
            )
        written = int(data["written"])
        streamed = "streamed" in data.files and int(data["streamed"])
        if samples is None and not streamed and written:
            raise TransientError(
                f"resume: checkpoint {path} holds its samples, not a streamed file's state; "
                "resume it without streaming"
            )
        if samples is not None and streamed and written:
            raise TransientError(
                f"resume: checkpoint {path} belongs to a streamed run (its samples are in "
                "the partial file); resume it streamed"
            )
        if samples is not None:
            samples[:, :written] = data["samples"]
        skip = ("key", "written", "samples", "streamed")
        state = {
            name: np.asfortranarray(data[name]) if data[name].ndim > 1 else np.array(data[name])
            for name in data.files
            if name not in skip and not name.startswith(SINK_PREFIX)
        }
        sink = {
            name.removeprefix(SINK_PREFIX): np.array(data[name])
            for name in data.files
            if name.startswith(SINK_PREFIX)
        }
    if samples is None:
        return state, written, sink
    return state, written
