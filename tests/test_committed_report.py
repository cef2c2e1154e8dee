"""The full experiment report committed in docs/experiments/ (made by make experiments): its tables are its CSVs,
and the raw sweep cells beside it hold what the report claims (every boxed run's optimum longer than its
unboxed twin's, no arrived run shorter than 0.98x its optimum), each figure carries its 95 % interval, test 3
has its IR-SIM robot, and the README and the site link it."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

from test_experiments import read_csv, tables_of

ROOT = Path(__file__).resolve().parent.parent
FOLDER = ROOT / "docs" / "experiments"
REPORT = FOLDER / "report.md"
# A share or a median with its 95 % interval: '0.95 [0.88, 0.99]' (an empty group prints '—').
INTERVAL = re.compile(r"^-?\d+(\.\d+)? \[-?\d+(\.\d+)?, -?\d+(\.\d+)?\]$")


def cells(name: str) -> list[dict[str, str]]:
    with (FOLDER / "sweeps" / f"{name}.csv").open(newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def test_the_report_is_the_full_configuration_and_its_tables_are_its_csvs():
    text = REPORT.read_text(encoding="utf-8")
    assert "(full configuration)" in text
    tables = tables_of(text)
    assert {"evolution", "devices", "simulation_same_frames", "simulation_trajectories", "extensibility",
            "environment"} <= set(tables)
    for name, (header, rows) in tables.items():
        assert read_csv(FOLDER / f"{name}.csv") == [header, *rows], name
    for png in re.findall(r"\]\(([a-z_]+\.png)\)", text):
        assert (FOLDER / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", png


def test_shares_medians_and_means_carry_their_intervals():
    tables = tables_of(REPORT.read_text(encoding="utf-8"))
    bare = figures = 0
    for name in ("evolution", "devices", "extensibility", "environment"):
        header, rows = tables[name]
        for i, column in enumerate(header):
            if column == "success":  # a share of every run: Wilson's interval always
                assert all(INTERVAL.match(row[i]) for row in rows), (name, column)
            elif column.endswith(("(median)", "(mean)")) and not column.startswith("optimum"):
                # (the optima are the tasks' own lengths, not an estimate from runs: no interval)
                for row in rows:  # a figure of fewer than two runs has no interval
                    figures += 1
                    bare += not INTERVAL.match(row[i])
                    assert INTERVAL.match(row[i]) or re.match(r"^(—|-?\d+(\.\d+)?)$", row[i]), (name, column, row)
    assert figures > 50 and bare <= figures // 20, (bare, figures)


def test_no_arrived_run_drove_less_than_0_98_of_its_optimum():
    arrived = 0
    for name in ("evolution", "devices", "environment"):
        for row in cells(name):
            if row["reached"] == "True" and row["optimal_m"]:
                arrived += 1
                assert float(row["path_length_m"]) >= 0.98 * float(row["optimal_m"]), row
    assert arrived > 500


def test_every_boxed_run_s_optimum_is_longer_than_its_unboxed_twin_s():
    rows = cells("environment")
    unboxed = {}
    for row in rows:
        params = json.loads(row["params"])
        if params.get("obstacles") == 0 and "people" not in params:
            unboxed[(row["world"], row["seed"])] = float(row["optimal_m"])
    boxed = failed = 0
    for row in rows:
        params = json.loads(row["params"])
        if not params.get("obstacles"):
            continue
        if row["error"]:
            # A box that found no place on the way is a failed run, counted as such in the report.
            assert row["error"].startswith("params.obstacles: room for"), row["error"]
            failed += 1
            continue
        boxed += 1
        assert float(row["optimal_m"]) >= unboxed[(row["world"], row["seed"])] + 0.02, row
        assert float(row["optimal_unchanged_m"]) == unboxed[(row["world"], row["seed"])], row
    assert boxed >= 90
    if failed:
        assert f"{failed} of {len(rows)} runs failed" in REPORT.read_text(encoding="utf-8")


def test_test_3_drove_the_irsim_robot_to_its_room():
    header, *rows = read_csv(FOLDER / "simulation_trajectories.csv")
    arrived = [row[header.index("arrived (IR-SIM)")] for row in rows]
    assert len(rows) >= 10 and arrived.count("yes") >= len(rows) // 2, arrived
    same = read_csv(FOLDER / "simulation_same_frames.csv")
    assert all(row[same[0].index("identical")] == "yes" for row in same[1:])


def test_the_readme_and_the_site_link_the_report():
    assert "docs/experiments/report.md" in (ROOT / "README.md").read_text(encoding="utf-8")
    assert "experiments/report.md" in (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    assert "experiments/report.md" in (ROOT / "docs" / "experiments.md").read_text(encoding="utf-8")
