"""One loader, one run path and one replay path for every kind of world file.

A world file is of one of the kinds registered in ``vwg.plugins.world_kinds``: ``robot`` (the case
study: a map, rooms, robots; vwg.robot.RobotWorld) and ``generic`` (an alphabet, an initial string,
generators, a backend; vwg.generic.WorldSpec). A kind recognises its files, loads them, says which
run options apply to it, starts a run and rebuilds the world a record of it was made with.
``vwg run``, ``vwg replay`` and ``vwg check`` go through here and nowhere else, so an option that
does not apply to a world is refused by name rather than ignored.

    world = vwg.load("office")                                   # a shipped world, or a file
    with vwg.start(world, vwg.RunOptions(goals=["kitchen"])) as run:
        outcome = run.execute()
    print(outcome.exit_status, outcome.summary["reached"])
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

import vwg._core as _core
from vwg.errors import Error, ReplayError, clip
from vwg.io.files import check_output_file
from vwg.io.record import Recorder, check_goals, read_key, robot_data, robot_world_file
from vwg.io.shipped import resolve_world
from vwg.io.yamldoc import YamlDoc
from vwg.model.limits import MAX_FRAMES, MAX_SEED
from vwg.plugins import world_kinds

__all__ = ["COMMON_OPTIONS", "EXIT_LINK_FAULT", "EXIT_UNREACHED", "Outcome", "Run", "RunOptions", "WorldKind",
           "clip", "describe", "kind_of", "load", "platform_faults", "replay_world", "start", "strict_json"]

#: Exit status of a run that finished with a robot short of the room it was sent to.
EXIT_UNREACHED = 3
#: Exit status of a run a real robot's link ended (the robot was stopped; the faults are in the summary).
EXIT_LINK_FAULT = 4

@dataclass
class RunOptions:
    """What a run may be told besides its world file; None (or False) leaves the file's choice.
    Which options a world takes is its kind's ``options``; giving another is an error."""

    frames: int | None = None
    seed: int | None = None
    dt: float | None = None
    max_symbols: int = 10_000_000
    threads: int = 0                  # for the frame's independent work; 0: the machine's cores
    backend: str | None = None        # a registered backend, shown on beside the world's own
    record: Path | None = None        # JSON Lines record of every frame (vwg replay reads it)
    record_key: Path | None = None    # a key file: the record's chain is an HMAC with it
    summary_json: Path | None = None  # the outcome's summary as JSON
    progress: bool | None = False
    # the robot case study
    platform: str | None = None       # a registered platform (vwg plugins), instead of the file's
    platform_options: dict[str, Any] = field(default_factory=dict)  # over the file's (--platform-opt KEY=VALUE)
    planner: str | None = None
    avoidance: str | None = None      # none or orca, for every robot, instead of the file's avoidance:
    goals: list[str] | None = None    # "ROOM" (the first robot) or "ROBOT:ROOM"; replace the file's orders
    no_world_orders: bool = False
    stdin_orders: bool = False
    video: Path | None = None
    images: Path | None = None
    trajectory: Path | None = None
    allow_unreached: bool = False
    mcap: Path | None = None          # the run's ROS 2 messages as an MCAP file (vwg.robot.topics)
    foxglove_port: int | None = None  # ... served live to Foxglove (0: a free port)
    foxglove_host: str = "127.0.0.1"

    def given(self) -> list[str]:
        """The options set to something other than their default, in declaration order."""
        defaults = RunOptions()
        return [f.name for f in dataclasses.fields(self) if getattr(self, f.name) != getattr(defaults, f.name)]

    def check(self) -> None:
        """Values no world could take: named by their command-line spelling."""
        if self.frames is not None and not 0 <= self.frames <= MAX_FRAMES:
            raise Error(f"--frames: expected a number of frames from 0 to 2**64 - 1, got {self.frames}")
        if self.seed is not None and not 0 <= self.seed <= MAX_SEED:
            raise Error(f"--seed: expected an integer from 0 to 2**64 - 1, got {self.seed}")
        if self.dt is not None:
            _core.check_dt(self.dt, "--dt")  # the engine's range and check (vwg::check_dt)
        if not 0 <= self.max_symbols < 2**63:
            raise Error(f"--max-symbols: expected a count from 0 (no limit) to 2**63 - 1, got {self.max_symbols}")
        if not 0 <= self.threads <= 256:
            raise Error(f"--threads: expected 0 (the machine's cores) to 256 threads, got {self.threads}")
        if self.record_key is not None and self.record is None:
            raise Error("--record-key keys the record that --record writes; give --record too")
        check_port("--foxglove-port", self.foxglove_port)


#: How the command line spells an option whose name differs.
_FLAGS = {"goals": "--goal"}

#: Options every kind of world takes.
COMMON_OPTIONS = frozenset({"frames", "seed", "dt", "max_symbols", "threads", "backend", "record", "record_key",
                            "summary_json", "progress"})


@dataclass
class Outcome:
    """How a run ended: a title and rows to print, the summary (JSON-ready), the exit status
    (0, or 3 when a robot did not reach its room) and what to say on standard error."""

    title: str
    rows: list[tuple[str, str]]
    summary: dict[str, Any]
    exit_status: int = 0
    message: str = ""
    outputs: dict[str, str] = field(default_factory=dict)


class Run(Protocol):
    """A world started with its options: ``engine`` runs it, ``execute()`` runs it to its end."""

    engine: _core.Engine
    #: The name of its world's kind ("robot", "generic"), kept in records.
    kind: str
    #: What the record's header keeps of the world, so ``vwg replay`` can rebuild it.
    record_data: dict[str, Any]

    def execute(self, progress: bool | None = False) -> Outcome: ...
    def save_state(self, path: str | Path | None = None) -> bytes:
        """The run's state after its last whole frame (vwg.saved_run), written to `path` when given."""
        ...
    def close(self) -> None: ...
    def __enter__(self) -> Run: ...
    def __exit__(self, *exc: object) -> None: ...


class WorldKind(Protocol):
    """A kind of world file (register one in vwg.plugins.world_kinds)."""

    name: str
    #: The run options that apply beyond COMMON_OPTIONS.
    options: frozenset[str]
    #: How a file of this kind is told apart, for errors ("a mapping with map:, rooms: and robots:").
    shape: str

    def matches(self, data: dict[str, Any]) -> bool: ...
    def matches_loaded(self, world: Any) -> bool: ...
    def load(self, path: Path) -> Any: ...
    def start(self, world: Any, options: RunOptions) -> Run: ...
    def replay_world(self, header: dict[str, Any], path: Path | None, record_path: Path, *,
                     allow_code_from_record: bool = False) -> Any: ...
    def describe(self, world: Any) -> tuple[str, list[tuple[str, str]]]: ...


def _kinds() -> list[WorldKind]:
    return [world_kinds.create(name) for name in world_kinds]


def kind_of(path: Path, data: Any) -> WorldKind:
    """The kind of a world file's content (the one registered kind that takes it); Error naming what
    each kind expects otherwise."""
    kinds = _kinds()
    if isinstance(data, dict):
        matching = [kind for kind in kinds if kind.matches(data)]
        if len(matching) == 1:
            return matching[0]
        if matching:
            raise Error(f"{path}: the file could be a world of each kind " +
                        " and ".join(f"{k.name} ({k.shape})" for k in matching) + "; it must be one")
        found = f"found keys: {', '.join(str(k) for k in list(data)[:8]) or 'none'}"
    else:
        found = f"found a {type(data).__name__}, not a mapping"
    expected = " or ".join(f"a {k.name} world ({k.shape})" for k in kinds)
    raise Error(f"{path}: not a world file: expected {expected}; {found}")


def load(world: str | Path) -> Any:
    """Load a world file of any kind, or a shipped world by name: a vwg.robot.RobotWorld or a WorldSpec."""

    path = resolve_world(world)
    return kind_of(path, YamlDoc(path).data).load(path)


def _kind_of_loaded(world: Any) -> WorldKind:
    for kind in _kinds():
        if kind.matches_loaded(world):
            return kind
    raise Error(f"not a loaded world: {type(world).__name__} (vwg.load gives one)")


def start(world: Any, options: RunOptions | None = None) -> Run:
    """Start a loaded world (vwg.load) with `options`; an option its kind does not take is an error."""
    options = options or RunOptions()
    options.check()
    kind = _kind_of_loaded(world)
    for name in options.given():
        if name not in COMMON_OPTIONS and name not in kind.options:
            takers = [k.name for k in _kinds() if name in k.options]
            where = f"is for {' and '.join(takers)} worlds" if takers else "does not apply"
            flag = _FLAGS.get(name, "--" + name.replace("_", "-"))
            raise Error(f"{flag} {where}; {world.path} is a {kind.name} world")
    check_outputs(world, options)
    run = kind.start(world, options)
    return RecordedRun(run, world, options) if options.record or options.summary_json else run


def run_inputs(world: Any) -> dict[str, Path]:
    """The files a run of `world` reads, by what they are: its world file and a robot world's map
    (and a map_server YAML's image)."""
    inputs = {"the world file being run": Path(world.path)}
    map_path = getattr(world, "map_path", None)
    if map_path is not None:
        inputs["the world's map"] = Path(map_path)
        if Path(map_path).suffix.lower() in (".yaml", ".yml"):

            try:  # the map was read when the world loaded: this only finds its image's name again
                data = YamlDoc(map_path).data
            except Error:
                data = None
            image = data.get("image") if isinstance(data, dict) else None
            if isinstance(image, str) and image:
                inputs["the map's image"] = Path(map_path).parent / image
    return inputs


TRAJECTORY_FORMATS = {".png": "png", ".jpg": "jpeg", ".jpeg": "jpeg"}


def trajectory_type_error(path: Path) -> str:
    """What is wrong with a --trajectory name whose extension is not a picture's we write."""
    return f"{path}: unknown picture type '{path.suffix}'; use {', '.join(TRAJECTORY_FORMATS)}"


def check_outputs(world: Any, options: RunOptions, inputs: dict[str, Path] | None = None) -> None:
    """Before a run starts: no output overwrites what the run reads (`inputs` adds to the world's) and
    none is a named pipe (a run would wait on it for ever, silently)."""

    inputs = {**run_inputs(world), **(inputs or {})}
    if options.record_key is not None:
        inputs["the record's key file"] = Path(options.record_key)
    trajectory = options.trajectory or (Path(options.video).with_suffix(".png") if options.video else None)
    for flag, path in (("--record", options.record), ("--summary-json", options.summary_json),
                       ("--video", options.video), ("--trajectory", trajectory), ("--mcap", options.mcap)):
        if path is not None:
            check_output_file(Path(path), flag, inputs)
    if options.images is not None:
        check_output_file(Path(options.images), "--images", inputs, folder=True)
    # --trajectory's picture type is found before the run, not after it (as --video's).
    if trajectory is not None and Path(trajectory).suffix.lower() not in TRAJECTORY_FORMATS:
        raise Error(f"--trajectory {trajectory_type_error(Path(trajectory))}")


class RecordedRun:
    """A run whose options ask for a record (every frame, flushed as it ends) or a summary JSON: both
    are written by execute(), whoever calls it (``vwg run`` or a script). Everything else is the run's."""

    def __init__(self, run: Run, world: Any, options: RunOptions) -> None:

        self.run = run
        self.options = options
        try:
            planned = options.frames if options.frames is not None else getattr(world, "frames", None)
            key = read_key(options.record_key) if options.record_key else None
            self.recorder = (Recorder(options.record, run.engine, world_file=world.path, world_data=run.record_data,
                                      world_kind=run.kind, frames_planned=planned, key=key)
                             if options.record else None)
        except OSError as e:  # a folder that cannot be made, a full disk (/dev/full) for the header
            run.close()
            raise Error(f"{options.record}: {e.strerror}: the record could not be started") from None
        except BaseException:
            run.close()
            raise

    def __getattr__(self, name: str) -> Any:
        return getattr(self.run, name)

    def execute(self, progress: bool | None = False) -> Outcome:
        try:
            outcome = self.run.execute(progress=progress)
        except OSError as e:
            # The only Python code of a frame whose errors are not FrameErrors is the engine's observers,
            # here the recorder: its file could not take a frame's line (a full disk, a file size limit).
            if self.recorder is None:
                raise
            raise self._record_failed(e) from None
        try:
            if self.recorder:
                self.recorder.close(faults=outcome.summary.get("faults", ()))
        except OSError as e:
            raise self._record_failed(e, end=True) from None
        if self.recorder:
            frames = "" if self.run.kind == "robot" else f" ({self.recorder.frames} frames)"
            outcome.outputs["record"] = f"{self.options.record}{frames}"
        if self.options.summary_json:
            outcome.outputs["summary"] = str(self.options.summary_json)
            try:
                write_summary(self.options.summary_json, {**outcome.summary, "outputs": dict(outcome.outputs)})
            except OSError as e:
                raise Error(f"{self.options.summary_json}: {e.strerror}: the summary could not be written"
                            + (f" (the record {self.options.record} is complete)" if self.recorder else "")) \
                    from None
        return outcome

    def _record_failed(self, e: OSError, end: bool = False) -> Error:
        """What a failed write of the record leaves, said: the lines before it were flushed as their
        frames ended and stay; no end line is written after a torn one, so vwg replay reads the record
        as cut short, up to its last whole line."""
        recorder, self.recorder = self.recorder, None
        written = 0
        if recorder is not None:
            recorder.abandon()
            written = recorder.frames
        lost = "its end line" if end else "the frame being written and those after it"
        return Error(f"{self.options.record}: {e.strerror}: the record holds its header and the first {written} "
                     f"frames, not {lost}; vwg replay replays it as cut short")

    def close(self) -> None:
        try:
            if self.recorder:
                # Still open: the run did not end through execute() (Ctrl-C, a frame that failed); the
                # robot's faults up to then are the record's too.
                self.recorder.close(faults=platform_faults(self.run))
        except OSError as e:
            error = self._record_failed(e, end=True)
            self.run.close()
            raise error from None
        self.run.close()

    def __enter__(self) -> RecordedRun:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def platform_faults(run: Any) -> list[dict[str, Any]]:
    """A real robot's faults so far (its platform's watchdog stops, each drop and return of its link),
    as a record's end line keeps them; [] for the simulator and for worlds with no platform."""
    platform = getattr(getattr(getattr(run, "case", None), "sim", None), "platform", None)
    return [f.to_json() for f in list(getattr(platform, "faults", []))]


def describe(world: Any) -> tuple[str, list[tuple[str, str]]]:
    """What a loaded world declares: a title ("a robot world (office)") and rows to print."""
    return _kind_of_loaded(world).describe(world)


def replay_world(header: dict[str, Any], world_file: str | Path | None, record_path: Path, *,
                 allow_code_from_record: bool = False) -> Any:
    """The world (vwg.World) a record's header was made with: from `world_file` when given (a file
    or a shipped world's name, which must be of the record's kind), else from what the header keeps,
    importing no code the record names unless `allow_code_from_record` (vwg.generic.world_of_record)."""

    name = header.get("world_kind") or ("robot" if "robot_world" in (header.get("world") or {}) else "generic")
    kind = world_kinds.create(name)
    path = None
    if world_file is None and name == "robot":  # the file the record names, refused naming the record's field
        world_file = robot_world_file(robot_data(header, record_path), record_path)
    if world_file is not None:
        path = record_world_path(world_file, kind.name)
    return kind.replay_world(header, path, record_path, allow_code_from_record=allow_code_from_record)


def record_world_path(world_file: str | Path, kind: str) -> Path:
    """The world file (a path, or a shipped world's name) to run a record of a `kind` world with, refused unless it
    is of that kind. Checked before it is loaded: a generic world file named as a robot world's would otherwise be
    loaded, and its code run, before anything noticed."""
    path = resolve_world(world_file)
    found = kind_of(path, YamlDoc(path).data).name
    if found != kind:
        raise Error(f"{path}: the record was made by a {kind} world; this is a {found} world")
    return path


def check_port(flag: str, port: int | None) -> None:
    """A port to listen on: 0 (any free one) to 65535, or None (not asked for)."""
    if port is not None and not 0 <= port <= 65535:
        raise Error(f"{flag}: expected a port from 0 (any free one) to 65535, got {port}")


def record_options(header: dict[str, Any], world: Any, record_path: Path) -> RunOptions:
    """The options that run `world` again as the record's run went: its seed and frames, and a robot world's
    planner, orders (--goal, or the file's) and avoidance, each checked against the world."""
    options = RunOptions(seed=header.get("seed"), frames=header.get("frames_planned"))
    if (header.get("world_kind") or "generic") != "robot":
        return options
    data = robot_data(header, record_path)
    check_goals(data, list(world.rooms), [r.id for r in world.robots], record_path)
    return dataclasses.replace(options, planner=data["planner"], goals=data["goals"] or None,
                               no_world_orders=not data["world_orders"], avoidance=data["avoidance"])


def step_as_recorded(engine: Any, frame: dict[str, Any], record_path: Path,
                     generated: Callable[[list[Any]], None] = lambda events: None) -> None:
    """One frame of a run started again from a record: the string checked against the frame's (ReplayError),
    the generators asked as the run asked them (so they go on where they were; `generated` is given what they
    gave, the record's events when the run is the same), then the frame run with the recorded events."""
    if str(engine.string) != frame["string"]:
        raise ReplayError(frame["t"], frame["string"], str(engine.string))
    generated(list(engine.collect_events()))
    alphabet = engine.world.alphabet
    engine.step_with([alphabet.parse_event(text, f"{record_path}: frame {frame['t']}") for text in frame["events"]])


def strict_json(value: Any) -> Any:
    """`value` with every float that is not finite replaced by None, so json.dumps(allow_nan=False)
    writes JSON that any parser reads (Python's default would write Infinity and NaN)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: strict_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [strict_json(v) for v in value]
    return value


def write_summary(path: Path, summary: dict[str, Any]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(strict_json(summary), indent=2, allow_nan=False) + "\n", encoding="utf-8")
