"""Saved states: the time to save and to restore a run's whole state and its size on disk, against the
time to run to that frame, and the time of `vwg replay RECORD --from FRAME` before and after states kept
beside the record.

1. A crowd: the shipped warehouse with 100 robots at seeded free places 0.6 m apart (bench_frame.crowd),
   each with the world file's laser alone, each ordered to a room (the rooms in turn), A*, 2 threads —
   written as a world file of its own in a temporary folder (a restored run is made again from its world
   file). For N frames (50, 150, 500): the run to frame N (`vwg.start(...).execute()`, its first plans
   included), `run.save_state(FILE)` and the file's size, then the reference in the same process: the 10
   frames after N; then the restore, `vwg.saved_run.resume(FILE)` (the run made from its world file and
   set to the state; checked to be at frame N with the saved string). Each as a ratio: restore / (the 10
   frames after N), the aim being under 1, and restore / (the run to N).
   The simulator's state is a journal of every call made to it, run again on restore (Box2D 2.4 keeps its
   broad phase and contact order private): a restore grows with N, and the table shows it.
2. `vwg replay RECORD --from 2000` of the shipped warehouse world (3 robots), recorded by
   `vwg run warehouse --frames 2100 --record R --snapshot-every 500`: timed (a) without the states
   folder R.states/ (moved away: frames 0 to 1999 run again) and (b) with it (from the latest state kept
   at or before frame 2000: frame 2000's own, so no recorded frame runs again; --quick: frame 400's, then
   frames 400 to 499 as recorded), each a `python -m vwg.cli` subprocess, both then live to the record's
   last frame; the ratio after / before.

    python benchmarks/bench_state.py [--quick]   (--quick: N in 50, 150; a 600-frame record, --from 500,
                                                 states every 200)

Prints a table and writes benchmarks/results/<machine>/bench_state.json: rows (one per N) with frames,
run_to_n_s, save_s, size_mb, ten_frames_s, restore_s, restore_over_ten_frames, restore_over_run_to_n;
and replay with record_frames, from_frame, snapshot_every, state_frame, before_s, after_s, after_over_before.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import yaml
from machine import write_results
from tqdm import tqdm

import vwg
from vwg.saved_run import resume

ROOT = Path(__file__).resolve().parents[1]
RESULTS = Path(__file__).resolve().parent / "results" / "bench_state.json"
ROBOTS, THREADS, AFTER = 100, 2, 10  # the crowd, its threads, the frames timed after N (the reference)


def crowd_world_file(folder: Path) -> Path:
    """The warehouse world file with bench_frame.crowd's 100 robots (laser only) and an order each to a
    room (robot k to room k mod the rooms), its map named by its absolute path: written into `folder`."""
    from bench_frame import crowd

    data = yaml.safe_load((ROOT / "maps" / "warehouse.yaml").read_text())
    rooms = list(data["rooms"])
    data["map"] = str(ROOT / "maps" / "warehouse" / "map.yaml")
    robots = crowd(ROBOTS).robots
    if len(robots) < ROBOTS:
        raise SystemExit(f"the warehouse holds {len(robots)} robots 0.6 m apart, not {ROBOTS}")
    data["robots"] = [{"id": r.id, "start": [float(v) for v in r.start], "sensors": ["laser"]} for r in robots]
    data["orders"] = [{"time": 0.0, "robot": r.id, "room": rooms[k % len(rooms)]} for k, r in enumerate(robots)]
    path = folder / "crowd.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def state_row(world_file: Path, frames: int, folder: Path) -> dict[str, Any]:
    """Run the crowd to `frames`, save its state, run the 10 frames after as the reference, restore it."""
    state = folder / f"at{frames}.vwgstate"
    options = vwg.RunOptions(frames=frames, threads=THREADS, allow_unreached=True)
    with vwg.start(vwg.load(str(world_file)), options) as run:
        t0 = time.perf_counter()
        run.execute()
        run_to_n = time.perf_counter() - t0
        if run.engine.frame != frames:
            raise SystemExit(f"the crowd's run stopped at frame {run.engine.frame}, not {frames}")
        saved_string = str(run.engine.string)
        t0 = time.perf_counter()
        run.save_state(state)
        save = time.perf_counter() - t0
        run.case.frames = AFTER
        t0 = time.perf_counter()
        run.execute()
        ten = time.perf_counter() - t0
        if run.engine.frame != frames + AFTER:
            raise SystemExit(f"the {AFTER} frames after {frames} stopped at frame {run.engine.frame}")
    t0 = time.perf_counter()
    restored = resume(state, vwg.RunOptions(frames=0, threads=THREADS, allow_unreached=True))
    restore = time.perf_counter() - t0
    with restored:
        if restored.engine.frame != frames or str(restored.engine.string) != saved_string:
            raise SystemExit(f"the state restored is not the run's at frame {frames}")
    return {"frames": frames, "run_to_n_s": run_to_n, "save_s": save, "size_mb": state.stat().st_size / 1e6,
            "ten_frames_s": ten, "restore_s": restore, "restore_over_ten_frames": restore / ten,
            "restore_over_run_to_n": restore / run_to_n}


def vwg_cli(*args: str, cwd: Path) -> tuple[float, subprocess.CompletedProcess[str]]:
    """`python -m vwg.cli ARGS` in `cwd`, its wall time and its outcome (exit 0, or the benchmark stops)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (str(ROOT / "python"),
                                                                   os.environ.get("PYTHONPATH")) if p)}
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "vwg.cli", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=3600)
    wall = time.perf_counter() - t0
    if done.returncode != 0:
        raise SystemExit(f"vwg {' '.join(args)} exited {done.returncode}:\n{done.stderr[-2000:]}")
    return wall, done


def replay_row(folder: Path, frames: int, start: int, every: int, bar: tqdm) -> dict[str, Any]:
    """Record the shipped warehouse with states every `every` frames; time replay --from `start` without the
    states (from frame 0) and with them (from the latest state at or before `start`)."""
    record = folder / "warehouse.jsonl"
    vwg_cli("run", "warehouse", "--frames", str(frames), "--record", str(record), "--snapshot-every", str(every),
            "--allow-unreached", "--threads", str(THREADS), "--quiet", cwd=folder)
    bar.update()
    states = record.with_name(record.name + ".states")
    kept = start // every * every
    if not (states / f"{kept:012d}.vwgstate").is_file():
        raise SystemExit(f"{states} holds no state of frame {kept}")
    away = folder / "states.away"
    states.rename(away)
    before, _ = vwg_cli("replay", str(record), "--from", str(start), "--allow-unreached", cwd=folder)
    bar.update()
    away.rename(states)
    after, done = vwg_cli("replay", str(record), "--from", str(start), "--allow-unreached", cwd=folder)
    bar.update()
    if f"the state kept at frame {kept}" not in done.stdout:
        raise SystemExit(f"vwg replay --from {start} with the states did not start from frame {kept}:\n{done.stdout}")
    return {"record_frames": frames, "from_frame": start, "snapshot_every": every, "state_frame": kept,
            "before_s": before, "after_s": after, "after_over_before": after / before}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N in 50, 150; a 600-frame record, --from 500")
    args = parser.parse_args()
    sizes = (50, 150) if args.quick else (50, 150, 500)
    frames, start, every = (600, 500, 200) if args.quick else (2100, 2000, 500)

    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_state.") as tmp:
        folder = Path(tmp)
        world_file = crowd_world_file(folder)
        with tqdm(total=len(sizes) + 3, desc="bench_state", unit="step") as bar:
            for n in sizes:
                rows.append(state_row(world_file, n, folder))
                (folder / f"at{n}.vwgstate").unlink()
                bar.update()
            replay = replay_row(folder, frames, start, every, bar)
        shutil.rmtree(folder, ignore_errors=True)

    print(f"{ROBOTS} robots on the warehouse, A*, {THREADS} threads; the reference: the {AFTER} frames after N")
    print(f"{'N':>5} {'run to N s':>10} {'save s':>7} {'size MB':>8} {f'{AFTER} frames s':>11} {'restore s':>9} "
          f"{f'restore/{AFTER} frames':>17} {'restore/run to N':>16}")
    for r in rows:
        print(f"{r['frames']:>5} {r['run_to_n_s']:>10.2f} {r['save_s']:>7.3f} {r['size_mb']:>8.2f} "
              f"{r['ten_frames_s']:>11.3f} {r['restore_s']:>9.3f} {r['restore_over_ten_frames']:>17.2f} "
              f"{r['restore_over_run_to_n']:>16.3f}")
    print(f"vwg replay (warehouse, 3 robots, {replay['record_frames']} frames) --from {replay['from_frame']}: "
          f"before {replay['before_s']:.2f} s (from frame 0), after {replay['after_s']:.2f} s (from the state "
          f"kept at frame {replay['state_frame']}): {replay['after_over_before']:.2f}× the time")
    write_results(RESULTS, quick=args.quick, robots=ROBOTS, threads=THREADS, frames_after=AFTER, rows=rows,
                  replay=replay)


if __name__ == "__main__":
    main()
