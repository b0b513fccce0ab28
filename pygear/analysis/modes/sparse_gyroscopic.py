"""Speed-dependent modes of a drivetrain or rotor model: the quadratic eigenproblem
M q'' + (C + Omega G) q' + K q = 0, sparse for large models, dense for small ones.

Sparse solver
    With q = u e^(lambda t) and v = lambda u, the first-order form
    ``[[0, I], [-K, -D]] z = lambda [[I, 0], [0, M]] z`` (D = C + Omega G) is solved by
    shift-invert Arnoldi (ARPACK through :func:`scipy.sparse.linalg.eigs`) about a real
    shift sigma < 0.  The operator ``(A - sigma B)^-1 B`` is applied with one sparse LU
    of the n x n matrix ``P(sigma) = sigma^2 M + sigma D + K`` (:func:`scipy.sparse
    .linalg.splu`): for ``(x, y)``, ``u = -P^-1 (M y + (D + sigma M) x)`` and
    ``v = x + sigma u``.  The eigenvalues nearest sigma come first: the lowest modes.
    sigma sits below zero by a fraction of the lowest scale of the model, so that a
    free rigid-body motion (lambda = 0) does not make P singular.
Dense solver
    :func:`pygear.analysis.modes.gyroscopic.quadratic_modes`: the whole state space.
    ``auto`` takes it up to :data:`DENSE_LIMIT` DOFs.  A free rigid-body motion is a
    double zero eigenvalue, which round-off splits by about sqrt(eps) omega_max: a
    model whose highest mode is 1e6 times its lowest (near-massless nodes on stiff
    bearings) loses its lowest modes in that floor; solve it with ``sparse``.

Each mode is one eigenvalue of a conjugate pair (Im lambda > 0).  Free rigid-body
motions (lambda = 0) and real eigenvalues (overdamped motions: a rigid rotation with
mass-proportional damping decays as e^(-alpha t)) have no frequency and are left out
of both solvers' results; a real eigenvalue > 0 (divergence) is therefore not
reported here.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ...errors import CaseError
from .gyroscopic import SpeedModes, quadratic_modes, whirl_names

__all__ = ["DENSE_LIMIT", "SOLVERS", "dense_quadratic_modes", "sparse_quadratic_modes", "solve"]

DENSE_LIMIT = 400
"""``auto`` solves models of at most this many DOFs densely (the state space of 800
rows costs less than ARPACK's setup there)."""

SOLVERS = ("auto", "sparse", "dense")
"""Solvers of the speed-dependent modes."""

RIGID_FRACTION = 1e-6
"""|lambda| below this fraction of the lowest elastic scale is a rigid-body motion."""


NULL_SPACE = 1e-12
"""A singular value of K below this fraction of its largest is a rigid-body motion."""

OVERDAMPED = 1e-6
"""|Im lambda| at most this fraction of |lambda|: a real eigenvalue, an overdamped
motion (a damped rigid-body rotation), not a mode with a frequency; left out.  A
repeated real eigenvalue (the rigid motions of a shaft with mass-proportional damping)
comes out of the dense solver split by about sqrt(eps) |lambda| into a complex pair."""


def solve(
    mass: sp.spmatrix,
    stiffness: sp.spmatrix,
    first_order: sp.spmatrix,
    modes: int,
    solver: str = "auto",
) -> SpeedModes:
    """The ``modes`` lowest elastic modes of M q'' + D q' + K q = 0.

    Parameters
    ----------
    mass, stiffness, first_order : sparse matrix
        M (symmetric positive definite), K and D = C + Omega G.
    modes : int
        How many modes (one eigenvalue of each conjugate pair), >= 1.
    solver : {"auto", "sparse", "dense"}
        ``auto``: dense up to :data:`DENSE_LIMIT` DOFs, sparse above.
    """
    if solver not in SOLVERS:
        raise CaseError(f"solver must be one of {', '.join(SOLVERS)} (got {solver!r})")
    if isinstance(modes, bool) or not isinstance(modes, (int, np.integer)) or modes < 1:
        raise CaseError(f"modes must be a whole number >= 1 (got {modes!r})")
    n = mass.shape[0]
    if solver == "dense" or (solver == "auto" and n <= DENSE_LIMIT):
        return dense_quadratic_modes(mass, stiffness, first_order, modes)
    return sparse_quadratic_modes(mass, stiffness, first_order, modes)


def dense_quadratic_modes(
    mass: sp.spmatrix, stiffness: sp.spmatrix, first_order: sp.spmatrix, modes: int
) -> SpeedModes:
    """The lowest ``modes`` elastic modes from the dense state space."""
    stiffness_dense = _dense(stiffness)
    # the free rigid-body motions are K's null space (singular values below NULL_SPACE
    # of the largest), counted from K alone: a model with stiff bearings and light nodes
    # has elastic modes below the state space's round-off floor for zero
    singular = np.linalg.svd(stiffness_dense, compute_uv=False)
    rigid_count = int(np.sum(singular < NULL_SPACE * singular.max(initial=0.0)))
    found = quadratic_modes(
        _dense(mass), stiffness_dense, _dense(first_order), rigid_count=rigid_count
    )
    oscillating = np.abs(found.eigenvalues.imag) > OVERDAMPED * np.abs(found.eigenvalues)
    keep = np.flatnonzero(~found.rigid & oscillating)[:modes]
    return SpeedModes(
        found.eigenvalues[keep], found.shapes[:, keep], found.rigid[keep], found.scale
    )


def sparse_quadratic_modes(
    mass: sp.spmatrix, stiffness: sp.spmatrix, first_order: sp.spmatrix, modes: int
) -> SpeedModes:
    """The lowest ``modes`` elastic modes by shift-invert Arnoldi on a sparse LU."""
    mass, stiffness, first_order = (sp.csc_matrix(a) for a in (mass, stiffness, first_order))
    n = mass.shape[0]
    # a scale of the lowest modes: the smallest positive diagonal ratio K_ii / M_ii
    # bounds nothing, but a shift well below the lowest frequency only needs a size
    diagonal = stiffness.diagonal() / np.where(mass.diagonal() > 0, mass.diagonal(), 1.0)
    positive = diagonal[diagonal > 0]
    scale = math.sqrt(positive.min()) if positive.size else 1.0
    sigma = -0.01 * scale
    pencil = sp.csc_matrix(sigma * sigma * mass + sigma * first_order + stiffness)
    lu = spla.splu(pencil)
    shifted = sp.csc_matrix(first_order + sigma * mass)

    def apply(z: np.ndarray) -> np.ndarray:
        x, y = z[:n], z[n:]
        u = -lu.solve(np.asarray(mass @ y + shifted @ x))
        return np.concatenate([u, x + sigma * u])

    operator = spla.LinearOperator((2 * n, 2 * n), matvec=apply, dtype=float)
    wanted = min(2 * modes + 8, 2 * n - 2)
    values, vectors = spla.eigs(
        operator, k=wanted, which="LM", tol=0.0, ncv=min(2 * n, max(2 * wanted + 1, 40))
    )
    eigenvalues = sigma + 1.0 / values
    shapes = vectors[:n]
    rigid = np.abs(eigenvalues) < RIGID_FRACTION * scale
    picked = np.flatnonzero((eigenvalues.imag > OVERDAMPED * np.abs(eigenvalues)) & ~rigid)
    order = np.lexsort((eigenvalues[picked].real, np.abs(eigenvalues[picked].imag)))
    picked = picked[order][:modes]
    if picked.size < modes:
        raise CaseError(
            f"modes: the sparse solver found {picked.size} elastic modes of {modes} asked "
            "(ask for fewer, or use the dense solver)"
        )
    values_out = eigenvalues[picked]
    shapes_out = shapes[:, picked]
    modal_mass = np.einsum("im,im->m", shapes_out.conj(), mass @ shapes_out).real
    shapes_out = shapes_out / np.sqrt(modal_mass)
    top = float(np.abs(values_out).max())
    return SpeedModes(values_out, shapes_out, np.zeros(picked.size, bool), max(top, 1.0))


def _dense(matrix: sp.spmatrix | np.ndarray) -> np.ndarray:
    return matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix, dtype=float)


# --------------------------------------------------------------------------- rotor modes

KINDS = ("lateral", "axial", "torsional")
"""A mode's kind: where most of its kinetic energy is (x, y and tilts; z; theta_z)."""


def _structure_groups(model) -> dict[str, np.ndarray]:
    """Indices of the structure's x, y, z, tilt and theta_z DOFs (before the gearbox
    block), and each x DOF's partner y."""
    own = model.labels[: model.gearbox_offset]
    index = {label: i for i, label in enumerate(own)}
    groups: dict[str, list[int]] = {"x": [], "y": [], "z": [], "tilt": [], "theta_z": []}
    ratio_of: list[float] = []
    for label, i in index.items():
        node, dof = label.rsplit(".", 1)
        if dof == "x" and f"{node}.y" in index:
            groups["x"].append(i)
            groups["y"].append(index[f"{node}.y"])
            shaft = node.rsplit("_", 1)[0]
            ratio_of.append(model.speed_ratios.get(shaft, 1.0))
        elif dof == "z":
            groups["z"].append(i)
        elif dof in ("theta_x", "theta_y"):
            groups["tilt"].append(i)
        elif dof == "theta_z":
            groups["theta_z"].append(i)
    out = {name: np.array(v, dtype=int) for name, v in groups.items()}
    out["ratio"] = np.array(ratio_of, dtype=float)
    return out


def whirl_and_kind(
    model, modes: SpeedModes, speed_rpm: float
) -> tuple[np.ndarray, list[str], list[str]]:
    """Per mode: the whirl ratio (forward - backward)/(forward + backward) of the shaft
    nodes' orbits, mass-weighted by the nodes' translational mass; its name
    (``forward``, ``backward``, ``planar``, or ``none`` for a mode without lateral
    motion); and its kind (:data:`KINDS`).

    A node's orbit x + i y = (a_x + i a_y)/2 e^(i w t) + (conj(a_x) + i conj(a_y))/2
    e^(-i w t) turns in the positive sense (about +z) with the first circle: it whirls
    forward when that is its shaft's sense of rotation (a shaft at rest: the rotor's).
    At zero speed every lateral mode is ``planar``: the x and y modes of a repeated
    pair may be combined into either circle.
    """
    groups = _structure_groups(model)
    shapes = np.where(modes.eigenvalues.imag < 0, modes.shapes.conj(), modes.shapes)
    diagonal = np.asarray(model.mass.diagonal())
    energy = np.abs(shapes) ** 2 * diagonal[:, None]
    sense = np.sign(groups["ratio"] * (speed_rpm if speed_rpm != 0 else 1.0))
    sense[sense == 0] = 1.0
    x, y = shapes[groups["x"]], shapes[groups["y"]]
    weight = diagonal[groups["x"]][:, None]
    positive = weight * np.abs(x + 1j * y) ** 2
    negative = weight * np.abs(x - 1j * y) ** 2
    forward = np.where(sense[:, None] > 0, positive, negative).sum(axis=0)
    backward = np.where(sense[:, None] > 0, negative, positive).sum(axis=0)
    lateral = energy[np.concatenate([groups["x"], groups["y"], groups["tilt"]])].sum(axis=0)
    shares = np.array(
        [lateral, energy[groups["z"]].sum(axis=0), energy[groups["theta_z"]].sum(axis=0)]
    )
    kinds = [KINDS[k] for k in np.argmax(shares, axis=0)]
    total = forward + backward
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(total > 0, (forward - backward) / total, 0.0)
    if speed_rpm == 0:
        ratio = np.zeros_like(ratio)  # no spin: a repeated pair has no whirl of its own
    names = whirl_names(ratio, np.array(kinds) != "lateral")  # the gearbox's rule
    return np.where(np.array(kinds) == "lateral", ratio, 0.0), names, kinds


def modes_at_speed(
    model, speed_rpm: float, modes: int = 12, *, solver: str = "auto", frame_terms=None
) -> SpeedModes:
    """The ``modes`` lowest modes of a drivetrain model at a rotor speed [rpm]: its
    damping, its table bearings at their speeds, Omega G (every shaft and disc at its
    own speed ratio) and, with ``frame_terms``
    (:func:`pygear.assembly.speed_terms.drivetrain_frame_terms`), the planets'
    Coriolis and centripetal terms at their carriers' speeds."""
    if not math.isfinite(speed_rpm):
        raise CaseError(f"--speed must be a finite number of rpm (got {speed_rpm!r})")
    omega = speed_rpm * math.pi / 30.0
    stiffness, damping = model.at_speed(speed_rpm)
    first_order = damping + omega * model.gyroscopic
    if frame_terms is not None:
        coriolis, centripetal = frame_terms.at(omega)
        first_order = first_order + coriolis
        stiffness = stiffness - centripetal
    return solve(model.mass, stiffness, first_order, modes, solver)


def rotor_modes(
    model, speed_rpm: float, modes: int = 12, *, solver: str = "auto", frame_terms=None
):
    """:func:`modes_at_speed` as an xarray Dataset over ``mode``: ``frequency`` [Hz],
    ``damping_ratio``, ``growth_rate`` [1/s], ``whirl``, ``whirl_ratio``, ``kind``."""
    import xarray as xr

    found = modes_at_speed(model, speed_rpm, modes, solver=solver, frame_terms=frame_terms)
    ratio, names, kinds = whirl_and_kind(model, found, speed_rpm)

    def var(values, units, long_name):
        return ("mode",), values, {"units": units, "long_name": long_name}

    return xr.Dataset(
        {
            "frequency": var(found.frequencies, "Hz", "damped natural frequency"),
            "damping_ratio": var(found.damping_ratios, "1", "-Re(lambda)/|lambda|"),
            "growth_rate": var(found.eigenvalues.real, "1/s", "real part of the eigenvalue"),
            "whirl": var(np.array(names, object), "1", "whirl direction seen from the ground"),
            "whirl_ratio": var(ratio, "1", "(forward - backward)/(forward + backward) whirl"),
            "kind": var(np.array(kinds, object), "1", "lateral, axial or torsional"),
        },
        coords={"mode": var(np.arange(1, found.eigenvalues.size + 1), "1", "mode number")},
        attrs={
            "case": model.case_name,
            "speed_rpm": float(speed_rpm),
            "dofs": model.size,
            "solver": _solver_name(model.size, solver),
            "speed_ratios": ", ".join(f"{k}: {v:.6g}" for k, v in model.speed_ratios.items()),
            "gyroscopic": _gyroscopic_note(frame_terms),
        },
    )


def _gyroscopic_note(frame_terms) -> str:
    note = "every shaft element and disc at its shaft's speed ratio (Friswell et al. 2010, ch. 5)"
    if frame_terms is None:
        return note
    carriers = ", ".join(f"{k}: {v:.6g}" for k, v in frame_terms.carrier_ratios.items())
    return (
        f"{note}; the planets' Coriolis and centripetal terms at their carriers' speed "
        f"ratios ({carriers}; Cooley & Parker 2012), carrier, ring and sun inertial"
    )


def _solver_name(size: int, solver: str) -> str:
    if solver == "auto":
        return "dense" if size <= DENSE_LIMIT else "sparse"
    return solver


# --------------------------------------------------------------------------- Campbell


def rotor_campbell(model, speeds_rpm, modes: int = 8, *, solver: str = "auto", frame_terms=None):
    """Campbell diagram of a drivetrain or rotor model: the ``modes`` lowest modes at
    every rotor speed, tracked by their shapes, and the critical speeds where a lateral
    mode crosses a shaft's 1x line (f = ratio |n| / 60).

    Each shaft's and disc's gyroscopic matrix enters at its own speed ratio
    (``model.gyroscopic``), table bearings at their shafts' speeds, and with
    ``frame_terms`` the gearbox block's planets' Coriolis and centripetal terms at their
    carriers' speeds (:func:`pygear.assembly.speed_terms.drivetrain_frame_terms`).

    Returns
    -------
    xarray.Dataset
        Over (``speed``, ``mode``): ``frequency`` [Hz], ``damping_ratio``, ``whirl``,
        ``kind``, ``tracking_mac``; over ``critical``: ``critical_speed`` [rpm],
        ``critical_frequency`` [Hz], ``critical_mode``, ``critical_whirl``,
        ``critical_shaft`` (the 1x line's shafts).
    """
    import xarray as xr

    from .campbell import check_speeds
    from .mode_tracking import ModeTracker

    speeds = check_speeds(speeds_rpm)
    dense_mass = model.mass.toarray()
    tracker = ModeTracker(
        lambda s: modes_at_speed(model, s, modes, solver=solver, frame_terms=frame_terms),
        dense_mass,
    )
    tracking = tracker.track(speeds)
    n = tracking.modes[0].eigenvalues.size
    frequency = np.array([m.frequencies for m in tracking.modes])
    damping = np.array([m.damping_ratios for m in tracking.modes])
    whirl = np.empty((speeds.size, n), dtype=object)
    kind = np.empty((speeds.size, n), dtype=object)
    for k, (speed, found) in enumerate(zip(speeds, tracking.modes)):
        _, whirl[k], kind[k] = whirl_and_kind(model, found, float(speed))
    lines: dict[float, list[str]] = {}
    for shaft, ratio in model.speed_ratios.items():
        lines.setdefault(round(abs(ratio), 12), []).append(shaft)
    rows = []
    for ratio, shafts in sorted(lines.items()):
        line = ratio * np.abs(speeds) / 60.0
        for m in range(n):
            difference = frequency[:, m] - line
            for k in range(speeds.size - 1):
                a, b = difference[k], difference[k + 1]
                if kind[k, m] != "lateral" or not (a == 0 or a * b < 0):
                    continue
                weight = 0.0 if a == 0 else a / (a - b)
                speed = speeds[k] + weight * (speeds[k + 1] - speeds[k])
                near = k if weight < 0.5 else k + 1
                rows.append(
                    (speed, ratio * abs(speed) / 60.0, m + 1, whirl[near, m], " ".join(shafts))
                )
    rows.sort(key=lambda r: (r[0], r[2]))
    columns = list(zip(*rows)) if rows else [[] for _ in range(5)]
    dims = ("speed", "mode")

    def var(dims, values, units, long_name):
        return dims, values, {"units": units, "long_name": long_name}

    return xr.Dataset(
        {
            "frequency": var(dims, frequency, "Hz", "damped natural frequency of the tracked mode"),
            "damping_ratio": var(dims, damping, "1", "-Re(lambda)/|lambda|"),
            "whirl": var(dims, whirl, "1", "whirl direction seen from the ground"),
            "kind": var(dims, kind, "1", "lateral, axial or torsional"),
            "tracking_mac": var(dims, tracking.mac, "1", "MAC with the previous speed's mode"),
            "critical_speed": var(
                ("critical",), np.array(columns[0], float), "rpm", "crossing with a 1x line"
            ),
            "critical_frequency": var(
                ("critical",), np.array(columns[1], float), "Hz", "frequency at the crossing"
            ),
            "critical_mode": var(
                ("critical",), np.array(columns[2], np.int64), "1", "tracked mode"
            ),
            "critical_whirl": var(
                ("critical",), np.array(columns[3], object), "1", "whirl of the mode there"
            ),
            "critical_shaft": var(
                ("critical",), np.array(columns[4], object), "1", "shafts of the 1x line"
            ),
        },
        coords={
            "speed": var(("speed",), speeds, "rpm", "rotor speed"),
            "mode": var(("mode",), np.arange(1, n + 1), "1", "tracked mode number"),
        },
        attrs={
            "case": model.case_name,
            "dofs": model.size,
            "solver": _solver_name(model.size, solver),
            "speed_ratios": ", ".join(f"{k}: {v:.6g}" for k, v in model.speed_ratios.items()),
            "gyroscopic": _gyroscopic_note(frame_terms),
            "tracking_refinements": tracking.refinements,
        },
    )
