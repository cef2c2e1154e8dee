"""Speed of the robot camera: render a 640×480 first-person image of the office and detect its
AprilTags (tag36h11, quad_decimate 2), one core. Rendering and detection are also timed alone.

    python benchmarks/bench_camera.py [--quick]  prints a table, writes benchmarks/results/<machine>/bench_camera.json
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path

from machine import write_results

import vwg
from vwg import _core

ROOT = Path(__file__).resolve().parents[1]
RESULTS = Path(__file__).resolve().parent / "results" / "bench_camera.json"


def poses_in_front_of_markers(world, n):
    """Poses 1 to 3 m in front of the rooms' markers, facing them (so there is something to find)."""
    rooms = list(world.rooms.values())
    out = []
    for k in range(n):
        room = rooms[k % len(rooms)]
        d = 1.0 + 2.0 * ((k * 7) % 10) / 10
        nx, ny = math.cos(room.facing), math.sin(room.facing)
        x, y = room.at[0] + d * nx, room.at[1] + d * ny
        if world.grid.contains(x, y) and not world.grid.blocked()[world.grid.world_to_cell(x, y)]:
            out.append((x, y, room.facing + math.pi + 0.2 * math.sin(k)))
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    world = vwg.robot.load_robot_world(ROOT / "maps" / "office.yaml")
    camera = _core.CameraRenderer(world.grid, world.rooms, vwg.robot.CameraSpec(wall_height=world.wall_height))
    poses = poses_in_front_of_markers(world, 60 if args.quick else 300)
    images = [camera.render(p, grey=True) for p in poses[:20]]  # warm up
    t0 = time.perf_counter()
    images = [camera.render(p, grey=True) for p in poses]
    render = time.perf_counter() - t0
    t0 = time.perf_counter()
    found = [vwg.perception.detect_apriltags(im) for im in images]
    detect = time.perf_counter() - t0
    t0 = time.perf_counter()
    for p in poses:
        vwg.perception.detect_apriltags(camera.render(p, grey=True))
    both = time.perf_counter() - t0
    n = len(poses)
    seen = sum(1 for f in found if f) / n
    results = {
        "render_detect_fps": n / both,
        "render_fps": n / render,
        "detect_fps": n / detect,
        "frames": n,
        "images_with_a_tag": seen,
        "width": 640,
        "height": 480,
        "quick": args.quick,
        "machine": {"python": sys.version.split()[0], "platform": platform.platform()},
        "vwg": vwg.__version__,
    }
    print(f"  640×480 grey, office markers from 1-3 m ({n} poses, {seen:.0%} with a tag found), one core")
    print(f"  {'render':<16} {results['render_fps']:8.0f} frames/s")
    print(f"  {'detect':<16} {results['detect_fps']:8.0f} frames/s")
    print(f"  {'render + detect':<16} {results['render_detect_fps']:8.0f} frames/s")
    write_results(RESULTS, **results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
