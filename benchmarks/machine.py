"""Where a benchmark ran, for its results file, and the process's resident memory.

    from machine import rss_mb, write_results
    write_results(RESULTS, quick=args.quick, rows=rows)   # after the machine, its CPU and SIMD, cores, python

The results go to benchmarks/results/<machine-id>/<bench>.json (the latest run of each benchmark on each
machine, <machine-id> a short name of its CPU: amd-epyc-f25-m17), and the same JSON is appended as one
line to benchmarks/results/history.jsonl. Each names its date (UTC) and the command that ran it.
"""

from __future__ import annotations

import json
import os
import platform
import re
import shlex
import sys
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from vwg.machine import cpu

ROOT = Path(__file__).resolve().parent.parent


def rss_mb() -> float:
    """The process's resident memory now, MB, each page counted once however many mappings share it
    (the proportional set size of /proc/self/smaps_rollup). Robots' maps share the known map's pages
    (vwg.Blob.share), and the plain resident size (statm) counts such a page once per robot."""
    for line in Path("/proc/self/smaps_rollup").read_text().splitlines():
        if line.startswith("Pss:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError("/proc/self/smaps_rollup has no Pss line")


def machine_id(described: dict[str, Any]) -> str:
    """A short name of the machine's CPU for its results folder: the vendor and the first word of the
    product name, then the family and model numbers (`AMD EPYC`, 25, 17 -> `amd-epyc-f25-m17`;
    `Intel(R) Xeon(R) Platinum 8375C CPU @ 2.90GHz`, 6, 106 -> `intel-xeon-f6-m106`). Without a CPU
    name: `unknown-` and the architecture."""
    name = re.sub(r"\((r|tm)\)", " ", str(described.get("cpu_model") or "").lower())
    words = re.findall(r"[a-z0-9]+", name)[:2]
    if not words:
        return "unknown-" + (re.sub(r"[^a-z0-9_]+", "-", str(described.get("machine") or "").lower()) or "cpu")
    parts = list(words)
    for prefix, key in (("f", "cpu_family"), ("m", "cpu_model_number")):
        value = str(described.get(key) or "").strip()
        if value:
            parts.append(prefix + re.sub(r"[^a-z0-9]+", "", value.lower()))
    return "-".join(parts)


def command_line(argv: list[str] | None = None) -> str:
    """The command that ran this benchmark, as one would type it at the repository's root:
    `python benchmarks/bench_x.py ARGS` (paths inside the repository made relative to it)."""
    argv = list(sys.argv if argv is None else argv)

    def shown(arg: str, script: bool = False) -> str:
        path = Path(arg)
        if script or path.is_absolute():
            try:
                return (Path.cwd() / path).resolve().relative_to(ROOT).as_posix()
            except (ValueError, OSError):
                return arg
        return arg

    return shlex.join(["python", shown(argv[0], script=True), *(shown(a) for a in argv[1:])])


def write_results(path: Path, **fields: Any) -> Path:
    """Write `fields` as JSON after a description of the machine, the date and the command, to
    `path`'s folder / <machine-id> / `path`'s name (the bench's name is `path`'s stem), append the same
    JSON as one line to `path`'s folder / history.jsonl, and say so. Returns the file written.

    A `machine` field that is a dict (python, platform, vwg) is merged into the description."""
    described: dict[str, Any] = {"machine": platform.machine(), "processor": platform.processor(), **cpu(),
                                 "cores": os.cpu_count(), "python": platform.python_version()}
    given = fields.pop("machine", {})
    if not isinstance(given, dict):
        raise TypeError(f"write_results: machine must be a dict of extra descriptions, not {given!r}")
    described.update({k: v for k, v in given.items() if k not in described})
    ident = machine_id(described)
    record = {**described, "bench": Path(path).stem, "machine_id": ident,
              "date": datetime.now(timezone.utc).isoformat(timespec="seconds"), "command": command_line(), **fields}
    results = Path(path).parent
    out = results / ident / Path(path).name
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(record, indent=2) + "\n")
    with (results / "history.jsonl").open("a") as history:
        history.write(json.dumps(record) + "\n")
    print(f"wrote {out}")
    return out
