"""A decider written in Python (paper test 1): the registered planner ``wavefront``.

A breadth-first wavefront spreads from the goal over the robot's own map (its grid attribute:
walls, what its sensors saw), SciPy's breadth-first search over the grid's graph, in one pass; the robot walks down
the wavefront's numbers to the goal. The path is kept while it stays clear on the robot's map, and made
again when a newly seen obstacle cuts it. It is a second, independent kind of planner beside the C++
ones (a wave of unit steps, 8-connected, so its paths are shortest in steps, not in metres), and an
example of what a user's decider looks like.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from vwg._core import Decider
from vwg.io.maps import OccupancyGrid
from vwg.robot.shortest import grid_graph

__all__ = ["WavefrontDecider", "wavefront"]


def wavefront(blocked: np.ndarray, goal: tuple[int, int]) -> np.ndarray:
    """Steps from each cell to `goal` over the free cells of `blocked`, 8-connected without cutting a
    blocked corner (-1: not reached): a breadth-first search, SciPy's, over the grid's graph in one pass."""
    from scipy.sparse.csgraph import shortest_path

    steps = np.full(blocked.shape, -1, dtype=np.int32)
    if blocked[goal]:
        return steps
    graph = grid_graph(blocked)  # 8-connected, no corner cutting; unweighted below: steps, not metres
    cols = blocked.shape[1]
    dist = shortest_path(graph, method="D", directed=False, unweighted=True, indices=goal[0] * cols + goal[1])
    reached = np.isfinite(dist)
    steps.ravel()[reached] = dist[reached].astype(np.int32)
    return steps


def descend(steps: np.ndarray, start: tuple[int, int]) -> list[tuple[int, int]]:
    """The cells from `start` down the wavefront to its goal (empty if the wave did not reach it)."""
    rows, cols = steps.shape
    r, c = start
    if steps[r, c] < 0:
        return []
    path = [(r, c)]
    while steps[r, c] > 0:
        best = None
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                down = (dr or dc) and 0 <= nr < rows and 0 <= nc < cols and 0 <= steps[nr, nc] == steps[r, c] - 1
                if down and (best is None or dr == 0 or dc == 0):  # a straight step before a diagonal one
                    best = (nr, nc)
        if best is None:
            break
        r, c = best
        path.append(best)
    return path


class WavefrontDecider(Decider):
    """The ``wavefront`` planner: a wavefront from the goal on the robot's map, in Python."""

    name = "wavefront"

    def __init__(self) -> None:
        super().__init__()
        self.searches = 0  # wavefronts made
        self.search_seconds = 0.0  # time spent making them (as GridDecider counts its searches)

    def decide(self, robot: Any) -> Any:

        grid = robot.grid
        # Walls, seen obstacles and markers (on walls) block; unknown cells are hoped free.
        occupancy = OccupancyGrid(np.where(grid >= 100, 100, 0).astype(np.int8), robot.resolution, robot.origin)
        path = np.asarray(robot.path)
        # Keep the rest of the current path (from its point nearest the robot) while every leg of it is
        # still clear on the robot's map.
        if len(path) >= 2:
            nearest = int(np.argmin(np.hypot(path[:, 0] - robot.pose[0], path[:, 1] - robot.pose[1])))
            rest = path[nearest:]
        if len(path) >= 2 and len(rest) >= 2 and all(robot.segment_clear(*rest[i], *rest[i + 1])
                                                     for i in range(len(rest) - 1)):
            points = [robot.pose[:2]] + [tuple(p) for p in rest[1:]]
            move = robot.follow(points)
            if move is not None:
                return (*move, points)
        blocked = occupancy.inflate(robot.radius)
        start = occupancy.world_to_cell(*robot.pose[:2])
        goal = occupancy.world_to_cell(*robot.goal)
        if not (occupancy.inside(*start) and occupancy.inside(*goal)):
            return None
        blocked[start] = False  # the robot stands where it stands, even pressed against a wall
        began = time.perf_counter()
        cells = descend(wavefront(blocked, goal), start)
        self.searches += 1
        self.search_seconds += time.perf_counter() - began
        if not cells:
            return None
        points = [robot.pose[:2]] + [occupancy.cell_to_world(r, c) for r, c in cells[1:-1]] + [robot.goal]
        move = robot.follow(points)
        if move is None:
            return None
        return (*move, points)
