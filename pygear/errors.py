"""Errors every layer raises: the one case-error type the CLI maps to exit code 2."""

from __future__ import annotations

__all__ = ["CaseError"]


class CaseError(ValueError):
    """A case parameter breaks a rule; the message names the parameter and the rule."""
