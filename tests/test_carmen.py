"""A real robot's scans (the ACES building's CARMEN log) through the LaserScan path into ARobot's
grid, against a map built here from the same log by another method (issue 10, "Data")."""

from __future__ import annotations

import gzip
import math
from pathlib import Path

import numpy as np
import pytest

import vwg
from vwg import _core
from vwg.io.maps import OccupancyGrid
from vwg.model.actor import Sym
from vwg.robot.links.ros_messages import laser_scan, scan_message

LOG = Path(__file__).parent / "data" / "carmen" / "aces-corrected.log.gz"
MAX_RANGE = 40.0  # readings at or beyond this are no return
RESOLUTION = 0.1
SEEN = 101        # ARobot's value of an obstacle its sensors reported


def read_scans() -> list[tuple[tuple[float, float, float], list[float]]]:
    scans = []
    with gzip.open(LOG, "rt") as f:
        for line in f:
            words = line.split()
            if not words or words[0] != "FLASER":
                continue
            n = int(words[1])
            ranges = [float(w) for w in words[2:2 + n]]
            x, y, theta = (float(w) for w in words[2 + n:5 + n])
            scans.append(((x, y, theta), ranges))
    return scans


def beam_angles(n: int) -> np.ndarray:
    return np.linspace(-math.pi / 2, math.pi / 2, n)  # −90° to +90°, both included


class CarmenReplay(_core.Generator):
    """One scan a frame: the robot's corrected pose as its odometry, then the scan as a
    sensor_msgs/LaserScan message read by vwg.robot.links.ros_messages.laser_scan and turned into events
    by vwg._core.laser_events (what a rosbridge link and its laser do)."""

    def __init__(self, scans: list) -> None:
        super().__init__()
        self.scans = scans

    def generate(self, frame: _core.FrameInfo) -> list[_core.Event]:
        (x, y, theta), ranges = self.scans[frame.frame]
        angles = beam_angles(len(ranges))
        message = scan_message(frame.time, float(angles[0]), float(angles[1] - angles[0]),
                               [r if r < MAX_RANGE else math.inf for r in ranges], 0.0, MAX_RANGE)
        scan = laser_scan(message)
        dist, angle = _core.laser_events(scan.ranges, scan.angle_min, scan.angle_increment, scan.range_min,
                                         scan.range_max)
        return [_core.Event("eOdometry", 1, x=x, y=y, angle=theta, busy=False, commands=0),
                *(_core.Event("eLaser", 1, dist=d, angle=a)
                  for d, a in zip(dist.tolist(), angle.tolist(), strict=True))]


def frame_of(scans: list) -> OccupancyGrid:
    """A free map holding every hit, with a margin."""
    xs, ys = [], []
    for (x, y, theta), ranges in scans:
        for a, r in zip(beam_angles(len(ranges)), ranges, strict=True):
            if r < MAX_RANGE:
                xs.append(x + r * math.cos(theta + a))
                ys.append(y + r * math.sin(theta + a))
    x0, y0 = min(xs) - 2.0, min(ys) - 2.0
    width = math.ceil((max(xs) + 2.0 - x0) / RESOLUTION)
    height = math.ceil((max(ys) + 2.0 - y0) / RESOLUTION)
    return OccupancyGrid(np.zeros((height, width), np.int8), RESOLUTION, (x0, y0, 0.0))


def independent_map(scans: list, grid: OccupancyGrid) -> np.ndarray:
    """Occupied cells by counting, as occupancy-grid mapping does: a cell is occupied when beams
    ended in it more often than they passed through it (a supercover walk at half-cell steps)."""
    hits = np.zeros(grid.data.shape, np.int32)
    passes = np.zeros(grid.data.shape, np.int32)
    x0, y0, _ = grid.origin
    for (x, y, theta), ranges in scans:
        for a, r in zip(beam_angles(len(ranges)), ranges, strict=True):
            if r >= MAX_RANGE:
                continue
            ex, ey = x + r * math.cos(theta + a), y + r * math.sin(theta + a)
            end = (int((ey - y0) // RESOLUTION), int((ex - x0) // RESOLUTION))
            steps = max(1, int(r / (RESOLUTION / 2)))
            crossed = {(int((y + (ey - y) * k / steps - y0) // RESOLUTION), int((x + (ex - x) * k / steps - x0)
                                                                                // RESOLUTION)) for k in range(steps)}
            crossed.discard(end)
            for cell in crossed:
                passes[cell] += 1
            hits[end] += 1
    return (hits > 0) & (hits >= passes)


def near(cells: np.ndarray) -> np.ndarray:
    """The cells within one cell (8-neighbourhood) of a marked one."""
    padded = np.pad(cells, 1)
    out = np.zeros_like(cells)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            out |= padded[1 + dr:1 + dr + cells.shape[0], 1 + dc:1 + dc + cells.shape[1]]
    return out


@pytest.mark.slow
def test_a_real_robots_scans_build_the_map_an_independent_method_builds():
    scans = read_scans()
    assert len(scans) == 440
    grid = frame_of(scans)
    events = {name: {f: spec[1] for f, spec in fields.items()} for name, fields in _core.arobot_event_types().items()}
    alphabet = vwg.Alphabet(events=events, visual=["eExecute"], **vwg.robot.platforms.sim.MOTION_SYMBOLS)
    _core.add_arobot(alphabet, _core.create_decider("random"), grid, {}, radius=0.25)
    world = vwg.World(alphabet)
    (x, y, theta), _ = scans[0]
    row, col = grid.world_to_cell(x, y)
    initial = world.string(Sym("ARobot", id=1, grid=_core.robot_map(grid, False), row=row, column=col,
                               angle=theta, x=x, y=y))
    engine = vwg.Engine(world, initial, [CarmenReplay(scans)])
    engine.run(len(scans))
    robot = next(a for a in engine.string.actors() if a.name == "ARobot")
    built = np.asarray(robot["grid"]) == SEEN
    truth = independent_map(scans, grid)
    # Within one cell (0.1 m): the same wall seen from two poses, corrected by SLAM to a few
    # centimetres, falls in neighbouring cells.
    precision = float((built & near(truth)).sum() / built.sum())
    recall = float((truth & near(built)).sum() / truth.sum())
    print(f"\nACES log, {len(scans)} scans: ARobot marked {built.sum()} cells, the counting map {truth.sum()}; "
          f"precision {precision:.3f}, recall {recall:.3f}")
    # The two methods differ where beams graze walls (which cells a ray walks through, and how a
    # wall seen once and passed through later is kept); they agree on the building.
    assert built.sum() > 5000
    assert precision > 0.85 and recall > 0.85
