"""Test 3, simulation and real robot: the same world string through the simulator platform and through
the rosbridge link to a robot (paper §III.F.3).

The robot here is vwg.testing.fake_robot's: a rosbridge v2 server on 127.0.0.1 with its own Box2D simulator,
driven only by the Twists vwg publishes and seen only through the Odometry and LaserScan it publishes.
It runs in lockstep (it steps when vwg asks), so the two runs can be compared frame by frame. The same
task also goes through the same link to a robot of independent physics, vwg.testing.irsim_robot's (IR-SIM's
kinematics and lidar), and the three robots' true trajectories are compared.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import vwg._core as _core
from vwg import launch
from vwg._core import NoiseModel
from vwg.experiments import plots
from vwg.experiments.section import Section
from vwg.experiments.tables import Table, bootstrap, fmt, group, mean, mean_cell, median_cell, share_cell
from vwg.robot.case_study import CaseStudy
from vwg.robot.world_file import LOCALIZATIONS, Localization, PlatformSpec
from vwg.testing.fake_robot import FakeRosbridgeRobot
from vwg.testing.irsim_robot import IrsimRosbridgeRobot, load_irsim
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

**Another robot's physics.** The same task (noise off, and with odometry noise at each level below) run
(a) on the simulator platform, (b) through rosbridge to a robot simulated by IR-SIM (vwg.testing.irsim_robot:
IR-SIM's own differential-drive kinematics, one Euler step per frame, and its own lidar, on the same map,
start, laser layout and limits; its odometry drifts by the simulator's noise law, with draws of its own) and
(c) through rosbridge to the fake robot, in lockstep. Each run's **true** pose after every frame (the
simulator's, IR-SIM's, the fake's) is compared at the same frame times (a robot that has arrived stays where
it stopped): **apart** is the mean and the largest distance between (a) and (b), and between (a) and (c);
**off path** how far apart the paths are whatever the pace along them (the largest distance from a point
of either to the nearest point of the other): a robot a little ahead on the same path is apart, not off
it; **frames** is when each robot said it had arrived. The IR-SIM row shows that the model, its planner and
its motion control hold on a robot whose physics and laser vwg did not write: the distance is what a
different integrator, different dynamics and a different laser make, not an error of either. It does not
show that either simulator is right about a real robot (neither has wheel slip or a real laser's
misses), and with noise on it mixes the two physics with two draws of the noise. The fake-robot columns show,
noise off, that the link itself adds nothing (0 apart): that is so by construction, as the fake robot is
the same simulator at the same step, so they check the link, not the simulation. With odometry noise the
fake robot parts from the simulator too, and rightly: the simulator platform closes its motion control on
the true pose, which it knows, while through a link vwg closes it on the robot's odometry, as it must on a
real robot.

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

    #: Tasks run on the three robots (the simulator, IR-SIM, the fake robot); default ``seeds``.
    trajectory_seeds: list[int] | None = None
    #: Their frame limit; default ``frames``.
    trajectory_frames: int | None = None

    @property
    def trajectory_levels(self) -> list[float]:
        """The odometry noise of the three-robot runs: off, then each level of ``noise_levels`` above 0."""
        return [0.0, *(level for level in self.noise_levels if level > 0)]

    @property
    def compared(self) -> int:
        """Tasks run on the three robots (three runs each)."""
        seeds = self.seeds if self.trajectory_seeds is None else self.trajectory_seeds
        return len(seeds) * len(self.trajectory_levels)

    @property
    def runs(self) -> int:
        return 2 * self.pairs + self.noisy + self.localized + 3 * self.compared


def _task(seed: int, frames: int) -> tuple[Any, dict[int, str]]:

    world, goals, _ = trial_world(Trial(WORLD, "astar", seed, frames, {"task": "random", "sensors": ["laser"]}))

    return dataclasses.replace(world.with_sensor("laser", noise=0.0), noise=NoiseModel()), goals


def _lockstep(world: Any, url: str, control_rate: float) -> Any:
    # In lockstep the watchdog is how long vwg waits for a step's answer: a loaded machine can hold a step back
    # for more than the default half second, and a late answer would end the run. It changes no number: the
    # steps are the same however long they take.
    return dataclasses.replace(world, platform=PlatformSpec("rosbridge", {
        "url": url, "lockstep": "/vwg/step", "control_rate": control_rate, "watchdog": 30.0}))


def _on_ros(world: Any, url: str) -> Any:
    return _lockstep(world, url, 100.0)  # the simulator's own step, 0.01 s: the same frames bit for bit


def _on_irsim(world: Any, robot: IrsimRosbridgeRobot) -> Any:
    return _lockstep(world, robot.url, 1.0 / robot.step)  # one IR-SIM step per control tick


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


KINDS = ("same", "trajectories", "noise", "localization")  # the kinds of row runs() gives


def _track(case: CaseStudy, frames: int, truth: Callable[[], tuple[float, float, float]]
           ) -> tuple[list[tuple[float, float]], Any]:
    """Run `case` a frame at a time, to `frames` or until its robot has arrived: the true (x, y) after each
    frame, and the last summary."""
    poses: list[tuple[float, float]] = []
    summary = None
    while case.engine.frame < frames:
        summary = case.run(frames=1)
        x, y, _ = truth()
        poses.append((x, y))
        if summary.reached:
            break
    return poses, summary


def _apart(a: list[tuple[float, float]], b: list[tuple[float, float]]) -> list[float]:
    """The distance between two trajectories at each frame; the one that ended first stays where it stopped."""
    n = max(len(a), len(b))
    a, b = a + a[-1:] * (n - len(a)), b + b[-1:] * (n - len(b))
    return [math.hypot(p[0] - q[0], p[1] - q[1]) for p, q in zip(a, b, strict=True)]


def _off_path(a: list[tuple[float, float]], b: list[tuple[float, float]]) -> float:
    """How far apart the two paths are, whatever the pace along them: the largest distance from a point of
    either to the nearest point of the other (the Hausdorff distance of the sampled paths), over the length
    both have driven (a run cut by the frame limit leaves the quicker robot further on, not off the path)."""
    pa, pb = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    driven = [np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))]) for p in (pa, pb)]
    both = min(d[-1] for d in driven)
    pa, pb = pa[driven[0] <= both + 1e-9], pb[driven[1] <= both + 1e-9]
    d = np.hypot(pa[:, None, 0] - pb[None, :, 0], pa[:, None, 1] - pb[None, :, 1])
    return float(max(d.min(axis=1).max(), d.min(axis=0).max()))


def trajectories(level: float, seed: int, frames: int) -> dict[str, Any]:
    """One task with odometry noise `level` on the simulator, through rosbridge to IR-SIM and through rosbridge
    to the fake robot; how far the second and third robots' true trajectories part from the first's."""

    world, goals = _task(seed, frames)
    world = dataclasses.replace(world, noise=NoiseModel(odometry=level))
    rid = world.robots[0].id
    with CaseStudy(world, "astar", goals=goals, seed=seed, threads=1) as case:
        sim, a = _track(case, frames, lambda: case.sim.robot(rid).pose)
    with IrsimRosbridgeRobot(world, seed=seed) as robot, \
            CaseStudy(_on_irsim(world, robot), "astar", goals=goals, seed=seed, threads=1) as case:
        irsim, b = _track(case, frames, lambda: robot.pose(rid))
        collisions = robot.collisions[rid]
    physics = _core.PhysicsSettings(noise=NoiseModel(odometry=level), seed=seed)
    with FakeRosbridgeRobot(world, lockstep=True, physics=physics) as fake, \
            CaseStudy(_on_ros(world, fake.url), "astar", goals=goals, seed=seed, threads=1) as case:
        faked, c = _track(case, frames, lambda: fake.pose(rid))
    to_irsim, to_fake = _apart(sim, irsim), _apart(sim, faked)
    return {"seed": seed, "level": level, "room": goals[rid],
            "frames_sim": a.frames, "frames_irsim": b.frames, "frames_fake": c.frames,
            "reached_sim": a.reached, "reached_irsim": b.reached, "reached_fake": c.reached,
            "collisions_irsim": collisions, "mean_irsim": sum(to_irsim) / len(to_irsim), "max_irsim": max(to_irsim),
            "mean_fake": sum(to_fake) / len(to_fake), "max_fake": max(to_fake), "apart_irsim": to_irsim,
            "path_irsim": _off_path(sim, irsim), "path_fake": _off_path(sim, faked),
            "dt": world.dt}


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


def jobs(config: SimulationConfig, records: Path) -> list[tuple[str, Callable[..., dict[str, Any]], tuple[Any, ...]]]:
    """Every run of the test as (kind, function, its arguments), a kind of KINDS, in the report's order: "same"
    (the frame logs of the simulator and the fake robot), "trajectories" (the three robots), "noise" (through
    rosbridge with odometry noise), "localization" (on the simulator, odometry alone and particles). Each is
    independent of the others (its servers on 127.0.0.1, on a port of its own), so they may run anywhere."""
    records.mkdir(parents=True, exist_ok=True)
    if config.compared:
        load_irsim()  # before any run: without IR-SIM the test stops at once, saying what to install
    todo: list[tuple[str, Callable[..., dict[str, Any]], tuple[Any, ...]]] = []
    todo += [("same", same_frames, (seed, config.frames, records)) for seed in config.seeds]
    seeds = config.seeds if config.trajectory_seeds is None else config.trajectory_seeds
    frames = config.frames if config.trajectory_frames is None else config.trajectory_frames
    todo += [("trajectories", trajectories, (level, seed, frames))
             for level in config.trajectory_levels for seed in seeds]
    todo += [("noise", drift, (level, seed, config.noise_frames))
             for level in config.noise_levels for seed in config.noise_seeds]
    todo += [("localization", localized, (level, seed, config.noise_frames, kind))
             for level in config.noise_levels for seed in config.noise_seeds for kind in LOCALIZATIONS]
    return todo


def runs(config: SimulationConfig, records: Path) -> Iterator[tuple[str, dict[str, Any]]]:
    """Every run of jobs() here, one after another, as (kind, row)."""
    for kind, work, args in jobs(config, records):
        yield kind, work(*args)


def section(found: dict[str, list[dict[str, Any]]], folder: Path) -> Section:
    """The test's section from the rows of runs(), by kind."""
    out = Section(3, "Test to validate the simulation", METHOD)
    same, compared, noise = found.get("same", []), found.get("trajectories", []), found.get("noise", [])
    localization = found.get("localization", [])
    table = Table("simulation_same_frames", "The simulator and the robot through rosbridge, noise off",
                  ["seed", "room", "frames (simulator)", "frames (rosbridge)", "reached (simulator)",
                   "reached (rosbridge)", "record bytes", "identical"])
    for r in same:
        table.add(str(r["seed"]), r["room"], str(r["frames_sim"]), str(r["frames_ros"]), _yes(r["reached_sim"]),
                  _yes(r["reached_ros"]), str(r["bytes"]), _yes(r["identical"]))
    out.tables.append(table)
    if compared:
        _trajectories(out, compared, folder)
    noisy = Table("simulation_odometry_noise", "Through rosbridge with odometry noise",
                  ["odometry noise", "runs", "believed arrived", "truly there", "trajectory error m (mean)",
                   "final error m (median)"])
    xs, ys, px, py, bands = [], [], [], [], []
    for level, rows in group(noise, lambda r: r["level"]).items():
        noisy.add(f"{level:g}", str(len(rows)), share_cell(r["reached"] for r in rows),
                  share_cell(r["truly_there"] for r in rows), mean_cell((r["mean_error"] for r in rows), 3),
                  median_cell((r["final_error"] for r in rows), 3))
        xs.append(level)
        ys.append(mean(r["mean_error"] for r in rows))
        bands.append(bootstrap((r["mean_error"] for r in rows), np.mean))
        px += [level] * len(rows)
        py += [r["mean_error"] for r in rows]
    out.tables.append(noisy)
    if localization:
        located = Table("simulation_localization",
                        "On the simulator with odometry noise: odometry alone and Monte Carlo localization",
                        ["odometry noise", "belief from", "runs", "believed arrived", "truly there",
                         "trajectory error m (mean)", "final error m (median)"])
        for (level, kind), rows in group(localization, lambda r: (r["level"], r["localization"])).items():
            located.add(f"{level:g}", kind, str(len(rows)), share_cell(r["reached"] for r in rows),
                        share_cell(r["truly_there"] for r in rows), mean_cell((r["mean_error"] for r in rows), 3),
                        median_cell((r["final_error"] for r in rows), 3))
        out.tables.append(located)
    out.plots.append(plots.lines(folder / "simulation_odometry_noise.png", "Where vwg believes the robot is, against "
                                 "where it is", "odometry noise (per metre and radian)", "trajectory error (m)",
                                 {"mean over runs": (xs, ys)}, points={"one run": (px, py)},
                                 intervals={"mean over runs": bands}))
    identical = sum(r["identical"] for r in same)
    out.findings.append(f"{identical} of {len(same)} pairs of frame logs were identical byte for byte.")
    return out


def _trajectories(out: Section, rows: list[dict[str, Any]], folder: Path) -> None:
    """The three-robot table, its picture (the IR-SIM robot's distance from the simulator's, frame by frame)
    and what its numbers say."""
    table = Table("simulation_trajectories", "The same task on the simulator, on IR-SIM through rosbridge and on "
                  "the fake robot through rosbridge: how far the true trajectories part",
                  ["seed", "odometry noise", "room", "frames (simulator)", "frames (IR-SIM)", "frames (fake robot)",
                   "arrived (simulator)", "arrived (IR-SIM)", "arrived (fake robot)", "IR-SIM apart m (mean)",
                   "IR-SIM apart m (max)", "IR-SIM off path m", "fake robot apart m (mean)",
                   "fake robot apart m (max)", "fake robot off path m"])
    series: dict[str, tuple[list[float], list[float]]] = {}
    for r in rows:
        table.add(str(r["seed"]), f"{r['level']:g}", r["room"], str(r["frames_sim"]), str(r["frames_irsim"]),
                  str(r["frames_fake"]), _yes(r["reached_sim"]), _yes(r["reached_irsim"]), _yes(r["reached_fake"]),
                  fmt(r["mean_irsim"], 3), fmt(r["max_irsim"], 3), fmt(r["path_irsim"], 3), fmt(r["mean_fake"], 3),
                  fmt(r["max_fake"], 3), fmt(r["path_fake"], 3))
        if r["level"] == 0:  # the two physics alone: with noise on, two draws of it come in too
            times = [(i + 1) * r["dt"] for i in range(len(r["apart_irsim"]))]
            series[f"seed {r['seed']}"] = (times, r["apart_irsim"])
    out.tables.append(table)
    if series:
        out.plots.append(plots.lines(folder / "simulation_trajectories.png", "How far the IR-SIM robot is from the "
                                     "simulator's, the same task, noise off", "simulated time (s)", "distance (m)",
                                     series))
    quiet = [r for r in rows if r["level"] == 0]
    arrived = sum(r["reached_irsim"] for r in rows)
    out.findings.append(f"The robot on IR-SIM arrived in {arrived} of {len(rows)} runs (on the simulator "
                        f"{sum(r['reached_sim'] for r in rows)}); it touched a wall or a robot, which stops an "
                        f"IR-SIM robot for good, in {sum(r['collisions_irsim'] > 0 for r in rows)} of them.")
    if quiet:
        out.findings.append(f"Noise off, its true trajectory parted from the simulator's by "
                            f"{mean(r['mean_irsim'] for r in quiet):.3f} m on average (at most "
                            f"{max(r['max_irsim'] for r in quiet):.3f} m, and its path by at most "
                            f"{max(r['path_irsim'] for r in quiet):.3f} m); the fake robot's by "
                            f"{max(r['max_fake'] for r in quiet):.3f} m at most.")


def _yes(flag: bool) -> str:
    return "yes" if flag else "no"
