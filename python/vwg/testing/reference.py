"""A straightforward pure-Python implementation of η, π and φ (paper eqs. 7-9) and of the
canonical printer, written from the paper and DESIGN.md independently of the C++ core.

It works on the nested form of ``String.tree(figures=True)``: ``("P", name, params)``,
``("F", [primitives])`` for a figure (paper rule 6, FIGURE → p+: primitives side by side),
``("A", name, params)`` and ``("T", name, params, children)``. η and π keep a figure as they keep a
primitive (eqs. 8, 9: w ∈ P gives w, for each of its primitives); φ runs α on each of its primitives in
order under the transformations around the whole figure (eq. 7: φ(T(Pa Pb)) = β(T); α(Pa); α(Pb); δ(T),
the calls of T(Pa . Pb)); the text puts a space between a figure's primitives. (In the form of
``String.tree()`` a figure's primitives stand one by one: φ gives the same calls, the text separate
objects.) The tests compare the core against it on generated strings,
and ``benchmarks/bench_core.py`` times it as the baseline. Actors are vwg.Actor classes with
per-actor handlers (batch handlers are a core optimisation and are not modelled here; a run
handler is called on each event as a run of one). Text
returned by a handler is parsed with the core's parser, figures and all; everything else is plain Python.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

import numpy as np

import vwg._core as _core
from vwg.model.actor import Actor, Context, Sym

__all__ = ["Reference"]


class _RunOfOne:
    """One event as a run handler sees a run: its fields as arrays of one value."""

    def __init__(self, e: _core.Event) -> None:
        self.type, self.target = e.type, e.target
        self.columns = {k: np.array([v]) for k, v in e.fields.items()}  # int64, float64 or bool

    def __len__(self) -> int:
        return 1

    def __getattr__(self, name: str) -> Any:
        try:
            return self.__dict__["columns"][name]
        except KeyError:
            raise AttributeError(name) from None

Tree = list[tuple[Any, ...]]


class Reference:
    """η, π and φ in plain Python for one alphabet and its actor classes."""

    def __init__(self, alphabet: _core.Alphabet, actors: Sequence[type[Actor]]) -> None:
        self.alphabet = alphabet
        self.classes = {cls.name: cls for cls in actors}
        self.responds = {name: set(alphabet.responds_to(name)) for name in alphabet.actors}
        self.visual = set(alphabet.visual_event_types)
        self.attribute_names: dict[str, list[str]] = {}
        self.has_int_id: dict[str, bool] = {}
        for name in alphabet.actors:
            params = alphabet.params(name) or {}
            self.attribute_names[name] = list(params)
            self.has_int_id[name] = "id" in params and params["id"][0] == "int"

    # --- η ------------------------------------------------------------------------------------
    def eta(self, w: Tree, events: Sequence[_core.Event], frame: int = 0) -> Tree:
        out: Tree = []
        for node in w:
            if node[0] in ("P", "F"):
                out.append(node)
            elif node[0] == "T":
                children = self.eta(node[3], events, frame)
                if children:  # t(ε) is not in L(M): an emptied scope goes with its transformation
                    out.append(("T", node[1], node[2], children))
            else:
                out.extend(self._fold(node, list(events), frame))
        return out

    def _fold(self, actor: tuple[Any, ...], events: list[_core.Event], frame: int) -> Tree:
        current = actor
        for k, e in enumerate(events):
            if e.type not in self.responds[current[1]] or not self._reaches(current, e):
                continue
            result = self._call(current, e, "on_", frame)
            if result is None:
                continue
            if len(result) == 1 and result[0][0] == "A" and result[0][1] == current[1]:
                current = result[0]
                continue
            return self.eta(result, events[k + 1:], frame)
        return [current]

    # --- π ------------------------------------------------------------------------------------
    def pi(self, w: Tree, events: Sequence[_core.Event], frame: int = 0) -> Tree:
        out: Tree = []
        for node in w:
            if node[0] in ("P", "F"):
                out.append(node)
            elif node[0] == "T":
                children = self.pi(node[3], events, frame)
                if children:
                    out.append(("T", node[1], node[2], children))
            else:
                for e in events:
                    if e.type in self.visual and e.type in self.responds[node[1]] and self._reaches(node, e):
                        shown = self._call(node, e, "show_", frame)
                        if shown:
                            out.extend(shown)
        return out

    # --- φ ------------------------------------------------------------------------------------
    def phi(self, v: Tree, calls: list[str] | None = None) -> list[str]:
        calls = [] if calls is None else calls
        for node in v:
            if node[0] == "P":
                calls.append("alpha " + self.symbol_text(node))
            elif node[0] == "F":
                calls.extend("alpha " + self.symbol_text(p) for p in node[1])
            elif node[0] == "T":
                calls.append("beta " + self.symbol_text(node))
                self.phi(node[3], calls)
                calls.append("delta " + self.symbol_text(node))
            else:
                raise ValueError(f"φ got the actor {self.symbol_text(node)}")
        return calls

    # --- text -----------------------------------------------------------------------------------
    @staticmethod
    def value_text(v: Any) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, int):
            return str(v)
        if isinstance(v, float):
            return repr(v)
        if isinstance(v, str):
            return json.dumps(v, ensure_ascii=False)
        if isinstance(v, _core.Blob):
            return "@" + v.name
        raise TypeError(f"no text for {v!r}")

    def symbol_text(self, node: tuple[Any, ...]) -> str:
        name, params = node[1], node[2]
        if not params:
            return name
        if node[0] == "A":
            names = self.attribute_names[name]
            inner = ", ".join(f"{k}={self.value_text(v)}" for k, v in zip(names, params, strict=True))
        else:
            inner = ", ".join(self.value_text(v) for v in params)
        return f"{name}<{inner}>"

    def text(self, w: Tree) -> str:
        parts = []
        for node in w:
            if node[0] == "F":
                parts.append(" ".join(self.symbol_text(p) for p in node[1]))
            elif node[0] == "T":
                parts.append(f"{self.symbol_text(node)}({self.text(node[3])})")
            else:
                parts.append(self.symbol_text(node))
        return " . ".join(parts)

    # --- helpers --------------------------------------------------------------------------------
    def _reaches(self, actor: tuple[Any, ...], e: _core.Event) -> bool:
        if e.target is None:
            return True
        if not self.has_int_id[actor[1]]:
            return False
        return actor[2][self.attribute_names[actor[1]].index("id")] == e.target

    def _call(self, actor: tuple[Any, ...], e: _core.Event, prefix: str, frame: int) -> Tree | None:
        cls = self.classes[actor[1]]
        fn = getattr(cls, f"{prefix}{e.type}", None)
        if fn is None and prefix == "on_" and (run := getattr(cls, f"on_{e.type}_run", None)) is not None:
            fn = run  # a run handler on a run of one (the same, by its contract)
            e = _RunOfOne(e)
        if fn is None:
            return None if prefix == "on_" else []
        instance = object.__new__(cls)
        object.__setattr__(instance, "_v", tuple(actor[2]))
        n_args = fn.__code__.co_argcount
        result = fn(instance, e, Context(frame, 0.0, 0)) if n_args == 3 else fn(instance, e)
        if result is instance:
            return [actor]
        return self._tree(result)

    def _tree(self, obj: Any) -> Tree:
        if isinstance(obj, str):
            return self.alphabet.parse(obj).tree(figures=True) if obj.strip() else []
        if isinstance(obj, _core.String):
            return obj.tree(figures=True)
        if isinstance(obj, Actor):
            return [("A", obj.name, tuple(obj._v))]
        if isinstance(obj, Sym):
            return [self._sym(obj)]
        if isinstance(obj, (list, tuple)):
            out: Tree = []
            for item in obj:
                out.extend(self._tree(item))
            return out
        raise TypeError(f"cannot make a string of {obj!r}")

    def _sym(self, s: Sym) -> tuple[Any, ...]:
        kind = self.alphabet.kind_of(s.name)
        declared = self.alphabet.params(s.name)
        if declared is None:
            params = tuple(s.params)
        else:
            names = list(declared)
            values = list(s.params) + [None] * (len(names) - len(s.params))
            for k, v in s.named.items():
                values[names.index(k)] = v
            params = tuple(declared[n][1] if v is None else v for n, v in zip(names, values, strict=True))
            # Widen ints given for reals, as the core does.
            params = tuple(
                float(v) if declared[n][0] == "real" and isinstance(v, int) and not isinstance(v, bool) else v
                for n, v in zip(names, params, strict=True)
            )
        if kind == "transformation":
            children: Tree = []
            for c in s.children or ():
                children.extend(self._tree(c))
            return ("T", s.name, params, children)
        return ("A" if kind == "actor" else "P", s.name, params)
