"""Frame logs: the size of a record of the demo run (the office world, A* to the kitchen, no world
orders: `make demo`), what its parts take, and the time to write, read and replay it. The same
run's size in record format 1 (event texts, whole blobs) is worked out from the record for scale.
Then a crowd: the warehouse with 100 robots (A* to rooms, 2 threads, as bench_frame), the frame's
time recorded against the same frame unrecorded in the same process.

    python benchmarks/bench_record.py  prints a table, writes benchmarks/results/<machine>/bench_record.json
"""

from __future__ import annotations

import base64
import json
import platform
import sys
import tempfile
import time
import zlib
from collections import Counter
from pathlib import Path

import numpy as np

import vwg
from vwg.generic import replay
from vwg.io.record import Recorder, read_record
from vwg.robot.case_study import CaseStudy, case_study_world, make_decider
from vwg.robot.world_file import load_robot_world

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_frame import crowd, room_goals
from machine import write_results

ROOT = Path(__file__).resolve().parents[1]
WORLD = ROOT / "maps" / "office.yaml"
RESULTS = Path(__file__).resolve().parent / "results" / "bench_record.json"
CROWD = 100  # robots


def run(path: Path | None) -> tuple[float, int]:
    world = load_robot_world(WORLD)
    with CaseStudy(world, "astar", goals={1: "kitchen"}, world_orders=False) as case:
        recorder = None
        if path is not None:
            recorder = Recorder(path, case.engine, world_file=world.path,
                                world_data={"robot_world": str(Path(world.path).resolve()), "planner": case.planner})
        start = time.perf_counter()
        summary = case.run()
        if recorder is not None:
            recorder.close()
        return time.perf_counter() - start, summary.frames


def crowd_frame_ms(path: Path | None, robots: int = CROWD, frames: int = 20) -> float:
    """ms a frame of the warehouse crowd, recorded to `path` or not (after 5 frames to settle)."""
    world = crowd(robots)
    with CaseStudy(world, "astar", goals=room_goals(world), sensors=("laser",), threads=2) as case:
        case.engine.run(5)
        recorder = Recorder(path, case.engine) if path is not None else None
        start = time.perf_counter()
        case.engine.run(frames)
        elapsed = time.perf_counter() - start
        if recorder is not None:
            recorder.close()
    return elapsed / frames * 1000


def parts(path: Path) -> Counter:
    """Bytes of each part of the frame lines."""
    sizes: Counter = Counter()
    for text in path.read_text().splitlines()[1:-1]:
        line = json.loads(text)
        for item in line["events"]:
            if isinstance(item, str):
                sizes["events as text"] += len(json.dumps(item, ensure_ascii=False)) + 1
            else:
                sizes[f"run columns ({item['run']})"] += len(json.dumps(item, separators=(",", ":"))) + 1
        sizes["strings"] += len(json.dumps(line["string"], ensure_ascii=False))
        sizes["blobs"] += len(json.dumps(line.get("blobs", {}), separators=(",", ":")))
    return sizes


def format1_size(path: Path) -> int:
    """The bytes the same run takes in format 1: event texts, every new blob whole (zlib, base64)."""
    record = read_record(path)
    header = json.loads(path.read_text().splitlines()[0])

    def whole(name: str) -> dict:
        blob = record.blobs[name]
        packed = base64.b64encode(zlib.compress(np.asarray(blob).tobytes())).decode()
        return {"dtype": blob.dtype, "shape": list(blob.shape), "zlib_base64": packed}

    def dumps(obj: dict) -> int:
        return len(json.dumps(obj, ensure_ascii=False, allow_nan=False).encode()) + 1

    header = {**header, "vwg_record": 1, "blobs": {n: whole(n) for n in header["blobs"]}}
    size = dumps(header)
    for frame in record.frames:
        line = {"t": frame["t"], "time": frame["time"], "events": frame["events"], "string": frame["string"]}
        if frame.get("blobs"):
            line["blobs"] = {n: whole(n) for n in frame["blobs"]}
        size += dumps(line)
    return size + dumps(record.end or {})


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "office_kitchen.jsonl"
        bare, frames = run(None)
        wall, _ = run(path)
        start = time.perf_counter()
        read_record(path)
        read = time.perf_counter() - start
        world = case_study_world(load_robot_world(WORLD), make_decider("astar"))
        start = time.perf_counter()
        replay(path, world=world)
        replayed = time.perf_counter() - start
        size = path.stat().st_size
        old = format1_size(path)
        sizes = parts(path)
        # The crowd, twice each way, interleaved: this machine's speed drifts by 10-30 %.
        crowd_path = Path(tmp) / "crowd.jsonl"
        runs = [(crowd_frame_ms(None), crowd_frame_ms(crowd_path)) for _ in range(2)]
        plain_ms = min(plain for plain, _ in runs)
        recorded_ms = min(recorded for _, recorded in runs)
        crowd_bytes = crowd_path.stat().st_size
    results = {
        "frames": frames,
        "bytes": size,
        "bytes_per_frame": size / frames,
        "format1_bytes": old,
        "format1_bytes_per_frame": old / frames,
        "parts_bytes_per_frame": {k: v / frames for k, v in sorted(sizes.items())},
        "run_s": bare,
        "run_recorded_s": wall,
        "write_ms_per_frame": (wall - bare) / frames * 1000,
        "read_record_s": read,
        "replay_s": replayed,
        "crowd": {"robots": CROWD, "frames": 20, "ms_per_frame": plain_ms, "recorded_ms_per_frame": recorded_ms,
                  "recorded_over_plain": recorded_ms / plain_ms, "bytes_per_frame": crowd_bytes / 20},
        "machine": {"python": sys.version.split()[0], "platform": platform.platform(), "vwg": vwg.__version__},
    }
    print(f"office, A* to the kitchen: {frames} frames")
    print(f"  record           {size:>10,} bytes  {size / frames:8.0f} B/frame   (format 1: {old:,} bytes, "
          f"{old / frames:.0f} B/frame, {old / size:.1f}x)")
    for name, v in sorted(sizes.items(), key=lambda kv: -kv[1]):
        print(f"    {name:<26} {v / frames:8.0f} B/frame")
    print(f"  run              {bare:.2f} s; recorded {wall:.2f} s (+{results['write_ms_per_frame']:.1f} ms/frame)")
    print(f"  read_record      {read:.2f} s")
    print(f"  replay           {replayed:.2f} s")
    print(f"warehouse, {CROWD} robots, A*, 2 threads, 20 frames")
    print(f"  frame            {plain_ms:.1f} ms; recorded {recorded_ms:.1f} ms ({recorded_ms / plain_ms:.1f}x), "
          f"{crowd_bytes / 20 / 1e3:.0f} kB/frame")
    write_results(RESULTS, **results)


if __name__ == "__main__":
    main()
