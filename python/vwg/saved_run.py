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

__all__ = ["RESUME_OPTIONS", "read_state_file", "resume", "save_state"]

#: The run options a resumed run takes: what it writes and how fast, not what it is (its world, seed,
#: dt, planner, platform and orders are the saved run's).
RESUME_OPTIONS = frozenset({"frames", "threads", "record", "record_key", "summary_json", "progress", "backend",
                            "video", "images", "trajectory", "allow_unreached", "stdin_orders", "max_symbols"})


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _platform_of(run: Any) -> _core.RobotPlatform | None:
    case = getattr(run, "case", None)
    return case.sim.platform if case is not None else None


def _frames_left(run: Any) -> int:
    case = getattr(run, "case", None)
    return int(case.frames if case is not None else run.frames_to_run)


def save_state(run: Run, path: str | Path | None = None) -> bytes:
    """The state of `run` after its last whole frame, as the bytes of a state file; written to `path`
    too when given (whole or not at all: through a temporary file in its folder). Error naming the part
    that cannot be saved (a real robot's platform, a Python generator holding an open file)."""

    world = getattr(run, "world", None) or getattr(run, "spec", None)
    engine = run.engine
    parts: dict[str, bytes] = {}
    platform = _platform_of(run)
    if platform is not None:  # first: a real robot's refusal names the platform, not a generator of its link
        parts["platform"] = bytes(platform.save_state())
    state = engine.save_state()
    parts.update(engine_parts(state))
    inputs = {role: {"path": str(Path(p).resolve()), "sha256": _sha256(Path(p))}
              for role, p in run_inputs(world).items() if Path(p).is_file()}
    manifest: dict[str, Any] = {
        "vwg": _core.__version__,
        "world_kind": run.kind,
        "world_file": str(Path(world.path).resolve()),
        "inputs": inputs,
        "seed": int(engine.seed),
        "dt": float(engine.dt),
        "frame": int(state.frame),
        "time": float(engine.time),
        "frames_left": max(0, _frames_left(run) - (int(state.frame) - int(getattr(run, "first_frame", 0)))),
        "platform": platform.name() if platform is not None else None,
        "run": run.record_data if run.kind == "robot" else {},
    }
    data = write_state(manifest, parts)
    if path is not None:
        _write_whole(Path(path), data)
    return data


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


def _check_saved_by_this_vwg(saved: SavedState, source: str) -> None:
    m = saved.manifest
    if m.get("vwg") != _core.__version__:
        raise Error(f"{source}: saved by vwg {m.get('vwg')}; this is vwg {_core.__version__}, and a run is resumed "
                    "by the vwg that saved it (the frames after it would differ)")
    for role, entry in (m.get("inputs") or {}).items():
        p = Path(str(entry.get("path", "")))
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
    _check_saved_by_this_vwg(saved, source)
    m = saved.manifest
    world = load(str(m["world_file"]))
    kind = m.get("world_kind")
    frames = options.frames if options.frames is not None else int(m.get("frames_left", 0))
    made = dataclasses.replace(options, frames=frames, seed=int(m["seed"]), dt=float(m["dt"]), record=None,
                               record_key=None, summary_json=None)
    if kind == "robot":
        data = m.get("run") or {}
        made = dataclasses.replace(made, planner=data.get("planner"), goals=data.get("goals") or None,
                                   no_world_orders=not data.get("world_orders", True),
                                   platform=m.get("platform") or None)
    check_outputs(world, options, {"the state being resumed": Path(source)} if not source.startswith("<") else None)
    run = start(world, made)
    try:
        if kind != run.kind:
            raise Error(f"{source}: saved by a {kind} world; {world.path} is a {run.kind} world")
        platform = _platform_of(run)
        if ("platform" in saved.parts) != (platform is not None):
            raise Error(f"{source}: the state {'has' if 'platform' in saved.parts else 'has no'} platform part; "
                        f"this run {'has' if platform is not None else 'has no'} platform")
        if platform is not None:
            platform.load_state(saved.parts["platform"])
        run.engine.load_state(engine_state(saved, int(m["frame"])))
        run.first_frame = int(m["frame"])  # type: ignore[attr-defined]
    except BaseException:
        run.close()
        raise
    given = RunOptions(record=options.record, record_key=options.record_key, summary_json=options.summary_json,
                       frames=frames)
    return RecordedRun(run, world, given) if options.record or options.summary_json else run
