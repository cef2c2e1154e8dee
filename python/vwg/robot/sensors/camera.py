"""gCamera: a camera whose images are searched for AprilTag markers (tag36h11): ``eCamera<to=robot,
marker, dist, angle>`` for each tag found. On the simulator the images are rendered from the map
(the other robots included); on a real robot they are the link's sensor_msgs/CompressedImage, with
the calibration of the world's camera settings."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, ClassVar

import vwg._core as _core
from vwg.robot.sensor import Sensor

if TYPE_CHECKING:
    from vwg.robot.platform import Platform

__all__ = ["PERIOD", "Camera"]

#: How often gCamera looks by default (frames): the C++ CameraSpec's ``period``, which a world file may set.
PERIOD: int = _core.CameraSpec().period


class Camera(Sensor):
    name = "camera"
    Settings = _core.CameraSpec
    events: ClassVar[dict[str, dict[str, Any]]] = {"eCamera": {"marker": 0, "dist": 0.0, "angle": 0.0}}
    ranging = False
    world_fields = ("wall_height",)
    summary = "a camera searched for AprilTag markers: eCamera<marker, dist, angle> per tag seen"

    def make(self, platform: Platform, alphabet: _core.Alphabet, robot: int) -> _core.Generator | None:
        world = platform.world
        sizes = {room.marker: room.size for room in world.rooms.values()}
        physics = getattr(platform, "physics", None)
        if isinstance(physics, _core.PhysicsWorld):  # the simulator renders what the robot would see
            seed = (platform.seed * 1009 + robot) % 2**64
            source = _core.SimulatedCamera(physics, robot, world.grid, world.rooms, self.settings, seed)
        else:
            images = getattr(platform.platform, "images", {}).get(robot)
            if images is None:
                return None
            source = images
        fx, fy, cx, cy = self.settings.apriltag_intrinsics()
        return _core.CameraGenerator(source, robot, alphabet, fx, fy, cx, cy, tag_sizes=sizes,
                                     period=self.settings.period)

    def describe(self) -> str:
        s = self.settings
        return f"{s.width}×{s.height}, {math.degrees(s.hfov):.0f}°"
