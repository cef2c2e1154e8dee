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

}  // namespace vwg::geometry
