"""Actor types written in Python, and ``Sym``, a way to build strings without text.

An actor type is a class::

    class Blinker(vwg.Actor):
        events = ("tick", "show")          # H: the event types it responds to
        attributes = {"on": False}         # name -> default (its type) or a type (required)

        def on_tick(self, e):              # λ for "tick": return a string of L(M)
            return self.with_(on=not self.on)

        def show_show(self, e):            # θ for the visual event "show": no actors
            return "Lamp<1>" if self.on else ""

λ handlers are ``on_<event>(self, e)``, θ handlers ``show_<event>(self, e)``; either may take a
third argument ``ctx`` (a ``Context`` with the frame, time and a seed). A handler returns ``self``
(unchanged), ``self.with_(...)``, another actor, text in the text form, a ``Sym``, or a list of
these (concatenated); ``""`` or ``[]`` is ε. Actors are values: their attributes cannot be
assigned, only replaced through ``with_``.

Run λ: ``on_<event>_run(self, events)`` (or with ``ctx``) receives at once every event of a run
that reaches the actor — consecutive events of that type, such as a laser's scan, one event a
beam — as a ``vwg.EventColumns``: ``events.dist`` and ``events.angle`` are read-only numpy arrays,
one value an event, in order (int and bool fields as int64 and bool arrays; the event type may
have no text or blob field). It stands for ``on_<event>`` on each event in turn and must give the
same result, so it returns ``self`` or ``self.with_(...)``: the actor stays one actor. With a run
handler, every event of that type goes through it (a lone event is a run of one); ``ctx`` is the
first event's.

Batch λ: a classmethod ``on_<event>_batch(cls, actors, e)`` receives all the actors of the type
that get the event at once, as writable numpy columns (``actors.x``). A class with batch handlers
needs one for every event it responds to, and its actors stay single actors. A class has run
handlers or batch handlers, not both.
"""

from __future__ import annotations

import inspect
import keyword
from collections.abc import Callable
from typing import Any, ClassVar

import numpy as np

from vwg.errors import SchemaError

__all__ = ["Actor", "Context", "Sym"]

_RESERVED = {"name", "events", "attributes", "with_", "handlers", "values"}


class Context:
    """What λ and θ know about the frame: ``frame``, ``time`` and ``seed`` (unique to the engine
    seed, frame, actor position and event position)."""

    __slots__ = ("frame", "seed", "time")

    def __init__(self, frame: int, time: float, seed: int) -> None:
        self.frame = frame
        self.time = time
        self.seed = seed

    def rng(self) -> np.random.Generator:
        """A numpy random generator seeded with ``seed``: reproducible random decisions."""
        return np.random.default_rng(self.seed)

    def __repr__(self) -> str:
        return f"vwg.Context(frame={self.frame}, time={self.time!r}, seed={self.seed})"


class Actor:
    """Base class of actor types written in Python (see the module documentation)."""

    __slots__ = ("_v",)

    name: ClassVar[str] = "Actor"
    events: ClassVar[tuple[str, ...]] = ()
    attributes: ClassVar[dict[str, Any]] = {}
    _attribute_names: ClassVar[tuple[str, ...]] = ()
    _attribute_index: ClassVar[dict[str, int]] = {}
    _v: tuple[Any, ...]

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "name" not in cls.__dict__:
            cls.name = cls.__name__
        cls.events = tuple(cls.events)
        attributes = cls.attributes
        if isinstance(attributes, (list, tuple)):
            raise SchemaError(f"{cls.name}.attributes: declare a dict {{name: default or type}}, not a list")
        names = tuple(attributes)
        for n in names:
            if not n.isidentifier() or keyword.iskeyword(n) or n.startswith("_"):
                raise SchemaError(f"{cls.name}.{n}: not a valid attribute name")
            if n in _RESERVED or n.startswith(("on_", "show_")):
                raise SchemaError(f"{cls.name}.{n}: the name is reserved by vwg.Actor")
        cls._attribute_names = names
        cls._attribute_index = {n: i for i, n in enumerate(names)}
        for i, n in enumerate(names):
            setattr(cls, n, property(lambda self, i=i: self._v[i], doc=f"Attribute {n}."))
        # Handlers named for events the class does not declare are typos; say so now.
        for attr in dir(cls):
            for prefix in ("on_", "show_"):
                if attr.startswith(prefix):
                    event = attr[len(prefix):]
                    if prefix == "on_" and event not in cls.events:
                        for suffix in ("_batch", "_run"):
                            if event.endswith(suffix):
                                event = event[: -len(suffix)]
                                break
                    if event not in cls.events:
                        raise SchemaError(
                            f"{cls.name}.{attr}: '{event}' is not among {cls.name}.events {cls.events}"
                        )

    def __init__(self, **attributes: Any) -> None:
        values = []
        for n in self._attribute_names:
            if n in attributes:
                values.append(attributes.pop(n))
                continue
            default = type(self).attributes[n]
            if isinstance(default, type):
                raise SchemaError(f"{self.name}.{n}: missing (it has no default)")
            values.append(default)
        if attributes:
            raise SchemaError(f"{self.name}.{next(iter(attributes))}: no such attribute "
                              f"(attributes: {', '.join(self._attribute_names) or 'none'})")
        object.__setattr__(self, "_v", tuple(values))

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"actors are values: use self.with_({name}=...) to return a changed copy")

    def with_(self, **changes: Any) -> Any:
        """A copy of this actor with some attributes changed."""
        values = list(self._v)
        for k, v in changes.items():
            i = self._attribute_index.get(k)
            if i is None:
                raise SchemaError(f"{self.name}.{k}: no such attribute "
                                  f"(attributes: {', '.join(self._attribute_names) or 'none'})")
            values[i] = v
        new = object.__new__(type(self))
        object.__setattr__(new, "_v", tuple(values))
        return new

    @property
    def values(self) -> dict[str, Any]:
        """The attributes as a dict."""
        return dict(zip(self._attribute_names, self._v, strict=True))

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and other._v == self._v  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash((type(self).name, self._v))

    def __repr__(self) -> str:
        if not self._v:
            return self.name
        inner = ", ".join(f"{k}={v!r}" for k, v in zip(self._attribute_names, self._v, strict=True))
        return f"{self.name}<{inner}>"

    @classmethod
    def handlers(cls) -> tuple[dict[str, tuple[Callable[..., Any], bool]], ...]:
        """The λ, θ, batch λ and run λ handlers by event name: {event: (function, wants_context)}."""

        def wants_context(fn: Callable[..., Any], base: int) -> bool:
            params = [p for p in inspect.signature(fn).parameters.values()
                      if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
            if len(params) not in (base, base + 1):
                raise SchemaError(f"{cls.name}.{fn.__name__}: takes {len(params)} positional arguments; "
                                  f"expected {base} or {base + 1} (with ctx)")
            return len(params) == base + 1

        on: dict[str, tuple[Callable[..., Any], bool]] = {}
        show: dict[str, tuple[Callable[..., Any], bool]] = {}
        batch: dict[str, tuple[Callable[..., Any], bool]] = {}
        run: dict[str, tuple[Callable[..., Any], bool]] = {}
        for e in cls.events:
            if (fn := cls.__dict__.get(f"on_{e}") or getattr(cls, f"on_{e}", None)) is not None:
                on[e] = (fn, wants_context(fn, 2))
            if (fn := getattr(cls, f"show_{e}", None)) is not None:
                show[e] = (fn, wants_context(fn, 2))
            # (on_<e>_batch and on_<e>_run are the λ of an event named "<e>_batch" or "<e>_run"
            # if the class has one)
            if f"{e}_batch" not in cls.events and (fn := getattr(cls, f"on_{e}_batch", None)) is not None:
                batch[e] = (fn, wants_context(fn, 2))  # a bound classmethod: (actors, e)
            if f"{e}_run" not in cls.events and (fn := getattr(cls, f"on_{e}_run", None)) is not None:
                run[e] = (fn, wants_context(fn, 2))
        return on, show, batch, run


class Sym:
    """A symbol built without text: ``Sym("Move", 0.5)(Sym("Robot"))`` is ``Move<0.5>(Robot)``.
    Parameters go by position or by name; calling a transformation's Sym gives it children."""

    __slots__ = ("children", "name", "named", "params")

    def __init__(self, name: str, *params: Any, **named: Any) -> None:
        self.name = name
        self.params = params
        self.named = named
        self.children: tuple[Any, ...] | None = None

    def __call__(self, *children: Any) -> Sym:
        new = Sym(self.name, *self.params, **self.named)
        new.children = children
        return new

    def __repr__(self) -> str:
        args = [repr(p) for p in self.params] + [f"{k}={v!r}" for k, v in self.named.items()]
        s = f"Sym({self.name!r}{''.join(', ' + a for a in args)})"
        if self.children is not None:
            s += "(" + ", ".join(repr(c) for c in self.children) + ")"
        return s
