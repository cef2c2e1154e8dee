"""Recording a run as JSON Lines and replaying it exactly.

A record is one JSON object per line:

    {"vwg_record": 1, "version": ..., "world_file": ..., "world": {...}, "seed": 0, "dt": 0.1,
     "frame": 0, "initial": "<text>", "blobs": {...}}                       the header
    {"t": 0, "time": 0.0, "events": ["tick", ...], "string": "<text of w at the start of frame t>"}
    ...
    {"end": true, "t": 10, "string": "<text of the last string>"}

Blobs (large attributes) appear by name in the texts and with their content (zlib, base64) the
first time a line refers to them. Replaying re-runs η/π/φ with the recorded events and checks every
string against the record, so a replay is a bit-for-bit determinism check as well.
"""

from __future__ import annotations

import base64
import json
import zlib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

import numpy as np

from . import _core
from .errors import ReplayError, WorldFileError
from .world import World

__all__ = ["Record", "Recorder", "decode_blob", "encode_blob", "read_record", "replay"]

FORMAT = 1


def encode_blob(blob: _core.Blob) -> dict[str, Any]:
    data = np.asarray(blob).tobytes()
    packed = base64.b64encode(zlib.compress(data)).decode()
    return {"dtype": blob.dtype, "shape": list(blob.shape), "zlib_base64": packed}


def decode_blob(d: dict[str, Any]) -> _core.Blob:
    raw = zlib.decompress(base64.b64decode(d["zlib_base64"]))
    return _core.Blob(np.frombuffer(raw, dtype=d["dtype"]).reshape(d["shape"]))


class Recorder:
    """Records an engine's frames to `path` from now on (flushed every frame, so a crash loses
    nothing that completed). Use as a context manager, or call close() to write the end line."""

    def __init__(self, path: str | Path, engine: _core.Engine, *, world_file: str | Path | None = None,
                 world_data: dict[str, Any] | None = None) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file: IO[str] | None = self.path.open("w", encoding="utf-8")
        self._engine = engine
        initial = engine.string
        self._known = set(initial.blobs())
        self._write({
            "vwg_record": FORMAT,
            "version": _core.__version__,
            "world_file": str(Path(world_file).resolve()) if world_file else None,
            "world": world_data,
            "seed": engine.seed,
            "dt": engine.dt,
            "frame": engine.frame,
            "initial": str(initial),
            "blobs": {name: encode_blob(b) for name, b in initial.blobs().items()},
        })
        self.frames = 0
        engine.add_observer(self._on_frame)

    def _write(self, obj: dict[str, Any]) -> None:
        if self._file is None:
            return
        self._file.write(json.dumps(obj, ensure_ascii=False, allow_nan=False) + "\n")
        self._file.flush()

    def _on_frame(self, record: _core.FrameRecord) -> None:
        line: dict[str, Any] = {"t": record.frame, "time": record.time, "events": record.event_texts,
                                "string": record.before_text}
        fresh = {n: b for n, b in record.blobs.items() if n not in self._known}
        if fresh:
            line["blobs"] = {n: encode_blob(b) for n, b in fresh.items()}
            self._known.update(fresh)
        self._write(line)
        self.frames += 1

    def close(self) -> None:
        if self._file is None:
            return
        self._write({"end": True, "t": self._engine.frame, "string": str(self._engine.string)})
        self._file.close()
        self._file = None

    def __enter__(self) -> Recorder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


@dataclass
class Record:
    header: dict[str, Any]
    frames: list[dict[str, Any]]
    end: dict[str, Any] | None
    blobs: dict[str, _core.Blob]


def _lines(path: Path) -> Iterator[tuple[int, dict[str, Any]]]:
    try:
        f = path.open(encoding="utf-8")
    except FileNotFoundError:
        raise WorldFileError(str(path), "", "file not found") from None
    with f:
        for n, text in enumerate(f, start=1):
            if not text.strip():
                continue
            try:
                obj = json.loads(text)
            except json.JSONDecodeError as e:
                raise WorldFileError(str(path), f"column {e.colno}", f"not valid JSON: {e.msg}", line=n) from None
            if not isinstance(obj, dict):
                raise WorldFileError(str(path), "", "expected a JSON object on each line", line=n)
            yield n, obj


def read_record(path: str | Path) -> Record:
    """Read and check a record file."""
    path = Path(path)
    header: dict[str, Any] | None = None
    frames: list[dict[str, Any]] = []
    end = None
    blobs: dict[str, _core.Blob] = {}
    for n, obj in _lines(path):
        if header is None:
            if obj.get("vwg_record") != FORMAT:
                raise WorldFileError(str(path), "vwg_record", f"not a vwg record of format {FORMAT}", line=n)
            for key in ("initial", "seed", "dt"):
                if key not in obj:
                    raise WorldFileError(str(path), key, "missing from the header", line=n)
            header = obj
        elif obj.get("end"):
            end = obj
        else:
            for key, kind in (("t", int), ("events", list), ("string", str)):
                if not isinstance(obj.get(key), kind):
                    raise WorldFileError(str(path), key, f"missing or not a {kind.__name__}", line=n)
            frames.append(obj)
        for name, d in obj.get("blobs", {}).items():
            try:
                blobs[name] = decode_blob(d)
            except Exception as e:
                raise WorldFileError(str(path), f"blobs.{name}", f"cannot decode: {e}", line=n) from None
    if header is None:
        raise WorldFileError(str(path), "", "empty record")
    return Record(header, frames, end, blobs)


def world_of_record(record: Record, path: Path) -> World:
    """Rebuild the world (alphabet and actor classes) a record was made with."""
    from .worldfile import build_world
    from .yamldoc import YamlDoc

    data = record.header.get("world")
    world_file = record.header.get("world_file")
    if data is None:
        raise WorldFileError(str(path), "world", "the record does not say which world it ran; pass the world")
    base = Path(world_file) if world_file else path
    doc = YamlDoc(base, text=json.dumps(data))
    return build_world(doc)


def replay(path: str | Path, *, world: World | None = None, backend: _core.Backend | None = None) -> _core.Engine:
    """Run a record again: the same initial string, the recorded events, the same seed. Raises
    ReplayError at the first frame whose string differs from the record. Returns the engine."""
    from .engine import Engine

    path = Path(path)
    record = read_record(path)
    if world is None:
        world = world_of_record(record, path)
    initial = world.parse(record.header["initial"], f"{path}:initial", record.blobs)
    engine = Engine(world, initial, [], backend, dt=record.header["dt"], seed=record.header["seed"],
                    first_frame=record.header.get("frame", 0))
    for frame in record.frames:
        got = str(engine.string)
        if got != frame["string"]:
            raise ReplayError(frame["t"], frame["string"], got)
        events = [world.alphabet.parse_event(text, f"{path}: frame {frame['t']}") for text in frame["events"]]
        engine.step_with(events)
    if record.end is not None and str(engine.string) != record.end["string"]:
        raise ReplayError(record.end["t"], record.end["string"], str(engine.string))
    return engine
