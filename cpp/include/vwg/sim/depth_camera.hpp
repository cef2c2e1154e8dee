// A simulated depth camera (a Kinect) in the world made from the map: walls extruded from the
// floor to the wall height, a flat ceiling there, other robots as cylinders. gKinect renders its
// depth image each frame and turns the middle rows into a laser scan, as ROS's
// depthimage_to_laserscan does, making the same eLaser<dist, angle> events as gLaser.
#pragma once

#include <concepts>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "vwg/alphabet.hpp"
#include "vwg/generator.hpp"
#include "vwg/random.hpp"
#include "vwg/sim/laser.hpp"

namespace vwg::sim {

struct DepthCameraSpec {
  int width = 640;
  int height = 480;
  double hfov = 1.0122909661567112;  ///< 58°, the Kinect's horizontal field of view
  double min_range = 0.5;            ///< depths nearer than this are invalid (the Kinect's blind zone)
  double max_range = 4.5;
  double mount_height = 0.3;  ///< optical centre above the floor, metres
  double wall_height = kDefaultWallHeight;  ///< walls and ceiling
  double robot_height = 0.4;  ///< other robots are cylinders this tall
  /// Axial noise σ(z) = noise_a + noise_b·(z - 0.4)² metres (Nguyen, Izadi & Lovell 2012);
  /// `noise` switches it on.
  bool noise = false;
  double noise_a = 0.0012;
  double noise_b = 0.0019;
  int scan_rows = 1;  ///< rows around the centre used for the scan (depthimage_to_laserscan's scan_height)
};

template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, DepthCameraSpec>
void visit_settings(S& s, F&& field) {
  field("width", s.width, "image width, pixels");
  field("height", s.height, "image height, pixels");
  field("hfov", s.hfov, "horizontal field of view, radians");
  field("min_range", s.min_range, "nearer depths are invalid (the blind zone), metres");
  field("max_range", s.max_range, "metres");
  field("mount_height", s.mount_height, "optical centre above the floor, metres");
  field("wall_height", s.wall_height, "walls and ceiling, metres");
  field("robot_height", s.robot_height, "other robots are cylinders this tall, metres");
  field("noise", s.noise, "axial noise noise_a + noise_b·(z - 0.4)² on or off");
  field("noise_a", s.noise_a, "metres");
  field("noise_b", s.noise_b, "metres per square metre");
  field("scan_rows", s.scan_rows, "rows around the centre turned into the scan");
}

/// Throws SchemaError naming `owner.field` for a size outside 1..8192, a field of view outside
/// (0, π), ranges that are not 0 <= min_range < max_range, heights that are not 0 < mount_height <
/// wall_height and 0 < robot_height, negative noise, or scan rows outside 1..height.
void check_settings(const DepthCameraSpec& spec, const std::string& owner);

/// Renders depth images (metres along the optical axis, NaN where invalid), row-major, row 0 at
/// the top, for a camera looking along the robot's heading, level with the floor.
class DepthCamera {
 public:
  DepthCamera(std::shared_ptr<const RangeScanner> scanner, DepthCameraSpec spec);
  void render(int robot, const Pose2& pose, std::span<float> depth, Rng* noise) const;
  /// depthimage_to_laserscan: per column, the nearest valid range (√(x² + z²)) over the scan
  /// rows; NaN if none. angles()[u] is the beam angle of column u (positive to the left).
  void to_scan(std::span<const float> depth, std::span<float> ranges) const;
  std::span<const double> angles() const { return angles_; }
  const DepthCameraSpec& spec() const { return spec_; }
  double fx() const { return fx_; }

 private:
  std::shared_ptr<const RangeScanner> scanner_;
  DepthCameraSpec spec_;
  double fx_, cx_, cy_;  // square pixels: fy = fx
  std::vector<double> angles_;      // azimuth of each column, left positive
  std::vector<double> column_x_;    // (u - cx) / fx
};

/// gKinect: a depth image each frame, its scan, and eLaser<to=robot, dist, angle> for each column
/// with a valid range.
class KinectGenerator final : public Generator {
 public:
  KinectGenerator(std::shared_ptr<const RangeScanner> scanner, int robot, DepthCameraSpec spec, const Alphabet& alphabet,
                  const std::string& event = "eLaser");
  void reset(std::uint64_t seed) override { rng_.reseed(derive_seed(seed, 0x6B696E656374ULL, static_cast<std::uint64_t>(robot_))); }
  void generate(const FrameInfo& frame, EventList& out) override;
  std::string name() const override { return "gKinect(" + std::to_string(robot_) + ")"; }
  /// Its noise's random stream (the scanner reads the platform as it is).
  void save_state(StateWriter& out) const override { rng_.save(out); }
  void load_state(StateReader& in) override {
    rng_.load(in);
    in.end();
  }

  std::span<const float> depth() const { return depth_; }  ///< the last depth image, height × width
  std::span<const float> ranges() const { return ranges_; }  ///< its scan (NaN: no return)
  std::span<const double> angles() const { return camera_.angles(); }
  const DepthCamera& camera() const { return camera_; }
  int robot() const { return robot_; }

 private:
  DepthCamera camera_;
  std::shared_ptr<const RangeScanner> scanner_;
  int robot_;
  EventTypeId event_;
  std::vector<float> depth_;
  std::vector<float> ranges_;
  ScanEvents events_;
  Rng rng_;
};

}  // namespace vwg::sim
