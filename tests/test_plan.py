"""Path planning from Python: vwg.plan.astar, vwg.plan.DStarLite, vwg.plan.plan_ompl / vwg.plan.OmplPlanner.

Expected lengths come from hand computation or from the MovingAI benchmark files (published
optimal lengths), never from running the planners."""

from __future__ import annotations

import itertools
import math
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import vwg

SQRT2 = math.sqrt(2.0)
MOVINGAI = Path(__file__).resolve().parent / "data" / "movingai"
# Mazes and city blocks made by benchmarks/heldout_maps.py, their optimal lengths from SciPy's Dijkstra.
HELDOUT = Path(__file__).resolve().parent / "data" / "heldout"


def grid(*rows: str) -> np.ndarray:
    """A mask from rows of text: '#' blocked. Row 0 is the first string."""
    return np.array([[ch == "#" for ch in row] for row in rows], dtype=bool)


def read_map(name: str, folder: Path = MOVINGAI) -> np.ndarray:
    lines = (folder / f"{name}.map").read_text().splitlines()
    height, width = int(lines[1].split()[1]), int(lines[2].split()[1])
    rows = lines[4:4 + height]
    assert all(len(r) == width for r in rows)
    return np.array([[ch not in ".GS" for ch in r] for r in rows], dtype=bool)


def read_scenarios(name: str, folder: Path = MOVINGAI) -> list[tuple[tuple[int, int], tuple[int, int], float]]:
    out = []
    for line in (folder / f"{name}.map.scen").read_text().splitlines()[1:]:
        f = line.split()
        if f:
            sx, sy, gx, gy = (int(v) for v in f[4:8])
            out.append(((sy, sx), (gy, gx), float(f[8])))  # x is the column, y the row from the top
    return out


def check_legal(blocked, path, start, goal, corner_cutting=False, diagonal=True) -> float:
    """Assert `path` is a legal walk from start to goal; return the sum of its move costs."""
    assert path[0] == tuple(start) and path[-1] == tuple(goal)
    total = 0.0
    for (r0, c0), (r1, c1) in itertools.pairwise(path):
        assert not blocked[r1, c1]
        dr, dc = r1 - r0, c1 - c0
        assert max(abs(dr), abs(dc)) == 1
        if dr and dc:
            assert diagonal
            if not corner_cutting:
                assert not blocked[r0 + dr, c0] and not blocked[r0, c0 + dc]
            total += SQRT2
        else:
            total += 1.0
    return total


# ---- A* --------------------------------------------------------------------------------------------
WALL = grid(".....", ".....", "####.", ".....", ".....")


def test_astar_wall_with_one_gap():
    # Through (2, 4) only, entered from (1, 4) and left to (3, 4) straight (the diagonals would cut
    # the wall's end): (3 + √2) + 2 + (3 + √2).
    path, length = vwg.plan.astar(WALL, (0, 0), (4, 0))
    assert length == pytest.approx(8 + 2 * SQRT2, abs=1e-12)
    assert isinstance(path, list) and all(isinstance(c, tuple) and len(c) == 2 for c in path)
    assert check_legal(WALL, path, (0, 0), (4, 0)) == pytest.approx(length, abs=1e-9)
    # Cutting corners: (0,0)→(1,3)→(2,4) is 2 + 2√2, and as much again down to (4, 0).
    path, length = vwg.plan.astar(WALL, (0, 0), (4, 0), corner_cutting=True)
    assert length == pytest.approx(4 + 4 * SQRT2, abs=1e-12)
    check_legal(WALL, path, (0, 0), (4, 0), corner_cutting=True)
    # 4-connected: 6 + 6.
    path, length = vwg.plan.astar(WALL, (0, 0), (4, 0), diagonal=False, heuristic="manhattan")
    assert length == pytest.approx(12.0)
    check_legal(WALL, path, (0, 0), (4, 0), diagonal=False)
    for h in ("euclidean", "octile", "zero"):
        assert vwg.plan.astar(WALL, (0, 0), (4, 0), heuristic=h)[1] == pytest.approx(8 + 2 * SQRT2, abs=1e-12)


def test_astar_does_not_cut_corners():
    blocked = grid(".#", "..")
    assert vwg.plan.astar(blocked, (0, 0), (1, 1)) == ([(0, 0), (1, 0), (1, 1)], 2.0)
    path, length = vwg.plan.astar(blocked, (0, 0), (1, 1), corner_cutting=True)
    assert path == [(0, 0), (1, 1)] and length == pytest.approx(SQRT2)


def test_astar_no_path_is_none_and_inf():
    assert vwg.plan.astar(grid(".#.", ".#.", ".#."), (0, 0), (2, 2)) == (None, math.inf)
    assert vwg.plan.astar(grid(".#", "#."), (0, 0), (1, 1)) == (None, math.inf)  # only a cut corner joins them
    assert vwg.plan.astar(grid(".#.", "...", "..."), (0, 0), (0, 1)) == (None, math.inf)  # blocked goal


def test_astar_start_is_goal():
    assert vwg.plan.astar(np.zeros((3, 3), bool), (1, 2), (1, 2)) == ([(1, 2)], 0.0)


def test_astar_accepts_lists_numpy_integers_and_strided_masks():
    blocked = WALL[::-1]  # a view with a negative stride: rows reversed
    path, length = vwg.plan.astar(blocked, [np.int64(4), 0], np.array([0, 0]))
    assert length == pytest.approx(8 + 2 * SQRT2, abs=1e-12)
    assert path[0] == (4, 0) and path[-1] == (0, 0)
    check_legal(blocked, path, (4, 0), (0, 0))


@pytest.mark.parametrize("name", ["arena", "den312d"])
@pytest.mark.parametrize("heuristic", ["octile", "euclidean"])
def test_astar_movingai_every_scenario_of_the_small_maps(name, heuristic):
    blocked = read_map(name)
    for i, (start, goal, optimal) in enumerate(read_scenarios(name)):
        path, length = vwg.plan.astar(blocked, start, goal, heuristic=heuristic)
        assert length == pytest.approx(optimal, rel=1e-4, abs=1e-4), (name, i)
        if i % 10 == 0:
            assert check_legal(blocked, path, start, goal) == pytest.approx(length, abs=1e-9)


@pytest.mark.parametrize("name", ["8room_000", "random512-10-0"])
def test_astar_movingai_512_maps_sampled(name):
    # Every scenario of these maps is checked by the C++ tests; here one in 20, both heuristics.
    blocked = read_map(name)
    for start, goal, optimal in read_scenarios(name)[::20]:
        for heuristic in ("octile", "euclidean"):
            _, length = vwg.plan.astar(blocked, start, goal, heuristic=heuristic)
            assert length == pytest.approx(optimal, rel=1e-4, abs=1e-4)


@pytest.mark.parametrize("name", ["maze-c2", "maze-c8", "city-a", "city-b"])
def test_planners_match_dijkstra_on_the_held_out_mazes_and_city_blocks(name):
    # 150 queries a map, the optima from SciPy's Dijkstra on the same graph (8 decimals in the file).
    blocked = read_map(name, HELDOUT)
    for i, (start, goal, optimal) in enumerate(read_scenarios(name, HELDOUT)):
        path, length = vwg.plan.astar(blocked, start, goal)
        assert length == pytest.approx(optimal, abs=1e-6), (name, i)
        assert vwg.plan.jps(blocked, start, goal)[1] == pytest.approx(optimal, abs=1e-6), (name, i)
        if i % 15 == 0:
            assert check_legal(blocked, path, start, goal) == pytest.approx(length, abs=1e-9)


@pytest.mark.parametrize("name", ["arena", "den312d", "8room_000"])
def test_jps_finds_the_published_optimal_lengths(name):
    # Every scenario of the small maps, one in 10 of the 512 × 512 one (the C++ tests take them all).
    blocked = read_map(name)
    scenarios = read_scenarios(name)
    for i, (start, goal, optimal) in enumerate(scenarios[::10] if len(scenarios) > 1000 else scenarios):
        path, length = vwg.plan.jps(blocked, start, goal)
        assert length == pytest.approx(optimal, rel=1e-4, abs=1e-4), (name, i)
        if i % 10 == 0:
            assert check_legal(blocked, path, start, goal) == pytest.approx(length, abs=1e-9)


def test_jps_no_path_start_is_goal_and_bad_input():
    blocked = np.zeros((3, 3), dtype=bool)
    blocked[:, 1] = True
    assert vwg.plan.jps(blocked, (0, 0), (2, 2)) == (None, math.inf)
    assert vwg.plan.jps(blocked, (0, 0), (0, 0)) == ([(0, 0)], 0.0)
    with pytest.raises(vwg.SchemaError, match="start"):
        vwg.plan.jps(blocked, (0, 1), (2, 2))
    with pytest.raises(vwg.SchemaError, match="goal"):
        vwg.plan.jps(blocked, (0, 0), (5, 2))


def test_astar_row_order_does_not_matter():
    blocked = read_map("den312d")
    h = blocked.shape[0]
    for start, goal, optimal in read_scenarios("den312d")[::40]:
        flipped = ((h - 1 - start[0], start[1]), (h - 1 - goal[0], goal[1]))
        assert vwg.plan.astar(blocked[::-1].copy(), *flipped)[1] == pytest.approx(optimal, rel=1e-4, abs=1e-4)


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: vwg.plan.astar(WALL, (-1, 0), (4, 0)), "start"),
        (lambda: vwg.plan.astar(WALL, (0, 5), (4, 0)), "start"),
        (lambda: vwg.plan.astar(WALL, (2, 0), (4, 0)), "start"),  # blocked
        (lambda: vwg.plan.astar(WALL, (0, 0), (5, 0)), "goal"),
        (lambda: vwg.plan.astar(WALL, (0,), (4, 0)), "start"),
        (lambda: vwg.plan.astar(WALL, (0.5, 0), (4, 0)), "start"),
        (lambda: vwg.plan.astar(WALL, "ab", (4, 0)), "start"),
        (lambda: vwg.plan.astar(WALL.astype(np.uint8), (0, 0), (4, 0)), "blocked"),
        (lambda: vwg.plan.astar(WALL.astype(float), (0, 0), (4, 0)), "blocked"),
        (lambda: vwg.plan.astar(WALL[0], (0, 0), (4, 0)), "blocked"),
        (lambda: vwg.plan.astar(WALL[None], (0, 0), (4, 0)), "blocked"),
        (lambda: vwg.plan.astar(WALL.tolist(), (0, 0), (4, 0)), "blocked"),
        (lambda: vwg.plan.astar(WALL, (0, 0), (4, 0), heuristic="chebyshev"), "heuristic"),
        (lambda: vwg.plan.astar(WALL, (0, 0), (4, 0), heuristic="manhattan"), "heuristic"),  # 8-connected
    ],
)
def test_astar_bad_input_is_a_schema_error_naming_the_argument(call, field):
    with pytest.raises(vwg.SchemaError) as info:
        call()
    assert info.value.field == field
    assert str(info.value).startswith(field + ": ")


def test_astar_error_messages_say_what_is_wrong():
    with pytest.raises(vwg.SchemaError, match=r"start: cell \(row 2, col 0\) is blocked"):
        vwg.plan.astar(WALL, (2, 0), (4, 0))
    with pytest.raises(vwg.SchemaError, match="outside the grid of 5 rows × 5 columns"):
        vwg.plan.astar(WALL, (0, 0), (9, 0))
    with pytest.raises(vwg.SchemaError, match="dtype bool"):
        vwg.plan.astar(WALL.astype(np.uint8), (0, 0), (4, 0))


def test_astar_releases_the_gil_and_is_thread_safe():
    # Dijkstra over a 1024 × 1024 grid towards a walled-in goal (tens of milliseconds each): the
    # main thread must get to run while a search is inside C++.
    blocked = np.zeros((1024, 1024), bool)
    blocked[900:1011, 900] = blocked[900:1011, 1010] = blocked[900, 900:1011] = blocked[1010, 900:1011] = True
    windows = []

    def work():
        for _ in range(5):
            begin = time.perf_counter()
            result = vwg.plan.astar(blocked, (0, 0), (1000, 1000), heuristic="zero")
            windows.append((begin, time.perf_counter(), result))

    worker = threading.Thread(target=work)
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    assert all(result == (None, math.inf) for _, _, result in windows)
    # Margins: a thread switch may fall between taking the time and entering the search.
    inside = [t for t in ticks for begin, end, _ in windows if begin + 0.006 < t < end - 0.002]
    assert inside, "the main thread never ran while a search was running"

    # Concurrent searches (one work area per thread) give the single-threaded answers.
    maze = read_map("den312d")
    cases = read_scenarios("den312d")[::10]
    expected = [optimal for _, _, optimal in cases]
    results: dict[int, list[float]] = {}

    def run(k):
        results[k] = [vwg.plan.astar(maze, s, g, heuristic="octile")[1] for s, g, _ in cases]

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k in range(4):
        assert results[k] == pytest.approx(expected, rel=1e-4, abs=1e-4)


# ---- D* Lite ---------------------------------------------------------------------------------------
def test_dstar_lite_hand_worked():
    # 3 × 5 open, start (1, 0), goal (1, 4): 4. Block (1, 2): over it by (0, 1), (0, 2), (0, 3),
    # diagonals only where no corner of (1, 2) is cut: √2 + 1 + 1 + √2.
    planner = vwg.plan.DStarLite(np.zeros((3, 5), bool), (1, 0), (1, 4))
    path, length = planner.path()
    assert path == [(1, 0), (1, 1), (1, 2), (1, 3), (1, 4)] and length == 4.0
    planner.update_cells([(1, 2)], True)
    path, length = planner.path()
    assert length == pytest.approx(2 + 2 * SQRT2)
    assert path == [(1, 0), (0, 1), (0, 2), (0, 3), (1, 4)] or path == [(1, 0), (2, 1), (2, 2), (2, 3), (1, 4)]
    planner.update_cells(np.array([[0, 2], [2, 2]]), True)  # the whole column
    assert planner.path() == (None, math.inf)
    planner.update_cells([(2, 2)], blocked=False)
    planner.move_to((1, 1))
    # From (1, 1): (2, 1), (2, 2), (2, 3) straight (the diagonal to (2, 2) would cut (1, 2)), then √2.
    path, length = planner.path()
    assert length == pytest.approx(3 + SQRT2)
    assert path[0] == (1, 1) and path[-1] == (1, 4)
    assert planner.start == (1, 1) and planner.goal == (1, 4)
    assert planner.expanded > 0


def test_dstar_lite_equals_astar_after_random_changes():
    rng = np.random.default_rng(7)
    for trial in range(30):
        rows, cols = rng.integers(8, 40, size=2)
        blocked = rng.random((rows, cols)) < 0.2
        start = (int(rng.integers(rows)), int(rng.integers(cols)))
        goal = (int(rng.integers(rows)), int(rng.integers(cols)))
        blocked[start] = False
        options = {"heuristic": "octile" if trial % 2 else "euclidean", "corner_cutting": trial % 3 == 0}
        planner = vwg.plan.DStarLite(blocked, start, goal, **options)
        for _ in range(15):
            path, length = planner.path()
            _, expected = vwg.plan.astar(blocked, planner.start, goal, **options)
            assert length == pytest.approx(expected, rel=1e-9) or length == expected == math.inf
            if path and len(path) > 2 and rng.random() < 0.5:
                planner.move_to(path[1])
            picked = zip(rng.integers(rows, size=4), rng.integers(cols, size=4), strict=True)
            cells = [(int(r), int(c)) for r, c in picked if (int(r), int(c)) != planner.start]
            value = bool(rng.random() < 0.7)
            planner.update_cells(cells, value)
            for cell in cells:
                blocked[cell] = value


def test_dstar_lite_bad_input():
    blocked = grid(".#.", "...", "...")
    with pytest.raises(vwg.SchemaError) as info:
        vwg.plan.DStarLite(blocked, (0, 1), (2, 2))
    assert info.value.field == "start"
    with pytest.raises(vwg.SchemaError) as info:
        vwg.plan.DStarLite(blocked.astype(np.int8), (0, 0), (2, 2))
    assert info.value.field == "blocked"
    planner = vwg.plan.DStarLite(blocked, (0, 0), (2, 2))
    for call, field in ((lambda: planner.move_to((0, 1)), "cell"),
                        (lambda: planner.move_to((7, 0)), "cell"),
                        (lambda: planner.update_cells([(1, 1), (3, 3)], True), "cells"),
                        (lambda: planner.update_cells([(1,)], True), "cells"),
                        (lambda: planner.update_cells(5, True), "cells")):
        with pytest.raises(vwg.SchemaError) as info:
            call()
        assert info.value.field == field
    assert planner.path()[1] == pytest.approx(2 + SQRT2)  # nothing changed


# ---- OMPL ------------------------------------------------------------------------------------------
RESOLUTION = 0.1
ORIGIN = (-1.0, 2.0, 0.3)  # rotated, to exercise the world frame
RADIUS = 0.15


@pytest.fixture(scope="module")
def arena():
    """The arena map with row 0 at the bottom, and its planner."""
    blocked = read_map("arena")[::-1].copy()
    return blocked, vwg.plan.OmplPlanner(blocked, RESOLUTION, ORIGIN, RADIUS)


def to_world(u, v, origin=ORIGIN, resolution=RESOLUTION):
    ox, oy, yaw = origin
    c, s = math.cos(yaw), math.sin(yaw)
    return ox + (c * u - s * v) * resolution, oy + (s * u + c * v) * resolution


def to_grid(x, y, origin=ORIGIN, resolution=RESOLUTION):
    ox, oy, yaw = origin
    c, s = math.cos(yaw), math.sin(yaw)
    dx, dy = x - ox, y - oy
    return (c * dx + s * dy) / resolution, (-s * dx + c * dy) / resolution


def distance_to_obstacles(blocked, u, v):
    """Distance (cells) from (u, v) to the nearest blocked square or the map's edge: brute force."""
    rows, cols = np.nonzero(blocked)
    du = np.maximum(np.maximum(cols - u, 0.0), u - (cols + 1))
    dv = np.maximum(np.maximum(rows - v, 0.0), v - (rows + 1))
    edge = min(u, blocked.shape[1] - u, v, blocked.shape[0] - v)
    return min(float(np.hypot(du, dv).min()) if rows.size else math.inf, edge)


def assert_path_clear(blocked, waypoints, radius_cells, step=0.02):
    """Every point along every segment, every `step` cells, keeps more than the radius from obstacles."""
    for (x0, y0, _), (x1, y1, _) in itertools.pairwise(waypoints):
        u0, v0 = to_grid(x0, y0)
        u1, v1 = to_grid(x1, y1)
        n = max(1, math.ceil(math.hypot(u1 - u0, v1 - v0) / step))
        for t in np.linspace(0.0, 1.0, n + 1):
            d = distance_to_obstacles(blocked, u0 + t * (u1 - u0), v0 + t * (v1 - v0))
            assert d > radius_cells - 1e-9, (x0, y0, x1, y1, t, d)


def free_poses(blocked, planner, count, seed):
    """Cell centres where the robot fits, picked at random."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        r, c = int(rng.integers(blocked.shape[0])), int(rng.integers(blocked.shape[1]))
        x, y = to_world(c + 0.5, r + 0.5)
        if distance_to_obstacles(blocked, c + 0.5, r + 0.5) > RADIUS / RESOLUTION + 0.3:
            assert planner.valid(x, y)
            out.append((x, y, float(rng.uniform(-math.pi, math.pi))))
    return out


@pytest.mark.parametrize("name", ["RRTConnect", "RRTstar", "PRM"])
def test_ompl_paths_reach_the_goal_and_never_touch_an_obstacle(arena, name):
    blocked, planner = arena
    poses = free_poses(blocked, planner, 6, seed=1)
    for start, goal in zip(poses[::2], poses[1::2], strict=True):
        plan = planner.plan(start, goal, planner=name, time_limit=0.3, seed=5)
        assert plan.solved and plan.status == "exact solution" and bool(plan)
        w = plan.waypoints
        assert w.shape[1] == 3 and w.dtype == np.float64
        assert w[0, :2] == pytest.approx(start[:2], abs=1e-9)
        assert w[-1, :2] == pytest.approx(goal[:2], abs=1e-9)
        assert math.remainder(w[-1, 2] - goal[2], 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
        steps = np.hypot(*np.diff(w[:, :2], axis=0).T)
        assert plan.length == pytest.approx(steps.sum(), rel=1e-9)
        assert steps.max() <= RESOLUTION + 1e-9  # spacing defaults to one cell
        # Never shorter than the straight line.
        assert plan.length >= math.hypot(goal[0] - start[0], goal[1] - start[1]) - 1e-9
        assert_path_clear(blocked, w, RADIUS / RESOLUTION)


def test_ompl_same_seed_same_path(arena):
    blocked, planner = arena
    # Two poses that do not see each other, so that the simplified path depends on the samples.
    seed = 2
    while True:
        start, goal = free_poses(blocked, planner, 2, seed=seed)
        if not planner.motion_valid(start[0], start[1], goal[0], goal[1]):
            break
        seed += 1
    first = planner.plan(start, goal, seed=11)
    again = planner.plan(start, goal, seed=11)
    other = planner.plan(start, goal, seed=12)
    assert first.solved and again.solved and other.solved
    np.testing.assert_array_equal(first.waypoints, again.waypoints)
    assert not np.array_equal(first.waypoints, other.waypoints)
    # RRT* with an iteration budget (the time limit never reached) repeats too.
    a = planner.plan(start, goal, planner="RRTstar", time_limit=30.0, seed=3, iterations=300)
    b = planner.plan(start, goal, planner="RRTstar", time_limit=30.0, seed=3, iterations=300)
    assert a.solved
    np.testing.assert_array_equal(a.waypoints, b.waypoints)
    # The module-level function plans the same as a reused planner.
    c = vwg.plan.plan_ompl(blocked, RESOLUTION, ORIGIN, start, goal, RADIUS, seed=11)
    np.testing.assert_array_equal(first.waypoints, c.waypoints)


def test_ompl_failures_are_clear_results(arena):
    blocked, planner = arena
    start = free_poses(blocked, planner, 1, seed=3)[0]
    # A goal inside a wall, and one off the map.
    r, c = map(int, np.argwhere(blocked)[len(np.argwhere(blocked)) // 2])
    for goal in ((*to_world(c + 0.5, r + 0.5), 0.0), (1e3, 1e3, 0.0)):
        plan = planner.plan(start, goal)
        assert not plan.solved and not plan
        assert plan.status.startswith("invalid goal")
        assert plan.waypoints.shape == (0, 3)
        assert plan.length == math.inf
    # A goal enclosed by walls: no path in the time given.
    boxed = np.zeros((40, 40), bool)
    boxed[20:31, 20] = boxed[20:31, 30] = boxed[20, 20:31] = boxed[30, 20:31] = True
    plan = vwg.plan.plan_ompl(boxed, 0.1, (0.0, 0.0), (0.5, 0.5), (2.5, 2.5), 0.05, time_limit=0.2)
    # (RRTConnect reports the state nearest the goal as an approximate solution: still no path.)
    assert not plan.solved and plan.status in ("timeout", "approximate solution")
    assert plan.length == math.inf and plan.waypoints.shape == (0, 3)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"start_pose": (0.0, 0.0, 0.0)}, "start_pose"),  # off the map (origin is outside the arena's free space)
        ({"planner": "RRTsharper"}, "planner"),
        ({"time_limit": 0.0}, "time_limit"),
        ({"time_limit": "1"}, "time_limit"),
        ({"robot_radius": -1.0}, "robot_radius"),
        ({"resolution": 0.0}, "resolution"),
        ({"blocked": np.zeros((5, 5), np.uint8)}, "blocked"),
        ({"goal_pose": (1.0,)}, "goal_pose"),
        ({"origin": "here"}, "origin"),
        ({"seed": -1}, "seed"),
    ],
)
def test_ompl_bad_input_is_a_schema_error(arena, kwargs, field):
    blocked, planner = arena
    start, goal = free_poses(blocked, planner, 2, seed=4)
    args = {"blocked": blocked, "resolution": RESOLUTION, "origin": ORIGIN, "start_pose": start,
            "goal_pose": goal, "robot_radius": RADIUS}
    args.update(kwargs)
    with pytest.raises(vwg.SchemaError) as info:
        vwg.plan.plan_ompl(**args)
    assert info.value.field == field


def test_ompl_start_in_collision_is_a_schema_error(arena):
    blocked, planner = arena
    r, c = map(int, np.argwhere(blocked)[len(np.argwhere(blocked)) // 2])
    goal = free_poses(blocked, planner, 1, seed=5)[0]
    with pytest.raises(vwg.SchemaError, match=r"start_pose: the robot .* does not fit"):
        planner.plan(to_world(c + 0.5, r + 0.5), goal)


def test_ompl_planner_names():
    names = vwg.plan.OmplPlanner.planners()
    for name in ("RRTConnect", "RRT", "RRTstar", "PRM", "PRMstar", "KPIECE1", "BITstar"):
        assert name in names
