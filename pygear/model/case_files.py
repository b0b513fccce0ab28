"""Case files: where named cases are looked up, and how ``case.py`` is executed.

A case is named either by its directory (a path) or by its directory's name, looked up
in order in every folder of :func:`case_search_dirs`: the folders of ``$PYGEAR_CASES``,
``./cases``, the cases installed with the package (``pygear/cases`` in a wheel) and the
``cases/`` folder of the source tree an editable install runs from.

A ``case.py`` that fails is reported in one line naming the file and the line of the
case file that failed, with the closest keyword when a dataclass was given one it does
not take (``Gear(mas=1.0)``: did you mean 'mass'?).
"""

from __future__ import annotations

import contextlib
import dataclasses
import difflib
import importlib.util
import inspect
import logging
import os
import re
import signal
import threading
import traceback
from collections.abc import Callable, Iterator
from pathlib import Path
from types import ModuleType

from ..errors import CaseError

__all__ = [
    "CASES_VARIABLE",
    "available_cases",
    "case_search_dirs",
    "find_case_dir",
    "load_case_module",
]

CASES_VARIABLE = "PYGEAR_CASES"
"""Environment variable naming folders of case directories (separated by ``os.pathsep``),
searched before the others."""

_log = logging.getLogger(__name__)

_PACKAGE = Path(__file__).resolve().parents[1]
"""The installed ``pygear`` package folder."""

_UNEXPECTED_KEYWORD = re.compile(
    r"^(?P<callable>[\w.]+)\(\) got an unexpected keyword argument '(?P<keyword>\w+)'$"
)
"""Python's message for a keyword a callable does not take (3.10 and later name the
callable by its qualified name: ``Gear.__init__()``)."""


def case_search_dirs() -> list[Path]:
    """Folders in which a case name is looked up, in the order they are searched.

    ``$PYGEAR_CASES`` (one or more folders), ``./cases``, the cases installed with the
    package, and the source tree's ``cases/`` when pygear runs from a source checkout
    (an editable install).  Folders that do not exist are left out; each folder is
    listed once.
    """
    folders: list[Path] = []
    for entry in os.environ.get(CASES_VARIABLE, "").split(os.pathsep):
        if entry.strip():
            folders.append(Path(entry).expanduser())
    folders.append(Path.cwd() / "cases")
    folders.append(_PACKAGE / "cases")  # package data of an installed wheel
    source_tree = _PACKAGE.parent
    if (source_tree / "meson.build").is_file():  # a source checkout, not site-packages
        folders.append(source_tree / "cases")
    unique: dict[Path, Path] = {}
    for folder in folders:
        if folder.is_dir():
            unique.setdefault(folder.resolve(), folder.resolve())
    return list(unique)


def available_cases() -> list[tuple[str, Path]]:
    """Every case a name can reach: (name, directory), in lookup order.

    A name found in several folders appears once for each; the first one is the case
    the name resolves to (:func:`find_case_dir`), the others are shadowed.
    """
    found: list[tuple[str, Path]] = []
    for folder in case_search_dirs():
        for directory in sorted(folder.iterdir()):
            if (directory / "case.py").is_file() and not directory.name.startswith((".", "_")):
                found.append((directory.name, directory))
    return found


def find_case_dir(reference: str | os.PathLike) -> Path:
    """The directory of a case given as a path or as a name (:func:`case_search_dirs`).

    Raises
    ------
    CaseError
        In one line: for a name, the known cases and the closest of them; for a path,
        the path that holds no ``case.py``.
    """
    path = Path(reference)
    if path.name == "case.py":
        path = path.parent
    if (path / "case.py").is_file():
        return path.resolve()
    is_name = not path.is_absolute() and len(path.parts) == 1
    if is_name:
        for folder in case_search_dirs():
            if (folder / path / "case.py").is_file():
                return (folder / path).resolve()
    known = sorted({name for name, _ in available_cases()})
    text = str(reference)
    message = f"CASE {text!r}: no case.py found"
    if not is_name:
        raise CaseError(f"{message} in {str(path)!r} (give a case directory or a case name)")
    close = difflib.get_close_matches(text, known, n=1, cutoff=0.6)
    hint = f"; did you mean {close[0]!r}?" if close else ""
    listed = ", ".join(known) if known else "none"
    looked = ", ".join(str(folder) for folder in case_search_dirs()) or "no cases folder"
    raise CaseError(
        f"{message}{hint} Known cases: {listed} (looked in {looked}; "
        f"${CASES_VARIABLE} adds folders)"
    )


def load_case_module(
    reference: str | os.PathLike, prefix: str = "pygear_case"
) -> tuple[Path, ModuleType]:
    """Execute ``<case dir>/case.py`` and return (its directory, the module).

    Raises
    ------
    CaseError
        When the file fails, in one line: ``<file>:<line>: <error type>: <message>``
        with the line of the case file that failed (a keyword a dataclass does not take
        adds the closest one it does), or when the file ends the program instead of
        defining a case: ``sys.exit()``, ``raise SystemExit`` or a KeyboardInterrupt
        it raises itself (a Ctrl-C while it runs still interrupts).  Left alone, such
        an exit would make the command end "successfully" without doing anything, and
        a batch skip every other case.  The original error is kept as the cause
        (``pygear --debug`` prints its traceback).
    """
    directory = find_case_dir(reference)
    path = directory / "case.py"
    _log.debug("case %s: executing %s", str(reference), path)
    spec = importlib.util.spec_from_file_location(f"{prefix}_{directory.name}", path)
    module = importlib.util.module_from_spec(spec)
    with _signalled_interrupts() as signalled:
        try:
            spec.loader.exec_module(module)
        except (SystemExit, GeneratorExit, KeyboardInterrupt) as exit_:
            if isinstance(exit_, KeyboardInterrupt) and signalled():
                raise
            what = type(exit_).__name__
            if isinstance(exit_, SystemExit):
                what = f"SystemExit (exit code {exit_.code!r})"
            raise CaseError(
                f"{path}: the case file raised {what} instead of defining "
                "`case = Case(...)`; a case file must not end the program"
            ) from None
        except Exception as error:  # noqa: BLE001 - any failure of the file is bad input
            raise CaseError(case_file_error(path, error, vars(module))) from error
    return directory, module


def case_file_error(path: Path, error: BaseException, namespace: dict | None = None) -> str:
    """One line for an error a case file raised: ``<file>:<line>: <type>: <message>``.

    The line is the case file's own (the innermost frame in ``path``; for a syntax
    error, the line Python points at).  A CaseError keeps its message, which already
    names the parameter; a keyword the called class or function does not take gets the
    closest one it does (looked up by name in ``namespace``, the case file's globals).
    """
    where = _display(path)
    line = _line_in(path, error)
    location = f"{where}:{line}" if line else where
    if isinstance(error, CaseError):
        return f"{location}: {error}"
    if isinstance(error, SyntaxError):
        detail = error.msg
        if error.filename and Path(error.filename).resolve() != path.resolve():
            detail += f" (in {_display(Path(error.filename))}:{error.lineno})"
        return f"{location}: {type(error).__name__}: {detail}"
    message = " ".join(str(error).split())  # one line
    hint = _keyword_hint(error, namespace or {})
    return f"{location}: {type(error).__name__}: {message}{hint}"


def _display(path: Path) -> str:
    """``path`` relative to the working directory when it lies under it."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def _line_in(path: Path, error: BaseException) -> int | None:
    if isinstance(error, SyntaxError):
        if error.filename and Path(error.filename).resolve() == path.resolve():
            return error.lineno
    target = str(path.resolve())
    line = None
    for frame in traceback.extract_tb(error.__traceback__):
        if frame.filename and str(Path(frame.filename).resolve()) == target:
            line = frame.lineno  # the innermost frame of the case file wins
    return line


def _keyword_hint(error: BaseException, namespace: dict) -> str:
    """``; did you mean 'mass'?`` for an unexpected keyword, or the keywords taken."""
    if not isinstance(error, TypeError):
        return ""
    match = _UNEXPECTED_KEYWORD.match(str(error))
    if match is None:
        return ""
    keyword = match.group("keyword")
    accepted = _keywords_of(match.group("callable"), namespace)
    if not accepted:
        return ""
    close = difflib.get_close_matches(keyword, accepted, n=1, cutoff=0.5)
    if close:
        return f"; did you mean {close[0]!r}?"
    return f" (it takes {', '.join(accepted)})"


def _keywords_of(qualified_name: str, namespace: dict) -> list[str]:
    """Keyword names of the callable Python named (``Gear.__init__`` is ``Gear``)."""
    parts = qualified_name.split(".")
    if parts[-1] == "__init__":
        parts = parts[:-1]
    target = _lookup(parts, namespace)
    if target is None:
        return []
    if dataclasses.is_dataclass(target) and isinstance(target, type):
        return [f.name for f in dataclasses.fields(target) if f.init]
    try:
        parameters = inspect.signature(target).parameters.values()
    except (TypeError, ValueError):
        return []
    kinds = (inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY)
    return [p.name for p in parameters if p.kind in kinds and p.name != "self"]


def _lookup(parts: list[str], namespace: dict) -> object | None:
    """The object ``parts`` names in the case file's globals, or in a module the file
    imported (``import pygear`` then ``pygear.Gear(...)``)."""
    if not parts:
        return None
    roots = [namespace.get(parts[0])]
    roots += [
        getattr(value, parts[0], None) for value in namespace.values() if inspect.ismodule(value)
    ]
    for root in roots:
        target = root
        for part in parts[1:]:
            target = getattr(target, part, None)
        if target is not None and callable(target):
            return target
    return None


@contextlib.contextmanager
def _signalled_interrupts() -> Iterator[Callable[[], bool]]:
    """Yield a function telling whether a real SIGINT arrived (main thread only; in
    other threads no signal can arrive, so any KeyboardInterrupt is the file's own)."""
    arrived = []
    if threading.current_thread() is not threading.main_thread():
        yield lambda: False
        return
    previous = signal.getsignal(signal.SIGINT)

    def handler(signum, frame):
        arrived.append(signum)
        if previous is signal.SIG_IGN:
            return
        if callable(previous):
            previous(signum, frame)  # Python's own raises KeyboardInterrupt
            return
        raise KeyboardInterrupt

    try:
        signal.signal(signal.SIGINT, handler)
    except (ValueError, OSError):  # no signal handling here: treat as the file's own
        yield lambda: False
        return
    try:
        yield lambda: bool(arrived)
    finally:
        signal.signal(signal.SIGINT, previous)
