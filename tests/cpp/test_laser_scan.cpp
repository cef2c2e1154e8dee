// A laser scan to eLaser events (platform::laser_events): REP 117's readings, the one choice at
// range_max, and the simulated laser going through the same rule. Expected events by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "vwg/error.hpp"
#include "vwg/platform/laser_scan.hpp"
#include "vwg/sim/laser.hpp"
#include "vwg/sim/physics.hpp"
#include "vwg/sim/raycast.hpp"

using namespace vwg;

namespace {

using Events = std::vector<std::pair<double, double>>;

Events pairs(const platform::ScanEvents& e) {
  Events out;
  for (std::size_t i = 0; i < e.size(); ++i) out.emplace_back(e.dist()[i], e.angle()[i]);
  return out;
}

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

std::string error_of(const auto& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(LaserScan, EachReadingAsRep117SaysWithNoReturnAtRangeMax) {
  // range_min 0.1, range_max 10; beam i at -1 + 0.5 i.
  const std::vector<float> ranges = {2.0f, kInf, -kInf, kNaN, 20.0f, 0.05f, 10.0f, 9.5f, 0.1f};
  platform::ScanEvents got;
  platform::laser_events(ranges, -1.0, 0.5, 0.1, 10.0, got);
  const Events want = {
      {2.0, -1.0},                           // in range: an obstacle
                                             // +Inf: no return
      {0.1, 0.0},                            // -Inf: nearer than range_min, taken at range_min
                                             // NaN: nothing known; 20: beyond range_max; 0.05: below range_min
                                             // exactly range_max: no return (drivers report it so)
      {9.5, 2.5},                            // in range
      {static_cast<double>(0.1f), 3.0},      // float32 0.1 is just above range_min: in range
  };
  EXPECT_EQ(pairs(got), want);

  // The same beams given by their angles (as the simulated laser gives them): the same events, added on.
  std::vector<double> angles;
  for (std::size_t i = 0; i < ranges.size(); ++i) angles.push_back(-1.0 + static_cast<double>(i) * 0.5);
  platform::ScanEvents by_angles;
  platform::laser_events(ranges, angles, 0.1, 10.0, by_angles);
  EXPECT_EQ(pairs(by_angles), want);
  platform::laser_events(ranges, angles, 0.1, 10.0, by_angles);
  EXPECT_EQ(by_angles.size(), 2 * want.size());
}

TEST(LaserScan, RangeMaxIsComparedAsTheFloat32TheReadingsAre) {
  // float32(3.3) = 3.2999999523 < 3.3: a sensor reporting no return as range_max writes that.
  const float max32 = 3.3f;
  const std::vector<float> ranges = {max32, std::nextafter(max32, 0.0f)};
  platform::ScanEvents got;
  platform::laser_events(ranges, 0.0, 1.0, 0.05, 3.3, got);
  EXPECT_EQ(pairs(got), (Events{{static_cast<double>(std::nextafter(max32, 0.0f)), 1.0}}));
}

TEST(LaserScan, BadLimitsAndLayoutsAreRefusedByName) {
  const std::vector<float> ranges = {1.0f, 2.0f};
  platform::ScanEvents out;
  EXPECT_NE(error_of([&] { platform::laser_events(ranges, 0.0, 0.1, -0.1, 5.0, out); }).find("range_min: expected a finite range >= 0"),
            std::string::npos);
  EXPECT_NE(error_of([&] { platform::laser_events(ranges, 0.0, 0.1, 1.0, 1.0, out); }).find("range_max: expected a finite range > range_min (1"),
            std::string::npos);
  EXPECT_NE(error_of([&] { platform::laser_events(ranges, 0.0, 0.1, 0.1, INFINITY, out); }).find("range_max"), std::string::npos);
  EXPECT_NE(error_of([&] { platform::laser_events(ranges, NAN, 0.1, 0.1, 5.0, out); }).find("angle_min: expected a finite angle"),
            std::string::npos);
  EXPECT_NE(error_of([&] { platform::laser_events(ranges, 0.0, INFINITY, 0.1, 5.0, out); }).find("angle_increment"),
            std::string::npos);
  const std::vector<double> one_angle = {0.0};
  EXPECT_NE(error_of([&] { platform::laser_events(ranges, one_angle, 0.1, 5.0, out); }).find("2 ranges for 1 angles"),
            std::string::npos);
  EXPECT_EQ(out.size(), 0u);
}

TEST(LaserScan, TheSimulatedLaserGoesThroughTheSameRule) {
  // A 10 × 10 m room of 0.5 m cells, a wall down column 6 (its face at x = 3 m); the robot at
  // (1, 2.5) looking along +x: the one beam (fov 0.1, 1 beam: straight ahead) meets the face 2 m away,
  // exactly (4 cells of 0.5 m).
  sim::OccupancyGrid grid;
  grid.width = grid.height = 20;
  grid.resolution = 0.5;
  grid.data.assign(400, sim::kFree);
  for (int row = 0; row < 20; ++row) grid.data[static_cast<std::size_t>(row) * 20 + 6] = sim::kOccupied;
  sim::RobotSettings robot;
  robot.id = 1;
  robot.start = {1.0, 2.5, 0.0};
  robot.radius = 0.2;
  const std::vector<sim::RobotSettings> robots = {robot};
  auto world = std::make_shared<sim::PhysicsWorld>(grid, robots, sim::PhysicsSettings{});
  auto scanner = std::make_shared<sim::RangeScanner>(std::make_shared<sim::GridRaycaster>(grid), world);
  auto alphabet = std::make_shared<Alphabet>();
  alphabet->add_event_type("eLaser", false, Schema{{ParamSpec{"dist", ValueKind::Real, 0.0}, ParamSpec{"angle", ValueKind::Real, 0.0}}});
  auto events_of = [&](double max_range) {
    sim::LaserSpec spec;
    spec.beams = 1;
    spec.fov = 0.1;
    spec.noise = 0.0;
    spec.max_range = max_range;
    sim::LaserGenerator laser(scanner, 1, spec, *alphabet);
    EventList out(alphabet);
    laser.generate(FrameInfo{}, out);
    EXPECT_EQ(laser.ranges()[0], 2.0f);  // the hit, exactly at the face
    Events got;
    for (std::size_t i = 0; i < out.size(); ++i) got.emplace_back(EventView(out, i).number(0), EventView(out, i).number(1));
    return got;
  };
  EXPECT_EQ(events_of(2.5), (Events{{2.0, 0.0}}));
  // The wall exactly at max_range: the raycaster counts the hit, but a reading of max_range is no
  // return (as a real LaserScan's is): no event.
  EXPECT_EQ(events_of(2.0), Events{});
}
