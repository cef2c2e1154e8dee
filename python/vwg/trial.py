"""One run of a robot world from a plain configuration: a sweep's cell (vwg.sweep) and an experiment's
unit (vwg.experiments). A Trial is plain data (strings, numbers, lists), so it travels to a Dask worker
as it is and the worker builds its own engine from it; the same Trial gives the same row anywhere
(every column but the timings).

    row = run_trial(Trial(world="office", planner="astar", seed=3, frames=600,
                          params={"task": "random", "robots": 2, "sensors": ["laser"]}))

Parameters (``params``; all optional):

- ``task``: ``world`` (default) runs the world file's robots and orders; ``random`` puts the robots at
  free places drawn from the seed and sends each to a room drawn from the seed (one it can reach).
- ``robots``: how many robots: the world file's first N, or with ``task: random`` N new ones.
- ``sensors``: the sensors every robot carries (``[laser]``, ``[kinect]``, ``[laser, kinect]``, ...).
- ``odometry_noise``, ``motor_noise``: the simulator's noise (vwg.robot.platforms.sim.NoiseModel's fields).
- ``knows_map``: false starts the robots with empty maps (they learn the walls with their sensors).
- ``obstacles``: boxes (0.5 m) put on the first robot's shortest way after the map was drawn: the
  robots start with the map without them and find them with their sensors (the world changed).
- ``localization``: ``odometry`` (the world file's default) or ``particles`` (Monte Carlo localization on
  the laser and the known map: vwg.robot.LocalizationSettings).
- ``avoidance``: ``none`` (the world file's default) or ``orca`` (every robot avoids the robots and people its
  laser sees: vwg.robot.AvoidanceSettings).
- ``people``: that many people who walk, added to the world's: each at a free place drawn from the seed (after the
  boxes, away from the robots), wandering between all the rooms (vwg.robot.world_file.Person).

The row: ``world, planner, seed, frames_limit, params`` (the cell), then ``reached`` (every ordered robot
reached its room), ``frames``, ``path_length_m`` (driven, all robots), ``optimal_m`` (the sum of the
ordered robots' shortest any-angle ways from start to within the goal tolerance of the room, by vwg.trial.any_angle_m;
empty when a robot has several orders), ``optimal_unchanged_m`` (the same on the map the robots were given, before
any boxes were put down), ``collisions``, ``replans``, ``robots``, ``reached_robots``, ``planning_s`` (the decider's
search time, where it counts it), ``map_precision`` and ``map_recall`` (with ``knows_map: false``: how
the maps the robots made agree with the true one, vwg.robot.map_quality), ``pose_error_m`` (the robots' mean
distance from where they believe they are to where they are, at the end), ``run_s`` (the frames' time),
``wall_s`` (the whole cell's, set-up included) and ``error`` (a failed frame's message; empty if none).
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import json
import math
import time
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vwg._core import NoiseModel, RobotSettings
from vwg.errors import Error, FrameError, SchemaError
from vwg.io.maps import OccupancyGrid
from vwg.io.shipped import resolve_world
from vwg.plugins import sensors
from vwg.robot.any_angle import AnyAngle
from vwg.robot.case_study import CaseStudy
from vwg.robot.map_quality import map_quality
from vwg.robot.shortest import DistanceField, grid_graph
from vwg.robot.world_file import Avoidance, Localization, Person, load_robot_world

__all__ = ["COLUMNS", "KNOWN_PARAMS", "Trial", "add_people", "any_angle_m", "any_angle_way", "cached_world",
           "random_task", "replace_robot", "run_trial", "shortest_m", "trial_world"]

#: The columns of a trial's row, in order (the first five name the cell).
COLUMNS = ("world", "planner", "seed", "frames_limit", "params", "reached", "frames", "path_length_m", "optimal_m",
           "optimal_unchanged_m", "collisions", "replans", "robots", "reached_robots", "planning_s", "map_precision",
           "map_recall", "pose_error_m", "run_s", "wall_s", "error")

#: Parameter -> (accepted types, meaning).
KNOWN_PARAMS: dict[str, tuple[tuple[type, ...], str]] = {
    "task": ((str,), "world (the file's robots and orders) or random (seeded starts and rooms)"),
    "robots": ((int,), "number of robots"),
    "sensors": ((list,), "the sensors every robot carries"),
    "odometry_noise": ((int, float), "odometry drift per metre and per radian"),
    "motor_noise": ((int, float), "relative noise of each commanded motion"),
    "knows_map": ((bool,), "whether the robots start with the map"),
    "obstacles": ((int,), "boxes added on the first robot's way, not on its map"),
    "localization": ((str,), "where the robots believe they are: odometry or particles"),
    "avoidance": ((str,), "how the robots pass each other: none or orca"),
    "people": ((int,), "people who walk, added at seeded places and wandering between the rooms"),
}

FLOAT_PARAMS = ("odometry_noise", "motor_noise")
BOX_M = 0.5  # the side of an added obstacle
SPACING_M = 0.6  # the least distance between two random starts
CANDIDATES = 4  # points of the way tried for each box (each also with the box moved to either side)
ROUNDS = 4  # rounds of CANDIDATES points at most
MIN_DETOUR_M = 0.02  # how much longer the first box must make the shortest way (above what sight tests may graze)


@dataclass(frozen=True)
class Trial:
    """One run: a world (a file or a shipped world's name), a planner, a seed, a frame limit, parameters."""

    world: str
    planner: str
    seed: int
    frames: int
    params: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        check_params(self.params, "params")
        # 0 and 0.0 name one cell: the noise levels are numbers, whichever way they were written.
        normal = {k: float(v) if k in FLOAT_PARAMS else v for k, v in self.params.items()}
        object.__setattr__(self, "params", normal)
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or not 0 <= self.seed < 2**63:
            raise SchemaError(f"seed: expected an integer from 0 to 2**63 - 1, got {self.seed!r}")
        if isinstance(self.frames, bool) or not isinstance(self.frames, int) or not 1 <= self.frames <= 10_000_000:
            raise SchemaError(f"frames: expected an integer from 1 to 10000000, got {self.frames!r}")

    def __hash__(self) -> int:
        return hash(self.key)

    @property
    def params_text(self) -> str:
        """The parameters as canonical JSON (sorted keys): the cell's name for them in a CSV."""
        return json.dumps(self.params, sort_keys=True, separators=(",", ":"))

    @property
    def key(self) -> tuple[str, str, str, str, str]:
        """What names the cell in a results file (the row's first five columns, as text)."""
        return (self.world, self.planner, str(self.seed), str(self.frames), self.params_text)


def check_params(params: dict[str, Any], where: str) -> None:
    """Refuse unknown parameters and values of the wrong kind, naming them (`where` says whose)."""
    for name, value in params.items():
        if name not in KNOWN_PARAMS:
            raise SchemaError(f"{where}.{name}: unknown parameter (known: {', '.join(KNOWN_PARAMS)})")
        kinds, meaning = KNOWN_PARAMS[name]
        if (isinstance(value, bool) and bool not in kinds) or not isinstance(value, kinds):
            raise SchemaError(f"{where}.{name}: expected {meaning} ({' or '.join(k.__name__ for k in kinds)}), "
                              f"got {value!r}")
    task = params.get("task", "world")
    if task not in ("world", "random"):
        raise SchemaError(f"{where}.task: expected world or random, got {task!r}")
    for name, kind in (("localization", Localization), ("avoidance", Avoidance)):
        if name in params:
            try:
                kind.of(params[name])
            except SchemaError as e:
                raise SchemaError(f"{where}.{e}") from None
    if "people" in params and not 0 <= params["people"] <= 1000:
        raise SchemaError(f"{where}.people: expected 0 to 1000, got {params['people']!r}")
    for name in ("robots", "obstacles"):
        if name in params and not 0 <= params[name] <= 100_000:
            raise SchemaError(f"{where}.{name}: expected 0 to 100000, got {params[name]!r}")
    if params.get("robots") == 0:
        raise SchemaError(f"{where}.robots: expected at least 1 robot")
    for name in ("odometry_noise", "motor_noise"):
        if name in params and not (math.isfinite(params[name]) and 0 <= params[name] <= 1):
            raise SchemaError(f"{where}.{name}: expected a number from 0 to 1, got {params[name]!r}")
    if "sensors" in params:

        if not params["sensors"]:
            raise SchemaError(f"{where}.sensors: expected at least one sensor")
        for s in params["sensors"]:
            if not isinstance(s, str):
                raise SchemaError(f"{where}.sensors: expected sensor names, got {s!r}")
            if s not in sensors:
                raise SchemaError(f"{where}.sensors: unknown sensor {s!r} (registered: {', '.join(sensors)})")


# ---- the world of a trial ------------------------------------------------------------------------------
@functools.lru_cache(maxsize=8)
def cached_world(path: str) -> Any:
    """The robot world of a file (or a shipped world's name), loaded once per process."""

    return load_robot_world(resolve_world(path))


_fields: OrderedDict[tuple[bytes, float, tuple[float, float], float], Any] = OrderedDict()
_graph: dict[tuple[bytes, float], Any] = {}


def _field(grid: Any, radius: float, goal: tuple[float, float], tolerance: float = 0.0) -> Any:
    """The distance field to `goal` (to within `tolerance` metres of it) on `grid` for a robot of
    `radius`, cached (the last 64): a sweep runs many cells on the same maps and rooms."""
    grid_key = _grid_key(grid)
    key = (grid_key, radius, goal, tolerance)
    if key in _fields:
        _fields.move_to_end(key)
        return _fields[key]
    blocked = grid.inflate(radius)
    graph = _graph.get((grid_key, radius))
    if graph is None:
        _graph.clear()  # one graph kept: they are large (Willow's has 11 M edges)
        graph = _graph[(grid_key, radius)] = grid_graph(blocked)
    field_ = _fields[key] = DistanceField(blocked, grid.world_to_cell(*goal), graph=graph,
                                          within=tolerance / grid.resolution)
    if len(_fields) > 64:
        _fields.popitem(last=False)
    return field_


def shortest_m(grid: Any, radius: float, start: tuple[float, float], goal: tuple[float, float],
               tolerance: float = 0.0) -> float:
    """The shortest way from `start` to `goal` (to within `tolerance` metres of it) in metres on `grid`
    for a robot of `radius` (inf: none)."""
    dist = _field(grid, radius, goal, tolerance).to(grid.world_to_cell(*start))
    return dist * grid.resolution


_yardsticks: OrderedDict[tuple[bytes, float], AnyAngle] = OrderedDict()


def _grid_key(grid: Any) -> bytes:
    import hashlib

    return hashlib.sha1(grid.data.tobytes() + repr((grid.resolution, grid.origin)).encode()).digest()


def _any_angle(grid: Any, radius: float) -> AnyAngle:
    """The any-angle yardstick of `grid` for a disc robot of `radius` (the last 4 kept): among the cells of its
    configuration space that the planners avoid (OccupancyGrid.inflate: centres within `radius` of a wall), so a
    doorway is open to it exactly when it is to them. The robot's centre can pass over such a cell's edge by up to
    half its diagonal without touching the wall, so a robot may drive a little less than the figure on a way with
    corners (experiments allow 2 %).
    """
    key = (_grid_key(grid), radius)
    if key in _yardsticks:
        _yardsticks.move_to_end(key)
        return _yardsticks[key]
    return _remember(grid, radius, AnyAngle(grid.inflate(radius)))


def _remember(grid: Any, radius: float, field_: AnyAngle) -> AnyAngle:
    """Keep `field_` as the yardstick of `grid` (one made by AnyAngle.with_blocked is the same as a new one)."""
    _yardsticks[(_grid_key(grid), radius)] = field_
    if len(_yardsticks) > 4:
        _yardsticks.popitem(last=False)
    return field_


def _map_point(grid: Any, x: float, y: float) -> tuple[float, float]:
    """World (x, y) as a point of the grid in cell units, (row, col), as AnyAngle takes it (the grid's own
    continuous coordinates, swapped)."""
    u, v = grid.world_to_grid(x, y)
    return v, u


def _world_points(grid: Any, way: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """An AnyAngle way's points (row, col) as world (x, y): _map_point's inverse."""
    return [grid.grid_to_world(c, r) for r, c in way]


def any_angle_m(grid: Any, radius: float, start: tuple[float, float], goal: tuple[float, float],
                tolerance: float = 0.0) -> float:
    """The shortest any-angle way in metres from `start` to within `tolerance` of `goal` on `grid` for a disc robot
    of `radius` (vwg.robot.any_angle; inf: none): the way to the goal less the tolerance. The robot counts as arrived
    anywhere within the tolerance; by the triangle inequality no such point is nearer than that (the goal's
    surroundings being open)."""
    cells = _any_angle(grid, radius).distance(_map_point(grid, *start), _map_point(grid, *goal))
    return max(0.0, cells * grid.resolution - tolerance)


def any_angle_way(grid: Any, radius: float, start: tuple[float, float],
                  goal: tuple[float, float]) -> list[tuple[float, float]]:
    """The points (world x, y) of that shortest way, from `start` to `goal` (empty: none)."""
    return _world_points(grid, _any_angle(grid, radius).path(_map_point(grid, *start), _map_point(grid, *goal)))


def trial_world(trial: Trial) -> tuple[Any, dict[int, str], Any]:
    """The robot world a trial runs (its robots, sensors and noise set by the parameters), the orders
    at the start (robot -> room; empty: the world file's), and the map the robots start with."""

    world = cached_world(trial.world)
    p = trial.params
    rng = np.random.default_rng(trial.seed)
    goals: dict[int, str] = {}
    if p.get("task", "world") == "random":
        world, goals = random_task(world, p.get("robots", 1), rng)
    elif "robots" in p:
        if p["robots"] > len(world.robots):
            raise SchemaError(f"params.robots: {trial.world} has {len(world.robots)} robots, {p['robots']} asked "
                              "(task: random places as many as asked)")
        kept = {r.id for r in world.robots[:p["robots"]]}
        world = dataclasses.replace(world, robots=world.robots[:p["robots"]],
                                    orders=[o for o in world.orders if o.robot in kept])
    if "sensors" in p:
        world = dataclasses.replace(world, robots=[replace_robot(r, sensors=tuple(p["sensors"])) for r in world.robots])
    if "odometry_noise" in p or "motor_noise" in p:
        noise = NoiseModel(odometry=float(p.get("odometry_noise", world.noise.odometry)),
                           motors=float(p.get("motor_noise", world.noise.motors)))
        world = dataclasses.replace(world, noise=noise)
    known = world.grid
    if p.get("obstacles", 0):
        world = _add_obstacles(world, goals, p["obstacles"], rng)
    if p.get("people", 0):
        world = add_people(world, p["people"], rng)
    return world, goals, known


def add_people(world: Any, n: int, rng: np.random.Generator) -> Any:
    """The world with `n` more people, each at a seeded free place SPACING_M from the robots and the other
    people from which it can walk to a room, wandering between the rooms it can walk to (a person walled off
    from its goal would look for a way there over the whole map at every step)."""
    grid = world.grid
    radius = Person.__dataclass_fields__["radius"].default
    free = np.argwhere(~grid.inflate(radius + 0.1))
    rooms = tuple(room.goal for room in world.rooms.values())
    if not rooms:
        raise SchemaError(f"params.people: {world.name} has no rooms to walk between")
    taken = [r.start[:2] for r in world.robots] + [p.start for p in world.people]
    people = list(world.people)
    for k in rng.permutation(len(free)):
        x, y = (float(v) for v in grid.cell_to_world(*free[k]))
        if any(math.hypot(x - a, y - b) < SPACING_M for a, b in taken):
            continue
        reachable = tuple(goal for goal in rooms if math.isfinite(shortest_m(grid, radius, (x, y), goal)))
        if len(reachable) < min(2, len(rooms)):
            continue
        taken.append((x, y))
        people.append(Person(len(people) + 1, (x, y), reachable, wander=True))
        if len(people) == len(world.people) + n:
            return dataclasses.replace(world, people=people)
    raise Error(f"{world.name}: room for {len(people) - len(world.people)} people {SPACING_M} m apart who can walk to "
                f"a room, {n} asked")


def replace_robot(robot: Any, **changes: Any) -> Any:
    """A robot's settings with these fields changed (vwg.robot.RobotSettings is immutable from Python)."""

    fields = {name: getattr(robot, name) for name, *_ in RobotSettings.fields()}
    return RobotSettings(**{**fields, **changes})


def random_task(world: Any, n: int, rng: np.random.Generator) -> tuple[Any, dict[int, str]]:
    """`n` robots at seeded free places SPACING_M apart, each sent to a seeded room it can reach: among those, one
    that the fewest robots are sent to already (rooms are dealt out evenly, as a dispatcher would; the seed
    orders the rooms, ties keep its order)."""
    grid = world.grid
    template = world.robots[0]
    radius = template.radius
    free = np.argwhere(~grid.inflate(radius + 0.1))
    rooms = list(world.rooms.values())
    robots: list[Any] = []
    goals: dict[int, str] = {}
    sent = {room.name: 0 for room in rooms}
    for k in rng.permutation(len(free)):
        x, y = grid.cell_to_world(*free[k])
        if any(math.hypot(x - r.start[0], y - r.start[1]) < SPACING_M for r in robots):
            continue
        # A room it can reach and is not in already (drawn in a seeded order).
        for j in sorted(rng.permutation(len(rooms)), key=lambda j: sent[rooms[j].name]):
            room = rooms[j]
            far = math.hypot(room.goal[0] - x, room.goal[1] - y) > 2 * world.goal_tolerance
            if far and math.isfinite(shortest_m(grid, radius, (x, y), room.goal)):
                rid = len(robots) + 1
                start = (float(x), float(y), float(rng.uniform(-math.pi, math.pi)))
                robots.append(replace_robot(template, id=rid, start=start))
                goals[rid] = room.name
                sent[room.name] += 1
                break
        if len(robots) == n:
            break
    if len(robots) < n:
        raise Error(f"{world.name}: room for {len(robots)} robots {SPACING_M} m apart that can reach a room, "
                    f"{n} asked")
    return dataclasses.replace(world, robots=robots, orders=[]), goals


def _add_obstacles(world: Any, goals: dict[int, str], count: int, rng: np.random.Generator) -> Any:
    """The world with `count` boxes on its first robot's shortest way to its room, put after the map was drawn.
    Each box goes at one of CANDIDATES seeded points of the middle of the way (any-angle, on the map with the boxes
    so far), clear of the start and the room: the one that lengthens the way most, where the planners' way stays
    open. The first must lengthen it by at least MIN_DETOUR_M (a box the robot need not go round is no change); the
    next ones then stand on the way that is left."""

    robot = world.robots[0]
    room = goals.get(robot.id) or next((o.room for o in world.orders if o.robot == robot.id), None)
    if room is None:
        raise SchemaError(f"params.obstacles: robot {robot.id} of {world.name} has no order to put boxes on the way of")
    goal = world.rooms[room].goal
    grid = world.grid
    data = grid.data.copy()
    half = max(1, round(BOX_M / grid.resolution / 2))
    start = robot.start[:2]
    # The box's corner reaches BOX_M/√2 from its centre; the robot must still fit at its start and arrive.
    keep_clear = BOX_M * math.sqrt(0.5) + robot.radius + 0.05
    placed = 0
    ends = (_map_point(grid, *start), _map_point(grid, *goal))
    for k in range(count):
        current = OccupancyGrid(data, grid.resolution, grid.origin)
        yardstick = _any_angle(current, robot.radius)
        before = yardstick.distance(*ends)
        way = _world_points(grid, yardstick.path(*ends))
        blocked = current.inflate(robot.radius)
        chosen = None
        for _ in range(ROUNDS):  # more places only when none of a round's would do: the same boxes otherwise
            # A few seeded points of the way's middle, the box centred on each or moved aside by up to half its side
            # (it still covers the way there); it goes where it lengthens the way most.
            tried = []
            for fraction in rng.uniform(0.2, 0.8, CANDIDATES):
                (x0, y0), (dx, dy) = _along(way, float(fraction))
                for aside in (0.0, -0.4 * BOX_M, 0.4 * BOX_M):
                    x, y = x0 - dy * aside, y0 + dx * aside
                    if math.hypot(x - start[0], y - start[1]) < keep_clear or \
                            math.hypot(x - goal[0], y - goal[1]) < keep_clear + world.goal_tolerance:
                        continue
                    r, c = current.world_to_cell(x, y)
                    boxed = data.copy()
                    boxed[max(0, r - half):r + half, max(0, c - half):c + half] = 100
                    boxed_grid = OccupancyGrid(boxed, grid.resolution, grid.origin)
                    changed = yardstick.with_blocked(boxed_grid.inflate(robot.radius) & ~blocked)
                    detour = (changed.distance(*ends) - before) * grid.resolution
                    tried.append((detour, float(fraction), aside, boxed_grid, changed))
            for detour, _, _, boxed_grid, changed in sorted(tried, key=lambda t: (-t[0], t[1], t[2])):
                # The first box must lengthen the way by MIN_DETOUR_M. A box often leaves two ways of about the same
                # length round it, so the next ones (on the way left, the best of their places) need not add as much.
                if k == 0 and detour < MIN_DETOUR_M:
                    break
                if math.isfinite(shortest_m(boxed_grid, robot.radius, start, goal)):  # the planners' way is open
                    chosen = boxed_grid
                    _remember(boxed_grid, robot.radius, changed)
                    break
            if chosen is not None:
                break
        if chosen is None:
            break
        data = chosen.data.copy()
        placed += 1
    if placed < count:
        raise Error(f"params.obstacles: room for {placed} of {count} boxes of {BOX_M} m on robot {robot.id}'s way "
                    f"to {room} in {world.name} (each must leave the way open, and the first make it "
                    f"{MIN_DETOUR_M} m longer)")
    return dataclasses.replace(world, grid=OccupancyGrid(data, grid.resolution, grid.origin))


def _along(way: list[tuple[float, float]], fraction: float) -> tuple[tuple[float, float], tuple[float, float]]:
    """The point at `fraction` of a polyline's length and the unit direction of the polyline there."""
    lengths = [math.dist(a, b) for a, b in itertools.pairwise(way)]
    left = fraction * sum(lengths)
    for (a, b), length in zip(itertools.pairwise(way), lengths, strict=True):
        if length > 0 and (left <= length or b == way[-1]):
            u = min(1.0, left / length)
            direction = ((b[0] - a[0]) / length, (b[1] - a[1]) / length)
            return (a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])), direction
        left -= length
    return way[-1], (1.0, 0.0)


# ---- running it ----------------------------------------------------------------------------------------
def run_trial(trial: Trial | dict[str, Any]) -> dict[str, Any]:
    """Run a trial (or its dict, as a Dask worker gets it) on one thread; its row (COLUMNS, a number
    that does not apply left empty). A trial that cannot be set up or whose frame fails gives a row
    with ``error`` set rather than an exception: a sweep goes on."""
    if isinstance(trial, dict):
        trial = Trial(**trial)
    row: dict[str, Any] = dict(zip(COLUMNS[:5], trial.key, strict=True))
    row["seed"], row["frames_limit"] = trial.seed, trial.frames
    start = time.perf_counter()
    try:
        row.update(_run(trial))
    except Error as e:  # the set-up failed (no room for the robots, a planner unknown on this world, ...)
        row.update({c: "" for c in COLUMNS[5:]}, reached=False, error=str(e))
    row["wall_s"] = round(time.perf_counter() - start, 3)
    return {k: "" if isinstance(v, float) and math.isnan(v) else v for k, v in row.items()}


def _run(trial: Trial) -> dict[str, Any]:

    world, goals, known = trial_world(trial)
    case = CaseStudy(world, trial.planner, goals=goals or None, seed=trial.seed, frames=trial.frames,
                     threads=1, knows_map=trial.params.get("knows_map", True), known_map=known,
                     localization=trial.params.get("localization"), avoidance=trial.params.get("avoidance"))
    error = ""
    try:
        try:
            summary = case.run()
        except FrameError as e:
            error = str(e)
            summary = case.summary()
        quality = (math.nan, math.nan)
        if not trial.params.get("knows_map", True):

            grids = [actor["grid"] for actor in case.robot_actors().values()]
            quality = map_quality(world.grid, grids, case.view.trajectories.values())
    finally:
        case.close()
    ordered = [r for r in summary.robots if r.room is not None]
    return dict(
        reached=summary.reached and not error, frames=summary.frames, path_length_m=round(summary.path_length_m, 6),
        optimal_m=_optimal(world, goals), optimal_unchanged_m=_optimal(dataclasses.replace(world, grid=known), goals),
        collisions=summary.collisions, replans=summary.replans,
        robots=len(summary.robots), reached_robots=sum(r.reached for r in ordered),
        planning_s=round(float(getattr(case.decider, "search_seconds", math.nan)), 6),
        map_precision=round(quality[0], 4), map_recall=round(quality[1], 4),
        pose_error_m=math.nan if summary.pose_error_m is None else round(summary.pose_error_m, 4),
        run_s=round(case.wall_time, 6),
        error=error)


def _optimal(world: Any, goals: dict[int, str]) -> float:
    """The sum of the ordered robots' shortest any-angle ways to their rooms, each to within the goal tolerance (where
    a robot counts as arrived); NaN when a robot has several orders, or none has one."""
    orders = dict(goals)
    if not orders:
        for o in world.orders:
            if o.robot in orders:
                return math.nan  # a second order: its way starts wherever the first one ended
            orders[o.robot] = o.room
    if not orders:
        return math.nan
    total = 0.0
    for rid, room in orders.items():
        robot = world.robot(rid)
        total += any_angle_m(world.grid, robot.radius, robot.start[:2], world.rooms[room].goal, world.goal_tolerance)
    return round(total, 6)
