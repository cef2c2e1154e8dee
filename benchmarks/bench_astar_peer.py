"""Grid A* against a peer: vwg.plan.astar and pyastar2d (a C++ A* with a Python face) on the same
queries — the MovingAI benchmark maps and their scenarios, and held-out mazes and city blocks
(tests/data/heldout, made by heldout_maps.py: the kinds of map of MovingAI's maze and street sets, with
optima from SciPy's Dijkstra) — each called as a user calls it (a numpy map in, a path out), in the same process.

    python benchmarks/bench_astar_peer.py [--quick]  writes benchmarks/results/<machine>/bench_astar_peer.json

pyastar2d is not a vwg dependency: `pip install pyastar2d` first (make bench does).
D* Lite is timed on its first plan (made and searched per query; its strength, the repairs, is
bench_planning's). Two problems:
- 4-connected moves of cost 1, the same problem for all: the number of steps of every path is checked equal;
- 8-connected, the paper's A* (diagonals cost √2, no corner cutting, the Euclidean heuristic) against pyastar2d's
  8-connected mode, whose diagonal costs as much as a straight step and whose Chebyshev heuristic is exact on an
  open grid: not the same problem (its searches expand far fewer cells), but the one a user of either would call.
  vwg's lengths are checked against the scenarios' published optimal lengths.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from machine import write_results
from tqdm import tqdm

import vwg

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
RESULTS = Path(__file__).resolve().parent / "results" / "bench_astar_peer.json"
MAPS = ("movingai/random512-10-0.map", "movingai/8room_000.map", "movingai/den312d.map", "movingai/arena.map",
        "heldout/maze-c2.map", "heldout/maze-c8.map", "heldout/city-a.map", "heldout/city-b.map")


def queries(name: str) -> tuple[np.ndarray, list[tuple[tuple[int, int], tuple[int, int]]], list[float]]:
    """The map (True = blocked), its scenarios' (start, goal) cells and their published 8-connected optimal lengths."""
    grid = vwg.io.maps.load_movingai(DATA / name)
    h = grid.height
    scenarios = vwg.io.maps.load_movingai_scenarios(DATA / f"{name}.scen")
    out = [(vwg.io.maps.movingai_cell(s.start_x, s.start_y, h), vwg.io.maps.movingai_cell(s.goal_x, s.goal_y, h))
           for s in scenarios]
    return grid.data != 0, out, [s.optimal_length for s in scenarios]


def timed(fn, items) -> float:
    t0 = time.perf_counter()
    for item in items:
        fn(*item)
    return time.perf_counter() - t0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the first 200 scenarios of each map")
    args = parser.parse_args()
    try:
        import pyastar2d
    except ImportError:
        print("bench_astar_peer: pyastar2d is not installed (pip install pyastar2d)", file=sys.stderr)
        return 2
    rows = []
    for name in tqdm(MAPS, desc="bench_astar_peer", unit="map"):
        blocked, qs, optimal = queries(name)
        if args.quick:
            qs, optimal = qs[:200], optimal[:200]
        weights = np.where(blocked, np.inf, 1.0).astype(np.float32)
        for s, g in qs:  # the same answers: the step counts of the shortest 4-connected paths
            path, _ = vwg.plan.astar(blocked, s, g, diagonal=False, heuristic="manhattan")
            theirs = pyastar2d.astar_path(weights, s, g, allow_diagonal=False)
            assert (path is None) == (theirs is None) and (path is None or len(path) == len(theirs)), (name, s, g)
        # The best of three passes over all the queries, for each planner.
        def ours_once(s, g, blocked=blocked):
            return vwg.plan.astar(blocked, s, g, diagonal=False, heuristic="manhattan")

        def peer_once(s, g, weights=weights):
            return pyastar2d.astar_path(weights, s, g, allow_diagonal=False)

        def dstar_once(s, g, blocked=blocked):
            return vwg.plan.DStarLite(blocked, s, g, diagonal=False, heuristic="manhattan").path()

        for s, g in qs[:50]:  # D* Lite's first plan gives the same answers too
            assert dstar_once(s, g)[1] == ours_once(s, g)[1], (name, s, g)
        def ours8_once(s, g, blocked=blocked):  # the paper's: 8-connected, no corner cutting, Euclidean
            return vwg.plan.astar(blocked, s, g)

        def peer8_once(s, g, weights=weights):
            return pyastar2d.astar_path(weights, s, g, allow_diagonal=True)

        for (s, g), length in zip(qs, optimal, strict=True):  # vwg's 8-connected lengths: the published optima
            assert abs(ours8_once(s, g)[1] - length) < 1e-4 * max(1.0, length), (name, s, g, length)
        ours = min(timed(ours_once, qs) for _ in range(3))
        peer = min(timed(peer_once, qs) for _ in range(3))
        dstar = min(timed(dstar_once, qs) for _ in range(3))
        ours8 = min(timed(ours8_once, qs) for _ in range(3))
        peer8 = min(timed(peer8_once, qs) for _ in range(3))
        rows.append({"map": Path(name).name, "kind": Path(name).parent.name, "cells": int(blocked.size),
                     "queries": len(qs), "vwg_ms": ours / len(qs) * 1e3,
                     "pyastar2d_ms": peer / len(qs) * 1e3, "speed_ratio": peer / ours,
                     "dstar_first_plan_ms": dstar / len(qs) * 1e3, "dstar_speed_ratio": peer / dstar,
                     "vwg_8_euclidean_ms": ours8 / len(qs) * 1e3, "pyastar2d_8_ms": peer8 / len(qs) * 1e3,
                     "speed_ratio_8": peer8 / ours8})
    print(f"{'map':<20} {'queries':>7} {'A* ms':>8} {'D* Lite ms':>11} {'pyastar2d ms':>13} "
          f"{'A* speed / peer':>16} {'D* Lite speed / peer':>21}   (4-connected, cost 1)")
    for r in rows:
        print(f"{r['map']:<20} {r['queries']:>7} {r['vwg_ms']:8.3f} {r['dstar_first_plan_ms']:11.3f} "
              f"{r['pyastar2d_ms']:13.3f} {r['speed_ratio']:16.2f} {r['dstar_speed_ratio']:21.2f}")
    print(f"{'map':<20} {'queries':>7} {'A* ms':>8} {'pyastar2d ms':>13} {'A* speed / peer':>16}   (8-connected: "
          "vwg's A* as the paper's, pyastar2d's own 8-connected mode)")
    for r in rows:
        print(f"{r['map']:<20} {r['queries']:>7} {r['vwg_8_euclidean_ms']:8.3f} {r['pyastar2d_8_ms']:13.3f} "
              f"{r['speed_ratio_8']:16.2f}")
    write_results(RESULTS, quick=args.quick, rows=rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
