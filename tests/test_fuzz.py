"""Fuzzing the readers of what users and robots send: the text form, events, world files, MovingAI and
map_server maps, the rosbridge messages and the serial base's answers. Each starts from a seed corpus
in the repository (tests/fuzz_corpus/, the shipped worlds, tests/data/movingai) and mutates it with
Hypothesis. Whatever comes in, the reader either succeeds (and what it gives holds: the string prints
and reads back, the numbers are finite) or refuses with its own error naming where; never another
exception, a crash or a hang.

``make test`` runs a bounded number of inputs per reader (VWG_FUZZ_EXAMPLES, default 150);
``make fuzz`` runs many more. A crash found becomes an explicit @example here.
"""

from __future__ import annotations

import json
import math
import os

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import vwg
from conftest import ROOT, make_world
from vwg import ros_messages
from vwg.errors import Error, ParseError, WorldFileError
from vwg.serial_platform import encoder_counts

CORPUS = ROOT / "tests" / "fuzz_corpus"
EXAMPLES = int(os.environ.get("VWG_FUZZ_EXAMPLES", "150"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                             HealthCheck.function_scoped_fixture])


def corpus(kind: str) -> list[str]:
    return [p.read_text(encoding="utf-8") for p in sorted((CORPUS / kind).iterdir())]


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
WORLD_SEEDS = [(ROOT / "maps" / f"{name}.yaml").read_text() for name in ("office", "maze")]
VALUES = ["-1", "0", "1.0e+39", "1.0e+400", ".nan", ".inf", "-.inf", "[]", "{}", '"x"', "999999999999999999999999",
          "true", "null", "[1, 2]", "[1.0e+39, 0, 0]", "*a", "&a 1", "!!binary aGk=", "1e9", "~", "'\\udcff'"]


@st.composite
def world_text(draw: st.DrawFn) -> str:
    lines = draw(st.sampled_from(WORLD_SEEDS)).splitlines()
    for _ in range(draw(st.integers(1, 4))):
        i = draw(st.integers(0, len(lines) - 1))
        op = draw(st.sampled_from(["value", "delete", "duplicate", "indent"]))
        if op == "value" and ":" in lines[i]:
            key = lines[i].split(":", 1)[0]
            lines[i] = f"{key}: {draw(st.sampled_from(VALUES))}"
        elif op == "delete":
            del lines[i]
        elif op == "duplicate":
            lines.insert(i, lines[i])
        else:
            lines[i] = "  " + lines[i]
        if not lines:
            break
    return "\n".join(lines)


@FUZZ
@given(world_text())
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


MOVINGAI = [(ROOT / "tests" / "data" / "movingai" / "arena.map").read_text()]


@FUZZ
@given(mutated(MOVINGAI))
def test_movingai_maps_load_or_refuse(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("m") / "x.map"
    path.write_bytes(text.encode("utf-8", errors="surrogatepass"))
    try:
        grid = vwg.maps.load_movingai(path)
    except WorldFileError as e:
        assert str(path) in str(e)
        return
    assert grid.data.ndim == 2 and grid.data.size > 0


@FUZZ
@given(st.binary(max_size=300), st.sampled_from([b"", b"P5\n4 4\n255\n", b"P2\n2 2\n255\n", b"\x89PNG\r\n\x1a\n"]))
def test_map_images_load_or_refuse(tmp_path_factory, body, head):
    folder = tmp_path_factory.mktemp("img")
    (folder / "m.pgm").write_bytes(head + body)
    (folder / "m.yaml").write_text("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
                                   "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    try:
        grid = vwg.maps.load_map(folder / "m.yaml")
    except WorldFileError as e:
        assert str(folder) in str(e)
        return
    assert grid.data.size > 0


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
        assert len(out.angles) == len(out.ranges) and all(out.range_min <= r <= out.range_max for r in out.ranges)
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
