"""A real robot as a vwg.robot.RobotPlatform: the motion commands of the frames (turn, drive) become
velocity commands closed on the robot's odometry, frames run at wall-clock rate, and the robot is
kept safe when its link goes quiet or away.

The link itself (rosbridge, a serial base) is a subclass: it sends velocities (``send_velocity``),
says whether it has failed (``link_failure``), calls ``link_up`` and ``link_down`` as its connection
comes and goes, and ``on_odometry`` (and ``on_scan``) from its own thread as messages come.

Safety, in this order of precedence:

- every velocity is clamped to the robot's limits (speed, turn rate and both accelerations);
- a watchdog: when no odometry has come for ``watchdog`` seconds the robot is sent a stop at once,
  and kept stopped until odometry comes again; the fault is logged and listed in ``faults``;
- every time the link drops and every time it comes back is a fault (robot 0, with its time); after
  a reconnection a robot is sent nothing but stops until odometry has come over the new connection
  (its plan goes on from rest then);
- a link that fails (lost for longer than its ``reconnect`` time) or flaps (drops more than
  ``flap_limit.drops`` times within ``flap_limit.seconds``) stops the run: ``advance`` raises
  LinkError after a last stop to every robot;
- ``close()`` (the end of any run) sends a stop to every robot before the link closes.

In lockstep (a simulated robot whose clock moves only when vwg steps it) a drop is a fault and counts
towards the flap limit as above, but it stops nothing and halts no plan: the robot's clock stands still
with the link, so the odometry vwg has is still the robot's. The frames wait for the link to come back;
the velocities of the tick under way and its step are then sent again over the new connection, the step
with the same id, so a robot that had stepped already (its answer lost with the connection) does not
step twice. A robot whose step service does not echo step ids ends the run instead when a step was in
flight: vwg cannot tell whether it stepped.
"""

from __future__ import annotations

import bisect
import contextlib
import logging
import math
import threading
import time
import uuid
import weakref
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import vwg._core as _core
from vwg.robot.links.ros_messages import LaserScan, Odometry, pose_compose, pose_relative
from vwg.robot.links.rosbridge_client import CallLostError, LinkError
from vwg.robot.platform import Option

__all__ = ["LINK_OPTIONS", "ODOMETRY_KEPT", "Fault", "FlapLimit", "RealRobotPlatform"]

log = logging.getLogger("vwg.robot")

#: Odometry messages kept per robot to place a sensor's reading from where the robot was when it was
#: taken (RealRobotPlatform.viewpoint): 10 s at 50 Hz, older than any image or scan still worth using.
ODOMETRY_KEPT = 500

@dataclass(frozen=True)
class Fault:
    """Something that went wrong with a real robot: when (seconds since the run started), which robot
    (0: the link), and what."""

    time: float
    robot: int
    what: str

    def to_json(self) -> dict[str, Any]:
        return {"time_s": round(self.time, 3), "robot": self.robot, "what": self.what}


@dataclass(frozen=True)
class FlapLimit:
    """A link that drops more than ``drops`` times within ``seconds`` is given up on (world file:
    ``platform: {flap_limit: {drops: 3, seconds: 10}}``): each reconnection feeds the watchdog
    again, so without a limit a link that keeps dropping would keep the robot going half-blind."""

    drops: int = 3
    seconds: float = 10.0

    MAX_DROPS = 1_000_000
    MAX_SECONDS = 86_400.0

    @classmethod
    def of(cls, value: FlapLimit | Mapping[str, Any] | None) -> FlapLimit:
        """The limit a platform option gives (a mapping with ``drops`` and/or ``seconds``, the others'
        defaults), checked as the world file's option is (LINK_OPTIONS); SchemaError naming the field."""
        if value is None:
            return cls()
        if isinstance(value, FlapLimit):
            return value
        return LINK_OPTIONS["flap_limit"].value("platform.flap_limit", value)  # type: ignore[no-any-return]


#: The options a real robot's link shares (the seconds bounded by a day).
LINK_OPTIONS: dict[str, Option] = {
    "watchdog": Option(float, 0.5, minimum=0.0, exclusive_minimum=True, maximum=86400.0,
                       help="seconds without odometry before the robot is stopped"),
    "reconnect": Option(float, 5.0, minimum=0.0, maximum=86400.0,
                        help="seconds to keep trying a dropped link before the run stops"),
    "control_rate": Option(float, 20.0, minimum=1.0, maximum=1000.0, help="velocity commands a second"),
    "flap_limit": Option(dict, {"drops": FlapLimit.drops, "seconds": FlapLimit.seconds},
                         help="{drops: N, seconds: S}: a link dropping more often is given up on",
                         fields={"drops": Option(int, minimum=1, maximum=FlapLimit.MAX_DROPS),
                                 "seconds": Option(float, minimum=0.0, exclusive_minimum=True,
                                                   maximum=FlapLimit.MAX_SECONDS)},
                         convert=lambda value: FlapLimit(**value)),
}


@dataclass
class _Robot:
    settings: _core.RobotSettings
    follower: _core.MotionFollower
    odom: Odometry | None = None     # relative to the first odometry this run received
    origin: Odometry | None = None   # that first odometry: the base's own count may not start at zero
    odom_at: float = 0.0            # monotonic time the last odometry came
    odom_connection: int = 0        # the link's connection that odometry came over
    silent: bool = False            # the watchdog has stopped it
    commands: int = 0
    travelled: float = 0.0
    scan: LaserScan | None = None
    # The odometry of the last ODOMETRY_KEPT messages (local, oldest first), and the one the frame under
    # way took when it began: every reading of that frame is placed from the same pose.
    history: deque[Odometry] = field(default_factory=lambda: deque(maxlen=ODOMETRY_KEPT))
    frame_odom: Odometry | None = None
    warned_stale: bool = False      # a reading outside the odometry kept has been logged


def _pose_at(history: deque[Odometry], stamp: float) -> tuple[float, float, float] | None:
    """The odometry pose at `stamp`, interpolated between the messages on either side of it (the
    newest when it is newer than all); None when it is older than the oldest kept."""
    if not history or stamp < history[0].time:
        return None
    after = bisect.bisect_left(history, stamp, key=lambda o: o.time)
    if after == len(history):
        newest = history[-1]
        return newest.x, newest.y, newest.yaw
    b = history[after]
    if b.time == stamp or after == 0:
        return b.x, b.y, b.yaw
    a = history[after - 1]
    t = (stamp - a.time) / (b.time - a.time)
    turn = math.remainder(b.yaw - a.yaw, math.tau)  # the short way round
    return a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), math.remainder(a.yaw + t * turn, math.tau)


class RealRobotPlatform(_core.RobotPlatform):
    """The robots of a world on a real link (a subclass gives the link). ``watchdog`` seconds of
    silence stop a robot; ``control_rate`` is how often (Hz) velocities are sent between frames;
    ``flap_limit`` how many drops of the link (within how many seconds) end the run."""

    kind = "real"

    def __init__(self, robots: list[_core.RobotSettings], *, watchdog: float = LINK_OPTIONS["watchdog"].default,
                 control_rate: float = LINK_OPTIONS["control_rate"].default,
                 lockstep: bool = False, flap_limit: FlapLimit | Mapping[str, Any] | None = None) -> None:
        super().__init__()
        if not (math.isfinite(watchdog) and watchdog > 0):
            raise LinkError(f"platform watchdog: expected seconds > 0, got {watchdog}")
        if not (math.isfinite(control_rate) and 1 <= control_rate <= 1000):
            raise LinkError(f"platform control_rate: expected 1 to 1000 Hz, got {control_rate}")
        self.watchdog = watchdog
        self.control_period = 1.0 / control_rate
        self.flap_limit = FlapLimit.of(flap_limit)
        self.lockstep = lockstep
        self._clock = 0.0    # lockstep: the robot's simulated time
        self._pending = 0.0  # lockstep: time asked for that is less than a control period
        self._steps = 0      # lockstep: steps asked for; step n's id is "<run>:<n>"
        self._run_id = uuid.uuid4().hex[:12]
        self._repeatable = False  # lockstep: the robot echoed a step id (a step sent again is not done twice)
        self.faults: list[Fault] = []
        self._lock = threading.Lock()
        self._robots: dict[int, _Robot] = {}
        self._t0 = time.monotonic()
        self._frame_end = self._t0
        self._closed = False
        self._failing = False              # _fail has begun (from one thread: the other leaves it)
        self._failure: str | None = None
        # The link's connections, as the subclass reports them: 0 until it reports any (a link that
        # does not report them is taken as always the same connection).
        self._connection = 0
        self._down_at: float | None = None  # when the link dropped, until it is back
        self._drops: deque[float] = deque()  # when it dropped, within the last flap_limit.seconds
        self._flapping: str | None = None   # the flap limit was passed: the run ends at the next check
        for r in robots:
            self.add_robot(r)
        # The robots are controlled and watched on a thread of their own, at control_rate, whatever
        # the frames are doing: a slow frame (a long replan, a video) leaves no robot unwatched. It
        # starts with the first command or frame, once the subclass has its link.
        self._stop_control = threading.Event()
        self._control_thread = threading.Thread(target=self._control_loop, name="vwg-robot-control", daemon=True)

    # ---- what the link calls ----------------------------------------------------------------------------------
    def on_odometry(self, robot: int, odom: Odometry) -> None:
        with self._lock:
            r = self._robots.get(robot)
            if r is None:
                return
            if r.origin is None:
                r.origin = odom
            # Odometry relative to where this run found the robot: origin⁻¹ ⊕ odom.
            x, y, yaw = pose_relative((r.origin.x, r.origin.y, r.origin.yaw), (odom.x, odom.y, odom.yaw))
            local = Odometry(odom.time, x, y, yaw, odom.speed, odom.turn_rate)
            if r.odom is not None:
                r.travelled += math.hypot(local.x - r.odom.x, local.y - r.odom.y)
            newest = r.history[-1].time if r.history else -math.inf
            if local.time >= newest:
                r.history.append(local)
            elif newest - local.time > self.watchdog:
                # The robot's clock went back (it restarted): the old stamps mean nothing now.
                r.history.clear()
                r.history.append(local)
                r.warned_stale = False
            # else a message older than the newest (reordered, or sent twice): kept out of the history
            r.odom = local
            r.odom_at = time.monotonic()
            r.odom_connection = self._connection

    def on_scan(self, robot: int, scan: LaserScan) -> None:
        with self._lock:
            r = self._robots.get(robot)
            if r is not None:
                r.scan = scan

    def viewpoint(self, robot: int, stamp: float) -> tuple[float, float, float] | None:
        """Where `robot` was at `stamp` (its odometry's clock) in its frame at the frame under way: (metres
        ahead, metres to the left, radians). An image or a scan arrives after it was taken, while the robot
        moves on; what it saw is placed from there: the pose interpolated between the odometry messages on
        either side of the stamp, or the newest one for a stamp after it.

        Placed from the frame's pose, (0, 0, 0): a stamp of 0 (a driver that does not stamp; ROS reads it as
        "the latest"), and any reading before the robot's first odometry (the frame has it at its start).
        None, and not used: a stamp older than the odometry kept, or more than ``watchdog`` seconds after the
        newest (a sensor on another clock than the odometry's, which the log says once), or not finite."""
        with self._lock:
            r = self._robots.get(robot)
            if r is None or not math.isfinite(stamp):
                return None
            now = r.frame_odom or r.odom
            if now is None or stamp == 0.0:
                return 0.0, 0.0, 0.0
            oldest, newest = r.history[0].time, r.history[-1].time
            then = _pose_at(r.history, stamp) if stamp <= newest + self.watchdog else None
            if then is None:
                if not r.warned_stale:  # once: a sensor on another clock than the odometry would lose every reading
                    r.warned_stale = True
                    log.warning("%s: robot %d: a reading stamped %.3f s is outside the odometry kept (%.3f to %.3f s, "
                                "and up to the watchdog's %g s after) and is not used; are the sensor's stamps on the "
                                "odometry's clock?", self.name(), robot, stamp, oldest, newest, self.watchdog)
                return None
            return pose_relative((now.x, now.y, now.yaw), then)

    def viewpoint_of(self, robot: int) -> Callable[[float], tuple[float, float, float] | None]:
        """viewpoint for one robot, holding this platform weakly: for a C++ image source
        (vwg._core.ReceivedImages(viewpoint=...)), which the garbage collector does not look into, so that a
        strong reference would keep the platform alive for ever."""
        ref = weakref.ref(self)

        def at(stamp: float) -> tuple[float, float, float] | None:
            platform = ref()
            return None if platform is None else platform.viewpoint(robot, stamp)

        return at

    def latest_scan(self, robot: int) -> LaserScan | None:
        with self._lock:
            r = self._robots.get(robot)
            return r.scan if r else None

    def link_up(self, connection: int) -> None:
        """The link's connection number `connection` is up (called by the subclass from the thread
        that delivers odometry, before any odometry of that connection). Every one after the first is
        a reconnection: a fault, and each robot is sent only stops until odometry has come over it."""
        with self._lock:
            self._connection = connection
            down_at, self._down_at = self._down_at, None
            if down_at is not None and not self._failing:  # once the run has ended on the link, not its news
                gap = time.monotonic() - down_at
                then = ("the robot's clock stood still meanwhile" if self.lockstep
                        else "robots wait for odometry over it")
                self._fault_locked(0, f"link back after {gap:.2f} s (connection {connection}); {then}",
                                   level=logging.WARNING)

    def link_down(self, reason: str) -> None:
        """The link's connection dropped (called by the subclass from its own thread, which must not
        block: no velocity is sent here). A fault; the robots halt; more drops than the flap limit
        within its seconds end the run (at the control thread's or the frames' next check)."""
        with self._lock:
            now = time.monotonic()
            if self._down_at is not None or self._failing:
                return  # still down (one drop), or the run has ended on the link already
            self._down_at = now
            self._drops.append(now)
            while now - self._drops[0] > self.flap_limit.seconds:
                self._drops.popleft()
            self._fault_locked(0, f"link lost ({reason}); drop {len(self._drops)} within "
                                  f"{self.flap_limit.seconds:g} s")
            if not self.lockstep:  # in lockstep the robot cannot move until it is stepped again
                for r in self._robots.values():
                    r.follower.halt()  # its plan goes on from rest once odometry comes over a new connection
            limit = self.flap_limit
            if len(self._drops) > limit.drops and self._flapping is None:
                self._flapping = (f"the link dropped {len(self._drops)} times within {limit.seconds:g} s "
                                  f"(flap_limit: more than {limit.drops} drops in {limit.seconds:g} s)")

    # ---- what a link subclass gives ---------------------------------------------------------------------------
    def send_velocity(self, robot: int, speed: float, turn_rate: float, *,
                      connection: int | None = None) -> bool:  # pragma: no cover - abstract
        """Send a velocity; with `connection`, only over that connection of the link (a motion
        computed from one connection's odometry is not sent over the next): False when not sent."""
        raise NotImplementedError

    def link_failure(self) -> str | None:  # pragma: no cover - abstract
        raise NotImplementedError

    def wait_link(self, timeout: float) -> bool:
        """Wait up to `timeout` seconds for the link to be up; whether it is (a link that does not say: up)."""
        return True

    def close_link(self) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    # ---- RobotPlatform -------------------------------------------------------------------------------------------
    def add_robot(self, settings: _core.RobotSettings) -> None:
        settings.check(f"robot {settings.id}")
        with self._lock:
            if settings.id in self._robots:
                raise LinkError(f"robot {settings.id}: the id is used twice")
            self._robots[settings.id] = _Robot(settings, _core.MotionFollower(settings), odom_at=time.monotonic())

    def remove_robot(self, robot: int) -> None:
        self.send_velocity(robot, 0.0, 0.0)
        with self._lock:
            self._robots.pop(robot, None)

    def _ensure_control(self) -> None:
        if self._control_thread.ident is None and not self._stop_control.is_set() and not self.lockstep:
            self._control_thread.start()

    def command(self, robot: int, steps: list[tuple[str, float] | tuple[str, float, float]]) -> None:
        self._ensure_control()
        with self._lock:
            r = self._robots[robot]
            r.follower.command(list(steps))
            r.commands += 1

    def advance(self, seconds: float) -> None:
        """Let `seconds` of wall-clock time pass from the end of the last frame (the robots follow
        their plans meanwhile, on the control thread); LinkError when the link has failed. In lockstep,
        the robot's clock is stepped instead, as the simulator steps its own."""
        if self.lockstep:
            self._advance_lockstep(seconds)
        else:
            self._advance_wall_clock(seconds)
        with self._lock:  # the next frame's poses: the odometry as it stands now
            for r in self._robots.values():
                r.frame_odom = r.odom  # None until its first odometry: the frame has it at its start

    def _advance_wall_clock(self, seconds: float) -> None:
        self._ensure_control()
        self._frame_end = max(self._frame_end + seconds, time.monotonic() - seconds)  # a late frame does not pile up
        while True:
            self._raise_if_failed()
            now = time.monotonic()
            if now >= self._frame_end:
                return
            time.sleep(min(self.control_period, self._frame_end - now))

    @staticmethod
    def _map_pose(r: _Robot, odom: Odometry | None = None) -> tuple[float, float, float]:
        """The map pose: start ⊕ odometry (by default the latest; odometry starts at zero where the robot
        starts), at the float resolution every platform reports (vwg.robot.quantize_pose; the start too,
        as the simulator places its bodies)."""
        odom = odom or r.odom
        local = (odom.x, odom.y, odom.yaw) if odom else (0.0, 0.0, 0.0)
        return _core.quantize_pose(pose_compose(_core.quantize_pose(r.settings.start), local))

    # ---- lockstep -------------------------------------------------------------------------------------------------
    def step_clock(self, seconds: float, step_id: str, connection: int | None) -> bool:  # pragma: no cover
        """Lockstep: let the robot's simulated clock advance `seconds` (0: publish where it is), the step
        called `step_id`, over the link's connection `connection` (None: whichever is up), and return once
        its odometry after the step has come: whether the robot echoed the id (it does not do a step whose
        id it has done again). CallLostError when the link was down or dropped before the answer; LinkError
        when the robot does not answer or refuses."""
        raise NotImplementedError

    def _step(self, sends: list[tuple[int, float, float, int | None]], seconds: float) -> None:
        """Lockstep: the velocities of a tick, then the step of the robot's clock, over one connection; when
        the link is down or drops before the answer, both again over the next connection (the same
        velocities, the same step id), as often as the link comes back within its reconnect time and flap
        limit. LinkError when it does not, or when a step was in flight and the robot takes no step ids."""
        self._steps += 1
        step_id = f"{self._run_id}:{self._steps}"
        while True:
            self._raise_if_failed()
            while not self.wait_link(self.control_period):
                self._raise_if_failed()
            connection = self._connection or None
            for rid, v, w, _ in sends:
                self.send_velocity(rid, v, w, connection=connection)  # lost with the connection: the step is too
            try:
                self._repeatable = self.step_clock(seconds, step_id, connection)
                return
            except CallLostError as e:
                if not e.sent:  # the step never went out: the link is down, or about to say so
                    log.debug("%s: lockstep: step %d not sent (%s); again once the link is up", self.name(),
                              self._steps, e)
                    time.sleep(self.control_period)
                    continue
                if not self._repeatable and seconds > 0:  # (a step of 0 s moves no clock: it can always go again)
                    raise LinkError(f"{e}; the robot's step service echoes no step_id, so vwg cannot tell "
                                    f"whether it stepped: step {self._steps} is not sent again") from None
                self._fault(0, f"lockstep: the link dropped before step {self._steps} was answered; "
                               "its velocities and the step go again over the next connection (the robot "
                               "does a step once)", level=logging.WARNING)

    def _advance_lockstep(self, seconds: float) -> None:
        # Whole control periods, the remainder carried over: the simulator's own arithmetic, so
        # both take the same number of steps in every frame.
        period = self.control_period
        total = self._pending + seconds
        steps = math.floor(total / period + 1e-9)
        self._pending = max(0.0, total - steps * period)
        for _ in range(steps):
            self._raise_if_failed()
            with self._lock:
                sends = [self._next_velocity(rid, r, period) for rid, r in self._robots.items()]
            try:
                self._step(sends, period)
            except LinkError as e:
                self._fail(str(e))
                raise
            self._clock += period
            with self._lock:
                for r in self._robots.values():
                    r.follower.settle(self._map_pose(r))

    def _next_velocity(self, rid: int, r: _Robot, dt: float) -> tuple[int, float, float, int | None]:
        """(robot, speed, turn rate, the connection it may go over): a stop while the link is down or
        the robot has had no odometry over its current connection (a reconnection), else the
        follower's next. In lockstep always the follower's next: the robot has not moved since its last
        odometry, whichever connection brought it (and the tick waits for the link)."""
        if not self.lockstep and (self._down_at is not None or r.odom_connection != self._connection):
            r.follower.halt()
            return rid, 0.0, 0.0, None
        v, w = r.follower.tick(self._map_pose(r), dt)
        return rid, v, w, self._connection or None

    def _send_all(self, sends: list[tuple[int, float, float, int | None]]) -> None:
        for rid, v, w, connection in sends:
            if connection is None:  # a stop goes over whatever connection there is
                self.send_velocity(rid, v, w)
            else:
                self.send_velocity(rid, v, w, connection=connection)

    def _fail(self, reason: str) -> None:
        """The link has failed: a fault, a stop to every robot that can still be stopped, and every
        advance from now on raises LinkError."""
        with self._lock:
            if self._failing:
                return  # the other thread is failing it already
            self._failing = True
        # In this order: advance() raises as soon as _failure is set, and by then the robots must
        # have been sent their stop and the fault be listed.
        with contextlib.suppress(Exception):
            self.stop_all()
        self._fault(0, reason)
        self._failure = reason

    def _link_failure(self) -> str | None:
        """Why the run must end because of the link: it flapped, or the subclass says it failed."""
        return self._flapping or self.link_failure()

    def _raise_if_failed(self) -> None:
        if not self._failing:
            failure = self._link_failure()
            if failure:
                self._fail(failure)
        if self._failure:
            raise LinkError(f"{self.name()} link: {self._failure}")

    def _control_loop(self) -> None:
        last = time.monotonic()
        while not self._stop_control.wait(self.control_period):
            now = time.monotonic()
            try:
                failure = self._link_failure()
                if failure:
                    self._fail(failure)
                    return
                # The time that really passed (capped): the accelerations stay within the limits.
                self._control(min(now - last, 2 * self.control_period))
            except Exception as e:  # a link that throws: stop what can be stopped, end the run
                self._fail(f"control failed: {type(e).__name__}: {e}")
                return
            last = now

    def _control(self, dt: float) -> None:
        now = time.monotonic()
        sends: list[tuple[int, float, float, int | None]] = []
        with self._lock:
            for rid, r in self._robots.items():
                if r.odom is None and now - r.odom_at <= self.watchdog:
                    sends.append((rid, 0.0, 0.0, None))  # waiting for the first odometry: keep still
                    continue
                if r.odom is None or now - r.odom_at > self.watchdog:
                    if not r.silent:
                        r.silent = True
                        quiet = now - r.odom_at
                        self._fault_locked(rid, f"no odometry for {quiet:.2f} s (watchdog {self.watchdog:g} s): "
                                                "stopped")
                    r.follower.halt()
                    sends.append((rid, 0.0, 0.0, None))
                    continue
                if r.silent:
                    r.silent = False
                    log.warning("%s: robot %d: odometry again; moving on", self.name(), rid)
                sends.append(self._next_velocity(rid, r, dt))
        self._send_all(sends)

    def _fault(self, robot: int, what: str, level: int | None = None) -> None:
        with self._lock:
            self._fault_locked(robot, what, level)

    def _fault_locked(self, robot: int, what: str, level: int | None = None) -> None:
        fault = Fault(time.monotonic() - self._t0, robot, what)
        self.faults.append(fault)
        if robot:
            log.log(level or logging.WARNING, "%s: robot %d: %s", self.name(), robot, what)
        else:
            log.log(level or logging.ERROR, "%s: %s", self.name(), what)

    def stop_all(self) -> bool:
        """Drop every plan and send every robot a stop; False when a stop could not be sent."""
        with self._lock:
            ids = list(self._robots)
            for r in self._robots.values():
                r.follower.stop()
        return all([self.send_velocity(rid, 0.0, 0.0) for rid in ids])  # a list: every robot is sent one

    def robots(self) -> list[_core.RobotState]:
        with self._lock:
            out = []
            for rid, r in self._robots.items():
                # The pose and velocities of the frame (its readings are placed from them); the counters
                # (commands, distance driven) as they stand.
                odom = r.frame_odom or r.odom
                pose = self._map_pose(r, odom)
                out.append(_core.RobotState(rid, pose, pose, radius=r.settings.radius, busy=r.follower.busy,
                                            commands=r.commands, travelled=r.travelled,
                                            speed=odom.speed if odom else 0.0,
                                            turn_rate=odom.turn_rate if odom else 0.0))
            return out

    def take_collisions(self) -> list[_core.Collision]:
        return []  # a real base reports no contacts here (a bumper topic would)

    def time(self) -> float:
        return self._clock if self.lockstep else time.monotonic() - self._t0

    def close(self) -> None:
        """Stop every robot, then close the link (the end of any run)."""
        if self._closed:
            return
        self._closed = True
        self._stop_control.set()
        if self._control_thread.ident is not None:
            self._control_thread.join(2.0)
        try:
            self._stop_before_closing()
        finally:
            self.close_link()

    def _stop_before_closing(self, patience: float = 1.0) -> None:
        """A stop to every robot; when one cannot go (a link that has just dropped, as a flapping one
        has when the run ends), again while the link reconnects, for up to `patience` seconds, unless
        it has given up."""
        until = time.monotonic() + patience
        while not self.stop_all() and time.monotonic() < until and not self.link_failure():
            time.sleep(self.control_period)
