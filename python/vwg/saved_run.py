"""Saved runs: a run's whole state in one file, and a run that goes on from it, here or elsewhere.

    with vwg.start(vwg.load("warehouse"), vwg.RunOptions(frames=150)) as run:
        run.execute()
        run.save_state("at150.vwgstate")
    with vwg.resume("at150.vwgstate", vwg.RunOptions(frames=150)) as run:   # in another process, say
        run.execute()            # frames 150 to 299, as the run would have made them without stopping

A state holds the string with its blobs, the frame number, what every generator keeps (random streams,
pending orders), what every actor type's behaviour keeps (the deciders' searches and grids) and the
platform's state (the simulator's; a real robot's cannot be saved), in the file format of
vwg.io.state_file. It names the vwg that wrote it, the world file and the SHA-256 of every file the run
read (the world file, its map), the planner and the seed: resuming refuses another vwg, or a world file
or map changed since. The number of threads is not kept: any count gives the same frames.

A resumed run is made as the saved one was (its world file, seed, planner, platform, orders) and then
set to the saved state; what it writes (a record, a summary, a video) starts at the saved frame, and a
record continues the saved run's frame numbers with the frame lines an uninterrupted run would write.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import tempfile
from pathlib import Path
from typing import Any

import vwg._core as _core
from vwg.errors import Error
from vwg.io.state_file import MAX_BYTES, SavedState, engine_parts, engine_state, read_state, write_state
from vwg.launch import RecordedRun, Run, RunOptions, check_outputs, load, run_inputs, start
from vwg.model.limits import MAX_DT, MAX_FRAMES, MAX_SEED, MIN_DT

__all__ = [
    "RESUME_OPTIONS",
    "check_saved_by_this_vwg",
    "input_hashes",
    "keep_snapshots",
    "load_parts",
    "nearest_snapshot",
    "read_state_file",
    "resume",
    "save_state",
    "snapshot_folder",
    "state_parts",
]

#: The role of the world file among a run's inputs (launch.run_inputs).
WORLD_FILE = "the world file being run"

#: The run options a resumed run takes: what it writes and how fast, not what it is (its world, seed,
#: dt, planner, platform and orders are the saved run's).
RESUME_OPTIONS = frozenset({"frames", "threads", "record", "record_key", "summary_json", "progress", "backend",
                            "video", "images", "trajectory", "allow_unreached", "stdin_orders", "max_symbols", "mcap",
                            "foxglove_port", "foxglove_host"})


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def input_hashes(world: Any) -> dict[str, dict[str, str]]:
    """Each file a run of `world` reads (launch.run_inputs), by role: its path and SHA-256, as a state's
    manifest keeps them for check_saved_by_this_vwg."""
    return {role: {"path": str(Path(p).resolve()), "sha256": _sha256(Path(p))}
            for role, p in run_inputs(world).items() if Path(p).is_file()}


def _platform_of(run: Any) -> _core.RobotPlatform | None:
    case = getattr(run, "case", None)
    return case.sim.platform if case is not None else None


def _platform_name(run: Any) -> str | None:
    platform = _platform_of(run)
    return platform.name() if platform is not None else None


def _frames_left(run: Any) -> int:
    case = getattr(run, "case", None)
    return int(case.frames if case is not None else run.frames_to_run)


def save_state(run: Run, path: str | Path | None = None, *, platform: bool = True) -> bytes:
    """The state of `run` after its last whole frame, as the bytes of a state file; written to `path`
    too when given (whole or not at all: through a temporary file in its folder). Error naming the part
    that cannot be saved (a real robot's platform, a Python generator holding an open file).

    ``platform=False`` keeps only the string (the robots' beliefs and maps) and what the actors' behaviours
    keep (their deciders' searches): what a real robot's run can give. Resumed, it goes on on the simulator
    with each robot where it believed it was; the generators start afresh."""

    world: Any = getattr(run, "world", None) or getattr(run, "spec", None)
    engine = run.engine
    if platform:
        parts, frame = state_parts(engine, _platform_of(run))
    else:
        state = engine.save_state(generators=False)
        parts, frame = engine_parts(state), int(state.frame)
        del parts["generators"]
    manifest: dict[str, Any] = {
        "vwg": _core.__version__,
        "world_kind": run.kind,
        "world_file": str(Path(world.path).resolve()),
        "inputs": input_hashes(world),
        "seed": int(engine.seed),
        "dt": float(engine.dt),
        "frame": frame,
        "time": float(engine.time),
        "frames_left": max(0, _frames_left(run) - (frame - int(getattr(run, "first_frame", 0)))),
        "platform": _platform_name(run) if platform else None,
        "partial": not platform,
        "run": run.record_data if run.kind == "robot" else {},
    }
    data = write_state(manifest, parts)
    if path is not None:
        _write_whole(Path(path), data)
    return data


def state_parts(engine: _core.Engine, platform: _core.RobotPlatform | None) -> tuple[dict[str, bytes], int]:
    """The parts of a state file for an engine and the platform it drives (if any), and the frame."""
    parts: dict[str, bytes] = {}
    if platform is not None:  # first: a real robot's refusal names the platform, not a generator of its link
        parts["platform"] = bytes(platform.save_state())
    state = engine.save_state()
    parts.update(engine_parts(state))
    return parts, int(state.frame)


def load_parts(saved: SavedState, engine: _core.Engine, platform: _core.RobotPlatform | None, source: str) -> None:
    """Set a freshly made engine and platform to the state a file holds."""
    if ("platform" in saved.parts) != (platform is not None):
        raise Error(f"{source}: the state {'has' if 'platform' in saved.parts else 'has no'} platform part; "
                    f"this run {'has' if platform is not None else 'has no'} platform")
    if platform is not None:  # its steps may pass no more time than the saved run's
        platform.load_state(saved.parts["platform"], seconds=float(saved.manifest["time"]))
    engine.load_state(engine_state(saved, int(saved.manifest["frame"])))


def _load_beliefs(saved: SavedState, run: Any, source: str) -> None:
    """A state without generators and platform (save_state(platform=False)): the string and the behaviours'
    states, the generators as they are made, each robot on the platform where its actor believes it is."""
    parts = dict(saved.parts)
    parts["generators"] = engine_parts(run.engine.save_state())["generators"]  # as made: they start afresh
    run.engine.load_state(engine_state(SavedState(saved.manifest, parts), int(saved.manifest["frame"])))
    platform = _platform_of(run)
    if platform is None:
        raise Error(f"{source}: a state of the robots' beliefs goes on on a robot platform; this run has none")
    settings = {r.id: r for r in run.case.world.robots}
    for actor in run.case.robot_actors().values():
        rid = int(actor["id"])
        robot = settings.get(rid)
        if robot is None:
            continue  # one a λ spawned: the platform follows the string by itself (keep_robots_in_step)
        fields = {name: getattr(robot, name) for name, *_ in _core.RobotSettings.fields()}
        fields["start"] = (float(actor["x"]), float(actor["y"]), float(actor["angle"]))
        platform.remove_robot(rid)
        platform.add_robot(_core.RobotSettings(**fields))


def _write_whole(path: Path, data: bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except OSError as e:
        Path(tmp).unlink(missing_ok=True)
        raise Error(f"{path}: {e.strerror}: the state could not be written") from None


def read_state_file(state: str | Path | bytes) -> SavedState:
    """A state file (a path, or its bytes) read and checked: Error naming the part that is wrong."""
    if isinstance(state, (bytes, bytearray, memoryview)):
        return read_state(bytes(state), "<state bytes>")
    path = Path(state)
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise Error(f"{path}: {size} bytes is more than a state file may hold ({MAX_BYTES})")
        data = path.read_bytes()
    except OSError as e:
        raise Error(f"{path}: {e.strerror}: the state file could not be read") from None
    return read_state(data, str(path))


def _check_manifest(m: dict[str, Any], source: str) -> None:
    """The fields a resume reads, of the types and ranges a run has (a forged file is refused by name)."""

    def bad(field: str, expected: str) -> Error:
        return Error(f"{source}: the manifest's {field} is {str(m.get(field))[:80]!r}; expected {expected}")

    def whole(v: Any, hi: int) -> bool:
        return isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= hi

    for field, hi in (("frame", MAX_FRAMES), ("seed", MAX_SEED), ("frames_left", MAX_FRAMES)):
        if not whole(m.get(field), hi):
            raise bad(field, f"an integer from 0 to {hi}")
    for field, low, high in (("dt", MIN_DT, MAX_DT), ("time", 0.0, 1e300)):  # seconds
        v = m.get(field)
        if not (isinstance(v, (int, float)) and not isinstance(v, bool) and low <= v <= high):
            raise bad(field, f"a number of seconds from {low:g} to {high:g}")
    for field in ("world_file", "world_kind"):
        if not isinstance(m.get(field), str):
            raise bad(field, "text")
    if not isinstance(m.get("partial", False), bool):
        raise bad("partial", "true or false")
    if not (m.get("platform") is None or isinstance(m.get("platform"), str)):
        raise bad("platform", "a platform's name or null")
    inputs = m.get("inputs")
    if not (isinstance(inputs, dict) and inputs and all(
            isinstance(e, dict) and isinstance(e.get("path"), str) and isinstance(e.get("sha256"), str)
            for e in inputs.values())):
        raise bad("inputs", "the files the run read, each {path, sha256} (at least the world file)")
    if inputs.get(WORLD_FILE, {}).get("path") != m["world_file"]:
        raise bad("world_file", f"the file of the inputs' {WORLD_FILE!r}")
    run = m.get("run", {})
    if not isinstance(run, dict):
        raise bad("run", "a mapping")
    if m["world_kind"] == "robot":
        goals = run.get("goals") or []
        if not (isinstance(run.get("planner"), str) and isinstance(goals, list)
                and all(isinstance(g, str) for g in goals) and isinstance(run.get("world_orders", True), bool)):
            raise bad("run", "the robot run's planner (text), goals (texts) and world_orders (true or false)")


def check_saved_by_this_vwg(saved: SavedState, source: str) -> None:
    """Error unless this vwg saved it, its manifest is well formed and every file its run read is as it was."""
    m = saved.manifest
    if m.get("vwg") != _core.__version__:
        raise Error(f"{source}: saved by vwg {str(m.get('vwg'))[:40]}; this is vwg {_core.__version__}, and a run is "
                    "resumed by the vwg that saved it (the frames after it would differ)")
    _check_manifest(m, source)
    for role, entry in m["inputs"].items():
        p = Path(entry["path"])
        if not p.is_file():
            raise Error(f"{source}: {role} ({p}) is gone; the run cannot be made again without it")
        if _sha256(p) != entry.get("sha256"):
            raise Error(f"{p}: {role} changed since the state {source} was saved (its SHA-256 differs); a run is "
                        "resumed with the files it was saved with")


def resume(state: str | Path | bytes, options: RunOptions | None = None) -> Run:
    """The run a state file (a path, or its bytes) holds, ready to go on: ``execute()`` runs
    ``options.frames`` more frames (default: those the saved run had left). Only the options of
    RESUME_OPTIONS may be given; the rest are the saved run's."""

    options = options or RunOptions()
    for name in options.given():
        if name not in RESUME_OPTIONS:
            raise Error(f"--{name.replace('_', '-')}: a resumed run keeps the saved run's; give it to vwg run instead")
    source = "<state bytes>" if isinstance(state, (bytes, bytearray, memoryview)) else str(state)
    saved = read_state_file(state)
    check_saved_by_this_vwg(saved, source)
    m = saved.manifest
    world = load(str(m["world_file"]))
    kind = m.get("world_kind")
    frames = options.frames if options.frames is not None else int(m.get("frames_left", 0))
    made = dataclasses.replace(options, frames=frames, seed=int(m["seed"]), dt=float(m["dt"]), record=None,
                               record_key=None, summary_json=None)
    partial = bool(m.get("partial"))
    if kind == "robot":
        data = m.get("run") or {}
        made = dataclasses.replace(made, planner=data.get("planner"), goals=data.get("goals") or None,
                                   no_world_orders=not data.get("world_orders", True),
                                   platform="sim" if partial else m.get("platform") or None)
    check_outputs(world, options, {"the state being resumed": Path(source)} if not source.startswith("<") else None)
    run = start(world, made)
    try:
        if kind != run.kind:
            raise Error(f"{source}: saved by a {kind} world; {world.path} is a {run.kind} world")
        if partial:
            _load_beliefs(saved, run, source)
        else:
            load_parts(saved, run.engine, _platform_of(run), source)
        run.first_frame = int(m["frame"])  # type: ignore[attr-defined]
    except BaseException:
        run.close()
        raise
    given = RunOptions(record=options.record, record_key=options.record_key, summary_json=options.summary_json,
                       frames=frames)
    return RecordedRun(run, world, given) if options.record or options.summary_json else run


# ---- states kept beside a record (vwg run --snapshot-every, vwg replay --from) ---------------------------
def snapshot_folder(record: str | Path) -> Path:
    """The folder of the states kept beside a record: ``RECORD.states/``, one ``FRAME.vwgstate`` each."""
    record = Path(record)
    return record.with_name(record.name + ".states")


def keep_snapshots(run: Run, record: str | Path, every: int) -> Path:
    """Save the run's state after every `every`-th frame into snapshot_folder(record) (from the engine's
    observers, when each frame is complete); returns the folder."""
    if every < 1:
        raise Error(f"--snapshot-every: expected a number of frames >= 1, got {every}")
    folder = snapshot_folder(record)
    folder.mkdir(parents=True, exist_ok=True)

    def keep(frame: _core.FrameRecord) -> None:
        done = frame.frame + 1  # frames complete: the state's frame
        if done % every == 0:
            save_state(run, folder / f"{done:012d}.vwgstate")

    run.engine.add_observer(keep)
    return folder


def nearest_snapshot(record: str | Path, frame: int) -> tuple[Path, int] | None:
    """The state kept beside `record` of the latest frame at or before `frame`, and that frame; None if
    there is none."""
    folder = snapshot_folder(record)
    best: tuple[Path, int] | None = None
    if folder.is_dir():
        for p in folder.glob("*.vwgstate"):
            if p.stem.isdigit() and int(p.stem) <= frame and (best is None or int(p.stem) > best[1]):
                best = (p, int(p.stem))
    return best
