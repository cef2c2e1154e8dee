"""Scale, side by side with IR-SIM: N robots on the shipped warehouse (30 × 20 m), each with a
180-beam, 180°, 10 m laser and an order to a room, 10 Hz frames, the full `vwg run` frame (the
generators, η, π, φ on the Box2D platform, A* decisions), on one thread and on every core — and the
same scenario in IR-SIM (the same map as a PNG, the same starts, a 180-beam `lidar2d` per robot,
`dash` behaviour to the same goals, headless) in the same run. Both engines' frames are timed
after 30 frames of warm-up, when the robots of a crowd have met and replan around one another. A thousand
robots run on a 500 × 500 cell map of rooms (25 × 25 m), which holds about 1,040 robots 0.6 m apart;
ten thousand on a 1600 × 1600 cell map of 12 × 12 rooms (80 × 80 m), with A* on every core (their
first plans, before the timed frames, take minutes).

    python benchmarks/bench_scale.py [--quick]   (make bench-scale installs IR-SIM in its own venv)

Prints a table and writes benchmarks/results/<machine>/bench_scale.json: rows with engine ("vwg" or "irsim"),
planner (vwg: "astar" on one thread and every core, "astar-octile" and "jps" on every core; IR-SIM:
"dash"), map, n_robots, threads, robot_steps_per_s, rays_per_s, ms_per_frame, realtime_factor,
rss_mb (the process's resident memory after the run, pages shared between robots counted once:
machine.rss_mb) and rss_per_robot_mb (what the run added, per robot, from 100 robots; None below);
vwg's rows also searches_per_robot_step and search_s_per_frame (the planner's searches in the timed
frames, their seconds summed over the threads); and the ratio vwg / IR-SIM for each N and planner
both ran (vwg on every core). IR-SIM runs in a subprocess with the interpreter given by
--irsim-python (its own environment: its dependencies are not vwg's); without one, its rows are
left out and the table says so.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from machine import rss_mb, write_results

RESULTS = Path(__file__).resolve().parent / "results" / "bench_scale.json"
BEAMS, FOV, RANGE, DT = 180, math.pi, 10.0, 0.1
# Frames before the timed ones: a crowd's robots meet and start replanning around one another
# from about frame 20 (a thousand on rooms500: 14 A* searches in frames 2-22, 500-1,000 in each
# 20 frames after), and a frame then costs about 40 % more: timing from frame 2 measured a calm
# that does not last.
WARMUP_FRAMES = 30
MEMORY_PER_ROBOT_FROM = 100  # robots: smaller crowds get no memory figure per robot (see vwg_row)


def settle_memory() -> None:
    """Give memory freed by earlier rows back to the system, so a row's growth is its own."""
    import ctypes
    import gc

    gc.collect()
    ctypes.CDLL("libc.so.6").malloc_trim(0)


# ---- IR-SIM, in its own interpreter ---------------------------------------------------------------------------------
IRSIM_WORKER = r"""
import json, sys, time
import irsim
spec = json.loads(sys.argv[1])
env = irsim.make(spec["yaml"], display=False)
for _ in range(spec["warmup"]):  # as vwg's: the robots have met when the timed steps start
    env.step()
t0 = time.perf_counter()
for _ in range(spec["frames"]):
    env.step()
wall = time.perf_counter() - t0
hwm = next(line for line in open("/proc/self/status") if line.startswith("VmHWM:"))
print(json.dumps({"wall": wall, "rss_mb": int(hwm.split()[1]) / 1024}))
"""


def irsim_scenario(world: Any, folder: Path) -> Path:
    """The world as IR-SIM reads it: the map as a PNG (black = occupied), robots with starts, goals
    (their rooms' goal poses) and a lidar2d like vwg's laser."""
    import numpy as np
    from PIL import Image

    grid = world.grid
    png = folder / "map.png"
    Image.fromarray(np.where(grid.blocked(), 0, 255).astype(np.uint8)).save(png)
    rooms = list(world.rooms.values())
    states = [[float(v) for v in r.start] for r in world.robots]
    goals = [[*rooms[k % len(rooms)].goal, 0.0] for k in range(len(world.robots))]
    doc = {
        "world": {"height": grid.height_m, "width": grid.width_m, "step_time": DT, "sample_time": DT,
                  "offset": [0, 0], "collision_mode": "stop", "obstacle_map": str(png), "mdownsample": 1},
        "robot": [{"number": len(states), "distribution": {"name": "manual"}, "kinematics": {"name": "diff"},
                   "shape": {"name": "circle", "radius": 0.18}, "state": states, "goal": goals,
                   "behavior": {"name": "dash"}, "vel_max": [0.5, 1.5],
                   "sensors": [{"name": "lidar2d", "range_min": 0.05, "range_max": RANGE, "angle_range": FOV,
                                "number": BEAMS}]}],
    }
    path = folder / "scenario.yaml"
    path.write_text(json.dumps(doc))  # JSON is YAML
    return path


def irsim_row(world: Any, frames: int, python: str) -> dict[str, Any] | None:
    with tempfile.TemporaryDirectory() as tmp:
        yaml = irsim_scenario(world, Path(tmp))
        spec = {"yaml": str(yaml), "frames": frames, "warmup": WARMUP_FRAMES}
        done = subprocess.run([python, "-c", IRSIM_WORKER, json.dumps(spec)],
                              capture_output=True, text=True, timeout=3600,
                              env={**os.environ, "MPLBACKEND": "Agg"})
    if done.returncode != 0:
        print(f"IR-SIM failed:\n{done.stderr[-2000:]}", file=sys.stderr)
        return None
    out = json.loads(done.stdout.strip().splitlines()[-1])
    return {**row("irsim", world, 1, frames, out["wall"], out["rss_mb"], None), "planner": "dash"}


# ---- vwg ----------------------------------------------------------------------------------------------------------
def vwg_row(world: Any, frames: int, threads: int, planner: str) -> dict[str, Any]:
    from bench_frame import room_goals

    from vwg.robot.case_study import CaseStudy

    goals = room_goals(world)
    settle_memory()
    before = rss_mb()
    with CaseStudy(world, planner, goals=goals, sensors=("laser",), threads=threads) as run:
        run.run(frames=WARMUP_FRAMES)  # first plans, first scans, and the crowd's robots met
        first, searches, search_s = run.engine.frame, run.decider.searches, run.decider.search_seconds
        t0 = time.perf_counter()
        run.engine.run(frames)  # the frames alone (no summary)
        wall = time.perf_counter() - t0
        done = run.engine.frame - first
        searches, search_s = run.decider.searches - searches, run.decider.search_seconds - search_s
        rss = rss_mb()
    # Below a hundred robots what a run adds is the process's own noise (a few MB either way: the
    # allocator, the first use of a module), not the robots': no figure per robot.
    n = len(world.robots)
    per_robot = (rss - before) / n if n >= MEMORY_PER_ROBOT_FROM else None
    # The replanning in the timed frames: how often a robot searched, and the searches' share of
    # the CPU time the frames took on every thread (search_seconds sums the threads' searches).
    return {**row("vwg", world, threads, done, wall, rss, per_robot), "planner": planner,
            "searches_per_robot_step": searches / max(1, n * done), "search_s_per_frame": search_s / max(1, done)}


def row(engine: str, world: Any, threads: int, frames: int, wall: float, rss: float,
        rss_per_robot: float | None) -> dict[str, Any]:
    n = len(world.robots)
    steps = n * frames / wall
    return {"engine": engine, "map": world.name, "n_robots": n, "threads": threads, "frames": frames,
            "robot_steps_per_s": steps, "rays_per_s": steps * BEAMS, "ms_per_frame": 1000 * wall / frames,
            "realtime_factor": frames * DT / wall, "rss_mb": rss, "rss_per_robot_mb": rss_per_robot}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer frames, N up to 100")
    parser.add_argument("--irsim-python", default=os.environ.get("VWG_IRSIM_PYTHON"),
                        help="the interpreter of an environment with ir-sim installed")
    args = parser.parse_args()

    from bench_frame import crowd, rooms_world
    from tqdm import tqdm

    import vwg

    cores = vwg._core.default_threads()
    thread_counts = sorted({1, cores})
    # (map, robots): the warehouse up to 100, the rooms maps for 1,000 and 10,000.
    sizes = [("warehouse", 1), ("warehouse", 10), ("warehouse", 100)]
    if not args.quick:
        sizes += [("rooms500", 1000), ("rooms1600", 10000)]
    frames = {1: 50, 10: 30, 100: 10} if args.quick else {1: 300, 10: 100, 100: 30, 1000: 30, 10000: 10}
    irsim_frames = {1: 50, 10: 20, 100: 5} if args.quick else {1: 200, 10: 50, 100: 10}
    # A* (the paper's decider, Euclidean heuristic) on one thread and every core; Jump Point Search
    # (A*'s path lengths, fewer cells expanded) and A* with the octile heuristic (the same lengths,
    # fewer cells expanded) on every core. Ten thousand robots: on every core alone, A* both ways
    # (their first plans take minutes).
    jobs = [(m, n, "vwg", t, "astar") for m, n in sizes for t in thread_counts if n < 10000 or t == cores]
    jobs += [(m, n, "vwg", cores, "astar-octile") for m, n in sizes]
    jobs += [(m, n, "vwg", cores, "jps") for m, n in sizes if n < 10000]
    jobs += [("warehouse", n, "irsim", 1, "dash") for n in irsim_frames if args.irsim_python]
    rows = []
    maps = {"warehouse": lambda: None, "rooms500": rooms_world, "rooms1600": lambda: rooms_world(1600, 12)}
    for name, n, engine, threads, planner in tqdm(jobs, desc="bench_scale", unit="run"):
        world = crowd(n, world=maps[name]())
        if len(world.robots) < n:
            print(f"{name} holds {len(world.robots)} robots 0.6 m apart, not {n}: left out", file=sys.stderr)
            continue
        if engine == "vwg":
            rows.append(vwg_row(world, frames[n], threads, planner))
        elif r := irsim_row(world, irsim_frames[n], args.irsim_python):
            rows.append(r)
    print(f"{'engine':>6} {'planner':>12} {'map':>9} {'robots':>6} {'threads':>7} {'robot-steps/s':>14} {'rays/s':>12} "
          f"{'ms/frame':>9} {'× real time':>11} {'RSS MB':>7} {'MB/robot':>8} {'searches/step':>13} "
          f"{'search ms/frame':>15}")
    for r in rows:
        per = "" if r["rss_per_robot_mb"] is None else f"{r['rss_per_robot_mb']:.2f}"
        searches = f"{r['searches_per_robot_step']:.4f}" if "searches_per_robot_step" in r else ""
        search_ms = f"{1000 * r['search_s_per_frame']:.1f}" if "search_s_per_frame" in r else ""
        print(f"{r['engine']:>6} {r['planner']:>12} {r['map']:>9} {r['n_robots']:>6} {r['threads']:>7} "
              f"{r['robot_steps_per_s']:>14,.0f} "
              f"{r['rays_per_s']:>12,.0f} {r['ms_per_frame']:>9.1f} {r['realtime_factor']:>11.2f} "
              f"{r['rss_mb']:>7.0f} {per:>8} {searches:>13} {search_ms:>15}")
    ratios: dict[str, float] = {}
    for r in rows:
        peer = next((p for p in rows if p["engine"] == "irsim" and p["n_robots"] == r["n_robots"]), None)
        if r["engine"] == "vwg" and r["threads"] == cores and peer:
            key = f"{r['n_robots']} {r['planner']}"
            ratios[key] = r["robot_steps_per_s"] / peer["robot_steps_per_s"]
            print(f"{r['n_robots']} robots: vwg ({r['planner']}, {cores} threads) {ratios[key]:,.0f}× IR-SIM's "
                  "robot-steps/s")
    if not args.irsim_python:
        print("IR-SIM not run: give --irsim-python (make bench-scale installs it in build/bench-irsim)")
    write_results(RESULTS, quick=args.quick, threads_compared=thread_counts, rows=rows, ratio_vwg_to_irsim=ratios)


if __name__ == "__main__":
    main()
