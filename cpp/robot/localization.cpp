#include "vwg/robot/localization.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
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
  for (std::size_t i = 0; i < d2.size(); ++i) {
    distance_[i] = static_cast<float>(std::min(std::sqrt(d2[i]) * map.resolution, max_dist_));
  }
}

double LikelihoodField::distance(double x, double y) const {
  int row, col;
  if (!geometry_.cell_of(x, y, row, col)) return max_dist_;
  return distance_[static_cast<std::size_t>(row) * geometry_.width + col];
}

double LikelihoodField::pz(double x, double y) const {
  const double d = distance(x, y);
  return z_hit_ * std::exp(-d * d / two_sigma2_) + rand_;
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
  thread_local std::vector<double> angles, ranges, turned, du, dv;
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
  turned.resize(angles.size()), du.resize(angles.size()), dv.resize(angles.size());
  double total = 0.0;
  for (Particle& p : particles_) {
    for (std::size_t k = 0; k < angles.size(); ++k) turned[k] = p.theta + angles[k];
    geometry::beam_directions(turned, "avx2", du, dv);  // vwg's own sine and cosine: the same bits everywhere
    double sum = 1.0;  // amcl's 1 + Σ pz³ ("works well in practice"): a few stray returns do not zero a weight
    for (std::size_t k = 0; k < angles.size(); ++k) {
      const double pz = field.pz(p.x + ranges[k] * du[k], p.y + ranges[k] * dv[k]);
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

void ParticleFilter::resample(Rng& rng) {
  const std::size_t n = particles_.size();
  if (n == 0) return;
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

void ParticleFilter::load(StateReader& in) {
  std::vector<Particle> particles = in.pods<Particle>();
  if (particles.size() != static_cast<std::size_t>(settings_.particles)) {
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
                                             std::vector<std::shared_ptr<const platform::ScanSource>> scans,
                                             std::shared_ptr<const LikelihoodField> field, LocalizationSettings settings,
                                             const Alphabet& alphabet, const std::string& event)
    : platform_(std::move(platform)), field_(std::move(field)), settings_(settings), event_(alphabet.event_type_id(event)) {
  if (!platform_) throw Error("LocalizationGenerator: no platform");
  if (!field_) throw Error("LocalizationGenerator: no likelihood field");
  check_settings(settings_, "localization");
  require_fields(alphabet, event_, {{"x", ValueKind::Real}, {"y", ValueKind::Real}, {"angle", ValueKind::Real},
                                    {"busy", ValueKind::Bool}, {"commands", ValueKind::Int}});
  for (auto& scan : scans) {
    if (!scan) throw Error("LocalizationGenerator: a null scan source");
    const int id = scan->scan_robot();
    if (!scans_.emplace(id, std::move(scan)).second) {
      throw SchemaError("localization", "robot " + std::to_string(id) + " has two lasers: give one");
    }
  }
  for (const platform::RobotState& s : platform_->robots()) {
    if (!scans_.contains(s.id)) {
      throw SchemaError("localization", "robot " + std::to_string(s.id) + " carries no laser: particles weigh the laser's scan");
    }
  }
}

LocalizationGenerator::Track& LocalizationGenerator::track(int id) {
  auto it = tracks_.find(id);
  if (it == tracks_.end()) {
    it = tracks_.emplace(id, Track{ParticleFilter(settings_), Rng(derive_seed(seed_, 0x6D636CULL, static_cast<std::uint64_t>(id)))})
             .first;
  }
  return it->second;
}

void LocalizationGenerator::reset(std::uint64_t seed) {
  seed_ = seed;
  tracks_.clear();
}

void LocalizationGenerator::generate(const FrameInfo&, EventList& out) {
  for (const platform::RobotState& s : platform_->robots()) {
    Track& t = track(s.id);
    const Pose2 odometry = s.odometry;
    if (!t.started) {
      // The robot starts where its world file puts it (where its odometry starts).
      t.filter.start(odometry, t.rng);
      t.started = true;
      t.odometry_update = odometry;
      t.estimate_update = t.filter.estimate();
    } else {
      const Pose2 moved = relative(t.odometry_update, t.odometry_last);
      if (std::hypot(moved.x, moved.y) >= settings_.update_min_d || std::abs(moved.theta) >= settings_.update_min_a) {
        const auto scan = scans_.find(s.id);
        t.filter.predict(t.odometry_update, t.odometry_last, t.rng);
        if (scan != scans_.end()) t.filter.weigh(scan->second->last_scan(), *field_);
        if (t.filter.effective_size() < settings_.resample_below * settings_.particles) t.filter.resample(t.rng);
        t.odometry_update = t.odometry_last;
        t.estimate_update = t.filter.estimate();
      }
    }
    t.odometry_last = odometry;
    t.sent = compose(t.estimate_update, relative(t.odometry_update, odometry));
    const Datum fields[] = {t.sent.x, t.sent.y, t.sent.theta, s.busy, static_cast<std::int64_t>(s.commands)};
    out.emit(event_, fields, s.id);
  }
}

std::optional<Pose2> LocalizationGenerator::estimate(int id) const {
  const auto it = tracks_.find(id);
  if (it == tracks_.end() || !it->second.started) return std::nullopt;
  return it->second.sent;
}

const ParticleFilter& LocalizationGenerator::filter(int id) const {
  const auto it = tracks_.find(id);
  if (it == tracks_.end()) throw Error("localization: no filter for robot " + std::to_string(id) + " yet");
  return it->second.filter;
}

void LocalizationGenerator::save_state(StateWriter& out) const {
  out.u64(tracks_.size());
  for (const auto& [id, t] : tracks_) {
    out.i64(id);
    t.rng.save(out);
    out.boolean(t.started);
    for (const Pose2& p : {t.odometry_last, t.odometry_update, t.estimate_update, t.sent}) {
      out.f64(p.x), out.f64(p.y), out.f64(p.theta);
    }
    t.filter.save(out);
  }
}

void LocalizationGenerator::load_state(StateReader& in) {
  std::map<int, Track> tracks;
  const std::size_t n = in.count(8, "robots");
  for (std::size_t k = 0; k < n; ++k) {
    const std::int64_t id = in.i64();
    if (!scans_.contains(static_cast<int>(id)) || tracks.contains(static_cast<int>(id))) {
      in.fail("a filter of robot " + std::to_string(id) + ", which this run does not localize (or twice)");
    }
    Track t{ParticleFilter(settings_), Rng()};
    t.rng.load(in);
    t.started = in.boolean();
    for (Pose2* p : {&t.odometry_last, &t.odometry_update, &t.estimate_update, &t.sent}) {
      p->x = in.f64(), p->y = in.f64(), p->theta = in.f64();
      if (!std::isfinite(p->x) || !std::isfinite(p->y) || !std::isfinite(p->theta)) in.fail("a pose that is not finite");
    }
    t.filter.load(in);
    tracks.emplace(static_cast<int>(id), std::move(t));
  }
  in.end();
  tracks_ = std::move(tracks);
}

}  // namespace vwg::robot
