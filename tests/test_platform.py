"""The robot platform: the motion backend and the feedback generators know only RobotPlatform, so a
platform written in Python (as a real robot's link can be) runs the same world string as the
simulator; the simulator adds and removes robots while it runs."""

from __future__ import annotations

import math

import pytest
from test_sim import case_study_world, empty_map

import vwg
from vwg import _core
from vwg.robot import RobotSettings


class Kinematic(vwg.robot.RobotPlatform):
    """A platform that executes every step exactly and at once when time passes: turn, then drive,
    in the robot's frame. Records what it was told."""

    def __init__(self) -> None:
        super().__init__()
        self.poses: dict[int, tuple[float, float, float]] = {}
        self.pending: dict[int, list[tuple[str, float]]] = {}
        self.commands: dict[int, int] = {}
        self.clock = 0.0
        self.told: list[tuple[int, list[tuple[str, float]]]] = []

    def add_robot(self, settings):
        self.poses[settings.id] = settings.start
        self.commands[settings.id] = 0

    def remove_robot(self, id):
        del self.poses[id]

    def command(self, robot, steps):
        self.told.append((robot, steps))
        self.pending[robot] = list(steps)
        self.commands[robot] += 1

    def advance(self, seconds):
        self.clock += seconds
        for robot, steps in self.pending.items():
            x, y, a = self.poses[robot]
            for kind, amount in steps:
                if kind == "turn":
                    a += amount
                else:
                    x, y = x + amount * math.cos(a), y + amount * math.sin(a)
            self.poses[robot] = (x, y, a)
        self.pending.clear()

    def robots(self):
        return [vwg.robot.RobotState(i, p, commands=self.commands[i]) for i, p in sorted(self.poses.items())]

    def take_collisions(self):
        return []

    def time(self):
        return self.clock

    def name(self):
        return "kinematic"


class Listener(vwg.Actor):
    """Shows Rotate<π/2>(Move<1>(Robot<1>)) when told to go; remembers its odometry."""

    events = ("go", "eOdometry")
    attributes = {"id": 1, "x": 0.0, "y": 0.0}

    def show_go(self, e):
        return vwg.Sym("Rotate", math.pi / 2)(vwg.Sym("Move", 1.0)(vwg.Sym("Robot", 1)))

    def on_eOdometry(self, e):
        return self.with_(x=e.x, y=e.y)


def test_a_python_platform_runs_the_world_string_through_the_motion_backend():
    platform = Kinematic()
    platform.add_robot(RobotSettings(id=1, start=(2.0, 3.0, 0.0)))
    sim = vwg.robot.platforms.sim
    world = vwg.World(**sim.MOTION_SYMBOLS, events={"go": None, "eOdometry": sim.SIM_EVENTS["eOdometry"]},
                      visual=["go"], actors=[Listener])
    feedback = vwg.robot.OdometryGenerator(platform, world.alphabet)
    engine = vwg.Engine(world, "Listener", [vwg.Schedule({0: ["go"]}), feedback],
                        vwg.robot.MotionBackend(platform), dt=0.5)
    engine.run(2)
    # Turn a quarter to the left, then 1 m: from (2, 3) facing +x to (2, 4) facing +y.
    assert platform.told == [(1, [("turn", pytest.approx(math.pi / 2)), ("drive", 1.0)])]
    assert platform.poses[1] == pytest.approx((2.0, 4.0, math.pi / 2))
    assert platform.clock == pytest.approx(1.0)  # each frame let dt pass on the platform
    actor = engine.string.actors()[0]
    assert (actor["x"], actor["y"]) == pytest.approx((2.0, 4.0))  # odometry came back as events


def test_the_simulator_adds_and_removes_robots_while_running():
    physics = _core.PhysicsWorld(empty_map(), [RobotSettings(id=1, start=(2.0, 2.5, 0.0))])
    assert isinstance(physics, vwg.robot.RobotPlatform) and physics.name() == "sim"
    physics.add_robot(RobotSettings(id=7, start=(5.0, 2.5, math.pi), radius=0.2))
    with pytest.raises(vwg.SchemaError, match="used twice"):
        physics.add_robot(RobotSettings(id=7, start=(8.0, 2.5, 0.0)))
    with pytest.raises(vwg.SchemaError, match="overlaps robot 7"):
        physics.add_robot(RobotSettings(id=8, start=(5.1, 2.5, 0.0)))
    physics.command(7, [("drive", 1.0)])
    physics.advance(5.0)
    x, y, yaw = physics.robot(7).pose
    assert (x, y, math.cos(yaw)) == pytest.approx((4.0, 2.5, -1.0), abs=1e-4)  # 1 m towards -x
    assert [r.id for r in physics.robots()] == [1, 7]
    physics.remove_robot(1)
    assert [r.id for r in physics.robots()] == [7]
    with pytest.raises(vwg.SchemaError, match="no robot with id 1"):
        physics.command(1, [("drive", 1.0)])
    physics.command(7, [("drive", 1.0)])  # the others go on
    physics.advance(5.0)
    assert physics.robot(7).pose[0] == pytest.approx(3.0, abs=1e-4)


def test_motion_backend_drives_the_simulator_as_before():
    world = case_study_world()
    physics = _core.PhysicsWorld(empty_map(), [RobotSettings(id=1, start=(2.0, 2.5, 0.0), radius=0.2)])
    engine = vwg.Engine(world, 'Driver<order="Rotate<1.5707963267948966>(Move<1.0>(Robot<1>))">',
                        [vwg.Schedule({0: ["go"]})], vwg.robot.MotionBackend(physics))
    engine.run(80)
    assert physics.robot(1).pose == pytest.approx((2.0, 3.5, math.pi / 2), abs=1e-4)


class Spawner(vwg.Actor):
    """On its first eDecide, spawns robot 3 at (12, 9) beside itself (a λ that returns two actors)."""

    events = ("eDecide",)
    attributes = {"grid": vwg.Blob, "left": 1}

    def on_eDecide(self, e):
        if self.left == 0:
            return self
        return [self.with_(left=0), vwg.Sym("ARobot", id=3, grid=self.grid, x=12.0, y=9.0, angle=0.0)]


def test_robots_spawned_by_a_lambda_get_a_body_and_those_gone_lose_it():
    from vwg.robot.case_study import CaseStudy

    run = CaseStudy(vwg.robot.load_robot_world("office"), "astar", sensors=())
    run.vworld.alphabet.add_actor_type(Spawner)
    initial = run.initial_string()
    run.engine.set_string(run.vworld.string(initial, vwg.Sym("Spawner", grid=_core.robot_map(run.world.grid))))
    run.run(frames=2)
    assert [r.id for r in run.sim.platform.robots()] == [1, 2, 3]
    assert run.sim.platform.robot(3).pose[:2] == pytest.approx((12.0, 9.0), abs=1e-3)
    run.engine.set_string(initial)  # robot 3 (and the spawner) leave the string
    run.run(frames=1)
    assert [r.id for r in run.sim.platform.robots()] == [1, 2]


def _office(feedback: str) -> vwg.robot.RobotWorld:
    """The office with every simulated sensor on both robots, and the feedback asked for (odometry alone, particles,
    or ORCA's neighbours)."""
    import dataclasses

    from vwg.robot.world_file import Avoidance, Localization

    world = vwg.robot.load_robot_world("office")
    robots = [RobotSettings(id=r.id, start=r.start, radius=r.radius, sensors=("laser", "kinect", "camera"))
              for r in world.robots]
    world = dataclasses.replace(world, robots=robots)
    if feedback == "particles":
        world = dataclasses.replace(world, localization=Localization.of("particles"))
    if feedback == "orca":
        world = dataclasses.replace(world, avoidance=Avoidance.of("orca"))
    return world


@pytest.mark.parametrize("feedback", ["odometry", "particles", "orca"])
def test_a_robot_that_leaves_the_string_leaves_its_sensors_quiet(feedback, tmp_path):
    # Robot 2's laser, depth camera, camera (and its particle filter, or its neighbour tracker) were made for it at
    # the start; once a λ takes it out of the string its body is gone, and they emit nothing (they made the next
    # frame fail, looking for the body). Robot 1 goes on as before, and the view, which draws the scans, draws on.
    from vwg.robot.case_study import CaseStudy

    world = _office(feedback)
    run = CaseStudy(world, "astar", images=tmp_path)
    run.run(frames=2)
    spec = world.robots[0]
    alone = run.vworld.string(vwg.Sym("ARobot", id=1, grid=_core.robot_map(world.grid), x=spec.start[0],
                                      y=spec.start[1], angle=spec.start[2], avoid=feedback == "orca"))
    run.engine.set_string(alone)
    targets: list[tuple[int, str, int]] = []
    run.engine.add_observer(lambda r: targets.extend((r.frame, e.type, e.target) for e in r.events))
    summary = run.run(frames=4)
    assert [r.id for r in run.sim.platform.robots()] == [1]
    assert run.sim.platform.find_robot(2) is None and run.sim.platform.find_robot(1).id == 1
    # The frame that took robot 2 out of the string (frame 2) still had its events; none after it.
    assert not [t for t in targets if t[0] > 2 and t[2] == 2]
    for frame in (3, 4, 5):
        assert {e for f, e, to in targets if f == frame and to == 1} >= {"eOdometry", "eLaser"}
    assert [(r.id, r.status) for r in summary.robots if r.id == 2] == [(2, "gone")]
    assert len(list(tmp_path.glob("*.png"))) == 6  # one picture a frame, frames 0-5


def test_a_robot_spawned_under_particle_localization_gets_its_odometry():
    # Robots 1 and 2 are localized by their particle filters; robot 3, spawned by a λ, has no filter: its pose is
    # its odometry, one eOdometry a frame, and robots 1 and 2 still get one each (their filters'), not two.
    from vwg.robot.case_study import CaseStudy

    world = _office("particles")
    run = CaseStudy(world, "astar", sensors=("laser",))
    run.vworld.alphabet.add_actor_type(Spawner)
    initial = run.initial_string()
    run.engine.set_string(run.vworld.string(initial, vwg.Sym("Spawner", grid=_core.robot_map(run.world.grid))))
    odometry: list[tuple[int, int]] = []
    run.engine.add_observer(lambda r: odometry.extend((r.frame, e.target) for e in r.events if e.type == "eOdometry"))
    run.run(frames=6)
    assert [r.id for r in run.sim.platform.robots()] == [1, 2, 3]
    # Robot 3's body is made after frame 0 (the λ ran in it): from frame 1 on, each robot has one eOdometry a frame.
    assert sorted(odometry) == sorted([(0, 1), (0, 2)] + [(f, r) for f in range(1, 6) for r in (1, 2, 3)])
    # Its odometry is where its body is (it has not been told to move).
    robot3 = run.robot_actors()[3]
    assert (float(robot3["x"]), float(robot3["y"])) == pytest.approx((12.0, 9.0), abs=1e-3)
