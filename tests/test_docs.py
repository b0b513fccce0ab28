"""The project cites its own documentation, and what it cites exists.

Code, tests, cases, Fortran comments and the docs cite ``docs/*.md`` pages (and
sections of the model page) or published papers, never design notes kept outside the
repository.  Three checks on the source tree as text:

- no file names one of the outside notes (their names are built below, so this file does
  not name them itself);
- every ``docs/<page>.md`` path cited in the package, the Fortran kernel, the cases, the
  tests or the README, and every relative ``.md`` link between the docs pages, exists;
- every section of the model page cited as ``§N`` or ``section N`` after its path is a
  numbered heading of that page.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
MODEL_PAGE = DOCS / "model.md"

SOURCE_DIRS = ("pygear", "fortran", "cases", "tests", "docs")
"""Directories whose every file is read (README.md is read too)."""

SKIPPED_PARTS = {"__pycache__", ".pytest_cache", ".ruff_cache", "_build", "generated"}
"""Generated directories: compiled modules fold split string constants back together, and
the documentation site's build (``docs/_build``, ``docs/generated``) copies every page."""

OUTSIDE_NOTES = tuple(stem + "." + "md" for stem in ("PHYSICS", "VALIDATION", "ARCHITECTURE"))
"""Design notes that live outside the repository; upper case, unlike ``docs/architecture.md``."""

DOCS_PATH = re.compile(r"docs/([A-Za-z0-9_\-/]+\.md)")
RELATIVE_LINK = re.compile(r"\]\(([A-Za-z0-9_\-/.]+\.md)(?:#[^)]*)?\)")
MODEL_CITATION = re.compile(r"docs/model\.md([^)\n]{0,60})")
SECTION_MARK = re.compile(r"§\s*(\d+(?:\.\d+)?)")
SECTION_WORDS = re.compile(r"sections?\s+(\d+(?:\.\d+)?(?:(?:,\s*|\s+and\s+)\d+(?:\.\d+)?)*)")
HEADING = re.compile(r"^#{2,3}\s+(\d+(?:\.\d+)?)\.?\s", re.MULTILINE)


def _files() -> list[Path]:
    files = [ROOT / "README.md"]
    for name in SOURCE_DIRS:
        files += sorted(
            path
            for path in (ROOT / name).rglob("*")
            if path.is_file() and not SKIPPED_PARTS.intersection(path.parts)
        )
    return files


FILES = _files()


def _text(path: Path) -> str:
    return path.read_bytes().decode("utf-8", errors="replace")


def _text_files() -> list[Path]:
    return [p for p in FILES if b"\0" not in p.read_bytes()[:4096]]


def test_the_tree_is_read():
    """The walk finds the files it is meant to check (a wrong root would pass vacuously)."""
    names = {path.relative_to(ROOT).as_posix() for path in FILES}
    assert {"README.md", "pygear/model/case.py", "fortran/elements.f90"} <= names
    assert "docs/model.md" in names


def _outside_note_citations(paths: list[Path]) -> list[str]:
    return [
        f"{path.name}: {note}"
        for path in paths
        for note in OUTSIDE_NOTES
        if note.encode() in path.read_bytes()
    ]


def test_no_file_names_the_outside_design_notes():
    """No file of the project names a design note that users never see."""
    found = _outside_note_citations(FILES)
    assert not found, "cite docs/*.md or the published paper instead:\n" + "\n".join(found)


def test_the_search_finds_an_outside_note_and_spares_the_docs_page(tmp_path):
    """A comment in the old style is caught; the project's own lower-case page is not."""
    old = tmp_path / "old.f90"
    old.write_text("!> Mesh of a gear (" + OUTSIDE_NOTES[0] + " 3.4)\n")
    own = tmp_path / "own.py"
    own.write_text('"""Layers (docs/architecture.md)."""\n')
    assert _outside_note_citations([old, own]) == [f"old.f90: {OUTSIDE_NOTES[0]}"]


def _missing_pages(paths: list[Path], docs: Path) -> list[str]:
    """Cited docs pages (and, for pages inside ``docs``, linked pages) that do not exist."""
    missing = []
    for path in paths:
        text = _text(path)
        for page in DOCS_PATH.findall(text):
            if not (docs / page).is_file():
                missing.append(f"{path.name}: docs/{page}")
        if path.parent == docs and path.suffix == ".md":
            for link in RELATIVE_LINK.findall(text):
                if not (docs / link).is_file():
                    missing.append(f"{path.name}: link to {link}")
    return sorted(set(missing))


def test_cited_docs_pages_exist():
    """Every docs/<page>.md a file cites, and every .md link between docs pages, exists."""
    missing = _missing_pages(_text_files(), DOCS)
    assert not missing, "cited pages that do not exist:\n" + "\n".join(missing)


def test_a_missing_page_is_found(tmp_path):
    """A citation of a page that is not there, in code or as a link between pages, fails."""
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "model.md").write_text("See [stability](stability.md) and [model](model.md#x).\n")
    code = tmp_path / "case.py"
    absent = "docs/" + "laws.md"  # split, so that this file does not cite it
    code.write_text(f"# damping (docs/model.md §3.7), laws ({absent})\n")
    assert _missing_pages([code, docs / "model.md"], docs) == [
        f"case.py: {absent}",
        "model.md: link to stability.md",
    ]


def _model_sections() -> set[str]:
    return set(HEADING.findall(MODEL_PAGE.read_text()))


def test_model_page_has_numbered_sections():
    """The model page numbers its sections (## N. and ### N.M) so code can cite them."""
    sections = _model_sections()
    assert {"1", "3.1", "5.2", "6.3", "10"} <= sections


@pytest.mark.parametrize(
    ("citation", "numbers"),
    [
        ("(docs/model.md §6.3, §3.7)", ["6.3", "3.7"]),
        ("(docs/model.md sections 5 and 6).", ["5", "6"]),
        ("docs/model.md section 3.4)", ["3.4"]),
    ],
)
def test_section_citations_are_read(citation, numbers):
    """The citation forms used in the tree are parsed into their section numbers."""
    assert _cited_sections(citation) == numbers


def _cited_sections(text: str) -> list[str]:
    cited = []
    for tail in MODEL_CITATION.findall(text):
        cited += SECTION_MARK.findall(tail)
        for group in SECTION_WORDS.findall(tail):
            cited += re.findall(r"\d+(?:\.\d+)?", group)
    return cited


def test_a_section_the_page_lacks_is_found():
    """A cited section number that is no heading of the model page is reported."""
    sections = _model_sections()
    absent = "5." + "99"  # split, so that this file does not cite it
    cited = _cited_sections(f"(docs/model.md §5.2, §{absent})")
    assert [n for n in cited if n not in sections] == [absent]


def test_cited_model_sections_exist():
    """Every section of docs/model.md cited after its path is a heading of that page."""
    sections = _model_sections()
    wrong = [
        f"{path.relative_to(ROOT)}: §{number}"
        for path in _text_files()
        for number in _cited_sections(_text(path))
        if number not in sections
    ]
    assert not wrong, "sections not in docs/model.md:\n" + "\n".join(wrong)


# --- the README as a front page ----------------------------------------------------------

README = ROOT / "README.md"
COMMAND_PAGES = (README, DOCS / "cli.md", DOCS / "results.md", DOCS / "performance.md")
"""Where users copy commands from: the README and the pages that took its commands."""

FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.MULTILINE | re.DOTALL)
LINK = re.compile(r"\]\(([^)\s#]+)(?:#([^)\s]*))?\)")
INLINE_CODE = re.compile(r"`([^`\n]+)`")


def _command_lines(text: str) -> list[str]:
    """Shell lines of the ``bash`` blocks (continuations joined, comments dropped) and
    inline code spans that start with ``make`` or ``.venv/bin/``."""
    lines = []
    for language, body in FENCE.findall(text):
        if language == "bash":
            lines += body.replace("\\\n", " ").splitlines()
    lines += INLINE_CODE.findall(text)
    commands = []
    for line in lines:
        command = re.split(r"\s+#", line)[0].strip()
        if command.startswith(("make ", ".venv/bin/")):
            commands.append(command)
    return commands


def test_readme_opens_with_the_two_commands():
    """The first code block is ``make run`` then ``make test``, before any other."""
    language, body = FENCE.findall(README.read_text())[0]
    assert language == "bash"
    assert _command_lines(f"```bash\n{body}```\n")[:2] == ["make run", "make test"]


def test_readme_keeps_its_front_page_sections():
    """What the front page promises: a quick start, an example, the docs, the layout of the
    tree (drawn by hand) and the licence."""
    text = README.read_text()
    headings = re.findall(r"^## (.+)$", text, re.MULTILINE)
    assert headings[0] == "Quick start"
    assert {"Documentation", "Layout", "Licence"} <= set(headings)
    assert "```python" in text
    assert "](LICENSE)" in text and "BSD 3-Clause" in text


def _anchors(page: Path) -> set[str]:
    """The heading anchors MyST makes for a page (``myst_heading_anchors = 3``)."""
    anchors = set()
    for heading in re.findall(r"^#{1,3} (.+)$", page.read_text(), re.MULTILINE):
        slug = re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")
        anchors.add(slug)
    return anchors


def test_readme_links_resolve():
    """Every relative link of the README names a file of the tree, and a link into a docs
    page with ``#anchor`` names one of that page's headings."""
    broken = []
    for target, anchor in LINK.findall(README.read_text()):
        if re.match(r"[a-z]+:", target):
            continue  # a web address
        path = ROOT / target
        if not path.exists():
            broken.append(target)
        elif anchor and path.suffix == ".md" and anchor not in _anchors(path):
            broken.append(f"{target}#{anchor}")
    assert not broken, "README links to nothing:\n" + "\n".join(broken)


def test_readme_and_command_pages_name_commands_that_exist():
    """Every ``make`` target exists in the Makefile, every ``.venv/bin/pygear`` line is
    accepted by the command's parser, and every script run by ``.venv/bin/python`` exists."""
    import shlex

    from pygear.cli.parser import build_parser

    targets = set(re.findall(r"^([a-z][\w-]*):", (ROOT / "Makefile").read_text(), re.MULTILINE))
    parser = build_parser()
    wrong, seen = [], 0
    for page in COMMAND_PAGES:
        if not page.is_file():
            continue
        for command in _command_lines(page.read_text()):
            words = shlex.split(command)
            seen += 1
            if words[0] == "make":
                wrong += [f"{page.name}: {command}"] * (words[1] not in targets)
            elif words[0] == ".venv/bin/pygear":
                try:
                    parser.parse_args(words[1:])
                except SystemExit:
                    wrong.append(f"{page.name}: {command}")
            elif words[0] == ".venv/bin/python" and words[1].endswith(".py"):
                wrong += [f"{page.name}: {command}"] * (not (ROOT / words[1]).is_file())
    assert seen > 20  # the pages hold the commands they are meant to
    assert not wrong, "commands that would fail:\n" + "\n".join(wrong)
