"""vwg's messages, and those of the libraries it wraps (OMPL's planner messages), through Python's
`logging`: loggers ``vwg`` and ``vwg.<source>`` (``vwg.ompl``). A library stays quiet unless asked:
the ``vwg`` logger has a NullHandler, so nothing is printed until the application configures
logging (``logging.basicConfig(level=logging.INFO)``, or ``vwg run --verbose``).

OMPL's levels arrive one lower: its "errors" (a start state in collision, say) are failed plans that
vwg handles and reports itself, so they are warnings here."""

from __future__ import annotations

import atexit
import logging

import vwg._core as _core

__all__ = ["logger"]

logger = logging.getLogger("vwg")
logger.addHandler(logging.NullHandler())


def _forward(level: int, source: str, message: str) -> None:
    logging.getLogger(f"vwg.{source}").log(level, message)


_core.set_log_sink(_forward)
# Messages after the interpreter starts shutting down would call into a dying interpreter.
atexit.register(_core.set_log_sink, None)
