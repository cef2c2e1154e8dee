// Which cells of a grid are blocked: the obstacle mask that clearance, inflation and the grid
// planners work on.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "vwg/geometry/occupancy_grid.hpp"
#include "vwg/detail/shared_pages.hpp"
#include "vwg/state.hpp"

namespace vwg::geometry {

/// A cell of a grid by (row, column) index. Which way rows run is the grid's business: row 0 is
/// the bottom row of an OccupancyGrid and the top row of a MovingAI map.
struct Cell {
  int row = 0;
  int col = 0;
  friend bool operator==(const Cell&, const Cell&) = default;
};

/// Text of a cell for messages: "(row 3, col 7)".
std::string to_string(Cell c);

/// A rows × cols mask of blocked cells, stored with a one-cell blocked border around it so that the
/// searches look at neighbours without bounds checks (the border stands for "outside the grid").
class BlockedGrid {
 public:
  BlockedGrid() = default;
  /// All cells free.
  BlockedGrid(int rows, int cols);

  /// From a row-major mask of `rows * cols` values, non-zero (or true) meaning blocked.
  template <class T>
  static BlockedGrid from_mask(std::span<const T> mask, int rows, int cols) {
    static_assert(std::is_arithmetic_v<T>, "a mask holds numbers or bools");
    BlockedGrid grid(rows, cols);
    grid.check_mask_size(mask.size());
    // Row by row through pointers: a planner called from Python converts its map on every call,
    // so this is on the path of every search (a bool row is copied as it is: its bytes are 0 or 1).
    for (int r = 0; r < rows; ++r) {
      const T* src = mask.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(cols);
      std::uint8_t* dst = grid.cells_.data() + grid.index({r, 0});
      if constexpr (std::is_same_v<T, bool>) {
        std::memcpy(dst, src, static_cast<std::size_t>(cols));
      } else {
        for (int c = 0; c < cols; ++c) dst[c] = src[c] != T{} ? 1 : 0;
      }
    }
    return grid;
  }

  /// The obstacles of an occupancy grid: values of at least `threshold` are blocked, unknown cells
  /// (negative values) too when `unknown_blocked`. Row 0 stays the bottom row.
  static BlockedGrid from_occupancy(const OccupancyGrid& grid, int threshold = kObstacleThreshold, bool unknown_blocked = true);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  bool inside(Cell c) const { return c.row >= 0 && c.col >= 0 && c.row < rows_ && c.col < cols_; }
  /// Cells outside the grid count as blocked.
  bool blocked(Cell c) const { return !inside(c) || cells_[index(c)] != 0; }
  /// Throws SchemaError("cell") outside the grid.
  void set_blocked(Cell c, bool blocked) {
    if (!inside(c)) throw_outside(c);
    cells_.set(static_cast<std::size_t>(index(c)), blocked ? 1 : 0);
  }
  std::size_t blocked_count() const;

  // --- the padded layout the searches work on ---
  /// Distance between vertically adjacent cells in the padded layout.
  std::int32_t stride() const { return cols_ + 2; }
  std::int32_t index(Cell c) const { return (c.row + 1) * stride() + (c.col + 1); }
  Cell cell(std::int32_t index) const { return {index / stride() - 1, index % stride() - 1}; }
  /// (rows + 2) * (cols + 2) flags, 1 = blocked, the border included.
  std::span<const std::uint8_t> padded() const { return cells_.span(); }
  /// Let copies share the memory pages neither writes (SharedPages): a grid many robots start from.
  /// For a saved run (vwg/state.hpp): the size and a bit a cell (1 blocked), each row in whole bytes.
  void save(StateWriter& out) const;
  /// A grid as save() wrote it; SchemaError (StateReader::fail) for a size or cell it cannot be.
  static BlockedGrid load(StateReader& in);
  void share() { cells_.share(); }
  /// See SharedPages::reshare.
  std::size_t reshare() { return cells_.reshare(); }
  std::size_t private_pages() const { return cells_.private_pages(); }

 private:
  [[noreturn]] void throw_outside(Cell c) const;
  void check_mask_size(std::size_t size) const;

  int rows_ = 0;
  int cols_ = 0;
  SharedArray<std::uint8_t> cells_;
};

}  // namespace vwg::geometry
