"""Test 5, changes in the environment: every map, and maps changed after the robot learned them
(paper §III.F.5)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from vwg.experiments import plots
from vwg.experiments.section import Section
from vwg.experiments.tables import Table, fmt, group, mean, median, number, share

__all__ = ["section"]

METHOD = """
Every shipped map (the office, the maze, the field, the warehouse and the Willow Garage building, a
real building's map) with A*, and each again with boxes of 0.5 m put on the robot's shortest way after
its map was drawn: the robot starts with the map without them and must find them with its laser and go
round. Then each also with people who walk (`people`: that many people at places drawn from the seed,
wandering between the rooms by the social force model, seen by the laser), and the robot avoiding the
robots and people its laser sees (ORCA, `avoidance: orca`) in those runs. **success** and **path / optimal**
as in test 1 (the optimum on the changed map, without the people); **replans**: the times the robot's path
was found blocked and made again; **collisions** per run (with people too).
"""


def _people(row: dict[str, Any]) -> int:
    return int(json.loads(row["params"]).get("people", 0))


def _boxes(row: dict[str, Any]) -> int:
    return int(json.loads(row["params"]).get("obstacles", 0))


def section(rows: list[dict[str, Any]], folder: Path) -> Section:
    out = Section(5, "Test of changes in the environment", METHOD)
    table = Table("environment", "Maps, and maps changed after they were drawn",
                  ["map", "boxes added", "people", "runs", "success", "replans per run (mean)",
                   "collisions per run (mean)", "path / optimal (median)"])
    success: dict[str, dict[str, float]] = {}
    for (world, boxes, people), runs in group(rows, lambda r: (Path(r["world"]).stem, _boxes(r), _people(r))).items():
        arrived = [r for r in runs if r["reached"] == "True"]
        rate = share(r["reached"] == "True" for r in runs)
        success.setdefault(world, {})[f"{boxes} boxes" + (f", {people} people" if people else "")] = rate
        table.add(world, str(boxes), str(people), str(len(runs)), fmt(rate, 2),
                  fmt(mean(number(r["replans"]) for r in runs), 1), fmt(mean(number(r["collisions"]) for r in runs), 1),
                  fmt(median(number(r["path_length_m"]) / number(r["optimal_m"]) for r in arrived), 3))
    out.tables.append(table)
    out.plots.append(plots.bars(folder / "environment_success.png", "Success by map", "share of runs", success))
    overall = share(r["reached"] == "True" for r in rows)
    out.findings.append(f"{fmt(overall, 2)} of all runs reached their room.")
    return out
