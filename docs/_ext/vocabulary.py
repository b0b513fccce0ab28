"""Sphinx extension: lists of the names a case chooses from, checked against the code.

In a page::

    ```{pygear-choices} pygear.model.case.EFFECTS
    - `time_varying_mesh_stiffness`: the tooth-contact table ...
    - `tooth_separation`: ...
    ```

The directive imports the constant (a tuple of names, or a dict of name to text), shows
its docstring (the string literal after its assignment in the source) and then the
page's explanation of each name, in the constant's order; for a dict each item also shows
the code's own text.  The build fails (a Sphinx warning under ``-W``) when the page
explains a name the code lacks or lacks a name the code has, so a new effect, analysis,
DOF or probe quantity cannot stay undocumented.

``mode-classes`` in place of a constant gives the mode classes that
:func:`pygear.analysis.modes.modal.classify` can return, found by classifying every
combination of present and absent motions.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import itertools
import re

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.application import Sphinx
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

logger = logging.getLogger(__name__)

ITEM = re.compile(r"^- `([^`]+)`\s*:?\s*(.*)$")
ROLE = re.compile(r":([a-z]+):`([^`]+)`")


def mode_classes() -> tuple[str, ...]:
    """Every class :func:`~pygear.analysis.modes.modal.classify` returns, in first-seen order.

    The classifier reads each mode's kinetic-energy shares by role (central member or
    planet), motion (translation, rotation) and plane; a mode per combination of
    present and absent shares (2^8 of them) reaches every branch.
    """
    import numpy as np

    from pygear.analysis.modes.modal import classify

    keys = list(itertools.product(("central", "planet"), ("translation", "rotation"),
                                  ("in-plane", "out-of-plane")))  # fmt: skip
    combos = np.array(list(itertools.product((0.0, 1.0), repeat=len(keys))))[1:]
    table = {key: combos[:, n] for n, key in enumerate(keys)}
    return tuple(dict.fromkeys(classify(table)))


SOURCES = {"mode-classes": mode_classes}
"""Names computed rather than read from a constant."""


def _constant(path: str) -> tuple[object, str]:
    """The value at ``module.NAME`` and its docstring from the module's source."""
    module_name, name = path.rsplit(".", 1)
    module = importlib.import_module(module_name)
    value = getattr(module, name)
    tree = ast.parse(inspect.getsource(module))
    body = tree.body
    doc = ""
    for statement, following in zip(body, body[1:]):
        targets = []
        if isinstance(statement, ast.Assign):
            targets = [t.id for t in statement.targets if isinstance(t, ast.Name)]
        elif isinstance(statement, ast.AnnAssign) and isinstance(statement.target, ast.Name):
            targets = [statement.target.id]
        if (
            name in targets
            and isinstance(following, ast.Expr)
            and isinstance(following.value, ast.Constant)
            and isinstance(following.value.value, str)
        ):
            doc = inspect.cleandoc(following.value.value)
    return value, doc


def _markdown(rst: str) -> str:
    """The few reStructuredText marks of a docstring, as MyST Markdown."""
    text = rst.replace("``", "`")
    return ROLE.sub(lambda m: f"{{{m.group(1)}}}`{m.group(2)}`", text)


def _items(lines: list[str]) -> dict[str, str]:
    """``{name: explanation}`` from a Markdown list whose items start with a code span."""
    items: dict[str, str] = {}
    current = None
    for line in lines:
        match = ITEM.match(line)
        if match:
            current = match.group(1)
            items[current] = match.group(2).strip()
        elif current is not None and line.strip():
            items[current] += " " + line.strip()
    return items


class Choices(SphinxDirective):
    """``{pygear-choices} module.CONSTANT``: the constant's names with the page's text."""

    required_arguments = 1
    has_content = True
    option_spec = {"no-docstring": lambda argument: True}

    def run(self) -> list[nodes.Node]:
        path = self.arguments[0]
        if path in SOURCES:
            value, doc = SOURCES[path](), ""
        else:
            value, doc = _constant(path)
        explained = _items(list(self.content))
        names = list(value)
        if path in SOURCES:  # computed names have no order of their own: the page's
            names = [n for n in explained if n in names] + [n for n in names if n not in explained]
        where = self.get_location()
        for name in names:
            if name not in explained:
                logger.warning("%s: %r has no explanation on this page", path, name,
                               location=where)  # fmt: skip
        for name in explained:
            if name not in names:
                logger.warning("%s: the page explains %r, which the code does not have",
                               path, name, location=where)  # fmt: skip
        lines = []
        if doc and "no-docstring" not in self.options:
            lines += [_markdown(doc), ""]
        for name in names:
            code_text = f" ({_markdown(str(value[name]))})" if isinstance(value, dict) else ""
            lines.append(f"- `{name}`{code_text}: {explained.get(name, '')}")
        container = nodes.container(classes=["pygear-choices"])
        self.state.nested_parse(StringList(lines, where), self.content_offset, container)
        return [container]


def setup(app: Sphinx) -> dict:
    app.add_directive("pygear-choices", Choices)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
