"""Alphabets and worlds: what the strings of a world are made of."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import vwg._core as _core
from vwg.errors import SchemaError
from vwg.model.actor import Actor

__all__ = ["Alphabet", "World"]

ParamSpec = None | Mapping[str, Any] | Iterable[str]


def _named(spec: Iterable[str] | Mapping[str, Any], what: str) -> list[tuple[str, Any]]:
    """[(name, params)] from a list of names or a dict {name: params}."""
    if isinstance(spec, str):
        raise SchemaError(f"{what}: give a list of names or a dict, not the string {spec!r}")
    if isinstance(spec, Mapping):
        return list(spec.items())
    return [(name, None) for name in spec]


class Alphabet(_core.Alphabet):
    """An alphabet declared in one go (paper §II.A)::

        vwg.Alphabet(primitives=["Lamp"], transformations={"Move": {"dist": 0.0}},
                     events=["tick", "show"], visual=["show"], actors=[Blinker])

    ``primitives`` and ``transformations``: a list of names (any positional parameters) or a dict
    {name: parameters}. ``events``: a list of names or a dict {name: fields}; ``visual`` names
    the visual ones (V ⊆ D). ``actors``: vwg.Actor classes, or (name, events, attributes, behavior)
    tuples for actor types implemented in C++. More can be added later with the add_* methods."""

    def __init__(
        self,
        primitives: Iterable[str] | Mapping[str, ParamSpec] = (),
        transformations: Iterable[str] | Mapping[str, ParamSpec] = (),
        events: Iterable[str] | Mapping[str, ParamSpec] = (),
        visual: Iterable[str] = (),
        actors: Iterable[type[Actor] | tuple[Any, ...]] = (),
    ) -> None:
        super().__init__()
        visual = set(visual)
        for name, params in _named(primitives, "primitives"):
            self.add_primitive(name, params)
        for name, params in _named(transformations, "transformations"):
            self.add_transformation(name, params)
        declared = set()
        for name, fields in _named(events, "events"):
            self.add_event_type(name, name in visual, fields)
            declared.add(name)
        for name in sorted(visual - declared):
            raise SchemaError(f"visual: '{name}' is not among the events")
        for actor in actors:
            self.add_actor_type(actor)

    def add_actor_type(self, actor: type[Actor] | tuple[Any, ...]) -> None:
        """Register a vwg.Actor class, or a C++ actor type given as (name, events, attributes, behavior)."""
        if isinstance(actor, tuple):
            self.add_actor(*actor)
            return
        if not (isinstance(actor, type) and issubclass(actor, Actor)):
            raise SchemaError(f"actors: expected a vwg.Actor subclass, got {actor!r}")
        on, show, batch, run = actor.handlers()
        if batch:
            missing = [e for e in on if e not in batch]
            if missing:
                raise SchemaError(f"{actor.name}.on_{missing[0]}_batch: missing; an actor with batch handlers "
                                  f"needs one for every λ event (it has on_{missing[0]})")
        # The type is registered first (the behavior resolves event names through the alphabet).
        self.add_actor(actor.name, list(actor.events), dict(actor.attributes), None)
        self.set_behavior(actor.name, _core.PythonActor(self, actor, on, show, batch, run))


class World:
    """An alphabet and the things made with it: parse strings, events and generators."""

    def __init__(self, alphabet: _core.Alphabet | None = None, **declarations: Any) -> None:
        if alphabet is not None and declarations:
            raise SchemaError("World: give an alphabet or declarations, not both")
        self.alphabet = alphabet if alphabet is not None else Alphabet(**declarations)

    def parse(self, text: str, source: str = "<string>", blobs: Mapping[str, Any] | None = None) -> _core.String:
        """Parse a world string; errors name `source`, the line and the column."""
        return self.alphabet.parse(text, source, dict(blobs) if blobs else None)

    def string(self, *parts: Any) -> _core.String:
        """A string built from actors, vwg.Sym, text and Strings, concatenated in order."""
        return _core.build_string(self.alphabet, list(parts))

    def event(self, text: str) -> _core.Event:
        """Parse one event from its text, e.g. ``'eLaser<dist=1.5, angle=0.1>'``."""
        return self.alphabet.parse_event(text)

    def __repr__(self) -> str:
        a = self.alphabet
        return (f"vwg.World(primitives={a.primitives}, transformations={a.transformations}, "
                f"actors={a.actors}, events={a.event_types}, visual={a.visual_event_types})")
