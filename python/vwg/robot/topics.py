"""A robot run as ROS 2 topics, frame by frame: what ``vwg run --mcap``, ``vwg export`` and
``--foxglove-port`` publish. Everything but the ground truth and the camera's pictures is read off the
frame as the engine's observers see it (its events and the string it made), so a record, which holds
exactly those, gives the same messages as the run did.

Per robot N (frames ``robotN/odom`` and ``robotN/base_link``):

- ``/robotN/odom``: nav_msgs/Odometry, the pose the robot believes (ARobot's x, y, angle after the
  frame), its twist the change of that belief over the frame;
- ``/robotN/scan``: sensor_msgs/LaserScan on the world's laser's beams, from the frame's eLaser events
  (+Inf where a beam met nothing, REP 117), stamped when the scan was taken (the frame's start);
- ``/robotN/plan``: nav_msgs/Path, the robot's way, when it changes;
- ``/robotN/map``: nav_msgs/OccupancyGrid, the robot's own map (what its sensors marked), when it
  changes, at most once a second of the run, and as it ends;
- ``/robotN/camera/image/compressed``: sensor_msgs/CompressedImage (JPEG), each picture its camera took;
- ``/robotN/ground_truth``: nav_msgs/Odometry in ``map``, where the simulator has the robot.

And ``/tf`` (map → robotN/odom → robotN/base_link; the belief is already in the map's frame, so
map → odom is the identity), ``/map`` (the known map, once), ``/rooms`` (visualization_msgs/MarkerArray:
a marker and its room's name, once) and ``/people`` (a cylinder per person, each frame, when people walk).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import numpy as np

import vwg._core as _core
from vwg.errors import Error
from vwg.io import ros2_messages as ros
from vwg.io.foxglove_server import FoxgloveServer
from vwg.io.mcap_file import McapFile
from vwg.robot.world_file import RobotWorld

__all__ = ["CAMERA", "GROUND_TRUTH", "MAP", "ODOM", "PEOPLE", "PLAN", "ROBOT_MAP", "ROOMS", "SCAN", "TF", "RobotTopic",
           "RunTopics", "Sink", "Topic", "case_topics", "open_sinks", "require_ros", "world_topics"]


@dataclass(frozen=True)
class Topic:
    """A topic of the run's: its name and its message type. The names live here alone: RunTopics writes them,
    world_topics declares them, the Foxglove layout shows them."""

    name: str
    type: str


@dataclass(frozen=True)
class RobotTopic:
    """A topic each robot has: ``of(robot)`` is robot `robot`'s name (``/robotN/...``)."""

    suffix: str
    type: str

    def of(self, robot: int) -> str:
        return f"/robot{robot}/{self.suffix}"


MAP = Topic("/map", "nav_msgs/msg/OccupancyGrid")
ROOMS = Topic("/rooms", "visualization_msgs/msg/MarkerArray")
PEOPLE = Topic("/people", "visualization_msgs/msg/MarkerArray")
TF = Topic("/tf", "tf2_msgs/msg/TFMessage")
ODOM = RobotTopic("odom", "nav_msgs/msg/Odometry")
PLAN = RobotTopic("plan", "nav_msgs/msg/Path")
ROBOT_MAP = RobotTopic("map", "nav_msgs/msg/OccupancyGrid")
SCAN = RobotTopic("scan", "sensor_msgs/msg/LaserScan")
CAMERA = RobotTopic("camera/image/compressed", "sensor_msgs/msg/CompressedImage")
GROUND_TRUTH = RobotTopic("ground_truth", "nav_msgs/msg/Odometry")


class Sink(Protocol):
    """Where messages go: an MCAP file, a Foxglove server."""

    def write(self, topic: str, message: ros.Message, log_time: int, latched: bool = False) -> None: ...

    def frame_done(self, log_time: int) -> None:
        """The run's state at `log_time` is written."""

    def close(self) -> None: ...


#: The robot's own map is sent at most this often (seconds of the run) while it changes.
MAP_PERIOD_S = 1.0


def _ns(seconds: float) -> int:
    return round(seconds * 1e9)


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


class RunTopics:
    """Publishes a run's frames to `sinks`: ``begin(string, time)`` once (the latched topics and the first
    poses), then ``frame(record)`` as an engine observer, then ``end()``. ``truth(robot)`` gives a robot's
    true pose (None: no truth, a real robot); ``cameras`` the camera generators by robot."""

    def __init__(self, world: RobotWorld, sinks: Iterable[Sink], *,
                 truth: Callable[[int], tuple[float, float, float] | None] | None = None,
                 cameras: Mapping[int, Any] | None = None) -> None:
        self.world = world
        self.sinks = list(sinks)
        self.truth = truth
        self.cameras = dict(cameras or {})
        # gCamera takes a picture on the frames its period divides: the world's camera settings, or their defaults.
        self.camera_period = int(world.sensor_settings("camera").period) if self.cameras else 1
        self.dt = world.dt
        self.laser = world.sensor_settings("laser")
        self.angle_min, self.increment = _core.beam_layout(self.laser)
        self.full_circle = math.isclose(self.increment * self.laser.beams, 2 * math.pi)  # the beams go all round
        self.scanning = {r.id for r in world.robots if "laser" in r.sensors}
        self._belief: dict[int, tuple[float, float, float]] = {}
        self._plans: dict[int, str] = {}
        self._maps: dict[int, str] = {}        # the robot map last sent, by blob name
        self._map_sent: dict[int, float] = {}  # when
        self._map_last: dict[int, Any] = {}    # the latest, sent or not
        self.time = 0.0

    # ---- the sinks ------------------------------------------------------------------------------------
    def _write(self, topic: str, message: ros.Message, seconds: float, latched: bool = False) -> None:
        for sink in self.sinks:
            sink.write(topic, message, _ns(seconds), latched)

    # ---- the run ---------------------------------------------------------------------------------------
    def begin(self, string: _core.String, seconds: float) -> None:
        """The known map and the rooms (latched), and the robots where the run starts."""
        g = self.world.grid
        self._write(MAP.name, ros.occupancy_grid(seconds, "map", np.asarray(g.data), g.resolution, g.origin), seconds,
                    latched=True)
        self._write(ROOMS.name, ros.marker_array(seconds, "map", self._room_markers()), seconds, latched=True)
        self._state(string, seconds, first=True)

    def frame(self, record: _core.FrameRecord) -> None:
        """An engine observer: the frame's scans (taken as it began), then the state it left."""
        start = float(record.time)
        self._scans(record, start)
        self._cameras(record, start)
        self._state(record.after, start + self.dt)

    def end(self) -> None:
        """The robots' maps as the run left them (a change held back by MAP_PERIOD_S)."""
        for robot, (name, blob) in sorted(self._map_last.items()):
            if self._maps.get(robot) != name:
                self._send_map(robot, name, blob, self.time)

    def close(self) -> None:
        for sink in self.sinks:
            sink.close()

    # ---- what a frame gives ----------------------------------------------------------------------------
    def _state(self, string: _core.String, seconds: float, first: bool = False) -> None:
        self.time = seconds
        transforms: list[tuple[str, str, tuple[float, float, float]]] = []
        people: list[ros.Marker] = []
        for actor in string.actors():
            if actor.name == "Person":
                people.append(ros.Marker("people", int(actor["id"]), ros.CYLINDER, float(actor["x"]),
                                         float(actor["y"]), 0.85, (2 * float(actor["radius"]), 1.7),
                                         (0.85, 0.7, 0.45, 1.0)))
            if actor.name != "ARobot":
                continue
            robot = int(actor["id"])
            prefix = f"robot{robot}"
            pose = (float(actor["x"]), float(actor["y"]), float(actor["angle"]))
            before = self._belief.get(robot, pose)
            self._belief[robot] = pose
            speed = turn = 0.0
            if not first:
                dx, dy = pose[0] - before[0], pose[1] - before[1]
                speed = (dx * math.cos(before[2]) + dy * math.sin(before[2])) / self.dt
                turn = _wrap(pose[2] - before[2]) / self.dt
            odom = ros.odometry(seconds, f"{prefix}/odom", f"{prefix}/base_link", pose, speed, turn)
            self._write(ODOM.of(robot), odom, seconds)
            transforms += [("map", f"{prefix}/odom", (0.0, 0.0, 0.0)), (f"{prefix}/odom", f"{prefix}/base_link", pose)]
            truth = self.truth(robot) if self.truth is not None else None
            if truth is not None:
                self._write(GROUND_TRUTH.of(robot), ros.odometry(seconds, "map", f"{prefix}/base_link", truth), seconds)
            plan = actor["path"]
            if self._plans.get(robot) != plan.name:
                self._plans[robot] = plan.name
                self._write(PLAN.of(robot), ros.path(seconds, "map", np.asarray(plan)), seconds, latched=True)
            grid = actor["grid"]
            self._map_last[robot] = (grid.name, grid)
            if self._maps.get(robot) != grid.name and seconds - self._map_sent.get(robot, -math.inf) >= MAP_PERIOD_S:
                self._send_map(robot, grid.name, grid, seconds)
        if transforms:
            self._write(TF.name, ros.tf(seconds, transforms), seconds)
        if people:
            self._write(PEOPLE.name, ros.marker_array(seconds, "map", people), seconds)
        for sink in self.sinks:
            sink.frame_done(_ns(seconds))

    def _send_map(self, robot: int, name: str, grid: Any, seconds: float) -> None:
        g = self.world.grid
        self._maps[robot] = name
        self._map_sent[robot] = seconds
        self._write(ROBOT_MAP.of(robot), ros.occupancy_grid(seconds, "map", np.asarray(grid), g.resolution, g.origin),
                    seconds, latched=True)

    def _scans(self, record: _core.FrameRecord, seconds: float) -> None:
        if not self.scanning:
            return
        beams = int(self.laser.beams)
        ranges = {robot: np.full(beams, np.inf, np.float32) for robot in self.scanning}
        for run in record.event_runs(1):
            if not (isinstance(run, tuple) and run[0] == "eLaser" and run[2] is not None):
                continue
            _, _, targets, fields = run
            columns = {name: column for name, _, column in fields}
            index = np.rint((np.asarray(columns["angle"]) - self.angle_min) / (self.increment or 1.0)).astype(np.int64)
            # A full circle's beams wrap round; a narrower laser's do not: a real robot's hit placed from where
            # it was when the scan was taken (RealRobotPlatform.viewpoint) may fall outside the arc now.
            on_arc = np.ones(index.shape, bool) if self.full_circle else (index >= 0) & (index < beams)
            index %= beams
            for robot, out in ranges.items():
                mine = (np.asarray(targets) == robot) & on_arc
                out[index[mine]] = np.asarray(columns["dist"])[mine]
        for robot in sorted(ranges):
            self._write(SCAN.of(robot),
                        ros.scan(seconds, f"robot{robot}/base_link", self.angle_min, self.increment, ranges[robot],
                                 self.laser.min_range, self.laser.max_range, self.dt), seconds)

    def _cameras(self, record: _core.FrameRecord, seconds: float) -> None:
        if record.frame % self.camera_period:
            return
        for robot, camera in sorted(self.cameras.items()):
            image = camera.image
            if image is not None:
                jpeg = _core.encode_image(np.asarray(image), format="jpeg")
                self._write(CAMERA.of(robot),
                            ros.compressed_image(seconds, f"robot{robot}/camera", jpeg, "jpeg"), seconds)

    def _room_markers(self) -> list[ros.Marker]:
        out = []
        for i, (name, room) in enumerate(self.world.rooms.items()):
            out.append(ros.Marker("markers", i, ros.CYLINDER, room.at[0], room.at[1], room.height / 2,
                                  (room.size, room.height), (0.2, 0.4, 0.9, 1.0)))
            out.append(ros.Marker("names", i, ros.TEXT, room.goal[0], room.goal[1], 1.0, (0.0, 0.5),
                                  (1.0, 1.0, 1.0, 1.0), text=name))
        return out


def case_topics(case: Any, sinks: Iterable[Sink]) -> RunTopics:
    """RunTopics for a run (a vwg.robot.CaseStudy, a layer above this one), observing its engine from its next
    frame: the simulator's truth (none on a real robot) and the robots' cameras."""
    sim = case.sim

    def truth(robot: int) -> tuple[float, float, float] | None:
        if not sim.ground_truth:
            return None
        state = sim.platform.find_robot(robot)  # None: gone from the platform
        return tuple(state.pose) if state is not None else None  # type: ignore[return-value]

    cameras = {g.robot: g for g in sim.made if isinstance(g, _core.CameraGenerator)}
    topics = RunTopics(case.world, sinks, truth=truth, cameras=cameras)
    topics.begin(case.engine.string, case.engine.time)
    case.engine.add_observer(topics.frame)
    return topics


def world_topics(world: RobotWorld, *, ground_truth: bool = True) -> dict[str, ros.Schema]:
    """Every topic a run of `world` may publish (RunTopics), with its message type: a live server declares them
    before it takes clients. `ground_truth`: whether the platform knows where its robots are (the simulator)."""
    topics = [MAP, ROOMS, TF, *([PEOPLE] if world.people else [])]
    named = {t.name: ros.schema(t.type) for t in topics}
    for robot in world.robots:
        mine = [ODOM, PLAN, ROBOT_MAP, *([SCAN] if "laser" in robot.sensors else []),
                *([CAMERA] if "camera" in robot.sensors else []), *([GROUND_TRUTH] if ground_truth else [])]
        named |= {t.of(robot.id): ros.schema(t.type) for t in mine}
    return named


def require_ros(*modules: str) -> None:
    """Error naming the extra to install when a module of the ros extra is missing."""
    import importlib.util

    missing = [m for m in modules if importlib.util.find_spec(m) is None]
    if missing:
        raise Error(f"ROS 2 topics (--mcap, vwg export, --foxglove-port) need {', '.join(missing)}: "
                    "pip install 'vwg[ros]'")


def open_sinks(mcap: str | Path | None, foxglove_port: int | None, host: str = "127.0.0.1",
               metadata: Mapping[str, str] | None = None, world: RobotWorld | None = None,
               ground_truth: bool = True) -> list[Sink]:
    """The sinks asked for: an MCAP file, a Foxglove server (either may be None). The topics of a run of `world`
    (world_topics, with `ground_truth`) are declared to the server before it takes clients."""
    needs = (["mcap", "rosbags"] if mcap is not None else []) + (["foxglove"] if foxglove_port is not None else [])
    require_ros(*needs)
    sinks: list[Sink] = []
    if mcap is not None:
        sinks.append(McapFile(mcap, dict(metadata or {})))
    if foxglove_port is not None:
        try:
            topics = world_topics(world, ground_truth=ground_truth) if world is not None else None
            sinks.append(FoxgloveServer(foxglove_port, host, topics=topics))
        except BaseException:
            for sink in sinks:
                sink.close()
            raise
    return sinks
