"""The ``mesh-stiffness`` output: the constant-speed mesh stiffness as NetCDF and figure,
and each mesh's law, gear geometry and stiffness."""

from __future__ import annotations

import os
from pathlib import Path

import xarray as xr

from ..analysis.contact.mesh_stiffness import mesh_stiffness_at_constant_speed, mesh_summary
from ..model.case import Case, load_case

__all__ = ["mesh_stiffness_report", "write_mesh_stiffness"]


def mesh_stiffness_report(
    case_ref: Case | str | os.PathLike,
    speed_rpm: float = 120.0,
    duration: float | None = None,
    out_path: str | os.PathLike | None = None,
    *,
    scene: str | None = None,
    law: str | None = None,
) -> tuple[xr.Dataset, dict[str, dict]]:
    """The constant-speed mesh stiffness of a case's scene and each mesh's summary.

    Parameters
    ----------
    case_ref : Case, str or path
        A case, or a case directory or name under ``cases/``.
    speed_rpm, duration
        As for :func:`write_mesh_stiffness`.
    out_path : str or path, optional
        Target ``.nc`` file (figure beside); None writes nothing.
    scene : str, optional
        Scene whose parameter changes and tooth defects apply.
    law : str, optional
        A law every mesh runs instead of its own
        (:func:`pygear.assembly.mesh_laws.with_mesh_law`).

    Returns
    -------
    dataset : xarray.Dataset
        The mesh stiffness along the constant-speed kinematics.
    summary : dict
        :func:`pygear.analysis.contact.mesh_stiffness.mesh_summary` of it, by mesh name.
    """
    from ..assembly.mesh_laws import with_mesh_law

    if out_path is not None:
        from ..io import check_suffix

        check_suffix("out_path", Path(out_path), ".nc", "the mesh stiffness as NetCDF")
    case = case_ref if isinstance(case_ref, Case) else load_case(case_ref)
    chosen = case.scene(scene) if scene is not None else None
    if chosen is not None:
        case = case.for_scene(chosen)
    if law is not None:
        case = with_mesh_law(case, law)
    dataset = mesh_stiffness_at_constant_speed(
        case, carrier_speed_rpm=speed_rpm, duration=duration, scene=chosen
    )
    if out_path is not None:
        _write(case, dataset, speed_rpm, Path(out_path), scene=scene)
    return dataset, mesh_summary(case, dataset)


def write_mesh_stiffness(
    case_ref: Case | str | os.PathLike,
    speed_rpm: float = 120.0,
    duration: float | None = None,
    out_path: str | os.PathLike = "mesh_stiffness.nc",
) -> xr.Dataset:
    """Compute the constant-speed mesh stiffness, write it as NetCDF and draw its figure.

    The NetCDF file is written as ``<out>.tmp`` in the same directory and renamed
    when complete; the figure goes next to it as ``<out stem>.png`` the same way.

    Parameters
    ----------
    case_ref : Case, str or path
        A case, or a case directory or name under ``cases/``.
    speed_rpm : float
        Carrier speed [rpm].
    duration : float, optional
        Length of the run [s]; see :func:`mesh_stiffness_at_constant_speed`.
    out_path : str or path
        Target ``.nc`` file (another suffix is refused with :class:`CaseError`).

    Returns
    -------
    xarray.Dataset
        The dataset as written.
    """
    from ..io import check_suffix

    out_path = Path(out_path)
    # the figure goes to <out stem>.png: any other suffix could name it, or another kind
    check_suffix("out_path", out_path, ".nc", "the mesh stiffness as NetCDF (figure beside)")
    case = case_ref if isinstance(case_ref, Case) else load_case(case_ref)
    dataset = mesh_stiffness_at_constant_speed(case, carrier_speed_rpm=speed_rpm, duration=duration)
    _write(case, dataset, speed_rpm, out_path)
    return dataset


def _write(
    case: Case, dataset: xr.Dataset, speed_rpm: float, out_path: Path, scene: str | None = None
) -> None:
    """The dataset as NetCDF and its figure beside it, each renamed only when whole."""
    from ..io import save_figure, write_netcdf
    from ..plots.mesh import plot_mesh_stiffness

    write_netcdf(
        dataset,
        out_path,
        title=f"Time-varying mesh stiffness of {case.name} at {speed_rpm:g} rpm",
        input_hash=case.input_hash(),
    )
    figure = plot_mesh_stiffness(dataset, scene=scene)
    save_figure(figure, out_path.with_suffix(".png"), dpi=figure.dpi, release=True)
