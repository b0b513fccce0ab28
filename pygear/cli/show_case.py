"""``pygear show-case CASE [--scene NAME] [--json]``: the resolved case, every default
and derived value included.

``--json`` prints the document every output file stores as its ``case_json``
attribute (:func:`pygear.model.case_json.case_json`); without it, one line per value,
``path = value``, in the case's own order.
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Callable, Iterator

__all__ = ["HANDLERS", "add_parsers", "flat_lines"]


def add_parsers(commands: argparse._SubParsersAction) -> None:
    """Add the ``show-case`` subcommand."""
    show = commands.add_parser(
        "show-case",
        help="print a case with every default and derived value (as JSON with --json)",
        description="Load CASE (a name or a case directory) and print it resolved: every "
        "parameter with its default, the values the gear geometry fills in and the "
        "properties derived from them.  The JSON is what output files store as case_json.",
    )
    show.add_argument("case", metavar="CASE", help="case directory or case name under cases/")
    show.add_argument(
        "--scene", help="apply this scene's parameter changes first (as `pygear run` does)"
    )
    show.add_argument("--json", action="store_true", help="print the case as JSON")


def flat_lines(value: object, path: str = "") -> Iterator[str]:
    """``path = value`` for every leaf of a JSON document (lists indexed ``[k]``)."""
    if isinstance(value, dict):
        for key, item in value.items():
            yield from flat_lines(item, f"{path}.{key}" if path else str(key))
    elif isinstance(value, list) and any(isinstance(item, (dict, list)) for item in value):
        for index, item in enumerate(value):
            yield from flat_lines(item, f"{path}[{index}]")
    else:
        yield f"{path} = {json.dumps(value)}"


def _show_case(args: argparse.Namespace) -> int:
    from ..model.case import load_case
    from ..model.case_json import case_dict, case_json

    case = load_case(args.case)
    if args.scene is not None:
        case = case.for_scene(case.scene(args.scene))
    if args.json:
        print(case_json(case, indent=1))
        return 0
    for line in flat_lines(case_dict(case)):
        print(line)
    return 0


HANDLERS: dict[str, Callable[[argparse.Namespace], int]] = {"show-case": _show_case}
