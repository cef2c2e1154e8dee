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
time instead: it steps only when the service ``/vwg/step`` is called (``{"seconds": s}``, with a
``step_id`` it does not do twice), then publishes and answers — a simulator that vwg steps, for the
frame-by-frame equivalence of paper test 3 (platform option ``lockstep: /vwg/step``).

A base stops by itself when no command has come for ``cmd_timeout`` seconds, as real bases do.
For fault tests: ``cut()`` closes every connection and refuses new ones until ``restore()``;
``silence(robot)`` stops its odometry until ``speak(robot)``; ``flap(after, hold)`` closes every
connection ``after`` seconds from the call and from then on each new one ``hold`` seconds after it
opened (a link that keeps dropping); ``odometry_delay`` holds back the odometry of each new
connection for that long (a driver that takes a moment); ``image_delay`` sends each camera image that
many seconds after it was taken, with the stamp of when it was taken (a slow camera driver); in
lockstep, ``drop_at_step(n, done=...)``
drops the link at the n-th call of the step service, the step done (its answer lost) or not (the call
lost). ``commands[robot]`` lists the (time, speed, turn rate) of every Twist received, the time on
the server's monotonic clock, and
``connections`` what each connection saw (when it opened and closed, when its first odometry went
out, the Twists that came over it).
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any

import vwg._core as _core
from vwg.robot.links.ros_messages import compressed_image_message, odometry_message, scan_message
from vwg.robot.world_file import RobotWorld
from vwg.testing.rosbridge_server import STEP_SERVICE, Connection, RosbridgeRobotServer

__all__ = ["STEP_SERVICE", "Connection", "FakeRosbridgeRobot"]


class FakeRosbridgeRobot(RosbridgeRobotServer):
    """vwg's own simulator behind a rosbridge v2 server (the server: vwg.testing.rosbridge_server)."""

    thread_name = "vwg-fake-robot"
    step_in_thread = False  # a step of Box2D and its C++ scans takes a millisecond or so: on the loop

    def __init__(self, world: RobotWorld, *, rate: float = 50.0, ros2: bool = False, cmd_timeout: float = 0.5,
                 odom_offset: tuple[float, float, float] = (0.0, 0.0, 0.0), lockstep: bool = False,
                 physics: _core.PhysicsSettings | None = None, odometry_delay: float = 0.0,
                 image_delay: float = 0.0) -> None:
        super().__init__(world, rate=rate, ros2=ros2, cmd_timeout=cmd_timeout, odom_offset=odom_offset,
                         lockstep=lockstep, odometry_delay=odometry_delay)
        # Seconds (the robot's clock) between taking a camera image and sending it, as a slow driver or
        # network makes them: the image keeps the stamp of when it was taken.
        self.image_delay = image_delay
        self._images_held: deque[tuple[float, str, dict[str, Any]]] = deque()
        # The simulator's own physics (its odometry noise too: the odometry published is the noisy one).
        self.physics = _core.PhysicsWorld(world.grid, list(world.robots),
                                          physics or _core.PhysicsSettings(noise=world.noise, seed=world.seed))
        self.scanner = _core.RangeScanner(_core.GridRaycaster(world.grid), self.physics)
        self.angle_min, self.angle_increment = _core.beam_layout(world.sensor_settings("laser"))
        # The robots' cameras: the simulator's renderer, JPEG-compressed, at 10 Hz of the robot's clock.
        self.camera = _core.CameraRenderer(world.grid, world.rooms, world.sensor_settings("camera"))
        self._camera_due = 0.0

    def pose(self, robot: int) -> tuple[float, float, float]:
        """The robot's true pose (the simulator's), not what its odometry says."""
        with self._lock:
            return self.physics.robot(robot).pose

    # ---- the simulator, for the server (the lock held) ----------------------------------------------------------
    def _drive(self, robot: int, speed: float, turn_rate: float) -> None:
        self.physics.drive(robot, speed, turn_rate)

    def _advance(self, seconds: float) -> None:
        self.physics.advance(seconds)

    def _sim_time(self) -> float:
        return self.physics.time()

    def _messages(self, now: float, wanted: set[str]) -> list[tuple[str, dict[str, Any]]]:
        out: list[tuple[str, dict[str, Any]]] = []
        laser = self.world.sensor_settings("laser")
        camera = self.physics.time() >= self._camera_due
        if camera:
            self._camera_due = self.physics.time() + 0.1
        for state in self.physics.robots():
            rid = state.id
            out.append((self.topics[rid]["odom"], odometry_message(now, *self._odometry(rid, state.odometry),
                                                                   state.speed, state.turn_rate, ros2=self.ros2)))
            if self.topics[rid]["scan"] in wanted:
                ranges = self.scanner.scan(rid, laser)
                out.append((self.topics[rid]["scan"], scan_message(
                    now, self.angle_min, self.angle_increment,
                    [float(r) if r < laser.max_range else math.inf for r in ranges],
                    laser.min_range, laser.max_range, ros2=self.ros2)))
            if camera and self.topics[rid]["camera"] in wanted:
                grey = self.camera.render(state.pose, [], grey=True)
                self._images_held.append((now + self.image_delay, self.topics[rid]["camera"],
                                          compressed_image_message(now, _core.encode_image(grey, "jpeg", 95), "jpeg",
                                                                   ros2=self.ros2)))
        while self._images_held and self._images_held[0][0] <= now:
            _, topic, image = self._images_held.popleft()
            out.append((topic, image))
        return out
