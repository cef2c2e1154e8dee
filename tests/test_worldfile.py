"""World files: loading, and errors that name the file, the line and the field."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

import vwg
from conftest import ROOT
from vwg.generic import load_world

GOOD = """\
name: tiny
alphabet:
  primitives: [Lamp]
  transformations: {Move: {dist: 0.0}}
  events: {tick: {}, show: {}}
  visual: [show]
  actors: ["actors.py:Blinker"]
initial: "Move<2.0>(Blinker<on=true>) . Blinker"
generators:
  - every_frame: tick
  - every_frame: show
  - schedule: {2: ["tick"]}
backend: trace
frames: 4
seed: 3
"""

ACTORS = """\
import vwg

class Blinker(vwg.Actor):
    events = ("tick", "show")
    attributes = {"on": False}

    def on_tick(self, e):
        return self.with_(on=not self.on)

    def show_show(self, e):
        return "Lamp" if self.on else ""
"""


def write(tmp_path: Path, text: str) -> Path:
    (tmp_path / "actors.py").write_text(ACTORS)
    path = tmp_path / "world.yaml"
    path.write_text(textwrap.dedent(text))
    return path


def test_a_world_file_loads_and_runs(tmp_path):
    spec = load_world(write(tmp_path, GOOD))
    assert (spec.name, spec.frames, spec.seed, spec.dt) == ("tiny", 4, 3, 0.1)
    engine = vwg.Engine(spec.world, spec.initial, spec.generators, spec.backend, seed=spec.seed)
    engine.run(spec.frames)
    # Blinkers toggle every tick; frame 2 has an extra scheduled tick: 5 toggles in 4 frames.
    assert str(engine.string) == "Move<2.0>(Blinker<on=false>) . Blinker<on=true>"
    assert spec.backend.calls[:4] == ["frame 0", "beta Move<2.0>", "alpha Lamp", "delta Move<2.0>"]


@pytest.mark.parametrize(
    ("change", "line", "field", "message"),
    [
        (("frames: 4", "frames: -1"), 14, "frames", "expected a number >= 0"),
        (("frames: 4", "frames: four"), 14, "frames", "expected an integer"),
        (("  visual: [show]", "  visual: [shw]"), 6, "alphabet.visual[0]", "'shw' is not among alphabet.events"),
        (('initial: "Move<2.0>(Blinker<on=true>) . Blinker"', 'initial: "Move<2.0>(Blinker<on=yes>)"'), 8, "initial",
         "found 'yes'"),
        (("  - every_frame: show", "  - every_frame: shout"), 11, "generators[1]", "unknown event type"),
        (("backend: trace", "backend: opengl"), 13, "backend", "unknown backend 'opengl' (known: null, trace"),
        (('  actors: ["actors.py:Blinker"]', '  actors: ["actors.py:Blinkr"]'), 7, "alphabet.actors[0]",
         "has no 'Blinkr'"),
        (('  actors: ["actors.py:Blinker"]', '  actors: ["missing.py:Blinker"]'), 7, "alphabet.actors[0]", "no file"),
        (("seed: 3", "seed: 3\ncolour: red"), 16, "colour", "unknown key"),
        (("  primitives: [Lamp]", "  primitives: [Lamp, Lamp]"), 3, "alphabet.primitives[1]", "already registered"),
        (("  transformations: {Move: {dist: 0.0}}", "  transformations: {Move: {dist: .nan}}"), 4,
         "alphabet.transformations.Move", "finite"),
    ],
)
def test_bad_world_files_name_file_line_and_field(tmp_path, change, line, field, message):
    path = write(tmp_path, GOOD.replace(*change))
    with pytest.raises(vwg.WorldFileError) as info:
        load_world(path)
    e = info.value
    assert e.path == str(path)
    assert (e.line, e.field) == (line, field), str(e)
    assert message in str(e)


def test_missing_and_malformed_files(tmp_path):
    with pytest.raises(vwg.WorldFileError, match="file not found"):
        load_world(tmp_path / "nope.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("alphabet: [unclosed\n")
    with pytest.raises(vwg.WorldFileError, match="not valid YAML") as info:
        load_world(bad)
    assert info.value.line == 2
    no_initial = write(tmp_path, GOOD.replace('initial: "Move<2.0>(Blinker<on=true>) . Blinker"\n', ""))
    with pytest.raises(vwg.WorldFileError, match="initial: missing"):
        load_world(no_initial)


# The generic worlds of the examples (examples/plugin's is a robot world of a plugin's parts:
# tests/test_example_plugin.py installs the plugin and runs it).
EXAMPLES = sorted(p for p in (ROOT / "examples").glob("*/world.yaml") if p.parent.name != "plugin")


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.parent.name for p in EXAMPLES])
def test_every_example_world_runs(path):
    spec = load_world(path, frames=20)
    engine = vwg.Engine(spec.world, spec.initial, spec.generators, spec.backend, dt=spec.dt, seed=spec.seed)
    reason = engine.run(spec.frames)
    assert engine.frame == 20 or reason == "empty"
