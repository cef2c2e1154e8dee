// Grids as graphs for the grid planners (A*, D* Lite): which cells are blocked, which moves exist
// between cells and what they cost, and the heuristics that estimate the rest of a path.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "vwg/geometry/blocked_grid.hpp"

namespace vwg::plan {

// The grids the planners search are the geometry library's obstacle masks.
using geometry::BlockedGrid;
using geometry::Cell;
using geometry::to_string;

/// The estimate of the remaining path length between two cells.
enum class Heuristic {
  Euclidean,  ///< straight-line distance: admissible for every move set (the paper's choice)
  Octile,     ///< exact on an empty 8-connected grid: fewer expansions than Euclidean, same path lengths
  Manhattan,  ///< exact on an empty 4-connected grid; overestimates diagonal moves, so 4-connected only
  Zero,       ///< none: Dijkstra's algorithm
};

/// The heuristic of a name ("euclidean", "octile", "manhattan", "zero"); SchemaError("heuristic") otherwise.
Heuristic heuristic_from_name(std::string_view name);
std::string_view heuristic_name(Heuristic h);

/// How cells connect. Straight moves cost 1 and diagonal moves √2 (in cells).
struct GridSearchOptions {
  bool diagonal = true;         ///< 8-connected; false: 4-connected
  bool corner_cutting = false;  ///< a diagonal move may pass a blocked orthogonal neighbour
  Heuristic heuristic = Heuristic::Euclidean;
};

/// Throws SchemaError("heuristic") for a heuristic that would overestimate with these moves
/// (Manhattan on an 8-connected grid), since the searches would then return longer paths.
void validate(const GridSearchOptions& options);

/// A path on the grid: cells from start to goal inclusive and the sum of the move costs (cells).
/// No path: no cells and an infinite length.
struct GridPath {
  std::vector<Cell> cells;
  double length = std::numeric_limits<double>::infinity();
  bool found() const { return !cells.empty(); }
};

/// Throws SchemaError(`field`) when `cell` is outside the grid, or blocked and `must_be_free`.
void check_cell(const BlockedGrid& grid, Cell cell, const std::string& field, bool must_be_free);

/// √2, the cost of a diagonal move.
inline constexpr double kDiagonalCost = 1.4142135623730951;

/// The heuristic between two cells `drow` rows and `dcol` columns apart.
inline double heuristic_distance(Heuristic h, int drow, int dcol) {
  const double dr = std::abs(drow), dc = std::abs(dcol);
  switch (h) {
    case Heuristic::Euclidean: return std::sqrt(dr * dr + dc * dc);
    case Heuristic::Octile: return dr > dc ? dr + (kDiagonalCost - 1.0) * dc : dc + (kDiagonalCost - 1.0) * dr;
    case Heuristic::Manhattan: return dr + dc;
    case Heuristic::Zero: break;
  }
  return 0.0;
}

/// A move to padded index `to` at `cost`.
struct Step {
  std::int32_t to;
  double cost;
};

/// Fills `out` with every move out of padded index `from` that the options allow and returns how
/// many: the target must be free and, for a diagonal move without corner cutting, both cells it
/// passes between too. Moves are symmetric, so these are also the moves into `from`. Whether
/// `from` itself is free is the caller's business. (An array rather than a callback: the caller's
/// loop over it has one call site, which compilers inline, where eight callback sites they don't.)
inline int moves_from(const BlockedGrid& grid, std::int32_t from, const GridSearchOptions& options,
                      std::array<Step, 8>& out) {
  const std::uint8_t* blocked = grid.padded().data();
  const std::int32_t s = grid.stride();
  int n = 0;
  for (std::int32_t d : {1, -1, s, -s}) {
    if (!blocked[from + d]) out[n++] = {from + d, 1.0};
  }
  if (!options.diagonal) return n;
  // Each diagonal as (row step, column step), in padded-index units.
  const std::int32_t diagonals[4][2] = {{s, 1}, {s, -1}, {-s, 1}, {-s, -1}};
  for (const auto& [dr, dc] : diagonals) {
    const std::int32_t to = from + dr + dc;
    if (blocked[to]) continue;
    if (!options.corner_cutting && (blocked[from + dr] || blocked[from + dc])) continue;
    out[n++] = {to, kDiagonalCost};
  }
  return n;
}

}  // namespace vwg::plan
