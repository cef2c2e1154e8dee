"""Tables of an experiment report: Markdown in the report, the same table as a CSV beside it, and the
few summaries the tables use (success rate, median, mean, and their 95 % intervals), each defined once here.

Intervals: a share's is Wilson's score interval (Wilson 1927; it stays inside [0, 1] and is not degenerate at 0 or
n successes, where the normal approximation is); a median's or a mean's is the percentile bootstrap over the runs
(Efron & Tibshirani 1993, ch. 13), 10,000 resamples from a fixed seed, so a report is the same every time it is
made from the same runs. With few runs the intervals are wide, as they should be; with one run there is none.
"""

from __future__ import annotations

import csv
import math
import statistics
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["Interval", "Table", "bootstrap", "count_share_cell", "fmt", "fmt_interval", "group", "mean", "mean_cell",
           "median", "median_cell", "number", "share", "share_cell", "wilson"]

Z95 = 1.959963984540054  # the standard normal's 97.5 % point
RESAMPLES = 10_000


def number(text: Any) -> float:
    """A CSV cell as a number (NaN when empty)."""
    if text in ("", None):
        return math.nan
    if text in ("True", "False"):
        return float(text == "True")
    return float(text)


def median(values: Iterable[float]) -> float:
    kept = [v for v in values if not math.isnan(v)]
    return statistics.median(kept) if kept else math.nan


def mean(values: Iterable[float]) -> float:
    kept = [v for v in values if not math.isnan(v)]
    return statistics.fmean(kept) if kept else math.nan


def share(flags: Iterable[bool]) -> float:
    flags = list(flags)
    return sum(flags) / len(flags) if flags else math.nan


Interval = tuple[float, float]
NO_INTERVAL: Interval = (math.nan, math.nan)


def wilson(successes: int, n: int, z: float = Z95) -> Interval:
    """Wilson's score interval of a share of `successes` in `n` trials (NaN, NaN for none)."""
    if n <= 0:
        return NO_INTERVAL
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return (max(0.0, centre - half), min(1.0, centre + half))


def bootstrap(values: Iterable[float], statistic: Callable[[np.ndarray], Any] = np.median,
              seed: int = 0) -> Interval:
    """The 95 % percentile-bootstrap interval of `statistic` (median by default; it must take an axis argument)
    over `values` (NaN left out); NaN, NaN for fewer than two values."""
    kept = np.array([v for v in values if not math.isnan(v)], dtype=float)
    if kept.size < 2:
        return NO_INTERVAL
    rng = np.random.default_rng(seed)
    samples = kept[rng.integers(0, kept.size, size=(RESAMPLES, kept.size))]
    stats = statistic(samples, axis=1)
    low, high = np.quantile(stats, [0.025, 0.975])
    return (float(low), float(high))


def fmt_interval(value: float, interval: Interval, digits: int) -> str:
    """A figure and its 95 % interval as the report prints them: '0.95 [0.88, 0.99]' ('—' when there is none)."""
    if math.isnan(interval[0]):
        return fmt(value, digits)
    return f"{fmt(value, digits)} [{fmt(interval[0], digits)}, {fmt(interval[1], digits)}]"


def share_cell(flags: Iterable[bool], digits: int = 2) -> str:
    """A share and its Wilson interval, printed."""
    flags = list(flags)
    return fmt_interval(share(flags), wilson(sum(flags), len(flags)), digits)


def count_share_cell(successes: int, n: int, digits: int = 2) -> str:
    """`successes` of `n` as a share and its Wilson interval, printed."""
    return fmt_interval(successes / n if n else math.nan, wilson(successes, n), digits)


def median_cell(values: Iterable[float], digits: int) -> str:
    """A median and its bootstrap interval, printed."""
    values = list(values)
    return fmt_interval(median(values), bootstrap(values), digits)


def mean_cell(values: Iterable[float], digits: int) -> str:
    """A mean and its bootstrap interval, printed."""
    values = list(values)
    return fmt_interval(mean(values), bootstrap(values, np.mean), digits)


def fmt(value: float, digits: int) -> str:
    """A number as the report prints it: fixed digits, '—' for NaN."""
    if isinstance(value, float) and math.isnan(value):
        return "—"
    return f"{value:.{digits}f}"


def group(rows: Sequence[dict[str, Any]], key: Callable[[dict[str, Any]], Any]) -> dict[Any, list[dict[str, Any]]]:
    """Rows by key, keys in the order first met."""
    out: dict[Any, list[dict[str, Any]]] = {}
    for row in rows:
        out.setdefault(key(row), []).append(row)
    return out


@dataclass
class Table:
    """A titled table; ``rows`` hold the printed text of each cell."""

    name: str  # the CSV's file name, without .csv
    title: str
    columns: list[str]
    rows: list[list[str]] = field(default_factory=list)

    def add(self, *cells: str) -> None:
        if len(cells) != len(self.columns):
            raise ValueError(f"table {self.name}: {len(cells)} cells for {len(self.columns)} columns")
        self.rows.append(list(cells))

    def markdown(self) -> str:
        lines = [f"**{self.title}** ([{self.name}.csv]({self.name}.csv))", "",
                 "| " + " | ".join(self.columns) + " |", "|" + "|".join("---" for _ in self.columns) + "|"]
        lines += ["| " + " | ".join(row) + " |" for row in self.rows]
        return "\n".join(lines) + "\n"

    def write_csv(self, folder: Path) -> Path:
        path = folder / f"{self.name}.csv"
        with path.open("w", newline="", encoding="utf-8") as f:
            writer = csv.writer(f)
            writer.writerow(self.columns)
            writer.writerows(self.rows)
        return path
