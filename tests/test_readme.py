"""The README says what vwg does: its console examples are run and their output compared (wall-clock
times aside), and its Python examples are run, each `print(...)  # expected` checked."""

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

README = (ROOT / "README.md").read_text(encoding="utf-8")
BIN = Path(sys.executable).parent


def blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", README, flags=re.S)


def sessions() -> list[tuple[str, list[str]]]:
    """(command, expected output lines) for every `$ command` of the console blocks."""
    out: list[tuple[str, list[str]]] = []
    for block in blocks("console"):
        for line in block.splitlines():
            if line.startswith("$ "):
                out.append((line[2:], []))
            else:
                out[-1][1].append(line)
    return out


def normal(text: str) -> str:
    """Output with the wall-clock parts (which differ between runs and machines) blanked."""
    text = re.sub(r"[\d.]+ s wall", "<t> s wall", text)
    text = re.sub(r"\(\d+\.\d+ s\)", "(<t> s)", text)
    return re.sub(r"(wall time\s+).*", r"\1<t>", text)


def test_the_readme_has_examples_to_check():
    assert len(sessions()) >= 5
    assert len(blocks("python")) >= 2


@pytest.mark.parametrize("command, expected", sessions(), ids=[c for c, _ in sessions()])
@pytest.mark.slow
def test_console_examples_print_what_the_readme_shows(command, expected, tmp_path_factory):
    # One folder for all commands, in README order, so `vwg replay run.jsonl` finds the record.
    where = tmp_path_factory.getbasetemp() / "readme"
    where.mkdir(exist_ok=True)
    for d in ("examples",):
        if not (where / d).exists():
            (where / d).symlink_to(ROOT / d)
    env = {**os.environ, "PATH": f"{BIN}{os.pathsep}{os.environ['PATH']}"}
    argv = shlex.split(command)
    if argv[0] == "python":
        argv[0] = sys.executable
    done = subprocess.run(argv, cwd=where, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert normal(done.stdout).splitlines() == normal("\n".join(expected)).splitlines()


@pytest.mark.parametrize("index", range(len(blocks("python"))))
@pytest.mark.slow
def test_python_examples_run_and_print_what_their_comments_say(index, tmp_path, monkeypatch):
    code = blocks("python")[index]
    monkeypatch.chdir(tmp_path)
    expected = [m.group(1).strip() for m in re.finditer(r"^\s*print\(.*\)\s*#\s*(.*)$", code, flags=re.M)]
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, f"README python block {index}", "exec"), {"__name__": f"readme_{index}"})
    printed = out.getvalue().splitlines()
    assert len(printed) == len(expected)
    for got, want in zip(printed, expected, strict=True):
        if want.endswith("...]"):  # an elided list: the shown items must start it
            assert got.startswith(want[: -len("...]")].rstrip(", ")), (got, want)
        else:
            assert got == want
