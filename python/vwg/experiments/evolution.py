"""Test 1, the evolution function: the same world with the decision inside λ(ARobot, eDecide) swapped,
nothing else changed (paper §III.F.1)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from vwg.experiments import plots
from vwg.experiments.section import Section
from vwg.experiments.tables import Table, bootstrap, fmt, group, median, median_cell, number, share, share_cell

__all__ = ["section"]

METHOD = """
Each planner drives one robot from a free place to a room, both drawn from the seed (a start/room
pair per seed), on each map, with everything else the same: the robot, its laser, the map it knows. (In tests 1, 4
and 5 the robots carry the laser only: the camera the shipped robots have feeds no decision measured here.)
**success** is the share of runs that reached the room within the frame limit; **path / optimal** is
the distance driven over the shortest way for the robot's radius, for the runs that arrived (**arrived**: how many);
**frames to goal** likewise; **planning** is the decider's own search time per run (the random decider does not
search). `wavefront` is a decider written in Python (vwg.robot.deciders.wavefront).

**The optimum** is the shortest any-angle way round the cells the planners avoid (the map inflated by the robot's
radius): the visibility graph of those cells' convex corners (Lozano-Pérez & Wesley 1979), searched by SciPy's
Dijkstra (vwg.robot.any_angle, code shared with no planner), to within the goal tolerance (0.25 m) of the room,
where the robot counts as arrived. The robot drives any angle too, so no planner should beat it; but a cell of the
inflated map is blocked when its centre is within the radius of a wall, and the robot's centre can cross its edge
by up to half a cell's diagonal (3.5 cm) without touching the wall, so on a way with several corners it can drive
up to about 2 % less (below 0.98 would be a yardstick fault, and the report says so).

Each figure is given with its 95 % interval in brackets: Wilson's for shares, the percentile bootstrap over the runs
for medians (vwg.experiments.tables).
"""


def section(rows: list[dict[str, Any]], folder: Path) -> Section:
    out = Section(1, "Test of the evolution function", METHOD)
    table = Table("evolution", "Planners over every map and start/room pair",
                  ["planner", "runs", "success", "arrived", "path / optimal (median)", "frames to goal (median)",
                   "planning ms per run (median)"])
    by_planner = group(rows, lambda r: r["planner"])
    ratios: dict[str, list[float]] = {}
    frames: dict[str, list[float]] = {}
    for planner, runs in by_planner.items():
        arrived = [r for r in runs if r["reached"] == "True"]
        ratios[planner] = [number(r["path_length_m"]) / number(r["optimal_m"]) for r in arrived]
        frames[planner] = [number(r["frames"]) for r in arrived]
        table.add(planner, str(len(runs)), share_cell(r["reached"] == "True" for r in runs), str(len(arrived)),
                  median_cell(ratios[planner], 3), median_cell(frames[planner], 0),
                  median_cell((number(r["planning_s"]) * 1000 for r in runs), 2))
    out.tables.append(table)
    maps = Table("evolution_by_map", "Success by map and planner (share of runs, 95 % interval)", ["map", *by_planner])
    for world, runs in group(rows, lambda r: r["world"]).items():
        per = group(runs, lambda r: r["planner"])
        maps.add(Path(world).stem, *(share_cell(r["reached"] == "True" for r in per.get(p, [])) for p in by_planner))
    out.tables.append(maps)
    out.plots.append(plots.boxes(folder / "evolution_path_ratio.png",
                                 "Path driven over the shortest way (arrived runs)", "path / optimal", ratios,
                                 {p: bootstrap(v) for p, v in ratios.items()}))
    out.plots.append(plots.boxes(folder / "evolution_frames.png", "Frames to reach the room (arrived runs)", "frames",
                                 frames, {p: bootstrap(v) for p, v in frames.items()}))
    below = [(p, v) for p, values in ratios.items() for v in values if v < 0.98]
    least = min((v for values in ratios.values() for v in values), default=math.nan)
    out.findings.append(f"The least path / optimal of an arrived run was {fmt(least, 3)}"
                        + (f"; {len(below)} runs drove less than 0.98 × the optimum (a fault of the yardstick or the "
                           "run): " + ", ".join(f"{p} {v:.3f}" for p, v in below[:5]) if below else
                           ": no arrived run drove less than 0.98 × its optimum") + ".")
    rates = {p: share(r["reached"] == "True" for r in runs) for p, runs in by_planner.items()}
    out.findings.append("Share of rooms reached: " + ", ".join(f"{p} {fmt(v, 2)}" for p, v in rates.items()) + ".")
    # Planners compared on the same pairs: those every planner that reached any room reached.
    able = [p for p, v in rates.items() if v > 0]
    pairs = [{(r["world"], r["seed"]) for r in by_planner[p] if r["reached"] == "True"} for p in able]
    common = set.intersection(*pairs) if pairs else set()
    if common and len(able) > 1:
        on_common = {p: median(number(r["path_length_m"]) / number(r["optimal_m"]) for r in by_planner[p]
                               if (r["world"], r["seed"]) in common) for p in able}
        out.findings.append(f"On the {len(common)} start/room pairs all of {', '.join(able)} reached, the median path "
                            "over the optimum was " + ", ".join(f"{p} {fmt(v, 3)}" for p, v in on_common.items())
                            + ".")
    return out
