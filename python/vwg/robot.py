"""The robot of the case study (paper §III): its world files (vwg.robot.load_robot_world), the
deciders inside eDecide, the platform interface a simulator or a real robot implements (and the real
robots' platforms: rosbridge, a serial base), the motion backend and the feedback generators, and
CaseStudy, which assembles a run.

    world = vwg.robot.load_robot_world("office")
    with vwg.robot.CaseStudy(world, "astar", goals={1: "kitchen"}) as run:
        print(run.run().reached)
"""

from __future__ import annotations

from ._core import (
    Collision,
    CollisionGenerator,
    Decider,
    GridDecider,
    MotionBackend,
    MotionFollower,
    OdometryGenerator,
    OmplDecider,
    RandomDecider,
    RobotPlatform,
    RobotSettings,
    RobotState,
    quantize_pose,
)
from .casestudy import CaseStudy, RobotSummary, RunSummary
from .real_robot import Fault, RealRobotPlatform
from .robotworld import Order, RobotWorld, Room, load_robot_world
from .rosbridge_platform import RosbridgePlatform
from .serial_platform import SerialPlatform

__all__ = ["CaseStudy", "Collision", "CollisionGenerator", "Decider", "Fault", "GridDecider", "MotionBackend",
           "MotionFollower", "OdometryGenerator", "OmplDecider", "Order", "RandomDecider", "RealRobotPlatform",
           "RobotPlatform", "RobotSettings", "RobotState", "RobotSummary", "RobotWorld", "Room", "RosbridgePlatform",
           "RunSummary", "SerialPlatform", "load_robot_world", "quantize_pose"]
