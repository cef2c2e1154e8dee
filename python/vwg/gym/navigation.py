"""The robots of a robot world driven by a learner: what vwg.gym's environments share.

The learner is the decision inside λ(ARobot, eDecide), as any planner is (paper test 1): an
AgentDecider hands ARobot the move the learner chose. Everything else is the case study as
``vwg run`` runs it: the simulator, each robot's laser, odometry, collisions, the robot's own map.

A step is one move: the learner gives each robot (turn, distance); ARobot takes it at its next
decision, the motors carry it out, and the step ends when every robot that was given a move has
finished it (at most ``frames_per_step`` frames). A robot asked to decide with no move given stays
where it is (a zero move).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import vwg._core as _core
from vwg.errors import Error, SchemaError
from vwg.io.state_file import write_state
from vwg.robot.case_study import CaseStudy
from vwg.robot.shortest import DistanceField
from vwg.robot.world_file import RobotWorld
from vwg.saved_run import check_saved_by_this_vwg, input_hashes, load_parts, read_state_file, state_parts
from vwg.trial import cached_world, random_task, replace_robot

__all__ = ["REWARD", "AgentDecider", "Navigation", "Reward"]


@dataclass(frozen=True)
class Reward:
    """The reward of a step (documented in vwg.gym): ``progress`` × the metres the robot came nearer its
    room along the shortest way round the walls, ``step`` each step, ``collision`` per contact,
    ``arrival`` when it reaches the room."""

    progress: float = 1.0
    step: float = -0.01
    collision: float = -1.0
    arrival: float = 10.0


REWARD = Reward()


class AgentDecider(_core.Decider):
    """The decision of λ(ARobot, eDecide) taken from a learner: ``moves[robot] = (turn, distance)``."""

    name = "agent"

    def __init__(self) -> None:
        super().__init__()
        self.moves: dict[int, tuple[float, float]] = {}

    def decide(self, robot: Any) -> tuple[float, float]:
        return self.moves.pop(int(robot.robot), (0.0, 0.0))


class Navigation:
    """The robots of `world` at seeded free places, each sent to a seeded room it can reach, moved by
    a learner. ``reset(seed)``, ``step({robot: (turn, distance)})``, ``observe(robot)``."""

    def __init__(self, world: str | Any, *, robots: int = 1, beams: int = 36, frames_per_step: int = 50,
                 reward: Reward = REWARD) -> None:

        base = world if isinstance(world, RobotWorld) else cached_world(str(world))
        if not 1 <= robots <= 1000:
            raise SchemaError(f"robots: expected 1 to 1000 robots, got {robots}")
        if not 1 <= beams <= 4096:
            raise SchemaError(f"beams: expected 1 to 4096 laser beams, got {beams}")
        if not 1 <= frames_per_step <= 10_000:
            raise SchemaError(f"frames_per_step: expected 1 to 10000, got {frames_per_step}")
        self.base = dataclasses.replace(base.with_sensor("laser", beams=beams), orders=[])
        self.n_robots = robots
        self.frames_per_step = frames_per_step
        self.reward = reward
        self.laser = self.base.sensor_settings("laser")
        grid = self.base.grid
        self.max_distance = math.hypot(grid.width_m, grid.height_m)  # no room is farther
        self.case: CaseStudy | None = None
        self.decider = AgentDecider()
        self.goals: dict[int, str] = {}
        self._fields: dict[int, Any] = {}
        self._last_way: dict[int, float] = {}
        self._last_collisions: dict[int, int] = {}
        self._arrived: dict[int, bool] = {}
        self.frames_run = 0  # over every episode (an engine's own count starts again at each reset)

    # ---- episodes ---------------------------------------------------------------------------------------
    def reset(self, seed: int) -> None:
        self._make(seed)
        # One frame: the first scans and the orders reach the robots (they decide nothing yet: no move).
        self._frames(1)

    def _make(self, seed: int) -> None:
        """The episode of `seed` made, before its first frame."""
        self.close()
        self.seed = seed
        world, goals = random_task(self.base, self.n_robots, np.random.default_rng(seed))
        world = dataclasses.replace(world, robots=[replace_robot(r, sensors=("laser",)) for r in world.robots])
        self.world, self.goals = world, goals
        self.decider = AgentDecider()
        self.case = CaseStudy(world, self.decider, goals=goals, seed=seed, threads=1, world_orders=False)
        self.lasers = {g.robot: g for g in self.case.sim.made if isinstance(g, _core.LaserGenerator)}
        self.actors = self.case.robot_actors()
        self._fields = {rid: self._field(world.rooms[room].goal) for rid, room in goals.items()}
        self._last_way = {rid: self.way_left(rid) for rid in goals}
        self._last_collisions = {rid: 0 for rid in goals}
        self._arrived = {}

    # ---- saved episodes ---------------------------------------------------------------------------------
    def save_state(self) -> bytes:
        """The episode as it stands between steps, as the bytes of a state file (vwg.io.state_file): its
        seed (the task), the engine's and the simulator's state, and the rewards' bookkeeping."""
        if self.case is None:
            raise Error("save_state: no episode yet (reset() first)")
        parts, frame = state_parts(self.case.engine, self.case.sim.platform)
        episode = {"robots": self.n_robots, "beams": self.laser.beams, "frames_per_step": self.frames_per_step,
                   "last_way": list(self._last_way.items()), "last_collisions": list(self._last_collisions.items()),
                   "arrived": list(self._arrived.items()), "frames_run": self.frames_run}
        manifest = {"vwg": _core.__version__, "world_kind": "gym-navigation",
                    "world_file": str(Path(self.base.path).resolve()), "inputs": input_hashes(self.base),
                    "seed": self.seed, "dt": self.world.dt, "frame": frame,
                    "time": float(self.case.engine.time), "frames_left": 0, "episode": episode}
        return write_state(manifest, parts)

    def restore(self, state: str | Path | bytes) -> None:
        """Go on with an episode save_state() saved (a path or its bytes), in this environment's settings."""
        source = "<state bytes>" if isinstance(state, (bytes, bytearray, memoryview)) else str(state)
        saved = read_state_file(state)
        check_saved_by_this_vwg(saved, source)
        m = saved.manifest
        episode = m.get("episode")
        if m.get("world_kind") != "gym-navigation" or not isinstance(episode, dict):
            raise Error(f"{source}: not an episode saved by a vwg.gym environment (env.unwrapped.save_state())")
        mine = {"robots": self.n_robots, "beams": self.laser.beams, "frames_per_step": self.frames_per_step}
        theirs = {k: episode.get(k) for k in mine}
        if theirs != mine or Path(str(m.get("world_file"))) != Path(self.base.path).resolve():
            raise Error(f"{source}: saved by an environment of {m.get('world_file')} with {theirs}; this one is of "
                        f"{self.base.path} with {mine}")
        self._make(int(m["seed"]))
        assert self.case is not None
        load_parts(saved, self.case.engine, self.case.sim.platform, source)
        self.actors = self.case.robot_actors()
        self._last_way = {int(k): float(v) for k, v in episode["last_way"]}
        self._last_collisions = {int(k): int(v) for k, v in episode["last_collisions"]}
        self._arrived = {int(k): bool(v) for k, v in episode["arrived"]}
        self.frames_run = int(episode["frames_run"])

    def _field(self, goal: tuple[float, float]) -> Any:

        grid = self.world.grid
        return DistanceField(grid.blocked(), grid.world_to_cell(*goal))

    @property
    def robots(self) -> list[int]:
        return list(self.goals)

    # ---- steps ------------------------------------------------------------------------------------------
    def step(self, moves: Mapping[int, tuple[float, float]]) -> dict[int, float]:
        """Give these robots a move each, run frames until they have done them; each robot's reward."""
        assert self.case is not None, "reset() first"
        moving = [rid for rid in moves if not self.reached(rid)]
        for rid in moving:
            self.decider.moves[rid] = moves[rid]
        platform = self.case.sim.platform
        for _ in range(self.frames_per_step):
            self._frames(1)
            if all(self._done(platform.robot(rid)) for rid in moving):
                break
        self.decider.moves.clear()  # a move not taken in time is dropped, not kept for the next step
        return {rid: self._reward(rid) for rid in moves}

    def _done(self, state: Any) -> bool:
        """Whether the robot took its move and the motors have received and finished it."""
        return (state.id not in self.decider.moves and state.commands >= int(self.actors[state.id]["sent"])
                and not state.busy)

    def _frames(self, n: int) -> None:
        assert self.case is not None
        for _ in range(n):
            self.case.engine.step()
        self.frames_run += n
        self.actors = self.case.robot_actors()

    def _reward(self, rid: int) -> float:
        way = self.way_left(rid)
        collisions = self.case.sim.robot(rid).collisions if self.case else 0
        r = self.reward.step + self.reward.progress * (self._last_way[rid] - way)
        r += self.reward.collision * (collisions - self._last_collisions[rid])
        if self.reached(rid) and not self._arrived.get(rid):
            r += self.reward.arrival
            self._arrived[rid] = True
        self._last_way[rid], self._last_collisions[rid] = way, collisions
        return float(r)

    # ---- what a robot knows -----------------------------------------------------------------------------
    def reached(self, rid: int) -> bool:
        return bool(self.actors[rid]["reached"])

    def way_left(self, rid: int) -> float:
        """Metres from the robot (where it truly is) to its room along the shortest way round the walls."""
        assert self.case is not None
        x, y, _ = self.case.sim.robot(rid).pose
        cell = self.world.grid.world_to_cell(x, y)
        d = self._fields[rid].to(cell)
        goal = self.world.rooms[self.goals[rid]].goal
        if not math.isfinite(d):  # pressed into a wall's cell by a collision: as the crow flies
            return math.hypot(goal[0] - x, goal[1] - y)
        return d * self.world.grid.resolution

    def observe(self, rid: int) -> dict[str, np.ndarray]:
        """The robot's laser ranges (metres, float32) and its room's distance (metres) and bearing
        (radians, from its heading), as it believes its pose (its string's x, y, angle)."""
        actor = self.actors[rid]
        x, y, angle = float(actor["x"]), float(actor["y"]), float(actor["angle"])
        gx, gy = self.world.rooms[self.goals[rid]].goal
        bearing = math.atan2(gy - y, gx - x) - angle
        bearing = math.atan2(math.sin(bearing), math.cos(bearing))
        distance = min(math.hypot(gx - x, gy - y), self.max_distance)  # a belief off the map is clipped
        return {"laser": np.minimum(self.lasers[rid].ranges, np.float32(self.laser.max_range)),
                "goal": np.array([distance, bearing], dtype=np.float32)}

    def info(self, rid: int) -> dict[str, Any]:
        assert self.case is not None
        state = self.case.sim.robot(rid)
        return {"room": self.goals[rid], "reached": self.reached(rid), "way_left_m": self.way_left(rid),
                "collisions": int(state.collisions), "travelled_m": float(state.travelled),
                "frame": self.case.engine.frame}

    def close(self) -> None:
        if self.case is not None:
            self.case.close()
            self.case = None
