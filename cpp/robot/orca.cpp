#include "vwg/robot/orca.hpp"

#include <algorithm>
#include <cmath>

namespace vwg::robot::orca {

namespace {

constexpr double kEpsilon = 1e-9;

Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
double det(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
double norm2(Vec2 a) { return dot(a, a); }
Vec2 unit(Vec2 a) {
  const double n = std::sqrt(norm2(a));
  return n > 0.0 ? (1.0 / n) * a : Vec2{};
}

/// The velocity on line `i` nearest `preferred` (or furthest along `preferred` when it is a direction) that
/// keeps within the speed disc and on the allowed side of lines 0..i−1; false when there is none.
bool on_line(std::span<const Line> lines, std::size_t i, double radius, Vec2 preferred, bool direction, Vec2& result) {
  const Line& line = lines[i];
  const double along = dot(line.point, line.direction);
  const double discriminant = along * along + radius * radius - norm2(line.point);
  if (discriminant < 0.0) return false;  // the line misses the speed disc
  const double root = std::sqrt(discriminant);
  double t_left = -along - root, t_right = -along + root;
  for (std::size_t j = 0; j < i; ++j) {
    const double denominator = det(line.direction, lines[j].direction);
    const double numerator = det(lines[j].direction, line.point - lines[j].point);
    if (std::abs(denominator) <= kEpsilon) {  // parallel lines
      if (numerator < 0.0) return false;      // line i lies wholly outside line j's half-plane
      continue;
    }
    const double t = numerator / denominator;
    if (denominator >= 0.0) {
      t_right = std::min(t_right, t);
    } else {
      t_left = std::max(t_left, t);
    }
    if (t_left > t_right) return false;
  }
  if (direction) {
    result = line.point + (dot(preferred, line.direction) > 0.0 ? t_right : t_left) * line.direction;
  } else {
    const double t = std::clamp(dot(line.direction, preferred - line.point), t_left, t_right);
    result = line.point + t * line.direction;
  }
  return true;
}

/// The 2-D linear program over the lines in order: how many it satisfied (all: lines.size()).
std::size_t program_2d(std::span<const Line> lines, double radius, Vec2 preferred, bool direction, Vec2& result) {
  if (direction) {
    result = radius * preferred;  // `preferred` is a unit direction: the furthest point of the disc along it
  } else if (norm2(preferred) > radius * radius) {
    result = radius * unit(preferred);
  } else {
    result = preferred;
  }
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (det(lines[i].direction, lines[i].point - result) > 0.0) {  // outside line i: the best is on it
      const Vec2 before = result;
      if (!on_line(lines, i, radius, preferred, direction, result)) {
        result = before;
        return i;
      }
    }
  }
  return lines.size();
}

/// From the first line the 2-D program could not satisfy on: the velocity that least violates the lines, each
/// line's violation its distance to the wrong side (a 3-D program solved as 2-D ones on projected lines).
void program_3d(std::span<const Line> lines, std::size_t first_failed, double radius, Vec2& result) {
  double distance = 0.0;
  std::vector<Line> projected;
  for (std::size_t i = first_failed; i < lines.size(); ++i) {
    if (det(lines[i].direction, lines[i].point - result) <= distance) continue;  // violated no more than allowed
    projected.clear();
    for (std::size_t j = 0; j < i; ++j) {
      Line line;
      const double determinant = det(lines[i].direction, lines[j].direction);
      if (std::abs(determinant) <= kEpsilon) {
        if (dot(lines[i].direction, lines[j].direction) > 0.0) continue;  // same direction: line j is no bound here
        line.point = 0.5 * (lines[i].point + lines[j].point);  // opposite: halfway between them
      } else {
        line.point = lines[i].point +
                     (det(lines[j].direction, lines[i].point - lines[j].point) / determinant) * lines[i].direction;
      }
      line.direction = unit(lines[j].direction - lines[i].direction);
      projected.push_back(line);
    }
    const Vec2 before = result;
    // Into line i as far as the others allow: optimise along its inward normal.
    if (program_2d(projected, radius, Vec2{-lines[i].direction.y, lines[i].direction.x}, true, result) < projected.size()) {
      result = before;  // in principle not possible: the result is then as good as it gets (rounding)
    }
    distance = det(lines[i].direction, lines[i].point - result);
  }
}

}  // namespace

Line half_plane(const Agent& agent, const Neighbour& other, double horizon, double step) {
  const Vec2 p = other.position - agent.position;
  const Vec2 v = agent.velocity - other.velocity;
  const double d2 = norm2(p), r = agent.radius + other.radius, r2 = r * r;
  Line line;
  Vec2 u;
  if (d2 > r2) {
    const Vec2 w = v - (1.0 / horizon) * p;  // from the cut-off circle's centre to v
    const double w2 = norm2(w), w_dot_p = dot(w, p);
    if (w_dot_p < 0.0 && w_dot_p * w_dot_p > r2 * w2) {  // nearest the cut-off circle
      const double w_len = std::sqrt(w2);
      const Vec2 w_unit = (1.0 / w_len) * w;
      line.direction = Vec2{w_unit.y, -w_unit.x};
      u = (r / horizon - w_len) * w_unit;
    } else {  // nearest a leg of the cone
      const double leg = std::sqrt(d2 - r2);
      if (det(p, w) > 0.0) {  // the left leg
        line.direction = (1.0 / d2) * Vec2{p.x * leg - p.y * r, p.x * r + p.y * leg};
      } else {  // the right leg (a tie takes this one, so symmetric cases part the same way every run)
        line.direction = (-1.0 / d2) * Vec2{p.x * leg + p.y * r, -p.x * r + p.y * leg};
      }
      u = dot(v, line.direction) * line.direction - v;
    }
  } else {  // already overlapping: apart within one step
    const Vec2 w = v - (1.0 / step) * p;
    const double w_len = std::sqrt(norm2(w));
    const Vec2 w_unit = w_len > 0.0 ? (1.0 / w_len) * w : Vec2{-p.x, -p.y};
    line.direction = Vec2{w_unit.y, -w_unit.x};
    u = (r / step - w_len) * w_unit;
  }
  line.point = agent.velocity + other.share * u;
  return line;
}

Vec2 solve(std::span<const Line> lines, double max_speed, Vec2 preferred) {
  Vec2 result;
  const std::size_t satisfied = program_2d(lines, max_speed, preferred, false, result);
  if (satisfied < lines.size()) program_3d(lines, satisfied, max_speed, result);
  return result;
}

Vec2 new_velocity(const Agent& agent, std::span<const Neighbour> neighbours, Vec2 preferred, double horizon,
                  double step) {
  std::vector<Line> lines;
  lines.reserve(neighbours.size());
  for (const Neighbour& n : neighbours) lines.push_back(half_plane(agent, n, horizon, step));
  return solve(lines, agent.max_speed, preferred);
}

}  // namespace vwg::robot::orca
