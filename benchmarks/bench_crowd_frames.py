"""A crowd's frames one by one: wall time, the planner's search time and the page faults of each frame.

bench_scale.py times a crowd's frames together. This one runs bench_scale's crowds (1,000 robots on the
500 × 500-cell rooms map, 10,000 on the 1600 × 1600 one, orders to the rooms in turn, a laser each) and
reports each timed frame after the same 30 frames of warm-up: its wall time, the seconds its searches
took (summed over the threads) and the minor page faults the process took in it. A fault is a robot's
first write to a page of a map it shares with the others copy-on-write: the kernel copies the page and
interrupts every other core running the process to flush its stale translation (docs/performance.md,
"Ten thousand robots"). With --pid-file the process writes its PID there when the warm-up is over, for
`perf record -g -p PID` on the timed frames.

    python benchmarks/bench_crowd_frames.py [--robots 10000] [--planner astar-octile] [--frames 10]
                                            [--threads 2] [--pid-file F]

Prints a table and writes benchmarks/results/<machine>/bench_crowd_frames.json: the settings, a row a
frame (ms, search_s, faults) and their means, with the process's memory after the run (rss_mb).
"""

from __future__ import annotations

import argparse
import os
import resource
import time
from pathlib import Path

from bench_frame import crowd, room_goals, rooms_world
from bench_scale import WARMUP_FRAMES
from machine import rss_mb, write_results
from tqdm import tqdm

import vwg
from vwg.robot.case_study import CaseStudy

RESULTS = Path(__file__).resolve().parent / "results" / "bench_crowd_frames.json"
MAPS = {1000: rooms_world, 10000: lambda: rooms_world(1600, 12)}  # bench_scale's rooms500 and rooms1600


def minor_faults() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, choices=sorted(MAPS), default=10000)
    parser.add_argument("--planner", default="astar-octile", help="a decider: astar, astar-octile, jps, ...")
    parser.add_argument("--frames", type=int, default=10, help="frames timed after the warm-up")
    parser.add_argument("--threads", type=int, default=vwg._core.default_threads())
    parser.add_argument("--pid-file", type=Path, help="write the PID here when the warm-up is over")
    args = parser.parse_args()
    if args.frames < 1:
        parser.error("--frames: expected at least 1")

    world = crowd(args.robots, world=MAPS[args.robots]())
    rows = []
    with CaseStudy(world, args.planner, goals=room_goals(world), sensors=("laser",), threads=args.threads) as run:
        run.engine.run(WARMUP_FRAMES, progress=True)  # first plans, first scans, the crowd's robots met
        if args.pid_file:
            args.pid_file.write_text(str(os.getpid()))
        for _ in tqdm(range(args.frames), desc="timed", unit="frame"):
            searched, faulted, t0 = run.decider.search_seconds, minor_faults(), time.perf_counter()
            run.engine.run(1)
            rows.append({"frame": run.engine.frame, "ms": 1000 * (time.perf_counter() - t0),
                         "search_s": run.decider.search_seconds - searched, "faults": minor_faults() - faulted})
        rss = rss_mb()
    print(f"{'frame':>6} {'ms':>9} {'search s':>9} {'faults':>8}")
    for r in rows:
        print(f"{r['frame']:>6} {r['ms']:>9.1f} {r['search_s']:>9.3f} {r['faults']:>8,}")
    mean = {k: sum(r[k] for r in rows) / len(rows) for k in ("ms", "search_s", "faults")}
    print(f"{'mean':>6} {mean['ms']:>9.1f} {mean['search_s']:>9.3f} {mean['faults']:>8,.0f}   RSS {rss:,.0f} MB")
    write_results(RESULTS, robots=len(world.robots), planner=args.planner, threads=args.threads,
                  warmup_frames=WARMUP_FRAMES, rows=rows, mean_ms=mean["ms"], mean_search_s=mean["search_s"],
                  mean_faults=mean["faults"], rss_mb=rss)


if __name__ == "__main__":
    main()
