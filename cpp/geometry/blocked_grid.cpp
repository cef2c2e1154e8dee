#include "vwg/geometry/blocked_grid.hpp"

#include <algorithm>
#include <limits>

#include "vwg/error.hpp"

namespace vwg::geometry {

std::string to_string(Cell c) { return "(row " + std::to_string(c.row) + ", col " + std::to_string(c.col) + ")"; }

BlockedGrid::BlockedGrid(int rows, int cols) : rows_(rows), cols_(cols) {
  if (rows < 0 || cols < 0) {
    throw SchemaError("grid", "a grid cannot have a negative size (" + std::to_string(rows) + " × " +
                                  std::to_string(cols) + ")");
  }
  // Padded indices are 32-bit to halve the searches' memory traffic.
  const auto padded = static_cast<std::int64_t>(rows + 2) * static_cast<std::int64_t>(cols + 2);
  if (padded > std::numeric_limits<std::int32_t>::max()) {
    throw SchemaError("grid", "grid too large for the planners (" + std::to_string(rows) + " × " +
                                  std::to_string(cols) + " cells)");
  }
  // The border blocked, the inside free: one pass.
  cells_.assign(static_cast<std::size_t>(padded), 0);
  const std::size_t stride = static_cast<std::size_t>(cols) + 2;
  std::fill_n(cells_.data(), stride, std::uint8_t{1});
  std::fill_n(cells_.data() + cells_.size() - stride, stride, std::uint8_t{1});
  for (int r = 0; r < rows; ++r) {
    cells_.set(static_cast<std::size_t>(index({r, 0})) - 1, 1);
    cells_.set(static_cast<std::size_t>(index({r, 0})) + static_cast<std::size_t>(cols), 1);
  }
}

BlockedGrid BlockedGrid::from_occupancy(const OccupancyGrid& grid, int threshold, bool unknown_blocked) {
  if (grid.data.size() != static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height)) {
    throw SchemaError("grid", "occupancy grid of " + std::to_string(grid.width) + " × " + std::to_string(grid.height) +
                                  " cells holds " + std::to_string(grid.data.size()) + " values");
  }
  BlockedGrid out(grid.height, grid.width);
  for (int r = 0; r < grid.height; ++r) {
    for (int c = 0; c < grid.width; ++c) {
      const int v = grid.at(r, c);
      out.cells_.set(static_cast<std::size_t>(out.index({r, c})), blocked_value(v, threshold, unknown_blocked) ? 1 : 0);
    }
  }
  return out;
}

void BlockedGrid::throw_outside(Cell c) const {
  throw SchemaError("cell", "cell " + to_string(c) + " is outside the " + std::to_string(rows_) + " × " +
                                std::to_string(cols_) + " grid");
}

std::size_t BlockedGrid::blocked_count() const {
  std::size_t n = 0;
  for (int r = 0; r < rows_; ++r) {
    const std::uint8_t* row = cells_.data() + index({r, 0});
    n += static_cast<std::size_t>(std::count(row, row + cols_, std::uint8_t{1}));
  }
  return n;
}

void BlockedGrid::check_mask_size(std::size_t size) const {
  if (size != static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_)) {
    throw SchemaError("blocked", "a mask of " + std::to_string(rows_) + " × " + std::to_string(cols_) +
                                     " cells needs " + std::to_string(rows_ * cols_) + " values, got " +
                                     std::to_string(size));
  }
}

void BlockedGrid::save(StateWriter& out) const {
  out.i64(rows_);
  out.i64(cols_);
  // The inside only (the border is always blocked), a bit a cell, a row at a time (a planner's grids
  // for a hundred robots are then 3 MB, not 24).
  std::vector<std::uint8_t> row((static_cast<std::size_t>(cols_) + 7) / 8);
  for (int r = 0; r < rows_; ++r) {
    std::fill(row.begin(), row.end(), std::uint8_t{0});
    const std::uint8_t* cells = cells_.data() + index({r, 0});
    for (int c = 0; c < cols_; ++c) row[static_cast<std::size_t>(c) >> 3] |= static_cast<std::uint8_t>((cells[c] != 0) << (c & 7));
    out.raw(row.data(), row.size());
  }
}

BlockedGrid BlockedGrid::load(StateReader& in) {
  const std::int64_t rows = in.i64(), cols = in.i64();
  // Every cell's byte must be there, and a grid with rows has columns (else 16 bytes would ask for a
  // grid of a billion empty rows).
  const std::uint64_t row_bytes = (static_cast<std::uint64_t>(cols) + 7) / 8;
  if (rows < 0 || cols < 0 || rows > (1 << 30) || cols > (1 << 30) || (rows == 0) != (cols == 0) ||
      (cols > 0 && static_cast<std::uint64_t>(rows) > in.left() / row_bytes)) {
    in.fail("a grid of " + std::to_string(rows) + " × " + std::to_string(cols) + " cells, more than the state holds");
  }
  BlockedGrid grid(static_cast<int>(rows), static_cast<int>(cols));
  std::vector<std::uint8_t> row(static_cast<std::size_t>(row_bytes));
  for (int r = 0; r < grid.rows_; ++r) {
    in.raw(row.data(), row.size(), "grid cells");
    if ((cols & 7) != 0 && (row.back() >> (cols & 7)) != 0) in.fail("a grid row with bits past its last cell");
    for (int c = 0; c < grid.cols_; ++c) {
      if ((row[static_cast<std::size_t>(c) >> 3] >> (c & 7)) & 1) grid.cells_.set(static_cast<std::size_t>(grid.index({r, c})), 1);
    }
  }
  return grid;
}

}  // namespace vwg::geometry
