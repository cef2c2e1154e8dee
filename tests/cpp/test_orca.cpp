// ORCA (vwg/robot/orca.hpp) against hand-worked two-agent cases: radius 0.2 each, horizon 2 s. The expected
// velocities were worked out from the paper's construction (the truncated cone, u, the half-plane through
// v_A + u/2) and checked with a second, independent computation.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "vwg/robot/orca.hpp"

namespace orca = vwg::robot::orca;

namespace {

orca::Vec2 avoid(orca::Vec2 p, orca::Vec2 v, double max_speed, std::vector<orca::Neighbour> others) {
  return orca::new_velocity(orca::Agent{p, v, 0.2, max_speed}, others, v, 2.0, 0.1);
}

}  // namespace

TEST(Orca, HeadOnBothSwerveToTheirRight) {
  // A at the origin going +x at 1 m/s, B 2 m ahead coming back: the relative velocity (2, 0) points at the cone's
  // axis, the tie takes the right leg; each takes half of u = (−0.08, −0.391918).
  const orca::Vec2 a = avoid({0, 0}, {1, 0}, 2.0, {{{2, 0}, {-1, 0}, 0.2, 0.5}});
  const orca::Vec2 b = avoid({2, 0}, {-1, 0}, 2.0, {{{0, 0}, {1, 0}, 0.2, 0.5}});
  EXPECT_NEAR(a.x, 0.96, 1e-6);
  EXPECT_NEAR(a.y, -0.195959, 1e-6);
  EXPECT_NEAR(b.x, -0.96, 1e-6);
  EXPECT_NEAR(b.y, 0.195959, 1e-6);
}

TEST(Orca, CrossingAtRightAngles) {
  // A from (−1, 0) going +x, B from (0, −1) going +y: they would meet at the origin at t = 1.
  const orca::Vec2 a = avoid({-1, 0}, {1, 0}, 2.0, {{{0, -1}, {0, 1}, 0.2, 0.5}});
  EXPECT_NEAR(a.x, 0.824353, 1e-6);
  EXPECT_NEAR(a.y, -0.095647, 1e-6);
  // B's half-plane point (0.175647, 1.095647) is beyond a speed of 1: the nearest allowed velocity on the disc.
  const orca::Vec2 b = avoid({0, -1}, {0, 1}, 1.0, {{{-1, 0}, {1, 0}, 0.2, 0.5}});
  EXPECT_NEAR(b.x, 0.244219, 1e-6);
  EXPECT_NEAR(b.y, 0.969720, 1e-6);
  EXPECT_NEAR(std::hypot(b.x, b.y), 1.0, 1e-9);
}

TEST(Orca, AStaticObstacleTakesNoShareOfTheAvoiding) {
  // A disc of radius 0.2 at (1, 0) that does not move: the robot takes all of u.
  const orca::Vec2 a = avoid({0, 0}, {1, 0}, 2.0, {{{1, 0}, {0, 0}, 0.2, 1.0}});
  EXPECT_NEAR(a.x, 0.84, 1e-6);
  EXPECT_NEAR(a.y, -0.366606, 1e-6);
}

TEST(Orca, ANeighbourBeyondTheHorizonChangesNothing) {
  const orca::Vec2 a = avoid({0, 0}, {1, 0}, 2.0, {{{10, 0}, {-1, 0}, 0.2, 0.5}});
  EXPECT_EQ(a.x, 1.0);
  EXPECT_EQ(a.y, 0.0);
}

TEST(Orca, WhenNothingIsAllowedTheLeastViolationIsTakenWithinTheSpeedLimit) {
  // Boxed in by four robots closing in from every side: no velocity satisfies all four half-planes.
  const std::vector<orca::Neighbour> around{{{0.5, 0}, {-1, 0}, 0.2, 0.5}, {{-0.5, 0}, {1, 0}, 0.2, 0.5},
                                            {{0, 0.5}, {0, -1}, 0.2, 0.5}, {{0, -0.5}, {0, 1}, 0.2, 0.5}};
  const orca::Vec2 v = orca::new_velocity(orca::Agent{{0, 0}, {0, 0}, 0.2, 0.5}, around, {0.5, 0}, 2.0, 0.1);
  EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y));
  EXPECT_LE(std::hypot(v.x, v.y), 0.5 + 1e-12);
  // Symmetric: staying put violates each half-plane equally, and nothing does better.
  EXPECT_NEAR(v.x, 0.0, 1e-9);
  EXPECT_NEAR(v.y, 0.0, 1e-9);
  const orca::Vec2 again = orca::new_velocity(orca::Agent{{0, 0}, {0, 0}, 0.2, 0.5}, around, {0.5, 0}, 2.0, 0.1);
  EXPECT_EQ(v.x, again.x);  // the same bits on every call
  EXPECT_EQ(v.y, again.y);
}

TEST(Orca, OverlappingRobotsPartWithinOneStep) {
  // 0.3 m apart with radii 0.2: the half-plane asks for the overlap of 0.1 m gone within the 0.1 s step.
  const orca::Line line = orca::half_plane(orca::Agent{{0, 0}, {0, 0}, 0.2, 1.0}, {{0.3, 0}, {0, 0}, 0.2, 0.5}, 2.0, 0.1);
  // u = (R/step − |w|)·ŵ with w = −p/step = (−3, 0): u = (4 − 3)·(−1, 0); A takes half.
  EXPECT_NEAR(line.point.x, -0.5, 1e-12);
  EXPECT_NEAR(line.point.y, 0.0, 1e-12);
}
