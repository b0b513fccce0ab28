"""Sphinx configuration of pygear's documentation site (``make docs``).

The pages are the Markdown files of this folder (MyST), the API reference is generated
from the numpydoc docstrings (autosummary), the case-parameter reference is written at
build time from the model's dataclasses (``_ext/parameter_reference.py``), and the
tutorial notebooks under ``tutorials/`` are executed on every build (myst-nb), so a
notebook that no longer runs fails the build.
"""

from __future__ import annotations

import os
import re
import sys
import types
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))

import pygear  # noqa: E402

# ``python -m pygear`` runs the command line when its __main__ modules are imported; the
# API reference imports every module of the package, so these two are left out
for _name in ("pygear.__main__", "pygear.cli.__main__"):
    sys.modules.setdefault(_name, types.ModuleType(_name))

project = "pygear"
author = "the pygear authors"
copyright = "the pygear authors"  # noqa: A001
release = pygear.__version__
version = release

extensions = [
    "myst_nb",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "parameter_reference",
    "vocabulary",
]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "_templates",
    "tutorials/*/case.py",
    "**.ipynb_checkpoints",
    "accuracy/**/*.txt",
]
templates_path = ["_templates"]

# Markdown: the pages use $...$ and $$...$$ for equations, and link to sections by their
# heading text (model.md#3-elements)
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
myst_dmath_double_inline = True

# notebooks: executed on every build, and any error in a cell fails it. Their kernel is
# the interpreter that runs the build: a kernel spec that names "python" finds this one
os.environ["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
nb_execution_mode = "force"
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_execution_timeout = 300
nb_merge_streams = True

# API reference: autosummary writes a page per module, numpydoc renders the sections
autosummary_generate = True
autosummary_imported_members = False
autodoc_typehints = "none"
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

html_theme = "alabaster"
html_title = f"pygear {release}"
html_static_path: list[str] = []
html_theme_options = {
    "description": "Gearbox dynamics for wind-turbine drivetrains",
    "fixed_sidebar": True,
    "page_width": "1180px",
    "sidebar_width": "250px",
}


LITERAL = re.compile(r"(``.+?``|`[^`]*`)")
"""Literal text and interpreted text (roles) inside a docstring line."""


def escape_bars(app, what, name, obj, options, lines: list[str]) -> None:
    """Docstrings write absolute values as ``|x|``, which reStructuredText reads as a
    substitution (or, at the start of a line, a line block): escape every bar outside
    literal and interpreted text."""
    for n, line in enumerate(lines):
        if "|" in line:
            parts = LITERAL.split(line)
            lines[n] = "".join(p if k % 2 else p.replace("|", r"\|") for k, p in enumerate(parts))


RELATIVE_ROLE = re.compile(r":(mod|func|class|data|meth|attr|exc):`\.([A-Za-z_][\w.]*)`")
"""A cross-reference relative to the docstring's package, as in a relative import."""


def absolute_references(app, what, name, obj, options, lines: list[str]) -> None:
    """Make ``:mod:`.signal``` absolute (``pygear.analysis.signals.signal`` in the analysis
    package): Sphinx takes a leading dot as "any name ending so", and pygear has a
    ``signal`` module in more than one package."""
    module = name if what == "module" else getattr(obj, "__module__", None) or name
    module_object = sys.modules.get(module)
    package = module if hasattr(module_object, "__path__") else module.rpartition(".")[0]
    for n, line in enumerate(lines):
        if ":`." in line:
            lines[n] = RELATIVE_ROLE.sub(lambda m: f":{m.group(1)}:`~{package}.{m.group(2)}`", line)


def _share_numpydoc_template() -> None:
    """numpydoc compiles its docstring template anew for every object it renders (a
    fresh Jinja environment each time), a sixth of this site's build: keep the first."""
    from numpydoc import docscrape_sphinx

    base = getattr(docscrape_sphinx, "SandboxedEnvironment", None)
    if base is None:
        return

    class SharedTemplates(base):
        compiled: dict = {}

        def get_template(self, name, *args, **kwargs):
            if name not in self.compiled:
                self.compiled[name] = super().get_template(name, *args, **kwargs)
            return self.compiled[name]

    docscrape_sphinx.SandboxedEnvironment = SharedTemplates


def setup(app) -> None:
    _share_numpydoc_template()
    app.connect("autodoc-process-docstring", escape_bars, priority=600)
    app.connect("autodoc-process-docstring", absolute_references, priority=600)
