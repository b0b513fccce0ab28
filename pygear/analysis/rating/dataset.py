"""A :class:`~.gearbox_rating.GearboxRating` as an ``xarray.Dataset``.

Dimensions: ``mesh`` (factors shared by a mesh's two gears), ``side`` (gear1, gear2 of
each mesh: per-gear factors of that mesh), ``gear`` (each gear's worst case over its
meshes: stresses, safeties, damage, life) and ``bearing`` (ISO 281 lives).  Every factor
variable carries ``units``, ``long_name`` and the ``clause`` that gave it; a string
variable ``<factor>_source`` per mesh says whether it was given or computed.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ...model.rating import Rating
from .gearbox_rating import GearboxRating

__all__ = ["rating_dataset"]

_UNITS = {"F_t": "N", "v": "m/s", "sigma_H0": "MPa", "sigma_H": "MPa", "sigma_F0": "MPa",
          "sigma_F": "MPa", "sigma_HG_ref": "MPa", "sigma_FG_ref": "MPa", "Z_E": "MPa^0.5",
          "c_prime": "N/(mm um)", "c_gamma_alpha": "N/(mm um)", "N_L": "1"}
_NAMES = {"F_t": "nominal tangential load per mesh", "v": "pitch line velocity",
          "sigma_H0": "nominal contact stress", "sigma_H": "contact stress",
          "sigma_F0": "nominal tooth root stress", "sigma_F": "tooth root stress",
          "S_H": "safety factor for pitting", "S_F": "safety factor for tooth bending",
          "N_L": "load cycles over the service life", "Z_BD": "single pair contact factor"}


def _attrs(name: str, clause: str) -> dict[str, str]:
    return {"units": _UNITS.get(name, "1"), "long_name": _NAMES.get(name, name),
            "clause": clause}


def rating_dataset(result: GearboxRating, rating: Rating, case_name: str = "") -> xr.Dataset:
    """The rating as a Dataset (see the module docstring); attrs name the limiting
    element and whether every requirement is met."""
    meshes = result.meshes
    names = [m.name for m in meshes]
    data: dict[str, tuple] = {}
    for factor in dict.fromkeys(k for m in meshes for k in m.rating.mesh):
        values, sources, clause = [], [], ""
        for m in meshes:
            item = m.rating.mesh.get(factor)
            values.append(np.nan if item is None else item.value)
            sources.append("" if item is None else item.source)
            clause = clause or ("" if item is None else item.clause)
        data[factor] = ("mesh", np.array(values), _attrs(factor, clause))
        data[f"{factor}_source"] = ("mesh", np.array(sources, dtype=object),
                                    {"long_name": f"where {factor} came from"})
    for factor in meshes[0].rating.gears[0]:
        values = np.array([[side[factor].value for side in m.rating.gears] for m in meshes])
        data[f"{factor}_side"] = (("mesh", "side"), values,
                                  _attrs(factor, meshes[0].rating.gears[0][factor].clause))
    data["gear_name"] = (("mesh", "side"), np.array([list(m.gears) for m in meshes],
                                                    dtype=object), {"long_name": "gear"})
    gears = list(dict.fromkeys(g for m in meshes for g in m.gears))
    worst = {g: {"sigma_H": 0.0, "sigma_F": 0.0, "sigma_F0": 0.0, "S_H": math.inf,
                 "S_F": math.inf} for g in gears}
    for m in meshes:
        for gear, side in zip(m.gears, m.rating.gears):
            slot = worst[gear]
            for key in ("sigma_H", "sigma_F", "sigma_F0"):
                slot[key] = max(slot[key], side[key].value)
            for key in ("S_H", "S_F"):
                slot[key] = min(slot[key], side[key].value)
    for key in ("sigma_H", "sigma_F0", "sigma_F", "S_H", "S_F"):
        data[key] = ("gear", np.array([worst[g][key] for g in gears]), _attrs(key, ""))
    damage = [max(result.damage.get(g, {}).get("pitting", 0.0),
                  result.damage.get(g, {}).get("bending", 0.0)) for g in gears]
    data["damage"] = ("gear", np.array(damage), {
        "units": "1", "long_name": "Palmgren-Miner damage over the service life",
        "clause": "ISO 6336-6:2019 (S-N curves of ISO 6336-2/-3 life factors)"})
    data["damage_from"] = ("gear", np.array(
        [result.damage.get(g, {}).get("source", "") for g in gears], dtype=object),
        {"long_name": "what the damage was summed from"})
    life = [rating.service_life_h / d if d > 0 else np.inf for d in damage]
    data["life_h"] = ("gear", np.array(life), {"units": "h", "long_name": "service life"})
    bearings = list(result.bearings)
    for key, unit, long_name in (("P", "N", "dynamic equivalent (mean) load"),
                                 ("speed", "rpm", "mean bearing speed"),
                                 ("L10_h", "h", "basic rating life L10"),
                                 ("a_ISO", "1", "life modification factor"),
                                 ("kappa", "1", "viscosity ratio"),
                                 ("L10m_h", "h", "modified rating life L10m")):
        data[f"bearing_{key}"] = ("bearing", np.array([result.bearings[b][key]
                                                       for b in bearings], dtype=float),
                                  {"units": unit, "long_name": long_name,
                                   "clause": "ISO 281:2007"})
    ds = xr.Dataset({k: xr.Variable(*v) for k, v in data.items()},
                    coords={"mesh": names, "side": ["gear1", "gear2"], "gear": gears,
                            "bearing": bearings})
    limiting, margin = _limiting(ds, rating, result)
    ds.attrs.update({
        "title": f"ISO 6336 / ISO 281 rating of {case_name}".strip(),
        "standards": "ISO 6336-1/-2/-3/-6:2019 method B, ISO 6336-5:2016, ISO 281:2007, "
                     "ASTM E1049-85",
        "required_sh": rating.required_sh, "required_sf": rating.required_sf,
        "service_life_h": rating.service_life_h, "limiting": limiting,
        "limiting_margin": margin, "passed": int(margin >= 1.0),
        "K_v_method": result.dynamic_factor_method,
    })
    return ds


def _limiting(ds: xr.Dataset, rating: Rating, result: GearboxRating) -> tuple[str, float]:
    """The element with the smallest margin: S/S_min of a gear, or life over the
    required life of a gear or bearing."""
    margins: list[tuple[float, str]] = []
    for gear in ds.gear.values:
        s_h = float(ds.S_H.sel(gear=gear))
        s_f = float(ds.S_F.sel(gear=gear))
        margins.append((s_h / rating.required_sh, f"{gear} pitting (S_H {s_h:.3f})"))
        margins.append((s_f / rating.required_sf, f"{gear} bending (S_F {s_f:.3f})"))
        damage = float(ds.damage.sel(gear=gear))
        if damage > 0.0:
            life = float(ds.life_h.sel(gear=gear))
            margins.append((1.0 / damage, f"{gear} service life ({life:.3g} h)"))
    for bearing, values in result.bearings.items():
        margins.append((values["L10m_h"] / rating.service_life_h,
                        f"{bearing} (L10m {values['L10m_h']:.3g} h)"))
    margin, name = min(margins)
    return name, margin
