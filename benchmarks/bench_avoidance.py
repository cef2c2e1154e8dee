"""What reciprocal avoidance costs and what it gives.

Cost: the whole frame of `vwg run` with 100 robots on the shipped warehouse (each with a 180-beam, 180°, 10 m
laser and an order to a room, A*, 2 threads), robot-steps per second with `avoidance: none` (the reference, in
the same process) and `orca` (gNeighbours on every robot's scans, ORCA and a decision every frame); the
difference is the avoidance's cost per robot-step. Also the A* searches a frame of each, which do not depend on
the machine: most of the difference.

Gain: eight robots in the warehouse at seeded starts, sent to seeded rooms (vwg.trial's random task, as test 4
of `vwg experiments`), without and with avoidance: collisions and robots that reached their rooms, per seed.

    python benchmarks/bench_avoidance.py [--quick]

prints two tables and writes benchmarks/results/<machine>/bench_avoidance.json.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

from bench_frame import crowd, room_goals
from machine import write_results
from tqdm import tqdm

import vwg
from vwg.robot.case_study import CaseStudy
from vwg.robot.world_file import Avoidance
from vwg.trial import Trial, run_trial

RESULTS = Path(__file__).resolve().parent / "results" / "bench_avoidance.json"


def crowd_rate(world: vwg.robot.RobotWorld, kind: str, frames: int) -> tuple[float, float]:
    """Robot-steps a second, and A* searches a frame (the same on any machine: what the rate depends on most)."""
    world = dataclasses.replace(world, avoidance=Avoidance.of(kind))
    with CaseStudy(world, "astar", goals=room_goals(world), sensors=("laser",), threads=2) as run:
        run.run(frames=3)  # warm up: first plans, first scans, the first tracks
        searches = run.decider.searches
        t0 = time.perf_counter()
        done = run.run(frames=frames).frames - 3
        rate = len(world.robots) * done / (time.perf_counter() - t0)
        return rate, (run.decider.searches - searches) / done


def eight_robots(seed: int, kind: str, frames: int) -> dict[str, object]:
    row = run_trial(Trial(world="warehouse", planner="astar", seed=seed, frames=frames,
                          params={"task": "random", "robots": 8, "avoidance": kind}))
    return {"collisions": int(row["collisions"]), "reached": int(row["reached_robots"]), "frames": int(row["frames"])}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer frames and seeds")
    args = parser.parse_args()
    frames, seeds, run_frames = (8, range(3), 3000) if args.quick else (30, range(10), 3000)
    world = crowd(100)
    gain = []
    with tqdm(total=2 + 2 * len(seeds), desc="bench_avoidance", unit="run") as bar:
        rates, searches = {}, {}
        for kind in ("none", "orca"):
            rates[kind], searches[kind] = crowd_rate(world, kind, frames)
            bar.update()
        cost = {"robots": len(world.robots), "frames": frames, "none_robot_steps_per_s": rates["none"],
                "orca_robot_steps_per_s": rates["orca"], "ratio_to_none": rates["orca"] / rates["none"],
                "avoidance_us_per_robot_step": 1e6 * (1 / rates["orca"] - 1 / rates["none"]),
                "none_searches_per_frame": searches["none"], "orca_searches_per_frame": searches["orca"]}
        for seed in seeds:
            row: dict[str, object] = {"seed": seed}
            for kind in ("none", "orca"):
                for key, value in eight_robots(seed, kind, run_frames).items():
                    row[f"{kind}_{key}"] = value
                bar.update()
            gain.append(row)
    print(f"100 robots, warehouse, A*, 2 threads: none {cost['none_robot_steps_per_s']:,.0f} robot-steps/s, orca "
          f"{cost['orca_robot_steps_per_s']:,.0f} ({cost['ratio_to_none']:.2f}×), avoidance "
          f"{cost['avoidance_us_per_robot_step']:.0f} µs a robot-step; A* searches a frame: none "
          f"{cost['none_searches_per_frame']:.1f}, orca {cost['orca_searches_per_frame']:.1f}")
    print(f"{'seed':>4} {'collisions none':>16} {'orca':>5} {'reached none':>13} {'orca':>5}")
    for r in gain:
        print(f"{r['seed']:>4} {r['none_collisions']:>16} {r['orca_collisions']:>5} {r['none_reached']:>11}/8 "
              f"{r['orca_reached']:>3}/8")
    totals = {k: sum(int(r[k]) for r in gain)  # type: ignore[call-overload]
              for k in ("none_collisions", "orca_collisions", "none_reached", "orca_reached")}
    robots = 8 * len(gain)
    print(f"collisions: none {totals['none_collisions']}, orca {totals['orca_collisions']}; robots reached: none "
          f"{totals['none_reached']}/{robots}, orca {totals['orca_reached']}/{robots}")
    write_results(RESULTS, quick=args.quick, cost=[cost], gain=gain, totals={**totals, "robots": robots})


if __name__ == "__main__":
    main()
