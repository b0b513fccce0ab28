"""Conventions every command shares: the version line, -v/-q through logging, progress
only on a terminal, case-file errors in one line with file and line, case lookup and
listing, one-line errors with exit codes, and --debug for the traceback."""

from __future__ import annotations

import io
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import pygear
from pygear.cli import main
from pygear.cli import modal as modal_cli
from pygear.errors import CaseError
from pygear.model.case_files import find_case_dir
from pygear.runs import progress as progress_module

ROOT = Path(__file__).resolve().parent.parent
CASES = ROOT / "cases"
CASE = str(CASES / "yang2016_planetary")
SENSITIVITY = ["sensitivity", CASE, "--parameter", "planetary.sun_mesh.stiffness"]


def _pygear(*argv: str, cwd: Path | None = None, env: dict | None = None):
    """``python -m pygear ARGV`` as a process of its own, stderr a pipe (not a terminal)."""
    return subprocess.run(
        [sys.executable, "-m", "pygear", *argv],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        timeout=600,
    )


def _lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if line.strip()]


# --- --version ----------------------------------------------------------------------------


def test_version_names_package_git_revision_and_kernel_blas(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == f"pygear {pygear.__version__}"
    assert lines[1].startswith("git revision: ")
    if (ROOT / ".git").exists():  # a checkout: the revision is the commit git reports
        head = subprocess.run(
            ["git", "-C", str(ROOT), "rev-parse", "HEAD"], capture_output=True, text=True
        ).stdout.strip()
        assert head and head[:12] in lines[1]
    assert lines[2].startswith("kernel BLAS: OpenBLAS") and "unknown" not in lines[2]


def test_python_m_pygear_runs_the_command_line():
    result = _pygear("--version")
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f"pygear {pygear.__version__}\n")


# --- -v / -q ------------------------------------------------------------------------------


def test_quiet_silences_the_diagnostics_and_verbose_shows_them(capsys):
    """The modal table is the result (stdout every time); its timing is information
    (stderr with -v only) and the case file's path is debug output (-vv)."""
    assert main(["modal", CASE]) == 0
    default = capsys.readouterr()
    assert "rotational" in default.out and default.err == ""

    assert main(["-v", "modal", CASE]) == 0
    verbose = capsys.readouterr()
    assert verbose.out == default.out
    assert "pygear: assembly and eigensolution:" in verbose.err
    assert "executing" not in verbose.err

    assert main(["modal", CASE, "-vv"]) == 0  # after the command too
    debug = capsys.readouterr().err
    assert "assembly and eigensolution" in debug and "case.py" in debug

    assert main(["modal", CASE, "-q"]) == 0
    quiet = capsys.readouterr()
    assert quiet.out == default.out and quiet.err == ""


def test_quiet_and_verbose_exclude_each_other(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["-q", "-v", "modal", CASE])
    assert stop.value.code == 2
    assert "not allowed with argument" in capsys.readouterr().err


def test_logging_is_left_as_it_was_after_a_command():
    import logging

    logger = logging.getLogger("pygear")
    before = (logger.level, list(logger.handlers), logger.propagate)
    assert main(["-vv", "modal", CASE, "--json"]) == 0
    assert (logger.level, list(logger.handlers), logger.propagate) == before


# --- progress -----------------------------------------------------------------------------


class _Log(io.StringIO):
    """A stream that is not a terminal (a log file)."""

    def isatty(self) -> bool:
        return False


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_in_a_log_is_plain_lines_at_most_every_interval(monkeypatch):
    """160 chunks over 20 simulated seconds (0.125 s each, exact in binary): a line at
    5, 10 and 15 s and the final one at 20 s, each without a carriage return."""
    clock = [0.0]
    monkeypatch.setattr(progress_module.time, "perf_counter", lambda: clock[0])
    log = _Log()
    monkeypatch.setattr(sys, "stderr", log)
    bar = progress_module.ProgressBar("run", log_interval=5.0)
    for done in range(1, 161):
        clock[0] += 0.125
        bar(done, 160)
    lines = log.getvalue().splitlines()
    assert "\r" not in log.getvalue()
    assert len(lines) == 4
    assert lines[0] == "run: 40/160 (25 %), 5.0 s elapsed, 15.0 s left"  # 40 x 0.125 s
    assert lines[1].startswith("run: 80/160 (50 %), 10.0 s elapsed")
    assert lines[-1] == "run: 160/160 done in 20.0 s"


def test_progress_on_a_terminal_redraws_in_place(monkeypatch):
    clock = [0.0]
    monkeypatch.setattr(progress_module.time, "perf_counter", lambda: clock[0])
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    bar = progress_module.ProgressBar("run")
    for done in range(1, 11):
        clock[0] += 0.5
        bar(done, 10)
    text = terminal.getvalue()
    assert text.count("\r") == 10 and text.endswith("10/10 5.0 s elapsed, 0.0 s left\n")


def test_progress_of_a_command_writing_into_a_pipe_has_no_carriage_return(tmp_path):
    values = ["--values", "linspace(1e8,3e8,3)", "--out", str(tmp_path)]
    result = _pygear(*SENSITIVITY, *values)
    assert result.returncode == 0, result.stderr
    assert "\r" not in result.stderr
    assert _lines(result.stderr)[-1].startswith("sensitivity: 3/3 done in ")
    quiet = _pygear(*SENSITIVITY, *values, "-q")
    assert quiet.returncode == 0 and quiet.stderr == ""


# --- case files ---------------------------------------------------------------------------


def _case_file(tmp_path: Path, text: str) -> Path:
    directory = tmp_path / "broken"
    directory.mkdir()
    (directory / "case.py").write_text(text)
    return directory


def test_misspelt_keyword_is_one_line_with_file_line_and_suggestion(tmp_path, capsys):
    directory = _case_file(
        tmp_path, "from pygear import Gear\n\n# the sun\nsun = Gear(mas=1.0, polar_inertia=0.1)\n"
    )
    assert main(["modal", str(directory)]) == 2
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1
    assert f"{directory / 'case.py'}:4: TypeError:" in err[0]
    assert "'mas'" in err[0] and "did you mean 'mass'?" in err[0]


def test_misspelt_keyword_through_the_module_name_gets_the_suggestion(tmp_path):
    directory = _case_file(tmp_path, "import pygear\n\nbearing = pygear.Bearing(radail=1e8)\n")
    with pytest.raises(CaseError, match=r"case\.py:3: .*did you mean 'radial'\?"):
        find_and_load(directory)


def find_and_load(directory: Path):
    from pygear.model.case import load_case

    return load_case(directory)


def test_syntax_error_names_file_and_line(tmp_path, capsys):
    directory = _case_file(tmp_path, "a = 1\nb = 2\nc = (1,\n")
    assert main(["modal", str(directory)]) == 2
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1 and f"{directory / 'case.py'}:3: SyntaxError:" in err[0]


def test_error_raised_inside_pygear_names_the_case_file_line(tmp_path, capsys):
    """An error raised deep in pygear's code points at the case file's line that called
    it, not at pygear's own source."""
    directory = _case_file(
        tmp_path, "from pygear import TorqueLaw\n\nlaw = TorqueLaw.table([0, 1], ['a', 'b'])\n"
    )
    assert main(["modal", str(directory)]) == 2
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1
    assert f"{directory / 'case.py'}:3: ValueError: could not convert string" in err[0]


def test_case_error_of_a_case_file_keeps_its_parameter_and_gains_the_line(tmp_path, capsys):
    text = (CASES / "yang2016_planetary" / "case.py").read_text()
    text = text.replace("Carrier(mass=5.43", "Carrier(mass=-5.43", 1)
    assert "mass=-5.43" in text
    directory = _case_file(tmp_path, text)
    assert main(["modal", str(directory)]) == 2
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1 and "planetary.carrier.mass" in err[0]
    assert re.search(re.escape(f"{directory / 'case.py'}:") + r"\d+: planetary", err[0])


# --- finding and listing cases ----------------------------------------------------------------


def _known_cases() -> list[str]:
    return sorted(p.name for p in CASES.iterdir() if (p / "case.py").is_file())


def test_misspelt_case_name_lists_the_cases_and_the_closest(capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    assert main(["modal", "yang2016_planetry"]) == 2
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1
    assert "did you mean 'yang2016_planetary'?" in err[0]
    for name in _known_cases():
        assert name in err[0]


def test_cases_lists_every_case_with_description_and_scenes(capsys, monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)  # no ./cases: the source tree's are found all the same
    monkeypatch.delenv("PYGEAR_CASES", raising=False)
    assert main(["cases"]) == 0
    out = capsys.readouterr().out
    for name in _known_cases():
        assert name in out
    assert "Planetary study case of Yang, Jiang & Han (2016)" in out and "runup_wide" in out
    assert main(["cases", "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)["cases"]
    study = next(entry for entry in listed if entry["name"] == "yang2016_planetary")
    assert Path(study["directory"]) == CASES / "yang2016_planetary"
    assert "modal" in study["scenes"] and study["error"] is None


def test_pygear_cases_variable_adds_folders_that_come_first(capsys, monkeypatch, tmp_path):
    """$PYGEAR_CASES folders are searched first: a case there is found by name, and one
    with a name the source tree also holds shadows it (and is listed as doing so)."""
    own = tmp_path / "mine"
    shutil.copytree(CASES / "yang2016_planetary", own / "gearbox_a")
    shutil.copytree(CASES / "yang2016_planetary", own / "yang2016_planetary")
    monkeypatch.setenv("PYGEAR_CASES", f"{tmp_path / 'missing'}{os.pathsep}{own}")
    monkeypatch.chdir(tmp_path)
    assert find_case_dir("gearbox_a") == own / "gearbox_a"
    assert find_case_dir("yang2016_planetary") == own / "yang2016_planetary"
    assert main(["cases", "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)["cases"]
    shadowed = [e for e in listed if e["name"] == "yang2016_planetary" and e["shadowed_by"]]
    assert [Path(e["directory"]) for e in shadowed] == [CASES / "yang2016_planetary"]
    assert shadowed[0]["shadowed_by"] == str(own / "yang2016_planetary")


def test_a_path_that_holds_no_case_says_so(tmp_path, capsys):
    assert main(["modal", str(tmp_path / "nowhere")]) == 2
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1 and "no case.py found in" in err[0]


# --- one-line errors and --debug ------------------------------------------------------------


@pytest.mark.parametrize(
    ("parameter", "words"),
    [
        ("planetary", ["'planetary' names the stage", "planetary.sun_mesh.stiffness"]),
        ("planetary.sun_mesh", ["'planetary.sun_mesh' names a Mesh", "stiffness"]),
        ("damping", ["'damping' names a RayleighDamping", "damping.mass_coefficient"]),
    ],
)
def test_sensitivity_of_a_group_path_is_one_line_exit_2(parameter, words, tmp_path, capsys):
    argv = ["sensitivity", CASE, "--parameter", parameter, "--values", "1e8", "2e8"]
    assert main([*argv, "--out", str(tmp_path)]) == 2
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1 and err[0].startswith("pygear sensitivity: error: parameter ")
    for word in words:
        assert word in err[0]
    assert not list(tmp_path.iterdir())  # refused before any work


def test_sensitivity_bug_as_a_whole_process_is_one_line(tmp_path):
    argv = ["sensitivity", CASE, "--parameter", "planetary", "--values", "1e8"]
    result = _pygear(*argv, "--out", str(tmp_path))
    assert result.returncode == 2
    assert len(_lines(result.stderr)) == 1 and "Traceback" not in result.stderr


def test_debug_shows_the_traceback(tmp_path):
    argv = ["sensitivity", CASE, "--parameter", "planetary", "--values", "1e8"]
    result = _pygear("--debug", *argv, "--out", str(tmp_path))
    assert result.returncode == 1  # Python's own exit for an uncaught exception
    assert "Traceback (most recent call last)" in result.stderr
    assert "pygear.errors.CaseError: parameter 'planetary'" in result.stderr
    with pytest.raises(CaseError, match="names the stage"):
        main([*argv, "--out", str(tmp_path), "--debug"])


def test_debug_shows_the_case_file_error_it_wraps(tmp_path):
    directory = _case_file(tmp_path, "from pygear import Gear\nsun = Gear(mas=1.0)\n")
    result = _pygear("modal", str(directory), "--debug")
    assert "Traceback" in result.stderr
    assert "TypeError: Gear.__init__() got an unexpected keyword argument 'mas'" in result.stderr


def test_an_unexpected_error_is_one_line_exit_1(monkeypatch, capsys):
    def broken(args):
        return [][1]  # an IndexError, as a bug would raise

    monkeypatch.setitem(modal_cli.HANDLERS, "modal", broken)
    assert main(["modal", CASE]) == 1
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1
    assert err[0].startswith("pygear modal: internal error: IndexError: list index out of range")
    assert "--debug" in err[0]
    with pytest.raises(IndexError):
        main(["modal", CASE, "--debug"])
