"""gLaser: a planar laser scanner. Each scan gives ``eLaser<to=robot, dist, angle>`` for each beam
that met an obstacle (paper Table II: "if obstacle").

On the simulator the beams are cast on the map and the other robots (C++, vwg::sim::LaserGenerator);
on a real robot they are the beams of its sensor_msgs/LaserScan; on any other platform with the
world's map (a kinematic one), they are cast on the map's walls from the pose the platform reports.
Every one turns its ranges into events by the same rule, REP 117's (vwg._core.laser_events)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, ClassVar

import vwg._core as _core
from vwg.errors import SchemaError
from vwg.robot.sensor import Sensor

if TYPE_CHECKING:
    from vwg.robot.platform import Platform

__all__ = ["Laser", "WallLaser"]


class WallLaser(_core.Generator):
    """gLaser cast on the map's walls only, from the pose a platform reports (platforms without a
    simulator of their own: the other robots are not seen)."""

    def __init__(self, platform: _core.RobotPlatform, raycaster: _core.GridRaycaster, robot: int,
                 spec: _core.LaserSpec, event: str = "eLaser") -> None:
        super().__init__()
        self.platform, self.raycaster, self.robot, self.spec, self.event = platform, raycaster, robot, spec, event
        self.angles = _core.beam_angles(spec)  # LaserGenerator's, bit for bit

    def generate(self, frame: _core.FrameInfo) -> list[Any]:
        state = self.platform.find_robot(self.robot)
        if state is None:
            return []  # out of the string (a λ took it away): no body, no scan
        ranges = self.raycaster.scan(state.pose, self.angles, self.spec.max_range)
        # The rule of every laser, simulated or real (C++ platform::laser_events), here without noise.
        dist, angle = _core.laser_events(ranges, self.angles, self.spec.min_range, self.spec.max_range)
        if dist.size == 0:
            return []
        return [_core.EventColumns(self.event, target=self.robot, dist=dist, angle=angle)]

    def save_state(self) -> bytes:
        return b""  # it casts from the pose the platform reports: nothing of its own

    def load_state(self, data: bytes) -> None:
        if data:
            raise SchemaError(f"{self.name}: expected an empty saved state, got {len(data)} bytes")


class Laser(Sensor):
    name = "laser"
    Settings = _core.LaserSpec
    events: ClassVar[dict[str, dict[str, Any]]] = {"eLaser": {"dist": 0.0, "angle": 0.0}}
    ranging = True
    summary = "a planar laser scanner: eLaser<dist, angle> per beam that met an obstacle"

    def make(self, platform: Platform, alphabet: _core.Alphabet, robot: int) -> _core.Generator | None:
        scanner = getattr(platform, "scanner", None)
        if isinstance(scanner, _core.RangeScanner):  # the simulator: walls and the other robots
            return _core.LaserGenerator(scanner, robot, self.settings, alphabet)
        scans = getattr(platform, "scan_generator", None)
        if scans is not None:  # a real robot: its LaserScan messages
            return scans(robot)
        raycaster = getattr(platform, "raycaster", None)
        if isinstance(raycaster, _core.GridRaycaster):
            return WallLaser(platform.platform, raycaster, robot, self.settings)
        return None

    def describe(self) -> str:
        s = self.settings
        return (f"{s.beams} beams over {math.degrees(s.fov):.0f}°, {s.max_range:g} m, noise {s.noise:g} m")
