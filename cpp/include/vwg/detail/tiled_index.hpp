// A 2D array's (row, column) to a flat index tile by tile, not row by row: tiles of
// 2^RowShift × 2^ColShift elements, one after another, each tile's elements in rows. A robot's
// grids are copies of shared grids whose pages are copied on a robot's first write (SharedPages);
// a sighting writes a small patch round each cell it marks, and in tiles the size of a page that
// patch writes one or two pages, where rows of a wide map put a page on every row or two of it.
//
// Not part of vwg's API (vwg/detail/): installed only because
// robot::RobotMap and robot::PlanningMap hold them by value.
#pragma once

#include <cstddef>

namespace vwg::robot {

template <int RowShift, int ColShift>
class TiledIndex {
 public:
  static constexpr int kTileRows = 1 << RowShift, kTileCols = 1 << ColShift;

  TiledIndex() = default;
  /// For a rows × cols array (each >= 0).
  TiledIndex(int rows, int cols) : across_((cols + kTileCols - 1) >> ColShift), down_((rows + kTileRows - 1) >> RowShift) {}
  /// Elements the array takes: whole tiles, so the last row and column of tiles are padded.
  std::size_t size() const { return static_cast<std::size_t>(across_) * static_cast<std::size_t>(down_) * kTileRows * kTileCols; }
  /// Where (row, col), inside the array, is.
  std::size_t operator()(int row, int col) const {
    const auto tile = static_cast<std::size_t>(row >> RowShift) * static_cast<std::size_t>(across_) + static_cast<std::size_t>(col >> ColShift);
    return tile * kTileRows * kTileCols +
           static_cast<std::size_t>(((row & (kTileRows - 1)) << ColShift) | (col & (kTileCols - 1)));
  }

 private:
  int across_ = 0, down_ = 0;  // tiles
};

}  // namespace vwg::robot
