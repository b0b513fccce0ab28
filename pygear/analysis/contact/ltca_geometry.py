"""Slices and initial separation of a loaded tooth contact analysis
(:mod:`pygear.assembly.ltca_geometry`, kept under this name for the analysis topics)."""

from ...assembly.ltca_geometry import (
    SliceGrid,
    contact_rolls,
    flank_roll_limits,
    lead_gap,
    profile_gap,
    separation,
    slice_grid,
)

__all__ = [
    "SliceGrid",
    "contact_rolls",
    "flank_roll_limits",
    "lead_gap",
    "profile_gap",
    "separation",
    "slice_grid",
]
