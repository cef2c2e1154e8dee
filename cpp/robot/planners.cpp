#include "vwg/robot/planners.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vwg/error.hpp"
#include "vwg/plan/astar.hpp"
#include "robot/segment_cells.hpp"
#include "vwg/geometry/clearance_field.hpp"
#include "vwg/plan/ompl_planner.hpp"

namespace vwg::robot {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

geometry::Cell cell_at(const geometry::MapGeometry& g, double x, double y) {
  int row, col;
  if (!g.cell_of(x, y, row, col)) return {-1, -1};
  return {row, col};
}

std::vector<double> to_world(const geometry::MapGeometry& g, const plan::GridPath& path, double start_x, double start_y,
                             double goal_x, double goal_y) {
  // The robot's own position first, the cells' centres, then the goal point itself.
  std::vector<double> xy{start_x, start_y};
  for (std::size_t i = 1; i + 1 < path.cells.size(); ++i) {
    double x, y;
    g.centre_of(path.cells[i].row, path.cells[i].col, x, y);
    xy.push_back(x);
    xy.push_back(y);
  }
  xy.push_back(goal_x);
  xy.push_back(goal_y);
  return xy;
}

}  // namespace

geometry::Cell nearest_free(const geometry::BlockedGrid& grid, geometry::Cell cell, int reach) {
  if (grid.inside(cell) && !grid.blocked(cell)) return cell;
  for (int d = 1; d <= reach; ++d) {
    geometry::Cell best{-1, -1};
    double best_dist = std::numeric_limits<double>::infinity();
    for (int dr = -d; dr <= d; ++dr) {
      for (int dc = -d; dc <= d; ++dc) {
        if (std::max(std::abs(dr), std::abs(dc)) != d) continue;  // the ring at distance d
        const geometry::Cell c{cell.row + dr, cell.col + dc};
        if (!grid.inside(c) || grid.blocked(c)) continue;
        const double dist = std::hypot(dr, dc);
        if (dist < best_dist) {
          best_dist = dist;
          best = c;
        }
      }
    }
    if (best.row >= 0) return best;
  }
  return {-1, -1};
}

namespace {

/// The path was planned for the centre of the robot: it is checked with a slightly smaller disc, so
/// that the cell-centre path's corners (inside the clearance by construction) do not count.
double path_check_radius(const DecisionInput& in) { return 0.9 * in.radius; }

bool path_segment_clear(const DecisionInput& in, std::span<const double> path, std::size_t i, double radius) {
  return segment_clear(*in.map, *in.geometry, path[2 * i], path[2 * i + 1], path[2 * i + 2], path[2 * i + 3], radius);
}

}  // namespace

bool path_clear(const DecisionInput& in, std::span<const double> path) {
  const std::size_t n = path.size() / 2;
  if (n < 2) return false;
  const double r = path_check_radius(in);
  for (std::size_t i = nearest_path_point(path, in.pose.x, in.pose.y); i + 1 < n; ++i) {
    if (!path_segment_clear(in, path, i, r)) return false;
  }
  return true;
}

bool ClearPathMemo::clear(const DecisionInput& in) {
  const std::span<const double> path = in.path;
  checked_ = 0;
  const std::size_t n = path.size() / 2;
  if (n < 2) {
    path_.reset();
    return false;
  }
  const geometry::MapGeometry& g = *in.geometry;
  const double radius = path_check_radius(in);
  // The cells written since the last answer that are obstacles now: only they can block a segment found clear.
  // Past a few hundred, testing each segment against them costs more than checking it.
  constexpr std::size_t kMostFollowed = 256;
  thread_local std::vector<geometry::Cell> obstacles;
  obstacles.clear();
  bool follow = path_ != nullptr && path_ == in.path_owner && radius == radius_;
  if (follow) {
    const auto cells = in.map->view<std::int16_t>();
    follow = in.map->written_since(map_, [&](std::size_t k) {
      if (is_obstacle(cells[k])) obstacles.push_back({static_cast<int>(k / g.width), static_cast<int>(k % g.width)});
    });
    follow = follow && obstacles.size() <= kMostFollowed;
  }
  bool clear = true;
  const std::size_t from = nearest_path_point(path, in.pose.x, in.pose.y);
  for (std::size_t i = from; clear && i + 1 < n; ++i) {
    if (follow && i >= from_) {
      const geometry::CellWindow looked_at =
          segment_clear_window(g, path[2 * i], path[2 * i + 1], path[2 * i + 2], path[2 * i + 3], radius);
      if (std::none_of(obstacles.begin(), obstacles.end(), [&](geometry::Cell c) { return looked_at.holds(c.row, c.col); })) {
        continue;
      }
    }
    ++checked_;
    clear = path_segment_clear(in, path, i, radius);
  }
  if (!clear) {
    path_.reset();
    return false;
  }
  path_ = in.path_owner;
  map_ = in.map->mark();
  from_ = from;
  radius_ = radius;
  return true;
}

void NoWayMemo::learn(const geometry::BlockedGrid& grid, geometry::Cell start) {
  known_ = false;
  if (!grid.inside(start) || grid.blocked(start)) return;
  rows_ = grid.rows(), cols_ = grid.cols();
  const std::uint8_t* blocked = grid.padded().data();
  const std::int32_t stride = grid.stride();
  const std::size_t nodes = grid.padded().size();
  side_.assign((nodes + 63) / 64, 0);
  border_.clear();
  thread_local std::vector<std::int32_t> stack;  // the flood's work list (a side can be most of the map)
  stack.clear();
  auto visit = [&](std::int32_t node) {
    if (blocked[node]) {
      // The padding round the map is blocked for good: only cells of the map can open.
      const std::int32_t row = node / stride - 1, col = node % stride - 1;
      if (row >= 0 && col >= 0 && row < rows_ && col < cols_) border_.push_back(node);
      return;
    }
    if (inside(node)) return;
    side_[node >> 6] |= std::uint64_t{1} << (node & 63);
    stack.push_back(node);
  };
  visit(grid.index(start));
  while (!stack.empty()) {
    const std::int32_t node = stack.back();
    stack.pop_back();
    for (const std::int32_t d : {1, -1, stride, -stride}) visit(node + d);
  }
  std::sort(border_.begin(), border_.end());
  border_.erase(std::unique(border_.begin(), border_.end()), border_.end());
  known_ = true;
}

bool NoWayMemo::shut(const geometry::BlockedGrid& grid, geometry::Cell start, geometry::Cell goal) const {
  if (!known_ || grid.rows() != rows_ || grid.cols() != cols_) return false;
  if (!grid.inside(start) || !grid.inside(goal) || !inside(grid.index(start)) || inside(grid.index(goal))) return false;
  const std::uint8_t* blocked = grid.padded().data();
  for (const std::int32_t node : border_) {
    if (!blocked[node]) return false;  // a way may have opened there
  }
  return true;
}

void NoWayMemo::save(StateWriter& out) const {
  out.boolean(known_);
  out.i64(rows_);
  out.i64(cols_);
  out.pods(side_);
  out.pods(border_);
}

void NoWayMemo::load(StateReader& in) {
  NoWayMemo m;
  m.known_ = in.boolean();
  const std::int64_t rows = in.i64(), cols = in.i64();
  m.side_ = in.pods<std::uint64_t>();
  m.border_ = in.pods<std::int32_t>();
  if (rows < 0 || cols < 0 || rows > (1 << 30) || cols > (1 << 30)) in.fail("a memo of a grid of impossible size");
  m.rows_ = static_cast<int>(rows), m.cols_ = static_cast<int>(cols);
  const std::uint64_t nodes = static_cast<std::uint64_t>(rows + 2) * static_cast<std::uint64_t>(cols + 2);
  if (m.known_ && m.side_.size() != (nodes + 63) / 64) in.fail("a memo whose side is not the size of its grid");
  for (const std::int32_t node : m.border_) {
    if (node < 0 || static_cast<std::uint64_t>(node) >= nodes) in.fail("a memo with a cell outside its grid");
  }
  *this = std::move(m);
}

GridDecider::GridDecider(Algorithm algorithm, plan::Heuristic heuristic) : algorithm_(algorithm) {
  options_.heuristic = heuristic;
  plan::validate(options_);
  if (algorithm == Algorithm::DStarLite && heuristic != plan::Heuristic::Euclidean)
    throw SchemaError("heuristic", "D* Lite's decider keeps its own heuristic (euclidean), not " +
                                       std::string(plan::heuristic_name(heuristic)));
}

std::string GridDecider::name() const {
  const std::string base = algorithm_ == Algorithm::AStar ? "astar" : algorithm_ == Algorithm::DStarLite ? "dstar" : "jps";
  return options_.heuristic == plan::Heuristic::Euclidean ? base : base + "-" + std::string(plan::heuristic_name(options_.heuristic));
}

double GridDecider::search_seconds() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return stats_.seconds;
}

std::size_t GridDecider::searches() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return stats_.searches;
}

void GridDecider::save_state(StateWriter& out) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  out.text(name());
  out.u64(robots_.size());
  for (const auto& [robot, s] : robots_) {
    out.i64(robot);
    s.map.save(out);
    out.boolean(s.dstar.has_value());
    if (s.dstar) s.dstar->save(out);
    out.i64(s.goal.row);
    out.i64(s.goal.col);
    s.no_way.save(out);
  }
}

void GridDecider::load_state(StateReader& in) {
  if (const std::string saved = in.text(); saved != name()) in.fail("saved by the decider " + saved + ", not " + name());
  std::map<std::int64_t, RobotState> robots;
  for (std::size_t n = in.count(1, "robots"); n > 0; --n) {
    const std::int64_t robot = in.i64();
    RobotState& s = robots.try_emplace(robot, robot).first->second;
    s.map.load(in);
    if (in.boolean()) s.dstar.emplace(plan::DStarLite::load(in));
    const std::int64_t row = in.i64(), col = in.i64();
    if (row < -1 || col < -1 || row > (1 << 30) || col > (1 << 30)) in.fail("a goal cell out of range");
    s.goal = {static_cast<int>(row), static_cast<int>(col)};
    s.no_way.load(in);
  }
  in.end();
  const std::lock_guard<std::mutex> lock(mutex_);
  robots_ = std::move(robots);
}

GridDecider::RobotState& GridDecider::state_of(std::int64_t robot) {
  const std::lock_guard<std::mutex> lock(mutex_);
  return robots_.try_emplace(robot, robot).first->second;
}

plan::GridPath GridDecider::search(RobotState& s, geometry::Cell start, geometry::Cell goal) {
  const auto t0 = Clock::now();
  plan::GridPath path;
  if (algorithm_ == Algorithm::AStar) {
    // One A* per thread, kept for every search: its node arrays (the size of the map) are made
    // once, not per search (they stay until the thread ends).
    thread_local plan::AStar astar;
    path = astar.search(s.map.inflated(), start, goal, options_);
  } else if (algorithm_ == Algorithm::JumpPoint) {
    thread_local plan::JumpPointSearch jps;  // as A*'s: one per thread
    path = jps.search(s.map.inflated(), start, goal, options_);
  } else {
    if (!s.dstar || !(s.goal == goal) || s.dstar->grid().rows() != s.map.inflated().rows()) {
      s.dstar.emplace(s.map.inflated(), start, goal);
    } else {
      // Tell D* Lite which cells differ from the grid it knows, both ways (also what changed while
      // the robot kept its plan): its repair touches only what they affect.
      const geometry::BlockedGrid& known = s.dstar->grid();
      std::vector<geometry::Cell> now_blocked, now_free;
      for (int r = 0; r < s.map.inflated().rows(); ++r) {
        for (int c = 0; c < s.map.inflated().cols(); ++c) {
          const bool was = known.blocked({r, c}), is = s.map.inflated().blocked({r, c});
          if (is && !was) now_blocked.push_back({r, c});
          if (!is && was) now_free.push_back({r, c});
        }
      }
      s.dstar->update_cells(now_blocked, true);
      s.dstar->update_cells(now_free, false);
      s.dstar->move_to(start);
    }
    path = s.dstar->path();
  }
  s.goal = goal;
  const double seconds = seconds_since(t0);
  const std::lock_guard<std::mutex> lock(mutex_);
  stats_.seconds += seconds;
  ++stats_.searches;
  return path;
}

Decision GridDecider::decide(const DecisionInput& in) {
  const geometry::MapGeometry& g = *in.geometry;
  RobotState& s = state_of(in.robot);
  const bool changed = s.map.update(*in.map, g, in.radius);
  Decision d;
  // Keep the plan while it is still clear and still leads to this goal.
  const std::size_t n = in.path.size() / 2;
  const bool same_goal = n >= 2 && std::hypot(in.path[2 * n - 2] - in.goal_x, in.path[2 * n - 1] - in.goal_y) < 1e-9;
  if (same_goal && (!changed || s.clear_path.clear(in)) && follow_path(in, in.path, d)) {
    d.keep_path = true;
    return d;
  }
  const int reach = static_cast<int>(std::ceil(in.radius / g.resolution)) + 2;
  const geometry::Cell start = nearest_free(s.map.inflated(), cell_at(g, in.pose.x, in.pose.y), reach);
  const geometry::Cell goal = nearest_free(s.map.inflated(), cell_at(g, in.goal_x, in.goal_y), reach);
  if (start.row < 0 || goal.row < 0) {
    d.kind = Decision::Kind::NoPath;
    return d;
  }
  d.replanned = n >= 2;  // there was a plan, and it no longer served
  if (s.no_way.shut(s.map.inflated(), start, goal)) {
    d.kind = Decision::Kind::NoPath;  // as a search would find (see NoWayMemo)
    return d;
  }
  const plan::GridPath path = search(s, start, goal);
  if (!path.found()) {
    s.no_way.learn(s.map.inflated(), start);
    d.kind = Decision::Kind::NoPath;
    return d;
  }
  s.no_way.forget();
  d.path = to_world(g, path, in.pose.x, in.pose.y, in.goal_x, in.goal_y);
  DecisionInput along = in;
  if (!follow_path(along, d.path, d)) {
    // The robot stands inside the clearance (pushed against something): take the first cell.
    const double x = d.path.size() >= 4 ? d.path[2] : in.goal_x, y = d.path.size() >= 4 ? d.path[3] : in.goal_y;
    d.turn = geometry::wrap_angle(std::atan2(y - in.pose.y, x - in.pose.x) - in.pose.theta);
    d.distance = std::min(std::hypot(x - in.pose.x, y - in.pose.y), in.step_length);
  }
  return d;
}

OmplDecider::OmplDecider(std::string planner, unsigned iterations) : planner_(std::move(planner)), iterations_(iterations) {
  bool known = false;
  for (const auto& name : plan::OmplGridPlanner::planner_names()) known |= name == planner_;
  if (!known) {
    std::string names;
    for (const auto& name : plan::OmplGridPlanner::planner_names()) names += (names.empty() ? "" : ", ") + name;
    throw SchemaError("planner", "unknown OMPL planner '" + planner_ + "' (known: " + names + ")");
  }
  if (planner_ == "PRM" || planner_ == "PRMstar") {
    throw SchemaError("planner", planner_ + " grows its roadmap on a second thread, so its plans are not reproducible; "
                                 "use LazyPRM (single-threaded)");
  }
  if (iterations_ == 0) throw SchemaError("iterations", "expected an iteration budget > 0");
}

void OmplDecider::save_state(StateWriter& out) const {
  out.text(planner_);
  out.u64(maps_.size());
  for (const auto& [robot, map] : maps_) {
    out.i64(robot);
    map.save(out);
  }
}

void OmplDecider::load_state(StateReader& in) {
  if (const std::string saved = in.text(); saved != planner_) in.fail("saved by the decider " + saved + ", not " + planner_);
  std::map<std::int64_t, PlanningMap> maps;
  for (std::size_t n = in.count(1, "robots"); n > 0; --n) {
    const std::int64_t robot = in.i64();
    maps.try_emplace(robot, robot).first->second.load(in);
  }
  in.end();
  maps_ = std::move(maps);
}

Decision OmplDecider::decide(const DecisionInput& in) {
  const geometry::MapGeometry& g = *in.geometry;
  PlanningMap& m = maps_.try_emplace(in.robot, in.robot).first->second;
  const bool changed = m.update(*in.map, g, in.radius);
  Decision d;
  const std::size_t n = in.path.size() / 2;
  const bool same_goal = n >= 2 && std::hypot(in.path[2 * n - 2] - in.goal_x, in.path[2 * n - 1] - in.goal_y) < 1e-9;
  if (same_goal && (!changed || path_clear(in, in.path)) && follow_path(in, in.path, d)) {
    d.keep_path = true;
    return d;
  }
  const auto t0 = Clock::now();
  plan::OmplGridPlanner planner(m.obstacles(), g.resolution, g.origin, in.radius);
  plan::OmplOptions options;
  options.planner = planner_;
  options.time_limit = 0.0;  // iterations alone: no wall clock inside a frame's decision
  options.iterations = iterations_;
  options.seed = static_cast<std::uint32_t>(in.seed & 0xFFFFFFFFu);
  plan::OmplPlan plan;
  try {
    plan = planner.plan(in.pose, geometry::Pose2{in.goal_x, in.goal_y, 0.0}, options);
  } catch (const SchemaError&) {
    // The robot or the goal does not fit where it is (pushed against something): no path now.
  }
  stats_.seconds += seconds_since(t0);
  ++stats_.searches;
  d.replanned = n >= 2;
  if (!plan.solved) {
    d.kind = Decision::Kind::NoPath;
    return d;
  }
  for (const auto& p : plan.waypoints) {
    d.path.push_back(p.x);
    d.path.push_back(p.y);
  }
  if (!follow_path(in, d.path, d)) d.kind = Decision::Kind::NoPath;
  return d;
}

}  // namespace vwg::robot
