// Grid planners: A* on hand-worked grids and on every MovingAI benchmark scenario (published optimal
// lengths), Jump Point Search on the same and against A*, D* Lite against A* after changes, and the
// replanning comparison of the case study.
#include <gtest/gtest.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <ostream>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "plan/dstar_lite_search.hpp"
#include "vwg/detail/filled_array.hpp"
#include "vwg/error.hpp"
#include "vwg/plan/astar.hpp"
#include "vwg/plan/dstar_lite.hpp"
#include "vwg/plan/jps.hpp"
#include "vwg/plan/movingai.hpp"

using namespace vwg::plan;

namespace {

constexpr double kSqrt2 = 1.4142135623730951;
constexpr double kInf = std::numeric_limits<double>::infinity();

std::filesystem::path movingai_dir() {
  if (const char* dir = std::getenv("VWG_TEST_DATA")) return std::filesystem::path(dir) / "movingai";
  return std::filesystem::path(__FILE__).parent_path().parent_path() / "data" / "movingai";
}

/// A grid from rows of text: '#' blocked, anything else free; row 0 is the first string.
BlockedGrid grid_of(const std::vector<std::string>& rows) {
  BlockedGrid g(static_cast<int>(rows.size()), static_cast<int>(rows.front().size()));
  for (int r = 0; r < g.rows(); ++r) {
    for (int c = 0; c < g.cols(); ++c) g.set_blocked({r, c}, rows[r][c] == '#');
  }
  return g;
}

GridSearchOptions opts(bool diagonal, bool corner_cutting, Heuristic h = Heuristic::Euclidean) {
  GridSearchOptions o;
  o.diagonal = diagonal;
  o.corner_cutting = corner_cutting;
  o.heuristic = h;
  return o;
}

/// A random query: a grid of min_side + (0 .. spread - 1) rows and columns whose cells are blocked
/// with probability `wall`, a start (made free) and a goal, drawn from rng in that order.
struct RandomQuery {
  BlockedGrid grid;
  Cell start, goal;
};
RandomQuery random_query(std::mt19937& rng, int min_side, int spread, double wall) {
  const int rows = min_side + static_cast<int>(rng() % static_cast<unsigned>(spread));
  const int cols = min_side + static_cast<int>(rng() % static_cast<unsigned>(spread));
  RandomQuery q{BlockedGrid(rows, cols), {}, {}};
  std::bernoulli_distribution blocked(wall);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) q.grid.set_blocked({r, c}, blocked(rng));
  }
  q.start = {static_cast<int>(rng() % rows), static_cast<int>(rng() % cols)};
  q.goal = {static_cast<int>(rng() % rows), static_cast<int>(rng() % cols)};
  q.grid.set_blocked(q.start, false);
  return q;
}

/// Checks that `p` is a legal path of the graph from `start` to `goal` whose moves add up to its length.
void expect_legal(const BlockedGrid& g, const GridPath& p, Cell start, Cell goal, const GridSearchOptions& o) {
  ASSERT_TRUE(p.found());
  EXPECT_EQ(p.cells.front(), start);
  EXPECT_EQ(p.cells.back(), goal);
  double sum = 0.0;
  for (std::size_t i = 0; i < p.cells.size(); ++i) {
    const Cell c = p.cells[i];
    ASSERT_FALSE(g.blocked(c)) << to_string(c);
    if (i == 0) continue;
    const Cell prev = p.cells[i - 1];
    const int dr = c.row - prev.row, dc = c.col - prev.col;
    ASSERT_TRUE(std::abs(dr) <= 1 && std::abs(dc) <= 1 && (dr != 0 || dc != 0)) << to_string(prev) << " -> " << to_string(c);
    if (dr != 0 && dc != 0) {
      ASSERT_TRUE(o.diagonal) << "diagonal move on a 4-connected grid";
      if (!o.corner_cutting) {
        ASSERT_FALSE(g.blocked({prev.row + dr, prev.col}) || g.blocked({prev.row, prev.col + dc}))
            << "corner cut at " << to_string(prev) << " -> " << to_string(c);
      }
      sum += kSqrt2;
    } else {
      sum += 1.0;
    }
  }
  EXPECT_NEAR(sum, p.length, 1e-9);
}

template <class F>
std::string schema_field(F&& f) {
  try {
    f();
  } catch (const vwg::SchemaError& e) {
    return e.field();
  }
  return "<no SchemaError>";
}

}  // namespace

// --- A*, worked by hand ---

// 5×5 with a wall across row 2 open only at column 4: every path squeezes through (2, 4), entered
// from (1, 4) and left to (3, 4) straight, since the diagonals there would cut the wall's end.
//   (0,0)→(1,4): 3 + √2;  (1,4)→(2,4)→(3,4): 2;  (3,4)→(4,0): 3 + √2.  Total 8 + 2√2.
TEST(AStar, WallWithOneGap) {
  const BlockedGrid g = grid_of({".....", ".....", "####.", ".....", "....."});
  const auto o = opts(true, false);
  const GridPath p = astar(g, {0, 0}, {4, 0}, o);
  EXPECT_NEAR(p.length, 8.0 + 2.0 * kSqrt2, 1e-12);
  expect_legal(g, p, {0, 0}, {4, 0}, o);
  // Cutting corners: (0,0)→(2,4) is 2 + 2√2 through (1,3)→(2,4), and (2,4)→(4,0) likewise: 4 + 4√2.
  const auto cut = opts(true, true);
  const GridPath q = astar(g, {0, 0}, {4, 0}, cut);
  EXPECT_NEAR(q.length, 4.0 + 4.0 * kSqrt2, 1e-12);
  expect_legal(g, q, {0, 0}, {4, 0}, cut);
  // 4-connected: |Δ| to (2,4) is 6, and 6 again to (4,0).
  const auto four = opts(false, false, Heuristic::Manhattan);
  const GridPath r = astar(g, {0, 0}, {4, 0}, four);
  EXPECT_NEAR(r.length, 12.0, 1e-12);
  expect_legal(g, r, {0, 0}, {4, 0}, four);
  // The octile heuristic finds the same lengths.
  EXPECT_NEAR(astar(g, {0, 0}, {4, 0}, opts(true, false, Heuristic::Octile)).length, 8.0 + 2.0 * kSqrt2, 1e-12);
  EXPECT_NEAR(astar(g, {0, 0}, {4, 0}, opts(true, false, Heuristic::Zero)).length, 8.0 + 2.0 * kSqrt2, 1e-12);
}

TEST(AStar, CornerIsNotCut) {
  // (0,0)→(1,1) would pass the blocked (0,1): go round by (1,0), length 2; √2 when cutting is allowed.
  const BlockedGrid g = grid_of({".#", ".."});
  const GridPath p = astar(g, {0, 0}, {1, 1});
  EXPECT_EQ(p.cells, (std::vector<Cell>{{0, 0}, {1, 0}, {1, 1}}));
  EXPECT_DOUBLE_EQ(p.length, 2.0);
  const GridPath q = astar(g, {0, 0}, {1, 1}, opts(true, true));
  EXPECT_EQ(q.cells, (std::vector<Cell>{{0, 0}, {1, 1}}));
  EXPECT_DOUBLE_EQ(q.length, kSqrt2);
}

TEST(AStar, NoPath) {
  const BlockedGrid wall = grid_of({".#.", ".#.", ".#."});
  const GridPath p = astar(wall, {0, 0}, {2, 2});
  EXPECT_FALSE(p.found());
  EXPECT_TRUE(p.cells.empty());
  EXPECT_EQ(p.length, kInf);
  // Two free cells touching only at a corner are disconnected unless corners may be cut.
  const BlockedGrid diagonal = grid_of({".#", "#."});
  EXPECT_FALSE(astar(diagonal, {0, 0}, {1, 1}).found());
  EXPECT_DOUBLE_EQ(astar(diagonal, {0, 0}, {1, 1}, opts(true, true)).length, kSqrt2);
  // A blocked goal has no path (not an error).
  EXPECT_FALSE(astar(wall, {0, 0}, {1, 1}).found());
}

TEST(AStar, StartIsGoal) {
  const BlockedGrid g = grid_of({"...", "...", "..."});
  const GridPath p = astar(g, {1, 2}, {1, 2});
  EXPECT_EQ(p.cells, (std::vector<Cell>{{1, 2}}));
  EXPECT_EQ(p.length, 0.0);
}

TEST(AStar, OpenGridLengths) {
  const BlockedGrid g(10, 10);
  for (Heuristic h : {Heuristic::Euclidean, Heuristic::Octile}) {
    EXPECT_NEAR(astar(g, {0, 0}, {9, 9}, opts(true, false, h)).length, 9.0 * kSqrt2, 1e-12);
    EXPECT_NEAR(astar(g, {0, 0}, {3, 9}, opts(true, false, h)).length, 3.0 * kSqrt2 + 6.0, 1e-12);
    EXPECT_NEAR(astar(g, {9, 0}, {0, 9}, opts(false, false, h)).length, 18.0, 1e-12);
  }
}

TEST(AStar, AmongEqualFTheLastPushedGoesFirst) {
  // On an open 4-connected grid with the Manhattan heuristic (exact there) every cell on a shortest way
  // has the same f: taking the last pushed of equal f first dives along one way, so a search expands
  // only the cells of the path it returns (a first-in-first-out order among the ties would expand the
  // whole rectangle between start and goal).
  const BlockedGrid g(60, 80);
  AStar search;
  for (const auto& [start, goal] : {std::pair{Cell{0, 0}, Cell{59, 79}}, std::pair{Cell{50, 3}, Cell{7, 60}}}) {
    const GridPath p = search.search(g, start, goal, opts(false, false, Heuristic::Manhattan));
    EXPECT_EQ(p.length, static_cast<double>(std::abs(goal.row - start.row) + std::abs(goal.col - start.col)));
    EXPECT_EQ(search.expanded(), p.cells.size());
  }
}

TEST(AStar, EqualsDijkstraOnRandomGridsForEveryHeuristic) {
  // The open list's ring of buckets: the lengths of Dijkstra's algorithm (the zero heuristic) on grids
  // with long detours, where f climbs far above its start and the ring goes round many times.
  std::mt19937 rng(7);
  AStar search;
  for (int trial = 0; trial < 60; ++trial) {
    BlockedGrid g(40 + trial % 7, 50 + trial % 5);
    std::bernoulli_distribution wall(0.05 + 0.006 * trial);
    for (int r = 0; r < g.rows(); ++r) {
      for (int c = 0; c < g.cols(); ++c) {
        if (wall(rng)) g.set_blocked({r, c}, true);
      }
    }
    const Cell s{0, 0}, t{g.rows() - 1, g.cols() - 1};
    g.set_blocked(s, false);
    g.set_blocked(t, false);
    for (const bool diagonal : {false, true}) {
      const double truth = search.search(g, s, t, opts(diagonal, false, Heuristic::Zero)).length;
      for (Heuristic h : {Heuristic::Euclidean, Heuristic::Octile, Heuristic::Manhattan}) {
        if (diagonal && h == Heuristic::Manhattan) continue;
        const double length = search.search(g, s, t, opts(diagonal, false, h)).length;
        if (std::isinf(truth)) {
          EXPECT_TRUE(std::isinf(length));
        } else {
          EXPECT_NEAR(length, truth, 1e-9) << "trial " << trial << " diagonal " << diagonal;
        }
      }
    }
  }
}

TEST(AStar, WorkspaceIsReusedAcrossGridsAndSearches) {
  AStar search;
  const BlockedGrid small = grid_of({".#", ".."});
  const BlockedGrid wall = grid_of({".....", ".....", "####.", ".....", "....."});
  for (int i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(search.search(small, {0, 0}, {1, 1}).length, 2.0);
    EXPECT_NEAR(search.search(wall, {0, 0}, {4, 0}).length, 8.0 + 2.0 * kSqrt2, 1e-12);
    EXPECT_FALSE(search.search(wall, {0, 0}, {2, 0}).found());
    EXPECT_GT(search.expanded(), 0u);
  }
}

TEST(AStar, BadInputIsASchemaErrorNamingTheArgument) {
  const BlockedGrid g = grid_of({".#.", "...", "..."});
  EXPECT_EQ(schema_field([&] { astar(g, {-1, 0}, {2, 2}); }), "start");
  EXPECT_EQ(schema_field([&] { astar(g, {0, 3}, {2, 2}); }), "start");
  EXPECT_EQ(schema_field([&] { astar(g, {0, 1}, {2, 2}); }), "start");  // blocked
  EXPECT_EQ(schema_field([&] { astar(g, {0, 0}, {3, 0}); }), "goal");
  EXPECT_EQ(schema_field([&] { astar(g, {0, 0}, {2, 2}, opts(true, false, Heuristic::Manhattan)); }), "heuristic");
  EXPECT_EQ(schema_field([] { heuristic_from_name("chebyshev"); }), "heuristic");
  EXPECT_EQ(heuristic_from_name("octile"), Heuristic::Octile);
  try {
    astar(g, {0, 1}, {2, 2});
  } catch (const vwg::SchemaError& e) {
    EXPECT_EQ(std::string(e.what()), "start: cell (row 0, col 1) is blocked");
  }
}

TEST(BlockedGrid, MasksOfEveryTypeGiveTheSamePaddedCells) {
  // A random 37 × 53 mask as bool, bytes and doubles: the padded cells, border included, are those
  // set one at a time on a free grid.
  std::mt19937 rng(5);
  std::vector<bool> bits(37 * 53);
  for (auto&& b : bits) b = rng() % 3 == 0;
  std::unique_ptr<bool[]> as_bool(new bool[bits.size()]);
  std::vector<std::uint8_t> as_bytes(bits.size());
  std::vector<double> as_doubles(bits.size());
  BlockedGrid reference(37, 53);
  for (std::size_t i = 0; i < bits.size(); ++i) {
    as_bool[i] = bits[i];
    as_bytes[i] = bits[i] ? 7 : 0;
    as_doubles[i] = bits[i] ? -0.5 : 0.0;
    if (bits[i]) reference.set_blocked({static_cast<int>(i / 53), static_cast<int>(i % 53)}, true);
  }
  const auto cells = [](const BlockedGrid& g) { return std::vector<std::uint8_t>(g.padded().begin(), g.padded().end()); };
  EXPECT_EQ(cells(BlockedGrid::from_mask(std::span<const bool>(as_bool.get(), bits.size()), 37, 53)), cells(reference));
  EXPECT_EQ(cells(BlockedGrid::from_mask(std::span<const std::uint8_t>(as_bytes), 37, 53)), cells(reference));
  EXPECT_EQ(cells(BlockedGrid::from_mask(std::span<const double>(as_doubles), 37, 53)), cells(reference));
  // The border is blocked all round, the inside of a new grid free.
  const BlockedGrid empty(2, 3);
  const std::vector<std::uint8_t> expected{1, 1, 1, 1, 1, 1, 0, 0, 0, 1, 1, 0, 0, 0, 1, 1, 1, 1, 1, 1};
  EXPECT_EQ(cells(empty), expected);
}

TEST(BlockedGrid, MaskOccupancyAndBorder) {
  const std::vector<std::uint8_t> mask{0, 1, 0, 0, 0, 1};
  const BlockedGrid g = BlockedGrid::from_mask(std::span<const std::uint8_t>(mask), 2, 3);
  EXPECT_TRUE(g.blocked({0, 1}));
  EXPECT_TRUE(g.blocked({1, 2}));
  EXPECT_FALSE(g.blocked({1, 0}));
  EXPECT_TRUE(g.blocked({-1, 0}));  // outside counts as blocked
  EXPECT_EQ(g.blocked_count(), 2u);
  EXPECT_EQ(schema_field([] {
              const std::vector<std::uint8_t> m(5, 0);
              BlockedGrid::from_mask(std::span<const std::uint8_t>(m), 2, 3);
            }),
            "blocked");

  vwg::geometry::OccupancyGrid occ;
  occ.width = 3;
  occ.height = 1;
  occ.data = {0, 100, -1};
  EXPECT_EQ(BlockedGrid::from_occupancy(occ).blocked_count(), 2u);
  EXPECT_EQ(BlockedGrid::from_occupancy(occ, 50, false).blocked_count(), 1u);
}

// --- MovingAI: every scenario's published optimal length ---

TEST(MovingAi, ReadsCrlfFiles) {
  const auto dir = std::filesystem::temp_directory_path() / "vwg_test_plan_movingai";
  std::filesystem::create_directories(dir);
  {
    std::ofstream map(dir / "tiny.map", std::ios::binary);
    map << "type octile\r\nheight 2\r\nwidth 3\r\nmap\r\n.@G\r\nS.T\r\n";
    std::ofstream scen(dir / "tiny.map.scen", std::ios::binary);
    scen << "version 1\r\n0\ttiny.map\t3\t2\t0\t0\t2\t0\t2.41421356\r\n";
  }
  const MovingAiMap m = read_movingai_map(dir / "tiny.map");
  EXPECT_EQ(m.width, 3);
  EXPECT_EQ(m.height, 2);
  EXPECT_TRUE(m.grid.blocked({0, 1}));
  EXPECT_FALSE(m.grid.blocked({0, 2}));
  EXPECT_TRUE(m.grid.blocked({1, 2}));
  EXPECT_FALSE(m.grid.blocked({1, 0}));
  const auto s = read_movingai_scenarios(dir / "tiny.map.scen");
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].start, (Cell{0, 0}));
  EXPECT_EQ(s[0].goal, (Cell{0, 2}));
  // Every way from (0,0) to (0,2) passes (1,1) by diagonals that cut a blocked corner: no path,
  // unless corners may be cut (√2 + √2). (The scenario's length is made up: only reading is tested.)
  EXPECT_FALSE(astar(m.grid, s[0].start, s[0].goal, opts(true, false, Heuristic::Octile)).found());
  EXPECT_NEAR(astar(m.grid, s[0].start, s[0].goal, opts(true, true, Heuristic::Octile)).length, 2.0 * kSqrt2, 1e-12);
  std::filesystem::remove_all(dir);
}

TEST(MovingAi, MalformedMapIsAFileErrorNamingTheFileLineAndColumn) {
  const auto dir = std::filesystem::temp_directory_path() / "vwg_test_plan_movingai_bad";
  std::filesystem::create_directories(dir);
  {
    std::ofstream map(dir / "bad.map", std::ios::binary);
    map << "type octile\nheight 2\nwidth 3\nmap\n...\n..\n";
  }
  try {
    read_movingai_map(dir / "bad.map");
    ADD_FAILURE() << "no FileError";
  } catch (const vwg::FileError& e) {
    EXPECT_EQ(e.path(), (dir / "bad.map").string());
    EXPECT_EQ(e.field(), "map[1]");
    EXPECT_EQ(e.line(), 6u);
    EXPECT_EQ(e.column(), 3u);  // the first missing character
    EXPECT_EQ(e.message(), "row has 2 characters, expected 3");
  }
  std::filesystem::remove_all(dir);
}

/// The FileError of parsing `text`, or a failure when it parses.
static vwg::FileError movingai_error(const std::string& text) {
  try {
    parse_movingai_map(text, "m.map");
  } catch (const vwg::FileError& e) {
    return e;
  }
  ADD_FAILURE() << "parsed: " << text;
  return vwg::FileError("", "", "");
}

TEST(MovingAi, UnknownTerrainIsRefusedByLineColumnAndCharacter) {
  // The old reader took any other character as blocked; a damaged map then planned around walls
  // that were not there. Now the character is named, with its place.
  const vwg::FileError e = movingai_error("type octile\nheight 2\nwidth 3\nmap\n.@.\nT?.\n");
  EXPECT_EQ(e.field(), "map[1]");
  EXPECT_EQ(e.line(), 6u);
  EXPECT_EQ(e.column(), 2u);
  EXPECT_EQ(std::string(e.what()), "m.map:6:2: map[1]: unknown terrain '?' at column 2 (passable: . G S; blocked: @ O T W)");
  EXPECT_EQ(movingai_error("type octile\nheight 1\nwidth 2\nmap\n.\x01\n").message(),
            "unknown terrain '\\x01' at column 2 (passable: . G S; blocked: @ O T W)");
  const vwg::FileError byte = movingai_error("type octile\nheight 1\nwidth 2\nmap\n.\xc3\xa9\n");
  EXPECT_EQ(byte.message(), "not an ASCII MovingAI map (byte 0xc3)");
  EXPECT_EQ(byte.line(), 5u);
  EXPECT_EQ(byte.column(), 2u);
}

TEST(MovingAi, HeadersAreCheckedBeforeTheGridIsMade) {
  // 10^12 cells claimed by a 48-byte file: refused by the size, not by running out of memory.
  const vwg::FileError wide = movingai_error("type octile\nheight 1\nwidth 1000000000000\nmap\n..\n");
  EXPECT_EQ(wide.field(), "width");
  EXPECT_EQ(wide.line(), 3u);
  EXPECT_EQ(wide.message(), "the header says 1 rows of 1000000000000 cells, more than the file's 48 bytes hold");
  // More digits than 64 bits hold: still the size check, with the digits as written.
  EXPECT_EQ(movingai_error("type octile\nheight 99999999999999999999\nwidth 2\nmap\n..\n").message(),
            "the header says 99999999999999999999 rows of 2 cells, more than the file's 55 bytes hold");
  EXPECT_EQ(movingai_error("type octile\nheight 0\nwidth 2\nmap\n").field(), "height");
  EXPECT_EQ(movingai_error("type octile\nheight -2\nwidth 2\nmap\n").message(), "expected a whole number > 0, got '-2'");
  EXPECT_EQ(movingai_error("height 2\nwidth 3\nmap\n").message(), "expected 'type <value>', got 'height 2'");
  EXPECT_EQ(movingai_error("type octile\nheight 1\nwidth 1\nmop\n.\n").message(), "expected 'map' on line 4, got 'mop'");
  const vwg::FileError extra = movingai_error("type octile\nheight 1\nwidth 1\nmap\n.\n.\n");
  EXPECT_EQ(extra.message(), "more than 1 rows (the header says height 1)");
  EXPECT_EQ(extra.line(), 6u);
}

TEST(MovingAi, LineEndsAndTrailingBlankLines) {
  // LF, CRLF and a lone CR read the same; blank lines after the rows end the file.
  for (const std::string end : {"\n", "\r\n", "\r"}) {
    const std::string text = "type octile" + end + "height 2" + end + "width 3" + end + "map" + end + ".@G" + end + "SWT" + end + end + "  " + end;
    const MovingAiMap m = parse_movingai_map(text, "m.map");
    ASSERT_EQ(m.height, 2);
    EXPECT_FALSE(m.grid.blocked({0, 0}));
    EXPECT_TRUE(m.grid.blocked({0, 1}));
    EXPECT_FALSE(m.grid.blocked({0, 2}));
    EXPECT_FALSE(m.grid.blocked({1, 0}));
    EXPECT_TRUE(m.grid.blocked({1, 1}));
    EXPECT_TRUE(m.grid.blocked({1, 2}));
  }
}

TEST(MovingAi, OccupancyGridFlipsTheRows) {
  // MovingAI (x, y) = (2, 0) is the top row's last cell: row height - 1 - y = 1 of the grid, from the bottom.
  const MovingAiMap m = parse_movingai_map("type octile\nheight 2\nwidth 3\nmap\n..@\n...\n", "m.map");
  const vwg::geometry::OccupancyGrid g = to_occupancy_grid(m, 0.5, {1.0, 2.0, 0.0});
  EXPECT_EQ(g.data, (std::vector<std::int8_t>{0, 0, 0, 0, 0, 100}));
  EXPECT_EQ(g.resolution, 0.5);
  EXPECT_EQ(g.origin.y, 2.0);
}

TEST(MovingAi, ScenarioLinesAreCheckedByLine) {
  const auto s = parse_movingai_scenarios("version 1\n\n3\ta.map\t4\t5\t1\t2\t3\t0\t2.5\n", "a.scen");
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].bucket, 3);
  EXPECT_EQ(s[0].start, (Cell{2, 1}));
  EXPECT_EQ(s[0].goal, (Cell{0, 3}));
  try {
    parse_movingai_scenarios("version 1\n0\ta.map\t4\t5\t1\t2\t3\t0\n", "a.scen");
    ADD_FAILURE() << "a line without its optimal length parsed";
  } catch (const vwg::FileError& e) {
    EXPECT_EQ(e.line(), 2u);
    EXPECT_EQ(e.field(), "scenario");
  }
  EXPECT_THROW(parse_movingai_scenarios("0\ta.map\n", "a.scen"), vwg::FileError);
  EXPECT_THROW(read_movingai_map("/no/such/file.map"), vwg::FileError);
}

// Sanitizer builds run several times slower (a minute for all 8180 searches). They are there to
// find memory errors and undefined behaviour, which every 4th scenario exercises as well as all
// of them do; release builds check every scenario.
#if defined(__SANITIZE_ADDRESS__)
constexpr std::size_t kScenarioStride = 4;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr std::size_t kScenarioStride = 4;
#else
constexpr std::size_t kScenarioStride = 1;
#endif
#else
constexpr std::size_t kScenarioStride = 1;
#endif

struct BenchmarkCase {
  const char* map;
  Heuristic heuristic;
};

// Readable test names in ctest and gtest output (gtest prints raw bytes otherwise).
void PrintTo(const BenchmarkCase& c, std::ostream* os) {
  const char* names[] = {"euclidean", "octile", "manhattan", "zero"};
  *os << c.map << ", " << names[static_cast<int>(c.heuristic)];
}

class MovingAiScenarios : public ::testing::TestWithParam<BenchmarkCase> {};

TEST_P(MovingAiScenarios, AStarFindsEveryPublishedOptimalLength) {
  const auto [name, heuristic] = GetParam();
  const MovingAiMap map = read_movingai_map(movingai_dir() / (std::string(name) + ".map"));
  const auto scenarios = read_movingai_scenarios(movingai_dir() / (std::string(name) + ".map.scen"));
  ASSERT_FALSE(scenarios.empty());
  const GridSearchOptions o = opts(true, false, heuristic);
  AStar search;
  std::size_t expanded = 0;
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t searches = 0;
  for (std::size_t i = 0; i < scenarios.size(); i += kScenarioStride) {
    const MovingAiScenario& s = scenarios[i];
    ASSERT_EQ(s.map_width, map.width);
    ASSERT_EQ(s.map_height, map.height);
    const GridPath p = search.search(map.grid, s.start, s.goal, o);
    expanded += search.expanded();
    ++searches;
    ASSERT_TRUE(p.found()) << name << " scenario " << i;
    ASSERT_NEAR(p.length, s.optimal_length, 1e-4 * std::max(1.0, s.optimal_length)) << name << " scenario " << i;
    if (i % 25 == 0) expect_legal(map.grid, p, s.start, s.goal, o);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ timing   ] A* %s, %s heuristic: %zu of %zu scenarios, %.3f ms/search, %.0f expansions/search\n",
              name, std::string(heuristic_name(heuristic)).c_str(), searches, scenarios.size(),
              1e3 * seconds / searches, static_cast<double>(expanded) / searches);
}

INSTANTIATE_TEST_SUITE_P(AllMaps, MovingAiScenarios,
                         ::testing::Values(BenchmarkCase{"arena", Heuristic::Octile},
                                           BenchmarkCase{"arena", Heuristic::Euclidean},
                                           BenchmarkCase{"den312d", Heuristic::Octile},
                                           BenchmarkCase{"den312d", Heuristic::Euclidean},
                                           BenchmarkCase{"8room_000", Heuristic::Octile},
                                           BenchmarkCase{"8room_000", Heuristic::Euclidean},
                                           BenchmarkCase{"random512-10-0", Heuristic::Octile},
                                           BenchmarkCase{"random512-10-0", Heuristic::Euclidean}),
                         [](const ::testing::TestParamInfo<BenchmarkCase>& info) {
                           std::string n = std::string(info.param.map) + "_" +
                                           std::string(heuristic_name(info.param.heuristic));
                           for (char& ch : n) {
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           }
                           return n;
                         });

// --- Jump Point Search: A*'s lengths ---

TEST_P(MovingAiScenarios, JumpPointSearchFindsEveryPublishedOptimalLength) {
  const auto [name, heuristic] = GetParam();
  const MovingAiMap map = read_movingai_map(movingai_dir() / (std::string(name) + ".map"));
  const auto scenarios = read_movingai_scenarios(movingai_dir() / (std::string(name) + ".map.scen"));
  ASSERT_FALSE(scenarios.empty());
  const GridSearchOptions o = opts(true, false, heuristic);
  JumpPointSearch jps;
  AStar astar_search;
  std::size_t expanded = 0, astar_expanded = 0, searches = 0;
  for (std::size_t i = 0; i < scenarios.size(); i += kScenarioStride) {
    const MovingAiScenario& s = scenarios[i];
    const GridPath p = jps.search(map.grid, s.start, s.goal, o);
    expanded += jps.expanded();
    ++searches;
    ASSERT_TRUE(p.found()) << name << " scenario " << i;
    ASSERT_NEAR(p.length, s.optimal_length, 1e-4 * std::max(1.0, s.optimal_length)) << name << " scenario " << i;
    if (i % 25 == 0) {
      expect_legal(map.grid, p, s.start, s.goal, o);
      astar_search.search(map.grid, s.start, s.goal, o);
      astar_expanded += astar_search.expanded() * 25;
    }
  }
  std::printf("[ counts   ] JPS %s, %s heuristic: %.0f jump points expanded per search (A*: about %.0f cells)\n", name,
              std::string(heuristic_name(heuristic)).c_str(), static_cast<double>(expanded) / searches,
              static_cast<double>(astar_expanded) / searches);
}

TEST(JumpPointSearch, EqualsAStarOnRandomGrids) {
  std::mt19937 rng(77);
  JumpPointSearch jps;
  AStar reference;
  int found = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const auto [g, start, goal] = random_query(rng, 2, 40, 0.05 * (trial % 8));
    const GridSearchOptions o = opts(true, false, trial % 2 ? Heuristic::Octile : Heuristic::Euclidean);
    const GridPath full = reference.search(g, start, goal, o);
    const GridPath jumped = jps.search(g, start, goal, o);
    ASSERT_EQ(jumped.found(), full.found()) << "trial " << trial;
    if (!full.found()) continue;
    ++found;
    ASSERT_NEAR(jumped.length, full.length, 1e-9) << "trial " << trial;
    expect_legal(g, jumped, start, goal, o);
  }
  EXPECT_GT(found, 250);
}

TEST(JumpPointSearch, HandWorkedGrids) {
  // The wall with one gap (see AStar.WallWithOneGap): 8 + 2√2, through (2, 4).
  const BlockedGrid g = grid_of({".....", ".....", "####.", ".....", "....."});
  JumpPointSearch jps;
  const GridPath p = jps.search(g, {0, 0}, {4, 0});
  EXPECT_NEAR(p.length, 8.0 + 2.0 * kSqrt2, 1e-12);
  expect_legal(g, p, {0, 0}, {4, 0}, opts(true, false));
  // No corner is cut; two cells touching at a corner only are apart; a start that is its goal.
  EXPECT_EQ(jps.search(grid_of({".#", ".."}), {0, 0}, {1, 1}).cells, (std::vector<Cell>{{0, 0}, {1, 0}, {1, 1}}));
  EXPECT_FALSE(jps.search(grid_of({".#", "#."}), {0, 0}, {1, 1}).found());
  EXPECT_EQ(jps.search(g, {1, 2}, {1, 2}).cells, (std::vector<Cell>{{1, 2}}));
  EXPECT_FALSE(jps.search(g, {0, 0}, {2, 0}).found());  // a blocked goal
  // An open grid: one diagonal run and one straight run.
  EXPECT_NEAR(jps.search(BlockedGrid(10, 10), {0, 0}, {3, 9}).length, 3.0 * kSqrt2 + 6.0, 1e-12);
  // It is for 8-connected moves without corner cutting only; bad cells are named.
  EXPECT_EQ(schema_field([&] { jps.search(g, {0, 0}, {4, 0}, opts(false, false, Heuristic::Manhattan)); }), "options");
  EXPECT_EQ(schema_field([&] { jps.search(g, {0, 0}, {4, 0}, opts(true, true)); }), "options");
  EXPECT_EQ(schema_field([&] { jps.search(g, {2, 0}, {4, 0}); }), "start");
  EXPECT_EQ(schema_field([&] { jps.search(g, {0, 0}, {9, 0}); }), "goal");
}

// --- D* Lite ---

// 3 × 5 open grid, start (1,0), goal (1,4): 4 straight moves.
// Block (1,2): the detour goes over it by (0,1), (0,2), (0,3), entered and left diagonally only
// where no corner of (1,2) is cut: √2 + 1 + 1 + √2 = 2 + 2√2.
TEST(DStarLite, HandWorkedChanges) {
  DStarLite d(BlockedGrid(3, 5), {1, 0}, {1, 4});
  EXPECT_DOUBLE_EQ(d.path().length, 4.0);
  d.set_blocked({1, 2}, true);
  EXPECT_NEAR(d.path().length, 2.0 + 2.0 * kSqrt2, 1e-12);
  d.set_blocked({1, 2}, false);
  EXPECT_DOUBLE_EQ(d.path().length, 4.0);
  const std::vector<Cell> column{{0, 2}, {1, 2}, {2, 2}};
  d.update_cells(column, true);
  const GridPath none = d.path();
  EXPECT_FALSE(none.found());
  EXPECT_EQ(none.length, kInf);
  d.set_blocked({2, 2}, false);
  EXPECT_NEAR(d.path().length, 2.0 + 2.0 * kSqrt2, 1e-12);
  // The robot steps to (1,1): (1,1)→(2,2) would cut (1,2), so (2,1), (2,2), (2,3), then √2 to (1,4).
  d.move_to({1, 1});
  const GridPath p = d.path();
  EXPECT_NEAR(p.length, 3.0 + kSqrt2, 1e-12);
  expect_legal(d.grid(), p, {1, 1}, {1, 4}, d.options());
  // The robot's own cell turning blocked leaves it without a path (not an error).
  d.set_blocked({1, 1}, true);
  EXPECT_FALSE(d.path().found());
}

TEST(DStarLite, BadInput) {
  const BlockedGrid g = grid_of({".#.", "...", "..."});
  EXPECT_EQ(schema_field([&] { DStarLite(g, {0, 1}, {2, 2}); }), "start");
  EXPECT_EQ(schema_field([&] { DStarLite(g, {0, 0}, {5, 2}); }), "goal");
  DStarLite d(g, {0, 0}, {2, 2});
  EXPECT_EQ(schema_field([&] { d.move_to({0, 1}); }), "cell");
  EXPECT_EQ(schema_field([&] { d.move_to({3, 0}); }), "cell");
  const std::vector<Cell> outside{{1, 1}, {9, 9}};
  EXPECT_EQ(schema_field([&] { d.update_cells(outside, true); }), "cells");
  EXPECT_FALSE(d.grid().blocked({1, 1}));  // nothing changed
  // (0,0)→(1,1) would cut the blocked (0,1): one straight move first, then 1 + √2.
  EXPECT_NEAR(d.path().length, 2.0 + kSqrt2, 1e-12);
}

TEST(DStarLite, EqualsAStarAfterRandomChangesAndMoves) {
  std::mt19937 rng(20240521);
  int checks = 0;
  for (int trial = 0; trial < 120; ++trial) {
    const auto [g, start, goal] = random_query(rng, 8, 40, 0.1 + 0.05 * (trial % 4));
    const int rows = g.rows(), cols = g.cols();
    GridSearchOptions o;
    o.diagonal = trial % 5 != 0;
    o.corner_cutting = trial % 3 == 0;
    o.heuristic = !o.diagonal ? Heuristic::Manhattan : (trial % 2 ? Heuristic::Octile : Heuristic::Euclidean);
    DStarLite d(g, start, goal, o);
    AStar reference;
    for (int step = 0; step < 25; ++step) {
      const GridPath incremental = d.path();
      const GridPath full = reference.search(d.grid(), d.start(), goal, o);
      ASSERT_EQ(incremental.found(), full.found()) << "trial " << trial << " step " << step;
      if (full.found()) {
        ASSERT_NEAR(incremental.length, full.length, 1e-9 * std::max(1.0, full.length))
            << "trial " << trial << " step " << step;
        expect_legal(d.grid(), incremental, d.start(), goal, o);
      }
      ++checks;
      // The robot walks a step or two, then cells around change (some new obstacles, some cleared).
      if (incremental.found() && incremental.cells.size() > 2 && rng() % 2) {
        d.move_to(incremental.cells[1 + rng() % 2]);
      }
      std::vector<Cell> cells;
      const int n = 1 + static_cast<int>(rng() % 6);
      for (int k = 0; k < n; ++k) {
        const Cell c{static_cast<int>(rng() % rows), static_cast<int>(rng() % cols)};
        if (!(c == d.start())) cells.push_back(c);
      }
      d.update_cells(cells, rng() % 3 != 0);
    }
  }
  EXPECT_EQ(checks, 120 * 25);
}

TEST(FilledArray, ReadsTheFillUntilWrittenAndKeepsEveryBit) {
  FilledArray<double> a(100000, kInf);
  EXPECT_EQ(a.size(), 100000u);
  for (std::size_t i : {0u, 1u, 4095u, 4096u, 99999u}) EXPECT_EQ(a[i], kInf);
  const double values[] = {0.0, -0.0, 1.5, -kInf, std::numeric_limits<double>::denorm_min(), kInf};
  for (std::size_t k = 0; k < std::size(values); ++k) a.set(7 * k, values[k]);
  for (std::size_t k = 0; k < std::size(values); ++k) {
    EXPECT_EQ(std::signbit(a[7 * k]), std::signbit(values[k]));
    EXPECT_EQ(a[7 * k], values[k]);
  }
  a.set(3, std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(std::isnan(a[3]));
  FilledArray<double> copy = a;  // a deep copy: writing one leaves the other
  copy.set(1, 2.0);
  EXPECT_EQ(a[1], kInf);
  EXPECT_EQ(copy[1], 2.0);
  EXPECT_EQ(copy[7], -0.0);
  FilledArray<std::uint32_t> slots(10, 0xFFFFFFFFu);
  EXPECT_EQ(slots[9], 0xFFFFFFFFu);
  slots.set(9, 0);
  EXPECT_EQ(slots[9], 0u);
  EXPECT_EQ(slots[8], 0xFFFFFFFFu);
}

// The first plan on an open 4-connected grid with the Manhattan heuristic: every cell of the
// 100 × 100 rectangle between the corners has the same k1 (198). Breaking ties toward the start,
// the search goes down one shortest path: the goal, the 198 cells to the start and their queued
// neighbours, not the 10,000 cells of the plateau the paper's tie-break sweeps.
TEST(DStarLite, FirstPlanOnAnOpenGridGoesDownOnePath) {
  GridSearchOptions o;
  o.diagonal = false;
  o.heuristic = Heuristic::Manhattan;
  DStarLite d(BlockedGrid(100, 100), {0, 0}, {99, 99}, o);
  const GridPath p = d.path();
  EXPECT_EQ(p.length, 198.0);
  expect_legal(d.grid(), p, {0, 0}, {99, 99}, o);
  EXPECT_LE(d.expanded(), 2u * 199u);
}

// The queue's single-number keys order as the paper's lexicographic comparison (k1, then k2; k2
// reversed while diving), written out here, on keys with many ties in k1 and in k2, zeros and
// infinities; and give their key back.
TEST(DStarLite, QueueOrderIsTheLexicographicOrderOfTheKeys) {
  const double values[] = {0.0, 1e-300, 0.5, 1.0, 1.4142135623730951, 2.0, 2.0000000000000004, 198.0, 1e300,
                           std::numeric_limits<double>::infinity()};
  for (const bool dive : {true, false}) {
    for (double a1 : values)
      for (double a2 : values)
        for (double b1 : values)
          for (double b2 : values) {
            const bool first = a1 < b1 || (a1 == b1 && (dive ? a2 > b2 : a2 < b2));
            EXPECT_EQ(dstar_order::encode(a1, a2, dive) < dstar_order::encode(b1, b2, dive), first)
                << a1 << " " << a2 << " / " << b1 << " " << b2 << " dive " << dive;
          }
    for (double k1 : values)
      for (double k2 : values) {
        double back1 = -1.0, back2 = -1.0;
        dstar_order::decode(dstar_order::encode(k1, k2, dive), dive, back1, back2);
        EXPECT_EQ(back1, k1);
        EXPECT_EQ(back2, k2);
      }
  }
}

// 4-connected, Manhattan: exact keys, the paper's stop rule, and ties toward the start until the
// first blocked cell. Freed cells and moves keep the dive; a blocked cell ends it (a vertex whose
// g is now too low, tied with the start in k1, must not be left behind). Every plan is checked
// against A* from scratch, many of them right after the first blocked cell.
TEST(DStarLite, FourConnectedEqualsAStarThroughTheEndOfTheDive) {
  std::mt19937 rng(77);
  GridSearchOptions o;
  o.diagonal = false;
  o.heuristic = Heuristic::Manhattan;
  int checks = 0, found = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const auto [g, start, goal] = random_query(rng, 6, 30, 0.05 * (trial % 5));
    const int rows = g.rows(), cols = g.cols();
    DStarLite d(g, start, goal, o);
    AStar reference;
    const int free_steps = static_cast<int>(rng() % 4);  // updates that only free cells, before the first block
    for (int step = 0; step < 12; ++step) {
      const GridPath incremental = d.path();
      const GridPath full = reference.search(d.grid(), d.start(), goal, o);
      ASSERT_EQ(incremental.found(), full.found()) << "trial " << trial << " step " << step;
      if (full.found()) {
        ASSERT_EQ(incremental.length, full.length) << "trial " << trial << " step " << step;
        expect_legal(d.grid(), incremental, d.start(), goal, o);
        ++found;
      }
      ++checks;
      if (incremental.found() && incremental.cells.size() > 2 && rng() % 2) d.move_to(incremental.cells[1]);
      // Cells on the path ahead (where a stale g matters), and anywhere.
      std::vector<Cell> cells;
      for (std::size_t k = 2; k < incremental.cells.size() && cells.size() < 2; k += 1 + rng() % 4) {
        cells.push_back(incremental.cells[k]);
      }
      for (int k = 0; k < 3; ++k) cells.push_back({static_cast<int>(rng() % rows), static_cast<int>(rng() % cols)});
      std::erase_if(cells, [&](const Cell& c) { return c == d.start(); });
      d.update_cells(cells, step >= free_steps && rng() % 4 != 0);
    }
  }
  EXPECT_EQ(checks, 300 * 12);
  EXPECT_GT(found, checks / 2);
}

// Whole-number keys in 32 bits (ExactKeys) order as the lexicographic comparison written out, on
// keys with ties, zero and the largest values; and give their key back.
TEST(DStarLite, ExactQueueOrderIsTheLexicographicOrderOfTheKeys) {
  const std::uint32_t values[] = {0, 1, 2, 198, 0x3FFFFFFF, 0x40000000, 0xBFFFFFFE, 0xFFFFFFFE, 0xFFFFFFFF};
  for (const bool dive : {true, false}) {
    for (std::uint32_t a1 : values)
      for (std::uint32_t a2 : values)
        for (std::uint32_t b1 : values)
          for (std::uint32_t b2 : values) {
            const bool first = a1 < b1 || (a1 == b1 && (dive ? a2 > b2 : a2 < b2));
            EXPECT_EQ(dstar_order::encode(a1, a2, dive) < dstar_order::encode(b1, b2, dive), first)
                << a1 << " " << a2 << " / " << b1 << " " << b2 << " dive " << dive;
          }
    for (std::uint32_t k1 : values)
      for (std::uint32_t k2 : values) {
        std::uint32_t back1 = 7, back2 = 7;
        dstar_order::decode(dstar_order::encode(k1, k2, dive), dive, back1, back2);
        EXPECT_EQ(back1, k1);
        EXPECT_EQ(back2, k2);
      }
  }
}

// DStarLite takes whole-number keys exactly where every move costs 1 and the heuristic is
// Manhattan or none.
TEST(DStarLite, ExactKeysWhereEveryKeyIsAWholeNumber) {
  auto with = [](bool diagonal, Heuristic h) {
    GridSearchOptions o;
    o.diagonal = diagonal;
    o.heuristic = h;
    return DStarLite(BlockedGrid(4, 4), {0, 0}, {3, 3}, o).exact();
  };
  EXPECT_TRUE(with(false, Heuristic::Manhattan));
  EXPECT_TRUE(with(false, Heuristic::Zero));
  EXPECT_FALSE(with(false, Heuristic::Euclidean));
  EXPECT_FALSE(with(true, Heuristic::Octile));
  EXPECT_FALSE(with(true, Heuristic::Zero));
}

// Whole-number keys with a km limit of 6 instead of 2^30, so that km passes it every few moves
// and the queue's keys are computed anew: the same plans, expansions and cells as double keys
// (whose km never resets) through moves and changes, and as long as A*'s from scratch.
struct TinyKmKeys : ExactKeys {
  static constexpr Cost kKmLimit = 6;
};
template class vwg::plan::DStarLiteSearch<TinyKmKeys>;

TEST(DStarLite, WholeNumberKeysPlanAsDoubleKeysAlsoWhenKmStartsAgain) {
  std::mt19937 rng(4242);
  GridSearchOptions o;
  o.diagonal = false;
  o.heuristic = Heuristic::Manhattan;
  int resets = 0, found = 0;
  for (int trial = 0; trial < 150; ++trial) {
    const auto [g, start, goal] = random_query(rng, 6, 30, 0.05 * (trial % 5));
    const int rows = g.rows(), cols = g.cols();
    DStarLiteSearch<TinyKmKeys> tiny(g, start, goal, o);
    DStarLiteSearch<ExactKeys> exact(g, start, goal, o);
    DStarLiteSearch<RealKeys> real(g, start, goal, o);
    AStar reference;
    for (int step = 0; step < 12; ++step) {
      const GridPath p = real.path();
      const GridPath e = exact.path();
      const GridPath t = tiny.path();
      ASSERT_EQ(e.cells, p.cells) << "trial " << trial << " step " << step;
      ASSERT_EQ(e.length, p.length);
      ASSERT_EQ(exact.expanded(), real.expanded()) << "trial " << trial << " step " << step;
      const GridPath full = reference.search(real.grid(), real.start(), goal, o);
      ASSERT_EQ(t.found(), full.found()) << "trial " << trial << " step " << step;
      if (full.found()) {
        ASSERT_EQ(t.length, full.length) << "trial " << trial << " step " << step;
        expect_legal(tiny.grid(), t, tiny.start(), goal, o);
        ++found;
      }
      ASSERT_LT(tiny.km(), TinyKmKeys::kKmLimit);
      const bool moves = p.found() && p.cells.size() > 3;
      if (moves) {
        const Cell next = p.cells[1 + rng() % 3];
        tiny.move_to(next);
        exact.move_to(next);
        real.move_to(next);
      }
      std::vector<Cell> cells;
      for (int k = 0; k < 4; ++k) cells.push_back({static_cast<int>(rng() % rows), static_cast<int>(rng() % cols)});
      std::erase_if(cells, [&](const Cell& c) { return c == real.start(); });
      const bool blocked = rng() % 3 != 0;
      tiny.update_cells(cells, blocked);
      exact.update_cells(cells, blocked);
      real.update_cells(cells, blocked);
      resets += moves && tiny.km() == 0;  // km grows by at least 1 a move, unless it starts again
    }
  }
  EXPECT_GT(resets, 50);
  EXPECT_GT(found, 150 * 12 / 2);
}

// The case study's comparison: a robot walks its path across a 512 × 512 map and, eight times,
// obstacles appear on the path ahead of it: a 5 × 5 block 8 cells ahead, or a wall 31 cells wide
// and 3 thick 30 cells ahead. D* Lite repairs its search; the alternative is a fresh A* from the
// robot's cell. Both must agree on the length every time; the times are printed.
struct ObstacleEvent {
  const char* name;
  std::size_t ahead;  ///< cells along the path from the robot to the obstacle's centre
  int half_rows, half_cols;
};

void PrintTo(const ObstacleEvent& e, std::ostream* os) { *os << e.name; }

class Replanning : public ::testing::TestWithParam<ObstacleEvent> {};

TEST_P(Replanning, DStarLiteAgainstAStarOnA512Map) {
  const ObstacleEvent setup = GetParam();
  const MovingAiMap map = read_movingai_map(movingai_dir() / "random512-10-0.map");
  const auto scenarios = read_movingai_scenarios(movingai_dir() / "random512-10-0.map.scen");
  const MovingAiScenario& s = scenarios.back();  // the last bucket holds the longest paths
  GridSearchOptions o;  // 8-connected, no corner cutting, Euclidean: the paper's A*
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };

  auto t0 = Clock::now();
  DStarLite dstar(map.grid, s.start, s.goal, o);
  GridPath path = dstar.path();
  const double dstar_initial = seconds(t0);
  AStar astar_search;
  t0 = Clock::now();
  const GridPath first = astar_search.search(dstar.grid(), s.start, s.goal, o);
  const double astar_initial = seconds(t0);
  ASSERT_TRUE(path.found());
  ASSERT_NEAR(path.length, s.optimal_length, 1e-4 * s.optimal_length);
  ASSERT_NEAR(path.length, first.length, 1e-9 * first.length);

  const int events = 8;
  const std::size_t leg = path.cells.size() / (events + 2);
  double dstar_replans = 0.0, astar_replans = 0.0;
  std::size_t dstar_expanded = 0, astar_expanded = 0;
  for (int event = 0; event < events; ++event) {
    // Walk one leg of the current path, telling D* Lite where the robot is.
    for (std::size_t k = 1; k <= leg && k < path.cells.size(); ++k) dstar.move_to(path.cells[k]);
    const Cell robot = dstar.start();
    const GridPath ahead = dstar.path();
    ASSERT_GT(ahead.cells.size(), setup.ahead + 1);
    // The obstacle, oriented across the path's direction there.
    const Cell centre = ahead.cells[setup.ahead];
    const Cell next = ahead.cells[setup.ahead + 1];
    const bool across_rows = std::abs(next.col - centre.col) >= std::abs(next.row - centre.row);
    const int half_r = across_rows ? setup.half_cols : setup.half_rows;
    const int half_c = across_rows ? setup.half_rows : setup.half_cols;
    std::vector<Cell> obstacle;
    for (int dr = -half_r; dr <= half_r; ++dr) {
      for (int dc = -half_c; dc <= half_c; ++dc) {
        const Cell c{centre.row + dr, centre.col + dc};
        if (dstar.grid().inside(c) && !(c == robot) && !(c == s.goal)) obstacle.push_back(c);
      }
    }
    const std::size_t before = dstar.expanded();
    t0 = Clock::now();
    dstar.update_cells(obstacle, true);
    path = dstar.path();
    dstar_replans += seconds(t0);
    dstar_expanded += dstar.expanded() - before;

    t0 = Clock::now();
    const GridPath fresh = astar_search.search(dstar.grid(), robot, s.goal, o);
    astar_replans += seconds(t0);
    astar_expanded += astar_search.expanded();

    ASSERT_TRUE(fresh.found());
    ASSERT_NEAR(path.length, fresh.length, 1e-9 * fresh.length) << "event " << event;
    expect_legal(dstar.grid(), path, robot, s.goal, o);
  }
  std::printf("[ timing   ] 512x512 replanning, %d events (%s): D* Lite %.2f ms (initial %.2f ms; %zu expansions "
              "in replans), A* %.2f ms (initial %.2f ms; %zu expansions); A*/D* Lite replanning time %.1f\n",
              events, setup.name, 1e3 * dstar_replans, 1e3 * dstar_initial, dstar_expanded, 1e3 * astar_replans,
              1e3 * astar_initial, astar_expanded, astar_replans / dstar_replans);
  // The point of D* Lite: far less work per replan than searching again.
  EXPECT_LT(dstar_expanded, astar_expanded);
}

INSTANTIATE_TEST_SUITE_P(Obstacles, Replanning,
                         ::testing::Values(ObstacleEvent{"5x5 block 8 cells ahead", 8, 2, 2},
                                           ObstacleEvent{"31x3 wall 30 cells ahead", 30, 1, 15}),
                         [](const ::testing::TestParamInfo<ObstacleEvent>& info) {
                           return info.param.ahead == 8 ? std::string("BlockNear") : std::string("WallFurther");
                         });
