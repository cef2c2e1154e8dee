"""MkDocs hooks of vwg's documentation site (mkdocs.yml: ``hooks:``): the parts of the pages that come from
the code, so that they cannot drift from it. A page asks for one with a marker on a line of its own:

    <!-- vwg:cli -->          every command and option of `vwg`, from its argparse parser (vwg.cli.build_parser)
    <!-- vwg:exit-codes -->   the exit statuses of `vwg` (vwg.cli.EXIT_CODES)
    <!-- vwg:registries -->   the registered deciders, sensors, platforms, backends, generators and world kinds
                              (vwg.plugins: vwg's own entry points and any installed plugin's)
    <!-- vwg:cpp-headers -->  the public C++ headers' comments (cpp/include/vwg), the C++ API reference
    <!-- vwg:performance -->  the benchmarks' latest results, a table per machine (benchmarks/results/)

An unknown marker fails the build (as ``mkdocs build --strict`` fails a broken link). The generated text
is made with the vwg that the build's Python imports (`make docs` installs it first)."""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
MARKER = re.compile(r"^<!-- vwg:([a-z-]+) -->$", flags=re.M)


# -- the command line ---------------------------------------------------------------------------------
def _subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:  # argparse keeps its subparsers only here
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _option_rows(parser: argparse.ArgumentParser) -> list[str]:
    formatter = parser._get_formatter()
    rows = []
    for group in parser._action_groups:
        actions = [a for a in group._group_actions if a.help != argparse.SUPPRESS
                   and not isinstance(a, argparse._SubParsersAction)]
        if not actions:
            continue
        rows.append(f"\n*{_cell(group.title or '')}*\n\n| option | meaning |\n|---|---|")
        for action in actions:
            if action.option_strings:
                metavar = formatter._format_args(action, action.dest.upper()) if action.nargs != 0 else ""
                names = ", ".join(f"`{o}{' ' + metavar if metavar else ''}`" for o in action.option_strings)
            else:
                names = f"`{formatter._metavar_formatter(action, action.dest)(1)[0]}`"
            meaning = formatter._expand_help(action) if action.help else ""
            rows.append(f"| {names} | {_cell(meaning)} |")
    return rows


def cli_markdown() -> str:
    from vwg.cli import build_parser, fill_registered_names

    parser = build_parser()
    parts = [f"```text\n{parser.format_usage().strip()}\n```", parser.description or "", *_option_rows(parser)]
    for name, sub in _subcommands(parser).items():
        description = fill_registered_names(sub.description or "")  # the registered parts' names, as the help has
        parts += [f"\n## vwg {name}\n", description, f"```text\n{sub.format_usage().strip()}\n```",
                  *_option_rows(sub)]
    return "\n".join(parts) + "\n"


def exit_codes_markdown() -> str:
    from vwg.cli import EXIT_CODES

    rows = ["| status | meaning |", "|---|---|"]
    rows += [f"| {status} | {_cell(meaning)} |" for status, meaning in sorted(EXIT_CODES.items())]
    return "\n".join(rows) + "\n"


# -- the registries ---------------------------------------------------------------------------------
def _summary(factory: Any) -> str:
    """The part's own one-line summary (a sensor's or platform's ``summary``), else its docstring's first sentence."""
    if getattr(factory, "summary", ""):
        return str(factory.summary)
    doc = (getattr(factory, "__doc__", None) or "").strip()
    return re.split(r"(?<=\.)\s", " ".join(doc.split("\n\n")[0].split()), maxsplit=1)[0] if doc else ""


def registries_markdown() -> str:
    from vwg.plugins import GROUPS

    parts = []
    for group, registry in GROUPS.items():
        parts += [f"\n**{registry.kind}s** (entry-point group `{group}`)\n", "| name | what it is | from |",
                  "|---|---|---|"]
        for plugin in registry.plugins():
            parts.append(f"| `{plugin.name}` | {_cell(_summary(registry.get(plugin.name)))} | {_cell(plugin.origin)} |")
        parts += [f"| `{f.name}` | **not loaded**: {_cell(f.error)} | {_cell(f.origin)} |" for f in registry.failures]
    return "\n".join(parts) + "\n"


# -- the C++ headers ----------------------------------------------------------------------------------
_DECLARATION = re.compile(r"^(template\s*<.*>\s*)?(class|struct|enum class|enum|using|inline constexpr|constexpr|"
                          r"[A-Za-z_][\w:<>,\s*&]*\s[\w:~]+\s*\()")
_MEMBER = re.compile(r"^  (?!//)(?!public|private|protected)\S.*$")


def _prose(text: str) -> str:
    """A comment as Markdown text: its `code` spans kept, and outside them the characters Markdown would take
    for links, HTML or emphasis (`v[i][j]`, `std::vector<T>`, `a*b`) escaped."""
    parts = text.split("`")
    for i in range(0, len(parts), 2):  # outside the code spans
        parts[i] = re.sub(r"([\\\[\]*_<>])", r"\\\1", parts[i])
    return "`".join(parts) if len(parts) % 2 else _prose(text.replace("`", ""))  # an unpaired backtick


def _comment_text(lines: list[str]) -> str:
    return _prose(" ".join(re.sub(r"^\s*///?<?\s?", "", line) for line in lines).strip())


def _declaration(lines: list[str], i: int) -> str:
    """The declaration starting at line i, up to its body or its end, on one line."""
    text = ""
    for line in lines[i:i + 6]:
        text += " " + line.strip()
        if re.search(r"[;{}]\s*(//.*)?$", line) or line.rstrip().endswith(")"):
            break
    text = re.sub(r"\s*//.*$", "", text)
    text = re.sub(r"(\)|const|override|noexcept|final)\s*\{.*\}\s*;?$", r"\1", text)  # an inline body
    text = re.sub(r"\s*\{[^}]*$", "", text).strip().rstrip(";").strip()  # a body that opens here
    return re.sub(r"\s+", " ", text)


def header_markdown(path: Path, include_root: Path = ROOT / "cpp" / "include") -> str:
    """A header's reference: its opening comment, then each namespace-level declaration with the comment
    above it, and the commented public members of its classes."""
    lines = path.read_text(encoding="utf-8").splitlines()
    rel = path.relative_to(include_root).as_posix()
    opening = []
    for line in lines:
        if not line.startswith("//"):
            break
        opening.append(line)
    laid_out = any(re.match(r"^//\s{2,}\S", line) for line in opening)  # pseudo-code keeps its lines
    text = "```text\n" + "\n".join(line[3:] for line in opening) + "\n```" if laid_out else _comment_text(opening)
    out = [f"\n### `{rel}`\n", text]
    comment: list[str] = []
    public = False
    for i, line in enumerate(lines[len(opening):], start=len(opening)):
        stripped = line.strip()
        if stripped.startswith("//"):
            comment.append(stripped)
            continue
        if not line.startswith(" ") and _DECLARATION.match(line) and not line.startswith(("namespace", "}")):
            declared = _declaration(lines, i)
            public = declared.startswith("struct")
            if comment or declared.startswith(("class", "struct", "enum")):
                out.append(f"\n- `{declared}`" + (f" — {_cell(_comment_text(comment))}" if comment else ""))
        elif stripped in ("public:", "private:", "protected:"):
            public = stripped == "public:"
        elif public and _MEMBER.match(line) and "///<" in line and stripped[0].isalpha():
            code, _, said = line.partition("///<")
            out.append(f"    - `{_declaration([code], 0)}` — {_cell(_prose(said.strip()))}")
        elif public and comment and _MEMBER.match(line) and (stripped[0].isalpha() or stripped.startswith("~")):
            out.append(f"    - `{_declaration(lines, i)}` — {_cell(_comment_text(comment))}")
        comment = []
    return "\n".join(out) + "\n"


def cpp_headers_markdown() -> str:
    headers = sorted((ROOT / "cpp" / "include" / "vwg").rglob("*.hpp"))
    public = [h for h in headers if "detail" not in h.relative_to(ROOT / "cpp" / "include").parts]
    by_folder: dict[str, list[Path]] = {}
    for h in public:
        folder = h.parent.relative_to(ROOT / "cpp" / "include").as_posix()
        by_folder.setdefault(folder, []).append(h)
    parts = []
    for folder, files in by_folder.items():
        parts.append(f"\n## `{folder}/`\n")
        parts += [header_markdown(h) for h in files]
    return "\n".join(parts)


# -- the benchmarks -----------------------------------------------------------------------------------
def performance_markdown() -> str:
    sys.path.insert(0, str(ROOT / "tools" / "docs"))
    try:
        from performance import performance_markdown as tables
    finally:
        sys.path.pop(0)
    return tables(ROOT / "benchmarks" / "results")


GENERATED: dict[str, Callable[[], str]] = {
    "cli": cli_markdown, "exit-codes": exit_codes_markdown, "registries": registries_markdown,
    "cpp-headers": cpp_headers_markdown, "performance": performance_markdown,
}


def expand(markdown: str, where: str) -> str:
    """The page with each marker replaced by what it asks for; an unknown marker is an error naming the page."""
    def replace(m: re.Match[str]) -> str:
        make = GENERATED.get(m.group(1))
        if make is None:
            raise ValueError(f"{where}: unknown marker <!-- vwg:{m.group(1)} --> (known: {', '.join(GENERATED)})")
        return make()
    return MARKER.sub(replace, markdown)


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    return expand(markdown, page.file.src_path)
