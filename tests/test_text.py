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
