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
