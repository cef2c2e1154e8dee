// Saved states (vwg/state.hpp): what is saved and loaded goes on as the original does, bit for bit, and
// a cut or damaged state is a SchemaError naming its part.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "vwg/engine.hpp"
#include "vwg/error.hpp"
#include "vwg/plan/dstar_lite.hpp"
#include "vwg/random.hpp"
#include "vwg/sim/physics.hpp"
#include "vwg/state.hpp"
#include "vwg/text.hpp"
#include "helpers.hpp"

using namespace vwg;

namespace {

sim::OccupancyGrid room(int w, int h) {
  sim::OccupancyGrid g;
  g.width = w;
  g.height = h;
  g.resolution = 0.05;
  g.data.assign(static_cast<std::size_t>(w) * h, sim::kFree);
  for (int r = 0; r < h; ++r) g.data[static_cast<std::size_t>(r) * w + w / 2] = r < h / 2 ? sim::kOccupied : sim::kFree;
  return g;
}

platform::RobotSettings robot_at(int id, double x, double y, double theta) {
  platform::RobotSettings r;
  r.id = id;
  r.start = {x, y, theta};
  r.radius = 0.2;
  return r;
}

/// Two robots driven into each other and into the wall (contacts under way at the save), with noise.
std::unique_ptr<sim::PhysicsWorld> pushing_world() {
  const platform::RobotSettings robots[] = {robot_at(1, 1.0, 1.0, 0.0), robot_at(2, 2.0, 1.05, 3.14159)};
  sim::PhysicsSettings s;
  s.noise.motors = 0.05;
  s.noise.odometry = 0.05;
  s.seed = 7;
  auto w = std::make_unique<sim::PhysicsWorld>(room(100, 60), robots, s);
  w->command(1, {{platform::MotionStep::Drive, 3.0}});
  w->command(2, {{platform::MotionStep::Drive, 3.0}});
  return w;
}

std::vector<std::uint64_t> bits_of(const sim::PhysicsWorld& w) {
  std::vector<std::uint64_t> out;
  for (const auto& r : w.robots()) {
    for (double v : {r.pose.x, r.pose.y, r.pose.theta, r.odometry.x, r.odometry.y, r.odometry.theta, r.speed, r.travelled}) {
      out.push_back(std::bit_cast<std::uint64_t>(v));
    }
    out.push_back(r.collisions);
  }
  return out;
}

}  // namespace

TEST(State, ReaderRefusesWhatIsNotThereNamingThePart) {
  StateWriter out;
  out.u64(3);
  out.text("abc");
  StateReader in(out.bytes(), "generator 2 (gLaser)");
  EXPECT_EQ(in.u64(), 3u);
  EXPECT_EQ(in.text(), "abc");
  in.end();
  StateReader cut(std::string_view(out.bytes()).substr(0, 17), "platform sim");
  cut.u64();
  try {
    cut.text();
    FAIL() << "a text longer than what is left was read";
  } catch (const SchemaError& e) {
    EXPECT_EQ(e.field(), "platform sim");
    EXPECT_NE(std::string(e.what()).find("more than the 1 bytes left"), std::string::npos) << e.what();
  }
  StateReader extra(out.bytes(), "x");
  extra.u64();
  EXPECT_THROW(extra.end(), SchemaError);
}

TEST(State, RandomStreamGoesOnWithItsSpare) {
  Rng a(42);
  a.normal();  // one of a pair: the spare is kept
  StateWriter out;
  a.save(out);
  Rng b(1);
  StateReader in(out.bytes(), "rng");
  b.load(in);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(std::bit_cast<std::uint64_t>(a.normal()), std::bit_cast<std::uint64_t>(b.normal()));
}

TEST(State, SimulatorLoadedMidContactGoesOnBitForBit) {
  auto a = pushing_world();
  for (int k = 0; k < 40; ++k) a->advance(0.1);  // the robots have met and push (contacts under way)
  ASSERT_GT(a->robot(1).collisions, 0u);
  a->take_collisions();
  StateWriter out;
  a->save_state(out);
  auto b = pushing_world();  // made the same way: its journal (two commands) begins the saved one
  StateReader in(out.bytes(), "platform sim");
  b->load_state(in);
  EXPECT_EQ(bits_of(*a), bits_of(*b));
  for (int k = 0; k < 30; ++k) {
    a->advance(0.1);
    b->advance(0.1);
    if (k == 10) {
      a->command(1, {{platform::MotionStep::Turn, 1.0}, {platform::MotionStep::Drive, -0.5}});
      b->command(1, {{platform::MotionStep::Turn, 1.0}, {platform::MotionStep::Drive, -0.5}});
    }
    ASSERT_EQ(bits_of(*a), bits_of(*b)) << "step " << k;
    ASSERT_EQ(a->take_collisions().size(), b->take_collisions().size());
  }
}

TEST(State, SimulatorRefusesAStateOfAnotherWorldOrOneUsedDifferently) {
  auto a = pushing_world();
  a->advance(1.0);
  StateWriter out;
  a->save_state(out);
  const platform::RobotSettings one[] = {robot_at(1, 1.0, 1.0, 0.0)};
  sim::PhysicsWorld other(room(100, 60), one, sim::PhysicsSettings{});
  StateReader in(out.bytes(), "platform sim");
  EXPECT_THROW(other.load_state(in), SchemaError);
  auto used = pushing_world();
  used->command(2, {{platform::MotionStep::Turn, 0.5}});  // not what the saved one was told
  StateReader again(out.bytes(), "platform sim");
  EXPECT_THROW(used->load_state(again), SchemaError);
}

TEST(State, DStarLiteLoadedRepairsAsTheOriginal) {
  using plan::Cell;
  plan::BlockedGrid g(30, 40);  // a wall across the middle, open at both ends
  for (int r = 5; r < 25; ++r) g.set_blocked({r, 20}, true);
  plan::DStarLite a(g, {15, 2}, {15, 37});
  const auto first = a.path();
  ASSERT_TRUE(first.found());
  a.move_to(first.cells[3]);
  const Cell wall[] = {{4, 20}, {25, 20}, {26, 20}};
  a.update_cells(wall, true);
  a.path();
  StateWriter out;
  a.save(out);
  StateReader in(out.bytes(), "decider dstar");
  plan::DStarLite b = plan::DStarLite::load(in);
  in.end();
  const Cell more[] = {{3, 20}, {27, 20}};
  const Cell gone[] = {{10, 20}};
  for (plan::DStarLite* d : {&a, &b}) {
    d->update_cells(more, true);
    d->move_to({14, 6});
    d->update_cells(gone, false);
  }
  const auto pa = a.path(), pb = b.path();
  ASSERT_EQ(pa.cells.size(), pb.cells.size());
  for (std::size_t k = 0; k < pa.cells.size(); ++k) EXPECT_TRUE(pa.cells[k] == pb.cells[k]) << k;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(pa.length), std::bit_cast<std::uint64_t>(pb.length));
  EXPECT_EQ(a.expanded(), b.expanded());
  // Cut anywhere, or a queue position changed: refused, never read past the end.
  const std::string bytes = out.bytes();
  for (std::size_t n : {std::size_t{0}, std::size_t{9}, bytes.size() / 2, bytes.size() - 1}) {
    StateReader cut(std::string_view(bytes).substr(0, n), "decider dstar");
    EXPECT_THROW(plan::DStarLite::load(cut), SchemaError) << n;
  }
}

namespace {

class Counting final : public Generator {
 public:
  void generate(const FrameInfo&, EventList&) override { ++calls; }
  void save_state(StateWriter& out) const override { out.u64(calls); }
  void load_state(StateReader& in) override {
    calls = in.u64();
    in.end();
  }
  std::uint64_t calls = 0;
};

class Silent final : public Generator {
 public:
  void generate(const FrameInfo&, EventList&) override {}
  std::string name() const override { return "silent"; }
};

}  // namespace

TEST(State, EngineSavesItsStringFrameAndGeneratorsAndRefusesOneThatDoesNotSay) {
  auto alphabet = std::make_shared<Alphabet>();
  alphabet->add_primitive("Lamp", vwg::testing::schema({vwg::testing::integer("on", 0)}));
  auto counting = std::make_shared<Counting>();
  Engine e(parse_string(alphabet, "Lamp<1>"), {counting}, nullptr);
  for (int k = 0; k < 3; ++k) e.step();
  const EngineState s = e.save_state();
  EXPECT_EQ(s.frame, 3u);
  EXPECT_EQ(s.string, "Lamp<1>");
  auto other = std::make_shared<Counting>();
  Engine f(parse_string(alphabet, "Lamp<0>"), {other}, nullptr);
  f.load_state(s);
  EXPECT_EQ(f.frame(), 3u);
  EXPECT_EQ(to_text(f.string()), "Lamp<1>");
  EXPECT_EQ(other->calls, 3u);
  Engine g(parse_string(alphabet, "Lamp<1>"), {std::make_shared<Silent>()}, nullptr);
  try {
    g.save_state();
    FAIL() << "a generator that does not say what it keeps was saved";
  } catch (const SchemaError& err) {
    EXPECT_EQ(err.field(), "silent");
  }
}

TEST(State, EngineSavesAFigureAndReadsAStringSavedBeforeFigures) {
  auto alphabet = std::make_shared<Alphabet>();
  alphabet->add_primitive("Lamp", vwg::testing::schema({vwg::testing::integer("on", 0)}));
  const WorldString w = parse_string(alphabet, "Lamp<1> Lamp<2> . Lamp<3>");
  Engine e(w, {std::make_shared<Counting>()}, nullptr);
  e.step();
  const EngineState s = e.save_state();
  EXPECT_EQ(s.string, "Lamp<1> Lamp<2> . Lamp<3>");
  Engine f(parse_string(alphabet, "Lamp<0>"), {std::make_shared<Counting>()}, nullptr);
  f.load_state(s);
  EXPECT_EQ(f.string(), w);
  EXPECT_TRUE(f.string().nodes()[1].joined);
  // A state written before figures existed holds '.' between every two primitives: it still loads,
  // as the objects it always meant.
  EngineState old = s;
  old.string = "Lamp<1> . Lamp<2> . Lamp<3>";
  f.load_state(old);
  EXPECT_EQ(to_text(f.string()), "Lamp<1> . Lamp<2> . Lamp<3>");
  EXPECT_FALSE(f.string().nodes()[1].joined);
}
