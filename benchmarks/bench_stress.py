"""A long run, to see that nothing grows or slows: 100 robots on the warehouse, each with a 180-beam
laser and A*, for 10,000 frames; every robot has an order from the first frame (the rooms in turn),
and a new one comes every 50 frames (a seeded robot to a seeded room). The resident memory and the
rate are sampled every 500 frames.

    python benchmarks/bench_stress.py [--frames N] [--robots N]    (make stress)

It prints a table, writes benchmarks/results/<machine>/bench_stress.json and exits 1 when the memory grew by more
than 10 % from the middle of the run to its end, or the last stretch ran slower than 0.7× the middle
one. Every robot works from the start, so its planning grids (made at its first decision) are there
from the first stretch: growth after that is not the workload. The rate falls over the first few
thousand frames while the robots' maps fill with what their lasers report (other robots, readings
short of walls: a reported obstacle is cleared only by a beam that passes through it) and more of
them find no way; the check is that it does not go on falling.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from bench_frame import crowd
from machine import rss_mb, write_results
from tqdm import tqdm

from vwg.robot.case_study import CaseStudy

RESULTS = Path(__file__).resolve().parent / "results" / "bench_stress.json"
STRETCH = 500  # frames between samples
ORDER_EVERY = 50
MEMORY_GROWTH = 0.10  # allowed from the middle of the run to its end
SLOWDOWN = 0.7  # the last stretch's rate at least this share of the middle one's


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=10_000)
    parser.add_argument("--robots", type=int, default=100)
    args = parser.parse_args()
    world = crowd(args.robots)
    rooms = list(world.rooms)
    case = CaseStudy(world, "astar", sensors=("laser",), frames=args.frames, world_orders=False)
    rng = np.random.default_rng(0)
    ids = [r.id for r in world.robots]
    for k, robot in enumerate(ids):
        case.orders.schedule(0, robot, rooms[k % len(rooms)])
    for frame in range(0, args.frames, ORDER_EVERY):
        case.orders.schedule(frame, int(rng.choice(ids)), rooms[int(rng.integers(len(rooms)))])
    case.engine.stop_when(None)  # run every frame: arrivals do not end a stress run
    rows = []
    done = 0
    with tqdm(total=args.frames, unit="frame") as bar:
        while done < args.frames:
            n = min(STRETCH, args.frames - done)
            t0 = time.perf_counter()
            case.engine.run(n)
            wall = time.perf_counter() - t0
            done += n
            bar.update(n)
            rows.append({"frame": done, "rss_mb": rss_mb(), "robot_steps_per_s": len(ids) * n / wall,
                         "orders_given": case.orders.given})
    case.close()
    middle = rows[len(rows) // 2]["rss_mb"]
    end = rows[-1]["rss_mb"]
    rate_middle = rows[len(rows) // 2]["robot_steps_per_s"]
    rate_last = rows[-1]["robot_steps_per_s"]
    growth = end / middle - 1
    ratio = rate_last / rate_middle
    print(f"{'frame':>7}{'RSS MB':>9}{'robot-steps/s':>15}{'orders':>8}")
    for r in rows:
        print(f"{r['frame']:>7}{r['rss_mb']:>9.0f}{r['robot_steps_per_s']:>15.0f}{r['orders_given']:>8}")
    ok = growth <= MEMORY_GROWTH and ratio >= SLOWDOWN
    print(f"memory from the middle to the end: {growth:+.1%} (at most {MEMORY_GROWTH:.0%}); last stretch's rate "
          f"{ratio:.2f}× the middle one's (at least {SLOWDOWN}): {'ok' if ok else 'FAILED'}")
    write_results(RESULTS, robots=args.robots, frames=args.frames, rows=rows, memory_growth=growth,
                  rate_ratio=ratio, ok=ok)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
