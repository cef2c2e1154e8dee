"""The machine a figure was measured on: its CPU as /proc/cpuinfo names it, with its family and model (figures
differ 2-4x between machines of one name: an "AMD EPYC" is a Zen 3 or a Zen 4 by those), the SIMD it has and its
cores. The benchmarks' results files (benchmarks/machine.py) and the experiments' report name the machine so."""

from __future__ import annotations

import os
import platform
from collections.abc import Mapping
from pathlib import Path
from typing import Any

__all__ = ["SIMD_NAMES", "cpu", "summary"]

#: The SIMD extensions vwg dispatches on, as /proc/cpuinfo's flags name them, and as people do.
SIMD_NAMES = {"avx2": "AVX2", "avx512f": "AVX-512F"}


def cpu(cpuinfo: str | None = None) -> dict[str, Any]:
    """The first processor of `cpuinfo` (by default /proc/cpuinfo's text): ``cpu_model`` (its name),
    ``cpu_family``, ``cpu_model_number`` and ``simd`` (those of SIMD_NAMES it has); {} when there is none to
    read (another system)."""
    if cpuinfo is None:
        try:
            cpuinfo = Path("/proc/cpuinfo").read_text()
        except OSError:
            return {}
    first: dict[str, str] = {}
    for line in cpuinfo.splitlines():
        if not line.strip():
            if first:
                break  # the first processor is enough
            continue
        key, _, value = line.partition(":")
        first[key.strip()] = value.strip()
    if not first:
        return {}
    flags = set(first.get("flags", "").split())
    return {"cpu_model": first.get("model name", ""), "cpu_family": first.get("cpu family", ""),
            "cpu_model_number": first.get("model", ""), "simd": [f for f in SIMD_NAMES if f in flags]}


def summary(described: Mapping[str, Any] | None = None) -> str:
    """One line naming the machine: ``AMD EPYC (family 25, model 17; AVX2, AVX-512F), 2 cores, x86_64``.
    `described` holds cpu()'s fields, ``cores`` and ``machine`` (by default this machine's)."""
    if described is None:
        described = {**cpu(), "cores": os.cpu_count(), "machine": platform.machine()}
    name = str(described.get("cpu_model") or "").strip() or "a CPU of unknown name"
    details = []
    family, model = described.get("cpu_family"), described.get("cpu_model_number")
    if family not in (None, "") or model not in (None, ""):
        details.append(f"family {family or '?'}, model {model or '?'}")
    simd = described.get("simd")
    if isinstance(simd, list):
        details.append(", ".join(SIMD_NAMES.get(str(s), str(s)) for s in simd) if simd else "no AVX2")
    line = name + (f" ({'; '.join(details)})" if details else "")
    cores = described.get("cores")
    if isinstance(cores, int):
        line += f", {cores} core" + ("s" if cores != 1 else "")
    arch = str(described.get("machine") or "").strip()
    return line + (f", {arch}" if arch else "")
