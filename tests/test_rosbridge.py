"""The real robot through rosbridge (issue 10): ROS messages read as ROS says, the same world file run
on a fake ROS robot served on 127.0.0.1, and a robot kept safe when its odometry or its link goes."""

from __future__ import annotations

import dataclasses
import gc
import json
import math
import threading
import time
import weakref

import numpy as np
import pytest

import vwg
from conftest import ROOT
from vwg.robot.links.ros_messages import (
    laser_scan,
    odometry,
    odometry_message,
    pose_compose,
    same_type,
    scan_message,
    stamp_seconds,
)
from vwg.robot.platforms.real_robot import RealRobotPlatform
from vwg.robot.platforms.real_robots import ScanGenerator
from vwg.robot.platforms.rosbridge import RosbridgePlatform, topics_for
from vwg.robot.world_file import PlatformSpec
from vwg.testing.fake_robot import FakeRosbridgeRobot

MAZE = vwg.robot.load_robot_world("maze")
# The office with its first robot only, twice as quick as the file's (frames run at wall-clock rate).
_OFFICE = vwg.robot.load_robot_world("office")
OFFICE = dataclasses.replace(_OFFICE, orders=[], robots=[_OFFICE.robots[0].replace(
    max_speed=1.0, max_accel=2.0, max_turn_rate=3.0, max_turn_accel=8.0)])


# ---- messages ---------------------------------------------------------------------------------------------------
def test_type_names_and_stamps_in_both_ros_spellings():
    assert same_type("geometry_msgs/Twist", "geometry_msgs/msg/Twist")
    assert same_type("/nav_msgs/msg/Odometry", "nav_msgs/Odometry")
    assert not same_type("geometry_msgs/Twist", "geometry_msgs/TwistStamped")
    assert stamp_seconds({"secs": 12, "nsecs": 500_000_000}) == 12.5
    assert stamp_seconds({"sec": 12, "nanosec": 250_000_000}) == 12.25
    with pytest.raises(ValueError, match="stamp: expected"):
        stamp_seconds({"seconds": 1})
    # JSON readers take NaN and Infinity: a reading placed at such a time would be placed nowhere.
    for bad in ({"secs": math.nan, "nsecs": 0}, {"sec": 1, "nanosec": math.inf}):
        with pytest.raises(ValueError, match="stamp: expected finite seconds"):
            stamp_seconds(bad)


def test_odometry_yaw_from_its_quaternion_and_the_start_pose_as_origin():
    msg = odometry_message(3.0, 1.0, 2.0, 0.7, speed=0.2, turn_rate=-0.1, ros2=True)
    o = odometry(msg)
    assert (o.time, o.x, o.y, o.speed, o.turn_rate) == (3.0, 1.0, 2.0, 0.2, -0.1)
    assert o.yaw == pytest.approx(0.7)
    # A base that started at (5, 1) facing +y and drove 2 m forward, then turned left a quarter, is
    # at (5, 3) facing -x: start ⊕ odometry, worked out by hand.
    assert pose_compose((5.0, 1.0, math.pi / 2), (2.0, 0.0, math.pi / 2)) == pytest.approx((5.0, 3.0, math.pi))
    with pytest.raises(ValueError, match=r"pose\.pose\.position\.x: missing"):
        odometry({"header": {"stamp": {"sec": 0, "nanosec": 0}}, "pose": {"pose": {}}})


def test_laser_scan_keeps_the_readings_as_float32_and_null_as_nan():
    msg = {"header": {"stamp": {"secs": 1, "nsecs": 0}}, "angle_min": -1.0, "angle_increment": 0.5,
           "range_min": 0.1, "range_max": 10.0,
           "ranges": [2.0, math.inf, -math.inf, math.nan, None, 0.1, 1e300, -1e300]}
    scan = laser_scan(msg)
    assert (scan.time, scan.angle_min, scan.angle_increment) == (1.0, -1.0, 0.5)
    assert (scan.range_min, scan.range_max) == (0.1, 10.0)
    assert scan.ranges.dtype == np.float32
    f32max = float(np.finfo(np.float32).max)  # a finite reading stays finite (not -Inf: an obstacle)
    np.testing.assert_array_equal(scan.ranges, np.array([2.0, math.inf, -math.inf, math.nan, math.nan, np.float32(0.1),
                                                         f32max, -f32max], np.float32))
    with pytest.raises(ValueError, match="range_min, range_max"):
        laser_scan({**msg, "range_min": 5.0, "range_max": 1.0})


class _ScanOnly(RealRobotPlatform):
    """A real robot's platform whose link only delivers scans (nothing is ever sent)."""

    def send_velocity(self, robot, speed, turn_rate, *, connection=None):
        return True

    def link_failure(self):
        return None

    def close_link(self):
        pass

    def name(self):
        return "scans only"


# One scan with each kind of reading of REP 117 (range_min 0.1, range_max 10; beam i at -1 + 0.5 i).
REP117_SCAN = {"header": {"stamp": {"secs": 3, "nsecs": 0}}, "angle_min": -1.0, "angle_increment": 0.5,
               "range_min": 0.1, "range_max": 10.0,
               "ranges": [2.0, 10.0, math.inf, -math.inf, math.nan, None, 20.0, 0.05, 9.5, 0.1]}
# By hand: beam 0 in range; 1 exactly range_max: no return (drivers report no return so), 2 +Inf: no
# return; 3 -Inf: nearer than range_min, taken at it; 4 NaN and 5 null: nothing known; 6 beyond
# range_max, 7 below range_min: no measurement; 8 in range; 9 float32 0.1 (just above range_min) in range.
REP117_EVENTS = [(2.0, -1.0), (0.1, 0.5), (9.5, 3.0), (float(np.float32(0.1)), 3.5)]


def test_a_laserscan_gives_the_same_events_on_the_simulated_and_the_real_path():
    scan = laser_scan(REP117_SCAN)
    # The simulated laser's path: its float32 ranges and its beam angles, through laser_events as
    # LaserGenerator calls it (C++ platform::laser_events).
    angles = scan.angle_min + np.arange(scan.ranges.size) * scan.angle_increment
    dist, angle = vwg._core.laser_events(scan.ranges, angles, scan.range_min, scan.range_max)
    simulated = list(zip(dist.tolist(), angle.tolist(), strict=True))
    # The real robot's path: the scan as its link hands it on, and the platform's laser generator
    # in an engine's frames.
    platform = _ScanOnly([vwg._core.RobotSettings(id=2)])
    try:
        alphabet = vwg.Alphabet(events=vwg.robot.platforms.sim.SIM_EVENTS, **vwg.robot.platforms.sim.MOTION_SYMBOLS)
        engine = vwg.Engine(vwg.World(alphabet), "Robot<2>", [ScanGenerator(platform, 2)])
        engine.step()
        assert engine.last_events == []  # no scan yet
        platform.on_odometry(2, _odometry_at(3.0, 0.0, 0.0, 0.0))  # where the robot was at the scan's stamp,
        platform.advance(0.0)  # and still is at the frame: the scan is placed as it reads
        platform.on_scan(2, scan)
        engine.step()
        events = engine.last_events
        engine.step()
        assert engine.last_events == []  # once per scan
    finally:
        platform.close()
    assert {e.type for e in events} == {"eLaser"} and {e.target for e in events} == {2}
    real = [(e.dist, e.angle) for e in events]
    assert simulated == real == REP117_EVENTS


def _odometry_at(time_s: float, x: float, y: float, yaw: float):
    return odometry(odometry_message(time_s, x, y, yaw, 0.0, 0.0))


def test_the_viewpoint_of_a_stamp_is_interpolated_from_the_odometry_kept():
    platform = _ScanOnly([vwg._core.RobotSettings(id=1)])
    try:
        assert platform.viewpoint(1, 1.0) == (0.0, 0.0, 0.0)  # no odometry yet: the frame has the robot at its start
        platform.on_odometry(1, _odometry_at(1.0, 0.0, 0.0, 0.0))
        platform.on_odometry(1, _odometry_at(2.0, 1.0, 0.0, math.pi / 2))
        platform.advance(0.0)  # the frame takes the odometry of t = 2: at (1, 0) facing +y
        # By hand, halfway (t = 1.5): at (0.5, 0) facing pi/4. From (1, 0) facing +y, (0.5, 0) is 0.5 m to
        # the left, and the heading then was pi/4 to the right of the frame's.
        assert platform.viewpoint(1, 1.5) == pytest.approx((0.0, 0.5, -math.pi / 4), abs=1e-12)
        assert platform.viewpoint(1, 2.0) == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)
        assert platform.viewpoint(1, 2.4) == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)  # newer: the newest
        assert platform.viewpoint(1, 2.6) is None  # beyond the watchdog's 0.5 s after the newest: another clock
        assert platform.viewpoint(1, 0.5) is None  # older than any odometry kept
        assert platform.viewpoint(1, math.nan) is None
        assert platform.viewpoint(1, 0.0) == (0.0, 0.0, 0.0)  # not stamped: ROS's "the latest", the frame's pose
        # A message older than the newest (reordered) stays out of the history.
        platform.on_odometry(1, _odometry_at(1.8, 5.0, 5.0, 0.0))
        assert platform.viewpoint(1, 1.5) == pytest.approx((0.0, 0.5, -math.pi / 4), abs=1e-12)
        # Odometry that comes after the frame began does not move the frame's pose.
        platform.on_odometry(1, _odometry_at(3.0, 1.0, 1.0, math.pi / 2))
        assert platform.viewpoint(1, 2.0) == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)
        assert platform.viewpoint(1, 3.0) == pytest.approx((1.0, 0.0, 0.0), abs=1e-12)
        assert platform.robots()[0].pose == pytest.approx((1.0, 0.0, math.pi / 2))
        # A turn across the wrap goes the short way: 3.0 rad to -3.1 rad is 2 pi - 6.1 = 0.18 rad to the left,
        # through pi; halfway the robot was half of it to the right of the frame's heading.
        platform.on_odometry(1, _odometry_at(4.0, 1.0, 1.0, 3.0))
        platform.on_odometry(1, _odometry_at(5.0, 1.0, 1.0, -3.1))
        platform.advance(0.0)
        assert platform.viewpoint(1, 4.5) == pytest.approx((0.0, 0.0, -(2 * math.pi - 6.1) / 2), abs=1e-9)
    finally:
        platform.close()


def test_a_tag_in_a_late_image_is_placed_from_where_the_robot_was_when_it_was_taken():
    # The robot stands at the kitchen's goal facing its marker, 1 m ahead, when the image is taken (t = 1);
    # by the frame that reads it (odometry of t = 1.3) it has turned 0.6 rad left and gone 0.2 m. The tag's
    # distance and bearing are then those of the marker from where the robot is now, worked out from the
    # world file, not those in the image.
    world = vwg.robot.load_robot_world(ROOT / "maps" / "office.yaml")
    room = world.rooms["kitchen"]
    start = (*room.goal, room.facing + math.pi)
    platform = _ScanOnly([vwg._core.RobotSettings(id=1, start=start)])
    try:
        images = vwg._core.ReceivedImages(viewpoint=platform.viewpoint_of(1))
        renderer = vwg._core.CameraRenderer(world.grid, world.rooms, world.sensor_settings("camera"))
        taken = vwg._core.encode_image(renderer.render(start, [], grey=True), "png")
        a = vwg.Alphabet(events=vwg.robot.platforms.sim.SIM_EVENTS, **vwg.robot.platforms.sim.MOTION_SYMBOLS)
        camera = vwg._core.CameraGenerator(images, 1, a, *renderer.apriltag_intrinsics(), tag_size=room.size)
        engine = vwg.Engine(vwg.World(a), "Robot<1>", [camera])
        platform.on_odometry(1, _odometry_at(1.0, 0.0, 0.0, 0.0))
        platform.on_odometry(1, _odometry_at(1.3, 0.2, 0.0, 0.6))
        platform.advance(0.0)
        images.push(taken, 1.0)
        engine.step()
        [event] = engine.last_events
        x, y, heading = platform.robots()[0].pose
        mx, my = room.at
        assert event.marker == room.marker
        assert event.dist == pytest.approx(math.hypot(mx - x, my - y), rel=0.05)
        bearing = math.remainder(math.atan2(my - y, mx - x) - heading, math.tau)
        assert event.angle == pytest.approx(bearing, abs=math.radians(2))
        assert abs(bearing) > 0.4  # in the image the marker is straight ahead: placing it so would be wrong
        # An image taken before the oldest odometry kept cannot be placed: it is counted, not searched.
        images.push(taken, 0.5)
        engine.step()
        assert engine.last_events == [] and images.stale == 1
    finally:
        platform.close()
    # The image source holds the platform weakly: the collector cannot see through C++, and a strong
    # reference would keep every closed platform alive.
    gone = weakref.ref(platform)
    del platform
    gc.collect()
    assert gone() is None
    images.push(taken, 1.0)
    engine.step()
    assert engine.last_events == [] and images.stale == 2  # no platform: no pose to place it from


def test_a_late_scan_is_placed_from_where_the_robot_was_when_it_was_taken(caplog):
    # At the scan's stamp (t = 3) the robot was at the odometry's origin facing +x. Its two beams met walls
    # 2 m straight ahead, at (2, 0), and 2 m on its left, at (0, 2). By the frame (odometry of t = 3.5) it
    # stands at (1, 0) facing +y, so +x is on its right and -x on its left. By hand: (2, 0) is 1 m away on its
    # right; (0, 2) is 2 m ahead and 1 m to its left, sqrt(5) m away at atan2(1, 2) rad.
    scan = laser_scan({"header": {"stamp": {"secs": 3, "nsecs": 0}}, "angle_min": 0.0, "angle_increment": math.pi / 2,
                       "range_min": 0.1, "range_max": 10.0, "ranges": [2.0, 2.0]})
    platform = _ScanOnly([vwg._core.RobotSettings(id=2)])
    try:
        laser = ScanGenerator(platform, 2)
        engine = vwg.Engine(vwg.World(vwg.Alphabet(events=vwg.robot.platforms.sim.SIM_EVENTS,
                                                   **vwg.robot.platforms.sim.MOTION_SYMBOLS)), "Robot<2>", [laser])
        platform.on_odometry(2, _odometry_at(3.0, 0.0, 0.0, 0.0))
        platform.on_odometry(2, _odometry_at(3.5, 1.0, 0.0, math.pi / 2))
        platform.advance(0.0)
        platform.on_scan(2, scan)
        engine.step()
        assert [v for e in engine.last_events for v in (e.dist, e.angle)] == pytest.approx(
            [1.0, -math.pi / 2, math.sqrt(5), math.atan2(1, 2)], abs=1e-12)
        # A scan older than the odometry kept is not used, and the log says why (once).
        for _ in range(2):
            platform.on_scan(2, laser_scan(scan_message(2.0, 0.0, 0.1, [2.0], 0.1, 10.0)))
            engine.step()
        assert engine.last_events == [] and laser.stale == 2
        [warning] = [r.getMessage() for r in caplog.records if "outside the odometry kept" in r.getMessage()]
        assert "robot 2: a reading stamped 2.000 s is outside the odometry kept (3.000 to 3.500 s" in warning
    finally:
        platform.close()


def test_laser_events_refuse_a_bad_scan_by_its_field():
    with pytest.raises(vwg.SchemaError, match="ranges: expected a 1-D array of numbers"):
        vwg._core.laser_events([1.0, "far"], 0.0, 0.1, 0.1, 5.0)
    with pytest.raises(vwg.SchemaError, match="ranges: expected a 1-D array, got 2 dimensions"):
        vwg._core.laser_events(np.zeros((2, 2)), 0.0, 0.1, 0.1, 5.0)
    with pytest.raises(vwg.SchemaError, match=r"range_max: expected a finite range > range_min \(5"):
        vwg._core.laser_events([1.0], 0.0, 0.1, 5.0, 5.0)
    with pytest.raises(vwg.SchemaError, match="angle_increment: expected a finite angle"):
        vwg._core.laser_events([1.0], 0.0, math.nan, 0.1, 5.0)
    with pytest.raises(vwg.Error, match="2 ranges for 1 angles"):
        vwg._core.laser_events([1.0, 2.0], [0.0], 0.1, 5.0)
    with pytest.raises(vwg.SchemaError, match="seen_from: expected finite numbers"):
        vwg._core.laser_events([1.0], 0.0, 0.1, 0.1, 5.0, seen_from=(0.0, math.nan, 0.0))
    with pytest.raises(vwg.SchemaError, match=r"seen_from: expected \(x, y, yaw\)"):
        vwg._core.laser_events([1.0], 0.0, 0.1, 0.1, 5.0, seen_from=(0.0, 0.0))


def test_topics_default_per_robot_and_take_the_robot_id():
    assert topics_for(1, False)["cmd_vel"] == "/cmd_vel"
    assert topics_for(2, True)["odom"] == "/robot2/odom"
    assert topics_for(3, True, {"scan": "/base{id}/laser"})["scan"] == "/base3/laser"


# ---- runs -------------------------------------------------------------------------------------------------------
def record_sent(platform: RealRobotPlatform) -> dict[int, list[tuple[float | None, float, float, bool]]]:
    """Record what `platform` sends each robot, in the order it sends it, on the sender's own time base:
    (dt, speed, turn rate, sent) for every velocity, dt being what the control tick that computed it
    gave its follower (None for a velocity sent outside a tick: the stop when the platform closes),
    sent whether it went out over the link. Call before the platform's first command or frame."""
    sent: dict[int, list[tuple[float | None, float, float, bool]]] = {r.id: [] for r in platform.robots()}
    tick = threading.local()  # the control tick under way on this thread, if any
    control, send_velocity = platform._control, platform.send_velocity

    def control_tick(dt: float) -> None:
        tick.dt = dt
        try:
            control(dt)
        finally:
            tick.dt = None

    def send(robot: int, speed: float, turn_rate: float, **kw: object) -> bool:
        ok = send_velocity(robot, speed, turn_rate, **kw)
        sent[robot].append((getattr(tick, "dt", None), speed, turn_rate, ok))
        return ok

    platform._control, platform.send_velocity = control_tick, send  # type: ignore[method-assign]
    return sent


@pytest.fixture
def fake():
    with FakeRosbridgeRobot(MAZE) as robot:
        yield robot


@pytest.mark.slow
def test_the_office_world_runs_on_a_ros_robot_through_rosbridge():
    # The world is the simulator's; only the platform changes (paper test 3).
    room = "office"
    with FakeRosbridgeRobot(OFFICE, image_delay=0.3) as fake:  # a slow camera: each image sent 0.3 s late
        options = vwg.RunOptions(platform="rosbridge", platform_options={"url": fake.url}, goals=[room], frames=250)
        started = time.monotonic()
        with vwg.start(OFFICE, options) as run:
            sent = record_sent(run.case.sim.platform)[1]
            outcome = run.execute()
            images = run.case.sim.platform.images[1]
            grid = np.asarray(run.case.robot_actors()[1]["grid"])
        took = time.monotonic() - started
        fake.read_to_close()  # every Twist sent before the link closed
    assert outcome.exit_status == 0 and outcome.summary["reached"], outcome.rows
    # The camera's JPEG images came over the link, and gCamera found the room's marker in them: the
    # robot's map holds it where the world file puts it, within the tag pose's error at a few metres.
    # An image is read 0.3 s or more after it was taken while the robot turns at up to 3 rad/s; its tags
    # are placed from the odometry at its stamp (RealRobotPlatform.viewpoint), so its age adds nothing:
    # 0.07 m measured, against 0.32 m when placed from the frame's pose.
    assert images.received > 20 and images.dropped == 0
    marker = OFFICE.rooms[room]
    rows, cols = np.nonzero(grid == 1000 + marker.marker)
    r0, c0 = OFFICE.grid.world_to_cell(*marker.at)
    assert len(rows) >= 1
    assert np.hypot(rows - r0, cols - c0).max() * OFFICE.grid.resolution <= 0.2
    # Where the fake robot really is (its own pose, not vwg's estimate) is within the goal tolerance.
    x, y, _ = fake.pose(1)
    gx, gy = OFFICE.rooms[room].goal
    assert math.hypot(x - gx, y - gy) <= OFFICE.goal_tolerance + 0.05
    # The last command the robot received is a stop, sent when the run closed.
    assert fake.commands[1][-1][1:] == (0.0, 0.0)
    assert outcome.summary["faults"] == []
    # Every command within the robot's limits: speeds, and their change from one command to the next
    # within the accelerations over the time the sender meant between them. The robot received the
    # very Twists the platform sent, in the order it sent them; each was computed by a control tick
    # for the time since the tick before (at most two control periods), and the ticks' times add up
    # to no more than the run took. Judged on that time base, not on the times the Twists arrived: on
    # a loaded 2-core machine two Twists 0.42 rad/s apart (a tick of at least 53 ms at 8 rad/s²)
    # arrived 27 ms apart, delivery through two event loops' threads being late now and then.
    limits, period = OFFICE.robots[0], run.case.sim.platform.control_period
    assert [(v, w) for _, v, w in fake.commands[1]] == [(v, w) for _, v, w, ok in sent if ok]
    assert all(abs(v) <= limits.max_speed + 1e-9 and abs(w) <= limits.max_turn_rate + 1e-9 for _, v, w, _ in sent)
    ticks = [dt for dt, *_ in sent if dt is not None]
    assert len(ticks) > 50 and all(0 < dt <= 2 * period + 1e-9 for dt in ticks) and sum(ticks) <= took
    assert [dt for dt, *_ in sent].index(None) == len(sent) - 1  # the stop at the end: no tick, no limit
    held, last = 0.0, (0.0, 0.0)  # the robot holds the last velocity it received (at rest before the first)
    for dt, v, w, ok in sent[:-1]:
        held += dt  # a tick whose Twist did not go out: the robot held the one before for it too
        if ok:
            assert abs(v - last[0]) <= limits.max_accel * held + 1e-9, (v, last, held)
            assert abs(w - last[1]) <= limits.max_turn_accel * held + 1e-9, (w, last, held)
            held, last = 0.0, (v, w)


def test_silent_odometry_stops_the_robot_within_the_watchdog(fake):
    watchdog = 0.3
    platform = RosbridgePlatform([MAZE.robots[0]], fake.url, watchdog=watchdog)
    try:
        platform.command(1, [("drive", 5.0)])
        platform.advance(0.6)
        assert fake.commands[1][-1][1] > 0.0  # driving
        silent_from = fake.silence(1)
        platform.advance(0.8)
        # The first stop after the silence, on the fake robot's clock: no sleep in the test can make
        # this hold; only the watchdog sending a stop at the right time.
        stops = [t for t, v, w in fake.commands[1] if t > silent_from and v == 0.0 and w == 0.0]
        assert stops, "no stop was sent"
        delay = stops[0] - silent_from
        assert watchdog - 0.05 <= delay <= watchdog + platform.control_period + 0.1, delay
        assert all(v == 0.0 for t, v, _ in fake.commands[1] if t >= stops[0])  # kept stopped
        assert "no odometry" in platform.faults[0].what and platform.faults[0].robot == 1
        fake.speak(1)
        platform.advance(0.5)
        assert fake.commands[1][-1][1] > 0.0  # odometry again: the plan goes on
    finally:
        platform.close()
    fake.read_to_close()  # every Twist sent before the link closed
    assert fake.commands[1][-1][1:] == (0.0, 0.0)


@pytest.mark.slow
def test_a_lost_link_ends_the_run_with_status_4_and_keeps_the_record(fake, tmp_path):
    world = dataclasses.replace(MAZE, platform=PlatformSpec("rosbridge", {"url": fake.url, "reconnect": 0.5}))
    record = tmp_path / "run.jsonl"
    options = vwg.RunOptions(goals=["dead_end_0_2"], frames=300, record=record)
    cut_at: list[float] = []
    timer = threading.Timer(1.5, lambda: (cut_at.append(time.monotonic()), fake.cut()))
    with vwg.start(world, options) as run:  # the run's own recorder (options.record): the one writer
        timer.start()
        outcome = run.execute()
    assert outcome.exit_status == vwg.launch.EXIT_LINK_FAULT == 4
    assert "link fault" in outcome.message and "did not come back within 0.5 s" in outcome.message
    assert outcome.summary["faults"][-1]["robot"] == 0
    # Every frame before the fault is in the record, each line whole, and it replays.
    recorded = vwg.read_record(record)
    assert [f["t"] for f in recorded.frames] == list(range(run.engine.frame)) and run.engine.frame >= 10
    vwg.replay(record, world=vwg.launch.replay_world(recorded.header, None, record))
    # The robot went quiet with the link: the base's own command timeout stopped it.
    x0, y0, _ = fake.pose(1)
    time.sleep(0.3)
    assert fake.pose(1)[:2] == pytest.approx((x0, y0))


@pytest.mark.slow
def test_rosbridge_options_are_checked_by_name():
    with pytest.raises(vwg.SchemaError, match=r"platform\.url: missing \(ws://HOST:PORT, or --url\)"):
        vwg.start(MAZE, vwg.RunOptions(platform="rosbridge", frames=1))
    with pytest.raises(vwg.SchemaError, match=r"unknown option\(s\) speed"):
        vwg.start(dataclasses.replace(MAZE, platform=PlatformSpec("rosbridge", {"url": "ws://127.0.0.1:1",
                                                                               "speed": 2})), vwg.RunOptions())
    with pytest.raises(vwg.Error, match="cannot connect"):
        RosbridgePlatform([MAZE.robots[0]], "ws://127.0.0.1:9", reconnect=0.2)


# ---- a serial base ----------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_the_office_world_runs_on_a_serial_base():
    from vwg.testing.fake_base import FakeSerialBase

    room = "office"
    with FakeSerialBase(OFFICE) as base:
        options = vwg.RunOptions(platform="serial", platform_options={"port": base.url}, goals=[room], frames=300)
        with vwg.start(OFFICE, options) as run:
            outcome = run.execute()
        x, y, _ = base.pose_now()
    assert outcome.exit_status == 0 and outcome.summary["reached"], outcome.rows
    gx, gy = OFFICE.rooms[room].goal
    # The base's true pose (integrated by the fake from its wheels), not vwg's odometry.
    assert math.hypot(x - gx, y - gy) <= OFFICE.goal_tolerance + 0.08
    assert base.commands[-1][1:] == (0, 0)  # stopped at the end


def test_serial_options_are_checked_by_name():
    with pytest.raises(vwg.SchemaError,
                       match=r"platform\.port: missing \(/dev/ttyUSB0, socket://HOST:PORT, or --serial-port\)"):
        vwg.start(OFFICE, vwg.RunOptions(platform="serial", frames=1))
    with pytest.raises(vwg.SchemaError, match="one base per serial line, and the world has 2 robots"):
        vwg.start(_OFFICE, vwg.RunOptions(platform="serial", platform_options={"port": "loop://"}, frames=1))
    with pytest.raises(vwg.SchemaError, match=r"cannot use socket://127\.0\.0\.1:9"):
        options = vwg.RunOptions(platform="serial", platform_options={"port": "socket://127.0.0.1:9"}, frames=1)
        vwg.start(OFFICE, options)


def test_a_serial_line_cut_while_it_opens_leaves_no_socket_open(monkeypatch):
    # The cable pulled just as the line is reopened: the connect succeeds (the base's listening socket
    # has queued it), then the base goes and the connection is reset, while pyserial is still in its
    # open() (emptying the input: "read failed"). The socket that open made is closed by vwg, not left
    # to the garbage collector (a ResourceWarning wherever it happens to collect it: an error here).
    import socket

    import serial.urlhandler.protocol_socket as protocol_socket

    from vwg.robot.platforms.serial_base import SerialBase

    made: list[socket.socket] = []
    reconfigure = protocol_socket.Serial._reconfigure_port
    with socket.create_server(("127.0.0.1", 0)) as listener:

        def connected_then_cut(line):  # pyserial calls it in open(), right after the connect
            made.append(line._socket)
            listener.close()  # the queued connection is reset
            reconfigure(line)

        monkeypatch.setattr(protocol_socket.Serial, "_reconfigure_port", connected_then_cut)
        base = SerialBase(f"socket://127.0.0.1:{listener.getsockname()[1]}")
        with pytest.raises(OSError, match="Connection reset"):
            base.open()
    assert len(made) == 1 and made[0].fileno() == -1  # closed
    base.close()


def test_malformed_and_oversized_messages_are_dropped_and_the_run_goes_on(fake):
    platform = RosbridgePlatform([MAZE.robots[0]], fake.url)
    try:
        link = platform.link
        before = link.dropped
        for text in ("not json", "[1, 2]", json.dumps({"op": "publish", "topic": "/odom", "msg": {"pose": 3}}),
                     json.dumps({"op": "publish", "topic": "/scan", "msg": {"ranges": "x"}}),
                     json.dumps({"op": "teleport"}), "x" * (link.max_message + 1)):
            link._receive(text)  # as if the server had sent it
        assert link.dropped == before + 6
        platform.command(1, [("drive", 0.3)])
        platform.advance(1.5)
        assert not platform.robots()[0].busy  # odometry kept coming: the drive finished
        assert platform.robots()[0].pose[0] == pytest.approx(MAZE.robots[0].start[0] + 0.3, abs=0.02)
    finally:
        platform.close()


@pytest.mark.slow
def test_a_serial_base_silent_or_cut_is_stopped_and_ends_the_run():
    from vwg.robot.platforms.serial_base import SerialPlatform
    from vwg.testing.fake_base import FakeSerialBase

    with FakeSerialBase(OFFICE) as base:
        platform = SerialPlatform(OFFICE.robots[0], base.url, watchdog=0.3, reconnect=0.5)
        try:
            platform.command(1, [("drive", 3.0)])
            platform.advance(0.6)
            assert base.commands[-1][1] > 0  # driving
            cut_at = time.monotonic()
            base.cut()  # the encoders stop answering: odometry stops
            with pytest.raises(vwg.Error, match=r"did not come back within 0\.5 s"):
                for _ in range(20):
                    platform.advance(0.1)
            assert time.monotonic() - cut_at < 0.5 + 0.5  # the fault ended it promptly
            assert any("no odometry" in f.what for f in platform.faults)
            # The link's own fault (robot 0: the whole link) is reported too; a watchdog stop may come
            # just before or after it, as the threads' timing has it on a loaded machine.
            assert any(f.robot == 0 and "did not come back" in f.what for f in platform.faults), platform.faults
        finally:
            platform.close()
        # The firmware's own timeout stops the motors once commands stop coming.
        time.sleep(base.auto_stop + 0.2)
        x0, y0, _ = base.pose_now()
        time.sleep(0.2)
        assert base.pose_now()[:2] == pytest.approx((x0, y0))


@pytest.mark.slow
def test_the_same_world_on_the_simulator_and_through_rosbridge_gives_the_same_frames(tmp_path):
    # Paper test 3 with noise off: the same world, (a) on the simulator platform, (b) through
    # rosbridge to the fake robot — its own Box2D simulator, stepped by vwg in lockstep, driven only by
    # the Twists vwg publishes and seen only through the Odometry and LaserScan it publishes. Two
    # robots, each to its room: the frame logs are the same, byte for byte (the header included).
    world = dataclasses.replace(_OFFICE.with_sensor("laser", noise=0.0), orders=[],
                                robots=[r.replace(sensors=["laser"]) for r in _OFFICE.robots])
    goals = ["1:office", "2:meeting"]
    with vwg.start(world, vwg.RunOptions(goals=goals, frames=400, record=tmp_path / "sim.jsonl")) as run:
        a = run.execute()
    with FakeRosbridgeRobot(world, lockstep=True) as fake:
        on_ros = dataclasses.replace(world, platform=PlatformSpec(
            "rosbridge", {"url": fake.url, "lockstep": "/vwg/step", "control_rate": 100,
                          "watchdog": 30}))  # a step may be slow on a loaded machine: the robot's clock waits
        with vwg.start(on_ros, vwg.RunOptions(goals=goals, frames=400, record=tmp_path / "ros.jsonl")) as run:
            b = run.execute()
        twists = len(fake.commands[1])
    assert a.summary["reached"] and b.summary["reached"] and a.summary["frames"] > 100, (a.rows, b.rows)
    sim, ros = (tmp_path / "sim.jsonl").read_bytes(), (tmp_path / "ros.jsonl").read_bytes()
    assert twists >= 10 * a.summary["frames"]  # the robot really was driven through the link, every step
    assert sim.count(b"\n") == a.summary["frames"] + 2 and sim == ros


@pytest.mark.slow
def test_with_odometry_noise_the_ros_robot_believes_itself_where_its_odometry_drifted():
    # The fake robot's odometry drifts (a random walk of 0.02 per √metre, as the simulator's noise
    # model): vwg knows the robot by its odometry only, so its idea of the pose parts from the truth
    # by the drift — measured here against the fake's true pose, and against the noise-off run.
    world = dataclasses.replace(_OFFICE.with_sensor("laser", noise=0.0), orders=[],
                                robots=[_OFFICE.robots[0].replace(sensors=["laser"])])
    noisy = _core_physics(odometry=0.02)
    with FakeRosbridgeRobot(world, lockstep=True, physics=noisy) as fake:
        on_ros = dataclasses.replace(world, platform=PlatformSpec(
            "rosbridge", {"url": fake.url, "lockstep": "/vwg/step", "control_rate": 100,
                          "watchdog": 30}))  # a step may be slow on a loaded machine: the robot's clock waits
        with vwg.start(on_ros, vwg.RunOptions(goals=["office"], frames=300)) as run:
            outcome = run.execute()
            believed = run.case.sim.platform.robots()[0].pose
        truth = fake.pose(1)
    drift = math.hypot(believed[0] - truth[0], believed[1] - truth[1])
    print(f"\nodometry noise 0.02/√m over {outcome.summary['path_length_m']:.2f} m: vwg's pose is {drift:.3f} m "
          f"from the robot's true pose")
    # A random walk of 0.02·√(4.8 m) ≈ 0.044 m in each increment's length, more through the heading.
    assert 0.001 < drift < 0.5


def _core_physics(odometry: float) -> vwg.robot.platforms.sim.PhysicsSettings:
    return vwg.robot.platforms.sim.PhysicsSettings(noise=vwg.robot.NoiseModel(odometry=odometry), seed=7)


@pytest.mark.slow
def test_a_ros_robot_at_wall_clock_rate_takes_the_way_the_simulator_takes():
    # The same world at wall-clock rate (as a real robot runs): the velocities come at the control
    # rate and meet the robot at whatever time the network brings them, so the frames differ; what
    # is compared is the way each took: both reach the room, and every point (b) drove lies close to
    # the path (a) drove.
    paths = {}
    with vwg.start(OFFICE, vwg.RunOptions(goals=["office"], frames=250)) as run:
        a = run.execute()
        paths["sim"] = np.asarray(run.case.view.trajectories[1])
    with FakeRosbridgeRobot(OFFICE) as fake, vwg.start(OFFICE, vwg.RunOptions(
            platform="rosbridge", platform_options={"url": fake.url}, goals=["office"], frames=250)) as run:
        b = run.execute()
        paths["rosbridge"] = np.asarray(run.case.view.trajectories[1])
    assert a.summary["reached"] and b.summary["reached"]
    sim, ros = paths["sim"], paths["rosbridge"]
    deviation = max(float(np.hypot(*(sim - p).T).min()) for p in ros)
    ends = float(np.hypot(*(sim[-1] - ros[-1])))
    print(f"\nsimulator: {a.summary['frames']} frames, {a.summary['path_length_m']:.2f} m; rosbridge: "
          f"{b.summary['frames']} frames, {b.summary['path_length_m']:.2f} m; largest distance of the ROS "
          f"robot's path from the simulated one {deviation:.3f} m; ends {ends:.3f} m apart")
    assert deviation < 0.35 and ends < 2 * OFFICE.goal_tolerance


def test_a_lockstep_robot_that_stops_answering_ends_the_run_with_a_link_fault(tmp_path):
    world = OFFICE.with_sensor("laser", noise=0.0)
    with FakeRosbridgeRobot(world, lockstep=True) as fake:
        on_ros = dataclasses.replace(world, platform=PlatformSpec(
            "rosbridge", {"url": fake.url, "lockstep": "/vwg/step", "control_rate": 100, "watchdog": 0.3}))
        with vwg.start(on_ros, vwg.RunOptions(goals=["office"], frames=400, record=tmp_path / "r.jsonl")) as run:
            fake.lockstep = False  # the step service is gone: every call fails
            b = run.execute()
    assert b.exit_status == vwg.launch.EXIT_LINK_FAULT
    assert "/vwg/step" in b.message and b.summary["faults"]
    assert fake.commands[1][-1][1:] == (0.0, 0.0)  # stopped before the run ended


@pytest.mark.parametrize(("ros", "twist", "scan"), [(1, "geometry_msgs/Twist", "sensor_msgs/LaserScan"),
                                                   (2, "geometry_msgs/msg/Twist", "sensor_msgs/msg/LaserScan")])
def test_type_names_are_spelled_for_the_robots_ros(fake, ros, twist, scan):
    platform = RosbridgePlatform([MAZE.robots[0]], fake.url, ros=ros)
    try:
        platform.advance(0.2)
    finally:
        platform.close()
    assert ("advertise", "/cmd_vel", twist) in fake.declared and ("subscribe", "/scan", scan) in fake.declared


# ---- what a review found ------------------------------------------------------------------------------------------
def test_odometry_that_did_not_start_at_zero_still_puts_the_robot_at_its_start():
    # A base whose driver has run before: its odometry stands at (3, -2, 1 rad) when vwg connects.
    with FakeRosbridgeRobot(MAZE, odom_offset=(3.0, -2.0, 1.0)) as fake:
        platform = RosbridgePlatform([MAZE.robots[0]], fake.url)
        try:
            platform.advance(0.3)
            assert platform.robots()[0].pose == pytest.approx(MAZE.robots[0].start, abs=1e-6)
            platform.command(1, [("drive", 0.5)])
            platform.advance(2.0)
            x, y, _ = platform.robots()[0].pose
            assert (x, y) == pytest.approx(fake.pose(1)[:2], abs=0.02)  # vwg's pose is the robot's true one
        finally:
            platform.close()


def test_a_quaternion_of_any_length_gives_its_yaw():
    from vwg.robot.links.ros_messages import yaw_of_quaternion

    assert yaw_of_quaternion({"x": 0.0, "y": 0.0, "z": 1.0, "w": 1.0}) == pytest.approx(math.pi / 2)
    assert yaw_of_quaternion({"x": 0.0, "y": 0.0, "z": 2.0, "w": 0.0}) == pytest.approx(math.pi)


def test_a_turn_of_half_a_circle_across_the_wrap_ends_where_it_should():
    follower = vwg.robot.MotionFollower(OFFICE.robots[0])
    follower.command([("turn", math.pi)])
    yaw, turned, dt = 3.0, 0.0, 0.05  # from 3.0 rad: the turn passes +π, where odometry's yaw wraps
    for _ in range(400):
        _, w = follower.tick((0.0, 0.0, math.atan2(math.sin(yaw), math.cos(yaw))), dt)
        yaw += w * dt
        turned += w * dt
        if not follower.busy:
            break
    assert not follower.busy and turned == pytest.approx(math.pi, abs=0.02)


def test_a_slow_frame_leaves_the_robot_controlled(fake):
    platform = RosbridgePlatform([MAZE.robots[0]], fake.url)
    try:
        platform.command(1, [("drive", 5.0)])
        platform.advance(0.3)
        gap_from = time.monotonic()
        time.sleep(1.0)  # a frame that takes a second (a long replan): no advance() meanwhile
        during = [t for t, _, _ in fake.commands[1] if gap_from < t < gap_from + 1.0]
        assert len(during) >= 10  # the control thread kept sending, 20 a second
    finally:
        platform.close()


def test_nested_settings_are_changed_in_place():
    physics = vwg.robot.platforms.sim.PhysicsSettings()
    physics.noise.motors = 0.1
    assert physics.noise.motors == 0.1 and physics.noise == vwg.robot.NoiseModel(motors=0.1)
