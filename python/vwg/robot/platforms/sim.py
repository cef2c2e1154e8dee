"""The simulator of the case study for a robot world: the physics (the Box2D RobotPlatform, which the
motion backend G commands with the robots' Move/Rotate actions), the range sensors and the robots'
feedback (event generators), and a view (a backend that draws the simulation and records video).

    world = vwg.robot.load_robot_world("maps/office.yaml")
    sim = vwg.robot.platforms.sim.Simulation(world)
    engine = vwg.Engine(world_of_symbols, initial,
                        generators=[*sim.make_sensors(alphabet), *others, *sim.feedback(alphabet)],
                        backend=vwg.BackendGroup([sim.backend, sim.view(video="run.mp4")]))

The events the sensors and feedback make (declare them in the alphabet; ``SIM_EVENTS`` has them):
``eLaser<dist, angle>`` per beam that met an obstacle, ``eCamera<marker, dist, angle>`` per tag seen,
``eOdometry<x, y, angle, busy, commands>`` per robot
per frame, ``eCollision<other>`` per contact; all addressed to the robot (``to=id``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import vwg._core as _core
from vwg._core import (
    CameraRenderer,
    CameraSpec,
    DepthCameraSpec,
    GridRaycaster,
    KinectGenerator,
    LaserGenerator,
    LaserSpec,
    NoiseModel,
    PhysicsSettings,
    PhysicsWorld,
    RangeScanner,
    SimulatedCamera,
    SimView,
    TopDownRenderer,
    render_overview,
)
from vwg.errors import SchemaError
from vwg.plugins import sensors as sensor_registry
from vwg.robot.platform import Platform
from vwg.robot.world_file import RobotWorld

__all__ = [
    "MOTION_SYMBOLS",
    "PEOPLE_SYMBOLS",
    "SIM_EVENTS",
    "CameraRenderer",
    "CameraSpec",
    "DepthCameraSpec",
    "GridRaycaster",
    "KinectGenerator",
    "LaserGenerator",
    "LaserSpec",
    "NoiseModel",
    "PhysicsSettings",
    "PhysicsWorld",
    "RangeScanner",
    "SimView",
    "SimulatedCamera",
    "Simulation",
    "TopDownRenderer",
    "render_overview",
]

#: Event types of the simulator's generators, as Alphabet(events=...) takes them.
SIM_EVENTS: dict[str, dict[str, Any]] = {
    "eLaser": {"dist": 0.0, "angle": 0.0},
    "eCamera": {"marker": 0, "dist": 0.0, "angle": 0.0},
    "eOdometry": {"x": 0.0, "y": 0.0, "angle": 0.0, "busy": False, "commands": 0},
    "eCollision": {"other": 0},
}

#: The primitives and transformations of the case study (paper Table I), and what a view shows of a
#: robot beside its action: its planned path (N×2 points) and its status line. Velocity<speed, turn_rate> is
#: the action of a robot that avoids (held by the platform until the next frame's).
MOTION_SYMBOLS: dict[str, dict[str, dict[str, Any]]] = {
    "primitives": {"Robot": {"id": 0}, "Path": {"robot": 0, "points": _core.Blob}, "Status": {"robot": 0, "text": ""}},
    "transformations": {"Move": {"dist": 0.0}, "Rotate": {"angle": 0.0},
                        "Velocity": {"speed": 0.0, "turn_rate": 0.0}},
}


#: What a person who walks shows of itself (vwg/sim/people.hpp): the people's backend puts its body there.
PEOPLE_SYMBOLS: dict[str, dict[str, Any]] = {
    "Pedestrian": {"id": 0, "x": 0.0, "y": 0.0, "vx": 0.0, "vy": 0.0, "radius": 0.0},
}


class Simulation(Platform):
    """One robot world simulated (the platform ``sim``): ``physics`` (Box2D, the robot platform),
    ``backend`` (α/β/δ of Robot, Move, Rotate on that platform), ``raycaster`` and ``scanner`` (walls
    and other robots: the range sensors cast their beams with them)."""

    name = "sim"
    sensors = ("laser", "kinect", "camera")
    summary = "the Box2D simulator: bodies, motors, odometry and contacts, with noise models"
    ground_truth = True

    def __init__(self, world: RobotWorld, seed: int | None = None, options: Mapping[str, Any] | None = None, *,
                 step: float | None = None) -> None:
        super().__init__(world, world.seed if seed is None else seed, options or {})
        settings = _core.PhysicsSettings(noise=world.noise, seed=self.seed)
        if step is not None:
            settings.step = step
        self.physics: _core.PhysicsWorld = _core.create_platform("sim", world.grid, list(world.robots), settings)
        self.raycaster = _core.GridRaycaster(world.grid)
        self.scanner = _core.RangeScanner(self.raycaster, self.physics)
        self.platform: _core.RobotPlatform = self.physics
        self.backend = _core.MotionBackend(self.physics)

    def sensor(self, name: str, alphabet: _core.Alphabet, robot: int, **overrides: Any) -> _core.Generator:
        """The sensor `name` (registered in vwg.plugins.sensors) for one robot, with the world's settings
        and these overrides of their fields (``sim.sensor("laser", alphabet, 1, beams=90)``); the view
        draws the scans of the range sensors made here."""
        settings = self.world.sensor_settings(name)
        sensor = sensor_registry.get(name)(settings.replace(**overrides) if overrides else settings)
        gen = sensor.make(self, alphabet, robot)
        if gen is None:
            raise SchemaError(f"sensor {name}: the simulator cannot carry it")
        self.made.append(gen)
        return gen
