"""Where a benchmark ran, for its results file, and the process's resident memory.

    from machine import rss_mb, write_results
    write_results(RESULTS, quick=args.quick, rows=rows)   # after the machine, its CPU and SIMD, cores, python
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


def cpu() -> dict[str, Any]:
    """The CPU as /proc/cpuinfo names it: figures differ 2-4x between machines of one name ("AMD
    EPYC" is a Zen 3 or a Zen 4 by its family and model), and with the SIMD it has."""
    first: dict[str, str] = {}
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if not line.strip():
                break  # the first processor is enough
            key, _, value = line.partition(":")
            first[key.strip()] = value.strip()
    except OSError:
        return {}
    flags = set(first.get("flags", "").split())
    return {"cpu_model": first.get("model name", ""), "cpu_family": first.get("cpu family", ""),
            "cpu_model_number": first.get("model", ""), "simd": [f for f in ("avx2", "avx512f") if f in flags]}


def write_results(path: Path, **fields: Any) -> None:
    """Write `fields` as JSON to `path`, after a description of the machine, and say so."""
    path.parent.mkdir(parents=True, exist_ok=True)
    described = {"machine": platform.machine(), "processor": platform.processor(), **cpu(), "cores": os.cpu_count(),
                 "python": platform.python_version()}
    path.write_text(json.dumps({**described, **fields}, indent=2) + "\n")
    print(f"wrote {path}")
