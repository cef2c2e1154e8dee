"""The report's pictures (Matplotlib, drawn off screen to PNG files)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

__all__ = ["bars", "boxes", "lines"]


def _pyplot():  # type: ignore[no-untyped-def]
    import matplotlib

    matplotlib.use("Agg")  # no display: files only
    import matplotlib.pyplot as plt

    return plt


def boxes(path: Path, title: str, ylabel: str, groups: dict[str, Sequence[float]]) -> Path:
    """A box plot per group (empty groups are shown empty), the points over it."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4), dpi=110)
    names = list(groups)
    data = [[v for v in groups[n]] or [float("nan")] for n in names]
    ax.boxplot(data, tick_labels=names, showfliers=False)
    for i, values in enumerate(data, start=1):
        ax.plot([i] * len(values), values, "o", alpha=0.45, markersize=3, color="tab:blue")
    ax.set_title(title)
    ax.set_ylabel(ylabel)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def bars(path: Path, title: str, ylabel: str, groups: dict[str, dict[str, float]]) -> Path:
    """Grouped bars: for each group (x), one bar per series."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4), dpi=110)
    names = list(groups)
    series = list(dict.fromkeys(s for g in groups.values() for s in g))
    width = 0.8 / max(1, len(series))
    for j, s in enumerate(series):
        xs = [i + (j - (len(series) - 1) / 2) * width for i in range(len(names))]
        ax.bar(xs, [groups[n].get(s, float("nan")) for n in names], width, label=s)
    ax.set_xticks(range(len(names)), names)
    ax.set_title(title)
    ax.set_ylabel(ylabel)
    ax.grid(axis="y", alpha=0.3)
    if len(series) > 1:
        ax.legend()
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def lines(path: Path, title: str, xlabel: str, ylabel: str, series: dict[str, tuple[Sequence[float], Sequence[float]]],
          points: dict[str, tuple[Sequence[float], Sequence[float]]] | None = None, logx: bool = False) -> Path:
    """A line per series (x, y), and optional scattered points."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4), dpi=110)
    for name, (xs, ys) in series.items():
        ax.plot(xs, ys, "o-", label=name)
    for name, (xs, ys) in (points or {}).items():
        ax.plot(xs, ys, ".", alpha=0.5, label=name)
    if logx:
        ax.set_xscale("log", base=2)
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path
