"""Replanning: D* Lite (which repairs its search) against A* from scratch, when obstacles appear on
the robot's path — and grid A* itself, on the MovingAI benchmark maps.

    walk     a robot walks its shortest path on a 512×512 MovingAI map; every 25 cells a 5×5 block
             appears 8 cells ahead on the path; both planners replan from where the robot stands
             (their path lengths are checked equal at every replan)
    astar    time of one A* search and one Jump Point Search per scenario of the benchmark files
             (octile and Euclidean), and A*'s time over JPS's

    python benchmarks/bench_planning.py [--quick]  writes benchmarks/results/<machine>/bench_planning.json
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np
from machine import write_results

import vwg

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "movingai"
RESULTS = Path(__file__).resolve().parent / "results" / "bench_planning.json"


def movingai_blocked(name: str) -> np.ndarray:
    grid = vwg.io.maps.load_movingai(DATA / name)
    return grid.data != 0  # rows flipped to map order; the planners do not mind


def scenarios(name: str) -> list[tuple[tuple[int, int], tuple[int, int], float]]:
    maps = vwg.io.maps
    height = maps.load_movingai(DATA / name).height
    return [(maps.movingai_cell(s.start_x, s.start_y, height), maps.movingai_cell(s.goal_x, s.goal_y, height),
             s.optimal_length) for s in maps.load_movingai_scenarios(DATA / f"{name}.scen")]


def walk(name: str, events: int) -> dict:
    """D* Lite and A* replanning as a robot walks and meets new obstacles."""
    blocked = movingai_blocked(name)
    scen = scenarios(name)
    start, goal, _ = max(scen, key=lambda s: s[2])  # the longest scenario
    dstar = vwg.plan.DStarLite(blocked, start, goal)
    t0 = time.perf_counter()
    path, _ = dstar.path()
    first_dstar = time.perf_counter() - t0
    t0 = time.perf_counter()
    vwg.plan.astar(blocked, start, goal)
    first_astar = time.perf_counter() - t0
    t_dstar = t_astar = 0.0
    replans = 0
    here = start
    for _ in range(events):
        if path is None or len(path) < 40:
            break
        here = path[25]
        ahead = path[33]
        cells = [(ahead[0] + dr, ahead[1] + dc) for dr in range(-2, 3) for dc in range(-2, 3)
                 if 0 <= ahead[0] + dr < blocked.shape[0] and 0 <= ahead[1] + dc < blocked.shape[1]
                 and (ahead[0] + dr, ahead[1] + dc) != here and (ahead[0] + dr, ahead[1] + dc) != goal]
        for r, c in cells:
            blocked[r, c] = True
        t0 = time.perf_counter()
        dstar.update_cells(cells, True)
        dstar.move_to(here)
        path, length_d = dstar.path()
        t_dstar += time.perf_counter() - t0
        t0 = time.perf_counter()
        _, length_a = vwg.plan.astar(blocked, here, goal)
        t_astar += time.perf_counter() - t0
        assert math.isclose(length_d, length_a, rel_tol=1e-9), (length_d, length_a)
        replans += 1
    return {"map": name, "replans": replans, "dstar_s": t_dstar, "astar_s": t_astar,
            "ratio": t_astar / t_dstar if t_dstar else math.nan,
            "first_plan_dstar_s": first_dstar, "first_plan_astar_s": first_astar}


def astar_speed(name: str, limit: int | None) -> dict:
    """A* and Jump Point Search (8-connected, no corner cutting) on every scenario, both heuristics."""
    blocked = movingai_blocked(name)
    scen = scenarios(name)[:limit]
    out: dict[str, dict[str, float]] = {"astar": {}, "jps": {}}
    for planner, search in (("astar", vwg.plan.astar), ("jps", vwg.plan.jps)):
        for heuristic in ("octile", "euclidean"):
            t0 = time.perf_counter()
            for start, goal, optimal in scen:
                _, length = search(blocked, start, goal, heuristic=heuristic)
                assert math.isclose(length, optimal, rel_tol=1e-4), (planner, start, goal, length, optimal)
            out[planner][heuristic] = (time.perf_counter() - t0) / len(scen) * 1e3
    return {"map": name, "scenarios": len(scen), "ms_per_search": out["astar"], "jps_ms_per_search": out["jps"],
            "astar_over_jps": {h: out["astar"][h] / out["jps"][h] for h in out["jps"]}}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    print("Replanning as obstacles appear on the path (5×5 blocks, 8 cells ahead), same path lengths:")
    print(f"  {'map':<18} {'replans':>7} {'D* Lite':>10} {'A*':>10} {'A* / D* Lite':>13}")
    walks = []
    for name in ("random512-10-0.map", "8room_000.map"):
        w = walk(name, 4 if args.quick else 12)
        walks.append(w)
        print(f"  {name:<18} {w['replans']:>7} {w['dstar_s'] * 1e3:8.2f} ms {w['astar_s'] * 1e3:8.2f} ms "
              f"{w['ratio']:12.1f}x")
    print("\nGrid A* and Jump Point Search per search on the benchmark scenarios (lengths checked against the "
          "published optima):")
    speeds = [astar_speed(n, 100 if args.quick else None) for n in ("random512-10-0.map", "8room_000.map")]
    for s in speeds:
        a, j, r = s["ms_per_search"], s["jps_ms_per_search"], s["astar_over_jps"]
        print(f"  {s['map']:<18} {s['scenarios']:>5} scenarios  A* octile {a['octile']:.2f} ms, euclidean "
              f"{a['euclidean']:.2f} ms;  JPS octile {j['octile']:.2f} ms ({r['octile']:.1f}x), euclidean "
              f"{j['euclidean']:.2f} ms ({r['euclidean']:.1f}x)")
    results = {
        "dstar_vs_astar_replan_ratio": min(w["ratio"] for w in walks),
        "walks": walks,
        "astar": speeds,
        "quick": args.quick,
        "machine": {"python": sys.version.split()[0], "platform": platform.platform()},
        "vwg": vwg.__version__,
    }
    write_results(RESULTS, **results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
