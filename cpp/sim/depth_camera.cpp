#include "vwg/sim/depth_camera.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vwg/error.hpp"
#include "vwg/text.hpp"
#include "vwg/sim/view3d.hpp"

namespace vwg::sim {

namespace {
constexpr float kInvalid = std::numeric_limits<float>::quiet_NaN();
}

void check_settings(const DepthCameraSpec& s, const std::string& owner) {
  if (s.width < 1 || s.width > 8192) throw SchemaError(owner + ".width", "expected 1 to 8192 pixels, got " + std::to_string(s.width));
  if (s.height < 1 || s.height > 8192) throw SchemaError(owner + ".height", "expected 1 to 8192 pixels, got " + std::to_string(s.height));
  if (!std::isfinite(s.hfov) || s.hfov <= 0 || s.hfov >= M_PI) throw SchemaError(owner + ".hfov", "expected a field of view in (0, π)");
  if (!std::isfinite(s.min_range) || s.min_range < 0) throw SchemaError(owner + ".min_range", "expected a finite range >= 0, metres");
  if (!std::isfinite(s.max_range) || s.max_range <= s.min_range) {
    throw SchemaError(owner + ".min_range", "must be less than max_range (" + format_real(s.max_range) + ")");
  }
  if (!std::isfinite(s.mount_height) || s.mount_height <= 0) throw SchemaError(owner + ".mount_height", "expected a finite height > 0, metres");
  if (!std::isfinite(s.wall_height) || s.wall_height <= s.mount_height) {
    throw SchemaError(owner + ".wall_height", "expected a finite height above the camera's mount_height");
  }
  if (!std::isfinite(s.robot_height) || s.robot_height <= 0) throw SchemaError(owner + ".robot_height", "expected a finite height > 0, metres");
  if (!std::isfinite(s.noise_a) || s.noise_a < 0) throw SchemaError(owner + ".noise_a", "expected a finite coefficient >= 0");
  if (!std::isfinite(s.noise_b) || s.noise_b < 0) throw SchemaError(owner + ".noise_b", "expected a finite coefficient >= 0");
  if (s.scan_rows < 1 || s.scan_rows > s.height) throw SchemaError(owner + ".scan_rows", "expected 1 to height rows");
}

DepthCamera::DepthCamera(std::shared_ptr<const RangeScanner> scanner, DepthCameraSpec spec)
    : scanner_(std::move(scanner)), spec_(spec) {
  check_settings(spec_, "kinect");
  fx_ = PinholeCamera::focal_for(spec_.width, spec_.hfov);
  cx_ = PinholeCamera::centre_of(spec_.width);
  cy_ = PinholeCamera::centre_of(spec_.height);
  angles_.resize(static_cast<std::size_t>(spec_.width));
  column_x_.resize(static_cast<std::size_t>(spec_.width));
  for (int u = 0; u < spec_.width; ++u) {
    column_x_[static_cast<std::size_t>(u)] = (u - cx_) / fx_;
    angles_[static_cast<std::size_t>(u)] = -std::atan(column_x_[static_cast<std::size_t>(u)]);
  }
}

void DepthCamera::render(int robot, const Pose2& pose, std::span<float> depth, Rng* noise) const {
  const auto w = static_cast<std::size_t>(spec_.width), h = static_cast<std::size_t>(spec_.height);
  if (depth.size() != w * h) throw Error("DepthCamera::render: the image buffer has the wrong size");
  // The horizontal distance to the first wall or robot along each column's azimuth.
  std::vector<float> wall(w);
  // Beyond the horizontal reach of max_range nothing is valid; search a little further so that
  // wall tops and floors just past it still resolve correctly.
  const double reach = spec_.max_range * std::sqrt(1.0 + column_x_[0] * column_x_[0]) + 1.0;
  scanner_->scan(robot, pose, angles_, reach, wall);
  const double hc = spec_.mount_height, top = spec_.wall_height - spec_.mount_height;
  for (std::size_t u = 0; u < w; ++u) {
    const double stretch = std::sqrt(1.0 + column_x_[u] * column_x_[u]);  // horizontal distance per unit depth
    const double z_wall = wall[u] / stretch;
    const bool wall_hit = wall[u] < reach;
    for (std::size_t v = 0; v < h; ++v) {
      const double down = (static_cast<double>(v) - cy_) / fx_;  // y_c / z_c: positive below the horizon
      double z;
      // The wall at z_wall is seen if the ray is between floor and ceiling there.
      const double height_at_wall = -down * z_wall;  // relative to the camera
      if (wall_hit && height_at_wall >= -hc && height_at_wall <= top) {
        z = z_wall;
      } else if (down > 0) {
        z = hc / down;  // the floor
      } else if (down < 0) {
        z = top / -down;  // the ceiling
      } else {
        z = std::numeric_limits<double>::infinity();
      }
      if (noise && std::isfinite(z)) {
        const double e = z - 0.4;
        z += noise->normal(0.0, spec_.noise_a + spec_.noise_b * e * e);
      }
      depth[v * w + u] = (z >= spec_.min_range && z <= spec_.max_range) ? static_cast<float>(z) : kInvalid;
    }
  }
}

void DepthCamera::to_scan(std::span<const float> depth, std::span<float> ranges) const {
  const auto w = static_cast<std::size_t>(spec_.width);
  const int first = static_cast<int>(std::lround(cy_ - (spec_.scan_rows - 1) / 2.0));
  for (std::size_t u = 0; u < w; ++u) {
    float best = kInvalid;
    for (int v = first; v < first + spec_.scan_rows; ++v) {
      const float z = depth[static_cast<std::size_t>(v) * w + u];
      if (std::isnan(z)) continue;
      const double x = column_x_[u] * z;
      const auto r = static_cast<float>(std::sqrt(x * x + static_cast<double>(z) * z));
      if (std::isnan(best) || r < best) best = r;
    }
    ranges[u] = best;
  }
}

KinectGenerator::KinectGenerator(std::shared_ptr<const RangeScanner> scanner, int robot, DepthCameraSpec spec,
                                 const Alphabet& alphabet, const std::string& event)
    : camera_(scanner, spec), scanner_(std::move(scanner)), robot_(robot), event_(alphabet.event_type_id(event)),
      depth_(static_cast<std::size_t>(spec.width) * spec.height, kInvalid), ranges_(static_cast<std::size_t>(spec.width), kInvalid) {
  require_fields(alphabet, event_, {{"dist", ValueKind::Real}, {"angle", ValueKind::Real}});
  (void)scanner_->world().robot(robot_);
}

void KinectGenerator::generate(const FrameInfo&, EventList& out) {
  const RobotState* robot = scanner_->world().find_robot(robot_);
  if (robot == nullptr) return;  // out of the string: no body, no picture
  const Pose2 pose = robot->pose;
  camera_.render(robot_, pose, depth_, camera_.spec().noise ? &rng_ : nullptr);
  camera_.to_scan(depth_, ranges_);
  const auto angles = camera_.angles();
  events_.clear();
  for (std::size_t u = 0; u < ranges_.size(); ++u) {
    if (std::isnan(ranges_[u])) continue;
    events_.add(ranges_[u], angles[u]);
  }
  events_.emit(out, event_, robot_);
}

}  // namespace vwg::sim
