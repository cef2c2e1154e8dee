"""The robot of independent physics (issue 41): IR-SIM's robot behind a rosbridge v2 server on 127.0.0.1
(vwg.testing.irsim_robot), checked against truths worked out here — a scan in a hand-built map, odometry
from a straight Twist, the room reached by IR-SIM's own state — and test 3's rows that compare it with the
simulator."""

from __future__ import annotations

import dataclasses
import json
import math
import socket
import sys
import time

import numpy as np
import pytest
from websockets.sync.client import connect

import vwg
from vwg.errors import Error
from vwg.experiments import simulation
from vwg.experiments.simulation import SimulationConfig
from vwg.io.maps import OccupancyGrid
from vwg.robot.case_study import CaseStudy
from vwg.robot.links.ros_messages import odometry, pose_compose
from vwg.testing.irsim_robot import IrsimRosbridgeRobot

pytest.importorskip("irsim")

OFFICE = vwg.robot.load_robot_world("office")
RES = 0.05


def world_of(data: np.ndarray, start: tuple[float, float, float], origin: tuple[float, float] = (0.0, 0.0),
             **limits: float) -> vwg.robot.RobotWorld:
    """The office's settings (its laser: 360 beams over the full circle, 8 m) on a map made here, one robot."""
    grid = OccupancyGrid(data, RES, (*origin, 0.0))
    robot = OFFICE.robots[0].replace(start=start, **limits)
    return dataclasses.replace(OFFICE.with_sensor("laser", noise=0.0), grid=grid, robots=[robot], orders=[],
                               noise=vwg._core.NoiseModel())


def talk(url: str, *messages: dict) -> list[dict]:
    """Send the messages over one connection (rosbridge v2) and read what comes back up to the answer to the
    last service call among them."""
    received: list[dict] = []
    calls = sum(m["op"] == "call_service" for m in messages)
    with connect(url) as ws:
        for m in messages:
            ws.send(json.dumps(m))
        while sum(m["op"] == "service_response" for m in received) < calls:
            received.append(json.loads(ws.recv(timeout=30)))
    return received


def step(seconds: float, call: str = "1") -> dict:
    return {"op": "call_service", "id": call, "service": "/vwg/step", "args": {"seconds": seconds}}


def twist(speed: float, turn_rate: float) -> dict:
    return {"op": "publish", "topic": "/cmd_vel",
            "msg": {"linear": {"x": speed, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": turn_rate}}}


SUBSCRIBE = [{"op": "subscribe", "topic": "/odom", "type": "nav_msgs/Odometry"},
             {"op": "subscribe", "topic": "/scan", "type": "sensor_msgs/LaserScan"}]


def published(messages: list[dict], topic: str) -> list[dict]:
    return [m["msg"] for m in messages if m["op"] == "publish" and m["topic"] == topic]


# ---- the lidar, against a map drawn here -------------------------------------------------------------------------
def test_a_scan_of_irsims_lidar_in_a_hand_built_map_has_the_hand_computed_ranges():
    # 2 m × 2 m at 5 cm, its corner at (-1, 2): a wall along column 30 (x from 0.5 to 0.55), the whole
    # height, and one along row 35 (y from 3.75 to 3.80) left of it. The robot at (-0.5, 3.01), turned 10°
    # (off the cells' corners: IR-SIM's beam along a row of corners can slip between two edges).
    data = np.zeros((40, 40), np.int8)
    data[:, 30] = 100
    data[35, :30] = 100
    world = world_of(data, (-0.5, 3.01, math.radians(10)), origin=(-1.0, 2.0))
    with IrsimRosbridgeRobot(world) as robot:
        scan = published(talk(robot.url, *SUBSCRIBE, step(0.0)), "/scan")[-1]
    # vwg's layout: beam i at -180° + i° from the heading (360 beams over the full circle).
    angle_min, increment = vwg._core.beam_layout(world.sensor_settings("laser"))
    assert scan["angle_min"] == pytest.approx(angle_min, abs=1e-12)
    assert scan["angle_increment"] == pytest.approx(increment, abs=1e-12)
    assert len(scan["ranges"]) == 360 and (scan["range_min"], scan["range_max"]) == (0.05, 8.0)
    ranges = scan["ranges"]
    assert ranges[170] == pytest.approx(1.0, abs=1e-9)    # -10°: along +x, to the wall's face at x = 0.5
    assert ranges[260] == pytest.approx(0.74, abs=1e-9)   # +80°: along +y, to y = 3.75
    assert ranges[215] == pytest.approx(0.74 * math.sqrt(2), abs=1e-9)  # +35°: at 45°, the lower wall first
    assert ranges[350] is None                            # +170°: along -x, nothing: no return, +Inf as null
    assert ranges[171] == pytest.approx(1.0 / math.cos(math.radians(1)), abs=1e-9)  # 1° off the wall's normal


# ---- odometry, from a straight Twist --------------------------------------------------------------------------
def test_odometry_starts_at_zero_and_follows_a_straight_twist_by_speed_times_time():
    empty = np.zeros((80, 80), np.int8)  # 4 m × 4 m, nothing in it
    start = (1.0, 2.0, 0.5)
    # Accelerations IR-SIM takes in one step: the commanded speed from the first step on.
    quick = world_of(empty, start, max_accel=100.0, max_turn_accel=100.0)
    with IrsimRosbridgeRobot(quick) as robot:
        assert robot.step == quick.dt == 0.1
        first = published(talk(robot.url, *SUBSCRIBE, step(0.0)), "/odom")[-1]
        after = published(talk(robot.url, *SUBSCRIBE, twist(0.2, 0.0), step(1.0)), "/odom")[-1]
        truth = robot.pose(1)
    o = odometry(first)
    assert (o.time, o.x, o.y, o.yaw, o.speed) == (0.0, 0.0, 0.0, 0.0, 0.0)
    o = odometry(after)
    assert o.time == pytest.approx(1.0) and o.speed == pytest.approx(0.2)
    assert (o.x, o.y, o.yaw) == pytest.approx((0.2 * 1.0, 0.0, 0.0), abs=1e-12)  # v·t, straight ahead
    assert truth == pytest.approx(pose_compose(start, (0.2, 0.0, 0.0)), abs=1e-12)  # IR-SIM's own state agrees
    # The world's acceleration (1 m/s²): IR-SIM lets the speed grow by 0.1 m/s a step, 0.1 then 0.2 m/s:
    # 0.1·0.1 + 9·0.2·0.1 = 0.19 m in the second.
    with IrsimRosbridgeRobot(world_of(empty, start)) as robot:
        after = published(talk(robot.url, *SUBSCRIBE, twist(0.2, 0.0), step(1.0)), "/odom")[-1]
    assert odometry(after).x == pytest.approx(0.19, abs=1e-12)


def test_odometry_noise_is_the_seeds_and_leaves_the_truth_alone():
    empty = np.zeros((80, 80), np.int8)
    world = world_of(empty, (1.0, 2.0, 0.0))

    def drive(seed: int) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        with IrsimRosbridgeRobot(world, odometry_noise=0.05, seed=seed) as robot:
            msgs = talk(robot.url, *SUBSCRIBE, twist(0.3, 0.4), step(2.0), twist(0.3, -0.4), step(2.0, "2"))
            o = odometry(published(msgs, "/odom")[-1])
            return (o.x, o.y, o.yaw), robot.pose(1)

    (a, truth_a), (b, truth_b), (c, truth_c) = drive(7), drive(7), drive(8)
    assert a == b and truth_a == truth_b        # the same seed, the same numbers: nothing reads the clock
    assert a != c and truth_a == truth_c        # another seed drifts otherwise; the robot moved the same
    believed = pose_compose((1.0, 2.0, 0.0), a)
    assert 1e-4 < math.hypot(believed[0] - truth_a[0], believed[1] - truth_a[1]) < 0.3


# ---- the server ------------------------------------------------------------------------------------------------
def test_the_server_binds_127_0_0_1_refuses_a_step_it_cannot_take_and_stops_by_itself():
    world = world_of(np.zeros((40, 40), np.int8), (1.0, 1.0, 0.0))
    with IrsimRosbridgeRobot(world) as robot:
        assert robot.url == f"ws://127.0.0.1:{robot.port}"
        assert robot._server.sockets[0].getsockname()[0] == "127.0.0.1"
        answer = talk(robot.url, step(0.05))[-1]
        assert answer["result"] is False and "control_rate 10 Hz" in answer["values"]
        assert talk(robot.url, step(0.3))[-1]["values"] == {"time": pytest.approx(0.3)}  # three steps
        port = robot.port
    assert not robot.running
    with pytest.raises(OSError):
        socket.create_connection(("127.0.0.1", port), timeout=2).close()


def test_a_step_sent_again_with_its_id_is_answered_but_not_done_again():
    # vwg sends a step again, with its id, when the link dropped before the answer: IR-SIM steps once.
    world = world_of(np.zeros((40, 40), np.int8), (1.0, 1.0, 0.0))
    with IrsimRosbridgeRobot(world) as robot:
        def step_with_id(step_id: str) -> dict:
            return {**step(0.3), "args": {"seconds": 0.3, "step_id": step_id}}

        first = talk(robot.url, twist(0.2, 0.0), step_with_id("run:1"))[-1]["values"]
        there = robot.pose(1)
        again = talk(robot.url, *SUBSCRIBE, twist(0.2, 0.0), step_with_id("run:1"))  # another connection
        assert robot.pose(1) == there and robot._steps == 3
        after = talk(robot.url, step_with_id("run:2"))[-1]["values"]
    assert first == {"time": pytest.approx(0.3), "step_id": "run:1"}
    assert again[-1]["values"] == {**first, "repeated": True}
    assert odometry(published(again, "/odom")[-1]).time == pytest.approx(0.3)  # where it is, published again
    assert after == {"time": pytest.approx(0.6), "step_id": "run:2"}


def test_the_server_answers_pings_while_irsim_steps():
    # IR-SIM steps on the server's simulation thread, not on its event loop: a step that takes 1.5 s (IR-SIM's
    # office and lidar on a loaded machine took up to 0.8 s a step) leaves the loop answering the client's
    # keepalive pings meanwhile, and the answer comes when the step is done.
    world = world_of(np.zeros((40, 40), np.int8), (1.0, 1.0, 0.0))
    with IrsimRosbridgeRobot(world) as robot:
        advance = robot._advance

        def long_step(seconds: float) -> None:
            time.sleep(1.5)
            advance(seconds)

        robot._advance = long_step
        with connect(robot.url) as ws:
            ws.send(json.dumps(step(0.1)))
            time.sleep(0.3)  # the step is under way
            pinged = time.monotonic()
            assert ws.ping().wait(1.0), "no pong while IR-SIM stepped"
            ponged = time.monotonic()
            answer = json.loads(ws.recv(timeout=30))
    assert ponged - pinged < 1.0
    assert answer["result"] is True and answer["values"] == {"time": pytest.approx(0.1)}


def test_without_irsim_the_error_names_the_package(monkeypatch):
    monkeypatch.setitem(sys.modules, "irsim", None)  # import irsim then fails as if it were not installed
    with pytest.raises(Error, match=r"pip install ir-sim"):
        IrsimRosbridgeRobot(world_of(np.zeros((20, 20), np.int8), (0.5, 0.5, 0.0)))


# ---- vwg drives it ---------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_vwg_drives_irsims_robot_through_the_link_to_the_room():
    world, goals = simulation._task(1, 300)
    (rid, room), = goals.items()
    with IrsimRosbridgeRobot(world) as robot, \
            CaseStudy(simulation._on_irsim(world, robot), "astar", goals=goals, seed=1, threads=1) as case:
        summary = case.run(frames=300)
        x, y, _ = robot.pose(rid)
        collisions = robot.collisions[rid]
    assert summary.reached and summary.frames < 300
    gx, gy = world.rooms[room].goal
    # IR-SIM's own state, not what vwg believes, stands at the room: within the world's goal tolerance.
    assert math.hypot(x - gx, y - gy) <= world.goal_tolerance
    assert collisions == 0


@pytest.mark.slow
def test_test_3_has_an_irsim_row_whose_trajectory_stays_near_the_simulators(tmp_path):
    config = SimulationConfig(seeds=[1], frames=200, noise_levels=[0.0], noise_seeds=[1], noise_frames=40)
    found: dict[str, list] = {kind: [] for kind in simulation.KINDS}
    for kind, row in simulation.runs(config, tmp_path / "records"):
        found[kind].append(row)
    section = simulation.section(found, tmp_path)
    table = next(t for t in section.tables if t.name == "simulation_trajectories")
    assert [t.name for t in section.tables][:2] == ["simulation_same_frames", "simulation_trajectories"]
    (row,) = table.rows
    cells = dict(zip(table.columns, row, strict=True))
    assert (cells["seed"], cells["odometry noise"]) == ("1", "0")
    assert cells["arrived (simulator)"] == cells["arrived (IR-SIM)"] == cells["arrived (fake robot)"] == "yes"
    # Measured here: 0.088 m apart on average, 0.200 m at most, paths 0.042 m apart (IR-SIM arrives 7 frames
    # sooner: an Euler step per frame against Box2D's ten steps, no dynamics). The bounds: on average
    # less than the robot's radius (0.18 m) with room to spare, at most less than its diameter, the paths less
    # than its radius. A wrong map, beam layout or odometry frame puts the robot metres off, or nowhere.
    assert float(cells["IR-SIM apart m (mean)"]) < 0.15
    assert float(cells["IR-SIM apart m (max)"]) < 2 * 0.18
    assert float(cells["IR-SIM off path m"]) < 0.18
    assert cells["fake robot apart m (mean)"] == cells["fake robot apart m (max)"] == "0.000"  # the link is exact
    assert cells["fake robot off path m"] == "0.000"
    assert (tmp_path / "simulation_trajectories.png").read_bytes()[:4] == b"\x89PNG"
    assert section.tables[0].rows[0][-1] == "yes"  # the frame logs are still identical byte for byte
