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


# ---- reading from other threads (issue 34: engine.string from a second thread was a segfault) -------------
READERS = 4


def test_every_read_accessor_from_four_threads_sees_whole_frames():
    """Four threads read each accessor while another runs frames; the string after frame k is
    Meddler<n=k+1> and S is one tick, so every read can be checked against the frame count around it."""
    _, engine = make_engine()
    Meddler.act = lambda: None
    seen_by_observer: list[int] = []
    failures: list[str] = []
    running = threading.Event()

    def read() -> None:
        reads = 0
        while running.is_set() or reads == 0:
            before = engine.frame
            text = str(engine.string)
            events = engine.last_events
            t = engine.time
            after = engine.frame
            n = int(text[len("Meddler<n="):-1])
            if not before <= n <= after:
                failures.append(f"string {text} read between frames {before} and {after}")
            if before > 0 and [e.type for e in events] != ["tick"]:
                failures.append(f"last_events {events!r} after frame {before}")
            if not before * 0.1 - 1e-9 <= t <= after * 0.1 + 1e-9:
                failures.append(f"time {t} read between frames {before} and {after}")
            assert engine.dt == 0.1 and engine.seed == 0 and engine.threads >= 1
            assert len(engine.generators) == 1 and engine.backend is None
            if reads % 50 == 0:  # observers added from other threads during the run
                engine.add_observer(lambda r: None)
            reads += 1

    engine.add_observer(lambda r: seen_by_observer.append(r.frame))
    threads = [threading.Thread(target=read) for _ in range(READERS)]
    running.set()
    for t in threads:
        t.start()
    for _ in range(20):
        assert engine.run(100) == "frames"
    running.clear()
    for t in threads:
        t.join(30)
    assert not failures, failures[:5]
    assert engine.frame == 2000 and str(engine.string) == "Meddler<n=2000>"
    assert seen_by_observer == list(range(2000))


def test_adding_an_observer_during_a_frame_of_the_same_engine_is_refused():
    _, engine = make_engine()
    Meddler.act = lambda: None
    engine.add_observer(lambda r: engine.add_observer(lambda r: None))
    with pytest.raises(vwg.Error, match="add_observer: called during a frame"):
        engine.step()


ROBOT_READERS = """
import sys, threading
import vwg
from vwg.robot.case_study import CaseStudy

case = CaseStudy(vwg.robot.load_robot_world("office"), "astar", goals={1: "kitchen", 2: "lab"}, threads=2)
engine = case.engine
frames = {str(engine.string)}
engine.add_observer(lambda r: frames.add(r.after_text))
running = threading.Event()
running.set()
read_strings, failures, counts = [], [], [0] * 4

def read(k):
    while running.is_set():
        read_strings.append(str(engine.string))
        events = engine.last_events
        if engine.frame > 0 and not any(e.type == "eLaser" for e in events):
            failures.append("a frame's S without its laser events")
        engine.time, engine.frame
        counts[k] += 1

threads = [threading.Thread(target=read, args=(k,)) for k in range(4)]
for t in threads:
    t.start()
engine.run(150)
running.clear()
for t in threads:
    t.join(60)
torn = [s for s in read_strings if s not in frames]
print(engine.frame, len(read_strings), min(counts), len(torn), len(failures))
sys.exit(1 if torn or failures or min(counts) == 0 else 0)
"""


def test_a_robot_run_read_from_four_threads_does_not_crash_and_reads_only_whole_frames():
    """The issue's reproduction: C++ robots change their maps in place during a frame. Run in a child
    process, so the old segfault fails this test instead of ending the test session."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", ROBOT_READERS], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, (done.returncode, done.stdout, done.stderr[-2000:])
    frames, reads, fewest, torn, failures = map(int, done.stdout.split())
    assert frames == 150 and reads > 0 and fewest > 0 and torn == 0 and failures == 0
