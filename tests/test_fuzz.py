"""Fuzzing the readers of what users and robots send: the text form, events, world files, MovingAI and
map_server maps, the rosbridge messages and the serial base's answers. Each starts from a seed corpus
in the repository (tests/fuzz_corpus/, the shipped worlds, tests/data/movingai) and mutates it with
Hypothesis. The corpora hold the hostile inputs found so far (tests/fuzz_corpus/world, mapyaml,
movingai, image: recursive aliases, deep nesting, huge integers, 1e308 and 5e-324, headers of
images of billions of pixels), and numbers near the limits of floats and of the engine's integers
are put into world files and maps. Whatever comes in, the reader either succeeds (and what it gives
holds: the string prints and reads back, the numbers are finite) or refuses with its own error naming
where; never another exception, a crash or a hang. A record that reads is also replayed (`vwg replay`
exits 0 or 2), and records are forged field by field too: any JSON value in any field, the links
made whole again.

``make test`` runs a bounded number of inputs per reader (VWG_FUZZ_EXAMPLES, default 150);
``make fuzz`` runs many more. A crash found becomes an explicit @example here.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import vwg
from conftest import ROOT, make_world
from vwg.errors import Error, ParseError, WorldFileError
from vwg.robot.links import ros_messages
from vwg.robot.platforms.serial_base import encoder_counts

CORPUS = ROOT / "tests" / "fuzz_corpus"
EXAMPLES = int(os.environ.get("VWG_FUZZ_EXAMPLES", "150"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                             HealthCheck.function_scoped_fixture])


def corpus(kind: str) -> list[str]:
    return [p.read_text(encoding="utf-8") for p in sorted((CORPUS / kind).iterdir())]


def corpus_files(kind: str) -> list[Path]:
    return sorted((CORPUS / kind).iterdir())


def yaml_number(x: float) -> str:
    """A float as YAML 1.1 reads it back as a float: with a dot before the exponent (PyYAML reads
    ``1e+308`` as text) and .inf / .nan."""
    if math.isnan(x):
        return ".nan"
    if math.isinf(x):
        return ".inf" if x > 0 else "-.inf"
    text = repr(x)
    mantissa, e, exponent = text.partition("e")
    if e and "." not in mantissa:
        mantissa += ".0"
    return mantissa + (f"e{exponent if exponent[0] in '+-' else '+' + exponent}" if e else "")


# Near the ends of floats and of the engine's integers (seeds and frames are unsigned 64-bit), and
# the limits vwg puts on them (dt from 1e-6 s, coordinates within ±1e6 m, 100-digit integers).
EDGE_FLOATS = [1.7976931348623157e308, 1e308, -1e308, 5e-324, -5e-324, 2.2250738585072014e-308, 1e-320, 1e-6,
               9.99e-7, 1e6, -1e6, 1000000.0000000001, 3600.0, 3600.0000000000005, 1e9, 1e15, 2.0**63, 2.0**64,
               math.inf, math.nan]
EDGE_INTS = [2**63 - 1, 2**63, 2**64 - 1, 2**64, -(2**63), 10**99, 10**100, 0, -1]
NUMBER = st.one_of(st.sampled_from(EDGE_FLOATS).map(yaml_number), st.floats().map(yaml_number),
                   st.sampled_from(EDGE_INTS).map(str), st.integers().map(str),
                   st.integers(90, 5000).map(lambda n: "9" * n))


# Characters that matter to the readers, then any character at all.
SPECIAL = [*"<>()=,.\"\\ \n\r\t@{}[]:-+#&*!|'", "\\u", "\\uD800", "\\uDC00", "1e+400", "nan", "é", "\u2028",
           "\udcff", "\x00", "ε", "·", "1" * 30]
TOKEN = st.one_of(st.sampled_from(SPECIAL), st.text(min_size=1, max_size=4))


@st.composite
def mutated(draw: st.DrawFn, seeds: list[str]) -> str:
    """A seed with a few insertions, deletions and duplications."""
    text = draw(st.sampled_from(seeds))
    for _ in range(draw(st.integers(0, 6))):
        at = draw(st.integers(0, len(text)))
        op = draw(st.sampled_from(["insert", "delete", "duplicate"]))
        if op == "insert":
            text = text[:at] + draw(TOKEN) + text[at:]
        elif op == "delete":
            text = text[:at] + text[at + draw(st.integers(1, 8)):]
        else:
            end = min(len(text), at + draw(st.integers(1, 20)))
            text = text[:end] + text[at:end] + text[end:]
    return text


# ---- the text form and events -----------------------------------------------------------------------------
WORLD = make_world()


@FUZZ
@given(mutated(corpus("text")))
@example('Dot<s="\\uDC00">')
@example("L" * 199 + "é")
@example("Lamp\udcff")
def test_the_text_form_reads_or_refuses(text):
    try:
        w = WORLD.parse(text, source="<fuzz>")
    except ParseError as e:
        assert e.line >= 1 and e.column >= 1
        str(e).encode("utf-8")  # the message prints
        return
    assert WORLD.parse(str(w)) == w  # what it read prints and reads back


@FUZZ
@given(mutated(["add<k=3>", "mul<to=2, k=-1>", "tick", "die<to=7>"]))
def test_events_read_or_refuse(text):
    try:
        WORLD.alphabet.parse_event(text, "<fuzz>")
    except ParseError as e:
        assert e.line >= 1 and e.column >= 1


# ---- world files and maps ---------------------------------------------------------------------------------
WORLD_SEEDS = [(ROOT / "maps" / f"{name}.yaml").read_text() for name in ("office", "maze")] + corpus("world")
VALUES = ["-1", "0", "1.0e+39", "1.0e+400", ".nan", ".inf", "-.inf", "[]", "{}", '"x"', "999999999999999999999999",
          "true", "null", "[1, 2]", "[1.0e+39, 0, 0]", "*a", "&a 1", "!!binary aGk=", "1e9", "~", "'\\udcff'"]


@st.composite
def world_text(draw: st.DrawFn) -> str:
    lines = draw(st.sampled_from(WORLD_SEEDS)).splitlines()
    for _ in range(draw(st.integers(1, 4))):
        i = draw(st.integers(0, len(lines) - 1))
        op = draw(st.sampled_from(["value", "number", "delete", "duplicate", "indent"]))
        if op == "value" and ":" in lines[i]:
            key = lines[i].split(":", 1)[0]
            lines[i] = f"{key}: {draw(st.sampled_from(VALUES))}"
        elif op == "number" and ":" in lines[i]:
            lines[i] = with_number(lines[i], draw(NUMBER), draw(st.integers(0, 2)))
        elif op == "delete":
            del lines[i]
        elif op == "duplicate":
            lines.insert(i, lines[i])
        else:
            lines[i] = "  " + lines[i]
        if not lines:
            break
    return "\n".join(lines)


def with_number(line: str, number: str, index: int) -> str:
    """`line` (``key: value``) with its value, or one item of its list value, replaced by `number`."""
    key, _, value = line.partition(":")
    value = value.strip()
    if value.startswith("[") and value.endswith("]"):
        items = [v.strip() for v in value[1:-1].split(",")]
        items[index % len(items)] = number
        return f"{key}: [{', '.join(items)}]"
    return f"{key}: {number}"


@FUZZ
@given(world_text())
@example((CORPUS / "world" / "alias_loop.yaml").read_text())
@example((CORPUS / "world" / "deep_lists.yaml").read_text())
@example((CORPUS / "world" / "room_at_1e308.yaml").read_text())
def test_world_files_load_or_refuse_by_place(tmp_path_factory, text):
    folder = tmp_path_factory.mktemp("w")
    for name in ("office", "maze"):
        text = text.replace(f"map: {name}/map.yaml", f"map: {ROOT / 'maps' / name / 'map.yaml'}")
    path = folder / "w.yaml"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    try:
        world = vwg.robot.load_robot_world(path)
    except Error as e:
        assert str(path) in str(e) or "ARobot" in str(e), str(e)
        return
    assert all(math.isfinite(v) for r in world.robots for v in r.start)


MOVINGAI = [(ROOT / "tests" / "data" / "movingai" / "arena.map").read_text(), *corpus("movingai")]


@FUZZ
@given(mutated(MOVINGAI))
def test_movingai_maps_load_or_refuse(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("m") / "x.map"
    path.write_bytes(text.encode("utf-8", errors="surrogatepass"))
    try:
        grid = vwg.io.maps.load_movingai(path)
    except WorldFileError as e:
        assert str(path) in str(e)
        return
    assert grid.data.ndim == 2 and grid.data.size > 0


@FUZZ
@given(st.binary(max_size=300), st.sampled_from([b"", b"P5\n4 4\n255\n", b"P2\n2 2\n255\n", b"\x89PNG\r\n\x1a\n",
                                                *(p.read_bytes() for p in corpus_files("image"))]))
def test_map_images_load_or_refuse(tmp_path_factory, body, head):
    folder = tmp_path_factory.mktemp("img")
    (folder / "m.pgm").write_bytes(head + body)
    (folder / "m.yaml").write_text("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
                                   "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    try:
        grid = vwg.io.maps.load_map(folder / "m.yaml")
    except WorldFileError as e:
        assert str(folder) in str(e)
        return
    assert grid.data.size > 0


@st.composite
def map_yaml(draw: st.DrawFn) -> str:
    """A map_server YAML of the corpus with numbers near the limits for its numbers."""
    lines = draw(st.sampled_from(corpus("mapyaml"))).splitlines()
    for _ in range(draw(st.integers(1, 3))):
        i = draw(st.integers(0, len(lines) - 1))
        if not lines[i].startswith("image:"):
            lines[i] = with_number(lines[i], draw(NUMBER), draw(st.integers(0, 2)))
    return "\n".join(lines) + "\n"


MAP_IMAGE = (ROOT / "tests" / "data" / "rosmaps" / "map_server_test" / "testmap.png").read_bytes()


@FUZZ
@given(map_yaml())
@example((CORPUS / "mapyaml" / "origin_1e308.yaml").read_text())
def test_map_yaml_numbers_load_or_refuse_by_place(tmp_path_factory, text):
    folder = tmp_path_factory.mktemp("mapyaml")
    (folder / "map.png").write_bytes(MAP_IMAGE)
    (folder / "m.yaml").write_text(text)
    try:
        grid = vwg.io.maps.load_map(folder / "m.yaml")
    except WorldFileError as e:
        assert str(folder / "m.yaml") in str(e), str(e)
        return
    assert math.isfinite(grid.resolution) and all(math.isfinite(v) for v in grid.origin)
    # Every point of the map has a cell, and a point beyond float range is outside it.
    assert grid.inside(*grid.world_to_cell(*grid.cell_to_world(0, 0)))
    assert not grid.contains(1e308, -1e308)


@pytest.mark.parametrize("path", corpus_files("world") + corpus_files("mapyaml") + corpus_files("movingai"),
                         ids=lambda p: f"{p.parent.name}/{p.name}")
def test_the_hostile_seeds_are_refused_by_place(tmp_path, path):
    """Each hostile input of the corpora as it is: refused with vwg's error naming the file."""
    if path.parent.name == "mapyaml":
        (tmp_path / "map.png").write_bytes(MAP_IMAGE)
        target = tmp_path / path.name
        target.write_text(path.read_text())
        load = vwg.io.maps.load_map
    elif path.parent.name == "world":
        target = tmp_path / path.name
        target.write_text(path.read_text().replace("map: office/map.yaml",
                                                   f"map: {ROOT / 'maps' / 'office' / 'map.yaml'}"))
        load = vwg.robot.load_robot_world
    else:
        target, load = path, vwg.io.maps.load_movingai
    if path.name == "plain.yaml":
        load(target)  # the corpus's one good map: it loads
        return
    with pytest.raises(WorldFileError) as info:
        load(target)
    assert str(info.value).startswith(str(target)) or str(target) in str(info.value), str(info.value)


# ---- records (vwg replay's reader) ------------------------------------------------------------------------
# The seeds: records that read (folder, blobs, small; lamp, of a world that names no code, also replays)
# and issue 34's hostile ones, each refused by line.
RECORD_SEEDS = corpus("record")
GOOD_RECORDS = {"folder.jsonl", "blobs.jsonl", "small.jsonl", "lamp.jsonl"}
REPLAY_FRAMES = 20  # a record that reads is also replayed (vwg replay) when it holds at most this many frames


def relinked(text: str) -> str:
    """A record's text with each line's link made whole again (prev, and the end line's self), without
    reading the lines as JSON: the mutations reach the reader's checks behind the chain."""
    import hashlib
    import re

    def link(line: str) -> str:
        return hashlib.sha256(line.encode("utf-8", "surrogatepass")).hexdigest()[:32]

    lines = text.split("\n")
    for i in range(1, len(lines)):
        line = re.sub('"prev":"[0-9a-f]{32}"', f'"prev":"{link(lines[i - 1])}"', lines[i])
        if line.startswith('{"end":true') and line.endswith("}"):
            body = re.sub(',"self":"[0-9a-f]{32}"', "", line)
            line = body[:-1] + f',"self":"{link(body)}"}}'
        lines[i] = line
    return "\n".join(lines)


@FUZZ
@given(mutated(RECORD_SEEDS), st.booleans())
def test_records_read_or_refuse(tmp_path_factory, text, relink):
    from vwg.io.record import read_record

    path = tmp_path_factory.mktemp("record") / "fuzz.jsonl"
    path.write_bytes((relinked(text) if relink else text).encode("utf-8", "surrogatepass"))
    try:
        record = read_record(path)
    except WorldFileError as e:
        assert e.path == str(path) and e.line >= 0
        str(e).encode("utf-8", "backslashreplace")
        return
    assert all(isinstance(t, str) for f in record.frames for t in f["events"])
    assert record.end is None or record.end["frames"] == len(record.frames)
    if len(record.frames) <= REPLAY_FRAMES:
        assert_replays_or_refuses(path)


def assert_replays_or_refuses(path: Path) -> None:
    """vwg replay of a record that reads: exit 0 (replayed) or 2 (refused, with vwg's error), never a
    traceback (an exception out of main, or one printed) nor a failed frame (a world that names no
    code has none that could fail)."""
    import contextlib
    import io

    from vwg.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(["replay", str(path)])
    assert status in (0, 2), (status, err.getvalue())
    assert "Traceback" not in err.getvalue(), err.getvalue()
    assert status == 0 or err.getvalue().startswith("vwg: error: "), err.getvalue()


# Any JSON value a forger might put in a field: null, the ends of the engine's integers and of floats,
# a 400-digit integer, texts with a NUL byte, lists and objects.
RECORD_VALUES = st.one_of(
    st.none(), st.sampled_from([*EDGE_INTS, 10**400, -(10**400), 2**31, 1e9 + 1, 1e-7, -1.5, True]),
    st.integers(), st.floats(allow_nan=False, allow_infinity=False),
    st.sampled_from(["", "\x00", "office", "a\x00b", "x" * 5000, "nosuch", "robot", "bogus"]), st.text(max_size=8),
    st.recursive(st.none() | st.integers() | st.text(max_size=4),
                 lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3),
                 max_leaves=6))


@st.composite
def record_with_a_field_changed(draw: st.DrawFn) -> str:
    """lamp.jsonl (a record that replays) with one to three fields of its lines set to any value or
    removed, each line's links made whole again: what a forger who knows the format can make."""
    lines = [json.loads(x) for x in (CORPUS / "record" / "lamp.jsonl").read_text().splitlines()]
    for _ in range(draw(st.integers(1, 3))):
        n = draw(st.sampled_from([0, 0, 0, 1, -1, -1]))  # mostly the header and the end line: most fields
        paths = [q for q in leaves(lines[n]) if q and q[0] not in ("prev", "self")]
        where = draw(st.sampled_from(paths))
        parent = lines[n]
        for key in where[:-1]:
            parent = parent[key]
        if draw(st.booleans()) or not isinstance(parent, dict):
            parent[where[-1]] = draw(RECORD_VALUES)
        else:
            del parent[where[-1]]
    return relinked("\n".join(json.dumps(x, ensure_ascii=False, separators=(",", ":")) for x in lines) + "\n")


@FUZZ
@given(record_with_a_field_changed())
def test_a_record_with_any_value_in_a_field_replays_or_is_refused(tmp_path_factory, text):
    from vwg.io.record import read_record

    path = tmp_path_factory.mktemp("record") / "forged.jsonl"
    path.write_bytes(text.encode("utf-8", "surrogatepass"))
    try:
        read_record(path)
    except WorldFileError as e:
        assert e.path == str(path) and e.line >= 1, str(e)
        return
    assert_replays_or_refuses(path)


@pytest.mark.parametrize("path", corpus_files("record"), ids=lambda p: p.name)
def test_the_record_seeds_read_or_are_refused_by_line(path):
    from vwg.io.record import read_record

    if path.name in GOOD_RECORDS:
        read_record(path)
        assert_replays_or_refuses(path)
        return
    with pytest.raises(WorldFileError) as e:
        read_record(path)
    assert e.value.line >= 1, str(e.value)


# ---- what robots send ---------------------------------------------------------------------------------------
ROS_SEEDS = {p.stem: json.loads(p.read_text()) for p in sorted((CORPUS / "ros").iterdir())}
JSON_VALUES = st.recursive(st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=5),
                           lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=6), inner,
                                                                                       max_size=4), max_leaves=8)


def leaves(obj, path=()):
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from leaves(v, (*path, k))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from leaves(v, (*path, i))
    yield path


@st.composite
def ros_message(draw: st.DrawFn) -> tuple[str, object]:
    name = draw(st.sampled_from(sorted(ROS_SEEDS)))
    msg = json.loads(json.dumps(ROS_SEEDS[name]))
    for _ in range(draw(st.integers(1, 3))):
        paths = [p for p in leaves(msg) if p]
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        parent = msg
        for key in path[:-1]:
            parent = parent[key]
        if draw(st.booleans()):
            parent[path[-1]] = draw(JSON_VALUES)
        elif isinstance(parent, dict):
            del parent[path[-1]]
    return name, msg


READERS = {"odometry": ros_messages.odometry, "odometry_ros2": ros_messages.odometry, "scan": ros_messages.laser_scan,
           "image": ros_messages.compressed_image, "twist": ros_messages.twist_of}


@FUZZ
@given(ros_message())
def test_ros_messages_read_or_refuse_by_field(case):
    name, msg = case
    try:
        out = READERS[name](msg)
    except ValueError as e:
        assert str(e)  # names the field and what was expected
        return
    if name.startswith("odometry"):
        assert all(math.isfinite(v) for v in (out.x, out.y, out.yaw, out.speed, out.turn_rate))
    elif name == "scan":
        assert out.ranges.dtype == np.float32 and out.ranges.ndim == 1
        dist, angle = vwg._core.laser_events(out.ranges, out.angle_min, out.angle_increment, out.range_min,
                                             out.range_max)
        assert len(dist) == len(angle) <= len(out.ranges) and all(out.range_min <= d < out.range_max for d in dist)
    elif name == "twist":
        assert all(isinstance(v, float) for v in out)


@FUZZ
@given(st.one_of(mutated(corpus("serial")), st.text(max_size=40)))
@example("99999999999999999999999 0")
@example("--0\n-0\n")  # found by this test: a sign twice
@example("١٢ ٣")  # digits, but not ASCII ones
def test_the_serial_bases_answers_read_or_refuse(reply):
    try:
        left, right = encoder_counts(reply)
    except ValueError as e:
        assert "encoders" in str(e)
        return
    assert -(2**31) <= left < 2**31 and -(2**31) <= right < 2**31


def test_the_corpora_are_there():
    assert len(corpus("text")) >= 5 and len(ROS_SEEDS) >= 5 and len(corpus("serial")) >= 2
    for text in corpus("text"):
        WORLD.parse(text)  # the seeds themselves read


@pytest.mark.parametrize("name", sorted(ROS_SEEDS))
def test_the_ros_seeds_read(name):
    READERS[name](ROS_SEEDS[name])
