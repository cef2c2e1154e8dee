"""The `vwg` command as a user meets it: shipped worlds by name, `check` on both kinds of world file,
commands that refuse the wrong kind with a sentence, exit statuses, strict JSON summaries, and every
shipped world's own orders reached, with nothing printed on stderr by the libraries."""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT
from vwg.cli import EXIT_UNREACHED, main, strict_json
from vwg.io.shipped import resolve_world, shipped_worlds

SHIPPED = ["field", "maze", "office", "warehouse", "willow"]
FIREFLIES = ROOT / "examples" / "01_fireflies" / "world.yaml"
VWG = [sys.executable, "-m", "vwg.cli"]


def strict_loads(text: str):
    """json.loads that refuses NaN and ±Infinity, as JSON.parse and every strict parser do."""

    def refuse(token: str):
        raise ValueError(f"not JSON: {token}")

    return json.loads(text, parse_constant=refuse)


def vwg(*args: str, cwd: Path | None = None, timeout: float = 600) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*VWG, *args], cwd=cwd, capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, "PYTHONWARNINGS": "ignore"})


def test_shipped_worlds_by_name_from_any_directory(tmp_path, capsys):
    assert sorted(shipped_worlds()) == SHIPPED
    os.chdir(tmp_path)
    try:
        assert resolve_world("office") == shipped_worlds()["office"]
        assert resolve_world("office.yaml") == shipped_worlds()["office"]
        assert main(["worlds"]) == 0
    finally:
        os.chdir(ROOT)
    out = capsys.readouterr().out
    for name in SHIPPED:
        assert f"\n  {name} " in out


def test_a_file_in_the_current_directory_wins_over_a_shipped_name(tmp_path):
    mine = tmp_path / "office"
    mine.write_text("alphabet: {}\ninitial: ''\n")
    os.chdir(tmp_path)
    try:
        assert resolve_world("office") == Path("office")
    finally:
        os.chdir(ROOT)


def test_unknown_world_name_says_what_was_looked_for(capsys):
    assert main(["run", "attic"]) == 2
    err = capsys.readouterr().err
    assert "attic: no such file, and no shipped world of that name" in err
    assert "office" in err and "vwg worlds" in err


@pytest.mark.parametrize("name", SHIPPED)
def test_check_describes_every_shipped_robot_world(name, capsys):
    assert main(["check", name]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"{name}: ok, a robot world")
    from vwg.robot.world_file import load_robot_world

    world = load_robot_world(name)
    for room in world.rooms:
        assert re.search(rf"\n    {room} +marker {world.rooms[room].marker} at", out)  # every room, by name
    for robot in world.robots:
        assert re.search(rf"\n    robot {robot.id} +start", out)


def test_check_describes_a_generic_world(capsys):
    assert main(["check", str(FIREFLIES)]) == 0
    out = capsys.readouterr().out
    assert "ok, a generic world (fireflies)" in out
    assert "Firefly ['tick', 'food', 'show']" in out


def test_commands_refuse_the_wrong_kind_of_file(tmp_path, capsys):
    assert main(["overview", str(FIREFLIES)]) == 2
    assert "vwg overview takes a robot world" in capsys.readouterr().err
    odd = tmp_path / "odd.yaml"
    odd.write_text("colour: blue\n")
    for command in ("run", "check", "overview"):
        assert main([command, str(odd)]) == 2
        err = capsys.readouterr().err
        assert "not a world file: expected a " in err, command  # each registered kind, by name
        assert "a robot world (a mapping with map:" in err and "a generic world (a mapping with alphabet:" in err
        assert "found keys: colour" in err
    assert main(["run", str(FIREFLIES), "--goal", "kitchen"]) == 2
    assert "--goal is for robot worlds" in capsys.readouterr().err
    assert main(["run", str(FIREFLIES), "--planner", "astar"]) == 2
    assert f"--planner is for robot worlds; {FIREFLIES} is a generic world" in capsys.readouterr().err


def test_strict_json_replaces_what_json_cannot_hold():
    value = {"a": math.inf, "b": [1.0, -math.inf, math.nan], "c": "x", "d": 2}
    assert strict_json(value) == {"a": None, "b": [1.0, None, None], "c": "x", "d": 2}
    with pytest.raises(ValueError):
        strict_loads(json.dumps({"a": math.inf}))  # what Python writes by default


def test_unreached_order_exits_3_with_a_reason_and_strict_json(tmp_path, capsys):
    # Robot 1 has far too few frames to reach the lounge; robot 2 has no order (its distance is
    # not finite: null in JSON).
    summary = tmp_path / "s.json"
    code = main(["run", "office", "--goal", "lounge", "--frames", "20", "--summary-json", str(summary)])
    assert code == EXIT_UNREACHED == 3
    captured = capsys.readouterr()
    assert "lounge: " in captured.out and "m away (to lounge)" in captured.out
    assert "not every order was reached: robot 1 (lounge)" in captured.err
    data = strict_loads(summary.read_text())
    assert data["reached"] is False
    assert data["robots"][1]["room"] is None and data["robots"][1]["distance_to_goal_m"] is None
    assert main(["run", "office", "--goal", "lounge", "--frames", "20", "--allow-unreached", "-q"]) == 0


@pytest.mark.parametrize("name", SHIPPED)
@pytest.mark.slow
def test_every_shipped_world_reaches_its_own_orders_quietly(name, tmp_path):
    # As shipped: the world file's orders, frames and seed; the A* robots reach every room in time.
    summary = tmp_path / "s.json"
    done = vwg("run", name, "--summary-json", str(summary), "-q", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""  # no library prints (OMPL, libapriltag) on a run that went well
    data = strict_loads(summary.read_text())
    assert data["reached"] is True
    from vwg.robot.world_file import load_robot_world

    world = load_robot_world(name)
    last = {o.robot: o.room for o in world.orders}
    assert {r["id"]: r["room"] for r in data["robots"] if r["room"]} == last
    assert data["frames"] < world.frames  # stopped because all arrived, not at the frame limit


def test_library_messages_go_to_logging_quiet_by_default(tmp_path):
    # What vwg's C++ parts and OMPL say goes through vwg's log sink to `logging` as vwg.<source>:
    # nothing is printed unless the application configures logging (vwg run -v does).
    script = ("import logging, sys, vwg\n"
              "if sys.argv[1] == 'loud': logging.basicConfig(level=logging.INFO)\n"
              "vwg._core.log_message(30, 'ompl', 'Start state is not valid')\n"
              "vwg._core.log_message(10, 'ompl', 'a detail')\n")
    quiet = subprocess.run([sys.executable, "-c", script, "quiet"], capture_output=True, text=True, check=True)
    loud = subprocess.run([sys.executable, "-c", script, "loud"], capture_output=True, text=True, check=True)
    assert quiet.stderr == ""
    assert loud.stderr == "WARNING:vwg.ompl:Start state is not valid\n"  # INFO and above: not the detail
    run = vwg("run", "office", "--planner", "rrtconnect", "--frames", "300", "--allow-unreached", "-q")
    assert run.returncode == 0 and run.stderr == ""
    assert "vwg.ompl: WARNING: from a planner" in logs_of_verbose_cli()


def logs_of_verbose_cli() -> str:
    """vwg -v configures logging: a message said during a run is printed with its source."""
    code = ("import vwg, vwg.cli\n"
            "vwg.cli.main(['-v', 'check', 'office'])\n"
            "vwg._core.log_message(30, 'ompl', 'from a planner')\n")
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stderr


def test_the_platform_is_one_setting(tmp_path, capsys):
    summary = tmp_path / "s.json"
    assert main(["run", "office", "--platform", "sim", "--goal", "kitchen", "--summary-json", str(summary), "-q"]) == 0
    assert strict_loads(summary.read_text())["reached"] is True
    assert main(["run", "office", "--platform", "warp", "--goal", "kitchen"]) == 2
    assert "unknown platform 'warp' (known: rosbridge, serial, sim)" in capsys.readouterr().err
    # In the world file: `platform:` names it (a name or a mapping with kind); an unknown one is an
    # error with the file and line.
    text = shipped_worlds()["office"].read_text().replace("map: office/map.yaml", "map: " + str(
        shipped_worlds()["office"].parent / "office" / "map.yaml"))
    mine = tmp_path / "office.yaml"
    mine.write_text(text + "platform: {kind: sim}\n")
    assert main(["check", str(mine)]) == 0
    mine.write_text(text + "platform: warp\n")
    assert main(["check", str(mine)]) == 2
    err = capsys.readouterr().err
    line = len(text.splitlines()) + 1
    assert f"{mine}:{line}: platform: unknown platform 'warp' (known: rosbridge, serial, sim)" in err


def test_a_third_party_decider_registers_by_name(tmp_path, capsys):
    import vwg
    from vwg.plugins import deciders

    class Straight(vwg.robot.Decider):
        """Face the goal, drive up to a metre: enough in the open field."""

        name = "straight"

        def decide(self, robot):
            return robot.follow([robot.pose[:2], robot.goal])

    deciders.register("straight-test", Straight)
    summary = tmp_path / "s.json"
    assert main(["run", "field", "--planner", "straight-test", "--goal", "rock", "--frames", "50",
                 "--allow-unreached", "--summary-json", str(summary), "-q"]) == 0
    assert strict_loads(summary.read_text())["planner"] == "straight-test"
    assert main(["run", "field", "--planner", "nope"]) == 2
    assert "unknown planner 'nope' (known: " in capsys.readouterr().err
