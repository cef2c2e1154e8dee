"""Actors written in Python: declarations, values, returns, batch λ, C++ actors, and errors."""

from __future__ import annotations

import numpy as np
import pytest

import vwg
from vwg.testing.reference import Reference


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
                           vwg._core.walker_behavior(cpp_alphabet, "step", "show", "Dot"))
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


# --- run λ: on_<event>_run ----------------------------------------------------------------------

RUN_CALLS: list[tuple[int, int, int | None]] = []


class ScanMapper(vwg.Actor):
    """A scan's beams at once: counts them, keeps the nearest and sums the distances; mark<k>
    (an int) adds k; ping<k, up> runs count the ups and sum the ks."""

    events = ("beam", "mark", "ping")
    attributes = {"id": int, "beams": 0, "nearest": 99.0, "total": 0.0, "marks": 0, "ups": 0}

    def on_beam_run(self, events):
        RUN_CALLS.append((self.id, len(events), events.target))
        return self.with_(beams=self.beams + len(events), nearest=min(self.nearest, float(events.dist.min())),
                          total=self.total + float(events.dist.sum()))

    def on_mark(self, e):
        return self.with_(marks=self.marks + e.k)

    def on_ping_run(self, events, ctx):
        assert events.k.dtype == np.int64 and events.up.dtype == np.bool_ and ctx.frame >= 0
        return self.with_(marks=self.marks + int(events.k.sum()), ups=self.ups + int(events.up.sum()))


class BeamByBeam(vwg.Actor):
    """The same actor, one event at a time: the second method."""

    name = "ScanMapper"
    events = ScanMapper.events
    attributes = ScanMapper.attributes

    def on_beam(self, e):
        return self.with_(beams=self.beams + 1, nearest=min(self.nearest, e.dist), total=self.total + e.dist)

    def on_mark(self, e):
        return self.with_(marks=self.marks + e.k)

    def on_ping(self, e):
        return self.with_(marks=self.marks + e.k, ups=self.ups + int(e.up))


def mapper_world(actor: type[vwg.Actor]) -> vwg.World:
    return vwg.World(events={"beam": {"dist": 0.0, "angle": 0.0}, "mark": {"k": 0}, "ping": {"k": 0, "up": False}},
                     actors=[actor])


class MapperScan(vwg.Generator):
    """Three beams to robot 2 by columns, a mark to it, a beam to all, two pings to robot 1."""

    def generate(self, frame):
        return [vwg.EventColumns("beam", target=2, dist=[1.0, 0.5, 2.25], angle=[0.0, 0.5, 1.0]),
                vwg.Event("mark", target=2, k=3),
                vwg.Event("beam", dist=0.25, angle=0.0),
                vwg.Event("ping", target=1, k=4, up=True), vwg.Event("ping", target=1, k=-1, up=False)]


def test_a_run_handler_gives_what_the_handler_of_each_event_gives():
    strings = []
    for actor in (ScanMapper, BeamByBeam):
        RUN_CALLS.clear()
        engine = vwg.Engine(mapper_world(actor), "ScanMapper<id=1> . ScanMapper<id=2>", [MapperScan()])
        engine.run(2)
        strings.append(str(engine.string))
    assert strings[0] == strings[1]
    # The pure-Python reference calls the run handler on each event as a run of one.
    world = mapper_world(ScanMapper)
    ref = Reference(world.alphabet, [ScanMapper])
    w = world.parse("ScanMapper<id=1> . ScanMapper<id=2>").tree()
    events = vwg.Engine(world, "ScanMapper<id=1>", [MapperScan()]).collect_events()  # one by one
    for frame in range(2):
        w = ref.eta(w, events, frame)
    assert ref.text(w) == strings[0]
    # By hand, two frames: robot 1 gets the broadcast beam and the pings; robot 2 three beams, the
    # mark, and the broadcast beam.
    assert strings[1] == ("ScanMapper<id=1, beams=2, nearest=0.25, total=0.5, marks=6, ups=2> . "
                          "ScanMapper<id=2, beams=8, nearest=0.25, total=8.0, marks=6, ups=0>")


def test_a_run_is_the_consecutive_events_of_one_type_that_reach_the_actor():
    RUN_CALLS.clear()
    vwg.Engine(mapper_world(ScanMapper), "ScanMapper<id=1> . ScanMapper<id=2>", [MapperScan()]).step()
    # Robot 1: the broadcast beam alone (a run of one, for all). Robot 2: the scan of three (to it),
    # cut by the mark, then the broadcast beam.
    assert RUN_CALLS == [(1, 1, None), (2, 3, 2), (2, 1, None)]


def test_run_handlers_refuse_what_they_cannot_keep():
    class Splits(vwg.Actor):
        events = ("beam",)
        attributes = {"id": int}

        def on_beam_run(self, events):
            return [self, self]

    world = vwg.World(events={"beam": {"dist": 0.0, "angle": 0.0}}, actors=[Splits])
    engine = vwg.Engine(world, "Splits<id=2>", [vwg.every_frame("beam", dist=1.0, angle=0.0)])
    with pytest.raises(vwg.FrameError, match=r"Splits\.on_beam_run: returned .*a run handler returns self"):
        engine.step()

    class Named(vwg.Actor):
        events = ("said",)

        def on_said_run(self, events):
            return self

    with pytest.raises(vwg.SchemaError, match=r"Named\.on_said_run: 'said\.text' is text or a blob"):
        vwg.World(events={"said": {"text": ""}}, actors=[Named])

    class Both(vwg.Actor):
        events = ("beam", "mark")

        def on_beam_run(self, events):
            return self

        @classmethod
        def on_mark_batch(cls, actors, e):
            pass

    with pytest.raises(vwg.SchemaError, match=r"both batch handlers .* and run handlers"):
        mapper_world(Both)

    with pytest.raises(vwg.SchemaError, match=r"Typo\.on_bean_run: 'bean' is not among"):
        class Typo(vwg.Actor):
            events = ("beam",)

            def on_bean_run(self, events):
                return self


def test_events_named_like_a_batch_or_a_run_handler_get_their_own_lambda():
    # on_tick_batch and on_tick_run are the λ of the events tick_batch and tick_run when the actor
    # takes those events, not a batch or a run handler of tick.
    class Counter(vwg.Actor):
        events = ("tick", "tick_batch", "tick_run")
        attributes = {"ticks": 0, "batches": 0, "runs": 0}

        def on_tick(self, e):
            return self.with_(ticks=self.ticks + 1)

        def on_tick_batch(self, e):
            return self.with_(batches=self.batches + e.k)

        def on_tick_run(self, e):
            return self.with_(runs=self.runs + e.k)

    world = vwg.World(events={"tick": None, "tick_batch": {"k": 0}, "tick_run": {"k": 0}}, actors=[Counter])

    class Script(vwg.Generator):
        name = "script"

        def generate(self, frame):
            return [vwg.Event("tick"), vwg.Event("tick_batch", k=10), vwg.Event("tick"), vwg.Event("tick_run", k=100),
                    vwg.Event("tick_run", k=1000)]

    engine = vwg.Engine(world, "Counter", [Script()])
    engine.run(2)
    assert str(engine.string) == "Counter<ticks=4, batches=20, runs=2200>"
