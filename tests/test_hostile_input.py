"""Hostile and broken input (issue 14's findings, each a regression test): every one is refused with an
error that names where and what, and none crashes, hangs or aborts the process."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time

import pytest

import vwg
from conftest import ROOT
from vwg.errors import FrameError, ParseError, WorldFileError

OFFICE = (ROOT / "maps" / "office.yaml").read_text()


# ---- the text form ------------------------------------------------------------------------------------------
def test_an_excerpt_cut_inside_a_character_stays_a_parse_error(world):
    # The excerpt of the line is cut at 200 bytes; "é" takes bytes 199-200: the cut goes before it.
    with pytest.raises(ParseError) as info:
        world.parse("L" * 199 + "é")
    assert info.value.line == 1 and info.value.column == 1
    str(info.value).encode("utf-8")  # the message itself is text that prints


def test_a_lone_surrogate_in_a_python_string_is_a_parse_error_with_its_place(world):
    text = "Lamp\nLamp Dot<s=\"a\udcff\">"  # as surrogateescape decoding leaves an undecodable byte
    with pytest.raises(ParseError) as info:
        world.parse(text)
    assert (info.value.line, info.value.column) == (2, 14)
    assert "U+DCFF" in str(info.value) and "lone surrogate" in str(info.value)


@pytest.mark.parametrize("escape", ["\\uDC00", "\\uDFFF", "\\uD800x", "\\uD800\\u0041"])
def test_an_escaped_lone_surrogate_is_refused(world, escape):
    with pytest.raises(ParseError) as info:
        world.parse(f'Dot<s="{escape}">')
    assert info.value.column == 8 and "surrogate" in str(info.value)
    # A pair makes one character, which prints and reads back.
    w = world.parse('Dot<s="\\uD83D\\uDE00">')
    assert world.parse(str(w)) == w and "\U0001F600" in str(w)


# ---- world files -----------------------------------------------------------------------------------------
def world_file(tmp_path, text):
    path = tmp_path / "w.yaml"
    path.write_text(text.replace("map: office/map.yaml", f"map: {ROOT / 'maps' / 'office' / 'map.yaml'}"))
    return path


def line_of(text: str, needle: str) -> int:
    return text[:text.index(needle)].count("\n") + 1


@pytest.mark.parametrize(("old", "new", "field", "words"), [
    ("start: [1.5, 9.0, 0.0]", "start: [1.5, 9.0, 1.0e+39]", "robots[0].start", "yaw within"),
    ("start: [1.5, 9.0, 0.0]", "start: [1.5, 9.0, 1.0e+300]", "robots[0].start", "yaw within"),
    ("  - id: 1\n", "  - id: 1180591620717411303424\n", "robots[0].id", "expected an integer from"),
    ("  - id: 1\n", "  - id: 1\n    radius: 1.0e+30\n", "robots[0].radius", "<= 100"),
    ("frames: 3000", "frames: 3000\nlaser: {beams: 1.0e+9}", "laser.beams", "expected an integer"),
    ("frames: 3000", "frames: 3000\nlaser: {beams: 1000000000}", "laser.beams", "1 to 100000 beams"),
])
def test_numbers_too_big_for_the_simulator_are_refused_by_field(tmp_path, old, new, field, words):
    assert old in OFFICE
    text = OFFICE.replace(old, new, 1)
    path = world_file(tmp_path, text)
    with pytest.raises(WorldFileError) as info:
        vwg.robot.load_robot_world(path)
    message = str(info.value)
    assert f"{path}:" in message and field in message and words in message, message


def test_a_map_resolution_too_big_for_the_simulator_is_refused_with_its_line(tmp_path):
    src = (ROOT / "maps" / "office" / "map.yaml").read_text()
    (tmp_path / "map.yaml").write_text(src.replace("resolution: 0.05", "resolution: 1.0e+30"))
    (tmp_path / "map.pgm").write_bytes((ROOT / "maps" / "office" / "map.pgm").read_bytes())
    with pytest.raises(WorldFileError) as info:
        vwg.maps.load_map(tmp_path / "map.yaml")
    assert f"{tmp_path / 'map.yaml'}:" in str(info.value) and "resolution" in str(info.value) and "<= 100" in \
        str(info.value)


def test_a_python_robot_or_map_beyond_the_simulators_floats_is_refused_not_aborted():
    # The C++ checks behind the world file's: the process must not abort on a Box2D assertion.
    code = """
import vwg, numpy as np
from vwg.maps import OccupancyGrid
grid = OccupancyGrid(np.zeros((10, 10), np.int8), 0.05)
for robot in (vwg.robot.RobotSettings(start=(0.2, 0.2, 1e39)), vwg.robot.RobotSettings(start=(1e30, 0.2, 0.0))):
    try:
        vwg.sim.PhysicsWorld(grid, [robot])
    except vwg.Error as e:
        print("refused:", e)
try:
    vwg.sim.PhysicsWorld(OccupancyGrid(np.zeros((10, 10), np.int8), 50.0, (1e6, 0, 0)), [])
except vwg.Error as e:
    print("refused:", e)
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert len(lines) == 3 and all(line.startswith("refused:") for line in lines), done.stdout
    assert "yaw" in lines[0] and "x and y" in lines[1] and "grid.origin" in lines[2]


def test_a_billion_laughs_yaml_is_refused_quickly(tmp_path):
    lines = ['a0: &a0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for k in range(1, 10):
        lines.append(f"a{k}: &a{k} [" + ", ".join([f"*a{k - 1}"] * 9) + "]")
    path = tmp_path / "laughs.yaml"
    path.write_text("\n".join(lines) + "\nmap: x\n")
    start = time.perf_counter()
    with pytest.raises(WorldFileError, match="aliases"):
        vwg.robot.load_robot_world(path)
    assert time.perf_counter() - start < 10  # refused, not expanded (the text is 1 KB, its tree 10⁹ values)


def test_a_named_pipe_or_a_device_is_refused_before_it_is_read(tmp_path):
    fifo = tmp_path / "map.map"
    os.mkfifo(fifo)
    # Nothing writes to the pipe: reading it would wait forever.
    result: list[BaseException] = []
    reader = threading.Thread(target=lambda: _try(lambda: vwg.maps.load_movingai(fifo), result), daemon=True)
    reader.start()
    reader.join(timeout=20)
    assert not reader.is_alive() and isinstance(result[0], WorldFileError) and "named pipe" in str(result[0])
    with pytest.raises(WorldFileError, match="a device"):
        vwg.maps.load_movingai("/dev/zero")
    with pytest.raises(WorldFileError, match="a device"):
        vwg.robot.load_robot_world("/dev/zero")
    with pytest.raises(WorldFileError, match="a folder"):
        vwg.robot.load_robot_world(tmp_path)


def _try(fn, out):
    try:
        fn()
    except BaseException as e:  # the test looks at whatever came out
        out.append(e)


# ---- the command line -------------------------------------------------------------------------------------
@pytest.mark.parametrize(("args", "words"), [
    (["--seed", str(2**70)], "--seed"), (["--frames", "-5"], "--frames"), (["--dt", "1e300"], "--dt"),
    (["--threads", "-1"], "--threads"),
])
def test_out_of_range_options_exit_2_naming_the_option(args, words):
    done = subprocess.run([sys.executable, "-m", "vwg.cli", "run", "office", *args], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2 and words in done.stderr and "Traceback" not in done.stderr, done.stderr


# ---- faults in user code ------------------------------------------------------------------------------------
class Interrupted(vwg.Actor):
    events = ("tick",)

    def on_tick(self, e):
        raise KeyboardInterrupt


class Exits(vwg.Actor):
    events = ("tick",)

    def on_tick(self, e):
        raise SystemExit(3)


class Fails(vwg.Actor):
    events = ("tick",)

    def on_tick(self, e):
        raise ValueError("broken")


@pytest.mark.parametrize(("actor", "expected"), [(Interrupted, KeyboardInterrupt), (Exits, SystemExit),
                                                 (Fails, FrameError)])
def test_ctrl_c_and_exit_inside_a_lambda_are_not_wrapped(actor, expected):
    w = vwg.World(primitives={"Lamp": None}, events={"tick": None}, actors=[actor])
    engine = vwg.Engine(w, actor.__name__, generators=[vwg.every_frame("tick")], backend=vwg.NullBackend())
    with pytest.raises(expected):
        engine.run(3)
    assert engine.frame == 0  # the frame did not happen: the engine kept its last complete one


def test_a_decider_path_with_nan_is_a_frame_error_naming_it():
    import numpy as np

    from vwg.casestudy import CaseStudy

    class NanPath(vwg.robot.Decider):
        def decide(self, robot):
            return 0.1, 0.5, np.array([[0.0, 0.0], [np.nan, 1.0]])

    case = CaseStudy(vwg.robot.load_robot_world("office"), NanPath(), goals={1: "kitchen"}, world_orders=False)
    with pytest.raises(FrameError, match=r"decide path: expected finite points; point 1 is \(nan, 1\.0\)"):
        case.run(frames=5)
    case.close()


def test_a_frame_time_too_long_is_refused_with_its_line(tmp_path):
    text = OFFICE.replace("dt: 0.1", "dt: 1.0e+300")
    path = world_file(tmp_path, text)
    with pytest.raises(WorldFileError) as info:
        vwg.robot.load_robot_world(path)
    assert f"{path}:{line_of(text, 'dt: 1.0e+300')}: dt" in str(info.value) and "<= 3600" in str(info.value)


class Slow(vwg.Actor):
    events = ("tick",)

    def on_tick(self, e):
        time.sleep(0.25)
        return self


def test_a_python_part_over_its_time_budget_is_reported_by_name(caplog):
    import logging

    w = vwg.World(primitives={"Lamp": None}, events={"tick": None}, actors=[Slow])

    def run(budget: float) -> str:
        vwg.set_python_budget(budget)
        try:
            engine = vwg.Engine(w, "Slow . Lamp", generators=[vwg.every_frame("tick")], backend=vwg.NullBackend())
            with caplog.at_level(logging.WARNING, logger="vwg"):
                engine.run(2)
            return str(engine.string)
        finally:
            vwg.set_python_budget(1.0)

    reported = run(0.1)
    messages = [r.getMessage() for r in caplog.records if r.name == "vwg.python"]
    assert len(messages) == 2, messages  # one call a frame, each over the budget
    assert all("the Python actor's λ Slow.on_tick took 0.2" in m and "budget of 0.100 s" in m for m in messages)
    caplog.clear()
    assert run(0) == reported  # only reported: the frames are the same without the budget
    assert not [r for r in caplog.records if r.name == "vwg.python"]
    with pytest.raises(vwg.SchemaError, match="python_budget"):
        vwg.set_python_budget(-1)
