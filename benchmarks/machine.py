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
    """The process's resident memory now (/proc/self/statm), MB."""
    pages = int(Path("/proc/self/statm").read_text().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE") / 2**20


def write_results(path: Path, **fields: Any) -> None:
    """Write `fields` as JSON to `path`, after a description of the machine, and say so."""
    path.parent.mkdir(parents=True, exist_ok=True)
    described = {"machine": platform.machine(), "processor": platform.processor(), "cores": os.cpu_count(),
                 "python": platform.python_version()}
    path.write_text(json.dumps({**described, **fields}, indent=2) + "\n")
    print(f"wrote {path}")
