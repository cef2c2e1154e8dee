"""The parts of the documentation made from the code (tools/docs/hooks.py): the CLI reference holds every
option `vwg COMMAND --help` prints, a part registered in-process shows up in the CLI's help and in the docs'
tables without editing either, the C++ reference reads a header's comments, and an unknown marker fails."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from conftest import ROOT

sys.path.insert(0, str(ROOT / "tools" / "docs"))
import hooks

from vwg.cli import EXIT_CODES, build_parser
from vwg.plugins import deciders
from vwg.robot.deciders.native import astar

COMMANDS = ["run", "resume", "replay", "export", "sweep", "experiments", "serve", "overview", "foxglove-layout",
            "check", "plugins", "worlds"]


@pytest.mark.parametrize("command", COMMANDS)
def test_the_cli_page_holds_every_option_the_help_prints(command):
    # The help as a user sees it, from another process: every --option it names is in the page's section.
    shown = subprocess.run([sys.executable, "-m", "vwg", command, "--help"], capture_output=True, text=True,
                           timeout=60, env={**os.environ, "COLUMNS": "200"})
    assert shown.returncode == 0, shown.stderr
    options = set(re.findall(r"(?<![\w-])(--[a-z][a-z-]*)", shown.stdout))
    page = hooks.cli_markdown()
    section = page.split(f"\n## vwg {command}\n")[1].split("\n## vwg ")[0]
    assert options and options <= set(re.findall(r"(--[a-z][a-z-]*)", section)), options


def test_the_cli_page_has_a_section_for_every_command():
    page = hooks.cli_markdown()
    assert re.findall(r"^## vwg ([\w-]+)$", page, flags=re.M) == COMMANDS
    # The helps name the registered parts by a mark filled in when shown (vwg.cli); the page shows the names.
    assert not re.search(r"@\w+@", page) and "a registered kind (generic, robot)" in page


def test_every_exit_status_of_the_cli_is_in_the_table():
    table = hooks.exit_codes_markdown()
    for status in (0, 1, 2, 3, 4, 130):
        assert re.search(rf"^\| {status} \| \w", table, flags=re.M)
    assert set(EXIT_CODES) == {0, 1, 2, 3, 4, 130}


def test_a_decider_registered_in_process_shows_up_in_the_help_and_the_docs():
    name = "docs-test-decider"
    deciders.register(name, astar)
    try:
        help_text = build_parser()._subparsers._group_actions[0].choices["run"].format_help()
        assert name in re.sub(r"\s+", "", help_text)  # the help wraps the list of planners
        assert f"| `{name}` |" in hooks.registries_markdown()
    finally:
        deciders.unregister(name)
    assert f"| `{name}` |" not in hooks.registries_markdown()


def test_the_cpp_reference_reads_a_headers_comments(tmp_path):
    header = tmp_path / "vwg" / "thing.hpp"
    header.parent.mkdir()
    header.write_text("// Things, counted.\n#pragma once\nnamespace vwg {\n\n"
                      "/// A thing with a grid[i][j] of std::vector<int>.\nclass Thing {\n public:\n"
                      "  /// How many there are.\n  int count() const { return n_; }\n  int hidden();\n"
                      " private:\n  /// Not shown.\n  int n_ = 0;\n};\n\n/// Makes one.\nThing make_thing(int n);\n}\n")
    text = hooks.header_markdown(header, tmp_path)
    assert "### `vwg/thing.hpp`" in text and "Things, counted." in text
    assert r"- `class Thing` — A thing with a grid\[i\]\[j\] of std::vector\<int\>." in text
    assert "    - `int count() const` — How many there are." in text
    assert "hidden" not in text and "Not shown" not in text
    assert "- `Thing make_thing(int n)` — Makes one." in text


def test_an_unknown_marker_is_an_error_naming_the_page():
    assert hooks.expand("a\n<!-- vwg:exit-codes -->\nb", "x.md").count("| 130 |") == 1
    with pytest.raises(ValueError, match=r"x\.md: unknown marker <!-- vwg:nothing -->"):
        hooks.expand("<!-- vwg:nothing -->", "x.md")


def test_the_readme_is_the_front_door():
    readme = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    assert len(readme) <= 200
    first = "\n".join(readme[:10])
    assert "make demo" in first and "make test" in first  # the two set-up commands come first


def test_every_page_is_in_the_nav():
    nav = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    pages = {p.relative_to(ROOT / "docs").as_posix() for p in (ROOT / "docs").rglob("*.md")}
    assert pages and pages <= set(re.findall(r"([\w/-]+\.md)", nav))
