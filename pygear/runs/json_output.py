"""JSON that every parser reads: what the ``--json`` options print.

Python's :func:`json.dumps` writes NaN and infinities as the bare tokens ``NaN`` and
``Infinity``, which are not JSON.  :func:`json_text` maps every non-finite number to
``null`` first (a missing value) and then refuses any that is left.
"""

from __future__ import annotations

import json
import math
import numbers

import numpy as np

__all__ = ["finite_or_none", "json_text"]


def finite_or_none(value: object) -> object:
    """``value`` with non-finite numbers replaced by None, recursively through dicts,
    lists and tuples; NumPy scalars and arrays become plain Python values."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    elif isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, dict):
        return {key: finite_or_none(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite_or_none(item) for item in value]
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return value if math.isfinite(value) else None
    return value


def json_text(value: object) -> str:
    """One line of strict JSON: non-finite numbers are written as ``null``."""
    return json.dumps(finite_or_none(value), allow_nan=False)
