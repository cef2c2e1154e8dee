// The robot's own map: the `grid` attribute of ARobot (paper eq. 11), an int16 blob of the world
// map's geometry. It starts as the known map (or empty, eq. 13) and grows with what the sensors
// report (eq. 12): obstacles from eLaser, markers from eCamera.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "vwg/blob_edit.hpp"
#include "vwg/geometry/map_geometry.hpp"

namespace vwg::robot {

/// What a robot map cell holds.
enum RobotCell : std::int16_t {
  kUnknownCell = -1,
  kFreeCell = 0,
  kWallCell = 100,     ///< an obstacle of the prior map
  kSeenCell = 101,     ///< an obstacle the sensors reported (may be cleared again: moving things)
  kMarkerBase = 1000,  ///< 1000 + tag id: a marker the camera saw there
};

inline bool is_obstacle(std::int16_t v) { return v >= kWallCell; }

/// Throws SchemaError("grid") unless `map` is an int16 array of the geometry's shape.
void check_robot_map(const Blob& map, const geometry::MapGeometry& g);

/// A robot map of the world's geometry: the known map (walls 100, free 0, unknown -1) when
/// `knows_map`, else all free (the empty grid of eq. 13).
std::shared_ptr<Blob> make_robot_map(const geometry::OccupancyGrid& world, bool knows_map, int threshold = 50);

/// The cells of a robot map being written (in place and journaled during a frame: ActorState::edit_blob).
using MapEdit = BlobEdit<std::int16_t>;

/// Which 8 × 8-cell blocks of a robot map hold reported obstacles (kSeenCell), so that clearing a
/// beam's cells reads only the blocks that have some: a beam crosses ~100 cells, and reading them
/// from every robot's map was most of a laser robot's frame. A cache of one map, valid for the
/// map's revision it was made or kept up to date for; made again from the map otherwise.
class SeenBlocks {
 public:
  static constexpr int kShift = 3;  // 8 × 8 cells
  /// Make it valid for `map`, scanning the map unless it already is.
  void sync(const Blob& map, const geometry::MapGeometry& g);
  /// After the edits that went through it: valid for the map as it is now.
  void keep(const Blob& map) { revision_ = map.revision(); }
  bool any(int row, int col) const { return counts_[block(row, col)] != 0; }
  /// False if no reported obstacle can be in the cells [lo_row, hi_row] × [lo_col, hi_col].
  bool may_hold(int lo_row, int lo_col, int hi_row, int hi_col) const {
    return lo_row <= hi_row_ && hi_row >= lo_row_ && lo_col <= hi_col_ && hi_col >= lo_col_;
  }
  void added(int row, int col) {
    ++counts_[block(row, col)];
    lo_row_ = std::min(lo_row_, row), hi_row_ = std::max(hi_row_, row);
    lo_col_ = std::min(lo_col_, col), hi_col_ = std::max(hi_col_, col);
  }
  void removed(int row, int col) { --counts_[block(row, col)]; }  // the box only grows until the next sync
  /// False if the cell walk from (u0, v0) to (u1, v1) (grid units) cannot meet a reported
  /// obstacle: no block along the segment, nor next to one (rounding at corners), holds any.
  bool along(double u0, double v0, double u1, double v1) const;

 private:
  std::size_t block(int row, int col) const {
    return static_cast<std::size_t>(row >> kShift) * static_cast<std::size_t>(columns_) + static_cast<std::size_t>(col >> kShift);
  }
  std::uint64_t revision_ = 0;
  int columns_ = 0, rows_ = 0;
  std::vector<std::uint32_t> counts_;
  int lo_row_ = 0, lo_col_ = 0, hi_row_ = -1, hi_col_ = -1;  // a box holding every reported obstacle
};

/// Mark a reported obstacle at (x, y); returns true if the cell changed. Markers and walls stay.
/// `seen`, if given, is kept valid (see SeenBlocks).
bool mark_obstacle(MapEdit& map, const geometry::MapGeometry& g, double x, double y, SeenBlocks* seen = nullptr);
/// Mark marker `tag` at (x, y); returns true if the cell changed.
bool mark_marker(MapEdit& map, const geometry::MapGeometry& g, double x, double y, int tag, SeenBlocks* seen = nullptr);
/// Clear reported obstacles (kSeenCell) on the cells the segment from (x0, y0) to (x1, y1)
/// crosses, the end cell excluded (a laser beam passed through them, so they are free now).
/// Returns how many cells changed.
/// With `seen` (valid for the map: SeenBlocks::sync), cells of blocks without reported obstacles
/// are not read; the cells cleared are the same.
int carve_free(MapEdit& map, const geometry::MapGeometry& g, double x0, double y0, double x1, double y1, SeenBlocks* seen = nullptr);
/// Whether a disc of `radius` moved along the segment stays off every obstacle of the map
/// (unknown cells count as obstacles when `unknown_blocked`).
bool segment_clear(const Blob& map, const geometry::MapGeometry& g, double x0, double y0, double x1, double y1, double radius,
                   bool unknown_blocked = false);
/// Distance from (x, y) to the nearest obstacle square of the map, or `cap` if none is nearer.
double clearance(const Blob& map, const geometry::MapGeometry& g, double x, double y, double cap);
/// Where marker `tag` was seen (the centre of its cell); false if it never was.
bool find_marker(const Blob& map, const geometry::MapGeometry& g, int tag, double& x, double& y);

}  // namespace vwg::robot
