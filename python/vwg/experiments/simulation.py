"""Test 3, simulation and real robot: the same world string through the simulator platform and through
the rosbridge link to a robot (paper §III.F.3).

The robot here is vwg.testing.fake_robot's: a rosbridge v2 server on 127.0.0.1 with its own Box2D simulator,
driven only by the Twists vwg publishes and seen only through the Odometry and LaserScan it publishes.
It runs in lockstep (it steps when vwg asks), so the two runs can be compared frame by frame.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import vwg._core as _core
from vwg import launch
from vwg._core import NoiseModel
from vwg.experiments import plots
from vwg.experiments.section import Section
from vwg.experiments.tables import Table, fmt, group, mean, median, share
from vwg.robot.case_study import CaseStudy
from vwg.robot.world_file import LOCALIZATIONS, Localization, PlatformSpec
from vwg.testing.fake_robot import FakeRosbridgeRobot
from vwg.trial import Trial, trial_world

__all__ = ["SimulationConfig", "section"]

WORLD = "office"

METHOD = """
**Same frames.** One robot, a start and a room drawn from the seed, noise off: the world runs (a) on
the simulator platform and (b) through rosbridge to a robot that is only reachable through its ROS
topics (vwg.testing.fake_robot, stepped in lockstep). Both runs are recorded; **identical** says whether the two
frame logs are the same byte for byte (header included).

**Odometry noise.** The same through rosbridge, the robot's odometry drifting (a random walk per metre
and per radian, the level below): vwg knows the robot only by its odometry, so where it believes the
robot is parts from where the robot is. **trajectory error**: the distance between the two, sampled
every 5 frames (mean over the run, and at the end); **truly there**: the share of runs in which the
robot, believing it had arrived, really stood within the goal tolerance of its room.

**Localization.** The same tasks and noise levels on the simulator platform (whose truth vwg can read),
with the belief from odometry alone and from Monte Carlo localization (`localization: particles`: a
particle filter per robot weighed on its laser against the known map); the same measures.
"""


@dataclass
class SimulationConfig:
    seeds: list[int]
    frames: int
    noise_levels: list[float]
    noise_seeds: list[int]
    noise_frames: int

    @property
    def pairs(self) -> int:
        """Tasks run on both platforms."""
        return len(self.seeds)

    @property
    def noisy(self) -> int:
        """Runs with odometry noise."""
        return len(self.noise_levels) * len(self.noise_seeds)

    @property
    def localized(self) -> int:
        """Runs on the simulator with and without localization."""
        return 2 * self.noisy

    @property
    def runs(self) -> int:
        return 2 * self.pairs + self.noisy + self.localized


def _task(seed: int, frames: int) -> tuple[Any, dict[int, str]]:

    world, goals, _ = trial_world(Trial(WORLD, "astar", seed, frames, {"task": "random", "sensors": ["laser"]}))

    return dataclasses.replace(world.with_sensor("laser", noise=0.0), noise=NoiseModel()), goals


def _on_ros(world: Any, url: str) -> Any:

    return dataclasses.replace(world, platform=PlatformSpec("rosbridge", {"url": url, "lockstep": "/vwg/step",
                                                                         "control_rate": 100}))


def same_frames(seed: int, frames: int, records: Path) -> dict[str, Any]:
    """Run one task on the simulator and through rosbridge, recording both; compare the records."""

    world, goals = _task(seed, frames)
    orders = [f"{robot}:{room}" for robot, room in goals.items()]
    sim, ros = records / f"sim_seed{seed}.jsonl", records / f"rosbridge_seed{seed}.jsonl"
    with launch.start(world, launch.RunOptions(goals=orders, frames=frames, record=sim)) as run:
        a = run.execute().summary
    with FakeRosbridgeRobot(world, lockstep=True) as fake, \
            launch.start(_on_ros(world, fake.url), launch.RunOptions(goals=orders, frames=frames, record=ros)) as run:
        b = run.execute().summary
    return {"seed": seed, "room": next(iter(goals.values())), "frames_sim": a["frames"], "frames_ros": b["frames"],
            "reached_sim": a["reached"], "reached_ros": b["reached"], "bytes": sim.stat().st_size,
            "identical": sim.read_bytes() == ros.read_bytes()}


def _follow(case: CaseStudy, world: Any, goals: dict[int, str], frames: int,
            truth: Callable[[int], tuple[float, float, float]]) -> dict[str, Any]:
    """Run `case` 5 frames at a time, to `frames` or until its robot has arrived; after each stretch, the distance
    from the pose the robot was told (its odometry, or its localization's estimate) to its true pose `truth(id)`.
    The row's measures: reached, frames, the mean and last distance, and whether it truly stood at its room."""
    rid = world.robots[0].id
    errors: list[float] = []
    while case.engine.frame < frames:
        summary = case.run(frames=min(5, frames - case.engine.frame))
        (bx, by, _), (tx, ty, _) = case.sensed_pose(rid), truth(rid)
        errors.append(math.hypot(bx - tx, by - ty))
        if summary.reached:
            break
    gx, gy = world.rooms[goals[rid]].goal
    tx, ty, _ = truth(rid)
    return {"reached": summary.reached, "frames": summary.frames, "mean_error": sum(errors) / len(errors),
            "final_error": errors[-1],
            "truly_there": summary.reached and math.hypot(tx - gx, ty - gy) <= world.goal_tolerance}


def drift(level: float, seed: int, frames: int) -> dict[str, Any]:
    """Run one task through rosbridge with odometry noise; vwg's belief against the robot's true pose."""

    world, goals = _task(seed, frames)
    physics = _core.PhysicsSettings(noise=_core.NoiseModel(odometry=level), seed=seed)
    with FakeRosbridgeRobot(world, lockstep=True, physics=physics) as fake, \
            CaseStudy(_on_ros(world, fake.url), "astar", goals=goals, seed=seed, threads=1) as case:
        return {"level": level, "seed": seed, **_follow(case, world, goals, frames, fake.pose)}


def localized(level: float, seed: int, frames: int, kind: str) -> dict[str, Any]:
    """Run one task on the simulator with odometry noise, the belief from odometry or from particles; the
    belief against the simulator's true pose."""

    world, goals = _task(seed, frames)
    world = dataclasses.replace(world, noise=NoiseModel(odometry=level), localization=Localization.of(kind))
    with CaseStudy(world, "astar", goals=goals, seed=seed, threads=1) as case:
        return {"level": level, "seed": seed, "localization": kind,
                **_follow(case, world, goals, frames, lambda rid: case.sim.robot(rid).pose)}


def runs(config: SimulationConfig, records: Path) -> Iterator[tuple[str, dict[str, Any]]]:
    """Every run of the test, as ("same", row), ("noise", row) or ("localization", row), as each finishes."""
    records.mkdir(parents=True, exist_ok=True)
    for seed in config.seeds:
        yield "same", same_frames(seed, config.frames, records)
    for level in config.noise_levels:
        for seed in config.noise_seeds:
            yield "noise", drift(level, seed, config.noise_frames)
    for level in config.noise_levels:
        for seed in config.noise_seeds:
            for kind in LOCALIZATIONS:
                yield "localization", localized(level, seed, config.noise_frames, kind)


def section(same: list[dict[str, Any]], noise: list[dict[str, Any]], folder: Path,
            localization: list[dict[str, Any]] | None = None) -> Section:
    out = Section(3, "Test to validate the simulation", METHOD)
    table = Table("simulation_same_frames", "The simulator and the robot through rosbridge, noise off",
                  ["seed", "room", "frames (simulator)", "frames (rosbridge)", "reached (simulator)",
                   "reached (rosbridge)", "record bytes", "identical"])
    for r in same:
        table.add(str(r["seed"]), r["room"], str(r["frames_sim"]), str(r["frames_ros"]), _yes(r["reached_sim"]),
                  _yes(r["reached_ros"]), str(r["bytes"]), _yes(r["identical"]))
    out.tables.append(table)
    noisy = Table("simulation_odometry_noise", "Through rosbridge with odometry noise",
                  ["odometry noise", "runs", "believed arrived", "truly there", "trajectory error m (mean)",
                   "final error m (median)"])
    xs, ys, px, py = [], [], [], []
    for level, rows in group(noise, lambda r: r["level"]).items():
        noisy.add(f"{level:g}", str(len(rows)), fmt(share(r["reached"] for r in rows), 2),
                  fmt(share(r["truly_there"] for r in rows), 2), fmt(mean(r["mean_error"] for r in rows), 3),
                  fmt(median(r["final_error"] for r in rows), 3))
        xs.append(level)
        ys.append(mean(r["mean_error"] for r in rows))
        px += [level] * len(rows)
        py += [r["mean_error"] for r in rows]
    out.tables.append(noisy)
    if localization:
        located = Table("simulation_localization",
                        "On the simulator with odometry noise: odometry alone and Monte Carlo localization",
                        ["odometry noise", "belief from", "runs", "believed arrived", "truly there",
                         "trajectory error m (mean)", "final error m (median)"])
        for (level, kind), rows in group(localization, lambda r: (r["level"], r["localization"])).items():
            located.add(f"{level:g}", kind, str(len(rows)), fmt(share(r["reached"] for r in rows), 2),
                        fmt(share(r["truly_there"] for r in rows), 2), fmt(mean(r["mean_error"] for r in rows), 3),
                        fmt(median(r["final_error"] for r in rows), 3))
        out.tables.append(located)
    out.plots.append(plots.lines(folder / "simulation_odometry_noise.png", "Where vwg believes the robot is, against "
                                 "where it is", "odometry noise (per metre and radian)", "trajectory error (m)",
                                 {"mean over runs": (xs, ys)}, points={"one run": (px, py)}))
    identical = sum(r["identical"] for r in same)
    out.findings.append(f"{identical} of {len(same)} pairs of frame logs were identical byte for byte.")
    return out


def _yes(flag: bool) -> str:
    return "yes" if flag else "no"
