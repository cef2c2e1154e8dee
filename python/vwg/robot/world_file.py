"""World files of the robot case study (paper §III): a map, rooms named by AprilTag markers on walls, robots,
their sensors, noise, and a timed script of user orders.

    name: office                       # [file stem]
    description: "..."                 # [""]
    map: office/map.yaml               # map_server YAML relative to this file, a MovingAI .map,
                                       # or {movingai: file.map, resolution: 0.1, origin: [0, 0, 0]}
    wall_height: 2.5                   # [2.5] metres, for 3D views and cameras
    rooms:                             # each room is named by a tag36h11 marker on a wall
      kitchen:
        marker: 3                      # tag id 0..586, unique across rooms
        at: [12.0, 4.3]                # x, y (m) of the marker's centre, on a wall face
        facing: 1.5708                 # direction the marker faces (outward normal of the wall), radians
        size: 0.3                      # [0.3] edge of the tag's outer black square, metres
        height: 0.6                    # [0.6] height of the marker centre above the floor (the camera is 0.5 m up)
        goal: [12.0, 3.3]              # [1 m in front of the marker] where a robot stands to have reached the room
    robots:
      - id: 1                          # int >= 1, unique
        start: [2.0, 3.0, 0.0]         # x, y (m), yaw (rad)
        radius: 0.18                   # [0.18] m
        max_speed: 0.5                 # [0.5] m/s
        max_turn_rate: 1.5             # [1.5] rad/s
        max_accel: 1.0                 # [1.0] m/s²
        max_turn_accel: 4.0            # [4.0] rad/s²
        sensors: [laser, camera]       # [[laser, camera]]; the registered sensors it carries (vwg plugins)
    sensors:                           # [{}] each sensor's settings, by its registered name
      laser: {beams: 360, fov: 6.283185307179586, min_range: 0.05, max_range: 8.0, noise: 0.01}
      kinect: {width: 640, height: 480, hfov: 1.0122909661567112, max_range: 4.5, min_range: 0.5, mount_height: 0.3}
      camera: {width: 640, height: 480, hfov: 1.0471975511965976, mount_height: 0.5, noise: 0.0, blur: 0.0, period: 3}
    noise: {odometry: 0.0, motors: 0.0, laser: 0.01}   # noise.SENSOR is that sensor's noise, given here instead
    frames: 3000                       # [3000]
    dt: 0.1                            # [0.1] seconds per frame
    goal_tolerance: 0.25               # [0.25] m: a robot whose pose is this near its room's goal has reached it
    seed: 0                            # [0]
    planner: astar                     # [astar] the decision inside eDecide: a registered decider (--planner)
    localization: odometry             # [odometry] where the robots believe they are: odometry, or particles
                                       # (Monte Carlo localization on the laser and the known map), or
                                       # {kind: particles, ...the fields of vwg.robot.LocalizationSettings}
    avoidance: none                    # [none] how robots pass each other: none, or orca (reciprocal avoidance
                                       # of the robots and people their lasers see), or
                                       # {kind: orca, ...the fields of vwg.robot.AvoidanceSettings}; a robot
                                       # entry's own ``avoidance: none|orca`` is that robot's
    platform: sim                      # [sim] where the robots run: a registered platform's name, or
                                       # {kind: NAME, ...its options} (vwg plugins lists them)
    orders:                            # [[]] the user's orders (gObjective), sorted by time when loaded
      - {time: 0.0, robot: 1, room: kitchen}

A robot entry takes the fields of vwg.robot.RobotSettings, ``noise`` those of vwg.robot.NoiseModel, and
``sensors.NAME`` those of the settings of the sensor registered as NAME (``Settings.fields()`` lists names,
types, defaults and meanings: for the built-in ones the C++ structs LaserSpec, DepthCameraSpec and
CameraSpec, which hold the one copy of every default), except the fields the world sets (``wall_height``).
The sections ``laser:``, ``kinect:`` and ``camera:`` at the top (older files) are read as
``sensors.laser`` and so on. The Kinect also takes
``robot_height``, ``noise`` (true: axial noise ``noise_a + noise_b·(z - 0.4)²`` metres), ``noise_a``,
``noise_b`` and ``scan_rows``; the camera ``robot_height``.

Sensors' image size is ``width``/``height`` (pixels) and their mounting height above the floor ``mount_height``
(metres): one mapping cannot hold two ``height`` keys. Camera ``noise`` is the standard deviation of added grey
levels (0..255), ``blur`` the Gaussian blur's sigma in pixels, ``period`` the frames between two looks for
markers (detection costs milliseconds). ``noise.odometry`` and ``noise.motors`` are relative
standard deviations (per metre travelled and per radian turned); 0 is exact.

The loader checks what a run would trip over later, and names the file, the line and the field: unknown keys,
wrong types, NaN or out-of-range numbers, duplicate marker or robot ids, a marker that is not on a wall face
(within one cell of ``at`` along the facing line, the cell behind must be occupied and the cell in front free),
a goal inside or closer to a wall than the largest robot's radius, a robot start off the map, in unknown space,
inside a wall or within its radius of one, robots overlapping at start, and orders naming an unknown room or
robot or a negative time. Unknown map cells count as walls for goals and starts.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

import vwg._core as _core
from vwg._core import NoiseModel, RobotSettings
from vwg.errors import SchemaError, WorldFileError
from vwg.io.files import MAX_MAP_BYTES
from vwg.io.maps import OccupancyGrid, _expand_user, _movingai_spec, _regular_file, load_map
from vwg.io.shipped import shipped_world
from vwg.io.yamldoc import YamlDoc, field_text
from vwg.model.limits import MAX_DT, MAX_FRAMES, MAX_SEED, MAX_TIME, MIN_DT
from vwg.plugins import deciders, platforms
from vwg.plugins import sensors as sensor_registry

__all__ = ["AVOIDANCES", "LOCALIZATIONS", "Avoidance", "Localization", "Order", "Person", "PlatformSpec", "RobotWorld",
           "Room", "load_robot_world"]

MAX_MARKER = 586  # tag36h11 has 587 codes
_TOP_KEYS = ("name", "description", "map", "wall_height", "rooms", "robots", "sensors", "noise", "frames", "dt", "seed",
             "orders", "platform", "planner", "goal_tolerance", "localization", "avoidance", "people")
_PERSON_KEYS = ("start", "radius", "speed", "waypoints", "loop", "wander")
#: The widest a person may be, metres, and the fastest it may walk, m/s.
MAX_PERSON_RADIUS = 1.0
MAX_PERSON_SPEED = 3.0
#: Sensor sections older files give at the top, read as ``sensors.NAME``.
_LEGACY_SENSOR_KEYS = ("laser", "kinect", "camera")
_ROOM_KEYS = ("marker", "at", "facing", "size", "height", "goal")
_ORDER_KEYS = ("time", "robot", "room")
_GOAL_DISTANCE = 1.0  # default goal: this far in front of the marker, metres


@dataclass(frozen=True)
class Room:
    """A room, named by the tag36h11 marker on one of its walls."""

    name: str
    marker: int
    at: tuple[float, float]
    facing: float
    size: float = 0.3
    height: float = 0.6
    goal: tuple[float, float] = (0.0, 0.0)

    @property
    def normal(self) -> tuple[float, float]:
        """Unit vector the marker faces (out of the wall)."""
        return math.cos(self.facing), math.sin(self.facing)


@dataclass(frozen=True)
class Order:
    """A user order: at ``time`` seconds, send robot ``robot`` to room ``room``."""

    time: float
    robot: int
    room: str


@dataclass(frozen=True)
class PlatformSpec:
    """Where the robots run: a registered platform (``sim``, the Box2D simulator) and its options."""

    kind: str = "sim"
    options: dict[str, Any] = field(default_factory=dict)

    def given(self, kind: str | None, **options: Any) -> PlatformSpec:
        """This platform as the command line changes it: another `kind` (with its defaults), and the
        `options` given (``--platform-opt KEY=VALUE``, ``--url``, ``--serial-port``; None: not given)
        over the file's."""
        spec = PlatformSpec(kind) if kind and kind != self.kind else self
        extra = {k: v for k, v in options.items() if v is not None}
        return PlatformSpec(spec.kind, {**spec.options, **extra}) if extra else spec


#: Where a robot's believed pose comes from: its odometry alone (the paper's robot), or Monte Carlo
#: localization weighing particles on its laser against the known map (vwg.robot.LocalizationSettings).
LOCALIZATIONS = ("odometry", "particles")


@dataclass(frozen=True)
class Localization:
    """How the robots localize: ``kind`` one of LOCALIZATIONS, with the particle filter's settings."""

    kind: str = "odometry"
    settings: Any = field(default_factory=_core.LocalizationSettings)

    @staticmethod
    def of(value: str | Localization) -> Localization:
        """A kind by name (``--localization``, a sweep's parameter) with the default settings; SchemaError
        naming the known kinds otherwise."""
        if isinstance(value, Localization):
            return value
        if value not in LOCALIZATIONS:
            raise SchemaError(f"localization: expected one of {', '.join(LOCALIZATIONS)}, got {value!r}")
        return Localization(value)


#: How a robot moves among others: straight along its decider's steps (the paper's robot), or with optimal
#: reciprocal collision avoidance on what its laser sees of the robots and people around it (ORCA).
AVOIDANCES = ("none", "orca")


@dataclass(frozen=True)
class Avoidance:
    """Which robots avoid their neighbours: ``kind`` one of AVOIDANCES for every robot, ``robots`` the kind of
    those whose own entry says otherwise (by id), and ORCA's settings (vwg.robot.AvoidanceSettings)."""

    kind: str = "none"
    settings: Any = field(default_factory=_core.AvoidanceSettings)
    robots: tuple[tuple[int, str], ...] = ()

    @staticmethod
    def of(value: str | Avoidance) -> Avoidance:
        """A kind by name (``--avoidance``, a sweep's parameter) for every robot, with the default settings;
        SchemaError naming the known kinds otherwise."""
        if isinstance(value, Avoidance):
            return value
        if value not in AVOIDANCES:
            raise SchemaError(f"avoidance: expected one of {', '.join(AVOIDANCES)}, got {value!r}")
        return Avoidance(value)

    def avoids(self, robot: int) -> bool:
        """Whether robot `robot` avoids: its own entry's kind, or the world's."""
        return dict(self.robots).get(robot, self.kind) == "orca"


@dataclass(frozen=True)
class Person:
    """A person who walks (vwg/sim/people.hpp): from ``start``, to each of ``goals`` in turn (again from the first
    when ``loop``), or, ``wander``, to goals drawn from the seed; at ``speed`` m/s, a disc of ``radius`` m."""

    id: int
    start: tuple[float, float]
    goals: tuple[tuple[float, float], ...]
    radius: float = 0.25
    speed: float = 1.0
    loop: bool = True
    wander: bool = False


@dataclass(eq=False)
class RobotWorld:
    """A loaded robot world file."""

    path: Path
    name: str
    description: str
    map_path: Path
    grid: OccupancyGrid
    wall_height: float
    rooms: dict[str, Room]
    robots: list[RobotSettings]
    #: The settings of each sensor the file configures or a robot carries, by registered name.
    sensors: dict[str, Any]
    noise: NoiseModel
    frames: int
    dt: float
    seed: int
    orders: list[Order]
    goal_tolerance: float = _core.ARobotConfig().goal_tolerance  # the one definition of "reached" (robots, summary)
    platform: PlatformSpec = field(default_factory=PlatformSpec)
    planner: str = "astar"  # the decider a run takes unless told another (--planner)
    localization: Localization = field(default_factory=Localization)
    avoidance: Avoidance = field(default_factory=Avoidance)
    people: list[Person] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)  # the YAML as read

    def sensor_settings(self, name: str) -> Any:
        """The settings of the sensor registered as `name` in this world: the file's, or the sensor's
        defaults with the fields the world sets (SchemaError for an unknown sensor)."""
        if name in self.sensors:
            return self.sensors[name]
        cls = sensor_registry.get(name)
        settings = cls.Settings()
        for field_name in cls.world_fields:
            setattr(settings, field_name, getattr(self, field_name))
        return settings

    def with_sensor(self, name: str, **changes: Any) -> RobotWorld:
        """This world with the settings of sensor `name` changed (``world.with_sensor("laser", noise=0.0)``)."""
        return dataclasses.replace(self, sensors={**self.sensors, name: self.sensor_settings(name).replace(**changes)})

    def robot(self, robot_id: int) -> RobotSettings:
        """The robot with this id (KeyError if none)."""
        for r in self.robots:
            if r.id == robot_id:
                return r
        raise KeyError(robot_id)

    def room_of_marker(self, marker: int) -> Room | None:
        """The room a marker id names, or None."""
        for room in self.rooms.values():
            if room.marker == marker:
                return room
        return None

    @property
    def markers(self) -> dict[int, str]:
        """Marker id -> room name."""
        return {room.marker: name for name, room in self.rooms.items()}

    def __repr__(self) -> str:
        return (f"RobotWorld({self.name!r}, {self.grid.width}×{self.grid.height} cells at {self.grid.resolution} m, "
                f"rooms={list(self.rooms)}, robots={[r.id for r in self.robots]}, orders={len(self.orders)})")


# ---- helpers ----------------------------------------------------------------------------------------------
def _p(x: float) -> str:
    return repr(float(x))


def _check_keys(doc: YamlDoc, path: tuple[Any, ...], value: dict[Any, Any], allowed: tuple[str, ...],
                none_allowed: str = "no keys are allowed here") -> None:
    for key in value:
        if key not in allowed:
            close = difflib.get_close_matches(str(key), allowed, n=1)
            hint = f"; did you mean '{close[0]}'?" if close else \
                f" (expected one of {', '.join(allowed)})" if allowed else f" ({none_allowed})"
            raise doc.error((*path, key), f"unknown key{hint}")


def _duplicate_keys(path: Path, root: yaml.Node | None) -> None:
    """PyYAML keeps the last of two equal keys silently; a world file with one is an error."""

    def walk(node: yaml.Node, where: str) -> None:
        if isinstance(node, yaml.MappingNode):
            seen: set[Any] = set()
            for key, value in node.value:
                k = key.value if isinstance(key, yaml.ScalarNode) else str(key)
                here = f"{where}.{k}" if where else str(k)
                if k in seen:
                    hint = ""
                    if k == "height" and where in ("kinect", "camera"):
                        hint = "; the image size is width/height and the mounting height is 'mount_height'"
                    raise WorldFileError(str(path), here, f"duplicate key{hint}", key.start_mark.line + 1)
                seen.add(k)
                walk(value, here)
        elif isinstance(node, yaml.SequenceNode):
            for i, item in enumerate(node.value):
                walk(item, f"{where}[{i}]")

    if root is not None:
        walk(root, "")


def _point(doc: YamlDoc, path: tuple[Any, ...], n: int, what: str) -> tuple[float, ...]:
    value = doc.get(path, list)
    if len(value) != n:
        raise doc.error(path, f"expected {what}, got {len(value)} values")
    return tuple(float(doc.number((*path, i))) for i in range(n))


def _on_wall_face(grid: OccupancyGrid, x: float, y: float, facing: float) -> bool:
    """Whether a wall face crosses the facing line within one cell of (x, y): some point there has an occupied
    cell half a cell behind it and a free cell half a cell in front."""
    nx, ny = math.cos(facing), math.sin(facing)
    res = grid.resolution
    for k in range(-4, 5):
        t = k * res / 4
        bx, by = x + (t - res / 2) * nx, y + (t - res / 2) * ny
        fx, fy = x + (t + res / 2) * nx, y + (t + res / 2) * ny
        rb, cb = grid.world_to_cell(bx, by)
        rf, cf = grid.world_to_cell(fx, fy)
        if grid.inside(rb, cb) and grid.inside(rf, cf) and grid.data[rb, cb] >= 50 and 0 <= grid.data[rf, cf] < 50:
            return True
    return False


def _place_problem(grid: OccupancyGrid, x: float, y: float, radius: float) -> str:
    """Why a disc of ``radius`` cannot stand at (x, y), or "" if it can."""
    row, col = grid.world_to_cell(x, y)
    if not grid.inside(row, col):
        return (f"is outside the map ({grid.width_m:g} × {grid.height_m:g} m, lower-left corner at "
                f"({_p(grid.origin[0])}, {_p(grid.origin[1])}))")
    value = int(grid.data[row, col])
    if value < 0:
        return "is in unknown space"
    if value >= 50:
        return "is inside a wall"
    clearance = grid.clearance(x, y, limit=radius + grid.resolution)
    if clearance < radius:
        return f"is {clearance:.3f} m from a wall, closer than the radius {_p(radius)} m"
    return ""


# ---- the loader -------------------------------------------------------------------------------------------
def _load_grid(doc: YamlDoc, base: Path) -> tuple[OccupancyGrid, Path]:
    spec = doc.get(("map",), (str, dict))
    if isinstance(spec, dict):
        grid = _movingai_spec(doc, ("map",), base)
        return grid, Path(grid.source)
    file = _expand_user(doc, ("map",), spec)
    if not file.is_absolute():
        file = base / file
    # A device (/dev/zero) or a named pipe is said to be one, not "not found"; load_map checks the size.
    _regular_file(doc, ("map",), file, MAX_MAP_BYTES, "map file")
    return load_map(file), file


def _robots(doc: YamlDoc, grid: OccupancyGrid) -> list[RobotSettings]:

    entries = doc.get(("robots",), list)
    if not entries:
        raise doc.error(("robots",), "expected at least one robot")
    robots: list[RobotSettings] = []
    seen: dict[int, int] = {}
    for i, entry in enumerate(entries):
        path: tuple[Any, ...] = ("robots", i)
        if not isinstance(entry, dict):
            raise doc.error(path, f"expected a mapping with id and start, got {entry!r}")
        doc.get((*path, "id"))  # required: "missing" names the robot's line
        doc.get((*path, "start"))
        robot = _settings(doc, path, RobotSettings(), skip=("avoidance",))
        if robot.id in seen:
            raise doc.error((*path, "id"), f"robot id {robot.id} is already used by robots[{seen[robot.id]}]")
        seen[robot.id] = i
        for j, name in enumerate(robot.sensors):
            if name not in sensor_registry:
                raise doc.error((*path, "sensors", j),
                                f"unknown sensor {name!r} (registered: {', '.join(sensor_registry)})")
        x, y, _ = robot.start
        problem = _place_problem(grid, x, y, robot.radius)
        if problem:
            raise doc.error((*path, "start"), f"robot {robot.id} at ({_p(x)}, {_p(y)}) {problem}")
        robots.append(robot)
    for i, a in enumerate(robots):
        for j in range(i):
            b = robots[j]
            if math.hypot(a.start[0] - b.start[0], a.start[1] - b.start[1]) < a.radius + b.radius:
                raise doc.error(("robots", i, "start"), f"robot {a.id} overlaps robot {b.id} at the start")
    return robots


def _rooms(doc: YamlDoc, grid: OccupancyGrid, wall_height: float, radius: float) -> dict[str, Room]:
    entries = doc.get(("rooms",), dict, default={})
    rooms: dict[str, Room] = {}
    markers: dict[int, str] = {}
    for name, entry in entries.items():
        path: tuple[Any, ...] = ("rooms", name)
        if not isinstance(name, str) or not name:
            raise doc.error(path, f"a room name must be text, got {name!r}")
        if not isinstance(entry, dict):
            raise doc.error(path, f"expected a mapping with marker, at and facing, got {entry!r}")
        _check_keys(doc, path, entry, _ROOM_KEYS)
        marker = int(doc.number((*path, "marker"), minimum=0, maximum=MAX_MARKER, integer=True))
        if marker in markers:
            raise doc.error((*path, "marker"), f"marker {marker} already names room {markers[marker]!r}")
        markers[marker] = name
        x, y = _point(doc, (*path, "at"), 2, "[x, y]")
        facing = float(doc.number((*path, "facing")))
        size = float(doc.number((*path, "size"), 0.3, minimum=0.0, exclusive_minimum=True))
        height = float(doc.number((*path, "height"), 0.6, minimum=0.0))
        if height - size / 2 < 0 or height + size / 2 > wall_height:
            raise doc.error((*path, "height"), f"a {_p(size)} m marker centred {_p(height)} m up does not fit on "
                                               f"a wall {_p(wall_height)} m high")
        if not grid.contains(x, y):
            raise doc.error((*path, "at"), f"marker {marker} at ({_p(x)}, {_p(y)}) is outside the map")
        if not _on_wall_face(grid, x, y, facing):
            raise doc.error((*path, "at"), f"marker {marker} at ({_p(x)}, {_p(y)}) facing {facing:.4g} rad is not on "
                                           "a wall face: within one cell of it the cell behind must be occupied and "
                                           "the cell in front free")
        nx, ny = math.cos(facing), math.sin(facing)
        if doc.get((*path, "goal"), default=None) is None:
            gx, gy = x + _GOAL_DISTANCE * nx, y + _GOAL_DISTANCE * ny
        else:
            gx, gy = _point(doc, (*path, "goal"), 2, "[x, y]")
        problem = _place_problem(grid, gx, gy, radius)
        if problem:
            raise doc.error((*path, "goal"), f"goal ({_p(gx)}, {_p(gy)}) of room {name!r} {problem}"
                                             + (" of the largest robot" if "radius" in problem else ""))
        rooms[name] = Room(name, marker, (x, y), facing, size, height, (gx, gy))
    return rooms


def _settings_path(owner: str, field: str) -> tuple[Any, ...]:
    """The key path of a SchemaError's field below `owner` ("laser.beams" below "laser" -> ("beams",))."""
    rest = field[len(owner):].lstrip(".") if field.startswith(owner) else field.partition(".")[2]
    return tuple(int(p[1:-1]) if p.startswith("[") else p for p in re.findall(r"\[\d+\]|[^.\[\]]+", rest))


def _settings(doc: YamlDoc, path: tuple[Any, ...], spec: Any, *, fixed: dict[str, Any] | None = None,
              skip: tuple[str, ...] = ()) -> Any:
    """`spec` (a settings struct of vwg._core) with the fields the mapping at `path` gives, then
    `fixed` (values the world sets, which the section may not), checked by the C++ side. The keys,
    types and defaults are the struct's: nothing here repeats them. Errors name file, line and field."""
    fixed = fixed or {}
    section = doc.get(path, dict, default={})
    names = tuple(name for name, *_ in type(spec).fields() if name not in fixed)
    _check_keys(doc, path, {k: v for k, v in section.items() if k not in skip}, (*names, *skip))
    owner = type(spec).__name__
    try:
        for key, value in [*((k, v) for k, v in section.items() if k not in skip), *fixed.items()]:
            setattr(spec, key, value)  # the struct refuses a value of the wrong kind or size by field
        owner = field_text(path)
        spec.check(owner)
    except SchemaError as e:
        field = getattr(e, "field", "")
        if not field and str(e).startswith(f"{owner}.") and ": " in str(e):  # raised in Python: "FIELD: what"
            field = str(e).split(": ", 1)[0]
        message = str(e)[len(field) + 2:] if field and str(e).startswith(field) else str(e)
        raise doc.error((*path, *_settings_path(owner, field)), message) from None
    return spec


def _sensors(doc: YamlDoc, wall_height: float, robots: list[RobotSettings]) -> tuple[dict[str, Any], NoiseModel]:
    """Each sensor's settings: ``sensors.NAME`` (or an older file's top-level section) checked by the
    settings of the sensor registered as NAME, for every sensor given or carried by a robot; and the
    noise model, whose ``noise.NAME`` is that sensor's ``noise`` setting."""
    sections: dict[str, tuple[Any, ...]] = {}
    for name in doc.get(("sensors",), dict, default={}):
        if name not in sensor_registry:
            raise doc.error(("sensors", name), f"unknown sensor {name!r} (registered: {', '.join(sensor_registry)})")
        sections[str(name)] = ("sensors", name)
    for name in _LEGACY_SENSOR_KEYS:
        if doc.get((name,), default=None) is not None:
            if name in sections:
                raise doc.error((name,), f"sensor {name} is given twice, here and in sensors.{name}; keep one")
            sections[name] = (name,)
    for robot in robots:
        for name in robot.sensors:
            sections.setdefault(name, ("sensors", name))
    for name in doc.get(("noise",), dict, default={}):
        if name in sensor_registry:
            sections.setdefault(str(name), ("sensors", name))
    noise = _settings(doc, ("noise",), NoiseModel(), skip=tuple(sensor_registry))
    out: dict[str, Any] = {}
    for name, path in sections.items():
        cls = sensor_registry.get(name)
        fixed = {f: wall_height for f in cls.world_fields if f == "wall_height"}
        settings = _settings(doc, path, cls.Settings(), fixed=fixed)
        if doc.get(("noise", name), default=None) is not None:
            given = float(doc.number(("noise", name), minimum=0.0))
            if not hasattr(settings, "noise"):
                raise doc.error(("noise", name), f"sensor {name} has no noise setting")
            if doc.get((*path, "noise"), default=None) is not None and given != settings.noise:
                raise doc.error(("noise", name), f"{_p(given)} conflicts with {field_text(path)}.noise "
                                                 f"({_p(settings.noise)}); give one of them")
            settings = settings.replace(noise=given)
        out[name] = settings
    return out, noise


def _orders(doc: YamlDoc, rooms: dict[str, Room], robots: list[RobotSettings]) -> list[Order]:
    ids = {r.id for r in robots}
    orders: list[Order] = []
    for i, entry in enumerate(doc.get(("orders",), list, default=[])):
        path: tuple[Any, ...] = ("orders", i)
        if not isinstance(entry, dict):
            raise doc.error(path, f"expected {{time, robot, room}}, got {entry!r}")
        _check_keys(doc, path, entry, _ORDER_KEYS)
        time = float(doc.number((*path, "time"), minimum=0.0, maximum=MAX_TIME))
        robot = int(doc.number((*path, "robot"), integer=True))
        if robot not in ids:
            raise doc.error((*path, "robot"), f"no robot with id {robot} (robots: {sorted(ids)})")
        room = doc.get((*path, "room"), str)
        if room not in rooms:
            close = difflib.get_close_matches(room, list(rooms), n=1)
            hint = f"; did you mean {close[0]!r}?" if close else f" (rooms: {', '.join(rooms) or 'none'})"
            raise doc.error((*path, "room"), f"no room named {room!r}{hint}")
        orders.append(Order(time, robot, room))
    return sorted(orders, key=lambda o: o.time)  # stable: equal times keep the file's order


def _platform(doc: YamlDoc) -> PlatformSpec:
    """The platform the file names, its options checked by that platform's own (as ``vwg check`` and
    ``vwg run`` alike take them), errors naming the option's line."""
    entry = doc.get(("platform",), (str, dict), default="sim")
    if isinstance(entry, str):
        kind, options = entry, {}
    else:
        kind = doc.get(("platform", "kind"), str)
        options = {k: v for k, v in entry.items() if k != "kind"}
    if kind not in platforms:
        raise doc.error(("platform",), f"unknown platform {kind!r} (known: {', '.join(platforms)})")
    cls = platforms.get(kind)
    _check_keys(doc, ("platform",), options, tuple(cls.options), f"the {kind} platform takes no options")
    try:
        cls.check_options(options)
    except SchemaError as e:
        where, _, message = str(e).partition(": ")
        raise doc.error(("platform", *where.removeprefix("platform.").split(".")), message) from None
    return PlatformSpec(kind, options)


def _avoidance(doc: YamlDoc, robots: list[RobotSettings]) -> Avoidance:
    """``avoidance: KIND`` or ``{kind: KIND, ...settings}`` for all robots, and ``robots[i].avoidance: KIND`` for
    one; the settings checked by the C++ struct."""
    kind, settings = _kind_and_settings(doc, "avoidance", Avoidance.of, unset="none", mapped="orca")
    own: list[tuple[int, str]] = []
    for i, robot in enumerate(robots):
        mine = doc.get(("robots", i, "avoidance"), str, default=None)
        if mine is not None:
            try:
                own.append((robot.id, Avoidance.of(mine).kind))
            except SchemaError as e:
                raise doc.error(("robots", i, "avoidance"), str(e).removeprefix("avoidance: ")) from None
    return Avoidance(kind, settings, tuple(own))


def _people(doc: YamlDoc, grid: OccupancyGrid, rooms: dict[str, Room]) -> list[Person]:
    """``people:``, each {start, waypoints | wander, radius, speed, loop}, numbered from 1 in the file's order."""
    people: list[Person] = []
    for i, entry in enumerate(doc.get(("people",), list, default=[])):
        path: tuple[Any, ...] = ("people", i)
        if not isinstance(entry, dict):
            raise doc.error(path, f"expected {{start, waypoints or wander, ...}}, got {entry!r}")
        _check_keys(doc, path, entry, _PERSON_KEYS)
        radius = float(doc.number((*path, "radius"), 0.25, minimum=0.0, exclusive_minimum=True,
                                  maximum=MAX_PERSON_RADIUS))
        speed = float(doc.number((*path, "speed"), 1.0, minimum=0.0, exclusive_minimum=True, maximum=MAX_PERSON_SPEED))
        start = _map_point(doc, (*path, "start"), grid)
        problem = _place_problem(grid, start[0], start[1], radius)
        if problem:
            raise doc.error((*path, "start"), f"person {i + 1} at ({_p(start[0])}, {_p(start[1])}) {problem}")
        loop = doc.get((*path, "loop"), bool, default=True)
        if ("waypoints" in entry) == ("wander" in entry):
            raise doc.error(path, "expected waypoints (a list of [x, y]) or wander (room names, or all), one of them")
        if "waypoints" in entry:
            points = doc.get((*path, "waypoints"), list)
            if not points:
                raise doc.error((*path, "waypoints"), "expected at least one [x, y]")
            goals = tuple(_map_point(doc, (*path, "waypoints", j), grid) for j in range(len(points)))
            people.append(Person(i + 1, start, goals, radius, speed, loop))
            continue
        wander = doc.get((*path, "wander"), (str, list))
        names = list(rooms) if wander == "all" else wander if isinstance(wander, list) else None
        if not names:
            raise doc.error((*path, "wander"), "expected a list of room names, or all")
        for j, name in enumerate(names):
            if name not in rooms:
                raise doc.error((*path, "wander", j) if isinstance(wander, list) else (*path, "wander"),
                                f"no room named {name!r} (rooms: {', '.join(rooms) or 'none'})")
        people.append(Person(i + 1, start, tuple(rooms[n].goal for n in names), radius, speed, True, True))
    return people


def _map_point(doc: YamlDoc, path: tuple[Any, ...], grid: OccupancyGrid) -> tuple[float, float]:
    """``[x, y]`` at `path`, a point of the map."""
    value = doc.get(path, list)
    if len(value) != 2:
        raise doc.error(path, f"expected [x, y], got {value!r}")
    x, y = float(doc.number((*path, 0))), float(doc.number((*path, 1)))
    if not grid.inside(*grid.world_to_cell(x, y)):
        raise doc.error(path, f"({_p(x)}, {_p(y)}) is outside the map")
    return x, y


def _localization(doc: YamlDoc) -> Localization:
    """``localization: KIND`` or ``{kind: KIND, ...settings}``."""
    return Localization(*_kind_and_settings(doc, "localization", Localization.of, unset="odometry", mapped="particles"))


def _kind_and_settings(doc: YamlDoc, key: str, of: Callable[[str], Any], *, unset: str, mapped: str) -> tuple[str, Any]:
    """``KEY: KIND`` (`unset` when the key is absent) or ``{kind: KIND, ...settings}`` (`mapped` when it gives no
    kind): the kind checked by `of` (Localization.of, Avoidance.of), the settings by the C++ struct, errors at
    their line."""
    entry = doc.get((key,), (str, dict), default=unset)
    kind = entry if isinstance(entry, str) else doc.get((key, "kind"), str, default=mapped)
    try:
        chosen = of(kind)
    except SchemaError as e:
        where = (key,) if isinstance(entry, str) else (key, "kind")
        raise doc.error(where, str(e).removeprefix(f"{key}: ")) from None
    if isinstance(entry, dict):
        return chosen.kind, _settings(doc, (key,), chosen.settings, skip=("kind",))
    return chosen.kind, chosen.settings


#: The highest wall a world may have, metres.
MAX_WALL_HEIGHT = 100.0


def load_robot_world(path: str | Path) -> RobotWorld:
    """Load and check a robot world file (see the module docs for the schema), or a shipped world by
    name (``"office"``); errors are WorldFileError naming the file, the line and the field."""
    path = Path(path)
    path = shipped_world(path) or path
    doc = YamlDoc(path)
    if not isinstance(doc.data, dict):
        raise doc.error((), "expected a mapping with map and robots")
    _duplicate_keys(path, doc.node)
    _check_keys(doc, (), doc.data, (*_TOP_KEYS, *_LEGACY_SENSOR_KEYS))
    base = path.parent
    name = doc.get(("name",), str, default=path.stem)
    description = doc.get(("description",), str, default="")
    grid, map_path = _load_grid(doc, base)
    # At most 100 m (a tall atrium's): views and cameras allocate by it (1e12 m was 148 TiB in vwg overview).
    wall_height = float(doc.number(("wall_height",), _core.CameraSpec().wall_height, minimum=0.0,
                                   exclusive_minimum=True, maximum=MAX_WALL_HEIGHT))
    robots = _robots(doc, grid)
    rooms = _rooms(doc, grid, wall_height, max(r.radius for r in robots))
    sensors, noise = _sensors(doc, wall_height, robots)
    frames = int(doc.number(("frames",), 3000, minimum=0, maximum=MAX_FRAMES, integer=True))
    engine = _core.EngineOptions()  # the defaults, and the range of dt (MIN_DT..MAX_DT, the engine's)
    dt = float(doc.number(("dt",), engine.dt, minimum=MIN_DT, maximum=MAX_DT))
    seed = int(doc.number(("seed",), engine.seed, minimum=0, maximum=MAX_SEED, integer=True))
    orders = _orders(doc, rooms, robots)
    platform = _platform(doc)
    planner = doc.get(("planner",), str, default="astar")
    if planner.lower() not in deciders:
        raise doc.error(("planner",), f"unknown planner {planner!r} (registered: {', '.join(deciders)})")
    tolerance = float(doc.number(("goal_tolerance",), _core.ARobotConfig().goal_tolerance, minimum=0.0,
                                 exclusive_minimum=True))
    localization = _localization(doc)
    avoidance = _avoidance(doc, robots)
    people = _people(doc, grid, rooms)
    if people and platform.kind != "sim":
        raise doc.error(("people",), f"people walk on the simulator only (the platform is {platform.kind})")
    return RobotWorld(path=path, platform=platform, planner=planner, goal_tolerance=tolerance, name=name,
                      localization=localization, avoidance=avoidance, people=people,
                      description=description, map_path=map_path, grid=grid,
                      wall_height=wall_height, rooms=rooms, robots=robots, sensors=sensors,
                      noise=noise, frames=frames, dt=dt, seed=seed, orders=orders, data=doc.data)
