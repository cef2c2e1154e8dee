"""The 3D overview of a robot world (the paper's Fig. 5), taken from where its robots can be seen.

A robot in a corridor is hidden from most oblique views by the corridor's walls. The view is chosen
among a few azimuths and elevations, preferring the default oblique one: the first that shows the
most robots wins. A robot counts as seen when the line from the top of its body towards the eye
clears every wall cell until it is above the walls.
"""

from __future__ import annotations

import math

import numpy as np

import vwg._core as _core
from vwg.robot.world_file import RobotWorld

__all__ = ["VIEWS", "render_world_overview", "robots_seen"]

_VIEW = _core.OverviewView()  # the C++ defaults of a view (vwg::sim::OverviewView)
_DEFAULT_AZIMUTH = _VIEW.azimuth
_DEFAULT_ELEVATION = _VIEW.elevation
#: (azimuth, elevation) candidates in order of preference: oblique first, steeper after.
VIEWS: tuple[tuple[float, float], ...] = tuple(
    (az, el)
    for el in (_DEFAULT_ELEVATION, 1.25, 1.4, 1.5)
    for az in (_DEFAULT_AZIMUTH, -1.2, -2.6, -0.5, 2.6, 1.9, 1.2, 0.5)
)


def robots_seen(world: RobotWorld, azimuth: float, elevation: float, robot_height: float = _VIEW.robot_height) -> int:
    """How many robots (at their starts) the view from (azimuth, elevation) sees over the walls."""
    grid = world.grid
    rise = math.tan(elevation)
    reach = max(world.wall_height - robot_height, 0.0) / rise  # beyond this the line is above the walls
    dx, dy = math.cos(azimuth), math.sin(azimuth)
    step = grid.resolution / 2
    seen = 0
    for robot in world.robots:
        x0, y0 = robot.start[0], robot.start[1]
        hidden = False
        for s in np.arange(robot.radius, reach + step, step):
            row, col = grid.world_to_cell(x0 + s * dx, y0 + s * dy)
            if not grid.inside(row, col):
                break
            if grid.data[row, col] >= _core.OBSTACLE_THRESHOLD:
                hidden = True
                break
        seen += not hidden
    return seen


def render_world_overview(world: RobotWorld, *, width: int = _VIEW.width, height: int = _VIEW.height,
                          labels: bool = _VIEW.labels) -> np.ndarray:
    """The world in 3D (H×W×3 uint8) from the preferred view that shows the most robots."""
    best = max(VIEWS, key=lambda v: (robots_seen(world, *v), -VIEWS.index(v)))
    # People at their starts, as cylinders too: bodies of id -(their id), which the view draws in sand.
    people = [{"x": p.start[0], "y": p.start[1], "radius": p.radius, "id": -p.id} for p in world.people]
    return _core.render_overview(world.grid, markers=world.rooms, robots=[*world.robots, *people],
                                 wall_height=world.wall_height,
                                 width=width, height=height, azimuth=best[0], elevation=best[1], labels=labels)
