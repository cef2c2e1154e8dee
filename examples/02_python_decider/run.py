"""Run the office world with the robot's decision written in Python.

    python examples/02_python_decider/run.py [--video out/python_decider.mp4]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import vwg
from vwg.robot.case_study import CaseStudy

sys.path.insert(0, str(Path(__file__).resolve().parent))
from decider import PythonAStar

ROOT = Path(__file__).resolve().parents[2]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--video", type=Path)
    parser.add_argument("--room", default="kitchen")
    args = parser.parse_args()
    world = vwg.robot.load_robot_world(ROOT / "maps" / "office.yaml")
    run = CaseStudy(world, PythonAStar(), goals={1: args.room}, sensors=("laser",), world_orders=False,
                    video=args.video)
    summary = run.run(frames=1500)
    robot = summary.robots[0]
    print(f"python-astar: robot 1 to {robot.room}: {'reached' if robot.reached else 'not reached'} "
          f"in {summary.frames} frames, {robot.path_length_m:.2f} m")
    return 0 if robot.reached else 1


if __name__ == "__main__":
    sys.exit(main())
