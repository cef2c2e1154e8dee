"""The supervisor interrupts a task (paper §III: it "can interrupt the current task or begin a new task"): an
eObjective<marker=-1> from gObjective, given by orders.cancel(robot) in Python, a `stop` or `cancel` line of
--stdin-orders, or the viewer's Stop button. The robot comes to rest within its braking distance and stays there;
the run does not wait for it; the summary says the task was interrupted, not failed; a new order starts it again."""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys

import pytest

import vwg
from vwg.errors import SchemaError

OFFICE = vwg.robot.load_robot_world("office")


def _speed_limits(world):
    r = world.robots[0]
    return r.max_speed, r.max_accel


@pytest.mark.parametrize("avoidance", ["none", "orca"])
def test_a_cancelled_robot_comes_to_rest_within_its_braking_distance_and_stays(avoidance):
    case = vwg.robot.CaseStudy(OFFICE, "astar", goals={1: "library"}, avoidance=avoidance)
    case.run(frames=60)
    before = case.sim.robot(1).pose
    assert math.hypot(before[0] - OFFICE.robots[0].start[0], before[1] - OFFICE.robots[0].start[1]) > 0.5
    case.orders.cancel(1)
    poses = []
    for _ in range(40):
        case.engine.step()
        poses.append(case.sim.robot(1).pose)
    v, a = _speed_limits(OFFICE)
    # From full speed, braking at max_accel takes v²/2a; the command reaches the robot within two frames.
    bound = v * v / (2 * a) + 2 * v * OFFICE.dt + 0.01
    x, y, _ = poses[-1]
    assert math.hypot(x - before[0], y - before[1]) <= bound
    rest = poses[15]
    assert all(math.hypot(p[0] - rest[0], p[1] - rest[1]) < 1e-3 for p in poses[15:])  # at rest, and it stays
    summary = case.summary()
    robot = summary.robots[0]
    assert robot.interrupted and robot.room is None and robot.status == "interrupted" and not robot.reached
    assert summary.reached  # nobody else was waited for: the task was interrupted, not failed
    case.close()


def test_the_run_stops_waiting_for_an_interrupted_robot_and_a_new_order_starts_it_again():
    case = vwg.robot.CaseStudy(OFFICE, "astar", goals={1: "library"}, frames=3000)
    case.run(frames=30)
    case.orders.cancel(1)
    summary = case.run(frames=100)
    # The run is done a frame after the cancel: the only order was interrupted.
    assert summary.frames <= 33 and summary.robots[0].interrupted
    case.orders.order(1, "kitchen")
    summary = case.run()
    robot = summary.robots[0]
    assert robot.room == "kitchen" and robot.reached and not robot.interrupted and summary.reached
    case.close()


def test_order_lines_take_stop_and_cancel_unless_a_room_has_that_name():
    case = vwg.robot.CaseStudy(OFFICE, "astar", world_orders=False)
    orders = case.orders
    orders.read_line("lab")
    orders.read_line("2 kitchen")
    case.engine.step()
    assert orders.last == {1: "lab", 2: "kitchen"}
    orders.read_line("stop")
    orders.read_line("2:cancel")
    case.engine.step()
    assert orders.last == {} and orders.interrupted == {1, 2}
    with pytest.raises(SchemaError, match=r"expected ROOM or ROBOT ROOM, got '1 2 stop'"):
        orders.read_line("1 2 stop")
    with pytest.raises(SchemaError, match=r"goal: no robot 7"):
        orders.read_line("7 stop")
    case.close()
    # A room called "stop" is a room.
    rooms = {**OFFICE.rooms, "stop": dataclasses.replace(OFFICE.rooms["lab"], name="stop")}
    case = vwg.robot.CaseStudy(dataclasses.replace(OFFICE, rooms=rooms), "astar", world_orders=False)
    case.orders.read_line("stop")
    case.engine.step()
    assert case.orders.last == {1: "stop"}
    case.close()


def test_stdin_stop_interrupts_and_the_summary_says_so(tmp_path):
    done = subprocess.run([sys.executable, "-m", "vwg", "run", "office", "--no-world-orders", "--stdin-orders",
                           "--frames", "3000", "--summary-json", str(tmp_path / "s.json")],
                          input="library\nstop\n", capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr  # interrupted is not unreached
    assert "robot 1      interrupted (its task was cancelled)" in done.stdout
    import json

    summary = json.loads((tmp_path / "s.json").read_text())
    assert summary["robots"][0]["interrupted"] and summary["robots"][0]["status"] == "interrupted"
    assert summary["frames"] < 3000
