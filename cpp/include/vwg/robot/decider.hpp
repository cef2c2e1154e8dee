// The decision inside λ(ARobot, eDecide): "the evolution function is the way of introducing
// intelligent behaviours" (paper §III.F, test 1). A Decider chooses the robot's next motion; the
// rest of the actor, the string and the world stay the same whichever decider is plugged in.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vwg/blob.hpp"
#include "vwg/state.hpp"
#include "vwg/geometry/map_geometry.hpp"
#include "vwg/geometry/pose.hpp"
#include "vwg/platform/platform.hpp"
#include "vwg/robot/robot_map.hpp"

namespace vwg::robot {

/// What the robot knows when it decides.
struct DecisionInput {
  std::int64_t robot = 0;  ///< the robot's id
  /// The robot's map (int16, see robot_map.hpp). Shared, so a view of it may outlive the call: the
  /// actor's next write then goes to a copy (copy-on-write), and the view keeps what it showed.
  std::shared_ptr<const Blob> map;
  const geometry::MapGeometry* geometry = nullptr;
  geometry::Pose2 pose{};            ///< where the robot believes it is
  double goal_x = 0, goal_y = 0;
  double radius = platform::kDefaultRobotRadius;  ///< robot radius plus the clearance it keeps, metres
  double step_length = 1.0;     ///< the longest straight move of one decision, metres
  std::span<const double> path; ///< the current plan: x0, y0, x1, y1, ... (may be empty)
  std::shared_ptr<const Blob> path_owner;  ///< the blob `path` views, if any (kept alive by views)
  std::uint64_t seed = 0;       ///< for random choices (fixed by the engine seed and the frame)
};

struct Decision {
  enum class Kind { Move, NoPath } kind = Kind::Move;
  double turn = 0.0;      ///< radians, counter-clockwise, done first
  double distance = 0.0;  ///< metres, then straight ahead
  /// The plan from now on (x0, y0, ...), shown and kept in the actor's `path`; `keep_path` keeps
  /// the previous one instead.
  std::vector<double> path;
  bool keep_path = false;
  bool replanned = false;  ///< a new plan had to be made because the old one became blocked
};

class Decider {
 public:
  virtual ~Decider() = default;
  virtual Decision decide(const DecisionInput& in) = 0;
  virtual std::string name() const = 0;
  /// True if decide() may run for several robots at the same time (the engine's threads); the
  /// default, false, keeps every robot with this decider on the engine's thread.
  virtual bool concurrent() const { return false; }
  /// What it keeps between decisions that decides anything (searches to repair, the grids a plan
  /// was checked on), for a saved run (vwg/state.hpp). The default refuses, naming the decider.
  virtual void save_state(StateWriter& out) const;
  /// Back to what save_state() wrote, before the first decision of a resumed run.
  virtual void load_state(StateReader& in);
};

/// The paper's first algorithm: random moves (a random heading, then up to step_length ahead)
/// that stay clear of known obstacles, until the robot happens to reach its goal.
class RandomDecider final : public Decider {
 public:
  Decision decide(const DecisionInput& in) override;
  std::string name() const override { return "random"; }
  bool concurrent() const override { return true; }  // no state: its randomness comes from in.seed
  void save_state(StateWriter&) const override {}
  void load_state(StateReader& in) override { in.end(); }
};

/// The point of `path` (x0, y0, ...) nearest to (x, y), the first of equals; 0 for an empty path. Compared by
/// squared distances: this runs over the whole plan at every decision of an avoiding robot, and std::hypot (here
/// and in the beams' test against the tracked neighbours) was 4 % of an avoiding crowd's CPU.
std::size_t nearest_path_point(std::span<const double> path, double x, double y);

/// The motion towards the farthest point of `path` (x0, y0, ...) within `step_length` that the
/// robot can reach in a straight line without touching an obstacle of its map. Returns false if
/// not even the path's first point is reachable so.
bool follow_path(const DecisionInput& in, std::span<const double> path, Decision& out);

}  // namespace vwg::robot
