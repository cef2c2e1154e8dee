"""Plugins by entry point (vwg.plugins): a part written outside vwg, installed with pip, is found by its
entry point and used by name from the command line; one that fails to import is named and the others
still load; vwg's own parts are registered the same way."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import vwg
import vwg._core as _core
from conftest import env_with_path, pip_install_apart
from vwg.errors import SchemaError
from vwg.plugins import GROUPS, Registry, deciders, platforms, sensors, world_kinds


def _dist(site: Path, name: str, group: str, entries: dict[str, str], modules: dict[str, str]) -> None:
    """A distribution as pip leaves it in site-packages: its modules and a .dist-info with entry points."""
    for module, source in modules.items():
        (site / f"{module}.py").write_text(textwrap.dedent(source))
    info = site / f"{name}-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: 1.0\n")
    lines = "\n".join(f"{k} = {v}" for k, v in entries.items())
    (info / "entry_points.txt").write_text(f"[{group}]\n{lines}\n")


@pytest.fixture
def site(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "site"
    folder.mkdir()
    monkeypatch.syspath_prepend(str(folder))
    return folder


def test_an_entry_point_is_found_and_a_broken_one_is_named_while_the_others_load(site: Path) -> None:
    _dist(site, "good-plugin", "vwg.testgroup", {"alpha": "good_mod:Alpha", "gamma": "good_mod:make_gamma"},
          {"good_mod": """
              class Alpha:
                  pass
              def make_gamma():
                  return "gamma made"
          """})
    _dist(site, "bad-plugin", "vwg.testgroup", {"beta": "bad_mod:Beta", "delta": "good_mod:NOT_THERE"},
          {"bad_mod": "raise ImportError('a dependency the plugin needs is missing')"})
    registry: Registry[object] = Registry("test part", "vwg.testgroup")
    assert list(registry) == ["alpha", "gamma"]
    assert registry.create("gamma") == "gamma made"
    assert registry.origin("alpha") == "good-plugin 1.0 (entry point good_mod:Alpha)"
    failures = {f.name: f for f in registry.failures}
    assert set(failures) == {"beta", "delta"}
    assert "a dependency the plugin needs is missing" in failures["beta"].error
    assert failures["beta"].origin == "bad-plugin 1.0 (entry point bad_mod:Beta)"
    with pytest.raises(SchemaError, match=r"test part 'beta' did not load .*a dependency the plugin needs"):
        registry.get("beta")
    with pytest.raises(SchemaError, match=r"unknown test part 'omega' \(known: alpha, gamma\)"):
        registry.get("omega")


def test_in_process_registration_and_duplicates() -> None:
    registry: Registry[object] = Registry("test part", "vwg.nosuchgroup")
    registry.register("mine", dict)
    assert "mine" in registry and registry.origin("mine") == "registered in-process by builtins"
    with pytest.raises(SchemaError, match="'mine' is already registered"):
        registry.register("mine", list)
    with pytest.raises(SchemaError, match="name: expected a non-empty name"):
        registry.register(" ", list)
    registry.unregister("mine")
    assert "mine" not in registry


def test_the_built_in_parts_are_entry_points_of_the_vwg_distribution() -> None:
    # The C++ deciders and backends each have an entry point (the C++ registry's names are the truth).
    for name in _core.decider_names():
        assert deciders.origin(name).startswith(f"vwg {vwg.__version__} (entry point vwg.robot.deciders.native:")
        assert isinstance(deciders.create(name), vwg.robot.Decider)
    assert deciders.origin("wavefront") == f"vwg {vwg.__version__} (entry point " \
                                           "vwg.robot.deciders.wavefront:WavefrontDecider)"
    assert set(sensors) >= {"laser", "kinect", "camera"}
    assert set(platforms) >= {"sim", "rosbridge", "serial"}
    assert set(world_kinds) >= {"robot", "generic"}
    for registry in GROUPS.values():
        assert registry.failures == []


def _install_decider_package(tmp_path: Path) -> dict[str, str]:
    """An out-of-tree package declaring a vwg.deciders entry point, installed with pip into a folder of
    its own; the environment of a child process that sees it (pip_install_apart)."""
    src = tmp_path / "straight-ahead"
    (src / "straight_ahead").mkdir(parents=True)
    (src / "pyproject.toml").write_text(textwrap.dedent("""
        [build-system]
        requires = ["setuptools>=61"]
        build-backend = "setuptools.build_meta"

        [project]
        name = "straight-ahead"
        version = "0.3"

        [project.entry-points."vwg.deciders"]
        straight = "straight_ahead.decider:StraightAhead"
    """))
    (src / "straight_ahead" / "__init__.py").write_text("")
    (src / "straight_ahead" / "decider.py").write_text(textwrap.dedent("""
        import math

        import vwg


        class StraightAhead(vwg.robot.Decider):
            '''Turn to face the goal, then drive 0.3 m: a decider a user writes in a few lines.'''

            def decide(self, robot):
                gx, gy = robot.goal
                x, y, theta = robot.pose
                turn = math.remainder(math.atan2(gy - y, gx - x) - theta, math.tau)
                return turn, min(0.3, math.hypot(gx - x, gy - y))
    """))
    return pip_install_apart(src, tmp_path / "installed")


@pytest.mark.slow
def test_an_installed_package_s_decider_runs_from_the_command_line(tmp_path: Path) -> None:
    env = _install_decider_package(tmp_path)
    cli = [sys.executable, "-m", "vwg.cli"]
    helped = subprocess.run([*cli, "run", "--help"], env=env, capture_output=True, text=True, check=True)
    assert "straight" in " ".join(helped.stdout.split())
    listed = subprocess.run([*cli, "plugins", "--group", "vwg.deciders"], env=env, capture_output=True, text=True,
                            check=True)
    assert "straight" in listed.stdout and "straight-ahead 0.3 (entry point straight_ahead.decider:StraightAhead)" \
        in listed.stdout
    summary = tmp_path / "s.json"
    run = subprocess.run([*cli, "run", "office", "--planner", "straight", "--goal", "kitchen", "--frames", "60",
                          "--allow-unreached", "--summary-json", str(summary), "-q"], env=env, capture_output=True,
                         text=True)
    assert run.returncode == 0, run.stderr
    import json

    robot = json.loads(summary.read_text())["robots"][0]
    assert robot["path_length_m"] > 0.5  # it drove, as its decision said


def test_vwg_plugins_lists_every_group() -> None:
    out = subprocess.run([sys.executable, "-m", "vwg.cli", "plugins"], capture_output=True, text=True, check=True)
    for group in GROUPS:
        assert f"{group}:" in out.stdout
    assert "  astar " in out.stdout and "  sim " in out.stdout and "  laser " in out.stdout


def test_a_command_imports_a_group_s_plugins_only_when_it_needs_them(site: Path, tmp_path: Path) -> None:
    # The commands' helps name the registered parts, but only when a help is shown: a command that needs no decider
    # does not import the deciders' plugins (a slow one would slow every command, a broken one be tried by each). A
    # robot world's planner is checked against the deciders: `vwg worlds`, `run` and `check` of one do load them.
    imported = tmp_path / "imported"
    _dist(site, "noted-decider", "vwg.deciders", {"noted": "noted_decider:Noted"},
          {"noted_decider": f"""
              import pathlib
              pathlib.Path({str(imported)!r}).write_text("imported")
              class Noted:
                  pass
          """})
    env = env_with_path(site)
    cli = [sys.executable, "-m", "vwg.cli"]
    for command in (["--version"], ["plugins", "--group", "vwg.sensors"]):  # they need no decider
        done = subprocess.run([*cli, *command], env=env, capture_output=True, text=True, check=True)
        assert done.stdout and not imported.exists(), command
    helped = subprocess.run([*cli, "run", "--help"], env=env, capture_output=True, text=True, check=True)
    assert "noted" in " ".join(helped.stdout.split()) and imported.exists()
