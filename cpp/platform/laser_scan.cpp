#include "vwg/platform/laser_scan.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "vwg/error.hpp"
#include "vwg/text.hpp"

namespace vwg::platform {

namespace {

void check_limits(double range_min, double range_max) {
  if (!std::isfinite(range_min) || range_min < 0)
    throw SchemaError("range_min", "expected a finite range >= 0, metres, got " + format_real(range_min));
  if (!std::isfinite(range_max) || range_max <= range_min)
    throw SchemaError("range_max", "expected a finite range > range_min (" + format_real(range_min) + "), metres, got " +
                                       format_real(range_max));
}

/// The rule of laser_scan.hpp for beam i, its angle given by angle_of(i).
template <class AngleOf>
void add_obstacles(std::span<const float> ranges, double range_min, double range_max, ScanEvents& out,
                   AngleOf&& angle_of) {
  // range_max as float32, as the ranges are: a range_max that float32 rounds down (3.3) must still
  // read as no return when a sensor reports it. Beyond float32's range, only +Inf is no return.
  const float high = range_max < static_cast<double>(std::numeric_limits<float>::max())
                         ? static_cast<float>(range_max)
                         : std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const float r = ranges[i];
    if (r >= high) continue;  // no return (+Inf, range_max): no obstacle
    if (r == -std::numeric_limits<float>::infinity()) {
      out.add(range_min, angle_of(i));  // nearer than range_min
    } else if (r >= range_min) {       // false for NaN: nothing is known
      out.add(r, angle_of(i));
    }
  }
}

}  // namespace

void laser_events(std::span<const float> ranges, std::span<const double> angles, double range_min, double range_max,
                  ScanEvents& out) {
  if (ranges.size() != angles.size())
    throw Error("laser_events: " + std::to_string(ranges.size()) + " ranges for " + std::to_string(angles.size()) +
                " angles");
  check_limits(range_min, range_max);
  add_obstacles(ranges, range_min, range_max, out, [&](std::size_t i) { return angles[i]; });
}

void laser_events(std::span<const float> ranges, double angle_min, double angle_increment, double range_min,
                  double range_max, ScanEvents& out) {
  if (!std::isfinite(angle_min)) throw SchemaError("angle_min", "expected a finite angle, radians, got " + format_real(angle_min));
  if (!std::isfinite(angle_increment))
    throw SchemaError("angle_increment", "expected a finite angle, radians, got " + format_real(angle_increment));
  check_limits(range_min, range_max);
  add_obstacles(ranges, range_min, range_max, out,
                [&](std::size_t i) { return angle_min + static_cast<double>(i) * angle_increment; });
}

}  // namespace vwg::platform
