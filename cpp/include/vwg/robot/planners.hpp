// Deciders that plan: shortest grid paths (A*, Jump Point Search, or D* Lite repairing its search
// as obstacles appear) and sampling-based motion planning (OMPL), on the robot's own map inflated by its
// radius. A plan is kept while it stays clear; when the map blocks it, a new one is made (a replan).
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "vwg/plan/astar.hpp"
#include "vwg/plan/dstar_lite.hpp"
#include "vwg/plan/grid_graph.hpp"
#include "vwg/plan/jps.hpp"
#include "vwg/robot/decider.hpp"
#include "vwg/robot/planning_map.hpp"

namespace vwg::robot {

/// Time and count of the searches a decider ran (for the replanning benchmark).
struct SearchStats {
  double seconds = 0.0;
  std::size_t searches = 0;
};

/// What a grid search that found no way leaves known: the start's side of the map — the free cells
/// it reaches, which without corner cutting are the 4-connected free cells round it (a diagonal
/// move needs both cells beside it free) — and the blocked cells round that side. Cells that become
/// blocked only shrink the side; it can grow only where one of those border cells becomes free. So
/// while none has, and the start is on that side and the goal is not, a search again would find no
/// way: the answer is known without searching. (Robots in a crowd whose maps shut them in try again
/// every few frames, and a search that finds nothing goes through their whole side of the map.)
class NoWayMemo {
 public:
  /// After a search from `start` on `grid` found no way.
  void learn(const geometry::BlockedGrid& grid, geometry::Cell start);
  /// Whether a search from `start` to `goal` on `grid` (a later state of the grid learnt on) would
  /// find no way, known from what was learnt.
  bool shut(const geometry::BlockedGrid& grid, geometry::Cell start, geometry::Cell goal) const;
  /// A way was found: what was learnt no longer holds.
  void forget() { known_ = false; }
  /// For a saved run (vwg/state.hpp).
  void save(StateWriter& out) const;
  void load(StateReader& in);

 private:
  bool inside(std::int32_t node) const { return (side_[node >> 6] >> (node & 63)) & 1; }
  bool known_ = false;
  int rows_ = 0, cols_ = 0;
  std::vector<std::uint64_t> side_;   // a bit a padded index of the grid: on the start's side
  std::vector<std::int32_t> border_;  // padded indices of the blocked cells round the side, in the map
};

/// path_clear of one robot's plan, following its map: a segment found clear stays clear while no cell that
/// segment_clear looks at for it becomes an obstacle. It asks the map which cells were written since its last answer
/// (Blob::written_since) and checks again only the segments near those that are obstacles now (and, if the robot
/// has gone back along its path, the segments it had not checked). The answer is path_clear's, bit for bit. A robot
/// that avoids decides every frame, and its map changes most frames: checking every segment of a long plan each
/// time was a fifth of an avoiding crowd's frame.
class ClearPathMemo {
 public:
  /// path_clear(in, in.path), in.path being the plan in.path_owner holds.
  bool clear(const DecisionInput& in);
  /// Segments checked by the last clear() (the others it knew clear).
  std::size_t checked() const { return checked_; }

 private:
  std::shared_ptr<const Blob> path_;  // the plan last found clear (held: no other blob can take its address)
  Blob::Mark map_;                    // the robot's map then
  std::size_t from_ = 0;              // its first segment then: those from it on were clear
  double radius_ = 0.0;               // the disc they were checked with
  std::size_t checked_ = 0;
};

class GridDecider final : public Decider {
 public:
  enum class Algorithm { AStar, DStarLite, JumpPoint };
  /// `heuristic` for A* and Jump Point Search (8-connected moves): Euclidean, the paper's, or
  /// Octile, exact on an open grid, so the same path lengths with fewer cells expanded (2.5x less
  /// time a query on the warehouse). D* Lite keeps its own (Euclidean); SchemaError("heuristic")
  /// for one that would overestimate (Manhattan) or for D* Lite with another.
  explicit GridDecider(Algorithm algorithm, plan::Heuristic heuristic = plan::Heuristic::Euclidean);
  Decision decide(const DecisionInput& in) override;
  /// "astar", "dstar" or "jps", and "-octile" after it with that heuristic.
  std::string name() const override;
  /// Each robot's state is its own, and each thread has its own A* work area.
  bool concurrent() const override { return true; }
  double search_seconds() const;
  std::size_t searches() const;
  /// Each robot's grids, D* Lite search, goal and what it knows has no way (the searches' times
  /// are not kept).
  void save_state(StateWriter& out) const override;
  void load_state(StateReader& in) override;

 private:
  struct RobotState {
    explicit RobotState(std::int64_t robot) : map(robot) {}
    PlanningMap map;
    std::optional<plan::DStarLite> dstar;
    geometry::Cell goal{-1, -1};
    NoWayMemo no_way;
    ClearPathMemo clear_path;  // not saved: it gives path_clear's answers, and a loaded run starts it afresh
  };
  plan::GridPath search(RobotState& s, geometry::Cell start, geometry::Cell goal);
  RobotState& state_of(std::int64_t robot);
  Algorithm algorithm_;
  plan::GridSearchOptions options_;  // A*'s and Jump Point Search's moves and heuristic
  mutable std::mutex mutex_;          // robots_ (the map, not its states: each robot's is its own) and stats_
  std::map<std::int64_t, RobotState> robots_;  // node-based: a robot's state stays where it is
  SearchStats stats_;
};

class OmplDecider final : public Decider {
 public:
  /// `iterations` bounds each plan (no clock: a run is the same on any machine, under any load).
  /// PRM and PRMstar are refused: they grow their roadmap on a second thread, so their plans differ
  /// from run to run; LazyPRM is the single-threaded roadmap planner.
  OmplDecider(std::string planner, unsigned iterations);
  /// Iterations of a plan when none is said: RRTConnect's ("rrtconnect" in the registry).
  static constexpr unsigned kDefaultIterations = 20000;
  Decision decide(const DecisionInput& in) override;
  std::string name() const override { return planner_; }
  double search_seconds() const { return stats_.seconds; }
  std::size_t searches() const { return stats_.searches; }
  /// Each robot's grids (a plan's randomness comes from the decision's seed).
  void save_state(StateWriter& out) const override;
  void load_state(StateReader& in) override;

 private:
  std::string planner_;
  unsigned iterations_;
  std::map<std::int64_t, PlanningMap> maps_;
  SearchStats stats_;
};

/// The nearest cell to `cell` that is free in `grid` (searching outwards up to `reach` cells); the
/// cell itself if free; {-1, -1} if none.
geometry::Cell nearest_free(const geometry::BlockedGrid& grid, geometry::Cell cell, int reach);
/// Whether every segment of the path from the robot onwards (x0, y0, ...) stays clear.
bool path_clear(const DecisionInput& in, std::span<const double> path);

}  // namespace vwg::robot
