"""The package's layering rule (docs/architecture.md), checked on the source with ``ast``.

Layers, lowest first: base (``_version``, ``errors``, ``_blas``, ``io``, ``resources``
and the kernel's foreign-function boundary ``kernel.calls`` / ``kernel._kernel``),
``model``, ``assembly``, ``kernel``, ``analysis``, ``plots``, ``runs``, ``cli``.  A
module imports only from its own layer or lower ones, imports inside functions
included; no two modules import each other, directly or through others; and nothing
below ``plots`` imports Matplotlib or ``pygear.plots``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "pygear"

LAYERS = ("base", "model", "assembly", "kernel", "analysis", "plots", "runs", "cli")
"""Layer names, lowest first; a subpackage's name is its layer."""

BOUNDARY = {"pygear.kernel", "pygear.kernel.calls", "pygear.kernel._kernel"}
"""The kernel's foreign-function boundary, in the base layer: the element matrices and
stiffness laws that assembly needs exist only in Fortran.  ``pygear/kernel/__init__``
imports nothing, so importing these does not load the integrator."""

FACADE = {"pygear": "model", "pygear.__main__": "cli"}
"""The package's ``__init__`` (public names of the model) and ``python -m pygear``."""

NO_FIGURES_BELOW = LAYERS.index("plots")
"""Layers under ``plots`` draw nothing: no Matplotlib, no ``pygear.plots``."""

KNOWN_CYCLES = {("pygear.model.gear_checks", "pygear.model.gear_geometry")}
"""Cycles kept on purpose, each with its reason.  ``GearGeometry.validate`` and
``MeshGeometry.validate`` call the rules of :mod:`pygear.model.gear_checks` (from inside
the methods), and those rules use the geometry's formulas: one concern split in two
files of the same layer, so a geometry and its rules stay one import away."""

ANALYSIS_TOPICS = ("contact", "modes", "signals", "condition", "time", "response", "rating")
"""The subpackages of ``pygear.analysis``, lowest first: a topic imports only from those
before it.  What the teeth give (``contact``) feeds the modes, the modes and the signal
tools feed the sensor path and the transient (``time``, which also checks its accuracy
against spectra), and the steady-state response and the rating build on all of them."""

MAX_LINES = 600
LENGTH_REASON = "longer than 600 lines because"
"""A module may exceed :data:`MAX_LINES` only if its docstring says why in these words."""


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _sources() -> dict[str, Path]:
    return {
        _module_name(p): p for p in sorted(PACKAGE.rglob("*.py")) if "__pycache__" not in p.parts
    }


SOURCES = _sources()


def _layer(module: str) -> int:
    if module in FACADE:
        return LAYERS.index(FACADE[module])
    if module in BOUNDARY:
        return 0
    parts = module.split(".")
    if len(parts) > 1 and parts[1] in LAYERS:
        return LAYERS.index(parts[1])
    return 0  # a top-level private module


def _topic(module: str) -> int:
    """Position of an analysis module's subpackage in :data:`ANALYSIS_TOPICS`."""
    parts = module.split(".")
    if len(parts) < 3 or parts[1] != "analysis" or parts[2] not in ANALYSIS_TOPICS:
        return -1
    return ANALYSIS_TOPICS.index(parts[2])


def _imports(module: str, path: Path) -> set[str]:
    """Every module ``module`` imports, at any depth of its code (functions included).

    ``from X import name`` counts as importing ``X.name`` when that is a module of the
    package (or the compiled kernel), else ``X``.
    """
    is_package = path.name == "__init__.py"
    package = module if is_package else module.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                source = ".".join(base + ([node.module] if node.module else []))
            else:
                source = node.module or ""
            for alias in node.names:
                candidate = f"{source}.{alias.name}"
                known = candidate in SOURCES or candidate == "pygear.kernel._kernel"
                found.add(candidate if known else source)
    return found


GRAPH = {module: _imports(module, path) for module, path in SOURCES.items()}


def _internal(targets: set[str]) -> set[str]:
    return {t for t in targets if t == "pygear" or t.startswith("pygear.")}


@pytest.mark.parametrize("module", sorted(m for m in SOURCES if m.startswith("pygear.kernel.")))
def test_kernel_takes_arrays_not_models(module):
    # the kernel layer takes arrays and small settings objects: no case, no assembled model
    above = sorted(
        t for t in _internal(GRAPH[module]) if t.startswith(("pygear.model", "pygear.assembly"))
    )
    assert not above, f"{module} imports the model or assembly: {above}"


def test_the_walk_sees_the_package():
    # the layers exist and the walk finds imports inside functions: the CLI imports its
    # handlers' modules lazily, so it must be seen importing pygear.analysis
    for layer in LAYERS[1:]:
        assert f"pygear.{layer}" in SOURCES, layer
    lazy = set().union(*(GRAPH[m] for m in SOURCES if m.startswith("pygear.cli")))
    assert any(t.startswith("pygear.analysis.") for t in lazy)


@pytest.mark.parametrize("module", sorted(SOURCES))
def test_no_upward_import(module):
    upward = sorted(
        target for target in _internal(GRAPH[module]) if _layer(target) > _layer(module)
    )
    assert not upward, f"{module} ({LAYERS[_layer(module)]}) imports a higher layer: {upward}"


def test_analysis_is_in_topics():
    # every analysis module lives in a declared topic subpackage
    loose = sorted(
        m
        for m in SOURCES
        if m.startswith("pygear.analysis.") and _topic(m) < 0
    )
    assert not loose, f"analysis modules outside the declared topics: {loose}"


@pytest.mark.parametrize("module", sorted(m for m in SOURCES if _topic(m) >= 0))
def test_no_upward_import_between_analysis_topics(module):
    upward = sorted(
        target for target in _internal(GRAPH[module]) if _topic(target) > _topic(module)
    )
    assert not upward, (
        f"{module} ({ANALYSIS_TOPICS[_topic(module)]}) imports a later analysis topic: "
        f"{upward}"
    )


def test_no_import_cycle():
    graph = {m: {t for t in _internal(GRAPH[m]) if t in SOURCES and t != m} for m in SOURCES}
    # a package's __init__ runs before its submodules; a submodule importing its own
    # package (for a sibling) is not a cycle of code, so that edge is left out
    for module, targets in graph.items():
        targets -= {p for p in targets if module.startswith(p + ".")}
    for first, second in KNOWN_CYCLES:
        graph[second].discard(first)
    state: dict[str, int] = {}  # 1 on the stack, 2 done
    stack: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for target in sorted(graph[node]):
            if state.get(target) == 1:
                cycle = stack[stack.index(target) :] + [target]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if target not in state:
                visit(target)
        stack.pop()
        state[node] = 2

    for module in sorted(graph):
        if module not in state:
            visit(module)


@pytest.mark.parametrize(
    "module", sorted(m for m in SOURCES if _layer(m) < NO_FIGURES_BELOW and m not in FACADE)
)
def test_no_figures_below_plots(module):
    drawn = sorted(
        t
        for t in GRAPH[module]
        if t.split(".")[0] == "matplotlib" or t == "pygear.plots" or t.startswith("pygear.plots.")
    )
    assert not drawn, f"{module} draws figures: {drawn}"


def test_the_rules_catch_what_they_should(tmp_path):
    # the walk on a made-up module: an import inside a function, a relative import of a
    # sibling module, and Matplotlib under a guard
    source = tmp_path / "probe.py"
    source.write_text(
        "def f():\n"
        "    from ...plots import modal\n"
        "    if True:\n"
        "        import matplotlib.pyplot\n"
        "    from . import modal as m\n"
    )
    found = _imports("pygear.analysis.modes.probe", source)
    assert {"pygear.plots.modal", "matplotlib.pyplot", "pygear.analysis.modes.modal"} <= found
    assert _layer("pygear.plots.modal") > _layer("pygear.analysis.modes.probe")
    assert _topic("pygear.analysis.time.transient") > _topic("pygear.analysis.modes.modal")
    assert _layer("pygear.kernel.calls") < _layer("pygear.assembly.matrices")
    assert _layer("pygear.kernel.newmark") > _layer("pygear.assembly.matrices")


def _runtime_names(path: Path) -> set[str]:
    """Names imported from ``pygear.model.case`` outside ``if TYPE_CHECKING:`` blocks."""
    names: set[str] = set()

    def visit(node: ast.AST) -> None:
        if isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING":
            for child in node.orelse:
                visit(child)
            return
        if isinstance(node, ast.ImportFrom) and (node.module or "").endswith("model.case"):
            names.update(alias.name for alias in node.names)
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(ast.parse(path.read_text()))
    return names


@pytest.mark.parametrize(
    "module",
    sorted(m for m in SOURCES if m.startswith(("pygear.assembly", "pygear.kernel"))),
)
def test_assembly_and_kernel_take_resolved_scene_settings(module):
    # a Scene reaches assembly only to be resolved by pygear.model.scene_settings;
    # importing the class at run time would let code read it
    assert "Scene" not in _runtime_names(SOURCES[module])


def test_the_scene_rule_sees_runtime_imports(tmp_path):
    source = tmp_path / "probe.py"
    source.write_text(
        "from typing import TYPE_CHECKING\n"
        "if TYPE_CHECKING:\n"
        "    from ..model.case import Scene\n"
        "def f():\n"
        "    from ..model.case import Case, Scene\n"
    )
    assert _runtime_names(source) == {"Case", "Scene"}


@pytest.mark.parametrize("module", sorted(SOURCES))
def test_module_length(module):
    path = SOURCES[module]
    lines = len(path.read_text().splitlines())
    docstring = ast.get_docstring(ast.parse(path.read_text())) or ""
    assert lines <= MAX_LINES or LENGTH_REASON in " ".join(docstring.split()), (
        f"{path.relative_to(PACKAGE.parent)} has {lines} lines; split it or say in its "
        f"docstring why it is {LENGTH_REASON} ..."
    )
