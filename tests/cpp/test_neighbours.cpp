// The neighbour tracker (vwg/platform/neighbours.hpp) on synthetic scans worked out here: the ranges of a
// 360-beam laser to a disc (the ray-circle intersection) and to a straight wall (the ray-line one).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "vwg/platform/neighbours.hpp"

namespace vwg::platform {

namespace {

constexpr double kMax = 8.0;

struct Scan {
  std::vector<double> angles;
  std::vector<float> ranges;
  ScanView view() const { return {ranges, angles, kMax}; }
};

/// From the origin facing +x: each beam's range to the nearest of a disc (cx, cy, r) and the wall x = wall_x
/// (none when wall_x <= 0), kMax where neither is met.
Scan scan_of(double cx, double cy, double r, double wall_x = 0.0) {
  Scan s;
  for (int k = 0; k < 360; ++k) {
    const double a = -std::numbers::pi + k * std::numbers::pi / 180.0, dx = std::cos(a), dy = std::sin(a);
    double best = kMax;
    const double b = dx * cx + dy * cy, c = cx * cx + cy * cy - r * r, disc = b * b - c;
    if (disc >= 0 && b - std::sqrt(disc) > 0) best = std::min(best, b - std::sqrt(disc));
    if (wall_x > 0 && dx > 1e-9) best = std::min(best, wall_x / dx);
    s.angles.push_back(a);
    s.ranges.push_back(static_cast<float>(best));
  }
  return s;
}

}  // namespace

TEST(Neighbours, ADiscInTheOpenIsOneNeighbourWhereItIs) {
  NeighbourTracker tracker;
  const Scan s = scan_of(2.0, 0.5, 0.2);
  tracker.update(s.view(), {0, 0, 0}, 0.0);
  ASSERT_EQ(tracker.neighbours().size(), 1u);
  const Neighbour& n = tracker.neighbours()[0];
  EXPECT_NEAR(n.x, 2.0, 0.06);
  EXPECT_NEAR(n.y, 0.5, 0.06);
  EXPECT_NEAR(n.radius, 0.2, 0.05);
  EXPECT_EQ(n.vx, 0.0);  // first seen: at rest
}

TEST(Neighbours, AMovingDiscGetsItsVelocity) {
  NeighbourTracker tracker;
  for (int step = 0; step <= 5; ++step) {  // 1 m/s along +y, a scan every 0.1 s
    const Scan s = scan_of(2.0, -0.5 + 0.1 * step, 0.2);
    tracker.update(s.view(), {0, 0, 0}, 0.1 * step);
  }
  ASSERT_EQ(tracker.neighbours().size(), 1u);
  const Neighbour& n = tracker.neighbours()[0];
  // The average weighs each new displacement by a half: after 5 of them, 1 − 2⁻⁵ of the speed.
  EXPECT_NEAR(n.vy, 1.0 - std::pow(0.5, 5), 0.1);
  EXPECT_NEAR(n.vx, 0.0, 0.1);
  EXPECT_EQ(n.id, 1);
}

TEST(Neighbours, AWallIsNoNeighbour) {
  NeighbourTracker tracker;
  const Scan s = scan_of(0.0, 0.0, 0.0, 1.5);  // a wall across the whole front, 1.5 m ahead
  tracker.update(s.view(), {0, 0, 0}, 0.0);
  EXPECT_TRUE(tracker.neighbours().empty());
}

TEST(Neighbours, ADiscInFrontOfAWallStandsOut) {
  NeighbourTracker tracker;
  Scan s = scan_of(1.5, 0.0, 0.2);
  const Scan wall = scan_of(0.0, 0.0, 0.0, 3.0);
  for (std::size_t k = 0; k < s.ranges.size(); ++k) s.ranges[k] = std::min(s.ranges[k], wall.ranges[k]);
  tracker.update(s.view(), {0, 0, 0}, 0.0);
  ASSERT_EQ(tracker.neighbours().size(), 1u);
  EXPECT_NEAR(tracker.neighbours()[0].x, 1.5, 0.06);
}

TEST(Neighbours, ANeighbourNotSeenForLongIsForgotten) {
  NeighbourTracker tracker;
  tracker.update(scan_of(2.0, 0.0, 0.2).view(), {0, 0, 0}, 0.0);
  const Scan empty = scan_of(0.0, 0.0, 0.0);  // nothing within range
  tracker.update(empty.view(), {0, 0, 0}, 0.3);
  EXPECT_EQ(tracker.neighbours().size(), 1u);  // 0.3 s unseen: kept
  tracker.update(empty.view(), {0, 0, 0}, 0.6);
  EXPECT_TRUE(tracker.neighbours().empty());  // 0.6 s: gone
}

}  // namespace vwg::platform
