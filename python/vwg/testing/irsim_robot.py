"""A robot of independent physics behind a rosbridge v2 server on 127.0.0.1: IR-SIM's simulator (the ``ir-sim``
package, imported as ``irsim``: ``pip install ir-sim``) with its own differential-drive kinematics and its own
``lidar2d``, for paper test 3 against a robot whose physics and laser vwg did not write.

    with IrsimRosbridgeRobot(world) as robot:          # serves ws://127.0.0.1:<free port>, in lockstep
        options = {"url": robot.url, "lockstep": "/vwg/step", "control_rate": 1 / robot.step}
        ...  # vwg's rosbridge platform drives it as it drives any rosbridge robot

The scene is the world's: its occupancy grid written as IR-SIM's obstacle map image (one pixel a cell, the
same resolution and origin), each robot at its start pose with its radius, speed, turn rate and
acceleration limits, and a lidar of the world's laser layout (the same beams, angles and ranges). The server
is vwg.testing.rosbridge_server's, as the fake robot's: Twists on ``cmd_vel`` in, nav_msgs/Odometry (zero
where each robot starts) and sensor_msgs/LaserScan out, the lockstep service ``/vwg/step``.

What IR-SIM does its own way, not vwg's simulator's (Box2D):

- Motion: the commanded (speed, turn rate), clipped to the limits and to what the accelerations allow
  from the last velocity, is integrated by one Euler step of ``step`` seconds (heading at the start of the
  step); there is no mass, motor or contact dynamics. vwg's simulator steps Box2D every 0.01 s.
- Collisions: a robot that touches a wall or another robot stops for good (IR-SIM's ``collision_mode:
  stop``); ``collisions[robot]`` counts them. In vwg's simulator Box2D keeps the bodies apart, and a robot
  that pushes without getting anywhere gives up its plan.
- The laser: IR-SIM casts each beam against the boundary lines of the occupied cells (vwg: exact grid
  traversal); a beam that meets nothing, or meets something nearer than ``min_range``, is published as
  +Inf / -Inf (REP 117), which rosbridge carries as null. A beam that runs exactly through a corner where
  two of IR-SIM's edges meet can slip between them and read no return (its casting's rounding).
- Odometry: IR-SIM has none of its own; the odometry published is the true pose, or with
  ``odometry_noise`` > 0 the true motion of each step drifted by vwg's simulator's model (per step a
  normal error of sd ``noise·√|distance|`` on the distance and ``noise·√|angle|`` on the turn), drawn
  from a generator of its own seeded by ``seed``: the same law, other draws.
- No camera images (IR-SIM has no camera), and the motors' noise of vwg's NoiseModel is not modelled
  (``motion_noise`` turns on IR-SIM's own velocity noise instead, a different model).

Time: each IR-SIM step is ``step`` seconds (default the world's frame time, ``world.dt``); in lockstep each
call of ``/vwg/step`` must ask for a whole number of steps (vwg's ``control_rate`` 1/step Hz asks for one),
else it is refused with the reason. Without lockstep it steps at 1/step Hz of the wall clock. The run is
deterministic for a seed: IR-SIM's generator and the odometry's are seeded, and nothing reads the clock.
"""

from __future__ import annotations

import contextlib
import io
import math
import tempfile
import threading
from pathlib import Path
from typing import Any

import numpy as np

import vwg._core as _core
from vwg.errors import Error
from vwg.robot.links.ros_messages import odometry_message, scan_message
from vwg.robot.world_file import RobotWorld
from vwg.testing.rosbridge_server import RosbridgeRobotServer

__all__ = ["IrsimRosbridgeRobot", "load_irsim"]

#: IR-SIM keeps its current environment in module-level state (each call binds its own): one
#: environment works at a time in a process, whichever server's thread calls.
_IRSIM = threading.Lock()


def load_irsim() -> Any:
    """The ``irsim`` module; Error naming the package when it is not installed."""
    try:
        # On import IR-SIM tries the GUI backends of Matplotlib in turn and prints each that fails.
        with contextlib.redirect_stdout(io.StringIO()):
            import irsim as module
    except ImportError as e:
        raise Error(f"the IR-SIM robot needs IR-SIM: pip install ir-sim (or pip install 'vwg[experiments]'): {e}") \
            from None
    return module


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


class IrsimRosbridgeRobot(RosbridgeRobotServer):
    """The robots of `world` simulated by IR-SIM behind a rosbridge v2 server (see the module).

    ``step``: IR-SIM's time step, seconds (default ``world.dt``); ``odometry_noise``: the odometry's drift
    per metre and radian (default the world's ``noise.odometry``); ``seed``: of IR-SIM's generator and the
    odometry's (default the world's); ``laser_noise``: IR-SIM's lidar range noise, sd in metres (0: exact);
    ``motion_noise``: IR-SIM's velocity noise parameters (its ``alpha``, four numbers; None: off);
    ``merge_map_edges``: merge the map's collinear cell edges before scanning (the same lines, fewer
    segments for the lidar to test: about three times faster on the office)."""

    thread_name = "vwg-irsim-robot"

    def __init__(self, world: RobotWorld, *, lockstep: bool = True, step: float | None = None,
                 odometry_noise: float | None = None, seed: int | None = None, laser_noise: float = 0.0,
                 motion_noise: list[float] | None = None, ros2: bool = False, cmd_timeout: float = 0.5,
                 odom_offset: tuple[float, float, float] = (0.0, 0.0, 0.0), odometry_delay: float = 0.0,
                 merge_map_edges: bool = True) -> None:
        self.step = float(world.dt if step is None else step)
        if not (math.isfinite(self.step) and 1e-4 <= self.step <= 1.0):
            raise Error(f"IrsimRosbridgeRobot.step: expected 0.0001 to 1 seconds, got {step!r}")
        self.odometry_noise = float(world.noise.odometry if odometry_noise is None else odometry_noise)
        if not (math.isfinite(self.odometry_noise) and self.odometry_noise >= 0):
            raise Error(f"IrsimRosbridgeRobot.odometry_noise: expected >= 0, got {odometry_noise!r}")
        if not (math.isfinite(laser_noise) and laser_noise >= 0):
            raise Error(f"IrsimRosbridgeRobot.laser_noise: expected >= 0 metres, got {laser_noise!r}")
        if motion_noise is not None and len(motion_noise) != 4:
            raise Error(f"IrsimRosbridgeRobot.motion_noise: expected IR-SIM's four alpha numbers, got {motion_noise!r}")
        self.seed = world.seed if seed is None else seed
        self.names = {r.id: f"robot{r.id}" for r in world.robots}
        with _IRSIM:
            self.env = _make_env(world, self.step, self.names, self.seed, laser_noise, motion_noise)
            if merge_map_edges:
                _merge_map_edges(self.env)
        # The server after IR-SIM: a scene IR-SIM will not take leaves no server behind.
        super().__init__(world, rate=1.0 / self.step, ros2=ros2, cmd_timeout=cmd_timeout, odom_offset=odom_offset,
                         lockstep=lockstep, odometry_delay=odometry_delay)
        self.bodies = {rid: self.env.get_object_by_name(name) for rid, name in self.names.items()}
        self._velocity = {r.id: (0.0, 0.0) for r in world.robots}  # what each robot was last told
        self._odom = {r.id: tuple(map(float, r.start)) for r in world.robots}  # its odometry, in the map's frame
        self._noise = {r.id: np.random.default_rng([self.seed, r.id]) for r in world.robots}
        self.collisions = {r.id: 0 for r in world.robots}  # times it ran into something (and stopped)
        self._colliding = {r.id: False for r in world.robots}
        self._steps = 0
        self._ended = False

    def stop(self) -> None:
        try:
            super().stop()
        finally:
            if not self._ended:
                self._ended = True
                with _IRSIM, contextlib.suppress(Exception):
                    self.env.end(0.0)  # headless: nothing to wait for; its log sinks go

    def pose(self, robot: int) -> tuple[float, float, float]:
        """The robot's true pose: IR-SIM's state of it."""
        with self._lock:
            return _state(self.bodies[robot])

    # ---- IR-SIM, for the server (the lock held) -----------------------------------------------------------------
    def _drive(self, robot: int, speed: float, turn_rate: float) -> None:
        self._velocity[robot] = (speed, turn_rate)

    def _advance(self, seconds: float) -> None:
        steps = round(seconds / self.step)
        if abs(steps * self.step - seconds) > 1e-9 * max(1.0, seconds):
            raise ValueError(f"IR-SIM steps {self.step:g} s at a time: {seconds:g} s is not a whole number of steps "
                             f"(drive it at control_rate {1 / self.step:g} Hz)")
        for _ in range(steps):
            before = {rid: _state(body) for rid, body in self.bodies.items()}
            with _IRSIM:
                self.env.step({self.names[rid]: [v, w] for rid, (v, w) in self._velocity.items()})
            self._steps += 1
            for rid, body in self.bodies.items():
                self._count(rid, before[rid], _state(body), bool(body.collision_flag))

    def _count(self, rid: int, before: tuple[float, float, float], after: tuple[float, float, float],
               colliding: bool) -> None:
        """One step of `rid`: its odometry (the true motion, drifted by the noise model of vwg's simulator) and
        its collisions (each time it comes to touch something)."""
        x0, y0, t0 = before
        ds = (after[0] - x0) * math.cos(t0) + (after[1] - y0) * math.sin(t0)
        da = _wrap(after[2] - t0)
        if self.odometry_noise > 0:
            rng = self._noise[rid]
            ds += rng.normal(0.0, self.odometry_noise * math.sqrt(abs(ds)))
            da += rng.normal(0.0, self.odometry_noise * math.sqrt(abs(da)))
            x, y, t = self._odom[rid]
            t += da / 2
            self._odom[rid] = (x + ds * math.cos(t), y + ds * math.sin(t), _wrap(t + da / 2))
        else:
            self._odom[rid] = after
        if colliding and not self._colliding[rid]:
            self.collisions[rid] += 1
        self._colliding[rid] = colliding

    def _sim_time(self) -> float:
        return self._steps * self.step  # counted, not summed: no drift over a long run

    def _messages(self, now: float, wanted: set[str]) -> list[tuple[str, dict[str, Any]]]:
        out: list[tuple[str, dict[str, Any]]] = []
        for rid, body in self.bodies.items():
            speed, turn_rate = (float(v) for v in np.asarray(body.velocity, dtype=float).reshape(-1)[:2])
            out.append((self.topics[rid]["odom"], odometry_message(now, *self._odometry(rid, self._odom[rid]),
                                                                   speed, turn_rate, ros2=self.ros2)))
            if self.topics[rid]["scan"] in wanted and body.lidar is not None:
                out.append((self.topics[rid]["scan"], self._scan(now, body)))
        return out

    def _scan(self, now: float, body: Any) -> dict[str, Any]:
        """IR-SIM's last scan of `body` as a LaserScan: its angles turned by the lidar's mounting (its beams
        are laid symmetric about the mounting's heading), no return +Inf, a return nearer than range_min -Inf."""
        scan = body.get_lidar_scan()
        mount = float(body.get_lidar_offset()[2])
        ranges = [float(r) if valid else (-math.inf if r <= scan["range_min"] else math.inf)
                  for r, valid in zip(scan["ranges"], scan["valid"], strict=True)]
        return scan_message(now, float(scan["angle_min"]) + mount, float(scan["angle_increment"]), ranges,
                            float(scan["range_min"]), float(scan["range_max"]), ros2=self.ros2)


def _state(body: Any) -> tuple[float, float, float]:
    x, y, yaw = (float(v) for v in np.asarray(body.state, dtype=float).reshape(-1)[:3])
    return x, y, _wrap(yaw)


def _lidar(laser: _core.LaserSpec, noise: float) -> dict[str, Any]:
    """IR-SIM's lidar2d laid as vwg's laser: IR-SIM spreads `number` beams evenly over `angle_range`, both ends
    included, about the mounting's heading; vwg's beam i points at angle_min + i·increment."""
    angle_min, increment = _core.beam_layout(laser)
    span = increment * (laser.beams - 1)
    return {"name": "lidar2d", "number": int(laser.beams), "angle_range": span, "range_min": float(laser.min_range),
            "range_max": float(laser.max_range), "offset": [0.0, 0.0, angle_min + span / 2],
            "noise": noise > 0, "std": float(noise)}


def _make_env(world: RobotWorld, step: float, names: dict[int, str], seed: int, laser_noise: float,
              motion_noise: list[float] | None) -> Any:
    """A headless IR-SIM environment of the world: the map as an image and a world file in a temporary folder,
    read by IR-SIM when it makes the environment."""
    import yaml

    module = load_irsim()
    grid = world.grid
    ox, oy, oyaw = grid.origin
    if oyaw != 0.0:
        raise Error(f"the IR-SIM robot: IR-SIM's maps are not rotated, the world's map origin has yaw {oyaw:g}")
    # Walls are the cells the simulator takes as walls (>= the obstacle threshold), black; the rest white.
    # An image's top row is the map's last row (IR-SIM reads it so too).
    image = np.where(grid.blocked(_core.OBSTACLE_THRESHOLD), 0, 255).astype(np.uint8)[::-1]
    kinematics: dict[str, Any] = {"name": "diff"}
    if motion_noise is not None:
        kinematics.update(noise=True, alpha=[float(a) for a in motion_noise])
    robots = []
    for r in world.robots:
        robot: dict[str, Any] = {
            "name": names[r.id], "kinematics": kinematics, "shape": {"name": "circle", "radius": float(r.radius)},
            "state": [float(v) for v in r.start],
            "vel_max": [float(r.max_speed), float(r.max_turn_rate)],
            "vel_min": [-float(r.max_speed), -float(r.max_turn_rate)],
            "acce": [float(r.max_accel), float(r.max_turn_accel)]}
        if "laser" in r.sensors:
            robot["sensors"] = [_lidar(world.sensor_settings("laser"), laser_noise)]
        robots.append(robot)
    with tempfile.TemporaryDirectory(prefix="vwg-irsim-") as folder:
        png = Path(folder) / "map.png"
        _core.write_image(str(png), np.ascontiguousarray(image))
        scene = {"world": {"width": grid.width * grid.resolution,
                           "height": grid.height * grid.resolution, "offset": [float(ox), float(oy)],
                           "step_time": step, "collision_mode": "stop", "obstacle_map": str(png)},
                 "robot": robots}
        path = Path(folder) / "world.yaml"
        path.write_text(yaml.safe_dump(scene), encoding="utf-8")
        return module.make(str(path), display=False, headless=True, log_level="ERROR", seed=seed)


def _merge_map_edges(env: Any) -> None:
    """IR-SIM's lidar tests every beam against every edge of the map in its reach, and IR-SIM draws the map as the
    boundary of the occupied cells with a vertex at each cell corner. Merging the collinear edges (shapely's
    simplify with no tolerance: the same lines) leaves a third of them. Skipped if IR-SIM's map object has
    changed shape."""
    import shapely
    from shapely.strtree import STRtree

    for obj in env.objects:
        if getattr(obj, "shape", None) == "map" and hasattr(obj, "linestrings") and hasattr(obj, "geometry_tree"):
            obj.linestrings = [shapely.simplify(line, 0.0) for line in obj.linestrings]
            obj.geometry_tree = STRtree(obj.linestrings)
