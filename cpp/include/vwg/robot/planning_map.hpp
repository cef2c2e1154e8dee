// What a planning decider keeps of a robot's map: its obstacles and, for the radius in use, the
// cells the robot's centre may not enter. A robot's map changes in a few cells most frames, so the
// grids follow those cells (each obstacle cell adds one to the cells its disc covers) instead of
// being rebuilt: rebuilding them was most of a planning robot's frame.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "vwg/blob.hpp"
#include "vwg/plan/grid_graph.hpp"
#include "vwg/robot/robot_map.hpp"
#include "vwg/detail/tiled_index.hpp"

namespace vwg::robot {

class PlanningMap {
 public:
  PlanningMap() = default;
  /// For robot `robot`: its looks at new revisions counted from reshare_phase(robot).
  explicit PlanningMap(std::int64_t robot) : looks_(reshare_phase(robot)) {}
  /// Bring the grids up to `map` (a robot map of geometry `g`) for a robot of `radius` metres;
  /// true if the grids changed since the last call (a cell became an obstacle, or unknown, or
  /// stopped being one), false if they are the same. The first call for a copy of a shared map
  /// (Blob::share: the known map every robot starts from) starts from the grids of the shared
  /// content, made once for all robots and shared page by page, and follows the cells this copy
  /// changed. Later calls follow the cells written
  /// since the last one (Blob::written_since), or compare every cell with the grids when the map
  /// cannot tell. Every kReshareEvery calls that see a new revision of the map, it calls reshare().
  bool update(const Blob& map, const geometry::MapGeometry& g, double radius);
  /// Give back the pages of the grids that are equal to the shared grids again (what a robot saw
  /// pass and then saw gone): SharedPages::reshare.
  void reshare();

  /// Walls, seen obstacles, markers and unknown cells.
  const geometry::BlockedGrid& obstacles() const { return obstacles_; }
  /// The cells whose centre is within `radius` of an obstacle square or of the map's edge: equal
  /// to geometry::inflate(obstacles(), radius / resolution).
  const geometry::BlockedGrid& inflated() const { return inflated_; }
  /// The memory pages of its grids that differ from the grids it started from (0 unless it
  /// started from those of a shared map): what this robot's grids cost beyond the shared ones.
  std::size_t private_pages() const;
  /// For a saved run (vwg/state.hpp): the radius and the obstacles it last followed (the inflated
  /// grid and the counts follow from them). What update() reports next depends on those alone.
  void save(StateWriter& out) const;
  /// Back to what save() wrote: the grids are made from the saved obstacles at the next update() (if
  /// its radius and map size are the saved ones, else from the map), which then compares the map
  /// with them cell by cell.
  void load(StateReader& in);

 private:
  void rebuild(std::span<const std::int16_t> cells, const geometry::MapGeometry& g, double radius);
  /// rebuild() from the obstacle mask (a byte a cell, 1 = obstacle).
  void rebuild_mask(std::vector<std::uint8_t> mask, const geometry::MapGeometry& g, double radius);
  std::optional<geometry::BlockedGrid> loaded_;  // saved obstacles for the next update() (load())
  double loaded_radius_ = -1.0;
  /// Become the shared grids of `map`'s original content; false if it has none.
  bool start_from_original(const Blob& map, const geometry::MapGeometry& g, double radius);
  void set_obstacle(int row, int col, bool blocked);
  /// Follow cell `i` of the map, which holds `value` now; true if the grids changed.
  bool follow(std::size_t i, std::int16_t value, int cols);
  /// follow() every cell of the map (`cells`), looking only at those the obstacle grid differs from.
  bool follow_all(std::span<const std::int16_t> cells, int cols);

  Blob::Mark looked_;  // the map as last looked at
  double radius_ = -1.0;
  geometry::BlockedGrid obstacles_, inflated_;
  std::vector<geometry::Cell> disc_;      // offsets covered by an obstacle cell's disc
  // Per cell: the obstacle discs (and the map's edge) covering it, in tiles of 32 × 64 cells (a
  // 4 KB page each): a disc of 11 × 11 cells writes one or two tiles, against nine pages of rows
  // on a map 1,600 cells wide.
  TiledIndex<5, 6> cover_at_;
  SharedArray<std::uint16_t> cover_;
  unsigned looks_ = 0;  // at a new revision of the map, counted for reshare()
  bool counted_ = false;              // cover_ is kept (false when a disc is too large to count)
};

}  // namespace vwg::robot
