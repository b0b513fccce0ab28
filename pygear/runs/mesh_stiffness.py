"""The ``mesh-stiffness`` output: the constant-speed mesh stiffness as NetCDF and figure."""

from __future__ import annotations

import os
from pathlib import Path

import xarray as xr

from ..analysis.mesh_stiffness import mesh_stiffness_at_constant_speed
from ..model.case import Case, load_case

__all__ = ["write_mesh_stiffness"]


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
    from ..io import atomic_path, check_suffix, write_netcdf
    from ..plots.mesh import plot_mesh_stiffness

    out_path = Path(out_path)
    # the figure goes to <out stem>.png: any other suffix could name it, or another kind
    check_suffix("out_path", out_path, ".nc", "the mesh stiffness as NetCDF (figure beside)")
    case = case_ref if isinstance(case_ref, Case) else load_case(case_ref)
    dataset = mesh_stiffness_at_constant_speed(case, carrier_speed_rpm=speed_rpm, duration=duration)
    write_netcdf(
        dataset,
        out_path,
        title=f"Time-varying mesh stiffness of {case.name} at {speed_rpm:g} rpm",
        input_hash=case.input_hash(),
    )
    with atomic_path(out_path.with_suffix(".png")) as temporary:
        plot_mesh_stiffness(dataset, temporary, format="png")
    return dataset
