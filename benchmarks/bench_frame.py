"""The whole frame of `vwg run` at scale: robot-steps per second (robots × frames / wall seconds)
with 1, 10 and 100 robots on the shipped warehouse, each with a 180-beam, 180°, 10 m laser and an
order to a room, for the random decider and A*.

The reference, in the same process: a plain loop over the same simulator parts with no engine, no
string and no decisions — for each robot a laser scan (GridRaycaster.scan) and the physics step
(PhysicsWorld.advance). The ratio says what the model's frame (η, π, φ, events, the robot's map and
decision) costs on top of sensing and physics.

    python benchmarks/bench_frame.py [--quick]  prints a table, writes benchmarks/results/<machine>/bench_frame.json
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time
from pathlib import Path

import numpy as np
from machine import write_results
from tqdm import tqdm

import vwg
from vwg import _core
from vwg.robot.case_study import CaseStudy

RESULTS = Path(__file__).resolve().parent / "results" / "bench_frame.json"
LASER = vwg.robot.LaserSpec(beams=180, fov=math.pi, max_range=10.0, noise=0.01)


def rooms_world(cells: int = 500, per_side: int = 4) -> vwg.robot.RobotWorld:
    """A square map of `cells` × `cells` (0.05 m each: 25 × 25 m for 500) divided into per_side ×
    per_side rooms by 0.15 m walls, each wall with a 1.2 m door; a room in each, its goal at the
    room's centre (its marker on the room's south wall). Big enough for a thousand robots."""
    from vwg.io.maps import OccupancyGrid
    from vwg.robot.world_file import Room

    res, side = 0.05, cells * 0.05
    occ = np.zeros((cells, cells), dtype=bool)
    wall, door, room = round(0.15 / res), round(1.2 / res), cells / per_side
    for k in range(per_side + 1):
        at = min(round(k * room), cells - wall)
        occ[at:at + wall, :] = True  # a wall along x (rows are y)
        occ[:, at:at + wall] = True
    for k in range(1, per_side):  # doors in the inner walls, in the middle of each room's side
        at = round(k * room)
        for j in range(per_side):
            mid = round((j + 0.5) * room)
            occ[at:at + wall, mid - door // 2:mid + door // 2] = False
            occ[mid - door // 2:mid + door // 2, at:at + wall] = False
    rooms = {}
    for j in range(per_side):
        for i in range(per_side):
            name = f"room_{j}_{i}"
            cx, cy = (i + 0.5) * side / per_side, (j + 0.5) * side / per_side
            marker = 30 + j * per_side + i
            rooms[name] = Room(name, marker, (cx, j * side / per_side + 0.15), math.pi / 2, goal=(cx, cy))
    base = vwg.robot.load_robot_world("warehouse")
    grid = OccupancyGrid(np.where(occ, 100, 0).astype(np.int8), res)
    return dataclasses.replace(base, name=f"rooms{cells}", grid=grid, rooms=rooms, robots=[], orders=[])


def crowd(n: int, seed: int = 0, world: vwg.robot.RobotWorld | None = None) -> vwg.robot.RobotWorld:
    """`world` (default the warehouse) with `n` robots at seeded free places (0.6 m apart), each
    with a laser; as many as fit if fewer do."""
    world = vwg.robot.load_robot_world("warehouse") if world is None else world
    grid = world.grid
    free = np.argwhere(~grid.inflate(0.35))
    rng = np.random.default_rng(seed)
    starts: list[tuple[float, float]] = []
    bins: dict[tuple[int, int], list[int]] = {}  # starts by 0.6 m bins: only the neighbours' are looked at
    for k in rng.permutation(len(free)):
        x, y = grid.cell_to_world(*free[k])
        bx, by = int(x // 0.6), int(y // 0.6)
        near = [starts[j] for dx in (-1, 0, 1) for dy in (-1, 0, 1) for j in bins.get((bx + dx, by + dy), ())]
        if all(math.hypot(x - a, y - b) >= 0.6 for a, b in near):
            bins.setdefault((bx, by), []).append(len(starts))
            starts.append((x, y))
            if len(starts) == n:
                break
    robots = [vwg.robot.RobotSettings(id=i + 1, start=(x, y, float(rng.uniform(-math.pi, math.pi))), sensors=("laser",))
              for i, (x, y) in enumerate(starts)]
    return dataclasses.replace(world, robots=robots, sensors={**world.sensors, "laser": LASER}, orders=[])


def room_goals(world: vwg.robot.RobotWorld) -> dict[int, str]:
    """Each robot's order: the rooms in turn, robot k to room k mod the number of rooms."""
    rooms = list(world.rooms)
    return {r.id: rooms[k % len(rooms)] for k, r in enumerate(world.robots)}


def vwg_rate(world: vwg.robot.RobotWorld, planner: str, frames: int) -> float:
    run = CaseStudy(world, planner, goals=room_goals(world), sensors=("laser",))
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
    write_results(out, quick=args.quick, long=args.long, rows=rows)


if __name__ == "__main__":
    main()
