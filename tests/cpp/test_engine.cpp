// The system algorithm (§II.D): generator priority, frames, stopping, and all-or-nothing frames.
#include <gtest/gtest.h>
#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

#include "helpers.hpp"

using namespace vwg;
using namespace vwg::testing;

namespace {

class FixedGenerator : public Generator {
 public:
  FixedGenerator(std::string type, std::int64_t k) : type_(std::move(type)), k_(k) {}
  void generate(const FrameInfo&, EventList& out) override { out.emit(type_, {k_}); }
  std::string name() const override { return type_; }

 private:
  std::string type_;
  std::int64_t k_;
};

class RandomGenerator : public Generator {
 public:
  void reset(std::uint64_t seed) override { rng_.reseed(seed); }
  void generate(const FrameInfo&, EventList& out) override {
    out.emit("add", {static_cast<std::int64_t>(rng_.below(10))});
  }

 private:
  Rng rng_;
};

std::shared_ptr<Alphabet> counter_alphabet(int fail_at_n = -1) {
  auto a = std::make_shared<Alphabet>();
  a->add_primitive("Lamp");
  a->add_event_type("add", false, schema({integer("k")}));
  a->add_event_type("mul", false, schema({integer("k")}));
  a->add_event_type("show", true);
  const EventTypeId add = *a->find_event_type("add");
  a->add_actor("Counter", {"add", "mul", "show"}, schema({integer("n", 0)}),
               std::make_shared<LambdaActor>(
                   [add, fail_at_n](ActorState& s, const EventView& e, const EvolutionContext&, Replacement& out) {
                     if (s.get_int(0) == fail_at_n) throw std::runtime_error("n reached " + std::to_string(fail_at_n));
                     if (e.field_count() == 0) return;  // show: nothing to evolve
                     const std::int64_t k = e.value(0).i;
                     const std::int64_t n = e.type() == add ? s.get_int(0) + k : s.get_int(0) * k;
                     if (n > 100) {
                       out.replace();  // the counter vanishes past 100, ending the world
                       return;
                     }
                     s.set_int(0, n);
                   },
                   [](const ActorState& s, const EventView&, StringBuilder& out) { out.primitive("Lamp", {s.get_int(0)}); }));
  return a;
}

}  // namespace

TEST(Engine, GeneratorPriorityOrdersTheEventsOfAFrame) {
  auto a = counter_alphabet();
  // Priority [add 2, mul 3]: (1 + 2) * 3 = 9. Priority [mul 3, add 2]: 1 * 3 + 2 = 5.
  Engine first(parse_string(a, "Counter<n=1>"),
               {std::make_shared<FixedGenerator>("add", 2), std::make_shared<FixedGenerator>("mul", 3)}, nullptr);
  first.step();
  EXPECT_EQ(to_text(first.string()), "Counter<n=9>");
  Engine second(parse_string(a, "Counter<n=1>"),
                {std::make_shared<FixedGenerator>("mul", 3), std::make_shared<FixedGenerator>("add", 2)}, nullptr);
  second.step();
  EXPECT_EQ(to_text(second.string()), "Counter<n=5>");
}

TEST(Engine, DisplaysTheStringOfTheFrameBeforeEvolution) {
  auto a = counter_alphabet();
  auto trace = std::make_shared<TraceBackend>();
  auto show = std::make_shared<EveryFrameGenerator>(*a, "show");
  Engine engine(parse_string(a, "Counter<n=1>"), {std::make_shared<FixedGenerator>("add", 2), show}, trace);
  engine.step();
  engine.step();
  // v = π(w, Z) uses w before η: frame 0 shows n=1, frame 1 shows n=3.
  const std::vector<std::string> expected = {"frame 0", "alpha Lamp<1>", "frame 1", "alpha Lamp<3>"};
  EXPECT_EQ(trace->calls(), expected);
  EXPECT_EQ(to_text(engine.string()), "Counter<n=5>");
}

TEST(Engine, StopsWhenTheWorldIsEmptyOrAtTheFrameLimit) {
  auto a = counter_alphabet();
  // n: 0 -> 30 -> 60 -> 90 -> vanishes at 120 (frame 3): ε after 4 frames.
  Engine engine(parse_string(a, "Counter<n=0>"), {std::make_shared<FixedGenerator>("add", 30)}, nullptr);
  EXPECT_EQ(engine.run(2), StopReason::FrameLimit);
  EXPECT_EQ(engine.frame(), 2u);
  EXPECT_EQ(engine.run(100), StopReason::Empty);
  EXPECT_EQ(engine.frame(), 4u);
  EXPECT_TRUE(engine.string().empty());
  EXPECT_FALSE(engine.step());
}

TEST(Engine, StopsOnRequest) {
  auto a = counter_alphabet();
  Engine engine(parse_string(a, "Counter<n=0>"), {std::make_shared<FixedGenerator>("add", 0)}, nullptr);
  engine.add_observer([&](const FrameRecord& r) {
    if (r.frame == 6) engine.request_stop();
  });
  EXPECT_EQ(engine.run(1000), StopReason::Requested);
  EXPECT_EQ(engine.frame(), 7u);
}

TEST(Engine, AFailedFrameLeavesTheLastCompleteFrame) {
  auto a = counter_alphabet(/*fail_at_n=*/20);
  Engine engine(parse_string(a, "Counter<n=0>"), {std::make_shared<FixedGenerator>("add", 10)}, nullptr);
  engine.step();  // 0 -> 10
  engine.step();  // 10 -> 20
  try {
    engine.step();  // λ throws at n = 20
    FAIL() << "no error";
  } catch (const FrameError& e) {
    EXPECT_EQ(e.frame(), 2u);
    EXPECT_EQ(e.actor(), "Counter<n=20>");
    EXPECT_EQ(e.event(), "add<k=10>");
  }
  EXPECT_EQ(engine.frame(), 2u);
  EXPECT_EQ(to_text(engine.string()), "Counter<n=20>");
}

TEST(Engine, GeneratorErrorsNameTheGenerator) {
  class Broken : public Generator {
    void generate(const FrameInfo&, EventList& out) override { out.emit("add", {1.5}); }  // wrong kind
    std::string name() const override { return "broken"; }
  };
  auto a = counter_alphabet();
  Engine engine(parse_string(a, "Counter<n=0>"), {std::make_shared<Broken>()}, nullptr);
  try {
    engine.step();
    FAIL() << "no error";
  } catch (const FrameError& e) {
    EXPECT_EQ(e.stage(), "generate");
    EXPECT_NE(e.where().find("broken"), std::string::npos);
    EXPECT_NE(e.cause_message().find("add.k"), std::string::npos) << e.cause_message();
  }
  EXPECT_EQ(engine.frame(), 0u);
}

TEST(Engine, SameSeedSameTraceOtherSeedOtherTrace) {
  auto a = counter_alphabet();
  auto trace_of = [&](std::uint64_t seed) {
    Engine engine(parse_string(a, "Counter<n=0> . Counter<n=0>"), {std::make_shared<RandomGenerator>()}, nullptr,
                  EngineOptions{0.1, seed});
    std::vector<std::uint64_t> hashes;
    engine.add_observer([&](const FrameRecord& r) { hashes.push_back(r.after.content_hash()); });
    engine.run(3);
    return hashes;
  };
  EXPECT_EQ(trace_of(1), trace_of(1));
  EXPECT_NE(trace_of(1), trace_of(2));
}

TEST(Engine, RefusesABadTimeStep) {
  auto a = counter_alphabet();
  EXPECT_THROW(Engine(parse_string(a, "Counter"), {}, nullptr, EngineOptions{0.0, 0}), SchemaError);
  EXPECT_THROW(Engine(parse_string(a, "Counter"), {}, nullptr, EngineOptions{std::nan(""), 0}), SchemaError);
}

// --- large attributes written in place during a frame (ActorState::edit_blob) ---------------

namespace {

/// Painter<canvas: 8 uint8 cells>: paint<cell, colour> sets a cell; fail<cell> sets it, then throws.
std::shared_ptr<Alphabet> painter_alphabet() {
  auto a = std::make_shared<Alphabet>();
  a->add_primitive("Shown");
  a->add_event_type("paint", false, schema({integer("cell"), integer("colour")}));
  a->add_event_type("fail", false, schema({integer("cell")}));
  a->add_event_type("add", false, schema({integer("cell"), integer("amount")}));
  a->add_event_type("show", true);
  const EventTypeId fail = *a->find_event_type("fail"), add = *a->find_event_type("add");
  a->add_actor("Painter", {"paint", "fail", "add", "show"}, schema({ParamSpec{"canvas", ValueKind::Blob, std::nullopt}}),
               std::make_shared<LambdaActor>(
                   [fail, add](ActorState& s, const EventView& e, const EvolutionContext&, Replacement&) {
                     if (e.field_count() == 0) return;
                     auto canvas = s.edit_blob<std::uint8_t>(0);
                     const auto cell = static_cast<std::size_t>(e.value(0).i);
                     if (e.type() == add) return canvas.set(cell, static_cast<std::uint8_t>(canvas[cell] + e.value(1).i));
                     canvas.set(static_cast<std::size_t>(e.value(0).i), e.type() == fail ? 99 : static_cast<std::uint8_t>(e.value(1).i));
                     if (e.type() == fail) throw std::runtime_error("failed after painting");
                   },
                   [](const ActorState&, const EventView&, StringBuilder& out) { out.primitive("Shown"); }));
  return a;
}

WorldString painter(const std::shared_ptr<Alphabet>& a, std::vector<std::uint8_t> cells) {
  auto canvas = std::make_shared<const Blob>(DType::UInt8, std::vector<std::int64_t>{8}, cells.data(), cells.size());
  StringBuilder b(a);
  b.actor("Painter", {Datum(std::shared_ptr<const Blob>(canvas))});
  return b.finish();
}

const Blob& canvas_of(const Engine& engine) {
  const WorldString& w = engine.string();
  return *w.store().blob(w.node(0).value(0));
}

std::vector<std::uint8_t> cells_of(const Blob& b) { return {b.view<std::uint8_t>().begin(), b.view<std::uint8_t>().end()}; }

class Script : public Generator {
 public:
  explicit Script(std::vector<std::vector<std::vector<std::int64_t>>> frames) : frames_(std::move(frames)) {}
  void generate(const FrameInfo& f, EventList& out) override {
    if (f.frame >= frames_.size()) return;
    for (const auto& e : frames_[f.frame]) {
      if (e.size() == 3) {
        out.emit("add", {e[0], e[1]});
      } else if (e.size() == 2) {
        out.emit("paint", {e[0], e[1]});
      } else {
        out.emit("fail", {e[0]});
      }
    }
  }

 private:
  std::vector<std::vector<std::vector<std::int64_t>>> frames_;
};

}  // namespace

TEST(EngineInPlace, AnUnsharedBlobIsWrittenInPlaceAndASharedOneIsCopied) {
  auto a = painter_alphabet();
  Engine engine(painter(a, {0, 0, 0, 0, 0, 0, 0, 0}), {std::make_shared<Script>(std::vector<std::vector<std::vector<std::int64_t>>>{
                    {{1, 5}}, {{2, 6}}, {{3, 7}}})},
                nullptr);
  const Blob* first = &canvas_of(engine);
  engine.step();
  EXPECT_EQ(&canvas_of(engine), first) << "held by the engine's string alone: no copy";
  EXPECT_EQ(cells_of(canvas_of(engine)), (std::vector<std::uint8_t>{0, 5, 0, 0, 0, 0, 0, 0}));
  const WorldString kept = engine.string();  // someone else holds the canvas now
  engine.step();
  EXPECT_NE(&canvas_of(engine), first) << "shared: written on a copy";
  EXPECT_EQ(cells_of(*kept.store().blob(kept.node(0).value(0))), (std::vector<std::uint8_t>{0, 5, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(cells_of(canvas_of(engine)), (std::vector<std::uint8_t>{0, 5, 6, 0, 0, 0, 0, 0}));
}

TEST(EngineInPlace, ActorsHoldingOneBlobEachWriteTheirOwnCopy) {
  // Two painters given the same canvas: each adds 5 to cell 1 of its own canvas. Written in place
  // by both (a store slot serving both hid the second reference), the sum would be 10.
  auto a = painter_alphabet();
  const std::vector<std::uint8_t> zeros(8, 0);
  for (unsigned threads : {1u, 2u}) {
    StringBuilder b(a);
    {
      auto canvas = std::make_shared<const Blob>(DType::UInt8, std::vector<std::int64_t>{8}, zeros.data(), zeros.size());
      b.actor("Painter", {Datum(std::shared_ptr<const Blob>(canvas))});
      b.actor("Painter", {Datum(std::shared_ptr<const Blob>(canvas))});
    }  // held by the string alone
    EngineOptions options;
    options.threads = threads;
    Engine engine(b.finish(), {std::make_shared<Script>(std::vector<std::vector<std::vector<std::int64_t>>>{{{1, 5, 0}}})}, nullptr,
                  options);
    engine.step();
    const WorldString& w = engine.string();
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_EQ(cells_of(*w.store().blob(w.node(k).value(0))), (std::vector<std::uint8_t>{0, 5, 0, 0, 0, 0, 0, 0}))
          << "painter " << k << ", " << threads << " threads";
    }
  }
}

TEST(EngineInPlace, AnActorHoldingOneBlobInTwoAttributesWritesACopy) {
  // Twin<a, b> given one array for both: writing `a` must leave `b` as it was, whether the actor
  // stands alone or was loaded from the engine's string (in place, journaled).
  auto a = std::make_shared<Alphabet>();
  const SymbolId twin = a->add_actor("Twin", {}, schema({ParamSpec{"a", ValueKind::Blob, std::nullopt}, ParamSpec{"b", ValueKind::Blob, std::nullopt}}),
                                     std::make_shared<LambdaActor>([](ActorState&, const EventView&, const EvolutionContext&, Replacement&) {},
                                                                   [](const ActorState&, const EventView&, StringBuilder&) {}));
  const std::vector<std::uint8_t> zeros(8, 0);
  auto fresh = [&] { return std::make_shared<const Blob>(DType::UInt8, std::vector<std::int64_t>{8}, zeros.data(), zeros.size()); };
  {
    ActorState s;
    {
      const auto shared = fresh();
      s.assign(*a, twin, std::vector<Datum>{Datum(shared), Datum(shared)});
    }  // held by the actor alone, in two attributes
    s.mutable_blob(0).mutable_view<std::uint8_t>()[1] = 5;
    s.edit_blob<std::uint8_t>(0).set(2, 6);
    EXPECT_EQ(cells_of(*s.get_blob(0)), (std::vector<std::uint8_t>{0, 5, 6, 0, 0, 0, 0, 0}));
    EXPECT_EQ(cells_of(*s.get_blob(1)), zeros);
  }
  StringBuilder b(a);
  {
    const auto shared = fresh();
    b.actor("Twin", {Datum(shared), Datum(shared)});
  }
  const WorldString w = b.finish();
  BlobJournal journal;
  ActorState s;
  s.load_in_place(w, 0, journal);
  s.edit_blob<std::uint8_t>(0).set(3, 7);
  EXPECT_EQ(cells_of(*s.get_blob(0)), (std::vector<std::uint8_t>{0, 0, 0, 7, 0, 0, 0, 0}));
  EXPECT_EQ(cells_of(*s.get_blob(1)), zeros);
  EXPECT_EQ(cells_of(*w.store().blob(w.node(0).value(0))), zeros) << "the string's array is not written";
  EXPECT_EQ(journal.size(), 0u);
}

TEST(EngineInPlace, AFailedFrameTakesBackWhatItWroteInPlace) {
  auto a = painter_alphabet();
  // Frame 1 paints cells 4 and 5 in place, then fails on cell 6: all three are taken back.
  Engine engine(painter(a, {1, 1, 1, 1, 1, 1, 1, 1}),
                {std::make_shared<Script>(std::vector<std::vector<std::vector<std::int64_t>>>{{{0, 9}}, {{4, 2}, {5, 3}, {6}}})},
                nullptr);
  engine.step();
  const Blob* canvas = &canvas_of(engine);
  const std::uint64_t revision = canvas->revision();
  EXPECT_THROW(engine.step(), FrameError);
  EXPECT_EQ(&canvas_of(engine), canvas);
  EXPECT_EQ(cells_of(canvas_of(engine)), (std::vector<std::uint8_t>{9, 1, 1, 1, 1, 1, 1, 1}));
  EXPECT_NE(canvas->revision(), revision) << "written and restored: a new revision (conservative)";
  EXPECT_EQ(engine.frame(), 1u);
}

TEST(EngineInPlace, AFailedDisplayTakesBackTheFrame) {
  class Show : public Generator {
    void generate(const FrameInfo&, EventList& out) override { out.emit("show"); }
  };
  class Broken : public Backend {
    void primitive(const NodeView&) override { throw std::runtime_error("display broke"); }
    void open(const NodeView&) override {}
    void close(const NodeView&) override {}
  };
  auto a = painter_alphabet();
  Engine engine(painter(a, {0, 0, 0, 0, 0, 0, 0, 0}),
                {std::make_shared<Script>(std::vector<std::vector<std::vector<std::int64_t>>>{{{3, 4}}}),
                 std::make_shared<Show>()},
                std::make_shared<Broken>());
  EXPECT_THROW(engine.step(), FrameError);
  EXPECT_EQ(cells_of(canvas_of(engine)), (std::vector<std::uint8_t>(8, 0)));
}

TEST(EngineInPlace, TheFreeFunctionEvolveNeverWritesItsInput) {
  auto a = painter_alphabet();
  const WorldString w = painter(a, {0, 0, 0, 0, 0, 0, 0, 0});
  EventList events(a);
  events.emit("paint", {std::int64_t{2}, std::int64_t{8}});
  const WorldString next = evolve(w, events, FrameContext{});
  EXPECT_EQ(cells_of(*w.store().blob(w.node(0).value(0))), (std::vector<std::uint8_t>(8, 0)));
  EXPECT_EQ(cells_of(*next.store().blob(next.node(0).value(0))), (std::vector<std::uint8_t>{0, 0, 8, 0, 0, 0, 0, 0}));
}

TEST(EngineInPlace, EditingWithTheWrongElementTypeIsRefused) {
  auto a = painter_alphabet();
  ActorState s;
  s.load(painter(a, {0, 0, 0, 0, 0, 0, 0, 0}), 0);
  EXPECT_THROW(s.edit_blob<std::int16_t>(0), SchemaError);
}

// --- reading from other threads ---------------------------------------------------------------------

namespace {

/// Every frame adds 1 to each of the canvas's 8 cells, in place when the string alone holds it.
class AddToEveryCell : public Generator {
 public:
  void generate(const FrameInfo&, EventList& out) override {
    for (std::int64_t cell = 0; cell < 8; ++cell) out.emit("add", {cell, 1});
  }
};

}  // namespace

TEST(EngineReads, CopiesTakenFromOtherThreadsAreWholeFrames) {
  // Frame k leaves every cell at k (mod 256); a copy taken in the middle of a frame's in-place
  // writes would hold cells of two frames, and a copy racing the in-place test could see its blob
  // written after it was taken.
  auto a = painter_alphabet();
  EngineOptions options;
  options.threads = 2;
  Engine engine(painter(a, std::vector<std::uint8_t>(8, 0)), {std::make_shared<AddToEveryCell>()}, nullptr, options);
  std::atomic<bool> running{true};
  std::atomic<int> torn{0}, reads{0};
  std::vector<std::thread> readers;
  for (int k = 0; k < 4; ++k) {
    readers.emplace_back([&] {
      while (running.load()) {
        const std::uint64_t before = engine.frame();
        const WorldString w = engine.string_copy();
        const EventList events = engine.last_events_copy();
        const std::vector<std::uint8_t> cells = cells_of(*w.store().blob(w.node(0).value(0)));
        const std::uint64_t after = engine.frame();
        bool whole = std::all_of(cells.begin(), cells.end(), [&](std::uint8_t c) { return c == cells[0]; });
        bool in_time = false;
        for (std::uint64_t f = before; f <= after; ++f) in_time = in_time || cells[0] == static_cast<std::uint8_t>(f);
        if (!whole || !in_time || (before > 0 && events.size() != 8)) ++torn;
        ++reads;
      }
    });
  }
  for (int k = 0; k < 20; ++k) EXPECT_EQ(engine.run(100), StopReason::FrameLimit);
  running = false;
  for (auto& t : readers) t.join();
  EXPECT_EQ(torn.load(), 0);
  EXPECT_GT(reads.load(), 0);
  EXPECT_EQ(cells_of(canvas_of(engine)), std::vector<std::uint8_t>(8, static_cast<std::uint8_t>(2000 % 256)));
}

TEST(EngineReads, AnObserverAddedDuringAFrameIsRefused) {
  auto a = counter_alphabet();
  Engine engine(parse_string(a, "Counter<n=0>"), {std::make_shared<FixedGenerator>("add", 0)}, nullptr);
  engine.add_observer([&](const FrameRecord&) { engine.add_observer([](const FrameRecord&) {}); });
  EXPECT_THROW(engine.step(), Error);
}
