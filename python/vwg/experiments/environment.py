"""Test 5, changes in the environment: every map, and maps changed after the robot learned them
(paper §III.F.5)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from vwg.experiments import plots
from vwg.experiments.section import Section
from vwg.experiments.tables import Table, fmt, group, mean_cell, median, median_cell, number, share, share_cell, wilson

__all__ = ["section"]

METHOD = """
Every shipped map (the office, the maze, the field, the warehouse and the Willow Garage building, a
real building's map) with A*, and each again with boxes of 0.5 m put on the robot's shortest way after
its map was drawn: the robot starts with the map without them and must find them with its laser and go
round. A box goes at a seeded point of the middle of the shortest any-angle way (test 1's optimum) and is kept only
if the way stays open and the optimum grows by at least 5 cm, so every box is one the robot must go round: the
table gives the optimum without and with the boxes (**optimum m**, median, same seeds) and in how many of the boxed
runs it grew (**optimum longer**). Then each map also with people who walk (`people`: that many people at places
drawn from the seed, wandering between the rooms by the social force model, seen by the laser), and the robot
avoiding the robots and people its laser sees (ORCA, `avoidance: orca`) in those runs. **success** and **path /
optimal** as in test 1 (the optimum on the changed map, without the people); **replans**: the times the robot's
path was found blocked and made again; **collisions** per run (with people too). 95 % intervals in brackets as in
test 1 (means: the percentile bootstrap too).
"""


def _people(row: dict[str, Any]) -> int:
    return int(json.loads(row["params"]).get("people", 0))


def _boxes(row: dict[str, Any]) -> int:
    return int(json.loads(row["params"]).get("obstacles", 0))


def section(rows: list[dict[str, Any]], folder: Path) -> Section:
    out = Section(5, "Test of changes in the environment", METHOD)
    table = Table("environment", "Maps, and maps changed after they were drawn",
                  ["map", "boxes added", "people", "runs", "optimum m without boxes (median)",
                   "optimum m as run (median)", "optimum longer", "success", "replans per run (mean)",
                   "collisions per run (mean)", "arrived", "path / optimal (median)"])
    success: dict[str, dict[str, float]] = {}
    intervals: dict[str, dict[str, tuple[float, float]]] = {}
    for (world, boxes, people), runs in group(rows, lambda r: (Path(r["world"]).stem, _boxes(r), _people(r))).items():
        arrived = [r for r in runs if r["reached"] == "True"]
        flags = [r["reached"] == "True" for r in runs]
        series = f"{boxes} boxes" + (f", {people} people" if people else "")
        success.setdefault(world, {})[series] = share(flags)
        intervals.setdefault(world, {})[series] = wilson(sum(flags), len(flags))
        longer = [number(r["optimal_m"]) > number(r["optimal_unchanged_m"]) for r in runs] if boxes else []
        table.add(world, str(boxes), str(people), str(len(runs)),
                  fmt(median(number(r["optimal_unchanged_m"]) for r in runs), 2),
                  fmt(median(number(r["optimal_m"]) for r in runs), 2),
                  f"{sum(longer)} of {len(longer)}" if boxes else "—", share_cell(flags),
                  mean_cell((number(r["replans"]) for r in runs), 1),
                  mean_cell((number(r["collisions"]) for r in runs), 1), str(len(arrived)),
                  median_cell((number(r["path_length_m"]) / number(r["optimal_m"]) for r in arrived), 3))
    out.tables.append(table)
    out.plots.append(plots.bars(folder / "environment_success.png", "Success by map", "share of runs", success,
                                intervals))
    flags = [r["reached"] == "True" for r in rows]
    out.findings.append(f"{share_cell(flags)} of all runs reached their room.")
    boxed = [r for r in rows if _boxes(r)]
    if boxed:
        grew = sum(number(r["optimal_m"]) > number(r["optimal_unchanged_m"]) for r in boxed)
        out.findings.append(f"The boxes made the shortest way longer in {grew} of {len(boxed)} runs with boxes.")
    return out
