"""The package version, in a module of its own so low layers can read it without
importing the package, and the git revision it runs from."""

from __future__ import annotations

import subprocess
from pathlib import Path

__all__ = ["__version__", "git_revision"]

__version__ = "0.1.0"

_SOURCE_TREE = Path(__file__).resolve().parents[1]
"""The folder above the package: the source checkout of an editable install."""


def git_revision() -> str | None:
    """The git revision pygear runs from, or None when it is not known.

    From a source checkout (an editable install) git is asked now, so the answer
    follows commits and edits (``-dirty``: files changed since that commit); an
    installed wheel answers with the revision recorded when it was built
    (``pygear/_git_revision.py``, written by meson).
    """
    if (_SOURCE_TREE / ".git").exists():
        try:
            described = subprocess.run(
                ["git", "-C", str(_SOURCE_TREE), "describe", "--always", "--dirty", "--abbrev=12"],
                capture_output=True,
                text=True,
                timeout=10,
            )
        except (OSError, subprocess.SubprocessError):
            described = None
        if described is not None and described.returncode == 0 and described.stdout.strip():
            return described.stdout.strip()
    try:
        from ._git_revision import GIT_REVISION
    except ImportError:
        return None
    return GIT_REVISION if GIT_REVISION and GIT_REVISION != "unknown" else None
