"""Checks a command makes on its plan before any work: its ``--out`` target, and the
memory a drivetrain's shafts will take, estimated from their element counts.

Everything here reads the case and the command line only (nothing is assembled), so
a plan too large for the machine is refused with its estimate in one line, exit code
2, before a model is built or a Dask cluster starts.
"""

from __future__ import annotations

import errno
import math
import os
from pathlib import Path

from ..errors import CaseError
from ..resources import FLOAT_BYTES, require_memory

__all__ = [
    "FILE_SUFFIXES",
    "SPARSE_BYTES_PER_ELEMENT",
    "check_drivetrain_memory",
    "check_out_dir",
    "disk_full",
    "drivetrain_size",
]

FILE_SUFFIXES = (".nc", ".npz", ".png", ".pdf", ".svg", ".csv", ".json", ".md", ".txt")
"""Suffixes of the files pygear writes: an ``--out`` directory named like one of them is
a file name given by mistake (``--out y.nc``), refused instead of made a directory."""

SPARSE_BYTES_PER_ELEMENT = 10_000
"""Memory of one shaft element in a sparse drivetrain model and its shift-invert
eigensolution [bytes]: 8.7 kB measured on the NREL 5 MW drivetrain with 16 000
elements a shaft (200 MB peak, 96 096 DOFs), rounded up."""

DENSE_MATRICES = 4
"""Dense n x n arrays a drivetrain's run holds at least: M, K, C and the reduction T
(:func:`pygear.assembly.drivetrain_model.as_model`)."""


def check_out_dir(option: str, path: str | os.PathLike | None, writer: str) -> None:
    """Refuse an ``--out`` directory that cannot be one, before any work; ``writer``
    names what writes there (``a sweep``) in the message.

    Raises
    ------
    CaseError
        When ``path`` is an existing file, lies below an existing file, or carries the
        suffix of a file pygear writes (:data:`FILE_SUFFIXES`).
    """
    if path is None:
        return
    target = Path(path)
    if target.exists() and not target.is_dir():
        raise CaseError(f"{option} {str(target)!r} is a file: {writer} writes into a directory")
    if target.suffix.lower() in FILE_SUFFIXES and not target.is_dir():
        raise CaseError(
            f"{option} {str(target)!r} names a {target.suffix} file, but {writer} writes "
            f"into a directory: give a directory name (without {target.suffix})"
        )
    for parent in target.absolute().parents:
        if parent.exists():
            if not parent.is_dir():
                raise CaseError(
                    f"{option} {str(target)!r}: {str(parent)!r} is a file, so no directory "
                    "can be made below it"
                )
            break


def drivetrain_size(case, dof_set: str | None = "spatial") -> tuple[int, int, str]:
    """DOFs, shaft elements and the parameter of the largest shaft of ``case``'s
    drivetrain, from the element counts alone (nothing assembled).

    DOFs count the shaft nodes only (six each, one in the torsional set): the
    gearbox's few dozen are left out, so the count is a lower bound.
    """
    drivetrain = case.drivetrain
    elements, largest, nodes = 0, (0, ""), 0
    for k, shaft in enumerate(drivetrain.shafts):
        count = len(shaft.sections) * int(shaft.elements_per_section)
        elements += count
        nodes += count + 1
        if count > largest[0]:
            largest = (count, f"drivetrain.shafts[{k}].elements_per_section")
    per_node = 1 if dof_set == "torsional" else 6
    return nodes * per_node, elements, largest[1]


def check_drivetrain_memory(case, *, dense: bool, dof_set: str | None = "spatial") -> None:
    """Refuse a drivetrain whose shafts' element counts make its model too large.

    ``dense``: the run's model (a transient, or a sweep point, holds M, K, C and T as
    dense n x n arrays); else the modal analysis's sparse model.  Nothing for a case
    without a drivetrain.

    Raises
    ------
    CaseError
        Naming the largest shaft's ``elements_per_section``, the estimate and the
        memory available.
    """
    if getattr(case, "drivetrain", None) is None:
        return
    dofs, elements, parameter = drivetrain_size(case, dof_set)
    if dense:
        needed = DENSE_MATRICES * float(dofs) ** 2 * FLOAT_BYTES
        what = f"{dofs:,} DOFs from {elements:,} shaft elements; M, K, C and T dense, 8 bytes each"
    else:
        needed = elements * float(SPARSE_BYTES_PER_ELEMENT)
        what = (
            f"{elements:,} shaft elements x {SPARSE_BYTES_PER_ELEMENT / 1e3:g} kB each "
            f"in the sparse model and its eigensolution, {dofs:,} DOFs"
        )
    if math.isfinite(needed):
        require_memory(parameter, needed, what, "use fewer elements per section")


def disk_full(error: BaseException) -> bool:
    """True for a write refused because the disk (or the user's quota) is full."""
    return isinstance(error, OSError) and error.errno in (errno.ENOSPC, errno.EDQUOT)
