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

void check_cell(const BlockedGrid& grid, Cell cell, const std::string& field, bool must_be_free) {
  if (!grid.inside(cell)) {
    throw SchemaError(field, "cell " + to_string(cell) + " is outside the grid of " + std::to_string(grid.rows()) +
                                 " rows × " + std::to_string(grid.cols()) + " columns");
  }
  if (must_be_free && grid.blocked(cell)) throw SchemaError(field, "cell " + to_string(cell) + " is blocked");
}

}  // namespace vwg::plan
