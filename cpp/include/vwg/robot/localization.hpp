// Monte Carlo localization (Thrun, Burgard & Fox, Probabilistic Robotics, ch. 8; the likelihood-field model
// and the odometry motion model of ROS amcl): a particle filter per robot, weighed on the robot's laser scan
// against the known map, which turns odometry and scans into the robot's pose estimate.
//
// In the model it is the generator of eOdometry<x, y, angle, busy, commands> in place of the platform's raw
// odometry: the robot's believed pose in the string comes from it, and nothing else of ARobot changes. Each
// frame, for each robot: the scan of the last frame, taken where the odometry of the last frame was, weighs
// the particles once the robot has moved update_min_d or turned update_min_a since the filter's last update
// (predicted there by the odometry since); the pose sent is the filter's estimate moved on by the odometry
// since that update (amcl's map → odom correction).
#pragma once

#include <concepts>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "vwg/alphabet.hpp"
#include "vwg/generator.hpp"
#include "vwg/geometry/map_geometry.hpp"
#include "vwg/geometry/occupancy_grid.hpp"
#include "vwg/geometry/pose.hpp"
#include "vwg/platform/platform.hpp"
#include "vwg/platform/scan_source.hpp"
#include "vwg/random.hpp"

namespace vwg::robot {

struct LocalizationSettings {
  int particles = 300;           ///< particles per robot
  int beams = 60;                ///< beams of each scan weighed, evenly spread over it
  double sigma_hit = 0.2;        ///< metres: the spread of a return around the nearest obstacle
  double z_hit = 0.95;           ///< weight of a return near an obstacle
  double z_rand = 0.05;          ///< weight of a return anywhere (divided by the laser's range)
  double max_dist = 2.0;         ///< metres: distances to the nearest obstacle are capped here
  double alpha_rot_rot = 0.2;    ///< α1: rotation noise from rotation
  double alpha_rot_trans = 0.2;  ///< α2: rotation noise from translation
  double alpha_trans_trans = 0.2;  ///< α3: translation noise from translation
  double alpha_trans_rot = 0.2;  ///< α4: translation noise from rotation
  double update_min_d = 0.1;     ///< metres driven before the filter is updated again
  double update_min_a = 0.2;     ///< radians turned before the filter is updated again
  double start_xy = 0.1;         ///< metres: the spread of the particles around the start
  double start_angle = 0.05;     ///< radians: the same for the heading
  double resample_below = 0.5;   ///< resample when the effective number of particles falls below this share
  /// KLD-sampling (Fox 2003): each resampling draws as many particles as bound the error of the estimate
  /// (KL distance kld_err with probability given by the normal quantile kld_z) over the histogram bins the
  /// drawn particles occupy, from min_particles up to `particles`. Off: always `particles`.
  bool kld = false;
  int min_particles = 100;       ///< KLD-sampling's least count
  double kld_err = 0.01;         ///< ε: the KL distance bounded
  double kld_z = 2.326;          ///< z_{1−δ}: the normal's upper quantile for δ = 0.01
  double kld_bin_xy = 0.5;       ///< metres: the histogram's bins in x and y
  double kld_bin_angle = 0.1745; ///< radians: its bins in heading (10°)
};

template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, LocalizationSettings>
void visit_settings(S& s, F&& field) {
  field("particles", s.particles, "particles per robot");
  field("beams", s.beams, "beams of each scan weighed, evenly spread over it");
  field("sigma_hit", s.sigma_hit, "metres: the spread of a return around the nearest obstacle");
  field("z_hit", s.z_hit, "weight of a return near an obstacle");
  field("z_rand", s.z_rand, "weight of a return anywhere (divided by the laser's range)");
  field("max_dist", s.max_dist, "metres: distances to the nearest obstacle are capped here");
  field("alpha_rot_rot", s.alpha_rot_rot, "rotation noise from rotation (alpha1)");
  field("alpha_rot_trans", s.alpha_rot_trans, "rotation noise from translation (alpha2)");
  field("alpha_trans_trans", s.alpha_trans_trans, "translation noise from translation (alpha3)");
  field("alpha_trans_rot", s.alpha_trans_rot, "translation noise from rotation (alpha4)");
  field("update_min_d", s.update_min_d, "metres driven before the filter is updated again");
  field("update_min_a", s.update_min_a, "radians turned before the filter is updated again");
  field("start_xy", s.start_xy, "metres: the spread of the particles around the start");
  field("start_angle", s.start_angle, "radians: the spread of the particles' headings around the start");
  field("resample_below", s.resample_below, "resample when the effective number of particles falls below this share");
  field("kld", s.kld, "KLD-sampling: draw as many particles as the histogram bins they occupy need (else a fixed count)");
  field("min_particles", s.min_particles, "KLD-sampling's least count of particles");
  field("kld_err", s.kld_err, "KLD-sampling: the KL distance bounded (epsilon)");
  field("kld_z", s.kld_z, "KLD-sampling: the normal's upper quantile (2.326: probability 0.99)");
  field("kld_bin_xy", s.kld_bin_xy, "KLD-sampling: metres, the histogram's bins in x and y");
  field("kld_bin_angle", s.kld_bin_angle, "KLD-sampling: radians, the histogram's bins in heading");
}

/// KLD-sampling's bound (Fox 2003, eq. 12): the particles needed for `bins` occupied histogram bins,
/// ⌈(k − 1)/(2ε) · (1 − 2/(9(k − 1)) + √(2/(9(k − 1)))·z)³⌉; 1 for k ≤ 1.
int kld_bound(int bins, double err, double z);

/// Throws SchemaError naming `owner.field`: particles from 1 to 100000, beams from 1 to 100000, a sigma,
/// max_dist or z_hit + z_rand that is not > 0, a negative or non-finite weight, alpha, spread or threshold, a
/// resample share outside [0, 1].
void check_settings(const LocalizationSettings& s, const std::string& owner);

/// The likelihood field of a map: for a beam ending at (x, y), pz = z_hit·exp(−d²/(2σ²)) + z_rand/max_range,
/// d the distance from the point to the centre of the nearest occupied cell (capped at max_dist; off the map:
/// max_dist), per cell: made once per map, a beam costs one lookup.
class LikelihoodField {
 public:
  /// Occupied: the map's cells of value >= 50 (its unknown cells are not obstacles).
  LikelihoodField(const geometry::OccupancyGrid& map, const LocalizationSettings& settings, double max_range);
  double pz(double x, double y) const;
  /// d for the point (metres), as the field holds it (for tests).
  double distance(double x, double y) const;

 private:
  geometry::MapGeometry geometry_;
  std::vector<float> distance_;  ///< per cell, metres, capped
  std::vector<float> pz_;        ///< per cell, the pz of a beam ending in it
  double max_dist_, z_hit_, two_sigma2_, rand_, off_map_ = 0.0;
};

struct Particle {
  double x = 0.0, y = 0.0, theta = 0.0, weight = 0.0;
};

class ParticleFilter {
 public:
  explicit ParticleFilter(LocalizationSettings settings);
  /// settings.particles particles around `pose` (normal spreads start_xy, start_angle), equal weights.
  void start(const geometry::Pose2& pose, Rng& rng);
  /// Each particle moved by the odometry from `from` to `to`, with the motion model's noise (Table 5.6).
  void predict(const geometry::Pose2& from, const geometry::Pose2& to, Rng& rng);
  /// Each weight times amcl's 1 + Σ pz³ over the scan's weighed beams (returns only), then normalised.
  void weigh(const platform::ScanView& scan, const LikelihoodField& field);
  /// 1 / Σ w² of the normalised weights.
  double effective_size() const;
  /// Low-variance resampling (Table 4.4): equal weights after. With kld set, KLD-sampling instead: particles
  /// drawn by weight one at a time until their count reaches kld_bound of the bins they occupy (at least
  /// min_particles, at most particles).
  void resample(Rng& rng);
  /// The weighted mean position and the weighted circular mean heading.
  geometry::Pose2 estimate() const;
  const std::vector<Particle>& particles() const { return particles_; }
  std::vector<Particle>& particles() { return particles_; }
  const LocalizationSettings& settings() const { return settings_; }

  void save(StateWriter& out) const;
  void load(StateReader& in);

 private:
  void resample_kld(Rng& rng);

  LocalizationSettings settings_;
  std::vector<Particle> particles_;
};

/// eOdometry<to=robot, x, y, angle, busy, commands> with the robot's pose estimate (see the top of this file),
/// weighed on `scan`, the robot's laser: one generator a robot, as gLaser is, and the robots' run side by side.
class LocalizationGenerator final : public Generator {
 public:
  LocalizationGenerator(std::shared_ptr<platform::RobotPlatform> platform,
                        std::shared_ptr<const platform::ScanSource> scan, std::shared_ptr<const LikelihoodField> field,
                        LocalizationSettings settings, const Alphabet& alphabet, const std::string& event = "eOdometry");
  void reset(std::uint64_t seed) override;
  void generate(const FrameInfo& frame, EventList& out) override;
  /// Reads the platform and its robot's laser (neither changes while events are collected: the lasers scan
  /// later in the priority order, and not in the same run of generators); writes its own filter.
  bool concurrent() const override { return true; }
  std::string name() const override { return "localization(" + std::to_string(robot_) + ")"; }
  /// The particles, the random stream and the odometry marks.
  void save_state(StateWriter& out) const override;
  void load_state(StateReader& in) override;

  int robot() const { return robot_; }
  /// The pose last sent (none before the first frame).
  std::optional<geometry::Pose2> estimate() const;
  const ParticleFilter& filter() const { return filter_; }

 private:
  std::shared_ptr<platform::RobotPlatform> platform_;
  std::shared_ptr<const platform::ScanSource> scan_;
  std::shared_ptr<const LikelihoodField> field_;
  LocalizationSettings settings_;
  EventTypeId event_;
  int robot_;
  ParticleFilter filter_;
  Rng rng_;
  bool started_ = false;
  geometry::Pose2 odometry_last_{};    ///< the odometry of the last frame (where its scan was taken)
  geometry::Pose2 odometry_update_{};  ///< the odometry at the filter's last update
  geometry::Pose2 estimate_update_{};  ///< the filter's estimate then
  geometry::Pose2 sent_{};             ///< the pose last sent
};

}  // namespace vwg::robot
