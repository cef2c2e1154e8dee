"""Reciprocal avoidance in the robots (vwg/robot/avoidance.hpp): the held velocity of the motion follower against
its acceleration limits, steer() against hand-worked values and a two-robot simulation of its own, the neighbours
a robot's laser sees against the simulator's truth, the world-file key and the command line, and runs in which
robots that avoid pass each other (determinism by thread count, resumed runs, replays)."""

from __future__ import annotations

import dataclasses
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import pytest

import vwg
import vwg._core as _core
from vwg.errors import SchemaError, WorldFileError
from vwg.robot.case_study import CaseStudy
from vwg.robot.world_file import Avoidance
from vwg.trial import Trial, run_trial

ROBOT = _core.RobotSettings()  # max_speed 0.5, max_turn_rate 1.5, max_accel 1.0, max_turn_accel 4.0
SETTINGS = _core.AvoidanceSettings()  # horizon 2 s, margin 0.1 m, heading_time 0.4 s


# ---- the platform holds a velocity -----------------------------------------------------------------------------
def test_a_steer_step_is_reached_within_the_acceleration_limits_and_held():
    f = _core.MotionFollower(ROBOT)
    f.command([("steer", 0.4, 0.5)])
    seen = [f.tick((0.0, 0.0, 0.0), 0.1) for _ in range(5)]
    # 1 m/s² and 4 rad/s² over 0.1 s: +0.1 m/s and +0.4 rad/s a tick, up to what was asked.
    assert [round(v[0], 9) for v in seen] == [0.1, 0.2, 0.3, 0.4, 0.4]
    assert [round(v[1], 9) for v in seen] == [0.4, 0.5, 0.5, 0.5, 0.5]
    assert not f.busy  # nothing to finish: the velocity is held until the next command
    f.command([])
    assert [round(f.tick((0.0, 0.0, 0.0), 0.1)[0], 9) for _ in range(5)] == [0.3, 0.2, 0.1, 0.0, 0.0]


def test_a_steer_beyond_the_limits_is_clamped_to_them():
    f = _core.MotionFollower(ROBOT)
    f.command([("steer", 3.0, -9.0)])
    for _ in range(20):
        v = f.tick((0.0, 0.0, 0.0), 0.1)
    assert v == pytest.approx((0.5, -1.5))


@pytest.mark.parametrize("steps", [[("steer", 0.3)], [("steer", 0.3, 0.1, 0.0)], [("drive", 1.0, 2.0)],
                                   [("steer", 0.3, math.nan)]])
def test_malformed_steps_are_refused_saying_what_a_step_is(steps):
    f = _core.MotionFollower(ROBOT)
    with pytest.raises(SchemaError, match=r"steer|non-finite"):
        f.command(steps)


# ---- steer() -----------------------------------------------------------------------------------------------------
def test_with_no_neighbour_steer_drives_the_preferred_velocity_along_the_heading():
    # Preferred 0.5 m/s at 0.2 rad from the heading: the speed along the heading is 0.5·cos 0.2, the turn rate
    # the error over heading_time, 0.2 / 0.4 (worked out by hand).
    speed, turn = _core.steer((0.0, 0.0, 0.0), 0.5, 0.18, ROBOT, 0.2, 0.5, [], SETTINGS)
    assert speed == pytest.approx(0.5 * math.cos(0.2)) and turn == pytest.approx(0.5)
    # More than a right angle away: turn on the spot, at most max_turn_rate.
    speed, turn = _core.steer((0.0, 0.0, 0.0), 0.0, 0.18, ROBOT, 2.5, 0.5, [], SETTINGS)
    assert speed == 0.0 and turn == pytest.approx(1.5)
    # Nowhere to go: stand still.
    assert _core.steer((1.0, 2.0, 0.3), 0.0, 0.18, ROBOT, 0.3, 0.0, [], SETTINGS) == (0.0, 0.0)


def test_a_far_neighbour_changes_nothing():
    alone = _core.steer((0.0, 0.0, 0.0), 0.5, 0.18, ROBOT, 0.0, 0.5, [], SETTINGS)
    far = _core.steer((0.0, 0.0, 0.0), 0.5, 0.18, ROBOT, 0.0, 0.5, [(0.0, 20.0, 0.0, 0.0, 0.2)], SETTINGS)
    assert far == alone


def two_robots_head_on(avoid: bool, offset: float = 0.05, seconds: float = 14.0) -> float:
    """Two unicycles 6 m apart driving at each other (one a little off the line), integrated here at 0.01 s with
    velocities re-chosen every 0.1 s, each seeing the other's true position and velocity; the least distance
    between their centres."""
    poses = [[0.0, 0.0, 0.0], [6.0, offset, math.pi]]
    goals = [(6.0, offset), (0.0, 0.0)]
    speeds = [0.0, 0.0]
    commands = [(0.0, 0.0), (0.0, 0.0)]
    least = math.inf
    for tick in range(int(seconds / 0.01)):
        if tick % 10 == 0:
            for i in (0, 1):
                x, y, th = poses[i]
                gx, gy = goals[i]
                heading = math.atan2(gy - y, gx - x)
                o = poses[1 - i]
                velocity = (speeds[1 - i] * math.cos(o[2]), speeds[1 - i] * math.sin(o[2]))
                if avoid:
                    commands[i] = _core.steer((x, y, th), speeds[i], 0.18, ROBOT, heading, 0.5,
                                              [(o[0], o[1], *velocity, 0.18)], SETTINGS)
                else:
                    commands[i] = (0.5, 0.0)
        for i in (0, 1):
            v, w = commands[i]
            # Within the acceleration limit, as the platform's follower.
            speeds[i] += max(-0.01, min(0.01, v - speeds[i]))
            poses[i][2] += w * 0.01
            poses[i][0] += speeds[i] * math.cos(poses[i][2]) * 0.01
            poses[i][1] += speeds[i] * math.sin(poses[i][2]) * 0.01
        least = min(least, math.hypot(poses[0][0] - poses[1][0], poses[0][1] - poses[1][1]))
    return least


def test_two_robots_that_steer_pass_head_on_without_touching():
    # The truth is geometry: discs of 0.18 m touch below 0.36 m between centres.
    assert two_robots_head_on(avoid=False) < 0.36  # the same set-up, not avoiding, collides
    assert two_robots_head_on(avoid=True) > 0.36


# ---- what the laser sees -------------------------------------------------------------------------------------------
def head_on_office(avoidance: str = "orca", **kw) -> CaseStudy:
    """The office's two robots sent past each other along the corridor: robot 1 east to the lounge, robot 2 west
    to the office."""
    return CaseStudy(vwg.robot.load_robot_world("office"), "astar", goals={1: "lounge", 2: "office"},
                     avoidance=avoidance, **kw)


def test_the_neighbours_a_robot_sees_are_where_the_simulator_has_the_other():
    with head_on_office(threads=1) as run:
        (seer,) = [g for g in run.feedback if isinstance(g, _core.NeighbourGenerator) and g.robot == 1]
        checked = 0
        poses = [(run.sim.robot(1).pose, run.sim.robot(2).pose)]
        for _ in range(400):
            run.run(1)
            poses.append((run.sim.robot(1).pose, run.sim.robot(2).pose))
            # The tracks are of the scan gNeighbours read in this frame: the laser's of the frame before, taken
            # where the platform had the robots two steps back.
            if len(poses) < 3:
                continue
            me, other = poses[-3]
            if math.hypot(other[0] - me[0], other[1] - me[1]) > 5.0:
                continue
            # Within 5 m the other robot is one of the tracks, its centre within 0.1 m (about half its radius).
            nearest = min(math.hypot(n["x"] - other[0], n["y"] - other[1]) for n in seer.neighbours)
            assert nearest < 0.1
            checked += 1
        assert checked > 10


def seen_cells_near_the_other(avoidance: str) -> float:
    """Robot 1's seen-obstacle cells (kSeenCell) within 0.6 m of where the simulator has robot 2, a frame on average,
    over the frames the two are within 5 m of each other on the head-on run."""
    import numpy as np

    with head_on_office(avoidance, threads=1) as run:
        g = run.world.grid
        near = frames = 0
        for _ in range(300):
            run.run(1)
            me, other = run.sim.robot(1).pose, run.sim.robot(2).pose
            if math.hypot(other[0] - me[0], other[1] - me[1]) > 5.0:
                continue
            rows, cols = np.nonzero(np.asarray(run.robot_actors()[1]["grid"]) == 101)  # kSeenCell
            xs, ys = g.origin[0] + (cols + 0.5) * g.resolution, g.origin[1] + (rows + 0.5) * g.resolution
            near += int(np.sum(np.hypot(xs - other[0], ys - other[1]) < 0.6))
            frames += 1
        assert frames > 40
        return near / frames


def test_an_avoiding_robot_marks_almost_nothing_of_the_robot_it_tracks():
    # Without avoidance the laser marks the other robot where it passes (about 70 cells near it a frame); an avoiding
    # robot tracks it and leaves its returns unmarked. With one cell of slack round the tracked disc 4 % of those
    # cells were still marked (returns off a disc fitted to an arc, a frame late); with two, 0.5 % (2 % allowed).
    marked = seen_cells_near_the_other("none")
    assert marked > 20
    assert seen_cells_near_the_other("orca") < 0.02 * marked


def test_a_robot_without_a_laser_cannot_avoid_and_is_told_why():
    office = vwg.robot.load_robot_world("office")
    robots = [r.replace(sensors=["camera"]) if r.id == 2 else r for r in office.robots]
    with pytest.raises(SchemaError, match=r"avoidance: orca sees the neighbours in a robot's laser scans, and robot 2 "
                                          r"has no laser"):
        CaseStudy(dataclasses.replace(office, robots=robots), "astar", avoidance="orca")


# ---- the world file, the sweep and the command line ----------------------------------------------------------------
def office_file(tmp_path: Path, extra: str, robot2: str = "") -> Path:
    office = vwg.robot.load_robot_world("office")
    text = office.path.read_text(encoding="utf-8").replace("map: office/map.yaml",
                                                           f"map: {office.map_path.resolve()}")
    if robot2:
        text = text.replace("  - id: 2\n", f"  - id: 2\n    {robot2}\n")
    path = tmp_path / "office.yaml"
    path.write_text(text + extra, encoding="utf-8")
    return path


def test_the_world_file_key_for_all_robots_and_for_one(tmp_path):
    loaded = vwg.robot.load_robot_world(office_file(tmp_path, "avoidance: {kind: orca, horizon: 3}\n"))
    assert loaded.avoidance.kind == "orca" and loaded.avoidance.settings.horizon == 3.0
    assert loaded.avoidance.avoids(1) and loaded.avoidance.avoids(2)
    one = vwg.robot.load_robot_world(office_file(tmp_path, "", robot2="avoidance: orca"))
    assert not one.avoidance.avoids(1) and one.avoidance.avoids(2)
    with CaseStudy(one, "astar") as run:
        actors = run.robot_actors()
        assert (actors[1]["avoid"], actors[2]["avoid"]) == (False, True)


def test_bad_avoidance_in_a_world_file_is_named_at_its_line(tmp_path):
    lines = vwg.robot.load_robot_world("office").path.read_text(encoding="utf-8").count("\n")
    for extra, message in [("avoidance: rvo\n", r"avoidance: expected one of none, orca, got 'rvo'"),
                           ("avoidance: {kind: orca, horizon: -1}\n",
                            r"avoidance\.horizon: expected a finite number > 0"),
                           ("avoidance: {kind: orca, radius: 1}\n", r"avoidance\.radius: unknown key")]:
        with pytest.raises(WorldFileError, match=message) as caught:
            vwg.robot.load_robot_world(office_file(tmp_path, extra))
        assert f":{lines + 1}:" in str(caught.value)
    with pytest.raises(WorldFileError, match=r"robots\[1\]\.avoidance: expected one of none, orca, got 'yes'"):
        vwg.robot.load_robot_world(office_file(tmp_path, "", robot2="avoidance: 'yes'"))


def test_the_sweep_parameter_is_checked():
    with pytest.raises(SchemaError, match=r"params\.avoidance: expected one of none, orca, got 'rvo'"):
        Trial("office", "astar", 0, 10, {"avoidance": "rvo"})
    assert Avoidance.of("orca").avoids(7)


def test_vwg_run_with_avoidance_records_velocities_and_replays(tmp_path):
    record = tmp_path / "run.jsonl"
    done = subprocess.run([sys.executable, "-m", "vwg", "run", "office", "--avoidance", "orca", "--goal", "1:lounge",
                           "--goal", "2:office", "--frames", "60", "--allow-unreached", "--record", str(record),
                           "--quiet"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    lines = record.read_text(encoding="utf-8").splitlines()
    assert json.loads(lines[0])["world"]["avoidance"] == "orca"
    assert "eNeighbour<to=1, x=" in "".join(lines[1:-1])  # robot 1 saw robot 2
    end = json.loads(lines[-1])
    assert re.search(r"speed=0\.\d+, turn_rate=[-0-9.e]+>", end["string"])  # moving, with the velocity it was given
    replayed = subprocess.run([sys.executable, "-m", "vwg", "replay", str(record)], capture_output=True, text=True,
                              timeout=300)
    assert replayed.returncode == 0, replayed.stdout + replayed.stderr
    bad = subprocess.run([sys.executable, "-m", "vwg", "run", "office", "--avoidance", "rvo"], capture_output=True,
                         text=True, timeout=60)
    assert bad.returncode == 2 and "invalid choice: 'rvo'" in bad.stderr


# ---- runs ----------------------------------------------------------------------------------------------------------
def test_robots_that_avoid_pass_each_other_in_the_corridor():
    with head_on_office(threads=1) as run:
        summary = run.run(1500)
    assert summary.reached and summary.collisions == 0


def test_avoiding_robots_give_the_same_frames_on_one_and_two_threads():
    strings = []
    for threads in (1, 2):
        with head_on_office(threads=threads, seed=4) as run:
            run.run(150)
            strings.append(str(run.engine.string))
    assert strings[0] == strings[1]


def test_a_run_with_avoidance_resumes_as_it_went_on(tmp_path):
    # The trackers and the held velocities are in the state: the frames after a resume are those of the run that
    # went on.
    world = vwg.load(office_file(tmp_path, "avoidance: orca\n"))
    options = {"goals": ["1:lounge", "2:office"], "allow_unreached": True}
    with vwg.start(world, vwg.RunOptions(frames=60, **options)) as run:
        run.execute()
        saved = run.save_state()
    with vwg.start(world, vwg.RunOptions(frames=120, **options)) as whole:
        whole.execute()
        expected = str(whole.engine.string)
    with vwg.resume(saved, vwg.RunOptions(frames=60, allow_unreached=True)) as again:
        again.execute()
        assert again.engine.frame == 120 and str(again.engine.string) == expected


def warehouse_eight(seed: int, avoidance: str) -> dict:
    return run_trial(Trial(world="warehouse", planner="astar", seed=seed, frames=3000,
                           params={"task": "random", "robots": 8, "avoidance": avoidance}))


@pytest.mark.slow
def test_eight_robots_in_the_warehouse_collide_far_less_and_arrive():
    # The held-out check, on seeds of its own: with ORCA at most a fifth of the collisions without it, and
    # at least 90 % of the robots in their rooms.
    seeds = (10, 11, 12)
    plain = [warehouse_eight(s, "none") for s in seeds]
    orca = [warehouse_eight(s, "orca") for s in seeds]
    assert not any(r["error"] for r in plain + orca)
    collisions = (sum(r["collisions"] for r in orca), sum(r["collisions"] for r in plain))
    assert collisions[0] <= collisions[1] / 5, collisions
    reached = sum(r["reached_robots"] for r in orca) / sum(r["robots"] for r in orca)
    assert reached >= 0.9, reached
