"""The paper's five tests (§III.F) as measured experiments: ``vwg experiments OUT_DIR [--quick]``.

    report = vwg.experiments.run_experiments("out/experiments", "quick")

writes ``OUT_DIR/report.md``: one section per test, each with its tables (a CSV of each beside the
report), its plots (PNG) and the sentences its numbers make. Tests 1, 2, 4 and 5 are sweeps
(vwg.sweep on Dask; their cells in ``OUT_DIR/sweeps/*.csv``); test 3's runs go to the same Dask cluster,
each with its robot behind a rosbridge server of its own on 127.0.0.1. Every number in the report comes
from the run that writes it (unless ``resume=True`` keeps the sweep cells of an earlier run, which the
report then says).
"""

from __future__ import annotations

import csv
import datetime
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from vwg.experiments import devices, environment, evolution, extensibility, simulation
from vwg.experiments.section import Section
from vwg.experiments.simulation import SimulationConfig
from vwg.machine import summary as machine_summary
from vwg.sweep import SweepSpec, dask_client, run_sweep

__all__ = ["CONFIGS", "Config", "run_experiments"]

ALL_MAPS = ["office", "maze", "field", "warehouse", "willow"]
PLANNERS = ["random", "astar", "dstar", "jps", "rrtconnect", "wavefront"]
SENSOR_SETS = [["laser"], ["kinect"], ["laser", "kinect"]]


@dataclass(frozen=True)
class Config:
    """The size of an experiment run: a sweep per test (1, 2, 4, 5) and test 3's runs."""

    name: str
    evolution: SweepSpec
    devices: SweepSpec
    simulation: SimulationConfig
    extensibility: SweepSpec
    environment: SweepSpec

    def sweeps(self) -> dict[str, SweepSpec]:
        return {"evolution": self.evolution, "devices": self.devices, "extensibility": self.extensibility,
                "environment": self.environment}

    @property
    def runs(self) -> int:
        return sum(len(s) for s in self.sweeps().values()) + self.simulation.runs


#: The robots of the sweeps carry the laser only: the camera (the shipped worlds' robots have one) feeds no decision
#: measured here and would take most of the time; test 2 chooses its own sensors.
LASER = {"task": ["random"], "sensors": [["laser"]]}


def _config(name: str, maps: list[str], planners: list[str], seeds: int, frames: int, sim: SimulationConfig,
            robots: list[int], boxes: list[int], devices_maps: list[str], people: int) -> Config:
    return Config(
        name,
        evolution=SweepSpec(maps, planners, list(range(seeds)), frames, dict(LASER)),
        devices=SweepSpec(devices_maps, ["astar"], list(range(seeds)), frames,
                          {**LASER, "knows_map": [False], "sensors": SENSOR_SETS}),
        simulation=sim,
        extensibility=SweepSpec(["warehouse"], ["astar"], list(range(max(2, seeds // 2))), frames,
                                {**LASER, "robots": robots, "avoidance": ["none", "orca"]}),
        # The maps with boxes, and the same maps and seeds with people walking, the robot avoiding them.
        environment=SweepSpec(ALL_MAPS, ["astar"], list(range(max(2, seeds // 2))), frames + 1500,
                              {**LASER, "obstacles": boxes},
                              [{**LASER, "people": [people], "avoidance": ["orca"]}]),
    )


#: The sizes: ``full`` (every map and planner, 20 start/room pairs), ``quick`` (1.5 min on 2 cores),
#: ``tiny`` (the tests': a minute).
CONFIGS: dict[str, Config] = {
    "full": _config("full", ALL_MAPS, PLANNERS, 20, 3000, SimulationConfig([0, 1, 2, 3, 4], 1500,
                    [0.0, 0.01, 0.02, 0.05, 0.1], [0, 1, 2, 3, 4], 1500), [1, 2, 4, 8, 16, 32, 64], [0, 1, 3],
                    ["office", "maze", "warehouse"], 6),
    "quick": _config("quick", ["office", "maze"], PLANNERS, 3, 1500, SimulationConfig([0], 600, [0.0, 0.02, 0.05],
                     [0], 800, trajectory_seeds=[1]), [1, 2, 4, 8], [0, 2], ["office"], 4),
    "tiny": Config(
        "tiny",
        evolution=SweepSpec(["office"], ["astar", "random", "wavefront"], [1, 3], 500, dict(LASER)),
        devices=SweepSpec(["office"], ["astar"], [1], 400, {"task": ["random"], "knows_map": [False],
                                                            "sensors": [["laser"], ["kinect"]]}),
        simulation=SimulationConfig([1], 200, [0.0, 0.05], [1], 150),
        extensibility=SweepSpec(["office"], ["astar"], [0], 200, {**LASER, "robots": [1, 2],
                                                                  "avoidance": ["none", "orca"]}),
        environment=SweepSpec(["office", "maze"], ["astar"], [1], 600, {**LASER, "obstacles": [0, 1]},
                              [{**LASER, "people": [2], "avoidance": ["orca"]}]),
    ),
}


def _read(path: Path) -> list[dict[str, Any]]:
    with path.open(newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def run_experiments(out_dir: str | Path, config: str | Config = "full", *, workers: int | None = None,
                    scheduler: str | None = None, resume: bool = False, progress: bool | None = None) -> Path:
    """Run the five tests at the size `config` names (full, quick, tiny) and write the report; its path."""
    config = CONFIGS[config] if isinstance(config, str) else config
    out = Path(out_dir)
    sweeps_dir = out / "sweeps"
    sweeps_dir.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    reused = 0
    rows: dict[str, list[dict[str, Any]]] = {}
    with dask_client(scheduler, workers) as client:
        # Test 3's runs go to the cluster first: they are the longest, and run beside the sweeps' cells.
        test3 = simulation.jobs(config.simulation, out / "records")
        submitted = [client.submit(work, *args, pure=False) for _, work, args in test3]
        for name, spec in config.sweeps().items():
            csv_path = sweeps_dir / f"{name}.csv"
            if not resume:
                csv_path.unlink(missing_ok=True)
            _say(progress, f"test {name}: {len(spec)} runs on Dask")
            result = run_sweep(spec, csv_path, client=client, progress=progress)
            reused += result.done_before
            keys = {t.key: i for i, t in enumerate(spec.trials())}
            # Only the cells of this configuration (a resumed file may hold others), each once.
            seen: set[tuple[str, ...]] = set()
            kept = []
            for row in _read(csv_path):
                key = (row["world"], row["planner"], row["seed"], row["frames_limit"], row["params"])
                if key in keys and key not in seen and row["error"] is not None:
                    seen.add(key)
                    kept.append(row)
            rows[name] = sorted(kept, key=lambda r: keys[(r["world"], r["planner"], r["seed"], r["frames_limit"],
                                                          r["params"])])  # the spec's order, not the finishing one
        _say(progress, f"test simulation: {config.simulation.runs} runs ({len(test3)} tasks on Dask), through "
                       "rosbridge on 127.0.0.1 and on the simulator")
        found: dict[str, list[dict[str, Any]]] = {kind: [] for kind in simulation.KINDS}
        for (kind, _, _), future in zip(test3, _progress(submitted, len(test3), progress), strict=True):
            found[kind].append(future.result())  # in the jobs' order, however they finished
    sections = [
        evolution.section(rows["evolution"], out),
        devices.section(rows["devices"], out),
        simulation.section(found, out),
        extensibility.section(rows["extensibility"], out),
        environment.section(rows["environment"], out),
    ]
    for section, name in zip((sections[0], sections[1], sections[3], sections[4]), rows, strict=True):
        failed = [r for r in rows[name] if r["error"]]
        if failed:
            section.findings.append(f"{len(failed)} of {len(rows[name])} runs failed (counted as not reached); the "
                                    f"first: {failed[0]['error']}")
    elapsed = time.perf_counter() - started
    report = out / "report.md"
    report.write_text(_report(config, sections, elapsed, reused, workers, scheduler), encoding="utf-8")
    for section in sections:
        for table in section.tables:
            table.write_csv(out)
    return report


def _report(config: Config, sections: list[Section], elapsed: float, reused: int, workers: int | None,
            scheduler: str | None) -> str:
    cluster = f"a local Dask cluster of {workers or os.cpu_count()} worker processes"
    where = f"the Dask scheduler {scheduler}" if scheduler else cluster
    lines = [
        "# vwg experiments: the paper's five tests (§III.F), measured",
        "",
        f"Made by `vwg experiments` ({config.name} configuration) on "
        f"{datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}: {config.runs} runs in "
        f"{elapsed / 60:.1f} min on {machine_summary()}, the sweeps on {where}. "
        "Every number below comes from this run" + (f", but for {reused} sweep cells kept from an earlier run "
                                                   "(--resume)." if reused else "."),
        "",
        "Sizes: " + "; ".join(f"test {n}: {len(s)} runs ({', '.join(Path(w).stem for w in s.worlds)}; "
                              f"{len(s.seeds)} seeds; at most {s.frames} frames of 0.1 s)"
                              for n, s in (("1", config.evolution), ("2", config.devices), ("4", config.extensibility),
                                           ("5", config.environment)))
        + f"; test 3: {config.simulation.runs} runs.",
        "",
    ]
    for section in sections:
        lines.append(section.markdown())
    return "\n".join(lines)


def _say(progress: bool | None, text: str) -> None:
    import sys

    if progress is not False:
        print(text, file=sys.stderr)


def _progress(items: Any, total: int, show: bool | None) -> Any:
    import sys

    from tqdm import tqdm

    disable = not sys.stderr.isatty() if show is None else not show
    return tqdm(items, total=total, desc="test 3", unit="task", disable=disable)
