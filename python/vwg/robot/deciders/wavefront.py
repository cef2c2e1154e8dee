"""A decider written in Python (paper test 1): the registered planner ``wavefront``.

A breadth-first wavefront spreads from the goal over the robot's own map (its grid attribute:
walls, what its sensors saw), in numpy, one ring of cells a step; the robot walks down the
wavefront's numbers to the goal. The path is kept while it stays clear on the robot's map, and made
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

__all__ = ["WavefrontDecider", "wavefront"]


def _shift(mask: np.ndarray, dr: int, dc: int) -> np.ndarray:
    """``out[r, c] = mask[r - dr, c - dc]`` (False where that falls outside)."""
    rows, cols = mask.shape
    out = np.zeros_like(mask)
    out[max(0, dr):rows + min(0, dr), max(0, dc):cols + min(0, dc)] = \
        mask[max(0, -dr):rows + min(0, -dr), max(0, -dc):cols + min(0, -dc)]
    return out


def wavefront(blocked: np.ndarray, goal: tuple[int, int], start: tuple[int, int] | None = None) -> np.ndarray:
    """Steps from each cell to `goal` over the free cells of `blocked`, 8-connected without cutting a
    blocked corner (-1: not reached). With `start`, the wave stops once it gets there."""
    steps = np.full(blocked.shape, -1, dtype=np.int32)
    if blocked[goal]:
        return steps
    free = ~blocked
    # A diagonal step from (r, c) by (dr, dc) needs (r + dr, c) and (r, c + dc) free: where it may start.
    diagonal_ok = {(dr, dc): _shift(free, -dr, 0) & _shift(free, 0, -dc) for dr in (-1, 1) for dc in (-1, 1)}
    frontier = np.zeros(blocked.shape, dtype=bool)
    frontier[goal] = True
    steps[goal] = 0
    k = 0
    while frontier.any() and not (start is not None and steps[start] >= 0):
        k += 1
        grown = np.zeros_like(frontier)
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                if dr and dc:
                    grown |= _shift(frontier & diagonal_ok[(dr, dc)], dr, dc)
                elif dr or dc:
                    grown |= _shift(frontier, dr, dc)
        frontier = grown & free & (steps < 0)
        steps[frontier] = k
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
        cells = descend(wavefront(blocked, goal, start), start)
        self.searches += 1
        self.search_seconds += time.perf_counter() - began
        if not cells:
            return None
        points = [robot.pose[:2]] + [occupancy.cell_to_world(r, c) for r, c in cells[1:-1]] + [robot.goal]
        move = robot.follow(points)
        if move is None:
            return None
        return (*move, points)
