"""What ``pygear rate`` writes: the JSON summary, the Markdown report and the NetCDF
dataset of a rating, and the duty-cycle files it reads.

Duty-cycle files (CSV, one header line): a load duration distribution with columns
``torque`` [N m] and ``hours`` (and optionally ``speed_rpm``), or an input torque time
series with columns ``time`` [s] and ``torque`` [N m], binned by time at level into a
distribution (:func:`pygear.analysis.rating.duty.load_spectrum_from_series`) and
counted by rainflow for the report.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import xarray as xr

from ..errors import CaseError
from ..model.rating import DutyCycle, Rating

__all__ = ["rating_json", "rating_markdown", "read_duty_cycle", "write_rating_outputs"]


def read_duty_cycle(path: str | Path, rated_speed_rpm: float) -> tuple[DutyCycle, dict]:
    """A :class:`DutyCycle` from a CSV file (see the module docstring) and notes on it
    (rainflow cycles of a time series)."""
    from ..analysis.rating.duty import load_spectrum_from_series, rainflow_cycles

    path = Path(path)
    try:
        with path.open(newline="") as handle:
            rows = list(csv.DictReader(handle))
    except OSError as error:
        raise CaseError(f"--duty-cycle {str(path)!r}: cannot read it ({error.strerror})") from None
    if not rows:
        raise CaseError(f"--duty-cycle {str(path)!r}: no data rows after the header")
    columns = set(rows[0])

    def column(name: str) -> list[float]:
        try:
            return [float(row[name]) for row in rows]
        except (TypeError, ValueError):
            raise CaseError(f"--duty-cycle {str(path)!r}: column {name!r} must hold numbers "
                            "in every row") from None

    if {"torque", "hours"} <= columns:
        speeds = column("speed_rpm") if "speed_rpm" in columns else None
        return DutyCycle(tuple(column("torque")), tuple(column("hours")), speeds), {}
    if {"time", "torque"} <= columns:
        time, torque = column("time"), column("torque")
        levels, seconds = load_spectrum_from_series(time, torque, 1.0)
        cycles = rainflow_cycles(torque)
        notes = {"rainflow_cycles": len(cycles),
                 "largest_range": max((c[0] for c in cycles), default=0.0),
                 "record_s": time[-1] - time[0]}
        return DutyCycle(tuple(levels), tuple(seconds / 3600.0)), notes
    raise CaseError(
        f"--duty-cycle {str(path)!r} needs columns 'torque' and 'hours' (a load duration "
        f"distribution) or 'time' and 'torque' (a time series); it has {sorted(columns)}"
    )


def rating_json(ds: xr.Dataset) -> dict:
    """The ``--json`` document: ``gears``, ``meshes``, ``bearings``, ``limiting``."""
    gears = {}
    for gear in ds.gear.values:
        row = ds.sel(gear=gear)
        gears[str(gear)] = {key: float(row[key]) for key in
                            ("sigma_F0", "sigma_F", "sigma_H", "S_H", "S_F", "damage", "life_h")}
        gears[str(gear)]["damage_from"] = str(row["damage_from"].item())
    meshes = {}
    mesh_keys = [k for k in ds.data_vars if ds[k].dims == ("mesh",) and ds[k].dtype != object]
    for mesh in ds.mesh.values:
        row = ds.sel(mesh=mesh)
        entry = {k: float(row[k]) for k in mesh_keys if math.isfinite(float(row[k]))}
        entry["given"] = sorted(k[: -len("_source")] for k in ds.data_vars
                                if k.endswith("_source") and row[k].item() in ("given",
                                                                              "response"))
        meshes[str(mesh)] = entry
    bearings = {str(b): {"L10_h": float(ds.bearing_L10_h.sel(bearing=b)),
                         "L10m_h": float(ds.bearing_L10m_h.sel(bearing=b)),
                         "P": float(ds.bearing_P.sel(bearing=b))}
                for b in ds.bearing.values}
    return {"gears": gears, "meshes": meshes, "bearings": bearings,
            "dynamic_factor_method": ds.attrs.get("K_v_method", ""),
            "limiting": ds.attrs["limiting"], "passed": bool(ds.attrs["passed"])}


_SOURCE_LABELS = {"computed": "ISO", "response": "model", "given": "given",
                  "default": "default", "run": "run", "model": "model"}
"""How the report names where a factor came from."""


def _fmt(value: float) -> str:
    if not math.isfinite(value):
        return "inf"
    return f"{value:.4g}"


def rating_markdown(ds: xr.Dataset, rating: Rating, case_name: str, notes: dict) -> str:
    """The report: inputs, factors with their sources and clauses, results, verdict."""
    lines = [f"# Rating of {case_name}", "",
             f"Standards: {ds.attrs['standards']}.", "", "## Inputs", "",
             f"- rated input torque {rating.rated_torque:.6g} N m at "
             f"{rating.rated_speed_rpm:g} rpm",
             f"- application factor K_A {rating.application_factor:g}, required S_H "
             f"{rating.required_sh:g}, S_F {rating.required_sf:g}",
             f"- service life {rating.service_life_h:g} h, ISO 1328 grade "
             f"{rating.accuracy_grade}, oil nu_40 {rating.oil_viscosity_40:g} mm^2/s"]
    for gear, material in rating.materials.items():
        lines.append(f"- {gear}: {material.name} ({material.kind}, {material.grade}), "
                     f"sigma_hlim {material.sigma_hlim / 1e6:g} MPa, sigma_flim "
                     f"{material.sigma_flim / 1e6:g} MPa")
    if rating.duty_cycle is not None:
        lines.append(f"- duty cycle: {len(rating.duty_cycle.torque)} torque bins, "
                     f"{sum(rating.duty_cycle.hours):.6g} h")
    for key, value in notes.items():
        text = value if isinstance(value, str) else _fmt(float(value))
        lines.append(f"- duty cycle {key.replace('_', ' ')}: {text}")
    lines.append(f"- K_v: {ds.attrs.get('K_v_method', '')}")
    lines.append("- factor sources: (given) typed in the case, (model) pygear's dynamic or "
                 "static model, (ISO) the standard's method, (default) a default value, "
                 "(run) held in a run's mesh forces")
    lines += ["", "## Factors per mesh", "", "| factor | " + " | ".join(map(str, ds.mesh.values))
              + " | clause |", "|---" * (len(ds.mesh) + 2) + "|"]
    for key in ds.data_vars:
        if ds[key].dims != ("mesh",) or ds[key].dtype == object:
            continue
        cells = []
        for mesh in ds.mesh.values:
            value = float(ds[key].sel(mesh=mesh))
            source = str(ds[f"{key}_source"].sel(mesh=mesh).item())
            mark = f" ({_SOURCE_LABELS.get(source, source)})" if source else ""
            cells.append(_fmt(value) + mark)
        lines.append(f"| {key} [{ds[key].attrs['units']}] | " + " | ".join(cells)
                     + f" | {ds[key].attrs['clause']} |")
    lines += ["", "## Factors per gear and mesh", "",
              "Every factor here by the standard's method (ISO), from the loads above.", "",
              "| factor | " + " | ".join(f"{m} / {g}" for m in ds.mesh.values
                                        for g in ds.gear_name.sel(mesh=m).values) + " |",
              "|---" * (2 * len(ds.mesh) + 1) + "|"]
    for key in ds.data_vars:
        if ds[key].dims != ("mesh", "side") or key == "gear_name":
            continue
        cells = [_fmt(float(v)) for v in ds[key].values.ravel()]
        lines.append(f"| {key[:-5]} | " + " | ".join(cells) + " |")
    lines += ["", "## Results per gear", "",
              "| gear | sigma_H [MPa] | sigma_F [MPa] | S_H | S_F | damage | life [h] | verdict "
              "| damage from |",
              "|---|---|---|---|---|---|---|---|---|"]
    for gear in ds.gear.values:
        row = ds.sel(gear=gear)
        ok = (float(row.S_H) >= rating.required_sh and float(row.S_F) >= rating.required_sf
              and float(row.damage) <= 1.0)
        lines.append(f"| {gear} | {_fmt(float(row.sigma_H))} | {_fmt(float(row.sigma_F))} | "
                     f"{float(row.S_H):.3f} | {float(row.S_F):.3f} | {_fmt(float(row.damage))} "
                     f"| {_fmt(float(row.life_h))} | {'pass' if ok else 'FAIL'} | "
                f"{row.damage_from.item()} |")
    if ds.sizes.get("bearing", 0):
        lines += ["", "## Bearings (ISO 281)", "",
                  "| bearing | P [N] | speed [rpm] | kappa | a_ISO | L10 [h] | L10m [h] "
                  "| verdict |",
                  "|---|---|---|---|---|---|---|---|"]
        for bearing in ds.bearing.values:
            row = ds.sel(bearing=bearing)
            ok = float(row.bearing_L10m_h) >= rating.service_life_h
            lines.append(
                f"| {bearing} | {_fmt(float(row.bearing_P))} | {_fmt(float(row.bearing_speed))}"
                f" | {_fmt(float(row.bearing_kappa))} | {_fmt(float(row.bearing_a_ISO))} | "
                f"{_fmt(float(row.bearing_L10_h))} | {_fmt(float(row.bearing_L10m_h))} | "
                f"{'pass' if ok else 'FAIL'} |")
    verdict = "passes" if ds.attrs["passed"] else "does NOT pass"
    lines += ["", "## Verdict", "", f"The design {verdict} its requirements; the limiting "
              f"element is {ds.attrs['limiting']} (margin {ds.attrs['limiting_margin']:.3f}).",
              ""]
    return "\n".join(lines)


def write_rating_outputs(ds: xr.Dataset, rating: Rating, case_name: str, out_dir: str | Path,
                         notes: dict) -> dict[str, Path]:
    """Write ``rating.nc`` and ``rating.md`` into ``out_dir``; their paths."""
    from ..io import write_netcdf

    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    stored = ds.copy()
    for key in list(stored.data_vars):
        if stored[key].dtype == object:
            stored[key] = stored[key].astype(str)
    paths = {"netcdf": folder / "rating.nc", "report": folder / "rating.md"}
    write_netcdf(stored, paths["netcdf"], title=f"Rating of {case_name}")
    paths["report"].write_text(rating_markdown(ds, rating, case_name, notes))
    return paths
