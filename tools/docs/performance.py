"""The performance page's tables, from the benchmark results files.

    performance_markdown(Path("benchmarks/results"))   # Markdown: a section per machine, a table per benchmark

benchmarks/machine.py:write_results writes benchmarks/results/<machine-id>/<bench>.json, the latest run of
each benchmark on each machine: a description of the machine (its CPU, family and model, SIMD, cores), the
date, the command, and the benchmark's own fields. This renders every such file; the history
(benchmarks/results/history.jsonl) is not read. Standard library only: the docs build runs it without vwg.
"""

from __future__ import annotations

import json
import math
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from vwg.machine import SIMD_NAMES

# The fields that describe where and how a benchmark ran, shown above its tables rather than in them.
META = ("machine", "processor", "cpu_model", "cpu_family", "cpu_model_number", "simd", "cores", "python",
        "platform", "vwg", "bench", "machine_id", "date", "date_inferred", "command", "command_inferred", "quick")
LONG_LIST = 6  # a list longer than this is shown by its first two values and its last


def performance_markdown(results_dir: Path) -> str:
    """Markdown for every results file under `results_dir`: a section per machine folder (its heading the
    CPU's name, family and model, SIMD and cores, as the folder's latest file records them), and in it a
    section per benchmark with its date and command, then its tables. A field a file lacks is said to be
    not recorded. Raises ValueError naming the file when one is not a JSON object, or when a results
    file lies outside a machine folder."""
    results_dir = Path(results_dir)
    if not results_dir.is_dir():
        raise ValueError(f"{results_dir}: no such folder of benchmark results")
    stray = sorted(results_dir.glob("*.json"))
    if stray:
        raise ValueError(f"{stray[0]}: a results file belongs in a folder per machine "
                         f"({results_dir}/<machine-id>/), as benchmarks/machine.py:write_results writes it")
    machines = {}
    for folder in sorted(p for p in results_dir.iterdir() if p.is_dir()):
        files = sorted(folder.glob("*.json"))
        if files:
            machines[folder.name] = [(path, _load(path)) for path in files]
    if not machines:
        return f"No benchmark results in `{_shown_dir(results_dir)}`.\n"
    order = sorted(machines, key=lambda name: (name.startswith("unknown"), name))
    return "\n".join(_machine(results_dir, name, machines[name]) for name in order)


def _load(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot be read ({exc})") from None
    if not isinstance(data, dict):
        raise ValueError(f"{path}: a results file is a JSON object, not {type(data).__name__}")
    return data


def _shown_dir(results_dir: Path) -> str:
    return f"{results_dir.parent.name}/{results_dir.name}" if results_dir.parent.name else results_dir.name


def _machine(results_dir: Path, name: str, files: list[tuple[Path, dict[str, Any]]]) -> str:
    latest = max((data for _, data in files), key=lambda data: str(data.get("date", "")))
    heading, missing = _machine_heading(latest)
    lines = [f"## {heading}", ""]
    where = f"Results in `{_shown_dir(results_dir)}/{name}/`"
    if missing:
        where += "; not recorded: " + ", ".join(missing)
    lines += [where + ".", ""]
    for path, data in files:
        lines += _bench(path, data)
    return "\n".join(lines)


def _machine_heading(data: dict[str, Any]) -> tuple[str, list[str]]:
    parts, missing = [], []
    cpu = str(data.get("cpu_model") or "").strip()
    arch = str(data.get("machine") or "").strip()
    parts.append(_escape(cpu) if cpu else "CPU not recorded" + (f" ({_escape(arch)})" if arch else ""))
    family, model = data.get("cpu_family"), data.get("cpu_model_number")
    if family not in (None, "") or model not in (None, ""):
        parts.append(f"family {family if family not in (None, '') else '?'}, "
                     f"model {model if model not in (None, '') else '?'}")
    else:
        missing.append("CPU family and model")
    simd = data.get("simd")
    if isinstance(simd, list):
        parts.append(", ".join(SIMD_NAMES.get(str(s), _escape(str(s))) for s in simd) if simd else "no AVX2")
    else:
        missing.append("SIMD")
    cores = data.get("cores")
    if isinstance(cores, int):
        parts.append(f"{cores} core" + ("s" if cores != 1 else ""))
    else:
        missing.append("cores")
    return " · ".join(parts), missing


def _bench(path: Path, data: dict[str, Any]) -> list[str]:
    lines = [f"### `{data.get('bench') or path.stem}`", ""]
    command = data.get("command")
    ran = f"`{command}`" if command else "Command not recorded"
    if command and data.get("command_inferred"):
        ran += " (the command inferred from the file's options)"
    date = _date(data.get("date"))
    when = date if date else "date not recorded"
    if date and data.get("date_inferred"):
        when += " (the date of the commit that wrote the file)"
    versions = [f"{label} {data[key]}" for key, label in (("python", "Python"), ("vwg", "vwg")) if data.get(key)]
    lines += [f"{ran}, {when}" + ("; " + ", ".join(versions) if versions else "") + ".", ""]

    fields = {k: v for k, v in data.items() if k not in META}
    scalars = {k: v for k, v in fields.items() if _table_kind(v) == "scalar"}
    if scalars:
        lines += [*_key_value_table("field", scalars), ""]
    for key, value in fields.items():
        kind = _table_kind(value)
        if kind == "rows":
            if key != "rows":
                lines += [f"**{_header(key)}**", ""]
            lines += [*_rows_table(value), ""]
        elif kind == "dict_of_dicts":
            lines += [f"**{_header(key)}**", ""]
            lines += [*_rows_table([{"": outer, **inner} for outer, inner in value.items()]), ""]
        elif kind == "dict_of_scalars":
            lines += [f"**{_header(key)}**", ""]
            lines += [*_key_value_table("", value), ""]
    if not fields:
        lines += ["No figures in this file.", ""]
    return lines


def _date(value: Any) -> str:
    if not value:
        return ""
    try:
        moment = datetime.fromisoformat(str(value))
    except ValueError:
        return _escape(str(value))
    if moment.tzinfo is not None:
        moment = moment.astimezone(timezone.utc)
        return moment.strftime("%Y-%m-%d %H:%M UTC")
    return moment.strftime("%Y-%m-%d %H:%M")


def _table_kind(value: Any) -> str:
    """How a top-level field is shown: in the file's table of single values, as a table of rows (a list of
    objects, or an object of objects, one row each), or as its own table of names and values."""
    if isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
        return "rows"
    if isinstance(value, dict) and value:
        if all(isinstance(v, dict) for v in value.values()):
            return "dict_of_dicts"
        return "dict_of_scalars"
    return "scalar"


def _flatten(row: dict[str, Any]) -> dict[str, Any]:
    """A row's objects of single values as columns of their own (`codes · avx2`)."""
    flat: dict[str, Any] = {}
    for key, value in row.items():
        if isinstance(value, dict) and value and not any(isinstance(v, (dict, list)) for v in value.values()):
            flat.update({f"{key} · {sub}": inner for sub, inner in value.items()})
        else:
            flat[key] = value
    return flat


def _rows_table(rows: list[dict[str, Any]]) -> list[str]:
    flat = [_flatten(row) for row in rows]
    columns: list[str] = []
    for row in flat:
        columns += [key for key in row if key not in columns]
    lines = ["| " + " | ".join(_header(c) for c in columns) + " |",
             "|" + "|".join("---" if _textual(flat, c) else "--:" for c in columns) + "|"]
    for row in flat:
        lines.append("| " + " | ".join(_cell(row[c]) if c in row else "—" for c in columns) + " |")
    return lines


def _textual(rows: list[dict[str, Any]], column: str) -> bool:
    return any(isinstance(row.get(column), (str, bool)) for row in rows)


def _key_value_table(first: str, values: dict[str, Any]) -> list[str]:
    lines = [f"| {_header(first)} | value |", "|---|--:|"]
    lines += [f"| {_header(str(key))} | {_cell(value)} |" for key, value in values.items()]
    return lines


def _header(key: str) -> str:
    return _escape(str(key).replace("_", " "))


def _escape(text: str) -> str:
    for char in "\\`*_[]|":
        text = text.replace(char, "\\" + char)
    return text.replace("<", "&lt;").replace("\n", " ")


def _cell(value: Any) -> str:
    return _escape(_compact(value))


def _compact(value: Any) -> str:
    """A value as short text: numbers with separators and four significant digits, lists and objects inline
    (a long list by its first two values and its last)."""
    if value is None:
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int):
        return f"{value:,}"
    if isinstance(value, float):
        return _number(value)
    if isinstance(value, str):
        return value
    if isinstance(value, list):
        if len(value) > LONG_LIST:
            shown = [_inner(v) for v in value[:2]] + ["…", _inner(value[-1])]
            return f"{len(value)} values: " + ", ".join(shown)
        return ", ".join(_inner(v) for v in value) if value else "none"
    if isinstance(value, dict):
        return ", ".join(f"{k}: {_inner(v)}" for k, v in value.items()) if value else "none"
    return str(value)


def _inner(value: Any) -> str:
    if isinstance(value, list):
        return "(" + ", ".join(_inner(v) for v in value) + ")"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_inner(v)}" for k, v in value.items()) + "}"
    return _compact(value)


def _number(value: float) -> str:
    if math.isnan(value):
        return "—"
    if math.isinf(value):
        return "∞" if value > 0 else "−∞"
    if value == 0:
        return "0"
    if abs(value) >= 1000:
        return f"{value:,.0f}"
    return f"{value:.4g}"
