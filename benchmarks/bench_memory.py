"""Resident memory of a robot run: per robot, and over a long run (it should stay flat).

The warehouse with N robots (bench_frame's crowd: a 180-beam laser each, A* orders to rooms), the full
frame of `vwg run`; the process's resident set size (from /proc/self/statm) is read before the run,
after the first frames and at the end. Each robot holds its own map (the paper's grid attribute),
written in place while nothing else shares it.

    python benchmarks/bench_memory.py [--quick]     prints a table, writes benchmarks/results/bench_memory.json
"""

from __future__ import annotations

import argparse
import gc
import sys
from pathlib import Path

from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_frame import crowd
from machine import rss_mb, write_results

from vwg.casestudy import CaseStudy

RESULTS = Path(__file__).resolve().parent / "results" / "bench_memory.json"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer frames")
    args = parser.parse_args()
    frames = 100 if args.quick else 600
    rows = []
    for n in tqdm((10, 100), desc="bench_memory", unit="run"):
        world = crowd(n)
        rooms = list(world.rooms)
        goals = {r.id: rooms[k % len(rooms)] for k, r in enumerate(world.robots)}
        gc.collect()
        before = rss_mb()
        run = CaseStudy(world, "astar", goals=goals, sensors=("laser",))
        run.run(frames=20)
        early = rss_mb()
        run.run(frames=frames - 20)
        late = rss_mb()
        cells = world.grid.width * world.grid.height
        rows.append({"robots": n, "frames": frames, "map_cells": cells, "rss_before_mb": before, "rss_at_20_mb": early,
                     "rss_at_end_mb": late, "mb_per_robot": (early - before) / n,
                     "growth_after_20_frames_mb": late - early})
        run.close()
        del run
    print(f"{'robots':>6} {'frames':>6} {'MB/robot':>9} {'map (int16)':>12} {'growth 20→end':>14}")
    for r in rows:
        print(f"{r['robots']:>6} {r['frames']:>6} {r['mb_per_robot']:9.2f} {r['map_cells'] * 2 / 2**20:10.2f} MB "
              f"{r['growth_after_20_frames_mb']:11.1f} MB")
    write_results(RESULTS, quick=args.quick, rows=rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
