// Optimal reciprocal collision avoidance (van den Berg, Guy, Lin and Manocha, "Reciprocal n-Body Collision
// Avoidance", ISRR 2009): the velocity nearest a preferred one that keeps a robot clear of its neighbours for
// a time horizon, each neighbour taking its share of the avoiding.
//
// For a neighbour at p (relative position) with relative velocity v and combined radius R, the velocity
// obstacle truncated at τ is the cone of velocities that collide within τ, cut by the circle of centre p/τ
// and radius R/τ. u is the smallest change of v that leaves it; the robot takes `share` of it (½ when the
// neighbour avoids too, 1 for one that does not), which gives the half-plane of allowed velocities
// {v' : (v' − (v_A + share·u))·û ≥ 0}. The new velocity is the point of all half-planes and the speed disc
// nearest the preferred velocity (a 2-D linear program, its constraints in the neighbours' order); when they
// leave nothing, the velocity that least violates the neighbours' half-planes (a 3-D linear program).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace vwg::robot::orca {

struct Vec2 {
  double x = 0.0, y = 0.0;
};

/// A directed line: the allowed velocities are on its left (det(direction, point − v) ≤ 0).
struct Line {
  Vec2 point, direction;
};

/// What the robot knows of another: its position and velocity relative to the world, its radius, and the share
/// of the avoiding the robot takes (½: it avoids too; 1: it does not, a static obstacle or a person).
struct Neighbour {
  Vec2 position, velocity;
  double radius = 0.0;
  double share = 0.5;
};

struct Agent {
  Vec2 position, velocity;
  double radius = 0.0;
  double max_speed = 0.0;
};

/// The half-plane of velocities `agent` may take to stay clear of `other` for `horizon` seconds; when they
/// already overlap, to be apart within `step` seconds.
Line half_plane(const Agent& agent, const Neighbour& other, double horizon, double step);

/// The velocity within max_speed nearest `preferred` in every half-plane; when none is in all of them, the one
/// whose largest violation of a half-plane is least. Deterministic: the lines are taken in their order.
Vec2 solve(std::span<const Line> lines, double max_speed, Vec2 preferred);

/// half_plane for each neighbour in order, then solve.
Vec2 new_velocity(const Agent& agent, std::span<const Neighbour> neighbours, Vec2 preferred, double horizon,
                  double step);

}  // namespace vwg::robot::orca
