"""Python access to the Fortran kernel (``pygear.kernel._kernel``), with error codes turned
into exceptions.  The element matrices themselves live only in Fortran."""

from __future__ import annotations

import numpy as np

from . import _kernel

__all__ = ["KernelError", "FORMULATION_CODES", "MESH_KINDS", "call"]

FORMULATION_CODES = {"improved": 1, "consistent": 2, "lin-parker": 3}
"""Formulation names and the codes the kernel knows them by."""

MESH_KINDS = {"sun": 1, "ring": 2}
"""Planetary mesh kinds: sun-planet (external) and ring-planet (internal)."""

_MESSAGES = {1: "a physical argument is out of range", 2: "an unknown option code"}


class KernelError(RuntimeError):
    """The kernel returned a non-zero error code."""


def call(name: str, *args: object) -> tuple[np.ndarray, ...]:
    """Call kernel routine ``name`` and return its outputs without the error code.

    Raises
    ------
    KernelError
        When the routine reports an error; the message names the routine.
    """
    result = getattr(_kernel, name)(*args)
    if not isinstance(result, tuple):
        result = (result,)
    *outputs, ierr = result
    if ierr != 0:
        reason = _MESSAGES.get(int(ierr), f"error code {int(ierr)}")
        raise KernelError(f"kernel routine {name}: {reason} (arguments {args!r})")
    return tuple(outputs)
