"""The ``pygear`` command line: the parser of every subcommand and the dispatch.

Each command family lives in its own module (:mod:`.modal`, :mod:`.run`,
:mod:`.batch`, :mod:`.accuracy`) and imports its work inside its handlers, so
``pygear --help`` loads no analysis, no xarray and no plotting.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import threading
from collections.abc import Iterator

from ..errors import CaseError
from . import accuracy, batch, campbell, condition, modal, run

__all__ = ["build_parser", "main"]

_FAMILIES = (run, modal, campbell, batch, accuracy, condition)
"""Command families, in the order their subcommands are listed."""

_USER_ERRORS = (("pygear.kernel.calls", "KernelError"), ("pygear.analysis.signal", "SignalError"))
"""Errors besides CaseError that mean bad input (exit code 2).  An error can only be an
instance of a class whose module is loaded, so these are looked up, never imported."""


_DASK_COMMANDS = frozenset({"batch", "sweep", "accuracy", "dataset"})
"""Commands that compute on Dask; every other command, run as a process of its own,
runs with Dask hidden (:func:`_dask_hidden`)."""


@contextlib.contextmanager
def _dask_hidden() -> Iterator[None]:
    """Dask reads as not installed while a command that never uses it runs as its own
    process.

    With Dask installed, xarray imports ``dask.array`` the first time it builds a
    variable (to recognise Dask arrays), and ``dask`` and ``distributed`` before every
    NetCDF write (to ask which scheduler is active): 0.6-0.8 s and 31 MB for a run
    that never computes with Dask.  A ``None`` entry in ``sys.modules`` makes
    ``import dask`` raise ImportError, which xarray (and pyFFTW) read as "not
    installed", and xarray keeps that answer for the rest of the process.  So this
    applies only where the process ends with the command (``pygear ...`` or ``python
    -m pygear ...``: :func:`main` without ``argv``) and neither Dask nor xarray is
    loaded yet; a call ``main([...])`` from Python changes nothing.
    """
    loaded = "dask" in sys.modules or "xarray" in sys.modules
    if loaded or threading.current_thread() is not threading.main_thread():
        yield
        return
    sys.modules["dask"] = None
    try:
        yield
    finally:
        if sys.modules.get("dask", 0) is None:
            del sys.modules["dask"]


class _VersionAction(argparse.Action):
    """``--version``: the package and the kernel's BLAS (library, version, CPU core)."""

    def __init__(self, option_strings: list[str], dest: str, **kwargs: object) -> None:
        super().__init__(option_strings, dest, nargs=0, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None) -> None:  # noqa: ANN001
        from .._blas import kernel_blas
        from .._version import __version__

        blas = kernel_blas()
        print(f"pygear {__version__}")
        print(f"kernel BLAS: OpenBLAS {blas['version']}, core {blas['core']} ({blas['library']})")
        parser.exit(0)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every subcommand."""
    parser = argparse.ArgumentParser(prog="pygear", description="The ``pygear`` command line.")
    parser.add_argument(
        "--version",
        action=_VersionAction,
        help="print the package version and the BLAS the kernel runs, then exit",
    )
    commands = parser.add_subparsers(dest="command", required=True)
    for family in _FAMILIES:
        family.add_parsers(commands)
    return parser


def _user_error_types() -> tuple[type[BaseException], ...]:
    types: list[type[BaseException]] = [CaseError]
    for module, name in _USER_ERRORS:
        if module in sys.modules:
            types.append(getattr(sys.modules[module], name))
    return tuple(types)


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit code (2 for bad input)."""
    args = build_parser().parse_args(argv)
    handlers = {}
    for family in _FAMILIES:
        handlers.update(family.HANDLERS)
    handler = handlers[args.command]
    whole_process = argv is None  # the console script or ``python -m pygear``
    hidden = (
        _dask_hidden()
        if whole_process and args.command not in _DASK_COMMANDS
        else contextlib.nullcontext()
    )
    try:
        with hidden:
            return handler(args)
    except KeyboardInterrupt as interrupt:  # Ctrl-C, or SIGTERM while a file is written
        print(f"pygear {args.command}: {interrupt or 'interrupted'}", file=sys.stderr)
        return 128 + getattr(interrupt, "signal_number", 2)  # 130 Ctrl-C, 143 SIGTERM
    except Exception as error:
        if not isinstance(error, _user_error_types()):
            raise
        print(f"pygear {args.command}: error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
