// Poses in the plane and the one angle wrap every part of vwg uses (robots, planners, simulator).
#pragma once

#include <cmath>
#include <numbers>

namespace vwg::geometry {

/// A pose in the plane: position in metres, heading in radians (counter-clockwise from +x).
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
};

/// The angle equal to `a` modulo 2π in [-π, π] (IEEE remainder: exact, no drift from repeated
/// subtraction, and bit for bit what robot runs were recorded with).
inline double wrap_angle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

/// A point as a robot's sensor reports it: metres away, radians from the heading (left positive).
struct Polar {
  double dist = 0.0;
  double bearing = 0.0;
};

/// A point seen at `seen` from `from` (where the robot was, in its frame now), as seen from where the
/// robot is now. A real robot's image or scan arrives after it was taken, while the robot moves on.
/// From (0, 0, 0) the point is returned as it is, bit for bit (a simulated sensor reads at the frame).
inline Polar seen_from(const Pose2& from, const Polar& seen) {
  if (from.x == 0.0 && from.y == 0.0 && from.theta == 0.0) return seen;
  const double ahead = seen.dist * std::cos(seen.bearing), left = seen.dist * std::sin(seen.bearing);
  const double c = std::cos(from.theta), s = std::sin(from.theta);
  const double x = from.x + c * ahead - s * left, y = from.y + s * ahead + c * left;
  return {std::hypot(x, y), std::atan2(y, x)};
}

}  // namespace vwg::geometry
