"""The package version, in a module of its own so low layers can read it without
importing the package, and the git revision it was built from."""

from __future__ import annotations

__all__ = ["__version__", "git_revision"]

__version__ = "0.1.0"


def git_revision() -> str | None:
    """The git revision pygear was built from, or None when it is not known.

    Written at build time into ``pygear/_git_revision.py`` (meson.build runs
    scripts/git_revision.py on every build, so an editable install, rebuilt on import,
    follows commits and edits; ``-dirty``: files changed since that commit).  git is
    never asked at run time: a repository around the installed package or the working
    directory would answer with its own commit.
    """
    try:
        from ._git_revision import GIT_REVISION
    except ImportError:  # a source tree imported without a build
        return None
    return GIT_REVISION if GIT_REVISION and GIT_REVISION != "unknown" else None
