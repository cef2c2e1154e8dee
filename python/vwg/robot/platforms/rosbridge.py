"""Robots behind a rosbridge v2 server (ROS 1 or ROS 2): the platform ``rosbridge`` of world files
and ``vwg run --platform rosbridge --url ws://HOST:PORT``.

    platform:
      kind: rosbridge
      url: ws://192.168.1.10:9090
      watchdog: 0.5        # seconds without odometry before a robot is stopped
      reconnect: 5         # seconds a lost link is retried before the run ends
      flap_limit: {drops: 3, seconds: 10}  # more drops than this within the seconds end the run
      topics: {cmd_vel: /cmd_vel, odom: /odom, scan: /scan, camera: /camera/image/compressed}
      ros: 1               # 2: type names spelled pkg/msg/Name (rosbridge for ROS 2 takes both)
      control_rate: 20     # Hz: velocities sent between frames
      lockstep: /vwg/step  # a simulated robot stepped by vwg (see below); default: none, wall-clock

Topic names default to ``/cmd_vel``, ``/odom``, ``/scan`` and ``/camera/image/compressed`` for one
robot and to ``/robot{id}/...`` for several; a name may hold ``{id}``. vwg publishes
geometry_msgs/Twist and reads nav_msgs/Odometry, sensor_msgs/LaserScan and
sensor_msgs/CompressedImage (type names in the ROS 1 spelling unless ``ros: 2``; headers' stamps are
read in both spellings).

``lockstep: SERVICE`` is for a robot that is itself simulated and advances its clock on request:
each control tick publishes the velocities, then calls SERVICE with ``{"seconds": period, "step_id":
"<run>:<n>"}`` and waits (up to ``watchdog`` seconds) for its response, by which time the robot has
published its odometry and scan after the step. With ``control_rate`` equal to the simulator's rate
(100 Hz for its 0.01 s step), the frames are those of ``--platform sim`` bit for bit (noise off).
When the link drops before a step is answered, the velocities and the step go again over the next
connection with the same ``step_id``: a service that has done that step already must not do it again
but publish where the robot is and answer with the id (``{"time": t, "step_id": id}``), as the
servers of vwg.testing do; vwg ends the run instead when the service's answers echo no ``step_id``.
The link's keepalive waits for a pong as long as for a step (``watchdog``): a robot busy stepping is
not a lost link (one that closes or crashes is seen at once).

Every drop of the link and every reconnection is a fault in the run's summary, with its time; after
a reconnection the robots are sent only stops until odometry has come over the new connection (not in
lockstep, where the robot has not moved: above); a link that drops more than ``flap_limit.drops`` times
within ``flap_limit.seconds`` ends the run (exit status 4), as one that stays away longer than
``reconnect`` seconds does.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, ClassVar

import vwg._core as _core
from vwg.errors import SchemaError
from vwg.robot.links.ros_messages import compressed_image, laser_scan, odometry, twist_message
from vwg.robot.links.rosbridge_client import RosbridgeLink
from vwg.robot.platform import Option
from vwg.robot.platforms.real_robot import LINK_OPTIONS, FlapLimit, RealRobotPlatform
from vwg.robot.platforms.real_robots import RealRobots

__all__ = ["DEFAULT_TOPICS", "RosbridgePlatform", "topics_for"]

DEFAULT_TOPICS = {"cmd_vel": "/cmd_vel", "odom": "/odom", "scan": "/scan", "camera": "/camera/image/compressed"}
TYPES = {"cmd_vel": "geometry_msgs/Twist", "odom": "nav_msgs/Odometry", "scan": "sensor_msgs/LaserScan",
         "camera": "sensor_msgs/CompressedImage"}


def _ros_version(value: int) -> int:
    if value not in (1, 2):
        raise SchemaError(f"platform.ros: expected 1 or 2 (how type names are spelled), got {value!r}")
    return value


#: The options of the platform rosbridge (world file's platform:, --platform-opt), with their defaults.
OPTIONS: dict[str, Option] = {
    "url": Option(str, required=True, help="ws://HOST:PORT, or --url"),
    "topics": Option(dict, help="topic names by key (cmd_vel, odom, scan, camera); {id} is the robot's id"),
    "ros": Option(int, 1, help="1 or 2: how message type names are spelled", convert=_ros_version),
    "lockstep": Option(str, help="a service the frames wait on, for a simulated robot run in step"),
    **LINK_OPTIONS,
}


def topics_for(robot: int, several: bool, topics: dict[str, str] | None = None) -> dict[str, str]:
    """The topics of one robot: the given names (``{id}`` replaced), else the defaults, under
    ``/robot{id}`` when there are several robots."""
    out = {}
    for key, default in DEFAULT_TOPICS.items():
        name = (topics or {}).get(key) or (f"/robot{{id}}{default}" if several else default)
        out[key] = name.replace("{id}", str(robot))
    return out


class RosbridgePlatform(RealRobotPlatform):
    """The robots of a world on one rosbridge server."""

    kind = "rosbridge"

    def __init__(self, robots: list[_core.RobotSettings], url: str, *, topics: dict[str, str] | None = None,
                 ros: int = OPTIONS["ros"].default, watchdog: float = OPTIONS["watchdog"].default,
                 reconnect: float = OPTIONS["reconnect"].default, control_rate: float = OPTIONS["control_rate"].default,
                 lockstep: str | None = None, flap_limit: FlapLimit | dict[str, Any] | None = None) -> None:
        self.link: RosbridgeLink | None = None
        unknown = set(topics or {}) - set(DEFAULT_TOPICS)
        if unknown:
            raise SchemaError(f"platform.topics: unknown topic key(s) {', '.join(sorted(unknown))} "
                              f"(known: {', '.join(DEFAULT_TOPICS)})")
        if ros not in (1, 2):
            raise SchemaError(f"platform.ros: expected 1 or 2 (how type names are spelled), got {ros!r}")
        # ROS 2 spells message types pkg/msg/Name; rosbridge for ROS 2 takes both, ROS 1 only pkg/Name.
        self.types = {k: v.replace("/", "/msg/") if ros == 2 else v for k, v in TYPES.items()}
        if not (math.isfinite(reconnect) and reconnect >= 0):
            raise SchemaError(f"platform.reconnect: expected seconds >= 0, got {reconnect}")
        several = len(robots) > 1
        self.topics = {r.id: topics_for(r.id, several, topics) for r in robots}
        self._by_topic: dict[str, tuple[str, int]] = {}
        for rid, named in self.topics.items():
            for key, topic in named.items():
                if topic in self._by_topic:
                    other = self._by_topic[topic]
                    raise SchemaError(f"platform.topics: robots {other[1]} and {rid} would share {topic} "
                                      "(with several robots, put {id} in the topic names)")
                self._by_topic[topic] = (key, rid)
        if lockstep is not None and (not isinstance(lockstep, str) or not lockstep.startswith("/")):
            raise SchemaError(f"platform.lockstep: expected a service name such as /vwg/step, got {lockstep!r}")
        self.step_service = lockstep
        super().__init__(robots, watchdog=watchdog, control_rate=control_rate, lockstep=lockstep is not None,
                         flap_limit=flap_limit)
        # Each robot's latest camera image, decoded when its gCamera asks (sensor_msgs/CompressedImage).
        # Its tags are placed from where the robot was when the image was taken (RealRobotPlatform.viewpoint).
        self.images = {r.id: _core.ReceivedImages(self.viewpoint_of(r.id)) for r in robots if "camera" in r.sensors}
        # In lockstep the robot's clock stands still until it is stepped: a pong may take as long as a step.
        self.link = RosbridgeLink(url, on_message=self._on_message, on_state=self._on_link_state, reconnect=reconnect,
                                  ping_timeout=watchdog if lockstep else None)
        self.link.connect()
        for rid, named in self.topics.items():
            self.link.advertise(named["cmd_vel"], self.types["cmd_vel"])
            self.link.subscribe(named["odom"], self.types["odom"])
            sensors = next(r.sensors for r in robots if r.id == rid)
            if "laser" in sensors:
                self.link.subscribe(named["scan"], self.types["scan"])
            if "camera" in sensors:
                self.link.subscribe(named["camera"], self.types["camera"])
        if self.step_service:
            self._step([], 0.0)  # the robot says where it is before the first frame

    def _on_message(self, topic: str, msg: Any) -> None:
        key, robot = self._by_topic.get(topic, ("", 0))
        if key == "odom":
            self.on_odometry(robot, odometry(msg))
        elif key == "scan":
            self.on_scan(robot, laser_scan(msg))
        elif key == "camera" and robot in self.images:
            image = compressed_image(msg)
            self.images[robot].push(image.data, image.time)

    def _on_link_state(self, connected: bool, detail: str) -> None:
        # On the link's thread, before any message of a new connection: its odometry is stamped with it.
        if self.link is None:
            return
        if connected:
            self.link_up(self.link.connection)
        else:
            self.link_down(detail)

    def send_velocity(self, robot: int, speed: float, turn_rate: float, *, connection: int | None = None) -> bool:
        topics = self.topics.get(robot)
        if topics is None or self.link is None:
            return False
        return self.link.publish(topics["cmd_vel"], twist_message(speed, turn_rate), connection=connection)

    def step_clock(self, seconds: float, step_id: str, connection: int | None) -> bool:
        assert self.link is not None and self.step_service is not None
        values = self.link.call_service(self.step_service, {"seconds": seconds, "step_id": step_id},
                                        timeout=self.watchdog, connection=connection)
        return isinstance(values, dict) and values.get("step_id") == step_id

    def wait_link(self, timeout: float) -> bool:
        assert self.link is not None
        return self.link.wait_connected(timeout)

    def link_failure(self) -> str | None:
        return self.link.failed if self.link is not None else None

    def close_link(self) -> None:
        if self.link is not None:
            self.link.close()

    def name(self) -> str:
        return "rosbridge"




class Rosbridge(RealRobots):
    """The platform ``rosbridge``: the world's robots behind a rosbridge v2 server (ROS 1 or 2)."""

    name = "rosbridge"
    summary = "robots behind a rosbridge v2 server (ROS 1 or ROS 2): Twist out; Odometry, LaserScan, images in"
    options: ClassVar[dict[str, Option]] = OPTIONS

    def __init__(self, world: Any, seed: int, options: Mapping[str, Any]) -> None:
        super().__init__(world, seed, options)
        given = {k: v for k, v in self.settings.items() if v is not None and k != "url"}
        self.attach(RosbridgePlatform(list(world.robots), self.settings["url"], **given))
