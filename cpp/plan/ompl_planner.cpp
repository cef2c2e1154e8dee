#include "vwg/plan/ompl_planner.hpp"

#include "vwg/log.hpp"

#include <ompl/base/MotionValidator.h>
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/base/terminationconditions/IterationTerminationCondition.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/est/BiEST.h>
#include <ompl/geometric/planners/est/EST.h>
#include <ompl/geometric/planners/fmt/FMT.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/kpiece/BKPIECE1.h>
#include <ompl/geometric/planners/kpiece/KPIECE1.h>
#include <ompl/geometric/planners/kpiece/LBKPIECE1.h>
#include <ompl/geometric/planners/prm/LazyPRM.h>
#include <ompl/geometric/planners/prm/LazyPRMstar.h>
#include <ompl/geometric/planners/prm/PRM.h>
#include <ompl/geometric/planners/prm/PRMstar.h>
#include <ompl/geometric/planners/rrt/BiTRRT.h>
#include <ompl/geometric/planners/rrt/InformedRRTstar.h>
#include <ompl/geometric/planners/rrt/LazyRRT.h>
#include <ompl/geometric/planners/rrt/RRT.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/geometric/planners/rrt/TRRT.h>
#include <ompl/geometric/planners/sbl/SBL.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <mutex>

#include "vwg/error.hpp"

namespace vwg::plan {

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

using PlannerFactory = std::function<ob::PlannerPtr(const ob::SpaceInformationPtr&)>;

template <class P>
PlannerFactory factory() {
  return [](const ob::SpaceInformationPtr& si) -> ob::PlannerPtr { return std::make_shared<P>(si); };
}

/// The planners by name: OMPL's class names, plus "RRT*" and "PRM*" for the starred ones.
const std::map<std::string, PlannerFactory>& planners() {
  static const std::map<std::string, PlannerFactory> table = {
      {"RRTConnect", factory<og::RRTConnect>()},
      {"RRT", factory<og::RRT>()},
      {"RRTstar", factory<og::RRTstar>()},
      {"RRT*", factory<og::RRTstar>()},
      {"InformedRRTstar", factory<og::InformedRRTstar>()},
      // BIT* uses k-nearest neighbours by default, and OMPL warns unless that variant is named kBITstar.
      {"BITstar", [](const ob::SpaceInformationPtr& si) -> ob::PlannerPtr {
         return std::make_shared<og::BITstar>(si, "kBITstar");
       }},
      {"LazyRRT", factory<og::LazyRRT>()},
      {"TRRT", factory<og::TRRT>()},
      {"BiTRRT", factory<og::BiTRRT>()},
      {"PRM", factory<og::PRM>()},
      {"PRMstar", factory<og::PRMstar>()},
      {"PRM*", factory<og::PRMstar>()},
      {"LazyPRM", factory<og::LazyPRM>()},
      {"LazyPRMstar", factory<og::LazyPRMstar>()},
      {"FMT", factory<og::FMT>()},
      {"KPIECE1", factory<og::KPIECE1>()},
      {"BKPIECE1", factory<og::BKPIECE1>()},
      {"LBKPIECE1", factory<og::LBKPIECE1>()},
      {"EST", factory<og::EST>()},
      {"BiEST", factory<og::BiEST>()},
      {"SBL", factory<og::SBL>()},
  };
  return table;
}

/// OMPL's random seed is process-wide: plans take turns so that each one's seed governs all of it.
std::mutex& ompl_mutex() {
  static std::mutex m;
  return m;
}

/// OMPL prints to the terminal unless given a handler: its messages go to vwg's log sink instead,
/// one level lower (an OMPL "error" such as a start state in collision is a failed plan that the
/// caller reports, not an error of the run).
class OmplToVwgLog final : public ompl::msg::OutputHandler {
 public:
  void log(const std::string& text, ompl::msg::LogLevel level, const char*, int) override {
    LogLevel to = LogLevel::Debug;
    if (level >= ompl::msg::LOG_ERROR) to = LogLevel::Warning;
    else if (level == ompl::msg::LOG_WARN) to = LogLevel::Info;
    vwg::log(to, "ompl", text);
  }
};

/// Installs the handler once, before OMPL's first message.
void route_ompl_messages() {
  static OmplToVwgLog handler;
  static std::once_flag once;
  std::call_once(once, [] { ompl::msg::useOutputHandler(&handler); });
}

/// Sets OMPL's log level for a scope and puts the previous one back.
class LogLevelScope {
 public:
  explicit LogLevelScope(ompl::msg::LogLevel level) : previous_(ompl::msg::getLogLevel()) {
    ompl::msg::setLogLevel(level);
  }
  ~LogLevelScope() { ompl::msg::setLogLevel(previous_); }
  LogLevelScope(const LogLevelScope&) = delete;
  LogLevelScope& operator=(const LogLevelScope&) = delete;

 private:
  ompl::msg::LogLevel previous_;
};

double x_of(const ob::State* s) { return s->as<ob::SE2StateSpace::StateType>()->getX(); }
double y_of(const ob::State* s) { return s->as<ob::SE2StateSpace::StateType>()->getY(); }

/// A state is valid when the robot's disc fits there.
class DiscValidityChecker : public ob::StateValidityChecker {
 public:
  DiscValidityChecker(const ob::SpaceInformationPtr& si, const OmplGridPlanner& robot)
      : ob::StateValidityChecker(si), robot_(robot) {}
  bool isValid(const ob::State* state) const override { return robot_.valid(x_of(state), y_of(state)); }

 private:
  const OmplGridPlanner& robot_;
};

/// A motion is valid when the disc swept along it touches nothing: tested exactly, so no
/// resolution can let a path clip the corner of a cell between two checked states.
class DiscMotionValidator : public ob::MotionValidator {
 public:
  DiscMotionValidator(const ob::SpaceInformationPtr& si, const OmplGridPlanner& robot)
      : ob::MotionValidator(si), robot_(robot) {}

  bool checkMotion(const ob::State* a, const ob::State* b) const override {
    const bool ok = robot_.motion_valid(x_of(a), y_of(a), x_of(b), y_of(b));
    ++(ok ? valid_ : invalid_);
    return ok;
  }

  bool checkMotion(const ob::State* a, const ob::State* b, std::pair<ob::State*, double>& last_valid) const override {
    if (checkMotion(a, b)) return true;
    // The free part of a segment is an interval from its start, so bisection finds where it ends.
    const double xa = x_of(a), ya = y_of(a), dx = x_of(b) - xa, dy = y_of(b) - ya;
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 30; ++i) {
      const double mid = 0.5 * (lo + hi);
      if (robot_.motion_valid(xa, ya, xa + mid * dx, ya + mid * dy)) lo = mid;
      else hi = mid;
    }
    if (last_valid.first != nullptr) si_->getStateSpace()->interpolate(a, b, lo, last_valid.first);
    last_valid.second = lo;
    return false;
  }

 private:
  const OmplGridPlanner& robot_;
};

bool finite_pose(const geometry::Pose2& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta); }

std::string pose_text(const geometry::Pose2& p) {
  return "(x " + std::to_string(p.x) + ", y " + std::to_string(p.y) + ", yaw " + std::to_string(p.theta) + ")";
}

void set_pose(ob::ScopedState<ob::SE2StateSpace>& state, const geometry::Pose2& p) {
  state->setXY(p.x, p.y);
  state->setYaw(geometry::wrap_angle(p.theta));  // SO(2) states live in [-π, π]
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

OmplGridPlanner::OmplGridPlanner(BlockedGrid grid, double resolution, geometry::Pose2 origin, double robot_radius)
    : resolution_(resolution), origin_(origin), robot_radius_(robot_radius) {
  if (!(std::isfinite(resolution) && resolution > 0.0)) {
    throw SchemaError("resolution", "expected a positive number of metres per cell, got " + std::to_string(resolution));
  }
  if (!(std::isfinite(robot_radius) && robot_radius >= 0.0)) {
    throw SchemaError("robot_radius", "expected a radius of 0 or more metres, got " + std::to_string(robot_radius));
  }
  if (!(std::isfinite(origin.x) && std::isfinite(origin.y) && std::isfinite(origin.theta))) {
    throw SchemaError("origin", "expected a finite pose");
  }
  if (grid.rows() == 0 || grid.cols() == 0) throw SchemaError("grid", "the map has no cells");
  radius_cells_ = robot_radius / resolution;
  field_ = geometry::ClearanceField(std::move(grid), true);
}

OmplGridPlanner OmplGridPlanner::from_occupancy(const geometry::OccupancyGrid& grid, double robot_radius, int threshold,
                                                bool unknown_blocked) {
  return OmplGridPlanner(BlockedGrid::from_occupancy(grid, threshold, unknown_blocked), grid.resolution, grid.origin,
                         robot_radius);
}

void OmplGridPlanner::world_to_grid(double x, double y, double& u, double& v) const {
  const double dx = x - origin_.x, dy = y - origin_.y;
  const double c = std::cos(origin_.theta), s = std::sin(origin_.theta);
  u = (c * dx + s * dy) / resolution_;
  v = (-s * dx + c * dy) / resolution_;
}

void OmplGridPlanner::grid_to_world(double u, double v, double& x, double& y) const {
  const double c = std::cos(origin_.theta), s = std::sin(origin_.theta);
  x = origin_.x + (c * u - s * v) * resolution_;
  y = origin_.y + (s * u + c * v) * resolution_;
}

bool OmplGridPlanner::valid(double x, double y) const {
  double u = 0.0, v = 0.0;
  world_to_grid(x, y, u, v);
  return field_.clearance(u, v, radius_cells_ + 1.0) > radius_cells_;
}

bool OmplGridPlanner::motion_valid(double x0, double y0, double x1, double y1) const {
  double u0 = 0.0, v0 = 0.0, u1 = 0.0, v1 = 0.0;
  world_to_grid(x0, y0, u0, v0);
  world_to_grid(x1, y1, u1, v1);
  return field_.segment_clear(u0, v0, u1, v1, radius_cells_);
}

double OmplGridPlanner::clearance(double x, double y, double cap) const {
  double u = 0.0, v = 0.0;
  world_to_grid(x, y, u, v);
  return field_.clearance(u, v, cap / resolution_) * resolution_;
}

std::vector<std::string> OmplGridPlanner::planner_names() {
  std::vector<std::string> names;
  for (const auto& entry : planners()) names.push_back(entry.first);
  return names;
}

OmplPlan OmplGridPlanner::plan(const geometry::Pose2& start, const geometry::Pose2& goal, const OmplOptions& options) const {
  const auto found = planners().find(options.planner);
  if (found == planners().end()) {
    std::string known;
    for (const auto& name : planner_names()) known += (known.empty() ? "" : ", ") + name;
    throw SchemaError("planner", "unknown planner '" + options.planner + "'; expected one of " + known);
  }
  if (!(std::isfinite(options.time_limit) && options.time_limit >= 0.0)) {
    throw SchemaError("time_limit", "expected 0 or a positive number of seconds, got " + std::to_string(options.time_limit));
  }
  if (options.time_limit == 0.0 && options.iterations == 0) {
    throw SchemaError("time_limit", "0 (no time limit) needs an iteration budget (iterations > 0)");
  }
  if (options.spacing && !(std::isfinite(*options.spacing) && *options.spacing >= 0.0)) {
    throw SchemaError("spacing", "expected 0 or a positive number of metres, got " + std::to_string(*options.spacing));
  }
  if (!finite_pose(start)) throw SchemaError("start_pose", "expected finite x, y and yaw");
  if (!finite_pose(goal)) throw SchemaError("goal_pose", "expected finite x, y and yaw");
  if (!valid(start.x, start.y)) {
    double u = 0.0, v = 0.0;
    world_to_grid(start.x, start.y, u, v);
    const bool on_map = u >= 0.0 && v >= 0.0 && u <= field_.grid().cols() && v <= field_.grid().rows();
    throw SchemaError("start_pose", "the robot (radius " + std::to_string(robot_radius_) + " m) does not fit at " +
                                        pose_text(start) +
                                        (on_map ? ": it overlaps an occupied cell or the map's edge" : ": off the map"));
  }

  OmplPlan out;
  out.planner = options.planner;
  if (!valid(goal.x, goal.y)) {
    out.status = "invalid goal: the robot (radius " + std::to_string(robot_radius_) + " m) does not fit at " +
                 pose_text(goal);
    return out;
  }

  route_ompl_messages();
  const std::lock_guard<std::mutex> lock(ompl_mutex());
  // OMPL prints an "Info:" line or two per plan; unless asked, keep only warnings and errors
  // (never making a quieter setting louder).
  std::optional<LogLevelScope> quiet;
  if (!options.verbose) quiet.emplace(std::max(ompl::msg::getLogLevel(), ompl::msg::LOG_WARN));
  {
    // Reseeding after the first plan makes OMPL log an error that does not apply here: the seed
    // generator is reset all the same, and every RNG of this plan is created after it.
    LogLevelScope silent(ompl::msg::LOG_NONE);
    ompl::RNG::setSeed(options.seed + 1u == 0u ? 1u : options.seed + 1u);  // OMPL refuses seed 0
  }

  auto space = std::make_shared<ob::SE2StateSpace>();
  // The bounds are the world-frame box around the (possibly rotated) map; samples outside the map
  // itself are invalid states.
  double lo_x = std::numeric_limits<double>::infinity(), lo_y = lo_x, hi_x = -lo_x, hi_y = -lo_x;
  for (const auto& [u, v] : {std::pair<double, double>{0.0, 0.0},
                             {static_cast<double>(field_.grid().cols()), 0.0},
                             {0.0, static_cast<double>(field_.grid().rows())},
                             {static_cast<double>(field_.grid().cols()), static_cast<double>(field_.grid().rows())}}) {
    double x = 0.0, y = 0.0;
    grid_to_world(u, v, x, y);
    lo_x = std::min(lo_x, x);
    lo_y = std::min(lo_y, y);
    hi_x = std::max(hi_x, x);
    hi_y = std::max(hi_y, y);
  }
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, lo_x);
  bounds.setLow(1, lo_y);
  bounds.setHigh(0, hi_x);
  bounds.setHigh(1, hi_y);
  space->setBounds(bounds);

  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker(std::make_shared<DiscValidityChecker>(si, *this));
  si->setMotionValidator(std::make_shared<DiscMotionValidator>(si, *this));
  si->setup();

  ob::ScopedState<ob::SE2StateSpace> start_state(space), goal_state(space);
  set_pose(start_state, start);
  set_pose(goal_state, goal);
  auto problem = std::make_shared<ob::ProblemDefinition>(si);
  problem->setStartAndGoalStates(start_state, goal_state);

  ob::PlannerPtr planner = found->second(si);
  planner->setProblemDefinition(problem);
  planner->setup();

  // The iteration counter must outlive the solve: the condition calls back into it.
  ob::IterationTerminationCondition iteration_limit(options.iterations);
  ob::PlannerTerminationCondition stop = ob::plannerNonTerminatingCondition();
  if (options.time_limit > 0.0 && options.iterations > 0) {
    stop = ob::plannerOrTerminationCondition(ob::timedPlannerTerminationCondition(options.time_limit), iteration_limit);
  } else if (options.time_limit > 0.0) {
    stop = ob::timedPlannerTerminationCondition(options.time_limit);
  } else {
    stop = iteration_limit;  // no clock at all: the same plan on any machine, under any load
  }

  const auto t0 = std::chrono::steady_clock::now();
  const ob::PlannerStatus status = planner->solve(stop);
  out.plan_time = seconds_since(t0);
  if (status != ob::PlannerStatus::EXACT_SOLUTION) {
    out.status = status == ob::PlannerStatus::TIMEOUT                ? "timeout"
                 : status == ob::PlannerStatus::APPROXIMATE_SOLUTION ? "approximate solution"
                                                                     : status.asString();
    return out;
  }

  og::PathGeometric path(*problem->getSolutionPath()->as<og::PathGeometric>());
  if (options.simplify) {
    // simplifyMax stops by itself after a bounded number of rounds, so unlike a timed
    // simplification it gives the same result for the same seed.
    const auto t1 = std::chrono::steady_clock::now();
    og::PathSimplifier simplifier(si);
    simplifier.simplifyMax(path);
    out.simplify_time = seconds_since(t1);
  }

  // Waypoints: the path's vertices, with straight segments cut into pieces of at most `spacing`.
  const double spacing = options.spacing.value_or(resolution_);
  ob::ScopedState<ob::SE2StateSpace> between(space);
  auto append = [&](const ob::State* s) {
    const auto* se2 = s->as<ob::SE2StateSpace::StateType>();
    out.waypoints.push_back({se2->getX(), se2->getY(), se2->getYaw()});
  };
  const std::size_t n = path.getStateCount();
  double length = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const ob::State* s = path.getState(i);
    if (i > 0) {
      const ob::State* prev = path.getState(i - 1);
      const double piece = std::hypot(x_of(s) - x_of(prev), y_of(s) - y_of(prev));
      // The planners' own checks are ours, but a path is only returned if every segment passes again.
      if (!motion_valid(x_of(prev), y_of(prev), x_of(s), y_of(s))) {
        out.status = "planner returned a path that collides (segment " + std::to_string(i) + ")";
        out.waypoints.clear();
        return out;
      }
      length += piece;
      const auto pieces = spacing > 0.0 ? static_cast<std::size_t>(std::ceil(piece / spacing)) : std::size_t{1};
      for (std::size_t k = 1; k < pieces; ++k) {
        space->interpolate(prev, s, static_cast<double>(k) / static_cast<double>(pieces), between.get());
        append(between.get());
      }
    }
    append(s);
  }
  out.solved = true;
  out.status = "exact solution";
  out.length = length;
  return out;
}

OmplPlan plan_ompl(const BlockedGrid& grid, double resolution, const geometry::Pose2& origin, const geometry::Pose2& start,
                   const geometry::Pose2& goal, double robot_radius, const OmplOptions& options) {
  const OmplGridPlanner planner(grid, resolution, origin, robot_radius);
  return planner.plan(start, goal, options);
}

}  // namespace vwg::plan
