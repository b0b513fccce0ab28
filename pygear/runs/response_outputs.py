"""The files of ``pygear response``: ``response.nc`` written atomically, and its figures;
with contact loss also ``response_backlash.nc`` (the branch) and its figure."""

from __future__ import annotations

import os
from pathlib import Path

import xarray as xr

from ..io import save_figure, write_netcdf
from ..model.case import Case
from ..model.case_json import case_json

__all__ = ["FIGURES", "write_response"]

FIGURES = ("dynamic_factor", "load_sharing", "stability")
"""Figures written beside the dataset, as ``response_<name>.png``."""


def write_response(
    case: Case,
    response: xr.Dataset,
    directory: str | os.PathLike,
    *,
    figures: bool = True,
    stem: str = "response",
    branch: xr.Dataset | None = None,
) -> list[Path]:
    """Write ``<stem>.nc`` (and its figures) into ``directory``.

    Parameters
    ----------
    case : Case
        The case the response belongs to (its hash and JSON go into the file).
    response : xarray.Dataset
        A :func:`pygear.analysis.response.forced_response` result.
    directory : path-like
        Target directory, created when missing.
    figures : bool
        Also draw the dynamic factor, load sharing and stability figures.
    stem : str
        File name without suffix.
    branch : xarray.Dataset, optional
        The contact-loss branch (:func:`pygear.analysis.response.contact_loss_response`):
        written as ``<stem>_backlash.nc`` with the figure ``<stem>_backlash.png``.

    Returns
    -------
    list of Path
        The files written, the dataset first.
    """
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    paths = [
        write_netcdf(
            response,
            directory / f"{stem}.nc",
            title=f"Periodic steady state of {case.name} over the input speed (harmonic balance)",
            input_hash=case.input_hash(),
            case_json=case_json(case),
        )
    ]
    if branch is not None:
        paths.append(
            write_netcdf(
                branch,
                directory / f"{stem}_backlash.nc",
                title=f"Periodic steady state of {case.name} with contact loss, continued "
                "in speed (AFT harmonic balance)",
                input_hash=case.input_hash(),
                case_json=case_json(case),
            )
        )
    if figures:
        from ..plots.response import (
            DPI,
            plot_dynamic_factor,
            plot_load_sharing,
            plot_stability,
        )

        drawings = (plot_dynamic_factor, plot_load_sharing, plot_stability)
        for name, draw in zip(FIGURES, drawings):
            path = directory / f"{stem}_{name}.png"
            paths.append(save_figure(draw(response), path, dpi=DPI, release=True))
        if branch is not None:
            from ..plots.response import plot_contact_loss

            path = directory / f"{stem}_backlash.png"
            paths.append(
                save_figure(plot_contact_loss(branch, response), path, dpi=DPI, release=True)
            )
    return paths
