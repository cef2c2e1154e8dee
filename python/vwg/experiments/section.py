"""A section of the report: its heading, its text, its tables and its pictures."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from vwg.experiments.tables import Table

__all__ = ["Section"]


@dataclass
class Section:
    number: int
    title: str  # the paper's name of the test
    method: str  # what was run, how it is measured
    tables: list[Table] = field(default_factory=list)
    plots: list[Path] = field(default_factory=list)
    findings: list[str] = field(default_factory=list)  # sentences made from the numbers of this run

    def markdown(self) -> str:
        parts = [f"## {self.number}. {self.title}\n", self.method.strip() + "\n"]
        for table in self.tables:
            parts.append(table.markdown())
        for plot in self.plots:
            parts.append(f"![{plot.stem}]({plot.name})\n")
        if self.findings:
            parts.append("In this run:\n\n" + "".join(f"- {f}\n" for f in self.findings))
        return "\n".join(parts)
