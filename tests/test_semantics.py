"""η (eq. 8), π (eq. 9) and φ (eq. 7) through Python actors: hand-worked cases, and generated
worlds on which the core must agree with the pure-Python reference implementation."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import vwg
from conftest import ACTORS, make_world
from vwg.testing.reference import Reference
from world_strategies import figure_worlds

WORLD = make_world()
REF = Reference(WORLD.alphabet, ACTORS)


def ev(*texts):
    return [WORLD.event(t) for t in texts]


def eta(w, *events):
    return str(vwg.evolve(WORLD.parse(w), ev(*events)))


def pi(w, *events):
    return str(vwg.visualize(WORLD.parse(w), ev(*events)))


# --- η ------------------------------------------------------------------------------------------

def test_primitives_and_transformations_are_kept():
    assert eta("Lamp<1> . Move<2.0>(Robot<3>)", "add<k=1>", "die") == "Lamp<1> . Move<2.0>(Robot<3>)"


def test_actors_fold_over_the_events_in_order():
    # (1 + 2) * 3 = 9 and 1 * 3 + 2 = 5; events outside H in between change nothing.
    assert eta("Counter<n=1>", "add<k=2>", "mul<k=3>") == "Counter<n=9>"
    assert eta("Counter<n=1>", "mul<k=3>", "add<k=2>") == "Counter<n=5>"
    assert eta("Counter<n=1>", "add<k=2>", "tick", "die", "mul<k=3>") == "Counter<n=9>"


def test_actor_becomes_empty_and_its_scope_goes_with_it():
    assert eta("Lamp . Mortal . Robot", "die") == "Lamp . Robot<0>"
    assert eta("Rotate<1.0>(Move<2.0>(Mortal)) . Lamp", "die") == "Lamp"
    assert eta("Move<2.0>(Mortal . Lamp)", "die") == "Move<2.0>(Lamp)"
    assert eta("Mortal", "die") == ""


def test_spawned_actors_take_the_remaining_events():
    assert eta("Splitter<gen=0>", "split") == "Splitter<gen=1> . Splitter<gen=1>"
    assert eta("Splitter<gen=0>", "split", "split") == " . ".join(["Splitter<gen=2>"] * 4)


def test_actor_wraps_itself_in_nested_scopes():
    assert eta("Rotate<0.5>(Mortal)", "poke", "poke") == "Rotate<0.5>(Move<1.0>(Move<1.0>(Mortal)))"
    assert eta("Mortal . Lamp", "poke", "die") == "Lamp"


def test_targeted_events_reach_only_that_actor():
    assert eta("Tagged<id=1> . Tagged<id=2>", "poke<to=2>", "poke") == (
        'Tagged<id=1, hits=1, label="t", on=true> . Tagged<id=2, hits=2, label="t", on=false>')


# --- π ------------------------------------------------------------------------------------------

def test_theta_for_visual_events_in_h_and_v_only():
    # Counter shows Lamp<n> for show; Mortal shows for glow only; add is not visual.
    assert pi("Robot<1> . Move<1.0>(Counter<n=7>) . Mortal", "add<k=1>", "show") == "Robot<1> . Move<1.0>(Lamp<7>)"
    assert pi("Counter<n=7> . Mortal", "glow") == 'Lamp<"m">'
    assert pi("Counter<n=2>", "show", "show") == "Lamp<2> . Lamp<2>"
    assert pi("Counter<n=2>", "tick") == ""


def test_theta_may_not_return_an_actor():
    class Liar(vwg.Actor):
        events = ("show",)

        def show_show(self, e):
            return self

    w = vwg.World(events=["show"], visual=["show"], actors=[Liar])
    try:
        vwg.visualize(w.parse("Liar"), [vwg.Event("show")], frame=4)
    except vwg.FrameError as e:
        assert (e.frame, e.stage, e.actor, e.event) == (4, "visualize", "Liar", "show")
        assert "L(M')" in str(e)
    else:
        raise AssertionError("no error")


# --- φ ------------------------------------------------------------------------------------------

def test_phi_calls_alpha_beta_delta_in_order():
    trace = vwg.TraceBackend()
    vwg.display(WORLD.parse("Move<1.0>(Rotate<2.0>(Robot) . Lamp) . Lamp<3>"), trace)
    assert trace.calls == ["beta Move<1.0>", "beta Rotate<2.0>", "alpha Robot<0>", "delta Rotate<2.0>",
                           "alpha Lamp", "delta Move<1.0>", "alpha Lamp<3>"]


def test_python_backend_receives_nodes():
    class Collect(vwg.Backend):
        def __init__(self):
            super().__init__()
            self.seen = []

        def primitive(self, p):
            self.seen.append(("alpha", p.name, p.params))

        def open(self, t):
            self.seen.append(("beta", t.name, t["dist"]))

        def close(self, t):
            self.seen.append(("delta", t.name))

    g = Collect()
    vwg.display(WORLD.parse("Move<2.5>(Robot<7>)"), g)
    assert g.seen == [("beta", "Move", 2.5), ("alpha", "Robot", (7,)), ("delta", "Move")]


# --- the core against the reference on generated worlds -------------------------------------------

small_int = st.integers(-5, 5)
actor = st.one_of(
    small_int.map(lambda n: vwg.Sym("Counter", n=n)),
    st.just(vwg.Sym("Mortal")),
    st.integers(0, 2).map(lambda g: vwg.Sym("Splitter", gen=g)),
    st.tuples(st.integers(0, 3), small_int).map(lambda t: vwg.Sym("Tagged", id=t[0], hits=t[1])),
)
leaf = st.one_of(actor, st.just(vwg.Sym("Lamp")), small_int.map(lambda i: vwg.Sym("Robot", i)))
objects = st.recursive(
    leaf,
    lambda kids: st.tuples(st.sampled_from(["Move", "Rotate"]), st.floats(-2, 2, allow_nan=False),
                           st.lists(kids, min_size=1, max_size=3)).map(lambda t: vwg.Sym(t[0], t[1])(*t[2])),
    max_leaves=10,
)
event = st.one_of(
    small_int.map(lambda k: vwg.Event("add", k=k)),
    small_int.map(lambda k: vwg.Event("mul", k=k)),
    st.sampled_from(["die", "poke", "show", "glow", "tick"]).map(vwg.Event),
    st.integers(0, 3).map(lambda t: vwg.Event("poke", target=t)),
    st.integers(0, 3).map(lambda t: vwg.Event("show", target=t)),
)


@settings(max_examples=400, deadline=None)
@given(st.lists(objects, max_size=4), st.lists(event, max_size=5), st.lists(st.just(vwg.Event("split")), max_size=2))
@pytest.mark.slow
def test_core_eta_pi_phi_agree_with_the_reference(parts, events, splits):
    w = WORLD.string(*parts)
    events = events + splits
    tree = w.tree()
    assert str(vwg.evolve(w, events)) == REF.text(REF.eta(tree, events))
    v = vwg.visualize(w, events)
    assert str(v) == REF.text(REF.pi(tree, events))
    trace = vwg.TraceBackend()
    vwg.display(v, trace)
    assert trace.calls == REF.phi(v.tree())


class Renamer(vwg.Actor):
    """rename<new>: takes the id `new`; ping: counts the pings that reach it."""

    events = ("rename", "ping")
    attributes = {"id": 1, "pings": 0}

    def on_rename(self, e):
        return self.with_(id=e.new)

    def on_ping(self, e):
        return self.with_(pings=self.pings + 1)


def test_addressed_events_follow_an_actor_that_changes_its_id_within_the_frame():
    # Events reach an actor by its id at the moment it takes them (the fold of DESIGN.md choice 1):
    # the first ping (to 2) and the last (to 1) miss it, the one after the rename reaches it.
    world = vwg.World(events={"rename": {"new": 0}, "ping": None}, actors=[Renamer])
    events = [world.event(t) for t in ("ping<to=2>", "rename<to=1, new=2>", "ping<to=2>", "ping<to=1>", "ping")]
    w = vwg.evolve(world.parse("Renamer<id=1> . Renamer<id=3>"), events)
    assert str(w) == "Renamer<id=2, pings=2> . Renamer<id=3, pings=1>"  # the untargeted ping reaches both


# --- figures (rule 6, FIGURE → p+) ----------------------------------------------------------------

primitive = st.one_of(st.just(("P", "Lamp", ())), small_int.map(lambda i: ("P", "Robot", (i,))))
tree_actor = st.one_of(
    small_int.map(lambda n: ("A", "Counter", (n,))),
    st.just(("A", "Mortal", ())),
    st.integers(0, 2).map(lambda g: ("A", "Splitter", (g,))),
    st.tuples(st.integers(0, 3), small_int).map(lambda t: ("A", "Tagged", (t[0], t[1], "t", False))),
)
tree_worlds = figure_worlds(
    primitive, tree_actor,
    st.tuples(st.sampled_from(["Move", "Rotate"]), st.floats(-2, 2, allow_nan=False).map(lambda d: (d,))),
    figure_size=3, max_leaves=10, max_objects=4)


@settings(max_examples=400, deadline=None)
@given(tree_worlds, st.lists(event, max_size=5),
       st.lists(st.just(vwg.Event("split")), max_size=2))
@pytest.mark.slow
def test_core_eta_pi_phi_of_figures_agree_with_the_reference(tree, events, splits):
    # The core reads the text; the reference works on the tree the text was written from.
    w = WORLD.parse(REF.text(tree))
    events = events + splits
    assert str(vwg.evolve(w, events)) == REF.text(REF.eta(tree, events))
    v = vwg.visualize(w, events)
    ref_v = REF.pi(tree, events)
    assert str(v) == REF.text(ref_v)
    trace = vwg.TraceBackend()
    vwg.display(v, trace)
    assert trace.calls == REF.phi(ref_v)


class Turtle(vwg.Backend):
    """A drawing: where each primitive lands, Move<d> going d along the heading and Rotate<a> turning by a
    (β applies them, δ undoes them)."""

    def __init__(self):
        super().__init__()
        self.poses = [(0.0, 0.0, 0.0)]
        self.drawn = []

    def primitive(self, p):
        x, y, _ = self.poses[-1]
        self.drawn.append((p.text, round(x, 9), round(y, 9)))

    def open(self, t):
        x, y, a = self.poses[-1]
        if t.name == "Move":
            self.poses.append((x + t["dist"] * math.cos(a), y + t["dist"] * math.sin(a), a))
        else:
            self.poses.append((x, y, a + t["angle"]))

    def close(self, t):
        self.poses.pop()


def drawing(text):
    turtle = Turtle()
    vwg.display(WORLD.parse(text), turtle)
    return turtle.drawn


def calls(text):
    trace = vwg.TraceBackend()
    vwg.display(WORLD.parse(text), trace)
    return trace.calls


def test_a_transformation_applies_to_the_whole_figure_alpha_to_each_primitive_in_order():
    # φ(T(Pa Pb)) = β(T); α(Pa); α(Pb); δ(T): the paper's α for the figure's sequence, under T once.
    assert calls("Rotate<1.5>(Move<2.0>(Lamp<1> Robot<2>)) . Lamp<3>") == REF.phi(
        [("T", "Rotate", (1.5,), [("T", "Move", (2.0,), [("F", [("P", "Lamp", (1,)), ("P", "Robot", (2,))])])]),
         ("P", "Lamp", (3,))]) == [
        "beta Rotate<1.5>", "beta Move<2.0>", "alpha Lamp<1>", "alpha Robot<2>", "delta Move<2.0>",
        "delta Rotate<1.5>", "alpha Lamp<3>"]
    # The same calls as T(Pa . Pb); T(Pa) . T(Pb) opens T twice, and draws the same picture.
    assert calls("Move<2.0>(Lamp<1> Robot<2>)") == calls("Move<2.0>(Lamp<1> . Robot<2>)")
    assert calls("Move<2.0>(Lamp<1> Robot<2>)") != calls("Move<2.0>(Lamp<1>) . Move<2.0>(Robot<2>)")
    x, y = 2.0 * math.cos(1.5), 2.0 * math.sin(1.5)
    expected = [("Lamp<1>", round(x, 9), round(y, 9)), ("Robot<2>", round(x, 9), round(y, 9)), ("Lamp<3>", 0.0, 0.0)]
    assert drawing("Rotate<1.5>(Move<2.0>(Lamp<1> Robot<2>)) . Lamp<3>") == expected
    assert drawing("Rotate<1.5>(Move<2.0>(Lamp<1>) . Move<2.0>(Robot<2>)) . Lamp<3>") == expected
    assert drawing("Rotate<1.5>(Move<2.0>(Lamp<1>)) . Rotate<1.5>(Move<2.0>(Robot<2>)) . Lamp<3>") == expected


def test_eta_and_pi_keep_figures_and_actors_may_return_them():
    assert eta("Lamp Robot<1> . Counter<n=1> . Robot<2> Lamp", "add<k=2>") == (
        "Lamp Robot<1> . Counter<n=3> . Robot<2> Lamp")
    # An actor that becomes ε between two figures leaves two figures, not one.
    assert eta("Lamp Robot<1> . Mortal . Robot<2> Lamp", "die") == "Lamp Robot<1> . Robot<2> Lamp"
    assert pi("Lamp Lamp . Counter<n=4>", "show") == "Lamp Lamp . Lamp<4>"

    class Painter(vwg.Actor):
        """paint: the figure Lamp<n> Robot<n> before itself, n + 1; show (visual): the figure Robot<n> Lamp."""

        events = ("paint", "show")
        attributes = {"n": 0}

        def on_paint(self, e):
            return [f"Lamp<{self.n}> Robot<{self.n}>", self.with_(n=self.n + 1)]

        def show_show(self, e):
            return f"Robot<{self.n}> Lamp"

    world = vwg.World(primitives={"Lamp": None, "Robot": {"id": 0}}, events=["paint", "show"], visual=["show"],
                      actors=[Painter])
    ref = Reference(world.alphabet, [Painter])
    w = world.parse("Robot<7> . Painter")
    after = vwg.evolve(w, [vwg.Event("paint")])
    assert str(after) == "Robot<7> . Lamp<0> Robot<0> . Painter<n=1>"
    assert str(after) == ref.text(ref.eta(w.tree(figures=True), [vwg.Event("paint")]))
    shown = vwg.visualize(after, [vwg.Event("show")])
    assert str(shown) == "Robot<7> . Lamp<0> Robot<0> . Robot<1> Lamp"
    assert shown == world.parse(str(shown))
