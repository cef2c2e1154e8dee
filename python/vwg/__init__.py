"""vwg, the Virtual Worlds Generator: worlds as strings of a grammar, evolved by actors, fed by
event generators and shown on swappable backends (López-García et al., "A Grammatical Approach to
the Modeling of an Autonomous Robot").

    import vwg

    class Blinker(vwg.Actor):
        events = ("tick", "show")
        attributes = {"on": False}
        def on_tick(self, e):
            return self.with_(on=not self.on)
        def show_show(self, e):
            return "Lamp" if self.on else ""

    world = vwg.World(primitives=["Lamp"], transformations=["Move"], events=["tick", "show"],
                      visual=["show"], actors=[Blinker])
    engine = vwg.Engine(world, "Move<2.0>(Blinker<on=true>) . Blinker", backend=vwg.TraceBackend(),
                        generators=[vwg.every_frame("tick"), vwg.every_frame("show")])
    engine.run(frames=3)
    print(engine.string)
"""

from __future__ import annotations

from . import logs as _logs  # noqa: F401  (routes the libraries' messages into `logging`)
from ._core import (
    ActorBatch,
    ActorBehavior,
    AprilTagDetection,
    AprilTagFamily,
    AprilTagPose,
    Backend,
    BackendGroup,
    Blob,
    CameraGenerator,
    CameraRenderer,
    CameraSpec,
    Collision,
    CollisionGenerator,
    Decider,
    DepthCameraSpec,
    DStarLite,
    Event,
    EveryFrame,
    FrameInfo,
    FrameRecord,
    FrameSink,
    Generator,
    GridDecider,
    GridRaycaster,
    ImageFiles,
    KinectGenerator,
    LaserGenerator,
    LaserSpec,
    MotionBackend,
    Node,
    NoiseModel,
    NullBackend,
    OdometryGenerator,
    OmplDecider,
    OmplPlan,
    OmplPlanner,
    PhysicsSettings,
    PhysicsWorld,
    PythonActor,
    RandomDecider,
    RobotPlatform,
    RobotSettings,
    RobotState,
    SimulatedCamera,
    String,
    TopDownRenderer,
    TraceBackend,
    VideoSource,
    __version__,
    apriltag_families,
    apriltag_family,
    apriltag_image,
    astar,
    build_string,
    detect_apriltags,
    display,
    estimate_tag_pose,
    evolve,
    plan_ompl,
    render_overview,
    visualize,
    walker_behavior,
)
from .actor import Actor, Context, Sym
from .engine import Engine
from .errors import Error, FrameError, ParseError, ReplayError, SchemaError, WorldFileError
from .generators import GeneratorSpec, Schedule, every_frame
from .launch import RunOptions, load, start
from .maps import OccupancyGrid, load_map, load_map_server, load_movingai, movingai_cell
from .record import Recorder, read_record, replay
from .robotworld import Order, RobotWorld, Room, load_robot_world
from .sim import MOTION_SYMBOLS, SIM_EVENTS, Simulation
from .video import VideoWriter
from .world import Alphabet, World

__all__ = [
    "MOTION_SYMBOLS",
    "SIM_EVENTS",
    "Actor",
    "ActorBatch",
    "ActorBehavior",
    "Alphabet",
    "AprilTagDetection",
    "AprilTagFamily",
    "AprilTagPose",
    "Backend",
    "BackendGroup",
    "Blob",
    "CameraGenerator",
    "CameraRenderer",
    "CameraSpec",
    "Collision",
    "CollisionGenerator",
    "Context",
    "DStarLite",
    "Decider",
    "DepthCameraSpec",
    "Engine",
    "Error",
    "Event",
    "EveryFrame",
    "FrameError",
    "FrameInfo",
    "FrameRecord",
    "FrameSink",
    "Generator",
    "GeneratorSpec",
    "GridDecider",
    "GridRaycaster",
    "ImageFiles",
    "KinectGenerator",
    "LaserGenerator",
    "LaserSpec",
    "MotionBackend",
    "Node",
    "NoiseModel",
    "NullBackend",
    "OccupancyGrid",
    "OdometryGenerator",
    "OmplDecider",
    "OmplPlan",
    "OmplPlanner",
    "Order",
    "ParseError",
    "PhysicsSettings",
    "PhysicsWorld",
    "PythonActor",
    "RandomDecider",
    "Recorder",
    "ReplayError",
    "RobotPlatform",
    "RobotSettings",
    "RobotState",
    "RobotWorld",
    "Room",
    "RunOptions",
    "Schedule",
    "SchemaError",
    "SimulatedCamera",
    "Simulation",
    "String",
    "Sym",
    "TopDownRenderer",
    "TraceBackend",
    "VideoSource",
    "VideoWriter",
    "World",
    "WorldFileError",
    "__version__",
    "apriltag_families",
    "apriltag_family",
    "apriltag_image",
    "astar",
    "build_string",
    "detect_apriltags",
    "display",
    "estimate_tag_pose",
    "every_frame",
    "evolve",
    "load",
    "load_map",
    "load_map_server",
    "load_movingai",
    "load_robot_world",
    "movingai_cell",
    "plan_ompl",
    "read_record",
    "render_overview",
    "replay",
    "start",
    "visualize",
    "walker_behavior",
]
