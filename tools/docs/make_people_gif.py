"""docs/images/office_people.gif: the office's two robots, avoiding, sent past each other along the corridor while six
people wander between the rooms (seed 3). Run from the repository: python tools/docs/make_people_gif.py"""

from __future__ import annotations

import dataclasses
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

import vwg
from vwg.robot.case_study import CaseStudy
from vwg.trial import add_people

OUT = Path(__file__).resolve().parents[2] / "docs" / "images" / "office_people.gif"
FRAMES, EVERY, WIDTH = 420, 3, 480


def main() -> None:
    office = vwg.robot.load_robot_world("office")
    world = add_people(dataclasses.replace(office, orders=[]), 6, np.random.default_rng(3))
    with tempfile.TemporaryDirectory() as folder:
        with CaseStudy(world, "astar", goals={1: "lounge", 2: "office"}, seed=3, avoidance="orca",
                       images=folder, view_width=WIDTH) as run:
            run.run(FRAMES)
        shots = sorted(Path(folder).glob("*.png"))[::EVERY]
        images = [Image.open(p).convert("P", palette=Image.Palette.ADAPTIVE, colors=64) for p in shots]
        images[0].save(OUT, save_all=True, append_images=images[1:], duration=100 * EVERY, loop=0, optimize=True)
    print(f"{OUT}: {len(images)} frames, {OUT.stat().st_size / 1e6:.1f} MB", file=sys.stderr)


if __name__ == "__main__":
    main()
