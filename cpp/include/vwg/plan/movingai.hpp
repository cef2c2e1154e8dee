// The MovingAI grid pathfinding benchmark formats (Sturtevant 2012, movingai.com): `.map` files
// and `.map.scen` scenario lists with published optimal lengths, to check and time the grid planners.
// The one reader of them: vwg.maps and the benchmarks call it through the bindings.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "vwg/geometry/occupancy_grid.hpp"
#include "vwg/plan/grid_graph.hpp"

namespace vwg::plan {

/// A MovingAI map. Rows are in file order (row 0 is the top line), so a scenario's (x, y) is
/// Cell{y, x}. Passable: '.', 'G', 'S'; blocked: '@', 'O', 'T', 'W'. Any other character is
/// refused (FileError naming its line, column and the character): the format has no other terrain,
/// and a map that holds one is damaged or not a map, so neither guess (free or blocked) is safe.
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
  Cell start;  ///< {y, x}: row from the top, column
  Cell goal;
  double optimal_length = 0.0;  ///< 8-connected, no corner cutting; printed to about 6 significant digits
};

/// Parse the text of a `.map` file ("type ..." / "height H" / "width W" / "map", then H rows of W
/// characters; LF, CRLF or CR line ends; blank lines at the end ignored). `source` names the file in
/// errors: FileError with the line, the column and the field ("type", "height", "width", "map",
/// "map[i]" for the i-th row from the top). A header whose H × W cells are more than the text's bytes
/// is refused before the grid is made (a 20-byte header can claim 10^12 cells).
MovingAiMap parse_movingai_map(std::string_view text, const std::string& source);
/// Read and parse a `.map` file (a regular file; a named pipe or a device is refused unread).
MovingAiMap read_movingai_map(const std::filesystem::path& path);

/// Parse the text of a `.map.scen` file ("version ..." then tab-separated lines of bucket, map,
/// width, height, start x, start y, goal x, goal y, optimal length; blank lines skipped). FileError
/// naming the line ("version", "scenario").
std::vector<MovingAiScenario> parse_movingai_scenarios(std::string_view text, const std::string& source);
/// Read and parse a `.map.scen` file.
std::vector<MovingAiScenario> read_movingai_scenarios(const std::filesystem::path& path);

/// The map as an occupancy grid (0 free, 100 blocked), its rows flipped so that row 0 is the bottom
/// row: MovingAI (x, y) is cell (height - 1 - y, x). The format has no scale or placement: they are
/// given here.
geometry::OccupancyGrid to_occupancy_grid(const MovingAiMap& map, double resolution = 1.0,
                                          const geometry::Pose2& origin = {});

}  // namespace vwg::plan
