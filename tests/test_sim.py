"""The simulator as a backend: the world string drives Box2D robots; feedback comes back as events."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import vwg
from vwg import _core
from vwg.robot import RobotSettings
from vwg.robot.platforms.sim import NoiseModel, PhysicsSettings


def empty_map(width_m=10.0, height_m=5.0, res=0.05, wall_x=None):
    data = np.zeros((round(height_m / res), round(width_m / res)), np.int8)
    if wall_x is not None:
        data[:, round(wall_x / res)] = 100  # a wall whose face is at x = wall_x
    return SimpleNamespace(data=data, resolution=res, origin=(0.0, 0.0, 0.0))


class Driver(vwg.Actor):
    """Shows its order once, when told to go; counts the collisions it hears of."""

    events = ("go", "eCollision")
    attributes = {"id": 1, "order": "Move<1.0>(Robot<1>)", "bumps": 0}

    def show_go(self, e):
        return self.order

    def on_eCollision(self, e):
        return self.with_(bumps=self.bumps + 1)


def case_study_world():
    return vwg.World(primitives={"Robot": {"id": 0}},
                     transformations={"Move": {"dist": 0.0}, "Rotate": {"angle": 0.0}},
                     events={"go": None, "eCollision": {"other": 0},
                             "eOdometry": {"x": 0.0, "y": 0.0, "angle": 0.0, "busy": False, "commands": 0}},
                     visual=["go"], actors=[Driver])


def run(order, grid, frames=60, seed=0, motor_noise=0.0, odometry_noise=0.0):
    world = case_study_world()
    physics = _core.PhysicsWorld(grid, [RobotSettings(id=1, start=(2.0, 2.5, 0.0), radius=0.2)],
                                 PhysicsSettings(noise=NoiseModel(motors=motor_noise, odometry=odometry_noise),
                                                     seed=seed))
    gens = [vwg.Schedule({0: ["go"]}), _core.CollisionGenerator(physics, world.alphabet),
            _core.OdometryGenerator(physics, world.alphabet)]
    engine = vwg.Engine(world, f'Driver<order="{order}">', gens, _core.MotionBackend(physics), seed=seed)
    poses = []
    engine.add_observer(lambda r: poses.append(physics.robot(1).pose))
    engine.run(frames)
    return engine, physics, poses


def test_move_1_moves_the_robot_1_m():
    engine, physics, _ = run("Move<1.0>(Robot<1>)", empty_map())
    x, y, theta = physics.robot(1).pose
    assert (x, y, theta) == pytest.approx((3.0, 2.5, 0.0), abs=1e-5)
    assert not physics.robot(1).busy
    assert engine.string.actors()[0]["bumps"] == 0


def test_rotate_then_move_composes_outside_in():
    _, physics, _ = run("Rotate<1.5707963267948966>(Move<1.0>(Robot<1>))", empty_map())
    # The turn's last tick brakes within the turn acceleration: past the angle by a fraction of
    # a·dt² (4e-4 rad), which the 1 m drive carries sideways.
    assert physics.robot(1).pose == pytest.approx((2.0, 3.5, math.pi / 2), abs=1e-4)


def test_the_robot_stops_at_a_wall_and_hears_the_collision():
    engine, physics, _ = run("Move<5.0>(Robot<1>)", empty_map(wall_x=4.0), frames=150)
    assert physics.robot(1).pose[0] == pytest.approx(4.0 - 0.2, abs=0.02)
    assert not physics.robot(1).busy
    assert engine.string.actors()[0]["bumps"] >= 1


def test_odometry_events_reach_the_robot_each_frame():
    world = case_study_world()
    robots = [RobotSettings(id=1, start=(2.0, 2.5, 0.0)), RobotSettings(id=2, start=(5.0, 2.5, 0.0))]
    physics = _core.PhysicsWorld(empty_map(), robots)
    engine = vwg.Engine(world, "Driver", [_core.OdometryGenerator(physics, world.alphabet)],
                        _core.MotionBackend(physics))
    engine.step()
    events = engine.last_events
    assert [(e.type, e.target, e.x, e.y, e.busy, e.commands) for e in events] == [
        ("eOdometry", 1, 2.0, 2.5, False, 0), ("eOdometry", 2, 5.0, 2.5, False, 0)]


def test_same_seed_same_trace_with_noise():
    a = run("Rotate<0.5>(Move<2.0>(Robot<1>))", empty_map(), seed=3, motor_noise=0.05, odometry_noise=0.05)[2]
    b = run("Rotate<0.5>(Move<2.0>(Robot<1>))", empty_map(), seed=3, motor_noise=0.05, odometry_noise=0.05)[2]
    c = run("Rotate<0.5>(Move<2.0>(Robot<1>))", empty_map(), seed=4, motor_noise=0.05, odometry_noise=0.05)[2]
    assert a == b
    assert a != c


def test_bad_physics_settings_name_the_field():
    with pytest.raises(vwg.SchemaError, match="inside a wall"):
        _core.PhysicsWorld(empty_map(wall_x=2.0), [RobotSettings(id=1, start=(2.05, 2.5, 0.0))])
    with pytest.raises(vwg.SchemaError, match=r"grid\.data"):
        _core.PhysicsWorld(SimpleNamespace(data=np.zeros((3, 3)), resolution=0.1, origin=(0, 0, 0)), [])
    with pytest.raises(vwg.SchemaError, match=r"eOdometry: expected the fields \(x: real, y: real, "
                                               r"angle: real, busy: bool, commands: int\)"):
        w = vwg.World(events={"eOdometry": {"x": 0.0}})
        _core.OdometryGenerator(_core.PhysicsWorld(empty_map(), []), w.alphabet)
