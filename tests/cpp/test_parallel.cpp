// The frame's work on several threads (parallel.hpp, EngineOptions::threads): every item once,
// the lowest failure reported, nested calls inline, a fresh pool after fork(); and an engine whose
// generators and actors run side by side gives the one-thread fold's frames, failures and undo.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <stdexcept>
#include <vector>

#include "helpers.hpp"
#include "src/parallel.hpp"

using namespace vwg;
using namespace vwg::testing;

TEST(ParallelFor, CallsEveryItemOnce) {
  for (unsigned threads : {1u, 2u, 4u, 9u}) {
    std::vector<std::atomic<int>> calls(1000);
    parallel_for(calls.size(), threads, [&](std::size_t i) { calls[i].fetch_add(1); });
    for (std::size_t i = 0; i < calls.size(); ++i) ASSERT_EQ(calls[i].load(), 1) << "item " << i << ", " << threads << " threads";
  }
  parallel_for(0, 4, [](std::size_t) { FAIL() << "no items: no call"; });
}

TEST(ParallelFor, RethrowsTheLowestFailingItemAfterRunningEveryItem) {
  for (int round = 0; round < 20; ++round) {
    std::atomic<int> ran{0};
    try {
      parallel_for(500, 4, [&](std::size_t i) {
        ran.fetch_add(1);
        if (i == 3 || i == 250 || i == 499) throw std::runtime_error("item " + std::to_string(i));
      });
      FAIL() << "expected a throw";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 3");
    }
    EXPECT_EQ(ran.load(), 500);
  }
}

TEST(ParallelFor, ANestedCallRunsOnTheCallingThread) {
  std::vector<std::atomic<int>> calls(64 * 8);
  parallel_for(64, 4, [&](std::size_t i) {
    parallel_for(8, 4, [&](std::size_t j) { calls[i * 8 + j].fetch_add(1); });
  });
  for (auto& c : calls) ASSERT_EQ(c.load(), 1);
}

TEST(ParallelFor, AForkedChildStartsAFreshPool) {
  std::atomic<int> sum{0};
  parallel_for(100, 4, [&](std::size_t i) { sum.fetch_add(static_cast<int>(i)); });  // the parent's pool runs
  ASSERT_EQ(sum.load(), 4950);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    alarm(20);  // a pool waiting on the parent's threads would hang: the alarm ends it with a signal
    std::atomic<int> s{0};
    parallel_for(100, 4, [&](std::size_t i) { s.fetch_add(static_cast<int>(i)); });
    _exit(s.load() == 4950 ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child was killed (signal " << WTERMSIG(status) << ")";
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

// --- an engine's frames on 1, 2 and 4 threads --------------------------------------------------

namespace {

class ConcurrentActor : public LambdaActor {
 public:
  using LambdaActor::LambdaActor;
  bool concurrent() const override { return true; }
};

/// Walker<id, n, canvas: 8 uint8>: step<k> (addressed) adds k and a number from the frame's seed,
/// then paints canvas[n % 8] in place; past 60 it splits into two walkers (a replacement);
/// boom<> addressed to it paints, then throws.
std::shared_ptr<Alphabet> walker_alphabet() {
  auto a = std::make_shared<Alphabet>();
  a->add_event_type("step", false, schema({integer("k")}));
  a->add_event_type("boom", false);
  a->add_event_type("tick", false);
  const EventTypeId boom = *a->find_event_type("boom"), tick = *a->find_event_type("tick");
  a->add_actor(
      "Walker", {"step", "boom", "tick"},
      schema({integer("id", 0), integer("n", 0), ParamSpec{"canvas", ValueKind::Blob, std::nullopt}}),
      std::make_shared<ConcurrentActor>([boom, tick](ActorState& s, const EventView& e, const EvolutionContext& ctx,
                                                      Replacement& out) {
        if (e.type() == tick) {
          s.set_int(1, s.get_int(1) + 1);
          return;
        }
        const std::int64_t n = s.get_int(1) + (e.type() == boom ? 0 : e.value(0).i) + static_cast<std::int64_t>(ctx.seed % 7);
        auto canvas = s.edit_blob<std::uint8_t>(2);
        canvas.set(static_cast<std::size_t>(n % 8), static_cast<std::uint8_t>(n % 251));
        if (e.type() == boom) throw std::runtime_error("walker " + std::to_string(s.get_int(0)) + " blew up");
        if (n > 60) {
          StringBuilder& b = out.replace();
          for (std::int64_t part : {1, 2}) {
            b.actor("Walker", {Datum(s.get_int(0) * 10 + part), Datum(std::int64_t{0}), Datum(s.get_blob(2))});
          }
          return;
        }
        s.set_int(1, n);
      }));
  return a;
}

/// step<to=id, k> with k from its own random stream: one per walker, run side by side.
class StepGenerator : public Generator {
 public:
  explicit StepGenerator(std::int64_t id) : id_(id) {}
  void reset(std::uint64_t seed) override { rng_.reseed(seed); }
  void generate(const FrameInfo&, EventList& out) override {
    const Datum k(static_cast<std::int64_t>(rng_.below(5)));
    out.emit(out.alphabet().event_type_id("step"), std::span<const Datum>(&k, 1), id_);
    if (boom_at_ && *boom_at_ == frame_) out.emit(out.alphabet().event_type_id("boom"), {}, id_);
    ++frame_;
  }
  bool concurrent() const override { return true; }
  std::optional<std::uint64_t> boom_at_;

 private:
  std::int64_t id_;
  Rng rng_;
  std::uint64_t frame_ = 0;
};

struct Walkers {
  explicit Walkers(unsigned threads, std::optional<std::uint64_t> boom_at = std::nullopt) {
    auto a = walker_alphabet();
    StringBuilder b(a);
    std::vector<std::shared_ptr<Generator>> gens;
    for (std::int64_t id = 1; id <= 12; ++id) {
      std::vector<std::uint8_t> cells(8, static_cast<std::uint8_t>(id));
      b.actor("Walker", {Datum(id), Datum(std::int64_t{0}),
                         Datum(std::make_shared<const Blob>(DType::UInt8, std::vector<std::int64_t>{8}, cells.data(), 8))});
      auto g = std::make_shared<StepGenerator>(id);
      if (id == 4 || id == 9) g->boom_at_ = boom_at;
      gens.push_back(g);
    }
    gens.push_back(std::make_shared<EveryFrameGenerator>(*a, "tick"));
    EngineOptions options;
    options.seed = 7;
    options.threads = threads;
    engine = std::make_unique<Engine>(b.finish(), gens, nullptr, options);
  }
  std::unique_ptr<Engine> engine;
};

/// The string with every canvas's cells (to_text names a blob by its hash).
std::string contents(const WorldString& w) {
  std::string s = to_text(w);
  for (std::size_t i = 0; i < w.nodes().size(); ++i) {
    if (w.nodes()[i].kind != NodeKind::Actor) continue;
    for (std::uint8_t c : w.store().blob(w.node(i).value(2))->view<std::uint8_t>()) s += " " + std::to_string(c);
  }
  return s;
}

}  // namespace

TEST(ParallelFrames, OneTwoAndFourThreadsGiveTheSameFrames) {
  Walkers one(1), two(2), four(4);
  bool split = false;
  for (int frame = 0; frame < 40; ++frame) {
    one.engine->step();
    two.engine->step();
    four.engine->step();
    const std::string expected = contents(one.engine->string());
    ASSERT_EQ(contents(two.engine->string()), expected) << "frame " << frame;
    ASSERT_EQ(contents(four.engine->string()), expected) << "frame " << frame;
    split = split || expected.find("id=11") != std::string::npos;
  }
  EXPECT_TRUE(split) << "a walker replaced itself during the run (the replacement path is covered)";
  EXPECT_EQ(four.engine->options().threads, 4u);
}

TEST(ParallelFrames, AFailedFrameNamesTheFirstActorAndUndoesEveryActorsInPlaceWrites) {
  std::string expected_error;
  for (unsigned threads : {1u, 2u, 4u}) {
    Walkers run(threads, 3);  // walkers 4 and 9 blow up in frame 3, after painting in place
    for (int frame = 0; frame < 3; ++frame) run.engine->step();
    const std::string before = contents(run.engine->string());
    try {
      run.engine->step();
      FAIL() << "frame 3 must fail";
    } catch (const FrameError& e) {
      if (expected_error.empty()) expected_error = e.what();
      EXPECT_EQ(std::string(e.what()), expected_error) << threads << " threads";
      EXPECT_NE(std::string(e.what()).find("walker 4 blew up"), std::string::npos) << e.what();
    }
    EXPECT_EQ(contents(run.engine->string()), before) << threads << " threads: every walker's writes undone";
    EXPECT_EQ(run.engine->frame(), 3u);
  }
}

TEST(ParallelFrames, RefusesMoreThreadsThanTheLimit) {
  auto a = walker_alphabet();
  EngineOptions options;
  options.threads = kMaxThreads + 1;
  EXPECT_THROW(Engine(WorldString(a), {}, nullptr, options), SchemaError);
}

TEST(ParallelFrames, AGeneratorThatRunsSideBySideIsListedOnce) {
  auto a = walker_alphabet();
  auto laser = std::make_shared<StepGenerator>(1);
  try {
    Engine(WorldString(a), {laser, std::make_shared<EveryFrameGenerator>(*a, "tick"), laser}, nullptr);
    FAIL() << "expected a SchemaError";
  } catch (const SchemaError& e) {
    EXPECT_NE(std::string(e.what()).find("generators[2]: 'generator' is listed twice (also as generators[0])"),
              std::string::npos) << e.what();
  }
}
