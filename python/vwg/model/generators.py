"""Event generators: ``every_frame`` (C++), ``Schedule`` (timed events) and the base class for
generators written in Python (``vwg.Generator``)."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from typing import Any

import vwg._core as _core
from vwg.errors import SchemaError

__all__ = ["GeneratorSpec", "Schedule", "every_frame", "resolve_generators"]


class GeneratorSpec:
    """A generator still to be made for an alphabet (the engine makes it when it is built)."""

    def __init__(self, make: Callable[[_core.Alphabet], _core.Generator], label: str) -> None:
        self.make = make
        self.label = label

    def __repr__(self) -> str:
        return self.label


def every_frame(event: str, target: int | None = None, **fields: Any) -> GeneratorSpec:
    """One ``event`` (with these fields, for ``target`` or for all) every frame: gDecide, gExecute."""
    return GeneratorSpec(lambda a: _core.EveryFrame(a, event, target, **fields), f"every_frame({event!r})")


class Schedule(_core.Generator):
    """Events at given frames: ``Schedule({0: ["goto<room=\\"kitchen\\">"], 50: [vwg.Event(...)]})``.
    Keys are frame numbers; values lists of events or their texts. ``at_times`` takes seconds."""

    name = "schedule"

    def __init__(self, by_frame: Mapping[int, Iterable[Any]]) -> None:
        super().__init__()
        self.by_frame: dict[int, list[Any]] = {}
        for frame, events in by_frame.items():
            if not isinstance(frame, int) or isinstance(frame, bool) or frame < 0:
                raise SchemaError(f"schedule: frame {frame!r} is not a frame number >= 0")
            self.by_frame[frame] = list(events)

    @classmethod
    def at_times(cls, by_time: Mapping[float, Iterable[Any]], dt: float) -> Schedule:
        """Events at simulated times (seconds), each at the first frame whose time reaches it."""
        import math

        by_frame: dict[int, list[Any]] = {}
        for t, events in by_time.items():
            if not (isinstance(t, (int, float)) and math.isfinite(t) and t >= 0):
                raise SchemaError(f"schedule: time {t!r} is not a finite time >= 0")
            by_frame.setdefault(math.ceil(t / dt - 1e-9), []).extend(events)
        return cls(by_frame)

    def generate(self, frame: _core.FrameInfo) -> list[Any]:
        return self.by_frame.get(frame.frame, [])


AnyGenerator = _core.Generator | GeneratorSpec


def resolve_generators(alphabet: _core.Alphabet, generators: Iterable[AnyGenerator]) -> list[_core.Generator]:
    """Generators ready for an engine: specs are made for `alphabet`."""
    out = []
    for i, g in enumerate(generators):
        if isinstance(g, GeneratorSpec):
            out.append(g.make(alphabet))
        elif isinstance(g, _core.Generator):
            out.append(g)
        else:
            raise SchemaError(f"generators[{i}]: expected a vwg.Generator or every_frame(...), got {type(g).__name__}")
    return out
