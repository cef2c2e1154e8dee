"""Recording runs, replaying them exactly, and the vwg command."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import vwg
from conftest import ROOT
from vwg.cli import main
from vwg.record import Recorder, read_record, replay
from vwg.worldfile import load_world

FIREFLIES = ROOT / "examples" / "01_fireflies" / "world.yaml"


def run_recorded(tmp_path, seed=7, frames=40):
    spec = load_world(FIREFLIES, seed=seed)
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
    with pytest.raises(vwg.ReplayError) as info:
        replay(path)
    assert info.value.frame == 6


def test_same_seed_same_record_bit_for_bit(tmp_path):
    a, _ = run_recorded(tmp_path / "a", seed=11)
    b, _ = run_recorded(tmp_path / "b", seed=11)
    c, _ = run_recorded(tmp_path / "c", seed=12)
    strip = lambda p: [json.loads(x) for x in p.read_text().splitlines()[1:]]  # noqa: E731
    assert strip(a) == strip(b)
    assert strip(a) != strip(c)


def test_bad_record_files(tmp_path):
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"vwg_record": 1, "initial": "", "seed": 0, "dt": 0.1}\n{"t": 0, "events": [], "string": ""\n')
    with pytest.raises(vwg.WorldFileError, match="not valid JSON") as info:
        read_record(bad)
    assert info.value.line == 2
    bad.write_text('{"something": "else"}\n')
    with pytest.raises(vwg.WorldFileError, match="not a vwg record"):
        read_record(bad)


def test_cli_run_record_replay_and_check(tmp_path, capsys):
    record = tmp_path / "run.jsonl"
    assert main(["run", str(FIREFLIES), "--frames", "30", "--seed", "3", "--record", str(record)]) == 0
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
