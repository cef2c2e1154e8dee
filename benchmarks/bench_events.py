"""Scans through Python: a generator and an actor written in Python, each robot's 180-beam scan a
frame, event by event against by columns (vwg.EventColumns) and by runs (on_<event>_run). The
reference is the plain way in the same process: 180 vwg.Event objects a scan, one λ call a beam.

    python benchmarks/bench_events.py [--quick]     # writes benchmarks/results/<machine>/bench_events.json

Every way must end in the same string (checked): the runs only change how the events travel.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from machine import write_results

import vwg

RESULTS = Path(__file__).resolve().parent / "results" / "bench_events.json"
ROBOTS, BEAMS = 10, 180
DIST = np.linspace(0.5, 9.5, BEAMS)
ANGLE = np.linspace(-1.5, 1.5, BEAMS)


class BeamByBeam(vwg.Actor):
    name = "Mapper"
    events = ("beam",)
    attributes = {"id": int, "beams": 0, "nearest": 99.0}

    def on_beam(self, e):
        return self.with_(beams=self.beams + 1, nearest=min(self.nearest, e.dist))


class ScanAtOnce(vwg.Actor):
    name = "Mapper"
    events = ("beam",)
    attributes = BeamByBeam.attributes

    def on_beam_run(self, events):
        return self.with_(beams=self.beams + len(events), nearest=min(self.nearest, float(events.dist.min())))


class Scans(vwg.Generator):
    def __init__(self, by_columns: bool) -> None:
        super().__init__()
        self.by_columns = by_columns

    def generate(self, frame):
        if self.by_columns:
            return [vwg.EventColumns("beam", target=r, dist=DIST, angle=ANGLE) for r in range(ROBOTS)]
        return [vwg.Event("beam", target=r, dist=float(d), angle=float(a))
                for r in range(ROBOTS) for d, a in zip(DIST, ANGLE, strict=True)]


WAYS = (("events, λ a beam (reference)", False, BeamByBeam),
        ("vwg.EventColumns, λ a beam", True, BeamByBeam),
        ("vwg.EventColumns, on_beam_run", True, ScanAtOnce))


def rate(by_columns: bool, actor: type[vwg.Actor], frames: int) -> tuple[float, str]:
    world = vwg.World(events={"beam": {"dist": 0.0, "angle": 0.0}}, actors=[actor])
    engine = vwg.Engine(world, " . ".join(f"Mapper<id={r}>" for r in range(ROBOTS)), [Scans(by_columns)])
    engine.step()  # warm up
    t0 = time.perf_counter()
    engine.run(frames)
    return ROBOTS * BEAMS * frames / (time.perf_counter() - t0), str(engine.string)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer frames")
    args = parser.parse_args()
    frames = 3 if args.quick else 20
    rows, strings = [], set()
    for label, by_columns, actor in WAYS:
        best, string = max(rate(by_columns, actor, frames) for _ in range(3))
        strings.add(string)
        rows.append({"way": label, "beams_per_s": best})
    if len(strings) != 1:
        print("the ways ended in different strings:", *strings, sep="\n", file=sys.stderr)
        return 1
    reference = rows[0]["beams_per_s"]
    print(f"{ROBOTS} robots, {BEAMS}-beam scans, {frames} frames, the best of three")
    print(f"{'way':<32} {'beams/s':>12} {'÷ reference':>12}")
    for r in rows:
        r["ratio"] = r["beams_per_s"] / reference
        print(f"{r['way']:<32} {r['beams_per_s']:>12,.0f} {r['ratio']:>11.1f}×")
    write_results(RESULTS, quick=args.quick, robots=ROBOTS, beams=BEAMS, frames=frames, rows=rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
