"""Hypothesis strategies shared by the test files (conftest puts this folder on sys.path).

figure_worlds: lists of objects in the nested form of ``String.tree(figures=True)`` (paper rule 6,
FIGURE → p+), built without the core, so that a test can print them with vwg.testing.reference and hold
the core's parser, printer, η, π and φ against them."""

from __future__ import annotations

from hypothesis import strategies as st


def figure_worlds(primitive, actor, transformation, *, figure_size, max_leaves, max_objects):
    """Lists of up to `max_objects` objects: a leaf is a `primitive` ("P", name, params), a figure
    ("F", [2 to `figure_size` primitives]) or an `actor` ("A", name, params); a scope is
    ("T", name, params, [1 to 3 objects]), its name and params drawn from `transformation`."""
    figure = st.lists(primitive, min_size=2, max_size=figure_size).map(lambda ps: ("F", ps))

    def scope(children):
        return transformation.flatmap(
            lambda t: st.lists(children, min_size=1, max_size=3).map(lambda kids: ("T", t[0], t[1], kids)))

    return st.lists(st.recursive(st.one_of(primitive, figure, actor), scope, max_leaves=max_leaves),
                    max_size=max_objects)
