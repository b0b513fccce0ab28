"""``pygear cases``: the cases a name can reach, with their descriptions and scenes.

Cases are listed folder by folder in the order a name is looked up
(:func:`pygear.model.case_files.case_search_dirs`); a case whose name an earlier folder
already holds is marked as shadowed.  Each case file is executed to read its
description and scenes; one that fails is listed with its one-line error.
"""

from __future__ import annotations

import argparse
import textwrap
from collections.abc import Callable
from pathlib import Path

__all__ = ["HANDLERS", "add_parsers", "case_listing"]


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``cases`` subcommand."""
    cases = commands.add_parser(
        "cases",
        help="list the cases a name can reach (name, description, scenes)",
        description="Cases are looked up, in order, in $PYGEAR_CASES (folders separated "
        "by ':'), ./cases, the cases installed with pygear and the source tree's cases/; "
        "a case directory can always be given as a path instead of a name.",
    )
    cases.add_argument("--json", action="store_true", help="print the list as JSON")


def case_listing() -> list[dict]:
    """One entry per case directory a name can reach, in lookup order.

    Returns
    -------
    list of dict
        ``name``, ``directory``, ``description``, ``scenes`` (names), ``shadowed_by``
        (the directory the name resolves to when it is another one, else None) and
        ``error`` (the case file's one-line error, else None).
    """
    from ..errors import CaseError
    from ..model.case import load_case
    from ..model.case_files import available_cases

    entries: list[dict] = []
    first: dict[str, Path] = {}
    for name, directory in available_cases():
        entry: dict = {
            "name": name,
            "directory": str(directory),
            "description": "",
            "scenes": [],
            "shadowed_by": None,
            "error": None,
        }
        if name in first:
            entry["shadowed_by"] = str(first[name])
        first.setdefault(name, directory)
        try:
            case = load_case(directory)
        except CaseError as error:
            entry["error"] = str(error)
        else:
            entry["description"] = case.description
            entry["scenes"] = [scene.name for scene in case.scenes]
        entries.append(entry)
    return entries


def _cases(args: argparse.Namespace) -> int:
    from ..model.case_files import CASES_VARIABLE, case_search_dirs
    from ..runs.json_output import json_text

    entries = case_listing()
    if args.json:
        folders = [str(folder) for folder in case_search_dirs()]
        print(json_text({"search_path": folders, "cases": entries}))
        return 0
    if not entries:
        print(f"no cases found; give a case directory or set ${CASES_VARIABLE}")
        return 0
    width = max(len(entry["name"]) for entry in entries) + 2
    folder = None
    for entry in entries:
        here = str(Path(entry["directory"]).parent)
        if here != folder:
            folder = here
            print(f"{folder}:")
        lines = [entry["description"] or "(no description)"]
        if entry["error"]:
            lines = [f"error: {entry['error']}"]
        elif entry["scenes"]:
            lines += textwrap.wrap("scenes: " + ", ".join(entry["scenes"]), 96 - width)
        if entry["shadowed_by"]:
            lines.append(f"(shadowed: the name resolves to {entry['shadowed_by']})")
        print(f"  {entry['name']:<{width}}{lines[0]}")
        for line in lines[1:]:
            print(f"  {'':<{width}}{line}")
    return 0


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {"cases": _cases}
"""Handlers of the commands :func:`add_parsers` adds; each returns the exit code."""
