#include "vwg/robot/localization.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_set>
#include <utility>

#include "geometry/distance_transform.hpp"
#include "vwg/error.hpp"
#include "vwg/geometry/directions.hpp"
#include "vwg/text.hpp"

namespace vwg::robot {

namespace {

using geometry::Pose2;
using geometry::wrap_angle;

constexpr int kMaxCount = 100000;

/// `b` seen from `a`: the motion from a to b in a's frame.
Pose2 relative(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta), dx = b.x - a.x, dy = b.y - a.y;
  return Pose2{c * dx + s * dy, -s * dx + c * dy, wrap_angle(b.theta - a.theta)};
}

/// `a` moved by `d` (given in a's frame).
Pose2 compose(const Pose2& a, const Pose2& d) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return Pose2{a.x + c * d.x - s * d.y, a.y + s * d.x + c * d.y, wrap_angle(a.theta + d.theta)};
}

}  // namespace

void check_settings(const LocalizationSettings& s, const std::string& owner) {
  const auto fail = [&](const char* field, const std::string& what) { throw SchemaError(owner + "." + field, what); };
  if (s.particles < 1 || s.particles > kMaxCount) fail("particles", "expected 1 to 100000 particles, got " + std::to_string(s.particles));
  if (s.beams < 1 || s.beams > kMaxCount) fail("beams", "expected 1 to 100000 beams, got " + std::to_string(s.beams));
  const std::pair<const char*, double> positive[] = {{"sigma_hit", s.sigma_hit}, {"max_dist", s.max_dist}};
  for (const auto& [name, v] : positive) {
    if (!std::isfinite(v) || v <= 0) fail(name, "expected a finite number > 0, got " + format_real(v));
  }
  const std::pair<const char*, double> non_negative[] = {
      {"z_hit", s.z_hit}, {"z_rand", s.z_rand}, {"alpha_rot_rot", s.alpha_rot_rot},
      {"alpha_rot_trans", s.alpha_rot_trans}, {"alpha_trans_trans", s.alpha_trans_trans},
      {"alpha_trans_rot", s.alpha_trans_rot}, {"update_min_d", s.update_min_d}, {"update_min_a", s.update_min_a},
      {"start_xy", s.start_xy}, {"start_angle", s.start_angle}};
  for (const auto& [name, v] : non_negative) {
    if (!std::isfinite(v) || v < 0) fail(name, "expected a finite number >= 0, got " + format_real(v));
  }
  if (!(s.z_hit + s.z_rand > 0)) fail("z_hit", "expected z_hit + z_rand > 0");
  if (!(s.resample_below >= 0 && s.resample_below <= 1)) {
    fail("resample_below", "expected a share from 0 to 1, got " + format_real(s.resample_below));
  }
  if (s.min_particles < 1 || (s.kld && s.min_particles > s.particles)) {
    fail("min_particles", "expected 1 to particles (" + std::to_string(s.particles) + "), got " + std::to_string(s.min_particles));
  }
  const std::pair<const char*, double> kld_positive[] = {{"kld_err", s.kld_err}, {"kld_z", s.kld_z},
                                                         {"kld_bin_xy", s.kld_bin_xy}, {"kld_bin_angle", s.kld_bin_angle}};
  for (const auto& [name, v] : kld_positive) {
    if (!std::isfinite(v) || v <= 0) fail(name, "expected a finite number > 0, got " + format_real(v));
  }
}

// ---- the likelihood field ------------------------------------------------------------------------
LikelihoodField::LikelihoodField(const geometry::OccupancyGrid& map, const LocalizationSettings& s, double max_range)
    : geometry_(geometry::MapGeometry::of(map)), max_dist_(s.max_dist), z_hit_(s.z_hit),
      two_sigma2_(2.0 * s.sigma_hit * s.sigma_hit), rand_(max_range > 0 ? s.z_rand / max_range : 0.0) {
  check_settings(s, "localization");
  if (!(max_range > 0) || !std::isfinite(max_range)) throw SchemaError("localization", "the laser's max_range must be > 0");
  std::vector<std::uint8_t> occupied(map.data.size());
  for (std::size_t i = 0; i < occupied.size(); ++i) occupied[i] = map.data[i] >= geometry::kObstacleThreshold ? 1 : 0;
  const std::vector<double> d2 = geometry::squared_distance_transform(occupied, map.height, map.width);
  distance_.resize(d2.size());
  pz_.resize(d2.size());
  for (std::size_t i = 0; i < d2.size(); ++i) {
    const double d = std::min(std::sqrt(d2[i]) * map.resolution, max_dist_);
    distance_[i] = static_cast<float>(d);
    pz_[i] = static_cast<float>(z_hit_ * std::exp(-d * d / two_sigma2_) + rand_);  // once a cell: a beam is a lookup
  }
  off_map_ = z_hit_ * std::exp(-max_dist_ * max_dist_ / two_sigma2_) + rand_;
}

double LikelihoodField::distance(double x, double y) const {
  int row, col;
  if (!geometry_.cell_of(x, y, row, col)) return max_dist_;
  return distance_[static_cast<std::size_t>(row) * geometry_.width + col];
}

double LikelihoodField::pz(double x, double y) const {
  int row, col;
  if (!geometry_.cell_of(x, y, row, col)) return off_map_;
  return pz_[static_cast<std::size_t>(row) * geometry_.width + col];
}

// ---- the particle filter -----------------------------------------------------------------------------
ParticleFilter::ParticleFilter(LocalizationSettings settings) : settings_(settings) {
  check_settings(settings_, "localization");
}

void ParticleFilter::start(const Pose2& pose, Rng& rng) {
  const int n = settings_.particles;
  particles_.assign(static_cast<std::size_t>(n), Particle{});
  for (Particle& p : particles_) {
    p.x = pose.x + rng.normal(0.0, settings_.start_xy);
    p.y = pose.y + rng.normal(0.0, settings_.start_xy);
    p.theta = wrap_angle(pose.theta + rng.normal(0.0, settings_.start_angle));
    p.weight = 1.0 / n;
  }
}

void ParticleFilter::predict(const Pose2& from, const Pose2& to, Rng& rng) {
  // The odometry motion model (Probabilistic Robotics, Table 5.6): a turn, a drive, a turn, each with noise
  // growing with the motion. A turn on the spot has no direction of travel: its first turn is taken as 0.
  const double dx = to.x - from.x, dy = to.y - from.y, trans = std::hypot(dx, dy);
  const double rot1 = trans < 0.01 ? 0.0 : wrap_angle(std::atan2(dy, dx) - from.theta);
  const double rot2 = wrap_angle(to.theta - from.theta - rot1);
  // A drive backwards turns by π twice in the model; its noise is that of the drive (as amcl does).
  const double r1 = std::min(std::abs(rot1), std::abs(wrap_angle(rot1 - std::numbers::pi)));
  const double r2 = std::min(std::abs(rot2), std::abs(wrap_angle(rot2 - std::numbers::pi)));
  const LocalizationSettings& a = settings_;
  const double sd_rot1 = std::sqrt(a.alpha_rot_rot * r1 * r1 + a.alpha_rot_trans * trans * trans);
  const double sd_trans = std::sqrt(a.alpha_trans_trans * trans * trans + a.alpha_trans_rot * (r1 * r1 + r2 * r2));
  const double sd_rot2 = std::sqrt(a.alpha_rot_rot * r2 * r2 + a.alpha_rot_trans * trans * trans);
  for (Particle& p : particles_) {
    const double h1 = rot1 - rng.normal(0.0, sd_rot1);
    const double t = trans - rng.normal(0.0, sd_trans);
    const double h2 = rot2 - rng.normal(0.0, sd_rot2);
    const double heading = p.theta + h1;
    p.x += t * std::cos(heading);
    p.y += t * std::sin(heading);
    p.theta = wrap_angle(heading + h2);
  }
}

void ParticleFilter::weigh(const platform::ScanView& scan, const LikelihoodField& field) {
  // The beams weighed: evenly spread, returns only (a beam that met nothing says little: amcl skips it).
  thread_local std::vector<double> angles, ranges, beam_cos, beam_sin, headings, cos_h, sin_h;
  angles.clear(), ranges.clear();
  const std::size_t n = scan.ranges.size(), step = std::max<std::size_t>(1, n / static_cast<std::size_t>(settings_.beams));
  for (std::size_t i = 0; i < n; i += step) {
    const double r = scan.ranges[i];
    if (r > 0.0 && r < scan.max_range) {
      angles.push_back(scan.angles[i]);
      ranges.push_back(r);
    }
  }
  if (angles.empty() || particles_.empty()) return;
  // A beam's end from a particle: its heading's direction turned by the beam's angle. The sines and cosines
  // are vwg's own (the same bits everywhere): the beams' once a scan, the particles' headings once each.
  beam_cos.resize(angles.size()), beam_sin.resize(angles.size());
  geometry::beam_directions(angles, "avx2", beam_cos, beam_sin);
  headings.resize(particles_.size()), cos_h.resize(particles_.size()), sin_h.resize(particles_.size());
  for (std::size_t i = 0; i < particles_.size(); ++i) headings[i] = particles_[i].theta;
  geometry::beam_directions(headings, "avx2", cos_h, sin_h);
  double total = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    Particle& p = particles_[i];
    const double c = cos_h[i], s = sin_h[i];
    double sum = 1.0;  // amcl's 1 + Σ pz³ ("works well in practice"): a few stray returns do not zero a weight
    for (std::size_t k = 0; k < angles.size(); ++k) {
      const double du = c * beam_cos[k] - s * beam_sin[k], dv = s * beam_cos[k] + c * beam_sin[k];
      const double pz = field.pz(p.x + ranges[k] * du, p.y + ranges[k] * dv);
      sum += pz * pz * pz;
    }
    p.weight *= sum;
    total += p.weight;
  }
  if (!(total > 0) || !std::isfinite(total)) {  // every weight underflowed: start the weights again
    for (Particle& p : particles_) p.weight = 1.0 / static_cast<double>(particles_.size());
    return;
  }
  for (Particle& p : particles_) p.weight /= total;
}

double ParticleFilter::effective_size() const {
  double sum2 = 0.0;
  for (const Particle& p : particles_) sum2 += p.weight * p.weight;
  return sum2 > 0 ? 1.0 / sum2 : 0.0;
}

int kld_bound(int bins, double err, double z) {
  if (bins <= 1) return 1;
  const double k = bins - 1.0, b = 2.0 / (9.0 * k);
  const double x = 1.0 - b + std::sqrt(b) * z;
  const double n = std::ceil(k / (2.0 * err) * x * x * x);
  return n >= 1e9 ? 1000000000 : static_cast<int>(n);
}

void ParticleFilter::resample(Rng& rng) {
  const std::size_t n = particles_.size();
  if (n == 0) return;
  if (settings_.kld) return resample_kld(rng);
  std::vector<Particle> drawn;
  drawn.reserve(n);
  const double share = 1.0 / static_cast<double>(n);
  const double r = rng.uniform() * share;
  double c = particles_[0].weight;
  std::size_t i = 0;
  for (std::size_t m = 0; m < n; ++m) {
    const double u = r + static_cast<double>(m) * share;
    while (u > c && i + 1 < n) c += particles_[++i].weight;
    drawn.push_back(particles_[i]);
    drawn.back().weight = share;
  }
  particles_ = std::move(drawn);
}

Pose2 ParticleFilter::estimate() const {
  double x = 0.0, y = 0.0, c = 0.0, s = 0.0, total = 0.0;
  for (const Particle& p : particles_) {
    x += p.weight * p.x;
    y += p.weight * p.y;
    c += p.weight * std::cos(p.theta);
    s += p.weight * std::sin(p.theta);
    total += p.weight;
  }
  if (!(total > 0)) return Pose2{};
  return Pose2{x / total, y / total, std::atan2(s, c)};
}

void ParticleFilter::save(StateWriter& out) const { out.pods(particles_); }

void ParticleFilter::resample_kld(Rng& rng) {
  // The cumulative weights, drawn from by bisection: one uniform number a particle, in order.
  std::vector<double> cumulative(particles_.size());
  double total = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) cumulative[i] = total += particles_[i].weight;
  const auto max = static_cast<std::size_t>(settings_.particles);
  const auto least = static_cast<std::size_t>(settings_.min_particles);
  std::vector<Particle> drawn;
  drawn.reserve(max);
  std::unordered_set<std::uint64_t> bins;
  std::size_t needed = least;
  while (drawn.size() < max && (drawn.size() < least || drawn.size() < needed)) {
    const double u = rng.uniform() * total;
    const auto at = static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
    const Particle& p = particles_[std::min(at, particles_.size() - 1)];
    drawn.push_back(p);
    // A bin is its three indices, 21 bits each (maps of up to a million bins a side).
    const auto cell = [](double v, double size) {
      return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / size))) & 0x1FFFFF;
    };
    const std::uint64_t bin = cell(p.x, settings_.kld_bin_xy) << 42 | cell(p.y, settings_.kld_bin_xy) << 21 |
                              cell(wrap_angle(p.theta), settings_.kld_bin_angle);
    if (bins.insert(bin).second) {
      needed = static_cast<std::size_t>(kld_bound(static_cast<int>(bins.size()), settings_.kld_err, settings_.kld_z));
    }
  }
  const double share = 1.0 / static_cast<double>(drawn.size());
  for (Particle& p : drawn) p.weight = share;
  particles_ = std::move(drawn);
}

void ParticleFilter::load(StateReader& in) {
  std::vector<Particle> particles = in.pods<Particle>();
  const bool kld_count = settings_.kld && particles.size() <= static_cast<std::size_t>(settings_.particles);
  if (!particles.empty() && !kld_count && particles.size() != static_cast<std::size_t>(settings_.particles)) {
    in.fail("expected " + std::to_string(settings_.particles) + " particles, found " + std::to_string(particles.size()));
  }
  for (const Particle& p : particles) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.theta) || !(p.weight >= 0 && p.weight <= 1)) {
      in.fail("a particle that is not a finite pose with a weight from 0 to 1");
    }
  }
  particles_ = std::move(particles);
}

// ---- the generator ---------------------------------------------------------------------------------
LocalizationGenerator::LocalizationGenerator(std::shared_ptr<platform::RobotPlatform> platform,
                                             std::shared_ptr<const platform::ScanSource> scan,
                                             std::shared_ptr<const LikelihoodField> field, LocalizationSettings settings,
                                             const Alphabet& alphabet, const std::string& event)
    : platform_(std::move(platform)), scan_(std::move(scan)), field_(std::move(field)), settings_(settings),
      event_(alphabet.event_type_id(event)), robot_(scan_ ? scan_->scan_robot() : 0), filter_(settings) {
  if (!platform_) throw Error("LocalizationGenerator: no platform");
  if (!scan_) throw Error("LocalizationGenerator: no laser");
  if (!field_) throw Error("LocalizationGenerator: no likelihood field");
  require_fields(alphabet, event_, {{"x", ValueKind::Real}, {"y", ValueKind::Real}, {"angle", ValueKind::Real},
                                    {"busy", ValueKind::Bool}, {"commands", ValueKind::Int}});
  (void)platform_->robot(robot_);  // throws if the platform has no such robot
}

void LocalizationGenerator::reset(std::uint64_t seed) {
  rng_.reseed(derive_seed(seed, 0x6D636CULL, static_cast<std::uint64_t>(robot_)));
  started_ = false;
}

void LocalizationGenerator::generate(const FrameInfo&, EventList& out) {
  const platform::RobotState* robot = platform_->find_robot(robot_);
  if (robot == nullptr) {  // out of the string: no body to localize; if it comes back, the filter starts afresh
    started_ = false;
    return;
  }
  const platform::RobotState& s = *robot;
  const Pose2 odometry = s.odometry;
  if (!started_) {
    // The robot starts where its world file puts it (where its odometry starts).
    filter_.start(odometry, rng_);
    started_ = true;
    odometry_update_ = odometry;
    estimate_update_ = filter_.estimate();
  } else {
    const Pose2 moved = relative(odometry_update_, odometry_last_);
    if (std::hypot(moved.x, moved.y) >= settings_.update_min_d || std::abs(moved.theta) >= settings_.update_min_a) {
      filter_.predict(odometry_update_, odometry_last_, rng_);
      filter_.weigh(scan_->last_scan(), *field_);
      const auto count = static_cast<double>(filter_.particles().size());
      if (filter_.effective_size() < settings_.resample_below * count) filter_.resample(rng_);
      odometry_update_ = odometry_last_;
      estimate_update_ = filter_.estimate();
    }
  }
  odometry_last_ = odometry;
  sent_ = compose(estimate_update_, relative(odometry_update_, odometry));
  const Datum fields[] = {sent_.x, sent_.y, sent_.theta, s.busy, static_cast<std::int64_t>(s.commands)};
  out.emit(event_, fields, robot_);
}

std::optional<Pose2> LocalizationGenerator::estimate() const {
  if (!started_) return std::nullopt;
  return sent_;
}

void LocalizationGenerator::save_state(StateWriter& out) const {
  rng_.save(out);
  out.boolean(started_);
  for (const Pose2& p : {odometry_last_, odometry_update_, estimate_update_, sent_}) out.f64(p.x), out.f64(p.y), out.f64(p.theta);
  filter_.save(out);
}

void LocalizationGenerator::load_state(StateReader& in) {
  Rng rng;
  rng.load(in);
  const bool started = in.boolean();
  Pose2 poses[4];
  for (Pose2& p : poses) {
    p.x = in.f64(), p.y = in.f64(), p.theta = in.f64();
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.theta)) in.fail("a pose that is not finite");
  }
  ParticleFilter filter(settings_);
  filter.load(in);
  if (started && filter.particles().empty()) in.fail("a started filter without particles");
  in.end();
  rng_ = rng;
  started_ = started;
  odometry_last_ = poses[0], odometry_update_ = poses[1], estimate_update_ = poses[2], sent_ = poses[3];
  filter_ = std::move(filter);
}

}  // namespace vwg::robot
