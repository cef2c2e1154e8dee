"""A robot world live in the browser (``vwg serve``): vwg.serve.live runs it, vwg.serve.server shows it."""

from __future__ import annotations

from vwg.serve.live import LiveRun, Snapshot

__all__ = ["LiveRun", "Snapshot"]
