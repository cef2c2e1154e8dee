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

from vwg import io, model, perception, plan, plugins, robot
from vwg import logs as _logs  # noqa: F401  (routes the libraries' messages into `logging`)
from vwg._core import (
    ActorBatch,
    ActorBehavior,
    Backend,
    BackendGroup,
    Blob,
    Event,
    EventColumns,
    EveryFrame,
    FrameInfo,
    FrameRecord,
    FrameSink,
    Generator,
    Node,
    NullBackend,
    PythonActor,
    String,
    TraceBackend,
    __version__,
    build_string,
    display,
    evolve,
    python_budget,
    set_python_budget,
    visualize,
)
from vwg.errors import Error, FrameError, ParseError, ReplayError, SchemaError, WorldFileError
from vwg.generic import replay
from vwg.io.record import Recorder, read_record
from vwg.io.video import VideoWriter
from vwg.launch import RunOptions, load, start
from vwg.model.actor import Actor, Context, Sym
from vwg.model.engine import Engine
from vwg.model.generators import GeneratorSpec, Schedule, every_frame
from vwg.model.world import Alphabet, World
from vwg.saved_run import resume
from vwg.sdk import get_cmake_dir, get_include

__all__ = [
    "Actor",
    "ActorBatch",
    "ActorBehavior",
    "Alphabet",
    "Backend",
    "BackendGroup",
    "Blob",
    "Context",
    "Engine",
    "Error",
    "Event",
    "EventColumns",
    "EveryFrame",
    "FrameError",
    "FrameInfo",
    "FrameRecord",
    "FrameSink",
    "Generator",
    "GeneratorSpec",
    "Node",
    "NullBackend",
    "ParseError",
    "PythonActor",
    "Recorder",
    "ReplayError",
    "RunOptions",
    "Schedule",
    "SchemaError",
    "String",
    "Sym",
    "TraceBackend",
    "VideoWriter",
    "World",
    "WorldFileError",
    "__version__",
    "build_string",
    "display",
    "every_frame",
    "evolve",
    "get_cmake_dir",
    "get_include",
    "io",
    "load",
    "model",
    "perception",
    "plan",
    "plugins",
    "python_budget",
    "read_record",
    "replay",
    "resume",
    "robot",
    "set_python_budget",
    "start",
    "visualize",
]
