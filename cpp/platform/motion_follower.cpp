#include "vwg/platform/motion_follower.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "vwg/error.hpp"
#include "vwg/text.hpp"

namespace vwg::platform {

namespace {

double approach(double current, double target, double max_change) {
  if (target > current) return std::min(target, current + max_change);
  return std::max(target, current - max_change);
}

/// Speed for a trapezoidal profile: accelerate towards the limit, brake so as to stop at the end.
/// Braking is planned in ticks: from n·a·dt, slowing by a·dt per tick covers a·dt²·n(n+1)/2, so
/// the fastest speed that still stops within `remaining` is a·dt·n for the n that covers it (√(2ar)
/// as dt → 0). The tick that can reach the end covers exactly what remains, within the limits.
double profile_speed(double remaining, double current, double max_speed, double max_accel, double dt, bool& lands) {
  const double direction = remaining >= 0 ? 1.0 : -1.0;
  const double step = max_accel * dt;
  const double braking = step * (std::sqrt(1.0 + 8.0 * std::abs(remaining) / (step * dt)) - 1.0) / 2.0;
  const double target = direction * std::min(max_speed, braking);
  double speed = approach(current, target, max_accel * dt);
  lands = std::abs(remaining) <= std::abs(speed) * dt + 1e-12 || std::abs(remaining) < 1e-9;
  if (lands) speed = std::clamp(remaining / dt, current - step, current + step);
  return speed;
}

}  // namespace

MotionFollower::MotionFollower(RobotLimits limits, double tolerance) : limits_(limits), tolerance_(tolerance) {
  if (!std::isfinite(tolerance) || tolerance <= 0.0) {
    throw SchemaError("tolerance", "expected a finite distance > 0, got " + format_real(tolerance));
  }
}

void MotionFollower::command(const std::vector<MotionStep>& steps) {
  for (const MotionStep& s : steps) {
    if (!std::isfinite(s.amount)) throw SchemaError("command", "non-finite amount " + format_real(s.amount));
    if (!std::isfinite(s.rate)) throw SchemaError("command", "non-finite turn rate " + format_real(s.rate));
  }
  plan_.assign(steps.begin(), steps.end());
  active_ = false;
  lands_ = false;
  hold_ = {};
}

double MotionFollower::remaining(const geometry::Pose2& pose) {
  if (current_.kind == MotionStep::Turn) {
    turned_ += geometry::wrap_angle(pose.theta - last_theta_);
    last_theta_ = pose.theta;
    return current_.amount - turned_;
  }
  const double done = (pose.x - origin_.x) * std::cos(origin_.theta) + (pose.y - origin_.y) * std::sin(origin_.theta);
  return current_.amount - done;
}

void MotionFollower::settle(const geometry::Pose2& pose) {
  if (!active_ || !lands_) return;
  lands_ = false;
  if (std::abs(remaining(pose)) > tolerance_) return;  // it did not get there: go on from here
  active_ = false;  // what speed is left is braked within the limits by the next tick
}

Velocity MotionFollower::tick(const geometry::Pose2& pose, double dt) {
  settle(pose);
  while (!active_ && !plan_.empty()) {
    current_ = plan_.front();
    plan_.pop_front();
    if (current_.kind == MotionStep::Steer) {
      hold_ = {std::clamp(current_.amount, -limits_.max_speed, limits_.max_speed),
               std::clamp(current_.rate, -limits_.max_turn_rate, limits_.max_turn_rate)};
      continue;
    }
    hold_ = {};
    origin_ = pose;
    turned_ = 0.0;
    last_theta_ = pose.theta;
    active_ = std::abs(current_.amount) >= 1e-12;  // nothing to do
  }
  if (!active_) {  // idle: come to rest (or to the held velocity) within the acceleration limits
    velocity_.speed = approach(velocity_.speed, hold_.speed, limits_.max_accel * dt);
    velocity_.turn_rate = approach(velocity_.turn_rate, hold_.turn_rate, limits_.max_turn_accel * dt);
    return velocity_;
  }
  // The other velocity is brought to rest within its limit (a drive that ends a little fast, then a turn).
  const double left = remaining(pose);
  if (current_.kind == MotionStep::Turn) {
    velocity_.speed = approach(velocity_.speed, 0.0, limits_.max_accel * dt);
    velocity_.turn_rate = profile_speed(left, velocity_.turn_rate, limits_.max_turn_rate, limits_.max_turn_accel, dt, lands_);
  } else {
    velocity_.turn_rate = approach(velocity_.turn_rate, 0.0, limits_.max_turn_accel * dt);
    velocity_.speed = profile_speed(left, velocity_.speed, limits_.max_speed, limits_.max_accel, dt, lands_);
  }
  return velocity_;
}

void MotionFollower::stop() {
  plan_.clear();
  active_ = false;
  lands_ = false;
  hold_ = {};
  velocity_ = {};
}

namespace {

/// `v` rounded to float. Through a volatile float: GCC 12.2 at -O3 drops the rounding of two
/// neighbouring double→float→double conversions (its basic-block vectorizer turns them into one
/// plain copy), which the sim-vs-rosbridge equivalence test caught.
double to_float(double v) {
  volatile float f = static_cast<float>(v);
  return f;
}

}  // namespace

geometry::Pose2 quantize_pose(const geometry::Pose2& pose) {
  constexpr double kPi = std::numbers::pi;
  double theta = to_float(geometry::wrap_angle(pose.theta));
  // Rounding may carry ±π just past itself: wrap once more, so both ends give the same float.
  if (theta > kPi) theta = to_float(theta - 2 * kPi);
  if (theta < -kPi) theta = to_float(theta + 2 * kPi);
  return {to_float(pose.x), to_float(pose.y), theta};
}

}  // namespace vwg::platform
