"""What Monte Carlo localization costs and what it gives.

Cost: the whole frame of `vwg run` with 100 robots on the shipped warehouse (each with a 180-beam, 180°, 10 m
laser and an order to a room, A*, odometry noise 0.05, 2 threads), robot-steps per second with
`localization: odometry` (the reference, in the same process) and `particles` (300 particles, 60 beams); the
difference is the localization's cost per robot-step.

Gain: the office's robot 1 sent to a room drawn from the seed, odometry noise 0.05 per metre: the distance
between where it believes it is and where it is (the simulator's truth) at the end of the run, with odometry
alone and with particles, over several seeds.

    python benchmarks/bench_localization.py [--quick]

prints two tables and writes benchmarks/results/<machine>/bench_localization.json.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
from pathlib import Path

import numpy as np
from bench_frame import crowd, room_goals
from machine import write_results
from tqdm import tqdm

import vwg
from vwg.robot.case_study import CaseStudy
from vwg.robot.world_file import Localization
from vwg.trial import random_task

RESULTS = Path(__file__).resolve().parent / "results" / "bench_localization.json"
NOISE = vwg.robot.NoiseModel(odometry=0.05)


def crowd_rate(world: vwg.robot.RobotWorld, kind: str, frames: int) -> float:
    world = dataclasses.replace(world, noise=NOISE, localization=Localization.of(kind))
    with CaseStudy(world, "astar", goals=room_goals(world), sensors=("laser",), threads=2) as run:
        run.run(frames=2)  # warm up: first plans, first scans, the filters started
        t0 = time.perf_counter()
        done = run.run(frames=frames).frames - 2
        return len(world.robots) * done / (time.perf_counter() - t0)


def final_error(seed: int, kind: str, frames: int) -> tuple[float, bool]:
    office = vwg.robot.load_robot_world("office")
    world, goals = random_task(office, 1, np.random.default_rng(seed))
    world = dataclasses.replace(world, noise=NOISE, localization=Localization.of(kind))
    with CaseStudy(world, "astar", goals=goals, seed=seed, frames=frames, threads=1) as run:
        summary = run.run()
    return float(summary.pose_error_m), summary.reached


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer frames and seeds")
    args = parser.parse_args()
    frames, seeds, run_frames = (8, range(3), 1500) if args.quick else (30, range(10), 3000)
    world = crowd(100)
    cost, gain = [], []
    with tqdm(total=2 + 2 * len(seeds), desc="bench_localization", unit="run") as bar:
        rates = {}
        for kind in ("odometry", "particles"):
            rates[kind] = crowd_rate(world, kind, frames)
            bar.update()
        cost.append({"robots": len(world.robots), "frames": frames, "odometry_robot_steps_per_s": rates["odometry"],
                     "particles_robot_steps_per_s": rates["particles"],
                     "ratio_to_odometry": rates["particles"] / rates["odometry"],
                     "localization_us_per_robot_step": 1e6 * (1 / rates["particles"] - 1 / rates["odometry"])})
        for seed in seeds:
            row: dict[str, object] = {"seed": seed}
            for kind in ("odometry", "particles"):
                error, reached = final_error(seed, kind, run_frames)
                row[f"{kind}_error_m"], row[f"{kind}_reached"] = error, reached
                bar.update()
            gain.append(row)
    c = cost[0]
    print(f"100 robots, warehouse, A*: odometry {c['odometry_robot_steps_per_s']:,.0f} robot-steps/s, particles "
          f"{c['particles_robot_steps_per_s']:,.0f} ({c['ratio_to_odometry']:.2f}×), localization "
          f"{c['localization_us_per_robot_step']:.0f} µs a robot-step")
    print(f"{'seed':>4} {'odometry m':>11} {'particles m':>12}")
    for r in gain:
        print(f"{r['seed']:>4} {r['odometry_error_m']:>11.3f} {r['particles_error_m']:>12.3f}")
    odo = statistics.median(float(r["odometry_error_m"]) for r in gain)  # type: ignore[arg-type]
    pf = statistics.median(float(r["particles_error_m"]) for r in gain)  # type: ignore[arg-type]
    print(f"median final pose error: odometry {odo:.3f} m, particles {pf:.3f} m ({pf / odo:.2f}×)")
    write_results(RESULTS, quick=args.quick, cost=cost, gain=gain,
                  median_error_m={"odometry": odo, "particles": pf, "ratio": pf / odo})


if __name__ == "__main__":
    main()
