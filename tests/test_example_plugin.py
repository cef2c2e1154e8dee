"""examples/plugin (vwg-example-plugin): a package outside vwg whose sensor (sonar), platform (kinematic)
and decider (wall-follower) are registered only by its entry points. Installed with pip into a folder of
its own, it is listed by ``vwg plugins`` and its world runs from the command line; in process, each part
against values worked out by hand."""

from __future__ import annotations

import dataclasses
import importlib.util
import json
import math
import shutil
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import vwg
import vwg._core as _core
from conftest import ROOT, pip_install_apart
from vwg.errors import SchemaError, WorldFileError
from vwg.plugins import deciders, platforms, sensors
from vwg.robot import RobotSettings
from vwg.robot.case_study import CaseStudy
from vwg.robot.platforms.sim import MOTION_SYMBOLS, SIM_EVENTS, Simulation
from vwg.robot.world_file import PlatformSpec

PLUGIN = ROOT / "examples" / "plugin"


def _import_plugin() -> None:
    """The package imported from its sources, without putting examples/plugin on sys.path: a build
    left there (its .egg-info) would register the plugin's entry points in every test of the session."""
    package = PLUGIN / "vwg_example_plugin"
    spec = importlib.util.spec_from_file_location("vwg_example_plugin", package / "__init__.py",
                                                  submodule_search_locations=[str(package)])
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("vwg_example_plugin", module)
    if sys.modules["vwg_example_plugin"] is module:
        spec.loader.exec_module(module)


_import_plugin()
from vwg_example_plugin.kinematic import Kinematic, KinematicRobots  # noqa: E402
from vwg_example_plugin.sonar import Sonar, SonarGenerator, SonarSettings  # noqa: E402
from vwg_example_plugin.wall_follower import WallFollower  # noqa: E402

RES = 0.05


def wall_map(wall_x: float = 4.0) -> SimpleNamespace:
    """A 10 m × 5 m map of 0.05 m cells, free but for a wall whose face is at x = wall_x."""
    data = np.zeros((100, 200), np.int8)
    data[:, round(wall_x / RES)] = 100
    return SimpleNamespace(data=data, resolution=RES, origin=(0.0, 0.0, 0.0))


def sonar_events(grid: SimpleNamespace, pose: tuple[float, float, float], **settings: object) -> \
        tuple[SonarGenerator, dict[float, float]]:
    """One frame of a sonar on the simulator's physics, robot 7 at `pose`: the generator, and its events
    as {angle: dist}."""
    alphabet = vwg.Alphabet(events=SIM_EVENTS, **MOTION_SYMBOLS)
    physics = _core.PhysicsWorld(grid, [RobotSettings(id=7, start=pose)])
    sonar = SonarGenerator(physics, _core.GridRaycaster(grid), 7, SonarSettings(**settings))
    engine = vwg.Engine(vwg.World(alphabet), "Robot<7>", [sonar])
    engine.step()
    events = engine.last_events
    assert {(e.type, e.target) for e in events} <= {("eLaser", 7)}
    return sonar, {round(e.fields["angle"], 9): e.fields["dist"] for e in events}


# ---- the sonar ----------------------------------------------------------------------------------------------
def test_sonar_ranges_to_a_wall_ahead_by_hand() -> None:
    # From (1, 2.5) facing the wall 3 m ahead: the beam ahead meets it square on (3 m); the beams at
    # ±45° see its nearest point through their cones' near edges, at ±30°: 3 / cos 30°. The others
    # (90° and more) meet nothing within 5 m: no event.
    sonar, events = sonar_events(wall_map(), (1.0, 2.5, 0.0), max_range=5.0)
    slant = 3.0 / math.cos(math.radians(30.0))
    assert sonar.angles == pytest.approx(np.radians([0, 45, 90, 135, -180, -135, -90, -45]))
    assert events == pytest.approx({0.0: 3.0, round(math.pi / 4, 9): slant, round(-math.pi / 4, 9): slant},
                                   abs=1e-5)
    assert sonar.ranges.tolist() == pytest.approx([3.0, slant, 5, 5, 5, 5, 5, slant], abs=1e-5)
    # Nothing within max_range: the beam ahead is silent too.
    _, far = sonar_events(wall_map(), (1.0, 2.5, 0.0), max_range=2.5)
    assert far == {}


def test_a_wall_at_an_angle_within_the_cone_is_seen_at_its_nearest_point() -> None:
    # Heading 15° to the right of the wall's normal: the normal lies on the cone's edge (its rays span
    # ±15°), so the beam ahead hears the wall's nearest point, 3 m, where a single ray along the beam's
    # centre would read 3 / cos 15°.
    turned = (1.0, 2.5, -math.radians(15.0))
    sonar, events = sonar_events(wall_map(), turned, max_range=5.0)
    assert sonar.ranges[0] == pytest.approx(3.0, abs=1e-5) and events[0.0] == pytest.approx(3.0, abs=1e-5)
    ray, _ = sonar_events(wall_map(), turned, max_range=5.0, rays=1)
    assert ray.ranges[0] == pytest.approx(3.0 / math.cos(math.radians(15.0)), abs=1e-5)
    # 25° off: the normal is outside the cone; its nearest ray is the edge, 10° off the normal.
    off, _ = sonar_events(wall_map(), (1.0, 2.5, -math.radians(25.0)), max_range=5.0)
    assert off.ranges[0] == pytest.approx(3.0 / math.cos(math.radians(10.0)), abs=1e-5)
    # A narrower cone (10°: edges at ±5°) from the 15° heading: its edge ray is 10° off the normal.
    narrow, _ = sonar_events(wall_map(), turned, max_range=5.0, cone=math.radians(10.0), rays=3)
    assert narrow.ranges[0] == pytest.approx(3.0 / math.cos(math.radians(10.0)), abs=1e-5)


def test_sonar_settings_check_names_the_field() -> None:
    SonarSettings().check("sensors.sonar")  # the defaults pass
    bad = {"beams": 0, "cone": 0.0, "rays": 0, "min_range": -0.1, "max_range": 0.01}
    for name, value in bad.items():
        with pytest.raises(SchemaError, match=rf"^sensors\.sonar\.{name}: expected ") as caught:
            SonarSettings(**{name: value}).check("sensors.sonar")
        assert caught.value.field == f"sensors.sonar.{name}"
    with pytest.raises(SchemaError, match=r"^sensors\.sonar\.cone: expected .*\(0, π\]"):
        SonarSettings(cone=4.0).check("sensors.sonar")
    with pytest.raises(SchemaError, match=r"^sonar\.beams: expected int"):
        SonarSettings(beams=2.5).check("sonar")  # type: ignore[arg-type]
    assert [f[0] for f in SonarSettings.fields()] == ["beams", "cone", "rays", "min_range", "max_range"]
    assert SonarSettings().cone == pytest.approx(math.pi / 6) and SonarSettings().beams == 8


@pytest.fixture
def registered():
    """The plugin's sensor, platform and decider registered in process (as its entry points register
    them once installed), removed afterwards."""
    parts = ((sensors, "sonar", Sonar), (platforms, "kinematic", Kinematic), (deciders, "wall-follower", WallFollower))
    added = [(r, name) for r, name, part in parts if name not in r and r.register(name, part)]
    yield
    for registry, name in added:
        registry.unregister(name)


def test_a_world_file_s_sonar_section_is_checked_by_its_settings(registered, tmp_path: Path) -> None:
    world = (PLUGIN / "world.yaml").read_text().replace("../../maps", str(ROOT / "maps"))
    good = tmp_path / "good.yaml"
    good.write_text(world)
    loaded = vwg.robot.load_robot_world(good)
    assert loaded.sensor_settings("sonar") == SonarSettings(cone=math.pi / 6, rays=7, max_range=3.0)
    assert loaded.platform.kind == "kinematic"
    bad = tmp_path / "bad.yaml"
    bad.write_text(world.replace("rays: 7", "rays: 0"))
    line = 1 + world.splitlines().index(next(t for t in world.splitlines() if t.startswith("  sonar:")))
    with pytest.raises(WorldFileError, match=rf"bad\.yaml:{line}: sensors\.sonar\.rays: expected 1 to 100 rays a "
                                             "cone, got 0"):
        vwg.robot.load_robot_world(bad)


def test_the_sonar_rides_the_simulator_and_the_kinematic_platform_alike(registered) -> None:
    world = vwg.robot.load_robot_world(ROOT / "maps" / "maze.yaml")
    alphabet = vwg.Alphabet(events=SIM_EVENTS, **MOTION_SYMBOLS)
    sonar = Sonar(SonarSettings(max_range=6.0))
    on_sim = sonar.make(Simulation(world), alphabet, 1)
    on_kinematic = sonar.make(Kinematic(world, 0, {}), alphabet, 1)
    assert isinstance(on_sim, SonarGenerator) and isinstance(on_kinematic, SonarGenerator)
    assert on_sim.generate(None)  # the maze's walls are near: it hears some
    on_kinematic.generate(None)
    np.testing.assert_array_equal(on_sim.ranges, on_kinematic.ranges)
    assert sonar.make(SimpleNamespace(platform=None), alphabet, 1) is None  # no map to cast on: not carried


# ---- the kinematic platform --------------------------------------------------------------------------------
def drive(platform: KinematicRobots, frames: int = 200, dt: float = 0.1) -> int:
    """Frames of dt until robot 1 is done (at most `frames`): how many."""
    for frame in range(1, frames + 1):
        platform.advance(dt)
        if not platform.robot(1).busy:
            return frame
    return frames


def test_kinematic_pose_after_a_turn_then_a_drive_by_hand() -> None:
    platform = KinematicRobots([RobotSettings(id=1, start=(2.0, 3.0, 0.0))])
    assert platform.name() == "kinematic" and platform.robot(1).pose == (2.0, 3.0, 0.0)
    platform.command(1, [("turn", math.pi / 2), ("drive", 1.0)])
    assert platform.robot(1).busy and platform.robot(1).commands == 1
    frames = drive(platform)
    state = platform.robot(1)
    # A quarter turn left, then 1 m: from (2, 3) facing +x to (2, 4) facing +y (within the follower's 0.01).
    assert state.pose == pytest.approx((2.0, 4.0, math.pi / 2), abs=0.011)
    assert state.odometry == state.pose and not state.busy and frames < 200
    assert state.travelled == pytest.approx(1.0, abs=0.011)  # the metres driven; the turn adds none
    assert platform.time() == pytest.approx(frames * 0.1)
    assert platform.take_collisions() == []
    # Driving back 1 m adds 1 m: travelled counts distance, not displacement.
    platform.command(1, [("drive", -1.0)])
    drive(platform)
    assert platform.robot(1).pose[:2] == pytest.approx((2.0, 3.0), abs=0.02)
    assert platform.robot(1).travelled == pytest.approx(2.0, abs=0.02)


def test_slip_makes_the_robot_fall_short_of_its_odometry() -> None:
    platform = KinematicRobots([RobotSettings(id=1, start=(2.0, 3.0, 0.0))], slip=0.25)
    platform.command(1, [("turn", math.pi / 2), ("drive", 1.0)])
    drive(platform)
    state = platform.robot(1)
    # The odometry counts the whole motion; the robot made three quarters of each: 3π/8, then 0.75 m.
    assert state.odometry == pytest.approx((2.0, 4.0, math.pi / 2), abs=0.011)
    heading = 3 * math.pi / 8
    assert state.pose == pytest.approx((2.0 + 0.75 * math.cos(heading), 3.0 + 0.75 * math.sin(heading), heading),
                                       abs=0.011)
    assert state.travelled == pytest.approx(0.75, abs=0.011)


def test_kinematic_robots_come_and_go_and_bad_options_are_named() -> None:
    platform = KinematicRobots([RobotSettings(id=1, start=(1.0, 1.0, 0.0))])
    platform.add_robot(RobotSettings(id=4, start=(3.0, 1.0, math.pi)))
    assert [r.id for r in platform.robots()] == [1, 4]
    with pytest.raises(SchemaError, match="robot 4: the id is used twice"):
        platform.add_robot(RobotSettings(id=4, start=(5.0, 1.0, 0.0)))
    platform.remove_robot(1)
    with pytest.raises(SchemaError, match="no robot with id 1"):
        platform.command(1, [("drive", 1.0)])
    with pytest.raises(SchemaError, match=r"platform\.slip: expected a number <= 1"):
        Kinematic.check_options({"slip": 1.5})
    with pytest.raises(SchemaError, match=r"unknown option\(s\) friction"):
        Kinematic.check_options({"friction": 0.1})
    assert Kinematic.check_options({}) == {"slip": 0.0, "step": 0.01}


def test_the_laser_on_the_kinematic_platform_gives_the_simulator_s_events(registered) -> None:
    # The same pose on the same map: vwg's laser cast from the kinematic platform's pose and the
    # simulator's (noiseless) laser give the same events (one robot: nothing else to see).
    world = vwg.robot.load_robot_world(ROOT / "maps" / "maze.yaml").with_sensor("laser", noise=0.0, beams=90)
    alphabet = vwg.Alphabet(events=SIM_EVENTS, **MOTION_SYMBOLS)
    events = []
    for platform in (Simulation(world), Kinematic(world, 0, {})):
        engine = vwg.Engine(vwg.World(alphabet), "Robot<1>", platform.make_sensors(alphabet, ("laser",)))
        engine.step()
        events.append([(e.target, e.fields["dist"], e.fields["angle"]) for e in engine.last_events])
    assert len(events[0]) > 20 and len(events[1]) == len(events[0])
    # The same to a float32 ulp or so (the beams' angles are laid out in Python here, in C++ there).
    np.testing.assert_allclose(np.array(events[1]), np.array(events[0]), rtol=0, atol=1e-6)


def test_travelled_is_the_length_of_the_path_the_robot_drove(registered) -> None:
    world = vwg.robot.load_robot_world(ROOT / "maps" / "maze.yaml")
    world = dataclasses.replace(world, platform=PlatformSpec("kinematic"))
    with CaseStudy(world, WallFollower(), goals={1: "dead_end_1_0"}, sensors=("laser",)) as run:
        assert isinstance(run.sim, Kinematic)
        # The path summed pose to pose, frame by frame (a second reckoning of the distance).
        last, summed = run.sim.robot(1).pose, 0.0
        for _ in range(400):
            run.run(frames=1)
            pose = run.sim.robot(1).pose
            summed += math.hypot(pose[0] - last[0], pose[1] - last[1])
            last = pose
        summary = run.summary()
    assert summed > 5.0
    # Frame to frame the robot turns on the spot or drives straight: the chords are the path.
    assert summary.path_length_m == pytest.approx(summed, rel=1e-3)


# ---- the wall follower ----------------------------------------------------------------------------------------
def decide(cells: np.ndarray, x: float, y: float, angle: float, goal: tuple[float, float]) -> tuple[float, float]:
    """The (turn, move) the wall follower decides for a robot at (x, y, angle) whose map is `cells`
    (0.1 m cells, row 0 at the bottom), its room's goal at `goal`, its radius with clearance 0.25 m."""
    rows, cols = cells.shape
    geometry = SimpleNamespace(data=np.zeros((rows, cols), np.int8), resolution=0.1, origin=(0.0, 0.0, 0.0))
    events = {n: {f: spec[1] for f, spec in fields.items()} for n, fields in _core.arobot_event_types().items()}
    alphabet = vwg.Alphabet(events=events, visual=["eExecute"], **MOTION_SYMBOLS)
    decider = WallFollower()  # kept while it decides: ARobot holds the C++ side only
    _core.add_arobot(alphabet, decider, geometry, {3: goal}, radius=0.2, margin=0.05, goal_tolerance=0.25,
                     step_length=1.0)
    world = vwg.World(alphabet)
    w = world.string(vwg.Sym("ARobot", id=1, grid=vwg.Blob(cells), row=int(y / 0.1), column=int(x / 0.1),
                             angle=angle, x=x, y=y, objective=3))
    (robot,) = _core.evolve(w, [world.event("eDecide<to=1>")]).actors()
    assert robot["acting"], robot["status"]
    return robot["turn"], robot["move"]


def corridor(wall_until: float = 4.0) -> np.ndarray:
    """A 4 m × 4 m map: a wall along the bottom (y in [0.5, 0.6)) from x = 0 to `wall_until`, and a wall
    across the way (x in [3.0, 3.1)) from it to the top; the goal, at (3.55, 1.05), is behind it."""
    cells = np.zeros((40, 40), np.int16)
    cells[5, :round(wall_until / 0.1)] = 100
    cells[6:, 30] = 100
    return cells


GOAL = (3.55, 1.05)


def test_the_wall_follower_goes_straight_to_a_goal_it_can_see() -> None:
    cells = np.zeros((40, 40), np.int16)
    # 2 m ahead: it turns to it and drives a step (1 m); one up and to the left: turns toward it.
    assert decide(cells, 1.05, 1.05, 0.0, (3.05, 1.05)) == pytest.approx((0.0, 1.0))
    assert decide(cells, 1.05, 1.05, 0.0, (0.55, 1.55)) == pytest.approx((3 * math.pi / 4, math.hypot(0.5, 0.5)))
    assert decide(cells, 1.05, 1.05, math.pi, (1.05, 3.05)) == pytest.approx((-math.pi / 2, 1.0))


def test_the_wall_follower_keeps_the_wall_on_its_right() -> None:
    # The wall 0.45 m to its right, the way ahead clear: straight on, a stride (0.5 m).
    assert decide(corridor(), 1.05, 1.05, 0.0, GOAL) == pytest.approx((0.0, 0.5))
    # At (2.70, 1.05) the wall across the way (face x = 3.0) is 0.30 m ahead: not even a quarter stride
    # keeps 0.25 m from it (2.825 + 0.25 > 3.0). It turns away from it, left; 0.5 m up is clear.
    assert decide(corridor(), 2.70, 1.05, 0.0, GOAL) == pytest.approx((math.pi / 2, 0.5))
    # No wall within 1 m on its right (facing +y at x = 1.05, y = 2.5: the nearest is 2 m away): straight on.
    assert decide(corridor(), 1.05, 2.55, math.pi / 2, GOAL) == pytest.approx((0.0, 0.5))


def test_the_wall_follower_turns_right_where_its_wall_ends() -> None:
    # The bottom wall ends at x = 1.2, 0.35 m behind the robot at (1.55, 1.05): nothing beside it on the
    # right (its rays 80° to 100° right meet y = 0.6 at x >= 1.47), the wall behind it on the right (the
    # ray 135° right meets it at x = 1.10, 0.64 m away). It turns right, round the wall's end: 0.5 m
    # down keeps 0.35 m from the end's corner (1.2, 0.6).
    assert decide(corridor(wall_until=1.2), 1.55, 1.05, 0.0, GOAL) == pytest.approx((-math.pi / 2, 0.5))


def test_a_wall_follower_closer_to_a_wall_than_its_clearance_backs_away() -> None:
    # 0.15 m above the wall's face (its clearance is 0.25 m): every move is refused; it backs away from
    # the nearest wall cell, straight below it (centre (1.05, 0.55)), by half a cell.
    assert decide(corridor(), 1.05, 0.75, 0.0, GOAL) == pytest.approx((math.pi / 2, 0.05))


# ---- installed with pip, from the command line --------------------------------------------------------------
@pytest.mark.slow
def test_the_installed_plugin_is_listed_and_its_world_runs_from_the_command_line(tmp_path: Path) -> None:
    # Built from a copy: pip builds in the source folder, and leaves build/ and .egg-info/ there.
    source = shutil.copytree(PLUGIN, tmp_path / "plugin", ignore=shutil.ignore_patterns("build", "*.egg-info",
                                                                                        "__pycache__"))
    env = pip_install_apart(source, tmp_path / "installed")
    cli = [sys.executable, "-m", "vwg.cli"]
    listed = subprocess.run([*cli, "plugins"], env=env, capture_output=True, text=True, check=True).stdout
    for name, group, value in (("sonar", "vwg.sensors", "vwg_example_plugin.sonar:Sonar"),
                               ("kinematic", "vwg.platforms", "vwg_example_plugin.kinematic:Kinematic"),
                               ("wall-follower", "vwg.deciders", "vwg_example_plugin.wall_follower:WallFollower")):
        section = listed.split(f"{group}:")[1].split("\nvwg.")[0]
        assert f"{name} " in section and f"vwg-example-plugin 0.1 (entry point {value})" in section, listed
    summary = tmp_path / "summary.json"
    # The world names the plugin's decider (planner: wall-follower) and platform; nothing else is said.
    run = subprocess.run([*cli, "run", str(PLUGIN / "world.yaml"), "--frames", "2500",
                          "--summary-json", str(summary), "-q"], env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    result = json.loads(summary.read_text())
    robot = result["robots"][0]
    # It followed the maze's walls to the dead end (about 45 m), driving the kinematic platform.
    assert result["reached"] and robot["room"] == "dead_end_8_1" and result["planner"] == "wall-follower"
    assert robot["path_length_m"] > 30.0 and robot["collisions"] == 0
