"""A differential-drive base on a serial line, speaking the ros_arduino_bridge commands (pyserial):
the platform ``serial`` of world files and ``vwg run --platform serial --serial-port /dev/ttyUSB0`` (or
any pyserial URL: ``socket://127.0.0.1:PORT``, ``loop://``).

    platform:
      kind: serial
      port: /dev/ttyUSB0
      baud: 57600
      wheel_radius: 0.0325   # m
      track_width: 0.16      # m between the wheels' contact points
      ticks_per_rev: 1920    # encoder ticks per wheel revolution
      pid_rate: 30           # the firmware's PID loop, Hz: motor speeds are ticks per PID interval
      watchdog: 0.5
      reconnect: 5
      flap_limit: {drops: 3, seconds: 10}

The commands (each ends with a carriage return): ``e`` → ``LEFT RIGHT`` encoder counts; ``m L R``
→ ``OK``, motor speeds in ticks per PID interval; ``r`` → ``OK``, encoders reset; ``b`` → the baud
rate. Odometry is integrated from the encoders (midpoint rule), from zero where the robot starts.
One base per line: a world with several robots needs several platforms.

A line that breaks (an error, or no answer within the timeout) is reopened every odometry period
for ``reconnect`` seconds. Each break and each reopening that answers again is a fault in the run's
summary; the encoder counts read on a reopened line are the robot's first odometry over it, and no
motion is sent over it before them; more breaks than ``flap_limit.drops`` within
``flap_limit.seconds`` end the run (exit status 4).
"""

from __future__ import annotations

import contextlib
import logging
import math
import re
import threading
import time
from collections.abc import Mapping
from typing import Any, ClassVar

import vwg._core as _core
from vwg.errors import SchemaError
from vwg.robot.links.ros_messages import Odometry
from vwg.robot.platform import Option
from vwg.robot.platforms.real_robot import LINK_OPTIONS, FlapLimit, RealRobotPlatform
from vwg.robot.platforms.real_robots import RealRobots

__all__ = ["Serial", "SerialBase", "SerialPlatform", "encoder_counts"]

log = logging.getLogger("vwg.serial")



def _positive(default: float, what: str) -> Option:
    return Option(float, default, minimum=0.0, exclusive_minimum=True, help=what)


#: The options of the platform serial (world file's platform:, --platform-opt), with their defaults.
OPTIONS: dict[str, Option] = {
    "port": Option(str, required=True, help="/dev/ttyUSB0, socket://HOST:PORT, or --serial-port"),
    "baud": Option(int, 57600, minimum=1, help="bits a second"),
    "wheel_radius": _positive(0.0325, "metres"),
    "track_width": _positive(0.16, "metres between the wheels"),
    "ticks_per_rev": _positive(1920.0, "encoder ticks a wheel turn"),
    "pid_rate": _positive(30.0, "the firmware's PID loops a second"),
    "odometry_rate": _positive(30.0, "encoder reads a second"),
    **LINK_OPTIONS,
}


def encoder_counts(reply: str) -> tuple[int, int]:
    """The two wheel counts of the base's answer to ``e`` ("LEFT RIGHT", decimal): ValueError for anything
    else, counts beyond a 32-bit long (the firmware's type) included."""
    words = reply.split()
    if len(words) != 2 or not all(re.fullmatch(r"[+-]?[0-9]+", w) for w in words):
        raise ValueError(f"encoders: expected two whole numbers, got {reply[:40]!r}")
    left, right = int(words[0]), int(words[1])
    if not (-(2**31) <= left < 2**31 and -(2**31) <= right < 2**31):
        raise ValueError(f"encoders: counts beyond a 32-bit long: {reply[:40]!r}")
    return left, right


class SerialBase:
    """The line to one base: commands and replies, one at a time (a lock), reopened when it breaks;
    ``opened`` counts the openings (the current one's number while open)."""

    def __init__(self, port: str, baud: int = OPTIONS["baud"].default, timeout: float = 0.2) -> None:
        self.port = port
        self.baud = baud
        self.timeout = timeout
        self._lock = threading.Lock()
        self._serial: Any = None
        self.opened = 0

    def open(self) -> None:
        import serial

        self.close()
        # Opened here, not by serial_for_url: an opening that fails half-way (a socket:// line connects,
        # then its peer resets it while pyserial empties the input: the cable pulled just then) leaves
        # an open socket in a line that serial_for_url would never have returned, to be closed by
        # nobody (pyserial's close() from the garbage collector skips it too: see _close_line).
        line = serial.serial_for_url(self.port, baudrate=self.baud, timeout=self.timeout, write_timeout=self.timeout,
                                     do_not_open=True)
        try:
            line.open()
            line.reset_input_buffer()
        except Exception:
            _close_line(line)
            raise
        with self._lock:
            self._serial = line
            self.opened += 1

    def ask(self, command: str, opening: int | None = None) -> str:
        """Send one command, return its reply line; OSError (pyserial's errors are) when the line is
        down or the base does not answer within the timeout, or when `opening` is given and the line
        has been reopened since (a command meant for the line as it was)."""
        import serial

        with self._lock:
            if self._serial is None:
                raise OSError(f"serial {self.port}: not open")
            if opening is not None and opening != self.opened:
                raise OSError(f"serial {self.port}: reopened since (opening {self.opened}, not {opening})")
            try:
                # A late reply to an earlier command must not be taken for this one's.
                self._serial.reset_input_buffer()
                self._serial.write((command + "\r").encode("ascii"))
                reply = self._serial.readline()
            except serial.SerialException as e:
                raise OSError(f"serial {self.port}: {e}") from None
        if not reply.endswith(b"\n"):
            raise OSError(f"serial {self.port}: no answer to {command!r} within {self.timeout:g} s")
        return reply.decode("ascii", errors="replace").strip()

    def close(self) -> None:
        with self._lock:
            if self._serial is not None:
                try:
                    _close_line(self._serial)
                finally:
                    self._serial = None


def _close_line(line: Any) -> None:
    """Close a pyserial line. Its socket:// close() skips closing its socket when shutdown() fails (the peer
    already gone, or reset), and the socket is then left to the garbage collector (a ResourceWarning, at
    whatever moment it collects it): close that socket here first."""
    sock = getattr(line, "_socket", None)
    if sock is not None:
        sock.close()
    line.close()


class SerialPlatform(RealRobotPlatform):
    """One differential-drive base on a serial line (ros_arduino_bridge commands)."""

    kind = "serial"

    def __init__(self, robot: _core.RobotSettings, port: str, *, baud: int = OPTIONS["baud"].default,
                 wheel_radius: float = OPTIONS["wheel_radius"].default,
                 track_width: float = OPTIONS["track_width"].default,
                 ticks_per_rev: float = OPTIONS["ticks_per_rev"].default, pid_rate: float = OPTIONS["pid_rate"].default,
                 watchdog: float = OPTIONS["watchdog"].default, reconnect: float = OPTIONS["reconnect"].default,
                 control_rate: float = OPTIONS["control_rate"].default,
                 odometry_rate: float = OPTIONS["odometry_rate"].default,
                 flap_limit: FlapLimit | dict[str, Any] | None = None) -> None:
        for name, value in (("wheel_radius", wheel_radius), ("track_width", track_width),
                            ("ticks_per_rev", ticks_per_rev), ("pid_rate", pid_rate), ("odometry_rate", odometry_rate)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise SchemaError(f"platform.{name}: expected a number > 0, got {value!r}")
        super().__init__([robot], watchdog=watchdog, control_rate=control_rate, flap_limit=flap_limit)
        self.robot_id = robot.id
        self.metres_per_tick = 2 * math.pi * wheel_radius / ticks_per_rev
        self.track_width = track_width
        self.pid_rate = pid_rate
        self.reconnect = reconnect
        self.base = SerialBase(port, int(baud))
        self._pose = (0.0, 0.0, 0.0)  # odometry, from zero where the robot starts
        self._ticks: tuple[int, int] | None = None
        self._line_failure: str | None = None
        self._lost_at: float | None = None
        self._running = True
        try:
            self.base.open()
            self._reset_encoders()
        except OSError as e:
            self.base.close()
            raise SchemaError(f"platform serial: cannot use {port}: {e}") from None
        self.link_up(self.base.opened)
        self._thread = threading.Thread(target=self._poll, args=(1.0 / odometry_rate,), name="vwg-serial", daemon=True)
        self._thread.start()

    def _reset_encoders(self, patience: float = 2.5) -> None:
        """`r`, retried while the board boots: opening the port resets an Arduino, whose bootloader
        answers nothing for a second or two."""
        until = time.monotonic() + patience
        while True:
            try:
                if self.base.ask("r") == "OK":
                    return
                problem = "the base did not accept 'r' (reset encoders)"
            except OSError as e:
                problem = str(e)
            if time.monotonic() >= until:
                raise OSError(problem)
            time.sleep(0.1)

    def _poll(self, period: float) -> None:
        """Encoders → odometry, on the link's own thread; a broken line is reopened for `reconnect` s."""
        start = time.monotonic()
        while self._running:
            try:
                opening = self.base.opened
                left, right = encoder_counts(self.base.ask("e", opening))
                if self._lost_at is not None:
                    self.link_up(opening)  # back: these counts are the first odometry over it
                self._integrate(left, right, time.monotonic() - start)
                self._lost_at = None
            except (OSError, ValueError, IndexError) as e:
                now = time.monotonic()
                if self._lost_at is None:
                    self._lost_at = now
                    self.link_down(str(e))
                if now - self._lost_at > self.reconnect:
                    self._line_failure = f"the line to {self.base.port} broke and did not come back within " \
                                    f"{self.reconnect:g} s ({e})"
                    return
                with contextlib.suppress(Exception):  # still down: try again next period
                    self.base.open()
                    # A reopened port may have rebooted the board (its counts back to zero): the next
                    # counts are a new baseline, the pose goes on from where it was.
                    self._ticks = None
                if not self._running:  # closed meanwhile: an opening (a connect) may outlast close_link's wait
                    self.base.close()
            time.sleep(period)

    def _integrate(self, left: int, right: int, t: float) -> None:
        if self._ticks is None:
            self._ticks = (left, right)
            self.on_odometry(self.robot_id, Odometry(t, *self._pose, 0.0, 0.0))
            return
        dl = (left - self._ticks[0]) * self.metres_per_tick
        dr = (right - self._ticks[1]) * self.metres_per_tick
        self._ticks = (left, right)
        ds, dtheta = (dl + dr) / 2, (dr - dl) / self.track_width
        x, y, yaw = self._pose
        x += ds * math.cos(yaw + dtheta / 2)
        y += ds * math.sin(yaw + dtheta / 2)
        yaw = math.atan2(math.sin(yaw + dtheta), math.cos(yaw + dtheta))
        self._pose = (x, y, yaw)
        self.on_odometry(self.robot_id, Odometry(t, x, y, yaw, 0.0, 0.0))

    def send_velocity(self, robot: int, speed: float, turn_rate: float, *, connection: int | None = None) -> bool:
        # Wheel speeds in ticks per PID interval, as the firmware's `m` takes them.
        left = (speed - turn_rate * self.track_width / 2) / self.metres_per_tick / self.pid_rate
        right = (speed + turn_rate * self.track_width / 2) / self.metres_per_tick / self.pid_rate
        try:
            return self.base.ask(f"m {round(left)} {round(right)}", connection) == "OK"
        except OSError:
            return False

    def link_failure(self) -> str | None:
        return self._line_failure

    def close_link(self) -> None:
        self._running = False
        self._thread.join(2.0)
        self.base.close()

    def name(self) -> str:
        return "serial"


class Serial(RealRobots):
    """The platform ``serial``: one differential-drive base on a serial line (ros_arduino_bridge)."""

    name = "serial"
    summary = "a differential-drive base on a serial line (ros_arduino_bridge commands, pyserial URLs)"
    sensors = ()
    options: ClassVar[dict[str, Option]] = OPTIONS

    def __init__(self, world: Any, seed: int, options: Mapping[str, Any]) -> None:
        super().__init__(world, seed, options)
        if len(world.robots) != 1:
            raise SchemaError(f"platform serial: one base per serial line, and the world has {len(world.robots)} "
                              "robots")
        given = {k: v for k, v in self.settings.items() if v is not None and k != "port"}
        self.attach(SerialPlatform(world.robots[0], self.settings["port"], **given))
