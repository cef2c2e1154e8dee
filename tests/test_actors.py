"""Actors written in Python: declarations, values, returns, batch λ, C++ actors, and errors."""

from __future__ import annotations

import numpy as np
import pytest

import vwg


class Walker(vwg.Actor):
    """The Python twin of the C++ walker_behavior: step<dt> moves x by v·dt; show: Dot<x>."""

    events = ("step", "show")
    attributes = {"x": 0.0, "v": 1.0}

    def on_step(self, e):
        return self.with_(x=self.x + self.v * e.dt)

    def show_show(self, e):
        return vwg.Sym("Dot", self.x)


class BatchWalker(vwg.Actor):
    events = ("step",)
    attributes = {"x": 0.0, "v": 1.0, "moves": 0, "moving": False, "label": "w"}

    @classmethod
    def on_step_batch(cls, actors, e):
        actors.x[:] += actors.v * e.dt
        actors["moves"][:] += 1
        actors.moving[:] = actors.v != 0


def walker_world(*actors):
    return vwg.World(primitives={"Dot": {"x": 0.0}}, events={"step": {"dt": 0.1}, "show": None},
                     visual=["show"], actors=actors)


def test_actor_values_are_frozen_and_changed_through_with():
    w = Walker(x=1.0)
    assert (w.x, w.v) == (1.0, 1.0)
    assert w.with_(v=2.0).v == 2.0 and w.v == 1.0
    with pytest.raises(AttributeError, match="with_"):
        w.x = 3.0
    with pytest.raises(vwg.SchemaError, match="no such attribute"):
        w.with_(y=1.0)
    assert repr(w) == "Walker<x=1.0, v=1.0>"


def test_declaration_mistakes_are_refused_at_class_creation():
    with pytest.raises(vwg.SchemaError, match="'tik' is not among"):
        class Typo(vwg.Actor):
            events = ("tick",)

            def on_tik(self, e):
                return self
    with pytest.raises(vwg.SchemaError, match="reserved"):
        class Reserved(vwg.Actor):
            attributes = {"name": ""}
    with pytest.raises(vwg.SchemaError, match="not a visual event"):
        class ShowsTick(vwg.Actor):
            events = ("tick",)

            def show_tick(self, e):
                return ""
        vwg.World(events=["tick"], actors=[ShowsTick])
    with pytest.raises(vwg.SchemaError, match="already registered"):
        vwg.World(events=["tick"], primitives=["tick"])


def test_handler_returns_text_sym_actor_list_or_empty():
    class Shape(vwg.Actor):
        events = ("a", "b", "c", "d")
        attributes = {"k": 0}

        def on_a(self, e):
            return "Dot<1.5> . Shape<k=1>"

        def on_b(self, e):
            return [vwg.Sym("Dot", 2.0), self.with_(k=self.k + 10)]

        def on_c(self, e):
            return []

        def on_d(self, e):
            return None

    world = vwg.World(primitives={"Dot": {"x": 0.0}}, events=["a", "b", "c", "d"], actors=[Shape])
    w = world.parse("Shape")
    assert str(vwg.evolve(w, [vwg.Event("a")])) == "Dot<1.5> . Shape<k=1>"
    assert str(vwg.evolve(w, [vwg.Event("a"), vwg.Event("b")])) == "Dot<1.5> . Dot<2.0> . Shape<k=11>"
    assert str(vwg.evolve(w, [vwg.Event("c")])) == ""
    with pytest.raises(vwg.FrameError, match="returned None; return self"):
        vwg.evolve(w, [vwg.Event("d")])


def test_errors_inside_a_python_actor_name_actor_event_and_frame():
    class Fragile(vwg.Actor):
        events = ("tick",)
        attributes = {"n": 0}

        def on_tick(self, e):
            if self.n == 2:
                raise ZeroDivisionError("boom")
            return self.with_(n=self.n + 1)

    world = vwg.World(events=["tick"], actors=[Fragile])
    engine = vwg.Engine(world, "Fragile", generators=[vwg.every_frame("tick")])
    with pytest.raises(vwg.FrameError) as info:
        engine.run(10)
    e = info.value
    assert (e.frame, e.stage, e.actor, e.event) == (2, "evolve", "Fragile<n=2>", "tick")
    assert isinstance(e.__cause__, ZeroDivisionError)
    assert "ZeroDivisionError: boom" in str(e)
    # The world stays at the last complete frame.
    assert engine.frame == 2 and str(engine.string) == "Fragile<n=2>"


def test_bad_attribute_values_are_clear_errors():
    class Bad(vwg.Actor):
        events = ("tick",)
        attributes = {"x": 0.0, "n": 0}

        def on_tick(self, e):
            return self.with_(x=float("nan")) if self.n == 0 else self.with_(n="three")

    world = vwg.World(events=["tick"], actors=[Bad])
    with pytest.raises(vwg.FrameError, match=r"Bad\.x: expected a finite real"):
        vwg.evolve(world.parse("Bad"), [vwg.Event("tick")])
    with pytest.raises(vwg.FrameError, match=r"Bad\.n: expected int, got str"):
        vwg.evolve(world.parse("Bad<n=1>"), [vwg.Event("tick")])


def test_cpp_and_python_actors_give_the_same_strings():
    py_world = walker_world(Walker)
    cpp_alphabet = vwg.Alphabet(primitives={"Dot": {"x": 0.0}}, events={"step": {"dt": 0.1}, "show": None},
                                visual=["show"])
    cpp_alphabet.add_actor("Walker", ["step", "show"], {"x": 0.0, "v": 1.0},
                           vwg.walker_behavior(cpp_alphabet, "step", "show", "Dot"))
    text = " . ".join(f"Walker<x={i * 0.5}, v={1.0 - i * 0.25}>" for i in range(8))
    events = [vwg.Event("step", dt=0.1), vwg.Event("show"), vwg.Event("step", dt=0.3)]
    py_w = vwg.evolve(py_world.parse(text), events)
    cpp_w = vwg.evolve(cpp_alphabet.parse(text), events)
    assert str(py_w) == str(cpp_w)
    assert str(vwg.visualize(py_world.parse(text), events)) == str(vwg.visualize(cpp_alphabet.parse(text), events))
    # Hand check of one: x = 0.5 + 0.75 * 0.1 + 0.75 * 0.3 = 0.8
    assert py_w.actors()[1]["x"] == pytest.approx(0.8)


def test_batch_handlers_match_per_actor_results():
    world = walker_world(BatchWalker)
    text = " . ".join(f"BatchWalker<x={float(i)}, v={float(i % 3)}>" for i in range(50))
    w = vwg.evolve(world.parse(text), [vwg.Event("step", dt=0.5), vwg.Event("step", dt=0.25)])
    actors = w.actors()
    for i, a in enumerate(actors):
        assert a["x"] == i + (i % 3) * 0.75
        assert a["moves"] == 2
        assert a["moving"] == (i % 3 != 0)
        assert a["label"] == "w"


def test_batch_targeted_events_reach_only_their_actor():
    class Unit(vwg.Actor):
        events = ("hit",)
        attributes = {"id": 0, "hp": 10}

        @classmethod
        def on_hit_batch(cls, actors, e):
            actors.hp[:] -= e.damage

    world = vwg.World(events={"hit": {"damage": 1}}, actors=[Unit])
    w = vwg.evolve(world.parse("Unit<id=1> . Unit<id=2> . Unit<id=3>"),
                   [vwg.Event("hit", damage=2), vwg.Event("hit", target=2, damage=5)])
    assert [a["hp"] for a in w.actors()] == [8, 3, 8]


def test_batch_handlers_must_cover_every_event():
    class Half(vwg.Actor):
        events = ("a", "b")

        def on_a(self, e):
            return self

        @classmethod
        def on_b_batch(cls, actors, e):
            pass

    with pytest.raises(vwg.SchemaError, match="on_a_batch: missing"):
        vwg.World(events=["a", "b"], actors=[Half])


def test_context_seed_makes_random_decisions_reproducible():
    class Dice(vwg.Actor):
        events = ("roll",)
        attributes = {"value": 0}

        def on_roll(self, e, ctx):
            return self.with_(value=int(ctx.rng().integers(1, 7)))

    world = vwg.World(events=["roll"], actors=[Dice])

    def run(seed):
        engine = vwg.Engine(world, " . ".join(["Dice"] * 20), [vwg.every_frame("roll")], seed=seed)
        engine.run(5)
        return str(engine.string)

    assert run(1) == run(1)
    assert run(1) != run(2)
    values = [a["value"] for a in world.parse(run(3)).actors()]
    assert len(set(values)) > 1 and all(1 <= v <= 6 for v in values)


def test_blob_attributes_are_copied_on_write():
    class Mapper(vwg.Actor):
        events = ("mark",)
        attributes = {"grid": vwg.Blob}

        def on_mark(self, e):
            g = np.array(self.grid)
            g.flat[e.cell] = 100
            return self.with_(grid=g)

    world = vwg.World(events={"mark": {"cell": 0}}, actors=[Mapper])
    start = vwg.Blob(np.zeros((2, 2), np.int8))
    w0 = world.parse("Mapper<grid=@g>", "<t>", {"g": start})
    w1 = vwg.evolve(w0, [vwg.Event("mark", cell=3)])
    np.testing.assert_array_equal(np.asarray(w0.actors()[0]["grid"]), [[0, 0], [0, 0]])
    np.testing.assert_array_equal(np.asarray(w1.actors()[0]["grid"]), [[0, 0], [0, 100]])
