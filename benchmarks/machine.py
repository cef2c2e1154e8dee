"""Where a benchmark ran, for its results file, and the process's resident memory.

    from machine import rss_mb, write_results
    write_results(RESULTS, quick=args.quick, rows=rows)   # with machine, processor, cores, python first
"""

from __future__ import annotations

import json
import os
import platform
from pathlib import Path
from typing import Any


def rss_mb() -> float:
    """The process's resident memory now, MB, each page counted once however many mappings share it
    (the proportional set size of /proc/self/smaps_rollup). Robots' maps share the known map's pages
    (vwg.Blob.share), and the plain resident size (statm) counts such a page once per robot."""
    for line in Path("/proc/self/smaps_rollup").read_text().splitlines():
        if line.startswith("Pss:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError("/proc/self/smaps_rollup has no Pss line")


def write_results(path: Path, **fields: Any) -> None:
    """Write `fields` as JSON to `path`, after a description of the machine, and say so."""
    path.parent.mkdir(parents=True, exist_ok=True)
    described = {"machine": platform.machine(), "processor": platform.processor(), "cores": os.cpu_count(),
                 "python": platform.python_version()}
    path.write_text(json.dumps({**described, **fields}, indent=2) + "\n")
    print(f"wrote {path}")
