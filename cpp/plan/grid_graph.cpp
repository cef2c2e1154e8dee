#include "vwg/plan/grid_graph.hpp"

#include <algorithm>

#include "vwg/error.hpp"

namespace vwg::plan {

Heuristic heuristic_from_name(std::string_view name) {
  if (name == "euclidean") return Heuristic::Euclidean;
  if (name == "octile") return Heuristic::Octile;
  if (name == "manhattan") return Heuristic::Manhattan;
  if (name == "zero") return Heuristic::Zero;
  throw SchemaError("heuristic", "unknown heuristic '" + std::string(name) +
                                     "'; expected 'euclidean', 'octile', 'manhattan' or 'zero'");
}

std::string_view heuristic_name(Heuristic h) {
  switch (h) {
    case Heuristic::Euclidean: return "euclidean";
    case Heuristic::Octile: return "octile";
    case Heuristic::Manhattan: return "manhattan";
    case Heuristic::Zero: return "zero";
  }
  return "?";
}

void validate(const GridSearchOptions& options) {
  if (options.diagonal && options.heuristic == Heuristic::Manhattan) {
    throw SchemaError("heuristic",
                      "'manhattan' overestimates diagonal moves, so the path found could be longer than the "
                      "shortest; use it with diagonal=false, or use 'octile' or 'euclidean'");
  }
}

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
  cells_.assign(static_cast<std::size_t>(padded), 1);
  for (int r = 0; r < rows; ++r) {
    std::fill_n(cells_.begin() + index({r, 0}), cols, std::uint8_t{0});
  }
}

BlockedGrid BlockedGrid::from_occupancy(const sim::OccupancyGrid& grid, int threshold, bool unknown_blocked) {
  if (grid.data.size() != static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height)) {
    throw SchemaError("grid", "occupancy grid of " + std::to_string(grid.width) + " × " + std::to_string(grid.height) +
                                  " cells holds " + std::to_string(grid.data.size()) + " values");
  }
  BlockedGrid out(grid.height, grid.width);
  for (int r = 0; r < grid.height; ++r) {
    for (int c = 0; c < grid.width; ++c) {
      const int v = grid.at(r, c);
      out.cells_[out.index({r, c})] = (v >= threshold || (unknown_blocked && v < 0)) ? 1 : 0;
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
    const auto row = cells_.begin() + index({r, 0});
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

void check_cell(const BlockedGrid& grid, Cell cell, const std::string& field, bool must_be_free) {
  if (!grid.inside(cell)) {
    throw SchemaError(field, "cell " + to_string(cell) + " is outside the grid of " + std::to_string(grid.rows()) +
                                 " rows × " + std::to_string(grid.cols()) + " columns");
  }
  if (must_be_free && grid.blocked(cell)) throw SchemaError(field, "cell " + to_string(cell) + " is blocked");
}

std::string to_string(Cell c) { return "(row " + std::to_string(c.row) + ", col " + std::to_string(c.col) + ")"; }

}  // namespace vwg::plan
