"""The platform ``kinematic``: the robots of a world moved exactly as they are told, in Python, with no
physics. Each robot follows its motion steps (turn, then drive) with vwg's MotionFollower, the speed
profile within the robot's limits that the simulator and a real robot's link use, and is moved along
the velocities it gives (a unicycle, integrated exactly over each step). Nothing collides: robots pass
through walls and each other, so the decider must keep them clear (every vwg decider does).

Its option ``slip`` is the fraction of each motion the wheels lose: the robot moves (1 - slip) of what
its odometry counts, and its motion is closed on its odometry, as a real robot's control loop is, so
with slip it falls short of where it believes it is. ``step`` is the integration step, seconds.

    platform: {kind: kinematic, slip: 0.05}     # in a world file; or --platform kinematic --platform-opt slip=0.05

It carries vwg's laser (cast on the map's walls from the true pose: the platform's ``raycaster``) and
this package's sonar; a camera or a Kinect needs the simulator and is left out with a warning.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import vwg._core as _core
from vwg.errors import SchemaError
from vwg.robot import MotionFollower, Option, Platform, RobotPlatform, RobotSettings, RobotState

__all__ = ["Kinematic", "KinematicRobots", "unicycle"]

Pose = tuple[float, float, float]


def unicycle(pose: Pose, speed: float, turn_rate: float, dt: float) -> Pose:
    """Where a unicycle at `pose` gets holding (speed, turn_rate) for dt seconds: along the arc exactly
    (a straight line when it does not turn)."""
    x, y, theta = pose
    turned = turn_rate * dt
    if abs(turned) < 1e-12:
        return x + speed * dt * math.cos(theta), y + speed * dt * math.sin(theta), theta
    radius = speed / turn_rate
    return (x + radius * (math.sin(theta + turned) - math.sin(theta)),
            y - radius * (math.cos(theta + turned) - math.cos(theta)),
            math.remainder(theta + turned, math.tau))


@dataclass
class _Robot:
    settings: RobotSettings
    follower: MotionFollower
    pose: Pose       # the truth
    odometry: Pose   # what the wheels count
    commands: int = 0
    travelled: float = 0.0
    speed: float = 0.0
    turn_rate: float = 0.0


class KinematicRobots(RobotPlatform):
    """A vwg.robot.RobotPlatform written in Python: `robots` moved by their motion followers, every
    `step` seconds, losing `slip` of each motion."""

    def __init__(self, robots: Iterable[RobotSettings] = (), *, slip: float = 0.0, step: float = 0.01) -> None:
        super().__init__()
        if not (math.isfinite(slip) and 0.0 <= slip <= 1.0):
            raise SchemaError(f"platform.slip: expected a fraction from 0 to 1, got {slip!r}")
        if not (math.isfinite(step) and 0.0 < step <= 1.0):
            raise SchemaError(f"platform.step: expected 0 < seconds <= 1, got {step!r}")
        self.slip = slip
        self.step = step
        self._robots: dict[int, _Robot] = {}
        self._clock = 0.0
        self._pending = 0.0  # time asked for that is less than a step, carried to the next advance
        for settings in robots:
            self.add_robot(settings)

    # -- RobotPlatform ------------------------------------------------------------------------------
    def add_robot(self, settings: RobotSettings) -> None:
        settings.check(f"robot {settings.id}")
        if settings.id in self._robots:
            raise SchemaError(f"robot {settings.id}: the id is used twice")
        start = _core.quantize_pose(tuple(settings.start))
        self._robots[settings.id] = _Robot(settings, MotionFollower(settings), start, start)

    def remove_robot(self, id: int) -> None:
        self._get(id)
        del self._robots[id]

    def command(self, robot: int, steps: list[tuple[str, float]]) -> None:
        r = self._get(robot)
        r.follower.command(list(steps))
        r.commands += 1

    def advance(self, seconds: float) -> None:
        # Whole steps, the rest carried over (as the simulator steps its physics).
        total = self._pending + seconds
        steps = math.floor(total / self.step + 1e-9)
        self._pending = max(0.0, total - steps * self.step)
        kept = 1.0 - self.slip
        for _ in range(steps):
            for r in self._robots.values():
                speed, turn_rate = r.follower.tick(r.odometry, self.step)
                r.odometry = unicycle(r.odometry, speed, turn_rate, self.step)
                r.pose = unicycle(r.pose, kept * speed, kept * turn_rate, self.step)
                r.travelled += abs(kept * speed) * self.step
                r.speed, r.turn_rate = kept * speed, kept * turn_rate
                r.follower.settle(r.odometry)
            self._clock += self.step

    def robots(self) -> list[RobotState]:
        return [self._state(rid, r) for rid, r in sorted(self._robots.items())]

    def robot(self, id: int) -> RobotState:
        return self._state(id, self._get(id))

    def take_collisions(self) -> list[_core.Collision]:
        return []  # no physics: nothing touches

    def time(self) -> float:
        return self._clock

    def name(self) -> str:
        return "kinematic"

    # -- helpers ------------------------------------------------------------------------------------
    def _get(self, robot: int) -> _Robot:
        try:
            return self._robots[robot]
        except KeyError:
            raise SchemaError(f"no robot with id {robot} (robots: {sorted(self._robots)})") from None

    @staticmethod
    def _state(rid: int, r: _Robot) -> RobotState:
        # Poses at the float resolution every platform reports them at (vwg.robot.quantize_pose).
        return RobotState(rid, _core.quantize_pose(r.pose), _core.quantize_pose(r.odometry), radius=r.settings.radius,
                          busy=r.follower.busy, commands=r.commands, travelled=r.travelled, speed=r.speed,
                          turn_rate=r.turn_rate)


class Kinematic(Platform):
    """The platform ``kinematic`` (entry point group vwg.platforms)."""

    name = "kinematic"
    sensors = ("laser", "sonar")
    summary = "robots moved exactly as told, in Python, without physics (nothing collides)"
    options: ClassVar[dict[str, Option]] = {
        "slip": Option(float, 0.0, minimum=0.0, maximum=1.0,
                       help="fraction of each motion the wheels lose (the odometry counts it all)"),
        "step": Option(float, 0.01, minimum=0.0, exclusive_minimum=True, maximum=1.0,
                       help="integration step, seconds"),
    }

    def __init__(self, world: Any, seed: int, options: Mapping[str, Any]) -> None:
        super().__init__(world, seed, options)
        self.platform = KinematicRobots(list(world.robots), slip=self.settings["slip"], step=self.settings["step"])
        self.backend = _core.MotionBackend(self.platform)
        # The laser and the sonar cast their rays on the map's walls with it.
        self.raycaster = _core.GridRaycaster(world.grid)
