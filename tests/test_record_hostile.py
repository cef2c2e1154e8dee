"""Records as an attacker or a damaged disk makes them: the chain and each line's layout are checked
before anything is inflated, nothing inflates past its declared size, a record runs no code of its
own, every byte of the file is accounted for, and `vwg replay --from` keeps the run's orders."""

from __future__ import annotations

import json
import tracemalloc
import zlib
from pathlib import Path

import pytest
from test_record import chained, rechain, run_recorded

import vwg
from conftest import ROOT
from vwg.cli import main
from vwg.io.record import read_record


def b85(data: bytes) -> str:
    """Base85 as the record's format says: RFC 1924's alphabet, as Python's base64.b85encode."""
    import base64

    return base64.b85encode(data).decode()


def deflated_zeros(n: int) -> bytes:
    """zlib of n zero bytes, made a megabyte at a time (the test never holds the n bytes)."""
    c = zlib.compressobj(9)
    chunk = bytes(2**20)
    out = [c.compress(chunk) for _ in range(n // len(chunk))]
    return b"".join(out) + c.compress(bytes(n % len(chunk))) + c.flush()


def header(**fields) -> dict:
    return {"vwg_record": vwg.io.record.FORMAT, "chain": "sha256", "initial": "", "seed": 0, "dt": 0.1, **fields}


def peak_bytes_of(fn) -> tuple[BaseException | None, int]:
    """What fn raised, and the most memory Python and numpy held at once while it ran."""
    tracemalloc.start()
    try:
        fn()
        raised = None
    except BaseException as e:
        raised = e
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return raised, peak


# ---- item 3: what a record expands to ----------------------------------------------------------------

BOMB = 2**27  # 128 MiB of zeros deflate to ~130 KB
NAME = "0123456789abcdef"


@pytest.fixture(scope="module")
def bomb() -> str:
    return b85(deflated_zeros(BOMB))


def test_a_blob_that_inflates_past_its_declared_size_stops_there(tmp_path, bomb):
    path = tmp_path / "bomb.jsonl"
    path.write_text(chained([header(blobs={NAME: {"dtype": "int8", "shape": [16], "zlib_base85": bomb}})]))
    assert path.stat().st_size < BOMB / 500
    raised, peak = peak_bytes_of(lambda: read_record(path))
    assert isinstance(raised, vwg.WorldFileError), raised
    assert peak < 32 * 2**20, f"{peak / 2**20:.0f} MiB held to refuse a blob of 16 bytes"
    assert raised.line == 1 and raised.field == f"blobs.{NAME}"
    assert "inflates to more than the 16 bytes its size declares" in str(raised)


def test_a_blob_of_more_elements_than_the_limit_is_refused_before_it_is_inflated(tmp_path, bomb):
    path = tmp_path / "big.jsonl"
    # 3 * 2**26 int16 elements (384 MiB): over the limit of 2**27 elements, whatever the payload.
    entry = {"dtype": "int16", "shape": [3, 2**26], "zlib_base85": bomb}
    path.write_text(chained([header(blobs={NAME: entry})]))
    raised, peak = peak_bytes_of(lambda: read_record(path))
    assert isinstance(raised, vwg.WorldFileError), raised
    assert peak < 32 * 2**20, f"{peak / 2**20:.0f} MiB held to refuse a blob by its shape"
    assert raised.line == 1 and raised.field == f"blobs.{NAME}"
    assert "201,326,592 elements, more than the 134,217,728 a record's blob may have" in str(raised)


def test_the_chain_is_checked_before_any_blob_is_inflated(tmp_path, bomb):
    path = tmp_path / "broken.jsonl"
    # A header blob of 128 MiB that is what it says (zeros, uint8), then a line whose link is wrong.
    entry = {"dtype": "uint8", "shape": [BOMB], "zlib_base85": bomb}
    frames = [{"t": t, "time": t / 10, "events": [], "string": ""} for t in range(3)]
    lines = chained([header(blobs={NAME: entry}), *frames]).splitlines(keepends=True)
    second = json.loads(lines[2])
    second["prev"] = "0" * 32
    lines[2] = json.dumps(second) + "\n"
    path.write_text("".join(lines))
    raised, peak = peak_bytes_of(lambda: read_record(path))
    assert isinstance(raised, vwg.WorldFileError), raised
    assert peak < 32 * 2**20, f"{peak / 2**20:.0f} MiB inflated before the chain was checked"
    assert raised.line == 3 and raised.field == "prev"
    assert "chain is broken here: frame 0's line (line 2)" in str(raised)


def test_a_run_of_more_events_than_a_frame_may_have_is_refused(tmp_path):
    path = tmp_path / "events.jsonl"
    run = {"run": "tick", "n": 2**24 + 1}  # 40 bytes standing for 16.8 M events
    path.write_text(chained([header(), {"t": 0, "time": 0.0, "events": [run], "string": ""}]))
    with pytest.raises(vwg.WorldFileError, match=r"events\[0\]\.n: missing or not an int from 1 to 16,777,216") as e:
        read_record(path)
    assert e.value.line == 2


# ---- item 5: every byte of the file is accounted for -----------------------------------------------------

def lines_of(path: Path) -> list[str]:
    return path.read_text().splitlines(keepends=True)


def test_a_blank_line_between_frames_is_named(tmp_path):
    path, _ = run_recorded(tmp_path, frames=10)
    lines = lines_of(path)
    path.write_text("".join([*lines[:4], "\n", *lines[4:]]))
    with pytest.raises(vwg.WorldFileError, match="a blank line") as e:
        read_record(path)
    assert e.value.line == 5


@pytest.mark.parametrize(("tail", "count"), [
    ("garbage", "7 bytes"),         # no newline: not a line cut short, the end line was written
    ("\n", "1 byte"),               # a blank line after the end
    ('{"t": 99}\n', "10 bytes"),
])
def test_bytes_after_the_end_line_are_named(tmp_path, capsys, tail, count):
    path, _ = run_recorded(tmp_path, frames=10)
    n = len(lines_of(path))
    path.write_text(path.read_text() + tail)
    with pytest.raises(vwg.WorldFileError, match=rf"{count} after the end line \(line {n}\)") as e:
        read_record(path)
    assert e.value.line == n + 1
    assert main(["replay", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}:{n + 1}: {count} after the end line" in err and "cut short" not in err


@pytest.mark.parametrize(("edit", "field", "said"), [
    (lambda end: end.update(t=end["t"] + 1), "t",
     "the end line says the run ended at frame 11; its frames end at frame 10"),
    (lambda end: end.update(note="x"), "",
     "the end line has the fields end, t, string, frames, faults, prev, self in that order; this one has end, t, "
     "string, frames, faults, prev, self, note"),
    (lambda end: end.update(faults=[{"time_s": 1.0, "robot": "1", "what": "x"}]), "faults[0]",
     "robot: expected a robot id from 0 (the link) to 2147483647, got '1'"),
    (lambda end: end.update(faults={"time_s": 1.0}), "faults",
     "expected a list of {\"time_s\": seconds, \"robot\": id, \"what\": text}"),
    (lambda end: end.update(string=end["string"] + " "), "self",
     "the end line does not match the link it holds of itself"),
])
def test_the_end_line_is_checked_whole(tmp_path, edit, field, said):
    path, _ = run_recorded(tmp_path, frames=10)
    lines = lines_of(path)
    end = json.loads(lines[-1])
    edit(end)
    lines[-1] = json.dumps(end, separators=(",", ":"), ensure_ascii=False) + "\n"
    path.write_text("".join(lines))
    with pytest.raises(vwg.WorldFileError) as e:
        read_record(path)
    assert e.value.line == len(lines) and e.value.field == field and said in str(e.value), str(e.value)


def test_the_end_line_with_a_space_added_is_named(tmp_path):
    path, _ = run_recorded(tmp_path, frames=10)
    text = path.read_text()
    path.write_text(text[:-2] + " }\n")  # the same JSON, another text
    with pytest.raises(vwg.WorldFileError, match="self: the end line does not match the link it holds of itself"):
        read_record(path)


def deep(levels: int) -> str:
    return "[" * levels + "]" * levels


@pytest.mark.parametrize("levels", [100_000, 150])
def test_a_line_nested_too_deep_is_named(tmp_path, capsys, levels):
    path, _ = run_recorded(tmp_path, frames=3)
    lines = lines_of(path)
    if levels > 1000:  # deeper than Python's JSON reader goes: a line of brackets
        lines[2] = deep(levels) + "\n"
        path.write_text("".join(lines))
    else:  # JSON that reads, but nests past the stated limit: in the header's world, the chain made whole
        first = json.loads(lines[0])
        first["world"]["deep"] = json.loads(deep(levels))
        lines[0] = json.dumps(first) + "\n"
        path.write_text("".join(lines))
        rechain(path)
    line = 3 if levels > 1000 else 1
    with pytest.raises(vwg.WorldFileError, match="nested deeper than the 100 levels a record's line may have") as e:
        read_record(path)
    assert e.value.line == line
    assert main(["replay", str(path)]) == 2
    assert f"{path}:{line}: lists or objects nested deeper" in capsys.readouterr().err


@pytest.mark.parametrize(("field", "value", "said"), [
    ("seed", 2**64, "seed: expected an integer from 0 to 2**64 - 1, got 18446744073709551616"),
    ("seed", -1, "seed: expected an integer from 0 to 2**64 - 1, got -1"),
    ("seed", "7", "seed: expected an integer from 0 to 2**64 - 1, got '7'"),
    ("frame", -5, "frame: expected a frame number from 0 to 2**62, got -5"),
    ("dt", 0, "dt: expected a number of seconds from 1e-06 to 3600, got 0"),
    # The bounds a run takes (vwg.launch.MIN_DT): 457d53e took any dt above 0.
    ("dt", 1e-7, "dt: expected a number of seconds from 1e-06 to 3600, got 1e-07"),
    ("dt", 3600.5, "dt: expected a number of seconds from 1e-06 to 3600, got 3600.5"),
    ("blobs", [], "blobs: expected an object, got list"),
    ("world_kind", "bogus", "world_kind: unknown world kind 'bogus' (this vwg knows generic, robot)"),
    ("world_kind", 3, "world_kind: expected a string or null, got int"),
    ("initial", 5, "initial: expected a string, got int"),
])
def test_a_forged_header_field_is_named(tmp_path, capsys, field, value, said):
    path, _ = run_recorded(tmp_path, frames=3)
    lines = [json.loads(x) for x in lines_of(path)]
    lines[0][field] = value
    path.write_text(chained(lines))  # the chain made whole again: the field's own check names it
    with pytest.raises(vwg.WorldFileError) as e:
        read_record(path)
    assert e.value.line == 1 and e.value.field == field and said in str(e.value), str(e.value)
    assert main(["replay", str(path)]) == 2
    assert f"{path}:1: {said}" in capsys.readouterr().err


def relink(lines: list[str]) -> str:
    """The lines' links made whole again without reading them as JSON (which would change their numbers):
    each ``prev``, and the end line's ``self``."""
    import hashlib
    import re

    def link(text: str) -> str:
        return hashlib.sha256(text.encode()).hexdigest()[:32]

    out = [lines[0]]
    for line in lines[1:]:
        text = re.sub('"prev":"[0-9a-f]{32}"', f'"prev":"{link(out[-1].rstrip(chr(10)))}"', line.rstrip("\n"))
        if text.startswith('{"end":true'):
            body = re.sub(',"self":"[0-9a-f]{32}"', "", text)
            text = body[:-1] + f',"self":"{link(body)}"}}'
        out.append(text + "\n")
    return "".join(out)


def test_a_number_json_cannot_hold_is_named(tmp_path):
    path, _ = run_recorded(tmp_path, frames=3)
    lines = lines_of(path)
    lines[1] = lines[1].replace('"time":0.0', '"time":1e999', 1)
    assert "1e999" in lines[1]
    path.write_text(relink(lines))
    with pytest.raises(vwg.WorldFileError, match="out of range") as e:
        read_record(path)
    assert e.value.line == 2


# ---- the chain as an HMAC (vwg run --record-key) ---------------------------------------------------------

def test_a_keyed_record_reads_only_with_its_key(tmp_path, capsys):
    key, other = tmp_path / "key", tmp_path / "other"
    key.write_bytes(bytes(range(32)))
    other.write_bytes(bytes(range(1, 33)))
    path = tmp_path / "run.jsonl"
    fireflies = str(ROOT / "examples" / "01_fireflies" / "world.yaml")
    assert main(["run", fireflies, "--frames", "12", "--backend", "trace", "--record", str(path),
                 "--record-key", str(key), "-q"]) == 0
    assert json.loads(lines_of(path)[0])["chain"] == "hmac-sha256"
    assert main(["replay", str(path), "--record-key", str(key)]) == 0
    assert "12 frames replayed" in capsys.readouterr().out
    assert main(["replay", str(path)]) == 2
    assert "the record's chain is keyed (hmac-sha256): give its key" in capsys.readouterr().err
    assert main(["replay", str(path), "--record-key", str(other)]) == 2
    assert f"{path}:2: prev: the chain is broken here" in capsys.readouterr().err
    # Edited and made whole again without the key: as an unkeyed chain, or as a keyed one with another key.
    lines = [json.loads(x) for x in lines_of(path)]
    lines[3]["events"] = lines[3]["events"][:-1]
    path.write_text(chained(lines, key=other.read_bytes()))
    assert main(["replay", str(path), "--record-key", str(key)]) == 2
    assert f"{path}:2: prev: the chain is broken here" in capsys.readouterr().err
    lines[0]["chain"] = "sha256"
    path.write_text(chained(lines))
    assert main(["replay", str(path), "--record-key", str(key)]) == 2
    assert "a key was given, but this record's chain is not keyed" in capsys.readouterr().err
    short = tmp_path / "short"
    short.write_bytes(b"0123456789")
    assert main(["run", fireflies, "--frames", "2", "--backend", "trace", "--record", str(path), "--record-key",
                 str(short), "-q"]) == 2
    assert "a record key has at least 16 bytes; this file has 10" in capsys.readouterr().err
    assert main(["run", fireflies, "--frames", "2", "--backend", "trace", "--record-key", str(key), "-q"]) == 2
    assert "--record-key keys the record that --record writes" in capsys.readouterr().err


# ---- item 4: a record runs no code of its own --------------------------------------------------------------

ACTOR = '''
import vwg

class Blink(vwg.Actor):
    events = ("tick",)
    attributes = {"n": 0}

    def on_tick(self, e):
        return self.with_(n=self.n + 1)
'''


@pytest.fixture()
def blink(tmp_path) -> tuple[Path, Path, Path]:
    """A generic world whose actor is in a file beside it, its record, and a module elsewhere that
    writes a marker file when it is imported (and has an actor of the same name)."""
    world = tmp_path / "world" / "blink.yaml"
    world.parent.mkdir()
    (world.parent / "blink.py").write_text(ACTOR)
    world.write_text('alphabet: {events: [tick], actors: ["blink.py:Blink"]}\ninitial: "Blink<n=0>"\n'
                     "generators: [{every_frame: tick}]\nframes: 8\n")
    marker = tmp_path / "marker"
    evil = tmp_path / "elsewhere" / "evil.py"
    evil.parent.mkdir()
    evil.write_text(f"import pathlib\npathlib.Path({str(marker)!r}).write_text('ran')\n{ACTOR}")
    record = tmp_path / "blink.jsonl"
    assert main(["run", str(world), "--record", str(record), "-q"]) == 0
    return world, record, evil


def edit_world(record: Path, edit) -> None:
    lines = [json.loads(x) for x in lines_of(record)]
    edit(lines[0])
    record.write_text(chained(lines))


def test_a_record_naming_other_code_is_refused_and_the_code_does_not_run(tmp_path, capsys, blink):
    world, record, evil = blink
    marker = tmp_path / "marker"
    edit_world(record, lambda h: h["world"]["alphabet"].update(actors=[f"{evil}:Blink"]))
    for extra in ([], ["--from", "4"]):
        assert main(["replay", str(record), *extra]) == 2
        err = capsys.readouterr().err
        assert not marker.exists(), "replaying the record ran the code it names"
        assert str(record) in err and str(world) in err, err
        assert "differs from the world file the record names" in err and "Traceback" not in err
    # The user's own world file: its code runs, and the record replays against it.
    assert main(["replay", str(record), "--world", str(world)]) == 0
    assert "8 frames replayed" in capsys.readouterr().out and not marker.exists()
    # Asked for by name: the record's code is imported (and here replays, as its actor does the same).
    assert main(["replay", str(record), "--allow-code-from-record"]) == 0
    assert marker.read_text() == "ran"


def test_a_robot_record_naming_a_generic_world_file_runs_none_of_its_code(tmp_path, capsys, blink):
    # A robot world's record names a world file and a planner; made to name a generic world file whose
    # actor is code elsewhere, going on from a frame refuses it before loading it.
    _, _, evil = blink
    generic = evil.parent / "evil.yaml"
    generic.write_text(f'alphabet: {{events: [tick], actors: ["{evil}:Blink"]}}\ninitial: "Blink<n=0>"\n')
    record = tmp_path / "office.jsonl"
    assert main(["run", "office", "--frames", "12", "--goal", "kitchen", "--allow-unreached", "--record",
                 str(record), "-q", "--no-progress"]) == 0
    edit_world(record, lambda h: h["world"].update(robot_world=str(generic)))
    for extra in (["--from", "6"], []):
        assert main(["replay", str(record), *extra]) == 2
        err = capsys.readouterr().err
        assert "Traceback" not in err and str(generic) in err, err
        assert not (tmp_path / "marker").exists(), "replaying the record ran the code of the world file it names"


def test_a_record_whose_world_file_is_gone_replays_only_code_free(tmp_path, capsys, blink):
    world, record, _ = blink
    (world.parent / "blink.py").rename(tmp_path / "kept.py")
    world.unlink()
    assert main(["replay", str(record)]) == 2
    err = capsys.readouterr().err
    assert "names Python code (blink.py:Blink), and the world file it names" in err and "cannot be read" in err
    # A world that names no code is rebuilt from the record's copy alone.
    plain = tmp_path / "plain.jsonl"
    code_free = {"alphabet": {"events": ["tick"], "primitives": ["Lamp"]}, "initial": "Lamp"}
    plain.write_text(chained([header(world=code_free, world_file=str(tmp_path / "gone.yaml"),
                                     initial="Lamp"),
                              {"t": 0, "time": 0.0, "events": ["tick"], "string": "Lamp"},
                              {"end": True, "t": 1, "string": "Lamp", "frames": 1, "faults": []}]))
    assert main(["replay", str(plain)]) == 0
    assert "1 frames replayed, every string as recorded" in capsys.readouterr().out


# ---- item 6: vwg replay --from keeps the run's orders ------------------------------------------------------

@pytest.mark.slow
def test_resuming_a_robot_run_keeps_its_goal_orders(tmp_path, capsys):
    first, resumed = tmp_path / "first.jsonl", tmp_path / "resumed.jsonl"
    assert main(["run", "office", "--goal", "kitchen", "--record", str(first), "-q", "--no-progress"]) == 0
    arrived = read_record(first).end["t"]  # the run stops at the frame its robot reached the kitchen
    assert 100 < arrived < 3000
    capsys.readouterr()
    assert main(["replay", str(first), "--from", "100", "--record", str(resumed)]) == 0
    out = capsys.readouterr().out
    assert f"then live to frame {arrived}" in out, out
    assert "no robot had an order" not in out and "kitchen: reached" in out
    assert read_record(resumed).end["t"] == arrived


def test_vwg_check_takes_no_record(tmp_path, capsys, blink):
    # Not a regression test: vwg check reads world files only, and a record is refused as none.
    _, record, evil = blink
    edit_world(record, lambda h: h["world"]["alphabet"].update(actors=[f"{evil}:Blink"]))
    for text in (record.read_text(), record.read_text().splitlines()[0] + "\n"):  # the record; its header alone
        record.write_text(text)
        assert main(["check", str(record)]) == 2
        err = capsys.readouterr().err
        assert "not valid YAML" in err or "not a world file" in err, err
    assert not (tmp_path / "marker").exists()


def test_the_faults_of_the_end_line_are_read_and_printed(tmp_path, capsys):
    # A real robot's run keeps its faults in the end line (tests/test_link_faults.py writes one);
    # here a code-free record holds two, and replay prints each with its time and who.
    path = tmp_path / "faults.jsonl"
    faults = [{"time_s": 1.5, "robot": 0, "what": "link lost: closed by the robot"},
              {"time_s": 2.25, "robot": 1, "what": "no odometry for 0.5 s: stopped"}]
    code_free = {"alphabet": {"events": ["tick"], "primitives": ["Lamp"]}, "initial": "Lamp"}
    path.write_text(chained([header(world=code_free, world_file=str(tmp_path / "gone.yaml"), initial="Lamp"),
                             {"t": 0, "time": 0.0, "events": ["tick"], "string": "Lamp"},
                             {"end": True, "t": 1, "string": "Lamp", "frames": 1, "faults": faults}]))
    assert read_record(path).faults == faults
    assert main(["replay", str(path)]) == 0
    out = capsys.readouterr().out
    assert "  fault: 1.500 s, the link: link lost: closed by the robot\n" in out
    assert "  fault: 2.250 s, robot 1: no odometry for 0.5 s: stopped\n" in out


# ---- the header's fields a replay builds from, and the end line's faults, of the kind a run writes -----------

CODE_FREE = {"alphabet": {"events": ["tick"], "primitives": ["Lamp"]}, "initial": "Lamp"}
FRAME = {"t": 0, "time": 0.0, "events": ["tick"], "string": "Lamp"}
END = {"end": True, "t": 1, "string": "Lamp", "frames": 1, "faults": []}


def lamp(**fields) -> dict:
    """The header of a one-frame record of a world that names no code (its file gone: built from the copy)."""
    return header(**{"world": CODE_FREE, "world_file": "/nonexistent/lamp.yaml", "initial": "Lamp", **fields})


def replay_fails(path: Path, capsys, *extra: str) -> str:
    """vwg replay's standard error for a record it refuses: exit 2, no traceback."""
    assert main(["replay", str(path), *extra]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err, err
    return err


@pytest.mark.parametrize(("field", "said"), [
    ("initial", "initial: expected a string, got null"),
    ("blobs", "blobs: expected an object, got null"),
])
def test_a_null_initial_string_or_blobs_in_the_header_is_named(tmp_path, capsys, field, said):
    # 457d53e: AttributeError ('NoneType' object has no attribute 'items') for blobs, a pybind
    # TypeError from world.parse for initial.
    path = tmp_path / "null.jsonl"
    path.write_text(chained([lamp(**{field: None}), FRAME, END]))
    for extra in ([], ["--from", "0"]):
        assert f"{path}:1: {said}" in replay_fails(path, capsys, *extra)


@pytest.mark.parametrize(("fault", "said"), [
    ({"time_s": 10**400, "robot": 0, "what": "x"}, "faults[0]: time_s: expected seconds from 0 to 1e+09, got 1000"),
    ({"time_s": -1.5, "robot": 0, "what": "x"}, "faults[0]: time_s: expected seconds from 0 to 1e+09, got -1.5"),
    ({"time_s": True, "robot": 0, "what": "x"}, "faults[0]: time_s: expected seconds from 0 to 1e+09, got True"),
    ({"time_s": 1.0, "robot": 2**31, "what": "x"},
     "faults[0]: robot: expected a robot id from 0 (the link) to 2147483647, got 2147483648"),
    ({"time_s": 1.0, "robot": -1, "what": "x"}, "faults[0]: robot: expected a robot id from 0 (the link)"),
    ({"time_s": 1.0, "robot": 0, "what": "x" * 4097},
     "faults[0]: what: expected a text of at most 4096 characters, got 4097 characters"),
    ({"time_s": 1.0, "robot": 0, "what": None},
     "faults[0]: what: expected a text of at most 4096 characters, got None"),
    ({"robot": 0, "time_s": 1.0, "what": "x"},
     "faults[0]: expected {\"time_s\": seconds, \"robot\": id, \"what\": text}"),
])
def test_a_fault_in_the_end_line_out_of_what_a_run_writes_is_named(tmp_path, capsys, fault, said):
    # 457d53e: a 400-digit time passed the reader and crashed the replay's print (OverflowError);
    # a negative time or robot, or a text of any length, was printed as the run's.
    path = tmp_path / "fault.jsonl"
    path.write_text(chained([lamp(), FRAME, {**END, "faults": [fault]}]))
    with pytest.raises(vwg.WorldFileError) as e:
        read_record(path)
    assert e.value.line == 3
    assert f"{path}:3: {said}" in replay_fails(path, capsys)


def test_a_long_fault_text_is_cut_to_what_a_reader_takes(tmp_path):
    # The writer keeps its own records readable: a fault's text of 10,000 characters is kept as 4,096.
    engine = vwg.Engine(vwg.World(vwg.Alphabet(events=["tick"], primitives=["Lamp"])), "Lamp", [])
    path = tmp_path / "long.jsonl"
    recorder = vwg.io.record.Recorder(path, engine)
    engine.run(2)
    recorder.close(faults=[{"time_s": 1.25, "robot": 0, "what": "y" * 10_000}])
    [fault] = read_record(path).faults
    assert fault == {"time_s": 1.25, "robot": 0, "what": "y" * 4093 + "..."}


def test_an_empty_record_key_is_refused():
    # 457d53e: Chain(b"") named itself "sha256" but linked with an HMAC of the empty key, so its own
    # records did not read.
    with pytest.raises(vwg.Error, match="a record key is empty"):
        vwg.io.record.Chain(b"")
    assert vwg.io.record.Chain(None).name == "sha256" and vwg.io.record.Chain(b"k" * 16).name == "hmac-sha256"


# ---- a robot world's record: what its header names is checked, and errors name the record's field -----------

@pytest.fixture(scope="module")
def office_record(tmp_path_factory) -> Path:
    """A record of the office world, 12 frames, robot 1 sent to the kitchen."""
    record = tmp_path_factory.mktemp("office") / "office.jsonl"
    assert main(["run", "office", "--frames", "12", "--goal", "kitchen", "--allow-unreached", "--record",
                 str(record), "-q", "--no-progress"]) == 0
    return record


@pytest.mark.parametrize(("edit", "said", "from_only"), [
    # 457d53e: "planner: unknown planner 'nosuch' (known: ...)", naming neither the record nor its field.
    (lambda w: w.update(planner="nosuch"), "world.planner: unknown planner 'nosuch' (this vwg knows astar,", False),
    # 457d53e: "/nonexistent.yaml: file not found", as if the user had named it.
    (lambda w: w.update(robot_world="/nonexistent.yaml"),
     "world.robot_world: the world file the record names, '/nonexistent.yaml': file not found; give the world file "
     "to replay it with (--world FILE)", False),
    # 457d53e: ValueError: embedded null byte (a traceback) from files.check_regular_file.
    (lambda w: w.update(robot_world="office\x00.yaml"),
     "world.robot_world: the world file the record names, 'office\\x00.yaml': no file can have this name (it holds "
     "a NUL byte)", False),
    (lambda w: w.update(goals=["x:kitchen"]), "world.goals[0]: expected ROOM or ROBOT:ROOM, got 'x:kitchen'", False),
    # 457d53e: "goal: unknown room 'nosuchroom'" (from --from), naming neither the record nor its field.
    (lambda w: w.update(goals=["nosuchroom"]),
     "world.goals[0]: the run's order 'nosuchroom' names no room of the world (rooms: kitchen, lab,", True),
    (lambda w: w.update(goals=["kitchen", "7:lab"]),
     "world.goals[1]: the run's order '7:lab' names no robot of the world (robots: 1, 2)", True),
])
def test_what_a_robot_record_names_is_refused_naming_the_record_and_field(tmp_path, capsys, office_record, edit,
                                                                         said, from_only):
    record = tmp_path / "office.jsonl"
    record.write_text(office_record.read_text())
    edit_world(record, lambda h: edit(h["world"]))
    for extra in (["--from", "6"], *([] if from_only else [[]])):
        err = replay_fails(record, capsys, *extra)
        assert f"{record}:1: {said}" in err, err


def test_an_unknown_world_kind_is_named_by_the_record_and_field(tmp_path, capsys, office_record):
    # 457d53e: "unknown world kind 'bogus' (known: generic, robot)", naming neither the record nor its field.
    record = tmp_path / "office.jsonl"
    record.write_text(office_record.read_text())
    edit_world(record, lambda h: h.update(world_kind="bogus"))
    for extra in ([], ["--from", "6"]):
        err = replay_fails(record, capsys, *extra)
        assert f"{record}:1: world_kind: unknown world kind 'bogus' (this vwg knows generic, robot)" in err, err


def test_a_file_name_with_a_nul_byte_is_refused_naming_it(tmp_path):
    # 457d53e: ValueError (embedded null byte) from os.stat, not the WorldFileError the readers catch.
    for read in (vwg.io.files.read_text, lambda p: vwg.io.files.read_bytes(p, 100)):
        with pytest.raises(vwg.WorldFileError, match=r"'a\\x00b.yaml': no file can have this name \(it holds a NUL"):
            read("a\x00b.yaml")


def test_a_real_robots_faults_are_kept_when_the_run_ends_by_an_exception(tmp_path):
    # A run on the fake rosbridge robot whose link is cut at frame 5, stopped by Ctrl-C (an observer
    # raising KeyboardInterrupt) at the first frame after the platform has the link's fault: the end
    # line, written as the run closes, holds that fault. 457d53e wrote "faults": [] on any end but
    # execute()'s own.
    import dataclasses

    from vwg.robot.world_file import PlatformSpec
    from vwg.testing.fake_robot import FakeRosbridgeRobot

    maze = vwg.robot.load_robot_world("maze")
    maze = dataclasses.replace(maze, orders=[], robots=[maze.robots[0].replace(sensors=["laser"])])
    record = tmp_path / "cut.jsonl"
    seen: list[dict] = []
    with FakeRosbridgeRobot(maze) as fake:
        spec = PlatformSpec("rosbridge", {"url": fake.url})
        options = vwg.RunOptions(goals=["dead_end_8_6"], frames=300, record=record)
        with pytest.raises(KeyboardInterrupt), vwg.start(dataclasses.replace(maze, platform=spec), options) as run:
            platform = run.case.sim.platform

            def interrupt(frame: vwg._core.FrameRecord) -> None:
                if frame.frame == 5:
                    fake.cut()
                if platform.faults:
                    seen.extend(f.to_json() for f in platform.faults)
                    raise KeyboardInterrupt

            run.engine.add_observer(interrupt)
            run.execute()
    assert seen and seen[0]["robot"] == 0 and seen[0]["what"].startswith("link lost"), seen
    kept = read_record(record).faults
    assert kept[:len(seen)] == seen and len(kept) >= 1


def test_recorded_run_close_passes_the_platforms_faults():
    # The same, without a robot: RecordedRun.close() on a run that did not end through execute() gives
    # the recorder the faults of the platform the run reaches (run.case.sim.platform).
    from types import SimpleNamespace

    from vwg.launch import RecordedRun
    from vwg.robot.platforms.real_robot import Fault

    closed: list[object] = []
    platform = SimpleNamespace(faults=[Fault(2.5, 1, "no odometry for 0.5 s: stopped")])
    run = SimpleNamespace(case=SimpleNamespace(sim=SimpleNamespace(platform=platform)),
                          close=lambda: closed.append("run"))
    recorded = object.__new__(RecordedRun)  # without starting a record: only close() is under test
    recorded.run = run
    recorded.recorder = SimpleNamespace(close=lambda faults=(): closed.append(list(faults)))
    recorded.close()
    assert closed == [[{"time_s": 2.5, "robot": 1, "what": "no odometry for 0.5 s: stopped"}], "run"]
