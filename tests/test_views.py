"""Every numpy array vwg hands to Python owns (or keeps alive) what it views: kept past the call
and past many frames, it stays valid and its content does not change."""

from __future__ import annotations

import gc

import numpy as np

import vwg
from vwg.robot.case_study import CaseStudy


class Keeper(vwg.robot.Decider):
    """Drives straight at the goal, and keeps every grid and path it is given, with a copy made at
    the time to compare them with later."""

    name = "keeper"

    def __init__(self) -> None:
        super().__init__()
        self.kept: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = []

    def decide(self, robot):
        grid, path = robot.grid, robot.path
        self.kept.append((grid, grid.copy(), path, path.copy()))
        return robot.follow([robot.pose[:2], robot.goal])


def test_grids_and_paths_kept_by_a_decider_stay_as_they_were():
    decider = Keeper()
    # The robot knows no map: its laser writes new walls into its grid every frame.
    run = CaseStudy(vwg.robot.load_robot_world("office"), decider, goals={1: "lounge"}, sensors=("laser",),
                    knows_map=False)
    run.run(frames=200)
    del run
    gc.collect()
    assert len(decider.kept) > 10
    for grid, grid_then, path, path_then in decider.kept:
        assert not grid.flags.writeable and not path.flags.writeable
        np.testing.assert_array_equal(grid, grid_then)
        np.testing.assert_array_equal(path, path_then)
    # The grid did change during the run: the kept views were of different states.
    first, last = decider.kept[0][1], decider.kept[-1][1]
    assert (first != last).sum() > 100


def test_sensor_arrays_are_copies_of_one_frame():
    world = vwg.robot.load_robot_world("office")
    run = CaseStudy(world, "astar", goals={1: "lounge"}, sensors=("laser",))
    run.run(frames=5)
    laser = next(g for g in run.sim.made if isinstance(g, vwg._core.LaserGenerator))
    kept, then = laser.ranges, laser.ranges.copy()
    run.run(frames=20)
    np.testing.assert_array_equal(kept, then)
    assert not np.array_equal(laser.ranges, then)  # the robot moved: the new scan differs
