"""Sensitivity of natural frequencies to stiffness parameters, and parameter sweeps
(the paper's Figures 7 and 8)."""

from __future__ import annotations

import ast
import dataclasses
import re
from collections.abc import Callable, Sequence

import numpy as np
import xarray as xr

from ...assembly.matrices import Model, assemble
from ...errors import CaseError
from ...model.case import Case, Scene, get_parameter, replace_parameter
from ...model.components import is_finite_number
from ...resources import require_memory
from .modal import modal_analysis, model_attributes, solve_eigenproblem

__all__ = ["frequency_sensitivity", "frequency_sweep", "parse_values"]

_RANGE = re.compile(r"^\s*(linspace|logspace)\s*\((.*)\)\s*$")

_BYTES_PER_VALUE = 8 + 8 + 24
"""Memory of one parsed value: the float64 array linspace builds, and the Python float
(24 bytes) with its list pointer (8 bytes) the values are gathered in."""


def parse_values(items: str | Sequence[str], name: str = "--values") -> np.ndarray:
    """Numbers from a list, ``linspace(a, b, n)`` or ``logspace(a, b, n)``.

    Raises
    ------
    CaseError
        Naming ``name`` and the rule the text breaks.
    """
    if isinstance(items, str):
        items = [items]
    values: list[float] = []
    for item in items:
        for part in _split_outside_parentheses(item):
            match = _RANGE.match(part)
            try:
                if match:
                    args = [float(ast.literal_eval(a.strip())) for a in match.group(2).split(",")]
                    if len(args) != 3 or args[2] < 1 or args[2] != int(args[2]):
                        raise ValueError
                else:
                    values.append(float(part))
            except (ValueError, SyntaxError, TypeError, OverflowError):
                raise CaseError(
                    f"{name}: {part!r} is not a number, linspace(a, b, n) or logspace(a, b, n)"
                ) from None
            if match:
                count = int(args[2])
                require_memory(
                    name,
                    count * _BYTES_PER_VALUE,
                    f"{part.strip()} is {count:g} values x {_BYTES_PER_VALUE} bytes",
                    "ask for fewer values",
                )
                space = np.linspace if match.group(1) == "linspace" else np.logspace
                values.extend(space(args[0], args[1], count).tolist())
    if not values:
        raise CaseError(f"{name} needs at least one value")
    array = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(array)):
        raise CaseError(f"{name} must be finite numbers (got {items!r})")
    return array


def _split_outside_parentheses(text: str) -> list[str]:
    parts, depth, current = [], 0, ""
    for char in text:
        depth += char == "("
        depth -= char == ")"
        if char in ", " and depth == 0:
            if current.strip():
                parts.append(current.strip())
            current = ""
        else:
            current += char
    if current.strip():
        parts.append(current.strip())
    return parts


def frequency_sensitivity(model: Model, parameters: list[str] | None = None) -> xr.Dataset:
    """Sensitivity of every natural frequency to stiffness parameters.

    With mass-normalised shapes, d(omega^2)/dp = phi^T (dK/dp) phi, so
    df/dp = phi^T K_p phi / (8 pi^2 f); the normalised sensitivity
    (p/f) df/dp is half the modal strain-energy fraction held by p's springs.

    Returns
    -------
    xarray.Dataset
        ``sensitivity(mode, parameter)`` [Hz per unit of the parameter] and
        ``strain_energy_fraction(mode, parameter)``.
    """
    parameters = parameters or model.stiffness_parameters()
    frequencies, shapes = solve_eigenproblem(model)
    eigenvalues = (2 * np.pi * frequencies) ** 2
    sensitivity = np.zeros((frequencies.size, len(parameters)))
    fraction = np.zeros_like(sensitivity)
    for j, parameter in enumerate(parameters):
        k_p = model.stiffness_of(parameter)
        value = _parameter_value(model, parameter)
        strain = np.einsum("im,ij,jm->m", shapes.conj(), k_p, shapes).real
        with np.errstate(divide="ignore", invalid="ignore"):
            sensitivity[:, j] = np.where(frequencies > 0, strain / (8 * np.pi**2 * frequencies), 0)
            fraction[:, j] = np.where(eigenvalues > 0, value * strain / eigenvalues, 0)
    return xr.Dataset(
        {
            "frequency": ("mode", frequencies, {"units": "Hz", "long_name": "natural frequency"}),
            "sensitivity": (
                ("mode", "parameter"),
                sensitivity,
                {
                    "units": "Hz per parameter unit",
                    "long_name": "derivative of the natural frequency",
                },
            ),
            "strain_energy_fraction": (
                ("mode", "parameter"),
                fraction,
                {"units": "1", "long_name": "modal strain energy held by the parameter"},
            ),
        },
        coords={
            "mode": ("mode", np.arange(1, frequencies.size + 1), {"long_name": "mode number"}),
            "parameter": (
                "parameter",
                np.array(parameters, dtype=object),
                {"long_name": "stiffness parameter path"},
            ),
        },
        attrs=model_attributes(model),
    )


def _parameter_value(model: Model, parameter: str) -> float:
    for spring in model.springs:
        for name, k in zip(spring.parameters, spring.stiffness):
            if name == parameter:
                return float(k)
    raise KeyError(parameter)


def frequency_sweep(
    case: Case,
    parameter: str,
    values: Sequence[float],
    *,
    formulations: Sequence[str] | None = None,
    scene: Scene | None = None,
    dof_set: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> xr.Dataset:
    """Natural frequencies, classes and strain-energy fractions over parameter values.

    Every value is validated by rebuilding the case before any eigenproblem is solved.

    Returns
    -------
    xarray.Dataset
        ``frequency(formulation, value, mode)`` [Hz], ``mode_class``, and
        ``strain_energy_fraction(formulation, value, mode)`` of the swept parameter.
    """
    formulations = list(formulations or [case.formulation])
    current = get_parameter(case, parameter)
    if not dataclasses.is_dataclass(current) and not is_finite_number(current):
        raise CaseError(
            f"parameter {parameter!r} is not a number (it holds {current!r}): the sweep "
            "sets a stiffness, e.g. planetary.sun_mesh.stiffness"
        )
    # a path naming a stage or a mesh is refused here, with the fields it holds
    cases = [replace_parameter(case, parameter, float(v)) for v in values]
    models = {
        f: [assemble(c, scene, formulation=f, dof_set=dof_set) for c in cases] for f in formulations
    }
    for built in models.values():
        built[0].stiffness_of(parameter)  # a clear error if it scales no spring
    n_modes = max(m.size for built in models.values() for m in built)
    shape = (len(formulations), len(values), n_modes)
    frequency = np.full(shape, np.nan)
    classes = np.full(shape, "", dtype=object)
    fraction = np.full(shape, np.nan)
    done, total = 0, len(formulations) * len(values)
    for i, f in enumerate(formulations):
        for j, model in enumerate(models[f]):
            modal = modal_analysis(model)
            sens = frequency_sensitivity(model, [parameter])
            n = model.size
            frequency[i, j, :n] = modal.frequency.values
            classes[i, j, :n] = modal.mode_class.values
            fraction[i, j, :n] = sens.strain_energy_fraction.values[:, 0]
            done += 1
            if progress:
                progress(done, total)
    units = "N m/rad" if parameter.endswith(("tilt", "torsional")) else "N/m"
    return xr.Dataset(
        {
            "frequency": (
                ("formulation", "value", "mode"),
                frequency,
                {"units": "Hz", "long_name": "natural frequency"},
            ),
            "mode_class": (("formulation", "value", "mode"), classes, {"long_name": "mode class"}),
            "strain_energy_fraction": (
                ("formulation", "value", "mode"),
                fraction,
                {"units": "1", "long_name": f"modal strain energy held by {parameter}"},
            ),
        },
        coords={
            "formulation": ("formulation", np.array(formulations, dtype=object)),
            "value": (
                "value",
                np.asarray(values, dtype=float),
                {"units": units, "long_name": parameter},
            ),
            "mode": ("mode", np.arange(1, n_modes + 1), {"long_name": "mode number"}),
        },
        attrs={
            "case": case.name,
            "parameter": parameter,
            "dof_set": models[formulations[0]][0].dof_set,
        },
    )
