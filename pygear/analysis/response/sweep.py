r"""The periodic steady state over a range of constant speeds, as one Dataset.

For each input speed :func:`forced_response` balances the harmonics of the mesh
frequency (:mod:`.hill`), rebuilds every mesh's deflection and force over a period,
and reads from them:

- the dynamic factor K_v,m = max_t F_m(t) / mean_t F_m(t), the peak over the mean load
  of the mesh at that speed (ISO 6336-1: dynamic over static tooth load; the mean
  over a period is the static load the mesh carries, so K_v is kept apart from the
  load sharing);
- the dynamic transmission error of each mesh: RMS about its mean and peak to peak of
  delta_m(t) along the line of action [m];
- the tooth-separation flag: F_m(t) < 0 somewhere in the period (the linear model then
  pulls the teeth together: the answer past that speed needs contact loss);
- the planet load-sharing factor of each planetary stage, K_gamma = max over planets of
  the mean sun-planet mesh force / mean over planets (IEC 61400-4:2012, which
  applies ISO 6336's mesh load factor to the mean planet branch loads), and the same
  ratio of the peak forces;
- the largest force of every bearing over the period [N];
- the largest Floquet multiplier modulus (:mod:`.floquet`) and the stability flag;
- the harmonics used and the residual.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import math
import time
from collections.abc import Callable

import numpy as np
import xarray as xr

from ...errors import CaseError
from ...model.case import Case, Scene
from .floquet import DEFAULT_SEGMENTS, system_multipliers
from .hill import AUTO_HARMONICS, HillSolution, fourier_coefficients, harmonic_balance, mesh_signals
from .mesh_excitation import refuse_excitation
from .quasi_sweep import quasi_balance, quasi_multipliers, quasi_record
from .system import ResponseSystem, response_system

__all__ = [
    "BRANCH_HARMONICS",
    "COVER_SHARE",
    "DEFAULT_TOLERANCE",
    "branch_jumps",
    "contact_loss_response",
    "forced_response",
    "response_summary",
    "scene_response",
    "sweep_system",
]

BRANCH_HARMONICS = 16
"""Harmonics of the contact-loss branch when the linear sweep chose its own count: the
branch's Jacobian is dense in n_mesh (2H + 1) unknowns, and 16 place the folds of the
spur pair and the study case (docs: response_nonlinear)."""

DEFAULT_TOLERANCE = 5e-3
"""Residual the automatic harmonic count reaches.  On the study case the mesh forces then
lie within about 0.5 % of the largest (the error runs at 0.4-0.95 times the residual
against a time integration), at 32-128 harmonics; 1e-3 costs 128 at most speeds."""

COVER_SHARE = 0.01
"""Modes storing at least this share of their strain energy in the meshes are the ones a
stiffness jump rings; the automatic count reaches their frequency before the residual
is trusted (below it the residual can be small by accident)."""

_log = logging.getLogger("pygear")


def _thread_limit() -> contextlib.AbstractContextManager:
    """One BLAS thread: the balance factorises matrices of a few hundred rows, which
    two threads on a shared machine slow down tenfold."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - a dependency
        return contextlib.nullcontext()
    return threadpool_limits(1, user_api="blas")


def forced_response(
    case: Case,
    speeds_rpm: np.ndarray,
    *,
    scene: Scene | None = None,
    harmonics: int | str = "auto",
    tolerance: float = DEFAULT_TOLERANCE,
    max_harmonics: int = AUTO_HARMONICS[-1],
    stability: bool = True,
    time_varying: bool = True,
    pin_errors: dict[str, float] | None = None,
    torque: float | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> xr.Dataset:
    """Periodic steady state of a case at each constant input speed.

    Parameters
    ----------
    case : Case
        The case.
    speeds_rpm : array_like
        Input member speeds [rpm], > 0.
    scene : Scene, optional
        Scene whose parameters, model choices and transient members apply.
    harmonics : int or "auto"
        Harmonic count H, or chosen per speed by ``tolerance``.
    tolerance : float
        Residual of the automatic count [-].
    max_harmonics : int
        Largest automatic count.
    stability : bool
        Compute the Floquet multipliers.
    time_varying : bool
        False holds every mesh at its mean stiffness (a linear frequency response).
    pin_errors : dict, optional
        Tangential planet pin errors [m] by planet (:func:`.response_system`).
    torque : float, optional
        Drive torque on the input member [N m]; default the scene's drive torque.
    progress : callable, optional
        Called with (done, total) after each speed.

    Returns
    -------
    xarray.Dataset
        Over ``speed``, ``mesh``, ``harmonic``, ``stage``, ``bearing`` and ``mode``.
    """
    speeds = _checked_speeds(speeds_rpm)
    system = response_system(
        case, scene, time_varying=time_varying, pin_errors=pin_errors, torque=torque
    )
    return sweep_system(
        system,
        speeds,
        harmonics=harmonics,
        tolerance=tolerance,
        max_harmonics=max_harmonics,
        stability=stability,
        progress=progress,
    )


def _checked_speeds(speeds_rpm: np.ndarray) -> np.ndarray:
    speeds = np.asarray(speeds_rpm, dtype=np.float64).reshape(-1)
    if speeds.size == 0 or not np.all(np.isfinite(speeds) & (speeds > 0)):
        raise CaseError("--speeds: speeds must be finite and > 0 rpm")
    return speeds


def contact_loss_response(
    case: Case,
    speeds_rpm: np.ndarray,
    *,
    scene: Scene | None = None,
    harmonics: int | str = "auto",
    tolerance: float = DEFAULT_TOLERANCE,
    stability: bool = True,
    pin_errors: dict[str, float] | None = None,
    torque: float | None = None,
    branch_harmonics: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[xr.Dataset, xr.Dataset | None]:
    """The linear sweep, then the contact-loss branch over its range where it separates.

    The linear sweep is :func:`forced_response`'s; where it flags tooth separation the
    branch with the kernel's flank law (:func:`.nonlinear.case_law`, the normal backlash
    of every mesh) is continued in speed over the sweep's range
    (:func:`.continuation.separated_response`), through every fold.

    Parameters
    ----------
    case, speeds_rpm, scene, harmonics, tolerance, stability, pin_errors, torque, progress
        As :func:`forced_response`; the torque matters now (the response is no longer
        linear in it).
    branch_harmonics : int, optional
        Harmonics of the branch; default ``harmonics`` when it is a number, else
        :data:`BRANCH_HARMONICS`.

    Returns
    -------
    (xarray.Dataset, xarray.Dataset or None)
        The linear sweep and the branch (:func:`.continuation.continue_response`), None
        when no mesh separates.

    Raises
    ------
    CaseError
        A mesh without backlash, or no static mesh load.
    """
    from .continuation import separated_response
    from .nonlinear import case_law

    speeds = _checked_speeds(speeds_rpm)
    if branch_harmonics is None:
        branch_harmonics = harmonics if isinstance(harmonics, int) else BRANCH_HARMONICS
    if not (isinstance(branch_harmonics, int) and branch_harmonics >= 1):
        raise CaseError(f"--harmonics must be >= 1 for contact loss (got {branch_harmonics!r})")
    system = response_system(case, scene, pin_errors=pin_errors, torque=torque)
    if system.groups > 1:
        raise CaseError(
            f"--contact-loss: case {case.name!r} has meshes at {system.groups} incommensurate "
            "mesh frequencies; contact loss is balanced for one frequency group only "
            "(a planetary stage or gear pair)"
        )
    refuse_excitation(system, "the contact-loss balance")
    law = case_law(case, system, scene)  # refuses a mesh without backlash before any work
    linear = sweep_system(system, speeds, harmonics=harmonics, tolerance=tolerance,
                          stability=stability, progress=progress)  # fmt: skip
    branch = separated_response(
        system, linear, law, harmonics=branch_harmonics, stability=stability
    )
    return linear, branch


def scene_response(
    case: Case, scene: Scene, progress: Callable[[int, int], None] | None = None
) -> tuple[xr.Dataset, xr.Dataset | None]:
    """The ``response`` analysis of a scene, as its :class:`~pygear.model.response_settings.
    Response` settings ask: the linear sweep, and the contact-loss branch when asked.

    Parameters
    ----------
    case : Case
        The case as the scene sees it (:meth:`Case.for_scene` applied, as the scene runner
        and a sweep point hold it): the scene's parameter changes are not applied again,
        so a swept value of the same parameter stays.
    scene : Scene
        A scene with ``response`` settings.
    progress : callable, optional
        Called with (done, total) after each speed.

    Returns
    -------
    (xarray.Dataset, xarray.Dataset or None)
        The linear sweep and the branch (None without contact loss or separation).
    """
    settings = scene.response
    if settings is None:
        raise CaseError(f"scenes.{scene.name}.response: the response analysis needs its settings")
    plain = dataclasses.replace(scene, parameters=())  # already applied to ``case``
    options = dict(
        scene=plain,
        harmonics=settings.harmonics,
        tolerance=settings.tolerance,
        stability=settings.stability,
        pin_errors=dict(settings.pin_errors) or None,
        torque=settings.torque,
        progress=progress,
    )
    speeds = np.array(settings.speeds)
    if settings.contact_loss:
        return contact_loss_response(case, speeds, **options)
    return forced_response(case, speeds, **options), None


def branch_jumps(branch: xr.Dataset | None, meshes: list[str]) -> dict[str, dict[str, list]]:
    """Jump speeds [rpm] of every mesh: ``{"up": [...], "down": [...]}`` by mesh.

    A fold belongs to the meshes whose drive flanks part at it (at the point before the
    fold or after it); with no branch every list is empty.
    """
    jumps: dict[str, dict[str, list]] = {m: {"up": [], "down": []} for m in meshes}
    if branch is None:
        return jumps
    turning = branch["turning"].values
    separation = branch["separation"].values
    names = [str(m) for m in branch.mesh.values]
    for kind, key in ((1, "up"), (-1, "down")):
        speeds = np.atleast_1d(branch.attrs[f"{key}_sweep_jumps"])
        for index, speed in zip(np.flatnonzero(turning == kind), speeds):
            near = separation[index : index + 2].any(axis=0)
            for m, name in enumerate(names):
                if near[m] and name in jumps:
                    jumps[name][key].append(float(speed))
    return jumps


def _cover_frequency(system: ResponseSystem) -> float:
    """Highest elastic natural angular frequency with a mesh energy share of
    :data:`COVER_SHARE` or more [rad/s] (0 at constant stiffness)."""
    if not np.any(system.stiffness_variation):
        return 0.0
    chosen = system.mesh_energy_share() >= COVER_SHARE
    return float(np.sqrt(system.eigenvalues[chosen]).max()) if chosen.any() else 0.0


def sweep_system(
    system: ResponseSystem,
    speeds: np.ndarray,
    *,
    harmonics: int | str = "auto",
    tolerance: float = DEFAULT_TOLERANCE,
    max_harmonics: int = AUTO_HARMONICS[-1],
    stability: bool = True,
    segments: int = DEFAULT_SEGMENTS,
    progress: Callable[[int, int], None] | None = None,
) -> xr.Dataset:
    """:func:`forced_response` of an already built system (parameters alike)."""
    if harmonics != "auto" and not (isinstance(harmonics, int) and 0 <= harmonics <= 1024):
        raise CaseError(f"--harmonics must be auto or a whole number 0-1024 (got {harmonics!r})")
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise CaseError(f"--tolerance must be > 0 (got {tolerance!r})")
    started = time.perf_counter()
    top = max_harmonics if harmonics == "auto" else int(harmonics)
    several = system.groups > 1
    if not several:
        coefficients = fourier_coefficients(system.stiffness_variation, 3 * top)
    cover = _cover_frequency(system)
    records = []
    with _thread_limit():
        for i, speed in enumerate(speeds):
            if several:  # incommensurate mesh frequencies: the multi-frequency balance
                records.append(
                    _quasi_speed(
                        system,
                        float(speed),
                        harmonics,
                        tolerance,
                        max_harmonics,
                        cover,
                        stability,
                        segments,
                    )
                )
                if progress is not None:
                    progress(i + 1, speeds.size)
                continue
            omega = system.omega(float(speed))
            start = max(AUTO_HARMONICS[0], math.ceil(cover / omega))
            solution = harmonic_balance(
                system,
                omega,
                harmonics,
                tolerance=tolerance,
                max_harmonics=max_harmonics,
                start=min(start, max_harmonics),
                coefficients=coefficients,
            )
            record = _speed_record(system, solution)
            if stability:
                multipliers = system_multipliers(system, omega, segments)
                record["multiplier"] = float(np.abs(multipliers[0]))
            records.append(record)
            if progress is not None:
                progress(i + 1, speeds.size)
    dataset = _dataset(system, speeds, records, stability)
    dataset.attrs.update(
        harmonics_requested=str(harmonics),
        tolerance=tolerance,
        floquet_segments=segments if stability else 0,
        wall_s=time.perf_counter() - started,
    )
    worst = float(np.nanmax(dataset.residual.values))
    if harmonics == "auto" and worst > tolerance:
        _log.warning(
            f"response: the residual reaches {worst:.2g} (tolerance {tolerance:g}) at "
            f"{max_harmonics} harmonics: the lowest speeds need more (--harmonics)"
        )
    return dataset


def _quasi_speed(
    system: ResponseSystem,
    speed: float,
    harmonics: int | str,
    tolerance: float,
    max_harmonics: int,
    cover: float,
    stability: bool,
    segments: int,
) -> dict:
    """One speed of a system of several frequency groups (:mod:`.quasi_sweep`)."""
    solution = quasi_balance(system, speed, harmonics, tolerance=tolerance,
                             max_harmonics=max_harmonics, cover=cover)  # fmt: skip
    record = quasi_record(system, solution)
    if stability:
        record["multiplier"] = quasi_multipliers(system, speed, segments)[0]
    return record


def _speed_record(system: ResponseSystem, solution: HillSolution) -> dict:
    """Everything the dataset keeps of one speed."""
    deflection, force = mesh_signals(system, solution)
    mean = force.mean(axis=0)
    peak = force.max(axis=0)
    dte = deflection - deflection.mean(axis=0)
    h = solution.harmonics
    amplitude = np.abs(solution.deflection[h:]).T  # (mesh, 0..H)
    amplitude[:, 1:] *= 2  # one-sided amplitudes
    return {
        "harmonics": h,
        "residual": solution.residual,
        "dynamic_factor": peak / mean,
        "force_mean": mean,
        "force_max": peak,
        "force_min": force.min(axis=0),
        "dte_rms": np.sqrt((dte**2).mean(axis=0)),
        "dte_pp": deflection.max(axis=0) - deflection.min(axis=0),
        "amplitude": amplitude,
        "bearing": _bearing_forces(system, solution),
    }


def _bearings(system: ResponseSystem) -> list:
    if system.model is None:
        return []
    return [s for s in system.model.springs if s.kind in ("central_bearing", "planet_bearing")]


def _bearing_forces(system: ResponseSystem, solution: HillSolution) -> np.ndarray:
    """Largest in-plane force magnitude of every bearing over the period [N]."""
    springs = _bearings(system)
    if not springs:
        return np.zeros(0)
    h = solution.harmonics
    samples = max(64, 8 * (2 * h + 1))
    spectrum = np.zeros((samples, system.size), dtype=complex)
    spectrum[np.arange(-h, h + 1) % samples] = solution.coordinates
    modal = np.real(np.fft.ifft(spectrum, axis=0)) * samples
    full = modal @ (system.model.reduction @ system.modes).T  # (samples, full DOFs)
    out = np.empty(len(springs))
    for i, spring in enumerate(springs):
        radial = full[:, spring.dofs] @ spring.deflection[:, :2] * spring.stiffness[:2]
        out[i] = float(np.sqrt((radial**2).sum(axis=1)).max())
    return out


def _load_sharing(system: ResponseSystem, values: np.ndarray) -> tuple[list[str], np.ndarray]:
    """K_gamma of every planetary stage from per-mesh values (speed, mesh): max over
    the stage's sun-planet meshes over their mean."""
    stages = []
    columns = []
    for stage in dict.fromkeys(system.stages):
        chosen = [
            i
            for i, (s, p, n) in enumerate(zip(system.stages, system.planets, system.names))
            if s == stage and p > 0 and n.split(".")[-1].startswith("sun-")
        ]
        if len(chosen) < 2:
            continue
        part = values[:, chosen]
        stages.append(stage)
        columns.append(part.max(axis=1) / part.mean(axis=1))
    return stages, np.array(columns).T.reshape(values.shape[0], len(stages))


def _dataset(
    system: ResponseSystem, speeds: np.ndarray, records: list[dict], stability: bool
) -> xr.Dataset:
    def stack(key: str) -> np.ndarray:
        return np.array([r[key] for r in records])

    h_max = max(r["harmonics"] for r in records)
    amplitude = np.full((speeds.size, len(system.names), h_max + 1), np.nan)
    for i, r in enumerate(records):
        amplitude[i, :, : r["harmonics"] + 1] = r["amplitude"]
    mean = stack("force_mean")
    stages, sharing = _load_sharing(system, mean)
    _, sharing_peak = _load_sharing(system, stack("force_max"))
    fundamental = np.array([system.omega(s) / (2 * math.pi) for s in speeds])
    mesh_frequency = np.array([system.mesh_frequencies(s) for s in speeds])
    share = system.mesh_energy_share()
    natural = system.natural_frequencies
    main = int(np.argmax(share))
    # ISO 6336-1 N = n / n_E1: mesh frequency over the main mesh mode's frequency
    ratio = mesh_frequency[:, 0] / natural[main]
    per_mesh = ("speed", "mesh")
    data = {
        "dynamic_factor": (per_mesh, stack("dynamic_factor"),
                           {"units": "1", "long_name": "dynamic factor K_v: peak over mean "
                            "mesh force over a period"}),
        "mesh_force_mean": (per_mesh, mean, {"units": "N", "long_name": "mean mesh force"}),
        "mesh_force_max": (per_mesh, stack("force_max"),
                           {"units": "N", "long_name": "largest mesh force over a period"}),
        "mesh_force_min": (per_mesh, stack("force_min"),
                           {"units": "N", "long_name": "smallest mesh force over a period"}),
        "dte_rms": (per_mesh, stack("dte_rms"),
                    {"units": "m", "long_name": "dynamic transmission error, RMS about "
                     "its mean along the line of action"}),
        "dte_peak_to_peak": (per_mesh, stack("dte_pp"),
                             {"units": "m", "long_name": "dynamic transmission error, "
                              "peak to peak"}),
        "separation": (per_mesh, (stack("force_min") < 0).astype(np.int8),
                       {"units": "1", "long_name": "tooth separation: 1 where the mesh "
                        "force falls below 0 in the period (linear model invalid)"}),
        "deflection_amplitude": (("speed", "mesh", "harmonic"), amplitude,
                                 {"units": "m", "long_name": "one-sided amplitude of the "
                                  "mesh deflection harmonic (mean at 0; NaN beyond H)"}),
        "mesh_frequency": (per_mesh, mesh_frequency,
                           {"units": "Hz", "long_name": "mesh frequency"}),
        "fundamental_frequency": ("speed", fundamental,
                                  {"units": "Hz", "long_name": "fundamental of the balance"}),
        "resonance_ratio": ("speed", ratio,
                            {"units": "1", "long_name": "ISO 6336-1 resonance ratio N: mesh "
                             "frequency over the main mesh mode's natural frequency"}),
        "harmonics": ("speed", stack("harmonics").astype(np.int32),
                      {"units": "1", "long_name": "harmonics H balanced"}),
        "residual": ("speed", stack("residual"),
                     {"units": "1", "long_name": "deflection of harmonics H+1..2H over the "
                      "largest static mesh deflection"}),
        "load_sharing": (("speed", "stage"), sharing,
                         {"units": "1", "long_name": "planet load-sharing factor K_gamma: "
                          "largest over mean planet mean sun-mesh force"}),
        "load_sharing_peak": (("speed", "stage"), sharing_peak,
                              {"units": "1", "long_name": "largest over mean planet peak "
                               "sun-mesh force"}),
        "bearing_force_max": (("speed", "bearing"), stack("bearing").reshape(speeds.size, -1),
                              {"units": "N", "long_name": "largest radial bearing force "
                               "over a period"}),
        "natural_frequency": ("mode", natural,
                              {"units": "Hz", "long_name": "elastic natural frequency at "
                               "mean mesh stiffness"}),
        "mesh_energy_share": ("mode", share,
                              {"units": "1", "long_name": "share of modal strain energy "
                               "in the meshes"}),
    }  # fmt: skip
    if stability:
        multiplier = stack("multiplier")
        data["floquet_multiplier"] = ("speed", multiplier, {
            "units": "1", "long_name": "largest Floquet multiplier modulus"})  # fmt: skip
        data["stable"] = ("speed", (multiplier < 1.0).astype(np.int8), {
            "units": "1", "long_name": "1 where every Floquet multiplier lies inside "
            "the unit circle"})  # fmt: skip
    coords = {
        "speed": ("speed", speeds, {"units": "rpm", "long_name": "input member speed"}),
        "mesh": ("mesh", np.array(system.names, dtype=object), {"long_name": "mesh"}),
        "harmonic": ("harmonic", np.arange(h_max + 1, dtype=np.int32),
                     {"units": "1", "long_name": "harmonic of the fundamental"}),
        "stage": ("stage", np.array(stages, dtype=object), {"long_name": "planetary stage"}),
        "bearing": ("bearing", np.array([s.name for s in _bearings(system)], dtype=object),
                    {"long_name": "bearing"}),
        "mode": ("mode", np.arange(1, natural.size + 1, dtype=np.int32),
                 {"units": "1", "long_name": "elastic mode number"}),
        "mesh_order": ("mesh", system.mesh_order.astype(np.int32),
                       {"units": "1", "long_name": "mesh frequency over the fundamental"}),
    }  # fmt: skip
    attrs = {
        **system.attrs,
        "main_mode": main + 1,
        "main_resonance_speed_rpm": float(speeds[0] * natural[main] / mesh_frequency[0, 0]),
        "method": "harmonic balance (Hill's method), condensed onto the mesh deflections",
    }
    if system.groups > 1:
        attrs["method"] = (
            "multi-frequency harmonic balance on a lattice of combination "
            "frequencies, condensed onto the mesh deflections"
        )
        attrs["group_fundamentals_per_rad_s"] = system.group_fundamentals
        attrs["mesh_group"] = system.mesh_group.astype(np.int32)
        attrs["stability"] = (
            "Floquet stability of every frequency group on its own, the "
            "other meshes at mean stiffness (quasi-periodic: no monodromy)"
        )
    return xr.Dataset(data, coords, attrs)


def response_summary(
    dataset: xr.Dataset, branch: xr.Dataset | None = None, *, contact_loss: bool = False
) -> dict:
    """The numbers ``pygear response --json`` prints; with ``contact_loss`` also
    ``jump_up_rpm`` and ``jump_down_rpm`` by mesh (:func:`branch_jumps` of ``branch``)."""
    meshes = [str(m) for m in dataset.mesh.values]
    stages = [str(s) for s in dataset.stage.values]
    summary = {
        "case": dataset.attrs.get("case", ""),
        "speeds_rpm": dataset.speed.values.tolist(),
        "dynamic_factor": {m: dataset.dynamic_factor.values[:, i].tolist()
                           for i, m in enumerate(meshes)},
        "load_sharing": {s: dataset.load_sharing.values[:, i].tolist()
                         for i, s in enumerate(stages)},
        "dte_rms_m": {m: dataset.dte_rms.values[:, i].tolist() for i, m in enumerate(meshes)},
        "separation": {m: [bool(v) for v in dataset.separation.values[:, i]]
                       for i, m in enumerate(meshes)},
        "stable": ([bool(v) for v in dataset.stable.values] if "stable" in dataset
                   else [None] * dataset.sizes["speed"]),
        "harmonics": [int(v) for v in dataset.harmonics.values],
        "residual": dataset.residual.values.tolist(),
    }  # fmt: skip
    if contact_loss:
        jumps = branch_jumps(branch, meshes)
        summary["jump_up_rpm"] = {m: jumps[m]["up"] for m in meshes}
        summary["jump_down_rpm"] = {m: jumps[m]["down"] for m in meshes}
    return summary
