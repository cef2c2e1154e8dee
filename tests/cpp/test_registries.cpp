// Registries by name: the built-in parts, a third party's, and the errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "vwg/alphabet.hpp"
#include "vwg/backend.hpp"
#include "vwg/robot/planners.hpp"
#include "vwg/robot/registries.hpp"
#include "vwg/sim/laser.hpp"
#include "vwg/sim/registries.hpp"

using namespace vwg;

namespace {

std::string error_of(const auto& make) {
  try {
    make();
  } catch (const SchemaError& e) {
    return e.what();
  }
  return "";
}

geometry::OccupancyGrid room(int cells, double res) {
  geometry::OccupancyGrid g;
  g.width = g.height = cells;
  g.resolution = res;
  g.data.assign(static_cast<std::size_t>(cells) * cells, 0);
  return g;
}

}  // namespace

TEST(Registries, BuiltInDecidersAreMadeByName) {
  const auto names = robot::deciders().names();
  for (const char* name : {"random", "astar", "jps", "dstar", "rrtconnect", "rrtstar", "prm", "astar-octile", "jps-octile"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  }
  // Each grid decider says its own name, heuristic included.
  for (const char* name : {"astar", "dstar", "jps", "astar-octile", "jps-octile"}) EXPECT_EQ(robot::deciders().create(name)->name(), name);
  EXPECT_NE(robot::deciders().create("astar"), robot::deciders().create("astar"));  // a new one each time
}

TEST(Registries, UnknownAndDuplicateNamesAreRefusedWithTheKnownOnes) {
  const std::string unknown = error_of([] { robot::deciders().create("dijkstra"); });
  EXPECT_NE(unknown.find("unknown decider 'dijkstra' (known: astar, astar-octile, dstar, jps, jps-octile, prm, random, rrtconnect, rrtstar"),
            std::string::npos) << unknown;
  const std::string twice = error_of([] { backends().add("trace", [] { return std::make_shared<NullBackend>(); }); });
  EXPECT_NE(twice.find("backend 'trace': is already registered"), std::string::npos) << twice;
}

TEST(Registries, AGridDeciderRefusesAHeuristicItCannotUse) {
  using Algorithm = robot::GridDecider::Algorithm;
  // Manhattan overestimates a diagonal move: the searches would return longer paths.
  const std::string manhattan = error_of([] { robot::GridDecider(Algorithm::AStar, plan::Heuristic::Manhattan); });
  EXPECT_NE(manhattan.find("heuristic"), std::string::npos) << manhattan;
  const std::string dstar = error_of([] { robot::GridDecider(Algorithm::DStarLite, plan::Heuristic::Octile); });
  EXPECT_NE(dstar.find("D* Lite's decider keeps its own heuristic (euclidean), not octile"), std::string::npos) << dstar;
  EXPECT_EQ(robot::GridDecider(Algorithm::JumpPoint, plan::Heuristic::Zero).name(), "jps-zero");
}

TEST(Registries, AThirdPartyRegistersWithoutEditingVwg) {
  Registry<Backend> local("backend");
  local.add("quiet", [] { return std::make_shared<NullBackend>(); });
  EXPECT_TRUE(local.contains("quiet"));
  EXPECT_NE(std::dynamic_pointer_cast<NullBackend>(local.create("quiet")), nullptr);
  EXPECT_NE(std::dynamic_pointer_cast<TraceBackend>(backends().create("trace")), nullptr);
}

TEST(Registries, TheSimulatorAndItsSensorsByName) {
  sim::PlatformSetup setup;
  setup.grid = room(100, 0.05);  // 5 × 5 m, no walls inside (the simulator walls the border)
  platform::RobotSettings r;
  r.id = 4;
  r.start = {2.5, 2.5, 0.0};
  setup.robots = {r};
  auto sim = sim::platforms().create("sim", setup);
  ASSERT_EQ(sim->name(), "sim");
  EXPECT_DOUBLE_EQ(sim->robot(4).pose.x, 2.5);
  setup.options["url"] = "ws://127.0.0.1:9090";
  const std::string option = error_of([&] { sim::platforms().create("sim", setup); });
  EXPECT_NE(option.find("unknown option 'url' (it takes none)"), std::string::npos) << option;

  auto alphabet = std::make_shared<Alphabet>();
  alphabet->add_event_type("eLaser", false, Schema{{ParamSpec{"dist", ValueKind::Real, 0.0}, ParamSpec{"angle", ValueKind::Real, 0.0}}});
  sim::SensorSetup s;
  s.platform = sim;
  s.alphabet = alphabet;
  s.robot = 4;
  s.grid = std::make_shared<const geometry::OccupancyGrid>(setup.grid);
  s.laser.beams = 4;
  s.laser.noise = 0.0;
  auto laser = std::dynamic_pointer_cast<sim::LaserGenerator>(sim::sensors().create("laser", s));
  ASSERT_NE(laser, nullptr);
  EXPECT_EQ(laser->spec().beams, 4);
  EXPECT_TRUE(sim::ranging_sensors().contains("laser") && !sim::ranging_sensors().contains("camera"));
  s.alphabet = nullptr;
  const std::string no_alphabet = error_of([&] { sim::sensors().create("kinect", s); });
  EXPECT_NE(no_alphabet.find("sensor kinect: needs the alphabet"), std::string::npos) << no_alphabet;
}
