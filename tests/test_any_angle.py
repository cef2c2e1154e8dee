"""The experiments' yardstick (vwg.robot.any_angle, vwg.trial.any_angle_m) against distances worked out by hand,
against a second method (Dijkstra over a 32-neighbour grid of cell corners, each move's sight line tested cell by
cell), and the boxes of test 5 against the optimum they must lengthen."""

from __future__ import annotations

import heapq
import itertools
import math

import numpy as np
import pytest

from vwg.robot.any_angle import AnyAngle
from vwg.robot.shortest import DistanceField
from vwg.trial import Trial, any_angle_m, any_angle_way, cached_world, shortest_m, trial_world


def test_an_open_grid_is_a_straight_line():
    field = AnyAngle(np.zeros((30, 40), bool))
    assert field.distance((1.5, 2.5), (27.5, 38.5)) == pytest.approx(math.hypot(26, 36))
    assert field.path((1.5, 2.5), (27.5, 38.5)) == [(1.5, 2.5), (27.5, 38.5)]


def test_round_a_block_by_its_two_near_corners():
    # A block of rows 5-14, columns 8-11 (the square [5, 15] x [8, 12]); from (10, 2) to (10, 18) the way goes over
    # its top corners (5, 8) and (5, 12): two legs of hypot(5, 6) and 4 between them.
    blocked = np.zeros((20, 20), bool)
    blocked[5:15, 8:12] = True
    field = AnyAngle(blocked)
    assert field.distance((10, 2), (10, 18)) == pytest.approx(2 * math.hypot(5, 6) + 4)
    assert field.path((10, 2), (10, 18)) == [(10, 2), (5, 8), (5, 12), (10, 18)]
    # Along the block's side, touching it, is clear: from (5, 2) to (5, 18) runs on the line row = 5.
    assert field.distance((5, 2), (5, 18)) == pytest.approx(16)


def test_a_wall_with_a_door_and_a_walled_in_goal():
    blocked = np.zeros((21, 21), bool)
    blocked[10, :] = True
    blocked[10, 15:17] = False  # a door two cells wide at columns 15-16: corners (10, 15) and (11, 15)...
    field = AnyAngle(blocked)
    # From (2, 2) to (18, 2): through the door, bending at its left jamb's corners (10, 15) and (11, 15).
    want = math.hypot(8, 13) + 1 + math.hypot(7, 13)
    assert field.distance((2, 2), (18, 2)) == pytest.approx(want)
    blocked[10, 15:17] = True
    assert AnyAngle(blocked).distance((2, 2), (18, 2)) == math.inf
    assert AnyAngle(blocked).path((2, 2), (18, 2)) == []


def _corner_grid_dijkstra(blocked: np.ndarray, start: tuple[int, int], goal: tuple[int, int], reach: int = 4) -> float:
    """A second method: Dijkstra over the lattice points (cell corners) with every move (dr, dc) of |dr|, |dc| <=
    reach, a move allowed when no cell its segment passes through the inside of is blocked (tested exactly, cell by
    cell, at the midpoints between the segment's crossings of the grid lines)."""
    rows, cols = blocked.shape
    moves = [(dr, dc) for dr in range(-reach, reach + 1) for dc in range(-reach, reach + 1)
             if (dr or dc) and math.gcd(abs(dr), abs(dc)) == 1]

    def clear(r0: int, c0: int, r1: int, c1: int) -> bool:
        ts = sorted({0.0, 1.0} | {k / abs(r1 - r0) for k in range(1, abs(r1 - r0))}
                    | {k / abs(c1 - c0) for k in range(1, abs(c1 - c0))})
        for a, b in itertools.pairwise(ts):
            t = (a + b) / 2
            r, c = r0 + t * (r1 - r0), c0 + t * (c1 - c0)
            # A point on a grid line (a move along a cell's side) is blocked only if both cells beside it are.
            rs = {math.floor(r - 1e-9), math.floor(r + 1e-9)}
            cs = {math.floor(c - 1e-9), math.floor(c + 1e-9)}
            if all(not (0 <= rr < rows and 0 <= cc < cols) or blocked[rr, cc] for rr in rs for cc in cs):
                return False
        return True

    dist = {start: 0.0}
    queue = [(0.0, start)]
    while queue:
        d, (r, c) = heapq.heappop(queue)
        if (r, c) == goal:
            return d
        if d > dist[(r, c)]:
            continue
        for dr, dc in moves:
            nr, nc = r + dr, c + dc
            if 0 <= nr <= rows and 0 <= nc <= cols and clear(r, c, nr, nc):
                nd = d + math.hypot(dr, dc)
                if nd < dist.get((nr, nc), math.inf):
                    dist[(nr, nc)] = nd
                    heapq.heappush(queue, (nd, (nr, nc)))
    return math.inf


def test_agrees_with_a_32_neighbour_grid_search_on_random_rooms():
    # The finer search moves only in its 32 directions, so it can only be longer, and not by more than the worst
    # angle between two of them allows: 1 / cos(half the largest gap, atan(1/3) - atan(1/4)) plus a cell.
    rng = np.random.default_rng(7)
    for _ in range(6):
        blocked = rng.random((24, 24)) < 0.12
        blocked[:3, :3] = blocked[-3:, -3:] = False
        exact = AnyAngle(blocked).distance((1, 1), (23, 23))
        grid = _corner_grid_dijkstra(blocked, (1, 1), (23, 23))
        assert math.isinf(exact) == math.isinf(grid)
        if math.isfinite(exact):
            assert exact <= grid + 1e-9
            assert grid <= exact * 1.0 / math.cos((math.atan(1 / 3) - math.atan(1 / 4)) / 2) * 1.01 + 1.0


@pytest.mark.parametrize("name", ["office", "maze", "warehouse"])
def test_between_the_straight_line_and_the_8_connected_way_on_the_shipped_maps(name):
    # Euclid <= any angle <= the 8-connected grid way (vwg.robot.shortest, SciPy's Dijkstra), which is at most
    # 1/cos(22.5°) = 8.2 % longer than the any-angle way it follows, plus a cell at each end for the grid's centres.
    world = cached_world(name)
    grid, radius = world.grid, world.robots[0].radius
    rng = np.random.default_rng(3)
    free = np.argwhere(~grid.inflate(radius))
    checked = 0
    for _ in range(12):
        a, b = (grid.cell_to_world(*free[k]) for k in rng.choice(len(free), 2))
        exact = any_angle_m(grid, radius, a, b)
        octile = shortest_m(grid, radius, a, b)
        if math.isinf(octile):
            assert math.isinf(exact)
            continue
        checked += 1
        assert math.dist(a, b) - 1e-9 <= exact <= octile + 1e-9
        assert octile <= exact / math.cos(math.pi / 8) + 2 * grid.resolution
    assert checked >= 8


def test_the_way_is_clear_and_bends_only_at_corners():
    world = cached_world("office")
    grid, radius = world.grid, world.robots[0].radius
    start, goal = (1.0, 1.0), world.rooms["kitchen"].goal
    way = any_angle_way(grid, radius, start, goal)
    assert way[0] == pytest.approx(start) and way[-1] == pytest.approx(goal)
    assert sum(math.dist(a, b) for a, b in itertools.pairwise(way)) == pytest.approx(
        any_angle_m(grid, radius, start, goal))
    blocked = grid.inflate(radius)
    for a, b in itertools.pairwise(way):  # sampled every millimetre: no free-space centre is crossed blocked
        for t in np.linspace(0.0, 1.0, int(math.dist(a, b) / 0.001) + 2)[1:-1]:
            x, y = a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])
            col, row = (x - grid.origin[0]) / grid.resolution, (y - grid.origin[1]) / grid.resolution
            # Within a quarter cell of a free cell (STEP / 2: what sight tests may graze).
            near = [(math.floor(row + dr), math.floor(col + dc)) for dr in (-0.25, 0, 0.25) for dc in (-0.25, 0, 0.25)]
            assert any(not blocked[r, c] for r, c in near), (x, y)


def test_with_the_goal_tolerance_it_is_the_way_less_the_tolerance():
    world = cached_world("office")
    grid, radius = world.grid, world.robots[0].radius
    start, goal = (1.0, 1.0), world.rooms["kitchen"].goal
    assert any_angle_m(grid, radius, start, goal, 0.25) == pytest.approx(any_angle_m(grid, radius, start, goal) - 0.25)
    assert any_angle_m(grid, radius, goal, goal, 0.25) == 0.0


@pytest.mark.parametrize(("name", "seed"), [("office", 0), ("office", 1), ("maze", 2), ("field", 0), ("field", 1)])
def test_every_box_lengthens_the_shortest_way(name, seed):
    # Field seeds 0 and 1 were among the runs whose boxes were off the way before (issue 41).
    plain, goals, _ = trial_world(Trial(name, "astar", seed, 100, {"task": "random"}))
    boxed, goals_boxed, known = trial_world(Trial(name, "astar", seed, 100, {"task": "random", "obstacles": 2}))
    assert goals == goals_boxed and np.array_equal(known.data, plain.grid.data)
    robot = boxed.robots[0]
    goal = boxed.rooms[goals[robot.id]].goal
    before = any_angle_m(plain.grid, robot.radius, robot.start[:2], goal)
    after = any_angle_m(boxed.grid, robot.radius, robot.start[:2], goal)
    assert after >= before + 2 * 0.02  # two boxes, each at least 2 cm (MIN_DETOUR_M)
    added = (boxed.grid.data == 100) & (plain.grid.data != 100)
    side = round(0.5 / boxed.grid.resolution)  # two boxes of 0.5 m (a box may overlap a wall or the other)
    assert side * side < added.sum() <= 2 * side * side
    assert math.isfinite(shortest_m(boxed.grid, robot.radius, robot.start[:2], goal))  # the planners' way is open
    # On the 8-connected grid the way is no shorter, but may be no longer either: its many ways of equal length are
    # why the old yardstick did not see the boxes.
    field_before = DistanceField(plain.grid.inflate(robot.radius), plain.grid.world_to_cell(*goal))
    field_after = DistanceField(boxed.grid.inflate(robot.radius), boxed.grid.world_to_cell(*goal))
    cell = plain.grid.world_to_cell(*robot.start[:2])
    assert field_after.to(cell) >= field_before.to(cell)
