"""A fake ROS robot behind a rosbridge v2 server on 127.0.0.1, for tests and demos: it takes
geometry_msgs/Twist on each robot's ``cmd_vel``, moves the robots as differential-drive bases
(their world-file limits, stopped by walls) on the world's map, and publishes nav_msgs/Odometry
(from zero where each robot starts, as a real base does) and sensor_msgs/LaserScan (the walls,
by vwg's ray caster) at ``rate`` Hz, and sensor_msgs/CompressedImage (the simulator's camera view,
JPEG) at 10 Hz, as a real robot's rosbridge server would.

    with FakeRosbridgeRobot(world) as robot:          # serves ws://127.0.0.1:<free port>
        vwg.start(world, vwg.RunOptions(platform="rosbridge", url=robot.url, goals=["kitchen"])).execute()

A base stops by itself when no command has come for ``cmd_timeout`` seconds, as real bases do.
For fault tests: ``cut()`` closes every connection and refuses new ones until ``restore()``;
``silence(robot)`` stops its odometry until ``speak(robot)``. ``commands[robot]`` lists the
(time, speed, turn rate) of every Twist received, the time on the server's monotonic clock.
"""

from __future__ import annotations

import asyncio
import http
import json
import math
import threading
import time
from typing import Any

import numpy as np

from . import _core
from .robotworld import RobotWorld
from .ros_messages import compressed_image_message, odometry_message, scan_message, twist_of
from .rosbridge_platform import topics_for

__all__ = ["FakeRosbridgeRobot"]


class _Base:
    def __init__(self, settings: _core.RobotSettings) -> None:
        self.settings = settings
        self.pose = tuple(settings.start)  # true pose, world frame
        self.speed = self.turn_rate = 0.0  # commanded
        self.commanded_at = 0.0            # monotonic time of the last command
        self.silent = False


class FakeRosbridgeRobot:
    def __init__(self, world: RobotWorld, *, rate: float = 50.0, ros2: bool = False, cmd_timeout: float = 0.5,
                 odom_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        self.world = world
        # Where each base's odometry count stood when vwg connected (a base that has run before).
        self.odom_offset = odom_offset
        self.cmd_timeout = cmd_timeout  # a base stops by itself when commands stop coming (as real ones do)
        self.rate = rate
        self.ros2 = ros2
        several = len(world.robots) > 1
        self.robots = {r.id: _Base(r) for r in world.robots}
        self.topics = {r.id: topics_for(r.id, several) for r in world.robots}
        self.commands: dict[int, list[tuple[float, float, float]]] = {r.id: [] for r in world.robots}
        self.raycaster = _core.GridRaycaster(world.grid)
        laser = world.laser
        self.angles = np.linspace(-laser.fov / 2, laser.fov / 2, laser.beams) if laser.fov < 2 * math.pi - 1e-9 else \
            -math.pi + 2 * math.pi * np.arange(laser.beams) / laser.beams
        # The robots' cameras: the simulator's renderer, JPEG-compressed, every `camera_every` ticks.
        self.camera = _core.CameraRenderer(world.grid, world.rooms, world.camera)
        self.camera_every = max(1, round(rate / 10))
        self._ticks = 0
        self.declared: list[tuple[str, str, str]] = []  # (op, topic, type) of each advertise and subscribe
        self._clients: set[Any] = set()
        self._subscriptions: dict[Any, set[str]] = {}
        self._cut = False
        self._lock = threading.Lock()
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, name="vwg-fake-robot", daemon=True)
        self._server: Any = None
        self._ticker: Any = None
        self._t0 = time.monotonic()
        self.port = 0

    # ---- life ----------------------------------------------------------------------------------------------------
    def start(self) -> FakeRosbridgeRobot:
        import websockets

        self._thread.start()

        async def serve() -> None:
            self._server = await websockets.serve(self._client, "127.0.0.1", 0, process_request=self._refuse)
            self.port = self._server.sockets[0].getsockname()[1]
            self._ticker = asyncio.ensure_future(self._tick())

        asyncio.run_coroutine_threadsafe(serve(), self._loop).result(5)
        return self

    @property
    def url(self) -> str:
        return f"ws://127.0.0.1:{self.port}"

    def stop(self) -> None:
        async def shut() -> None:
            if self._ticker is not None:
                self._ticker.cancel()
            if self._server is not None:
                self._server.close()
                await self._server.wait_closed()

        try:
            asyncio.run_coroutine_threadsafe(shut(), self._loop).result(5)
        finally:
            self._loop.call_soon_threadsafe(self._loop.stop)
            self._thread.join(5)
            if not self._thread.is_alive():
                self._loop.close()

    def __enter__(self) -> FakeRosbridgeRobot:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # ---- faults --------------------------------------------------------------------------------------------------
    def cut(self) -> None:
        """Close every connection and refuse new ones (a cable pulled, a router down)."""
        async def close_all() -> None:
            self._cut = True
            for ws in list(self._clients):
                await ws.close()

        asyncio.run_coroutine_threadsafe(close_all(), self._loop).result(5)

    def restore(self) -> None:
        self._cut = False

    def silence(self, robot: int) -> float:
        """Stop publishing `robot`'s odometry; returns when (the server's monotonic clock)."""
        with self._lock:
            self.robots[robot].silent = True
        return time.monotonic()

    def speak(self, robot: int) -> None:
        with self._lock:
            self.robots[robot].silent = False

    def pose(self, robot: int) -> tuple[float, float, float]:
        with self._lock:
            return tuple(self.robots[robot].pose)  # type: ignore[return-value]

    # ---- the server ---------------------------------------------------------------------------------------------
    def _refuse(self, connection: Any, request: Any) -> Any:
        """While cut, the handshake itself fails (HTTP 503): a client cannot even connect."""
        if self._cut:
            return connection.respond(http.HTTPStatus.SERVICE_UNAVAILABLE, "the link is cut\n")
        return None

    async def _client(self, ws: Any) -> None:
        self._clients.add(ws)
        self._subscriptions[ws] = set()
        try:
            async for text in ws:
                try:
                    message = json.loads(text)
                except ValueError:
                    continue
                if not isinstance(message, dict):
                    continue
                op = message.get("op")
                if op in ("advertise", "subscribe"):
                    self.declared.append((op, str(message.get("topic")), str(message.get("type"))))
                if op == "subscribe":
                    self._subscriptions[ws].add(message.get("topic"))
                elif op == "publish":
                    self._command(message.get("topic"), message.get("msg"))
        except Exception:
            pass
        finally:
            self._clients.discard(ws)
            self._subscriptions.pop(ws, None)

    def _command(self, topic: Any, msg: Any) -> None:
        for rid, named in self.topics.items():
            if named["cmd_vel"] == topic:
                try:
                    v, w = twist_of(msg)
                except ValueError:
                    return
                with self._lock:
                    base = self.robots[rid]
                    base.speed, base.turn_rate = v, w
                    base.commanded_at = time.monotonic()
                    self.commands[rid].append((base.commanded_at, v, w))

    async def _tick(self) -> None:
        period = 1.0 / self.rate
        next_at = time.monotonic()
        while True:
            next_at += period
            self._move(period)
            await self._publish()
            await asyncio.sleep(max(0.0, next_at - time.monotonic()))

    def _move(self, dt: float) -> None:
        grid = self.world.grid
        now = time.monotonic()
        with self._lock:
            for base in self.robots.values():
                if now - base.commanded_at > self.cmd_timeout:
                    base.speed = base.turn_rate = 0.0
                x, y, yaw = base.pose
                yaw2 = yaw + base.turn_rate * dt
                x2 = x + base.speed * dt * math.cos(yaw + base.turn_rate * dt / 2)
                y2 = y + base.speed * dt * math.sin(yaw + base.turn_rate * dt / 2)
                if grid.clearance(x2, y2, limit=base.settings.radius + 0.1) < base.settings.radius:
                    x2, y2 = x, y  # a wall: the base stops against it
                base.pose = (x2, y2, math.atan2(math.sin(yaw2), math.cos(yaw2)))

    async def _publish(self) -> None:
        now = time.monotonic() - self._t0
        out: list[tuple[str, dict[str, Any]]] = []
        self._ticks += 1
        wanted = set().union(*self._subscriptions.values()) if self._subscriptions else set()
        with self._lock:
            for rid, base in self.robots.items():
                sx, sy, st = base.settings.start
                x, y, yaw = base.pose
                dx, dy = x - sx, y - sy
                local = (math.cos(st) * dx + math.sin(st) * dy, -math.sin(st) * dx + math.cos(st) * dy,
                         math.atan2(math.sin(yaw - st), math.cos(yaw - st)))
                ox, oy, oyaw = self.odom_offset  # offset ⊕ local: the base's count did not start at zero here
                local = (ox + math.cos(oyaw) * local[0] - math.sin(oyaw) * local[1],
                         oy + math.sin(oyaw) * local[0] + math.cos(oyaw) * local[1],
                         math.atan2(math.sin(oyaw + local[2]), math.cos(oyaw + local[2])))
                if not base.silent:
                    out.append((self.topics[rid]["odom"], odometry_message(now, *local, base.speed, base.turn_rate,
                                                                           ros2=self.ros2)))
                laser = self.world.laser
                ranges = self.raycaster.scan(base.pose, self.angles, laser.max_range)
                ranges = [float(r) if r < laser.max_range else math.inf for r in ranges]
                out.append((self.topics[rid]["scan"], scan_message(now, float(self.angles[0]),
                                                                   float(self.angles[1] - self.angles[0])
                                                                   if len(self.angles) > 1 else 0.0,
                                                                   ranges, laser.min_range, laser.max_range,
                                                                   ros2=self.ros2)))
                if self._ticks % self.camera_every == 0 and self.topics[rid]["camera"] in wanted:
                    grey = self.camera.render(base.pose, [], grey=True)
                    out.append((self.topics[rid]["camera"],
                                compressed_image_message(now, _core.encode_image(grey, "jpeg", 95), "jpeg",
                                                         ros2=self.ros2)))
        for ws in list(self._clients):
            wanted = self._subscriptions.get(ws, set())
            for topic, msg in out:
                if topic in wanted:
                    try:
                        await ws.send(json.dumps({"op": "publish", "topic": topic, "msg": msg}))
                    except Exception:
                        break

