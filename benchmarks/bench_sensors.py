"""Speed of the simulated sensors and physics.

    laser   full 360-beam scans from random free poses on 1000×1000-cell maps (0.05 m cells, 10 m
            range), one core: the fast scan, and the plain cell walk (DDA) on the same poses in the
            same run (ranges checked equal); and each SIMD code the CPU has on the same poses
            (VWG_RAYCAST_SIMD), against each other, to check that the code a raycaster runs by
            default is the faster on this CPU (AVX2 on AMD's Zen 4, which has AVX-512 too)
    box2d   one physics step (Box2D, 0.01 s) with 1 to 1,000 robots driving about and colliding

    python benchmarks/bench_sensors.py [--quick]  prints tables, writes benchmarks/results/<machine>/bench_sensors.json
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np
from machine import write_results

import vwg
from vwg import _core

ROOT = Path(__file__).resolve().parents[1]
RESULTS = Path(__file__).resolve().parent / "results" / "bench_sensors.json"


def office_1000() -> SimpleNamespace:
    """The shipped office floor tiled 2×3 and cut to 1000×1000 cells (50 × 50 m)."""
    office = vwg.io.maps.load_map(ROOT / "maps" / "office" / "map.yaml").data
    tiled = np.tile(office, (3, 2))[:1000, :1000]
    return SimpleNamespace(data=np.ascontiguousarray(tiled), resolution=0.05, origin=(0.0, 0.0, 0.0))


def willow_1000() -> SimpleNamespace:
    """The real Willow Garage map cut to 1000×1000 cells."""
    willow = vwg.io.maps.load_map(ROOT / "maps" / "willow" / "map.yaml").data
    return SimpleNamespace(data=np.ascontiguousarray(willow[100:1100, 66:1066]), resolution=0.05,
                           origin=(0.0, 0.0, 0.0))


def free_poses(grid: SimpleNamespace, n: int, rng: np.random.Generator) -> np.ndarray:
    rows, cols = np.nonzero(grid.data == 0)
    pick = rng.integers(len(rows), size=n)
    x = (cols[pick] + rng.random(n)) * grid.resolution
    y = (rows[pick] + rng.random(n)) * grid.resolution
    return np.column_stack([x, y, rng.uniform(-math.pi, math.pi, n)])


def best(repeats: int, fn, *args, **kwargs) -> float:
    """The shortest of `repeats` timings of fn(*args, **kwargs)."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn(*args, **kwargs)
        times.append(time.perf_counter() - t0)
    return min(times)


def bench_laser(quick: bool) -> dict:
    angles = np.linspace(-math.pi, math.pi, 360, endpoint=False)
    rng = np.random.default_rng(1)
    out = {}
    print(f"  {'map':<10} {'fast scan':>14} {'DDA':>12} {'ratio':>7}  ranges equal")
    for name, grid in (("office", office_1000()), ("willow", willow_1000())):
        caster = _core.GridRaycaster(grid)
        poses = free_poses(grid, 500 if quick else 4000, rng)
        dda_poses = poses[: 50 if quick else 300]
        t_fast = best(3, caster.scans, poses, angles, 10.0)
        t_dda = best(2, caster.scans, dda_poses, angles, 10.0, method="dda")
        fast_rays = poses.shape[0] * 360 / t_fast
        dda_rays = dda_poses.shape[0] * 360 / t_dda
        equal = bool(np.array_equal(caster.scans(dda_poses, angles, 10.0),
                                    caster.scans(dda_poses, angles, 10.0, method="dda")))
        out[name] = {"rays_per_s": fast_rays, "dda_rays_per_s": dda_rays, "ratio": fast_rays / dda_rays,
                     "poses": int(poses.shape[0]), "equal_to_dda": equal, "simd": caster.simd,
                     "codes": each_code(grid, poses, angles)}
        ratio = fast_rays / dda_rays
        print(f"  {name:<10} {fast_rays / 1e6:10.1f} M/s {dda_rays / 1e6:8.2f} M/s {ratio:6.1f}x  {equal}"
              f"  ({caster.simd})")
    print("  each SIMD code this CPU has, on the same poses (M rays/s, CPU time, codes alternating, best of 3): "
          + "; ".join(f"{name} " + ", ".join(f"{code} {rate / 1e6:.1f}" for code, rate in v["codes"].items())
                      for name, v in out.items()))
    return out


def each_code(grid: SimpleNamespace, poses: np.ndarray, angles: np.ndarray) -> dict[str, float]:
    """Rays/s of each scan code the CPU has (VWG_RAYCAST_SIMD chooses it when a raycaster is made),
    in CPU time, the codes taking turns so that a slow minute hits them alike."""
    casters = {}
    before = os.environ.get("VWG_RAYCAST_SIMD")
    for code in ("avx512", "avx2", "none"):
        os.environ["VWG_RAYCAST_SIMD"] = code
        try:
            caster = _core.GridRaycaster(grid)
        finally:
            if before is None:
                del os.environ["VWG_RAYCAST_SIMD"]
            else:
                os.environ["VWG_RAYCAST_SIMD"] = before
        if caster.simd == code:
            casters[code] = caster
    best_s = dict.fromkeys(casters, math.inf)
    for _ in range(3):
        for code, caster in casters.items():
            c0 = time.process_time()
            caster.scans(poses, angles, 10.0)
            best_s[code] = min(best_s[code], time.process_time() - c0)
    return {code: poses.shape[0] * len(angles) / s for code, s in best_s.items()}


def bench_box2d(quick: bool) -> dict:
    counts = [1, 10, 100] if quick else [1, 10, 100, 1000]
    size = 52.0
    grid = SimpleNamespace(data=np.zeros((round(size / 0.05), round(size / 0.05)), np.int8), resolution=0.05,
                           origin=(0.0, 0.0, 0.0))
    rng = np.random.default_rng(2)
    out = {}
    print(f"\n  {'robots':>7} {'ms per step':>12} {'µs per robot-step':>18}")
    for n in counts:
        side = math.ceil(math.sqrt(n))
        robots = [vwg.robot.RobotSettings(id=i + 1, start=(1.0 + 1.6 * (i % side), 1.0 + 1.6 * (i // side),
                                                     float(rng.uniform(-3, 3)))) for i in range(n)]
        physics = _core.PhysicsWorld(grid, robots)
        for r in robots:
            physics.command(r.id, [("turn", float(rng.uniform(-3, 3))), ("drive", float(rng.uniform(1, 5)))])
        physics.advance(0.5)  # get them moving and touching
        steps = 100 if n < 1000 else 30
        t = best(3, physics.advance, steps * 0.01) / steps
        out[str(n)] = {"ms_per_step": t * 1e3, "us_per_robot_step": t * 1e6 / n, "wall_shapes": physics.wall_shapes}
        print(f"  {n:>7} {t * 1e3:12.3f} {t * 1e6 / n:18.2f}")
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer poses and robots (a smoke run)")
    args = parser.parse_args()
    print("Laser: 360 beams over 2π, 10 m range, 1000×1000 cells at 0.05 m, one core")
    laser = bench_laser(args.quick)
    print("\nBox2D: one 0.01 s step, robots driving and colliding on a 52 × 52 m floor")
    box2d = bench_box2d(args.quick)
    results = {
        "laser_rays_per_s": min(v["rays_per_s"] for v in laser.values()),
        "laser_dda_rays_per_s": min(v["dda_rays_per_s"] for v in laser.values()),
        "laser": laser,
        "box2d": box2d,
        "box2d_step_ms_1000_robots": box2d.get("1000", {}).get("ms_per_step"),
        "quick": args.quick,
        "machine": {"python": sys.version.split()[0], "platform": platform.platform()},
        "vwg": vwg.__version__,
    }
    print(f"\n  laser_rays_per_s (the slower map): {results['laser_rays_per_s'] / 1e6:.1f} M  (aim: >= 20 M)")
    write_results(RESULTS, **results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
