"""On-the-fly reductions of a streamed run (placeholder, filled below)."""

from __future__ import annotations

__all__ = ["scene_reductions"]


def scene_reductions(problem) -> list:
    """The reductions the scene asks for, as consumers of a streamed run's blocks."""
    return []
