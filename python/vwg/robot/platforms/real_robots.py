"""A robot world's robots on a real platform (rosbridge, serial): what vwg.robot.platforms.sim.Simulation is for the
simulator — the platform, the motion backend on it, the feedback and sensor generators, a view —
so that CaseStudy and ``vwg run`` take either without knowing which.

The laser's events are those of the simulated laser: ``eLaser<to=robot, dist, angle>`` for each beam
that met an obstacle, by the simulated laser's rule (REP 117, vwg._core.laser_events), in the same place of the priority
order, for each scan that came since the last frame. The camera's are gCamera's, on the images the
link receives (sensor_msgs/CompressedImage), with the calibration of the world file's ``camera``.
Both are placed from where the robot was at the message's stamp, not where the frame finds it
(RealRobotPlatform.viewpoint: the odometry of that time, against the frame's).
"""

from __future__ import annotations

from typing import Any

import numpy as np

import vwg._core as _core
from vwg.robot.links.ros_messages import LaserScan
from vwg.robot.platform import Platform
from vwg.robot.platforms.real_robot import RealRobotPlatform

__all__ = ["RealRobots", "ScanGenerator"]


class ScanGenerator(_core.Generator):
    """gLaser on a real robot: the beams of its latest LaserScan that met an obstacle, once per scan."""

    def __init__(self, platform: RealRobotPlatform, robot: int, event: str = "eLaser") -> None:
        super().__init__()
        self.platform = platform
        self.robot = robot
        self.event = event
        self.stale = 0  # scans the platform could not place (RealRobotPlatform.viewpoint gave None): not used
        self._last: Any = None

    def generate(self, frame: _core.FrameInfo) -> list[_core.Event]:
        scan = self.platform.latest_scan(self.robot)
        if scan is None or scan is self._last:
            return []
        self._last = scan
        hits = self.hits(scan)
        if hits is None:
            self.stale += 1
            return []
        dist, angle = hits
        return [_core.Event(self.event, self.robot, dist=d, angle=a) for d, a in zip(dist.tolist(), angle.tolist(),
                                                                                      strict=True)]

    def hits(self, scan: LaserScan) -> tuple[np.ndarray, np.ndarray] | None:
        """The (dist, angle) of each beam of `scan` that met an obstacle, by the simulated laser's rule (C++
        platform::laser_events: the same scan, the same events), placed from where the robot was at the scan's
        stamp: the scan came after it was taken, while the robot moved on. None when the platform cannot place
        it (RealRobotPlatform.viewpoint)."""
        taken_from = self.platform.viewpoint(self.robot, scan.time)
        if taken_from is None:
            return None
        return _core.laser_events(scan.ranges, scan.angle_min, scan.angle_increment, scan.range_min, scan.range_max,
                                  seen_from=taken_from)


class RealRobots(Platform):
    """The robots of a world on a real robot's link (a subclass makes ``self.platform``, a
    RealRobotPlatform, and calls ``attach``): the motion backend on it, its laser scans and camera
    images for the sensors (vwg.robot.sensors), and a stop to every robot when it closes."""

    sensors = ("laser", "camera")

    def attach(self, platform: RealRobotPlatform) -> None:
        self.platform = platform
        self.backend = _core.MotionBackend(platform)

    def scan_generator(self, robot: int) -> _core.Generator:
        """gLaser of `robot` from its link's LaserScan messages (vwg.robot.sensors.laser)."""
        return ScanGenerator(self.platform, robot)

    def close(self) -> None:
        self.platform.close()
