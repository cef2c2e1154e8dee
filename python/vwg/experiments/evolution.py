"""Test 1, the evolution function: the same world with the decision inside λ(ARobot, eDecide) swapped,
nothing else changed (paper §III.F.1)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from vwg.experiments import plots
from vwg.experiments.section import Section
from vwg.experiments.tables import Table, fmt, group, median, number, share

__all__ = ["section"]

METHOD = """
Each planner drives one robot from a free place to a room, both drawn from the seed (a start/room
pair per seed), on each map, with everything else the same: the robot, its laser, the map it knows.
**success** is the share of runs that reached the room within the frame limit; **path / optimal** is
the distance driven over the shortest way for the robot's radius (SciPy's Dijkstra on the grid,
vwg.robot.shortest: independent of the planners), for the runs that arrived; **frames to goal** likewise;
**planning** is the decider's own search time per run (the random decider does not search). The
optimum is the way to the nearest point within the goal tolerance (0.25 m), where the robot counts as
arrived; the robot drives any angle and the optimum follows the grid's 8 directions, so a ratio a little
below 1 is possible. `wavefront` is a decider written in Python (vwg.robot.deciders.wavefront).
"""


def section(rows: list[dict[str, Any]], folder: Path) -> Section:
    out = Section(1, "Test of the evolution function", METHOD)
    table = Table("evolution", "Planners over every map and start/room pair",
                  ["planner", "runs", "success", "path / optimal (median)", "frames to goal (median)",
                   "planning ms per run (median)"])
    by_planner = group(rows, lambda r: r["planner"])
    ratios: dict[str, list[float]] = {}
    frames: dict[str, list[float]] = {}
    for planner, runs in by_planner.items():
        arrived = [r for r in runs if r["reached"] == "True"]
        ratios[planner] = [number(r["path_length_m"]) / number(r["optimal_m"]) for r in arrived]
        frames[planner] = [number(r["frames"]) for r in arrived]
        table.add(planner, str(len(runs)), fmt(share(r["reached"] == "True" for r in runs), 2),
                  fmt(median(ratios[planner]), 3), fmt(median(frames[planner]), 0),
                  fmt(median(number(r["planning_s"]) * 1000 for r in runs), 2))
    out.tables.append(table)
    maps = Table("evolution_by_map", "Success by map and planner", ["map", *by_planner])
    for world, runs in group(rows, lambda r: r["world"]).items():
        per = group(runs, lambda r: r["planner"])
        maps.add(Path(world).stem, *(fmt(share(r["reached"] == "True" for r in per.get(p, [])), 2) for p in by_planner))
    out.tables.append(maps)
    out.plots.append(plots.boxes(folder / "evolution_path_ratio.png",
                                 "Path driven over the shortest way (arrived runs)", "path / optimal", ratios))
    out.plots.append(plots.boxes(folder / "evolution_frames.png", "Frames to reach the room (arrived runs)", "frames",
                                 frames))
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
