"""vwg sweep: a small sweep on a local Dask cluster checked against single runs of the same cells,
resuming, the SPEC's errors; the trials it runs; the independent shortest paths it measures against."""

from __future__ import annotations

import csv
import io
import json
import math
import re
import subprocess
import sys
import time

import numpy as np
import pytest

from conftest import plain_dijkstra
from vwg.errors import Error, SchemaError, WorldFileError
from vwg.robot.case_study import CaseStudy
from vwg.robot.shortest import DistanceField
from vwg.sweep import finished_keys, load_spec, run_sweep
from vwg.trial import COLUMNS, Trial, any_angle_m, run_trial, shortest_m, trial_world

SPEC = """\
worlds: [office, maze]
planners: [astar, random]
seeds: [4, 5]
frames: 150
params:
  task: [random]
  robots: [1, 2]
"""

TIMINGS = ("wall_s", "run_s", "planning_s")


def read_rows(path):
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def as_csv_row(row):
    """A row as the CSV holds it (every value as text)."""
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=COLUMNS)
    writer.writeheader()
    writer.writerow(row)
    return next(csv.DictReader(io.StringIO(text.getvalue())))


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    (folder / "spec.yaml").write_text(SPEC)
    out = folder / "results.csv"
    result = run_sweep(load_spec(folder / "spec.yaml"), out, workers=2, progress=False)
    return folder, out, result


@pytest.mark.slow
def test_a_sweep_on_dask_gives_the_rows_of_single_runs(sweep):
    _, out, result = sweep
    assert (result.cells, result.done_before, result.ran, result.failed) == (16, 0, 16, 0)
    rows = read_rows(out)
    assert len(rows) == 16
    cells = {(r["world"], r["planner"], r["seed"], r["params"]) for r in rows}
    assert len(cells) == 16  # every cell once
    # Each cell run again here, in this process and on one thread, gives the same row but the timings.
    for row in rows[::3]:
        trial = Trial(row["world"], row["planner"], int(row["seed"]), int(row["frames_limit"]),
                      json.loads(row["params"]))
        again = as_csv_row(run_trial(trial))
        for column in COLUMNS:
            if column not in TIMINGS:
                assert again[column] == row[column], (column, row)
    # The measures make sense against what they are: A* on a known map reaches most rooms in 150
    # frames (15 s) no shorter than the grid optimum allows (less a cell per turn it smooths).
    for row in rows:
        assert int(row["reached_robots"]) <= int(row["robots"]) == json.loads(row["params"])["robots"]
        if row["reached"] == "True":
            assert float(row["path_length_m"]) >= 0.9 * float(row["optimal_m"]) - 0.3


@pytest.mark.slow
def test_a_rerun_runs_only_what_is_missing(sweep, tmp_path):
    folder, out, _ = sweep
    # A finished sweep finishes at once, without starting a cluster.
    start = time.perf_counter()
    again = run_sweep(load_spec(folder / "spec.yaml"), out, workers=2, progress=False)
    assert (again.done_before, again.ran) == (16, 0)
    assert time.perf_counter() - start < 5
    # A sweep stopped in the middle of writing a row: that row and the ones never written run again.
    cut = tmp_path / "cut.csv"
    lines = out.read_text().splitlines(keepends=True)
    cut.write_text("".join(lines[:11]) + lines[11][:20])
    assert len(finished_keys(cut)) == 10
    ran = []
    resumed = run_sweep(load_spec(folder / "spec.yaml"), cut, workers=1, progress=False, on_row=ran.append)
    assert (resumed.done_before, resumed.ran) == (10, 6)
    rows = read_rows(cut)
    assert len(rows) == 16  # the torn row was cut off: its cell ran again
    assert sorted(map(untimed, rows)) == sorted(map(untimed, read_rows(out)))


@pytest.mark.slow
def test_the_command_line(sweep, tmp_path):
    folder, out, _ = sweep
    done = subprocess.run([sys.executable, "-m", "vwg.cli", "sweep", str(folder / "spec.yaml"), "-o", str(out)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "16 cells; 16 were already in the CSV, 0 ran now" in done.stdout
    done = subprocess.run([sys.executable, "-m", "vwg.cli", "sweep", str(folder / "spec.yaml"), "-o", str(out),
                           "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2 and "--workers sizes the local cluster" in done.stderr
    bad = tmp_path / "bad.yaml"
    bad.write_text("worlds: [office]\nplanners: [astar, teleport]\nseeds: 1\nframes: 10\n")
    done = subprocess.run([sys.executable, "-m", "vwg.cli", "sweep", str(bad), "-o", str(tmp_path / "r.csv")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert f"{bad}:2" in done.stderr and "planners[1]" in done.stderr and "teleport" in done.stderr


def untimed(row):
    return tuple(row[c] for c in COLUMNS if c not in TIMINGS)


@pytest.mark.slow
def test_a_last_row_that_lacks_only_its_line_break_runs_again(sweep, tmp_path):
    # A stop between a row's last character and its line break: the row looks whole, but its last
    # field may be cut short, so it is not counted as finished. It was counted and then cut off,
    # so the rerun ran one cell and left 15 of 16 rows.
    folder, out, _ = sweep
    lines = out.read_bytes().splitlines(keepends=True)  # the header and 16 rows, each ending in \r\n
    assert len(lines) == 17 and all(line.endswith(b"\r\n") for line in lines)
    cut = tmp_path / "cut.csv"
    cut.write_bytes(b"".join(lines[:15]) + lines[15].removesuffix(b"\r\n"))
    assert len(finished_keys(cut)) == 14
    resumed = run_sweep(load_spec(folder / "spec.yaml"), cut, workers=1, progress=False)
    assert (resumed.done_before, resumed.ran) == (14, 2)
    assert "line 16 was left half-written" in resumed.repaired
    rows = read_rows(cut)
    assert len(rows) == 16
    assert sorted(map(untimed, rows)) == sorted(map(untimed, read_rows(out)))


@pytest.mark.slow
def test_a_row_torn_inside_a_quoted_line_break_runs_again(sweep, tmp_path):
    # An error text of two lines is written quoted; a stop just after its line break leaves a quote
    # open. Cutting at the last line break kept it, and the next row appended went inside the quote.
    folder, out, _ = sweep
    lines = out.read_bytes().splitlines(keepends=True)
    torn = lines[15].removesuffix(b",\r\n") + b',"first line\nsecond line"\r\n'  # the error column, last
    assert next(csv.reader(io.StringIO(torn.decode(), newline="")))[-1] == "first line\nsecond line"
    cut = tmp_path / "cut.csv"
    cut.write_bytes(b"".join(lines[:15]) + torn[:torn.index(b"\n") + 1])
    assert len(finished_keys(cut)) == 14
    resumed = run_sweep(load_spec(folder / "spec.yaml"), cut, workers=1, progress=False)
    assert (resumed.done_before, resumed.ran) == (14, 2)
    rows = read_rows(cut)
    assert len(rows) == 16 and all(r["error"] == "" for r in rows)
    assert sorted(map(untimed, rows)) == sorted(map(untimed, read_rows(out)))


def test_a_header_cut_short_is_written_again(tmp_path):
    # A stop while the header was being written: the file is started again, not refused for good.
    (tmp_path / "spec.yaml").write_text("worlds: [office]\nplanners: [astar]\nseeds: [1]\nframes: 5\n")
    out = tmp_path / "r.csv"
    out.write_text("world,planner,se", newline="")
    done = subprocess.run([sys.executable, "-m", "vwg.cli", "sweep", str(tmp_path / "spec.yaml"), "-o", str(out),
                           "--workers", "1"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert f"{out}: its header was cut short: started again" in done.stderr
    assert "1 cells; 0 were already in the CSV, 1 ran now" in done.stdout
    assert out.read_bytes().split(b"\r\n")[0] == ",".join(COLUMNS).encode()
    rows = read_rows(out)
    assert [(r["world"], r["planner"], r["seed"], r["frames_limit"]) for r in rows] == [("office", "astar", "1", "5")]


def test_a_results_file_broken_in_the_middle_is_refused_with_its_line(tmp_path):
    out = tmp_path / "r.csv"
    row = ",".join(["x"] * len(COLUMNS)) + "\r\n"
    out.write_text(",".join(COLUMNS) + "\r\n" + row + '"x"y' + row[1:] + row, newline="")
    with pytest.raises(Error, match=re.escape(f"{out}:3: not a row as vwg sweep writes them") + ".*mend or delete"):
        finished_keys(out)


@pytest.mark.parametrize(("text", "line", "field", "words"), [
    ("worlds: [office]\nplanners: [astar]\nseeds: 1\nframes: 10\nfrmes: 3\n", 5, "frmes", "unknown key"),
    ("worlds: [nowhere]\nplanners: [astar]\nseeds: 1\nframes: 10\n", 1, "worlds[0]", "no shipped world"),
    ("worlds: []\nplanners: [astar]\nseeds: 1\nframes: 10\n", 1, "worlds", "non-empty list"),
    ("worlds: [office]\nplanners: [astar]\nseeds: -1\nframes: 10\n", 3, "seeds", "count of seeds"),
    ("worlds: [office]\nplanners: [astar]\nseeds: [1, x]\nframes: 10\n", 3, "seeds[1]", "integer"),
    ("worlds: [office]\nplanners: [astar]\nseeds: 1\nframes: 0\n", 4, "frames", ">= 1"),
    ("worlds: [office]\nplanners: [astar, jps, astar]\nseeds: 1\nframes: 9\n", 2, "planners[2]", "listed twice"),
    ("worlds: [office]\nplanners: [astar]\nseeds: [4, 4]\nframes: 9\n", 3, "seeds[1]", "listed twice"),
    ("worlds: [office]\nplanners: [astar]\nseeds: 1\nframes: 9\nparams:\n  sensors: [[[laser]]]\n", 6,
     "params.sensors[0]", "expected sensor names"),
    ("worlds: [office]\nplanners: [astar]\nseeds: 1\nframes: 10\nparams:\n  speed: [1]\n", 6, "params.speed",
     "unknown parameter"),
    ("worlds: [office]\nplanners: [astar]\nseeds: 1\nframes: 10\nparams:\n  task: [random, chaos]\n", 6,
     "params.task[1]", "world or random"),
    ("worlds: [office]\nplanners: [astar]\nseeds: 1\nframes: 10\nparams:\n  sensors: [[sonar]]\n", 6,
     "params.sensors[0]", "unknown sensor"),
])
def test_spec_errors_name_the_line_and_field(tmp_path, text, line, field, words):
    path = tmp_path / "spec.yaml"
    path.write_text(text)
    with pytest.raises(WorldFileError) as info:
        load_spec(path)
    message = str(info.value)
    assert f"{path}:{line}" in message and field in message and words in message, message


def test_a_world_file_beside_the_spec_and_a_results_file_of_another_kind(tmp_path):
    from conftest import ROOT

    maze = (ROOT / "maps" / "maze.yaml").read_text()
    (tmp_path / "mine.yaml").write_text(maze.replace("maze/map.yaml", str(ROOT / "maps" / "maze" / "map.yaml")))
    (tmp_path / "spec.yaml").write_text("worlds: [mine.yaml]\nplanners: [astar]\nseeds: 1\nframes: 10\n")
    spec = load_spec(tmp_path / "spec.yaml")
    assert spec.worlds == [str(tmp_path / "mine.yaml")]
    other = tmp_path / "other.csv"
    other.write_text("a,b\n1,2\n")
    with pytest.raises(Error, match=r"not a results file of vwg sweep.*name another file with -o, or move this one"):
        run_sweep(spec, other, workers=1, progress=False)


# ---- trials -------------------------------------------------------------------------------------------------
def test_a_random_task_is_drawn_from_the_seed():
    a, goals_a, _ = trial_world(Trial("office", "astar", 7, 10, {"task": "random", "robots": 3}))
    b, goals_b, _ = trial_world(Trial("office", "astar", 7, 10, {"task": "random", "robots": 3}))
    c, _, _ = trial_world(Trial("office", "astar", 8, 10, {"task": "random", "robots": 3}))
    assert [r.start for r in a.robots] == [r.start for r in b.robots] != [r.start for r in c.robots]
    assert goals_a == goals_b and len(goals_a) == 3 and set(goals_a.values()) <= set(a.rooms)
    for r in a.robots:  # apart, each with a room it can reach
        assert all(math.hypot(r.start[0] - o.start[0], r.start[1] - o.start[1]) >= 0.6 for o in a.robots if o is not r)
        assert math.isfinite(shortest_m(a.grid, r.radius, r.start[:2], a.rooms[goals_a[r.id]].goal))


def test_a_trial_that_cannot_be_set_up_gives_a_row_with_its_error():
    row = run_trial(Trial("office", "astar", 1, 10, {"robots": 5}))
    assert row["reached"] is False and "office has 2 robots, 5 asked" in row["error"]
    assert row["frames"] == "" and row["wall_s"] != ""


def test_trials_name_their_cells_one_way():
    a = Trial("office", "astar", 1, 10, {"odometry_noise": 0})
    b = Trial("office", "astar", 1, 10, {"odometry_noise": 0.0})
    assert a.key == b.key and hash(a) == hash(b) and a == b
    assert len({a, b, Trial("office", "astar", 2, 10, {})}) == 2


def test_trial_parameters_reach_the_run():
    world, _, known = trial_world(Trial("office", "astar", 1, 10, {"robots": 1, "sensors": ["kinect"],
                                                                   "odometry_noise": 0.02, "motor_noise": 0.01}))
    assert [r.id for r in world.robots] == [1] and world.robots[0].sensors == ("kinect",)
    assert {o.robot for o in world.orders} == {1}
    assert (world.noise.odometry, world.noise.motors) == (0.02, 0.01)
    assert known is world.grid
    with pytest.raises(SchemaError, match="office has 2 robots, 5 asked"):
        trial_world(Trial("office", "astar", 1, 10, {"robots": 5}))
    with pytest.raises(SchemaError, match=r"params\.robots: expected number of robots \(int\), got 1.5"):
        Trial("office", "astar", 1, 10, {"robots": 1.5})
    with pytest.raises(SchemaError, match="frames: expected an integer"):
        Trial("office", "astar", 1, 0, {})


def test_added_obstacles_are_on_the_way_and_not_on_the_robots_map():
    trial = Trial("office", "astar", 1, 10, {"task": "random", "obstacles": 2})
    world, goals, known = trial_world(trial)
    added = (world.grid.data == 100) & (known.data != 100)
    assert 10 * 10 < added.sum() <= 2 * 10 * 10  # two boxes of 0.5 m at 0.05 m a cell (one may overlap a wall)
    robot = world.robots[0]
    goal = world.rooms[goals[robot.id]].goal
    # The planners' way stays open; the shortest any-angle way got at least 2 cm longer (the 8-connected one may
    # not: it has many ways of the same length).
    assert math.isfinite(shortest_m(world.grid, robot.radius, robot.start[:2], goal))
    before = any_angle_m(known, robot.radius, robot.start[:2], goal)
    assert any_angle_m(world.grid, robot.radius, robot.start[:2], goal) >= before + 0.02
    # The robot starts with the map it knew and goes round what it finds.
    case = CaseStudy(world, "astar", goals=goals, known_map=known, threads=1)
    grid = np.asarray(case.robot_actors()[robot.id]["grid"])
    assert not (grid[added] >= 100).any()
    assert case.run(frames=800).reached
    case.close()
    with pytest.raises(SchemaError, match="known_map: expected a map of the world's size"):
        from vwg.io.maps import OccupancyGrid

        CaseStudy(world, "astar", known_map=OccupancyGrid(np.zeros((3, 3), np.int8), 0.05))


# ---- the independent shortest paths -----------------------------------------------------------------------
def test_distance_fields_by_hand():
    open3 = np.zeros((3, 3), bool)
    field = DistanceField(open3, (0, 0))
    assert field.to((2, 2)) == pytest.approx(2 * math.sqrt(2))
    assert field.to((2, 1)) == pytest.approx(1 + math.sqrt(2))
    assert field.to((5, 5)) == math.inf
    # A blocked corner: the diagonal past it is not taken (no corner cutting): 2 steps, not √2.
    corner = np.zeros((2, 2), bool)
    corner[0, 1] = True
    assert DistanceField(corner, (0, 0)).to((1, 1)) == pytest.approx(2.0)
    # A wall with no gap: cut off.
    wall = np.zeros((3, 3), bool)
    wall[:, 1] = True
    assert DistanceField(wall, (0, 0)).to((0, 2)) == math.inf
    assert DistanceField(wall, (0, 1)).to((0, 0)) == math.inf  # a blocked goal


def test_a_goal_reached_within_a_tolerance():
    open_row = np.zeros((1, 10), bool)
    # From cell 0 to within 2.5 cells of cell 9: cell 7 is the nearest that counts (7 steps).
    assert DistanceField(open_row, (0, 9), within=2.5).to((0, 0)) == pytest.approx(7.0)
    assert DistanceField(open_row, (0, 9), within=0.0).to((0, 0)) == pytest.approx(9.0)
    walled = open_row.copy()
    walled[0, 7:9] = True  # the cells near the goal are blocked: only the goal's own cell counts
    assert DistanceField(walled, (0, 9), within=2.5).to((0, 0)) == math.inf
    assert DistanceField(walled, (0, 9), within=2.5).to((0, 9)) == 0.0


def test_distance_fields_match_a_plain_dijkstra_on_random_grids():
    rng = np.random.default_rng(3)
    for _ in range(40):
        shape = tuple(rng.integers(2, 18, size=2))
        blocked = rng.random(shape) < rng.uniform(0.0, 0.45)
        goal = (int(rng.integers(shape[0])), int(rng.integers(shape[1])))
        np.testing.assert_allclose(DistanceField(blocked, goal).distance, plain_dijkstra(blocked, goal))


@pytest.mark.slow
def test_two_sweeps_on_one_client_keep_their_own_cells(tmp_path):
    from vwg.sweep import SweepSpec, dask_client

    first = SweepSpec(["office"], ["astar"], [1, 2], 20, {"task": ["random"]})
    second = SweepSpec(["maze"], ["random"], [1, 2], 20, {"task": ["random"]})
    with dask_client(None, 1) as client:
        run_sweep(first, tmp_path / "a.csv", client=client, progress=False)
        run_sweep(second, tmp_path / "b.csv", client=client, progress=False)
    for spec, name in ((first, "a.csv"), (second, "b.csv")):
        rows = read_rows(tmp_path / name)
        assert sorted((r["world"], r["planner"], r["seed"]) for r in rows) == \
            sorted((t.world, t.planner, str(t.seed)) for t in spec.trials())


@pytest.mark.slow
def test_a_sweep_on_a_running_scheduler(tmp_path):
    # A cluster of its own, as a user would start one (dask scheduler + workers), here on 127.0.0.1.
    from dask.distributed import LocalCluster

    (tmp_path / "spec.yaml").write_text("worlds: [office]\nplanners: [jps]\nseeds: [2, 3]\nframes: 30\n"
                                        "params:\n  task: [random]\n")
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0", host="127.0.0.1",
                      silence_logs=40) as cluster:
        done = subprocess.run([sys.executable, "-m", "vwg.cli", "sweep", str(tmp_path / "spec.yaml"), "-o",
                               str(tmp_path / "r.csv"), "--scheduler", cluster.scheduler_address],
                              capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "2 cells; 0 were already in the CSV, 2 ran now" in done.stdout
    rows = read_rows(tmp_path / "r.csv")
    again = {tuple(as_csv_row(run_trial(Trial("office", "jps", s, 30, {"task": "random"})))[c]
                   for c in ("seed", "frames", "path_length_m")) for s in (2, 3)}
    assert {(r["seed"], r["frames"], r["path_length_m"]) for r in rows} == again
    unreachable = subprocess.run([sys.executable, "-m", "vwg.cli", "sweep", str(tmp_path / "spec.yaml"), "-o",
                                  str(tmp_path / "s.csv"), "--scheduler", "tcp://127.0.0.1:9"],
                                 capture_output=True, text=True, timeout=120)
    assert unreachable.returncode == 2 and "cannot reach the Dask scheduler" in unreachable.stderr
