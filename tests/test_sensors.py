"""Range sensors: the laser and the Kinect-style depth camera, against distances worked out by hand,
and against each other (the paper's device-independence test)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import vwg
from conftest import ROOT
from vwg import _core
from vwg.robot import RobotSettings
from vwg.robot.platforms.sim import DepthCameraSpec, LaserSpec
from vwg.robot.sensors.laser import WallLaser


def box_map(cells=100, res=0.05):
    """A (cells·res)² m room whose border cells are walls: inner faces at res and (cells-1)·res."""
    data = np.zeros((cells, cells), np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = 100
    return SimpleNamespace(data=data, resolution=res, origin=(0.0, 0.0, 0.0))


def sim_world(grid, robots):
    alphabet = vwg.Alphabet(events=vwg.robot.platforms.sim.SIM_EVENTS, **vwg.robot.platforms.sim.MOTION_SYMBOLS)
    physics = _core.PhysicsWorld(grid, robots)
    scanner = _core.RangeScanner(_core.GridRaycaster(grid), physics)
    return alphabet, physics, scanner


def test_laser_ranges_and_events_by_hand():
    alphabet, _, scanner = sim_world(box_map(), [RobotSettings(id=7, start=(2.52, 2.51, 0.0))])
    laser = _core.LaserGenerator(scanner, 7, LaserSpec(beams=4, max_range=10.0, noise=0.0), alphabet)
    engine = vwg.Engine(vwg.World(alphabet), "Robot<7>", [laser])
    engine.step()
    # Beams at -π, -π/2, 0, π/2 from heading 0; faces at x = 0.05, 4.95 and y = 0.05, 4.95.
    expected = [2.52 - 0.05, 2.51 - 0.05, 4.95 - 2.52, 4.95 - 2.51]
    assert laser.angles.tolist() == pytest.approx([-math.pi, -math.pi / 2, 0.0, math.pi / 2])
    assert laser.ranges.tolist() == pytest.approx(expected, abs=1e-6)
    events = engine.last_events
    assert [e.target for e in events] == [7] * 4
    assert [e.dist for e in events] == pytest.approx(expected, abs=1e-6)
    assert [e.angle for e in events] == pytest.approx(laser.angles.tolist())
    kept = laser.ranges  # a copy: writing it does not reach the generator, the next frame not it
    kept[0] = -1.0
    engine.step()
    assert laser.ranges.tolist() == pytest.approx(expected, abs=1e-6)


def test_noisy_readings_are_float32_and_spread_as_the_noise_says():
    # The same scanner without noise gives the true ranges (checked by hand above); the noisy laser
    # must scatter around them with the spec's σ and report each reading as a float32, as a real
    # laser's LaserScan does.
    alphabet, _, scanner = sim_world(box_map(), [RobotSettings(id=7, start=(2.52, 2.51, 0.3))])
    sigma = 0.02
    clean = _core.LaserGenerator(scanner, 7, LaserSpec(beams=360, max_range=10.0, noise=0.0), alphabet)
    noisy = _core.LaserGenerator(scanner, 7, LaserSpec(beams=360, max_range=10.0, noise=sigma), alphabet)
    truth = vwg.Engine(vwg.World(alphabet), "Robot<7>", [clean])
    truth.step()
    true_dist = np.array([e.dist for e in truth.last_events])
    assert true_dist.size == 360  # a closed room: every beam hits
    engine = vwg.Engine(vwg.World(alphabet), "Robot<7>", [noisy], seed=5)
    residuals = []
    for _ in range(20):
        engine.step()
        dist = np.array([e.dist for e in engine.last_events])
        assert dist.size == 360
        assert np.array_equal(dist.astype(np.float32).astype(np.float64), dist)
        residuals.append(dist - true_dist)
    r = np.concatenate(residuals)
    assert abs(r.mean()) < 4 * sigma / math.sqrt(r.size)
    assert r.std() == pytest.approx(sigma, rel=0.05)


def test_clamped_noisy_readings_are_float32_within_the_range():
    # The left wall's face is 0.31 m away: with σ = 0.2 many readings clamp to min_range (0.3, which
    # float32 rounds up to 0.30000001) or to max_range. Each must still be a float32 in the range,
    # and a hit clamped at the top stays a hit: just below max_range, which reads as no return.
    alphabet, _, scanner = sim_world(box_map(), [RobotSettings(id=7, start=(0.36, 2.5, 0.0))])
    laser = _core.LaserGenerator(scanner, 7, LaserSpec(beams=360, min_range=0.3, max_range=0.625, noise=0.2), alphabet)
    engine = vwg.Engine(vwg.World(alphabet), "Robot<7>", [laser], seed=3)
    dist = []
    for _ in range(10):
        engine.step()
        dist += [e.dist for e in engine.last_events]
    d = np.array(dist)
    assert d.size > 100
    assert np.array_equal(d.astype(np.float32).astype(np.float64), d)
    below_max = float(np.nextafter(np.float32(0.625), np.float32(0)))
    assert d.min() >= 0.3 and d.max() == below_max
    assert (d < 0.3 + 1e-6).sum() > 10 and (d == below_max).sum() > 10  # both bounds were reached


def test_a_max_range_that_float32_rounds_down_reads_as_no_obstacle():
    # float32(3.3) is 3.2999999523: a beam that met nothing must not become an event at that range.
    alphabet, _, scanner = sim_world(box_map(200), [RobotSettings(id=1, start=(5.0, 5.0, 0.0))])
    for noise in (0.0, 0.01):  # walls 4.95 m away
        laser = _core.LaserGenerator(scanner, 1, LaserSpec(beams=90, max_range=3.3, noise=noise), alphabet)
        engine = vwg.Engine(vwg.World(alphabet), "Robot<1>", [laser])
        engine.step()
        assert len(engine.last_events) == 0


def test_laser_sees_other_robots_and_only_hits_make_events():
    grid = box_map(200)  # 10 m room
    robots = [RobotSettings(id=1, start=(2.0, 5.0, 0.0)),
              RobotSettings(id=2, start=(6.0, 5.0, 0.0), radius=0.3)]
    alphabet, _, scanner = sim_world(grid, robots)
    laser = _core.LaserGenerator(scanner, 1, LaserSpec(beams=2, fov=math.pi, max_range=3.0, noise=0.0), alphabet)
    engine = vwg.Engine(vwg.World(alphabet), "Robot<1>", [laser])
    engine.step()
    # Beams at -π/2 (wall at 5 - 0.05 = 4.95 m: beyond 3 m, no event) and +π/2 (same), none hit.
    assert len(engine.last_events) == 0
    laser = _core.LaserGenerator(scanner, 1, LaserSpec(beams=1, fov=0.1, max_range=10.0, noise=0.0), alphabet)
    engine = vwg.Engine(vwg.World(alphabet), "Robot<1>", [laser])
    engine.step()
    # Straight ahead: robot 2's disc surface at 6.0 - 0.3 = 5.7 m, 3.7 m away (nearer than the wall).
    assert [e.dist for e in engine.last_events] == pytest.approx([3.7], abs=1e-6)


@pytest.mark.parametrize("heading, fov, beams", [(0.3, 2 * math.pi, 360), (10.0, math.pi, 181), (-7.5, 1.0, 64)])
def test_laser_in_a_crowd_equals_a_test_of_every_beam_against_every_disc(heading, fov, beams):
    # The scanner tests only the beams near each neighbour's bearing; the truth here tests them all.
    rng = np.random.default_rng(3)
    grid = box_map(200)
    robots = [RobotSettings(id=1, start=(5.0, 5.0, heading))]
    while len(robots) < 40:
        x, y = rng.uniform(0.5, 9.5, 2)
        if all(math.hypot(x - r.start[0], y - r.start[1]) > 0.5 for r in robots):
            robots.append(RobotSettings(id=len(robots) + 1, start=(x, y, 0.0), radius=float(rng.uniform(0.1, 0.3))))
    alphabet, _, scanner = sim_world(grid, robots)
    laser = _core.LaserGenerator(scanner, 1, LaserSpec(beams=beams, fov=fov, max_range=8.0, noise=0.0), alphabet)
    vwg.Engine(vwg.World(alphabet), "Robot<1>", [laser]).step()
    angles = laser.angles
    truth = _core.GridRaycaster(grid).scan((5.0, 5.0, heading), angles, 8.0).astype(np.float64)
    a = heading + angles
    dx, dy = np.cos(a), np.sin(a)
    for r in robots[1:]:
        cx, cy = r.start[0] - 5.0, r.start[1] - 5.0
        along = cx * dx + cy * dy
        across2 = cx * cx + cy * cy - along**2
        hit = across2 <= r.radius ** 2
        t = along - np.sqrt(np.where(hit, r.radius ** 2 - across2, 0.0))
        truth = np.where(hit & (t >= 0) & (t < truth), t, truth)
    assert (truth < 8.0).sum() > beams // 4  # the crowd is seen, not only walls
    np.testing.assert_allclose(laser.ranges, truth, atol=1e-5)


def test_kinect_depth_image_by_hand():
    grid = box_map(200)  # inner faces at 0.05 and 9.95
    alphabet, _, scanner = sim_world(grid, [RobotSettings(id=1, start=(7.95, 5.0, 0.0))])
    kinect = _core.KinectGenerator(scanner, 1, DepthCameraSpec(min_range=0.5, max_range=4.5,
                                                                   mount_height=0.3, wall_height=2.5), alphabet)
    vwg.Engine(vwg.World(alphabet), "Robot<1>", [kinect]).step()
    depth = kinect.depth
    assert depth.shape == (480, 640) and depth.dtype == np.float32
    fx = 320 / math.tan(math.radians(29))  # 640 px over 58°
    # Centre columns look at the wall 2.0 m ahead; depth is along the optical axis.
    u = 320
    z_wall = 2.0 / math.sqrt(1 + ((u - 319.5) / fx) ** 2)
    assert depth[240, u] == pytest.approx(z_wall, abs=1e-5)
    # The top row sees the wall too (its top is 2.2 m above the camera, at 47.7° > 22.5°).
    assert depth[0, u] == pytest.approx(z_wall, abs=1e-5)
    # The bottom row sees the floor 0.3 m below, nearer than the wall's foot.
    down = (479 - 239.5) / fx
    assert depth[479, u] == pytest.approx(0.3 / down, abs=1e-5)
    # Its scan: one range per column, √(x² + z²) = 2.0 / cos(angle) at the wall.
    angles = kinect.angles
    assert angles[0] == pytest.approx(math.atan(319.5 / fx))  # leftmost column, positive to the left
    assert kinect.ranges[u] == pytest.approx(2.0 / math.cos(angles[u]), abs=1e-5)


def test_kinect_blind_zone_and_range():
    grid = box_map(200)
    alphabet, _, scanner = sim_world(grid, [RobotSettings(id=1, start=(9.6, 5.0, 0.0))])
    kinect = _core.KinectGenerator(scanner, 1, DepthCameraSpec(), alphabet)
    engine = vwg.Engine(vwg.World(alphabet), "Robot<1>", [kinect])
    engine.step()
    # The wall is 0.35 m ahead: inside the 0.5 m blind zone, so the centre column has no range.
    assert math.isnan(kinect.ranges[320])


def scans_around(sensor_kind, world, alphabet, spots):
    """The obstacle cells a sensor's eLaser events mark as the robot turns in place at each spot."""
    marked = np.zeros(world.grid.data.shape, bool)
    for x, y in spots:
        robot_world = vwg.World(alphabet)
        physics = _core.PhysicsWorld(world.grid, [RobotSettings(id=1, start=(x, y, 0.0))])
        scanner = _core.RangeScanner(_core.GridRaycaster(world.grid), physics)
        gen = (_core.LaserGenerator(scanner, 1, LaserSpec(beams=360, max_range=4.5, noise=0.0), alphabet)
               if sensor_kind == "laser" else _core.KinectGenerator(scanner, 1, DepthCameraSpec(), alphabet))
        engine = vwg.Engine(robot_world, "Robot<1>", [gen])
        for _ in range(12):  # 12 headings, 30° apart: the Kinect's 58° sees all around
            physics.command(1, [("turn", 0.0)])
            engine.step()
            _, _, theta = physics.robot(1).pose
            for e in engine.last_events:
                hx = x + e.dist * math.cos(theta + e.angle)
                hy = y + e.dist * math.sin(theta + e.angle)
                row, col = world.grid.world_to_cell(hx + 1e-3 * math.cos(theta + e.angle),
                                                    hy + 1e-3 * math.sin(theta + e.angle))
                if world.grid.inside(row, col):
                    marked[row, col] = True
            physics.command(1, [("turn", math.pi / 6)])
            physics.advance(2.0)
    return marked


def test_kinect_and_laser_build_nearly_the_same_grid():
    world = vwg.robot.load_robot_world(ROOT / "maps" / "office.yaml")
    alphabet = vwg.Alphabet(events=vwg.robot.platforms.sim.SIM_EVENTS, **vwg.robot.platforms.sim.MOTION_SYMBOLS)
    spots = [(1.5, 9.0), (5.5, 9.0), (12.0, 9.0), (5.0, 14.0)]
    laser = scans_around("laser", world, alphabet, spots)
    kinect = scans_around("kinect", world, alphabet, spots)
    # Compare up to one cell of slack: each cell one sensor marked has a marked neighbour in the other.
    def near(a, b):
        grown = b.copy()
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                grown |= np.roll(np.roll(b, dr, 0), dc, 1)
        return (a & grown).sum() / a.sum()
    laser_in_kinect, kinect_in_laser = near(laser, kinect), near(kinect, laser)
    print(f"laser cells near kinect cells {laser_in_kinect:.3f}, kinect near laser {kinect_in_laser:.3f}, "
          f"cells: laser {laser.sum()}, kinect {kinect.sum()}")
    assert laser.sum() > 200 and kinect.sum() > 200
    assert laser_in_kinect > 0.9 and kinect_in_laser > 0.9


def test_a_laser_cast_on_the_walls_alone_gives_the_simulated_lasers_events():
    # A platform without a simulator of its own (WallLaser: the map's walls from the pose it reports)
    # and the simulator's laser, with no other robot about: the same ranges through the same rule
    # (vwg._core.laser_events), so the same events. Some beams meet no wall within 3 m.
    grid = box_map()
    alphabet, physics, scanner = sim_world(grid, [RobotSettings(id=7, start=(1.3, 2.2, 0.4))])
    spec = LaserSpec(beams=90, min_range=0.2, max_range=3.0, noise=0.0)
    events = []
    walls = WallLaser(physics, _core.GridRaycaster(grid), 7, spec)
    for laser in (_core.LaserGenerator(scanner, 7, spec, alphabet), walls):
        engine = vwg.Engine(vwg.World(alphabet), "Robot<7>", [laser])
        engine.step()
        events.append([(e.target, e.dist, e.angle) for e in engine.last_events])
    assert events[0] == events[1]
    assert 10 < len(events[0]) < 80
