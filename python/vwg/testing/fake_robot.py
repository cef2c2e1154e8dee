"""A fake ROS robot behind a rosbridge v2 server on 127.0.0.1, for tests and demos: vwg's own Box2D
simulator (vwg.robot.platforms.sim.PhysicsWorld) with the world's map and robots, driven by geometry_msgs/Twist on
each robot's ``cmd_vel`` as a differential-drive base is, publishing nav_msgs/Odometry (from zero
where each robot starts, as a real base does), sensor_msgs/LaserScan (the simulator's noiseless
ranges, walls and other robots) and sensor_msgs/CompressedImage (the simulator's camera view, JPEG,
10 Hz), as a real robot's rosbridge server would.

    with FakeRosbridgeRobot(world) as robot:          # serves ws://127.0.0.1:<free port>
        options = vwg.RunOptions(platform="rosbridge", platform_options={"url": robot.url}, goals=["kitchen"])
        vwg.start(world, options).execute()

By default it runs at wall-clock rate (``rate`` Hz). With ``lockstep=True`` it runs in simulated
time instead: it steps only when the service ``/vwg/step`` is called (``{"seconds": s}``), then
publishes and answers — a simulator that vwg steps, for the frame-by-frame equivalence of paper
test 3 (platform option ``lockstep: /vwg/step``).

A base stops by itself when no command has come for ``cmd_timeout`` seconds, as real bases do.
For fault tests: ``cut()`` closes every connection and refuses new ones until ``restore()``;
``silence(robot)`` stops its odometry until ``speak(robot)``; ``flap(after, hold)`` closes every
connection ``after`` seconds from the call and from then on each new one ``hold`` seconds after it
opened (a link that keeps dropping); ``odometry_delay`` holds back the odometry of each new
connection for that long (a driver that takes a moment). ``commands[robot]`` lists the (time,
speed, turn rate) of every Twist received, the time on the server's monotonic clock, and
``connections`` what each connection saw (when it opened and closed, when its first odometry went
out, the Twists that came over it).
"""

from __future__ import annotations

import asyncio
import contextlib
import http
import json
import math
import threading
import time
from dataclasses import dataclass, field
from typing import Any

import vwg._core as _core
from vwg.robot.links.ros_messages import (
    compressed_image_message,
    odometry_message,
    pose_compose,
    pose_relative,
    scan_message,
    twist_of,
)
from vwg.robot.platforms.rosbridge import topics_for
from vwg.robot.world_file import RobotWorld

__all__ = ["Connection", "FakeRosbridgeRobot"]


STEP_SERVICE = "/vwg/step"


@dataclass
class Connection:
    """One client connection as the server saw it, times on the server's monotonic clock."""

    opened: float
    closed: float | None = None         # when the server closed it (began to), or saw it closed
    closed_by_server: bool = False      # flap() closed it (not the client)
    first_odometry: float | None = None  # when its first odometry message was sent
    twists: list[tuple[float, int, float, float]] = field(default_factory=list)  # (time, robot, speed, turn rate)


class FakeRosbridgeRobot:
    def __init__(self, world: RobotWorld, *, rate: float = 50.0, ros2: bool = False, cmd_timeout: float = 0.5,
                 odom_offset: tuple[float, float, float] = (0.0, 0.0, 0.0), lockstep: bool = False,
                 physics: _core.PhysicsSettings | None = None, odometry_delay: float = 0.0) -> None:
        self.world = world
        # Where each base's odometry count stood when vwg connected (a base that has run before).
        self.odom_offset = odom_offset
        self.cmd_timeout = cmd_timeout  # a base stops by itself when commands stop coming (as real ones do)
        self.rate = rate
        self.ros2 = ros2
        self.lockstep = lockstep
        self.odometry_delay = odometry_delay
        self.connections: list[Connection] = []
        self._connection_of: dict[Any, Connection] = {}
        self._flap_hold: float | None = None  # flapping: each connection is closed this long after it opened
        # The simulator's own physics (its odometry noise too: the odometry published is the noisy one).
        self.physics = _core.PhysicsWorld(world.grid, list(world.robots),
                                          physics or _core.PhysicsSettings(noise=world.noise, seed=world.seed))
        self.scanner = _core.RangeScanner(_core.GridRaycaster(world.grid), self.physics)
        self.angle_min, self.angle_increment = _core.beam_layout(world.sensor_settings("laser"))
        several = len(world.robots) > 1
        self.starts = {r.id: tuple(r.start) for r in world.robots}
        self.topics = {r.id: topics_for(r.id, several) for r in world.robots}
        self.commands: dict[int, list[tuple[float, float, float]]] = {r.id: [] for r in world.robots}
        self._commanded_at = {r.id: 0.0 for r in world.robots}
        self._silent: set[int] = set()
        # The robots' cameras: the simulator's renderer, JPEG-compressed, at 10 Hz of the robot's clock.
        self.camera = _core.CameraRenderer(world.grid, world.rooms, world.sensor_settings("camera"))
        self._camera_due = 0.0
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
            if not self.lockstep:
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

    def read_to_close(self, timeout: float = 10.0) -> None:
        """Wait until the server has read every connection to its close: it reads on its own thread, which a
        loaded machine keeps behind the client, and the Twists a client sent before it closed are then all in
        ``commands``. TimeoutError after `timeout` seconds."""
        end = time.monotonic() + timeout
        while any(c.closed is None for c in self.connections):
            if time.monotonic() > end:
                raise TimeoutError(f"fake robot: a connection still open after {timeout:g} s")
            time.sleep(0.01)

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

    def flap(self, after: float = 0.0, hold: float = 0.15) -> None:
        """In `after` seconds, close every connection; from then on accept each new one and close it
        `hold` seconds after it opened, until ``steady()``."""
        async def start() -> None:
            await asyncio.sleep(after)
            self._flap_hold = hold
            for ws in list(self._clients):
                await self._hang_up(ws)

        asyncio.run_coroutine_threadsafe(start(), self._loop)

    def steady(self) -> None:
        self._flap_hold = None

    def silence(self, robot: int) -> float:
        """Stop publishing `robot`'s odometry; returns when (the server's monotonic clock)."""
        with self._lock:
            self._silent.add(robot)
        return time.monotonic()

    def speak(self, robot: int) -> None:
        with self._lock:
            self._silent.discard(robot)

    def pose(self, robot: int) -> tuple[float, float, float]:
        """The robot's true pose (the simulator's), not what its odometry says."""
        with self._lock:
            return self.physics.robot(robot).pose

    # ---- the server ---------------------------------------------------------------------------------------------
    def _refuse(self, connection: Any, request: Any) -> Any:
        """While cut, the handshake itself fails (HTTP 503): a client cannot even connect."""
        if self._cut:
            return connection.respond(http.HTTPStatus.SERVICE_UNAVAILABLE, "the link is cut\n")
        return None

    async def _hang_up(self, ws: Any) -> None:
        connection = self._connection_of.get(ws)
        if connection is not None and connection.closed is None:
            connection.closed, connection.closed_by_server = time.monotonic(), True
        await ws.close()

    async def _close_after(self, ws: Any, hold: float) -> None:
        await asyncio.sleep(hold)
        await self._hang_up(ws)

    async def _client(self, ws: Any) -> None:
        connection = Connection(time.monotonic())
        self.connections.append(connection)
        self._connection_of[ws] = connection
        self._clients.add(ws)
        self._subscriptions[ws] = set()
        closer = asyncio.ensure_future(self._close_after(ws, self._flap_hold)) if self._flap_hold is not None else None
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
                    self._command(message.get("topic"), message.get("msg"), connection)
                elif op == "call_service":
                    await self._call(ws, message)
        except Exception:
            pass
        finally:
            connection.closed = connection.closed or time.monotonic()
            if closer is not None:
                closer.cancel()
            self._clients.discard(ws)
            self._subscriptions.pop(ws, None)
            self._connection_of.pop(ws, None)

    def _command(self, topic: Any, msg: Any, connection: Connection | None = None) -> None:
        for rid, named in self.topics.items():
            if named["cmd_vel"] == topic:
                try:
                    v, w = twist_of(msg)
                except ValueError:
                    return
                with self._lock:
                    self.physics.drive(rid, v, w)
                    self._commanded_at[rid] = time.monotonic()
                    self.commands[rid].append((self._commanded_at[rid], v, w))
                    if connection is not None:
                        connection.twists.append((self._commanded_at[rid], rid, v, w))

    async def _call(self, ws: Any, message: dict[str, Any]) -> None:
        """The step service of a lockstep robot: advance the simulator, publish, then answer."""
        args = message.get("args")
        seconds = args.get("seconds") if isinstance(args, dict) else None
        ok = (self.lockstep and message.get("service") == STEP_SERVICE and isinstance(seconds, (int, float))
              and math.isfinite(seconds) and 0 <= seconds <= 10)
        if ok:
            with self._lock:
                self.physics.advance(float(seconds))
            await self._publish()
        answer = {"op": "service_response", "service": message.get("service"), "id": message.get("id"),
                  "values": {"time": self.physics.time()} if ok else "no such service, or bad arguments",
                  "result": ok}
        with contextlib.suppress(Exception):
            await ws.send(json.dumps(answer))

    async def _tick(self) -> None:
        period = 1.0 / self.rate
        next_at = time.monotonic()
        while True:
            next_at += period
            now = time.monotonic()
            with self._lock:
                for rid, at in self._commanded_at.items():
                    if now - at > self.cmd_timeout:
                        self.physics.drive(rid, 0.0, 0.0)
                self.physics.advance(period)
            await self._publish()
            await asyncio.sleep(max(0.0, next_at - time.monotonic()))

    def _odometry(self, rid: int, pose: tuple[float, float, float]) -> tuple[float, float, float]:
        """`pose` in the base's odometry frame: zero where the robot started (⊕ the offset its count
        stood at when vwg connected)."""
        return pose_compose(self.odom_offset, pose_relative(self.starts[rid], pose))

    async def _publish(self) -> None:
        out: list[tuple[str, dict[str, Any]]] = []
        wanted = set().union(*self._subscriptions.values()) if self._subscriptions else set()
        laser = self.world.sensor_settings("laser")
        with self._lock:
            now = self.physics.time() if self.lockstep else time.monotonic() - self._t0
            camera = self.physics.time() >= self._camera_due
            if camera:
                self._camera_due = self.physics.time() + 0.1
            for state in self.physics.robots():
                rid = state.id
                if rid not in self._silent:
                    out.append((self.topics[rid]["odom"], odometry_message(now, *self._odometry(rid, state.odometry),
                                                                           state.speed, state.turn_rate,
                                                                           ros2=self.ros2)))
                if self.topics[rid]["scan"] in wanted:
                    ranges = self.scanner.scan(rid, laser)
                    out.append((self.topics[rid]["scan"], scan_message(
                        now, self.angle_min, self.angle_increment,
                        [float(r) if r < laser.max_range else math.inf for r in ranges],
                        laser.min_range, laser.max_range, ros2=self.ros2)))
                if camera and self.topics[rid]["camera"] in wanted:
                    grey = self.camera.render(state.pose, [], grey=True)
                    out.append((self.topics[rid]["camera"],
                                compressed_image_message(now, _core.encode_image(grey, "jpeg", 95), "jpeg",
                                                         ros2=self.ros2)))
        odometry_topics = {named["odom"] for named in self.topics.values()}
        for ws in list(self._clients):
            wanted = self._subscriptions.get(ws, set())
            connection = self._connection_of.get(ws)
            held = connection is not None and time.monotonic() - connection.opened < self.odometry_delay
            for topic, msg in out:
                if topic in wanted and not (held and topic in odometry_topics):
                    if topic in odometry_topics and connection is not None and connection.first_odometry is None:
                        connection.first_odometry = time.monotonic()  # before it goes: no client has it earlier
                    try:
                        await ws.send(json.dumps({"op": "publish", "topic": topic, "msg": msg}))
                    except Exception:
                        break
