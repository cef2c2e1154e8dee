"""The ``vwg`` command: run a world file, replay a record, check a world file."""

from __future__ import annotations

import argparse
import sys
import time
import traceback
from collections.abc import Sequence
from pathlib import Path

from . import _core
from .errors import Error, FrameError

__all__ = ["main"]


def _clip(text: str, n: int = 200) -> str:
    return text if len(text) <= n else text[: n - 3] + "..."


def _print_summary(rows: list[tuple[str, str]]) -> None:
    width = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"  {k:<{width}}  {v}")


def _is_robot_world(path: Path) -> bool:
    """A robot world file (the case study) names a map; a generic world file declares an alphabet."""
    from .yamldoc import YamlDoc

    data = YamlDoc(path).data
    return isinstance(data, dict) and "map" in data


def _goals(values: list[str] | None, robots: list[int]) -> dict[int, str]:
    goals: dict[int, str] = {}
    for value in values or []:
        robot, _, room = value.rpartition(":")
        try:
            goals[int(robot) if robot else robots[0]] = room
        except ValueError:
            raise Error(f"--goal: expected ROOM or ROBOT:ROOM, got '{value}'") from None
    return goals


def _run_robot(args: argparse.Namespace) -> int:
    import json

    from .casestudy import CaseStudy
    from .record import Recorder
    from .robotworld import load_robot_world

    world = load_robot_world(args.world)
    video = args.video
    case = CaseStudy(world, args.planner, goals=_goals(args.goal, [r.id for r in world.robots]), seed=args.seed,
                     frames=args.frames, video=video, images=args.images, max_symbols=args.max_symbols,
                     world_orders=not args.no_world_orders)
    if args.stdin_orders:
        case.orders.read_lines(sys.stdin, lambda message: print(f"vwg: {message}", file=sys.stderr))
    recorder = None
    if args.record:
        recorder = Recorder(args.record, case.engine, world_file=world.path,
                            world_data={"robot_world": str(Path(world.path).resolve()), "planner": case.planner})
    try:
        summary = case.run(progress=args.progress)
    finally:
        if recorder:
            recorder.close()
    trajectory = args.trajectory or (Path(video).with_suffix(".png") if video else None)
    if trajectory:
        case.save_trajectory(trajectory)
        summary.outputs["trajectory"] = str(trajectory)
    if args.record:
        summary.outputs["record"] = str(args.record)
    if args.summary_json:
        Path(args.summary_json).parent.mkdir(parents=True, exist_ok=True)
        summary.outputs["summary"] = str(args.summary_json)
        Path(args.summary_json).write_text(json.dumps(summary.to_json(), indent=2) + "\n")
    if not args.quiet:
        print(f"vwg run {world.path} — {world.name}, planner {summary.planner}, seed {summary.seed}")
        rows = [
            ("reached", "yes" if summary.reached else "no"),
            ("frames", f"{summary.frames} ({summary.simulated_time_s:.1f} s simulated, "
                       f"{summary.wall_time_s:.1f} s wall)"),
            ("path length", f"{summary.path_length_m:.2f} m"),
            ("collisions", str(summary.collisions)),
            ("replans", str(summary.replans)),
        ]
        for r in summary.robots:
            state = "reached" if r.reached else f"{r.distance_to_goal_m:.2f} m away"
            where = f"{r.room}: {state}" if r.room else "no order"
            rows.append((f"robot {r.id}", f"{where}, {r.path_length_m:.2f} m, {r.collisions} collisions, "
                                           f"{r.replans} replans"))
        for name, path in summary.outputs.items():
            rows.append((name, path))
        _print_summary(rows)
    return 0


def _cmd_run(args: argparse.Namespace) -> int:
    from .engine import Engine
    from .record import Recorder
    from .worldfile import load_world

    if _is_robot_world(args.world):
        return _run_robot(args)
    robot_options = ("planner", "goal", "video", "images", "summary_json", "trajectory", "no_world_orders",
                     "stdin_orders")
    for option in robot_options:
        if getattr(args, option) not in (None, False, "astar"):
            raise Error(f"--{option.replace('_', '-')} is for robot worlds (world files that name a map)")
    spec = load_world(args.world, seed=args.seed, frames=args.frames, dt=args.dt, backend=args.backend)
    engine = Engine(spec.world, spec.initial, spec.generators, spec.backend, dt=spec.dt, seed=spec.seed,
                    max_symbols=args.max_symbols)
    recorder = Recorder(args.record, engine, world_file=spec.path, world_data=spec.data) if args.record else None
    start = time.perf_counter()
    try:
        reason = engine.run(spec.frames, progress=None if args.progress is None else args.progress)
    finally:
        if recorder:
            recorder.close()
    wall = time.perf_counter() - start
    w = engine.string
    if not args.quiet:
        print(f"vwg run {spec.path} — {spec.name}")
        why = {"empty": "the world became empty", "stopped": "stopped"}.get(reason, "frame limit")
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

    header = read_record(args.record).header
    robot = (header.get("world") or {}).get("robot_world")
    if robot:
        from .casestudy import case_study_world, make_decider
        from .robotworld import load_robot_world

        world = case_study_world(load_robot_world(args.world or robot), make_decider(header["world"]["planner"]))
    else:
        world = load_world(args.world).world if args.world else None
    backend = backends.create(args.backend, world=world) if args.backend else None
    start = time.perf_counter()
    engine = replay(args.record, world=world, backend=backend)
    wall = time.perf_counter() - start
    record = read_record(args.record)
    print(f"vwg replay {args.record}: {len(record.frames)} frames replayed, every string as recorded "
          f"({wall:.3f} s)")
    print(f"  final string: {_clip(str(engine.string)) or 'ε'}")
    return 0


def _cmd_check(args: argparse.Namespace) -> int:
    from .worldfile import load_world

    spec = load_world(args.world)
    a = spec.world.alphabet
    print(f"{spec.path}: ok")
    _print_summary([
        ("primitives", ", ".join(a.primitives) or "-"),
        ("transformations", ", ".join(a.transformations) or "-"),
        ("actors", ", ".join(f"{n} {a.responds_to(n)}" for n in a.actors) or "-"),
        ("events", ", ".join(a.event_types) or "-"),
        ("visual events", ", ".join(a.visual_event_types) or "-"),
        ("generators", ", ".join(g.name for g in spec.generators) or "-"),
        ("initial string", _clip(str(spec.initial)) or "ε"),
    ])
    return 0


def _cmd_overview(args: argparse.Namespace) -> int:
    from .robotworld import load_robot_world

    world = load_robot_world(args.world)
    image = _core.render_overview(world.grid, markers=world.rooms, robots=world.robots, wall_height=world.wall_height,
                                  width=args.width, height=args.height)
    out = args.output or Path(f"{world.name}_3d.png")
    _core.write_image(str(out), image)
    print(f"{out}: {world.name} in 3D ({image.shape[1]}×{image.shape[0]})")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="vwg", description="vwg, the Virtual Worlds Generator: run worlds written as strings of a grammar.")
    parser.add_argument("--version", action="version", version=f"vwg {_core.__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    run = sub.add_parser("run", help="run a world file", description="Run a world file and print a summary.")
    run.add_argument("world", type=Path, help="the world file (YAML)")
    run.add_argument("--frames", type=int, help="number of frames (default: the file's, else 100)")
    run.add_argument("--seed", type=int, help="random seed (default: the file's, else 0)")
    run.add_argument("--dt", type=float, help="seconds per frame (default: the file's, else 0.1)")
    run.add_argument("--backend", help="backend by name, instead of the file's (trace, null, ...)")
    run.add_argument("--max-symbols", type=int, default=10_000_000,
                     help="fail if the string grows past this many symbols (default 10 000 000; 0: no limit)")
    robot = run.add_argument_group("robot worlds (the case study: world files that name a map)")
    robot.add_argument("--planner", default="astar",
                       help="the decision inside eDecide: random, astar, dstar, rrtconnect, rrtstar, prm "
                            "(default astar)")
    robot.add_argument("--goal", action="append", metavar="[ROBOT:]ROOM",
                       help="send a robot (default the first) to a room at the start; repeatable")
    robot.add_argument("--no-world-orders", action="store_true",
                       help="ignore the orders scripted in the world file (only --goal and standard input)")
    robot.add_argument("--stdin-orders", action="store_true",
                       help="read orders while running from standard input: ROOM or ROBOT ROOM per line")
    robot.add_argument("--video", type=Path, help="write the run as a video (.mp4 H.264 or .gif)")
    robot.add_argument("--images", type=Path, help="write every frame as a PNG into this folder")
    robot.add_argument("--trajectory", type=Path, help="PNG of the trajectories (default: beside the video)")
    robot.add_argument("--summary-json", type=Path, help="write the summary as JSON")
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
    ovw.add_argument("world", type=Path, help="a robot world file (one that names a map)")
    ovw.add_argument("-o", "--output", type=Path, help="the PNG to write (default: NAME_3d.png)")
    ovw.add_argument("--width", type=int, default=1000)
    ovw.add_argument("--height", type=int, default=700)
    ovw.set_defaults(func=_cmd_overview)

    chk = sub.add_parser("check", help="load a world file and report what it declares")
    chk.add_argument("world", type=Path)
    chk.set_defaults(func=_cmd_check)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
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


if __name__ == "__main__":
    sys.exit(main())
