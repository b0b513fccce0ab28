"""Banded Newmark integration of a reduced model through the Fortran kernel.

:class:`BandedNewmark` takes M, C, K0 (any symmetric matrices over the same DOFs),
orders the DOFs by reverse Cuthill-McKee on the pattern of M + C + K0 + sum b b^T,
stores them as LAPACK band matrices, hands them to the kernel once as a problem
(``transient_problem_create``, which returns a handle) and runs ``transient_start`` /
``transient_advance`` on it (``fortran/newmark.f90``).  The kernel advances a chunk of
steps per call and returns its whole state, so this module shows progress, stops
cleanly between chunks on Ctrl-C, writes checkpoints, and turns error codes into
:class:`TransientError` messages naming the time, the DOF or mesh and the likely
cause.  Nothing here knows about gearboxes: :mod:`pygear.analysis.time.transient` builds the
inputs from a case.

This module is longer than 600 lines because the chunked run loop, its checkpoints
and its interrupt handling share the integrator's state; the argument packing and
error decoding already live in :mod:`pygear.kernel.newmark_support`.
"""

from __future__ import annotations

import functools
import math
import os
import signal
import time
import weakref
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from . import _kernel
from .bearing_terms import BearingTerms, bearing_arguments
from .newmark_rebase import RigidRebase
from .newmark_rotor import RotorTerms, rotor_arguments
from .newmark_storage import is_sparse_matrix, kernel_storage
from .newmark_support import (
    EQUIVALENT_LOAD_CODES,
    ISTATE_LAYOUT,
    LAW_CODES,
    LINEAR_SOLVER_CODES,
    PROBE_CODES,
    GrowthDiagnostic,
    PhysicalInstabilityError,
    TransientError,
    TransientInterrupted,
    blas_threads,
    checkpoint_key,
    deferred_interrupt,
    growth_diagnostic,
    kernel_error,
    limited_blas,
    load_checkpoint,
    save_checkpoint,
    scheme_coefficients,
)

__all__ = [
    "EQUIVALENT_LOAD_CODES",
    "LAW_CODES",
    "PROBE_CODES",
    "BandedNewmark",
    "GrowthDiagnostic",
    "KernelProbe",
    "LawArrays",
    "MeshTerms",
    "PhysicalInstabilityError",
    "RunResult",
    "SampleSink",
    "TransientError",
    "TransientInterrupted",
    "growth_diagnostic",
    "scheme_coefficients",
]


@dataclass
class MeshTerms:
    """Meshes whose stiffness varies (equivalent load) over the integrator's DOFs.

    Attributes
    ----------
    deflection : ndarray, shape (n_mesh, n)
        b_m [m/m, m/rad].
    mean_stiffness : ndarray, shape (n_mesh,)
        kbar_m, the stiffness inside K0 [N/m].
    contact_sign : ndarray of int, shape (n_mesh,)
        s_m: s_m delta_m > 0 means teeth pressed together.
    angle : ndarray, shape (n_mesh, n)
        theta_m = angle[m] . q, gear 1's rotation relative to the carrier [rad/rad].
    table : object or None
        A :class:`pygear.assembly.contact_table.ContactTable` (time-varying stiffness) or None.
    time_varying, separation : bool
        Effects in force.
    names : list of str
        Mesh names for messages.
    backlash : ndarray, shape (n_mesh,), optional
        b_m >= 0 [m]: the gap between the coast flanks along b_m when the drive flanks
        touch (module ``flank_contact`` of the kernel).  With ``separation`` the force is
        k delta on the drive flank (s delta > 0), 0 while -b <= s delta <= 0 and
        k_coast (delta + s b) on the coast flank.  ``inf`` (the default, None) leaves
        the coast flank out: the teeth part without limit.
    coast_phase : ndarray, shape (n_mesh,), optional
        Phase of the coast flanks' mesh stiffness against the drive flanks' [mesh
        cycles]; default 0 (the drive flank's phase, an assumption for symmetric teeth).
    damping : ndarray, shape (n_mesh,), optional
        c_m >= 0 [N s/m]: the share c_m b_m b_m^T of the damping matrix that is the
        mesh's own damper (beta kbar_m of Rayleigh damping beta K0); default 0.  The
        damping matrix keeps it; with ``separation`` the kernel takes it out while the
        flanks are apart, so the damper acts only in contact, like the spring.  The
        ``mesh_force`` probe reports k delta + c_m delta' in contact, 0 across the gap.
    """

    deflection: np.ndarray
    mean_stiffness: np.ndarray
    contact_sign: np.ndarray
    angle: np.ndarray
    table: object | None = None
    time_varying: bool = False
    separation: bool = False
    names: list[str] = field(default_factory=list)
    backlash: np.ndarray | None = None
    coast_phase: np.ndarray | None = None
    damping: np.ndarray | None = None

    def __post_init__(self) -> None:
        for name, default in (("backlash", math.inf), ("coast_phase", 0.0), ("damping", 0.0)):
            given = getattr(self, name)
            values = np.full(self.size, default) if given is None else given
            values = np.array(values, dtype=np.float64).reshape(-1)
            if values.shape != (self.size,):
                raise ValueError(f"MeshTerms.{name} must hold one value per mesh ({self.size})")
            setattr(self, name, values)
        if not np.all(self.backlash >= 0):
            raise ValueError(
                f"MeshTerms.backlash must be >= 0 m or inf (got {self.backlash.tolist()})"
            )
        if not np.all((self.damping >= 0) & np.isfinite(self.damping)):
            raise ValueError(
                f"MeshTerms.damping must be finite and >= 0 N s/m (got {self.damping.tolist()})"
            )
        if not np.all(np.isfinite(self.coast_phase)):
            raise ValueError(
                f"MeshTerms.coast_phase must be finite (got {self.coast_phase.tolist()})"
            )

    @property
    def size(self) -> int:
        """Number of meshes."""
        return len(self.mean_stiffness)


@dataclass
class LawArrays:
    """A torque law as the kernel takes it: code, 4 parameters, (time, torque) table."""

    kind: str = "none"
    param: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    times: Sequence[float] = ()
    torques: Sequence[float] = ()


@dataclass
class KernelProbe:
    """One output channel: a kernel probe kind and its weights over the DOFs (or a mesh)."""

    name: str
    kind: str
    weights: np.ndarray | None = None  # over the DOFs (linear kinds)
    mesh: int = -1  # 0-based mesh index (mesh kinds)
    attrs: dict = field(default_factory=dict)


@dataclass
class RunResult:
    """What one run returns.

    Attributes
    ----------
    time : ndarray
        Sample times [s].
    samples : ndarray, shape (n_probe, n_time)
        Probe values.
    q, v, a : ndarray
        Final state in the caller's DOF order.
    mean_velocity : ndarray
        Mean velocity of every DOF over the averaging window (NaN without window).
    t_s : float
        First instant the input speed reached omega_0 (NaN if never).
    steps : int
        Steps completed.
    counters : dict
        Iterations, refactors, the most iterations in one step, mesh-steps without force
        (``separated``) and on the coast flank (``coast``), and tooth-contact table
        evaluations (``contact_evaluations``: calls of the kernel's table, each for every
        mesh at once, two per step with a finite backlash; 0 at constant mesh stiffness).
    solver_wall_s : float
        Wall time spent inside the kernel [s].
    """

    time: np.ndarray
    samples: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    mean_velocity: np.ndarray
    t_s: float
    steps: int
    counters: dict
    solver_wall_s: float


class SampleSink(Protocol):
    """Where a streamed run's samples go (:meth:`BandedNewmark.run` with ``sink``).

    ``block_samples`` caps the samples of one kernel call; ``write(first, samples)``
    receives samples ``first ..`` of the run as (probe, sample) (a view: copy what is
    kept); ``flush()`` makes everything received durable; ``state()`` is what the sink
    carries between chunks (filter states, running statistics, rainflow residues) as
    arrays for a checkpoint, and ``restore(state, written)`` takes it back on resuming
    at sample ``written``.
    """

    block_samples: int

    def write(self, first: int, samples: np.ndarray) -> None: ...

    def flush(self) -> None: ...

    def state(self) -> dict: ...

    def restore(self, state: dict, written: int) -> None: ...


def _blas_limited(method):
    """Run ``method`` with the BLAS threads the model needs (:func:`blas_threads`: one
    below a few hundred DOFs), the previous limits restored after it."""

    @functools.wraps(method)
    def limited(self, *args, **kwargs):
        with limited_blas(getattr(self, "blas_threads", 1)):
            return method(self, *args, **kwargs)

    return limited


def _last_samples(tail: list, fresh: np.ndarray, limit: int) -> list:
    """``tail`` (blocks of samples, oldest first) with a copy of ``fresh`` added and the
    oldest blocks dropped while the rest still hold ``limit`` samples (joined only if a
    run diverges: :func:`_joined`)."""
    tail.append(fresh.copy())
    while len(tail) > 1 and sum(b.shape[1] for b in tail[1:]) >= limit:
        tail.pop(0)
    return tail


def _joined(tail: list, limit: int, rows: int) -> np.ndarray:
    """The last ``limit`` samples of the blocks in ``tail`` (none yet: no samples)."""
    if not tail:
        return np.zeros((rows, 0))
    return np.concatenate(tail, axis=1)[:, -limit:]


class BandedNewmark:
    """Banded implicit integrator of M q'' + C q' + K0 q = F(t) - N(q, t).

    Parameters
    ----------
    mass, damping, stiffness : ndarray, shape (n, n)
        M, C and K0 (mean mesh stiffness).
    time_step : float
        Delta t [s].
    integrator : str
        ``newmark``, ``hht`` or ``generalized-alpha``.
    spectral_radius : float, optional
        rho_inf of HHT or generalized-alpha.
    meshes : MeshTerms, optional
        Meshes with time-varying stiffness or tooth separation.
    equivalent_load : str
        ``predictor``, ``iterate`` or ``refactor``; ignored without mesh terms.
    restart_at_jumps : bool
        When a mesh stiffness jumps by more than ``refactor_threshold`` of its mean
        between two steps, take the acceleration at the step start from the equation
        of motion with the new stiffness (average acceleration, no tooth separation).
    drive, load : LawArrays, optional
        Torque on the input member, torque against the output member.
    input_weights, output_weights : ndarray, optional
        Members as rotations per DOF (rows of the reduction matrix).
    speed_reference : float
        omega_0 [rad/s] for t_s (0: none).
    labels : sequence of str, optional
        DOF names for messages.
    linear_solver : str
        ``auto`` (by the model's size and the entries a step reads,
        :mod:`~pygear.kernel.newmark_storage`), ``dense_refined`` (a dense inverse with
        one step of iterative refinement), ``banded_cholesky``, ``sparse_cholesky``
        (CHOLMOD) or ``dense_inverse`` (not backward stable): how the kernel solves
        Khat a = rhs; the environment variable ``PYGEAR_LINEAR_SOLVER``
        overrides it.  ``linear_solver`` and ``linear_solver_reason`` hold the choice.
        M, C and K0 may be SciPy sparse matrices (flexible drivetrains).
    rotor : RotorTerms, optional
        Gyroscopic force -Omega(t) G v and unbalances (:mod:`~pygear.kernel.newmark_rotor`).
    """

    def __init__(
        self,
        mass: np.ndarray | object,
        damping: np.ndarray | object,
        stiffness: np.ndarray | object,
        time_step: float,
        *,
        integrator: str = "newmark",
        spectral_radius: float | None = None,
        meshes: MeshTerms | None = None,
        equivalent_load: str = "predictor",
        tolerance: float = 1e-8,
        max_iterations: int = 50,
        refactor_threshold: float = 0.1,
        max_refactors: int = 3,
        restart_at_jumps: bool = False,
        drive: LawArrays | None = None,
        load: LawArrays | None = None,
        input_weights: np.ndarray | None = None,
        output_weights: np.ndarray | None = None,
        speed_reference: float = 0.0,
        deflection_limit: float = 1e-3,
        acceleration_limit: float = 1e15,
        labels: Sequence[str] | None = None,
        linear_solver: str = "auto",
        rotor: RotorTerms | None = None,
        bearings: BearingTerms | None = None,
    ) -> None:
        mass, damping, stiffness = (
            x if is_sparse_matrix(x) else np.asarray(x, dtype=np.float64)
            for x in (mass, damping, stiffness)
        )
        n = mass.shape[0]
        self.n = n
        self.labels = list(labels) if labels is not None else [f"dof {i}" for i in range(n)]
        self.time_step = float(time_step)
        self.integrator = integrator
        self.coefficients = scheme_coefficients(integrator, spectral_radius)
        self.meshes = meshes if meshes is not None and meshes.size else None
        nonlinear = self.meshes is not None and (self.meshes.time_varying or self.meshes.separation)
        # rolling bearings (fortran/rolling_bearing.f90) join the meshes' equivalent load
        self.bearings = bearings if bearings is not None and bearings.size else None
        if self.bearings is not None and equivalent_load == "linear":
            equivalent_load = "iterate"
        self.equivalent_load = (
            equivalent_load if nonlinear or self.bearings is not None else "linear"
        )

        storage = kernel_storage(
            mass,
            damping,
            stiffness,
            self.meshes.deflection if self.meshes is not None else None,
            linear_solver,
        )
        dense = storage.linear_solver in ("dense_inverse", "dense_refined")
        if self.bearings is not None and dense:
            # the dense operators hold load columns for the meshes only
            storage = kernel_storage(
                mass,
                damping,
                stiffness,
                self.meshes.deflection if self.meshes is not None else None,
                "banded_cholesky",
            )
        self.order = storage.order
        self.position = np.empty(n, dtype=int)
        self.position[self.order] = np.arange(n)
        self.bandwidth = storage.bandwidth
        self.linear_solver, self.linear_solver_reason = storage.linear_solver, storage.reason
        self.bands = storage.bands
        self.blas_threads = blas_threads(n)  # what a step's solve can use
        self.sparse_arguments = storage.sparse

        c = self.coefficients
        self.rparam = np.array(
            [
                self.time_step,
                c["beta"],
                c["gamma"],
                c["alpha_m"],
                c["alpha_f"],
                tolerance,
                refactor_threshold,
                deflection_limit,
                speed_reference,
                acceleration_limit,
            ],
            dtype=np.float64,
        )
        self.iparam = np.array(
            [
                EQUIVALENT_LOAD_CODES[self.equivalent_load],
                max_iterations,
                int(bool(nonlinear and self.meshes.time_varying)),
                int(bool(nonlinear and self.meshes.separation)),
                max_refactors,
                int(bool(restart_at_jumps)),
                LINEAR_SOLVER_CODES[self.linear_solver],
            ],
            dtype=np.int32,
        )
        self.input_weights, self.output_weights = (
            np.zeros(n) if w is None else np.asarray(w, dtype=np.float64)
            for w in (input_weights, output_weights)
        )
        self.arguments = {
            **self._mesh_arguments(),
            **self._load_arguments(
                drive or LawArrays(), load or LawArrays(), input_weights, output_weights
            ),
        }
        self.rotor_arguments = rotor_arguments(rotor, self.position) if rotor is not None else {}
        table = self.meshes.table if self.meshes is not None and self.meshes.time_varying else None
        self.table = table
        self._problem_handle: int | None = None
        self.rebase = RigidRebase(
            mass,
            stiffness,
            self.order,
            angle=self.meshes.angle if table is not None else None,
            cycle_sign=table.cycle_sign if table is not None else None,
            teeth=table.teeth if table is not None else None,
        )
        if self.bearings is not None:  # the cage angle is the rings' angles: keep them whole
            self.rebase.modes = np.zeros((n, 0))

    # --- set-up ------------------------------------------------------------------------------

    def _sparse_rows(self, rows: Sequence[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Pointers, 1-based RCM positions and values of sparse rows over the DOFs."""
        pointers, index, value = [0], [], []
        for row in rows:
            nz = np.nonzero(row)[0]
            index.extend(self.position[nz] + 1)
            value.extend(np.asarray(row)[nz])
            pointers.append(len(index))
        return (
            np.array(pointers, dtype=np.int32),
            np.array(index or [1], dtype=np.int32),
            np.array(value or [0.0], dtype=np.float64),
        )

    def _mesh_arguments(self) -> dict:
        meshes = self.meshes
        if meshes is None:
            # f2py refuses zero-size arrays: one inert mesh without entries, never evaluated
            ptr, idx, val = self._sparse_rows([np.zeros(self.n)])
            arguments = {
                "mesh_ptr": ptr,
                "mesh_index": idx,
                "mesh_value": val,
                "angle_ptr": ptr,
                "angle_index": idx,
                "angle_value": val,
                "mean_stiffness": np.ones(1),
                "contact_sign": np.ones(1, np.int32),
                "backlash": np.full(1, math.inf),
                "coast_phase": np.zeros(1),
                "mesh_damping": np.zeros(1),
            }
            return arguments
        ptr, idx, val = self._sparse_rows(list(meshes.deflection))
        angle_ptr, angle_idx, angle_val = self._sparse_rows(list(meshes.angle))
        return {
            "mesh_ptr": ptr,
            "mesh_index": idx,
            "mesh_value": val,
            "angle_ptr": angle_ptr,
            "angle_index": angle_idx,
            "angle_value": angle_val,
            "mean_stiffness": np.asarray(meshes.mean_stiffness, dtype=np.float64),
            "contact_sign": np.asarray(meshes.contact_sign, dtype=np.int32),
            "backlash": np.asarray(meshes.backlash, dtype=np.float64),
            "coast_phase": np.asarray(meshes.coast_phase, dtype=np.float64),
            "mesh_damping": np.asarray(meshes.damping, dtype=np.float64),
        }

    def _load_arguments(self, drive, load, input_weights, output_weights) -> dict:
        zero = np.zeros(self.n)
        members = [
            zero if w is None else np.asarray(w, float) for w in (input_weights, output_weights)
        ]
        ptr, idx, val = self._sparse_rows(members)
        tables, starts, sizes, offset = [], [], [], 0
        for law in (drive, load):
            table = np.array([law.times, law.torques], dtype=np.float64).reshape(2, -1)
            tables.append(table)
            starts.append(offset)
            sizes.append(table.shape[1])
            offset += table.shape[1]
        law_table = np.concatenate(tables + [np.zeros((2, 1))], axis=1)
        return {
            "load_ptr": ptr,
            "load_index": idx,
            "load_value": val,
            "law_kind": np.array([LAW_CODES[drive.kind], LAW_CODES[load.kind]], dtype=np.int32),
            "law_param": np.asfortranarray(np.array([drive.param, load.param], dtype=float).T),
            "law_start": np.array(starts, dtype=np.int32),
            "law_size": np.array(sizes, dtype=np.int32),
            "law_table": np.asfortranarray(law_table),
        }

    def _probe_arguments(self, probes: Sequence[KernelProbe]) -> dict:
        rows, kinds = [], []
        for probe in probes:
            kinds.append(PROBE_CODES[probe.kind])
            if probe.kind in ("mesh_force", "mesh_stiffness"):
                rows.append(None)
            else:
                rows.append(np.zeros(self.n) if probe.weights is None else probe.weights)
        pointers, index, value = [0], [], []
        for probe, row in zip(probes, rows):
            if row is None:
                index.append(probe.mesh + 1)
                value.append(1.0)
            else:
                nz = np.nonzero(row)[0]
                index.extend(self.position[nz] + 1)
                value.extend(np.asarray(row)[nz])
            pointers.append(len(index))
        return {
            "probe_kind": np.array(kinds, dtype=np.int32),
            "probe_ptr": np.array(pointers, dtype=np.int32),
            "probe_index": np.array(index or [1], dtype=np.int32),
            "probe_value": np.array(value or [0.0], dtype=np.float64),
        }

    def _problem(self) -> int:
        """The kernel's handle of this problem, created (and checked) on first use; the
        kernel keeps the matrices, settings, meshes and loads until this object is
        garbage collected."""
        if self._problem_handle is None:
            handle, bad, ierr = _kernel.transient_problem_create(
                mass_band=self.bands["mass"],
                damping_band=self.bands["damping"],
                stiffness_band=self.bands["stiffness"],
                rparam=self.rparam,
                iparam=self.iparam,
                table_handle=self.table.handle if self.table is not None else 0,
                **self.arguments,
                **self.sparse_arguments,
            )
            if ierr:
                raise self._error(int(ierr), int(bad), 0, "starting")
            self._problem_handle = int(handle)
            weakref.finalize(self, _kernel.transient_problem_free, int(handle)).atexit = False
            if self.rotor_arguments:
                bad, ierr = _kernel.transient_problem_set_rotor(
                    handle=handle,
                    n=self.n,
                    kd=self.bandwidth,
                    n_mesh=len(self.arguments["mean_stiffness"]),
                    **self.rotor_arguments,
                )
                if ierr:
                    raise ValueError(
                        f"rotor terms refused by the kernel (code {int(ierr)}, entry {int(bad)})"
                    )
            if self.bearings is not None:
                bad, ierr = _kernel.transient_problem_bearings(
                    handle=int(handle),
                    n=self.n,
                    kd=self.bandwidth,
                    n_mesh=len(self.arguments["mean_stiffness"]),
                    **bearing_arguments(self.bearings, self.position),
                )
                if ierr:
                    raise ValueError(
                        f"rolling bearings refused by the kernel (entry {int(bad)}: a bearing's "
                        "constants, a defect, or the dense solver)"
                    )
        return self._problem_handle

    def _table_phases(self) -> dict:
        """The tooth-contact table's phases and tooth offsets as a run starts (zeros, for
        the kernel's one inert mesh, without a table)."""
        if self.table is not None:
            return {"phase": self.table.phase, "tooth_offset": self.table.tooth_offset}
        n_mesh = len(self.arguments["mean_stiffness"])
        return {"phase": np.zeros(n_mesh), "tooth_offset": np.zeros((2, n_mesh), np.int32)}

    def __getstate__(self) -> dict:
        """The solver without its kernel handle, which is valid only in this process."""
        state = dict(self.__dict__)
        state["_problem_handle"] = None
        return state

    # --- running -----------------------------------------------------------------------------

    @_blas_limited
    def start(
        self,
        q0: np.ndarray | None = None,
        v0: np.ndarray | None = None,
        a0: np.ndarray | None = None,
    ) -> dict:
        """Factor Khat and find the initial acceleration (or take ``a0``); the state of step 0."""
        q0 = np.zeros(self.n) if q0 is None else np.asarray(q0, dtype=np.float64)
        v0 = np.zeros(self.n) if v0 is None else np.asarray(v0, dtype=np.float64)
        out = _kernel.transient_start(
            handle=self._problem(),
            kd=self.bandwidth,
            n_mesh=len(self.arguments["mean_stiffness"]),
            q=q0[self.order],
            v=v0[self.order],
        )
        a, k_used, mesh_var, k_factored, factor, rstate, istate, bad, ierr = out
        if ierr:
            raise self._error(int(ierr), int(bad), 0, "starting")
        return {
            "q": np.array(q0[self.order], dtype=np.float64),
            "v": np.array(v0[self.order], dtype=np.float64),
            "a": np.array(a if a0 is None else np.asarray(a0, np.float64)[self.order]),
            "k_used": np.array(k_used, dtype=np.float64),
            "mesh_var": np.array(mesh_var, dtype=np.float64),
            "k_factored": np.array(k_factored, dtype=np.float64),
            "factor": np.asfortranarray(factor),
            "velocity_sum": np.zeros(self.n),
            "rstate": np.array(rstate, dtype=np.float64),
            "istate": np.array(istate, dtype=np.int32),
        }

    @_blas_limited
    def run(
        self,
        n_steps: int,
        probes: Sequence[KernelProbe] = (),
        *,
        decimation: int = 1,
        window_steps: int = 0,
        q0: np.ndarray | None = None,
        v0: np.ndarray | None = None,
        a0: np.ndarray | None = None,
        progress: Callable[[int, int], None] | None = None,
        chunk_seconds: float = 0.1,
        checkpoint: str | os.PathLike | None = None,
        checkpoint_every: float = 60.0,
        resume: str | os.PathLike | None = None,
        identity: str = "",
        sink: SampleSink | None = None,
    ) -> RunResult:
        """Integrate ``n_steps`` steps and record ``probes`` every ``decimation`` steps.

        Parameters
        ----------
        n_steps : int
            Steps to take.
        probes : sequence of KernelProbe
            Output channels.
        decimation : int
            Steps per sample (sample 0 is the initial state).
        window_steps : int
            Average the velocities over the last ``window_steps`` steps.
        q0, v0 : ndarray, optional
            Initial state (zero by default).
        a0 : ndarray, optional
            Initial acceleration (default: from the equation of motion at t = 0); a state
            off the equation of motion gives the columns of the amplification matrix.
        progress : callable, optional
            ``progress(done, total)`` after every chunk.
        chunk_seconds : float
            Target wall time of one kernel call [s].
        checkpoint : path, optional
            Write the whole state here every ``checkpoint_every`` seconds, on Ctrl-C or
            SIGTERM, and once the last step is taken (so a finished run survives until
            its caller has written the result and removes the file).
        resume : path, optional
            Continue from a checkpoint written by the same settings.
        identity : str
            What else shapes the state and the outputs and the matrices do not show
            (the case, the scene, the code version); a checkpoint of another identity
            is refused.
        sink : SampleSink, optional
            Hand the samples to ``sink`` chunk by chunk instead of keeping them: the run
            then holds at most ``sink.block_samples`` samples per probe (memory O(chunk),
            whatever its length), its result has no samples, and a checkpoint holds the
            sink's own state (:meth:`SampleSink.state`) instead of the samples, which the
            sink has flushed (to its file) before the checkpoint is written.

        Raises
        ------
        TransientError
            The state stopped being finite or a mesh deflection ran away; the
            message names the time, the DOF or mesh and the likely cause.
        TransientInterrupted
            Ctrl-C or SIGTERM; the run stopped between two chunks (state checkpointed
            if asked), or after its last step when a checkpoint holds it.
        """
        if n_steps < 1 or decimation < 1:
            raise ValueError("n_steps and decimation must be >= 1")
        window_steps = min(max(int(window_steps), 0), n_steps)
        recording = {
            "decimation": decimation,
            "window_first_step": n_steps - window_steps + 1 if window_steps else 0,
        }
        n_samples = n_steps // decimation + 1
        if sink is not None:  # a chunk of s steps records at most s // decimation + 1 samples
            block = max(int(sink.block_samples), 2)
            max_chunk = (block - 1) * decimation
            samples = np.zeros((max(len(probes), 1), block), order="F")
        else:
            max_chunk = n_steps
            samples = np.zeros((max(len(probes), 1), n_samples), order="F")
        probe_args = (
            self._probe_arguments(probes)
            if probes
            else self._probe_arguments([KernelProbe("none", "drive_torque")])
        )
        table = self.table.kernel_arguments() if self.table is not None else ()
        key = checkpoint_key(
            (
                *self.bands.values(),
                *self.sparse_arguments.values(),
                self.rparam,
                self.iparam,
                *self.arguments.values(),
                *self.rotor_arguments.values(),
                *table,
            ),
            (n_steps, decimation, window_steps, identity),
            probes,
            (*probe_args.values(), *(x for x in (q0, v0, a0) if x is not None)),
        )
        if resume is not None and sink is not None:
            state, written, kept = load_checkpoint(resume, key, None)
            sink.restore(kept, written)
        elif resume is not None:
            state, written = load_checkpoint(resume, key, samples)
        else:
            state, written = self.start(q0, v0, a0), 0
        saved_step = int(state["istate"][ISTATE_LAYOUT.index("step")]) if resume is not None else -1
        if "rigid_offset" not in state:
            state.update(self.rebase.initial_state(self._table_phases()))
        rigid_probes = [
            (p, np.asarray(probe.weights, dtype=np.float64)[self.order])
            for p, probe in enumerate(probes)
            if probe.kind == "displacement" and probe.weights is not None and self.rebase.active
        ]
        step_of = ISTATE_LAYOUT.index("step")
        chunk = max(100, min(20000, n_steps // 50 or 1))
        chunk = min(chunk, max_chunk)
        base = written if sink is not None else 0  # the run's sample at samples[:, 0]
        tail: list = []  # with a sink: the last samples, for a diverged run's diagnostic
        solver_wall = 0.0
        last_checkpoint = time.perf_counter()
        with deferred_interrupt() as interrupted:
            while state["istate"][step_of] < n_steps:
                step = int(state["istate"][step_of])
                steps = self.rebase.aligned_steps(step, int(min(chunk, n_steps - step)))
                started = time.perf_counter()
                written_now, bad, ierr = self._advance(
                    state, recording, probe_args, steps, samples, written - base
                )
                elapsed = time.perf_counter() - started
                solver_wall += elapsed
                local = written - base
                if rigid_probes and written_now:  # give displacements their rigid rotation
                    for p, weights in rigid_probes:
                        offset = self.rebase.probe_offsets(weights, state)
                        if offset:
                            samples[p, local : local + written_now] += offset
                if sink is not None and written_now:
                    fresh = samples[: len(probes), local : local + written_now]
                    sink.write(written, fresh)
                    tail = _last_samples(tail, fresh, max(block, 4096))
                    base = written + written_now
                written += written_now
                self.rebase.apply(state, int(state["istate"][step_of]))
                if ierr:
                    failed_step = int(state["istate"][step_of]) + 1
                    error = self._error(ierr, bad, failed_step, "running")
                    recorded = (
                        samples[: len(probes), :written]
                        if sink is None
                        else _joined(tail, max(block, 4096), len(probes))
                    )
                    raise self._physical_growth(error, ierr, recorded, decimation, probes)
                chunk = int(max(100, min(10 * chunk, steps * chunk_seconds / max(elapsed, 1e-6))))
                chunk = min(chunk, max_chunk)
                if progress is not None:
                    try:
                        progress(int(state["istate"][step_of]), n_steps)
                    except KeyboardInterrupt:
                        interrupted.set()
                now = time.perf_counter()
                if checkpoint is not None and now - last_checkpoint >= checkpoint_every:
                    self._checkpoint(checkpoint, key, state, samples, written, sink)
                    last_checkpoint, saved_step = now, int(state["istate"][step_of])
                if interrupted.is_set():
                    break
            done = int(state["istate"][step_of])
            if checkpoint is not None and saved_step != done:  # mid-run, or the finished run
                self._checkpoint(checkpoint, key, state, samples, written, sink)
            # a signal in the last chunk stops a checkpointed run too: the finished state is
            # saved, and the result is written on resuming; without a checkpoint it goes on
            if interrupted.is_set() and (done < n_steps or checkpoint is not None):
                where = f"; state saved to {checkpoint}" if checkpoint is not None else ""
                number = interrupted.signal_number
                raise TransientInterrupted(
                    f"interrupted at t = {done * self.time_step:.6g} s (step {done} of "
                    f"{n_steps}) by {signal.Signals(number).name}{where}; no result file "
                    "written",
                    number,
                )
        istate = dict(zip(ISTATE_LAYOUT, (int(x) for x in state["istate"])))
        count = istate["window"]
        mean = np.full(self.n, np.nan)
        if count:
            mean[self.order] = state["velocity_sum"] / count
        t_s = float(state["rstate"][0])
        unpermute = np.empty(self.n, dtype=int)
        unpermute[self.order] = np.arange(self.n)
        if sink is not None:
            sink.flush()
            kept = written - base  # nothing: the sink holds every sample
        return RunResult(
            time=np.arange(written) * decimation * self.time_step
            if sink is None
            else np.zeros(kept),
            samples=samples[: len(probes), :written] if sink is None else samples[:0, :kept],
            q=(state["q"] + self.rebase.displacement(state))[unpermute]
            if self.rebase.active
            else state["q"][unpermute],
            v=state["v"][unpermute],
            a=state["a"][unpermute],
            mean_velocity=mean,
            t_s=t_s if t_s >= 0 else math.nan,
            steps=istate["step"],
            counters={
                k: istate[k]
                for k in (
                    "iterations",
                    "refactors",
                    "max_iterations",
                    "separated",
                    "contact_evaluations",
                    "restarts",
                    "coast",
                )
            },
            solver_wall_s=solver_wall,
        )

    @staticmethod
    def _checkpoint(path, key, state, samples, written, sink) -> None:
        """Save the state; the samples too, or, with a sink, the sink's state once it
        has flushed every sample so far (a checkpoint never runs ahead of the file)."""
        if sink is None:
            save_checkpoint(path, key, state, samples[:, :written], written)
            return
        sink.flush()
        save_checkpoint(path, key, state, samples[:, :0], written, extra=sink.state())

    def _advance(
        self, state, recording, probe_args, steps, samples, written
    ) -> tuple[int, int, int]:
        view = samples[:, written:]
        n_written, bad, ierr = _kernel.transient_advance(
            handle=self._problem(),
            khat_factor=state["factor"],
            n_steps=steps,
            phase=state["phase"],
            tooth_offset=state["tooth_offset"],
            q=state["q"],
            v=state["v"],
            a=state["a"],
            k_used=state["k_used"],
            mesh_var=state["mesh_var"],
            k_factored=state["k_factored"],
            velocity_sum=state["velocity_sum"],
            rstate=state["rstate"],
            istate=state["istate"],
            samples=view,
            **recording,
            **probe_args,
        )
        return int(n_written), int(bad), int(ierr)

    def _physical_growth(
        self,
        error: TransientError,
        ierr: int,
        samples: np.ndarray,
        decimation: int,
        probes: Sequence[KernelProbe],
    ) -> TransientError:
        """``error`` as a :class:`PhysicalInstabilityError` when a run that ran away (state not
        finite, deflection beyond the limit) had grown as a resolved oscillation."""
        if ierr not in (4, 5) or not probes:
            return error
        diagnostic = growth_diagnostic(samples, decimation * self.time_step, self.time_step)
        if diagnostic is None or not diagnostic.physical:
            return error
        stopped = str(error).split("; likely cause", 1)[0]
        per_period = math.exp(diagnostic.rate / diagnostic.frequency)
        return PhysicalInstabilityError(
            f"{stopped}; the response grew physically, not numerically: probe "
            f"{probes[diagnostic.channel].name} oscillates at {diagnostic.frequency:.6g} Hz "
            f"({diagnostic.steps_per_period:.0f} steps per period) and grows at "
            f"{diagnostic.rate:.6g} 1/s (x{per_period:.4g} per period); likely cause: an "
            f"instability of the model (a mesh frequency near twice a natural frequency, a "
            f"parametric resonance, or too little damping), which a smaller time_step does "
            f"not remove",
            diagnostic,
        )

    def _error(self, ierr: int, bad: int, step: int, phase: str) -> TransientError:
        """The kernel's error code as a message naming time, DOF or mesh and cause."""
        return kernel_error(
            ierr,
            bad,
            step,
            phase,
            time_step=self.time_step,
            labels=self.labels,
            order=self.order,
            mesh_names=self.meshes.names if self.meshes is not None else [],
            mode=self.equivalent_load,
            max_iterations=int(self.iparam[1]),
            deflection_limit=float(self.rparam[7]),
        )
