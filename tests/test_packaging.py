"""What an installed pygear holds and does: the install plan's files (cases, py.typed,
the recorded git revision), the licence in the metadata, type hints on the public API,
and, marked slow, a fresh virtual environment with only ``pip install .`` of a clean
clone running ``pygear modal yang2016_planetary`` and ``pygear cases``."""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest
import tomllib

import pygear

ROOT = Path(__file__).resolve().parent.parent
CASES = ROOT / "cases"


def _installed_files() -> set[str]:
    """Every file the editable build's meson install plan puts in a wheel, as
    ``{py_platlib}/...`` paths (install_subdir folders walked as meson walks them)."""
    importlib.import_module("pygear.kernel._kernel")  # an editable install re-plans on import
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    plan_path = ROOT / "build" / tag / "meson-info" / "intro-install_plan.json"
    plan = json.loads(plan_path.read_text())
    files: set[str] = set()
    for section in ("targets", "configure", "data", "python"):
        files.update(entry["destination"] for entry in plan.get(section, {}).values())
    for source, entry in plan.get("install_subdirs", {}).items():
        skipped_dirs = set(entry.get("exclude_dirs", []))
        skipped_files = set(entry.get("exclude_files", []))
        for path in Path(source).rglob("*"):
            relative = path.relative_to(source)
            if not path.is_file() or str(relative) in skipped_files:
                continue
            parents = {str(p) for p in relative.parents} | set(relative.parts[:-1])
            if parents & skipped_dirs:
                continue
            files.add(f"{entry['destination']}/{relative.as_posix()}")
    return files


def test_install_plan_holds_the_cases_py_typed_and_the_git_revision():
    files = _installed_files()
    for case in sorted(p.name for p in CASES.iterdir() if (p / "case.py").is_file()):
        assert f"{{py_platlib}}/pygear/cases/{case}/case.py" in files, case
    assert "{py_platlib}/pygear/py.typed" in files
    assert "{py_platlib}/pygear/_git_revision.py" in files  # written by meson
    assert "{py_platlib}/pygear/_git_revision.py.in" not in files  # its template
    assert "{py_platlib}/pygear/__init__.py" in files
    assert not any("__pycache__" in name for name in files)


def test_metadata_names_the_licence_file():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["license"] == "BSD-3-Clause"
    assert project["license-files"] == ["LICENSE"]
    assert (ROOT / "LICENSE").read_text().startswith("BSD 3-Clause License")
    assert (ROOT / "pygear" / "py.typed").is_file()


def test_cibuildwheel_bundles_the_blas_it_links():
    """The wheel configuration points meson at the scipy-openblas32 library before each
    build and lets auditwheel find that library to copy it into the wheel."""
    settings = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["cibuildwheel"]
    assert "pkg_config_path=/project/.openblas" in settings["config-settings"]["setup-args"]
    before = (ROOT / "scripts" / "cibw_before_build.sh").read_text()
    assert "get_pkg_config()" in before and ".openblas/scipy-openblas.pc" in before
    repair = settings["linux"]["repair-wheel-command"]
    assert "scipy_openblas32" in repair and "auditwheel repair" in repair
    assert "yang2016_planetary" in settings["test-command"]


def _public_callables() -> list[tuple[str, object]]:
    found: list[tuple[str, object]] = []
    for name in pygear.__all__:
        value = getattr(pygear, name)
        if inspect.isfunction(value):
            found.append((name, value))
        if not inspect.isclass(value):
            continue
        for klass in value.__mro__:
            if not klass.__module__.startswith("pygear"):
                continue
            for attribute, member in vars(klass).items():
                if attribute.startswith("_") and attribute != "__init__":
                    continue
                if isinstance(member, (staticmethod, classmethod)):
                    member = member.__func__
                if isinstance(member, property):
                    member = member.fget
                if inspect.isfunction(member):
                    found.append((f"{klass.__name__}.{attribute}", member))
    return found


def test_public_api_is_annotated():
    """Every parameter and return of the public names' functions and methods carries a
    type, and no dataclass field of a public class is a bare ``tuple``."""
    unannotated = []
    for name, function in _public_callables():
        signature = inspect.signature(function)
        for parameter in signature.parameters.values():
            if parameter.name not in ("self", "cls") and parameter.annotation is parameter.empty:
                unannotated.append(f"{name}({parameter.name})")
        if signature.return_annotation is signature.empty and not name.endswith("__init__"):
            unannotated.append(f"{name} -> ?")
    assert len(_public_callables()) > 40  # the walk sees the methods
    for name in pygear.__all__:
        value = getattr(pygear, name)
        if dataclasses.is_dataclass(value):
            for spec in dataclasses.fields(value):
                if spec.type == "tuple" and not spec.name.startswith("_"):
                    unannotated.append(f"{name}.{spec.name}: tuple of what?")
    assert unannotated == []


# --- a fresh environment -----------------------------------------------------------------


def _run(command: list[str], cwd: Path, env: dict) -> subprocess.CompletedProcess:
    result = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True)
    assert result.returncode == 0, f"{command}: {result.stdout[-2000:]}\n{result.stderr[-4000:]}"
    return result


@pytest.mark.slow
def test_pip_install_of_a_clean_clone_runs_the_named_cases(tmp_path):
    """``git clone``, ``python -m venv``, ``pip install .`` (build isolation, as a user
    would), then the installed commands from a folder without cases: the study case is
    found among the installed package data and its Lin-Parker frequency matches Table 2
    of Yang, Jiang & Han (2016).  Times are printed (pytest -s) for the record."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYGEAR_CASES", "PYTHONPATH")}
    started = time.perf_counter()
    clone = tmp_path / "clone"
    _run(["git", "clone", "--quiet", str(ROOT), str(clone)], tmp_path, env)
    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", str(venv)], tmp_path, env)
    python = venv / "bin" / "python"
    _run([str(python), "-m", "pip", "install", "-q", "--upgrade", "pip"], tmp_path, env)
    prepared = time.perf_counter()
    _run([str(python), "-m", "pip", "install", "-q", "."], clone, env)
    installed = time.perf_counter()

    elsewhere = tmp_path / "work"
    elsewhere.mkdir()
    pygear_command = str(venv / "bin" / "pygear")
    files = _run(
        [str(python), "-c", "import importlib.metadata as m; print(*m.files('pygear'), sep='\\n')"],
        elsewhere,
        env,
    ).stdout.split()
    assert "pygear/cases/yang2016_planetary/case.py" in files
    assert "pygear/py.typed" in files and "pygear/_git_revision.py" in files
    assert any(name.endswith(".dist-info/licenses/LICENSE") for name in files)

    modal = _run(
        [pygear_command, "modal", "yang2016_planetary", "--formulation", "lin-parker", "--json"],
        elsewhere,
        env,
    )
    frequencies = json.loads(modal.stdout)["frequencies_hz"]
    assert abs(frequencies[5] / 1477.4 - 1) < 0.005  # Table 2, Lin-Parker rotational 2
    table = _run([pygear_command, "modal", "yang2016_planetary"], elsewhere, env)
    assert "rotational" in table.stdout
    listed = json.loads(_run([pygear_command, "cases", "--json"], elsewhere, env).stdout)
    study = next(e for e in listed["cases"] if e["name"] == "yang2016_planetary")
    assert Path(study["directory"]).is_relative_to(venv)  # the installed package data
    version = _run([pygear_command, "--version"], elsewhere, env).stdout
    head = _run(["git", "rev-parse", "HEAD"], clone, env).stdout.strip()
    assert f"git revision: {head[:12]}" in version  # recorded when the wheel was built
    assert "scipy_openblas32" in version  # the kernel runs the wheel's OpenBLAS
    finished = time.perf_counter()
    print(
        f"\nclone and venv {prepared - started:.0f} s, pip install . "
        f"{installed - prepared:.0f} s, commands {finished - installed:.0f} s"
    )


# --- set-up by task (Makefile, scripts/setup.sh) ----------------------------------------


def _make_dry_run(target: str, tmp_path: Path) -> str:
    """The commands ``make TARGET`` would run for a venv that does not exist yet."""
    result = subprocess.run(
        ["make", "-n", target, f"VENV={tmp_path / 'venv'}"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    )
    return result.stdout


@pytest.mark.parametrize(
    ("target", "levels"),
    [
        ("run", ["runtime"]),
        ("test", ["runtime", "test"]),
        ("lint", ["runtime", "test"]),
        ("docs", ["runtime", "docs"]),
        ("setup", ["runtime", "test", "docs"]),
    ],
)
def test_each_make_target_sets_up_only_its_levels(target, levels, tmp_path):
    """``make run`` installs the runtime alone; the test and docs tools come with the
    targets that use them, each level once (a stamp per level)."""
    planned = re.findall(r"scripts/setup\.sh (\w+)", _make_dry_run(target, tmp_path))
    assert planned == levels


def test_setup_refuses_an_unknown_level(tmp_path):
    """A mistyped level stops before anything is installed."""
    result = subprocess.run(
        ["bash", str(ROOT / "scripts" / "setup.sh"), "everything"],
        env={**os.environ, "VENV": str(tmp_path / "venv")},
        capture_output=True,
        text=True,
    )
    assert result.returncode == 2
    assert "unknown level" in result.stderr
    assert not (tmp_path / "venv").exists()
