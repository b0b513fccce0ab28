"""What accuracy costs in time: a ladder of fidelities and time steps for one scene.

:func:`pygear.runs.accuracy.accuracy_study` runs a transient scene at every rung of a ladder of
fidelities (DOF set torsional / planar / pygear's pick / spatial, constant or
time-varying mesh stiffness, the equivalent-load modes) and formulations, each at
time steps halving from coarse to fine.  Each setting is timed (median of repeats)
and read in the quantities users read: equilibrium speeds, t_s, RMS and peak of each
dynamic mesh force, frequency and amplitude of the main spectral peaks of each
acceleration channel, and natural frequencies.  Errors are measured against the
finest, fullest run of the same formulation (formulations are different models, not
fidelities of one); Richardson extrapolation over the three finest steps of each
fidelity gives the observed order and an estimate of the reference's own
time-discretisation error.  A metric whose reference is not converged to the
tolerance (its two finest steps disagree by more, or the fixed-point iteration and the
reference's solver disagree at the finest step) is reported but not judged.  The
recommendation is the cheapest setting whose every judged metric meets the
tolerance.  This module holds the ladder, one column of runs (:func:`run_column`)
and the grid of results (:func:`accuracy_grid`); scheduling the columns (in this
process or on a Dask cluster) is the runner's.  Figures live in
:mod:`pygear.plots.accuracy`.
"""

from __future__ import annotations

import dataclasses
import math
import statistics
import time
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ...assembly.matrices import assemble, choose_dof_set
from ...errors import CaseError
from ...kernel.calls import KernelError
from ...model.case import FORMULATIONS, Case, Scene, load_case_module
from ...model.scene_settings import scene_settings
from ..signals.channels import channel_series, run_channels
from .accuracy_report import accuracy_table_text, grid_dataset, recommendation

__all__ = [
    "AccuracyStudy",
    "Fidelity",
    "accuracy_grid",
    "accuracy_table_text",
    "fidelity_ladder",
    "load_accuracy_study",
    "metric_errors",
    "observed_orders",
    "recommendation",
    "run_column",
    "run_setting",
]

STIFFNESS_EFFECT = "time_varying_mesh_stiffness"
NONLINEAR_EFFECTS = (STIFFNESS_EFFECT, "tooth_separation")
EQUIVALENT_LOAD_LADDER = ("predictor", "iterate", "refactor")  # cheapest to fullest
DOF_SET_LADDER = ("torsional", "planar", "auto", "spatial")  # smallest to fullest
SAMPLED_KINDS = ("t_s", "mesh_force_rms", "mesh_force_peak", "peak_frequency", "peak_amplitude")
"""Metrics read from the samples, taken at the same instants in every run, so their
observed order is the integrator's.  Equilibrium speeds are the kernel's mean over the
window's *steps*: that sum is a rectangle rule whose own error is first order in dt
while the speed still drifts; their orders are reported per metric only."""


@dataclass(frozen=True)
class AccuracyStudy:
    """Settings of an accuracy study (a case file may define ``accuracy = dict(...)``).

    Parameters
    ----------
    tolerance : float
        Largest accepted error of a judged metric, relative to its scale [-].
    duration : float, optional
        Simulated time of every run [s]; None keeps the scene's.
    mean_window : float, optional
        Window of the equilibrium speeds and mesh-force statistics [s]; None keeps the scene's.
    coarsest_time_step : float, optional
        First rung of the time-step ladder [s]; default 8 times the scene's step.
    levels : int
        Time steps, halving from the coarsest (>= 3 for an observed order).
    repeats : int
        Timed repeats of each setting (the median is kept).
    sample_rate : float, optional
        Output rate of every run [Hz]; default 1/coarsest_time_step, so that every run
        is sampled at the same instants.
    signal_after : float
        Spectra skip the start-up before this time [s].
    peaks : int
        Largest spectral peaks of each acceleration channel that are metrics.
    natural_frequencies : int
        Lowest distinct non-zero natural frequencies of the reference that are metrics.
    formulations : tuple of str, optional
        Formulations to study; default every formulation the gearbox allows.
    dof_sets : tuple of str
        DOF sets of the ladder; ``auto`` is pygear's own pick (kept when it differs).
    mesh_stiffness : tuple of str
        ``constant`` and/or ``time-varying`` rungs.
    equivalent_loads : tuple of str
        Equivalent-load modes of the rungs that need a mesh term.
    """

    tolerance: float = 0.01
    duration: float | None = None
    mean_window: float | None = None
    coarsest_time_step: float | None = None
    levels: int = 5
    repeats: int = 3
    sample_rate: float | None = None
    signal_after: float = 1.0
    peaks: int = 3
    natural_frequencies: int = 6
    formulations: tuple[str, ...] | None = None
    dof_sets: tuple[str, ...] = DOF_SET_LADDER
    mesh_stiffness: tuple[str, ...] = ("constant", "time-varying")
    equivalent_loads: tuple[str, ...] = EQUIVALENT_LOAD_LADDER

    def validate(self) -> None:
        """Raise :class:`CaseError` naming the first bad setting."""
        if not (isinstance(self.tolerance, (int, float)) and math.isfinite(self.tolerance)):
            raise CaseError(f"--tolerance must be a finite number (got {self.tolerance!r})")
        if self.tolerance <= 0:
            raise CaseError(f"--tolerance must be > 0 (got {self.tolerance!r})")
        for name in ("duration", "mean_window", "coarsest_time_step", "sample_rate"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise CaseError(f"accuracy.{name} must be a positive number (got {value!r})")
        if not (isinstance(self.levels, int) and self.levels >= 3):
            raise CaseError(f"accuracy.levels must be a whole number >= 3 (got {self.levels!r})")
        for name in ("repeats", "peaks", "natural_frequencies"):
            value = getattr(self, name)
            if not (isinstance(value, int) and value >= (1 if name == "repeats" else 0)):
                raise CaseError(f"accuracy.{name} must be a whole number (got {value!r})")
        for f in self.formulations or ():
            if f not in FORMULATIONS:
                raise CaseError(f"accuracy.formulations: {f!r} is not one of {FORMULATIONS}")
        for name, allowed in (
            ("dof_sets", DOF_SET_LADDER),
            ("mesh_stiffness", ("constant", "time-varying")),
            ("equivalent_loads", EQUIVALENT_LOAD_LADDER),
        ):
            chosen = getattr(self, name)
            if not chosen or any(c not in allowed for c in chosen):
                raise CaseError(f"accuracy.{name} must list some of {allowed} (got {chosen!r})")


@dataclass(frozen=True)
class Fidelity:
    """One rung of the fidelity ladder."""

    dof_set: str  # torsional, planar, auto (pygear's pick) or spatial
    time_varying: bool
    equivalent_load: str  # linear (no mesh term) or a mode of EQUIVALENT_LOAD_LADDER

    @property
    def name(self) -> str:
        stiffness = "time-varying" if self.time_varying else "constant"
        return f"{self.dof_set}/{stiffness}/{self.equivalent_load}"

    def scene(self, base: Scene, time_step: float, study: AccuracyStudy, rate: float) -> Scene:
        """The base scene at this fidelity and time step (durations as the study says)."""
        effects = tuple(e for e in base.effects if e != STIFFNESS_EFFECT)
        if self.time_varying:
            effects += (STIFFNESS_EFFECT,)
        settings = base.transient
        changes = {"time_step": time_step, "sample_rate": rate}
        if study.duration is not None:
            changes["duration"] = study.duration
        if study.mean_window is not None:
            changes["mean_window"] = study.mean_window
        if self.equivalent_load != "linear":
            changes["equivalent_load"] = self.equivalent_load
        return dataclasses.replace(
            base,
            analyses=("transient",),  # the study reads its own spectra
            dof_set=None if self.dof_set == "auto" else self.dof_set,
            effects=effects,
            transient=dataclasses.replace(settings, **changes),
        )


def load_accuracy_study(reference: str) -> AccuracyStudy | None:
    """The accuracy-study settings a case file defines (``accuracy = dict(...)`` with the
    fields of :class:`AccuracyStudy`, or an :class:`AccuracyStudy`), or None."""
    directory, module = load_case_module(reference, "pygear_accuracy")
    study = getattr(module, "accuracy", None)
    if isinstance(study, dict):
        try:
            study = AccuracyStudy(**study)
        except TypeError as error:
            raise CaseError(f"{directory / 'case.py'}: accuracy: {error}") from None
    if study is not None and not isinstance(study, AccuracyStudy):
        raise CaseError(f"{directory / 'case.py'}: `accuracy` must be a dict or AccuracyStudy")
    return study


def fidelity_ladder(case: Case, scene: Scene, study: AccuracyStudy) -> list[Fidelity]:
    """The rungs from cheapest to fullest; the last is the reference.

    ``auto`` is kept only when pygear's pick differs from the explicit DOF sets; a
    DOF set the scene's effects refuse (e.g. helical coupling) is left out.
    """
    auto, _ = choose_dof_set(case, scene_settings(dataclasses.replace(scene, dof_set=None)))
    separation = "tooth_separation" in scene.effects
    ladder = []
    for dof_set in study.dof_sets:
        if dof_set == "auto" and auto in study.dof_sets:
            continue
        try:
            Scene.validate(
                dataclasses.replace(scene, dof_set=None if dof_set == "auto" else dof_set), "s"
            )
        except CaseError:
            continue
        for varying in (False, True):
            if ("time-varying" if varying else "constant") not in study.mesh_stiffness:
                continue
            modes = study.equivalent_loads if (varying or separation) else ("linear",)
            ladder += [Fidelity(dof_set, varying, mode) for mode in modes]
    return ladder


# --------------------------------------------------------------------------- one setting


def run_setting(case: Case, scene: Scene, formulation: str, repeats: int, after: float) -> dict:
    """Run one setting ``repeats`` times; its metric values, spectra and median wall time.

    A run that diverges or is refused is recorded (status, message), never raised.
    """
    from ..signals.signal import SignalError, amplitude_spectrum
    from .transient import run_transient

    walls, run = [], None
    for _ in range(repeats):
        started = time.perf_counter()
        try:
            run = run_transient(case, scene, formulation=formulation)
        except (KernelError, CaseError) as error:
            status = "refused" if isinstance(error, CaseError) else "diverged"
            return {"status": status, "message": str(error), "wall": math.nan, "values": {}}
        walls.append(time.perf_counter() - started)
    window = float(run.attrs["mean_window"])
    late = run.sel(time=slice(float(run.time[-1]) - window, None))
    values = {"t_s": float(run.t_s)}
    for member, speed in zip(run.body.values, run.equilibrium_speed.values):
        values[f"equilibrium_speed:{member}"] = float(speed)
    spectra = {}
    for name, (variable, _, label) in run_channels(run).items():
        if variable == "mesh_force":
            force = channel_series(late, name).values
            dynamic = force - force.mean()
            values[f"mesh_force_rms:{label}"] = float(np.sqrt(np.mean(dynamic**2)))
            values[f"mesh_force_peak:{label}"] = float(np.abs(dynamic).max())
        elif str(run[variable].attrs.get("units", "")).endswith("s^2"):
            try:
                series = channel_series(run, name)
                spectrum = amplitude_spectrum(series, after=after, remove_mean=True)
            except SignalError:
                continue
            spectra[name] = (spectrum.frequency.values, spectrum.values)
    return {
        "status": "ok",
        "message": "",
        "wall": statistics.median(walls),
        "values": values,
        "spectra": spectra,
        "contact_evaluations": int(run.attrs.get("solver_contact_evaluations", -1)),
        "dof_count": int(run.attrs.get("dof_count", -1)),
    }


def run_column(args: tuple) -> list[dict]:
    """Every time step of one (formulation, fidelity): a unit of work for Dask."""
    case, scene, fidelity, formulation, steps, study, rate = args
    return [
        run_setting(
            case,
            fidelity.scene(scene, dt, study, rate),
            formulation,
            study.repeats,
            study.signal_after,
        )
        for dt in steps
    ]


# --------------------------------------------------------------------------- metrics


def _spectral_metrics(spectra: dict, reference: dict, n_peaks: int) -> dict[str, float]:
    """Frequency and amplitude near each of the reference's ``n_peaks`` largest peaks."""
    import scipy.signal

    values = {}
    for channel, (freq_ref, amp_ref) in reference.items():
        indices, _ = scipy.signal.find_peaks(amp_ref)
        indices = indices[np.argsort(amp_ref[indices])[::-1][:n_peaks]]
        for k, index in enumerate(sorted(indices, key=lambda i: -amp_ref[i]), start=1):
            key = f"{channel}:{k}"
            f0 = freq_ref[index]
            if channel not in spectra:
                values[f"peak_frequency:{key}"] = values[f"peak_amplitude:{key}"] = math.nan
                continue
            freq, amp = spectra[channel]
            width = max(3 * (freq[1] - freq[0]), 0.02 * f0)  # where the peak may have moved
            near = np.flatnonzero(np.abs(freq - f0) <= width)
            best = near[np.argmax(amp[near])] if near.size else None
            values[f"peak_frequency:{key}"] = float(freq[best]) if best is not None else math.nan
            values[f"peak_amplitude:{key}"] = float(amp[best]) if best is not None else math.nan
    return values


OUT_OF_PLANE_CLASSES = ("axial", "tilting", "planet-out-of-plane")


def _modal_frequencies(case: Case, scene: Scene, formulation: str) -> np.ndarray:
    """Distinct non-zero natural frequencies of a setting's model [Hz], purely
    out-of-plane modes left out (a spur stage's are decoupled from every in-plane answer)."""
    from ..modes.modal import modal_analysis

    modal = modal_analysis(assemble(case, scene, formulation=formulation))
    frequencies = modal.frequency.values
    kept = ~np.isin(modal.mode_class.values.astype(str), OUT_OF_PLANE_CLASSES)
    kept &= frequencies > 1e-6 * max(frequencies.max(), 1.0)
    distinct: list[float] = []
    for f in np.sort(frequencies[kept]):
        if not distinct or f - distinct[-1] > 1e-6 * f:
            distinct.append(float(f))
    return np.array(distinct)


def metric_scales(reference: dict[str, float]) -> dict[str, float]:
    """The scale each metric's error is divided by.

    Frequencies and t_s: their own reference value (relative error).  Speeds, mesh-force
    statistics and peak amplitudes: the largest reference value of their group
    (all equilibrium speeds; all RMS; all peaks; the peaks of one channel), so that a
    member at rest or a weak peak does not turn round-off into a large relative error.
    """
    groups: dict[str, float] = {}
    for name, value in reference.items():
        group = _scale_group(name)
        if group is not None and math.isfinite(value):
            groups[group] = max(groups.get(group, 0.0), abs(value))
    scales = {}
    for name, value in reference.items():
        group = _scale_group(name)
        scales[name] = groups.get(group, 0.0) if group is not None else abs(value)
    return scales


def _scale_group(name: str) -> str | None:
    kind = name.split(":", 1)[0]
    if kind in ("equilibrium_speed", "mesh_force_rms", "mesh_force_peak"):
        return kind
    if kind == "peak_amplitude":
        return name.rsplit(":", 1)[0]
    return None


def metric_errors(values: dict, reference: dict, scales: dict) -> dict[str, float]:
    """|value - reference| / scale per metric (inf where the value is missing)."""
    errors = {}
    for name, ref in reference.items():
        value = values.get(name, math.nan)
        scale = scales.get(name, 0.0)
        if not (math.isfinite(ref) and scale > 0):
            errors[name] = math.nan
        elif not math.isfinite(value):
            errors[name] = math.inf
        else:
            errors[name] = abs(value - ref) / scale
    return errors


def observed_orders(series: np.ndarray, scale: float) -> tuple[float, float]:
    """Observed order and Richardson error estimate from values at halving steps.

    Uses the three finest finite values x1, x2, x3 (step h, h/2, h/4):
    p = log2(|x1 - x2| / |x2 - x3|) and the finest run's error (x2 - x3)/(2^p - 1),
    divided by ``scale``.  The order is NaN when a difference is at round-off
    (below 1e-12 of the scale); the error estimate then falls back to |x2 - x3|.
    """
    finite = series[np.isfinite(series)]
    if finite.size < 2 or not scale > 0:
        return math.nan, math.nan
    last = abs(finite[-2] - finite[-1])
    if finite.size < 3:
        return math.nan, last / scale
    first = abs(finite[-3] - finite[-2])
    floor = 1e-12 * scale
    if first <= floor or last <= floor:
        return math.nan, last / scale
    order = math.log2(first / last)
    estimate = last / (2**order - 1) if order > 0.5 else last
    return order, estimate / scale


def accuracy_grid(case, scene, study, formulations, ladder, steps, results) -> xr.Dataset:
    """The results as a Dataset: values, errors, orders, recommendation."""
    shape = (len(formulations), len(ladder), len(steps))
    wall = np.full(shape, np.nan)
    status = np.full(shape, "", dtype=object)
    message = np.full(shape, "", dtype=object)
    contact = np.full(shape, -1, dtype=np.int64)
    dofs = np.full(shape[:2], -1, dtype=np.int64)
    values: dict[tuple[int, int, int], dict] = {}
    references: dict[int, dict] = {}
    for i, formulation in enumerate(formulations):
        reference_run = results[(formulation, ladder[-1])][-1]
        if reference_run["status"] != "ok":
            raise CaseError(
                f"accuracy: the reference run ({formulation}, {ladder[-1].name}, "
                f"dt = {steps[-1]:g} s) failed: {reference_run['message']}"
            )
        ref_modal = _modal_frequencies(
            case, ladder[-1].scene(scene, steps[-1], study, 1.0 / steps[-1]), formulation
        )[: study.natural_frequencies]
        for j, fid in enumerate(ladder):
            modal = _modal_frequencies(case, fid.scene(scene, steps[-1], study, 1.0), formulation)
            natural = {
                f"natural_frequency:{k + 1}": float(modal[np.argmin(abs(modal - f))])
                if modal.size
                else math.nan
                for k, f in enumerate(ref_modal)
            }
            for k, run in enumerate(results[(formulation, fid)]):
                wall[i, j, k] = run["wall"]
                status[i, j, k] = run["status"]
                message[i, j, k] = run["message"]
                if run["status"] != "ok":
                    continue
                contact[i, j, k] = run["contact_evaluations"]
                dofs[i, j] = run["dof_count"]
                spectral = _spectral_metrics(run["spectra"], reference_run["spectra"], study.peaks)
                values[i, j, k] = {**run["values"], **spectral, **natural}
        references[i] = values[i, len(ladder) - 1, len(steps) - 1]
    metrics = list(dict.fromkeys(m for ref in references.values() for m in ref))
    value = np.full((*shape, len(metrics)), np.nan)
    error = np.full_like(value, np.nan)
    for (i, j, k), vals in values.items():
        scales = metric_scales(references[i])
        errs = metric_errors(vals, references[i], scales)
        value[i, j, k] = [vals.get(m, math.nan) for m in metrics]
        error[i, j, k] = [errs.get(m, math.nan) for m in metrics]
    for i, j, k in zip(*np.nonzero(status != "ok")):
        error[i, j, k] = math.inf
    order = np.full((len(formulations), len(ladder), len(metrics)), np.nan)
    estimate = np.full_like(order, np.nan)
    judged = np.zeros((len(formulations), len(metrics)), dtype=bool)
    fullest = ladder[-1]
    twins = [
        j
        for j, fid in enumerate(ladder[:-1])
        if fid.dof_set == fullest.dof_set
        and fid.time_varying == fullest.time_varying
        and fid.equivalent_load == "iterate"
        and fullest.equivalent_load != "iterate"
    ]
    for i in range(len(formulations)):
        scales = metric_scales(references[i])
        for n, m in enumerate(metrics):
            scale = scales.get(m, 0.0)
            for j in range(len(ladder)):
                order[i, j, n], estimate[i, j, n] = observed_orders(value[i, j, :, n], scale)
            finest = value[i, -1, -2:, n]
            judged[i, n] = bool(
                scale > 0
                and np.all(np.isfinite(finest))
                and abs(finest[0] - finest[1]) <= study.tolerance * scale
            )
            # and the converged solvers agree at the finest step: a channel carrying only
            # round-off (the symmetric study case's ring acceleration) does not
            for twin in twins:
                other = value[i, twin, -1, n]
                judged[i, n] &= bool(
                    np.isfinite(other) and abs(other - finest[1]) <= study.tolerance * scale
                )
        for n, m in enumerate(metrics):  # a peak's frequency means nothing without its peak
            if m.startswith("peak_frequency:"):
                judged[i, n] &= judged[i, metrics.index(m.replace("frequency", "amplitude", 1))]
    worst = np.where(judged[:, None, None, :], np.nan_to_num(error, nan=np.inf), -np.inf)
    max_error = np.where(judged.any(-1)[:, None, None], worst.max(-1), np.nan)
    return grid_dataset(
        case, scene, study, formulations, ladder, steps, metrics,
        dict(value=value, error=error, wall=wall, status=status, message=message,
             contact=contact, dofs=dofs, order=order, estimate=estimate, judged=judged,
             max_error=max_error),
        SAMPLED_KINDS,
    )  # fmt: skip
