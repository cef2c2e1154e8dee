"""gKinect: a Kinect-style depth camera read as a laser (the row at the optical centre's height):
``eLaser<to=robot, dist, angle>`` for each column that met an obstacle, the same events as gLaser
(paper test 2, device independence). Simulated only: a real link carries no depth images yet."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, ClassVar

import vwg._core as _core
from vwg.robot.sensor import Sensor

if TYPE_CHECKING:
    from vwg.robot.platform import Platform

__all__ = ["Kinect"]


class Kinect(Sensor):
    name = "kinect"
    Settings = _core.DepthCameraSpec
    events: ClassVar[dict[str, dict[str, Any]]] = {"eLaser": {"dist": 0.0, "angle": 0.0}}
    ranging = True
    world_fields = ("wall_height",)
    summary = "a depth camera read as a laser: eLaser<dist, angle> per column that met an obstacle"

    def make(self, platform: Platform, alphabet: _core.Alphabet, robot: int) -> _core.Generator | None:
        scanner = getattr(platform, "scanner", None)
        if isinstance(scanner, _core.RangeScanner):
            return _core.KinectGenerator(scanner, robot, self.settings, alphabet)
        return None

    def describe(self) -> str:
        s = self.settings
        return f"{s.width}×{s.height}, {math.degrees(s.hfov):.0f}°, {s.min_range:g}-{s.max_range:g} m"
