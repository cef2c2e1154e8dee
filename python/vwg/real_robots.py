"""A robot world's robots on a real platform (rosbridge, serial): what vwg.sim.Simulation is for the
simulator — the platform, the motion backend on it, the feedback and sensor generators, a view —
so that CaseStudy and ``vwg run`` take either without knowing which.

The laser's events are those of the simulated laser: ``eLaser<to=robot, dist, angle>`` for each beam
that met an obstacle (REP 117, see vwg.ros_messages.laser_scan), in the same place of the priority
order, for each scan that came since the last frame. The camera's are gCamera's, on the images the
link receives (sensor_msgs/CompressedImage), with the calibration of the world file's ``camera``.
"""

from __future__ import annotations

import logging
from typing import Any

from . import _core
from .real_robot import RealRobotPlatform
from .robotworld import RobotWorld
from .sim import WorldRobots

__all__ = ["RealRobots", "ScanGenerator"]

log = logging.getLogger("vwg.robot")


class ScanGenerator(_core.Generator):
    """gLaser on a real robot: the beams of its latest LaserScan that met an obstacle, once per scan."""

    def __init__(self, platform: RealRobotPlatform, robot: int, event: str = "eLaser") -> None:
        super().__init__()
        self.platform = platform
        self.robot = robot
        self.event = event
        self._last: Any = None

    def generate(self, frame: _core.FrameInfo) -> list[_core.Event]:
        scan = self.platform.latest_scan(self.robot)
        if scan is None or scan is self._last:
            return []
        self._last = scan
        return [_core.Event(self.event, self.robot, dist=d, angle=a) for a, d in zip(scan.angles, scan.ranges,
                                                                                      strict=True)]


class RealRobots(WorldRobots):
    """The robots of `world` on `platform`; sensors a real link does not carry yet (the cameras) are
    left out with a warning, so a world file written for the simulator runs unchanged."""

    def __init__(self, world: RobotWorld, platform: RealRobotPlatform) -> None:
        self.world = world
        self.platform = platform
        self.backend = _core.MotionBackend(platform)
        self.lasers: list[ScanGenerator] = []

    def sensor(self, name: str, alphabet: _core.Alphabet, robot: int) -> _core.Generator | None:
        if name == "laser":
            gen = ScanGenerator(self.platform, robot)
            self.lasers.append(gen)
            return gen
        images = getattr(self.platform, "images", {}).get(robot)
        if name == "camera" and images is not None:
            # The robot's camera as the world file describes it (its calibration), AprilTag detection
            # on each new image, every third frame as in the simulator.
            fx, fy, cx, cy = self.world.camera.apriltag_intrinsics()
            sizes = {room.marker: room.size for room in self.world.rooms.values()}
            return _core.CameraGenerator(images, robot, alphabet, fx, fy, cx, cy, tag_sizes=sizes, period=3)
        log.warning("%s: robot %d: sensor %r is not carried by this link yet; left out", self.platform.name(), robot,
                    name)
        return None

    def close(self) -> None:
        self.platform.close()
