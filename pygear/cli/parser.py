"""The ``pygear`` command line: the parser of every subcommand and the dispatch.

Each command family lives in its own module (:mod:`.modal`, :mod:`.run`,
:mod:`.batch`, :mod:`.accuracy`) and imports its work inside its handlers, so
``pygear --help`` loads no analysis, no xarray and no plotting.

Conventions every command shares: results on standard output, diagnostics on standard
error through the ``pygear`` logger (``-v`` info, ``-vv`` debug, ``-q`` errors only),
and any error in one line (exit code 2 for bad input, 1 otherwise) unless ``--debug``
asks for the traceback.
"""

from __future__ import annotations

import argparse
import contextlib
import logging
import os
import sys
import threading
import warnings
from collections.abc import Iterator

from ..errors import CaseError
from . import (
    accuracy,
    batch,
    campbell,
    cases,
    condition,
    contact,
    frf,
    modal,
    rate,
    response,
    run,
    show_case,
)

__all__ = ["build_parser", "main"]

_FAMILIES = (
    run,
    modal,
    campbell,
    frf,
    response,
    batch,
    accuracy,
    condition,
    contact,
    rate,
    cases,
    show_case,
)
"""Command families, in the order their subcommands are listed."""

_USER_ERRORS = (
    ("pygear.kernel.calls", "KernelError"),
    ("pygear.analysis.signals.signal", "SignalError"),
)
"""Errors besides CaseError that mean bad input (exit code 2).  An error can only be an
instance of a class whose module is loaded, so these are looked up, never imported."""

_RUN_ERRORS = (("pygear.runs.fault_dataset", "DatasetError"),)
"""Errors of sound input whose work failed (every record of a dataset): a one-line
error with exit code 1, not an internal error.  Looked up like :data:`_USER_ERRORS`."""


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
    """``--version``: the package, the git revision it was built from and the kernel's
    BLAS (library, version, CPU core)."""

    def __init__(self, option_strings: list[str], dest: str, **kwargs: object) -> None:
        super().__init__(option_strings, dest, nargs=0, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None) -> None:  # noqa: ANN001
        from .._blas import kernel_blas
        from .._version import __version__, git_revision

        blas = kernel_blas()
        print(f"pygear {__version__}")
        print(f"git revision: {git_revision() or 'unknown (not built from a git checkout)'}")
        print(f"kernel BLAS: OpenBLAS {blas['version']}, core {blas['core']} ({blas['library']})")
        parser.exit(0)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every subcommand."""
    parser = argparse.ArgumentParser(
        prog="pygear",
        description="Gearbox and drivetrain dynamics: modes, transients, signals and "
        "condition monitoring.  Results go to stdout, diagnostics to stderr; exit code 0 "
        "on success, 2 for bad input, 1 for other errors.",
    )
    parser.add_argument(
        "--version",
        action=_VersionAction,
        help="print the package version, its git revision and the BLAS the kernel runs",
    )
    _add_common_options(parser, top_level=True)
    commands = parser.add_subparsers(dest="command", required=True)
    for family in _FAMILIES:
        family.add_parsers(commands)
    for command in commands.choices.values():
        _add_common_options(command, top_level=False)
    return parser


def _add_common_options(parser: argparse.ArgumentParser, top_level: bool) -> None:
    """``-v``, ``-q`` and ``--debug``, taken before the command or after it.

    A subcommand's defaults are suppressed so that they never overwrite what was
    given before the command (argparse copies a subparser's defaults over it).
    """
    default = {} if top_level else {"default": argparse.SUPPRESS}
    group = parser.add_argument_group("output")
    loudness = group.add_mutually_exclusive_group()
    loudness.add_argument(
        "-v",
        "--verbose",
        action="count",
        **({"default": 0} if top_level else default),
        help="diagnostics on stderr: -v what is done and how long it takes, -vv debug",
    )
    loudness.add_argument(
        "-q",
        "--quiet",
        action="store_true",
        **default,
        help="errors only on stderr (no progress, warnings or diagnostics)",
    )
    group.add_argument(
        "--debug",
        action="store_true",
        **default,
        help="print the traceback of an error instead of its one-line message",
    )


def log_level(verbose: int, quiet: bool) -> int:
    """The ``pygear`` logger's level: errors only with ``-q``, warnings by default,
    info with ``-v``, debug with ``-vv``."""
    if quiet:
        return logging.ERROR
    return (logging.WARNING, logging.INFO)[verbose] if verbose < 2 else logging.DEBUG


class _StderrHandler(logging.StreamHandler):
    """Writes to whatever ``sys.stderr`` is when a record is emitted (a test or a
    notebook may replace it between commands)."""

    def __init__(self) -> None:
        super().__init__()

    @property
    def stream(self):  # noqa: ANN201
        return sys.stderr

    @stream.setter
    def stream(self, value: object) -> None:  # StreamHandler.__init__ sets it
        pass


class _Formatter(logging.Formatter):
    """``pygear: message`` for information, ``pygear: warning: message`` above it, and
    the module's name in debug records."""

    def format(self, record: logging.LogRecord) -> str:
        message = record.getMessage()
        if record.levelno >= logging.WARNING:
            return f"pygear: {record.levelname.lower()}: {message}"
        if record.levelno < logging.INFO:
            return f"pygear: debug: [{record.name}] {message}"
        return f"pygear: {message}"


@contextlib.contextmanager
def _logging(args: argparse.Namespace, whole_process: bool) -> Iterator[None]:
    """The ``pygear`` logger at the level ``-v``/``-q`` ask for, on stderr, while a
    command runs; the logger's previous state is restored afterwards.  When the command
    is the whole process, Python warnings are logged too (``-q`` hides them)."""
    logger = logging.getLogger("pygear")
    saved = (logger.level, list(logger.handlers), logger.propagate)
    handler = _StderrHandler()
    handler.setFormatter(_Formatter())
    logger.handlers = [handler]
    logger.setLevel(log_level(args.verbose, args.quiet))
    logger.propagate = False
    shown = warnings.showwarning
    if whole_process:

        def show(message, category, filename, lineno, file=None, line=None):  # noqa: ANN001
            logger.warning(f"{category.__name__}: {message}")

        warnings.showwarning = show
    try:
        yield
    finally:
        warnings.showwarning = shown
        logger.setLevel(saved[0])
        logger.handlers = saved[1]
        logger.propagate = saved[2]


def _loaded_types(names: tuple[tuple[str, str], ...]) -> tuple[type[BaseException], ...]:
    return tuple(
        getattr(sys.modules[module], name) for module, name in names if module in sys.modules
    )


def _user_error_types() -> tuple[type[BaseException], ...]:
    types: list[type[BaseException]] = [CaseError]
    for module, name in _USER_ERRORS:
        if module in sys.modules:
            types.append(getattr(sys.modules[module], name))
    return tuple(types)


CLOSED_PIPE = 141
"""Exit code when stdout's reader closed the pipe: 128 + SIGPIPE, what a command killed by
the signal gives, so ``set -o pipefail`` still tells it from a success."""


def _closed_pipe(whole_process: bool) -> int:
    """End quietly after stdout's pipe closed: nothing on stderr, and stdout pointed at
    the null device so that the interpreter's own flush at exit finds no pipe to fail on
    (a call ``main([...])`` from Python leaves its streams alone)."""
    if whole_process:
        with contextlib.suppress(OSError, ValueError):
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, sys.stdout.fileno())
            os.close(null)
    return CLOSED_PIPE


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
        with hidden, _logging(args, whole_process):
            code = handler(args)
            sys.stdout.flush()  # a closed pipe shows here, not at the interpreter's exit
            return code
    except BrokenPipeError:  # the reader of stdout went away (`pygear modal CASE | head -1`)
        return _closed_pipe(whole_process)
    except KeyboardInterrupt as interrupt:  # Ctrl-C, or SIGTERM while a file is written
        print(f"pygear {args.command}: {str(interrupt) or 'interrupted'}", file=sys.stderr)
        return 128 + getattr(interrupt, "signal_number", 2)  # 130 Ctrl-C, 143 SIGTERM
    except Exception as error:
        if args.debug:
            raise
        message = " ".join(str(error).split())  # one line
        if isinstance(error, _user_error_types()):
            print(f"pygear {args.command}: error: {message}", file=sys.stderr)
            return 2
        if isinstance(error, _loaded_types(_RUN_ERRORS)):
            print(f"pygear {args.command}: error: {message}", file=sys.stderr)
            return 1
        if isinstance(error, OSError):  # a file or folder the system refused
            what = type(error).__name__
            print(f"pygear {args.command}: error: {what}: {message}", file=sys.stderr)
            return 1
        print(
            f"pygear {args.command}: internal error: {type(error).__name__}: {message} "
            "(pygear --debug prints the traceback; please report it)",
            file=sys.stderr,
        )
        return 1


if __name__ == "__main__":
    sys.exit(main())
