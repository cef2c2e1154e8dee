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
        vwg.io.maps.load_map(tmp_path / "map.yaml")
    assert f"{tmp_path / 'map.yaml'}:" in str(info.value) and "resolution" in str(info.value) and "<= 100" in \
        str(info.value)


def test_a_python_robot_or_map_beyond_the_simulators_floats_is_refused_not_aborted():
    # The C++ checks behind the world file's: the process must not abort on a Box2D assertion.
    code = """
import vwg, numpy as np
from vwg.io.maps import OccupancyGrid
grid = OccupancyGrid(np.zeros((10, 10), np.int8), 0.05)
for robot in (vwg.robot.RobotSettings(start=(0.2, 0.2, 1e39)), vwg.robot.RobotSettings(start=(1e30, 0.2, 0.0))):
    try:
        vwg.robot.platforms.sim.PhysicsWorld(grid, [robot])
    except vwg.Error as e:
        print("refused:", e)
try:
    vwg.robot.platforms.sim.PhysicsWorld(OccupancyGrid(np.zeros((10, 10), np.int8), 50.0, (1e6, 0, 0)), [])
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
    reader = threading.Thread(target=lambda: _try(lambda: vwg.io.maps.load_movingai(fifo), result), daemon=True)
    reader.start()
    reader.join(timeout=20)
    assert not reader.is_alive() and isinstance(result[0], WorldFileError) and "named pipe" in str(result[0])
    with pytest.raises(WorldFileError, match="a device"):
        vwg.io.maps.load_movingai("/dev/zero")
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

    from vwg.robot.case_study import CaseStudy

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


# ---- issue 34: what a small file expands to, numbers at the edges of floats, full disks -------------------
def vwg_cli(*args: str, cwd=None, limit_file_bytes: int | None = None) -> subprocess.CompletedProcess:
    """`vwg ARGS` in a fresh process (its exit status and messages as a user sees them)."""
    def limit() -> None:
        import resource

        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_file_bytes, limit_file_bytes))

    # The same vwg as this process, also from another folder (PYTHONPATH=python made absolute).
    paths = [os.path.abspath(p) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(paths)}
    # (errors=: a message may name a file whose name is not UTF-8.)
    return subprocess.run([sys.executable, "-m", "vwg.cli", *args], capture_output=True, text=True,
                          errors="backslashreplace", timeout=300, cwd=cwd, env=env,
                          preexec_fn=limit if limit_file_bytes else None)


@pytest.mark.parametrize(("text", "line", "column", "words"), [
    # An alias inside the value it names: PyYAML builds a list holding itself (a RecursionError before).
    ("name: x\nloop: &x [1, *x]\nmap: x\n", 2, 14, "the alias *x is inside the value it names"),
    ("loop: &x {a: {b: *x}}\n", 1, 18, "the alias *x is inside the value it names"),
    # 1,000 lists inside each other (a RecursionError before). The top mapping is level 1, the list at
    # column 6 level 2: level 101 is the "[" at column 105.
    ("map: " + "[" * 1000 + "]" * 1000 + "\n", 1, 105, "nested more than 100 levels deep"),
    # A 5,000-digit integer (Python's ValueError for long integers before); 101 digits are refused too.
    ("map: x\nseed: " + "9" * 5000 + "\n", 2, 7, "an integer of 5000 digits"),
    ("seed: 0x" + "f" * 101 + "\n", 1, 7, "an integer of 101 digits"),
    # A lone surrogate escape: a string that cannot be printed or written as UTF-8 (UnicodeEncodeError before).
    ('name: "\\ud800"\nmap: x\n', 1, 7, "\\uD800 is half of a UTF-16 surrogate pair"),
    ("seed: !!int abc\n", 1, 7, "cannot read this int"),
])
def test_yaml_that_expands_or_cannot_be_a_value_is_refused_at_its_place(tmp_path, text, line, column, words):
    path = tmp_path / "w.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(WorldFileError) as info:
        vwg.robot.load_robot_world(path)
    assert (info.value.line, info.value.column) == (line, column), str(info.value)
    assert str(info.value).startswith(f"{path}:{line}:{column}: ") and words in str(info.value)
    done = vwg_cli("check", str(path))
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert done.stderr.startswith(f"vwg: error: {path}:{line}:{column}: "), done.stderr


@pytest.mark.parametrize("key", ["²", "١٢", "9" * 5000])
def test_keys_of_digits_python_cannot_make_an_integer_of_stay_keys(tmp_path, key):
    # A key of digits is also found as an integer (robots[0] and robots.0); "²" is a digit to
    # str.isdigit but not to int() (a ValueError before), and 5,000 digits are past int()'s limit.
    path = tmp_path / "w.yaml"
    path.write_text(f'map: x\n? "{key}"\n: 1\n', encoding="utf-8")
    with pytest.raises(WorldFileError) as info:
        vwg.robot.load_robot_world(path)
    assert str(info.value).startswith(f"{path}:2: {key}: unknown key"), str(info.value)[:200]


def test_an_escaped_surrogate_pair_is_one_character(tmp_path):
    text = OFFICE.replace("name: office", 'name: "\\ud83d\\ude00 office"')
    assert vwg.robot.load_robot_world(world_file(tmp_path, text)).name == "\U0001F600 office"


def test_a_sweep_spec_with_a_recursive_alias_is_refused_at_its_place(tmp_path):
    from vwg.sweep import load_spec

    spec = tmp_path / "spec.yaml"
    spec.write_text("worlds: &w [office, *w]\nplanners: [astar]\nseeds: 1\nframes: 10\n")
    with pytest.raises(WorldFileError) as info:
        load_spec(spec)
    assert (info.value.line, info.value.column) == (1, 21) and "inside the value it names" in str(info.value)


def office_map(tmp_path, origin: str):
    """The office's map_server YAML with another origin, beside a copy of its image."""
    folder = tmp_path / "map"
    folder.mkdir()
    text = (ROOT / "maps" / "office" / "map.yaml").read_text()
    (folder / "map.yaml").write_text("\n".join(f"origin: {origin}" if line.startswith("origin:") else line
                                              for line in text.splitlines()) + "\n")
    (folder / "map.pgm").write_bytes((ROOT / "maps" / "office" / "map.pgm").read_bytes())
    return folder / "map.yaml"


@pytest.mark.parametrize(("old", "new", "field", "words"), [
    # A point 1e308 m away: its cell number (x / 0.05 m) is infinite (OverflowError in math.floor before).
    ("at: [5.5, 17.8]", "at: [1.0e+308, 17.8]", "rooms.kitchen.at", "outside the map"),
    ("at: [5.5, 17.8]", "at: [-1.0e+308, 17.8]", "rooms.kitchen.at", "outside the map"),
    # The smallest float as seconds per frame: an order at 0 s is frame 0 / 5e-324 (inf before).
    ("dt: 0.1", "dt: 4.9e-324", "dt", ">= 1e-06"),
    ("time: 0.0", "time: 1.0e+308", "orders[0].time", "<= 1000000000.0"),
    # One more than the engine's 64-bit seed: vwg check passed it and vwg run refused it without the file.
    ("seed: 0", "seed: 18446744073709551616", "seed", "<= 18446744073709551615"),
    ("frames: 3000", "frames: 18446744073709551616", "frames", "<= 18446744073709551615"),
])
def test_numbers_at_the_edges_of_floats_and_integers_are_refused_by_field(tmp_path, old, new, field, words):
    assert old in OFFICE
    text = OFFICE.replace(old, new, 1)
    path = world_file(tmp_path, text)
    line = line_of(text, new)
    with pytest.raises(WorldFileError) as info:
        vwg.robot.load_robot_world(path)
    assert str(info.value).startswith(f"{path}:{line}: {field}: ") and words in str(info.value), str(info.value)
    done = vwg_cli("check", str(path))
    assert done.returncode == 2 and done.stderr.startswith(f"vwg: error: {path}:{line}: {field}: "), done.stderr


@pytest.mark.parametrize(("origin", "field", "words"), [
    ("[1.0e+308, 1.0e+308, 0]", "origin[0]", "<= 1000000.0"),  # an OverflowError before
    ("[0, 0, 1.0e+308]", "origin[2]", "<= 1000.0"),
    ("[999990.0, 0, 0]", "origin", "reaches beyond ±1e+06 m"),  # the office is 30 m wide
])
def test_a_map_origin_beyond_the_simulator_is_refused_with_its_line(tmp_path, origin, field, words):
    path = office_map(tmp_path, origin)
    line = line_of(path.read_text(), "origin:")
    with pytest.raises(WorldFileError) as info:
        vwg.io.maps.load_map(path)
    assert str(info.value).startswith(f"{path}:{line}: {field}: ") and words in str(info.value), str(info.value)
    text = OFFICE.replace("map: office/map.yaml", f"map: {path}")
    (tmp_path / "w.yaml").write_text(text)
    done = vwg_cli("check", str(tmp_path / "w.yaml"))
    assert done.returncode == 2 and done.stderr.startswith(f"vwg: error: {path}:{line}: {field}: "), done.stderr


@pytest.mark.parametrize(("args", "words"), [
    (["--frames", "100000000000000000000000"], "--frames: expected a number of frames from 0 to 2**64 - 1"),
    (["--dt", "1e-320"], "--dt: expected a number of seconds from 1e-06 to 3600"),
    (["--max-symbols", "100000000000000000000000"], "--max-symbols: expected a count from 0"),
])
def test_options_beyond_the_engines_integers_and_floats_exit_2_naming_the_option(args, words):
    done = vwg_cli("run", "office", *args)
    assert done.returncode == 2 and done.stderr.startswith(f"vwg: error: {words}"), done.stderr


def test_a_movingai_header_larger_than_its_file_is_refused_before_the_grid_is_made(tmp_path):
    path = tmp_path / "wide.map"
    path.write_text("type octile\nheight 1\nwidth 1000000000000\nmap\n..\n")  # 10**12 cells: 931 GiB before
    with pytest.raises(WorldFileError) as info:
        vwg.io.maps.load_movingai(path)
    assert info.value.field == "width" and info.value.line == 3
    assert "1 rows of 1000000000000 cells, more than the file's 48 bytes hold" in str(info.value)


def grey_png(width: int, height: int, rows: bytes) -> bytes:
    """A PNG of 8-bit grey pixels: its signature, header chunk (IHDR), compressed rows (IDAT) and end."""
    import struct
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", rows) + chunk(b"IEND", b""))


def test_a_map_image_over_the_pixel_limit_is_refused_from_its_header(tmp_path):
    import zlib

    # 20,000 × 20,000 grey pixels, all free: 439 KB on disk, 400 M pixels (3.2 GB as float64) decoded.
    packer = zlib.compressobj(9)
    row = b"\x00" + b"\xfe" * 20_000  # filter type 0, then the row's pixels
    png = grey_png(20_000, 20_000, b"".join(packer.compress(row) for _ in range(20_000)) + packer.flush())
    path = office_map(tmp_path, "[0, 0, 0]")
    (path.parent / "map.pgm").write_bytes(png)  # a PNG named .pgm: the format is told by its first bytes
    assert len(png) < 500_000
    with pytest.raises(WorldFileError) as info:
        vwg.io.maps.load_map(path)
    assert info.value.field == "image" and info.value.line == 1
    assert "a PNG of 20000 × 20000 = 400,000,000 pixels, over the limit of 100,000,000 pixels" in str(info.value)


@pytest.mark.parametrize(("name", "size"), [("m.png", (7, 5)), ("m.pgm", (7, 5)), ("m.bmp", (7, 5)),
                                            ("m.jpg", (16, 9)), ("m.ppm", (3, 11))])
def test_image_sizes_are_read_from_headers(tmp_path, name, size):
    import numpy as np

    from vwg.io.image_size import image_size

    width, height = size
    channels = (height, width, 3) if name.endswith((".jpg", ".ppm")) else (height, width)
    vwg._core.write_image(str(tmp_path / name), np.zeros(channels, np.uint8))
    with (tmp_path / name).open("rb") as f:
        assert image_size(f)[1:] == (width, height)


def test_image_headers_with_comments_and_unknown_formats():
    import io

    from vwg.io.image_size import ImageHeaderError, image_size

    assert image_size(io.BytesIO(b"P5\n# made by hand\n# two comments\n 640\t480\n255\n" + b"\0" * 10)) == \
        ("PNM", 640, 480)
    assert image_size(io.BytesIO(b"P7\nWIDTH 4\nHEIGHT 2\nDEPTH 1\nMAXVAL 255\nTUPLTYPE GRAYSCALE\nENDHDR\n")) == \
        ("PAM", 4, 2)
    # A JPEG whose frame header comes after an application segment and fill bytes.
    jpeg = b"\xff\xd8\xff\xe0\x00\x04ab\xff\xff\xc0\x00\x11\x08\x01\x2c\x01\x90\x03" + b"\0" * 20
    assert image_size(io.BytesIO(jpeg)) == ("JPEG", 400, 300)
    for head in (b"II*\x00" + b"\0" * 40, b"GIF89a" + b"\0" * 40, b"", b"P5\n# only a comment"):
        with pytest.raises(ImageHeaderError):
            image_size(io.BytesIO(head))


@pytest.mark.parametrize(("make", "what"), [(lambda p: os.mkfifo(p), "a named pipe"), (None, "a device")])
def test_a_map_that_is_a_device_or_a_pipe_is_named_as_such_not_as_missing(tmp_path, make, what):
    if make is None:
        target = "/dev/zero"
    else:
        target = str(tmp_path / "map.yaml")
        make(target)
    for spec in (target, f"{{movingai: {target}}}"):
        text = OFFICE.replace("map: office/map.yaml", f"map: {spec}")
        path = tmp_path / "w.yaml"
        path.write_text(text)
        with pytest.raises(WorldFileError) as info:
            vwg.robot.load_robot_world(path)
        assert f"{path}:{line_of(text, 'map:')}: map" in str(info.value) and what in str(info.value), \
            str(info.value)
        assert "not found" not in str(info.value)


def test_a_folder_named_like_a_shipped_world_runs_the_shipped_world_and_says_so(tmp_path):
    (tmp_path / "office").mkdir()
    done = vwg_cli("run", "office", "--frames", "1", "--allow-unreached", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "vwg: warning: office here is a folder, not a world file: running the shipped world office (" \
        in done.stderr and "office.yaml)" in done.stderr
    assert "vwg run office — office, planner astar" in done.stdout


@pytest.mark.parametrize("flag", ["--record", "--summary-json"])
def test_a_full_disk_is_an_error_naming_the_file(flag):
    done = vwg_cli("run", "office", "--frames", "3", flag, "/dev/full")
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert done.stderr.startswith("vwg: error: /dev/full: No space left on device: "), done.stderr


def test_a_world_file_whose_name_is_not_utf8_is_refused_for_a_record_before_it_is_started(tmp_path):
    # A record holds its world file's name as JSON text; w\xff.yaml's name cannot be (it was a
    # UnicodeEncodeError traceback once the header was written, leaving an empty record behind).
    import shutil

    shutil.copytree(ROOT / "maps" / "office", tmp_path / "office")
    name = os.fsdecode(b"w\xff.yaml")
    (tmp_path / name).write_text(OFFICE)
    done = vwg_cli("run", name, "--frames", "3", "--record", "r.jsonl", cwd=tmp_path)
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert "the name is not UTF-8 text" in done.stderr and "rename the file" in done.stderr, done.stderr
    assert not (tmp_path / "r.jsonl").exists()
    # Without a record it runs.
    assert vwg_cli("run", name, "--frames", "3", "--allow-unreached", cwd=tmp_path).returncode == 0


def test_a_record_cut_by_a_file_size_limit_says_what_it_holds(tmp_path):
    import json
    import re

    record = tmp_path / "r.jsonl"
    done = vwg_cli("run", "office", "--frames", "300", "--record", str(record), limit_file_bytes=60_000)
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    said = re.match(rf"vwg: error: {re.escape(str(record))}: File too large: the record holds its header and the "
                    r"first (\d+) frames", done.stderr)
    assert said, done.stderr
    # What it says is in the file: the header and that many frame lines whole, then at most a torn line.
    lines = record.read_bytes().split(b"\n")
    whole = [json.loads(line) for line in lines[:-1]]
    assert len(whole) == 1 + int(said[1]) and "vwg_record" in whole[0]
    assert [line["t"] for line in whole[1:]] == list(range(int(said[1])))
    assert os.path.getsize(record) <= 60_000


def test_a_map_image_turned_into_cells_a_block_of_rows_at_a_time_gives_every_row(monkeypatch):
    import numpy as np

    from vwg.io import maps

    # map_saver's grey levels: 254 free, 0 occupied, 205 unknown; row r of the image (top first) is
    # row height - 1 - r of the grid. Blocks of 7 pixels: 3 rows of this 2-wide image a block, 5 blocks.
    grey = np.array([254, 0, 205], dtype=np.uint8)
    image = np.repeat(grey[np.arange(13) % 3][:, None], 2, axis=1)
    monkeypatch.setattr(maps, "_PIXEL_ROWS", 7)
    cells = maps._pixels_to_grid(image, "trinary", False, 0.65, 0.196)
    expected = np.array([[0, 0], [100, 100], [-1, -1]], dtype=np.int8)[np.arange(13) % 3][::-1]
    assert cells.shape == (13, 2) and np.array_equal(cells, expected)


def test_a_world_name_the_system_cannot_take_is_an_error_not_a_traceback():
    # A name over the system's limit was an OSError traceback (ENAMETOOLONG) from vwg run and
    # vwg replay --world.
    from vwg.io.shipped import resolve_world

    name = "w" * 5000 + ".yaml"
    with pytest.raises(vwg.Error, match="not a file name this system takes"):
        resolve_world(name)
    with pytest.raises(vwg.Error, match="no such file"):  # a NUL byte: no file has it
        resolve_world("office\x00.yaml")
    done = vwg_cli("run", name, "--frames", "1")
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert "not a file name this system takes (File name too long)" in done.stderr, done.stderr
    assert "(5005 characters)" in done.stderr


# ---- issue 34, second hostile pass: YAML text, keys and names the readers did not expect --------------------
@pytest.mark.parametrize(("data", "line", "column", "character"), [
    (b"name: x\n# \x00\n", 2, 3, "#x0000"),            # a NUL byte in a comment
    (b"name: x\x1b[31m\nmap: y\n", 1, 8, "#x001b"),     # a raw ESC (a terminal's colour code pasted in)
    ("name: x\nmap: y\ufffe\n".encode(), 2, 7, "#xfffe"),  # U+FFFE, a noncharacter
    ("name: x\n".encode("utf-16-le"), 1, 2, "#x0000"),  # UTF-16 without its byte-order mark
    (b"\x00" * 100, 1, 1, "#x0000"),                     # head -c 100 /dev/zero
], ids=["nul", "esc", "fffe", "utf16le", "zeros"])
def test_a_character_yaml_does_not_allow_is_refused_at_its_place(tmp_path, data, line, column, character):
    # PyYAML's reader refuses these before parsing: a yaml.reader.ReaderError traceback, exit 1, before.
    path = tmp_path / "w.yaml"
    path.write_bytes(data)
    with pytest.raises(WorldFileError) as info:
        vwg.robot.load_robot_world(path)
    assert (info.value.line, info.value.column) == (line, column), str(info.value)
    assert str(info.value).startswith(f"{path}:{line}:{column}: not valid YAML: unacceptable character {character}")
    for command in (["check", str(path)], ["sweep", str(path), "-o", str(tmp_path / "out.csv")]):
        done = vwg_cli(*command)
        assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
        assert done.stderr.startswith(f"vwg: error: {path}:{line}:{column}: not valid YAML: unacceptable "
                                      f"character {character}"), done.stderr


def test_a_nul_byte_in_a_map_yaml_is_refused_at_its_place(tmp_path):
    path = tmp_path / "map.yaml"
    path.write_bytes(b"image: map.pgm\nresolution: 0.05\x00\n")
    with pytest.raises(WorldFileError) as info:
        vwg.io.maps.load_map(path)
    assert str(info.value).startswith(f"{path}:2:17: not valid YAML: unacceptable character #x0000")


@pytest.mark.parametrize(("text", "line", "column", "kind"), [
    ("name: x\n? [a, b]\n: 1\n", 2, 3, "a list"),
    ("name: x\n? {a: 1}\n: 1\n", 2, 3, "a mapping"),
    ("name: x\nrobots:\n  - {[1]: 2}\n", 3, 6, "a list"),
    ("name: x\nk: &k [1]\n*k : 2\n", 3, 1, "a list"),  # an alias of a list as the key
])
def test_a_key_that_is_a_list_or_a_mapping_is_refused_at_its_place(tmp_path, text, line, column, kind):
    # A TypeError (unhashable type: 'list') traceback before.
    path = tmp_path / "w.yaml"
    path.write_text(text)
    with pytest.raises(WorldFileError) as info:
        vwg.robot.load_robot_world(path)
    assert str(info.value) == f"{path}:{line}:{column}: a key must be text or a number, got {kind}"
    done = vwg_cli("check", str(path))
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert done.stderr.startswith(f"vwg: error: {path}:{line}:{column}: a key must be text or a number"), done.stderr


def test_a_sweep_spec_with_a_list_as_a_key_is_refused_at_its_place(tmp_path):
    spec = tmp_path / "spec.yaml"
    spec.write_text("worlds: [office]\nplanners: [astar]\nseeds: 1\nframes: 3\n? [a]\n: 1\n")
    done = vwg_cli("sweep", str(spec), "-o", str(tmp_path / "out.csv"))
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert done.stderr.startswith(f"vwg: error: {spec}:5:3: a key must be text or a number, got a list"), done.stderr


NO_USER = "vwg-h8-no-such-user"  # a user no test machine has


def test_a_home_folder_of_no_user_is_an_error_naming_the_user(tmp_path):
    # Path.expanduser raised RuntimeError("Could not determine home directory.") for ~nosuchuser.
    from vwg.io.shipped import resolve_world

    with pytest.raises(vwg.Error, match=f"^~{NO_USER}/w.yaml: no user {NO_USER}$"):
        resolve_world(f"~{NO_USER}/w.yaml")
    done = vwg_cli("check", f"~{NO_USER}/w.yaml")
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert done.stderr.startswith(f"vwg: error: ~{NO_USER}/w.yaml: no user {NO_USER}"), done.stderr


@pytest.mark.parametrize("where", ["world map", "movingai map", "map image"])
def test_a_home_folder_of_no_user_in_a_file_is_named_by_its_line(tmp_path, where):
    if where == "map image":
        path = tmp_path / "map.yaml"
        path.write_text(f"image: ~{NO_USER}/map.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
                        "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
        load, line, field = vwg.io.maps.load_map, 1, "image"
    else:
        ref = f'"~{NO_USER}/map.yaml"' if where == "world map" else f'{{movingai: "~{NO_USER}/x.map"}}'
        path = world_file(tmp_path, OFFICE.replace("map: office/map.yaml", f"map: {ref}"))
        load, line = vwg.robot.load_robot_world, line_of(OFFICE, "map: office/map.yaml")
        field = "map" if where == "world map" else "map.movingai"
    with pytest.raises(WorldFileError) as info:
        load(path)
    assert str(info.value).startswith(f"{path}:{line}: {field}: ~{NO_USER}/"), str(info.value)
    assert str(info.value).endswith(f": no user {NO_USER}"), str(info.value)
    done = vwg_cli("check", str(path)) if where != "map image" else None
    if done is not None:
        assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
        assert done.stderr.startswith(f"vwg: error: {path}:{line}: {field}: ~{NO_USER}/"), done.stderr


@pytest.mark.parametrize(("world", "words"), [
    (f"~{NO_USER}/w.yaml", f"~{NO_USER}/w.yaml: no user {NO_USER}"),
    # Over the system's limit for a name (ENAMETOOLONG from is_file: an OSError traceback before).
    ("a" * 5000, "a" * 60 + "... (5000 characters): not a file name this system takes (File name too long)"),
])
def test_a_sweep_spec_naming_a_world_no_system_has_is_refused_at_its_place(tmp_path, world, words):
    spec = tmp_path / "spec.yaml"
    spec.write_text(f'worlds: ["{world}"]\nplanners: [astar]\nseeds: 1\nframes: 3\n')
    done = vwg_cli("sweep", str(spec), "-o", str(tmp_path / "out.csv"))
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert done.stderr.startswith(f"vwg: error: {spec}:1: worlds[0]: {words}"), done.stderr


MERGED_ROBOTS = """robots:
  - &first {id: 1, start: [1.5, 9.0, 0.0], sensors: [laser, camera]}
  - <<: *first
    id: 2
    start: [23.5, 9.0, 3.141592653589793]
"""


def test_a_key_overriding_a_merged_key_is_no_duplicate(tmp_path):
    # YAML's merge key (<<: *first) gives a mapping the keys of another, which its own keys override;
    # PyYAML puts the merged keys into the mapping's node, and they were called duplicate keys.
    start = OFFICE.index("robots:")
    text = OFFICE[:start] + MERGED_ROBOTS + OFFICE[OFFICE.index("frames:"):]
    world = vwg.robot.load_robot_world(world_file(tmp_path, text))
    assert [(r.id, tuple(r.start), r.sensors) for r in world.robots] == [
        (1, (1.5, 9.0, 0.0), ("laser", "camera")), (2, (23.5, 9.0, 3.141592653589793), ("laser", "camera"))]
    # A key given twice by the mapping itself still is one.
    twice = OFFICE[:start] + MERGED_ROBOTS.replace("    id: 2\n", "    id: 2\n    id: 3\n") + \
        OFFICE[OFFICE.index("frames:"):]
    with pytest.raises(WorldFileError) as info:
        vwg.robot.load_robot_world(world_file(tmp_path, twice))
    assert "robots[1].id: duplicate key" in str(info.value) and info.value.line == line_of(twice, "id: 3")


def test_a_platform_that_takes_no_options_says_so(tmp_path):
    # "unknown key (expected one of )" before: the sim platform has no options to list.
    path = world_file(tmp_path, OFFICE + "platform: {kind: sim, extra: 1}\n")
    with pytest.raises(WorldFileError) as info:
        vwg.robot.load_robot_world(path)
    line = OFFICE.count("\n") + 1
    assert str(info.value) == f"{path}:{line}: platform.extra: unknown key (the sim platform takes no options)"


@pytest.mark.parametrize(("flag", "value", "words"), [
    ("--planner", "", "argument --planner: expected a planner's name, got ''"),
    ("--planner", " ", "argument --planner: expected a planner's name, got ' '"),
    ("--goal", ":", "argument --goal: expected ROOM or ROBOT:ROOM, got ':'"),
    ("--goal", "", "argument --goal: expected ROOM or ROBOT:ROOM, got ''"),
    ("--goal", "1:", "argument --goal: expected ROOM or ROBOT:ROOM, got '1:'"),
])
def test_an_empty_planner_or_room_on_the_command_line_is_refused(flag, value, words):
    # --planner "" ran astar silently; --goal ':' said "unknown room ''".
    done = vwg_cli("run", "office", "--frames", "1", "--allow-unreached", flag, value)
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert words in done.stderr and "vwg run" not in done.stdout, done.stderr
