"""One loader, one run path and one replay path for every kind of world file (vwg.launch)."""

from __future__ import annotations

import json

import pytest

import vwg
from conftest import ROOT
from vwg import _core
from vwg.generic import WorldSpec
from vwg.launch import describe, replay_world
from vwg.plugins import backends

FIREFLIES = ROOT / "examples" / "01_fireflies" / "world.yaml"


def test_one_loader_reads_both_kinds():
    office = vwg.load("office")
    assert isinstance(office, vwg.robot.RobotWorld) and office.name == "office"
    fireflies = vwg.load(FIREFLIES)
    assert isinstance(fireflies, WorldSpec) and fireflies.name == "fireflies"
    assert describe(office)[0] == "a robot world (office)\n  " + office.description
    assert describe(fireflies)[0] == "a generic world (fireflies)"


def test_an_option_that_does_not_apply_is_refused_by_name():
    with pytest.raises(vwg.Error, match=r"--planner is for robot worlds; .*world.yaml is a generic world"):
        vwg.start(vwg.load(FIREFLIES), vwg.RunOptions(planner="astar"))
    with pytest.raises(vwg.Error, match=r"--video is for robot worlds"):
        vwg.start(vwg.load(FIREFLIES), vwg.RunOptions(video=ROOT / "x.mp4"))


@pytest.mark.parametrize(("options", "message"), [
    ({"frames": -5}, "--frames: expected a number of frames from 0 to 2**64 - 1, got -5"),
    ({"seed": 2**70}, "--seed: expected an integer from 0 to 2**64 - 1"),
    ({"dt": 0.0}, "--dt: expected a number of seconds from 1e-06 to 3600"),
    ({"dt": float("nan")}, "--dt: expected a number of seconds from 1e-06 to 3600"),
])
def test_values_no_world_takes_are_refused(options, message):
    with pytest.raises(vwg.Error) as info:
        vwg.start(vwg.load(FIREFLIES), vwg.RunOptions(**options))
    assert message in str(info.value)


def test_dt_and_seed_apply_to_robot_worlds():
    # Before, a robot world ignored --dt: 4 frames of 0.05 s are 0.2 s of simulated time.
    with vwg.start(vwg.load("office"), vwg.RunOptions(dt=0.05, frames=4, seed=7, allow_unreached=True)) as run:
        outcome = run.execute()
    assert outcome.summary["frames"] == 4 and outcome.summary["seed"] == 7
    assert outcome.summary["simulated_time_s"] == pytest.approx(0.2)


def test_a_backend_by_name_shows_a_robot_world_beside_its_simulator():
    kept: list[_core.TraceBackend] = []

    def keep(**_: object) -> _core.TraceBackend:
        kept.append(_core.TraceBackend())
        return kept[-1]

    backends.register("test-launch-trace", keep)
    try:
        with vwg.start(vwg.load("office"), vwg.RunOptions(backend="test-launch-trace", frames=3,
                                                         allow_unreached=True)) as run:
            run.execute()
    finally:
        backends.unregister("test-launch-trace")
    # The trace saw each frame's displayable string: the robots (Robot<id>) under their motion.
    assert len(kept) == 1
    shown = [c for c in kept[0].calls if "Robot" in str(c)]
    assert len(shown) >= 3


@pytest.mark.parametrize(("world", "kind"), [("office", "robot"), (FIREFLIES, "generic")])
def test_records_name_their_kind_and_replay_through_one_path(tmp_path, world, kind):
    record = tmp_path / "run.jsonl"
    # One writer of the record: this test's own Recorder (the run's options ask for none).
    options = vwg.RunOptions(frames=5, allow_unreached=True) if kind == "robot" else vwg.RunOptions(frames=5)
    loaded = vwg.load(world)
    with vwg.start(loaded, options) as run:
        recorder = vwg.Recorder(record, run.engine, world_file=loaded.path, world_data=run.record_data,
                                world_kind=run.kind)
        run.execute()
        recorder.close()
    header = json.loads(record.read_text().splitlines()[0])
    assert header["world_kind"] == kind
    rebuilt = replay_world(header, None, record)
    engine = vwg.replay(record, world=rebuilt)
    assert engine.frame == 5
    other = FIREFLIES if kind == "robot" else "office"
    with pytest.raises(vwg.Error, match=f"the record was made by a {kind} world"):
        replay_world(header, other, record)
