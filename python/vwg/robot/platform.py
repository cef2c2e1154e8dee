"""Where a robot world's robots run: a platform (paper test 3: the simulator or a real robot, the
world string the same). A platform is one class in one file, registered by name (entry point group
``vwg.platforms``): its options, the vwg.robot.RobotPlatform it drives, the motion backend on it, the
feedback generators, and the sensors it can carry.

    class Kinematic(vwg.robot.Platform):
        name = "kinematic"
        options = {"slip": Option(float, 0.0, minimum=0.0, help="fraction of each step lost")}

        def __init__(self, world, seed, options):
            super().__init__(world, seed, options)     # self.settings: the options checked, with defaults
            self.platform = MyRobotPlatform(world.robots, self.settings["slip"])
            self.backend = vwg.robot.MotionBackend(self.platform)

The sensors a robot lists are made by the sensors (vwg.robot.sensor.Sensor.make): each says how it
is made on the platforms that can carry it, and a platform that cannot carry one leaves it out with a
warning, so a world file written for the simulator runs on a real robot unchanged. What a sensor looks
for on a platform: ``scanner`` (a vwg::sim::RangeScanner: the simulator's lasers), ``scan_generator(robot)``
(a real robot's LaserScan messages), ``raycaster`` (a GridRaycaster on the world's map: any platform
that knows where its robots are carries the laser that way), ``physics`` (the simulator's cameras).

The RobotPlatform reports each robot's RobotState: its pose, odometry, busy, commands and ``travelled``
(metres driven, which the run's summary reports as path_length_m: a platform that leaves it 0 reports
robots that never moved).
"""

from __future__ import annotations

import difflib
import logging
import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import vwg._core as _core
from vwg.errors import SchemaError
from vwg.io.video import VideoWriter
from vwg.io.yamldoc import KIND_NAMES
from vwg.plugins import sensors as sensor_registry
from vwg.robot.world_file import Avoidance, Localization, RobotWorld

__all__ = ["Option", "Platform", "world_view"]

log = logging.getLogger("vwg.robot")

@dataclass(frozen=True)
class Option:
    """One option of a platform: its type (float, int, str, bool or dict), its default (None: the
    platform's own), its bounds, whether it must be given, a line of help, the options of a mapping
    (``fields``), and a conversion of the checked value (``convert``). World files and the command line
    are checked by the same ``value()``; its messages are those of the world file's other fields."""

    kind: type
    default: Any = None
    minimum: float | None = None
    exclusive_minimum: bool = False
    maximum: float | None = None
    required: bool = False
    help: str = ""
    fields: Mapping[str, Option] | None = None
    convert: Callable[[Any], Any] | None = None

    def value(self, where: str, given: Any) -> Any:
        """`given` checked and converted; SchemaError("WHERE: expected ...") naming the field."""
        kinds: tuple[type, ...] = (int, float) if self.kind is float else (self.kind,)
        if not isinstance(given, kinds) or (isinstance(given, bool) and bool not in kinds):
            expected = " or ".join(KIND_NAMES.get(k, k.__name__) for k in kinds)
            raise SchemaError(f"{where}: expected {expected}, got {type(given).__name__} {given!r}")
        if self.kind in (int, float):
            if not math.isfinite(given):
                raise SchemaError(f"{where}: expected a finite number, got {given!r}")
            low, high = self.minimum, self.maximum
            if low is not None and (given < low or (self.exclusive_minimum and given == low)):
                raise SchemaError(f"{where}: expected a number {'>' if self.exclusive_minimum else '>='} {low}, "
                                  f"got {given!r}")
            if high is not None and given > high:
                raise SchemaError(f"{where}: expected a number <= {high}, got {given!r}")
            given = float(given) if self.kind is float else given
        if self.fields is not None:
            for key in given:
                if key not in self.fields:
                    close = difflib.get_close_matches(str(key), list(self.fields), n=1)
                    hint = f"; did you mean '{close[0]}'?" if close else f" (expected one of {', '.join(self.fields)})"
                    raise SchemaError(f"{where}.{key}: unknown key{hint}")
            given = {key: self.fields[key].value(f"{where}.{key}", v) for key, v in given.items()}
        return self.convert(given) if self.convert is not None else given


class Platform:
    """A robot world's robots on a platform: what CaseStudy and ``vwg run`` use of it. A subclass sets
    ``name``, ``options`` and ``sensors`` (the names of the sensors it can carry, for ``vwg plugins``
    and the docs), and in ``__init__`` ``platform`` (a vwg.robot.RobotPlatform) and ``backend`` (the
    motion backend on it). ``Platform(world, seed, options)`` is how vwg makes one."""

    name: ClassVar[str] = ""
    #: The options a world file's ``platform:`` and ``--platform-opt KEY=VALUE`` may give.
    options: ClassVar[dict[str, Option]] = {}
    #: The sensors it can carry (informative: each sensor's make() decides).
    sensors: ClassVar[tuple[str, ...]] = ()
    #: What the platform is, in a line (``vwg plugins``).
    summary: ClassVar[str] = ""
    #: Whether its robots' ``pose`` is the truth (a simulator), so that a run can say how far each robot's
    #: belief is from it; a real robot's pose is its own odometry.
    ground_truth: ClassVar[bool] = False

    world: RobotWorld
    platform: _core.RobotPlatform
    backend: _core.Backend

    def __init__(self, world: RobotWorld, seed: int, options: Mapping[str, Any]) -> None:
        self.world = world
        self.seed = seed
        self.settings = self.check_options(options)
        #: The sensors' generators made on this platform, in the order they were made (the view draws
        #: the scans of the range sensors among them).
        self.made: list[_core.Generator] = []

    @classmethod
    def check_options(cls, options: Mapping[str, Any]) -> dict[str, Any]:
        """The options with their defaults, each checked; SchemaError naming ``platform.KEY``."""
        unknown = sorted(str(k) for k in options if k not in cls.options)
        if unknown:
            known = ", ".join(cls.options) or "none: it takes no options"
            raise SchemaError(f"platform {cls.name}: unknown option(s) {', '.join(unknown)} (known: {known})")
        out: dict[str, Any] = {}
        for key, option in cls.options.items():
            if key in options and options[key] is not None:
                out[key] = option.value(f"platform.{key}", options[key])
            elif option.required:
                raise SchemaError(f"platform.{key}: missing ({option.help or 'required'})")
            else:
                out[key] = option.default
        return out

    # -- what a run uses ---------------------------------------------------------------------------
    def make_sensors(self, alphabet: _core.Alphabet, kinds: tuple[str, ...] | None = None) -> list[_core.Generator]:
        """The sensors each robot lists (those of `kinds`, or all), made by the sensor registry
        (vwg.plugins.sensors) with the world's settings: the ranging ones robot by robot (gLaser,
        gKinect), then the others (gCamera), as the paper's priority order has them; those this platform
        does not carry are left out with a warning."""
        ranging: list[_core.Generator] = []
        others: list[_core.Generator] = []
        for robot in self.world.robots:
            for name in robot.sensors:
                if kinds is not None and name not in kinds:
                    continue
                cls = sensor_registry.get(name)
                sensor = cls(self.world.sensor_settings(name))
                gen = sensor.make(self, alphabet, robot.id)
                if gen is None:
                    log.warning("%s: robot %d: sensor %r is not carried by this platform; left out", self.name,
                                robot.id, name)
                    continue
                self.made.append(gen)
                (ranging if cls.ranging else others).append(gen)
        return ranging + others

    def feedback(self, alphabet: _core.Alphabet, localization: Localization | None = None,
                 known_map: _core.OccupancyGrid | None = None,
                 avoidance: Avoidance | None = None) -> list[_core.Generator]:
        """Each robot's believed pose, what it sees of its neighbours, and its collisions, as events (from the
        platform). The pose is its odometry, or with ``localization`` of kind ``particles`` the estimate of
        Monte Carlo localization on its laser's scans against `known_map`; the robots that ``avoidance`` has
        avoid get gNeighbours on their laser's scans (make_sensors first: both read the lasers made there)."""
        collisions = _core.CollisionGenerator(self.platform, alphabet)
        avoiding = [r for r in self.world.robots if avoidance is not None and avoidance.avoids(r.id)]
        neighbours = [_core.NeighbourGenerator(self.platform, self._laser(r, "avoidance: orca sees the neighbours "
                                                                             "in a robot's laser scans"),
                                               _core.NeighbourSettings(), alphabet) for r in avoiding]
        # Before the collisions: the lasers, which scan later in the frame, never run beside what reads them.
        if localization is None or localization.kind == "odometry":
            return [_core.OdometryGenerator(self.platform, alphabet), *neighbours, collisions]
        if known_map is None:
            raise SchemaError("localization: particles need the map the robots know (knows_map=False gives none)")
        why = "localization: particles weigh a robot's laser scans"
        lasers = {r.id: self._laser(r, why) for r in self.world.robots}
        field = _core.LikelihoodField(known_map, localization.settings, max(g.max_range for g in lasers.values()))
        # One a robot, as the lasers are: the robots' filters run side by side (the same frames on any threads).
        # A robot a λ spawns has no filter: its odometry is its pose (after the filters' poses).
        filters = [_core.LocalizationGenerator(self.platform, lasers[r.id], field, localization.settings, alphabet)
                   for r in self.world.robots]
        odometry = _core.OdometryGenerator(self.platform, alphabet, localized=[r.id for r in self.world.robots])
        return [*filters, odometry, *neighbours, collisions]

    def _laser(self, robot: _core.RobotSettings, why: str) -> _core.LaserGenerator:
        """Robot `robot`'s laser as made by make_sensors; SchemaError saying `why` it is needed when it has none
        of the simulator's (a real robot's scans come from Python generators)."""
        for g in self.made:
            if isinstance(g, _core.LaserGenerator) and g.robot == robot.id:
                return g
        raise SchemaError(f"{why}, and robot {robot.id} has no laser of the simulator's on the platform "
                          f"{self.name} (it carries {', '.join(robot.sensors) or 'no sensor'})")

    def view(self, *, width: int = 800, video: str | os.PathLike[str] | None = None, fps: float | None = None,
             images: str | None = None) -> _core.SimView:
        """A backend drawing the robots on the world's map: the markers, robots, trajectories and the
        scans of the range sensors made here; recording to `video` (MP4/GIF at `fps`, by default the
        world's frame rate) and/or PNG files in `images`."""
        view = world_view(self.platform, self.world, width=width, video=video, fps=fps, images=images)
        for gen in self.made:
            if isinstance(gen, _core.LaserGenerator):
                view.add_laser(gen)
            elif isinstance(gen, _core.KinectGenerator):
                view.add_kinect(gen)
        return view

    def robot(self, robot: int) -> _core.RobotState:
        return self.platform.robot(robot)

    def close(self) -> None:
        """Release the platform (a real robot's link stops its robots first)."""


def world_view(platform: _core.RobotPlatform, world: RobotWorld, *, width: int = 800,
               video: str | os.PathLike[str] | None = None, fps: float | None = None,
               images: str | None = None) -> _core.SimView:
    """A view of `world`'s robots on `platform` (the simulator or a real robot): its map, its rooms'
    markers, recording to `video` (MP4/GIF at `fps`, by default the world's frame rate) and/or PNG
    files in `images`."""
    view = _core.SimView(platform, world.grid, width=width)
    for room in world.rooms.values():
        view.add_marker(room.at[0], room.at[1], room.facing, room.name, room.marker)
    if video:
        view.record_video(VideoWriter(video, fps=fps if fps is not None else 1.0 / world.dt))
    if images:
        view.record_images(str(images))
    return view
