"""Test 4, extensibility: more robots by adding ARobot symbols to the string (paper §III.F.4)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from vwg.experiments import plots
from vwg.experiments.section import Section
from vwg.experiments.tables import (
    Table,
    bootstrap,
    count_share_cell,
    fmt,
    group,
    mean,
    mean_cell,
    median,
    median_cell,
    number,
    share_cell,
)

__all__ = ["section"]

METHOD = """
The same world with 1 to N robots: the initial string gets one more ARobot symbol per robot, and
nothing else changes. Each robot starts at a free place drawn from the seed and is sent to a room
drawn from the seed (several robots may share a room). Every size runs twice: the robots as the paper has
them (**avoidance none**: each drives its decider's steps, and avoids others only once they are on its map),
and with **avoidance orca** (reciprocal collision avoidance on what each robot's laser sees of the others,
`avoidance: orca`; a robot that has arrived stays but gives way). **success**: every robot of the run reached
its room; **robots reached**: the share of robots that did; **collisions** per run (contacts between bodies,
robots or walls); **frames/s** and **robot-steps/s**: the run's frames over the time the frames took, on one
thread. 95 % intervals in brackets: Wilson's for shares (robots reached: over all the robots of the runs), the
percentile bootstrap over the runs for means and medians.
"""


def _robots(row: dict[str, Any]) -> int:
    return int(json.loads(row["params"])["robots"])


def _avoidance(row: dict[str, Any]) -> str:
    return str(json.loads(row["params"]).get("avoidance", "none"))


def section(rows: list[dict[str, Any]], folder: Path) -> Section:
    out = Section(4, "Test of the system extensibility", METHOD)
    table = Table("extensibility", "From one robot to many, without and with reciprocal avoidance",
                  ["robots", "avoidance", "runs", "success", "robots reached", "collisions per run (mean)",
                   "frames/s (median)", "robot-steps/s (median)"])
    rates: dict[str, tuple[list[float], list[float]]] = {}
    collisions: dict[str, tuple[list[float], list[float]]] = {}
    bands: dict[str, dict[str, list[tuple[float, float]]]] = {"rates": {}, "collisions": {}}
    for (n, kind), runs in sorted(group(rows, lambda r: (_robots(r), _avoidance(r))).items()):
        per_run = [number(r["frames"]) / number(r["run_s"]) for r in runs]
        rate = median(per_run)
        robots = int(sum(number(r["robots"]) for r in runs))
        reached = int(sum(number(r["reached_robots"]) for r in runs))
        hits = [number(r["collisions"]) for r in runs]
        table.add(str(n), kind, str(len(runs)), share_cell(r["reached"] == "True" for r in runs),
                  count_share_cell(reached, robots), mean_cell(hits, 1), median_cell(per_run, 0),
                  median_cell((v * n for v in per_run), 0))
        for series, band, value, interval in (
                (rates, "rates", rate * n, tuple(v * n for v in bootstrap(per_run))),
                (collisions, "collisions", mean(hits), bootstrap(hits, np.mean))):
            xs, ys = series.setdefault(kind, ([], []))
            xs.append(n)
            ys.append(value)
            bands[band].setdefault(kind, []).append(interval)
    out.tables.append(table)
    out.plots.append(plots.lines(folder / "extensibility_rate.png", "Robot-steps per second", "robots",
                                 "robot-steps per second (one thread)",
                                 {f"avoidance {k}": v for k, v in rates.items()}, logx=True,
                                 intervals={f"avoidance {k}": v for k, v in bands["rates"].items()}))
    out.plots.append(plots.lines(folder / "extensibility_collisions.png", "Collisions per run", "robots",
                                 "collisions per run (mean)", {f"avoidance {k}": v for k, v in collisions.items()},
                                 logx=True, intervals={f"avoidance {k}": v for k, v in bands["collisions"].items()}))
    most = max(n for n, _ in group(rows, lambda r: (_robots(r), _avoidance(r))))
    for kind, (xs, ys) in rates.items():
        if xs and xs[-1] == most:
            out.findings.append(f"With {most} robots and avoidance {kind} the run made {fmt(ys[-1], 0)} robot-steps "
                                f"per second on one thread.")
    if "none" in collisions and "orca" in collisions and collisions["none"][0][-1] == collisions["orca"][0][-1] == most:
        out.findings.append(f"With {most} robots: {fmt(collisions['none'][1][-1], 1)} collisions a run without "
                            f"avoidance, {fmt(collisions['orca'][1][-1], 1)} with ORCA.")
    return out
