#include "vwg/robot/avoidance.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "vwg/error.hpp"
#include "vwg/text.hpp"

namespace vwg::robot {

using geometry::Pose2;
using geometry::wrap_angle;

void check_settings(const AvoidanceSettings& s, const std::string& owner) {
  const auto fail = [&](const char* field, const std::string& what) { throw SchemaError(owner + "." + field, what); };
  const std::pair<const char*, double> positive[] = {{"horizon", s.horizon}, {"heading_time", s.heading_time}, {"step", s.step}};
  for (const auto& [name, v] : positive) {
    if (!std::isfinite(v) || v <= 0) fail(name, "expected a finite number > 0, got " + format_real(v));
  }
  const std::pair<const char*, double> non_negative[] = {{"margin", s.margin}, {"wall_lookahead", s.wall_lookahead}};
  for (const auto& [name, v] : non_negative) {
    if (!std::isfinite(v) || v < 0) fail(name, "expected a finite number >= 0, got " + format_real(v));
  }
}

platform::Velocity steer(const SteerInput& in, const AvoidanceSettings& s) {
  const double c = std::cos(in.pose.theta), sn = std::sin(in.pose.theta);
  const double preferred = std::clamp(in.preferred_speed, 0.0, in.limits.max_speed);
  const orca::Agent agent{{in.pose.x, in.pose.y}, {in.speed * c, in.speed * sn}, in.radius + s.margin, in.limits.max_speed};
  const orca::Vec2 want{preferred * std::cos(in.preferred_heading), preferred * std::sin(in.preferred_heading)};
  const orca::Vec2 v = orca::new_velocity(agent, in.neighbours, want, s.horizon, s.step);
  const double magnitude = std::hypot(v.x, v.y);
  const auto turn_toward = [&](double heading) {
    const double error = wrap_angle(heading - in.pose.theta);
    return std::clamp(error / s.heading_time, -in.limits.max_turn_rate, in.limits.max_turn_rate);
  };
  // Below a thousandth of the speed limit the direction means nothing: face the way to go, on the spot.
  if (magnitude < 1e-3 * in.limits.max_speed) return {0.0, turn_toward(in.preferred_heading)};
  const double heading = std::atan2(v.y, v.x);
  const double along = std::cos(wrap_angle(heading - in.pose.theta));
  return {std::min(magnitude * std::max(0.0, along), in.limits.max_speed), turn_toward(heading)};
}

NeighbourGenerator::NeighbourGenerator(std::shared_ptr<platform::RobotPlatform> platform,
                                       std::shared_ptr<const platform::ScanSource> scan,
                                       platform::NeighbourSettings settings, const Alphabet& alphabet,
                                       const std::string& event)
    : platform_(std::move(platform)), scan_(std::move(scan)), settings_(settings), event_(alphabet.event_type_id(event)),
      robot_(scan_ ? scan_->scan_robot() : 0), tracker_(settings) {
  if (!platform_) throw Error("NeighbourGenerator: no platform");
  if (!scan_) throw Error("NeighbourGenerator: no laser");
  platform::check_settings(settings_, "neighbours");
  require_fields(alphabet, event_, {{"x", ValueKind::Real}, {"y", ValueKind::Real}, {"vx", ValueKind::Real},
                                    {"vy", ValueKind::Real}, {"radius", ValueKind::Real}});
  (void)platform_->robot(robot_);  // throws if the platform has no such robot
}

void NeighbourGenerator::reset(std::uint64_t) {
  tracker_ = platform::NeighbourTracker(settings_);
  scanned_ = false;
}

void NeighbourGenerator::generate(const FrameInfo& frame, EventList& out) {
  const platform::RobotState* robot = platform_->find_robot(robot_);
  if (robot == nullptr) {  // out of the string: no body, no scans; tracks start afresh if it comes back
    if (scanned_) reset(0);
    return;
  }
  const Pose2 pose = robot->odometry;  // a copy, read at once
  if (scanned_) tracker_.update(scan_->last_scan(), scan_pose_, scan_time_);
  scanned_ = true;
  scan_pose_ = pose;
  scan_time_ = frame.time;
  const auto& tracks = tracker_.neighbours();
  if (tracks.empty()) return;
  thread_local std::vector<double> x, y, vx, vy, radius;
  for (auto* column : {&x, &y, &vx, &vy, &radius}) column->clear();
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  for (const platform::Neighbour& t : tracks) {
    const double ahead = frame.time - t.seen;
    const double dx = t.x + t.vx * ahead - pose.x, dy = t.y + t.vy * ahead - pose.y;
    x.push_back(c * dx + s * dy);
    y.push_back(-s * dx + c * dy);
    vx.push_back(c * t.vx + s * t.vy);
    vy.push_back(-s * t.vx + c * t.vy);
    radius.push_back(t.radius);
  }
  const std::span<const double> columns[] = {x, y, vx, vy, radius};
  out.emit_columns(event_, columns, robot_);
}

void NeighbourGenerator::save_state(StateWriter& out) const {
  out.boolean(scanned_);
  out.f64(scan_pose_.x), out.f64(scan_pose_.y), out.f64(scan_pose_.theta), out.f64(scan_time_);
  tracker_.save(out);
}

void NeighbourGenerator::load_state(StateReader& in) {
  const bool scanned = in.boolean();
  Pose2 pose;
  pose.x = in.f64(), pose.y = in.f64(), pose.theta = in.f64();
  const double time = in.f64();
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.theta) || !std::isfinite(time)) {
    in.fail("a pose or time that is not finite");
  }
  platform::NeighbourTracker tracker(settings_);
  tracker.load(in);
  in.end();
  scanned_ = scanned, scan_pose_ = pose, scan_time_ = time;
  tracker_ = std::move(tracker);
}

}  // namespace vwg::robot
