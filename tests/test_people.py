"""People who walk (vwg/sim/people.hpp): the social force against hand-computed pushes, walks along waypoints, what
the sensors and the robots' maps make of people, the world-file key and the sweep parameter, determinism and resumed
runs, and robots that avoid reaching their rooms among people."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import vwg
import vwg._core as _core
from vwg.errors import SchemaError, WorldFileError
from vwg.robot.case_study import CaseStudy
from vwg.robot.world_file import Person
from vwg.trial import Trial, run_trial

SOCIAL = _core.SocialForceSettings()  # people A 2.1, B 0.3; robots A 3.0, B 0.5; walls A 5.0, B 0.1; reach 3 m


# ---- the social force -----------------------------------------------------------------------------------------------
def test_the_push_of_another_person_by_hand():
    # 2.1·exp((0.25 + 0.25 − 1)/0.3) = 2.1·e^(−5/3) = 0.396639, away from the other (worked out by hand).
    fx, fy = _core.social_push((0.0, 0.0, 0.25), (1.0, 0.0, 0.25), 2.1, 0.3, 3.0)
    assert fx == pytest.approx(-0.396639, abs=1e-6) and fy == 0.0
    # Along a diagonal: the same size, split along it.
    fx, fy = _core.social_push((0.0, 0.0, 0.25), (-0.6, -0.8, 0.25), 2.1, 0.3, 3.0)
    assert (fx, fy) == pytest.approx((0.6 * 0.396639, 0.8 * 0.396639), abs=1e-6)
    assert _core.social_push((0.0, 0.0, 0.25), (3.5, 0.0, 0.25), 2.1, 0.3, 3.0) == (0.0, 0.0)  # beyond reach


def open_floor(wall_column: int | None = None) -> _core.OccupancyGrid:
    """A 10 × 10 m floor of 0.05 m cells, free, with a wall along column `wall_column` if given."""
    data = np.zeros((200, 200), np.int8)
    if wall_column is not None:
        data[:, wall_column] = 100
    return _core.OccupancyGrid(data, 0.05, (0.0, 0.0, 0.0))


def test_gsocial_sums_a_robot_s_push_and_a_wall_s_by_hand():
    robot = _core.RobotSettings(id=1, start=(5.0, 5.0, 0.0))
    world = _core.PhysicsWorld(open_floor(), [robot], _core.PhysicsSettings())
    world.set_person(1, 6.0, 5.0, 0.0, 0.0, 0.25)  # 1 m east of the robot, standing: no sidestep
    # The robot: 3.0·exp((0.25 + 0.18 − 1)/0.5) = 3·e^(−1.14) = 0.959457, east; the floor's edge is 4 m away.
    fx, fy = _core.social_force(world, 1, SOCIAL)
    assert fx == pytest.approx(0.959457, abs=1e-5) and fy == pytest.approx(0.0, abs=1e-9)
    # A wall whose cells start at x = 2.0 m (column 40), the person 0.5 m east of it: 5·exp((0.25 − 0.5)/0.1)
    # = 5·e^(−2.5) = 0.410425, east (no robot this time).
    walled = _core.PhysicsWorld(open_floor(wall_column=39), [_core.RobotSettings(id=1, start=(8.0, 8.0, 0.0))],
                                _core.PhysicsSettings())
    walled.set_person(1, 2.5, 5.0, 0.0, 0.0, 0.25)
    fx, fy = _core.social_force(walled, 1, SOCIAL)
    assert fx == pytest.approx(0.410425, rel=1e-3) and fy == pytest.approx(0.0, abs=1e-6)


def test_bad_social_force_settings_are_named():
    with pytest.raises(SchemaError, match=r"people\.relaxation: expected a finite number > 0"):
        SOCIAL.replace(relaxation=0.0).check("people")
    with pytest.raises(SchemaError, match=r"people\.max_speed: expected 1 to 10"):
        SOCIAL.replace(max_speed=0.5).check("people")


# ---- worlds with people ---------------------------------------------------------------------------------------------
def office_with(people: list[Person], **changes) -> vwg.robot.RobotWorld:
    return dataclasses.replace(vwg.robot.load_robot_world("office"), people=people, **changes)


def person(case: CaseStudy, pid: int):
    (p,) = [a for a in case.engine.string.actors() if a.name == "Person" and a["id"] == pid]
    return p


def test_a_person_walks_its_waypoints_round_the_walls_and_stops_at_the_last():
    # From the corridor into the kitchen and out to the lab: through two doors.
    walker = Person(1, (4.0, 9.0), ((5.5, 16.0), (11.0, 16.0)), loop=False)
    with CaseStudy(office_with([walker]), "astar", threads=1) as run:
        for _ in range(600):
            run.run(1)
            p = person(run, 1)
            if p["leg"] == -1:  # the walk has ended: there (within `arrive`, 0.4 m, of the last point)
                break
        assert p["leg"] == -1 and math.hypot(p["x"] - 11.0, p["y"] - 16.0) < 0.5
        on_sim = run.sim.physics.people[0]
        assert (on_sim["x"], on_sim["y"]) == pytest.approx((p["x"], p["y"]), abs=0.2)  # its body went with it
        assert run.summary().collisions == 0


def test_a_looping_walk_goes_round_again():
    walker = Person(1, (4.0, 9.0), ((8.0, 9.0), (4.0, 9.0)), loop=True)
    with CaseStudy(office_with([walker]), "astar", threads=1) as run:
        run.run(300)
        assert person(run, 1)["leg"] >= 3


def test_the_laser_sees_a_person_and_an_avoiding_robot_tracks_it():
    # Robot 1 stands; a person walks past 2-3 m in front of it.
    walker = Person(1, (3.5, 10.2), ((7.5, 10.2),), loop=False)
    office = office_with([walker], avoidance=vwg.robot.Avoidance("orca"))
    with CaseStudy(office, "astar", threads=1) as run:
        (seer,) = [g for g in run.feedback if isinstance(g, _core.NeighbourGenerator) and g.robot == 1]
        seen = []
        for _ in range(40):
            before = dict(run.sim.physics.people[0]) if run.sim.physics.people else None
            run.run(1)
            if before and seer.neighbours:
                seen.append(min(math.hypot(n["x"] - before["x"], n["y"] - before["y"]) for n in seer.neighbours))
        assert len(seen) > 10 and np.median(seen) < 0.15


def test_a_person_leaves_no_wall_on_a_robot_s_map():
    # A robot that does not avoid marks a person as an obstacle; once the person has walked on, later scans see
    # through those cells and clear them: in the end its map holds nothing the true map does not, where it sees.
    walker = Person(1, (3.5, 9.6), ((9.0, 9.6),), loop=False)
    with CaseStudy(office_with([walker]), "astar", threads=1) as run:
        run.run(15)
        grid = np.asarray(run.robot_actors()[1]["grid"])
        assert (grid == 101).sum() > 0  # the person was marked
        run.run(120)
        grid = np.asarray(run.robot_actors()[1]["grid"])
        cells = [run.world.grid.cell_to_world(r, c) for r, c in zip(*np.nonzero(grid == 101), strict=True)]
        # Within 4 m of the robot, in the corridor it looks along: no reported obstacle off the true walls.
        assert not [(x, y) for x, y in cells if math.hypot(x - 1.5, y - 9.0) < 4.0 and abs(y - 9.0) < 0.8]


def test_people_give_the_same_frames_on_one_and_two_threads():
    strings = []
    for threads in (1, 2):
        walkers = [Person(1, (6.0, 9.0), ((20.0, 9.0),)), Person(2, (12.0, 9.5), ((5.5, 16.0), (23.8, 4.0)))]
        with CaseStudy(office_with(walkers), "astar", goals={1: "lounge", 2: "office"}, threads=threads,
                       avoidance="orca") as run:
            run.run(150)
            strings.append(str(run.engine.string))
    assert strings[0] == strings[1]


def office_file(tmp_path: Path, extra: str, platform: str = "") -> Path:
    office = vwg.robot.load_robot_world("office")
    text = office.path.read_text(encoding="utf-8").replace("map: office/map.yaml", f"map: {office.map_path.resolve()}")
    path = tmp_path / "office.yaml"
    path.write_text(text + extra + platform, encoding="utf-8")
    return path


def test_a_run_with_people_resumes_as_it_went_on(tmp_path):
    world = vwg.load(office_file(tmp_path, "people:\n  - {start: [6.0, 9.0], wander: all}\n"
                                           "  - {start: [12.0, 9.5], waypoints: [[20.0, 9.0], [5.0, 9.0]]}\n"))
    options = {"goals": ["1:lounge", "2:office"], "allow_unreached": True}
    with vwg.start(world, vwg.RunOptions(frames=50, **options)) as run:
        run.execute()
        saved = run.save_state()
    with vwg.start(world, vwg.RunOptions(frames=100, **options)) as whole:
        whole.execute()
        expected = str(whole.engine.string)
    with vwg.resume(saved, vwg.RunOptions(frames=50, allow_unreached=True)) as again:
        again.execute()
        assert again.engine.frame == 100 and str(again.engine.string) == expected


def test_the_world_file_key_and_its_errors(tmp_path):
    text = ("people:\n  - {start: [6.0, 9.0], wander: [kitchen, lab], speed: 0.8}\n"
            "  - {start: [12, 9], waypoints: [[20, 9]], loop: false, radius: 0.3}\n")
    loaded = vwg.robot.load_robot_world(office_file(tmp_path, text))
    assert loaded.people == [Person(1, (6.0, 9.0), (loaded.rooms["kitchen"].goal, loaded.rooms["lab"].goal), 0.25, 0.8,
                                    True, True),
                             Person(2, (12.0, 9.0), ((20.0, 9.0),), 0.3, 1.0, False, False)]
    for extra, message in [
            ("people:\n  - {start: [6.0, 9.0]}\n", r"people\[0\]: expected waypoints .* or wander"),
            ("people:\n  - {start: [6.0, 9.0], wander: [attic]}\n", r"people\[0\]\.wander\[0\]: no room named 'attic'"),
            ("people:\n  - {start: [0.0, 0.0], wander: all}\n", r"people\[0\]\.start: person 1 at \(0.0, 0.0\)"),
            ("people:\n  - {start: [6.0, 9.0], waypoints: [[99, 9]]}\n",
             r"people\[0\]\.waypoints\[0\]: .* outside the map"),
            ("people:\n  - {start: [6.0, 9.0], wander: all, speed: 9}\n", r"people\[0\]\.speed"),
            ("people:\n  - {start: [6.0, 9.0], wander: all, height: 2}\n", r"people\[0\]\.height: unknown key")]:
        with pytest.raises(WorldFileError, match=message):
            vwg.robot.load_robot_world(office_file(tmp_path, extra))
    with pytest.raises(WorldFileError, match=r"people: people walk on the simulator only \(the platform is rosbr"):
        vwg.robot.load_robot_world(office_file(tmp_path, "people:\n  - {start: [6.0, 9.0], wander: all}\n",
                                               "platform: {kind: rosbridge, url: 'ws://127.0.0.1:9090'}\n"))


def test_the_sweep_parameter_adds_wandering_people():
    with pytest.raises(SchemaError, match=r"params\.people: expected 0 to 1000"):
        Trial("office", "astar", 0, 10, {"people": -1})
    row = run_trial(Trial("office", "astar", 3, 30, {"people": 4}))
    assert row["error"] == ""


@pytest.mark.slow
def test_robots_that_avoid_reach_their_rooms_among_six_people():
    # The held-out check, on seeds of its own: the office's robots and orders with 6 people and ORCA;
    # at least 90 % of the runs arrive.
    rows = [run_trial(Trial("office", "astar", seed, 3000, {"people": 6, "avoidance": "orca"}))
            for seed in range(10, 15)]
    assert not any(r["error"] for r in rows)
    assert sum(r["reached"] is True for r in rows) / len(rows) >= 0.9, [(r["reached"], r["frames"]) for r in rows]


def test_the_3d_overview_draws_people_where_they_start():
    from vwg.robot.overview import render_world_overview

    alone = render_world_overview(vwg.robot.load_robot_world("office"))
    walker = Person(1, (6.0, 9.0), ((20.0, 9.0),))
    with_one = render_world_overview(office_with([walker]))
    changed = np.argwhere((alone != with_one).any(axis=2))
    # A cylinder of 0.25 m: some hundreds of pixels, all in one place (a box of at most 80 px a side).
    assert len(changed) > 200 and np.ptp(changed[:, 0]) < 80 and np.ptp(changed[:, 1]) < 80
    # Sand, as the 2D views draw people ((222, 184, 135): red above green above blue), not the palette colour a robot
    # of its id would take (people come to the view as ids below zero; -1 mod 10 is (23, 190, 207), cyan).
    bare = [render_world_overview(office_with(people), labels=False) for people in ([], [walker])]
    body = np.argwhere((bare[0] != bare[1]).any(axis=2))
    r, g, b = (bare[1][body[:, 0], body[:, 1]].astype(int).T)
    assert len(body) > 100 and ((r > g) & (g > b)).mean() > 0.9


def test_a_person_with_no_way_to_its_goals_stands_and_tries_again_after_give_up():
    # Both waypoints are in a box of walls 1.6 m square in the middle room: no way in. A person then stands `give_up`
    # (3 s: 30 frames of 0.1 s) before it looks for a way to its next goal, rather than search the map every frame.
    # Its first eSocial comes in frame 2 (frame 1's θ puts it on the simulator): legs begun at frames 2, 32 and 62
    # (worked out from give_up and dt), not one a frame.
    world = vwg.robot.load_robot_world("office")
    grid = world.grid.copy()
    (r0, c0), (r1, c1) = grid.world_to_cell(10.2, 10.6), grid.world_to_cell(11.8, 12.2)
    lo_r, hi_r, lo_c, hi_c = min(r0, r1), max(r0, r1), min(c0, c1), max(c0, c1)
    assert not grid.blocked()[lo_r:hi_r + 1, lo_c:hi_c + 1].any()  # free floor before the box
    across, along = slice(lo_c, hi_c + 1), slice(lo_r, hi_r + 1)  # its walls, two cells (0.1 m) thick
    for rows, cols in ((slice(lo_r, lo_r + 2), across), (slice(hi_r - 1, hi_r + 1), across),
                       (along, slice(lo_c, lo_c + 2)), (along, slice(hi_c - 1, hi_c + 1))):
        grid.data[rows, cols] = 100
    walker = Person(1, (4.0, 9.0), ((11.0, 11.4), (10.8, 11.2)), loop=True)
    with CaseStudy(dataclasses.replace(world, grid=grid, people=[walker]), "astar", threads=1) as run:
        run.run(31)
        assert person(run, 1)["leg"] == 1 and person(run, 1)["rest"] > 0
        run.run(30)
        assert person(run, 1)["leg"] == 2
        run.run(1)
        assert person(run, 1)["leg"] == 3
        p = person(run, 1)
        # It walked nowhere (6 s at 1 m/s would have taken it 6 m), though the robots near its start push it a little.
        assert math.hypot(p["x"] - 4.0, p["y"] - 9.0) < 1.0
