// The motion follower shared by the simulator and the real robots' links, on an ideal robot (the
// pose integrates the commanded velocities exactly), against values worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include "vwg/error.hpp"
#include "vwg/platform/motion_follower.hpp"

using namespace vwg::platform;
using vwg::geometry::Pose2;

namespace {

/// Ticks until the follower is idle and at rest (or `max_ticks`), moving an ideal robot.
int follow(MotionFollower& f, Pose2& pose, double dt, double& peak_speed, double& peak_change, int max_ticks = 10000) {
  Velocity last{};
  peak_speed = peak_change = 0.0;
  for (int k = 1; k <= max_ticks; ++k) {
    const Velocity v = f.tick(pose, dt);
    peak_speed = std::max(peak_speed, std::abs(v.speed));
    peak_change = std::max(peak_change, std::abs(v.speed - last.speed) / dt);
    last = v;
    pose.theta += v.turn_rate * dt;
    pose.x += v.speed * dt * std::cos(pose.theta);
    pose.y += v.speed * dt * std::sin(pose.theta);
    f.settle(pose);
    if (!f.busy() && v.speed == 0.0 && v.turn_rate == 0.0) return k;
  }
  return -1;
}

bool is_float(double v) { return static_cast<double>(static_cast<float>(v)) == v; }

}  // namespace

TEST(MotionFollower, DrivesTwoMetresOnATrapezoidWithinTheLimits) {
  // 0.5 m/s, 1 m/s²: 0.5 s up (0.125 m), 1.75 m at full speed (3.5 s), 0.5 s down (0.125 m):
  // 4.5 s for 2 m, ±1 tick of 10 ms for the sampling.
  RobotLimits limits;  // 0.5 m/s, 1.5 rad/s, 1 m/s², 4 rad/s²
  MotionFollower f(limits);
  f.command({{MotionStep::Drive, 2.0}});
  Pose2 pose{1.0, 2.0, 0.0};
  double peak = 0, change = 0;
  const int ticks = follow(f, pose, 0.01, peak, change);
  EXPECT_NEAR(ticks * 0.01, 4.5, 0.03);
  EXPECT_NEAR(pose.x, 3.0, 1e-3);
  EXPECT_NEAR(pose.y, 2.0, 1e-12);
  EXPECT_LE(peak, 0.5 + 1e-12);
  EXPECT_LE(change, 1.0 + 1e-9);  // every change of speed within the acceleration, the last one too
}

TEST(MotionFollower, TurnsHalfACircleAcrossTheWrapOnAWrappedPose) {
  MotionFollower f(RobotLimits{});
  f.command({{MotionStep::Turn, std::numbers::pi}});
  double turned = 0.0, yaw = 3.0;
  for (int k = 0; k < 1000 && f.busy(); ++k) {
    const Velocity v = f.tick({0.0, 0.0, std::remainder(yaw, 2 * std::numbers::pi)}, 0.05);
    yaw += v.turn_rate * 0.05;
    turned += v.turn_rate * 0.05;
    f.settle({0.0, 0.0, std::remainder(yaw, 2 * std::numbers::pi)});
  }
  EXPECT_FALSE(f.busy());
  EXPECT_NEAR(turned, std::numbers::pi, 0.01);
}

TEST(MotionFollower, ARobotThatLagsIsDrivenOnUntilItIsThere) {
  // A robot that does only half of what it is told each tick: the step is not over when its
  // time is, but when the pose says it got there (within the tolerance).
  MotionFollower f(RobotLimits{}, 0.01);
  f.command({{MotionStep::Drive, 1.0}});
  Pose2 pose{};
  for (int k = 0; k < 5000 && f.busy(); ++k) {
    const Velocity v = f.tick(pose, 0.05);
    pose.x += 0.5 * v.speed * 0.05;
    f.settle(pose);
  }
  EXPECT_FALSE(f.busy());
  EXPECT_NEAR(pose.x, 1.0, 0.01);
}

TEST(MotionFollower, HaltKeepsThePlanAndStopDropsIt) {
  MotionFollower f(RobotLimits{});
  f.command({{MotionStep::Drive, 1.0}});
  Pose2 pose{};
  (void)f.tick(pose, 0.1);
  f.halt();
  EXPECT_TRUE(f.busy());
  EXPECT_EQ(f.velocity().speed, 0.0);
  EXPECT_NEAR(f.tick(pose, 0.1).speed, 0.1, 1e-12);  // from rest again: 1 m/s² for 0.1 s
  f.stop();
  EXPECT_FALSE(f.busy());
  EXPECT_EQ(f.velocity().speed, 0.0);
  EXPECT_THROW(f.command({{MotionStep::Drive, NAN}}), vwg::SchemaError);
}

TEST(QuantizePose, RoundsEachCoordinateToFloatAndWrapsTheAngle) {
  // 21.0759353637695 is no float; the float nearest is 21.075935363769531 (2^-19 apart at 16..32).
  const Pose2 q = quantize_pose({21.0759353637695, -9.5000001, 4.0});
  EXPECT_TRUE(is_float(q.x) && is_float(q.y) && is_float(q.theta));
  EXPECT_EQ(q.x, static_cast<double>(21.0759353637695f));
  EXPECT_EQ(q.y, static_cast<double>(-9.5000001f));
  EXPECT_EQ(q.theta, static_cast<double>(static_cast<float>(4.0 - 2 * std::numbers::pi)));
  // float(π) is past π: it comes back as the float just inside -π, from either side of the wrap.
  EXPECT_EQ(quantize_pose({0, 0, std::numbers::pi}).theta, quantize_pose({0, 0, static_cast<float>(std::numbers::pi)}).theta);
  EXPECT_GE(quantize_pose({0, 0, std::numbers::pi}).theta, -std::numbers::pi);
}
