"""The engine (system algorithm §II.D) with Python generators, backends and observers."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

import vwg
from conftest import make_world


class Adder(vwg.Generator):
    def __init__(self, k):
        super().__init__()
        self.k = k

    def generate(self, frame):
        return [vwg.Event("add", k=self.k)]


class Noise(vwg.Generator):
    name = "noise"

    def reset(self, seed):
        self.rng = np.random.default_rng(seed)

    def generate(self, frame):
        return [vwg.Event("add", k=int(self.rng.integers(-3, 4)))] * 2


def test_generator_priority_orders_s():
    world = make_world()
    for generators, expected in (([Adder(2), vwg.every_frame("mul", k=3)], 9),
                                 ([vwg.every_frame("mul", k=3), Adder(2)], 5)):
        engine = vwg.Engine(world, "Counter<n=1>", generators)
        engine.step()
        assert str(engine.string) == f"Counter<n={expected}>"


def test_display_shows_the_string_before_evolution():
    world = make_world()
    trace = vwg.TraceBackend()
    engine = vwg.Engine(world, "Counter<n=1>", [Adder(2), vwg.every_frame("show")], trace)
    engine.run(2)
    assert trace.calls == ["frame 0", "alpha Lamp<1>", "frame 1", "alpha Lamp<3>"]
    assert [e.type for e in engine.last_events] == ["add", "show"]


def test_run_stops_when_empty_at_the_limit_or_on_request():
    world = make_world()
    engine = vwg.Engine(world, "Mortal . Lamp", [vwg.Schedule({3: ["die"]})])
    assert engine.run(2) == "frames"
    assert engine.run(100) == "frames"  # Lamp stays: never empty
    engine = vwg.Engine(world, "Mortal", [vwg.Schedule({3: ["die"]})])
    assert engine.run(100) == "empty" and engine.frame == 4 and not engine.step()
    engine = vwg.Engine(world, "Counter", [Adder(1)])
    engine.add_observer(lambda r: engine.request_stop() if r.frame == 4 else None)
    assert engine.run(1000) == "stopped" and engine.frame == 5


def test_observers_see_each_completed_frame():
    world = make_world()
    seen = []
    engine = vwg.Engine(world, "Counter<n=1>", [Adder(2)])
    engine.add_observer(lambda r: seen.append((r.frame, r.event_texts, r.after_text)))
    engine.run(2)
    assert seen == [(0, ["add<k=2>"], "Counter<n=3>"), (1, ["add<k=2>"], "Counter<n=5>")]
    kept = []
    engine.add_observer(kept.append)
    engine.step()
    with pytest.raises(vwg.SchemaError, match="only available during"):
        _ = kept[0].after


def test_same_seed_same_trace_bit_for_bit():
    world = make_world()

    def trace(seed):
        hashes = []
        engine = vwg.Engine(world, "Counter . Tagged<id=1> . Splitter", [Noise(), vwg.every_frame("poke")], seed=seed)
        engine.add_observer(lambda r: hashes.append(r.after.content_hash()))
        engine.run(30)
        return hashes

    assert trace(5) == trace(5)
    assert trace(5) != trace(6)


def test_generator_and_backend_errors_keep_the_last_frame():
    world = make_world()

    class Broken(vwg.Generator):
        def generate(self, frame):
            if frame.frame == 2:
                raise RuntimeError("sensor unplugged")
            return ["add<k=1>"]

    engine = vwg.Engine(world, "Counter", [Broken()])
    with pytest.raises(vwg.FrameError) as info:
        engine.run(5)
    assert (info.value.frame, info.value.stage) == (2, "generate")
    assert "Broken" in info.value.where and isinstance(info.value.__cause__, RuntimeError)
    assert engine.frame == 2 and str(engine.string) == "Counter<n=2>"

    class Screen(vwg.Backend):
        def primitive(self, p):
            raise OSError("screen off")

    engine = vwg.Engine(world, "Counter", [Adder(1), vwg.every_frame("show")], Screen())
    with pytest.raises(vwg.FrameError) as info:
        engine.step()
    assert info.value.stage == "display" and isinstance(info.value.__cause__, OSError)
    assert engine.frame == 0 and str(engine.string) == "Counter<n=0>"


def test_bad_events_from_a_generator_are_clear_errors():
    world = make_world()

    class Wrong(vwg.Generator):
        def generate(self, frame):
            return [vwg.Event("add", k=1.5)]

    with pytest.raises(vwg.FrameError, match=r"add\.k: expected int, got float"):
        vwg.Engine(world, "Counter", [Wrong()]).step()

    class Unknown(vwg.Generator):
        def generate(self, frame):
            return [vwg.Event("nope")]

    with pytest.raises(vwg.FrameError, match="unknown event type 'nope'"):
        vwg.Engine(world, "Counter", [Unknown()]).step()


def test_frame_info_and_world_view():
    world = make_world()
    seen = []

    class Look(vwg.Generator):
        def generate(self, frame):
            seen.append((frame.frame, frame.time, len(frame.world)))
            return []

    vwg.Engine(world, "Counter . Lamp", [Look()], dt=0.25).run(3)
    assert seen == [(0, 0.0, 2), (1, 0.25, 2), (2, 0.5, 2)]


def test_max_symbols_stops_runaway_growth():
    world = make_world()
    engine = vwg.Engine(world, "Splitter", [vwg.every_frame("split")], max_symbols=1000)
    with pytest.raises(vwg.FrameError, match="over the limit of 1000"):
        engine.run(100)
    assert len(engine.string) == 512  # the last complete frame: 2^9


def test_bad_engine_settings():
    world = make_world()
    with pytest.raises(vwg.SchemaError, match="dt"):
        vwg.Engine(world, "Lamp", dt=0.0)
    with pytest.raises(vwg.SchemaError, match="generators"):
        vwg.Engine(world, "Lamp", ["tick"])


def test_run_releases_the_gil():
    # Another Python thread keeps counting while the C++ frame loop runs; if run() held the GIL,
    # the count would stand still for the whole run.
    world = make_world()
    engine = vwg.Engine(world, " . ".join(["Move<1.0>(Lamp)"] * 2000), [], vwg.NullBackend())
    counter = [0]
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            counter[0] += 1

    t = threading.Thread(target=spin)
    t.start()
    try:
        while counter[0] == 0:
            pass
        before = counter[0]
        start = time.perf_counter()
        engine.run(20000)
        elapsed = time.perf_counter() - start
        during = counter[0] - before
    finally:
        stop.set()
        t.join()
    assert elapsed > 0.05, "the run was too short to tell"
    assert during > 10000


def test_python_subclasses_are_named_by_their_class():
    class Quiet(vwg.Generator):
        def generate(self, frame):
            return []

    class Named(vwg.Generator):
        name = "gNamed"

        def generate(self, frame):
            return []

    class Plain(vwg.robot.Decider):
        def decide(self, robot):
            return None

    engine = vwg.Engine(make_world(), "Lamp", [Quiet(), Named()])
    assert [g.name for g in engine.generators] == ["Quiet", "gNamed"]
    assert Plain().name == "Plain"  # no recursion through the base class's property


class Tally(vwg.Actor):
    """beam<dist, angle>: sums dist and angle and counts the beams that reach it (by id)."""

    events = ("beam",)
    attributes = {"id": int, "dist": 0.0, "angle": 0.0, "beams": 0}

    def on_beam(self, e):
        return self.with_(dist=self.dist + e.dist, angle=self.angle + e.angle, beams=self.beams + 1)


def tally_world() -> vwg.World:
    return vwg.World(events={"beam": {"dist": 0.0, "angle": 0.0}}, actors=[Tally])


class Scan(vwg.Generator):
    """A scan of three beams to actor 2, then one beam to every actor; by columns or one by one."""

    def __init__(self, by_columns: bool) -> None:
        super().__init__()
        self.by_columns = by_columns

    def generate(self, frame):
        dist, angle = np.array([1.0, 2.5, 0.25]), [0.5, -1.0, 0.125]
        if self.by_columns:
            scan = [vwg.EventColumns("beam", target=2, dist=dist, angle=angle)]
        else:
            scan = [vwg.Event("beam", target=2, dist=float(d), angle=a) for d, a in zip(dist, angle, strict=True)]
        return [*scan, vwg.Event("beam", dist=10.0, angle=0.0)]


def test_a_batch_by_columns_is_the_same_events_as_one_by_one():
    strings, events = [], []
    for by_columns in (True, False):
        engine = vwg.Engine(tally_world(), "Tally<id=1> . Tally<id=2>", [Scan(by_columns)])
        engine.run(2)
        strings.append(str(engine.string))
        events.append([str(e) for e in engine.last_events])
    assert strings[0] == strings[1]
    assert events[0] == events[1]
    assert events[0][:2] == ["beam<to=2, dist=1.0, angle=0.5>", "beam<to=2, dist=2.5, angle=-1.0>"]
    # By hand: actor 2 gets the three beams and the broadcast one each frame, actor 1 the broadcast.
    assert strings[0] == ("Tally<id=1, dist=20.0, angle=0.0, beams=2> . "
                          "Tally<id=2, dist=27.5, angle=-0.75, beams=8>")


def test_event_columns_refuse_what_does_not_fit():
    batch = vwg.EventColumns("beam", target=2, dist=[1, 2], angle=np.array([0.5, 0.25], dtype=np.float32))
    assert len(batch) == 2 and batch.target == 2 and batch.type == "beam"
    assert batch.columns["dist"].dtype == np.float64 and not batch.columns["dist"].flags.writeable
    source = np.array([1.0, 2.0])
    copied = vwg.EventColumns("beam", dist=source, angle=source)
    source[0] = 99.0
    assert copied.columns["dist"][0] == 1.0, "the batch keeps a copy of its own"
    with pytest.raises(vwg.SchemaError, match=r"beam\.angle: has 3 values; dist has 2"):
        vwg.EventColumns("beam", dist=[1, 2], angle=[0, 0, 0])
    with pytest.raises(vwg.SchemaError, match=r"beam\.dist: expected a 1-D array of reals"):
        vwg.EventColumns("beam", dist=[[1, 2]], angle=[0, 0])
    with pytest.raises(vwg.SchemaError, match=r"beam\.dist: expected a 1-D array of reals.*got str"):
        vwg.EventColumns("beam", dist="far", angle=[0])
    with pytest.raises(vwg.SchemaError, match="needs a column for each field"):
        vwg.EventColumns("beam")

    def step_with(*batches):
        class Once(vwg.Generator):
            def generate(self, frame):
                return list(batches)

        engine = vwg.Engine(tally_world(), "Tally<id=1>", [Once()])
        engine.step()
        return engine

    refused = (
        (vwg.EventColumns("beam", dist=[1.0]), r"beam\.angle: missing"),
        (vwg.EventColumns("beam", dist=[1.0], angle=[0.0], far=[2.0]), r"beam\.far: no such field"),
        (vwg.EventColumns("ray", dist=[1.0]), "unknown event type 'ray'"),
        (vwg.EventColumns("beam", dist=[1.0, np.inf], angle=[0.0, 0.0]), r"beam\.dist: expected a finite real"),
    )
    for batch, message in refused:
        with pytest.raises(vwg.FrameError, match=message) as info:
            step_with(vwg.Event("beam", dist=1.0, angle=0.0), batch)
        assert info.value.stage == "generate"
    empty = step_with(vwg.EventColumns("beam", dist=[], angle=[]))
    assert str(empty.string) == "Tally<id=1, dist=0.0, angle=0.0, beams=0>"
