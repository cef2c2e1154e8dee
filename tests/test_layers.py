"""The Python face's layout: no module imports vwg's root package (which imports everything) but the
compiled module vwg._core through it, and imports inside functions only where a heavy optional
dependency is deferred. The layers themselves are import-linter's contracts in pyproject.toml
(make lint); this checks what those contracts cannot see."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "python" / "vwg"
#: (module, imported module) pairs allowed inside a function: the applications the command line starts
#: (Dask, aiohttp, Matplotlib, Gymnasium are optional extras), imported only by the command that needs them.
DEFERRED = {("cli.py", "vwg.sweep"), ("cli.py", "vwg.experiments"), ("cli.py", "vwg.serve.live"),
            ("cli.py", "vwg.serve.server"), ("cli.py", "vwg.robot.overview")}
#: The root itself.
SKIPPED = {"__init__.py"}


def _modules() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if str(p.relative_to(PACKAGE)) not in SKIPPED)


def _vwg_imports(tree: ast.AST) -> list[tuple[ast.AST, str, bool]]:
    """(node, module, inside a function) for each import of a vwg module."""
    out = []

    def visit(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            inside = in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef))
            if isinstance(child, ast.ImportFrom) and child.module and child.level == 0 \
                    and (child.module == "vwg" or child.module.startswith("vwg.")):
                out.append((child, child.module, in_function))
            elif isinstance(child, ast.ImportFrom) and child.level > 0:
                out.append((child, "." * child.level + (child.module or ""), in_function))
            elif isinstance(child, ast.Import):
                out.extend((child, a.name, in_function) for a in child.names if a.name.split(".")[0] == "vwg")
            visit(child, inside)

    visit(tree, False)
    return out


def test_no_module_imports_the_root_package_or_imports_relatively() -> None:
    bad = []
    for path in _modules():
        for node, module, _ in _vwg_imports(ast.parse(path.read_text())):
            rel = path.relative_to(PACKAGE)
            if module.startswith("."):
                bad.append(f"{rel}:{node.lineno}: relative import {module}")
            elif module == "vwg" and isinstance(node, ast.ImportFrom):
                names = [a.name for a in node.names]
                # `from vwg import launch` names a submodule; `from vwg import Engine` would be the root.
                roots = [n for n in names if not (PACKAGE / n).exists() and not (PACKAGE / f"{n}.py").exists()
                         and n != "_core"]
                if roots:
                    bad.append(f"{rel}:{node.lineno}: from vwg import {', '.join(roots)} (the root package)")
            elif module == "vwg":
                bad.append(f"{rel}:{node.lineno}: import vwg (the root package)")
    assert bad == []


def test_imports_inside_functions_only_defer_heavy_optional_parts() -> None:
    bad = []
    for path in _modules():
        rel = str(path.relative_to(PACKAGE))
        for node, module, inside in _vwg_imports(ast.parse(path.read_text())):
            if inside and (rel, module) not in DEFERRED:
                bad.append(f"{rel}:{node.lineno}: {module}")
    assert bad == []


def test_import_linter_contracts_hold() -> None:
    linter = Path(sys.executable).with_name("lint-imports")
    if not linter.exists():
        pytest.fail("import-linter is not installed: pip install '.[test]'")
    root = PACKAGE.parents[1]
    out = subprocess.run([str(linter), "--config", str(root / "pyproject.toml")], cwd=root, capture_output=True,
                         text=True, env={"PYTHONPATH": str(PACKAGE.parent), "PATH": "/usr/bin:/bin"})
    assert out.returncode == 0, out.stdout + out.stderr
    assert "2 kept, 0 broken" in out.stdout


def test_the_module_names_before_the_layout_by_concept_are_gone() -> None:
    # The redesign by concept replaced vwg.casestudy, vwg.sim, vwg.fake_robot, ...: the old names no longer
    # import (no alias beside the new layout), and the new modules are where the old ones went.
    import importlib

    import vwg

    for old in ("casestudy", "sim", "fake_robot", "maps", "registry", "worldfile"):
        sys.modules.pop(f"vwg.{old}", None)
        with pytest.raises(ImportError):
            importlib.import_module(f"vwg.{old}")
    assert not hasattr(vwg, "sim") and not hasattr(vwg, "casestudy")
    assert importlib.import_module("vwg.robot.case_study").CaseStudy is vwg.robot.CaseStudy
    assert importlib.import_module("vwg.testing.fake_robot").FakeRosbridgeRobot


def test_no_import_cycle_between_any_two_modules() -> None:
    """Every module's imports (at module level and in functions), as import-linter's graph has them:
    no module reaches itself again (the contracts order the layers; this covers modules within one)."""
    import grimp

    sys.path.insert(0, str(PACKAGE.parent))
    try:
        graph = grimp.build_graph("vwg", cache_dir=None)
    finally:
        sys.path.remove(str(PACKAGE.parent))
    edges = {m: {i for i in graph.find_modules_directly_imported_by(m) if i != "vwg"} for m in graph.modules}
    cycles = []
    state: dict[str, int] = {}  # 1: on the path, 2: done

    def visit(module: str, path: list[str]) -> None:
        state[module] = 1
        for other in sorted(edges.get(module, ())):
            if state.get(other) == 1:
                cycles.append(" -> ".join([*path[path.index(other):], other]))
            elif other not in state:
                visit(other, [*path, other])
        state[module] = 2

    for module in sorted(edges):
        if module not in state:
            visit(module, [module])
    assert cycles == []
