"""vwg experiments on the tests' small configuration: the report has a section per test, its tables
parse, match the CSVs beside them, and hold the numbers of the runs (recomputed here from the sweeps'
rows and the records); the map agreement measure by hand."""

from __future__ import annotations

import csv
import json
import math
import os
import statistics
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from vwg.experiments import CONFIGS, run_experiments
from vwg.io.maps import OccupancyGrid
from vwg.robot.map_quality import map_quality

HEADINGS = ["## 1. Test of the evolution function", "## 2. Test of device independence",
            "## 3. Test to validate the simulation", "## 4. Test of the system extensibility",
            "## 5. Test of changes in the environment"]


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("experiments")
    path = run_experiments(out, "tiny", workers=2, progress=False)
    return out, path.read_text()


def tables_of(text):
    """Each Markdown table of the report by its CSV's name: (header, rows)."""
    tables = {}
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.startswith("**") and ".csv](" in line:
            name = line.split("](")[1].split(".csv")[0]
            header = [c.strip() for c in lines[i + 2].strip("|").split("|")]
            assert set(lines[i + 3].replace("|", "")) == {"-"}
            rows = []
            for row in lines[i + 4:]:
                if not row.startswith("|"):
                    break
                rows.append([c.strip() for c in row.strip("|").split("|")])
            tables[name] = (header, rows)
    return tables


def read_csv(path):
    with path.open(newline="") as f:
        return list(csv.reader(f))


def sweep_rows(out, name):
    with (out / "sweeps" / f"{name}.csv").open(newline="") as f:
        return list(csv.DictReader(f))


def printed(value, digits):
    return "—" if math.isnan(value) else f"{value:.{digits}f}"


def figure(cell):
    """A cell's figure, without its 95 % interval ('0.95 [0.88, 0.99]' -> '0.95')."""
    return cell.split(" [")[0]


def interval(cell):
    """A cell's 95 % interval as two floats (None when the cell has none)."""
    if " [" not in cell:
        return None
    low, high = cell.split(" [")[1].rstrip("]").split(", ")
    return float(low), float(high)


def wilson_by_roots(k, n, z=1.959964):
    """Wilson's interval as the two roots p of (k/n - p)^2 = z^2 p (1 - p) / n (a second way to compute it)."""
    phat = k / n
    roots = np.roots([1 + z * z / n, -(2 * phat + z * z / n), phat * phat])
    return tuple(sorted(float(r.real) for r in roots))


def check_share(cell, flags):
    """The cell holds the share of the flags and Wilson's interval round it."""
    k, n = sum(flags), len(flags)
    assert figure(cell) == printed(k / n, 2), cell
    low, high = interval(cell)
    want = wilson_by_roots(k, n)
    assert abs(low - want[0]) <= 0.006 and abs(high - want[1]) <= 0.006, (cell, want)


@pytest.mark.slow
def test_one_section_per_test_in_order_with_its_pictures(report):
    out, text = report
    places = [text.index(h) for h in HEADINGS]
    assert places == sorted(places)
    # The header names the CPU as /proc/cpuinfo does (read here apart), not only the architecture.
    names = [line.partition(":")[2].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
             if line.startswith("model name")]
    header = text.split("\n\n")[1]
    assert (names[0] if names else "a CPU of unknown name") in header and f"{os.cpu_count()} core" in header, header
    for name in ("evolution_path_ratio", "evolution_frames", "devices_map", "simulation_odometry_noise",
                 "simulation_trajectories", "extensibility_rate", "extensibility_collisions", "environment_success"):
        assert f"]({name}.png)" in text
        png = (out / f"{name}.png").read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 5000
    assert "tiny configuration" in text and "Every number below comes from this run." in text


@pytest.mark.slow
def test_every_table_parses_and_matches_its_csv(report):
    out, text = report
    tables = tables_of(text)
    assert set(tables) == {"evolution", "evolution_by_map", "devices", "simulation_same_frames",
                           "simulation_trajectories", "simulation_odometry_noise", "simulation_localization",
                           "extensibility", "environment"}
    for name, (header, rows) in tables.items():
        assert read_csv(out / f"{name}.csv") == [header, *rows], name


@pytest.mark.slow
def test_the_evolution_table_holds_the_sweeps_numbers(report):
    out, text = report
    _, rows = tables_of(text)["evolution"]
    cells = sweep_rows(out, "evolution")
    config = CONFIGS["tiny"].evolution
    assert len(cells) == len(config)
    assert [r[0] for r in rows] == config.planners
    for row in rows:
        mine = [c for c in cells if c["planner"] == row[0]]
        arrived = [c for c in mine if c["reached"] == "True"]
        assert row[1] == str(len(mine)) and row[3] == str(len(arrived))
        check_share(row[2], [c["reached"] == "True" for c in mine])
        ratios = [float(c["path_length_m"]) / float(c["optimal_m"]) for c in arrived]
        assert figure(row[4]) == printed(statistics.median(ratios) if ratios else math.nan, 3)
        if len(ratios) > 1:  # the median's interval holds it and lies within the runs'
            low, high = interval(row[4])
            assert min(ratios) - 1e-3 <= low <= statistics.median(ratios) <= high <= max(ratios) + 1e-3
    # A* plans; the random decider does not reach a room in 50 s here.
    assert figure(dict((r[0], r[2]) for r in rows)["astar"]) == "1.00"
    # What arrived drove at least the any-angle optimum, to within the 2 % the inflated map's cells allow (the
    # robot's centre may cross their edges by half a diagonal), and not wildly more.
    for c in cells:
        if c["reached"] == "True":
            assert 0.98 <= float(c["path_length_m"]) / float(c["optimal_m"]) < 1.3, c


@pytest.mark.slow
def test_the_devices_table_holds_the_sweeps_numbers(report):
    out, text = report
    _, rows = tables_of(text)["devices"]
    cells = sweep_rows(out, "devices")
    for row in rows:
        mine = [c for c in cells if " + ".join(json.loads(c["params"])["sensors"]) == row[0]]
        assert figure(row[3]) == printed(statistics.median(float(c["map_precision"]) for c in mine), 3)
        assert figure(row[4]) == printed(statistics.median(float(c["map_recall"]) for c in mine), 3)
        check_share(row[2], [c["reached"] == "True" for c in mine])
        assert 0 < float(figure(row[4])) <= 1
    recall = {r[0]: float(figure(r[4])) for r in rows}
    assert recall["laser"] > recall["kinect"]  # 180° against the Kinect's 57°: it sees more of the walls


@pytest.mark.slow
def test_the_simulation_tables_hold_the_records(report):
    out, text = report
    _, rows = tables_of(text)["simulation_same_frames"]
    config = CONFIGS["tiny"].simulation
    assert [int(r[0]) for r in rows] == config.seeds
    for row in rows:
        sim = (out / "records" / f"sim_seed{row[0]}.jsonl").read_bytes()
        ros = (out / "records" / f"rosbridge_seed{row[0]}.jsonl").read_bytes()
        assert row[6] == str(len(sim)) and row[7] == ("yes" if sim == ros else "no") == "yes"
        assert int(row[2]) == sim.count(b"\n") - 2  # a header line, a frame per line, a closing line
    header, compared = tables_of(text)["simulation_trajectories"]
    assert [(int(r[0]), float(r[1])) for r in compared] == [(seed, level) for level in config.trajectory_levels
                                                            for seed in config.seeds]
    for r in (dict(zip(header, row, strict=True)) for row in compared):
        assert r["arrived (IR-SIM)"] == "yes"  # IR-SIM's robot, driven through the link, arrives too
        if r["odometry noise"] == "0":
            assert r["fake robot apart m (max)"] == "0.000"  # the link adds nothing: the same frames
    _, noisy = tables_of(text)["simulation_odometry_noise"]
    errors = {float(r[0]): float(figure(r[4])) for r in noisy}
    assert errors[0.0] == 0.0 and errors[0.05] > 0.0  # no drift without noise; some with it
    _, located = tables_of(text)["simulation_localization"]
    assert [(float(r[0]), r[1]) for r in located] == [(level, kind) for level in config.noise_levels
                                                      for kind in ("odometry", "particles")]
    final = {(float(r[0]), r[1]): float(figure(r[6])) for r in located}
    assert final[(0.0, "odometry")] == 0.0  # odometry without noise is the truth
    assert final[(0.05, "particles")] < final[(0.05, "odometry")]  # the filter corrects the drift


@pytest.mark.slow
def test_the_extensibility_and_environment_tables_hold_the_sweeps_numbers(report):
    out, text = report
    _, rows = tables_of(text)["extensibility"]
    cells = sweep_rows(out, "extensibility")
    assert [(int(r[0]), r[1]) for r in rows] == [(1, "none"), (1, "orca"), (2, "none"), (2, "orca")]
    for row in rows:
        mine = [c for c in cells if json.loads(c["params"])["robots"] == int(row[0])
                and json.loads(c["params"])["avoidance"] == row[1]]
        assert len(mine) == int(row[2]) and all(int(c["robots"]) == int(row[0]) for c in mine)
        rate = statistics.median(int(c["frames"]) / float(c["run_s"]) for c in mine)
        assert figure(row[6]) == printed(rate, 0)
        assert figure(row[5]) == printed(statistics.fmean(int(c["collisions"]) for c in mine), 1)
        check_share(row[3], [c["reached"] == "True" for c in mine])
        reached = sum(int(c["reached_robots"]) for c in mine)
        check_share(row[4], [True] * reached + [False] * (sum(int(c["robots"]) for c in mine) - reached))
    _, rows = tables_of(text)["environment"]
    cells = sweep_rows(out, "environment")
    assert [(r[0], r[1], r[2]) for r in rows] == [("office", "0", "0"), ("office", "1", "0"), ("maze", "0", "0"),
                                                  ("maze", "1", "0"), ("office", "0", "2"), ("maze", "0", "2")]
    for row in rows:
        mine = [c for c in cells if Path(c["world"]).stem == row[0]
                and json.loads(c["params"]).get("obstacles", 0) == int(row[1])
                and json.loads(c["params"]).get("people", 0) == int(row[2])]
        assert len(mine) == int(row[3])
        assert row[4] == printed(statistics.median(float(c["optimal_unchanged_m"]) for c in mine), 2)
        assert row[5] == printed(statistics.median(float(c["optimal_m"]) for c in mine), 2)
        assert figure(row[8]) == printed(statistics.fmean(int(c["replans"]) for c in mine), 1)
        assert figure(row[9]) == printed(statistics.fmean(int(c["collisions"]) for c in mine), 1)
        check_share(row[7], [c["reached"] == "True" for c in mine])
        if int(row[1]):  # every box lengthened the shortest way: the boxed run's optimum is above its unboxed twin's
            twins = {(c["world"], c["seed"]): float(c["optimal_m"]) for c in cells
                     if not json.loads(c["params"]).get("obstacles", 0) and not json.loads(c["params"]).get("people")}
            assert row[6] == f"{len(mine)} of {len(mine)}"
            for c in mine:
                assert float(c["optimal_m"]) >= twins[(c["world"], c["seed"])] + 0.02, c
                assert float(c["optimal_unchanged_m"]) == twins[(c["world"], c["seed"])]
        else:
            assert row[6] == "—" and all(c["optimal_m"] == c["optimal_unchanged_m"] for c in mine)


def test_the_command_refuses_bad_options(tmp_path):
    not_a_folder = tmp_path / "file"
    not_a_folder.write_text("x")
    for args, words in ((["--workers", "0", str(tmp_path / "out")], "--workers"),
                        ([str(not_a_folder), "--quick"], "is not a folder")):
        done = subprocess.run([sys.executable, "-m", "vwg.cli", "experiments", *args], capture_output=True, text=True,
                              timeout=60)
        assert done.returncode == 2 and words in done.stderr, done.stderr


def test_map_agreement_by_hand():
    # A 10 × 10 room of 1 m cells: walls all round. The robot went along row 5, from column 2 to 7.
    data = np.zeros((10, 10), np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = 100
    true = OccupancyGrid(data, 1.0)
    path = np.array([[c + 0.5, 5.5] for c in range(2, 8)])
    robot = np.zeros((10, 10), np.int16)
    robot[5, 0] = 101  # a true wall cell
    robot[5, 9] = 101  # a true wall cell
    robot[5, 5] = 101  # a phantom in the middle of the room
    robot[0, 5] = 1005  # a marker: not counted
    precision, recall = map_quality(true, [robot], [path], reach=3.0)
    assert precision == pytest.approx(2 / 3)
    # Wall cells within 3 m of the path: (5, 0), (5, 9) and their neighbours (4, 0), (6, 0), (4, 9), (6, 9),
    # and (5,0)…: cells whose centre is at most 3 m from a visited centre. Marked within one cell: rows 4-6.
    visited_rows, visited_cols = {5}, set(range(2, 8))
    near = {(r, c) for r in range(10) for c in range(10) if data[r, c]
            and min(math.hypot(r - vr, c - vc) for vr in visited_rows for vc in visited_cols) <= 3.0}
    seen = {(r, c) for r, c in near if abs(r - 5) <= 1 and (c <= 1 or c >= 8)}
    assert recall == pytest.approx(len(seen) / len(near))
    nothing = map_quality(true, [np.zeros((10, 10), np.int16)], [path])
    assert math.isnan(nothing[0]) and nothing[1] == 0.0
