// η (eq. 8), π (eq. 9), φ (eq. 7) case by case. Every expected string below is worked out by hand
// from the equations and DESIGN.md's choices, in the comment beside it.
#include <gtest/gtest.h>

#include "helpers.hpp"

using namespace vwg;
using namespace vwg::testing;

namespace {

/// P = {Robot, Lamp}, T = {Move<dist>, Rotate<angle>}, D = {add<k>, mul<k>, split, die, poke,
/// show (visual), glow (visual), tick}, and actors:
///   Counter<n> responds to add, mul, show:  add<k>: n+k   mul<k>: n*k   show: Lamp<n>
///   Mortal responds to die, poke:           die: ε        poke: Move<1.0>(Mortal)
///   Splitter<gen> responds to split:        split: Splitter<gen+1> . Splitter<gen+1>
///   Tagged<id, hits> responds to poke:      poke: hits+1
struct World {
  std::shared_ptr<Alphabet> a = std::make_shared<Alphabet>();
  World() {
    a->add_primitive("Robot");
    a->add_primitive("Lamp");
    a->add_transformation("Move", schema({real("dist")}));
    a->add_transformation("Rotate", schema({real("angle")}));
    a->add_event_type("add", false, schema({integer("k")}));
    a->add_event_type("mul", false, schema({integer("k")}));
    a->add_event_type("split", false);
    a->add_event_type("die", false);
    a->add_event_type("poke", false);
    a->add_event_type("show", true);
    a->add_event_type("glow", true);
    a->add_event_type("tick", false);
    const EventTypeId add = *a->find_event_type("add"), mul = *a->find_event_type("mul");
    a->add_actor("Counter", {"add", "mul", "show"}, schema({integer("n", 0)}),
                 std::make_shared<LambdaActor>(
                     [add, mul](ActorState& s, const EventView& e, const EvolutionContext&, Replacement&) {
                       if (e.type() == add) s.set_int(0, s.get_int(0) + e.value(0).i);
                       if (e.type() == mul) s.set_int(0, s.get_int(0) * e.value(0).i);
                     },
                     [](const ActorState& s, const EventView&, StringBuilder& out) {
                       out.primitive("Lamp", {s.get_int(0)});
                     }));
    const EventTypeId die = *a->find_event_type("die");
    a->add_actor("Mortal", {"die", "poke"}, {},
                 std::make_shared<LambdaActor>(
                     [die](ActorState& s, const EventView& e, const EvolutionContext&, Replacement& out) {
                       if (e.type() == die) {
                         out.replace();  // ε
                       } else {
                         out.replace().open("Move", {1.0}).actor(s).close();
                       }
                     }));
    a->add_actor("Splitter", {"split"}, schema({integer("gen", 0)}),
                 std::make_shared<LambdaActor>(
                     [](ActorState& s, const EventView&, const EvolutionContext&, Replacement& out) {
                       s.set_int(0, s.get_int(0) + 1);
                       out.replace().actor(s).actor(s);
                     }));
    a->add_actor("Tagged", {"poke"}, schema({integer("id"), integer("hits", 0)}),
                 std::make_shared<LambdaActor>(
                     [](ActorState& s, const EventView&, const EvolutionContext&, Replacement&) {
                       s.set_int(1, s.get_int(1) + 1);
                     }));
  }
  WorldString parse(std::string_view s) const { return parse_string(a, s); }
  EventList events(std::initializer_list<const char*> texts) const {
    EventList list(a);
    for (const char* t : texts) parse_event(list, t);
    return list;
  }
  std::string eta(std::string_view w, std::initializer_list<const char*> s) const {
    return to_text(evolve(parse(w), events(s), FrameContext{}));
  }
  std::string pi(std::string_view w, std::initializer_list<const char*> s) const {
    return to_text(visualize(parse(w), events(s), FrameContext{}));
  }
};

}  // namespace

// --- η, eq. 8 ---------------------------------------------------------------------------------

TEST(Eta, PrimitiveIsUnchanged) {
  World W;
  EXPECT_EQ(W.eta("Robot . Lamp<1, 2>", {"add<1>", "die"}), "Robot . Lamp<1, 2>");
}

TEST(Eta, TransformationKeepsItsScopeAndEvolvesInside) {
  World W;
  // η(Move<2>(Counter<1>), add<3>) = Move<2>(η(Counter<1>)) = Move<2>(Counter<4>)
  EXPECT_EQ(W.eta("Move<2.0>(Counter<n=1>)", {"add<3>"}), "Move<2.0>(Counter<n=4>)");
}

TEST(Eta, ConcatenationEvolvesEachPart) {
  World W;
  // η(u . v) = η(u) . η(v): both counters take add<2>.
  EXPECT_EQ(W.eta("Counter<n=1> . Robot . Counter<n=10>", {"add<2>"}), "Counter<n=3> . Robot . Counter<n=12>");
}

TEST(Eta, ActorFoldsOverSeveralEventsInOrder) {
  World W;
  // Fold: (1 + 2) * 3 = 9; in the other order 1 * 3 + 2 = 5.
  EXPECT_EQ(W.eta("Counter<n=1>", {"add<2>", "mul<3>"}), "Counter<n=9>");
  EXPECT_EQ(W.eta("Counter<n=1>", {"mul<3>", "add<2>"}), "Counter<n=5>");
  // Events outside H in between change nothing: ((1 + 2) * 3) + 2 = 11.
  EXPECT_EQ(W.eta("Counter<n=1>", {"add<2>", "die", "mul<3>", "tick", "add<2>"}), "Counter<n=11>");
}

TEST(Eta, UnchangedForEventsOutsideH) {
  World W;
  EXPECT_EQ(W.eta("Counter<n=1> . Mortal", {"split", "tick"}), "Counter<n=1> . Mortal");
}

TEST(Eta, ActorBecomesEmpty) {
  World W;
  EXPECT_EQ(W.eta("Mortal", {"die"}), "");
  EXPECT_EQ(W.eta("Robot . Mortal . Lamp", {"die"}), "Robot . Lamp");
  // Move<1>(ε) is not in L(M): the emptied scope goes with its transformation, nested too.
  EXPECT_EQ(W.eta("Rotate<1.0>(Move<1.0>(Mortal)) . Robot", {"die"}), "Robot");
  EXPECT_EQ(W.eta("Rotate<1.0>(Move<1.0>(Mortal) . Robot)", {"die"}), "Rotate<1.0>(Robot)");
}

TEST(Eta, ActorSpawnsSeveralSymbolsThatTakeTheRemainingEvents) {
  World W;
  // S<0> -split-> S<1> . S<1>; each takes the second split -> S<2> . S<2> . S<2> . S<2>.
  EXPECT_EQ(W.eta("Splitter<gen=0>", {"split"}), "Splitter<gen=1> . Splitter<gen=1>");
  EXPECT_EQ(W.eta("Splitter<gen=0>", {"split", "split"}),
            "Splitter<gen=2> . Splitter<gen=2> . Splitter<gen=2> . Splitter<gen=2>");
}

TEST(Eta, ActorWrapsItselfInNestedScopes) {
  World W;
  // Mortal -poke-> Move<1>(Mortal); the inner Mortal takes the second poke -> Move<1>(Move<1>(Mortal)).
  EXPECT_EQ(W.eta("Mortal", {"poke"}), "Move<1.0>(Mortal)");
  EXPECT_EQ(W.eta("Rotate<0.5>(Mortal)", {"poke", "poke"}), "Rotate<0.5>(Move<1.0>(Move<1.0>(Mortal)))");
  // poke then die: Move<1>(Mortal) then the inner Mortal dies: Move<1>(ε) -> ε.
  EXPECT_EQ(W.eta("Mortal . Robot", {"poke", "die"}), "Robot");
}

TEST(Eta, TargetedEventsReachOnlyTheActorWithThatId) {
  World W;
  EXPECT_EQ(W.eta("Tagged<id=1> . Tagged<id=2> . Tagged<id=2>", {"poke<to=2>", "poke"}),
            "Tagged<id=1, hits=1> . Tagged<id=2, hits=2> . Tagged<id=2, hits=2>");
  // A type without an integer id never receives targeted events.
  EXPECT_EQ(W.eta("Mortal", {"poke<to=1>"}), "Mortal");
}

TEST(Eta, TheInputStringIsNotChanged) {
  World W;
  const WorldString w = W.parse("Counter<n=1> . Move<1.0>(Counter<n=2>)");
  const std::string before = to_text(w);
  (void)evolve(w, W.events({"add<5>"}), FrameContext{});
  EXPECT_EQ(to_text(w), before);
}

// --- π, eq. 9 ---------------------------------------------------------------------------------

TEST(Pi, ActorsShowThemselvesForVisualEventsInHAndV) {
  World W;
  // Counter responds to show (visual): θ = Lamp<n>. glow is visual but not in Counter's H: ε.
  // add is in H but not visual: ε. Primitives and transformations stay (π recurses in scopes).
  EXPECT_EQ(W.pi("Robot . Move<1.0>(Counter<n=7>) . Counter<n=8>", {"add<1>", "show", "glow"}),
            "Robot . Move<1.0>(Lamp<7>) . Lamp<8>");
}

TEST(Pi, ThetaIsEmptyOutsideHAndV) {
  World W;
  EXPECT_EQ(W.pi("Counter<n=7> . Mortal", {"glow", "add<1>"}), "");
  // An actor with no visual events shows nothing; its scope empties and goes (t(ε) ∉ L(M')).
  EXPECT_EQ(W.pi("Move<1.0>(Mortal) . Robot", {"show"}), "Robot");
}

TEST(Pi, SeveralVisualEventsConcatenateInOrder) {
  World W;
  // ∏ over S': θ(a, show) . θ(a, show).
  EXPECT_EQ(W.pi("Counter<n=2>", {"show", "show"}), "Lamp<2> . Lamp<2>");
}

TEST(Pi, ThetaMustNotReturnActors) {
  auto a = std::make_shared<Alphabet>();
  a->add_event_type("show", true);
  a->add_actor("Liar", {"show"}, {},
               std::make_shared<LambdaActor>([](ActorState&, const EventView&, const EvolutionContext&, Replacement&) {},
                                             [](const ActorState& s, const EventView&, StringBuilder& out) { out.actor(s); }));
  EventList events(a);
  events.emit("show");
  try {
    visualize(parse_string(a, "Liar"), events, FrameContext{3, 0.3, 0});
    FAIL() << "no error";
  } catch (const FrameError& e) {
    EXPECT_EQ(e.frame(), 3u);
    EXPECT_EQ(e.stage(), "visualize");
    EXPECT_EQ(e.actor(), "Liar");
    EXPECT_EQ(e.event(), "show");
    EXPECT_NE(e.cause_message().find("L(M')"), std::string::npos);
  }
}

// --- φ, eq. 7 ---------------------------------------------------------------------------------

TEST(Phi, CallsAlphaBetaDeltaInStringOrderForNestedScopes) {
  World W;
  TraceBackend g;
  display(W.parse("Move<1.0>(Rotate<2.0>(Robot) . Robot) . Lamp"), g);
  const std::vector<std::string> expected = {"beta Move<1.0>",  "beta Rotate<2.0>", "alpha Robot",
                                             "delta Rotate<2.0>", "alpha Robot",      "delta Move<1.0>",
                                             "alpha Lamp"};
  EXPECT_EQ(g.calls(), expected);
}

TEST(Phi, RefusesActors) {
  World W;
  TraceBackend g;
  EXPECT_THROW(display(W.parse("Robot . Counter<n=1>"), g), Error);
}

// --- figures (rule 6, FIGURE → p+) -------------------------------------------------------------

TEST(Phi, AFigureRunsAlphaOnEachPrimitiveInOrderUnderItsTransformation) {
  World W;
  // φ(Move<1>(Robot Lamp)) = β(Move); α(Robot); α(Lamp); δ(Move): the transformation applies once, to
  // the whole figure, as to Robot . Lamp.
  TraceBackend figure, objects;
  display(W.parse("Move<1.0>(Robot Lamp Robot) . Lamp Lamp<2>"), figure);
  display(W.parse("Move<1.0>(Robot . Lamp . Robot) . Lamp . Lamp<2>"), objects);
  const std::vector<std::string> expected = {"beta Move<1.0>", "alpha Robot", "alpha Lamp", "alpha Robot",
                                             "delta Move<1.0>", "alpha Lamp", "alpha Lamp<2>"};
  EXPECT_EQ(figure.calls(), expected);
  EXPECT_EQ(objects.calls(), expected);
}

TEST(Eta, AFigureIsUnchangedAndKeepsItsPrimitivesTogether) {
  World W;
  // η(p+) = p+ (eq. 8, first case, for each primitive); the actors beside it evolve.
  EXPECT_EQ(W.eta("Robot Lamp . Counter<n=1> . Lamp Robot", {"add<2>"}), "Robot Lamp . Counter<n=3> . Lamp Robot");
  // An actor that becomes ε between two figures leaves two figures, not one.
  EXPECT_EQ(W.eta("Robot Lamp . Mortal . Lamp Robot", {"die"}), "Robot Lamp . Lamp Robot");
  EXPECT_EQ(W.eta("Move<1.0>(Robot Lamp . Mortal)", {"poke"}), "Move<1.0>(Robot Lamp . Move<1.0>(Mortal))");
  EXPECT_EQ(W.pi("Robot Lamp . Counter<n=4> . Lamp Robot", {"show"}), "Robot Lamp . Lamp<4> . Lamp Robot");
}

TEST(Pi, ThetaMayShowAnActorAsAFigure) {
  auto a = std::make_shared<Alphabet>();
  a->add_primitive("Robot");
  a->add_primitive("Lamp");
  a->add_event_type("show", true);
  a->add_actor("Shower", {"show"}, {},
               std::make_shared<LambdaActor>(
                   [](ActorState&, const EventView&, const EvolutionContext&, Replacement&) {},
                   [](const ActorState&, const EventView&, StringBuilder& out) {
                     out.primitive("Lamp").juxtapose("Robot");
                   }));
  EventList show(a);
  parse_event(show, "show");
  const WorldString v = visualize(parse_string(a, "Robot . Shower . Shower"), show, FrameContext{});
  // θ's figure is one object: '.' before it, a space inside it.
  EXPECT_EQ(to_text(v), "Robot . Lamp Robot . Lamp Robot");
  EXPECT_EQ(v, parse_string(a, "Robot . Lamp Robot . Lamp Robot"));
}

// --- errors inside λ -------------------------------------------------------------------------

TEST(Eta, AnErrorInLambdaNamesTheActorTheEventAndTheFrame) {
  auto a = std::make_shared<Alphabet>();
  a->add_event_type("boom", false, schema({integer("k")}));
  a->add_actor("Fragile", {"boom"}, schema({integer("n", 0)}),
               std::make_shared<LambdaActor>([](ActorState&, const EventView&, const EvolutionContext&, Replacement&) {
                 throw std::runtime_error("cannot take it");
               }));
  EventList events(a);
  events.emit("boom", {7});
  try {
    evolve(parse_string(a, "Fragile<n=2>"), events, FrameContext{12, 1.2, 0});
    FAIL() << "no error";
  } catch (const FrameError& e) {
    EXPECT_EQ(e.frame(), 12u);
    EXPECT_EQ(e.stage(), "evolve");
    EXPECT_EQ(e.actor(), "Fragile<n=2>");
    EXPECT_EQ(e.event(), "boom<k=7>");
    EXPECT_EQ(e.cause_message(), "cannot take it");
    EXPECT_NE(std::string(e.what()).find("frame 12"), std::string::npos);
  }
}

// --- large attributes -------------------------------------------------------------------------

TEST(Blob, CopyOnWriteLeavesTheOldStringsGridUntouched) {
  auto a = std::make_shared<Alphabet>();
  a->add_event_type("mark", false, schema({integer("cell")}));
  a->add_actor("Mapper", {"mark"}, Schema{{ParamSpec{"grid", ValueKind::Blob, std::nullopt}}, false},
               std::make_shared<LambdaActor>([](ActorState& s, const EventView& e, const EvolutionContext&, Replacement&) {
                 s.mutable_blob(0).mutable_view<std::int8_t>()[static_cast<std::size_t>(e.value(0).i)] = 100;
               }));
  auto grid = std::make_shared<const Blob>(DType::Int8, std::vector<std::int64_t>{2, 2});
  const WorldString w0 = StringBuilder(a).actor("Mapper", {Datum(grid)}).finish();
  EventList events(a);
  events.emit("mark", {1});
  events.emit("mark", {3});
  const WorldString w1 = evolve(w0, events, FrameContext{});
  const auto& g0 = *w0.node(0).datum(0).as_blob();
  const auto& g1 = *w1.node(0).datum(0).as_blob();
  const std::vector<std::int8_t> before(g0.view<std::int8_t>().begin(), g0.view<std::int8_t>().end());
  const std::vector<std::int8_t> after(g1.view<std::int8_t>().begin(), g1.view<std::int8_t>().end());
  EXPECT_EQ(before, (std::vector<std::int8_t>{0, 0, 0, 0}));
  EXPECT_EQ(after, (std::vector<std::int8_t>{0, 100, 0, 100}));
  EXPECT_NE(to_text(w0), to_text(w1));  // the blob's name is its content hash
}

// --- λ over runs of events (ActorBehavior::evolve_run) ------------------------------------------

namespace {

/// Counter<id, n> whose add and mul come a run at a time: it records each run's length, and can be
/// made to break the run's contract (replace itself, or change its id).
class RunCounter final : public ActorBehavior {
 public:
  enum class Fault { None, Replace, NewId };
  RunCounter(EventTypeId add, EventTypeId mul, Fault fault) : add_(add), mul_(mul), fault_(fault) {}
  void evolve(ActorState& s, const EventView& e, const EvolutionContext&, Replacement&) override {
    s.set_int(1, e.type() == add_ ? s.get_int(1) + e.value(0).i : s.get_int(1) * e.value(0).i);
  }
  bool takes_runs(EventTypeId type) const override { return type == add_ || type == mul_; }
  void evolve_run(ActorState& s, const EventList& events, std::span<const std::uint32_t> at, const EvolutionContext& ctx,
                  Replacement& out) override {
    runs.push_back(at.size());
    ActorBehavior::evolve_run(s, events, at, ctx, out);
    if (fault_ == Fault::Replace) out.replace().actor(s);
    if (fault_ == Fault::NewId) s.set_int(0, 99);
  }
  std::vector<std::size_t> runs;

 private:
  EventTypeId add_, mul_;
  Fault fault_;
};

struct RunWorld {
  std::shared_ptr<Alphabet> a = std::make_shared<Alphabet>();
  std::shared_ptr<RunCounter> counter;
  explicit RunWorld(RunCounter::Fault fault = RunCounter::Fault::None) {
    a->add_event_type("add", false, schema({integer("k")}));
    a->add_event_type("mul", false, schema({integer("k")}));
    counter = std::make_shared<RunCounter>(*a->find_event_type("add"), *a->find_event_type("mul"), fault);
    a->add_actor("Counter", {"add", "mul"}, schema({integer("id"), integer("n", 0)}), counter);
  }
  std::string eta(std::string_view w, std::initializer_list<const char*> s) const {
    EventList list(a);
    for (const char* t : s) parse_event(list, t);
    return to_text(evolve(parse_string(a, w), list, FrameContext{}));
  }
};

}  // namespace

TEST(Eta, ARunOfEventsOfOneTypeFoldsAsOneEventAtATime) {
  // Counter 1: ((1 + 2 + 3) · 2 · 5) + 4 = 64; counter 2: (0 + 10) · 3 = 30. The events for
  // counter 1 come as runs add×2 (the add to 2 between them splits nothing: it is not counter 1's),
  // add×1, mul×2, add×1; counter 2's as add×1, mul×1.
  RunWorld W;
  EXPECT_EQ(W.eta("Counter<id=1, n=1> . Counter<id=2>",
                  {"add<to=1, k=2>", "add<to=2, k=10>", "add<to=1, k=3>", "mul<to=2, k=3>", "mul<to=1, k=2>",
                   "mul<to=1, k=5>", "add<to=1, k=4>"}),
            "Counter<id=1, n=64> . Counter<id=2, n=30>");
  EXPECT_EQ(W.counter->runs, (std::vector<std::size_t>{2, 2}));  // runs of one event go to evolve()
}

TEST(Eta, ARunThatReplacesTheActorOrChangesItsIdIsAnError) {
  for (const auto fault : {RunCounter::Fault::Replace, RunCounter::Fault::NewId}) {
    RunWorld W(fault);
    try {
      W.eta("Counter<id=1>", {"add<to=1, k=2>", "add<to=1, k=3>"});
      FAIL() << "a broken run contract was accepted";
    } catch (const FrameError& e) {
      EXPECT_NE(std::string(e.what()).find("evolve_run"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("Counter"), std::string::npos) << e.what();
    }
  }
}

TEST(Events, ColumnsStoreWhatEmitStoresAndRefuseWhatItRefuses) {
  auto a = std::make_shared<Alphabet>();
  a->add_event_type("beam", false, schema({real("dist"), real("angle")}));
  a->add_event_type("count", false, schema({integer("k")}));
  const EventTypeId beam = *a->find_event_type("beam"), count = *a->find_event_type("count");
  EventList fast(a), plain(a);
  // Three beams to robot 7 by columns, between two events emitted one by one.
  const std::vector<double> dist = {1.5, 2.0, 0.125}, angle = {-0.25, 0.0, 3.0};
  const std::span<const double> columns[] = {dist, angle};
  fast.emit(count, std::vector<Datum>{std::int64_t{4}});
  fast.emit_columns(beam, columns, 7);
  fast.emit(beam, std::vector<Datum>{9.0, 1.0});
  plain.emit(count, std::vector<Datum>{std::int64_t{4}});
  for (std::size_t j = 0; j < 3; ++j) plain.emit(beam, std::vector<Datum>{dist[j], angle[j]}, 7);
  plain.emit(beam, std::vector<Datum>{9.0, 1.0});
  EXPECT_TRUE(fast == plain);
  ASSERT_EQ(fast.size(), 5u);
  EXPECT_EQ(to_text(fast[1]), "beam<to=7, dist=1.5, angle=-0.25>");
  EXPECT_EQ(to_text(fast[3]), "beam<to=7, dist=0.125, angle=3.0>");
  EXPECT_EQ(fast[2].number(1), 0.0);
  EXPECT_EQ(fast.batch_count(), 3u) << "one batch a call";
  EXPECT_EQ(fast.sizes().reals, 6u) << "the beams' fields as bare reals";
  // Copies keep the events: a whole list, and one event of a batch.
  EventList copy(a), one(a);
  copy.append(fast);
  EXPECT_TRUE(copy == plain);
  one.append_from(fast, 3);
  EXPECT_EQ(to_text(one[0]), "beam<to=7, dist=0.125, angle=3.0>");
  auto message = [&](EventTypeId type, std::vector<std::vector<double>> values) {
    std::vector<std::span<const double>> spans(values.begin(), values.end());
    try {
      fast.emit_columns(type, spans);
    } catch (const SchemaError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(beam, {{1.0, std::nan("")}, {0.0, 0.0}}).find("beam.dist"), std::string::npos);
  EXPECT_NE(message(beam, {{1.0}, {0.0}, {3.0}}).find("has 2 fields, got 3"), std::string::npos);
  EXPECT_NE(message(beam, {{1.0, 2.0}, {0.0}}).find("beam.angle"), std::string::npos);  // columns of unequal length
  EXPECT_NE(message(count, {{1.0}}).find("count.k"), std::string::npos);  // an integer field is not a real
  EXPECT_EQ(fast.size(), 5u) << "a refused batch leaves the list as it was";
  EXPECT_EQ(message(beam, {{}, {}}), "accepted");
  EXPECT_EQ(fast.size(), 5u) << "an empty batch adds no event";
}
