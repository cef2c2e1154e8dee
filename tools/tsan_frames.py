"""Robots' frames on four threads under ThreadSanitizer: run by `make tsan` with the extension built
with -fsanitize=thread (build/tsan) and libtsan preloaded; it fails when TSan reports a data race.

Twelve robots on the warehouse, each with a laser, for each decider that runs side by side (A*, JPS,
D* Lite, random): 40 frames on four threads, the parallel frame path with every shared table of
ARobot and the deciders in use; meanwhile two other Python threads read the engine (its string, last
events, frame and time) and add an observer, as a viewer or a script may (the engine's state lock).
"""

from __future__ import annotations

import sys
import threading
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_frame import crowd, room_goals

from vwg.robot.case_study import CaseStudy


def read_while(engine, running: threading.Event, reads: list[int]) -> None:
    """Read every accessor of `engine` until `running` is cleared; count the reads."""
    n = 0
    while running.is_set():
        _ = (str(engine.string), engine.last_events, engine.frame, engine.time)
        if n == 10:
            engine.add_observer(lambda record: None)
        n += 1
    reads.append(n)


def main() -> None:
    world = crowd(12)
    goals = room_goals(world)
    for planner in ("astar", "jps", "dstar", "random"):
        with CaseStudy(world, planner, goals=goals, sensors=("laser",), threads=4) as run:
            running, reads = threading.Event(), []
            running.set()
            readers = [threading.Thread(target=read_while, args=(run.engine, running, reads)) for _ in range(2)]
            for reader in readers:
                reader.start()
            try:
                run.run(frames=40)
            finally:
                running.clear()
                for reader in readers:
                    reader.join()
            print(f"{planner}: {run.engine.frame} frames on {run.engine.threads} threads, {sum(reads)} reads from "
                  "two other threads", flush=True)


if __name__ == "__main__":
    main()
