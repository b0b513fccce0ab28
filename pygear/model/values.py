"""Tests of single values that every model module shares: a finite real number, a
whole number.  They sit below the components and the gear geometry so that both can
use them without importing each other."""

from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = ["is_finite_number", "is_whole_number"]


def is_finite_number(value: object) -> bool:
    """True for a finite real number: an int or float, or a NumPy scalar such as
    ``np.float32`` or ``np.int64`` (not a bool, a string or None)."""
    return (
        isinstance(value, numbers.Real)
        and not isinstance(value, (bool, np.bool_))
        and math.isfinite(value)
    )


def is_whole_number(value: object) -> bool:
    """True for an int or a NumPy integer scalar (not a bool)."""
    return isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))
