"""The robot case study of the paper (§III), assembled from a robot world file:

- the alphabet: the primitive Robot, the transformations Move and Rotate (Table I); the events of
  Table II (eLaser, eCamera, eObjective, eDecide, eExecute — the visual one) and the simulator's
  feedback (eOdometry, eCollision); the actor ARobot (eq. 11) with the decider chosen by name;
- the initial string (eq. 13): one ARobot per robot, its grid the known map, no objective, no action;
- the generators, in priority order: odometry (or the pose Monte Carlo localization estimates from it and
  the laser: the world's ``localization``) and collisions (the robot's own state first), then
  gLaser / gKinect, gCamera, gObjective (the users' orders), gDecide, gExecute;
- the backend: the simulator, and a view when asked for video or images.

    run = vwg.robot.CaseStudy(vwg.robot.load_robot_world("maps/office.yaml"), planner="astar", goals={1: "kitchen"})
    summary = run.run()
"""

from __future__ import annotations

import math
import sys
import threading
import time
import weakref
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

import numpy as np

import vwg._core as _core
from vwg.errors import Error, FrameError, SchemaError
from vwg.io.maps import OccupancyGrid
from vwg.io.record import robot_data
from vwg.launch import EXIT_LINK_FAULT, EXIT_UNREACHED, TRAJECTORY_FORMATS, Outcome, trajectory_type_error
from vwg.model.actor import Sym
from vwg.model.engine import Engine
from vwg.model.generators import every_frame
from vwg.model.limits import MAX_TIME
from vwg.model.world import Alphabet, World
from vwg.plugins import backends as backend_registry
from vwg.plugins import deciders, platforms
from vwg.plugins import sensors as sensor_registry
from vwg.robot.links.rosbridge_client import LinkError
from vwg.robot.platforms.sim import MOTION_SYMBOLS, PEOPLE_SYMBOLS, Simulation
from vwg.robot.topics import RunTopics, Sink, case_topics, open_sinks
from vwg.robot.world_file import Avoidance, Localization, PlatformSpec, RobotWorld, load_robot_world
from vwg.saved_run import save_state

__all__ = ["CANCEL_WORDS", "CaseStudy", "Orders", "RobotSummary", "RunSummary", "case_study_world", "make_decider"]


def make_decider(planner: str | _core.Decider) -> _core.Decider:
    """A decider by its registered name (vwg.plugins.deciders: random, astar, astar-octile, dstar,
    jps, jps-octile, rrtconnect, rrtstar, prm, and any a third party registers), or the one given."""
    if isinstance(planner, _core.Decider):
        return planner
    name = planner.lower()
    if name not in deciders:
        raise SchemaError(f"planner: unknown planner '{planner}' (known: {', '.join(deciders)})")
    return deciders.create(name)


#: A robot's radius when a world has no robots (RobotSettings' default, the C++ platform::kDefaultRobotRadius).
_DEFAULT_RADIUS: float = _core.RobotSettings().radius


def case_study_world(world: RobotWorld, decider: _core.Decider, *,
                     step_length: float = _core.ARobotConfig().step_length,
                     avoidance: Avoidance | None = None) -> World:
    """The alphabet of the case study with ARobot deciding by `decider`, for this robot world (its robots avoiding
    as `avoidance`, by default the world's, says)."""
    events = {name: {f: spec[1] for f, spec in fields.items()} for name, fields in _core.arobot_event_types().items()}
    # The events of the sensors the robots carry (a plugin's sensor may emit its own kinds).
    for name in sorted({s for r in world.robots for s in r.sensors}):
        for event, fields in sensor_registry.get(name).events.items():
            events.setdefault(event, fields)
    symbols = MOTION_SYMBOLS
    if world.people:  # people who walk: Person actors, shown as Pedestrian, pushed by gSocial's eSocial
        events["eSocial"] = {"fx": 0.0, "fy": 0.0}
        symbols = {**MOTION_SYMBOLS, "primitives": {**MOTION_SYMBOLS["primitives"], **PEOPLE_SYMBOLS}}
    alphabet = Alphabet(events=events, visual=["eExecute"], **symbols)
    if world.people:
        _core.add_person_actor(alphabet, world.grid, _core.SocialForceSettings(), world.dt,
                               max(p.radius for p in world.people))
    rooms = {room.marker: room.goal for room in world.rooms.values()}
    radius = max((r.radius for r in world.robots), default=_DEFAULT_RADIUS)
    _core.add_arobot(alphabet, decider, world.grid, rooms, radius=radius, goal_tolerance=world.goal_tolerance,
                     step_length=step_length, robots=list(world.robots),
                     avoidance=(world.avoidance if avoidance is None else avoidance).settings)
    return World(alphabet)


#: The words of an order line that interrupt a robot's task (vwg run --stdin-orders: ``stop``, ``2 cancel``).
CANCEL_WORDS = ("cancel", "stop")


class Orders:
    """gObjective, the users' orders: a timed script, calls to order(), and lines read from a stream
    (``kitchen`` for robot 1, or ``2 kitchen``), by room name. The events (eObjective<to=robot,
    marker>) come from ``generator``, a C++ OrderGenerator: orders given from other threads go out at
    the next frame, and the run's stop condition reads it without calling into Python."""

    def __init__(self, world: RobotWorld, alphabet: _core.Alphabet) -> None:
        self.world = world
        self.generator = _core.OrderGenerator(alphabet)
        self._rooms = {room.marker: name for name, room in world.rooms.items()}

    def marker_of(self, room: str) -> int:
        if room not in self.world.rooms:
            raise SchemaError(f"goal: unknown room '{room}' (rooms: {', '.join(self.world.rooms)})")
        return self.world.rooms[room].marker

    def check_robot(self, robot: int) -> None:
        if robot not in {r.id for r in self.world.robots}:
            raise SchemaError(f"goal: no robot {robot} (robots: {', '.join(str(r.id) for r in self.world.robots)})")

    def order(self, robot: int, room: str) -> None:
        """Send `robot` to `room` at the next frame (from any thread)."""
        self.check_robot(robot)
        self.generator.order(robot, self.marker_of(room))

    def schedule(self, frame: int, robot: int, room: str) -> None:
        """Send `robot` to `room` at `frame`."""
        self.check_robot(robot)
        self.generator.schedule(frame, robot, self.marker_of(room))

    def cancel(self, robot: int) -> None:
        """Interrupt `robot`'s task at the next frame (eObjective<marker=-1>, from any thread): it comes to rest
        where it is and waits for its next order; the run does not wait for it to arrive."""
        self.check_robot(robot)
        self.generator.cancel(robot)

    def pending(self, frame: int) -> bool:
        """Whether orders are still to come after `frame`."""
        return bool(self.generator.pending(frame))

    @property
    def given(self) -> int:
        """Orders sent so far."""
        return int(self.generator.given)

    @property
    def last(self) -> dict[int, str]:
        """Robot -> the room of the last order it was sent (a robot whose task was interrupted since is not in it)."""
        return {robot: self._rooms[marker] for robot, marker in self.generator.last.items() if marker >= 0}

    @property
    def interrupted(self) -> set[int]:
        """The robots whose last order interrupted their task."""
        return {robot for robot, marker in self.generator.last.items() if marker < 0}

    def read_line(self, line: str) -> None:
        """One line of orders: ``ROOM`` or ``ROBOT ROOM`` (``ROBOT:ROOM``) sends a robot (the first one unless
        named) to a room; ``cancel`` or ``stop`` in the room's place interrupts its task, unless a room has
        that name. SchemaError or ValueError names what is wrong."""
        words = line.replace(":", " ").split()
        if not words:
            return
        if len(words) > 2:
            raise SchemaError(f"order: expected ROOM or ROBOT ROOM, got {line.strip()!r}")
        robot, room = (int(words[0]), words[1]) if len(words) > 1 else (self.world.robots[0].id, words[0])
        if room in CANCEL_WORDS and room not in self.world.rooms:
            self.cancel(robot)
        else:
            self.order(robot, room)

    def read_lines(self, stream: TextIO, on_error: Callable[[str], None]) -> threading.Thread:
        """Take orders (read_line) from `stream` as they come, in a background thread."""

        def loop() -> None:
            for line in stream:
                try:
                    self.read_line(line)
                except (SchemaError, ValueError) as e:
                    on_error(str(e))

        thread = threading.Thread(target=loop, name="vwg-orders", daemon=True)
        thread.start()
        return thread


@dataclass
class RobotSummary:
    id: int
    room: str | None       # the last room ordered
    reached: bool          # the robot says it reached that room (its pose within the world's goal_tolerance)
    distance_to_goal_m: float
    path_length_m: float   # metres driven (true)
    collisions: int
    replans: int
    commands: int
    status: str            # the robot's last status, rooms by name ("arrived at kitchen", "no path to lab")
    pose_error_m: float | None = None  # how far its believed pose is from the truth (None: no truth, a real robot)
    interrupted: bool = False  # its last order interrupted its task (room is then None: it is not waited for)


@dataclass
class RunSummary:
    world: str
    planner: str
    reached: bool          # every robot that had an order reached its last room (true when none had one)
    frames: int
    simulated_time_s: float
    wall_time_s: float
    path_length_m: float
    collisions: int
    replans: int
    seed: int
    robots: list[RobotSummary] = field(default_factory=list)
    outputs: dict[str, str] = field(default_factory=dict)
    faults: list[dict[str, Any]] = field(default_factory=list)  # a real robot's: watchdog stops, a lost link
    pose_error_m: float | None = None  # the robots' mean distance from belief to truth (None: no truth)

    def to_json(self) -> dict[str, Any]:
        import dataclasses

        return dataclasses.asdict(self)


class CaseStudy:
    """A robot world ready to run: ``engine``, ``sim``, ``orders``; ``run()`` gives a RunSummary.

    ``planner`` names the decider (or is one); ``goals`` are orders at the start, which replace the
    world file's timed orders unless ``world_orders=True`` (``False``: no timed orders); ``sensors`` the
    kinds of sensors to make among those each robot lists (default all; it selects, it does not add:
    a robot without a Kinect in the world file gets none; sensors come from vwg.plugins.sensors);
    ``video``/``images`` record a view; ``backends`` adds backends after the simulator (or factories
    given the Simulation);
    ``knows_map=False`` starts the robots with empty grids (eq. 13); ``known_map`` is the map they start
    with instead of the world's (the world changed since it was drawn: they find out with their sensors);
    ``platform`` names where the
    robots run (default: the world file's ``platform``, the simulator); ``threads`` (0: the machine's
    cores) run the robots' lasers and decisions side by side, with the same frames for any count."""

    def __init__(self, world: RobotWorld, planner: str | _core.Decider = "astar", *,
                 goals: Mapping[int, str] | None = None, seed: int | None = None, frames: int | None = None,
                 sensors: Iterable[str] | None = None, video: str | Path | None = None,
                 images: str | Path | None = None, view_width: int = 800, max_symbols: int = 0, threads: int = 0,
                 world_orders: bool | None = None, knows_map: bool = True, known_map: OccupancyGrid | None = None,
                 backends: Iterable[_core.Backend | Callable[[Simulation], _core.Backend]] = (),
                 platform: str | PlatformSpec | None = None, localization: str | Localization | None = None,
                 avoidance: str | Avoidance | None = None) -> None:

        # A world made in Python (or changed with dataclasses.replace) is checked as a world file is: a
        # frame time of 5e-324 s would make an order's frame number (time / dt) overflow.
        _core.check_dt(world.dt, "dt")
        for order in world.orders:
            if not (math.isfinite(order.time) and 0 <= order.time <= MAX_TIME):
                raise SchemaError(f"orders: expected a time from 0 to {MAX_TIME:g} seconds, got {order.time!r}")
        self.world = world
        self.knows_map = knows_map
        if known_map is not None and known_map.data.shape != world.grid.data.shape:
            raise SchemaError(f"known_map: expected a map of the world's size {world.grid.data.shape}, "
                              f"got {known_map.data.shape}")
        self.known_map = world.grid if known_map is None else known_map
        self.localization = world.localization if localization is None else Localization.of(localization)
        self.avoidance = world.avoidance if avoidance is None else Avoidance.of(avoidance)
        self.seed = world.seed if seed is None else seed
        self.frames = world.frames if frames is None else frames
        self.decider = make_decider(planner)
        self.planner = planner if isinstance(planner, str) else self.decider.name
        self.vworld = case_study_world(world, self.decider, avoidance=self.avoidance)
        alphabet = self.vworld.alphabet
        # The platform by name (the world file's, or `platform`): the simulator unless said otherwise.
        spec = world.platform if platform is None else PlatformSpec(platform) if isinstance(platform, str) else platform
        self.sim = platforms.create(spec.kind, world, self.seed, dict(spec.options))
        try:
            self.orders = Orders(world, alphabet)
            # The world file's timed orders play unless orders are given here (or world_orders says).
            if world_orders is None:
                world_orders = not goals
            for order in world.orders if world_orders else ():
                self.orders.schedule(math.ceil(order.time / world.dt - 1e-9), order.robot, order.room)
            for robot, room in (goals or {}).items():
                self.orders.schedule(0, robot, room)
            kinds = None if sensors is None else tuple(sensors)
            sensing = self.sim.make_sensors(alphabet, kinds)  # first: the localization reads the lasers
            #: The generators of the robots' poses (odometry, or localization) and collisions.
            self.feedback = self.sim.feedback(alphabet, self.localization, self.known_map if knows_map else None,
                                              self.avoidance)
            # People who walk: pushed by gSocial from where the simulator has everyone when the frame begins, put on
            # the simulator by the people's backend (φ of Pedestrian).
            walking: list[Any] = []
            people_backend: list[_core.Backend] = []
            if world.people:
                if not isinstance(self.sim, Simulation):
                    raise SchemaError(f"people: people walk on the simulator only (the platform is {self.sim.name})")
                walking = [_core.SocialForceGenerator(self.sim.physics, _core.SocialForceSettings(), alphabet)]
                people_backend = [_core.PeopleBackend(self.sim.physics, alphabet)]
            generators: list[Any] = [*self.feedback, *walking, *sensing, self.orders.generator, every_frame("eDecide"),
                                     every_frame("eExecute")]
            # The view draws what θ shows of the robots (their actions, paths and status lines) through π
            # and φ, and keeps the trajectories; without video or images it draws nothing.
            self.view: _core.SimView = self.sim.view(width=view_width, video=str(video) if video else None,
                                                     images=str(images) if images else None)
            # Extra backends (after the simulator): ready ones, or factories given the simulation.
            shown = [self.view, *(b if isinstance(b, _core.Backend) else b(self.sim) for b in backends)]
            # The platform's motion backend first (it moves the robots), then what shows them.
            backend = _core.BackendGroup([self.sim.backend, *people_backend, *shown])
            self.engine = Engine(self.vworld, self.initial_string(), generators, backend, dt=world.dt, seed=self.seed,
                                 max_symbols=max_symbols, threads=threads)
            # Done when every robot sent somewhere is there: checked in C++ after each frame.
            self.engine.stop_when(_core.ArrivalCondition(alphabet, self.orders.generator))
            # A robot a λ spawns gets a body on the platform; one that leaves the string loses it.
            self.engine.keep_robots_in_step(self.sim.platform,
                                            radius=max((r.radius for r in world.robots), default=_DEFAULT_RADIUS))
            self.video = str(video) if video else None
            # The video is finished by close(), or at the latest when this object goes or Python exits.
            self._hold = max(1, round(1.0 / world.dt))
            self._finish = weakref.finalize(self, self.view.finish, self._hold)
        except BaseException:
            # A real robot's link is open now: nothing may leave it so.
            close = getattr(self.sim, "close", None)
            if callable(close):
                close()
            raise
        self._closed = False
        self.wall_time = 0.0

    def initial_string(self) -> _core.String:
        """Eq. 13: ARobot<grid, row, column, angle, ε, ε> per robot, its grid the known map (or,
        with knows_map=False, all free: the robot learns the walls from its sensors)."""

        parts = []
        # One map for all: a robot's first write copies it, sharing the pages it does not change.
        grid = _core.robot_map(self.known_map, self.knows_map)
        for robot in self.world.robots:
            x, y, yaw = robot.start
            row, col = self.world.grid.world_to_cell(x, y)
            parts.append(Sym("ARobot", id=robot.id, grid=grid, row=row, column=col, angle=float(yaw), x=float(x),
                             y=float(y), avoid=self.avoidance.avoids(robot.id)))
        for person in self.world.people:
            goals = _core.Blob(np.array(person.goals, dtype=np.float64).reshape(-1, 2))
            parts.append(Sym("Person", id=person.id, x=person.start[0], y=person.start[1], radius=person.radius,
                             speed=person.speed, goals=goals, loop=person.loop, wander=person.wander))
        return self.vworld.string(*parts)

    def sensed_pose(self, robot: int) -> tuple[float, float, float]:
        """The pose robot `robot` was last told it has (its eOdometry): its localization's estimate, or its
        odometry. Its belief in the string is this moved on by the step it decided, while it drives."""
        for g in self.feedback:
            if isinstance(g, _core.LocalizationGenerator) and g.robot == robot:
                estimate = g.estimate()
                if estimate is not None:
                    return estimate
        return self.sim.robot(robot).odometry

    def robot_actors(self, w: _core.String | None = None) -> dict[int, _core.Node]:
        w = self.engine.string if w is None else w
        return {a["id"]: a for a in w.actors() if a.name == "ARobot"}

    def status_of(self, robot: int, actor: _core.Node, last: dict[int, str] | None = None) -> str:
        """The robot's status with its room by name ("to kitchen" rather than "to marker 1");
        `last` is orders.last if the caller has it already (it is made afresh on each call)."""
        room = (self.orders.last if last is None else last).get(robot)
        status = str(actor["status"])
        return status.replace(f"marker {actor['objective']}", room) if room else status

    def run(self, frames: int | None = None, progress: bool | None = False) -> RunSummary:
        """Run up to `frames` frames (default the world's), stopping early when every order is
        reached. A later run() continues the same run: the same video, record and trajectories."""
        if self._closed:
            raise SchemaError("CaseStudy.run: this run is closed (its video is finished); make a new CaseStudy")
        start = time.perf_counter()
        try:
            self.engine.run(self.frames if frames is None else frames, progress=progress)
        finally:
            self.wall_time += time.perf_counter() - start
        return self.summary()

    def close(self) -> None:
        """Finish the video: its last second shows the final state (arrivals included). Done at
        exit too, and by ``with CaseStudy(...) as run:``; running again after close() is an error."""
        if not self._closed and self._finish.alive:
            self._finish.detach()
            # The end shows the state reached: π of the last string (an arrival decided in the last frame).
            final = _core.visualize(self.engine.string, [self.vworld.event("eExecute")])
            self.view.finish(self._hold, final)
        if not self._closed:
            # A real robot is sent a stop before its link closes, however the run ended.
            close = getattr(self.sim, "close", None)
            if callable(close):
                close()
        self._closed = True

    def __enter__(self) -> CaseStudy:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def summary(self) -> RunSummary:
        actors = self.robot_actors()
        last = self.orders.last  # once: it is made from the generator on each call
        interrupted = self.orders.interrupted
        robots = []
        for spec in self.world.robots:
            # None: a λ took it out of the string, and the platform its body (what it drove went with it).
            state = self.sim.platform.find_robot(spec.id)
            room = last.get(spec.id)
            dist = math.inf
            if room is not None and state is not None:
                gx, gy = self.world.rooms[room].goal
                dist = math.hypot(state.pose[0] - gx, state.pose[1] - gy)
            actor = actors.get(spec.id) if state is not None else None
            error = (math.hypot(float(actor["x"]) - state.pose[0], float(actor["y"]) - state.pose[1])
                     if actor is not None and state is not None and self.sim.ground_truth else None)
            # One definition of "reached": the robot's own (ARobot, the world's goal_tolerance).
            reached = room is not None and actor is not None and bool(actor["reached"])
            robots.append(RobotSummary(
                id=spec.id, room=room, reached=reached, distance_to_goal_m=dist,
                path_length_m=state.travelled if state is not None else 0.0,
                collisions=int(state.collisions) if state is not None else 0,
                replans=int(actor["replans"]) if actor is not None else 0,
                commands=int(state.commands) if state is not None else 0,
                status=self.status_of(spec.id, actor, last) if actor is not None else "gone", pose_error_m=error,
                interrupted=spec.id in interrupted))
        ordered = [r for r in robots if r.room is not None]
        errors = [r.pose_error_m for r in robots if r.pose_error_m is not None]
        outputs = {"video": self.video} if self.video else {}
        return RunSummary(
            world=self.world.name, planner=self.planner, reached=all(r.reached for r in ordered),
            # frames × dt to what dt's digits hold: 30.7 s, not 30.700000000000003
            frames=self.engine.frame, simulated_time_s=round(self.engine.time, 9), wall_time_s=self.wall_time,
            path_length_m=sum(r.path_length_m for r in robots), collisions=sum(r.collisions for r in robots),
            replans=sum(r.replans for r in robots), seed=self.seed, robots=robots, outputs=outputs,
            faults=[f.to_json() for f in getattr(self.sim.platform, "faults", [])],
            pose_error_m=sum(errors) / len(errors) if errors else None)

    def save_trajectory(self, path: str | Path) -> None:
        """A PNG of the map with every robot's trajectory (full strength, no fading), its start
        (a hollow square) and final pose (a disc), the rooms, and a legend of where each went."""
        style = _core.RenderStyle()
        style.trajectory_fade = 1  # a summary picture: the whole trajectory at full strength
        style.trajectory_faint = 1.0
        style.trajectory_px = 3
        renderer = _core.TopDownRenderer(self.world.grid, width=900, header=40, style=style)
        renderer.begin(frame=self.engine.frame, time=self.engine.time, status=f"{self.world.name}: {self.planner}")
        for room in self.world.rooms.values():
            renderer.draw_marker(room.at[0], room.at[1], room.facing, room.name, room.marker)
        for rid, points in self.view.trajectories.items():
            renderer.draw_trajectory(points, rid)
        legend = []
        for robot, spec in zip(self.summary().robots, self.world.robots, strict=True):
            renderer.draw_start(spec.start[0], spec.start[1], spec.id)
            if (state := self.sim.platform.find_robot(spec.id)) is not None:
                renderer.draw_robot(state.pose, spec.radius, spec.id)
            state = "reached" if robot.reached else "not reached"
            where = ("interrupted" if robot.interrupted else "no order" if robot.room is None
                     else f"{robot.room}, {state}")
            legend.append((spec.id, f"robot {spec.id}: {where}, {robot.path_length_m:.1f} m"))
        renderer.draw_legend(legend)
        path = Path(path)
        encoding = TRAJECTORY_FORMATS.get(path.suffix.lower())
        if encoding is None:
            raise Error(trajectory_type_error(path))
        data = _core.encode_image(renderer.image(), format=encoding)
        try:  # written here, not by the renderer, so that a full disk is said with the system's reason
            path.write_bytes(data)
        except OSError as e:
            raise Error(f"{path}: {e.strerror}: the trajectory picture could not be written") from None


#: File extensions a trajectory picture is written as, and the encoding each means.
def _check_record_map(header: dict[str, Any], world: RobotWorld, record_path: Path) -> None:
    """A record replays only on a world whose map has its robots' map's shape (another world's ran to
    frame 0 and failed there, exit 1): Error naming both shapes, before anything runs."""
    import re

    found = re.search(r"\bgrid=@([0-9a-f]+)", str(header.get("initial", "")))
    blob = (header.get("blobs") or {}).get(found.group(1)) if found else None
    shape = blob.get("shape") if isinstance(blob, dict) else None
    if not (isinstance(shape, list) and len(shape) == 2):
        return  # no robot map in the record to compare (the replay says what is wrong, if anything)
    rows, cols = shape
    if (rows, cols) != (world.grid.height, world.grid.width):
        raise Error(f"{world.path}: its map is {world.grid.width}×{world.grid.height} cells; the record "
                    f"{record_path} was made on a map of {cols}×{rows} cells (another world's)")


def _stderr(message: str) -> None:
    print(f"vwg: {message}", file=sys.stderr)


# ---- the robot kind of world file (vwg.launch) -----------------------------------------------------------
def _goals(values: list[str] | None, robots: list[int]) -> dict[int, str]:
    goals: dict[int, str] = {}
    for value in values or []:
        robot, _, room = value.rpartition(":")
        try:
            goals[int(robot) if robot else robots[0]] = room
        except ValueError:
            raise SchemaError(f"--goal: expected ROOM or ROBOT:ROOM, got '{value}'") from None
    return goals


class RobotRun:
    """A robot world started from run options (vwg.launch): the CaseStudy, and what the outcome says."""

    def __init__(self, world: RobotWorld, options: Any) -> None:
        import dataclasses


        if options.dt is not None:
            world = dataclasses.replace(world, dt=options.dt)
        self.world = world
        self.options = options
        shown = [lambda sim: backend_registry.create(options.backend, world=None)] if options.backend else []
        goals = _goals(options.goals, [r.id for r in world.robots])
        # The platform: the world file's, or the one named, with the options given over the file's.
        spec = world.platform.given(options.platform, **options.platform_options)
        self.case = CaseStudy(world, options.planner or world.planner, goals=goals,
                              platform=spec, seed=options.seed, frames=options.frames, video=options.video,
                              images=options.images, max_symbols=options.max_symbols, threads=options.threads,
                              backends=shown, avoidance=options.avoidance,
                              world_orders=False if options.no_world_orders else None)
        self.engine = self.case.engine
        # What a record needs to run this again (vwg replay, and --from, which re-runs it live). Not
        # the platform: the same world on the simulator and on a robot makes the same record (test 3).
        self.record_data: dict[str, Any] = {"robot_world": str(Path(world.path).resolve()),
                                            "planner": self.case.planner,
                                            "world_orders": not (options.no_world_orders or goals),
                                            "goals": list(options.goals or [])}  # vwg replay --from gives them again
        if options.avoidance is not None:
            self.record_data["avoidance"] = options.avoidance
        # The run as ROS 2 topics (vwg.robot.topics): to an MCAP file, to Foxglove live, or both. The sinks open
        # now (a port taken is said before anything runs); the topics begin when the run does (after a resumed
        # run's state is loaded).
        self.sinks: list[Sink] = []
        self.topics: RunTopics | None = None
        if options.mcap is not None or options.foxglove_port is not None:
            try:
                self.sinks = open_sinks(options.mcap, options.foxglove_port, options.foxglove_host,
                                        {"world": world.name, "planner": self.case.planner,
                                         "seed": str(self.case.seed)}, world=world,
                                        ground_truth=self.case.sim.ground_truth)
            except BaseException:
                self.case.close()
                raise
        if options.stdin_orders:
            self.case.orders.read_lines(sys.stdin, _stderr)

    kind = "robot"

    def execute(self, progress: bool | None = False) -> Any:

        if self.sinks and self.topics is None:
            self.topics = case_topics(self.case, self.sinks)
        link_fault = ""
        try:
            summary = self.case.run(progress=progress)
        except FrameError as e:
            if not isinstance(e.__cause__, LinkError):
                raise
            link_fault = str(e.__cause__)  # the frames up to the fault are recorded; the summary says what happened
            summary = self.case.summary()
        options = self.options
        trajectory = options.trajectory or (Path(options.video).with_suffix(".png") if options.video else None)
        if trajectory:
            self.case.save_trajectory(trajectory)
            summary.outputs["trajectory"] = str(trajectory)
        ordered = [r for r in summary.robots if r.room is not None]
        rows = [
            ("reached", ("yes" if summary.reached else "no") if ordered else "- (no robot had an order)"),
            ("frames", f"{summary.frames} ({summary.simulated_time_s:.1f} s simulated, "
                       f"{summary.wall_time_s:.1f} s wall)"),
            ("path length", f"{summary.path_length_m:.2f} m"),
            ("collisions", str(summary.collisions)),
            ("replans", str(summary.replans)),
        ]
        for r in summary.robots:
            if r.interrupted:
                where = "interrupted (its task was cancelled)"
            elif r.room is None:
                where = "no order"
            elif r.reached:
                where = f"{r.room}: reached"
            else:
                where = f"{r.room}: {r.distance_to_goal_m:.2f} m away ({r.status})"
            rows.append((f"robot {r.id}", f"{where}, {r.path_length_m:.2f} m, {r.collisions} collisions, "
                                           f"{r.replans} replans"))
        status, message = 0, ""
        for fault in summary.faults:
            rows.append(("fault", f"{fault['time_s']:.2f} s, robot {fault['robot']}: {fault['what']}"))
        if link_fault:
            status, message = EXIT_LINK_FAULT, f"the run ended on a link fault: {link_fault}"
        elif not summary.reached and not options.allow_unreached:
            missed = ", ".join(f"robot {r.id} ({r.room})" for r in summary.robots if r.room and not r.reached)
            status = EXIT_UNREACHED
            message = (f"not every order was reached: {missed}; exit status {EXIT_UNREACHED} "
                       "(--allow-unreached exits 0)")
        title = f"{self.world.name}, planner {summary.planner}, seed {summary.seed}"
        return Outcome(title, rows, summary.to_json(), status, message, summary.outputs)

    def save_state(self, path: str | Path | None = None, *, platform: bool = True) -> bytes:
        """The run's state after its last whole frame (vwg.saved_run): the string, the generators',
        deciders' and platform's states; written to `path` when given. ``platform=False``: the robots'
        beliefs, maps and planners only (a real robot's run), to go on on the simulator."""
        return save_state(self, path, platform=platform)

    def close(self) -> None:
        try:
            if self.topics is not None:
                self.topics.end()
        finally:
            sinks, self.sinks, self.topics = self.sinks, [], None
            try:
                for sink in sinks:
                    sink.close()
            finally:
                self.case.close()

    def __enter__(self) -> RobotRun:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class RobotKind:
    """World files of the case study: a map, rooms named by markers, robots, sensors, orders."""

    name = "robot"
    shape = "a mapping with map:, rooms: and robots:"
    options = frozenset({"platform", "platform_options", "planner", "avoidance", "goals", "no_world_orders",
                         "stdin_orders", "video", "images", "trajectory", "allow_unreached", "mcap", "foxglove_port",
                         "foxglove_host"})

    def matches(self, data: dict[str, Any]) -> bool:
        return "map" in data

    def matches_loaded(self, world: Any) -> bool:
        return isinstance(world, RobotWorld)

    def load(self, path: Path) -> RobotWorld:

        return load_robot_world(path)

    def start(self, world: RobotWorld, options: Any) -> RobotRun:
        return RobotRun(world, options)

    def replay_world(self, header: dict[str, Any], path: Path | None, record_path: Path, *,
                     allow_code_from_record: bool = False) -> World:

        data = robot_data(header, record_path)
        loaded = load_robot_world(path or data["robot_world"])
        _check_record_map(header, loaded, record_path)
        avoidance = Avoidance.of(data["avoidance"]) if data["avoidance"] is not None else None
        return case_study_world(loaded, make_decider(data["planner"]), avoidance=avoidance)

    def describe(self, w: RobotWorld) -> tuple[str, list[tuple[str, str]]]:
        g = w.grid
        rows = [
            ("map", f"{w.map_path.name}: {g.width}×{g.height} cells of {g.resolution:g} m "
                    f"({g.width_m:g} × {g.height_m:g} m), walls {w.wall_height:g} m high"),
            ("rooms", f"{len(w.rooms)}"),
        ]
        for name, room in w.rooms.items():
            rows.append((f"  {name}", f"marker {room.marker} at ({room.at[0]:g}, {room.at[1]:g}), "
                                      f"goal ({room.goal[0]:.2f}, {room.goal[1]:.2f})"))
        rows.append(("robots", f"{len(w.robots)}"))
        for r in w.robots:
            rows.append((f"  robot {r.id}", f"start ({r.start[0]:g}, {r.start[1]:g}, {r.start[2]:.3g} rad), radius "
                                            f"{r.radius:g} m, {r.max_speed:g} m/s, sensors: {', '.join(r.sensors)}"))
        rows += [(name, sensor_registry.get(name)(settings).describe()) for name, settings in w.sensors.items()]
        rows += [
            ("noise", f"odometry {w.noise.odometry:g}, motors {w.noise.motors:g}"),
            ("orders", "; ".join(f"{o.time:g} s: robot {o.robot} to {o.room}" for o in w.orders) or "none"),
            ("frames", f"{w.frames} (dt {w.dt:g} s, seed {w.seed})"),
            ("platform", w.platform.kind + "".join(f", {k} {v}" for k, v in w.platform.options.items())),
        ]
        if w.avoidance.kind != "none" or w.avoidance.robots:
            own = "".join(f", robot {r} {k}" for r, k in w.avoidance.robots)
            rows.append(("avoidance", f"{w.avoidance.kind}{own} (horizon {w.avoidance.settings.horizon:g} s)"))
        if w.localization.kind != "odometry":
            s = w.localization.settings
            rows.append(("localization", f"{w.localization.kind}: {s.particles} particles a robot, {s.beams} beams "
                                         f"of its laser weighed on the known map"))
        title = f"a robot world ({w.name})" + (f"\n  {w.description}" if w.description else "")
        return title, rows
