"""Recording runs, replaying them exactly, and the vwg command."""

from __future__ import annotations

import json
import math
import struct
import subprocess
import sys

import numpy as np
import pytest

import vwg
from conftest import ROOT
from vwg.cli import main
from vwg.generic import load_world, replay
from vwg.io.record import Recorder, decode_blob, encode_blob, read_record

FIREFLIES = ROOT / "examples" / "01_fireflies" / "world.yaml"



def chained(objects, key: bytes | None = None) -> str:
    """Record lines for these objects as the writer makes them (format 5): each after the first holding
    the link of the line before (the first 32 hex digits of its SHA-256, or HMAC-SHA-256 with `key`),
    the end line also its own link (of its text without it): a record edited by hand, or by someone
    who knows the format. Written here from the format's description, not with vwg.io.record."""
    import hashlib
    import hmac

    def link(text: str) -> str:
        data = text.encode()
        return (hmac.new(key, data, hashlib.sha256) if key else hashlib.sha256(data)).hexdigest()[:32]

    def dumps(obj) -> str:
        return json.dumps(obj, ensure_ascii=False, separators=(",", ":"))

    out, prev = [], None
    for obj in objects:
        obj = {k: v for k, v in obj.items() if k not in ("prev", "self")}
        if prev is not None:
            obj["prev"] = prev
        if obj.get("end") is True:
            obj["self"] = link(dumps(obj))
        text = dumps(obj)
        out.append(text + "\n")
        prev = link(text)
    return "".join(out)


def rechain(path) -> None:
    path.write_text(chained(json.loads(x) for x in path.read_text().splitlines()))

def run_recorded(tmp_path, seed=7, frames=40):
    spec = load_world(FIREFLIES, seed=seed, backend="trace")  # the trace of φ, not the file's GIF
    engine = vwg.Engine(spec.world, spec.initial, spec.generators, spec.backend, seed=spec.seed)
    path = tmp_path / f"run{seed}.jsonl"
    with Recorder(path, engine, world_file=spec.path, world_data=spec.data):
        engine.run(frames)
    return path, engine


def test_record_has_a_header_one_line_per_frame_and_an_end(tmp_path):
    path, engine = run_recorded(tmp_path)
    record = read_record(path)
    assert record.header["seed"] == 7 and record.header["initial"].startswith("Firefly<id=1")
    assert [f["t"] for f in record.frames] == list(range(engine.frame))
    assert all("tick" in f["events"] and "show" in f["events"] for f in record.frames)
    assert record.end["string"] == str(engine.string)


def test_replay_gives_the_same_trace(tmp_path):
    path, engine = run_recorded(tmp_path)
    trace = vwg.TraceBackend()
    replayed = replay(path, backend=trace)
    assert str(replayed.string) == str(engine.string)
    assert trace.calls[0] == "frame 0"


def test_replay_detects_a_changed_record(tmp_path):
    path, _ = run_recorded(tmp_path)
    lines = path.read_text().splitlines()
    frame = json.loads(lines[6])  # frame 5
    frame["events"] = [e for e in frame["events"] if e != "tick"]
    lines[6] = json.dumps(frame)
    path.write_text("\n".join(lines) + "\n")
    # The chain names the change at once: the next line's hash of frame 5's line does not match.
    with pytest.raises(vwg.WorldFileError, match=r"chain is broken here: frame 5's line \(line 7\)") as info:
        read_record(path)
    assert info.value.line == 8
    # Made to look whole again (the hashes recomputed), the change is still found: by replaying it.
    rechain(path)
    with pytest.raises(vwg.ReplayError) as replayed:
        replay(path)
    assert replayed.value.frame == 6


def test_same_seed_same_record_bit_for_bit(tmp_path):
    a, _ = run_recorded(tmp_path / "a", seed=11)
    b, _ = run_recorded(tmp_path / "b", seed=11)
    c, _ = run_recorded(tmp_path / "c", seed=12)
    strip = lambda p: [json.loads(x) for x in p.read_text().splitlines()[1:]]  # noqa: E731
    assert strip(a) == strip(b)
    assert strip(a) != strip(c)


def test_bad_record_files(tmp_path):
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"vwg_record": 5, "chain": "sha256", "initial": "", "seed": 0, "dt": 0.1}\n'
                   '{"t": 0, "events": [], "string": ""\n')
    with pytest.raises(vwg.WorldFileError, match="not valid JSON") as info:
        read_record(bad)
    assert info.value.line == 2
    bad.write_text('{"something": "else"}\n')
    with pytest.raises(vwg.WorldFileError, match="not a vwg record"):
        read_record(bad)


def test_cli_run_record_replay_and_check(tmp_path, capsys):
    record = tmp_path / "run.jsonl"
    assert main(["run", str(FIREFLIES), "--frames", "30", "--seed", "3", "--backend", "trace",
                 "--record", str(record)]) == 0
    out = capsys.readouterr().out
    assert "frames" in out and "record" in out
    assert main(["replay", str(record)]) == 0
    assert "every string as recorded" in capsys.readouterr().out
    assert main(["check", str(FIREFLIES)]) == 0
    assert "Firefly" in capsys.readouterr().out


def test_cli_errors_are_one_clear_line(tmp_path, capsys):
    bad = tmp_path / "w.yaml"
    bad.write_text("alphabet: {}\ninitial: 'Nope'\n")
    assert main(["run", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"vwg: error: {bad}:2: initial:") and "unknown symbol 'Nope'" in err


def test_the_installed_command_runs():
    out = subprocess.run([sys.executable, "-m", "vwg.cli", "--version"], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == f"vwg {vwg.__version__}"


# --- format 2: events as columns, blobs as changes ---------------------------------------------

SPECIAL_FLOATS = [0.1 + 0.2, -0.0, 0.0, 1e-300, 5e-324, 2.225073858507201e-308, 1.7976931348623157e308,
                  -1e16, 1e16, 123456789.125, math.pi, -2.5, 1.0, 0.1, 1e-5, 9.999999999999999e15]
SPECIAL_INTS = [-2**63, 2**63 - 1, 0, -1, 1, 2**53 + 1, -(2**31), 7]


def _bits(v):
    if isinstance(v, float):
        return struct.unpack("<q", struct.pack("<d", v))[0]
    return int(v) + (7 if isinstance(v, bool) else 0)


class Folder(vwg.Actor):
    """Folds every event it gets, in order and bit for bit, into h: a changed, lost or reordered
    event changes the string."""

    events = ("sample", "flag", "note", "tick", "ping")
    attributes = {"id": 1, "h": 0}

    def _fold(self, *values):
        h = self.h
        for v in values:
            h = (h * 1000003 + _bits(v)) % (2**61 - 1)
        return self.with_(h=h)

    def on_sample(self, e):
        return self._fold(1, e.k, e.x, e.b)

    def on_flag(self, e):
        return self._fold(2, e.on)

    def on_note(self, e):
        return self._fold(3, len(e.text))

    def on_tick(self, e):
        return self._fold(4)

    def on_ping(self, e):
        return self._fold(5)


def folder_world():
    return vwg.World(events={"sample": {"k": 0, "x": 0.0, "b": False}, "flag": {"on": False},
                             "note": {"text": ""}, "tick": None, "ping": None},
                     actors=(Folder,))


def script(frame):
    """Every kind of value, runs long and short, mixed, in an order that matters."""
    n = len(SPECIAL_FLOATS)
    out = [vwg.Event("sample", 1, k=SPECIAL_INTS[(i + frame) % len(SPECIAL_INTS)],
                     x=SPECIAL_FLOATS[(i + frame) % n], b=(i + frame) % 3 == 0) for i in range(12)]
    out += [vwg.Event("sample", k=i, x=i / 3, b=True) for i in range(7)]  # one short of a run
    out.append(vwg.Event("note", 2, text='a, b=c "d"'))
    out += [vwg.Event("tick")] * 10
    out += [vwg.Event("ping", 1 + i % 2) for i in range(9 + frame % 2)]
    out += [vwg.Event("flag", on=(i * frame) % 2 == 1) for i in range(8)]
    out += [vwg.Event("sample", 2, k=frame, x=frame + i * 0.5, b=False) for i in range(8)]
    out.append(vwg.Event("tick"))
    return out


class Script(vwg.Generator):
    name = "script"

    def generate(self, frame):
        return script(frame.frame)


def run_folder(path, frames=6):
    world = folder_world()
    engine = vwg.Engine(world, "Folder<id=1, h=0> . Folder<id=2, h=0>", [Script()])
    texts = []
    engine.add_observer(lambda r: texts.append(r.event_texts))
    with Recorder(path, engine, world_data={"note": "folder"}):
        engine.run(frames)
    return world, engine, texts


def test_runs_of_every_value_kind_read_back_as_the_engine_wrote_them(tmp_path):
    path = tmp_path / "folder.jsonl"
    world, engine, texts = run_folder(path)
    record = read_record(path)
    assert [f["events"] for f in record.frames] == texts
    # Runs of 8 or more (long samples, ticks, pings, flags) are columns; shorter ones and the
    # note (a text field) stay text.
    line = json.loads(path.read_text().splitlines()[1])
    kinds = [(item["run"], item["n"]) if isinstance(item, dict) else item.split("<")[0] for item in line["events"]]
    assert kinds == [("sample", 12)] + ["sample"] * 7 + ["note", ("tick", 10), ("ping", 9), ("flag", 8),
                                                          ("sample", 8), "tick"]
    assert line["events"][0]["fields"].keys() == {"k", "x", "b"} and "to" in line["events"][0]
    assert "to" not in line["events"][-3] and "fields" not in line["events"][-4]  # flag; ping
    # Every float is the same double, every int the same int.
    for frame, frame_texts in zip(record.frames, texts, strict=True):
        got = [world.event(t) for t in frame["events"][:12]]
        want = script(frame["t"])[:12]
        assert [(e.target, e.k, _bits(e.x), e.b) for e in got] == [(e.target, e.k, _bits(e.x), e.b) for e in want]
        assert frame["events"] == frame_texts
    assert str(replay(path, world=world).string) == str(engine.string)


def test_columns_keep_any_bits(tmp_path):
    from vwg.io.record import _Columns

    rng = np.random.default_rng(1)
    floats = rng.integers(-(2**63), 2**63 - 1, 300, dtype=np.int64, endpoint=True).view(np.float64)
    ints = np.array(SPECIAL_INTS * 5, dtype=np.int64)
    bools = rng.random(41) < 0.5
    writer, reader = _Columns(), _Columns()
    sig = ("e", True, (("x", "f"),))
    for frame in range(3):  # later frames decode with the earlier ones as dictionaries
        writer.start_frame()
        reader.start_frame()
        for name, a in (("x", floats[frame:]), ("k", ints), ("b", bools), ("none", ints[:0])):
            back = reader.decode((sig, 0, name), writer.encode((sig, 0, name), a), a.dtype, a.size)
            assert back.dtype == a.dtype and back.tobytes() == a.tobytes()


def test_base85_is_pythons(tmp_path):
    import base64

    from vwg.io.record import _b85decode, _b85encode

    rng = np.random.default_rng(2)
    for n in [*range(12), 1000, 4097]:
        data = rng.integers(0, 256, n, dtype=np.uint8).tobytes()
        assert _b85encode(data) == base64.b85encode(data).decode()
        assert _b85decode(_b85encode(data)) == data


def rewrite_events(path, world, edit):
    """Re-encode a record's events after `edit(t, texts)` changed the texts of frame t."""
    from vwg.io.record import MIN_RUN, _Columns, _decode_events, _encode_events

    lines = [json.loads(x) for x in path.read_text().splitlines()]
    reader, writer = _Columns(), _Columns()
    # An engine takes the edited events, so that the runs are the engine's as a recorder sees them.
    engine = vwg.Engine(world, lines[0]["initial"], [])
    runs = []
    engine.add_observer(lambda r: runs.append(r.event_runs(MIN_RUN)))
    for obj in lines[1:]:
        if "events" in obj:
            texts = _decode_events(reader, obj["events"])
            edit(obj["t"], texts)
            engine.step_with([world.event(t) for t in texts])
            obj["events"] = _encode_events(writer, runs[-1])
    path.write_text(chained(lines))


def test_replay_detects_a_changed_event_value(tmp_path):
    path = tmp_path / "folder.jsonl"
    world, _, _ = run_folder(path)
    rewrite_events(path, world, lambda t, texts: None)
    assert replay(path, world=world)  # re-encoded as it was: still replays

    def one_ulp(t, texts):
        if t == 3:  # the 5th long-run sample: a column value, one bit changed
            e = world.event(texts[4])
            texts[4] = str(world.event(f"sample<to={e.target}, k={e.k}, x={float(np.nextafter(e.x, 1e308))!r}, "
                                       f"b={str(e.b).lower()}>"))

    rewrite_events(path, world, one_ulp)
    assert isinstance(json.loads(path.read_text().splitlines()[4])["events"][0], dict)
    with pytest.raises(vwg.ReplayError) as info:
        replay(path, world=world)
    assert info.value.frame == 4


def blob_pair(dtype, shape, changes):
    rng = np.random.default_rng(3)
    base = (rng.random(shape) * 100).astype(dtype)
    new = base.copy()
    for index, value in changes:
        new[index] = value
    return vwg.Blob(base), vwg.Blob(new)


@pytest.mark.parametrize(("dtype", "shape", "changes"), [
    (np.int16, (36, 50), [((0, 0), -1), ((35, 49), 101), ((10, 7), 101), ((10, 8), 0)]),
    (np.int8, (7,), [((6,), -128)]),
    (np.float64, (20, 2), [((3, 1), -0.0), ((0, 0), 5e-324)]),
    (np.uint8, (4, 4, 3), []),
])
def test_blob_change_round_trip(dtype, shape, changes):
    base, new = blob_pair(dtype, shape, changes)
    entry = encode_blob(new, base, base.name)
    assert entry.keys() == {"base", "zlib_base85"}
    back = decode_blob(entry, {base.name: base})
    assert back.name == new.name and np.asarray(back).tobytes() == np.asarray(new).tobytes()
    assert back.dtype == new.dtype and back.shape == new.shape


def write_record(path, header_blobs, frames=()):
    header = {"vwg_record": 5, "chain": "sha256", "initial": "", "seed": 0, "dt": 0.1, "blobs": header_blobs}
    lines = [header, *({"t": t, "time": t / 10, "events": [], "string": "", "blobs": b} for t, b in enumerate(frames))]
    path.write_text(chained(lines))


def test_a_recorded_robot_grid_is_stored_as_changes(tmp_path):
    base, new = blob_pair(np.int16, (360, 500), [((100, 200), 101), ((101, 200), 101)])
    path = tmp_path / "blobs.jsonl"
    write_record(path, {base.name: encode_blob(base)}, [{new.name: encode_blob(new, base, base.name)}])
    record = read_record(path)
    assert record.blobs[new.name] == new
    assert len(path.read_text().splitlines()[1]) < 200  # two changed cells of a 360 KB grid


UNSIGNED = {1: np.uint8, 2: np.uint16, 4: np.uint32, 8: np.uint64}


@pytest.mark.parametrize("dtype", [np.int8, np.uint8, np.int16, np.int32, np.int64, np.float32, np.float64])
def test_changes_from_finds_every_changed_element_and_stops_past_the_limit(dtype):
    rng = np.random.default_rng(5)
    base = rng.integers(0, 100, (37, 61)).astype(dtype)  # 2,257 elements: stretches of 256 bytes and a tail
    new = base.copy()
    flat = new.reshape(-1)
    per_stretch = 256 // base.itemsize
    picks = [0, 1, per_stretch - 1, per_stretch, 5 * per_stretch + 3, flat.size - 1, *rng.integers(0, flat.size, 20)]
    for i in picks:
        flat[i] += 1
    if np.issubdtype(dtype, np.floating):
        flat[100], base.reshape(-1)[100] = -0.0, 0.0  # equal as numbers, not as bits: a change
    u = UNSIGNED[base.itemsize]
    x = new.view(u).reshape(-1) ^ base.view(u).reshape(-1)
    want = np.flatnonzero(x)  # numpy's own count, as bits
    where, values = vwg.Blob(new).changes_from(vwg.Blob(base))
    assert where.dtype == np.int64 and values.dtype == u
    assert where.tolist() == want.tolist() and values.tolist() == x[want].tolist()
    assert vwg.Blob(new).changes_from(vwg.Blob(base), len(want))[0].tolist() == want.tolist()
    assert vwg.Blob(new).changes_from(vwg.Blob(base), len(want) - 1) is None
    same = vwg.Blob(base).changes_from(vwg.Blob(base.copy()), 0)
    assert same is not None and same[0].size == 0 and same[1].size == 0


def test_changes_from_refuses_another_shape_or_a_negative_limit():
    a = vwg.Blob(np.zeros((4, 5), np.int16))
    with pytest.raises(vwg.SchemaError, match=r"base: expected a blob of the same dtype and shape as int16 \(4, 5\), "
                                              r"got int16 \(5, 4\)"):
        a.changes_from(vwg.Blob(np.zeros((5, 4), np.int16)))
    with pytest.raises(vwg.SchemaError, match="got int8"):
        a.changes_from(vwg.Blob(np.zeros((4, 5), np.int8)))
    with pytest.raises(vwg.SchemaError, match="limit: expected a count of elements >= 0, got -1"):
        a.changes_from(a, -1)


class Painter(vwg.Actor):
    """Paints one cell of its own grid each tick: where depends on its id and the frame."""

    events = ("tick",)
    attributes = {"id": int, "n": 0, "grid": vwg.Blob}

    def on_tick(self, e):
        g = np.array(self.grid)
        g.flat[(self.n * 37 + self.id * 101) % g.size] += 1
        return self.with_(n=self.n + 1, grid=g)


class Ticker(vwg.Generator):
    name = "ticker"

    def generate(self, frame):
        return [vwg.Event("tick")]


def test_a_changed_grid_is_stored_against_what_its_slot_held_the_frame_before(tmp_path):
    # Six actors share the start of one grid and each paints its own cells: the closest blob to
    # an actor's new grid is its own grid a frame before, not the other actors' newer ones.
    world = vwg.World(events={"tick": None}, actors=(Painter,))
    rng = np.random.default_rng(8)
    grids = {f"g{k}": vwg.Blob(rng.integers(0, 50, (60, 80)).astype(np.int16)) for k in range(6)}
    initial = world.parse(" . ".join(f"Painter<id={k}, n=0, grid=@g{k}>" for k in range(6)), "<t>", grids)
    engine = vwg.Engine(world, initial, [Ticker()])
    held = [[a["grid"].name for a in initial.actors()]]
    engine.add_observer(lambda r: held.append([a["grid"].name for a in r.after.actors()]))
    path = tmp_path / "painters.jsonl"
    with Recorder(path, engine, world_data={"note": "painters"}):
        engine.run(5)
    lines = [json.loads(x) for x in path.read_text().splitlines()]
    for t in range(1, 6):
        entries = lines[t]["blobs"]
        assert set(entries) == set(held[t])
        for k, name in enumerate(held[t]):
            assert entries[name]["base"] == held[t - 1][k]  # the actor's own grid a frame before
    assert str(replay(path, world=world).string) == str(engine.string)


def test_every_double_a_run_holds_reads_back_as_its_repr(tmp_path):
    # The record stores a run's floats by their bits and writes them back as Python's repr: that
    # must be the engine's own text for every double, or replay would parse other texts.
    rng = np.random.default_rng(11)
    bits = rng.integers(-(2**63), 2**63 - 1, 4000, dtype=np.int64, endpoint=True).view(np.float64)
    xs = [float(x) for x in bits if math.isfinite(x)] + SPECIAL_FLOATS

    class Floats(vwg.Generator):
        name = "floats"

        def generate(self, frame):
            return [vwg.Event("sample", 1, k=i, x=x, b=False) for i, x in enumerate(xs)]

    world = folder_world()
    engine = vwg.Engine(world, "Folder<id=1, h=0>", [Floats()])
    path = tmp_path / "floats.jsonl"
    with Recorder(path, engine, world_data={"note": "floats"}):
        engine.run(1)
    line = json.loads(path.read_text().splitlines()[1])
    assert [item["n"] for item in line["events"]] == [len(xs)]  # one run, by columns
    texts = read_record(path).frames[0]["events"]
    assert texts == [f"sample<to=1, k={i}, x={x!r}, b=false>" for i, x in enumerate(xs)]


def test_a_damaged_blob_change_is_detected(tmp_path):
    base, new = blob_pair(np.int16, (36, 50), [((3, 4), 7)])
    _, other = blob_pair(np.int16, (36, 50), [((3, 4), 8)])
    path = tmp_path / "bad.jsonl"
    # A change that decodes, but to other content than its name says.
    write_record(path, {base.name: encode_blob(base)}, [{new.name: encode_blob(other, base, base.name)}])
    with pytest.raises(vwg.WorldFileError, match=f"blobs.{new.name}: decodes to blob {other.name}") as info:
        read_record(path)
    assert info.value.line == 2 and str(path) in str(info.value)
    # Payload damage, and a base that was never written.
    entry = encode_blob(new, base, base.name)
    entry["zlib_base85"] = entry["zlib_base85"][:-3] + "~~~"
    write_record(path, {base.name: encode_blob(base)}, [{new.name: entry}])
    with pytest.raises(vwg.WorldFileError, match="cannot decode") as info:
        read_record(path)
    assert info.value.line == 2
    write_record(path, {new.name: encode_blob(new, base, base.name)})
    with pytest.raises(vwg.WorldFileError, match="was not written before it") as info:
        read_record(path)
    assert info.value.line == 1


def test_a_format_1_record_is_refused(tmp_path):
    old = tmp_path / "old.jsonl"
    old.write_text('{"vwg_record": 1, "initial": "", "seed": 0, "dt": 0.1}\n{"t": 0, "events": [], "string": ""}\n')
    with pytest.raises(vwg.WorldFileError, match="this record is format 1; this vwg reads format 5 only") as info:
        read_record(old)
    assert info.value.line == 1 and info.value.field == "vwg_record"
    with pytest.raises(vwg.WorldFileError, match="format 1"):
        replay(old)


def test_a_damaged_run_names_the_file_and_line(tmp_path):
    path, _ = run_recorded(tmp_path)
    lines = path.read_text().splitlines()
    for n, text in enumerate(lines[1:-1], start=2):
        frame = json.loads(text)
        runs = [i for i, item in enumerate(frame["events"]) if isinstance(item, dict)]
        if runs:
            frame["events"][runs[0]]["n"] += 1
            lines[n - 1] = json.dumps(frame)
            break
    else:
        pytest.fail("no run in the fireflies record")
    path.write_text("\n".join(lines) + "\n")
    rechain(path)  # past the chain: the run's own check names it
    with pytest.raises(vwg.WorldFileError, match=f"events\\[{runs[0]}\\]: cannot decode") as info:
        read_record(path)
    assert info.value.line == n


@pytest.mark.slow
def test_the_demo_run_record_is_small_and_replays(tmp_path):
    # Each frame of the office demo has ~690 laser ranges with 1 cm of noise: ~46 bits of each
    # are noise, ~4.2 KB a frame after deflate, ~5.3 KB in base85; with the string (~0.5 KB),
    # odometry, angles and grid changes a frame takes ~6.6 KB. Format 1 took ~54 KB.
    from vwg.robot.case_study import CaseStudy
    from vwg.robot.world_file import load_robot_world

    world = load_robot_world(ROOT / "maps" / "office.yaml")
    case = CaseStudy(world, "astar", goals={1: "kitchen"}, world_orders=False)
    path = tmp_path / "office.jsonl"
    with Recorder(path, case.engine, world_file=world.path,
                  world_data={"robot_world": str(world.path), "planner": case.planner}):
        summary = case.run(frames=320)
    assert summary.reached and 250 <= summary.frames <= 320
    size = path.stat().st_size
    assert size <= 7_000 * summary.frames, f"{size / summary.frames:.0f} bytes a frame"
    record = read_record(path)
    assert len(record.frames) == summary.frames
    assert sum(isinstance(item, dict) for item in json.loads(path.read_text().splitlines()[5])["events"]) >= 1
    from vwg.robot.case_study import case_study_world, make_decider

    replayed = replay(path, world=case_study_world(load_robot_world(world.path), make_decider("astar")))
    assert str(replayed.string) == record.end["string"]


# ---- crash-safe records: the chain, a cut run, a torn last line --------------------------------------
@pytest.mark.parametrize(("damage", "line", "before"), [
    ("drop", 6, "frame 3's line (line 5)"),          # frame 4's line taken out
    ("swap", 6, "frame 3's line (line 5)"),          # frames 4 and 5 change places
    # frame 4 says it is frame 14: named by its own line (the chain would name it at the next)
    ("renumber", 6, "t: frame 14; the line before holds frame 3, so this line holds frame 4"),
    ("seed", 2, "the header (line 1)"),              # the header's seed changed
    ("dt", 2, "the header (line 1)"),                # the header's dt changed
])
def test_the_chain_names_any_edit_drop_or_reorder(tmp_path, damage, line, before):
    path = tmp_path / "folder.jsonl"
    run_folder(path)
    lines = path.read_text().splitlines()
    if damage == "drop":
        del lines[5]
    elif damage == "swap":
        lines[5], lines[6] = lines[6], lines[5]
    elif damage == "renumber":
        lines[5] = lines[5].replace('"t":4,', '"t":14,', 1)
    else:
        header = json.loads(lines[0])
        header[damage] += 1
        lines[0] = json.dumps(header, separators=(",", ":"))
    assert "\n".join(lines) + "\n" != path.read_text()
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(vwg.WorldFileError) as info:
        read_record(path)
    said = before if damage == "renumber" else f"chain is broken here: {before}"
    assert info.value.line == line and said in str(info.value), str(info.value)


def test_a_flipped_byte_in_a_blob_is_named(tmp_path):
    from vwg.robot.case_study import CaseStudy
    from vwg.robot.world_file import load_robot_world

    case = CaseStudy(load_robot_world("office"), "astar", goals={1: "kitchen"}, world_orders=False)
    path = tmp_path / "office.jsonl"
    with Recorder(path, case.engine):
        case.run(frames=3)
    case.close()
    lines = path.read_text().splitlines()
    header = json.loads(lines[0])
    blob = next(iter(header["blobs"].values()))  # a robot's grid
    text = blob["zlib_base85"]
    blob["zlib_base85"] = text[:40] + ("A" if text[40] != "A" else "B") + text[41:]
    lines[0] = json.dumps(header, separators=(",", ":"), ensure_ascii=False)
    path.write_text("\n".join(lines) + "\n")
    # The chain is checked before any blob is inflated: it names the change at line 2.
    with pytest.raises(vwg.WorldFileError, match=r"chain is broken here: the header \(line 1\)") as info:
        read_record(path)
    assert info.value.line == 2
    # Made to look whole again, the blob is named where it is: it no longer decodes to its content.
    rechain(path)
    with pytest.raises(vwg.WorldFileError, match=r"blobs\.[0-9a-f]{16}: (cannot decode|decodes to blob)") as info:
        read_record(path)
    assert info.value.line == 1


def test_a_run_killed_mid_way_replays_and_says_it_was_cut(tmp_path):
    import signal
    import time

    record = tmp_path / "run.jsonl"
    run = subprocess.Popen([sys.executable, "-m", "vwg.cli", "run", "office", "--frames", "3000", "--goal", "kitchen",
                            "--record", str(record), "--allow-unreached", "--no-progress"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        while not record.exists() or record.read_bytes().count(b"\n") < 30:
            assert run.poll() is None, "the run ended before it could be killed"
            time.sleep(0.05)
    finally:
        run.send_signal(signal.SIGKILL)  # no chance to write anything more
        run.wait()
    # A kill between two lines, or in the middle of one: both replay what is whole, and say what is missing.
    data = record.read_bytes()
    whole = data[:data.rindex(b"\n") + 1]
    for name, content in (("between.jsonl", whole), ("torn.jsonl", whole + data[len(whole):] + b'{"t":9999,"ti')):
        path = tmp_path / name
        path.write_bytes(content)
        done = subprocess.run([sys.executable, "-m", "vwg.cli", "replay", str(path)], capture_output=True, text=True,
                              timeout=300)
        frames = whole.count(b"\n") - 1
        assert done.returncode == 0, done.stderr
        assert f"{frames} frames replayed, every string as recorded" in done.stdout
        assert f"the run was cut after {frames} frames of the 3000 planned" in done.stdout
        torn = "the last line is cut short" in done.stderr
        assert torn == (name == "torn.jsonl"), done.stderr


def test_a_replay_that_differs_shows_where_with_context():
    from vwg.errors import ReplayError

    record = "ARobot<id=1, " + "x" * 500 + "status=\"to kitchen\", wait=0>"
    got = record.replace("kitchen", "kitchem")
    message = str(ReplayError(12, record, got))
    at = record.index("kitchen") + 6
    assert f"frame 12: the replay's string differs from the record's at character {at + 1}:" in message
    lines = message.splitlines()
    replay_line, record_line, caret = lines[1], lines[2], lines[3]
    assert "kitchem" in replay_line and "kitchen" in record_line and len(replay_line) < 150
    column = caret.index("^")
    assert replay_line[column] == "m" and record_line[column] == "n"


@pytest.mark.parametrize(("world", "args"), [
    (str(FIREFLIES), ["--frames", "40"]),
    ("office", ["--frames", "60", "--goal", "kitchen", "--allow-unreached"]),  # the robot world, on the simulator
])
def test_a_run_goes_on_from_a_recorded_frame_as_it_went_the_first_time(tmp_path, world, args):
    first, resumed = tmp_path / "first.jsonl", tmp_path / "resumed.jsonl"
    assert main(["run", world, *args, "--record", str(first), "--quiet"]) == 0
    a = read_record(first)
    at = len(a.frames) // 2 + 3
    # The robot keeps its order (kitchen, not reached in 60 frames): exit 0 as the first run, by the same flag.
    allow = ["--allow-unreached"] if "--allow-unreached" in args else []
    assert main(["replay", str(first), "--from", str(at), "--record", str(resumed), *allow]) == 0
    b = read_record(resumed)
    # The frames from `at` on again, live with the world's generators from there (their state carried
    # through the frames before): the same events, the same strings, the same end.
    assert [f["t"] for f in b.frames] == [f["t"] for f in a.frames[at:]]
    assert [(f["events"], f["string"]) for f in b.frames] == [(f["events"], f["string"]) for f in a.frames[at:]]
    assert b.end["string"] == a.end["string"]


def test_going_on_from_a_frame_the_record_does_not_hold_is_refused(tmp_path, capsys):
    first = tmp_path / "first.jsonl"
    assert main(["run", str(FIREFLIES), "--frames", "10", "--record", str(first), "--quiet"]) == 0
    assert main(["replay", str(first), "--from", "99"]) == 2
    assert "--from: the record holds frames 0 to 9; got 99" in capsys.readouterr().err
