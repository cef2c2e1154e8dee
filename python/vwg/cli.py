"""The ``vwg`` command: ``run`` a world file (or a shipped world by name), ``replay`` a record, ``check``
a world file, draw a robot world in 3D (``overview``), list the shipped ``worlds``.

Exit status: 0 on success; 1 when a frame failed (an error in an actor, generator or backend); 2 for
bad input (a file, an option); 3 when ``vwg run`` finished but a robot with an order did not reach
its room (``--allow-unreached`` makes that 0); 130 when interrupted."""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from . import _core
from .errors import Error, FrameError

__all__ = ["main"]


def _clip(text: str, n: int = 200) -> str:
    return text if len(text) <= n else text[: n - 3] + "..."


def _print_summary(rows: list[tuple[str, str]]) -> None:
    width = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"  {k:<{width}}  {v}")


def _world_file(arg: Path, command: str, expected: str | None = None) -> tuple[Path, str]:
    """The world file an argument names (a file, or a shipped world's name) and its kind, "robot" or
    "generic"; with `expected`, another kind is refused with a sentence saying what `command` takes."""
    from .worlds import kind_of_world, resolve_world
    from .yamldoc import YamlDoc

    path = resolve_world(arg)
    kind = kind_of_world(path, YamlDoc(path).data)
    if expected and kind != expected:
        what = {"robot": "a robot world (a file that names a map:, such as `vwg worlds` lists)",
                "generic": "a generic world (a file that declares an alphabet:)"}
        raise Error(f"{path}: vwg {command} takes {what[expected]}; this is {what[kind].split(' (')[0]}")
    return path, kind


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


def _goals(values: list[str] | None, robots: list[int]) -> dict[int, str]:
    goals: dict[int, str] = {}
    for value in values or []:
        robot, _, room = value.rpartition(":")
        try:
            goals[int(robot) if robot else robots[0]] = room
        except ValueError:
            raise Error(f"--goal: expected ROOM or ROBOT:ROOM, got '{value}'") from None
    return goals


#: Exit status of `vwg run` when the run finished but a robot with an order did not reach its room.
EXIT_UNREACHED = 3


def _run_robot(args: argparse.Namespace, path: Path) -> int:
    import dataclasses

    from .casestudy import CaseStudy
    from .record import Recorder
    from .robotworld import load_robot_world

    if args.backend:
        raise Error("--backend is for generic worlds; a robot world runs on its simulator "
                    "(show it with --video, --images or --trajectory)")
    world = load_robot_world(path)
    if args.dt is not None:
        if not (math.isfinite(args.dt) and args.dt > 0):
            raise Error(f"--dt: expected a number of seconds > 0, got {args.dt}")
        world = dataclasses.replace(world, dt=args.dt)
    goals = _goals(args.goal, [r.id for r in world.robots])
    # Orders on the command line replace the world file's timed orders.
    case = CaseStudy(world, args.planner or "astar", goals=goals, platform=args.platform, seed=args.seed,
                     frames=args.frames, video=args.video,
                     images=args.images, max_symbols=args.max_symbols,
                     world_orders=False if args.no_world_orders else None)
    if args.stdin_orders:
        case.orders.read_lines(sys.stdin, lambda message: print(f"vwg: {message}", file=sys.stderr))
    recorder = None
    if args.record:
        recorder = Recorder(args.record, case.engine, world_file=world.path,
                            world_data={"robot_world": str(Path(world.path).resolve()), "planner": case.planner})
    try:
        with case:
            summary = case.run(progress=args.progress)
    finally:
        if recorder:
            recorder.close()
    trajectory = args.trajectory or (Path(args.video).with_suffix(".png") if args.video else None)
    if trajectory:
        case.save_trajectory(trajectory)
        summary.outputs["trajectory"] = str(trajectory)
    if args.record:
        summary.outputs["record"] = str(args.record)
    if args.summary_json:
        Path(args.summary_json).parent.mkdir(parents=True, exist_ok=True)
        summary.outputs["summary"] = str(args.summary_json)
        text = json.dumps(strict_json(summary.to_json()), indent=2, allow_nan=False)
        Path(args.summary_json).write_text(text + "\n", encoding="utf-8")
    if not args.quiet:
        print(f"vwg run {args.world} — {world.name}, planner {summary.planner}, seed {summary.seed}")
        ordered = [r for r in summary.robots if r.room is not None]
        rows = [
            ("reached", ("yes" if summary.reached else "no") if ordered else "- (no robot had an order)"),
            ("frames", f"{summary.frames} ({summary.simulated_time_s:.1f} s simulated, "
                       f"{summary.wall_time_s:.1f} s wall)"),
            ("path length", f"{summary.path_length_m:.2f} m"),
            ("collisions", str(summary.collisions)),
            ("replans", str(summary.replans)),
        ]
        for r in summary.robots:
            if r.room is None:
                where = "no order"
            elif r.reached:
                where = f"{r.room}: reached"
            else:
                where = f"{r.room}: {r.distance_to_goal_m:.2f} m away ({r.status})"
            rows.append((f"robot {r.id}", f"{where}, {r.path_length_m:.2f} m, {r.collisions} collisions, "
                                           f"{r.replans} replans"))
        for name, out in summary.outputs.items():
            rows.append((name, out))
        _print_summary(rows)
    if not summary.reached and not args.allow_unreached:
        missed = ", ".join(f"robot {r.id} ({r.room})" for r in summary.robots if r.room and not r.reached)
        print(f"vwg: not every order was reached: {missed}; exit status {EXIT_UNREACHED} "
              "(--allow-unreached exits 0)", file=sys.stderr)
        return EXIT_UNREACHED
    return 0


def _cmd_run(args: argparse.Namespace) -> int:
    from .engine import Engine
    from .record import Recorder
    from .worldfile import load_world

    path, kind = _world_file(args.world, "run")
    if kind == "robot":
        return _run_robot(args, path)
    robot_options = ("planner", "goal", "video", "images", "summary_json", "trajectory", "no_world_orders",
                     "stdin_orders", "allow_unreached", "platform")
    for option in robot_options:
        if getattr(args, option) not in (None, False):
            raise Error(f"--{option.replace('_', '-')} is for robot worlds (world files that name a map); "
                        f"{path} is a generic world")
    spec = load_world(path, seed=args.seed, frames=args.frames, dt=args.dt, backend=args.backend)
    engine = Engine(spec.world, spec.initial, spec.generators, spec.backend, dt=spec.dt, seed=spec.seed,
                    max_symbols=args.max_symbols)
    recorder = Recorder(args.record, engine, world_file=spec.path, world_data=spec.data) if args.record else None
    start = time.perf_counter()
    try:
        reason = engine.run(spec.frames, progress=None if args.progress is None else args.progress)
    finally:
        if recorder:
            recorder.close()
        # A backend that writes files (a video) finishes them in its finish(), if it has one
        # (close() is δ, the end of a transformation's scope).
        finish = getattr(spec.backend, "finish", None)
        if callable(finish):
            finish()
    wall = time.perf_counter() - start
    w = engine.string
    if not args.quiet:
        print(f"vwg run {spec.path} — {spec.name}")
        why = {"empty": "the world became empty", "stopped": "stopped", "done": "done"}.get(reason, "frame limit")
        rows = [
            ("frames", f"{engine.frame} ({why})"),
            ("simulated time", f"{engine.time:.3f} s (dt {spec.dt} s)"),
            ("seed", str(spec.seed)),
            ("final string", f"{len(w)} symbols, {w.actor_count} actors"),
            ("", _clip(str(w)) or "ε"),
            ("wall time", f"{wall:.3f} s ({engine.frame / wall:.0f} frames/s)" if wall > 0 else "0 s"),
        ]
        if isinstance(spec.backend, _core.TraceBackend):
            rows.append(("backend calls", f"{len(spec.backend.calls)} (trace)"))
        if recorder:
            rows.append(("record", f"{args.record} ({recorder.frames} frames)"))
        _print_summary(rows)
    return 0


def _cmd_replay(args: argparse.Namespace) -> int:
    from .record import read_record, replay
    from .registry import backends
    from .worldfile import load_world

    record = read_record(args.record)  # read once: decoding a long record is most of a replay's reading
    header = record.header
    robot = (header.get("world") or {}).get("robot_world")
    if robot:
        from .casestudy import case_study_world, make_decider
        from .robotworld import load_robot_world

        path = _world_file(args.world, "replay", expected="robot")[0] if args.world else robot
        world = case_study_world(load_robot_world(path), make_decider(header["world"]["planner"]))
    else:
        world = load_world(_world_file(args.world, "replay", expected="generic")[0]).world if args.world else None
    backend = backends.create(args.backend, world=world) if args.backend else None
    start = time.perf_counter()
    engine = replay(args.record, world=world, backend=backend, record=record)
    wall = time.perf_counter() - start
    print(f"vwg replay {args.record}: {len(record.frames)} frames replayed, every string as recorded "
          f"({wall:.1f} s)")
    print(f"  final string: {_clip(str(engine.string)) or 'ε'}")
    return 0


def _cmd_check(args: argparse.Namespace) -> int:
    path, kind = _world_file(args.world, "check")
    if kind == "robot":
        return _check_robot(path, args.world)
    from .worldfile import load_world

    spec = load_world(path)
    a = spec.world.alphabet
    print(f"{args.world}: ok, a generic world ({spec.name})")
    _print_summary([
        ("primitives", ", ".join(a.primitives) or "-"),
        ("transformations", ", ".join(a.transformations) or "-"),
        ("actors", ", ".join(f"{n} {a.responds_to(n)}" for n in a.actors) or "-"),
        ("events", ", ".join(a.event_types) or "-"),
        ("visual events", ", ".join(a.visual_event_types) or "-"),
        ("generators", ", ".join(g.name for g in spec.generators) or "-"),
        ("initial string", _clip(str(spec.initial)) or "ε"),
        ("frames", f"{spec.frames} (dt {spec.dt} s, seed {spec.seed})"),
    ])
    return 0


def _check_robot(path: Path, arg: Path) -> int:
    from .robotworld import load_robot_world

    w = load_robot_world(path)
    g = w.grid
    print(f"{arg}: ok, a robot world ({w.name})")
    if w.description:
        print(f"  {w.description}")
    rows = [
        ("map", f"{w.map_path.name}: {g.width}×{g.height} cells of {g.resolution:g} m "
                f"({g.width_m:g} × {g.height_m:g} m), walls {w.wall_height:g} m high"),
        ("rooms", f"{len(w.rooms)}"),
    ]
    for name, room in w.rooms.items():
        rows.append((f"  {name}", f"marker {room.marker} at ({room.at[0]:g}, {room.at[1]:g}), "
                                  f"goal ({room.goal[0]:.2f}, {room.goal[1]:.2f})"))
    rows.append(("robots", f"{len(w.robots)}"))
    for r in w.robots:
        rows.append((f"  robot {r.id}", f"start ({r.start[0]:g}, {r.start[1]:g}, {r.start[2]:.3g} rad), radius "
                                        f"{r.radius:g} m, {r.max_speed:g} m/s, sensors: {', '.join(r.sensors)}"))
    rows += [
        ("laser", f"{w.laser.beams} beams over {math.degrees(w.laser.fov):.0f}°, {w.laser.max_range:g} m, "
                  f"noise {w.laser.noise:g} m"),
        ("kinect", f"{w.kinect.width}×{w.kinect.height}, {math.degrees(w.kinect.hfov):.0f}°, "
                   f"{w.kinect.min_range:g}-{w.kinect.max_range:g} m"),
        ("camera", f"{w.camera.width}×{w.camera.height}, {math.degrees(w.camera.hfov):.0f}°"),
        ("noise", f"odometry {w.noise.odometry:g}, motors {w.noise.motors:g}"),
        ("orders", "; ".join(f"{o.time:g} s: robot {o.robot} to {o.room}" for o in w.orders) or "none"),
        ("frames", f"{w.frames} (dt {w.dt:g} s, seed {w.seed})"),
    ]
    _print_summary(rows)
    return 0


def _cmd_overview(args: argparse.Namespace) -> int:
    from .overview import render_world_overview
    from .robotworld import load_robot_world

    path, _ = _world_file(args.world, "overview", expected="robot")
    world = load_robot_world(path)
    image = render_world_overview(world, width=args.width, height=args.height)
    out = args.output or Path(f"{world.name}_3d.png")
    _core.write_image(str(out), image)
    print(f"{out}: {world.name} in 3D ({image.shape[1]}×{image.shape[0]})")
    return 0


def _cmd_worlds(args: argparse.Namespace) -> int:
    from .robotworld import load_robot_world
    from .worlds import shipped_worlds

    print(f"{len(shipped_worlds())} shipped worlds; run one with `vwg run NAME`, describe it with `vwg check NAME`:")
    rows = []
    for name, path in shipped_worlds().items():
        w = load_robot_world(path)
        rows.append((name, f"{len(w.robots)} robot{'s' if len(w.robots) > 1 else ''}, {len(w.rooms)} rooms, "
                           f"{w.grid.width_m:g} × {w.grid.height_m:g} m. {w.description}"))
    _print_summary(rows)
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="vwg", description="vwg, the Virtual Worlds Generator: run worlds written as strings of a grammar.")
    parser.add_argument("--version", action="version", version=f"vwg {_core.__version__}")
    parser.add_argument("--verbose", "-v", action="count", default=0,
                        help="print vwg's and its libraries' messages (-v: warnings and info, -vv: debug)")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    run = sub.add_parser("run", help="run a world file", description="Run a world file and print a summary.")
    run.add_argument("world", type=Path, help="a world file (YAML), or the name of a shipped world (vwg worlds)")
    run.add_argument("--frames", type=int, help="number of frames (default: the file's, else 100)")
    run.add_argument("--seed", type=int, help="random seed (default: the file's, else 0)")
    run.add_argument("--dt", type=float, help="seconds per frame (default: the file's, else 0.1)")
    run.add_argument("--backend", help="backend by name, instead of the file's (trace, null, ...)")
    run.add_argument("--max-symbols", type=int, default=10_000_000,
                     help="fail if the string grows past this many symbols (default 10 000 000; 0: no limit)")
    robot = run.add_argument_group("robot worlds (the case study: world files that name a map)")
    robot.add_argument("--platform", help="where the robots run (default: the world file's platform:, else sim, "
                                           "the Box2D simulator)")
    robot.add_argument("--planner",
                       help="the decision inside eDecide: random, astar, dstar, rrtconnect, rrtstar, prm "
                            "(default astar)")
    robot.add_argument("--goal", action="append", metavar="[ROBOT:]ROOM",
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
    robot.add_argument("--allow-unreached", action="store_true",
                       help=f"exit 0 even when a robot did not reach its room (otherwise exit {EXIT_UNREACHED})")
    run.add_argument("--record", type=Path, help="write every frame to this JSON Lines file")
    run.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                     help="show a progress bar (default: on a terminal)")
    run.add_argument("--quiet", "-q", action="store_true", help="print nothing on success")
    run.set_defaults(func=_cmd_run)

    rep = sub.add_parser("replay", help="replay a record and check it",
                         description="Run a record's events again and check every string against it.")
    rep.add_argument("record", type=Path, help="a file written by `vwg run --record`")
    rep.add_argument("--world", type=Path, help="the world file (default: the one the record names)")
    rep.add_argument("--backend", help="show the replay on this backend (e.g. trace)")
    rep.set_defaults(func=_cmd_replay)

    ovw = sub.add_parser("overview", help="draw a robot world's map in 3D (the paper's Fig. 5)",
                         description="Draw a robot world in 3D: walls extruded, markers, robots at their starts.")
    ovw.add_argument("world", type=Path, help="a robot world file (one that names a map), or a shipped world's name")
    ovw.add_argument("-o", "--output", type=Path, help="the PNG to write (default: NAME_3d.png)")
    ovw.add_argument("--width", type=int, default=1000)
    ovw.add_argument("--height", type=int, default=700)
    ovw.set_defaults(func=_cmd_overview)

    chk = sub.add_parser("check", help="load a world file, check it and report what it declares",
                         description="Check a robot world (map, rooms, robots, sensors, orders) or a generic world "
                                     "(alphabet, generators, initial string) and describe it.")
    chk.add_argument("world", type=Path, help="a world file, or the name of a shipped world")
    chk.set_defaults(func=_cmd_check)

    wld = sub.add_parser("worlds", help="list the worlds that ship with vwg",
                         description="List the shipped robot worlds; run one with `vwg run NAME`.")
    wld.set_defaults(func=_cmd_worlds)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.verbose:
        import logging

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
