#include "vwg/sim/laser.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "vwg/error.hpp"
#include "vwg/text.hpp"
#include "vwg/geometry/pose.hpp"
#include "vwg/sim/raycast.hpp"

namespace vwg::sim {

BeamLayout beam_layout(const LaserSpec& spec) {
  if (spec.fov >= 2 * M_PI - 1e-9) return {-M_PI, 2 * M_PI / spec.beams};
  if (spec.beams == 1) return {0.0, 0.0};
  return {-spec.fov / 2, spec.fov / (spec.beams - 1)};
}

std::vector<double> beam_angles(const LaserSpec& spec) {
  const BeamLayout layout = beam_layout(spec);
  std::vector<double> angles(static_cast<std::size_t>(std::max(spec.beams, 0)));
  // As a LaserScan's reader computes them (angle_min + i·angle_increment), bit for bit.
  for (std::size_t i = 0; i < angles.size(); ++i) angles[i] = layout.angle_min + static_cast<double>(i) * layout.increment;
  return angles;
}

void check_settings(const LaserSpec& spec, const std::string& owner) {
  if (spec.beams < 1 || spec.beams > 100000) throw SchemaError(owner + ".beams", "expected 1 to 100000 beams, got " + std::to_string(spec.beams));
  if (!std::isfinite(spec.fov) || spec.fov <= 0 || spec.fov > 2 * M_PI + 1e-9) {
    throw SchemaError(owner + ".fov", "expected a field of view in (0, 2π] radians, got " + format_real(spec.fov));
  }
  if (!std::isfinite(spec.min_range) || spec.min_range < 0) throw SchemaError(owner + ".min_range", "expected a finite range >= 0, metres");
  if (!std::isfinite(spec.max_range) || spec.max_range <= spec.min_range) {
    throw SchemaError(owner + ".max_range", "expected a finite range > min_range (" + format_real(spec.min_range) + "), metres");
  }
  if (!std::isfinite(spec.noise) || spec.noise < 0) {
    throw SchemaError(owner + ".noise", "expected a finite standard deviation >= 0, metres, got " + format_real(spec.noise));
  }
}

double approximate_atan2(double y, double x) {
  // Abramowitz & Stegun 4.4.49: arctan a on [-1, 1] within 1e-5 by an odd polynomial of degree 9
  // (1.15e-5 measured, with its coefficients rounded to 7 digits);
  // the other octants by symmetry.
  const double ax = std::abs(x), ay = std::abs(y);
  const double big = std::max(ax, ay);
  if (!(big > 0.0)) return 0.0;
  const double a = std::min(ax, ay) / big, z = a * a;
  double r = a * (0.9998660 + z * (-0.3302995 + z * (0.1801410 + z * (-0.0851330 + z * 0.0208351))));
  if (ay > ax) r = M_PI_2 - r;
  if (x < 0) r = M_PI - r;
  return y < 0 ? -r : r;
}

RangeScanner::RangeScanner(std::shared_ptr<const GridRaycaster> raycaster, std::shared_ptr<const PhysicsWorld> world)
    : raycaster_(std::move(raycaster)), world_(std::move(world)) {
  if (!raycaster_ || !world_) throw Error("RangeScanner: needs a raycaster and a physics world");
}

void RangeScanner::scan(int self, const Pose2& pose, std::span<const double> angles, double max_range,
                        std::span<float> out) const {
  raycaster_->scan(pose, angles, max_range, out);
  // Other robots are discs: the nearest intersection in front of the sensor, if nearer. Only the
  // beams within the angle the disc subtends are tested (with the same arithmetic as a full test),
  // so a crowd costs a few beams per neighbour instead of every beam (the angles are sorted, as
  // LaserGenerator's are; otherwise every beam is tested).
  const bool windowed = std::is_sorted(angles.begin(), angles.end()) && !angles.empty() &&
                        angles.front() >= -3 * M_PI && angles.back() <= 3 * M_PI;
  // Beams spanning at most half a turn all lie in the half-plane ahead of their middle direction:
  // a robot wholly behind that line (its disc, with a margin well above rounding) meets none.
  const bool half_plane = windowed && angles.back() - angles.front() <= M_PI;
  const double mid = pose.theta + 0.5 * (windowed ? angles.front() + angles.back() : 0.0);
  const double mid_x = std::cos(mid), mid_y = std::sin(mid);
  // Kept from scan to scan, and named once here (a thread_local used in the loops below was
  // looked up again, __tls_get_addr, after every call).
  thread_local struct {
    std::vector<double> turned, dir_x, dir_y;
  } scratch;
  auto& [turned, dir_x, dir_y] = scratch;
  bool have_directions = false;
  // The first beam whose angle is >= a (std::lower_bound's answer), found from the mean spacing
  // and settled by comparisons: one or two steps for a laser's evenly spaced beams, where a
  // binary search was a fifth of this function (its branches mispredicted).
  const std::size_t n = angles.size();
  const double spacing = n > 1 ? (angles.back() - angles.front()) / static_cast<double>(n - 1) : 0.0;
  auto first_at_or_above = [&](double a) {
    const double guess = spacing > 0.0 ? (a - angles.front()) / spacing : 0.0;
    std::size_t i = !(guess > 0.0) ? 0 : guess >= static_cast<double>(n) ? n : static_cast<std::size_t>(guess);
    while (i > 0 && angles[i - 1] >= a) --i;
    while (i < n && angles[i] < a) ++i;
    return i;
  };
  // Visits the beams whose angle (relative to the sensor) lies within `half` of `bearing` (in
  // [-π, π]), in each of its turns the angles reach, until visit(i) returns false; returns
  // whether it went through them all.
  auto beams_within = [&](double bearing, double half, auto&& visit) {
    for (const double turn : {-2 * M_PI, 0.0, 2 * M_PI}) {
      const double lo = bearing + turn - half, hi = bearing + turn + half;
      if (hi < angles.front() || lo > angles.back()) continue;
      std::size_t i = first_at_or_above(lo);
      for (; i < angles.size() && angles[i] <= hi; ++i)
        if (!visit(i)) return false;
    }
    return true;
  };
  // A robot changes a range only where it is nearer than the walls: none farther than the
  // farthest wall range counts (ranges only shrink from here). In rooms that is often far less
  // than max_range. Unsorted angles (the tests' reference) keep max_range.
  double farthest = max_range;
  if (windowed) farthest = std::min(max_range, static_cast<double>(*std::max_element(out.begin(), out.end())));
  const std::vector<PhysicsWorld::Disc>& discs = world_->discs();
  const DiscIndex& index = world_->disc_index();
  const double query = (farthest + index.max_radius()) * (1 + 1e-6) + 1e-6;
  // The squares to visit: those within `query` of the sensor on each axis; for a scan of at most
  // half a turn, only the side of the half-plane test below (a disc kept by it has c·m >= -ρ and
  // |c| <= query, so c_x <= ρ + query·|m_y| when m_x < 0, and likewise on each side).
  double x_lo = -query, x_hi = query, y_lo = -query, y_hi = query;
  if (half_plane) {
    const double rho = index.max_radius() * (1 + 1e-6) + 1e-6 * (query + 1.0);
    if (mid_x < 0) x_hi = std::min(query, rho + query * std::abs(mid_y));
    if (mid_x > 0) x_lo = -std::min(query, rho + query * std::abs(mid_y));
    if (mid_y < 0) y_hi = std::min(query, rho + query * std::abs(mid_x));
    if (mid_y > 0) y_lo = -std::min(query, rho + query * std::abs(mid_x));
  }
  index.within(pose.x + x_lo, pose.x + x_hi, pose.y + y_lo, pose.y + y_hi, [&](std::uint32_t k) {
    const PhysicsWorld::Disc& other = discs[k];
    if (other.id == self) return;
    const double cx = other.x - pose.x, cy = other.y - pose.y;
    // Far robots first by squared distance (a crowd is mostly far), with a margin well above
    // rounding, so that every robot the exact test below keeps gets to it.
    const double reach = farthest + other.radius;
    const double squared = cx * cx + cy * cy;
    if (squared > reach * reach * (1 + 1e-9) + 1e-9) return;
    if (half_plane && cx * mid_x + cy * mid_y < -(other.radius + 1e-9 * (std::abs(cx) + std::abs(cy) + 1.0))) return;
    const double r2 = other.radius * other.radius;
    auto test = [&](std::size_t i) {
      // The beams' directions are worked out once per scan, all together (4 at a time), when a
      // robot first needs them. Their sine and cosine are the raycaster's own (the same bits on
      // every machine, where libm's may differ between its FMA and plain code).
      if (!have_directions) {
        turned.resize(n), dir_x.resize(n), dir_y.resize(n);
        for (std::size_t j = 0; j < n; ++j) turned[j] = pose.theta + angles[j];
        beam_directions(turned, "avx2", dir_x, dir_y);
        have_directions = true;
      }
      const double dx = dir_x[i], dy = dir_y[i];
      const double along = cx * dx + cy * dy;
      const double across2 = cx * cx + cy * cy - along * along;
      if (across2 > r2) return;
      const double t = along - std::sqrt(r2 - across2);
      if (t >= 0.0 && t < out[i]) out[i] = static_cast<float>(t);
    };
    const double d = std::sqrt(squared);
    if (!windowed || !(d > 2 * other.radius)) {  // unsorted angles, or a robot close by: every beam
      for (std::size_t i = 0; i < n; ++i) test(i);
      return;
    }
    // The beams whose angle (relative to the sensor) lies within the disc's half-angle asin(r / d)
    // of its bearing, found from an approximate bearing and widened by far more than its error
    // (tan(asin(r / d)) >= asin(r / d); 1e-4 >> 1.2e-5 + rounding): every beam that can meet the
    // disc, and a few that cannot (the exact test turns them down).
    const double half = other.radius / std::sqrt(squared - r2) + 1e-4;
    double bearing = approximate_atan2(cy, cx) - pose.theta;
    if (!(std::abs(bearing) < 64.0)) bearing = std::remainder(bearing, 2 * M_PI);
    while (bearing > M_PI) bearing -= 2 * M_PI;
    while (bearing < -M_PI) bearing += 2 * M_PI;
    // Only the beams that stop beyond the disc's nearest point are tested: the exact test would
    // change no other range (at a wall, or at a robot tested before). In a building most robots
    // within reach are behind walls, and none of their beams is tested. No point of the disc is
    // nearer than d - radius; the margin covers the exact test's rounding.
    const double nearest = (d - other.radius) * (1 - 1e-9) - 1e-9;
    beams_within(bearing, half, [&](std::size_t i) {
      if (static_cast<double>(out[i]) > nearest) test(i);
      return true;
    });
  });
}

LaserGenerator::LaserGenerator(std::shared_ptr<const RangeScanner> scanner, int robot, LaserSpec spec,
                               const Alphabet& alphabet, const std::string& event)
    : scanner_(std::move(scanner)), robot_(robot), spec_(spec), event_(alphabet.event_type_id(event)),
      angles_(beam_angles(spec_)), ranges_(angles_.size(), static_cast<float>(spec_.max_range)) {
  check_settings(spec_, "laser");
  require_fields(alphabet, event_, {{"dist", ValueKind::Real}, {"angle", ValueKind::Real}});
  (void)scanner_->world().robot(robot_);  // throws if there is no such robot
}

void LaserGenerator::save_state(StateWriter& out) const {
  rng_.save(out);
  out.pods(ranges_);
}

void LaserGenerator::load_state(StateReader& in) {
  rng_.load(in);
  std::vector<float> ranges = in.pods<float>();
  if (ranges.size() != angles_.size()) {
    in.fail("expected the last scan's " + std::to_string(angles_.size()) + " ranges, found " + std::to_string(ranges.size()));
  }
  for (const float r : ranges) {
    if (!(r >= 0.0f && r <= static_cast<float>(spec_.max_range))) in.fail("a range outside [0, max_range] in the last scan");
  }
  in.end();
  ranges_ = std::move(ranges);
}

void LaserGenerator::generate(const FrameInfo&, EventList& out) {
  const RobotState* robot = scanner_->world().find_robot(robot_);
  if (robot == nullptr) return;  // out of the string: no body, no scan
  const Pose2 pose = robot->pose;
  scanner_->scan(robot_, pose, angles_, spec_.max_range, ranges_);
  // The bounds as floats. The scan writes max_range as a float (no return): a max_range that
  // float32 rounds down (3.3) must still read as no obstacle.
  const auto low = static_cast<float>(spec_.min_range), high = static_cast<float>(spec_.max_range);
  if (spec_.noise > 0.0) {
    for (std::size_t i = 0; i < ranges_.size(); ++i) {
      if (ranges_[i] >= high) continue;  // no return: nothing to blur
      // A noisy reading in single precision, as a real laser's scan (sensor_msgs/LaserScan)
      // carries it: the events of the simulated and the real robot alike, and a frame log a third
      // smaller. Clamped to the float32 values within [min_range, max_range): a hit stays a hit
      // (a reading of max_range is no return, platform/laser_scan.hpp).
      const double noisy = ranges_[i] + rng_.normal(0.0, spec_.noise);
      float reading = static_cast<float>(std::clamp(noisy, spec_.min_range, spec_.max_range));
      if (reading < spec_.min_range) reading = std::nextafter(low, high);
      if (reading >= high) reading = std::nextafter(high, low);
      ranges_[i] = reading;
    }
  }
  // What a real robot's LaserScan goes through (Table II: an event "if obstacle").
  events_.clear();
  platform::laser_events(ranges_, angles_, spec_.min_range, spec_.max_range, events_);
  events_.emit(out, event_, robot_);
}

}  // namespace vwg::sim
