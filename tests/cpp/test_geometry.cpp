// The geometry library against values worked out by hand, and its three former copies (the robot's
// map, the planners' distance field, Python's maps) answering alike through it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/clearance.hpp"
#include "geometry/inflate.hpp"
#include "vwg/blob.hpp"
#include "vwg/geometry/clearance_field.hpp"
#include "vwg/geometry/map_geometry.hpp"
#include "vwg/geometry/pose.hpp"
#include "vwg/robot/robot_map.hpp"

using namespace vwg;
using namespace vwg::geometry;

namespace {

constexpr double kPi = std::numbers::pi;

/// A 7 × 7 map of 1 m cells, origin (0, 0), with one wall at (row 3, col 3).
OccupancyGrid one_wall() {
  OccupancyGrid g;
  g.width = g.height = 7;
  g.resolution = 1.0;
  g.data.assign(49, kFree);
  g.data[3 * 7 + 3] = kOccupied;
  return g;
}

Blob robot_map_of(const OccupancyGrid& g) { return *robot::make_robot_map(g, true); }

}  // namespace

TEST(Geometry, WrapAngleIsTheRemainderModuloTwoPi) {
  EXPECT_DOUBLE_EQ(wrap_angle(1.5 * kPi), -0.5 * kPi);
  EXPECT_DOUBLE_EQ(wrap_angle(-1.5 * kPi), 0.5 * kPi);
  EXPECT_DOUBLE_EQ(wrap_angle(0.25), 0.25);
  EXPECT_DOUBLE_EQ(wrap_angle(0.25 + 6 * kPi), 0.25);
  EXPECT_EQ(wrap_angle(kPi), kPi);  // a tie goes to the even quotient, 0: π stays π
}

TEST(Geometry, APointSeenFromAnEarlierPoseIsGivenFromTheRobotNow) {
  // By hand: the robot was 1 m ahead and 2 m to the left of where it is now, turned a quarter turn to the
  // left. It saw a point 3 m away on its right (bearing -pi/2): from there, that is its own heading
  // turned right, i.e. the direction it faces now, so the point is 1 + 3 m ahead and 2 m left now.
  const Polar now = seen_from(Pose2{1.0, 2.0, 0.5 * kPi}, Polar{3.0, -0.5 * kPi});
  EXPECT_NEAR(now.dist, std::hypot(4.0, 2.0), 1e-12);
  EXPECT_NEAR(now.bearing, std::atan2(2.0, 4.0), 1e-12);
  // The other way round: turned a quarter turn right, a point 2 m ahead of it then is 2 m to the right now.
  const Polar right = seen_from(Pose2{0.0, 0.0, -0.5 * kPi}, Polar{2.0, 0.0});
  EXPECT_NEAR(right.dist, 2.0, 1e-12);
  EXPECT_NEAR(right.bearing, -0.5 * kPi, 1e-12);
  // Where it is now: the same point, bit for bit (a simulated sensor's events stay as they were).
  const Polar same = seen_from(Pose2{}, Polar{2.5, 0.7});
  EXPECT_EQ(same.dist, 2.5);
  EXPECT_EQ(same.bearing, 0.7);
}

TEST(Geometry, MapGeometryCellsAndCentres) {
  const MapGeometry g{4, 3, 0.5, {1.0, 2.0, 0.0}};
  int row = -1, col = -1;
  ASSERT_TRUE(g.cell_of(1.6, 3.1, row, col));
  EXPECT_EQ(row, 2);
  EXPECT_EQ(col, 1);
  EXPECT_FALSE(g.cell_of(0.9, 2.1, row, col));
  EXPECT_FALSE(g.cell_of(3.0, 2.1, row, col));  // x = 1 + 4 × 0.5 is the right edge, outside
  double x = 0, y = 0;
  g.centre_of(2, 1, x, y);
  EXPECT_DOUBLE_EQ(x, 1.75);
  EXPECT_DOUBLE_EQ(y, 3.25);
}

// The three former clearances (robot map, distance field, Python maps) give the distance to the
// wall's square worked out by hand: 1.5 straight, √2·1.5 to its corner, 0 inside.
TEST(Geometry, ClearanceIsTheSameEverywhere) {
  const OccupancyGrid g = one_wall();
  const Blob map = robot_map_of(g);
  const MapGeometry mg = MapGeometry::of(g);
  const ClearanceField field(BlockedGrid::from_occupancy(g), /*outside_blocked=*/false);
  struct Case {
    double x, y, want;
  };
  for (const Case& k : {Case{5.5, 3.5, 1.5}, Case{5.5, 5.5, std::hypot(1.5, 1.5)}, Case{3.5, 3.5, 0.0}, Case{3.2, 1.0, 2.0}}) {
    EXPECT_DOUBLE_EQ(robot::clearance(map, mg, k.x, k.y, 10.0), k.want) << k.x << ", " << k.y;
    EXPECT_DOUBLE_EQ(field.clearance(k.x, k.y, 10.0), k.want) << k.x << ", " << k.y;
    EXPECT_DOUBLE_EQ(clearance(g, k.x, k.y, 10.0, 50, /*unknown_blocked=*/false), k.want) << k.x << ", " << k.y;
  }
  // Capped: nothing nearer than the cap gives the cap itself.
  EXPECT_EQ(robot::clearance(map, mg, 5.5, 3.5, 1.0), 1.0);
  EXPECT_EQ(clearance(g, 5.5, 3.5, 1.0), 1.0);
  // Unknown space off the map counts when asked: 0.5 m from (0.5, 3.5) to the left edge.
  EXPECT_DOUBLE_EQ(clearance(g, 0.5, 3.5, 10.0, 50, true), 0.5);
  EXPECT_DOUBLE_EQ(ClearanceField(BlockedGrid::from_occupancy(g), true).clearance(0.5, 3.5, 10.0), 0.5);
  EXPECT_EQ(clearance(g, -1.0, 3.5, 10.0, 50, true), 0.0);
}

// Where the copies differed: a disc exactly `radius` from a wall. The robot's map lets it touch
// (its radius holds a margin; its runs are pinned by test_determinism.py), the planners' field does
// not (OMPL's validity is clearance > radius and its motion check must agree).
TEST(Geometry, SegmentTouchingAWallDependsOnTheRule) {
  const OccupancyGrid g = one_wall();
  // Along y = 2.5, 0.5 m below the wall's square [3, 4] × [3, 4].
  auto blocked = [&](int r, int c) { return g.at(r, c) >= 50; };
  EXPECT_TRUE(segment_clear_of_blocked(1.5, 2.5, 5.5, 2.5, 0.5, Touch::Allowed, 7, 7, blocked));
  EXPECT_FALSE(segment_clear_of_blocked(1.5, 2.5, 5.5, 2.5, 0.5, Touch::Refused, 7, 7, blocked));
  EXPECT_FALSE(segment_clear_of_blocked(1.5, 2.5, 5.5, 2.5, 0.51, Touch::Allowed, 7, 7, blocked));
  EXPECT_TRUE(segment_clear_of_blocked(1.5, 2.5, 5.5, 2.5, 0.49, Touch::Refused, 7, 7, blocked));
  // Through the wall: blocked under both rules, whatever the radius.
  EXPECT_FALSE(segment_clear_of_blocked(3.5, 0.5, 3.5, 6.5, 0.0, Touch::Refused, 7, 7, blocked));
  EXPECT_FALSE(segment_clear_of_blocked(3.5, 0.5, 3.5, 6.5, 0.1, Touch::Allowed, 7, 7, blocked));

  const Blob map = robot_map_of(g);
  EXPECT_TRUE(robot::segment_clear(map, MapGeometry::of(g), 1.5, 2.5, 5.5, 2.5, 0.5));
  EXPECT_FALSE(ClearanceField(BlockedGrid::from_occupancy(g), false).segment_clear(1.5, 2.5, 5.5, 2.5, 0.5));
}

TEST(Geometry, InflationDiscWorkedOutByHand) {
  // Radius 1: the 3 × 3 block (a diagonal neighbour's square is 0.5·√2 from the centre).
  EXPECT_EQ(inflation_disc(1.0).size(), 9u);
  // Radius 1.5: also the four cells two away in a line, exactly 1.5 away (inclusive); not (1, 2) at √2.5.
  const auto disc = inflation_disc(1.5);
  EXPECT_EQ(disc.size(), 13u);
  EXPECT_NE(std::find(disc.begin(), disc.end(), Cell{0, 2}), disc.end());
  EXPECT_EQ(std::find(disc.begin(), disc.end(), Cell{1, 2}), disc.end());
  EXPECT_TRUE(inflation_disc(-1.0).empty());
}

// Python's maps counted a centre exactly `radius` away as free, the C++ planners as blocked: the
// planners' rule is kept (it is the configuration space every robot has planned in).
TEST(Geometry, InflateIncludesTheTieAndTheEdge) {
  const BlockedGrid walls = BlockedGrid::from_occupancy(one_wall());
  const BlockedGrid in = inflate(walls, 1.5, /*outside_blocked=*/false);
  EXPECT_TRUE(in.blocked({3, 5}));   // centre (5.5, 3.5), 1.5 from the square
  EXPECT_FALSE(in.blocked({4, 5}));  // √(1.5² + 0.5²)
  EXPECT_FALSE(in.blocked({0, 0}));
  EXPECT_EQ(in.blocked_count(), 13u);
  const BlockedGrid edged = inflate(walls, 0.5, true);
  EXPECT_TRUE(edged.blocked({0, 3}));   // centre 0.5 from the bottom edge
  EXPECT_FALSE(edged.blocked({1, 1}));  // 1.5 from the edges, 1.5·√2 from the wall
  EXPECT_EQ(edged.blocked_count(), 24u + 5u);  // the outer ring, and the wall with its 4 side neighbours (0.5 away)
}

// The copies differed for a negative radius too: C++ inflated to nothing (the walls vanished from
// the configuration space), Python kept the walls. Walls are kept: no radius lets a robot into one.
TEST(Geometry, NegativeRadiusKeepsTheWalls) {
  const BlockedGrid walls = BlockedGrid::from_occupancy(one_wall());
  const BlockedGrid in = inflate(walls, -0.5, false);
  EXPECT_EQ(in.blocked_count(), 1u);
  EXPECT_TRUE(in.blocked({3, 3}));
}
