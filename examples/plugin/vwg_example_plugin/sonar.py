"""The sensor ``sonar``: a ring of sonar beams around the robot, the first straight ahead, each a cone.
A sonar hears the nearest echo within its cone, wherever in the cone it comes from, so each beam's
range is the nearest wall across its cone (several rays cast over the map's walls, the nearest kept),
reported at the beam's centre: ``eLaser<to=robot, dist, angle>`` for each beam that heard an echo
within ``max_range``, the laser's events, so that the robot (ARobot) maps them as it maps a laser's.

It is carried by every platform that has the world's map as a ``raycaster`` (a vwg GridRaycaster) and
a RobotPlatform that knows where its robots are: vwg's simulator (``sim``: the true pose of its
physics) and this package's ``kinematic`` platform. It hears walls only, not the other robots.

    sensors:
      sonar: {beams: 8, cone: 0.5235987755982988, rays: 7, max_range: 3.0}
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, ClassVar

import numpy as np

import vwg._core as _core
from vwg.errors import SchemaError
from vwg.robot.sensor import Sensor, Settings

__all__ = ["Sonar", "SonarGenerator", "SonarSettings"]

#: The most beams, and rays a cone, a sonar may have (a real ring has 8 to 24 transducers).
MAX_BEAMS = 360
MAX_RAYS = 100
#: The farthest a sonar hears, metres.
MAX_RANGE = 100.0


def _refuse(owner: str, name: str, expected: str, got: Any) -> SchemaError:
    """SchemaError("OWNER.NAME: expected ..., got ...") with its ``field``, as the C++ settings raise it."""
    error = SchemaError(f"{owner}.{name}: expected {expected}, got {got!r}")
    error.field = f"{owner}.{name}"
    return error


@dataclasses.dataclass
class SonarSettings(Settings):
    """The settings of a sonar ring: the world file's ``sensors.sonar`` section (each field's default
    here is the only one)."""

    beams: int = dataclasses.field(default=8, metadata={"help": "beams in the ring, evenly spaced, the first "
                                                                "straight ahead"})
    cone: float = dataclasses.field(default=math.radians(30.0), metadata={"help": "each beam's opening angle, "
                                                                                  "radians"})
    rays: int = dataclasses.field(default=7, metadata={"help": "rays cast across each cone, its edges included "
                                                               "(1: the centre only)"})
    min_range: float = dataclasses.field(default=0.05, metadata={"help": "nearer echoes are dropped, metres"})
    max_range: float = dataclasses.field(default=3.0, metadata={"help": "farther than this nothing is heard, "
                                                                        "metres"})

    def check(self, owner: str) -> None:
        super().check(owner)  # the types: each field's default's
        if not 1 <= self.beams <= MAX_BEAMS:
            raise _refuse(owner, "beams", f"1 to {MAX_BEAMS} beams", self.beams)
        if not 0.0 < self.cone <= math.pi:
            raise _refuse(owner, "cone", "an opening angle in (0, π] radians", self.cone)
        if not 1 <= self.rays <= MAX_RAYS:
            raise _refuse(owner, "rays", f"1 to {MAX_RAYS} rays a cone", self.rays)
        if self.min_range < 0.0:
            raise _refuse(owner, "min_range", "a range >= 0, metres", self.min_range)
        if not self.min_range < self.max_range <= MAX_RANGE:
            raise _refuse(owner, "max_range", f"a range > min_range ({self.min_range:g}) and <= {MAX_RANGE:g}, "
                                              "metres", self.max_range)

    def centres(self) -> np.ndarray:
        """Each beam's centre relative to the heading, in [-π, π): 0, 2π/beams, ... wrapped."""
        turns = np.arange(self.beams, dtype=np.float64) * (2.0 * math.pi / self.beams)
        return np.remainder(turns + math.pi, 2.0 * math.pi) - math.pi

    def offsets(self) -> np.ndarray:
        """The rays of a cone relative to its centre: evenly over [-cone/2, cone/2] (the centre alone for one)."""
        if self.rays == 1:
            return np.zeros(1)
        return np.linspace(-0.5 * self.cone, 0.5 * self.cone, self.rays)


class SonarGenerator(_core.Generator):
    """The sonar ring of one robot: each frame, its pose from `platform` (a vwg.robot.RobotPlatform), the
    rays of every cone cast at once on `raycaster`, the nearest of each cone kept. ``ranges`` holds the
    last frame's range of each beam (max_range: no echo), ``angles`` the beams' centres."""

    name = "sonar"

    def __init__(self, platform: _core.RobotPlatform, raycaster: _core.GridRaycaster, robot: int,
                 settings: SonarSettings, event: str = "eLaser") -> None:
        super().__init__()
        settings.check("sonar")
        self.platform, self.raycaster, self.robot, self.settings, self.event = (platform, raycaster, robot, settings,
                                                                                event)
        self.angles = settings.centres()
        # Every ray of every cone, beam by beam: (beams × rays) angles relative to the heading.
        self._rays = (self.angles[:, None] + settings.offsets()[None, :]).ravel()
        self.ranges = np.full(settings.beams, settings.max_range, dtype=np.float32)

    def generate(self, frame: _core.FrameInfo) -> list[Any]:
        s = self.settings
        pose = self.platform.robot(self.robot).pose
        rays = self.raycaster.scan(pose, self._rays, s.max_range)
        self.ranges = rays.reshape(s.beams, -1).min(axis=1)
        # As the laser reads its ranges: one at max_range (as float32, the raycaster's) heard nothing;
        # nearer than min_range is dropped.
        heard = (self.ranges < np.float32(s.max_range)) & (self.ranges.astype(np.float64) >= s.min_range)
        if not heard.any():
            return []
        return [_core.EventColumns(self.event, target=self.robot, dist=self.ranges[heard].astype(np.float64),
                                   angle=self.angles[heard])]


class Sonar(Sensor):
    """The sensor ``sonar`` (entry point group vwg.sensors)."""

    name = "sonar"
    Settings = SonarSettings
    events: ClassVar[dict[str, dict[str, Any]]] = {"eLaser": {"dist": 0.0, "angle": 0.0}}
    ranging = True
    summary = "a ring of sonar beams with a cone each: eLaser<dist, angle> per beam that heard an echo"

    def make(self, platform: Any, alphabet: _core.Alphabet, robot: int) -> _core.Generator | None:
        raycaster = getattr(platform, "raycaster", None)
        if not isinstance(raycaster, _core.GridRaycaster):
            return None  # no map to cast on (a real robot's link): not carried
        return SonarGenerator(platform.platform, raycaster, robot, self.settings)

    def describe(self) -> str:
        s = self.settings
        return (f"{s.beams} beams, cones of {math.degrees(s.cone):.0f}° ({s.rays} rays), "
                f"{s.min_range:g}-{s.max_range:g} m")
