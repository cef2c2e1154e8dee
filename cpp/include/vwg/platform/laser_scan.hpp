// A laser scan to gLaser's events (paper Table II: eLaser<dist, angle> "if obstacle"): the one rule
// every robot's laser goes through, the simulator's (sim::LaserGenerator) and a real robot's
// sensor_msgs/LaserScan alike, so that the same scan gives the same events on either.
//
// The rule, reading by reading (REP 117, with one choice of vwg's at range_max):
// - a reading in [range_min, range_max) is an obstacle at that distance;
// - a reading >= range_max, +Inf included, is no return: no obstacle. REP 117 would count a reading
//   of exactly range_max as a measurement, but many drivers (and vwg's simulator) report a beam
//   that met nothing as range_max: taken as a wall it would paint phantom walls at the edge of the
//   range. Ranges are float32, as a LaserScan carries them, and range_max is compared as float32
//   too, so that a range_max float32 rounds down (3.3) still reads as no return;
// - -Inf is an obstacle nearer than range_min: taken at range_min;
// - NaN (rosbridge sends null for NaN and both infinities: nothing is known) and a finite reading
//   below range_min: no measurement, no event.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "vwg/alphabet.hpp"
#include "vwg/event.hpp"

namespace vwg::platform {

/// A range sensor's events of one frame, `<event><to=robot, dist, angle>` a beam, gathered by
/// columns and emitted as one batch (EventList::emit_columns). Kept by a generator, so a frame
/// allocates nothing.
class ScanEvents {
 public:
  void clear() { dist_.clear(), angle_.clear(); }
  void add(double dist, double angle) { dist_.push_back(dist), angle_.push_back(angle); }
  std::size_t size() const { return dist_.size(); }
  std::span<const double> dist() const { return dist_; }
  std::span<const double> angle() const { return angle_; }
  void emit(EventList& out, EventTypeId event, int robot) const {
    const std::span<const double> columns[] = {dist_, angle_};
    out.emit_columns(event, columns, robot);
  }

 private:
  std::vector<double> dist_, angle_;
};

/// Adds to `out`, in beam order, (dist, angle) of each beam of the scan that met an obstacle, by
/// the rule above: ranges[i] is the reading of the beam at angles[i] (radians from the heading,
/// counter-clockwise). Throws vwg::Error if the spans' sizes differ, SchemaError naming range_min
/// or range_max unless 0 <= range_min < range_max, both finite.
void laser_events(std::span<const float> ranges, std::span<const double> angles, double range_min, double range_max,
                  ScanEvents& out);
/// The same for a LaserScan's layout: beam i at angle_min + i·angle_increment (computed so, as
/// sim::beam_angles computes the simulator's). SchemaError naming angle_min or angle_increment
/// unless finite.
void laser_events(std::span<const float> ranges, double angle_min, double angle_increment, double range_min,
                  double range_max, ScanEvents& out);

}  // namespace vwg::platform
