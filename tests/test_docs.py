"""The README and the documentation site say what vwg does: every ```console block is run and its output
compared (wall-clock times blanked), every ```python block is run and each `print(...)  # expected` checked.

A page's console commands run in order in one folder (a later command sees an earlier one's files), with
`examples/` linked into it; its python blocks then run there in order, in one namespace. In a console
block's expected output a line `...` stands for any number of lines."""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

BIN = Path(sys.executable).parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def page_name(page: Path) -> str:
    return page.relative_to(ROOT).as_posix()


def fenced(text: str, language: str) -> list[tuple[int, str]]:
    """(line number, body) of each block fenced as ```language, at any indentation (admonitions, lists)."""
    found = []
    for m in re.finditer(rf"^([ \t]*)```{language}[ \t]*\n(.*?)^\1```[ \t]*$", text, flags=re.S | re.M):
        indent = m.group(1)
        body = "".join(line[len(indent):] if line.startswith(indent) else line
                       for line in m.group(2).splitlines(keepends=True))
        found.append((text.count("\n", 0, m.start()) + 1, body))
    return found


def sessions(page: Path) -> list[tuple[int, str, list[str]]]:
    """(line, command, expected output lines) for every `$ command` of a page's console blocks."""
    out: list[tuple[int, str, list[str]]] = []
    for start, body in fenced(page.read_text(encoding="utf-8"), "console"):
        for offset, line in enumerate(body.splitlines()):
            if line.startswith("$ "):
                out.append((start + 1 + offset, line[2:], []))
            elif not out or out[-1][0] < start:
                raise AssertionError(f"{page_name(page)}:{start + 1 + offset}: console output before any `$ command`")
            else:
                out[-1][2].append(line)
    return out


def normal(text: str) -> str:
    """Output with the wall-clock parts (which differ between runs and machines) blanked."""
    text = re.sub(r"[\d.]+ s wall", "<t> s wall", text)
    text = re.sub(r"\(\d+\.\d+ s\)", "(<t> s)", text)
    return re.sub(r"(wall time\s+).*", r"\1<t>", text)


def matches(got: list[str], want: list[str]) -> bool:
    """Line by line; a wanted line `...` matches any number of lines."""
    if not want:
        return not got
    if want[0] == "...":
        return any(matches(got[i:], want[1:]) for i in range(len(got) + 1))
    return bool(got) and got[0] == want[0] and matches(got[1:], want[1:])


def folder_for(page: Path, factory: pytest.TempPathFactory) -> Path:
    where = factory.getbasetemp() / ("docs-" + page_name(page).replace("/", "-").removesuffix(".md"))
    where.mkdir(exist_ok=True)
    if not (where / "examples").exists():
        (where / "examples").symlink_to(ROOT / "examples")
    return where


CONSOLE = [(page, line, command, expected) for page in PAGES for line, command, expected in sessions(page)]
PYTHON = [page for page in PAGES if fenced(page.read_text(encoding="utf-8"), "python")]


def test_the_docs_have_examples_to_check():
    assert len(CONSOLE) >= 10
    assert len(PYTHON) >= 5
    assert {page_name(p) for p, *_ in CONSOLE} >= {"README.md"}
    assert "README.md" in {page_name(p) for p in PYTHON}


def test_the_wildcard_line_matches_any_number_of_lines():
    assert matches(["a", "b", "c"], ["a", "...", "c"])
    assert matches(["a", "c"], ["a", "...", "c"])
    assert not matches(["a", "b"], ["a", "...", "c"])
    assert not matches(["a", "b"], ["a"])


@pytest.mark.slow
@pytest.mark.parametrize("page, line, command, expected", CONSOLE,
                         ids=[f"{page_name(p)}:{n} {c}" for p, n, c, _ in CONSOLE])
def test_console_examples_print_what_the_docs_show(page, line, command, expected, tmp_path_factory):
    where = folder_for(page, tmp_path_factory)
    env = {**os.environ, "PATH": f"{BIN}{os.pathsep}{os.environ['PATH']}"}
    argv = shlex.split(command)
    if argv[0] == "python":
        argv[0] = sys.executable
    done = subprocess.run(argv, cwd=where, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"{page_name(page)}:{line}: `{command}` exited {done.returncode}\n{done.stderr}"
    got = normal(done.stdout).splitlines()
    want = normal("\n".join(expected)).splitlines()
    assert matches(got, want), f"{page_name(page)}:{line}: `{command}` printed\n{done.stdout}"


def expected_prints(code: str) -> list[str]:
    return [m.group(1).strip() for m in re.finditer(r"^\s*print\(.*\)\s*#\s*(.*)$", code, flags=re.M)]


def same_line(got: str, want: str) -> bool:
    if want.endswith("...]"):  # an elided list: the shown items must start it
        return got.startswith(want[: -len("...]")].rstrip(", "))
    return got == want


@pytest.mark.slow
@pytest.mark.parametrize("page", PYTHON, ids=[page_name(p) for p in PYTHON])
def test_python_examples_run_and_print_what_their_comments_say(page, tmp_path_factory, monkeypatch):
    monkeypatch.chdir(folder_for(page, tmp_path_factory))
    namespace: dict[str, object] = {"__name__": "docs_example"}
    for line, code in fenced(page.read_text(encoding="utf-8"), "python"):
        where = f"{page_name(page)}:{line}"
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile("\n" * line + code, str(page), "exec", dont_inherit=True), namespace)
        printed, expected = out.getvalue().splitlines(), expected_prints(code)
        assert len(printed) == len(expected), f"{where}: printed {printed}, the comments say {expected}"
        for got, want in zip(printed, expected, strict=True):
            assert same_line(got, want), f"{where}: printed {got!r}, the comment says {want!r}"
