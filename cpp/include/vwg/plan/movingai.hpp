// The MovingAI grid pathfinding benchmark formats (Sturtevant 2012, movingai.com): `.map` files
// and `.map.scen` scenario lists with published optimal lengths, to check and time the grid planners.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "vwg/plan/grid_graph.hpp"

namespace vwg::plan {

/// A MovingAI map. Rows are in file order (row 0 is the top line), so a scenario's (x, y) is
/// Cell{y, x}. Passable: '.', 'G', 'S'; everything else ('@', 'O', 'T', 'W') is blocked.
struct MovingAiMap {
  int width = 0;
  int height = 0;
  BlockedGrid grid;
};

/// One line of a `.map.scen` file.
struct MovingAiScenario {
  int bucket = 0;
  std::string map;  ///< the map path as written in the file
  int map_width = 0;
  int map_height = 0;
  Cell start;
  Cell goal;
  double optimal_length = 0.0;  ///< 8-connected, no corner cutting; printed to about 6 significant digits
};

/// Read a `.map` file (LF or CRLF). Throws ParseError naming the file, line and column.
MovingAiMap read_movingai_map(const std::filesystem::path& path);
/// Read a `.map.scen` file ("version 1", tab-separated). Throws ParseError naming the file and line.
std::vector<MovingAiScenario> read_movingai_scenarios(const std::filesystem::path& path);

}  // namespace vwg::plan
