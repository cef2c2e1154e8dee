"""The robot of the case study (paper §III): its world files (vwg.robot.load_robot_world), the
deciders inside eDecide, the platform interface a simulator or a real robot implements (and the real
robots' platforms: rosbridge, a serial base), the motion backend and the feedback generators, and
CaseStudy, which assembles a run.

    world = vwg.robot.load_robot_world("office")
    with vwg.robot.CaseStudy(world, "astar", goals={1: "kitchen"}) as run:
        print(run.run().reached)
"""

from __future__ import annotations

from vwg._core import (
    AvoidanceSettings,
    CameraSpec,
    Collision,
    CollisionGenerator,
    Decider,
    DepthCameraSpec,
    GridDecider,
    LaserSpec,
    LikelihoodField,
    LocalizationGenerator,
    LocalizationSettings,
    MotionBackend,
    MotionFollower,
    NeighbourGenerator,
    NeighbourSettings,
    NoiseModel,
    OdometryGenerator,
    OmplDecider,
    ParticleFilter,
    RandomDecider,
    RobotPlatform,
    RobotSettings,
    RobotState,
    quantize_pose,
)
from vwg.robot.case_study import CaseStudy, RobotSummary, RunSummary
from vwg.robot.platform import Option, Platform
from vwg.robot.platforms.real_robot import Fault, RealRobotPlatform
from vwg.robot.platforms.rosbridge import RosbridgePlatform
from vwg.robot.platforms.serial_base import SerialPlatform
from vwg.robot.sensor import Sensor
from vwg.robot.world_file import Avoidance, Localization, Order, RobotWorld, Room, load_robot_world

__all__ = [
    "Avoidance",
    "AvoidanceSettings",
    "CameraSpec",
    "CaseStudy",
    "Collision",
    "CollisionGenerator",
    "Decider",
    "DepthCameraSpec",
    "Fault",
    "GridDecider",
    "LaserSpec",
    "LikelihoodField",
    "Localization",
    "LocalizationGenerator",
    "LocalizationSettings",
    "MotionBackend",
    "MotionFollower",
    "NeighbourGenerator",
    "NeighbourSettings",
    "NoiseModel",
    "OdometryGenerator",
    "OmplDecider",
    "Option",
    "Order",
    "ParticleFilter",
    "Platform",
    "RandomDecider",
    "RealRobotPlatform",
    "RobotPlatform",
    "RobotSettings",
    "RobotState",
    "RobotSummary",
    "RobotWorld",
    "Room",
    "RosbridgePlatform",
    "RunSummary",
    "Sensor",
    "SerialPlatform",
    "load_robot_world",
    "quantize_pose",
]
