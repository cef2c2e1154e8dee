"""Robots' frames on four threads under ThreadSanitizer: run by `make tsan` with the extension built
with -fsanitize=thread (build/tsan) and libtsan preloaded; it fails when TSan reports a data race.

Twelve robots on the warehouse, each with a laser, for each decider that runs side by side (A*, JPS,
D* Lite, random): 40 frames on four threads, the parallel frame path with every shared table of
ARobot and the deciders in use.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_frame import crowd, room_goals

from vwg.casestudy import CaseStudy


def main() -> None:
    world = crowd(12)
    goals = room_goals(world)
    for planner in ("astar", "jps", "dstar", "random"):
        with CaseStudy(world, planner, goals=goals, sensors=("laser",), threads=4) as run:
            run.run(frames=40)
            print(f"{planner}: {run.engine.frame} frames on {run.engine.threads} threads", flush=True)


if __name__ == "__main__":
    main()
