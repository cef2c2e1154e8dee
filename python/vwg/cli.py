"""The ``vwg`` command: ``run`` a world file (or a shipped world by name), ``replay`` a record, ``check``
a world file, draw a robot world in 3D (``overview``), list the shipped ``worlds``, run a ``sweep``
of many runs on Dask, measure the paper's five tests (``experiments``), show a run live in the
browser (``serve``).

Exit status: 0 on success; 1 when a frame failed (an error in an actor, generator or backend); 2 for
bad input (a file, an option); 3 when ``vwg run`` (or ``vwg replay --from``) finished but a robot
with an order did not reach its room (``--allow-unreached`` makes that 0); 4 when a real robot's
link failed (the robot was stopped first; the summary lists the faults); 130 when interrupted.

A run that seems stuck: ``kill -USR1 PID`` prints the Python stack of each of its threads on stderr
(the standard library's faulthandler), and the run goes on."""

from __future__ import annotations

import argparse
import dataclasses
import faulthandler
import re
import signal
import sys
import time
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import yaml

import vwg._core as _core
from vwg.errors import Error, FrameError, ReplayError, clip
from vwg.generic import named_world_file, replay
from vwg.io.files import check_output_file
from vwg.io.foxglove_server import FoxgloveServer
from vwg.io.record import Recorder, read_key, read_record, robot_data, robot_world_file
from vwg.io.shipped import resolve_world, shipped_worlds
from vwg.io.state_file import engine_state
from vwg.io.yamldoc import YamlDoc
from vwg.launch import (
    EXIT_LINK_FAULT,
    EXIT_UNREACHED,
    RunOptions,
    check_outputs,
    check_port,
    describe,
    kind_of,
    load,
    platform_faults,
    record_options,
    record_world_path,
    replay_world,
    run_inputs,
    start,
    step_as_recorded,
    strict_json,
)
from vwg.plugins import GROUPS, backends, deciders, platforms, world_kinds
from vwg.robot.export import export_record
from vwg.robot.foxglove_layout import write_layout
from vwg.robot.topics import open_sinks
from vwg.robot.world_file import AVOIDANCES, Avoidance, load_robot_world
from vwg.saved_run import keep_snapshots, nearest_snapshot, read_state_file, resume

__all__ = ["EXIT_CODES", "EXIT_UNREACHED", "main", "strict_json"]

#: What each exit status of `vwg` means (`vwg --help` and the docs show this table).
EXIT_CODES = {
    0: "done: the run ended, every robot sent to a room reached it; a replay matched its record",
    1: "a frame failed (a part raised: the error names the frame, stage, actor and event); `vwg plugins`: an "
       "entry point did not load",
    2: "bad input (a world file, record, state, option or output path), named with its file, line and field; "
       "a record that does not replay (the first differing frame is shown)",
    EXIT_UNREACHED: "a robot did not reach the room it was sent to (`--allow-unreached` makes this 0)",
    EXIT_LINK_FAULT: "a real robot's link was lost or flapped: the robot was stopped, the faults are in the "
                     "summary and the record",
    130: "interrupted (Ctrl-C): the robot stopped, the record and --save-state kept up to the last whole frame",
}


def _print_summary(rows: list[tuple[str, str]]) -> None:
    width = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"  {k:<{width}}  {v}")


def _world_file(arg: Path, command: str, expected: str) -> Path:
    """The world file an argument names (a file, or a shipped world's name), refused with a sentence
    saying what `command` takes when it is not of the `expected` kind."""

    path = resolve_world(arg)
    kind = kind_of(path, YamlDoc(path).data)
    if kind.name != expected:
        raise Error(f"{path}: vwg {command} takes a {expected} world; this is a {kind.name} world")
    return path


def _options(args: argparse.Namespace) -> Any:

    return RunOptions(frames=args.frames, seed=args.seed, dt=args.dt, max_symbols=args.max_symbols,
                      threads=args.threads, backend=args.backend, record=args.record, record_key=args.record_key,
                      summary_json=args.summary_json,
                      progress=args.progress, platform=args.platform, platform_options=_platform_options(args),
                      planner=args.planner, avoidance=args.avoidance, goals=args.goal,
                      no_world_orders=args.no_world_orders, stdin_orders=args.stdin_orders, video=args.video,
                      images=args.images, trajectory=args.trajectory, allow_unreached=args.allow_unreached,
                      mcap=args.mcap, foxglove_port=args.foxglove_port, foxglove_host=args.foxglove_host)


class _StopOnInterrupt:
    """While a run that saves its state runs, the first Ctrl-C asks the engine to stop after the frame under
    way (so the state saved is that of the last whole frame); a second one interrupts at once."""

    def __init__(self, engine: Any, active: bool) -> None:
        self.engine, self.active, self.interrupted = engine, active, False
        self.previous: Any = None

    def _handle(self, signum: int, frame: Any) -> None:
        self.interrupted = True
        self.engine.request_stop()
        signal.signal(signal.SIGINT, signal.default_int_handler)
        print("vwg: interrupted: stopping after this frame to save the state (Ctrl-C again to stop at once)",
              file=sys.stderr)

    def __enter__(self) -> _StopOnInterrupt:
        if self.active:
            self.previous = signal.signal(signal.SIGINT, self._handle)
        return self

    def __exit__(self, *exc: object) -> None:
        if self.active:
            signal.signal(signal.SIGINT, self.previous)


def _execute(run: Any, args: argparse.Namespace, progress: bool | None) -> tuple[Any, bool]:
    """Run it to its end, keeping states beside the record (--snapshot-every) and the last one
    (--save-state, also when Ctrl-C stops it); the outcome and whether Ctrl-C stopped it."""
    if args.snapshot_every is not None:
        if not getattr(run, "recorder", None):
            raise Error("--snapshot-every keeps the states beside the record: give --record too")
        keep_snapshots(run, args.record, args.snapshot_every)
    with _StopOnInterrupt(run.engine, active=args.save_state is not None) as stop:
        outcome = run.execute(progress=progress)
    if args.save_state is not None:
        note = ""
        try:
            run.save_state(args.save_state)
        except Error as e:
            if run.kind != "robot" or not str(e).startswith("platform "):
                raise
            # A real robot: what it believed and mapped, to go on on the simulator.
            run.save_state(args.save_state, platform=False)
            note = "; the robots' beliefs, maps and planners only (its platform cannot be saved): resumed, on the sim"
        outcome.outputs["state"] = f"{args.save_state} (frame {run.engine.frame}{note})"
    return outcome, stop.interrupted


def _check_state_outputs(world: Any, args: argparse.Namespace, inputs: dict[str, Path] | None = None) -> None:
    if args.save_state is not None:
        check_output_file(Path(args.save_state), "--save-state", {**run_inputs(world), **(inputs or {})})


def _report(args: argparse.Namespace, title: str, outcome: Any, interrupted: bool) -> int:
    if not args.quiet:
        print(f"{title} — {outcome.title}")
        _print_summary(outcome.rows + list(outcome.outputs.items()))
    if interrupted:
        print("vwg: interrupted", file=sys.stderr)
        return 130
    if outcome.exit_status:
        print(f"vwg: {outcome.message}", file=sys.stderr)
    return int(outcome.exit_status)


def _cmd_run(args: argparse.Namespace) -> int:

    if not 0 <= args.python_budget <= 86400:  # (NaN fails both)
        raise Error(f"--python-budget: expected 0 (no reports) to 86400 seconds, got {args.python_budget}")
    _core.set_python_budget(args.python_budget)
    world = load(args.world)
    options = _options(args)
    if args.snapshot_every is not None and args.record is None:
        raise Error("--snapshot-every keeps the states beside the record: give --record too")
    _check_state_outputs(world, args)
    try:
        run = start(world, options)
        _say_foxglove("vwg run", getattr(run, "sinks", []))
        try:
            outcome, interrupted = _execute(run, args, options.progress)
        finally:
            run.close()
    except (FrameError, MemoryError) as e:
        if not _out_of_memory(e):
            raise
        grid = getattr(world, "grid", None)
        cells = f" (its map has {grid.width * grid.height:,} cells)" if grid is not None else ""
        raise Error(f"{args.world}: not enough memory for this run{cells}: use a smaller map or a machine "
                    "with more memory") from None
    return _report(args, f"vwg run {args.world}", outcome, interrupted)


def _say_foxglove(command: str, sinks: Sequence[Any]) -> None:
    for sink in sinks:
        if isinstance(sink, FoxgloveServer):
            print(f"{command}: the Foxglove server is on ws://{sink.host}:{sink.port} (in Foxglove: Open connection, "
                  "Foxglove WebSocket)", file=sys.stderr, flush=True)


def _cmd_resume(args: argparse.Namespace) -> int:

    options = RunOptions(frames=args.frames, threads=args.threads, record=args.record, record_key=args.record_key,
                         summary_json=args.summary_json, progress=args.progress, backend=args.backend,
                         video=args.video, images=args.images, trajectory=args.trajectory,
                         allow_unreached=args.allow_unreached, stdin_orders=args.stdin_orders, mcap=args.mcap,
                         foxglove_port=args.foxglove_port, foxglove_host=args.foxglove_host)
    if args.snapshot_every is not None and args.record is None:
        raise Error("--snapshot-every keeps the states beside the record: give --record too")
    run = resume(args.state, options)
    _say_foxglove("vwg resume", getattr(run, "sinks", []))
    try:
        world = getattr(run, "world", None) or getattr(run, "spec", None)
        _check_state_outputs(world, args, {"the state being resumed": args.state})
        first = run.engine.frame
        outcome, interrupted = _execute(run, args, options.progress)
    finally:
        run.close()
    return _report(args, f"vwg resume {args.state} (from frame {first})", outcome, interrupted)


def _out_of_memory(e: BaseException) -> bool:
    """A MemoryError, or C++'s std::bad_alloc inside a frame (a FrameError caused by one)."""
    return any(isinstance(x, MemoryError) or "bad_alloc" in str(x) for x in (e, e.__cause__) if x is not None)


def _cmd_replay(args: argparse.Namespace) -> int:

    key = read_key(args.record_key) if args.record_key else None
    record = read_record(args.record, key)  # read once: decoding a long record is most of a replay's reading
    if args.resume_from is not None:
        return _resume(args, record, key)
    world = replay_world(record.header, args.world, Path(args.record),
                         allow_code_from_record=args.allow_code_from_record)
    backend = backends.create(args.backend, world=world) if args.backend else None
    start = time.perf_counter()
    engine = replay(args.record, world=world, backend=backend, record=record)
    wall = time.perf_counter() - start
    for warning in record.warnings:
        print(f"vwg: warning: {warning}", file=sys.stderr)
    print(f"vwg replay {args.record}: {len(record.frames)} frames replayed, every string as recorded "
          f"({wall:.1f} s)")
    if record.cut:
        print(f"  incomplete: {record.cut}")
    for fault in record.faults:  # a real robot's run: its watchdog stops and link drops, with their times
        who = "the link" if fault["robot"] == 0 else f"robot {fault['robot']}"
        print(f"  fault: {fault['time_s']:.3f} s, {who}: {fault['what']}")
    print(f"  final string: {clip(str(engine.string)) or 'ε'}")
    return 0


def _resume(args: argparse.Namespace, record: Any, key: bytes | None) -> int:
    """vwg replay --from FRAME: run the world again from its start (or from the latest state kept beside
    the record at or before FRAME, vwg run --snapshot-every), the frames before FRAME with the
    recorded events (each checked against the record; the generators still run, so they are where
    they were), then live from FRAME on with the world's generators (a new record with --record).
    The world file is --world, or the one the record names: a generic world's only if it holds the
    world kept in the record (else its code is not the record's), unless --allow-code-from-record.
    A robot world's run gets its --goal orders again from the record."""

    frames = [f["t"] for f in record.frames]
    if args.resume_from not in frames:
        raise Error(f"--from: the record holds frames {frames[0] if frames else '-'} to "
                    f"{frames[-1] if frames else '-'}; got {args.resume_from}")
    header = record.header
    expected = header.get("world_kind") or "generic"  # a kind this vwg knows (read_record checked it)
    robot = expected == "robot"
    data = robot_data(header, Path(args.record)) if robot else {}
    world_file = args.world or (robot_world_file(data, Path(args.record)) if robot else None)
    if world_file is None:
        world_file, why = named_world_file(header)
        if world_file is None:
            named = header.get("world_file")
            if not (args.allow_code_from_record and isinstance(named, str) and named):
                raise Error(f"--from: {args.record}: the world kept in the record cannot be run from its world "
                            f"file: {why}. Give the world file to run it with (--world FILE), or "
                            "--allow-code-from-record to run the file the record names")
            world_file = Path(named)
    try:
        path = record_world_path(world_file, expected)
    except Error as e:
        raise Error(f"--from: {e}") from None
    loaded = load(path)
    # A robot world's own orders again: the frames before FRAME get them from the record as they went, and
    # the run knows whom it sent where (when to stop, the summary).
    options = record_options(header, loaded, Path(args.record))
    if robot:
        options = dataclasses.replace(options, allow_unreached=args.allow_unreached)
    elif args.allow_unreached:
        raise Error("--allow-unreached is for robot worlds; this record is of a generic world")
    # The new record overwrites neither the record read nor the world's files, nor is it a named pipe.
    check_outputs(loaded, RunOptions(record=args.new_record), {"the record being replayed": Path(args.record)})
    snapshot = nearest_snapshot(args.record, args.resume_from)
    start_frame = int(header.get("frame") or 0)  # a resumed run's record starts at the frame it resumed at
    if not snapshot and start_frame:
        raise Error(f"--from: {args.record} starts at frame {start_frame}: its run went on from a saved state, and "
                    f"no state at or before frame {args.resume_from} is kept beside it (vwg resume --snapshot-every "
                    "keeps them); replay it without --from, or replay the record of the run that was saved")
    first = snapshot[1] if snapshot else 0
    if snapshot:
        _check_snapshot(snapshot[0], header, record, first, path)
    with (resume(snapshot[0], RunOptions(allow_unreached=args.allow_unreached)) if snapshot
          else start(loaded, options)) as run:
        engine = run.engine
        try:
            for frame in record.frames:
                if frame["t"] < first:
                    continue
                if frame["t"] == args.resume_from:
                    break
                step_as_recorded(engine, frame, Path(args.record))
            if str(engine.string) != frame["string"]:
                raise ReplayError(frame["t"], frame["string"], str(engine.string))
        except ReplayError as e:
            raise Error(f"--from: running the world again does not give the record's frames (a run on a real "
                        f"robot cannot be run again on the simulator): {e}") from None
        recorder = Recorder(args.new_record, engine, world_file=world_file, world_data=run.record_data,
                            world_kind=run.kind, frames_planned=header.get("frames_planned"), key=key) \
            if args.new_record else None
        try:
            left = max(0, start_frame + int(header.get("frames_planned") or 0) - args.resume_from)
            if robot:
                run.case.frames = left
            else:
                run.frames_to_run = left
            outcome = run.execute()
        finally:
            if recorder is not None:
                recorder.close(faults=platform_faults(run))
    kept = f"the state kept at frame {first}, " if snapshot else ""
    print(f"vwg replay {args.record} --from {args.resume_from}: {kept}frames {first} to {args.resume_from - 1} as "
          f"recorded, then live to frame {engine.frame}")
    _print_summary(outcome.rows + list(outcome.outputs.items()))
    if robot and outcome.exit_status:
        print(f"vwg: {outcome.message}", file=sys.stderr)
    return 0 if not robot else outcome.exit_status


def _check_snapshot(state: Path, header: dict[str, Any], record: Any, frame: int, world_file: Path) -> None:
    """A state kept beside a record is of that record's run: its world file, seed and the string the record
    holds at its frame (else it was left there by another run)."""
    saved = read_state_file(state)
    strings = {f["t"]: f["string"] for f in record.frames}
    m = saved.manifest
    if (Path(str(m.get("world_file"))) != world_file.resolve() or m.get("seed") != header.get("seed")
            or frame not in strings):
        raise Error(f"--from: {state} was not kept by the run of this record (another world, seed or frame); "
                    f"remove it or its folder to replay from frame 0")
    if engine_state(saved, frame).string != strings[frame]:
        raise Error(f"--from: {state} holds another string at frame {frame} than the record; it was not kept by "
                    "this record's run")


def _cmd_export(args: argparse.Namespace) -> int:
    key = read_key(args.record_key) if args.record_key else None
    start_time = time.perf_counter()
    done = export_record(args.record, args.output, world_file=args.world, key=key, progress=args.progress,
                         allow_cut=args.allow_cut)
    if done.truth_frames == done.frames:
        truth = "with the ground truth"
    elif done.truth_frames:
        truth = (f"with the ground truth for the first {done.truth_frames} frames (the record's sensors part from the "
                 "simulator's there: a real robot's run)")
    else:
        truth = "without ground truth (a real robot's run)"
    print(f"vwg export {args.record}: {done.frames} frames, {done.messages} messages to {args.output}, {truth} "
          f"({time.perf_counter() - start_time:.1f} s)")
    return 0


def _cmd_check(args: argparse.Namespace) -> int:

    world = load(args.world)
    title, rows = describe(world)
    print(f"{args.world}: ok, {title}")
    _print_summary(rows)
    return 0


def _check_workers(args: argparse.Namespace) -> None:
    """--workers sizes the local cluster: 1 to 1024, and not with --scheduler (whose cluster is sized already)."""
    if args.workers is not None and not 1 <= args.workers <= 1024:
        raise Error(f"--workers: expected 1 to 1024 worker processes, got {args.workers}")
    if args.workers is not None and args.scheduler:
        raise Error("--workers sizes the local cluster; with --scheduler the scheduler's workers run the cells")


def _cmd_sweep(args: argparse.Namespace) -> int:
    from vwg.sweep import load_spec, run_sweep

    spec = load_spec(args.spec)
    _check_workers(args)
    result = run_sweep(spec, args.output, scheduler=args.scheduler, workers=args.workers, progress=args.progress)
    if result.repaired:
        print(f"vwg sweep: {result.repaired}", file=sys.stderr)
    print(f"vwg sweep {args.spec}: {result.cells} cells; {result.done_before} were already in the CSV, {result.ran} "
          f"ran now ({result.reached} reached their rooms, {result.failed} with an error)")
    print(f"  rows in {result.out}")
    return 0


def _cmd_experiments(args: argparse.Namespace) -> int:
    from vwg.experiments import run_experiments

    _check_workers(args)
    if args.output.exists() and not args.output.is_dir():
        raise Error(f"{args.output}: is not a folder (expected the folder to write the report in)")
    size = "quick" if args.quick else "full"
    config: Any = size
    if args.planner:  # test 1 swaps these deciders (any registered, a plugin's too)
        from vwg.experiments import CONFIGS

        unknown = [p for p in args.planner if p.lower() not in deciders]
        if unknown:
            raise Error(f"--planner: unknown planner {unknown[0]!r} (known: {_registered(deciders)})")
        base = CONFIGS[size]
        config = dataclasses.replace(base, evolution=dataclasses.replace(base.evolution, planners=list(args.planner)))
    report = run_experiments(args.output, config, workers=args.workers, scheduler=args.scheduler, resume=args.resume,
                             progress=args.progress)
    print(f"vwg experiments ({size}): {report}")
    return 0


def _cmd_serve(args: argparse.Namespace) -> int:

    try:
        from vwg.serve.live import LiveRun
        from vwg.serve.server import serve
    except ImportError as e:
        raise Error(f"vwg serve needs aiohttp: pip install 'vwg[serve]' ({e})") from None
    path = _world_file(args.world, "serve", expected="robot")
    world = load_robot_world(path)
    check_port("--port", args.port)
    check_port("--foxglove-port", args.foxglove_port)
    if args.dt is not None:
        import dataclasses

        _core.check_dt(args.dt, "--dt")  # the range vwg run and world files take
        world = dataclasses.replace(world, dt=args.dt)
    if args.avoidance is not None:
        world = dataclasses.replace(world, avoidance=Avoidance.of(args.avoidance))
    spec = world.platform.given(args.platform, **_platform_options(args))
    truth = bool(getattr(platforms.get(spec.kind), "ground_truth", False)) if args.foxglove_port is not None else False
    sinks = open_sinks(None, args.foxglove_port, args.host, world=world, ground_truth=truth)
    try:
        live = LiveRun(world, planner=args.planner or world.planner, platform=spec, speed=args.speed, seed=args.seed,
                       threads=args.threads, world_orders=not args.no_world_orders, paused=args.paused,
                       topics_to=sinks)
    except BaseException:
        for sink in sinks:
            sink.close()
        raise
    _say_foxglove("vwg serve", sinks)
    if args.host not in ("127.0.0.1", "localhost", "::1"):
        print(f"vwg serve: listening on {args.host}: anyone who can reach it can drive the robots", file=sys.stderr)

    def ready(url: str) -> None:
        print(f"vwg serve {args.world}: {url} (Ctrl-C stops)", flush=True)

    try:
        serve(live, host=args.host, port=args.port, on_ready=ready)
    finally:
        live.stop()
    return 0


def _cmd_foxglove_layout(args: argparse.Namespace) -> int:
    path = _world_file(args.world, "foxglove-layout", expected="robot")
    world = load_robot_world(path)
    check_output_file(args.output, "the layout", run_inputs(world))
    write_layout(world, args.output)
    print(f"vwg foxglove-layout {args.world}: {args.output} (in Foxglove: Layouts, Import from file)")
    return 0


def _cmd_overview(args: argparse.Namespace) -> int:
    from vwg.robot.overview import render_world_overview

    path = _world_file(args.world, "overview", expected="robot")
    world = load_robot_world(path)
    image = render_world_overview(world, width=args.width, height=args.height)
    out = args.output or Path(f"{world.name}_3d.png")
    _core.write_image(str(out), image)
    print(f"{out}: {world.name} in 3D ({image.shape[1]}×{image.shape[0]})")
    return 0


def _cmd_worlds(args: argparse.Namespace) -> int:

    print(f"{len(shipped_worlds())} shipped worlds; run one with `vwg run NAME`, describe it with `vwg check NAME`:")
    rows = []
    for name, path in shipped_worlds().items():
        w = load_robot_world(path)
        rows.append((name, f"{len(w.robots)} robot{'s' if len(w.robots) > 1 else ''}, {len(w.rooms)} rooms, "
                           f"{w.grid.width_m:g} × {w.grid.height_m:g} m. {w.description}"))
    _print_summary(rows)
    return 0


def _cmd_plugins(args: argparse.Namespace) -> int:
    """Every registered part by group (name and where it came from), and the entry points that did not load."""
    failed = 0
    for group, registry in GROUPS.items():
        if args.group and group != args.group:
            continue
        print(f"{group}:")
        for plugin in registry.plugins():
            print(f"  {plugin.name:<14} {plugin.origin}")
            part = registry.get(plugin.name)
            if getattr(part, "summary", ""):
                print(f"  {'':<14} {part.summary}")
            for key, option in (getattr(part, "options", None) or {}).items() if group == "vwg.platforms" else ():
                default = "required" if option.required else "unset by default" if option.default is None \
                    else f"default {option.default!r}"
                print(f"  {'':<14}   --platform-opt {key}=... ({option.kind.__name__}, {default}) {option.help}")
        for failure in registry.failures:
            failed += 1
            print(f"  {failure.name:<14} NOT LOADED ({failure.origin}): {failure.error}")
    return 1 if failed else 0


def _dask_options(command: argparse.ArgumentParser) -> None:
    """Where a command's runs go: a running Dask scheduler, or a local cluster of --workers processes."""
    command.add_argument("--scheduler", help="a running Dask scheduler (tcp://HOST:PORT); default: a local cluster")
    command.add_argument("--workers", type=int, help="worker processes of the local cluster (default: the cores)")
    command.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                         help="show progress bars (default: on a terminal)")


def _platform_option(value: str) -> tuple[str, Any]:
    """--platform-opt KEY=VALUE: VALUE read as YAML (a number, true/false, text, or {a: 1, b: 2})."""
    key, eq, text = value.partition("=")
    if not eq or not key.strip():
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {value!r}")
    try:
        parsed = yaml.safe_load(text) if text.strip() else ""
    except yaml.YAMLError as e:
        raise argparse.ArgumentTypeError(f"{key}: VALUE is not YAML ({getattr(e, 'problem', None) or e})") from None
    return key.strip(), parsed


def _platform_options(args: argparse.Namespace) -> dict[str, Any]:
    """The platform options the command line gives: --platform-opt KEY=VALUE, and the shorthands --url
    (rosbridge) and --serial-port (serial)."""
    options = dict(args.platform_opt or [])
    for key, value in (("url", args.url), ("port", args.serial_port)):
        if value is not None:
            if key in options:
                raise Error(f"--platform-opt {key}= and its shorthand are both given; give one")
            options[key] = value
    return options


def _registered(registry: Any) -> str:
    return ", ".join(registry) or "none"


# Help texts name the registered parts by a mark, filled in only when a help is shown: listing them loads every
# plugin of their group, and a command that shows no help should not (a broken plugin warned on every command, a
# slow one slowed every command).
_PARTS = {"deciders": deciders, "platforms": platforms, "backends": backends, "world_kinds": world_kinds}


def _names_of(group: str) -> str:
    """The mark of a group's registered names in a help text (see _HelpFormatter)."""
    assert group in _PARTS, group
    return f"@{group}@"


def fill_registered_names(text: str) -> str:
    """`text` with each group's mark (_names_of) replaced by the group's registered names."""
    return re.sub(r"@(\w+)@", lambda m: _registered(_PARTS[m[1]]) if m[1] in _PARTS else m[0], text)


class _HelpFormatter(argparse.HelpFormatter):
    """argparse's, with the registered parts' names put in a help before it is wrapped."""

    def _expand_help(self, action: argparse.Action) -> str:
        return fill_registered_names(super()._expand_help(action))

    def _format_text(self, text: str) -> str:
        return super()._format_text(fill_registered_names(text))


class _Parser(argparse.ArgumentParser):
    """A parser (and its commands', of the same class) whose helps name the registered parts when shown."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", _HelpFormatter)
        super().__init__(*args, **kwargs)


def _planner_name(value: str) -> str:
    """--planner: a name (an empty one ran astar silently); which names exist is checked at the run."""
    if not value.strip():
        raise argparse.ArgumentTypeError(f"expected a planner's name, got {value!r}")
    return value


def _goal(value: str) -> str:
    """--goal: ROOM or ROBOT:ROOM with a room ('1:' and ':' were "unknown room ''" at the run)."""
    if not value.rpartition(":")[2].strip():
        raise argparse.ArgumentTypeError(f"expected ROOM or ROBOT:ROOM, got {value!r}")
    return value


def _platform_arguments(group: Any) -> None:
    group.add_argument("--platform-opt", action="append", type=_platform_option, metavar="KEY=VALUE",
                       help="an option of the platform, over the world file's (repeatable; vwg plugins lists each "
                            "platform's options)")
    group.add_argument("--url", help="the rosbridge server of --platform rosbridge (ws://HOST:PORT): "
                                     "--platform-opt url=URL")
    group.add_argument("--serial-port", help="the serial port of --platform serial (/dev/ttyUSB0, "
                                             "socket://HOST:PORT): --platform-opt port=PORT")


def _ros_arguments(group: Any) -> None:
    group.add_argument("--mcap", type=Path, metavar="FILE.mcap",
                       help="write the run's ROS 2 messages (odometry, scans, plans, maps, camera, /tf) to an MCAP "
                            "file that ros2 bag play and Foxglove read")
    group.add_argument("--foxglove-port", type=int, metavar="PORT",
                       help="serve the same messages live to the Foxglove app (ws://127.0.0.1:PORT; 0: a free port)")
    group.add_argument("--foxglove-host", default="127.0.0.1",
                       help="the address the Foxglove server listens on (default 127.0.0.1: this machine)")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="vwg", description="vwg, the Virtual Worlds Generator: run worlds written as strings of a grammar.",
        epilog="exit status: " + "; ".join(f"{status} {meaning.split(':')[0].split(' (')[0]}"
                                           for status, meaning in sorted(EXIT_CODES.items())),
    )
    parser.add_argument("--version", action="version", version=f"vwg {_core.__version__}")
    parser.add_argument("--verbose", "-v", action="count", default=0,
                        help="print vwg's and its libraries' messages (-v: warnings and info, -vv: debug)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    run = sub.add_parser("run", help="run a world file", description="Run a world file and print a summary.")
    run.add_argument("world", type=Path, help="a world file (YAML), or the name of a shipped world (vwg worlds)")
    run.add_argument("--frames", type=int, help="number of frames, 0 to 2**64 - 1 (default: the file's, else 100)")
    run.add_argument("--seed", type=int, help="random seed, 0 to 2**64 - 1 (default: the file's, else 0)")
    run.add_argument("--dt", type=float, help="seconds per frame, 1e-6 to 3600 (default: the file's, else 0.1)")
    run.add_argument("--backend", help=f"a registered backend ({_names_of('backends')}): instead of the file's in "
                                       "a generic world, beside the simulator and its view in a robot world")
    run.add_argument("--max-symbols", type=int, default=10_000_000,
                     help="fail if the string grows past this many symbols (default 10 000 000; 0: no limit)")
    run.add_argument("--python-budget", type=float, default=1.0, metavar="SECONDS",
                     help="warn when one call of a Python part (actor, generator, backend, decider) takes longer "
                          "(default 1 s; 0: never); the frames do not change")
    run.add_argument("--threads", type=int, default=0,
                     help="threads for the robots' lasers and decisions (default 0: the machine's cores); any "
                          "count gives the same frames")
    robot = run.add_argument_group("robot worlds (the case study: world files that name a map)")
    robot.add_argument("--platform", help=f"where the robots run: a registered platform ({_names_of('platforms')}; "
                                           "default: the world file's platform:, else sim)")
    _platform_arguments(robot)
    robot.add_argument("--planner", type=_planner_name,
                       help=f"the decision inside eDecide, a registered decider ({_names_of('deciders')}; "
                            "default: the world file's planner:, else astar)")
    robot.add_argument("--avoidance", choices=AVOIDANCES,
                       help="how every robot passes the others: none, or orca (reciprocal avoidance of the robots "
                            "and people its laser sees; default: the world file's avoidance:, else none)")
    robot.add_argument("--goal", action="append", metavar="[ROBOT:]ROOM", type=_goal,
                       help="send a robot (default the first) to a room at the start; repeatable; replaces "
                            "the world file's orders")
    robot.add_argument("--no-world-orders", action="store_true",
                       help="ignore the orders scripted in the world file (only --goal and standard input)")
    robot.add_argument("--stdin-orders", action="store_true",
                       help="read orders while running from standard input: ROOM or ROBOT ROOM per line")
    robot.add_argument("--video", type=Path, help="write the run as a video (.mp4 H.264 or .gif)")
    robot.add_argument("--images", type=Path, help="write every frame as a PNG into this folder")
    robot.add_argument("--trajectory", type=Path, help="PNG of the trajectories (default: beside the video)")
    robot.add_argument("--summary-json", type=Path, help="write the summary as JSON (non-finite numbers as null)")
    _ros_arguments(robot)
    robot.add_argument("--allow-unreached", action="store_true",
                       help=f"exit 0 even when a robot did not reach its room (otherwise exit {EXIT_UNREACHED})")
    run.add_argument("--record", type=Path, help="write every frame to this JSON Lines file")
    run.add_argument("--record-key", type=Path, metavar="FILE",
                     help="make the record's chain an HMAC with the key in FILE (at least 16 bytes): only the key's "
                          "holder can then change a record and have it read whole (vwg replay --record-key FILE)")
    run.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                     help="show a progress bar (default: on a terminal)")
    run.add_argument("--quiet", "-q", action="store_true", help="print nothing on success")
    _state_arguments(run)
    run.set_defaults(func=_cmd_run)

    res = sub.add_parser("resume", help="go on with a run saved by --save-state",
                         description="Go on from a state saved by `vwg run --save-state` (or --snapshot-every): the "
                                     "same world, seed, planner, platform and orders, for --frames more frames "
                                     "(default: those the saved run had left), on this machine or another. A record "
                                     "it writes continues the saved run's frame numbers. Exit status as vwg run's.")
    res.add_argument("state", type=Path, help="a state file (vwg run --save-state)")
    res.add_argument("--frames", type=int,
                     help="frames to run from the saved one (default: what the saved run had left)")
    res.add_argument("--threads", type=int, default=0, help="threads (default 0: the machine's cores); any count gives "
                                                            "the same frames")
    res.add_argument("--backend", help="a registered backend by name, shown on beside the world's own")
    res.add_argument("--record", type=Path, help="write every frame from the saved one on to this JSON Lines file")
    res.add_argument("--record-key", type=Path, metavar="FILE", help="make the record's chain an HMAC with this key")
    res.add_argument("--summary-json", type=Path, help="write the summary as JSON")
    res.add_argument("--video", type=Path, help="a robot world: write the frames from the saved one on as a video")
    res.add_argument("--images", type=Path, help="a robot world: write every frame as a PNG into this folder")
    res.add_argument("--trajectory", type=Path, help="a robot world: PNG of the trajectories from the saved frame on")
    res.add_argument("--allow-unreached", action="store_true",
                     help=f"a robot world: exit 0 even when a robot did not reach its room (otherwise "
                          f"{EXIT_UNREACHED})")
    res.add_argument("--stdin-orders", action="store_true", help="a robot world: read orders from standard input")
    _ros_arguments(res)
    res.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                     help="show a progress bar (default: on a terminal)")
    res.add_argument("--quiet", "-q", action="store_true", help="print nothing on success")
    _state_arguments(res)
    res.set_defaults(func=_cmd_resume)

    rep = sub.add_parser("replay", help="replay a record and check it",
                         description="Run a record's events again and check every string against it.")
    rep.add_argument("record", type=Path, help="a file written by `vwg run --record`")
    rep.add_argument("--world", type=Path,
                     help="the world file to replay it with; its code (actors, generators) is what runs (default: "
                          "the one the record names, if it holds the world kept in the record)")
    rep.add_argument("--allow-code-from-record", action="store_true",
                     help="a record runs no code of its own: without --world, a generic world is built from the "
                          "copy kept in the record only if that names no Python code or is the same as the world "
                          "file the record names. This builds it anyway, importing the modules the record names: "
                          "only for a record you trust")
    rep.add_argument("--record-key", type=Path, metavar="FILE",
                     help="the key the record was made with (vwg run --record-key): its chain is checked with it")
    rep.add_argument("--backend", help=f"show the replay on this registered backend ({_names_of('backends')})")
    rep.add_argument("--from", dest="resume_from", type=int, metavar="FRAME",
                     help="replay up to FRAME, then go on live from there with the world's generators (a robot "
                          "world: with the run's --goal orders, kept in the record)")
    rep.add_argument("--record", dest="new_record", type=Path, help="with --from: record the run that goes on")
    rep.add_argument("--allow-unreached", action="store_true",
                     help=f"with --from, a robot world: exit 0 even when a robot did not reach the room the run sent "
                          f"it to (otherwise exit {EXIT_UNREACHED})")
    rep.set_defaults(func=_cmd_replay)

    exp_mcap = sub.add_parser("export", help="a robot run's record as an MCAP file of ROS 2 messages",
                              description="Write a robot run's record (vwg run --record) as the MCAP file that vwg run "
                                          "--mcap writes: the world is run again on the record's events, each frame "
                                          "checked against it, and its topics written (odometry, scans, plans, maps, "
                                          "camera, /tf, the ground truth of a run on the simulator).")
    exp_mcap.add_argument("record", type=Path, help="a file written by `vwg run --record`")
    exp_mcap.add_argument("output", type=Path, metavar="FILE.mcap", help="the MCAP file to write")
    exp_mcap.add_argument("--world", type=Path, help="the world file (default: the one the record names)")
    exp_mcap.add_argument("--record-key", type=Path, metavar="FILE", help="the key of a record written with one")
    exp_mcap.add_argument("--allow-cut", action="store_true",
                          help="export a record with no end line (its run was killed): the whole frames it holds")
    exp_mcap.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                          help="show a progress bar (default: on a terminal)")
    exp_mcap.set_defaults(func=_cmd_export)

    swp = sub.add_parser("sweep", help="run worlds × planners × seeds × parameters on Dask, into a CSV",
                         description="Run every cell of a sweep SPEC (YAML: worlds, planners, seeds, frames, "
                                     "params) on Dask, appending a CSV row per cell as it finishes; a rerun skips "
                                     "the cells the CSV holds.")
    swp.add_argument("spec", type=Path, help="the sweep's SPEC file (YAML)")
    swp.add_argument("-o", "--output", type=Path, required=True, help="the results CSV (appended to; resumable)")
    _dask_options(swp)
    swp.set_defaults(func=_cmd_sweep)

    exp = sub.add_parser("experiments", help="the paper's five tests, measured, into a Markdown report",
                         description="Run the paper's five tests (§III.F) and write OUT_DIR/report.md with tables "
                                     "(and their CSVs) and plots. The full size takes about 35 minutes on 2 cores; "
                                     "--quick about a minute and a half.")
    exp.add_argument("output", type=Path, metavar="OUT_DIR", help="the folder for the report, its tables and plots")
    exp.add_argument("--quick", action="store_true", help="a small configuration (about 1.5 min on 2 cores)")
    exp.add_argument("--planner", action="append", type=_planner_name, metavar="NAME",
                     help=f"a decider test 1 compares, instead of its list (repeatable; registered: "
                          f"{_names_of('deciders')})")
    exp.add_argument("--resume", action="store_true",
                     help="keep the sweep cells of an earlier run in OUT_DIR/sweeps (the report says how many)")
    _dask_options(exp)
    exp.set_defaults(func=_cmd_experiments)

    srv = sub.add_parser("serve", help="run a robot world live in the browser; click a room to send a robot",
                         description="Run a robot world and show it live on a web page (127.0.0.1 unless --host): "
                                     "the map, robots, lasers, paths, markers, the selected robot's camera, string and "
                                     "a 3D view; orders by clicking a room or its marker; pause, step, speed, reset.")
    srv.add_argument("world", type=Path, help="a robot world file, or a shipped world's name")
    srv.add_argument("--port", type=int, default=8765, help="the port (default 8765; 0: any free port)")
    srv.add_argument("--host", default="127.0.0.1", help="the address to listen on (default 127.0.0.1: this machine)")
    srv.add_argument("--foxglove-port", type=int, metavar="PORT",
                     help="also serve the run's ROS 2 topics to the Foxglove app on this port, on --host (0: a free "
                          "port)")
    srv.add_argument("--planner", type=_planner_name,
                     help=f"the decision inside eDecide, a registered decider ({_names_of('deciders')}; default: the "
                          "world file's planner:, else astar)")
    srv.add_argument("--avoidance", choices=AVOIDANCES,
                     help="how every robot passes the others: none or orca (default: the world file's, else none)")
    srv.add_argument("--platform", help=f"a registered platform ({_names_of('platforms')}; default: the file's "
                                         "platform:, else sim)")
    _platform_arguments(srv)
    srv.add_argument("--speed", type=float, default=1.0, help="times real time (default 1; 0: as fast as it goes)")
    srv.add_argument("--seed", type=int, help="random seed (default: the file's)")
    srv.add_argument("--dt", type=float, help="seconds per frame (default: the file's)")
    srv.add_argument("--threads", type=int, default=0, help="threads for the lasers and decisions (default: cores)")
    srv.add_argument("--no-world-orders", action="store_true", help="ignore the orders scripted in the world file")
    srv.add_argument("--paused", action="store_true", help="start paused (Run starts the frames)")
    srv.set_defaults(func=_cmd_serve)

    ovw = sub.add_parser("overview", help="draw a robot world's map in 3D (the paper's Fig. 5)",
                         description="Draw a robot world in 3D: walls extruded, markers, robots at their starts.")
    ovw.add_argument("world", type=Path, help="a robot world file (one that names a map), or a shipped world's name")
    ovw.add_argument("-o", "--output", type=Path, help="the PNG to write (default: NAME_3d.png)")
    ovw.add_argument("--width", type=int, default=1000, help="the picture's width in pixels (default 1000)")
    ovw.add_argument("--height", type=int, default=700, help="the picture's height in pixels (default 700)")
    ovw.set_defaults(func=_cmd_overview)

    lay = sub.add_parser("foxglove-layout", help="write a Foxglove layout for a robot world's topics",
                         description="Write the Foxglove layout for a robot world's run (vwg run --mcap, "
                                     "--foxglove-port): the 3D panel from above with the maps, scans, plans and poses "
                                     "of each robot, and each robot's camera. Import it in Foxglove (Layouts, Import "
                                     "from file).")
    lay.add_argument("world", type=Path, help="a robot world file, or a shipped world's name")
    lay.add_argument("output", type=Path, metavar="FILE.json", help="the layout file to write")
    lay.set_defaults(func=_cmd_foxglove_layout)

    chk = sub.add_parser("check", help="load a world file, check it and report what it declares",
                         description=f"Check a world file of a registered kind ({_names_of('world_kinds')}) and "
                                     "describe it: a robot world's map, rooms, robots, sensors, orders and platform; a "
                                     "generic world's alphabet, generators and initial string.")
    chk.add_argument("world", type=Path, help="a world file, or the name of a shipped world")
    chk.set_defaults(func=_cmd_check)

    plg = sub.add_parser("plugins", help="list the registered deciders, sensors, platforms, backends and world kinds",
                         description="List every registered part by entry-point group, with where it came from "
                                     "(vwg itself or an installed plugin); exit status 1 if an entry point did "
                                     "not load (it is listed with its error).")
    plg.add_argument("--group", choices=list(GROUPS), help="only this group")
    plg.set_defaults(func=_cmd_plugins)

    wld = sub.add_parser("worlds", help="list the worlds that ship with vwg",
                         description="List the shipped robot worlds; run one with `vwg run NAME`.")
    wld.set_defaults(func=_cmd_worlds)
    return parser


def _state_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--save-state", type=Path, metavar="FILE",
                   help="write the run's state after its last frame (also when Ctrl-C stops it: the state of the last "
                        "whole frame); vwg resume FILE goes on from it")
    p.add_argument("--snapshot-every", type=int, metavar="K",
                   help="keep the state every K frames beside the record (RECORD.states/), from which vwg replay "
                        "RECORD --from FRAME starts instead of frame 0")


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:  # bare `vwg`: what it can do, not only that a command is missing
        parser.print_help(sys.stderr)
        return 2
    import logging

    if argv is None and hasattr(signal, "SIGUSR1"):  # the program, not a call from Python code
        faulthandler.register(signal.SIGUSR1, all_threads=True)

    # A Python part over its time budget, robots' memory no longer shared (the system's limit of
    # memory mappings), and a shipped world run in place of a folder of its name, are said on the
    # terminal even when nothing else is.
    for name in ("vwg.python", "vwg.shared_pages", "vwg.io.shipped"):
        said = logging.getLogger(name)
        if not said.handlers:
            handler = logging.StreamHandler(sys.stderr)
            handler.setFormatter(logging.Formatter("vwg: warning: %(message)s"))
            said.addHandler(handler)
            said.setLevel(logging.WARNING)
            said.propagate = bool(args.verbose)
    if args.verbose:
        logging.basicConfig(level=logging.DEBUG if args.verbose > 1 else logging.INFO,
                            format="%(name)s: %(levelname)s: %(message)s")
    try:
        return int(args.func(args))
    except FrameError as e:
        cause = e.__cause__
        if cause is not None and not isinstance(cause, Error):
            traceback.print_exception(type(cause), cause, cause.__traceback__, file=sys.stderr)
        print(f"vwg: error: {e}", file=sys.stderr)
        return 1
    except Error as e:
        print(f"vwg: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("vwg: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader of the output went away (`vwg run ... | head`): not a failure of the run.
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
