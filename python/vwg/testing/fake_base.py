"""A fake microcontroller base for tests and demos: a TCP server on 127.0.0.1 (pyserial reaches it as
``socket://127.0.0.1:PORT``) that speaks the ros_arduino_bridge commands (``e``, ``m L R``, ``r``,
``b``) and moves one differential-drive robot on a world's map, its wheel encoders counting as it
goes. Like the firmware, it stops the motors when no ``m`` has come for ``auto_stop`` seconds.
For fault tests: ``cut()`` pulls the cable for good; ``flap(after, hold)`` closes every connection
``after`` seconds from the call and from then on each new one ``hold`` seconds after it opened.
``connections`` holds what each connection saw: when it opened and each command line, with its time.

    with FakeSerialBase(world) as base:
        options = vwg.RunOptions(platform="serial", platform_options={"port": base.url}, goals=["office"])
        vwg.start(world, options).execute()
"""

from __future__ import annotations

import contextlib
import math
import socket
import socketserver
import threading
import time
from dataclasses import dataclass, field

from vwg.robot.world_file import RobotWorld

__all__ = ["BaseConnection", "FakeSerialBase"]


@dataclass
class BaseConnection:
    """One connection to the base as it saw it, times on its monotonic clock."""

    opened: float
    lines: list[tuple[float, str]] = field(default_factory=list)  # (time, command) as each came


class FakeSerialBase:
    def __init__(self, world: RobotWorld, *, wheel_radius: float = 0.0325, track_width: float = 0.16,
                 ticks_per_rev: float = 1920, pid_rate: float = 30, auto_stop: float = 2.0) -> None:
        self.world = world
        self.settings = world.robots[0]
        self.metres_per_tick = 2 * math.pi * wheel_radius / ticks_per_rev
        self.track_width = track_width
        self.pid_rate = pid_rate
        self.auto_stop = auto_stop
        self.pose = tuple(self.settings.start)
        self.ticks = [0.0, 0.0]
        self.motors = (0, 0)          # ticks per PID interval, as commanded
        self.commanded_at = 0.0
        self.commands: list[tuple[float, int, int]] = []  # (monotonic time, left, right) of every `m`
        self._lock = threading.Lock()
        self._running = True   # taking connections and commands
        self._alive = True     # the motors (they run on after a cut, until the firmware's auto-stop)
        self.connections: list[BaseConnection] = []
        self._open: set[socket.socket] = set()
        self._flap_hold: float | None = None  # flapping: each connection is closed this long after it opened
        fake = self

        class Handler(socketserver.StreamRequestHandler):
            def handle(self) -> None:
                connection = BaseConnection(time.monotonic())
                with fake._lock:
                    fake.connections.append(connection)
                    fake._open.add(self.request)
                    hold = fake._flap_hold
                if hold is not None:
                    closer = threading.Timer(hold, fake._hang_up, args=(self.request,))
                    closer.daemon = True
                    closer.start()
                try:
                    self._serve(connection)
                finally:
                    with fake._lock:
                        fake._open.discard(self.request)

            def _serve(self, connection: BaseConnection) -> None:
                buffer = b""
                while fake._running:
                    try:
                        chunk = self.request.recv(256)
                    except OSError:
                        return
                    if not chunk:
                        return
                    buffer += chunk
                    while b"\r" in buffer:
                        line, _, buffer = buffer.partition(b"\r")
                        command = line.decode("ascii", errors="replace").strip()
                        connection.lines.append((time.monotonic(), command))
                        reply = fake._answer(command)
                        try:
                            self.request.sendall((reply + "\r\n").encode("ascii"))
                        except OSError:
                            return

        self._server = socketserver.ThreadingTCPServer(("127.0.0.1", 0), Handler)
        self._server.daemon_threads = True
        self.port = self._server.server_address[1]
        self._threads = [threading.Thread(target=self._server.serve_forever, name="vwg-fake-base", daemon=True),
                         threading.Thread(target=self._move, name="vwg-fake-base-motors", daemon=True)]

    @property
    def url(self) -> str:
        return f"socket://127.0.0.1:{self.port}"

    def start(self) -> FakeSerialBase:
        for t in self._threads:
            t.start()
        return self

    def stop(self) -> None:
        self._alive = False
        if self._running:
            self._running = False
            self._server.shutdown()
        self._server.server_close()
        for t in self._threads:
            t.join(2)

    def __enter__(self) -> FakeSerialBase:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def _answer(self, line: str) -> str:
        words = line.split()
        with self._lock:
            if words == ["e"]:
                return f"{math.floor(self.ticks[0])} {math.floor(self.ticks[1])}"
            if words == ["r"]:
                self.ticks = [0.0, 0.0]
                return "OK"
            if words == ["b"]:
                return "57600"
            if len(words) == 3 and words[0] == "m":
                try:
                    self.motors = (int(words[1]), int(words[2]))
                except ValueError:
                    return "Invalid Command"
                self.commanded_at = time.monotonic()
                self.commands.append((self.commanded_at, *self.motors))
                return "OK"
        return "Invalid Command"

    def _move(self) -> None:
        dt = 0.01
        grid = self.world.grid
        while self._alive:
            with self._lock:
                if time.monotonic() - self.commanded_at > self.auto_stop:
                    self.motors = (0, 0)
                dl = self.motors[0] * self.pid_rate * dt  # ticks this step
                dr = self.motors[1] * self.pid_rate * dt
                ds = (dl + dr) / 2 * self.metres_per_tick
                dtheta = (dr - dl) * self.metres_per_tick / self.track_width
                x, y, yaw = self.pose
                x2, y2 = x + ds * math.cos(yaw + dtheta / 2), y + ds * math.sin(yaw + dtheta / 2)
                if grid.clearance(x2, y2, limit=self.settings.radius + 0.1) >= self.settings.radius:
                    self.ticks[0] += dl
                    self.ticks[1] += dr
                    self.pose = (x2, y2, math.atan2(math.sin(yaw + dtheta), math.cos(yaw + dtheta)))
                # against a wall the wheels stall: no ticks, no motion
            time.sleep(dt)

    @staticmethod
    def _hang_up(sock: socket.socket) -> None:
        """Close a connection from this side: its handler's recv returns b"", the client's next read fails."""
        with contextlib.suppress(OSError):  # already closed by the client
            sock.shutdown(socket.SHUT_RDWR)

    def flap(self, after: float = 0.0, hold: float = 0.15) -> None:
        """In `after` seconds, close every connection; from then on take each new one and close it
        `hold` seconds after it opened."""
        def start() -> None:
            with self._lock:
                self._flap_hold = hold
                current = list(self._open)
            for sock in current:
                self._hang_up(sock)

        timer = threading.Timer(after, start)
        timer.daemon = True
        timer.start()

    def cut(self) -> None:
        """Pull the cable: every connection closes and no new one is taken."""
        self._running = False
        self._server.shutdown()  # serve_forever returns (it runs on its own thread)
        self._server.socket.close()

    def pose_now(self) -> tuple[float, float, float]:
        with self._lock:
            return tuple(self.pose)  # type: ignore[return-value]

