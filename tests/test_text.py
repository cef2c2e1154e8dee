"""The text form: canonical printing, parse(print(w)) == w, and errors that say where and what."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import vwg
from conftest import make_world
from vwg.testing.reference import Reference
from world_strategies import figure_worlds

WORLD = make_world()
REF = Reference(WORLD.alphabet, [])

finite = st.floats(allow_nan=False, allow_infinity=False)
ints = st.integers(min_value=-(2**63), max_value=2**63 - 1)
texts = st.text(max_size=12)
variadic_value = st.one_of(ints, finite, st.booleans(), texts)

leaf = st.one_of(
    st.just(vwg.Sym("Lamp")),
    st.lists(variadic_value, max_size=3).map(lambda p: vwg.Sym("Lamp", *p)),
    ints.map(lambda i: vwg.Sym("Robot", i)),
    st.tuples(ints, finite, texts, st.booleans()).map(lambda t: vwg.Sym("Dot", *t)),
    ints.map(lambda n: vwg.Sym("Counter", n=n)),
    st.just(vwg.Sym("Mortal")),
    st.tuples(ints, ints, texts, st.booleans()).map(
        lambda t: vwg.Sym("Tagged", id=t[0], hits=t[1], label=t[2], on=t[3])
    ),
)


def scope(children):
    return st.one_of(
        finite.map(lambda d: vwg.Sym("Move", d)),
        finite.map(lambda a: vwg.Sym("Rotate", a)),
        st.lists(variadic_value, max_size=2).map(lambda p: vwg.Sym("Group", *p)),
    ).flatmap(lambda t: st.lists(children, min_size=1, max_size=3).map(lambda kids: t(*kids)))


objects = st.recursive(leaf, scope, max_leaves=12)
worlds = st.lists(objects, max_size=5)


@settings(max_examples=300, deadline=None)
@given(worlds)
@pytest.mark.slow
def test_parse_of_print_is_the_same_string(parts):
    w = WORLD.string(*parts)
    text = str(w)
    back = WORLD.parse(text)
    assert back == w
    assert str(back) == text  # printing is canonical
    assert hash(back) == hash(w)


@settings(max_examples=300, deadline=None)
@given(worlds)
@pytest.mark.slow
def test_core_printer_agrees_with_an_independent_python_printer(parts):
    w = WORLD.string(*parts)
    assert str(w) == REF.text(w.tree())


@given(finite)
def test_reals_print_as_python_repr_and_round_trip(x):
    w = WORLD.string(vwg.Sym("Move", x)(vwg.Sym("Lamp")))
    assert str(w) == f"Move<{x!r}>(Lamp)"
    value = w.nodes()[0].params[0]
    assert value == x and math.copysign(1.0, value) == math.copysign(1.0, x)


@given(texts)
def test_text_values_print_as_json_and_round_trip(s):
    import json

    w = WORLD.string(vwg.Sym("Lamp", s))
    assert str(w) == f"Lamp<{json.dumps(s, ensure_ascii=False)}>"
    assert WORLD.parse(str(w)).nodes()[0].params[0] == s


def test_hand_written_canonical_forms(world):
    assert str(world.parse("Move<1>( Robot )·Lamp<2, 2.5, true, \"x\"> # comment")) == \
        'Move<1.0>(Robot<0>) . Lamp<2, 2.5, true, "x">'
    assert str(world.parse("Tagged<id=4>")) == 'Tagged<id=4, hits=0, label="t", on=false>'
    assert str(world.parse("Dot<b=1e16, a=-3>")) == 'Dot<-3, 1e+16, "", false>'
    assert str(world.parse("")) == "" and world.parse("").empty


@pytest.mark.parametrize(
    ("text", "line", "column", "found", "expected"),
    [
        ("Move<1.0>(Robot) .\n  Robt", 2, 3, "unknown symbol 'Robt'", "did you mean 'Robot'?"),
        ("Move<1.0>(Robot", 1, 16, "end of text", "')' to close the scope of 'Move' opened at line 1, column 1"),
        ("Move<1.0>()", 1, 11, "')'", "rule 5"),
        ("Move<\"far\">(Robot)", 1, 6, 'text "far"', "real for Move.dist"),
        ("Tagged<hits=2>", 1, 1, "'Tagged' without it", "attribute 'id' of 'Tagged'"),
        ("Tagged<id=1, hit=2>", 1, 18, "'hit'", "id, hits, label, on"),
        ("Robot(Lamp)", 1, 6, "'('", "only transformations take a scope"),
        ("Lamp . add", 1, 8, "unknown symbol 'add'", "'add' is an event type"),
        ("Lamp<nan>", 1, 6, "'nan'", "a value"),
        ("Lamp<1e400>", 1, 6, "'1e400'", "a finite real number"),
        ("Lamp)", 1, 5, "')'", "no scope is open"),
        # Rule 6 juxtaposes primitives only (FIGURE → p+); anything else beside an object wants '.'.
        ("Lamp Tagged<id=1>", 1, 6, "'Tagged'", "'Tagged' is an actor"),
        ("Tagged<id=1> Lamp", 1, 14, "'Lamp'", "an actor is followed by '.'"),
        ("Lamp Move<1.0>(Lamp)", 1, 6, "'Move'", "'Move' is a transformation"),
        ("Move<1.0>(Lamp) Lamp", 1, 17, "'Lamp'", "a transformation's scope is followed by '.'"),
        ("Move<1.0>(Lamp\n  Mortal)", 2, 3, "'Mortal'", "'.' or ')'"),
        ("Lamp<1>Lamp", 1, 8, "'Lamp'", "white space between the primitives of a figure"),
        ("Lamp Lmp", 1, 6, "unknown symbol 'Lmp'", "did you mean 'Lamp'?"),
    ],
)
def test_parse_errors_name_line_column_found_and_expected(world, text, line, column, found, expected):
    with pytest.raises(vwg.ParseError) as info:
        world.parse(text, source="w.txt")
    e = info.value
    assert (e.source, e.line, e.column) == ("w.txt", line, column)
    assert e.found == found
    assert expected in e.expected
    assert str(e).startswith(f"w.txt:{line}:{column}: found {found}")


def test_blobs_are_named_by_content_and_resolved_through_a_table(world):
    a = np.arange(6, dtype=np.int8).reshape(2, 3)
    blob = vwg.Blob(a)
    assert blob == vwg.Blob(a.copy()) and blob.name == vwg.Blob(a.copy()).name
    assert blob.name != vwg.Blob(a + 1).name
    view = np.asarray(blob)
    assert view.dtype == np.int8 and view.shape == (2, 3) and not view.flags.writeable
    np.testing.assert_array_equal(view, a)
    alphabet = vwg.Alphabet(events=[], primitives={"Grid": {"g": vwg.Blob}})
    w = alphabet.parse("Grid<@mine>", "<t>", {"mine": blob})
    assert str(w) == f"Grid<@{blob.name}>"
    assert alphabet.parse(str(w), "<t>", w.blobs()) == w
    with pytest.raises(vwg.ParseError, match="unknown blob"):
        alphabet.parse("Grid<@other>", "<t>", {"mine": blob})
    with pytest.raises(vwg.SchemaError, match="NaN"):
        vwg.Blob(np.array([1.0, np.nan]))
    with pytest.raises(vwg.SchemaError, match="dtype"):
        vwg.Blob(np.array(["a"]))


# --- figures: primitives side by side (paper rule 6, FIGURE → p+) --------------------------------

primitive = st.one_of(
    st.lists(variadic_value, max_size=3).map(lambda p: ("P", "Lamp", tuple(p))),
    ints.map(lambda i: ("P", "Robot", (i,))),
    st.tuples(ints, finite, texts, st.booleans()).map(lambda t: ("P", "Dot", t)),
)
tree_actor = st.one_of(
    ints.map(lambda n: ("A", "Counter", (n,))),
    st.just(("A", "Mortal", ())),
    st.tuples(ints, ints, texts, st.booleans()).map(lambda t: ("A", "Tagged", t)),
)
tree_transformation = st.one_of(
    finite.map(lambda d: ("Move", (d,))),
    finite.map(lambda a: ("Rotate", (a,))),
    st.lists(variadic_value, max_size=2).map(lambda p: ("Group", tuple(p))),
)
tree_worlds = figure_worlds(primitive, tree_actor, tree_transformation, figure_size=4, max_leaves=12, max_objects=5)


@settings(max_examples=300, deadline=None)
@given(tree_worlds)
@pytest.mark.slow
def test_figures_parse_to_their_tree_and_print_back_as_written(tree):
    text = REF.text(tree)  # printed by the reference, independently of the core
    w = WORLD.parse(text)
    assert str(w) == text  # print(parse(text)) == text
    assert w.tree(figures=True) == tree
    back = WORLD.parse(str(w))  # parse(print(w)) == w
    assert back == w and hash(back) == hash(w)


def test_figures_of_primitives_side_by_side(world):
    text = 'Move<1.0>(Robot<1> Lamp<2, "x">) . Lamp Dot<1, 2.0, "", true> . Counter<n=3>'
    w = world.parse(text)
    assert str(w) == text
    assert world.parse(str(w)) == w
    assert len(w) == 6
    assert [(n.name, n.joined) for n in w.nodes()] == [
        ("Move", False), ("Robot", False), ("Lamp", True), ("Lamp", False), ("Dot", True), ("Counter", False)]
    assert w.tree(figures=True) == [
        ("T", "Move", (1.0,), [("F", [("P", "Robot", (1,)), ("P", "Lamp", (2, "x"))])]),
        ("F", [("P", "Lamp", ()), ("P", "Dot", (1, 2.0, "", True))]),
        ("A", "Counter", (3,)),
    ]
    # Without figures=True the tree lists a figure's primitives one by one, as before.
    assert w.tree()[1:3] == [("P", "Lamp", ()), ("P", "Dot", (1, 2.0, "", True))]
    # Any white space or comment between the primitives of a figure.
    assert str(world.parse("Robot<1>\n   Lamp  # a comment\n\tRobot")) == "Robot<1> Lamp Robot<0>"
    # A figure is not the string of its primitives as separate objects (φ runs both alike).
    assert world.parse("Lamp Lamp") != world.parse("Lamp . Lamp")
    assert hash(world.parse("Lamp Lamp")) != hash(world.parse("Lamp . Lamp"))
    # Strings from Python parts: text keeps its figures; parts are objects joined by '.'.
    assert str(world.string("Lamp Robot<2>", vwg.Sym("Lamp"))) == "Lamp Robot<2> . Lamp"
