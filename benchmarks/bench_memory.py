"""Memory of a robot run: per robot, and over a long run (it should stay flat).

The warehouse with 10 and 100 robots and the 500 × 500-cell rooms map with 1,000 (bench_frame's
crowd: a 180-beam laser each, A* orders to rooms, 2 threads), the full frame of `vwg run`; the
process's memory (machine.rss_mb: the proportional set size, a page shared by many robots counted
once) is read before the run, after 20 frames, then every 25 frames to the end. Each robot holds
its own map (the paper's grid attribute), sharing the pages it has not written with the known map.

    python benchmarks/bench_memory.py [--quick]  prints a table, writes benchmarks/results/<machine>/bench_memory.json
"""

from __future__ import annotations

import argparse
import gc
import sys
from pathlib import Path

from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_frame import crowd, room_goals, rooms_world
from machine import rss_mb, write_results

from vwg.robot.case_study import CaseStudy

RESULTS = Path(__file__).resolve().parent / "results" / "bench_memory.json"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer frames")
    args = parser.parse_args()
    frames = 100 if args.quick else 600
    rows = []
    for name, n in tqdm((("warehouse", 10), ("warehouse", 100), ("rooms500", 1000)), desc="bench_memory", unit="run"):
        world = crowd(n, world=rooms_world() if name == "rooms500" else None)
        goals = room_goals(world)
        gc.collect()
        before = rss_mb()
        trace = []  # (frame, MB)
        with CaseStudy(world, "astar", goals=goals, sensors=("laser",), threads=2) as run:
            run.engine.run(20)
            trace.append((20, rss_mb()))
            while run.engine.frame < frames:
                run.engine.run(min(25, frames - run.engine.frame))
                trace.append((run.engine.frame, rss_mb()))
        early, late = trace[0][1], trace[-1][1]
        half = min(trace, key=lambda t: abs(t[0] - frames // 2))[1]
        cells = world.grid.width * world.grid.height
        rows.append({"map": name, "robots": n, "frames": frames, "map_cells": cells, "rss_before_mb": before,
                     "rss_at_20_mb": early, "rss_at_half_mb": half, "rss_at_end_mb": late,
                     "mb_per_robot": (early - before) / n, "growth_after_20_frames_mb": late - early,
                     "growth_second_half_mb": late - half, "trace_mb": trace})
    print(f"{'map':>9} {'robots':>6} {'frames':>6} {'MB/robot':>9} {'map (int16)':>12} {'growth 20→end':>14} "
          f"{'growth half→end':>16}")
    for r in rows:
        map_mb = r["map_cells"] * 2 / 2**20
        print(f"{r['map']:>9} {r['robots']:>6} {r['frames']:>6} {r['mb_per_robot']:9.2f} {map_mb:10.2f} MB "
              f"{r['growth_after_20_frames_mb']:11.1f} MB {r['growth_second_half_mb']:13.1f} MB")
    write_results(RESULTS, quick=args.quick, rows=rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
