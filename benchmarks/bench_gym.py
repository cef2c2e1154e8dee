"""Steps per second of vwg/Navigate-v0: one environment, several in one process (vwg.gym.make_vec,
Gymnasium's SyncVectorEnv), and the same number with a process each (Gymnasium's AsyncVectorEnv, the
usual way to run many simulators), with random actions, as ratios to the single environment.

    python benchmarks/bench_gym.py [--quick]     # writes benchmarks/results/<machine>/bench_gym.json

A step is one move of the robot (about 16 frames of 0.1 s: turn, drive 0.5 m at most), with a
36-beam laser on the office map.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import gymnasium

sys.path.insert(0, str(Path(__file__).resolve().parent))
from machine import write_results

import vwg.gym

RESULTS = Path(__file__).resolve().parent / "results" / "bench_gym.json"
WORLD = "office"


def rate(envs: gymnasium.Env | gymnasium.vector.VectorEnv, steps: int, n: int) -> tuple[float, float]:
    """(environment steps per second, frames per second) over `steps` calls of step()."""
    envs.reset(seed=0)
    envs.action_space.seed(0)
    envs.step(envs.action_space.sample())  # warm up
    frames0 = total_frames(envs)
    t0 = time.perf_counter()
    for _ in range(steps):
        _, _, term, trunc, _ = envs.step(envs.action_space.sample())
        if n == 1 and (term or trunc):
            envs.reset()
    wall = time.perf_counter() - t0
    return steps * n / wall, (total_frames(envs) - frames0) / wall if frames0 is not None else float("nan")


def total_frames(envs: object) -> int | None:
    """Frames run so far by the environments in this process (None for other processes')."""
    if isinstance(envs, gymnasium.vector.SyncVectorEnv):
        return sum(e.unwrapped.nav.frames_run for e in envs.envs)
    if isinstance(envs, gymnasium.Env):
        return envs.unwrapped.nav.frames_run
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    steps = 100 if args.quick else 500
    rows = []
    single = gymnasium.make(vwg.gym.ENV_ID, world=WORLD)
    base, base_frames = rate(single, steps, 1)
    single.close()
    rows.append({"form": "single", "envs": 1, "steps_per_s": base, "frames_per_s": base_frames, "ratio": 1.0})
    for n in (2, 8):
        sync = vwg.gym.make_vec(n, world=WORLD)
        r, f = rate(sync, steps // n * 2, n)
        sync.close()
        rows.append({"form": "sync (vwg.gym.make_vec)", "envs": n, "steps_per_s": r, "frames_per_s": f,
                     "ratio": r / base})
    n = 2
    spawned = gymnasium.make_vec(vwg.gym.ENV_ID, num_envs=n, vectorization_mode="async", world=WORLD,
                                 vector_kwargs={"context": "spawn"})
    r, _ = rate(spawned, steps // n * 2, n)
    spawned.close()
    rows.append({"form": "async (a process each)", "envs": n, "steps_per_s": r, "frames_per_s": float("nan"),
                 "ratio": r / base})
    print(f"vwg/Navigate-v0 on {WORLD}, random actions ({'quick' if args.quick else 'full'} run)")
    print(f"{'form':<26}{'envs':>5}{'steps/s':>10}{'frames/s':>10}{'× single':>10}")
    for row in rows:
        print(f"{row['form']:<26}{row['envs']:>5}{row['steps_per_s']:>10.0f}{row['frames_per_s']:>10.0f}"
              f"{row['ratio']:>10.2f}")
    write_results(RESULTS, quick=args.quick, world=WORLD, rows=rows)


if __name__ == "__main__":
    main()
