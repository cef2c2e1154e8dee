"""The floor under a crowd's frame: what its two unavoidable parts cost, with nothing else.

bench_scale.py runs the whole frame. This one runs only Box2D's advance of the crowd (one
PhysicsWorld.advance of a 0.1 s frame, the platform's ten 0.01 s steps; b2World steps on one
thread) and the crowd's wall scans (every robot's 180-beam, 180°, 10 m scan in one
GridRaycaster.scans call: no Python between scans), on bench_scale's crowds (1,000 robots on the
500 × 500-cell rooms map, 10,000 on the 1600 × 1600 one). There are no robots in the scans, no
maps, no decisions and no engine. The smallest frame two cores could then make is Box2D's time
(one thread) plus half the scans' (two): compared with the 100 ms a 10 Hz frame has at real time.

    python benchmarks/bench_floor.py [--quick]   (--quick: 1,000 robots only)

Prints a table and writes benchmarks/results/<machine>/bench_floor.json: rows with n_robots, the CPU time
per robot-step of the advance and of the scans (µs, the best of three), the scans' rays/s and
which code ran them, floor_ms_per_frame on two cores and floor_realtime_factor (100 ms over it).
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from bench_frame import crowd, rooms_world
from machine import write_results

from vwg import _core

RESULTS = Path(__file__).resolve().parent / "results" / "bench_floor.json"
BEAMS, FOV, RANGE = 180, math.pi, 10.0


def cpu_seconds(fn: Callable[[], Any], repeats: int = 3) -> float:
    """The least process CPU time of `repeats` calls of fn."""
    best = math.inf
    for _ in range(repeats):
        c0 = time.process_time()
        fn()
        best = min(best, time.process_time() - c0)
    return best


def floor_row(n: int, cells: int, per_side: int) -> dict[str, Any]:
    world = crowd(n, world=rooms_world(cells, per_side))
    robots = list(world.robots)
    physics = _core.PhysicsWorld(world.grid, robots)
    for r in robots:
        physics.command(r.id, [("drive", 2.0)])
    physics.advance(world.dt)  # under way: contacts made
    advance = cpu_seconds(lambda: physics.advance(world.dt))
    caster = _core.GridRaycaster(world.grid)
    poses = np.array([physics.robot(r.id).pose for r in robots], dtype=np.float64)
    angles = np.linspace(-FOV / 2, FOV / 2, BEAMS)
    scans = cpu_seconds(lambda: caster.scans(poses, angles, RANGE))
    floor_s = advance + scans / 2  # Box2D on one thread, the scans split over two cores
    return {"n_robots": len(robots), "map_cells": cells, "advance_us_per_robot": 1e6 * advance / len(robots),
            "scan_us_per_robot": 1e6 * scans / len(robots), "scan_rays_per_s": len(robots) * BEAMS / scans,
            "simd": caster.simd, "floor_ms_per_frame": 1000 * floor_s, "floor_realtime_factor": world.dt / floor_s}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1,000 robots only")
    args = parser.parse_args()
    sizes = [(1000, 500, 4)] + ([] if args.quick else [(10000, 1600, 12)])
    rows = [floor_row(*size) for size in sizes]
    print(f"{'robots':>6} {'map':>9} {'Box2D µs':>9} {'scan µs':>8} {'rays/s':>8} {'code':>6} "
          f"{'floor ms/frame':>14} {'floor × real time':>17}")
    for r in rows:
        print(f"{r['n_robots']:>6} {r['map_cells']:>4}×{r['map_cells']:<4} {r['advance_us_per_robot']:>9.2f} "
              f"{r['scan_us_per_robot']:>8.2f} {r['scan_rays_per_s'] / 1e6:>7.1f}M {r['simd']:>6} "
              f"{r['floor_ms_per_frame']:>14.1f} {r['floor_realtime_factor']:>17.2f}")
    print("(µs: CPU time per robot-step on one core; floor: Box2D's advance on one thread plus half the scans)")
    write_results(RESULTS, quick=args.quick, rows=rows)


if __name__ == "__main__":
    main()
