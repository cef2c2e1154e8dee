"""The report's pictures (Matplotlib, drawn off screen to PNG files). Each figure shows its 95 % intervals where
they are given (error bars), and its legend outside the axes, so that it never covers the data."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = ["bars", "boxes", "lines"]

Interval = tuple[float, float]


def _pyplot():  # type: ignore[no-untyped-def]
    import matplotlib

    matplotlib.use("Agg")  # no display: files only
    import matplotlib.pyplot as plt

    return plt


def _figure() -> tuple[Any, Any]:
    # Constrained layout makes room for a legend placed "outside" the axes.
    return _pyplot().subplots(figsize=(7.5, 4), dpi=110, layout="constrained")


def _legend(fig: Any, ax: Any) -> None:
    if len(ax.get_legend_handles_labels()[0]) > 1:
        fig.legend(loc="outside right upper", fontsize="small")


def _save(fig: Any, path: Path) -> Path:
    fig.savefig(path)
    _pyplot().close(fig)
    return path


def _error(value: float, interval: Interval | None) -> tuple[float, float]:
    """The lengths below and above `value` of its interval, for errorbar (0, 0 when there is none)."""
    if interval is None or math.isnan(interval[0]) or math.isnan(value):
        return (0.0, 0.0)
    return (max(0.0, value - interval[0]), max(0.0, interval[1] - value))


def boxes(path: Path, title: str, ylabel: str, groups: dict[str, Sequence[float]],
          intervals: dict[str, Interval] | None = None) -> Path:
    """A box plot per group (empty groups are shown empty), the points over it, and the median's 95 % interval as a
    bar beside each box."""
    fig, ax = _figure()
    names = list(groups)
    data = [[v for v in groups[n]] or [float("nan")] for n in names]
    ax.boxplot(data, tick_labels=names, showfliers=False)
    for i, values in enumerate(data, start=1):
        ax.plot([i] * len(values), values, "o", alpha=0.45, markersize=3, color="tab:blue",
                label="one run" if i == 1 else None)
    for i, name in enumerate(names, start=1):
        interval = (intervals or {}).get(name)
        if interval is not None and not math.isnan(interval[0]):
            ax.plot([i + 0.3, i + 0.3], interval, color="tab:red", linewidth=2.5,
                    label="median, 95 % interval" if i == 1 else None)
    ax.set_title(title)
    ax.set_ylabel(ylabel)
    ax.grid(axis="y", alpha=0.3)
    _legend(fig, ax)
    return _save(fig, path)


def bars(path: Path, title: str, ylabel: str, groups: dict[str, dict[str, float]],
         intervals: dict[str, dict[str, Interval]] | None = None) -> Path:
    """Grouped bars: for each group (x), one bar per series, with its 95 % interval where given."""
    fig, ax = _figure()
    names = list(groups)
    series = list(dict.fromkeys(s for g in groups.values() for s in g))
    width = 0.8 / max(1, len(series))
    for j, s in enumerate(series):
        xs = [i + (j - (len(series) - 1) / 2) * width for i in range(len(names))]
        values = [groups[n].get(s, float("nan")) for n in names]
        errors = [_error(v, (intervals or {}).get(n, {}).get(s)) for n, v in zip(names, values, strict=True)]
        ax.bar(xs, values, width, label=s, yerr=list(zip(*errors, strict=True)) if errors else None, capsize=3)
    ax.set_xticks(range(len(names)), names)
    ax.set_title(title)
    ax.set_ylabel(ylabel)
    ax.grid(axis="y", alpha=0.3)
    _legend(fig, ax)
    return _save(fig, path)


def lines(path: Path, title: str, xlabel: str, ylabel: str, series: dict[str, tuple[Sequence[float], Sequence[float]]],
          points: dict[str, tuple[Sequence[float], Sequence[float]]] | None = None, logx: bool = False,
          intervals: dict[str, Sequence[Interval]] | None = None) -> Path:
    """A line per series (x, y) with each point's 95 % interval where given, and optional scattered points."""
    fig, ax = _figure()
    for name, (xs, ys) in series.items():
        given = (intervals or {}).get(name)
        if given is not None:
            errors = [_error(y, i) for y, i in zip(ys, given, strict=True)]
            ax.errorbar(xs, ys, yerr=list(zip(*errors, strict=True)), fmt="o-", capsize=3, label=name)
        else:
            ax.plot(xs, ys, "o-", label=name)
    for name, (xs, ys) in (points or {}).items():
        ax.plot(xs, ys, ".", alpha=0.5, label=name)
    if logx:
        ax.set_xscale("log", base=2)
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    _legend(fig, ax)
    return _save(fig, path)
