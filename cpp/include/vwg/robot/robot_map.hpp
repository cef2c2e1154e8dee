// The robot's own map: the `grid` attribute of ARobot (paper eq. 11), an int16 blob of the world
// map's geometry. It starts as the known map (or empty, eq. 13) and grows with what the sensors
// report (eq. 12): obstacles from eLaser, markers from eCamera.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>

#include "vwg/blob_edit.hpp"
#include "vwg/sim/grid.hpp"

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

/// Size and placement of a robot map (those of the world map).
struct MapGeometry {
  int width = 0, height = 0;
  double resolution = 0.05;
  sim::Pose2 origin{};

  static MapGeometry of(const sim::OccupancyGrid& g) { return MapGeometry{g.width, g.height, g.resolution, g.origin}; }
  sim::OccupancyGrid frame() const;  ///< an empty grid of this geometry, for its coordinate functions
  /// The cell holding (x, y); false when it is outside the map.
  bool cell_of(double x, double y, int& row, int& col) const;
  /// The centre of cell (row, col) in world coordinates.
  void centre_of(int row, int col, double& x, double& y) const;
  std::size_t cells() const { return static_cast<std::size_t>(width) * height; }
};

/// A robot map of the world's geometry: the known map (walls 100, free 0, unknown -1) when
/// `knows_map`, else all free (the empty grid of eq. 13).
std::shared_ptr<Blob> make_robot_map(const sim::OccupancyGrid& world, bool knows_map, int threshold = 50);

/// The cells of a robot map being written (in place and journaled during a frame: ActorState::edit_blob).
using MapEdit = BlobEdit<std::int16_t>;

/// Mark a reported obstacle at (x, y); returns true if the cell changed. Markers and walls stay.
bool mark_obstacle(MapEdit& map, const MapGeometry& g, double x, double y);
/// Mark marker `tag` at (x, y); returns true if the cell changed.
bool mark_marker(MapEdit& map, const MapGeometry& g, double x, double y, int tag);
/// Clear reported obstacles (kSeenCell) on the cells the segment from (x0, y0) to (x1, y1)
/// crosses, the end cell excluded (a laser beam passed through them, so they are free now).
/// Returns how many cells changed.
int carve_free(MapEdit& map, const MapGeometry& g, double x0, double y0, double x1, double y1);
/// Whether a disc of `radius` moved along the segment stays off every obstacle of the map
/// (unknown cells count as obstacles when `unknown_blocked`).
bool segment_clear(const Blob& map, const MapGeometry& g, double x0, double y0, double x1, double y1, double radius,
                   bool unknown_blocked = false);
/// Distance from (x, y) to the nearest obstacle square of the map, or `cap` if none is nearer.
double clearance(const Blob& map, const MapGeometry& g, double x, double y, double cap);
/// Where marker `tag` was seen (the centre of its cell); false if it never was.
bool find_marker(const Blob& map, const MapGeometry& g, int tag, double& x, double& y);

}  // namespace vwg::robot
