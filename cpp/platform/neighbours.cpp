#include "vwg/platform/neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace vwg::platform {

namespace {

struct Piece {
  double x, y, radius;
};

}  // namespace

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
    double sx = px, sy = py, fx = px, fy = py, lx = px, ly = py, far = scan.ranges[i];
    while (j + 1 < n && hit(j + 1)) {
      double qx, qy;
      point(j + 1, qx, qy);
      if (std::hypot(qx - lx, qy - ly) > settings_.jump) break;
      ++j;
      sx += qx, sy += qy, lx = qx, ly = qy;
      far = std::max(far, static_cast<double>(scan.ranges[j]));
    }
    const std::size_t count = j - i + 1;
    const double width = std::hypot(lx - fx, ly - fy);
    const bool left = i == 0 || in_front(i - 1, far), right = j + 1 >= n || in_front(j + 1, far);
    if (count >= 2 && width <= settings_.max_width && left && right) {
      const double mx = sx / static_cast<double>(count), my = sy / static_cast<double>(count);
      const double radius = std::clamp(0.5 * width, settings_.min_radius, settings_.max_radius);
      const double d = std::hypot(mx - pose.x, my - pose.y);
      const double ux = d > 0 ? (mx - pose.x) / d : 0.0, uy = d > 0 ? (my - pose.y) / d : 0.0;
      pieces.push_back({mx + radius * ux, my + radius * uy, radius});
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

}  // namespace vwg::platform
