"""World files: a world's alphabet, initial string, generators and backend in one YAML file.

    alphabet:
      primitives: [Lamp]                       # or {Lamp: {level: 1.0}}
      transformations: {Move: {dist: 0.0}}
      events: [tick, show]                     # or {eLaser: {dist: 0.0, angle: 0.0}}
      visual: [show]
      actors: ["blinker.py:Blinker"]           # a file beside the world file, or "package.module:Class"
    initial: "Move<2.0>(Blinker<on=true>) . Blinker<on=false>"
    generators:                                # in priority order
      - every_frame: tick
      - every_frame: show
      - schedule: {10: ["tick"]}               # events at frames
      - python: "gens.py:Noise"                # a vwg.Generator subclass, with optional args: {...}
    backend: trace                             # trace, null, a registered name, or {python: ..., args: ...}
                                               # (`vwg run` calls the backend's finish(), if any, at the end)
    frames: 10
    seed: 0
    dt: 0.1

Errors name the file, the line and the key path.
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import json
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import vwg._core as _core
from vwg.errors import Error, ReplayError, WorldFileError, clip
from vwg.io.record import Record, read_record
from vwg.io.yamldoc import YamlDoc
from vwg.launch import Outcome
from vwg.model.actor import Actor
from vwg.model.engine import Engine
from vwg.model.generators import Schedule, every_frame, resolve_generators
from vwg.model.limits import MAX_DT, MAX_FRAMES, MAX_SEED, MAX_TIME, MIN_DT
from vwg.model.world import Alphabet, World
from vwg.plugins import backends
from vwg.plugins import generators as generator_registry
from vwg.saved_run import save_state

__all__ = ["GenericKind", "WorldSpec", "build_world", "load_object", "load_world", "replay", "world_of_record"]

_TOP_KEYS = {"name", "alphabet", "initial", "generators", "backend", "frames", "seed", "dt", "description"}


@dataclass
class WorldSpec:
    """A loaded world file, ready to run."""

    path: Path
    name: str
    world: World
    initial: _core.String
    generators: list[_core.Generator]
    backend: _core.Backend | None
    frames: int
    seed: int
    dt: float
    data: dict[str, Any] = field(default_factory=dict)  # the YAML, stored in records for replay


def load_object(ref: str, base_dir: Path, where: str = "") -> Any:
    """Import ``"file.py:Name"`` (relative to base_dir) or ``"package.module:Name"``."""
    if ":" not in ref:
        raise Error(f"{where}: '{ref}' is not of the form 'file.py:Name' or 'module:Name'")
    module_ref, _, name = ref.rpartition(":")
    if module_ref.endswith(".py"):
        file = (base_dir / module_ref).resolve()
        if not file.is_file():
            raise Error(f"{where}: no file {file}")
        module_name = f"vwg_user_{abs(hash(str(file)))}_{file.stem}"
        module = sys.modules.get(module_name)
        if module is None:
            spec = importlib.util.spec_from_file_location(module_name, file)
            if spec is None or spec.loader is None:
                raise Error(f"{where}: cannot import {file}")
            module = importlib.util.module_from_spec(spec)
            sys.modules[module_name] = module
            spec.loader.exec_module(module)
    else:
        module = importlib.import_module(module_ref)
    try:
        return getattr(module, name)
    except AttributeError:
        raise Error(f"{where}: {module_ref} has no '{name}'") from None


def _wrap(doc: YamlDoc, path: tuple[Any, ...], fn: Any, /, *args: Any, **kwargs: Any) -> Any:
    """Run fn; a vwg error inside is re-raised naming the file, line and key."""
    try:
        return fn(*args, **kwargs)
    except WorldFileError:
        raise
    except (Error, ImportError, TypeError, ValueError) as e:
        raise doc.error(path, str(e)) from e


def build_world(doc: YamlDoc) -> World:
    """The alphabet and actor classes of a world file."""
    base = doc.path.parent
    doc.get(("alphabet",), dict)
    alphabet = Alphabet()
    for key, adder in (("primitives", alphabet.add_primitive), ("transformations", alphabet.add_transformation)):
        spec = doc.get(("alphabet", key), (list, dict), default=[])
        items = spec.items() if isinstance(spec, dict) else ((n, None) for n in spec)
        for i, (name, params) in enumerate(items):
            path = ("alphabet", key, name if isinstance(spec, dict) else i)
            if not isinstance(name, str):
                raise doc.error(path, f"expected a name, got {name!r}")
            _wrap(doc, path, adder, name, params)
    visual = doc.get(("alphabet", "visual"), list, default=[])
    events = doc.get(("alphabet", "events"), (list, dict), default=[])
    items = events.items() if isinstance(events, dict) else ((n, None) for n in events)
    declared = set()
    for i, (name, fields) in enumerate(items):
        path = ("alphabet", "events", name if isinstance(events, dict) else i)
        if not isinstance(name, str):
            raise doc.error(path, f"expected an event name, got {name!r}")
        _wrap(doc, path, alphabet.add_event_type, name, name in visual, fields or None)
        declared.add(name)
    for i, name in enumerate(visual):
        if name not in declared:
            raise doc.error(("alphabet", "visual", i), f"'{name}' is not among alphabet.events")
    for i, ref in enumerate(doc.get(("alphabet", "actors"), list, default=[])):
        path = ("alphabet", "actors", i)
        if not isinstance(ref, str):
            raise doc.error(path, f"expected 'file.py:Class' or 'module:Class', got {ref!r}")
        cls = _wrap(doc, path, load_object, ref, base, ref)
        if not (isinstance(cls, type) and issubclass(cls, Actor)):
            raise doc.error(path, f"'{ref}' is not a vwg.Actor subclass")
        _wrap(doc, path, alphabet.add_actor_type, cls)
    return World(alphabet)


def _generator(doc: YamlDoc, world: World, i: int, entry: Any, dt: float) -> Any:
    path = ("generators", i)
    base = doc.path.parent
    if isinstance(entry, str):
        entry = {entry: {}}
    if not isinstance(entry, dict) or len(entry) == 0:
        raise doc.error(path, "expected a mapping such as {every_frame: tick}")
    kind = next(iter(entry))
    if kind == "every_frame":
        event = doc.get((*path, "every_frame"), str)
        fields = doc.get((*path, "fields"), dict, default={})
        target = doc.get((*path, "target"), int, default=None)
        return _wrap(doc, path, lambda: resolve_generators(world.alphabet, [every_frame(event, target, **fields)])[0])
    if kind in ("schedule", "schedule_times"):
        table = doc.get((*path, kind), dict)
        for key, events in table.items():
            if not isinstance(events, list):
                raise doc.error((*path, kind, key), "expected a list of events")
            if kind == "schedule_times" and isinstance(key, (int, float)) and not isinstance(key, bool) \
                    and key > MAX_TIME:
                raise doc.error((*path, kind, key), f"expected a time of at most {MAX_TIME:g} seconds, got {key!r}")
        if kind == "schedule":
            return _wrap(doc, (*path, kind), Schedule, table)
        return _wrap(doc, (*path, kind), Schedule.at_times, table, dt)
    args = doc.get((*path, "args"), dict, default={})
    if kind == "python":
        ref = doc.get((*path, "python"), str)
        cls = _wrap(doc, (*path, "python"), load_object, ref, base, ref)
        gen = _wrap(doc, path, cls, **args)
    else:
        gen = _wrap(doc, path, generator_registry.create, kind, world=world, spec=entry)
    return _wrap(doc, path, lambda: resolve_generators(world.alphabet, [gen])[0])


def _backend(doc: YamlDoc, world: World) -> _core.Backend | None:
    entry = doc.get(("backend",), (str, dict), default=None)
    if entry is None:
        return None
    base = doc.path.parent
    if isinstance(entry, str):
        return _wrap(doc, ("backend",), backends.create, entry, world=world)
    if "python" in entry:
        ref = doc.get(("backend", "python"), str)
        cls = _wrap(doc, ("backend", "python"), load_object, ref, base, ref)
        args = doc.get(("backend", "args"), dict, default={})
        return _wrap(doc, ("backend",), cls, **args)
    name = doc.get(("backend", "type"), str)
    return _wrap(doc, ("backend",), backends.create, name, world=world, spec=entry)


def load_world(path: str | Path, *, seed: int | None = None, frames: int | None = None,
               dt: float | None = None, backend: str | None = None) -> WorldSpec:
    """Load and check a world file; the keyword arguments override the file's values."""
    doc = YamlDoc(path)
    if not isinstance(doc.data, dict):
        raise WorldFileError(str(doc.path), "", "expected a mapping at the top of the world file")
    for key in doc.data:
        if key not in _TOP_KEYS:
            raise doc.error((key,), f"unknown key (known: {', '.join(sorted(_TOP_KEYS))})")
    world = build_world(doc)
    initial_text = doc.get(("initial",), str)
    initial = _wrap(doc, ("initial",), world.parse, initial_text, f"{doc.path}:initial")
    dt_value = dt if dt is not None else doc.number(("dt",), _core.EngineOptions().dt, minimum=MIN_DT, maximum=MAX_DT)
    gens = [_generator(doc, world, i, g, dt_value) for i, g in enumerate(doc.get(("generators",), list, default=[]))]
    backend_obj = _wrap(doc, ("backend",), backends.create, backend, world=world) if backend else _backend(doc, world)
    return WorldSpec(
        path=doc.path,
        name=doc.get(("name",), str, default=doc.path.stem),
        world=world,
        initial=initial,
        generators=gens,
        backend=backend_obj,
        frames=frames if frames is not None else doc.number(("frames",), 100, minimum=0, maximum=MAX_FRAMES,
                                                            integer=True),
        seed=seed if seed is not None else doc.number(("seed",), 0, minimum=0, maximum=MAX_SEED, integer=True),
        dt=dt_value,
        data=doc.data,
    )


# ---- the generic kind of world file (vwg.launch) ---------------------------------------------------------
class GenericRun:
    """A generic world started: its engine, recorded with the world file's YAML (replay rebuilds the
    alphabet from it)."""

    def __init__(self, spec: WorldSpec, max_symbols: int, threads: int = 0) -> None:

        self.spec = spec
        self.frames_to_run = spec.frames  # fewer when the run goes on from a recorded frame (vwg replay --from)
        self.engine = Engine(spec.world, spec.initial, spec.generators, spec.backend, dt=spec.dt, seed=spec.seed,
                             max_symbols=max_symbols, threads=threads)
        self.record_data: dict[str, Any] = spec.data

    kind = "generic"

    def execute(self, progress: bool | None = False) -> Any:
        import time


        start = time.perf_counter()
        reason = self.engine.run(self.frames_to_run, progress=progress)
        wall = time.perf_counter() - start
        w = self.engine.string
        why = {"empty": "the world became empty", "stopped": "stopped", "done": "done"}.get(reason, "frame limit")
        rows = [
            ("frames", f"{self.engine.frame} ({why})"),
            ("simulated time", f"{self.engine.time:.3f} s (dt {self.spec.dt} s)"),
            ("seed", str(self.spec.seed)),
            ("final string", f"{len(w)} symbols, {w.actor_count} actors"),
            ("", clip(str(w)) or "ε"),
            ("wall time", f"{wall:.3f} s ({self.engine.frame / wall:.0f} frames/s)" if wall > 0 else "0 s"),
        ]
        if isinstance(self.spec.backend, _core.TraceBackend):
            rows.append(("backend calls", f"{len(self.spec.backend.calls)} (trace)"))
        summary = {"world": self.spec.name, "kind": "generic", "frames": self.engine.frame, "end": reason,
                   "simulated_time_s": round(self.engine.time, 9), "wall_time_s": wall, "seed": self.spec.seed,
                   "symbols": len(w), "actors": w.actor_count}
        return Outcome(self.spec.name, rows, summary)

    def save_state(self, path: str | Path | None = None) -> bytes:
        """The run's state after its last whole frame (vwg.saved_run): the string and what its generators
        keep; written to `path` when given."""
        return save_state(self, path)

    def close(self) -> None:
        # A backend that writes files (a video) finishes them in its finish(), if it has one
        # (close() is δ, the end of a transformation's scope).
        finish = getattr(self.spec.backend, "finish", None)
        if callable(finish):
            finish()

    def __enter__(self) -> GenericRun:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class GenericKind:
    """World files that declare an alphabet: their own actors, generators and backend."""

    name = "generic"
    shape = "a mapping with alphabet: and initial:"
    options: frozenset[str] = frozenset()

    def matches(self, data: dict[str, Any]) -> bool:
        return "alphabet" in data

    def matches_loaded(self, world: Any) -> bool:
        return isinstance(world, WorldSpec)

    def load(self, path: Path) -> WorldSpec:
        return load_world(path)

    def start(self, spec: WorldSpec, options: Any) -> GenericRun:
        if any(v is not None for v in (options.seed, options.frames, options.dt, options.backend)):
            # dt shapes the generators (schedule_times), so the file is read again with the overrides.
            spec = load_world(spec.path, seed=options.seed, frames=options.frames, dt=options.dt,
                              backend=options.backend)
        return GenericRun(spec, options.max_symbols, options.threads)

    def replay_world(self, header: dict[str, Any], path: Path | None, record_path: Path, *,
                     allow_code_from_record: bool = False) -> World:
        if path is not None:
            return load_world(path).world

        return world_of_record(header, record_path, allow_code_from_record=allow_code_from_record)

    def describe(self, spec: WorldSpec) -> tuple[str, list[tuple[str, str]]]:

        a = spec.world.alphabet
        return f"a generic world ({spec.name})", [
            ("primitives", ", ".join(a.primitives) or "-"),
            ("transformations", ", ".join(a.transformations) or "-"),
            ("actors", ", ".join(f"{n} {a.responds_to(n)}" for n in a.actors) or "-"),
            ("events", ", ".join(a.event_types) or "-"),
            ("visual events", ", ".join(a.visual_event_types) or "-"),
            ("generators", ", ".join(g.name for g in spec.generators) or "-"),
            ("initial string", clip(str(spec.initial)) or "ε"),
            ("frames", f"{spec.frames} (dt {spec.dt} s, seed {spec.seed})"),
        ]


# ---- the world a record ran ------------------------------------------------------------------------
def world_code(data: Any) -> list[str]:
    """The Python code a generic world's data names that rebuilding its alphabet imports: its actors."""
    alphabet = data.get("alphabet") if isinstance(data, dict) else None
    actors = alphabet.get("actors") if isinstance(alphabet, dict) else None
    return [str(ref) for ref in actors] if isinstance(actors, list) else []


def _content_hash(data: Any) -> str:
    """The hash of a world's data as JSON with sorted keys (the same for a world file and its copy in a record)."""
    text = json.dumps(json.loads(json.dumps(data, allow_nan=False)), sort_keys=True, ensure_ascii=False,
                      separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def named_world_file(header: dict[str, Any]) -> tuple[Path | None, str]:
    """The world file a generic world's record names, if it holds the world kept in the record (the
    same content): (path, ""), else (None, why not)."""

    named = header.get("world_file")
    if not isinstance(named, str) or not named:
        return None, "it names no world file"
    try:
        data = YamlDoc(Path(named)).data
        same = _content_hash(data) == _content_hash(header.get("world"))
    except (Error, OSError, TypeError, ValueError, RecursionError):
        return None, f"the world file it names, {named}, cannot be read"
    return (Path(named), "") if same else (None, f"it differs from the world file the record names, {named}")


def world_of_record(header: dict[str, Any], path: Path, *, allow_code_from_record: bool = False) -> World:
    """Rebuild the world (alphabet and actor classes) a generic world's record was made with. A record
    runs no code of its own: the world is built from the world file the record names when that file
    holds the world kept in the record, else from the record's copy only if that names no Python code
    (actors), or when `allow_code_from_record` says to import what it names."""

    data = header.get("world")
    if not isinstance(data, dict):
        raise WorldFileError(str(path), "world", "the record does not say which world it ran; pass the world",
                             line=1)
    world_file, why = named_world_file(header)
    if world_file is not None:
        return build_world(YamlDoc(world_file))
    code = world_code(data)
    if code and not allow_code_from_record:
        raise WorldFileError(str(path), "world", f"the world kept in the record names Python code "
                             f"({', '.join(code)}), and {why}: a record runs no code of its own. Give the world "
                             "file to replay it with (--world FILE), or --allow-code-from-record to import the "
                             "modules the record names", line=1)
    named = header.get("world_file")
    base = Path(named) if isinstance(named, str) and named else path
    return build_world(YamlDoc(base, text=json.dumps(data)))


def replay(path: str | Path, *, world: World | None = None, backend: _core.Backend | None = None,
           record: Record | None = None, key: bytes | None = None,
           allow_code_from_record: bool = False) -> _core.Engine:
    """Run a record again: the same initial string, the recorded events, the same seed. Raises
    ReplayError at the first frame whose string differs from the record. Returns the engine.
    ``record`` is the file already read (read_record(path, key)), if the caller has it; without
    `world`, the world is rebuilt as world_of_record says (importing no code the record names
    unless `allow_code_from_record`)."""
    path = Path(path)
    if record is None:
        record = read_record(path, key)
    if world is None:
        world = world_of_record(record.header, path, allow_code_from_record=allow_code_from_record)
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
