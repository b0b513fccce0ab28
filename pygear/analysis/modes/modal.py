"""Modal analysis: natural frequencies, mode shapes, mode classes, modal energy and
the sensitivity of every natural frequency to any stiffness parameter.

Classes follow Lin & Parker (1999) and, for spatial models, their out-of-plane
counterparts: a **rotational** mode has no central-member translation, a
**translational** mode no central-member rotation, a **planet** mode no
central-member motion at all.  Classes are read off the mode shapes through the
kinetic energy of each body's translation and rotation, never assumed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ...assembly.matrices import Model
from ...linalg import generalized_eigh

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "ENERGY_GROUPS",
    "ModalResult",
    "classify",
    "modal_analysis",
    "modal_dataset",
    "modal_results",
    "solve_eigenproblem",
]

ENERGY_GROUPS = (
    "central rotation",
    "central translation",
    "planet rotation",
    "planet translation",
)
"""The paper's four modal-energy bars (Figures 4 and 5)."""

ZERO_EIGENVALUE = 1e-11
"""Eigenvalues below this fraction of the largest are rigid-body modes (0 Hz)."""

CLASS_TOLERANCE = 1e-6
"""Energy share below which a motion counts as absent when classifying."""

REPEAT_TOLERANCE = 1e-6
"""Relative frequency difference below which modes count as one repeated frequency."""


def solve_eigenproblem(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequencies [Hz] and mass-normalised mode shapes (reduced DOFs).

    Solves K phi = omega^2 M phi with a symmetric solver; rigid-body modes are
    reported as exactly 0 Hz.  With speed-dependent planet terms the gyroscopic
    problem is solved in state space and the shapes are complex.
    """
    if model.gyroscopic is not None and np.any(model.gyroscopic):
        return _solve_gyroscopic(model)
    eigenvalues, shapes = generalized_eigh(model.stiffness, model.mass)
    scale = max(abs(eigenvalues).max(), 1.0)
    eigenvalues = np.where(eigenvalues < ZERO_EIGENVALUE * scale, 0.0, eigenvalues)
    return np.sqrt(eigenvalues) / (2 * np.pi), shapes


def _solve_gyroscopic(model: Model) -> tuple[np.ndarray, np.ndarray]:
    import scipy.linalg  # the non-symmetric problem only: a plain modal run never loads it

    n = model.size
    mass_inverse = np.linalg.inv(model.mass)
    state = np.block(
        [
            [np.zeros((n, n)), np.eye(n)],
            [-mass_inverse @ model.stiffness, -mass_inverse @ model.gyroscopic],
        ]
    )
    eigenvalues, vectors = scipy.linalg.eig(state)
    omega = eigenvalues.imag
    scale = max(abs(eigenvalues).max(), 1.0)
    rigid = abs(eigenvalues) < np.sqrt(ZERO_EIGENVALUE) * scale
    keep = (omega > 0) & ~rigid
    order = np.argsort(omega[keep])
    frequencies = omega[keep][order] / (2 * np.pi)
    shapes = vectors[:n, keep][:, order]
    n_rigid = n - frequencies.size
    if n_rigid:
        null = scipy.linalg.null_space(model.stiffness, rcond=1e-9)[:, :n_rigid]
        frequencies = np.concatenate([np.zeros(n_rigid), frequencies])
        shapes = np.concatenate([null.astype(complex), shapes], axis=1)
    modal_mass = np.einsum("im,ij,jm->m", shapes.conj(), model.mass, shapes).real
    return frequencies, shapes / np.sqrt(modal_mass)


def energy_table(
    model: Model, shapes: np.ndarray, stage: str | None = None
) -> dict[tuple[str, str, str], np.ndarray]:
    """Kinetic-energy share of every (role, motion, plane) group, per mode.

    Returns a mapping such as ``("central", "rotation", "in-plane") -> shares``; the
    shares of all groups sum to one for every mode.  With ``stage`` only that stage's
    bodies count, as shares of the stage's own energy.
    """
    full = model.reduction @ shapes
    parts = [p for p in model.mass_parts if stage is None or p.body.startswith(f"{stage}.")]
    energies = [_part_energy(full, p) for p in parts]
    total = np.maximum(sum(energies), np.finfo(float).tiny)
    table: dict[tuple[str, str, str], np.ndarray] = {}
    for part, energy in zip(parts, energies):
        key = (part.role, part.motion, part.plane)
        table[key] = table.get(key, 0.0) + energy / total
    return table


def _part_energy(full: np.ndarray, part) -> np.ndarray:
    block = full[part.dofs]
    return np.einsum("im,ij,jm->m", block.conj(), part.matrix, block).real


def stage_energy(model: Model, shapes: np.ndarray) -> tuple[list[str], np.ndarray]:
    """Share of each mode's kinetic energy held by each stage: (stage names, shares)."""
    full = model.reduction @ shapes
    stages = list(dict.fromkeys(p.body.split(".", 1)[0] for p in model.mass_parts))
    energy = np.zeros((shapes.shape[1], len(stages)))
    for part in model.mass_parts:
        energy[:, stages.index(part.body.split(".", 1)[0])] += _part_energy(full, part)
    return stages, energy / energy.sum(axis=1, keepdims=True)


def classify_by_stage(model: Model, shapes: np.ndarray) -> tuple[list[str], list[str], np.ndarray]:
    """Dominant stage, class within it, and the stage energy shares of every mode.

    A planetary stage's class comes from :func:`classify` on its own energy; a
    parallel stage or a shaft is ``rotational`` when rotation about the axis holds
    most of its energy, ``other`` otherwise (the paper's Table 5).
    """
    stages, shares = stage_energy(model, shapes)
    dominant = [stages[i] for i in shares.argmax(axis=1)]
    planetary = {node.name.split(".", 1)[0] for node in model.nodes if node.role == "planet"}
    classes = [""] * len(dominant)
    for stage in stages:
        modes = [m for m, d in enumerate(dominant) if d == stage]
        if not modes:
            continue
        table = energy_table(model, shapes[:, modes], stage)
        if stage in planetary:
            names = classify(table)
        else:
            rotation = table.get(("central", "rotation", "in-plane"), np.zeros(len(modes)))
            names = ["rotational" if r >= 0.5 else "other" for r in rotation]
        for m, name in zip(modes, names):
            classes[m] = name
    return dominant, classes, shares


def _full_mass(model: Model) -> np.ndarray:
    n = len(model.full_labels)
    mass = np.zeros((n, n))
    for part in model.mass_parts:
        mass[np.ix_(part.dofs, part.dofs)] += part.matrix
    return mass


def classify(table: dict[tuple[str, str, str], np.ndarray]) -> list[str]:
    """Mode class of every mode from its energy table.

    ``planet`` (central members still), ``rotational`` (no central translation),
    ``translational`` (no central rotation); out of plane the same families are
    ``planet-out-of-plane``, ``axial`` and ``tilting``, and a helical stage couples them
    into ``rotational-axial`` and ``translational-tilting``.  ``mixed`` otherwise.
    """
    n_modes = len(next(iter(table.values())))

    def share(role: str | None = None, motion: str | None = None, plane: str | None = None):
        total = np.zeros(n_modes)
        for (r, m, p), values in table.items():
            if (role in (None, r)) and (motion in (None, m)) and (plane in (None, p)):
                total = total + values
        return total

    central = share("central")
    central_rotation = share("central", "rotation", "in-plane")  # theta_z
    central_tilt = share("central", "rotation", "out-of-plane")
    central_translation = share("central", "translation", "in-plane")
    central_axial = share("central", "translation", "out-of-plane")
    in_plane, out_of_plane = share(plane="in-plane"), share(plane="out-of-plane")
    classes = []
    tol = CLASS_TOLERANCE
    for m in range(n_modes):
        planar, spatial = out_of_plane[m] < tol, in_plane[m] < tol
        if central[m] < tol:
            name = "planet" if planar else "planet-out-of-plane" if spatial else "planet-coupled"
        elif central_translation[m] + central_tilt[m] < tol:
            name = "rotational" if planar else "axial" if spatial else "rotational-axial"
        elif central_rotation[m] + central_axial[m] < tol:
            name = "translational" if planar else "tilting" if spatial else "translational-tilting"
        else:
            name = "mixed"
        classes.append(name)
    return classes


def multiplicities(frequencies: np.ndarray) -> np.ndarray:
    """How many modes share each mode's natural frequency."""
    scale = max(frequencies.max(initial=0.0), 1.0)
    result = np.ones(frequencies.size, dtype=int)
    for i, f in enumerate(frequencies):
        close = np.abs(frequencies - f) <= REPEAT_TOLERANCE * max(f, 1e-9 * scale)
        result[i] = close.sum()
    return result


@dataclass(frozen=True)
class ModalResult:
    """A modal analysis in NumPy arrays: what :func:`modal_analysis` puts in its Dataset.

    The ``pygear modal`` table needs nothing more, so it prints without loading xarray.
    """

    frequency: np.ndarray
    """Natural frequencies [Hz], ``(mode,)``."""
    shape: np.ndarray
    """Mass-normalised mode shapes on the reduced DOFs, ``(dof, mode)``."""
    mode_class: list[str]
    """Lin & Parker class of every mode (:func:`classify`)."""
    class_index: np.ndarray
    """1-based order within the class, repeated frequencies counted once."""
    multiplicity: np.ndarray
    """Number of modes at each mode's frequency."""
    stage_name: list[str]
    """Stage holding most of each mode's kinetic energy."""
    energy_share: np.ndarray
    """Share of modal kinetic energy per :data:`ENERGY_GROUPS`, ``(mode, group)``."""
    stage_energy: np.ndarray
    """Share of modal kinetic energy per stage, ``(mode, stage)``."""
    stages: list[str]
    """Stage names, the columns of :attr:`stage_energy`."""
    dof_labels: list[str]
    """Reduced DOF labels, the rows of :attr:`shape`."""
    attrs: dict
    """:func:`model_attributes` of the model."""


def modal_results(model: Model) -> ModalResult:
    """Natural frequencies, shapes, classes, multiplicities and energy shares."""
    frequencies, shapes = solve_eigenproblem(model)
    table = energy_table(model, shapes)
    dominant, classes, stage_shares = classify_by_stage(model, shapes)
    stages = list(dict.fromkeys(p.body.split(".", 1)[0] for p in model.mass_parts))
    bars = np.stack(
        [
            sum(v for (role, motion, _), v in table.items() if f"{role} {motion}" == group)
            + np.zeros(frequencies.size)
            for group in ENERGY_GROUPS
        ],
        axis=1,
    )
    return ModalResult(
        frequency=frequencies,
        shape=shapes,
        mode_class=list(classes),
        class_index=_class_indices(frequencies, [f"{d} {c}" for d, c in zip(dominant, classes)]),
        multiplicity=multiplicities(frequencies),
        stage_name=list(dominant),
        energy_share=bars,
        stage_energy=stage_shares,
        stages=stages,
        dof_labels=list(model.dof_labels),
        attrs=model_attributes(model),
    )


def modal_analysis(model: Model) -> xr.Dataset:
    """Natural frequencies, shapes, classes, multiplicities and energy shares.

    Returns
    -------
    xarray.Dataset
        ``frequency(mode)`` [Hz], ``mode_class(mode)``, ``class_index(mode)`` (1-based
        order within the class, repeated frequencies counted once), ``multiplicity(mode)``,
        ``shape(dof, mode)`` (mass-normalised, reduced DOFs) and
        ``energy_share(mode, energy_group)`` (the paper's four bars).
    """
    return modal_dataset(modal_results(model))


def modal_dataset(result: ModalResult) -> xr.Dataset:
    """The Dataset of :func:`modal_analysis` from a :class:`ModalResult`."""
    import xarray as xr

    shapes = result.shape
    frequencies = result.frequency
    dataset = xr.Dataset(
        {
            "frequency": ("mode", frequencies, {"units": "Hz", "long_name": "natural frequency"}),
            "mode_class": (
                "mode",
                np.array(result.mode_class, dtype=object),
                {"long_name": "mode class (Lin & Parker families)"},
            ),
            "class_index": (
                "mode",
                result.class_index,
                {"units": "1", "long_name": "order within the class, repeated frequencies once"},
            ),
            "multiplicity": (
                "mode",
                result.multiplicity,
                {"units": "1", "long_name": "number of modes at this frequency"},
            ),
            "shape": (
                ("dof", "mode"),
                shapes.real if not np.iscomplexobj(shapes) else abs(shapes),
                {"units": "1", "long_name": "mass-normalised mode shape (reduced DOFs)"},
            ),
            "energy_share": (
                ("mode", "energy_group"),
                result.energy_share,
                {"units": "1", "long_name": "share of modal kinetic energy"},
            ),
            "stage_name": (
                "mode",
                np.array(result.stage_name, dtype=object),
                {"long_name": "stage holding most of the mode's kinetic energy"},
            ),
            "stage_energy": (
                ("mode", "stage"),
                result.stage_energy,
                {"units": "1", "long_name": "share of modal kinetic energy per stage"},
            ),
        },
        coords={
            "mode": (
                "mode",
                np.arange(1, frequencies.size + 1),
                {"units": "1", "long_name": "mode number"},
            ),
            "dof": (
                "dof",
                np.array(result.dof_labels, dtype=object),
                {"long_name": "reduced degree of freedom"},
            ),
            "stage": ("stage", np.array(result.stages, dtype=object), {"long_name": "stage"}),
            "energy_group": (
                "energy_group",
                np.array(ENERGY_GROUPS, dtype=object),
                {"long_name": "body family and motion"},
            ),
        },
        attrs=dict(result.attrs),
    )
    return dataset


def _class_indices(frequencies: np.ndarray, classes: list[str]) -> np.ndarray:
    index = np.zeros(frequencies.size, dtype=int)
    counters: dict[str, list[float]] = {}
    for m, (f, name) in enumerate(zip(frequencies, classes)):
        seen = counters.setdefault(name, [])
        if not seen or abs(f - seen[-1]) > REPEAT_TOLERANCE * max(f, 1e-9):
            seen.append(f)
        index[m] = len(seen)
    return index


def model_attributes(model: Model) -> dict[str, str | int]:
    """Global attributes that say which model produced a result (and its effects in force)."""
    from ...assembly.effects import effect_attributes

    return {
        "case": model.case_name,
        "formulation": model.formulation,
        "dof_set": model.dof_set,
        "dof_set_reason": model.dof_set_reason,
        "dof_count": model.size,
        "effects": ", ".join(model.effects) or "none",
        **effect_attributes(model),
    }


def distinct_frequencies(modal: xr.Dataset, stage: str, mode_class: str) -> np.ndarray:
    """Distinct natural frequencies of one class within one stage, ascending [Hz]."""
    chosen = (modal.stage_name.values == stage) & (modal.mode_class.values == mode_class)
    values: list[float] = []
    for f in modal.frequency.values[chosen]:
        if not values or abs(f - values[-1]) > REPEAT_TOLERANCE * max(f, 1.0):
            values.append(float(f))
    return np.array(values)


def stage_comparison(case, stage_name: str, formulation: str | None = None) -> xr.Dataset:
    """A stage's frequencies inside the gearbox against the same stage alone (Table 6).

    Returns
    -------
    xarray.Dataset
        ``in_gearbox(mode_class, order)`` and ``independent(mode_class, order)`` [Hz] and
        their relative difference, for the stage's rotational, translational and planet
        families.
    """
    import dataclasses

    import xarray as xr

    from ...assembly.matrices import assemble

    stage = case.gearbox.stage(stage_name)
    alone = dataclasses.replace(
        case,
        gearbox=dataclasses.replace(
            case.gearbox,
            stages=(stage,),
            couplings=(),
            input_dof=None,
            output_dof=None,
            rigid_body_modes=1,
        ),
        scenes=(),
    )
    formulation = formulation or case.formulation
    in_gearbox = modal_analysis(assemble(case, formulation=formulation))
    independent = modal_analysis(assemble(alone, formulation=formulation))
    families = ("rotational", "translational", "planet")
    pairs = [
        (
            distinct_frequencies(in_gearbox, stage_name, c),
            distinct_frequencies(independent, stage_name, c),
        )
        for c in families
    ]
    width = max(1, max(max(a.size, b.size) for a, b in pairs))
    table = np.full((2, len(families), width), np.nan)
    for k, (a, b) in enumerate(pairs):
        table[0, k, : a.size] = a
        table[1, k, : b.size] = b
    with np.errstate(invalid="ignore", divide="ignore"):
        difference = np.where(table[1] > 0, table[0] / table[1] - 1, 0.0)
    dims = ("mode_class", "order")
    hz = {"units": "Hz"}
    return xr.Dataset(
        {
            "in_gearbox": (dims, table[0], {**hz, "long_name": "natural frequency in the gearbox"}),
            "independent": (dims, table[1], {**hz, "long_name": "natural frequency alone"}),
            "relative_difference": (dims, difference, {"units": "1"}),
        },
        coords={"mode_class": np.array(families, dtype=object), "order": np.arange(1, width + 1)},
        attrs={"case": case.name, "stage": stage_name, "formulation": formulation},
    )
