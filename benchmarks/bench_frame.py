"""The whole frame of `vwg run` at scale: robot-steps per second (robots × frames / wall seconds)
with 1, 10 and 100 robots on the shipped warehouse, each with a 180-beam, 180°, 10 m laser and an
order to a room, for the random decider and A*.

The reference, in the same process: a plain loop over the same simulator parts with no engine, no
string and no decisions — for each robot a laser scan (GridRaycaster.scan) and the physics step
(PhysicsWorld.advance). The ratio says what the model's frame (η, π, φ, events, the robot's map and
decision) costs on top of sensing and physics.

    python benchmarks/bench_frame.py [--quick]    prints a table, writes benchmarks/results/bench_frame.json
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import platform
import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

import vwg
from vwg import _core
from vwg.casestudy import CaseStudy

RESULTS = Path(__file__).resolve().parent / "results" / "bench_frame.json"
LASER = vwg.sim.LaserSpec(beams=180, fov=math.pi, max_range=10.0, noise=0.01)


def crowd(n: int, seed: int = 0) -> vwg.robot.RobotWorld:
    """The warehouse with `n` robots at seeded free places (0.6 m apart), each with a laser."""
    world = vwg.robot.load_robot_world("warehouse")
    grid = world.grid
    free = np.argwhere(~grid.inflate(0.35))
    rng = np.random.default_rng(seed)
    starts: list[tuple[float, float]] = []
    for k in rng.permutation(len(free)):
        x, y = grid.cell_to_world(*free[k])
        if all(math.hypot(x - a, y - b) >= 0.6 for a, b in starts):
            starts.append((x, y))
            if len(starts) == n:
                break
    robots = [vwg.robot.RobotSettings(id=i + 1, start=(x, y, float(rng.uniform(-math.pi, math.pi))), sensors=("laser",))
              for i, (x, y) in enumerate(starts)]
    return dataclasses.replace(world, robots=robots, laser=LASER, orders=[])


def vwg_rate(world: vwg.robot.RobotWorld, planner: str, frames: int) -> float:
    rooms = list(world.rooms)
    goals = {r.id: rooms[k % len(rooms)] for k, r in enumerate(world.robots)}
    run = CaseStudy(world, planner, goals=goals, sensors=("laser",))
    run.run(frames=2)  # warm up: first plans, first scans
    t0 = time.perf_counter()
    done = run.run(frames=frames).frames - 2
    return len(world.robots) * done / (time.perf_counter() - t0)


def plain_rate(world: vwg.robot.RobotWorld, frames: int) -> float:
    physics = _core.PhysicsWorld(world.grid, list(world.robots))
    raycaster = _core.GridRaycaster(world.grid)
    angles = np.linspace(-LASER.fov / 2, LASER.fov / 2, LASER.beams)
    for r in world.robots:
        physics.command(r.id, [("drive", 2.0)])
    t0 = time.perf_counter()
    for _ in range(frames):
        for r in world.robots:
            raycaster.scan(physics.robot(r.id).pose, angles, LASER.max_range)
        physics.advance(world.dt)
    return len(world.robots) * frames / (time.perf_counter() - t0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer frames")
    parser.add_argument("--long", action="store_true",
                        help="100 robots over 300 frames: the rate once the maps hold the crowd's traces")
    args = parser.parse_args()
    sizes: tuple[int, ...] = (1, 10, 100)
    frames = {1: 400, 10: 100, 100: 30} if not args.quick else {1: 100, 10: 30, 100: 8}
    if args.long:
        sizes, frames = (100,), {100: 300}
    rows = []
    with tqdm(total=len(sizes) * 3, desc="bench_frame", unit="run") as bar:
        for n in sizes:
            world = crowd(n)
            plain = plain_rate(world, frames[n])
            bar.update()
            for planner in ("random", "astar"):
                rate = vwg_rate(world, planner, frames[n])
                rows.append({"robots": n, "planner": planner, "frames": frames[n], "robot_steps_per_s": rate,
                             "plain_robot_steps_per_s": plain, "ratio_to_plain": rate / plain})
                bar.update()
    print(f"{'robots':>6} {'planner':>8} {'robot-steps/s':>14} {'plain loop':>11} {'ratio':>6}")
    for r in rows:
        print(f"{r['robots']:>6} {r['planner']:>8} {r['robot_steps_per_s']:>14,.0f} "
              f"{r['plain_robot_steps_per_s']:>11,.0f} {r['ratio_to_plain']:>6.2f}")
    out = RESULTS.with_name("bench_frame_long.json") if args.long else RESULTS
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"machine": platform.machine(), "processor": platform.processor(),
                                   "python": platform.python_version(), "quick": args.quick, "long": args.long,
                                   "rows": rows},
                                  indent=2) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
