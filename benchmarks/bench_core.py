"""Speed of the core: frames of η + π + φ over strings of 10^3 to 10^6 symbols.

    (a) static      primitives and transformations only                symbols per second
    (b) C++ actors  Walker<x, v> in C++, one λ event per actor          actor-events per second
    (c) Python      the same Walker in Python, one call per event       actor-events per second
    (d) batch       the same Walker in Python through a batch handler   actor-events per second

An actor-event is one (actor, event) pair through λ. Every frame runs the three semantic functions
explicitly (vwg.evolve, vwg.visualize, vwg.display on a NullBackend), so the engine's shortcut for
strings without actors does not flatter (a). In the same run, vwg.testing.reference (plain Python) evolves
the same strings and the ratio is printed. Times are the best of several repeats on one thread.

    python benchmarks/bench_core.py [--quick]  prints a table, writes benchmarks/results/<machine>/bench_core.json
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from pathlib import Path

from machine import write_results

import vwg
from vwg.testing.reference import Reference

RESULTS = Path(__file__).resolve().parent / "results" / "bench_core.json"
STATIC_UNIT = "Move<1.0>(Robot<1> . Rotate<0.5>(Robot<2>)) . Lamp"  # 5 symbols


class Walker(vwg.Actor):
    events = ("step",)
    attributes = {"x": 0.0, "v": 1.0}

    def on_step(self, e):
        return self.with_(x=self.x + self.v * e.dt)


class BatchWalker(vwg.Actor):
    name = "Walker"
    events = ("step",)
    attributes = {"x": 0.0, "v": 1.0}

    @classmethod
    def on_step_batch(cls, actors, e):
        actors.x[:] += actors.v * e.dt


def base_declarations():
    return {"primitives": {"Robot": {"id": 0}, "Lamp": None},
            "transformations": {"Move": {"dist": 0.0}, "Rotate": {"angle": 0.0}},
            "events": {"step": {"dt": 0.1}}}


def world_for(kind: str) -> vwg.World:
    if kind == "python":
        return vwg.World(actors=[Walker], **base_declarations())
    if kind == "batch":
        return vwg.World(actors=[BatchWalker], **base_declarations())
    alphabet = vwg.Alphabet(**base_declarations())
    if kind == "cpp":
        alphabet.add_actor("Walker", ["step"], {"x": 0.0, "v": 1.0}, vwg._core.walker_behavior(alphabet, "step"))
    return vwg.World(alphabet)


def make_string(world: vwg.World, kind: str, symbols: int) -> vwg.String:
    if kind == "static":
        return world.parse(" . ".join([STATIC_UNIT] * (symbols // 5)))
    return world.parse(" . ".join(f"Walker<x={i % 100}.0, v=1.5>" for i in range(symbols)))


def best_frame_time(w: vwg.String, events: list, budget: float, min_repeats: int = 3) -> float:
    """Best time of one frame of η + π + φ over repeats that fit in `budget` seconds."""
    null = vwg.NullBackend()
    best = float("inf")
    spent = 0.0
    repeats = 0
    while repeats < min_repeats or spent < budget:
        t0 = time.perf_counter()
        vwg.evolve(w, events)
        v = vwg.visualize(w, events)
        vwg.display(v, null)
        dt = time.perf_counter() - t0
        best = min(best, dt)
        spent += dt
        repeats += 1
        if spent > 4 * budget:
            break
    return best


def best_time(fn, budget: float, min_repeats: int = 2) -> float:
    best = float("inf")
    spent = 0.0
    repeats = 0
    while repeats < min_repeats or spent < budget:
        t0 = time.perf_counter()
        fn()
        dt = time.perf_counter() - t0
        best = min(best, dt)
        spent += dt
        repeats += 1
        if spent > 4 * budget:
            break
    return best


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes and shorter budgets (a smoke run)")
    args = parser.parse_args()
    sizes = [1_000, 10_000, 100_000] if args.quick else [1_000, 10_000, 100_000, 1_000_000]
    budget = 0.05 if args.quick else 0.3
    events = [vwg.Event("step", dt=0.1)]

    rows = []
    per_size: dict[str, dict[str, float]] = {}
    for kind, unit in (("static", "symbols/s"), ("cpp", "actor-events/s"), ("python", "actor-events/s"),
                       ("batch", "actor-events/s")):
        world = world_for(kind)
        per_size[kind] = {}
        for n in sizes:
            if kind == "python" and n > 100_000 and args.quick:
                continue
            w = make_string(world, kind, n)
            kind_budget = budget if kind != "python" else min(budget, 0.1)
            t = best_frame_time(w, events, kind_budget, 1 if n >= 1_000_000 else 3)
            rate = len(w) / t  # one event per actor for the actor kinds; symbols for static
            per_size[kind][str(n)] = rate
            rows.append((kind, n, t, rate, unit))
            print(f"  {kind:<7} {n:>9,} symbols  {t * 1e3:10.3f} ms/frame  {rate / 1e6:10.2f} M {unit}", flush=True)

    # The pure-Python reference on the same strings (η alone, which is what it implements).
    ref_n = 100_000
    static_world = world_for("static")
    w_static = make_string(static_world, "static", ref_n)
    ref_static = Reference(static_world.alphabet, [])
    tree_static = w_static.tree()
    t_ref_static = best_time(lambda: ref_static.eta(tree_static, events), budget)
    t_core_static = best_time(lambda: vwg.evolve(w_static, events), budget, 5)
    py_world = world_for("python")
    cpp_world = world_for("cpp")
    w_py = make_string(py_world, "python", ref_n)
    w_cpp = make_string(cpp_world, "cpp", ref_n)
    ref_actors = Reference(py_world.alphabet, [Walker])
    tree_py = w_py.tree()
    t_ref_actors = best_time(lambda: ref_actors.eta(tree_py, events), budget)
    t_core_actors = best_time(lambda: vwg.evolve(w_cpp, events), budget, 5)
    assert str(vwg.evolve(w_cpp, events)) == ref_actors.text(ref_actors.eta(tree_py, events))  # same result

    largest = str(sizes[-1])
    results = {
        "static_symbols_per_s": per_size["static"][largest],
        "cpp_actor_events_per_s": per_size["cpp"][largest],
        # --quick skips Python per-event calls at the largest size: take its largest measured one.
        "python_actor_events_per_s": per_size["python"][max(per_size["python"], key=int)],
        "python_batch_actor_events_per_s": per_size["batch"][largest],
        "speedup_vs_pure_python": t_ref_static / t_core_static,
        "speedup_vs_pure_python_actors": t_ref_actors / t_core_actors,
        "pure_python_eta_static_s": t_ref_static,
        "core_eta_static_s": t_core_static,
        "pure_python_eta_actors_s": t_ref_actors,
        "core_eta_cpp_actors_s": t_core_actors,
        "reference_symbols": ref_n,
        "headline_symbols": int(largest),
        "per_size": per_size,
        "quick": args.quick,
        "machine": {"python": sys.version.split()[0], "platform": platform.platform(), "processor": platform.machine()},
        "vwg": vwg.__version__,
    }
    print()
    print(f"  η on {ref_n:,} static symbols: core {t_core_static * 1e3:.2f} ms, pure Python {t_ref_static * 1e3:.1f} ms"
          f" -> {results['speedup_vs_pure_python']:.0f}x")
    print(f"  η on {ref_n:,} Walkers: core with C++ λ {t_core_actors * 1e3:.2f} ms, pure Python with Python λ "
          f"{t_ref_actors * 1e3:.1f} ms -> {results['speedup_vs_pure_python_actors']:.0f}x")
    print()
    aims = [("static_symbols_per_s", 50e6), ("cpp_actor_events_per_s", 10e6),
            ("python_batch_actor_events_per_s", 1e6), ("speedup_vs_pure_python", 50)]
    print(f"  {'figure':<34} {'measured':>14} {'aim':>10}")
    for key, aim in aims:
        value = results[key]
        mark = "ok" if value >= aim else "below"
        print(f"  {key:<34} {value:>14,.1f} {aim:>10,.0f}  {mark}")
    print(f"  {'python_actor_events_per_s':<34} {results['python_actor_events_per_s']:>14,.1f} {'-':>10}")
    write_results(RESULTS, **results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
