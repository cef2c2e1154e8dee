"""The simulator of the case study for a robot world: the physics (the Box2D RobotPlatform, which the
motion backend G commands with the robots' Move/Rotate actions), the range sensors and the robots'
feedback (event generators), and a view (a backend that draws the simulation and records video).

    world = vwg.robot.load_robot_world("maps/office.yaml")
    sim = vwg.sim.Simulation(world)
    engine = vwg.Engine(world_of_symbols, initial,
                        generators=[*sim.sensors(alphabet), *others, *sim.feedback(alphabet)],
                        backend=vwg.BackendGroup([sim.backend, sim.view(video="run.mp4")]))

The events the sensors and feedback make (declare them in the alphabet; ``SIM_EVENTS`` has them):
``eLaser<dist, angle>`` per beam that met an obstacle, ``eCamera<marker, dist, angle>`` per tag seen,
``eOdometry<x, y, angle, busy, commands>`` per robot
per frame, ``eCollision<other>`` per contact; all addressed to the robot (``to=id``).
"""

from __future__ import annotations

import os
from typing import Any

from . import _core
from ._core import (
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
from .robotworld import RobotWorld
from .video import VideoWriter

__all__ = [
    "MOTION_SYMBOLS",
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
    "WorldRobots",
    "render_overview",
    "world_view",
]

#: Event types of the simulator's generators, as Alphabet(events=...) takes them.
SIM_EVENTS: dict[str, dict[str, Any]] = {
    "eLaser": {"dist": 0.0, "angle": 0.0},
    "eCamera": {"marker": 0, "dist": 0.0, "angle": 0.0},
    "eOdometry": {"x": 0.0, "y": 0.0, "angle": 0.0, "busy": False, "commands": 0},
    "eCollision": {"other": 0},
}

#: The primitives and transformations of the case study (paper Table I), and what a view shows of a
#: robot beside its action: its planned path (N×2 points) and its status line.
MOTION_SYMBOLS: dict[str, dict[str, dict[str, Any]]] = {
    "primitives": {"Robot": {"id": 0}, "Path": {"robot": 0, "points": _core.Blob}, "Status": {"robot": 0, "text": ""}},
    "transformations": {"Move": {"dist": 0.0}, "Rotate": {"angle": 0.0}},
}


def world_view(platform: _core.RobotPlatform, world: RobotWorld, *, width: int = 800,
               video: str | os.PathLike[str] | None = None, fps: float | None = None,
               images: str | None = None) -> _core.SimView:
    """A view of `world`'s robots on `platform` (the simulator or a real robot): its map, its rooms'
    markers, recording to `video` (MP4/GIF at `fps`, by default the world's frame rate) and/or PNG
    files in `images`."""
    view = _core.SimView(platform, world.grid, width=width)
    for room in world.rooms.values():
        view.add_marker(room.at[0], room.at[1], room.facing, room.name, room.marker)
    if video:
        view.record_video(VideoWriter(video, fps=fps if fps is not None else 1.0 / world.dt))
    if images:
        view.record_images(str(images))
    return view


class WorldRobots:
    """A robot world's robots on a platform (the simulator, vwg.sim.Simulation, or a real robot's link,
    vwg.real_robots.RealRobots): what CaseStudy and ``vwg run`` use of either. A subclass sets
    ``world``, ``platform`` and ``backend`` and makes each sensor in ``sensor()`` (None: not carried)."""

    world: RobotWorld
    platform: _core.RobotPlatform
    backend: _core.Backend

    def sensor(self, name: str, alphabet: _core.Alphabet, robot: int) -> _core.Generator | None:
        raise NotImplementedError

    def sensors(self, alphabet: _core.Alphabet, kinds: tuple[str, ...] | None = None) -> list[_core.Generator]:
        """The sensors each robot lists (those of `kinds`, or all), made by the sensor registry
        (vwg.registry.sensors): the ranging ones robot by robot (gLaser, gKinect), then the others
        (gCamera), as the paper's priority order has them; those the platform does not carry are left out."""
        from .registry import sensors as registry

        ranging: list[_core.Generator] = []
        others: list[_core.Generator] = []
        for robot in self.world.robots:
            for name in robot.sensors:
                if kinds is not None and name not in kinds:
                    continue
                sensor = registry.create(name)
                gen = sensor.make(self, alphabet, robot.id)
                if gen is not None:
                    (ranging if sensor.ranging else others).append(gen)
        return ranging + others

    def feedback(self, alphabet: _core.Alphabet) -> list[_core.Generator]:
        """Odometry and collisions of every robot, as events (from the platform)."""
        return [_core.OdometryGenerator(self.platform, alphabet), _core.CollisionGenerator(self.platform, alphabet)]

    def view(self, *, width: int = 800, video: str | os.PathLike[str] | None = None, fps: float | None = None,
             images: str | None = None) -> _core.SimView:
        """A backend drawing the robots on the world's map: the markers, robots and trajectories;
        recording to `video` (MP4/GIF, a vwg.VideoWriter at `fps`, by default the world's frame rate)
        and/or PNG files in `images`."""
        return world_view(self.platform, self.world, width=width, video=video, fps=fps, images=images)

    def robot(self, robot: int) -> _core.RobotState:
        return self.platform.robot(robot)


class Simulation(WorldRobots):
    """One robot world simulated: ``physics`` (Box2D, the robot platform), ``backend`` (α/β/δ of Robot,
    Move, Rotate on that platform),
    ``raycaster`` and ``scanner`` (walls and other robots), and factories for the generators."""

    def __init__(self, world: RobotWorld, *, seed: int | None = None, step: float | None = None) -> None:
        self.world = world
        self.seed = world.seed if seed is None else seed
        settings = _core.PhysicsSettings(noise=world.noise, seed=self.seed)
        if step is not None:
            settings.step = step
        self.physics: _core.PhysicsWorld = _core.create_platform("sim", world.grid, list(world.robots), settings)
        self.raycaster = _core.GridRaycaster(world.grid)
        self.scanner = _core.RangeScanner(self.raycaster, self.physics)
        self.platform: _core.RobotPlatform = self.physics
        self.backend = _core.MotionBackend(self.physics)
        self.lasers: list[_core.LaserGenerator] = []
        self.kinects: list[_core.KinectGenerator] = []
        self.cameras: list[_core.CameraGenerator] = []

    def sensor(self, name: str, alphabet: _core.Alphabet, robot: int, *, laser: _core.LaserSpec | None = None,
               kinect: _core.DepthCameraSpec | None = None, camera: _core.CameraSpec | None = None) -> _core.Generator:
        """A sensor of the C++ registry (laser, kinect, camera) for one robot, with the world's settings
        (or these); the view draws the scans of the range sensors made here."""
        gen = _core.create_sensor(name, self.physics, alphabet, robot, grid=self.world.grid, scanner=self.scanner,
                                  laser=laser or self.world.laser, kinect=kinect or self.world.kinect,
                                  camera=camera or self.world.camera, markers=self.world.rooms, seed=self.seed)
        for kind, kept in ((_core.LaserGenerator, self.lasers), (_core.KinectGenerator, self.kinects),
                           (_core.CameraGenerator, self.cameras)):
            if isinstance(gen, kind):
                kept.append(gen)  # type: ignore[arg-type]
        return gen

    def laser(self, alphabet: _core.Alphabet, robot: int, **overrides: Any) -> _core.LaserGenerator:
        """gLaser for one robot, with the world's laser settings (and these overrides of vwg.sim.LaserSpec's fields)."""
        return self.sensor("laser", alphabet, robot, laser=self.world.laser.replace(**overrides))  # type: ignore[return-value]

    def kinect(self, alphabet: _core.Alphabet, robot: int, **overrides: Any) -> _core.KinectGenerator:
        """gKinect for one robot, with the world's Kinect settings (and these overrides of DepthCameraSpec's)."""
        return self.sensor("kinect", alphabet, robot, kinect=self.world.kinect.replace(**overrides))  # type: ignore[return-value]

    def camera(self, alphabet: _core.Alphabet, robot: int, **overrides: Any) -> _core.CameraGenerator:
        """gCamera for one robot: its simulated camera (the world's settings and these overrides of
        vwg.sim.CameraSpec's fields), AprilTag detection every third frame."""
        return self.sensor("camera", alphabet, robot, camera=self.world.camera.replace(**overrides))  # type: ignore[return-value]

    def view(self, *, width: int = 800, video: str | os.PathLike[str] | None = None, fps: float | None = None,
             images: str | None = None) -> _core.SimView:
        """WorldRobots.view, with the scans of the range sensors made so far."""
        view = super().view(width=width, video=video, fps=fps, images=images)
        for laser in self.lasers:
            view.add_laser(laser)
        for kinect in self.kinects:
            view.add_kinect(kinect)
        return view
