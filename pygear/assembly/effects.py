"""The record of what a result was computed with: DOF set, pruned DOF count and effects.

A scene lists the effects it calls for (docs/model.md §7); assembly and the solver build
only those.  :func:`effect_attributes` turns an assembled model (and, for a run, the
equivalent-load mode) into the global attributes every output file carries, so a file
says which DOF set was used and why, how many DOFs the pruning kept of the spatial
model's, and which effects were in force.
"""

from __future__ import annotations

from .matrices import Model

__all__ = ["effect_attributes", "effects_in_force"]


def effects_in_force(model: Model, equivalent_load: str | None = None) -> dict[str, str]:
    """Each effect a scene may call for and whether (and how) it was in force.

    Parameters
    ----------
    model : Model
        The assembled model (its scene's effects and attributes).
    equivalent_load : str, optional
        The run's equivalent-load mode (``linear`` when no mesh term was needed);
        None for analyses without time integration.

    Returns
    -------
    dict of str to str
        One line per effect, keyed by its name.
    """
    effects = set(model.effects)
    info = model.attributes
    varying = "time_varying_mesh_stiffness" in effects
    defects = int(info.get("tooth_defects", 0))
    helical = tuple(info.get("helical_stages", ()))
    record = {
        "dof_set": (
            f"{model.dof_set}: {model.size} of {model.spatial_size or model.size} DOFs "
            f"({model.dof_set_reason})"
        ),
        "time_varying_mesh_stiffness": (
            "on (tooth-contact table)" if varying else "off (mean stiffness; table never evaluated)"
        ),
        "tooth_defects": (
            "none"
            if not defects
            else f"{defects} defective teeth, "
            + ("in force" if varying else "not in force (they act through the contact table)")
        ),
        "tooth_separation": "on" if "tooth_separation" in effects else "off",
        "rolling_bearing_contact": (
            "on (rolling bearings as Hertz contacts in place of their springs)"
            if "rolling_bearing_contact" in effects
            else "off"
        ),
        "speed_dependent_planet_terms": (
            f"on at {info.get('carrier_speed_rpm', 0.0):g} rpm"
            if model.gyroscopic is not None and "speed_dependent_planet_terms" in effects
            else "off"
        ),
        "gyroscopic_all_members": (
            f"on at {info.get('carrier_speed_rpm', 0.0):g} rpm of the first planetary "
            "carrier (Cooley & Parker 2012, every member in its carrier's frame)"
            if "gyroscopic_all_members" in effects
            else "off"
        ),
        "helical_coupling": _helical(model, helical),
        "damping": str(info.get("damping", "as assembled")),
    }
    if equivalent_load is not None:
        record["equivalent_load"] = (
            "linear (no mesh term needed: constant stiffness, no separation)"
            if equivalent_load == "linear"
            else equivalent_load
        )
    return record


def _helical(model: Model, helical: tuple[str, ...]) -> str:
    if not helical:
        return "none (spur stages only)"
    if model.dof_set in ("planar", "torsional"):
        return f"dropped by the {model.dof_set} DOF set ({', '.join(helical)} helical)"
    return f"on ({', '.join(helical)})"


def effect_attributes(model: Model, equivalent_load: str | None = None) -> dict[str, str | int]:
    """Global attributes of an output file: DOF set, reason, pruned counts, effects in force."""
    record = effects_in_force(model, equivalent_load)
    return {
        "dof_set": model.dof_set,
        "dof_set_reason": model.dof_set_reason,
        "dof_count": model.size,
        "dof_count_spatial": model.spatial_size or model.size,
        "effects_in_force": "; ".join(f"{k}: {v}" for k, v in record.items()),
    }
