"""Hostile saved-run state files (issue 36): truncated files, a flipped byte in each part of the layout,
another vwg or format, a world file or map changed since, and well-formed files (their hashes right)
whose parts a forger wrote: the C++ parts (the simulator's journal, the deciders' grids and D* Lite
searches, the generators' random streams and orders), the manifest's fields and a Python generator's
kept attributes (vwg.model.state). Whatever comes in, reading and resuming either succeed or raise
vwg.errors.Error naming the file or the part; never another exception, a crash or a hang, and reading a
state imports no code.

The layout is worked out here from vwg.io.state_file's description, not from its code: b"vwg-state\\n",
a u64 length and the manifest's JSON, the parts (zlib) in the manifest's order with its "bytes" sizes,
then 32 bytes of SHA-256 of the manifest and 32 of everything before them. The C++ parts' layouts are
those their save() functions write (planners.cpp, planning_map.cpp, blocked_grid.cpp,
dstar_lite_search.hpp, filled_array.hpp, physics.cpp).

What would crash the process (a segfault) runs in a child process, which reports case by case.
tests/fuzz_corpus/state/ holds hostile files (small: the office with A*, a few KB); regenerate them with
``PYTHONPATH=python python tests/test_state_hostile.py --write-corpus``.
"""

from __future__ import annotations

import hashlib
import json
import os
import random
import shutil
import struct
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import vwg
import vwg._core as _core
from vwg.errors import Error, SchemaError
from vwg.io.state_file import FORMAT, read_state, write_state
from vwg.launch import RunOptions, load, run_inputs, start
from vwg.model.state import MAX_DEPTH, capture, restore
from vwg.saved_run import read_state_file, resume

ROOT = Path(__file__).resolve().parents[1]
CORPUS = ROOT / "tests" / "fuzz_corpus" / "state"
EXAMPLES = int(os.environ.get("VWG_FUZZ_EXAMPLES", "150"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])
# Each example of these resumes a run (~0.1 s): a third as many.
FUZZ_RESUME = settings(max_examples=max(10, EXAMPLES // 3), deadline=None, suppress_health_check=[HealthCheck.too_slow])

MAGIC = b"vwg-state\n"
U64 = struct.Struct("<Q")
I64 = struct.Struct("<q")
F64 = struct.Struct("<d")


# ---- the layout, as documented ----------------------------------------------------------------------------
def regions(data: bytes) -> dict[str, tuple[int, int]]:
    """Where each region of a state file is: [start, end) of the magic, the manifest's length, the
    manifest, each part (by name) and the two hashes."""
    (n,) = U64.unpack_from(data, len(MAGIC))
    at = len(MAGIC) + 8
    out = {"magic": (0, len(MAGIC)), "length": (len(MAGIC), at), "manifest": (at, at + n)}
    at += n
    for entry in json.loads(data[out["manifest"][0]:out["manifest"][1]])["parts"]:
        out[f"part {entry['name']}"] = (at, at + entry["bytes"])
        at += entry["bytes"]
    out["manifest hash"] = (at, at + 32)
    out["file hash"] = (at + 32, at + 64)
    assert at + 64 == len(data)
    return out


def forge(head: bytes, body: bytes = b"") -> bytes:
    """A state file with this manifest text and these stored parts, its hashes right."""
    data = MAGIC + U64.pack(len(head)) + head + body + hashlib.sha256(head).digest()
    return data + hashlib.sha256(data).digest()


def flip(data: bytes, at: int, bits: int = 0x01) -> bytes:
    return data[:at] + bytes([data[at] ^ bits]) + data[at + 1:]


def rewrap(data: bytes, manifest: dict[str, Any] | None = None, parts: dict[str, bytes] | None = None,
           drop: tuple[str, ...] = ()) -> bytes:
    """`data` written again (its checksums right) with these manifest fields and raw parts."""
    saved = read_state(data, "<test>")
    fields = {k: v for k, v in saved.manifest.items() if k not in ("parts", "format")}
    if fields.get("world_file") == "office":  # a corpus file (kept path-free): this checkout's office world
        fields.update(world_file=str(Path(load("office").path).resolve()), inputs={
            role: {"path": str(Path(p).resolve()), "sha256": hashlib.sha256(Path(p).read_bytes()).hexdigest()}
            for role, p in run_inputs(load("office")).items()})
    fields.update(manifest or {})
    for key in drop:
        fields.pop(key, None)
    return write_state(fields, {**saved.parts, **(parts or {})})


def unpack_list(data: bytes) -> list[tuple[str, bytes]]:
    """The parts 'generators' and 'actors': u64 count, then each name and bytes with a u64 length."""
    (count,), at, items = U64.unpack_from(data, 0), 8, []
    for _ in range(count):
        (n,) = U64.unpack_from(data, at)
        name = data[at + 8:at + 8 + n].decode("utf-8")
        at += 8 + n
        (n,) = U64.unpack_from(data, at)
        items.append((name, data[at + 8:at + 8 + n]))
        at += 8 + n
    assert at == len(data)
    return items


def pack_list(items: list[tuple[str, bytes]]) -> bytes:
    out = U64.pack(len(items))
    for name, blob in items:
        out += U64.pack(len(name.encode())) + name.encode() + U64.pack(len(blob)) + blob
    return out


def with_item(data: bytes, part: str, index: int, blob: bytes) -> bytes:
    """`data` with the state of generator or actor type `index` (of `part`) replaced by `blob`."""
    items = unpack_list(read_state(data, "<test>").parts[part])
    items[index] = (items[index][0], blob)
    return rewrap(data, parts={part: pack_list(items)})


def journal_with(data: bytes, extra: bytes) -> bytes:
    """The simulator's journal (u64 format, u64 fingerprint, u64 length, the entries) with `extra`
    entries after its own."""
    platform = read_state(data, "<test>").parts["platform"]
    fmt, fingerprint, n = struct.unpack_from("<QQQ", platform)
    journal = platform[24:24 + n] + extra
    return rewrap(data, parts={"platform": struct.pack("<QQQ", fmt, fingerprint, len(journal)) + journal})


# The simulator journal's entries (physics.cpp): one byte for the call, then its arguments.
ADD_ROBOT, REMOVE_ROBOT, COMMAND, DRIVE, ADVANCE, TAKE_COLLISIONS = range(1, 7)


class GridState:
    """A GridDecider's saved state (astar, dstar) read field by field, so one field can be set:
    ``fields[name] = (offset, size)``."""

    def __init__(self, data: bytes) -> None:
        self.data, self.at, self.fields = data, 0, {}
        self.take("name", self.u64("name.length"))
        for k in range(self.u64("robots")):
            self.robot(f"r{k}.")
        assert self.at == len(data)

    def take(self, name: str, n: int) -> bytes:
        self.fields.setdefault(name, (self.at, n))
        self.at += n
        return self.data[self.at - n:self.at]

    def u64(self, name: str) -> int:
        return U64.unpack(self.take(name, 8))[0]

    def grid(self, name: str) -> None:  # BlockedGrid::save: rows, cols, a bit a cell, rows in whole bytes
        rows, cols = I64.unpack(self.take(name + ".rows", 8))[0], I64.unpack(self.take(name + ".cols", 8))[0]
        self.take(name + ".cells", rows * ((cols + 7) // 8))

    def robot(self, p: str) -> None:
        self.take(p + "id", 8)
        self.take(p + "map.radius", 8)  # PlanningMap::save: the radius, then its obstacles
        self.grid(p + "map")
        if self.take(p + "has_dstar", 1)[0]:
            d = p + "dstar."
            exact = self.take(d + "exact", 1)[0]  # DStarLite::save, then DStarLiteSearch::save
            self.grid(d + "grid")
            for f in ("diagonal", "corner_cutting", "heuristic"):
                self.take(d + f, 1)
            for f in ("start.row", "start.col", "goal.row", "goal.col", "start_node", "goal_node", "last_node", "km"):
                self.take(d + f, 8)
            for array, width in (("g", 4 if exact else 8), ("rhs", 4 if exact else 8), ("slot", 4)):
                self.take(d + array + ".fill", 8)
                self.take(d + array + ".bits", width * self.u64(d + array + ".size"))
            self.take(d + "queue", (16 if exact else 24) * self.u64(d + "queue.count"))
            for f, n in (("expanded", 8), ("dive", 1), ("exact_keys", 1)):
                self.take(d + f, n)
        self.take(p + "goal", 16)
        self.take(p + "noway.known", 1)  # NoWayMemo::save
        self.take(p + "noway.size", 16)
        self.take(p + "noway.side", 8 * self.u64(p + "noway.side.count"))
        self.take(p + "noway.border", 4 * self.u64(p + "noway.border.count"))

    def with_value(self, name: str, value: bytes, offset: int = 0) -> bytes:
        at = self.fields[name][0] + offset
        return self.data[:at] + value + self.data[at + len(value):]

    def with_bytes_replaced(self, first: str, last: str, value: bytes) -> bytes:
        """Fields `first` to `last` (inclusive) replaced by `value`."""
        start, (end, n) = self.fields[first][0], self.fields[last]
        return self.data[:start] + value + self.data[end + n:]


def with_actor(data: bytes, change: Any) -> bytes:
    """`data` with the ARobot decider's state changed by change(GridState) -> bytes."""
    (name, blob), = unpack_list(read_state(data, "<test>").parts["actors"])
    return rewrap(data, parts={"actors": pack_list([(name, change(GridState(blob)))])})


# ---- the saved states ---------------------------------------------------------------------------------------
def saved_office(planner: str, world: str = "office", frames: int = 40) -> bytes:
    with start(load(world), RunOptions(frames=frames, planner=planner, allow_unreached=True, threads=1)) as run:
        run.execute()
        return run.save_state()


@pytest.fixture(scope="module")
def astar() -> bytes:
    """The office with A* after 40 frames (13 KB)."""
    return saved_office("astar")


@pytest.fixture(scope="module")
def dstar() -> bytes:
    """The office with D* Lite after 40 frames: the decider keeps both robots' searches (170 KB)."""
    return saved_office("dstar")


def resumes_or_refuses(data: bytes | Path) -> str:
    """'resumed' or 'refused' (a vwg Error); any other exception propagates."""
    try:
        run = resume(data)
    except Error as e:
        str(e).encode("utf-8")
        return "refused"
    run.close()
    return "resumed"


def refusal(data: bytes | Path) -> Error:
    """The vwg Error resuming `data` raises (the test fails if it resumes, or raises anything else)."""
    with pytest.raises(Error) as info:
        run = resume(data)
        run.close()
    return info.value


def test_the_states_resume():
    """The states the tests damage resume as they are (else every refusal below would prove nothing)."""
    for planner in ("astar", "dstar"):
        data = saved_office(planner, frames=5)
        with resume(data, RunOptions(frames=3, threads=1)) as run:
            run.execute()
            assert run.engine.frame == 8


# ---- 1. truncated files -------------------------------------------------------------------------------------
@pytest.mark.parametrize("length", [0, 5, 9, 10, 17, 18, 100, "half", "parts", "-64", "-33", "-32", "-1"])
def test_a_truncated_file_is_an_error_naming_it(astar, tmp_path, length):
    where = regions(astar)
    n = {"half": len(astar) // 2, "parts": where["part actors"][0] + 3, "-64": len(astar) - 64,
         "-33": len(astar) - 33, "-32": len(astar) - 32, "-1": len(astar) - 1}.get(length, length)
    path = tmp_path / "cut.vwgstate"
    path.write_bytes(astar[:n])
    for read in (read_state_file, resume):
        with pytest.raises(Error) as info:
            read(path)
        assert str(path) in str(info.value)
    with pytest.raises(Error) as info:
        read_state_file(astar[:n])
    assert "<state bytes>" in str(info.value)


def test_a_missing_or_unreadable_state_file_is_an_error_naming_it(tmp_path):
    for path in (tmp_path / "nosuch.vwgstate", tmp_path):
        with pytest.raises(Error) as info:
            resume(path)
        assert str(path) in str(info.value)


# ---- 2. a flipped byte in each region ------------------------------------------------------------------------
@pytest.mark.parametrize("bits", [0x01, 0x80])
def test_a_flipped_byte_in_a_part_names_that_part(dstar, bits):
    parts = [name for name in regions(dstar) if name.startswith("part ")]
    assert {p[5:] for p in parts} == {"platform", "string", "blobs", "generators", "actors"}
    for part in parts:
        start, end = regions(dstar)[part]
        for at in sorted({start, start + 1, (start + end) // 2, end - 2, end - 1}):
            with pytest.raises(Error) as info:
                read_state_file(flip(dstar, at, bits))
            assert f"the part '{part[5:]}'" in str(info.value), (part, at - start, str(info.value))


def test_a_flipped_byte_in_the_magic_says_it_is_not_a_state_file(astar):
    for at in range(len(MAGIC)):
        with pytest.raises(Error, match="not a vwg state file"):
            read_state_file(flip(astar, at))


def test_a_flipped_byte_in_the_manifests_length_is_an_error(astar):
    for at in range(len(MAGIC), len(MAGIC) + 8):
        for bits in (0x01, 0x80):
            with pytest.raises(Error):
                read_state_file(flip(astar, at, bits))


def manifest_offsets(data: bytes) -> dict[str, int]:
    """Bytes of the manifest to flip: its first and last (the braces), one in its middle, and one
    inside a text value (the world file's name) and inside a number (the frame)."""
    start, end = regions(data)["manifest"]
    head = data[start:end]
    return {"first": start, "middle": (start + end) // 2, "last": end - 1,
            "in a text": start + head.index(b'"world_file": "') + len('"world_file": "') + 3,
            "in a number": start + head.index(b'"frame": ') + len('"frame": ')}


@pytest.mark.parametrize("where", ["first", "middle", "last", "in a text", "in a number"])
def test_a_flipped_byte_in_the_manifest_names_the_manifest(astar, where):
    """Wherever the byte is, it is the manifest that is named (not the hashes, not a part)."""
    with pytest.raises(Error) as info:
        read_state_file(flip(astar, manifest_offsets(astar)[where]))
    assert "manifest" in str(info.value), str(info.value)


@pytest.mark.parametrize("which", ["manifest hash", "file hash"])
def test_a_flipped_byte_in_the_hashes_at_the_end_names_the_hashes(astar, which):
    """The manifest and the parts are whole: the message says the hashes at the end are damaged,
    not the manifest."""
    start, end = regions(astar)[which]
    for at in (start, (start + end) // 2, end - 1):
        with pytest.raises(Error) as info:
            read_state_file(flip(astar, at))
        message = str(info.value)
        assert "hashes at its end" in message and "manifest is damaged" not in message, (which, message)


# ---- 3. another version, another format ----------------------------------------------------------------------
def test_a_state_of_another_vwg_is_refused_naming_both_versions(astar, tmp_path):
    path = tmp_path / "old.vwgstate"
    path.write_bytes(rewrap(astar, {"vwg": "0.0.1"}))
    read_state_file(path)  # a well-formed file
    message = str(refusal(path))
    assert "0.0.1" in message and _core.__version__ in message and str(path) in message


@pytest.mark.parametrize("fmt", [FORMAT + 1, 0, -1, "1", None, 1.5, [1]])
def test_a_state_file_of_another_format_is_refused(astar, fmt):
    manifest = json.loads(astar[regions(astar)["manifest"][0]:regions(astar)["manifest"][1]])
    manifest["format"] = fmt
    start, end = regions(astar)["manifest"][1], regions(astar)["manifest hash"][0]
    forged = forge(json.dumps(manifest, sort_keys=True).encode(), astar[start:end])
    with pytest.raises(Error) as info:
        read_state_file(forged)
    assert "format" in str(info.value) and str(FORMAT) in str(info.value)


# ---- 4. the world file or its map changed, or gone ------------------------------------------------------------
@pytest.fixture
def office_copy(tmp_path) -> tuple[Path, bytes]:
    """The shipped office world copied into tmp_path (the world file, its map's YAML and image, at the
    same places relative to each other) and a state saved from a run of the copy."""
    world = load("office")
    base = Path(world.path).parent
    for source in run_inputs(world).values():
        target = tmp_path / Path(source).relative_to(base)
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, target)
    path = tmp_path / Path(world.path).name
    with start(load(str(path)), RunOptions(frames=10, planner="astar", allow_unreached=True, threads=1)) as run:
        run.execute()
        data = run.save_state()
    assert resumes_or_refuses(data) == "resumed"
    return path, data


def test_a_world_file_changed_since_is_refused(office_copy):
    path, data = office_copy
    path.write_text(path.read_text() + "# edited after the state was saved\n")
    message = str(refusal(data))
    assert str(path.resolve()) in message and "changed" in message


def test_a_number_changed_in_the_world_file_is_refused(office_copy):
    path, data = office_copy
    text = path.read_text()
    assert "wall_height: 2.5" in text
    path.write_text(text.replace("wall_height: 2.5", "wall_height: 2.6"))
    assert "changed" in str(refusal(data))


def test_a_map_image_changed_since_is_refused(office_copy):
    path, data = office_copy
    image = next(path.parent.rglob("*.pgm"))
    image.write_bytes(flip(image.read_bytes(), image.stat().st_size - 10))
    message = str(refusal(data))
    assert str(image.resolve()) in message and "changed" in message


def test_a_world_file_gone_is_refused(office_copy):
    path, data = office_copy
    path.unlink()
    message = str(refusal(data))
    assert str(path.resolve()) in message


def test_a_state_made_to_name_another_world_is_refused(office_copy):
    """The manifest edited (checksums right) to name another world: the simulator's fingerprint differs."""
    _, data = office_copy
    other = str(Path(load("maze").path).resolve())
    assert resumes_or_refuses(rewrap(data, {"world_file": other})) == "refused"


# ---- the manifest's fields, forged ----------------------------------------------------------------------------
FORGED_FIELDS = [("frame", "abc"), ("frame", -1), ("frame", 2**70), ("frame", None), ("frame", 1.5),
                 ("seed", None), ("seed", "x"), ("seed", -5), ("dt", None), ("dt", "x"), ("dt", 0),
                 ("world_file", None), ("world_file", 5), ("world_kind", "generic"),
                 ("inputs", [1]), ("inputs", "x"), ("inputs", {"a": 5}), ("inputs", {"a": {"path": None}}),
                 ("frames_left", "x"), ("frames_left", -3), ("frames_left", 2**70),
                 ("platform", "nosuch"), ("platform", 5),
                 ("run", [1]), ("run", "x"), ("run", {"planner": 5}), ("run", {"planner": "nosuch"}),
                 ("run", {"planner": "astar", "goals": [5]}), ("run", {"planner": "astar", "goals": [{}]}),
                 ("run", {"planner": "astar", "goals": "kitchen"})]


@pytest.mark.parametrize(("field", "value"), FORGED_FIELDS, ids=[f"{f}={v!r}"[:40] for f, v in FORGED_FIELDS])
def test_a_forged_manifest_field_is_refused(astar, field, value):
    assert resumes_or_refuses(rewrap(astar, {field: value})) == "refused"


@pytest.mark.parametrize("field", ["frame", "seed", "dt", "world_file", "world_kind", "vwg"])
def test_a_manifest_without_a_field_is_refused(astar, field):
    assert resumes_or_refuses(rewrap(astar, drop=(field,))) == "refused"


@pytest.mark.parametrize("part", ["platform", "string", "blobs", "generators", "actors"])
def test_a_state_without_a_part_is_refused(astar, part):
    saved = read_state(astar, "<test>")
    fields = {k: v for k, v in saved.manifest.items() if k not in ("parts", "format")}
    assert resumes_or_refuses(write_state(fields, {k: v for k, v in saved.parts.items() if k != part})) == "refused"


@pytest.mark.parametrize("head", [
    b"[" * 100_000 + b"]" * 100_000,                            # deeper than Python's JSON reader recurses
    b'{"format": 1, "parts": [' + b"[" * 5000 + b"]" * 5000 + b"]}",
    b'{"format": ' + b"9" * 5000 + b"}",                        # more digits than int() takes
    b'{"format": 1, "parts": [{"name": "x", "bytes": 1e400, "size": 0, "sha256": ""}]}',
    b'{"format": 1, "parts": [{"name": "x", "bytes": 0, "size": 99999999999999999999, "sha256": ""}]}',
    b'{"format": 1, "parts": {}}', b'{"format": 1}', b"null", b'"vwg"', b"\xef\xbb\xbf{}", b"{}\x00",
])
def test_a_forged_manifest_text_is_refused(head):
    with pytest.raises(Error):
        read_state_file(forge(head))


# ---- 5. well-formed files with hostile C++ parts ----------------------------------------------------------------
def cpp_items(data: bytes) -> list[tuple[str, int, str, bytes]]:
    """(part, index, what the error names, bytes) of every C++ state in `data`: the platform, each
    generator and each actor type's behaviour."""
    saved = read_state(data, "<test>")
    out = [("platform", 0, "platform", saved.parts["platform"])]
    out += [("generators", k, f"state.generators[{k}]", b)
            for k, (_, b) in enumerate(unpack_list(saved.parts["generators"]))]
    out += [("actors", k, f"state.actors.{name}", b) for k, (name, b) in enumerate(unpack_list(saved.parts["actors"]))]
    return out


def replaced(data: bytes, part: str, index: int, blob: bytes) -> bytes:
    return rewrap(data, parts={"platform": blob}) if part == "platform" else with_item(data, part, index, blob)


def test_every_cpp_state_cut_short_or_longer_is_refused_naming_it(astar):
    items = cpp_items(astar)
    assert [i[2] for i in items if i[0] == "actors"] == ["state.actors.ARobot"]
    assert len([i for i in items if i[0] == "generators" and i[3]]) >= 3  # the lasers' streams, the orders
    for part, index, name, blob in items:
        n = len(blob)
        for cut in sorted({0, 1, 8, 9, n // 2, n - 1} & set(range(n))):
            with pytest.raises(Error) as info:
                resume(replaced(astar, part, index, blob[:cut])).close()
            assert name in str(info.value), (name, cut, str(info.value))
        with pytest.raises(Error) as info:  # a byte after its end
            resume(replaced(astar, part, index, blob + b"\x00")).close()
        assert name in str(info.value), (name, str(info.value))


def test_every_cpp_state_replaced_by_random_bytes_is_refused_or_read(astar):
    rng = np.random.default_rng(36)
    for part, index, name, blob in cpp_items(astar):
        for size in sorted({len(blob), 64}):
            try:
                resume(replaced(astar, part, index, rng.bytes(size))).close()
            except Error as e:
                assert name in str(e), (name, str(e))
    # Random bytes after the first 8 (a count, a format, a length kept) of each state.
    for part, index, _, blob in cpp_items(astar):
        if len(blob) > 16:
            forged = blob[:8] + rng.bytes(len(blob) - 8)
            assert resumes_or_refuses(replaced(astar, part, index, forged)) in ("resumed", "refused")


def test_a_dstar_state_cut_inside_its_search_is_refused(dstar):
    (_, blob), = unpack_list(read_state(dstar, "<test>").parts["actors"])
    fields = GridState(blob).fields
    for name in ("r0.dstar.grid.cells", "r0.dstar.g.bits", "r0.dstar.slot.bits", "r0.dstar.queue", "r0.dstar.km",
                 "r1.noway.side.count"):
        at, n = fields[name]
        assert n > 1
        cut = pack_list([("ARobot", blob[:at + n // 2])])
        with pytest.raises(SchemaError, match="ARobot"):
            resume(rewrap(dstar, parts={"actors": cut})).close()


def queue_node(state: GridState, k: int) -> int:
    return I64.unpack_from(state.data, state.fields["r0.dstar.queue"][0] + 24 * k + 16)[0]


@pytest.mark.parametrize("node", ["another queued", "not queued", "outside the grid", "negative"])
def test_a_dstar_queue_whose_positions_disagree_is_refused(dstar, node):
    def change(s: GridState) -> bytes:
        assert s.fields["r0.dstar.queue"][1] >= 48  # two entries at least (RealKeys: 16-byte order, node)
        queued = {queue_node(s, k) for k in range(s.fields["r0.dstar.queue"][1] // 24)}
        value = {"another queued": queue_node(s, 1),
                 "not queued": next(v for v in range(1000, 10**6) if v not in queued),
                 "outside the grid": 10**9, "negative": -1}[node]
        return s.with_value("r0.dstar.queue", I64.pack(value), offset=16)

    message = str(refusal(with_actor(dstar, change)))
    assert "ARobot" in message and ("queue" in message or "node" in message), message


@pytest.mark.parametrize(("field", "value"), [
    ("r0.dstar.heuristic", b"\x09"), ("r0.dstar.diagonal", b"\x02"), ("r0.dstar.start.row", I64.pack(-2)),
    ("r0.dstar.goal.col", I64.pack(2**40)), ("r0.dstar.start_node", I64.pack(-1)), ("r0.dstar.g.size", U64.pack(7)),
    ("r0.dstar.slot.size", U64.pack(2**62)), ("r0.dstar.queue.count", U64.pack(2**61)),
    ("r0.dstar.grid.rows", I64.pack(-1)),
    ("r0.map.rows", I64.pack(2**40)), ("r0.map.radius", F64.pack(float("nan"))), ("r0.map.radius", F64.pack(-0.5)),
    ("r0.noway.known", b"\x07"), ("r0.noway.size", I64.pack(-4)), ("r0.noway.border.count", U64.pack(2**60)),
    ("robots", U64.pack(2**40)), ("name.length", U64.pack(2**63)),
    ("name", b"\xff\xfe\xfd\xfc\xfb"),  # named in the message: not UTF-8 (a UnicodeDecodeError reached Python)
])
def test_a_dstar_state_with_a_field_out_of_range_is_refused(dstar, field, value):
    assert "ARobot" in str(refusal(with_actor(dstar, lambda s: s.with_value(field, value))))


def test_a_decider_state_of_another_decider_is_refused(astar, dstar):
    (_, blob), = unpack_list(read_state(dstar, "<test>").parts["actors"])
    assert "dstar" in str(refusal(rewrap(astar, parts={"actors": pack_list([("ARobot", blob)])})))


def grid_of(rows: int, cols: int):
    """A decider state whose first robot's planning map is a grid of rows × cols (no cells stored:
    with 0 columns there are none)."""
    return lambda s: s.with_bytes_replaced("r0.map.rows", "r0.map.cells", I64.pack(rows) + I64.pack(cols))


@pytest.mark.parametrize("rows", [2**31 - 1, 2**31 - 2, 500_000_000])
def test_a_grid_of_no_columns_and_many_rows_is_refused(astar, rows):
    """16 bytes may not make a grid of 2**31 - 1 rows (rows + 2 overflows an int in BlockedGrid's
    constructor: std::bad_alloc) or of 5e8 rows (1 GB of padding allocated and walked)."""
    assert "ARobot" in str(refusal(with_actor(astar, grid_of(rows, 0))))


@pytest.mark.parametrize("radius", [1e300, 1e5, float("inf")])
def test_a_planning_radius_other_than_the_robot_s_is_not_used(astar, radius):
    """A saved planning map inflated by 1e5 m once made the first plan after resuming take 4 GB and half
    a minute, and by 1e300 m crashed in PlanningMap::rebuild_mask: the saved grids are now used only for
    the radius the robot plans with, so a forged one is a first look at the map (made from the map)."""
    forged = with_actor(astar, lambda s: s.with_value("r0.map.radius", F64.pack(radius)))
    if not np.isfinite(radius):  # not a radius at all: refused by name
        assert "planning radius" in str(refusal(forged))
        return
    with resume(forged, RunOptions(frames=30, allow_unreached=True)) as run:
        run.execute()
        assert run.engine.frame == 70


def test_a_journal_entry_of_unknown_kind_is_refused(astar):
    message = str(refusal(journal_with(astar, b"\x09")))
    assert "journal" in message and "unknown" in message


@pytest.mark.parametrize(("label", "extra"), [
    ("advance NaN", bytes([ADVANCE]) + F64.pack(float("nan"))),
    ("advance -1", bytes([ADVANCE]) + F64.pack(-1.0)),
    ("advance 1e4 s", bytes([ADVANCE]) + F64.pack(1e4)),       # more than a frame's dt can be (3600 s)
    ("advance 1e300 s", bytes([ADVANCE]) + F64.pack(1e300)),   # its steps overflow an int64 (undefined)
    ("remove robot 2**32 + 1", bytes([REMOVE_ROBOT]) + I64.pack(2**32 + 1)),  # robot 1 once cut to an int
    ("drive robot 2**32 + 2", bytes([DRIVE]) + I64.pack(2**32 + 2) + F64.pack(0.1) + F64.pack(0.0)),
    ("drive NaN", bytes([DRIVE]) + I64.pack(1) + F64.pack(float("nan")) + F64.pack(0.0)),
    ("command of a step of kind 9", bytes([COMMAND]) + I64.pack(1) + U64.pack(1) + b"\x09" + F64.pack(1.0)),
    ("command of 2**60 steps", bytes([COMMAND]) + I64.pack(1) + U64.pack(2**60)),
    ("remove robot 7", bytes([REMOVE_ROBOT]) + I64.pack(7)),
    ("add robot 1 again", bytes([ADD_ROBOT]) + I64.pack(1) + F64.pack(1.5) * 2 + F64.pack(0.0) + F64.pack(0.2)
     + F64.pack(1.0) * 4 + U64.pack(0)),
    ("add robot of id 0", bytes([ADD_ROBOT]) + I64.pack(0)),
    ("cut inside an entry", bytes([ADVANCE]) + b"\x00\x00"),
])
def test_a_journal_with_a_forged_entry_is_refused(astar, label, extra):
    refusal(journal_with(astar, extra))


def test_a_journal_of_another_simulator_is_refused(astar):
    platform = read_state(astar, "<test>").parts["platform"]
    for offset in (0, 8):  # the journal's format; the simulator's fingerprint (map, settings, robots)
        forged = platform[:offset] + U64.pack(U64.unpack_from(platform, offset)[0] ^ 1) + platform[offset + 8:]
        assert "platform" in str(refusal(rewrap(astar, parts={"platform": forged})))


# The forged states that are read and then run: whatever happens, in a child process (a crash there
# is reported with the case that caused it).
RUNNER = textwrap.dedent("""
    import json, sys
    from vwg.errors import Error
    from vwg.launch import RunOptions
    from vwg.saved_run import resume
    for path in sys.argv[2:]:
        print(json.dumps({"case": path, "stage": "start"}), flush=True)
        stage = "resume"
        try:
            with resume(path, RunOptions(frames=int(sys.argv[1]), threads=1, allow_unreached=True)) as run:
                stage = "run"
                run.execute()
            outcome = {"stage": "ran"}
        except Error as e:
            outcome = {"stage": stage, "error": type(e).__name__, "message": str(e)[:300]}
        except BaseException as e:
            outcome = {"stage": stage, "other": type(e).__name__, "message": str(e)[:300]}
        print(json.dumps({"case": path, **outcome}), flush=True)
""")


def child_env() -> dict[str, str]:
    """The environment of a child process that imports this vwg (PYTHONPATH, and LD_PRELOAD under ASan)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(Path(vwg.__file__).resolve().parents[1]), env.get("PYTHONPATH", "")])
    return env


def run_cases(cases: dict[str, bytes], folder: Path, frames: int, timeout: float = 300) -> dict[str, dict[str, Any]]:
    """Resume each case and run `frames` frames in a child process; each case's outcome by name.
    Fails naming the case that crashed or hung it."""
    paths = {}
    for name, data in cases.items():
        paths[name] = folder / f"{name}.vwgstate"
        paths[name].write_bytes(data)
    by_path = {str(p): name for name, p in paths.items()}
    try:
        done = subprocess.run([sys.executable, "-c", RUNNER, str(frames), *map(str, paths.values())], env=child_env(),
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired as e:
        pytest.fail(f"hung (no end after {timeout} s); its output:\n{e.stdout}")
    outcomes: dict[str, dict[str, Any]] = {}
    last = None
    for line in done.stdout.splitlines():
        entry = json.loads(line)
        last = by_path[entry["case"]]
        if entry["stage"] != "start":
            outcomes[last] = entry
    if done.returncode != 0:
        pytest.fail(f"the child process ended with status {done.returncode} on the case {last!r} "
                    f"({paths[last] if last else ''}):\n{done.stderr[-3000:]}")
    return outcomes


def test_forged_decider_and_journal_states_run_or_fail_with_a_vwg_error(astar, dstar, tmp_path):
    """States read with the values a check may let through, then run for 40 frames (both robots plan
    again in them): they run, or stop with a vwg error, and never crash."""
    def field(name: str, value: bytes, data: bytes = dstar) -> bytes:
        return with_actor(data, lambda s: s.with_value(name, value))

    cases = {
        "radius_1e300": field("r0.map.radius", F64.pack(1e300), astar),
        "radius_2": field("r0.map.radius", F64.pack(2.0), astar),
        "robot_99": field("r0.id", I64.pack(99), astar),
        "goal_far": field("r0.goal", I64.pack(2**30)),
        "dstar_start_node_0": field("r0.dstar.start_node", I64.pack(0)),
        "dstar_goal_node_0": field("r0.dstar.goal_node", I64.pack(0)),
        "dstar_last_node_0": field("r0.dstar.last_node", I64.pack(0)),
        "dstar_km_nan": field("r0.dstar.km", F64.pack(float("nan"))),
        "dstar_km_1e300": field("r0.dstar.km", F64.pack(1e300)),
        "dstar_g_fill_nan": field("r0.dstar.g.fill", U64.pack(0x7FF8000000000001)),
        "dstar_heuristic_manhattan": field("r0.dstar.heuristic", b"\x01"),
        "dstar_no_diagonal": field("r0.dstar.diagonal", b"\x00"),
        "journal_advance_1e300": journal_with(astar, bytes([ADVANCE]) + F64.pack(1e300)),
        "journal_drive_fast": journal_with(astar, bytes([DRIVE]) + I64.pack(1) + F64.pack(1e300) * 2
                                           + bytes([ADVANCE]) + F64.pack(1.0)),
        "journal_command_far": journal_with(astar, bytes([COMMAND]) + I64.pack(1) + U64.pack(1) + b"\x01"
                                            + F64.pack(1e300) + bytes([ADVANCE]) + F64.pack(1.0)),
    }
    outcomes = run_cases(cases, tmp_path, frames=40)
    assert set(outcomes) == set(cases)
    others = {name: o for name, o in outcomes.items() if "other" in o}
    assert not others, others


# ---- 6. a Python generator's kept attributes (vwg.model.state) ---------------------------------------------------
class Kept:
    """A generator's attributes of every kind capture() keeps."""

    def __init__(self) -> None:
        self.count = 3
        self.name = "drops"
        self.ratio = float("nan")
        self.sizes = (1, 2.5, None)
        self.table = {("a", 1): [True, -1e308]}
        self.grid = np.arange(6, dtype="<i2").reshape(2, 3)
        self.rng = np.random.default_rng(7)
        self.py_rng = random.Random(5)


def kept(value: Any) -> bytes:
    """A kept state whose attribute `count` holds `value` (a JSON value as capture() writes them)."""
    return json.dumps({"attributes": {"count": value}}).encode()


class One:
    """A generator of one attribute."""

    def __init__(self) -> None:
        self.count = 0


def test_kept_attributes_come_back_as_they_were():
    a = Kept()
    a.rng.random(3)
    b = Kept()
    b.rng, b.count, b.grid = np.random.default_rng(99), 0, np.zeros(1)
    restore(b, capture(a, "generator 0"), "generator 0")
    assert b.count == 3 and b.name == "drops" and np.isnan(b.ratio) and b.sizes == (1, 2.5, None)
    assert b.table == {("a", 1): [True, -1e308]}
    assert b.grid.dtype == np.dtype("<i2") and b.grid.tolist() == [[0, 1, 2], [3, 4, 5]]
    assert b.rng.random(4).tolist() == a.rng.random(4).tolist()  # the stream goes on where it was
    assert b.py_rng.random() == a.py_rng.random()


@pytest.mark.parametrize("bits", ["PCG64", "PCG64DXSM", "MT19937", "Philox", "SFC64"])
def test_a_numpy_generator_of_each_bit_generator_is_kept(bits):
    """The module's description: "the random generators of numpy (numpy.random.Generator, any of numpy's
    bit generators)". MT19937, Philox and SFC64 keep numpy arrays in their state."""
    a, b = One(), One()
    a.count = np.random.Generator(getattr(np.random, bits)(11))
    a.count.random(5)
    b.count = np.random.Generator(getattr(np.random, bits)(12))
    restore(b, capture(a, "generator 0"), "generator 0")
    assert type(b.count.bit_generator).__name__ == bits
    assert b.count.integers(0, 2**62, 6).tolist() == a.count.integers(0, 2**62, 6).tolist()


def nested(depth: int, inner: str = "1") -> bytes:
    return b'{"attributes": {"count": ' + b"[" * depth + inner.encode() + b"]" * depth + b"}}"


def nested_tuples(depth: int) -> bytes:
    return b'{"attributes": {"count": ' + b'{"tuple": [' * depth + b"1" + b"]}" * depth + b"}}"


HOSTILE_KEPT = {
    "unknown kind": kept({"pickle": "gASVAAAAAAAAAAA="}),
    "two kinds": kept({"tuple": [], "dict": []}),
    "numpy rng os.system": kept({"numpy_rng": {"bit_generator": "os.system", "state": {}}}),
    "numpy rng subprocess.Popen": kept({"numpy_rng": {"bit_generator": "subprocess.Popen"}}),
    "numpy rng __import__": kept({"numpy_rng": {"bit_generator": "__import__"}}),
    "numpy rng of no name": kept({"numpy_rng": {"state": {}}}),
    "numpy rng without a state": kept({"numpy_rng": {"bit_generator": "PCG64"}}),
    "numpy rng of a text state": kept({"numpy_rng": {"bit_generator": "PCG64", "state": "x"}}),
    "numpy rng of a short key": kept({"numpy_rng": {"bit_generator": "MT19937", "state": {"key": [1, 2], "pos": 0}}}),
    "ndarray of objects": kept({"ndarray": {"dtype": "|O", "shape": [1], "base64": "AAAAAAAAAAA="}}),
    "ndarray of objects (O)": kept({"ndarray": {"dtype": "O", "shape": [1], "base64": "AAAAAAAAAAA="}}),
    "ndarray of records holding objects": kept({"ndarray": {"dtype": [["a", "O"]], "shape": [1], "base64": ""}}),
    "ndarray of dtype os.system": kept({"ndarray": {"dtype": "os.system", "shape": [1], "base64": ""}}),
    "ndarray of an unknown dtype": kept({"ndarray": {"dtype": "zz9", "shape": [1], "base64": ""}}),
    "ndarray of bad base64": kept({"ndarray": {"dtype": "<f8", "shape": [1], "base64": "!!!!"}}),
    "ndarray of a text shape": kept({"ndarray": {"dtype": "<f8", "shape": "ab", "base64": ""}}),
    "ndarray of a negative shape": kept({"ndarray": {"dtype": "<f8", "shape": [-1], "base64": ""}}),
    "ndarray of a huge empty shape": kept({"ndarray": {"dtype": "<f8", "shape": [2**62, 2**62, 0], "base64": ""}}),
    "ndarray of itemsize 0": kept({"ndarray": {"dtype": "V0", "shape": [2**40], "base64": ""}}),
    "random of a short state": kept({"random": [3, [1, 2, 3], None]}),
    "random of a text state": kept({"random": [3, "abc", None]}),
    "random of a number state": kept({"random": ["x", 5, None]}),
    "float of another text": kept({"float": "1e999"}),
    "dict with a dict key": kept({"dict": [[{"dict": []}, 1]]}),
    "dict with an array key": kept({"dict": [[{"ndarray": {"dtype": "<f8", "shape": [1], "base64": "AAAAAAAAAAA="}},
                                              1]]}),
    "dict of odd pairs": kept({"dict": [[1]]}),
    f"lists {MAX_DEPTH + 1} deep": nested(MAX_DEPTH + 1),
    "lists 500 deep": nested(500),
    "lists 100000 deep": nested(100_000),
    "tuples 500 deep": nested_tuples(500),
    "a 5000-digit number": b'{"attributes": {"count": ' + b"9" * 5000 + b"}}",
    "not JSON": b"\xff\xfe",
    "not an object": b"[1]",
    "attributes of another object": kept(1)[:-2] + b', "other": 2}}',
    "no attributes": b'{"attributes": {}}',
}


@pytest.mark.parametrize("name", list(HOSTILE_KEPT))
def test_a_hostile_kept_attribute_is_a_schema_error_and_imports_nothing(name):
    obj = One()
    before = set(sys.modules)
    with pytest.raises(SchemaError) as info:
        restore(obj, HOSTILE_KEPT[name], "generator 3 (food_drops)")
    assert "generator 3 (food_drops)" in str(info.value)
    assert set(sys.modules) == before  # no module imported by name
    assert obj.count == 0  # and nothing set


def test_capture_refuses_what_restore_refuses():
    """capture() writes only what restore() reads back: nesting up to MAX_DEPTH."""
    value: Any = 1
    for _ in range(MAX_DEPTH):
        value = [value]
    obj = One()
    obj.count = value
    data = capture(obj, "g")
    restore(One(), data, "g")
    obj.count = [value]
    with pytest.raises(SchemaError, match="nested"):
        capture(obj, "g")


GENERIC = textwrap.dedent("""
    # A generic world with a Python generator (examples/01_fireflies, copied): saved, resumed, and resumed
    # from states whose first generator's part (FoodDrops) is hostile. One JSON line per case.
    import json, struct, sys
    from vwg.errors import Error
    from vwg.launch import RunOptions, load, start
    from vwg.saved_run import read_state_file, resume
    from vwg.io.state_file import write_state

    def report(case, **outcome):
        print(json.dumps({"case": case, **outcome}), flush=True)

    report("saved", stage="start")
    with start(load(sys.argv[1]), RunOptions(frames=6, threads=1)) as run:
        run.execute()
        data = run.save_state()
        expected = str(run.engine.string)
    report("saved", stage="done")
    report("resumed", stage="start")
    with resume(data, RunOptions(frames=0, threads=1)) as run:
        report("resumed", stage="done", same=str(run.engine.string) == expected)
    saved = read_state_file(data)
    fields = {k: v for k, v in saved.manifest.items() if k not in ("parts", "format")}
    raw, at, items = saved.parts["generators"], 8, []
    for _ in range(struct.unpack_from("<Q", raw)[0]):
        n = struct.unpack_from("<Q", raw, at)[0]
        name = raw[at + 8:at + 8 + n]
        at += 8 + n
        n = struct.unpack_from("<Q", raw, at)[0]
        items.append([name, raw[at + 8:at + 8 + n]])
        at += 8 + n
    attributes = json.loads(items[0][1])["attributes"]
    report("kept", stage="done", attributes=sorted(attributes))
    for case, (how, text) in json.loads(sys.argv[2]).items():
        report(case, stage="start")
        if how == "rng":  # the attribute rng (a numpy Generator) set to this JSON text
            kept = json.dumps({"attributes": {**attributes, "rng": "@HOSTILE@"}})
            items[0][1] = kept.replace('"@HOSTILE@"', text).encode()
        else:  # the whole state: these bytes
            items[0][1] = bytes.fromhex(text)
        packed = struct.pack("<Q", len(items)) + b"".join(
            struct.pack("<Q", len(name)) + name + struct.pack("<Q", len(b)) + b for name, b in items)
        try:
            forged = write_state(fields, {**saved.parts, "generators": packed})
            with resume(forged, RunOptions(frames=2, threads=1)) as run:
                run.execute()
            report(case, stage="done", outcome="resumed")
        except Error as e:
            report(case, stage="done", outcome="refused", error=type(e).__name__, message=str(e)[:300])
        except BaseException as e:
            report(case, stage="done", outcome="other", error=type(e).__name__, message=str(e)[:300])
""")


def test_a_generic_world_with_a_python_generator_saves_resumes_and_refuses_hostile_generator_state(tmp_path):
    """examples/01_fireflies (FoodDrops keeps a numpy random generator): saved and resumed as it was;
    its generator's state forged (another bit generator's name, objects, deep nesting, random bytes)
    is refused with a vwg error. In a child process: a crash there names the case."""
    folder = tmp_path / "fireflies"
    shutil.copytree(ROOT / "examples" / "01_fireflies", folder)
    prefix, suffix = b'{"attributes": {"count": ', b"}}"
    hostile = {name: ("rng", HOSTILE_KEPT[name][len(prefix):-len(suffix)].decode()) for name in
               ("numpy rng os.system", "numpy rng of a text state", "ndarray of objects", "ndarray of bad base64",
                "unknown kind", "dict with a dict key", "lists 500 deep")}
    hostile["not JSON"] = ("bytes", HOSTILE_KEPT["not JSON"].hex())
    hostile["random bytes"] = ("bytes", np.random.default_rng(1).bytes(64).hex())
    hostile["empty"] = ("bytes", "")
    try:
        done = subprocess.run([sys.executable, "-c", GENERIC, str(folder / "world.yaml"), json.dumps(hostile)],
                              env=child_env(), capture_output=True, text=True, timeout=300, cwd=folder)
    except subprocess.TimeoutExpired as e:
        pytest.fail(f"hung; its output:\n{e.stdout}")
    lines = [json.loads(x) for x in done.stdout.splitlines()]
    last = lines[-1]["case"] if lines else "(starting)"
    assert done.returncode == 0, f"ended with status {done.returncode} at {last!r}:\n{done.stderr[-3000:]}"
    outcomes = {x["case"]: x for x in lines if x["stage"] == "done"}
    assert outcomes["resumed"]["same"]
    assert outcomes["kept"]["attributes"] == ["capacity", "rng", "size"]
    for case, (how, _) in hostile.items():
        assert outcomes[case]["outcome"] == "refused", outcomes[case]
        assert "food_drops" in outcomes[case]["message"], outcomes[case]
        if how == "rng":
            assert "food_drops.rng" in outcomes[case]["message"], outcomes[case]


# ---- 7. the fuzz corpus and Hypothesis ---------------------------------------------------------------------------
def portable(data: bytes) -> bytes:
    """A state of the shipped office naming it as "office" (found wherever vwg is) and no input files'
    hashes: one a corpus can keep."""
    saved = read_state(data, "<test>")
    run_data = {**saved.manifest["run"], "robot_world": "office"}
    return rewrap(data, {"world_file": "office", "inputs": {}, "run": run_data})


def corpus_files(astar_state: bytes) -> dict[str, bytes]:
    """The hostile files of tests/fuzz_corpus/state/ (the office with A* after 40 frames)."""
    base = portable(astar_state)
    manifest_at = regions(base)["manifest"][0]
    return {
        "office_astar.vwgstate": base,
        "truncated.vwgstate": base[:len(base) // 2],
        "flipped_manifest.vwgstate": flip(base, manifest_at + 40),
        "version_0.0.1.vwgstate": rewrap(base, {"vwg": "0.0.1"}),
        "random_platform.vwgstate": rewrap(base, parts={"platform": np.random.default_rng(36).bytes(64)}),
        "journal_unknown_op.vwgstate": journal_with(base, b"\x09"),
        "planning_radius_1e300.vwgstate": with_actor(base, lambda s: s.with_value("r0.map.radius", F64.pack(1e300))),
        "deep_manifest.vwgstate": forge(b"[" * 5000 + b"]" * 5000),
    }


SEEDS = sorted(CORPUS.iterdir()) if CORPUS.is_dir() else []


def test_the_corpus_holds_a_state_that_resumes():
    """office_astar.vwgstate, the seed the others are made from, resumes with this vwg (a version or
    format change: regenerate the corpus, see the module's description)."""
    names = {p.name for p in SEEDS}
    assert {"office_astar.vwgstate", "truncated.vwgstate", "flipped_manifest.vwgstate"} <= names
    seed = (CORPUS / "office_astar.vwgstate").read_bytes()
    assert resumes_or_refuses(rewrap(seed, {"vwg": _core.__version__})) == "resumed"


@pytest.mark.parametrize("path", SEEDS, ids=[p.name for p in SEEDS])
def test_the_corpus_files_resume_or_are_refused(path):
    assert resumes_or_refuses(path) in ("resumed", "refused")


@st.composite
def mutated_bytes(draw: st.DrawFn, seeds: list[bytes]) -> bytes:
    """A seed with a few bytes flipped, set, inserted or deleted, or cut short."""
    data = bytearray(draw(st.sampled_from(seeds)))
    for _ in range(draw(st.integers(1, 4))):
        op = draw(st.sampled_from(["flip", "set", "insert", "delete", "truncate"]))
        at = draw(st.integers(0, max(0, len(data) - 1)))
        if op == "flip" and data:
            data[at] ^= 1 << draw(st.integers(0, 7))
        elif op == "set" and data:
            data[at] = draw(st.sampled_from([0, 1, 0x7F, 0x80, 0xFF, ord("["), ord('"')]))
        elif op == "insert":
            data[at:at] = draw(st.binary(min_size=1, max_size=16))
        elif op == "delete":
            del data[at:at + draw(st.integers(1, 16))]
        else:
            del data[at:]
    return bytes(data)


CORPUS_SEEDS = [p.read_bytes() for p in SEEDS]


@FUZZ
@given(mutated_bytes(CORPUS_SEEDS) if CORPUS_SEEDS else st.just(b""))
def test_a_mutated_state_file_reads_or_is_refused(data):
    try:
        saved = read_state_file(data)
    except Error as e:
        assert str(e).startswith("<state bytes>: ")
        return
    assert isinstance(saved.manifest, dict) and all(isinstance(b, bytes) for b in saved.parts.values())
    assert resumes_or_refuses(data) in ("resumed", "refused")


@pytest.fixture(scope="module")
def fuzz_bases(astar) -> list[bytes]:
    """Well-formed states to forge parts of: the corpus's seed (made this vwg's) and a fresh one."""
    seeds = [rewrap(b, {"vwg": _core.__version__}) for b in CORPUS_SEEDS if reads(b)]
    return [*seeds, astar]


def reads(data: bytes) -> bool:
    try:
        read_state(data, "<test>")
        return True
    except Exception:  # a seed that does not read is no base, whatever it raises
        return False


@st.composite
def part_mutation(draw: st.DrawFn) -> tuple[int, str, int, list[tuple[str, int, bytes]]]:
    """Which base, which C++ state (by order in cpp_items), and its bytes' changes."""
    edits = draw(st.lists(st.tuples(st.sampled_from(["flip", "set", "insert", "delete", "truncate", "u64"]),
                                    st.integers(0, 2**20), st.binary(min_size=1, max_size=8)), min_size=1, max_size=4))
    part = draw(st.sampled_from(["platform", "generators", "actors"]))
    return draw(st.integers(0, 7)), part, draw(st.integers(0, 8)), edits


def apply_edits(blob: bytes, edits: list[tuple[str, int, bytes]]) -> bytes:
    data = bytearray(blob)
    for op, where, value in edits:
        at = where % (len(data) + 1)
        if op == "flip" and at < len(data):
            data[at] ^= value[0] or 1
        elif op == "set" and at < len(data):
            data[at] = value[0]
        elif op == "insert":
            data[at:at] = value
        elif op == "delete":
            del data[at:at + len(value)]
        elif op == "truncate":
            del data[at:]
        elif op == "u64":  # a length, count or number set to an edge value
            data[at:at + 8] = U64.pack([0, 1, 2**31 - 1, 2**32, 2**63, 2**64 - 1, 7, 8][value[0] % 8])
    return bytes(data)


@FUZZ_RESUME
@given(part_mutation())
def test_a_state_with_a_mutated_cpp_part_resumes_or_is_refused(fuzz_bases, mutation):
    """Well-formed files (their hashes right) whose platform, generator or decider state is mutated."""
    base_index, part, index, edits = mutation
    base = fuzz_bases[base_index % len(fuzz_bases)]
    items = [i for i in cpp_items(base) if i[0] == part]
    part, index, _, blob = items[index % len(items)]
    assert resumes_or_refuses(replaced(base, part, index, apply_edits(blob, edits))) in ("resumed", "refused")


MANIFEST_VALUES = st.one_of(
    st.none(), st.booleans(), st.integers(), st.floats(allow_nan=False, allow_infinity=False), st.text(max_size=8),
    st.sampled_from([2**64, 2**63, -(2**63), 10**30, 1e308, "office", "maze", "", "\x00", "robot", "generic", "sim"]),
    st.recursive(st.none() | st.integers() | st.text(max_size=4),
                 lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3),
                 max_leaves=6))


@FUZZ_RESUME
@given(st.sampled_from(["frame", "seed", "dt", "time", "frames_left", "world_kind", "world_file", "inputs",
                        "platform", "run", "vwg", "extra"]), MANIFEST_VALUES, st.booleans())
def test_a_state_with_any_value_in_a_manifest_field_resumes_or_is_refused(astar, field, value, drop):
    data = rewrap(astar, drop=(field,)) if drop else rewrap(astar, {field: value})
    assert resumes_or_refuses(data) in ("resumed", "refused")


if __name__ == "__main__":
    if sys.argv[1:] != ["--write-corpus"]:
        sys.exit("usage: PYTHONPATH=python python tests/test_state_hostile.py --write-corpus")
    CORPUS.mkdir(parents=True, exist_ok=True)
    for name, data in corpus_files(saved_office("astar")).items():
        (CORPUS / name).write_bytes(data)
        print(f"{CORPUS / name}: {len(data)} bytes")
