"""The ``pygear`` command line; :func:`main` is the console entry point."""

from .parser import main

__all__ = ["main"]
