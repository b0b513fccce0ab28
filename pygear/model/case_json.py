"""A case as plain JSON: every input, every default and the values derived from them.

Output files store it as their ``case_json`` attribute and ``pygear show-case CASE
--json`` prints it, so that a file says which inputs made it without anything being
executed to read them (JSON is data; a case file is Python).

The layout mirrors the case's dataclasses: an object per dataclass with a ``"type"``
(the class name), each field under its own name (defaults included; a value the gear
geometry filled in is listed under ``"filled_from_geometry"``) and, under
``"derived"``, the read-only properties the class computes from its fields (a stage's
``speed_ratio``, a mesh's ``pressure_angle``, a transient's ``steps``, ...).  Tuples
become lists, mappings objects with string keys, NumPy values plain numbers and
lists.  A float that JSON cannot hold is written as the string ``"NaN"``,
``"Infinity"`` or ``"-Infinity"``.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Mapping

import numpy as np

from .._version import __version__
from .case import Case

__all__ = ["FORMAT", "case_dict", "case_json", "plain"]

FORMAT = "pygear-case-json-1"
"""Name and version of the layout, stored as the document's ``"format"``."""


def _number(value: float) -> float | str:
    if math.isnan(value):
        return "NaN"
    if math.isinf(value):
        return "Infinity" if value > 0 else "-Infinity"
    return value


def _derived(value: object) -> dict:
    """The values of the class's properties that compute without error."""
    found = {}
    for name in dir(type(value)):
        if name.startswith("_") or not isinstance(getattr(type(value), name), property):
            continue
        try:
            result = getattr(value, name)
        except Exception:  # noqa: BLE001 - a property the case leaves undefined
            continue
        if callable(result):
            continue
        found[name] = plain(result)
    return found


def plain(value: object) -> object:
    """``value`` as JSON-ready data: dataclasses, tuples, mappings, NumPy values."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        document: dict = {"type": type(value).__name__}
        for field in dataclasses.fields(value):
            if not field.name.startswith("_"):
                document[field.name] = plain(getattr(value, field.name))
        filled = [name for name, _ in getattr(value, "_derived", ()) if isinstance(name, str)]
        if filled:
            document["filled_from_geometry"] = filled
        derived = _derived(value)
        if derived:
            document["derived"] = derived
        return document
    if isinstance(value, Mapping):
        return {str(key): plain(item) for key, item in value.items()}
    if isinstance(value, np.ndarray):
        return [plain(item) for item in value.tolist()]
    if isinstance(value, (list, tuple, set, frozenset)):
        items = sorted(value, key=repr) if isinstance(value, (set, frozenset)) else value
        return [plain(item) for item in items]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return _number(float(value))
    if value is None or isinstance(value, str):
        return value
    return repr(value)


def case_dict(case: Case) -> dict:
    """The case as a JSON-ready dict: ``format``, ``pygear`` (the version),
    ``input_hash`` (:meth:`Case.input_hash`) and ``case`` (:func:`plain` of it)."""
    return {
        "format": FORMAT,
        "pygear": __version__,
        "input_hash": case.input_hash(),
        "case": plain(case),
    }


def case_json(case: Case, *, indent: int | None = None) -> str:
    """:func:`case_dict` as JSON text (strict: no NaN literals)."""
    return json.dumps(case_dict(case), indent=indent, allow_nan=False)
