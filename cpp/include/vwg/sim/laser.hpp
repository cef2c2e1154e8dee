// Simulated range sensors as event generators (paper Table II): gLaser, a 2D laser scanner, and
// gKinect, a depth camera turned into a scan as depthimage_to_laserscan does. Both make the same
// events eLaser<dist, angle> (metres, radians from the robot's heading, counter-clockwise), one
// per beam that met an obstacle, addressed to the robot — so either can replace the other.
#pragma once

#include <cmath>
#include <concepts>
#include <type_traits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vwg/alphabet.hpp"
#include "vwg/generator.hpp"
#include "vwg/platform/laser_scan.hpp"
#include "vwg/platform/scan_source.hpp"
#include "vwg/random.hpp"
#include "vwg/sim/physics.hpp"
#include "vwg/sim/raycast.hpp"

namespace vwg::sim {

/// A planar range finder. The defaults here are the only ones: the bindings and the world files
/// take them from this struct (visit_settings lists its fields).
struct LaserSpec {
  int beams = 360;
  double fov = 2 * M_PI;  ///< radians; a full circle has no duplicate beam at ±π
  double min_range = 0.05;
  double max_range = 8.0;
  double noise = 0.01;  ///< standard deviation of each range, metres (a noisy reading is rounded to float32)
};

/// Each field with its name and meaning, for bindings and file loaders.
template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, LaserSpec>
void visit_settings(S& s, F&& field) {
  field("beams", s.beams, "rays per scan");
  field("fov", s.fov, "field of view, radians, centred ahead (2π: a full circle)");
  field("min_range", s.min_range, "nearer returns are dropped, metres");
  field("max_range", s.max_range, "metres");
  field("noise", s.noise, "standard deviation of each range, metres");
}

/// The beams as sensor_msgs/LaserScan lays them out: beam i at angle_min + i·increment from the
/// heading. A full circle is [-π, π) in `beams` steps; a smaller field of view runs from -fov/2 to
/// +fov/2 inclusive.
struct BeamLayout {
  double angle_min;
  double increment;
};
BeamLayout beam_layout(const LaserSpec& spec);
/// The beam angles of that layout, computed as a LaserScan's reader does (so they agree bit for bit).
std::vector<double> beam_angles(const LaserSpec& spec);

/// atan2(y, x) within 1.2e-5 radians (Abramowitz & Stegun 4.4.49 on each octant), for bounds that
/// are widened by more than that; 0 at the origin.
double approximate_atan2(double y, double x);

/// Ranges over the map's walls and the other robots (discs of their radius, at their true poses).
class RangeScanner {
 public:
  RangeScanner(std::shared_ptr<const GridRaycaster> raycaster, std::shared_ptr<const PhysicsWorld> world);
  /// out[i]: range from `pose` along pose.theta + angles[i], up to max_range; robot `self` is
  /// not an obstacle to itself.
  void scan(int self, const Pose2& pose, std::span<const double> angles, double max_range, std::span<float> out) const;
  const GridRaycaster& raycaster() const { return *raycaster_; }
  const PhysicsWorld& world() const { return *world_; }

 private:
  std::shared_ptr<const GridRaycaster> raycaster_;
  std::shared_ptr<const PhysicsWorld> world_;
};

/// Checks the spec (1 <= beams <= 100000, 0 < fov <= 2π, 0 <= min_range < max_range, finite noise
/// >= 0); throws SchemaError naming `owner.field`.
void check_settings(const LaserSpec& spec, const std::string& owner);

/// The eLaser batch of a range sensor (vwg/platform/laser_scan.hpp).
using platform::ScanEvents;

/// gLaser: each frame, a scan from the robot's true pose with range noise, turned into events
/// `<event><to=robot, dist, angle>` by the rule a real robot's LaserScan goes through
/// (platform::laser_events): one for each beam that hit something nearer than max_range. A beam
/// that hit nothing reads max_range (no return, as many drivers report it). A hit's noisy reading is
/// float32 (as sensor_msgs/LaserScan's ranges), clamped to [min_range, max_range): a hit stays a hit.
class LaserGenerator final : public Generator, public platform::ScanSource {
 public:
  LaserGenerator(std::shared_ptr<const RangeScanner> scanner, int robot, LaserSpec spec, const Alphabet& alphabet,
                 const std::string& event = "eLaser");
  void reset(std::uint64_t seed) override { rng_.reseed(derive_seed(seed, 0x6C61736572ULL, static_cast<std::uint64_t>(robot_))); }
  void generate(const FrameInfo& frame, EventList& out) override;
  /// Reads the physics world (unchanged while events are collected); writes its own scan and rng.
  bool concurrent() const override { return true; }
  std::string name() const override { return "gLaser(" + std::to_string(robot_) + ")"; }
  /// Its noise's random stream (the scanner reads the platform as it is) and its last scan's ranges, which
  /// the parts that read it (the localization, a learning environment's observation) see until it scans again.
  void save_state(StateWriter& out) const override;
  void load_state(StateReader& in) override;

  /// The last scan: ranges (max_range where nothing was hit), and the beam angles.
  std::span<const float> ranges() const { return ranges_; }
  std::span<const double> angles() const { return angles_; }
  int robot() const { return robot_; }
  const LaserSpec& spec() const { return spec_; }
  int scan_robot() const override { return robot_; }
  platform::ScanView last_scan() const override { return {ranges_, angles_, spec_.max_range}; }

 private:
  std::shared_ptr<const RangeScanner> scanner_;
  int robot_;
  LaserSpec spec_;
  EventTypeId event_;
  std::vector<double> angles_;
  std::vector<float> ranges_;
  ScanEvents events_;
  Rng rng_;
};

}  // namespace vwg::sim
