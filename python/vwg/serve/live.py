"""A robot world running live for a viewer: its frames on a thread of their own, paced to the clock
(or as fast as they go), with pause, step, speed, reset, orders and a selected robot.

The run's thread is the only one that touches the engine. After each frame it makes a snapshot (plain
data: poses, objectives, paths, scans, the selected robot's string and camera image) and hands it to
``on_frame``, which must not block (the server keeps the latest snapshot and tells its clients).
Commands from other threads go through a queue the run's thread empties between frames; orders go
straight to gObjective (vwg.robot.case_study.Orders), which takes them from any thread at the next frame.

The queue is bounded per client (``client=``: the viewer passes its WebSocket): at most MAX_WAITING
commands from one client wait at a time, and one more is refused with an error that client is sent.
A command of the same kind as the last one waiting merges into it, when doing both is the same as
doing the last: reset, pause, resume (twice is once), speed, select (the last value holds) and step
(one entry that counts its steps). Of the commands taken at once, resets before the last one are not
done (nor orders before it, which it would drop): a reset builds the world again (0.1-0.3 s for
the office), and 1,000 of them in a row cost one or two, not 263 s of stalled frames.
"""

from __future__ import annotations

import dataclasses
import json
import threading
import time
from collections import Counter
from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

import vwg._core as _core
from vwg.errors import Error, SchemaError
from vwg.robot.case_study import CaseStudy
from vwg.robot.platforms.real_robots import ScanGenerator
from vwg.robot.topics import Sink, case_topics
from vwg.robot.world_file import PlatformSpec, RobotWorld

__all__ = ["MAX_SPEED", "MAX_WAITING", "LiveRun", "Snapshot"]

MAX_SPEED = 0.0  # the speed that means "as fast as the frames go"
SCAN_ROBOTS = 50  # robots whose laser is shown (beyond this the view shows robots and paths only)
STRING_CHARS = 4000  # the selected robot's string is clipped to this
MAX_WAITING = 32  # commands from one client waiting for the run's thread (a person clicks a few a second)
MERGING = ("reset", "pause", "resume", "speed", "select", "step")  # repeated, these are one command


@dataclass
class Snapshot:
    """What the viewer shows of one frame (plain data, safe to read from any thread)."""

    frame: int
    time: float
    status: str  # running, paused, stopped
    speed: float
    selected: int | None
    robots: list[dict[str, Any]]
    string: str = ""  # the selected robot's string
    people: list[dict[str, Any]] = field(default_factory=list)  # id, x, y, radius of each person who walks
    camera: np.ndarray | None = None  # the selected robot's last camera image (H×W×3), if it has a camera
    serial: int = 0  # counts snapshots: a viewer tells a new one from the last
    errors: list[str] = field(default_factory=list)
    text: str | None = field(default=None, repr=False)  # message() as JSON, made once for every client

    def state(self) -> dict[str, Any]:
        """GET /api/state: frame, time, status, each robot's id, pose, objective, reached and status ("to kitchen",
        "interrupted", ...), and the people."""
        keys = ("id", "x", "y", "angle", "objective", "reached", "status")
        return {"frame": self.frame, "time": self.time, "status": self.status, "speed": self.speed,
                "selected": self.selected, "robots": [{k: r[k] for k in keys} for r in self.robots],
                "people": self.people}

    def message(self) -> dict[str, Any]:
        """The WebSocket message of this frame: the state with paths, scans, statuses, the string, errors."""
        return {"type": "frame", **self.state(), "robots": self.robots, "string": self.string, "errors": self.errors}

    def encode(self) -> str:
        """message() as JSON text, kept: made once however many clients are sent it."""
        if self.text is None:
            self.text = json.dumps(self.message())
        return self.text


@dataclass
class Command:
    """A command waiting for the run's thread: ``kind``, its ``value``, the ``client`` that gave it,
    and ``count`` (the steps merged into one step)."""

    kind: str
    value: Any
    client: Hashable
    count: int = 1


class CommandQueue:
    """The commands waiting for the run's thread, in the order given, at most ``bound`` from each
    client; a command of a MERGING kind that repeats the last one waiting merges into it."""

    def __init__(self, bound: int = MAX_WAITING) -> None:
        self.bound = bound
        self._ready = threading.Condition()
        self._waiting: list[Command] = []
        self._per_client: Counter[Hashable] = Counter()
        self._woken = False  # wake() was called: no take() waits any more

    def put(self, kind: str, value: Any = None, client: Hashable = None) -> None:
        """Queue a command; over the bound of its client it is refused (an Error saying so)."""
        with self._ready:
            last = self._waiting[-1] if self._waiting else None
            if last is not None and last.kind == kind and kind in MERGING:
                if kind == "step":
                    last.count += 1
                else:
                    last.value = value  # speed, select: the last value holds; reset, pause, resume: once is twice
                return
            if self._per_client[client] >= self.bound:
                raise Error(f"{kind}: refused, {self.bound} commands from this client are still waiting for the "
                            "run (a reset or a slow frame under way); send it again once a frame has come")
            self._waiting.append(Command(kind, value, client))
            self._per_client[client] += 1
            self._ready.notify()

    def take(self, timeout: float) -> list[Command]:
        """Every command waiting, in order, once there is one or after `timeout` seconds (then [])."""
        with self._ready:
            if timeout > 0:
                self._ready.wait_for(lambda: self._waiting or self._woken, timeout)
            taken, self._waiting = self._waiting, []
            self._per_client.clear()
            return taken

    def wake(self) -> None:
        """End a take() that is waiting, and any later one's wait (the run is stopping)."""
        with self._ready:
            self._woken = True
            self._ready.notify_all()

    def __len__(self) -> int:
        with self._ready:
            return len(self._waiting)


class LiveRun:
    """A robot world run live: ``start()``, then ``pause()``, ``resume()``, ``step()``, ``set_speed()``,
    ``reset()``, ``order(robot, room)``, ``cancel(robot)``, ``select(robot)``; ``stop()`` ends it. Each command
    is checked where it is given (an error names what is wrong) and done by the run's thread between frames; each
    takes ``client=`` (who gave it), whose waiting commands are bounded (MAX_WAITING, see the module)."""

    def __init__(self, world: RobotWorld, *, planner: str = "astar", platform: PlatformSpec | None = None,
                 speed: float = 1.0, seed: int | None = None, threads: int = 0, world_orders: bool = True,
                 paused: bool = False, on_frame: Callable[[Snapshot], None] = lambda s: None,
                 topics_to: Sequence[Sink] = ()) -> None:
        self.world = world
        self.topics_to = list(topics_to)  # where each case's ROS 2 topics go (a Foxglove server), across resets
        self.planner = planner
        self.platform = platform
        self.seed = seed
        self.threads = threads
        self.world_orders = world_orders
        self.on_frame = on_frame
        self._commands = CommandQueue()
        self._stop = threading.Event()
        self._speed = self._checked_speed(speed)
        self._paused = paused
        self._steps = 0
        self._selected: int | None = world.robots[0].id if world.robots else None
        self._serial = 0
        self._errors: list[str] = []
        self._failed = False  # the run stopped on an error (a frame, a reset): it says so and waits
        self.case: CaseStudy | None = self._new_case()
        try:
            # A real robot's platform keeps the frames to the clock itself (vwg.robot.platforms.real_robot); the
            # simulator's frames are paced here, at the chosen speed.
            self.real_time_platform = not isinstance(self.case.sim.platform, _core.PhysicsWorld)
            if self.real_time_platform and speed != 1.0:
                raise SchemaError(f"speed: a real robot runs at real time (1), got {speed!r}")
            self.thread = threading.Thread(target=self._loop, name="vwg-live-run", daemon=True)
            self.latest = self._snapshot()
        except BaseException:
            self.case.close()  # a real robot's link is open: it is stopped and closed
            raise

    # ---- commands (any thread) ---------------------------------------------------------------------------
    def start(self) -> None:
        self.thread.start()

    def stop(self) -> None:
        """End the run; the run's thread closes its case (a real robot is sent a stop)."""
        self._stop.set()
        self._commands.wake()
        if self.thread.is_alive():
            if threading.current_thread() is not self.thread:
                self.thread.join(timeout=30)
        else:  # never started: nothing else touches the case
            if self.case is not None:
                self.case.close()
                self.case = None
            for sink in self.topics_to:
                sink.close()

    def pause(self, client: Hashable = None) -> None:
        """Stop the frames (and any steps still to run)."""
        self._commands.put("pause", None, client)

    def resume(self, client: Hashable = None) -> None:
        self._commands.put("resume", None, client)

    def step(self, client: Hashable = None) -> None:
        """One frame, when paused."""
        self._commands.put("step", None, client)

    def reset(self, client: Hashable = None) -> None:
        """Start the world again from its first frame (orders given so far are dropped)."""
        self._commands.put("reset", None, client)

    def set_speed(self, speed: float, client: Hashable = None) -> None:
        speed = self._checked_speed(speed)
        if self.real_time_platform and speed != 1.0:
            raise SchemaError(f"speed: a real robot runs at real time (1), got {speed!r}")
        self._commands.put("speed", speed, client)

    def select(self, robot: int, client: Hashable = None) -> None:
        self.check_robot(robot)
        self._commands.put("select", robot, client)

    def order(self, robot: int, room: str, client: Hashable = None) -> None:
        """Send `robot` to `room` through gObjective (an eObjective<marker> event at the next frame)."""
        self.check_robot(robot)
        if not isinstance(room, str) or room not in self.world.rooms:
            raise SchemaError(f"order: unknown room {room!r} (rooms: {', '.join(self.world.rooms)})")
        self._commands.put("order", (robot, room), client)

    def cancel(self, robot: int, client: Hashable = None) -> None:
        """Interrupt `robot`'s task through gObjective (eObjective<marker=-1> at the next frame): it stops."""
        self.check_robot(robot)
        self._commands.put("cancel", robot, client)

    @staticmethod
    def _checked_speed(speed: Any) -> float:
        ok = isinstance(speed, (int, float)) and not isinstance(speed, bool)
        ok = ok and (speed == MAX_SPEED or 0.05 <= speed <= 100)  # (a huge int compares without overflow)
        if not ok:
            raise SchemaError(f"speed: expected 0.05 to 100 times real time, or 0 for as fast as it goes; "
                              f"got {speed!r}")
        return float(speed)

    def check_robot(self, robot: Any) -> None:
        if isinstance(robot, bool) or not isinstance(robot, int) or robot not in {r.id for r in self.world.robots}:
            raise SchemaError(f"robot: no robot {robot!r} (robots: {', '.join(str(r.id) for r in self.world.robots)})")

    # ---- the run's thread ------------------------------------------------------------------------------
    def _new_case(self) -> CaseStudy:
        case = CaseStudy(self.world, self.planner, seed=self.seed, frames=2**62, platform=self.platform,
                         threads=self.threads, world_orders=self.world_orders)
        if self.topics_to:
            case_topics(case, self.topics_to)  # it observes the case's engine: gone with the case
        return case

    def _waiting(self) -> bool:
        return self._failed or (self._paused and self._steps == 0)

    def _loop(self) -> None:
        try:
            next_time = time.monotonic()
            while not self._stop.is_set():
                # Between frames: the commands, waiting for one while paused or until the next frame is due.
                wait = None if self._waiting() else max(0.0, next_time - time.monotonic())
                self._apply_commands(timeout=0.5 if wait is None else wait)
                if self._stop.is_set():
                    break
                if self._waiting() or time.monotonic() < next_time:
                    continue
                self._frame()
                if self._speed != MAX_SPEED and not self._paused and not self.real_time_platform:
                    next_time = max(next_time + self.world.dt / self._speed, time.monotonic() - 0.5)
                else:
                    next_time = time.monotonic()
        finally:
            if self.case is not None:
                self.case.close()  # on this thread, the only one that touches it (a real robot is stopped)
                self.case = None
            for sink in self.topics_to:
                sink.close()

    def _frame(self) -> None:
        assert self.case is not None
        try:
            self.case.engine.step()
        except Exception as e:  # a frame that failed: the run stops and says why; the viewer stays up
            self._fail(f"frame {self.case.engine.frame}: {e}")
        if self._steps:
            self._steps -= 1
        self._publish()

    def _fail(self, message: str) -> None:
        self._errors.append(message)
        self._failed = True
        if self.real_time_platform and self.case is not None:
            self.case.sim.platform.stop_all()

    def _apply_commands(self, timeout: float) -> None:
        commands = self._commands.take(timeout)
        if not commands:
            return
        # Only the last reset is done: the world built by an earlier one would be thrown away by it, with
        # the orders given to it. The other commands (pause, speed, ...) outlive a reset and are all done.
        last_reset = max((i for i, c in enumerate(commands) if c.kind == "reset"), default=-1)
        for i, command in enumerate(commands):
            if i < last_reset and command.kind in ("reset", "order"):
                continue
            self._apply(command.kind, command.value, command.count)
        self._publish()  # once for all of them

    def _apply(self, kind: str, value: Any, count: int = 1) -> None:
        if kind == "pause":
            self._paused, self._steps = True, 0
            if self.real_time_platform and self.case is not None:
                self.case.sim.platform.stop_all()  # a real robot stops where it is, not at the end of its move
        elif kind == "resume":
            self._paused, self._steps = False, 0
        elif kind == "step":
            self._paused, self._steps = True, self._steps + count
        elif kind == "speed":
            self._speed = value
        elif kind == "select":
            self._selected = value
        elif kind == "order" and self.case is not None:
            self.case.orders.order(*value)
        elif kind == "cancel" and self.case is not None:
            self.case.orders.cancel(value)
        elif kind == "reset":
            if self.case is not None:
                self.case.close()
                self.case = None
            self._errors.clear()
            self._failed = False
            try:
                self.case = self._new_case()
            except Exception as e:  # a link refused, ...: said on the page; Reset tries again
                self._fail(f"reset: {e}")

    def _publish(self) -> None:
        try:
            self.latest = self._snapshot()
        except Exception as e:
            self._fail(f"showing frame: {e}")
            self.latest = dataclasses.replace(self.latest, status="stopped", errors=list(self._errors),
                                              serial=self._next_serial())
        self.on_frame(self.latest)

    def _next_serial(self) -> int:
        self._serial += 1
        return self._serial

    def _status(self) -> str:
        return "stopped" if self._failed else "paused" if self._paused else "running"

    def _snapshot(self) -> Snapshot:
        case = self.case
        if case is None:
            return Snapshot(frame=0, time=0.0, status="stopped", speed=self._speed, selected=self._selected,
                            robots=[], serial=self._next_serial(), errors=list(self._errors))
        actors = case.robot_actors()
        last = case.orders.last
        platform = case.sim.platform
        robots = []
        lasers = {g.robot: g for g in case.sim.made if isinstance(g, (_core.LaserGenerator, ScanGenerator))}
        for n, spec in enumerate(self.world.robots):
            state = platform.find_robot(spec.id)
            if state is None:
                continue  # gone from the world (a λ took it away)
            actor = actors.get(spec.id)
            x, y, angle = state.pose
            entry: dict[str, Any] = {
                "id": spec.id, "x": round(x, 4), "y": round(y, 4), "angle": round(angle, 4),
                "radius": spec.radius, "objective": last.get(spec.id),
                "reached": bool(actor is not None and actor["reached"] and spec.id in last),
                "status": case.status_of(spec.id, actor, last) if actor is not None else "gone",
                "path": [], "scan": [],
            }
            if actor is not None:
                path = np.asarray(actor["path"])
                if path.size:
                    entry["path"] = np.round(path[:: max(1, len(path) // 200)], 3).tolist()
            if n < SCAN_ROBOTS and spec.id in lasers:
                entry["scan"] = _scan_points(lasers[spec.id], (x, y, angle))
            robots.append(entry)
        string = ""
        camera = None
        if self._selected is not None:
            actor = actors.get(self._selected)
            if actor is not None:
                string = str(actor)
                string = string if len(string) <= STRING_CHARS else string[:STRING_CHARS] + " …"
            for gen in case.sim.made:
                if isinstance(gen, _core.CameraGenerator) and gen.robot == self._selected and gen.image is not None:
                    camera = np.asarray(gen.image)
        physics = getattr(case.sim, "physics", None)  # the simulator's people (no other platform has any)
        people = [{"id": p["id"], "x": round(p["x"], 4), "y": round(p["y"], 4), "radius": p["radius"]}
                  for p in (physics.people if physics is not None else [])]
        return Snapshot(frame=case.engine.frame, time=round(case.engine.time, 6), status=self._status(),
                        speed=self._speed, selected=self._selected, robots=robots, string=string, camera=camera,
                        serial=self._next_serial(), errors=list(self._errors), people=people)


def _scan_points(laser: Any, pose: tuple[float, float, float]) -> list[list[float]]:
    """The world points where a robot's last scan met something, by the rule of its eLaser events
    (vwg._core.laser_events): the simulator's laser or a real robot's latest LaserScan (placed from where the
    robot was at its stamp)."""
    x, y, angle = pose
    if hasattr(laser, "ranges"):
        ranges, angles = _core.laser_events(laser.ranges, laser.angles, laser.spec.min_range, laser.max_range)
    else:
        scan = laser.platform.latest_scan(laser.robot)
        hits = None if scan is None else laser.hits(scan)
        if hits is None:  # none yet, or one its ScanGenerator does not use either
            return []
        ranges, angles = hits
    a = angle + angles
    return np.round(np.stack([x + ranges * np.cos(a), y + ranges * np.sin(a)], 1), 3).tolist()
