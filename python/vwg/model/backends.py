"""The backends written in C++ that ship with vwg, as factories the ``vwg.backends`` entry points of
vwg's pyproject.toml name (each takes the world file's ``world=`` and ``spec=`` and needs neither):
``null`` (shows nothing) and ``trace`` (keeps what α/β/δ were called with)."""

from __future__ import annotations

from typing import Any

import vwg._core as _core

__all__ = ["null", "trace"]


def null(**_options: Any) -> _core.Backend:
    """A backend that shows nothing."""
    return _core.create_backend("null")


def trace(**_options: Any) -> _core.Backend:
    """A backend that records the α, β and δ calls of each frame (vwg.TraceBackend)."""
    return _core.create_backend("trace")
