"""What ``pygear contact`` writes: the JSON summary, the NetCDF file and a Markdown note
of a loaded tooth contact analysis (:mod:`pygear.analysis.contact.ltca`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

__all__ = ["contact_json", "contact_markdown", "parse_torques", "write_contact_outputs"]


def parse_torques(torque: float | None, torques: str | None) -> np.ndarray:
    """The torques [N m] of ``--torque T`` or ``--torques A:B:N`` (N values from A to B).

    Raises
    ------
    CaseError
        Neither or both given, a range that does not parse, or a value not > 0.
    """
    from ..errors import CaseError

    if (torque is None) == (torques is None):
        raise CaseError("give exactly one of --torque T and --torques A:B:N")
    if torque is not None:
        values = np.array([torque], dtype=float)
    else:
        parts = torques.split(":")
        try:
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
            if len(parts) != 3:
                raise ValueError
        except (ValueError, IndexError):
            raise CaseError(
                f"--torques must be A:B:N, N torques from A to B in N m (got {torques!r})"
            ) from None
        if not 2 <= count <= 200:
            raise CaseError(f"--torques: N must be a whole number in [2, 200] (got {count})")
        values = np.linspace(start, stop, count)
    if not np.all(np.isfinite(values) & (values > 0)):
        raise CaseError(f"--torque values must be positive finite torques [N m] (got {values})")
    return values


def contact_json(ds: xr.Dataset) -> dict:
    """The ``--json`` summary: one value per torque under each key."""
    harmonics = {
        str(int(order)): ds.te_harmonics.sel(order=order).values.tolist()
        for order in ds.order.values
    }
    return {
        "case": ds.attrs.get("case"),
        "mesh": ds.attrs.get("mesh"),
        "torques_nm": ds.torque.values.tolist(),
        "force_n": ds.force.values.tolist(),
        "mean_te_m": ds.mean_te.values.tolist(),
        "te_peak_to_peak_m": ds.te_peak_to_peak.values.tolist(),
        "te_harmonics_m": harmonics,
        "k_h_beta": ds.k_h_beta.values.tolist(),
        "k_h_alpha": ds.k_h_alpha.values.tolist(),
        "max_contact_pressure_pa": ds.max_contact_pressure.values.tolist(),
    }


def contact_markdown(ds: xr.Dataset) -> str:
    """A short report: one row per torque."""
    lines = [
        f"# Loaded tooth contact: {ds.attrs.get('case')} {ds.attrs.get('mesh')}",
        "",
        f"Source: {ds.attrs.get('source', '')}; {int(ds.attrs['n_slice'])} slices, "
        f"{ds.position.size} positions, eps_alpha = {ds.attrs['eps_alpha']:.4g}, "
        f"eps_beta = {ds.attrs['eps_beta']:.4g}.",
        "",
        "| torque N m | force N | mean TE um | TE p-p um | TE order 1 um | K_Hbeta | K_Halpha "
        "| p_H max MPa |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for i in range(ds.force.size):
        lines.append(
            f"| {float(ds.torque[i]):.5g} | {float(ds.force[i]):.5g} "
            f"| {float(ds.mean_te[i]) * 1e6:.4g} | {float(ds.te_peak_to_peak[i]) * 1e6:.4g} "
            f"| {float(ds.te_harmonics[i, 0]) * 1e6:.4g} | {float(ds.k_h_beta[i]):.4g} "
            f"| {float(ds.k_h_alpha[i]):.4g} | {float(ds.max_contact_pressure[i]) / 1e6:.4g} |"
        )
    return "\n".join(lines) + "\n"


def write_contact_outputs(ds: xr.Dataset, out_dir: str | Path) -> dict[str, Path]:
    """Write ``contact.nc`` and ``contact.md`` into ``out_dir``; their paths."""
    from ..io import write_netcdf

    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    paths = {"netcdf": folder / "contact.nc", "report": folder / "contact.md"}
    title = f"Loaded tooth contact of {ds.attrs.get('case')} {ds.attrs.get('mesh')}"
    write_netcdf(ds, paths["netcdf"], title=title)
    paths["report"].write_text(contact_markdown(ds))
    return paths
