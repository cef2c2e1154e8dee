#include "vwg/platform/neighbours.hpp"

#include "vwg/error.hpp"
#include "vwg/text.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

namespace vwg::platform {

namespace {

struct Piece {
  double x, y, radius;
};

}  // namespace

void check_settings(const NeighbourSettings& s, const std::string& owner) {
  const std::pair<const char*, double> positive[] = {{"jump", s.jump},           {"max_width", s.max_width},
                                                     {"min_radius", s.min_radius}, {"max_radius", s.max_radius},
                                                     {"gate", s.gate},           {"forget", s.forget}};
  for (const auto& [name, v] : positive) {
    if (!std::isfinite(v) || v <= 0) throw SchemaError(owner + "." + name, "expected a finite number > 0, got " + format_real(v));
  }
  if (!(s.smoothing > 0 && s.smoothing <= 1)) {
    throw SchemaError(owner + ".smoothing", "expected a weight in (0, 1], got " + format_real(s.smoothing));
  }
  if (s.min_radius > s.max_radius) throw SchemaError(owner + ".min_radius", "expected at most max_radius");
}

NeighbourTracker::NeighbourTracker(NeighbourSettings settings) : settings_(settings) {}

void NeighbourTracker::update(const ScanView& scan, const geometry::Pose2& pose, double time) {
  const std::size_t n = std::min(scan.ranges.size(), scan.angles.size());
  const auto hit = [&](std::size_t i) { return scan.ranges[i] > 0.0f && scan.ranges[i] < scan.max_range; };
  const auto point = [&](std::size_t i, double& x, double& y) {
    const double a = pose.theta + scan.angles[i], r = scan.ranges[i];
    x = pose.x + r * std::cos(a);
    y = pose.y + r * std::sin(a);
  };
  // Nearer than its side beams by `jump` (a side with no return, or beyond the scan, is far).
  const auto in_front = [&](std::size_t side, double range) {
    return !hit(side) || scan.ranges[side] >= range + settings_.jump;
  };
  std::vector<Piece> pieces;
  std::size_t i = 0;
  while (i < n) {
    if (!hit(i)) {
      ++i;
      continue;
    }
    std::size_t j = i;  // the piece is beams i..j
    double px, py;
    point(i, px, py);
    double fx = px, fy = py, lx = px, ly = py, far = scan.ranges[i];
    std::size_t nearest = i;
    while (j + 1 < n && hit(j + 1)) {
      double qx, qy;
      point(j + 1, qx, qy);
      if (std::hypot(qx - lx, qy - ly) > settings_.jump) break;
      ++j;
      lx = qx, ly = qy;
      far = std::max(far, static_cast<double>(scan.ranges[j]));
      if (scan.ranges[j] < scan.ranges[nearest]) nearest = j;
    }
    const std::size_t count = j - i + 1;
    // The ends of a piece are within half a beam's spacing of its edges, on each side: add one spacing.
    const double spacing = count >= 2 ? std::abs(scan.angles[j] - scan.angles[i]) / static_cast<double>(count - 1) : 0.0;
    const double width = std::hypot(lx - fx, ly - fy) + spacing * scan.ranges[nearest];
    const bool left = i == 0 || in_front(i - 1, far), right = j + 1 >= n || in_front(j + 1, far);
    if (count >= 2 && width <= settings_.max_width && left && right) {
      // A disc's nearest point to the laser is on the line to its centre: the centre is one radius beyond it.
      const double radius = std::clamp(0.5 * width, settings_.min_radius, settings_.max_radius);
      const double a = pose.theta + scan.angles[nearest], r = scan.ranges[nearest] + radius;
      pieces.push_back({pose.x + r * std::cos(a), pose.y + r * std::sin(a), radius});
    }
    i = j + 1;
  }
  // Tracks not seen for too long go; then each piece continues the nearest free track within the gate.
  std::erase_if(tracks_, [&](const Neighbour& t) { return time - t.seen > settings_.forget; });
  std::vector<bool> taken(tracks_.size(), false);
  std::vector<Neighbour> started;
  for (const Piece& p : pieces) {
    std::size_t best = tracks_.size();
    double best_d = settings_.gate;
    for (std::size_t k = 0; k < tracks_.size(); ++k) {
      const double d = std::hypot(p.x - tracks_[k].x, p.y - tracks_[k].y);
      if (!taken[k] && d <= best_d) best = k, best_d = d;
    }
    if (best == tracks_.size()) {
      started.push_back(Neighbour{next_id_++, p.x, p.y, 0.0, 0.0, p.radius, time});
      continue;
    }
    Neighbour& t = tracks_[best];
    taken[best] = true;
    const double dt = time - t.seen;
    if (dt > 0) {
      const double a = settings_.smoothing;
      t.vx = (1.0 - a) * t.vx + a * (p.x - t.x) / dt;
      t.vy = (1.0 - a) * t.vy + a * (p.y - t.y) / dt;
    }
    t.x = p.x, t.y = p.y, t.radius = p.radius, t.seen = time;
  }
  tracks_.insert(tracks_.end(), started.begin(), started.end());
}

void NeighbourTracker::save(StateWriter& out) const {
  out.i64(next_id_);
  out.u64(tracks_.size());
  for (const Neighbour& t : tracks_) {
    out.i64(t.id);
    for (const double v : {t.x, t.y, t.vx, t.vy, t.radius, t.seen}) out.f64(v);
  }
}

void NeighbourTracker::load(StateReader& in) {
  const std::int64_t next = in.i64();
  if (next < 1 || next > std::numeric_limits<int>::max()) in.fail("a track number out of range");
  std::vector<Neighbour> tracks(in.count(56, "tracks"));
  for (Neighbour& t : tracks) {
    const std::int64_t id = in.i64();
    if (id < 1 || id >= next) in.fail("a track number out of range");
    t.id = static_cast<int>(id);
    for (double* v : {&t.x, &t.y, &t.vx, &t.vy, &t.radius, &t.seen}) {
      *v = in.f64();
      if (!std::isfinite(*v)) in.fail("a track that is not finite");
    }
  }
  tracks_ = std::move(tracks);
  next_id_ = static_cast<int>(next);
}

}  // namespace vwg::platform
