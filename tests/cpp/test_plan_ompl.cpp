// The exact collision test of a disc robot (geometry::ClearanceField) against brute force, and the OMPL
// planners on a MovingAI map: paths reach the goal, never come within the robot's radius of a
// blocked cell (checked densely along every segment), and repeat for the same seed.
#include <gtest/gtest.h>

#include "vwg/random.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "vwg/error.hpp"
#include "vwg/geometry/clearance_field.hpp"
#include "vwg/plan/movingai.hpp"
#include "vwg/plan/ompl_planner.hpp"

using namespace vwg::plan;
namespace geometry = vwg::geometry;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::filesystem::path movingai_dir() {
  if (const char* dir = std::getenv("VWG_TEST_DATA")) return std::filesystem::path(dir) / "movingai";
  return std::filesystem::path(__FILE__).parent_path().parent_path() / "data" / "movingai";
}

std::vector<Cell> blocked_cells(const BlockedGrid& g) {
  std::vector<Cell> out;
  for (int r = 0; r < g.rows(); ++r) {
    for (int c = 0; c < g.cols(); ++c) {
      if (g.blocked({r, c})) out.push_back({r, c});
    }
  }
  return out;
}

/// Brute force: distance (cells) from (u, v) to the nearest of the blocked squares `cells` of
/// `g`, and to the map's edge when `edge`.
double brute_clearance(const BlockedGrid& g, const std::vector<Cell>& cells, double u, double v, bool edge) {
  double best = kInf;
  for (const Cell& cell : cells) {
    const double du = std::max({cell.col - u, 0.0, u - (cell.col + 1)});
    const double dv = std::max({cell.row - v, 0.0, v - (cell.row + 1)});
    best = std::min(best, du * du + dv * dv);
  }
  best = std::sqrt(best);
  if (edge) best = std::min(best, std::max(0.0, std::min({u, g.cols() - u, v, g.rows() - v})));
  return best;
}

BlockedGrid random_grid(std::mt19937& rng, int rows, int cols, double density) {
  BlockedGrid g(rows, cols);
  std::bernoulli_distribution wall(density);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) g.set_blocked({r, c}, wall(rng));
  }
  return g;
}

/// A MovingAI map with its rows flipped, so that row 0 is the bottom row as the planner expects.
BlockedGrid bottom_up(const MovingAiMap& map) {
  BlockedGrid g(map.height, map.width);
  for (int r = 0; r < map.height; ++r) {
    for (int c = 0; c < map.width; ++c) g.set_blocked({map.height - 1 - r, c}, map.grid.blocked({r, c}));
  }
  return g;
}

template <class F>
std::string schema_field(F&& f) {
  try {
    f();
  } catch (const vwg::SchemaError& e) {
    return e.field();
  }
  return "<no SchemaError>";
}

}  // namespace

// --- the exact collision test ---

TEST(Clearance, CellBoundsPointsAndSegmentsAgreeWithBruteForce) {
  std::mt19937 rng(11);
  int segments = 0, clear = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int rows = 3 + static_cast<int>(rng() % 30), cols = 3 + static_cast<int>(rng() % 30);
    const BlockedGrid g = random_grid(rng, rows, cols, 0.03 + 0.1 * (trial % 3));
    const std::vector<Cell> cells = blocked_cells(g);
    const bool edge = trial % 2 == 0;
    const geometry::ClearanceField field(g, edge);
    // The cell bound is the square-to-square distance to the nearest blocked cell.
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        double want = kInf;
        for (int r2 = 0; r2 < rows; ++r2) {
          for (int c2 = 0; c2 < cols; ++c2) {
            if (g.blocked({r2, c2})) {
              want = std::min(want, std::hypot(std::max(0, std::abs(r2 - r) - 1), std::max(0, std::abs(c2 - c) - 1)));
            }
          }
        }
        if (std::isinf(want)) EXPECT_TRUE(std::isinf(field.cell_clearance({r, c})));
        else EXPECT_NEAR(field.cell_clearance({r, c}), want, 1e-9);
      }
    }
    std::uniform_real_distribution<double> u_of(-1.0, cols + 1.0), v_of(-1.0, rows + 1.0);
    for (int k = 0; k < 100; ++k) {
      const double u = u_of(rng), v = v_of(rng), cap = 0.5 + 0.1 * (rng() % 80);
      const bool off = u < 0 || v < 0 || u > cols || v > rows;
      if (!edge && off) continue;  // without the edge, points off the map have no defined answer
      ASSERT_NEAR(field.clearance(u, v, cap), std::min(brute_clearance(g, cells, u, v, edge), cap), 1e-9);
      // A segment is clear iff its distance to every blocked square (and, with the edge, both ends'
      // distance to the edge) exceeds the radius; that distance by dense sampling.
      const double u1 = u_of(rng), v1 = v_of(rng), radius = 0.1 * (rng() % 25);
      if (!edge && (u1 < 0 || v1 < 0 || u1 > cols || v1 > rows)) continue;
      double nearest = kInf;
      const int n = 2000;
      for (int i = 0; i <= n; ++i) {
        const double t = static_cast<double>(i) / n;
        nearest = std::min(nearest, brute_clearance(g, cells, u + t * (u1 - u), v + t * (v1 - v), edge));
      }
      const bool want = nearest > radius;
      const double sample_step = std::hypot(u1 - u, v1 - v) / n;
      if (std::abs(nearest - radius) <= sample_step) continue;  // too close to call by sampling
      ++segments;
      clear += want;
      ASSERT_EQ(field.segment_clear(u, v, u1, v1, radius), want)
          << "(" << u << ", " << v << ") - (" << u1 << ", " << v1 << ") radius " << radius;
    }
  }
  EXPECT_GT(segments, 2000);
  EXPECT_GT(clear, 100);  // both outcomes were exercised
}

TEST(Clearance, HandWorked) {
  // One blocked cell (1, 1) in a 3 × 3 grid, no edge.
  BlockedGrid g(3, 3);
  g.set_blocked({1, 1}, true);
  const geometry::ClearanceField field(g, false);
  EXPECT_DOUBLE_EQ(field.clearance(0.5, 0.5, 10.0), std::hypot(0.5, 0.5));  // to the corner (1, 1)
  EXPECT_DOUBLE_EQ(field.clearance(1.5, 0.25, 10.0), 0.75);                 // straight below
  EXPECT_DOUBLE_EQ(field.clearance(1.5, 1.5, 10.0), 0.0);                   // inside
  EXPECT_DOUBLE_EQ(field.clearance(0.5, 0.5, 0.1), 0.1);                    // capped
  // Passing under the cell at v = 0.5 stays 0.5 away: clear for 0.4, not for 0.5.
  EXPECT_TRUE(field.segment_clear(0.0, 0.5, 3.0, 0.5, 0.4));
  EXPECT_FALSE(field.segment_clear(0.0, 0.5, 3.0, 0.5, 0.5));
  // A diagonal through the corner region: from (0, 0) to (3, 3) crosses the cell.
  EXPECT_FALSE(field.segment_clear(0.0, 0.0, 3.0, 3.0, 0.0));
  // The inflated grid: centres within 0.5 of the cell are its 4 side neighbours (corners are √2/2 away).
  const BlockedGrid inflated = field.inflated(0.5);
  EXPECT_EQ(inflated.blocked_count(), 5u);
  EXPECT_FALSE(inflated.blocked({0, 0}));
  EXPECT_TRUE(inflated.blocked({0, 1}));
  // With the map's edge as an obstacle, every cell centre is 0.5 from it.
  EXPECT_EQ(geometry::ClearanceField(g, true).inflated(0.5).blocked_count(), 9u);
  EXPECT_EQ(geometry::ClearanceField(g, true).inflated(0.49).blocked_count(), 1u);
}

// --- OMPL ---

class OmplArena : public ::testing::Test {
 protected:
  static constexpr double kResolution = 0.1, kRadius = 0.15;
  void SetUp() override {
    grid_ = bottom_up(read_movingai_map(movingai_dir() / "arena.map"));
    cells_ = blocked_cells(grid_);
    planner_ = std::make_unique<OmplGridPlanner>(grid_, kResolution, vwg::geometry::Pose2{-1.0, 2.0, 0.3}, kRadius);
  }

  /// Free cell centres (with a margin beyond the radius), as poses with random headings.
  std::vector<vwg::geometry::Pose2> free_poses(int count, unsigned seed) const {
    std::mt19937 rng(seed);
    std::vector<vwg::geometry::Pose2> out;
    while (static_cast<int>(out.size()) < count) {
      const int r = static_cast<int>(rng() % grid_.rows()), c = static_cast<int>(rng() % grid_.cols());
      if (brute_clearance(grid_, cells_, c + 0.5, r + 0.5, true) <= kRadius / kResolution + 0.3) continue;
      vwg::geometry::Pose2 p;
      planner_->grid_to_world(c + 0.5, r + 0.5, p.x, p.y);
      p.theta = std::uniform_real_distribution<double>(-3.0, 3.0)(rng);
      out.push_back(p);
    }
    return out;
  }

  /// Every point along every segment, every 0.01 cell, is farther than the radius from every
  /// blocked cell and the map's edge (brute force over the whole map).
  void expect_clear(const OmplPlan& plan) const {
    const double radius = kRadius / kResolution;
    for (std::size_t i = 1; i < plan.waypoints.size(); ++i) {
      double u0 = 0, v0 = 0, u1 = 0, v1 = 0;
      planner_->world_to_grid(plan.waypoints[i - 1].x, plan.waypoints[i - 1].y, u0, v0);
      planner_->world_to_grid(plan.waypoints[i].x, plan.waypoints[i].y, u1, v1);
      const int n = std::max(1, static_cast<int>(std::ceil(std::hypot(u1 - u0, v1 - v0) / 0.01)));
      for (int k = 0; k <= n; ++k) {
        const double t = static_cast<double>(k) / n;
        const double d = brute_clearance(grid_, cells_, u0 + t * (u1 - u0), v0 + t * (v1 - v0), true);
        ASSERT_GT(d, radius - 1e-9) << "segment " << i << " at t = " << t;
      }
    }
  }

  BlockedGrid grid_;
  std::vector<Cell> cells_;
  std::unique_ptr<OmplGridPlanner> planner_;
};

TEST_F(OmplArena, PlannersReachTheGoalWithoutTouchingObstacles) {
  const auto poses = free_poses(8, 1);
  for (const char* name : {"RRTConnect", "RRTstar", "PRM"}) {
    for (std::size_t i = 0; i + 1 < poses.size(); i += 2) {
      OmplOptions o;
      o.planner = name;
      o.time_limit = 5.0;
      o.iterations = 1500;  // RRT* would otherwise use all of the time limit
      o.seed = 5;
      const OmplPlan plan = planner_->plan(poses[i], poses[i + 1], o);
      ASSERT_TRUE(plan.solved) << name << ": " << plan.status;
      EXPECT_EQ(plan.status, "exact solution");
      EXPECT_EQ(plan.planner, name);
      ASSERT_GE(plan.waypoints.size(), 2u);
      EXPECT_NEAR(plan.waypoints.front().x, poses[i].x, 1e-9);
      EXPECT_NEAR(plan.waypoints.front().y, poses[i].y, 1e-9);
      EXPECT_NEAR(plan.waypoints.back().x, poses[i + 1].x, 1e-9);
      EXPECT_NEAR(plan.waypoints.back().y, poses[i + 1].y, 1e-9);
      EXPECT_NEAR(std::remainder(plan.waypoints.back().theta - poses[i + 1].theta, 2 * std::numbers::pi), 0.0, 1e-9);
      double length = 0.0;
      for (std::size_t k = 1; k < plan.waypoints.size(); ++k) {
        const double step = std::hypot(plan.waypoints[k].x - plan.waypoints[k - 1].x,
                                       plan.waypoints[k].y - plan.waypoints[k - 1].y);
        EXPECT_LE(step, kResolution + 1e-9);  // waypoints one cell apart at most, by default
        length += step;
      }
      EXPECT_NEAR(plan.length, length, 1e-9);
      EXPECT_GE(plan.length, std::hypot(poses[i + 1].x - poses[i].x, poses[i + 1].y - poses[i].y) - 1e-9);
      expect_clear(plan);
    }
  }
}

TEST_F(OmplArena, SameSeedSamePath) {
  // Two poses that do not see each other, so that the simplified paths depend on the samples.
  std::vector<vwg::geometry::Pose2> poses;
  for (unsigned seed = 2; poses.empty(); ++seed) {
    poses = free_poses(2, seed);
    if (planner_->motion_valid(poses[0].x, poses[0].y, poses[1].x, poses[1].y)) poses.clear();
  }
  OmplOptions o;
  o.seed = 11;
  const OmplPlan a = planner_->plan(poses[0], poses[1], o);
  const OmplPlan b = planner_->plan(poses[0], poses[1], o);
  o.seed = 12;
  const OmplPlan c = planner_->plan(poses[0], poses[1], o);
  ASSERT_TRUE(a.solved && b.solved && c.solved);
  auto same = [](const OmplPlan& x, const OmplPlan& y) {
    if (x.waypoints.size() != y.waypoints.size()) return false;
    for (std::size_t i = 0; i < x.waypoints.size(); ++i) {
      if (x.waypoints[i].x != y.waypoints[i].x || x.waypoints[i].y != y.waypoints[i].y ||
          x.waypoints[i].theta != y.waypoints[i].theta) {
        return false;
      }
    }
    return true;
  };
  EXPECT_TRUE(same(a, b));
  EXPECT_FALSE(same(a, c));
  // RRT* runs until stopped: with an iteration budget instead of the clock it repeats as well.
  OmplOptions star;
  star.planner = "RRTstar";
  star.time_limit = 30.0;
  star.iterations = 2000;
  star.seed = 3;
  const OmplPlan d = planner_->plan(poses[0], poses[1], star);
  const OmplPlan e = planner_->plan(poses[0], poses[1], star);
  ASSERT_TRUE(d.solved) << d.status;
  EXPECT_LT(d.plan_time, 30.0);
  EXPECT_TRUE(same(d, e));
}

TEST_F(OmplArena, FailuresAndBadInput) {
  const auto poses = free_poses(2, 3);
  // A goal in a wall, or off the map: a failed plan, not an exception.
  for (const vwg::geometry::Pose2& goal : {vwg::geometry::Pose2{1e3, 1e3, 0.0}, [&] {
         vwg::geometry::Pose2 p;
         for (int r = 0; r < grid_.rows(); ++r) {
           if (grid_.blocked({r, 20})) planner_->grid_to_world(20.5, r + 0.5, p.x, p.y);
         }
         return p;
       }()}) {
    const OmplPlan plan = planner_->plan(poses[0], goal);
    EXPECT_FALSE(plan.solved);
    EXPECT_EQ(plan.status.rfind("invalid goal", 0), 0u) << plan.status;
    EXPECT_TRUE(plan.waypoints.empty());
    EXPECT_EQ(plan.length, kInf);
  }
  EXPECT_EQ(schema_field([&] { planner_->plan({1e3, 0.0, 0.0}, poses[1]); }), "start_pose");
  EXPECT_EQ(schema_field([&] { planner_->plan({std::nan(""), 0.0, 0.0}, poses[1]); }), "start_pose");
  OmplOptions bad;
  bad.planner = "RRTsharper";
  EXPECT_EQ(schema_field([&] { planner_->plan(poses[0], poses[1], bad); }), "planner");
  bad = OmplOptions{};
  bad.time_limit = -1.0;
  EXPECT_EQ(schema_field([&] { planner_->plan(poses[0], poses[1], bad); }), "time_limit");
  EXPECT_EQ(schema_field([&] { OmplGridPlanner(grid_, 0.0, {}, 0.1); }), "resolution");
  EXPECT_EQ(schema_field([&] { OmplGridPlanner(grid_, 0.1, {}, -0.1); }), "robot_radius");
  const auto names = OmplGridPlanner::planner_names();
  for (const char* name : {"RRTConnect", "RRTstar", "PRM"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  }
}

TEST(Ompl, EnclosedGoalTimesOut) {
  BlockedGrid g(40, 40);
  for (int k = 20; k <= 30; ++k) {
    g.set_blocked({k, 20}, true);
    g.set_blocked({k, 30}, true);
    g.set_blocked({20, k}, true);
    g.set_blocked({30, k}, true);
  }
  OmplOptions o;
  o.time_limit = 0.2;
  const OmplPlan plan = plan_ompl(g, 0.1, {}, {0.5, 0.5, 0.0}, {2.5, 2.5, 0.0}, 0.05, o);
  EXPECT_FALSE(plan.solved);
  // RRTConnect reports the state nearest the goal as an approximate solution; that is no path.
  EXPECT_TRUE(plan.status == "timeout" || plan.status == "approximate solution") << plan.status;
  EXPECT_TRUE(plan.waypoints.empty());
  EXPECT_EQ(plan.length, kInf);
}

namespace {

/// Plans from the ends of the longest scenarios of a MovingAI map (those where the robot fits) with
/// RRTConnect, RRT* and PRM, and prints the times.
void time_planners(const std::string& name, double resolution, double radius, double time_limit) {
  const MovingAiMap map = read_movingai_map(movingai_dir() / (name + ".map"));
  const auto scenarios = read_movingai_scenarios(movingai_dir() / (name + ".map.scen"));
  const auto t0 = std::chrono::steady_clock::now();
  const OmplGridPlanner planner(bottom_up(map), resolution, {}, radius);
  const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<std::pair<vwg::geometry::Pose2, vwg::geometry::Pose2>> queries;
  for (auto it = scenarios.rbegin(); it != scenarios.rend() && queries.size() < 5; ++it) {
    auto pose = [&](Cell c) {
      return vwg::geometry::Pose2{(c.col + 0.5) * resolution, (map.height - 1 - c.row + 0.5) * resolution, 0.0};
    };
    const auto s = pose(it->start), g = pose(it->goal);
    if (planner.valid(s.x, s.y) && planner.valid(g.x, g.y)) queries.emplace_back(s, g);
  }
  ASSERT_EQ(queries.size(), 5u);
  std::printf("[ timing   ] OMPL on %s (%dx%d, %.2f m/cell, radius %.2f m, time limit %.1f s): distance transform "
              "%.1f ms\n",
              name.c_str(), map.width, map.height, resolution, radius, time_limit, 1e3 * setup);
  for (const char* planner_name : {"RRTConnect", "RRTstar", "PRM"}) {
    double plan_time = 0.0, simplify_time = 0.0, length = 0.0;
    int solved = 0;
    for (const auto& [s, g] : queries) {
      OmplOptions o;
      o.planner = planner_name;
      o.time_limit = time_limit;
      o.seed = 1;
      const OmplPlan plan = planner.plan(s, g, o);
      plan_time += plan.plan_time;
      simplify_time += plan.simplify_time;
      if (plan.solved) {
        ++solved;
        length += plan.length;
      }
    }
    std::printf("[ timing   ]   %-10s solved %d/5, mean plan %.1f ms, simplify %.1f ms, mean length %.2f m\n",
                planner_name, solved, 1e3 * plan_time / 5, 1e3 * simplify_time / 5, solved ? length / solved : 0.0);
    if (std::string(planner_name) != "RRTstar") {
      EXPECT_GE(solved, 4) << planner_name;
    }
  }
}

}  // namespace

TEST(Ompl, PlanTimes) { time_planners("den312d", 0.1, 0.1, 0.2); }

TEST(Clearance, InflatedEqualsThePerCellClearanceTest) {
  // The stamped inflation against its definition: a cell is blocked when its centre's clearance
  // (exact, map edge included) is at most the radius.
  vwg::Rng rng(11);
  for (int trial = 0; trial < 12; ++trial) {
    const int rows = 20 + static_cast<int>(rng.below(30)), cols = 20 + static_cast<int>(rng.below(30));
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(rows) * cols);
    for (auto& m : mask) m = rng.uniform() < 0.08 ? 1 : 0;
    for (bool outside : {true, false}) {
      vwg::geometry::ClearanceField field(vwg::geometry::BlockedGrid::from_mask(std::span<const std::uint8_t>(mask), rows, cols), outside);
      for (double radius : {0.0, 0.5, 1.3, 2.7, 4.0, 5.2}) {
        const auto inflated = field.inflated(radius);
        for (int r = 0; r < rows; ++r) {
          for (int c = 0; c < cols; ++c) {
            const bool expected = field.clearance(c + 0.5, r + 0.5, radius + 1.0) <= radius;
            ASSERT_EQ(inflated.blocked({r, c}), expected) << "r=" << r << " c=" << c << " radius=" << radius << " outside=" << outside;
          }
        }
      }
    }
  }
}
