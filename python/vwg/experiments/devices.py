"""Test 2, device independence: gLaser, gKinect or both feed the same eLaser events to the same robot
(paper §III.F.2)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from vwg.experiments import plots
from vwg.experiments.section import Section
from vwg.experiments.tables import Table, bootstrap, fmt, group, median, median_cell, number, share_cell

__all__ = ["section"]

METHOD = """
The robot starts with an empty map (eq. 13) and learns the walls from its range sensor: the laser
(gLaser), the Kinect (gKinect, a depth image turned into the same eLaser<dist, angle> events), or
both; the world string and the robot are the same in all three. **map precision**: of the cells the
robot marked occupied, the share within one cell of a true wall; **map recall**: of the wall surface
within 2 m of where the robot went, the share it marked (vwg.robot.map_quality; walls out of sight, such as
the far side of a wall, count as missed, so no sensor reaches 1). Success and path as in test 1, and so are the 95 %
intervals in brackets.
"""


def _sensors(row: dict[str, Any]) -> str:
    return " + ".join(json.loads(row["params"])["sensors"])


def section(rows: list[dict[str, Any]], folder: Path) -> Section:
    out = Section(2, "Test of device independence", METHOD)
    table = Table("devices", "The robot's own map and its navigation, by sensor",
                  ["sensors", "runs", "success", "map precision (median)", "map recall (median)", "arrived",
                   "path / optimal (median)"])
    quality: dict[str, dict[str, float]] = {}
    intervals: dict[str, dict[str, tuple[float, float]]] = {}
    for sensors, runs in group(rows, _sensors).items():
        arrived = [r for r in runs if r["reached"] == "True"]
        precisions = [number(r["map_precision"]) for r in runs]
        recalls = [number(r["map_recall"]) for r in runs]
        quality[sensors] = {"precision": median(precisions), "recall": median(recalls)}
        intervals[sensors] = {"precision": bootstrap(precisions), "recall": bootstrap(recalls)}
        table.add(sensors, str(len(runs)), share_cell(r["reached"] == "True" for r in runs),
                  median_cell(precisions, 3), median_cell(recalls, 3), str(len(arrived)),
                  median_cell((number(r["path_length_m"]) / number(r["optimal_m"]) for r in arrived), 3))
    out.tables.append(table)
    out.plots.append(plots.bars(folder / "devices_map.png", "The robot's map against the true map (medians)", "share",
                                quality, intervals))
    measured = {s: q["recall"] for s, q in quality.items() if not math.isnan(q["recall"])}
    if measured:
        out.findings.append("Median recall of the walls: " + ", ".join(f"{s} {fmt(v, 3)}" for s, v in measured.items())
                            + ".")
    return out
