"""Test 4, extensibility: more robots by adding ARobot symbols to the string (paper §III.F.4)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from vwg.experiments import plots
from vwg.experiments.section import Section
from vwg.experiments.tables import Table, fmt, group, mean, median, number, share

__all__ = ["section"]

METHOD = """
The same world with 1 to N robots: the initial string gets one more ARobot symbol per robot, and
nothing else changes. Each robot starts at a free place drawn from the seed and is sent to a room
drawn from the seed. **success**: every robot of the run reached its room; **robots reached**: the
share of robots that did; **collisions** per run (robots meet in doors and corridors); **frames/s** and
**robot-steps/s**: the run's frames over the time the frames took, on one thread.
"""


def _robots(row: dict[str, Any]) -> int:
    return int(json.loads(row["params"])["robots"])


def section(rows: list[dict[str, Any]], folder: Path) -> Section:
    out = Section(4, "Test of the system extensibility", METHOD)
    table = Table("extensibility", "From one robot to many",
                  ["robots", "runs", "success", "robots reached", "collisions per run (mean)", "frames/s (median)",
                   "robot-steps/s (median)"])
    xs, fps, steps = [], [], []
    for n, runs in sorted(group(rows, _robots).items()):
        rate = median(number(r["frames"]) / number(r["run_s"]) for r in runs)
        reached = sum(number(r["reached_robots"]) for r in runs) / sum(number(r["robots"]) for r in runs)
        table.add(str(n), str(len(runs)), fmt(share(r["reached"] == "True" for r in runs), 2), fmt(reached, 2),
                  fmt(mean(number(r["collisions"]) for r in runs), 1), fmt(rate, 0), fmt(rate * n, 0))
        xs.append(n)
        fps.append(rate)
        steps.append(rate * n)
    out.tables.append(table)
    out.plots.append(plots.lines(folder / "extensibility_rate.png", "Frames and robot-steps per second", "robots",
                                 "per second (one thread)", {"frames/s": (xs, fps), "robot-steps/s": (xs, steps)},
                                 logx=True))
    out.findings.append(f"With {xs[-1]} robots the run made {fmt(steps[-1], 0)} robot-steps per second on one thread.")
    return out
