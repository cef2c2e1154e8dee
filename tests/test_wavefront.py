"""The decider written in Python (``wavefront``): its wave against a plain breadth-first search, and
robots that reach their rooms with it."""

from __future__ import annotations

import itertools
from collections import deque

import numpy as np
import pytest

from vwg.plugins import deciders
from vwg.robot.deciders.wavefront import WavefrontDecider, descend, wavefront
from vwg.trial import Trial, run_trial


def plain_bfs(blocked, goal):
    rows, cols = blocked.shape
    steps = np.full(blocked.shape, -1)
    if blocked[goal]:
        return steps
    steps[goal] = 0
    queue = deque([goal])
    while queue:
        r, c = queue.popleft()
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                if not (dr or dc) or not (0 <= nr < rows and 0 <= nc < cols) or blocked[nr, nc] or steps[nr, nc] >= 0:
                    continue
                if dr and dc and (blocked[r + dr, c] or blocked[r, c + dc]):
                    continue
                steps[nr, nc] = steps[r, c] + 1
                queue.append((nr, nc))
    return steps


def test_the_wave_matches_a_plain_breadth_first_search():
    rng = np.random.default_rng(5)
    for _ in range(60):
        shape = tuple(rng.integers(1, 20, size=2))
        blocked = rng.random(shape) < rng.uniform(0, 0.5)
        goal = (int(rng.integers(shape[0])), int(rng.integers(shape[1])))
        np.testing.assert_array_equal(wavefront(blocked, goal), plain_bfs(blocked, goal))


def test_descending_the_wave_walks_to_the_goal_one_step_at_a_time():
    blocked = np.zeros((6, 7), bool)
    blocked[1:5, 3] = True  # a wall with gaps at both ends
    steps = wavefront(blocked, (2, 6))
    path = descend(steps, (2, 0))
    assert path[0] == (2, 0) and path[-1] == (2, 6)
    assert len(path) - 1 == steps[2, 0] == plain_bfs(blocked, (2, 6))[2, 0]
    for (r0, c0), (r1, c1) in itertools.pairwise(path):
        assert max(abs(r1 - r0), abs(c1 - c0)) == 1 and not blocked[r1, c1]
    assert descend(wavefront(blocked, (0, 3)), (5, 3)) != []
    cut = np.zeros((3, 3), bool)
    cut[:, 1] = True
    assert descend(wavefront(cut, (0, 0)), (0, 2)) == []


@pytest.mark.parametrize(("world", "seed"), [("office", 1), ("warehouse", 2), ("maze", 2)])
def test_robots_reach_their_rooms_with_the_python_decider(world, seed):
    assert isinstance(deciders.create("wavefront"), WavefrontDecider)
    row = run_trial(Trial(world, "wavefront", seed, 1500, {"task": "random"}))
    assert row["reached"], row
    # Shortest in steps, not in metres, and smoothed by the robot's following: near the optimum.
    assert 0.9 * row["optimal_m"] < row["path_length_m"] < 1.2 * row["optimal_m"]
    assert row["planning_s"] > 0
