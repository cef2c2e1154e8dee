"""An engine is not re-entrant and is used by one thread at a time: misuse is a clear error, never
corrupted memory. The alphabet cannot grow while a frame reads it."""

from __future__ import annotations

import threading
import time

import pytest

import vwg


class Meddler(vwg.Actor):
    """On `tick`, calls whatever `Meddler.act` holds (set by each test)."""

    events = ("tick",)
    attributes = {"n": 0}
    act = None

    def on_tick(self, e):
        type(self).act()
        return self.with_(n=self.n + 1)


def make_engine():
    world = vwg.World(primitives=["Lamp"], events=["tick"], actors=[Meddler])
    return world, vwg.Engine(world, "Meddler", generators=[vwg.every_frame("tick")])


@pytest.mark.parametrize("call", ["step", "run", "set_string"])
def test_a_lambda_that_drives_its_own_engine_is_refused(call):
    world, engine = make_engine()
    actions = {"step": engine.step, "run": lambda: engine.run(3),
               "set_string": lambda: engine.set_string(world.parse("Lamp"))}
    Meddler.act = actions[call]
    with pytest.raises(vwg.FrameError) as info:
        engine.step()
    assert isinstance(info.value.__cause__, vwg.Error)
    assert "not re-entrant" in str(info.value.__cause__)
    assert engine.frame == 0 and str(engine.string) == "Meddler<n=0>"  # the failed frame left no trace
    Meddler.act = lambda: None
    assert engine.step() and str(engine.string) == "Meddler<n=1>"  # and the engine still works


def test_adding_to_the_alphabet_during_a_frame_is_refused():
    world, engine = make_engine()
    Meddler.act = lambda: world.alphabet.add_primitive("Late")
    with pytest.raises(vwg.FrameError) as info:
        engine.step()
    assert "while an engine runs a frame" in str(info.value.__cause__)
    Meddler.act = lambda: None
    world.alphabet.add_primitive("Late")  # between frames it is fine
    assert "Late" in world.alphabet.primitives


def test_a_second_thread_is_refused_while_the_first_runs_a_frame():
    _, engine = make_engine()
    inside, release = threading.Event(), threading.Event()

    def slow():
        inside.set()
        release.wait(10)

    Meddler.act = slow
    runner = threading.Thread(target=engine.step)
    runner.start()
    assert inside.wait(10)
    try:
        with pytest.raises(vwg.Error, match="another thread"):
            engine.step()
    finally:
        release.set()
        runner.join(10)
    Meddler.act = lambda: None
    time.sleep(0)
    assert engine.frame == 1 and engine.step() and engine.frame == 2
