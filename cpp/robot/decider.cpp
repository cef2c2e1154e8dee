#include "vwg/robot/decider.hpp"

#include <cmath>
#include <limits>

#include "vwg/geometry/pose.hpp"
#include "vwg/random.hpp"

namespace vwg::robot {

Decision RandomDecider::decide(const DecisionInput& in) {
  Rng rng(in.seed);
  Decision d;
  for (int attempt = 0; attempt < 30; ++attempt) {
    const double heading = rng.uniform(-M_PI, M_PI);
    const double distance = rng.uniform(0.3 * in.step_length, in.step_length);
    const double tx = in.pose.x + distance * std::cos(heading), ty = in.pose.y + distance * std::sin(heading);
    if (segment_clear(*in.map, *in.geometry, in.pose.x, in.pose.y, tx, ty, in.radius)) {
      d.turn = geometry::wrap_angle(heading - in.pose.theta);
      d.distance = distance;
      d.path = {in.pose.x, in.pose.y, tx, ty};
      return d;
    }
  }
  // Boxed in: turn on the spot and try again next time.
  d.turn = rng.uniform(-M_PI, M_PI);
  d.path = {in.pose.x, in.pose.y};
  return d;
}

std::size_t nearest_path_point(std::span<const double> path, double x, double y) {
  std::size_t nearest = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < path.size() / 2; ++i) {
    const double dx = path[2 * i] - x, dy = path[2 * i + 1] - y, d2 = dx * dx + dy * dy;
    if (d2 < best) {
      best = d2;
      nearest = i;
    }
  }
  return nearest;
}

bool follow_path(const DecisionInput& in_, std::span<const double> path, Decision& out) {
  const std::size_t n = path.size() / 2;
  if (n == 0) return false;
  DecisionInput in = in_;
  in.radius = move_radius(*in_.map, *in_.geometry, in_.pose.x, in_.pose.y, in_.radius);
  // Start from the path point nearest to the robot, so points already passed are skipped.
  const std::size_t nearest = nearest_path_point(path, in.pose.x, in.pose.y);
  // The farthest point ahead within reach that a straight move gets to without touching anything.
  std::size_t target = n;
  for (std::size_t i = nearest; i < n; ++i) {
    const double px = path[2 * i], py = path[2 * i + 1];
    const double d = std::hypot(px - in.pose.x, py - in.pose.y);
    if (d > in.step_length) break;
    if (d < 1e-6) continue;
    if (!segment_clear(*in.map, *in.geometry, in.pose.x, in.pose.y, px, py, in.radius)) break;
    target = i;
  }
  if (target == n) {
    // Nothing within a step: head straight for the next point if it is clear, however far.
    const std::size_t next = std::min(nearest + 1, n - 1);
    const double px = path[2 * next], py = path[2 * next + 1];
    const double d = std::hypot(px - in.pose.x, py - in.pose.y);
    if (d < 1e-6 || !segment_clear(*in.map, *in.geometry, in.pose.x, in.pose.y, px, py, in.radius)) return false;
    target = next;
  }
  const double px = path[2 * target], py = path[2 * target + 1];
  const double dx = px - in.pose.x, dy = py - in.pose.y;
  const double distance = std::min(std::hypot(dx, dy), in.step_length);
  out.kind = Decision::Kind::Move;
  out.turn = geometry::wrap_angle(std::atan2(dy, dx) - in.pose.theta);
  out.distance = distance;
  return true;
}

void Decider::save_state(StateWriter&) const {
  throw SchemaError("decider " + name(), "cannot be saved: it does not say what it keeps between decisions "
                                         "(override save_state and load_state)");
}

void Decider::load_state(StateReader& in) { in.fail("the decider " + name() + " does not say how to load a state"); }

}  // namespace vwg::robot
