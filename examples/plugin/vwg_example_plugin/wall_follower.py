"""The decider ``wall-follower``: the decision inside λ(ARobot, eDecide) (paper test 1) of a robot that
follows the wall on its right, and heads straight for its goal whenever the way there is clear on its
map. It keeps no memory: each decision looks at the robot's own map (the walls it knows and what its
sensors saw) afresh, as a robot steering by its range sensors would.

Each decision:

1. the segment to the goal is clear (robot.segment_clear: the robot's radius and clearance kept):
   turn to the goal and drive to it, a step at most;
2. it feels for walls on its right, with rays cast on its map from its centre: beside it (80° to 100°
   right of its heading) and behind it on the right (100° to 170°), within ``feel`` metres;
3. a wall beside it: straight on; else, if a wall is behind it on the right, the wall it followed has
   ended: a quarter turn right, round its end; no wall at all: straight on, until it meets one;
4. when that way is not clear, it turns away from what is ahead: a quarter turn left, else half a turn
   (the wall it meets ends up on its right). A move goes a ``stride``, or the half or the quarter of one
   that is clear. A robot that cannot move at all (closer to an obstacle than its clearance, which every
   test from where it stands refuses) backs away from the nearest one a little.

It turns by quarter turns, so along straight walls it keeps to the lines it started on.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from vwg._core import GridRaycaster
from vwg.io.maps import OccupancyGrid
from vwg.robot import Decider

__all__ = ["WallFollower"]

#: Obstacles on a robot's map: walls (100), seen obstacles (101) and markers (1000 + id).
OBSTACLE = 100
#: The rays that feel for walls on the right, relative to the heading, every 5°: behind it on the
#: right (-170° to -105°), then beside it (-100° to -80°).
RAYS = np.radians(np.arange(-170.0, -79.0, 5.0))
BESIDE = slice(14, None)
BEHIND = slice(0, 14)

LEFT, RIGHT, BACK = math.pi / 2, -math.pi / 2, math.pi


class WallFollower(Decider):
    """Follows the wall on its right; goes straight to the goal when the way is clear. ``stride``: the
    longest move along a wall (metres, and at most the robot's step length); ``feel``: how near a wall
    on its right must be to be followed (metres from the robot's centre)."""

    name = "wall-follower"

    def __init__(self, stride: float = 0.5, feel: float = 1.0) -> None:
        super().__init__()
        for key, value in (("stride", stride), ("feel", feel)):
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"WallFollower.{key}: expected a finite number > 0, got {value!r}")
        self.stride, self.feel = stride, feel

    def decide(self, robot: Any) -> Any:
        x, y, theta = robot.pose
        gx, gy = robot.goal
        if robot.segment_clear(x, y, gx, gy):
            distance = min(math.hypot(gx - x, gy - y), robot.step_length)
            return _wrap(math.atan2(gy - y, gx - x) - theta), distance, [(x, y), (gx, gy)]
        beside, behind = self.feel_right(robot)
        turns = (RIGHT, 0.0, LEFT, BACK) if behind and not beside else (0.0, LEFT, BACK)
        stride = min(self.stride, robot.step_length)
        for turn in turns:
            a = theta + turn
            for length in (stride, stride / 2, stride / 4):
                tx, ty = x + length * math.cos(a), y + length * math.sin(a)
                if robot.segment_clear(x, y, tx, ty):
                    return turn, length, [(x, y), (tx, ty)]
        return self.back_away(robot)

    def feel_right(self, robot: Any) -> tuple[bool, bool]:
        """(a wall beside the robot on its right, a wall behind it on its right): an obstacle of its
        map within `feel` of its centre along a ray of RAYS."""
        occupied = np.where(np.asarray(robot.grid) >= OBSTACLE, 100, 0).astype(np.int8)
        raycaster = GridRaycaster(OccupancyGrid(occupied, robot.resolution, robot.origin))
        near = raycaster.scan(robot.pose, RAYS, self.feel) < np.float32(self.feel)
        return bool(near[BESIDE].any()), bool(near[BEHIND].any())

    @staticmethod
    def back_away(robot: Any) -> Any:
        """Half a cell straight away from the nearest obstacle cell of the robot's map (it stands closer
        to one than its clearance), or half a turn when none is near."""
        x, y, theta = robot.pose
        grid = np.asarray(robot.grid)
        res = robot.resolution
        ox, oy = robot.origin[0], robot.origin[1]
        reach = math.ceil(robot.radius / res) + 1
        row, col = math.floor((y - oy) / res), math.floor((x - ox) / res)
        r0, c0 = max(row - reach, 0), max(col - reach, 0)
        rows, cols = np.nonzero(grid[r0:row + reach + 1, c0:col + reach + 1] >= OBSTACLE)
        if len(rows) == 0:
            return BACK, 0.0
        cx, cy = ox + (c0 + cols + 0.5) * res, oy + (r0 + rows + 0.5) * res
        nearest = int(np.argmin(np.hypot(cx - x, cy - y)))
        return _wrap(math.atan2(y - cy[nearest], x - cx[nearest]) - theta), 0.5 * res


def _wrap(angle: float) -> float:
    """`angle` wrapped into [-π, π]."""
    return math.remainder(angle, math.tau)
