"""The rosbridge v2 side of a simulated robot, for tests and experiments: a WebSocket server on 127.0.0.1
(a free port) that speaks the subset of the protocol vwg's rosbridge link uses — ``advertise``,
``subscribe``, ``publish`` (geometry_msgs/Twist on each robot's ``cmd_vel``), ``call_service`` (the
lockstep service ``/vwg/step``) — and publishes what a subclass's robot has to say (nav_msgs/Odometry from
zero where each robot starts, sensor_msgs/LaserScan, ...) to the clients subscribed to it.

A subclass brings the robot (vwg.testing.fake_robot: vwg's own Box2D simulator; vwg.testing.irsim_robot:
IR-SIM) by giving ``_drive``, ``_advance``, ``_sim_time``, ``_messages`` and ``pose``; the server, the
clock (wall-clock at ``rate`` Hz, or lockstep: it steps only when ``/vwg/step`` is called with
``{"seconds": s}``, then publishes, then answers), the stop when commands stop coming, and the link's
faults for tests (``cut``, ``flap``, ``silence``, ``odometry_delay``, ``drop_at_step``) are here, once.

The simulation steps on a thread of its own (the server's worker), not on the event loop: a step that takes
long (IR-SIM's, on a loaded machine) leaves the server answering the client's keepalive pings meanwhile. A
subclass whose steps take a millisecond or so sets ``step_in_thread = False`` (the fake robot: a hand-over
to another thread and back would take longer than its step, on a loaded machine several times as long).

A step call may carry ``"step_id"`` (a string): a step whose id has been done already, over whatever
connection, is not done again; the robot is published where it is and the answer is the same, with
``"repeated": true``. vwg sends a step again with its id when the link dropped before the answer came.
"""

from __future__ import annotations

import asyncio
import contextlib
import http
import json
import math
import threading
import time
from collections import OrderedDict
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any, Self

from vwg.robot.links.ros_messages import pose_compose, pose_relative, twist_of
from vwg.robot.platforms.rosbridge import topics_for
from vwg.robot.world_file import RobotWorld

__all__ = ["STEP_SERVICE", "Connection", "RosbridgeRobotServer"]


STEP_SERVICE = "/vwg/step"
_STEP_IDS_KEPT = 1024  # the step ids a server remembers as done (a repeated step comes within a few)


@dataclass
class Connection:
    """One client connection as the server saw it, times on the server's monotonic clock."""

    opened: float
    closed: float | None = None         # when the server closed it (began to), or saw it closed
    closed_by_server: bool = False      # flap() closed it (not the client)
    first_odometry: float | None = None  # when its first odometry message was sent
    twists: list[tuple[float, int, float, float]] = field(default_factory=list)  # (time, robot, speed, turn rate)


class RosbridgeRobotServer:
    """A rosbridge v2 server for the robots of `world`; a subclass simulates them (see the module)."""

    thread_name = "vwg-rosbridge-robot"
    step_in_thread = True  # step (and compute the messages) on the worker, not on the event loop

    def __init__(self, world: RobotWorld, *, rate: float = 50.0, ros2: bool = False, cmd_timeout: float = 0.5,
                 odom_offset: tuple[float, float, float] = (0.0, 0.0, 0.0), lockstep: bool = False,
                 odometry_delay: float = 0.0) -> None:
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
        self._drop_at: tuple[int, bool, float] | None = None  # drop_at_step: (call, done first, hold)
        self.step_calls = 0  # service calls received (the step service's, or refused), over every connection
        several = len(world.robots) > 1
        self.starts = {r.id: tuple(r.start) for r in world.robots}
        self.topics = {r.id: topics_for(r.id, several) for r in world.robots}
        self._odometry_topics = {named["odom"]: rid for rid, named in self.topics.items()}
        self.commands: dict[int, list[tuple[float, float, float]]] = {r.id: [] for r in world.robots}
        self._commanded_at = {r.id: 0.0 for r in world.robots}
        self._silent: set[int] = set()
        self.declared: list[tuple[str, str, str]] = []  # (op, topic, type) of each advertise and subscribe
        self._clients: set[Any] = set()
        self._subscriptions: dict[Any, set[str]] = {}
        self._cut = False
        self._lock = threading.Lock()
        # The simulation's own thread (started with the first step): the event loop goes on talking (and
        # answering pings) while a step runs.
        self._worker = ThreadPoolExecutor(max_workers=1, thread_name_prefix=f"{self.thread_name}-sim")
        self._steps_done: OrderedDict[str, None] = OrderedDict()  # the step ids done, oldest first
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, name=self.thread_name, daemon=True)
        self._server: Any = None
        self._ticker: Any = None
        self._t0 = time.monotonic()
        self.port = 0

    # ---- what a subclass gives (called with the lock held; on the worker if step_in_thread) ----------------------
    def _drive(self, robot: int, speed: float, turn_rate: float) -> None:  # pragma: no cover - abstract
        """Hold `robot` at these velocities from now on (a Twist came, or commands stopped)."""
        raise NotImplementedError

    def _advance(self, seconds: float) -> None:  # pragma: no cover - abstract
        """Let `seconds` of simulated time pass; ValueError (its text goes back to the caller) to refuse."""
        raise NotImplementedError

    def _sim_time(self) -> float:  # pragma: no cover - abstract
        """The robots' simulated clock, seconds."""
        raise NotImplementedError

    def _messages(self, now: float, wanted: set[str]) -> list[tuple[str, dict[str, Any]]]:  # pragma: no cover
        """(topic, message) to publish now, stamped `now`: every robot's odometry, and of the rest those in
        `wanted` (the topics some client is subscribed to)."""
        raise NotImplementedError

    def pose(self, robot: int) -> tuple[float, float, float]:  # pragma: no cover - abstract
        """The robot's true pose (the simulation's), not what its odometry says."""
        raise NotImplementedError

    # ---- life ----------------------------------------------------------------------------------------------------
    def start(self) -> Self:
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
        if not self._thread.is_alive():
            if self._thread.ident is None and not self._loop.is_closed():
                self._loop.close()  # never started: its loop never ran
            self._worker.shutdown(wait=True)
            return  # never started, or stopped already

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
            self._worker.shutdown(wait=True)  # a step under way ends first

    @property
    def running(self) -> bool:
        """Whether the server's thread is still up (it is not once stop() or the with-block is done)."""
        return self._thread.is_alive()

    def read_to_close(self, timeout: float = 10.0) -> None:
        """Wait until the server has read every connection to its close: it reads on its own thread, which a
        loaded machine keeps behind the client, and the Twists a client sent before it closed are then all in
        ``commands``. TimeoutError after `timeout` seconds."""
        end = time.monotonic() + timeout
        while any(c.closed is None for c in self.connections):
            if time.monotonic() > end:
                raise TimeoutError(f"{type(self).__name__}: a connection still open after {timeout:g} s")
            time.sleep(0.01)

    def __enter__(self) -> Self:
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

    def drop_at_step(self, call: int, *, done: bool = True, hold: float = 0.3) -> None:
        """Lockstep: on the `call`-th call of the step service (from 1, over any connection), close every
        connection and refuse new ones for `hold` seconds: after doing the step (``done``: its answer is lost)
        or instead of it (the call is lost on the way)."""
        self._drop_at = (call, done, hold)

    async def _drop(self, hold: float) -> None:
        self._cut = True
        for ws in list(self._clients):
            await ws.close()
        self._loop.call_later(hold, self.restore)

    def silence(self, robot: int) -> float:
        """Stop publishing `robot`'s odometry; returns when (the server's monotonic clock)."""
        with self._lock:
            self._silent.add(robot)
        return time.monotonic()

    def speak(self, robot: int) -> None:
        with self._lock:
            self._silent.discard(robot)

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
                at = time.monotonic()
                self._commanded_at[rid] = at
                self.commands[rid].append((at, v, w))
                if connection is not None:
                    connection.twists.append((at, rid, v, w))
                if not self.step_in_thread:
                    self._drive_locked(rid, v, w)
                    continue
                # On the worker, after a step under way (the loop does not wait for its lock) and before the
                # steps that come after.
                with contextlib.suppress(RuntimeError):  # the server is stopping: the worker takes no more
                    self._worker.submit(self._drive_locked, rid, v, w)

    def _drive_locked(self, rid: int, v: float, w: float) -> None:
        with self._lock:
            self._drive(rid, v, w)

    async def _on_worker(self, work: Any, *args: Any) -> Any:
        """`work(*args)` on the simulation's thread (inline when the subclass steps on the loop)."""
        if not self.step_in_thread:
            return work(*args)
        return await asyncio.get_running_loop().run_in_executor(self._worker, work, *args)

    def _step(self, seconds: float, step_id: str | None, wanted: set[str]) -> tuple[dict[str, Any], list[Any]]:
        """Step (unless `step_id` has been done); the answer's values and the messages (on the worker)."""
        with self._lock:
            repeated = step_id is not None and step_id in self._steps_done
            if not repeated:
                self._advance(seconds)
                if step_id is not None:
                    self._steps_done[step_id] = None
                    while len(self._steps_done) > _STEP_IDS_KEPT:
                        self._steps_done.popitem(last=False)
            values: dict[str, Any] = {"time": self._sim_time()}
            if step_id is not None:
                values["step_id"] = step_id
            if repeated:
                values["repeated"] = True
            return values, self._outgoing(wanted)

    async def _call(self, ws: Any, message: dict[str, Any]) -> None:
        """The step service of a lockstep robot: advance the simulation (unless this step's id has been done),
        publish, then answer."""
        args = message.get("args")
        seconds = args.get("seconds") if isinstance(args, dict) else None
        step_id = args.get("step_id") if isinstance(args, dict) else None
        ok = (self.lockstep and message.get("service") == STEP_SERVICE and isinstance(seconds, (int, float))
              and math.isfinite(seconds) and 0 <= seconds <= 10 and (step_id is None or isinstance(step_id, str)))
        values: Any = "no such service, or bad arguments"
        self.step_calls += 1
        drop = self._drop_at if self._drop_at is not None and self._drop_at[0] == self.step_calls else None
        if drop is not None and not drop[1]:
            await self._drop(drop[2])  # the call is lost on the way: no step, no answer
            return
        if ok:
            try:
                values, out = await self._on_worker(self._step, float(seconds), step_id, self._wanted())
            except ValueError as e:
                ok, values = False, str(e)
            else:
                await self._send_out(out)
        if drop is not None:
            await self._drop(drop[2])  # the step is done, its answer lost
            return
        answer = {"op": "service_response", "service": message.get("service"), "id": message.get("id"),
                  "values": values, "result": ok}
        with contextlib.suppress(Exception):
            await ws.send(json.dumps(answer))

    def _tick_once(self, period: float, wanted: set[str]) -> list[Any]:
        """A wall-clock tick (a base whose commands stopped coming stops), and the messages (on the worker)."""
        now = time.monotonic()
        with self._lock:
            for rid, at in self._commanded_at.items():
                if now - at > self.cmd_timeout:
                    self._drive(rid, 0.0, 0.0)
            self._advance(period)
            return self._outgoing(wanted)

    async def _tick(self) -> None:
        period = 1.0 / self.rate
        next_at = time.monotonic()
        while True:
            next_at += period
            await self._send_out(await self._on_worker(self._tick_once, period, self._wanted()))
            await asyncio.sleep(max(0.0, next_at - time.monotonic()))

    def _odometry(self, rid: int, pose: tuple[float, float, float]) -> tuple[float, float, float]:
        """`pose` (the robot's odometry, in the map's frame) in the base's odometry frame: zero where the robot
        started (⊕ the offset its count stood at when vwg connected)."""
        return pose_compose(self.odom_offset, pose_relative(self.starts[rid], pose))

    def _wanted(self) -> set[str]:
        """The topics some client is subscribed to (on the loop, which keeps the subscriptions)."""
        return set().union(*self._subscriptions.values()) if self._subscriptions else set()

    def _outgoing(self, wanted: set[str]) -> list[tuple[str, dict[str, Any]]]:
        """What to publish now (the lock held)."""
        now = self._sim_time() if self.lockstep else time.monotonic() - self._t0
        return [(topic, msg) for topic, msg in self._messages(now, wanted)
                if self._odometry_topics.get(topic) not in self._silent]

    async def _send_out(self, out: list[tuple[str, dict[str, Any]]]) -> None:
        for ws in list(self._clients):
            wanted = self._subscriptions.get(ws, set())
            connection = self._connection_of.get(ws)
            held = connection is not None and time.monotonic() - connection.opened < self.odometry_delay
            for topic, msg in out:
                odometry = topic in self._odometry_topics
                if topic in wanted and not (held and odometry):
                    if odometry and connection is not None and connection.first_odometry is None:
                        connection.first_odometry = time.monotonic()  # before it goes: no client has it earlier
                    try:
                        await ws.send(json.dumps({"op": "publish", "topic": topic, "msg": msg}))
                    except Exception:
                        break
