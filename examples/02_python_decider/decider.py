"""A decision written in Python (paper test 1): the intelligence of the robot is the decision inside
λ(ARobot, eDecide), and it can be swapped without touching anything else of the world.

This one plans on the robot's own map (its `grid` attribute, as the robot knows it: walls, what its
laser saw, markers) with vwg.plan.astar, inflating obstacles by the robot's radius, and follows the path.
"""

from __future__ import annotations

import numpy as np

import vwg


class PythonAStar(vwg.robot.Decider):
    name = "python-astar"

    def decide(self, robot: vwg.DecisionInput):
        grid = robot.grid  # int16: -1 unknown, 0 free, 100 wall, 101 seen obstacle, 1000+ marker
        occupancy = vwg.io.maps.OccupancyGrid(np.where((grid >= 100) | (grid < 0), 100, 0).astype(np.int8),
                                      robot.resolution, robot.origin)
        blocked = occupancy.inflate(robot.radius)
        start = occupancy.world_to_cell(*robot.pose[:2])
        goal = occupancy.world_to_cell(*robot.goal)
        blocked[start] = False  # the robot stands where it stands, even if pressed against a wall
        if blocked[goal]:
            return None
        path, _ = vwg.plan.astar(blocked, start, goal)
        if path is None:
            return None
        points = [robot.pose[:2]] + [occupancy.cell_to_world(r, c) for r, c in path[1:-1]] + [robot.goal]
        move = robot.follow(points)
        if move is None:
            return None
        return (*move, points)
