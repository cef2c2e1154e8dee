// The grids a planning decider keeps of a robot's map, followed cell by cell as the map changes,
// against their definition worked out from scratch at every step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "helpers.hpp"
#include "geometry/inflate.hpp"
#include "vwg/error.hpp"
#include "vwg/plan/astar.hpp"
#include "vwg/robot/planners.hpp"
#include "vwg/robot/planning_map.hpp"

using namespace vwg;
using namespace vwg::robot;

namespace {

bool blocks(std::int16_t v) { return v >= kWallCell || v == kUnknownCell; }

/// Whether the centre of (row, col) is within `rc` cells of a blocking square or of the map's edge,
/// by testing every square (the definition, no stamping).
bool within(const std::vector<std::int16_t>& cells, int rows, int cols, int row, int col, double rc) {
  const double cx = col + 0.5, cy = row + 0.5;
  if (std::min({cx, cols - cx, cy, rows - cy}) <= rc) return true;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!blocks(cells[static_cast<std::size_t>(r) * cols + c])) continue;
      const double ex = std::max({c - cx, cx - (c + 1), 0.0}), ey = std::max({r - cy, cy - (r + 1), 0.0});
      if (ex * ex + ey * ey <= rc * rc) return true;
    }
  }
  return false;
}

/// The grids `pm` keeps of `map` (rows × cols) equal those made from scratch by geometry::inflate
/// (stamping discs: a second method) over the map's cells.
void expect_grids_as_rebuilt(const PlanningMap& pm, const Blob& map, int rows, int cols, double rc, const std::string& what) {
  const auto cells = map.view<std::int16_t>();
  std::vector<std::uint8_t> mask(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) mask[i] = blocks(cells[i]);
  const auto obstacles = geometry::BlockedGrid::from_mask(std::span<const std::uint8_t>(mask), rows, cols);
  const auto inflated = geometry::inflate(obstacles, rc);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      ASSERT_EQ(pm.obstacles().blocked({r, c}), obstacles.blocked({r, c})) << what << " " << r << "," << c;
      ASSERT_EQ(pm.inflated().blocked({r, c}), inflated.blocked({r, c})) << what << " " << r << "," << c;
    }
  }
}

}  // namespace

TEST(PlanningMap, FollowsChangesCellByCellAsIfRebuilt) {
  const int rows = 24, cols = 31;
  const geometry::MapGeometry g{cols, rows, 0.1, {}};
  const double radius = 0.23;  // 2.3 cells
  Blob map(DType::Int16, {rows, cols});
  std::mt19937 rng(7);
  const std::int16_t values[] = {kFreeCell, kFreeCell, kFreeCell, kUnknownCell, kWallCell, kSeenCell, 1003};
  PlanningMap pm;
  EXPECT_TRUE(pm.update(map, g, radius));
  EXPECT_FALSE(pm.update(map, g, radius)) << "nothing changed";
  for (int step = 0; step < 60; ++step) {
    BlobEdit<std::int16_t> edit(map);
    const int changes = static_cast<int>(rng() % 6);
    for (int k = 0; k < changes; ++k) edit.set(rng() % map.size(), values[rng() % 7]);
    const bool changed = pm.update(map, g, radius);
    const auto cells_view = map.view<std::int16_t>();
    const std::vector<std::int16_t> cells(cells_view.begin(), cells_view.end());
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        ASSERT_EQ(pm.obstacles().blocked({r, c}), blocks(cells[static_cast<std::size_t>(r) * cols + c])) << step;
        ASSERT_EQ(pm.inflated().blocked({r, c}), within(cells, rows, cols, r, c, radius / g.resolution))
            << "step " << step << " cell " << r << "," << c;
      }
    }
    if (changes == 0) {
      EXPECT_FALSE(changed);
    }
  }
}

namespace {

/// A map of `rows` × `cols` with random walls, unknown cells and markers, shared (Blob::share).
std::shared_ptr<Blob> shared_random_map(int rows, int cols, std::mt19937& rng) {
  auto map = std::make_shared<Blob>(DType::Int16, std::vector<std::int64_t>{rows, cols});
  BlobEdit<std::int16_t> edit(*map);
  const std::int16_t values[] = {kWallCell, kWallCell, kUnknownCell, 1007};
  for (int k = 0; k < rows * cols / 40; ++k) edit.set(rng() % map->size(), values[rng() % 4]);
  map->share();
  return map;
}

/// Random reported obstacles set and cleared, as a robot's laser does.
void random_sightings(Blob& map, std::mt19937& rng, int n) {
  BlobEdit<std::int16_t> edit(map);
  for (int k = 0; k < n; ++k) {
    const std::size_t cell = rng() % map.size();
    if (map.view<std::int16_t>()[cell] == kFreeCell || map.view<std::int16_t>()[cell] == kSeenCell) {
      edit.set(cell, rng() % 2 ? kSeenCell : kFreeCell);
    }
  }
}

}  // namespace

TEST(PlanningMap, ACopyOfASharedMapStartsFromItsGridsAndFollowsItsChanges) {
  // Robots' maps copied from one shared map (the known map): each one's grids start from the grids
  // of the shared content and follow its own changes. Compared at every step with grids made from
  // scratch by geometry::inflate (stamping discs: a second method) over the copy's cells.
  const int rows = 260, cols = 300;  // every grid above SharedPages::kMinShared (64 KB), even a byte a cell
  const geometry::MapGeometry g{cols, rows, 0.05, {}};
  const double radius = 0.2;
  std::mt19937 rng(11);
  const auto shared = shared_random_map(rows, cols, rng);
  ASSERT_TRUE(shared->shared());
  auto seeing = shared->clone(), idle = shared->clone();
  random_sightings(*seeing, rng, 300);  // before its first look: the start must follow these too
  PlanningMap pm_seeing, pm_idle;
  EXPECT_TRUE(pm_idle.update(*idle, g, radius));
  EXPECT_EQ(pm_idle.private_pages(), 0u) << "an unchanged copy's grids are the shared ones";
  for (int step = 0; step < 8; ++step) {
    if (step > 0) random_sightings(*seeing, rng, 40);
    pm_seeing.update(*seeing, g, radius);
    expect_grids_as_rebuilt(pm_seeing, *seeing, rows, cols, radius / g.resolution, "step " + std::to_string(step));
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(pm_seeing.private_pages(), 0u);
  // The idle robot's grids are still those of the shared map.
  const auto cells = shared->view<std::int16_t>();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const geometry::Cell c{static_cast<int>(i / cols), static_cast<int>(i % cols)};
    ASSERT_EQ(pm_idle.obstacles().blocked(c), blocks(cells[i]));
  }
}

TEST(PlanningMap, RobotsOfOneSharedMapWithOtherCellSizesGetTheirOwnGrids) {
  // The shared grids are made per map, radius and cell size: the same radius is 4 cells at 0.05 m
  // and 2 at 0.1 m.
  const int rows = 260, cols = 300;
  std::mt19937 rng(9);
  const auto shared = shared_random_map(rows, cols, rng);
  for (const double resolution : {0.05, 0.1, 0.05}) {
    const geometry::MapGeometry g{cols, rows, resolution, {}};
    PlanningMap pm;
    pm.update(*shared->clone(), g, 0.2);
    const auto cells = shared->view<std::int16_t>();
    std::vector<std::uint8_t> mask(cells.size());
    for (std::size_t i = 0; i < cells.size(); ++i) mask[i] = blocks(cells[i]);
    const auto inflated =
        geometry::inflate(geometry::BlockedGrid::from_mask(std::span<const std::uint8_t>(mask), rows, cols), 0.2 / resolution);
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) ASSERT_EQ(pm.inflated().blocked({r, c}), inflated.blocked({r, c})) << resolution << ": " << r << "," << c;
    }
  }
}

TEST(PlanningMap, GridsGiveBackThePagesOfWhatHasGone) {
  const int rows = 260, cols = 300;
  const geometry::MapGeometry g{cols, rows, 0.05, {}};
  std::mt19937 rng(5);
  const auto shared = shared_random_map(rows, cols, rng);
  auto map = shared->clone();
  PlanningMap pm;
  pm.update(*map, g, 0.2);
  // A passer-by seen in the middle of the map, then gone.
  std::vector<std::size_t> seen;
  for (int r = 120; r < 126; ++r) {
    for (int c = 140; c < 146; ++c) {
      const auto at = static_cast<std::size_t>(r) * cols + c;
      if (map->view<std::int16_t>()[at] == kFreeCell) seen.push_back(at);
    }
  }
  ASSERT_FALSE(seen.empty());
  BlobEdit<std::int16_t> edit(*map);
  // What the kernel holds privately for the map and the two grids (pages copied on write).
  auto held = [&] {
    return std::vector<long long>{vwg::testing::anonymous_bytes(map->data()), vwg::testing::anonymous_bytes(pm.obstacles().padded().data()),
                                  vwg::testing::anonymous_bytes(pm.inflated().padded().data())};
  };
  for (const std::size_t at : seen) edit.set(at, kSeenCell);
  pm.update(*map, g, 0.2);
  EXPECT_GT(pm.private_pages(), 0u);
  for (const long long bytes : held()) EXPECT_GT(bytes, 0);
  for (const std::size_t at : seen) edit.set(at, kFreeCell);
  pm.update(*map, g, 0.2);
  EXPECT_EQ(pm.private_pages(), 0u) << "equal again";
  // The grids give the pages back within kReshareEvery looks at a new revision of the map (here
  // a cell set and set back: a new revision, the same content).
  for (int k = 0; k < kReshareEvery; ++k) {
    edit.set(seen[0], kSeenCell);
    edit.set(seen[0], kFreeCell);
    EXPECT_FALSE(pm.update(*map, g, 0.2));
  }
  EXPECT_EQ(held()[1], 0) << "the grids keep no page of the passer-by";
  EXPECT_EQ(held()[2], 0);
  EXPECT_GT(held()[0], 0) << "the map gives its pages back when its robot does (ARobot::edit_map)";
  EXPECT_GT(edit.reshare(), 0u);
  EXPECT_EQ(held()[0], 0);
  EXPECT_EQ(map->private_pages(), 0u);
  // And at once when asked.
  for (const std::size_t at : seen) edit.set(at, kSeenCell);
  pm.update(*map, g, 0.2);
  for (const std::size_t at : seen) edit.set(at, kFreeCell);
  pm.update(*map, g, 0.2);
  EXPECT_GT(held()[1], 0) << "the 21st look at a new revision, not a multiple of 16: not yet given back";
  pm.reshare();
  EXPECT_EQ(held()[1], 0);
  EXPECT_EQ(held()[2], 0);
}

TEST(PlanningMap, EachRobotGivesBackItsPagesInAFrameOfItsOwn) {
  // A robot's looks are counted from reshare_phase(robot), its id mod 16: robot 5 gives its grids' pages back at
  // its 11th look at a new revision (5 + 11 = 16), robot 16 at its 16th, robot -3 (-3 mod 16 = 13) at its 3rd. The
  // first look, from the shared grids, counts and keeps the count.
  const int rows = 260, cols = 300;
  const geometry::MapGeometry g{cols, rows, 0.05, {}};
  for (const auto& [robot, due] : {std::pair{5, 11}, std::pair{16, 16}, std::pair{-3, 3}}) {
    std::mt19937 rng(5);
    const auto shared = shared_random_map(rows, cols, rng);
    auto map = shared->clone();
    PlanningMap pm(robot);
    pm.update(*map, g, 0.2);  // look 1
    std::size_t at = static_cast<std::size_t>(123) * cols + 143;
    while (map->view<std::int16_t>()[at] != kFreeCell) ++at;
    BlobEdit<std::int16_t> edit(*map);
    edit.set(at, kSeenCell);
    pm.update(*map, g, 0.2);  // look 2: a passer-by, its pages copied
    for (int look = 3; look <= due; ++look) {
      EXPECT_GT(vwg::testing::anonymous_bytes(pm.obstacles().padded().data()), 0) << robot << ": look " << look;
      edit.set(at, look == 3 ? kFreeCell : kSeenCell);
      if (look > 3) edit.set(at, kFreeCell);
      pm.update(*map, g, 0.2);
    }
    EXPECT_EQ(vwg::testing::anonymous_bytes(pm.obstacles().padded().data()), 0) << robot << ": given back at look " << due;
  }
}

TEST(ObstacleBits, EachRobotCountsItsEditsFromItsOwnPhase) {
  // reshare_due_after_edit() is true at the 11th edit for robot 5, the 16th for robot 32, the 3rd for robot -3,
  // and every 16 edits after (worked out from the ids mod 16: 5, 0, 13); a copy of a shared map's bits keeps the
  // robot's count.
  const int rows = 64, cols = 64;
  const geometry::MapGeometry g{cols, rows, 0.05, {}};
  std::mt19937 rng(7);
  const auto shared = shared_random_map(rows, cols, rng);
  using Due = std::vector<int>;
  for (const auto& [robot, expected] : {std::pair{5, Due{11, 27}}, std::pair{32, Due{16, 32}}, std::pair{-3, Due{3, 19, 35}}}) {
    ObstacleBits bits(robot);
    auto map = shared->clone();
    bits.sync(*map, g);
    std::vector<int> due;
    for (int edit = 1; edit <= 40; ++edit) {
      if (bits.reshare_due_after_edit()) due.push_back(edit);
    }
    EXPECT_EQ(due, expected) << robot;
  }
}

TEST(PlanningMap, ACellChangedAndChangedBackIsNoChange) {
  const geometry::MapGeometry g{10, 10, 0.1, {}};
  Blob map(DType::Int16, {10, 10});
  PlanningMap pm;
  pm.update(map, g, 0.2);
  BlobEdit<std::int16_t> edit(map);
  edit.set(55, kSeenCell);
  edit.set(55, kFreeCell);
  EXPECT_FALSE(pm.update(map, g, 0.2));
  edit.set(55, kSeenCell);
  EXPECT_TRUE(pm.update(map, g, 0.2));
  EXPECT_TRUE(pm.obstacles().blocked({5, 5}));
}

TEST(PlanningMap, FollowsAMapThatCannotTellWhatWasWritten) {
  // Between two looks: more writes than the map's log keeps, or a write of the whole map. The
  // grids then compare every cell; checked against grids made from scratch (geometry::inflate).
  const int rows = 60, cols = 70;
  const geometry::MapGeometry g{cols, rows, 0.05, {}};
  const double radius = 0.12;
  std::mt19937 rng(17);
  Blob map(DType::Int16, {rows, cols});
  PlanningMap pm;
  pm.update(map, g, radius);
  BlobEdit<std::int16_t> edit(map);
  const std::int16_t values[] = {kFreeCell, kFreeCell, kUnknownCell, kSeenCell};
  for (std::size_t k = 0; k < 3 * Blob::kLoggedWrites; ++k) edit.set(rng() % map.size(), values[rng() % 4]);
  EXPECT_FALSE(map.written_since(Blob::Mark{}, [](std::size_t) {})) << "the case under test: the log cannot tell";
  EXPECT_TRUE(pm.update(map, g, radius));
  expect_grids_as_rebuilt(pm, map, rows, cols, radius / g.resolution, "after more writes than the log keeps");
  auto whole = map.mutable_view<std::int16_t>();
  for (int c = 0; c < cols; ++c) whole[static_cast<std::size_t>(30) * cols + c] = kWallCell;  // a wall across
  EXPECT_TRUE(pm.update(map, g, radius));
  expect_grids_as_rebuilt(pm, map, rows, cols, radius / g.resolution, "after a write of the whole map");
  EXPECT_FALSE(pm.update(map, g, radius));
}

TEST(TiledIndex, EveryCellHasItsOwnPlaceAndATileIsOnePage) {
  // A 70 × 150 array in tiles of 32 × 64 two-byte elements (the disc counts): every cell inside
  // the padded size, no two at one place, and the cells of a tile on one 4 KB page.
  const int rows = 70, cols = 150;
  const TiledIndex<5, 6> at(rows, cols);
  EXPECT_EQ(at.size(), 3u * 3u * 32u * 64u);  // 3 tiles down (96 rows), 3 across (192 columns)
  std::vector<int> seen(at.size(), 0);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = at(r, c);
      ASSERT_LT(i, at.size());
      ASSERT_EQ(seen[i]++, 0) << r << "," << c;
      ASSERT_EQ(i * 2 / 4096, at(r / 32 * 32, c / 64 * 64) * 2 / 4096) << "a tile is one page: " << r << "," << c;
    }
  }
}

TEST(PlanningMap, RefusesAMapOfAnotherShape) {
  PlanningMap pm;
  Blob map(DType::Int16, {4, 4});
  EXPECT_THROW(pm.update(map, geometry::MapGeometry{5, 4, 0.1, {}}, 0.2), SchemaError);
}

namespace {
/// One beam from (x0, y0) to (x1, y1) through sense_scan, clearing only: its mark point is off the
/// map. Returns how many cells changed.
int clear_along(MapEdit& map, const geometry::MapGeometry& g, ObstacleBits& bits, double x0, double y0, double x1, double y1) {
  const ScanBeam beam{x1, y1, -1e6, -1e6};
  return sense_scan(map, g, bits, x0, y0, std::span<const ScanBeam>(&beam, 1));
}
}  // namespace

TEST(ObstacleBits, ACopyOfASharedMapStartsFromItsBitsAndItsOwnCells) {
  const int rows = 260, cols = 300;
  const geometry::MapGeometry g{cols, rows, 0.05, {}};
  std::mt19937 rng(3);
  const auto shared = shared_random_map(rows, cols, rng);
  for (int robot = 0; robot < 3; ++robot) {
    auto map = shared->clone();
    random_sightings(*map, rng, robot * 200);
    ObstacleBits bits;
    bits.sync(*map, g);
    const auto cells = map->view<std::int16_t>();
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        const std::int16_t v = cells[static_cast<std::size_t>(r) * cols + c];
        ASSERT_EQ(bits.seen(r, c), v == kSeenCell) << robot << ": " << r << "," << c;
        ASSERT_EQ(bits.obstacle(r, c), is_obstacle(v)) << robot << ": " << r << "," << c;
        if ((r & 7) == 0 && (c & 7) == 0) {
          bool any = false;
          for (int dr = 0; dr < 8 && r + dr < rows; ++dr) {
            for (int dc = 0; dc < 8 && c + dc < cols; ++dc) any = any || cells[static_cast<std::size_t>(r + dr) * cols + c + dc] == kSeenCell;
          }
          ASSERT_EQ(bits.block_flag(r >> 3, c >> 3), any) << robot << ": block " << r << "," << c;
        }
      }
    }
  }
}

TEST(ObstacleBits, ClearingWithTheBitsClearsWhatTheCellWalkClears) {
  // Two maps with the same random reported obstacles; beams from random places carve both, one
  // walking every cell (carve_free), one through sense_scan, which reads ObstacleBits.
  const geometry::MapGeometry g{45, 37, 0.1, {}};
  Blob plain(DType::Int16, {37, 45}), fast(DType::Int16, {37, 45});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x(-0.5, 5.0), y(-0.5, 4.2);
  BlobEdit<std::int16_t> a(plain), b(fast);
  ObstacleBits seen;
  for (int k = 0; k < 300; ++k) {
    const double px = x(rng), py = y(rng);
    mark_obstacle(a, g, px, py);
    seen.sync(fast, g);
    mark_obstacle(b, g, px, py, &seen);
    seen.keep(fast);
  }
  for (int k = 0; k < 60; ++k) {
    const double x0 = x(rng), y0 = y(rng), x1 = x(rng), y1 = y(rng);
    const int n = carve_free(a, g, x0, y0, x1, y1);
    seen.sync(fast, g);
    EXPECT_EQ(clear_along(b, g, seen, x0, y0, x1, y1), n);
    seen.keep(fast);
    if (k % 20 == 0) mark_obstacle(b, g, x0, y0, &seen), mark_obstacle(a, g, x0, y0), seen.keep(fast);
  }
  // Beams along the grid's lines, along diagonals and through block corners.
  for (int k = 0; k < 400; ++k) {
    const double px = x(rng), py = y(rng);
    if (k % 3 == 0) mark_obstacle(a, g, px, py), seen.sync(fast, g), mark_obstacle(b, g, px, py, &seen), seen.keep(fast);
    const int kind = k % 4;
    const double x0 = kind == 0 ? std::round(px * 10) / 10 : (kind == 1 ? 0.8 : px), y0 = kind == 0 ? std::round(py * 10) / 10 : py;
    const double len = 0.5 + (k % 37) * 0.1, a0 = kind == 1 ? M_PI / 4 * (k % 8) : std::atan2(py - 2, px - 2.5) + (k % 5) * 0.3;
    const double x1 = x0 + len * std::cos(a0), y1 = y0 + len * std::sin(a0);
    const int n = carve_free(a, g, x0, y0, x1, y1);
    seen.sync(fast, g);
    ASSERT_EQ(clear_along(b, g, seen, x0, y0, x1, y1), n) << "beam " << k;
    seen.keep(fast);
  }
  const auto pa = plain.view<std::int16_t>(), pb = fast.view<std::int16_t>();
  EXPECT_TRUE(std::equal(pa.begin(), pa.end(), pb.begin(), pb.end()));
  EXPECT_GT(std::count(pa.begin(), pa.end(), kSeenCell), 5) << "some are left";
  EXPECT_LT(std::count(pa.begin(), pa.end(), kSeenCell), 290) << "some were cleared";
}

TEST(ObstacleBits, OnALargeMapWithFewObstaclesTheBitsClearWhatTheCellWalkClears) {
  // A large map with few reported obstacles, so that most blocks have none; beams from cell
  // centres and block corners, along the grid's lines and diagonals; new obstacles are marked as
  // the beams go.
  const geometry::MapGeometry g{200, 150, 0.05, {}};
  Blob plain(DType::Int16, {150, 200}), fast(DType::Int16, {150, 200});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(-0.2, 10.2), y(-0.2, 7.7), unit(0.0, 1.0);
  BlobEdit<std::int16_t> a(plain), b(fast);
  ObstacleBits seen;
  auto mark = [&](double px, double py) {
    mark_obstacle(a, g, px, py);
    seen.sync(fast, g);
    mark_obstacle(b, g, px, py, &seen);
    seen.keep(fast);
  };
  for (int k = 0; k < 40; ++k) mark(x(rng), y(rng));
  int cleared = 0;
  for (int k = 0; k < 5000; ++k) {
    // From cell centres, cell corners (on a block's corner every 8 cells) or anywhere.
    double x0 = x(rng), y0 = y(rng);
    if (k % 3 == 0) x0 = std::round(x0 / 0.05) * 0.05, y0 = std::round(y0 / 0.05) * 0.05;
    if (k % 3 == 1) x0 = std::round(x0 / 0.4) * 0.4, y0 = std::round(y0 / 0.4) * 0.4;
    const double angle = k % 2 ? std::round(unit(rng) * 16) * M_PI / 8 : unit(rng) * 2 * M_PI;
    const double len = 0.1 + 9.0 * unit(rng);
    const double x1 = x0 + len * std::cos(angle), y1 = y0 + len * std::sin(angle);
    const int n = carve_free(a, g, x0, y0, x1, y1);
    seen.sync(fast, g);
    ASSERT_EQ(clear_along(b, g, seen, x0, y0, x1, y1), n) << "beam " << k;
    seen.keep(fast);
    cleared += n;
    if (k % 25 == 0) mark(x1, y1);
  }
  const auto pa = plain.view<std::int16_t>(), pb = fast.view<std::int16_t>();
  EXPECT_TRUE(std::equal(pa.begin(), pa.end(), pb.begin(), pb.end()));
  EXPECT_GT(cleared, 50) << "beams did clear reported obstacles";
}

namespace {
/// Whether the segment p0 -> p1 passes through the inside of the unit square of cell (row, col)
/// (grid units), by clipping its parameter to the square's slabs (Liang-Barsky): an independent
/// account of the cells a beam crosses.
bool crosses_inside(double u0, double v0, double u1, double v1, int row, int col) {
  double lo = 0.0, hi = 1.0;
  const double d[2] = {u1 - u0, v1 - v0}, p[2] = {u0, v0}, a[2] = {double(col), double(row)};
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0) {
      if (p[k] <= a[k] || p[k] >= a[k] + 1) return false;
      continue;
    }
    double t0 = (a[k] - p[k]) / d[k], t1 = (a[k] + 1 - p[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0), hi = std::min(hi, t1);
  }
  return lo < hi;
}
}  // namespace

TEST(ObstacleBits, ABeamClearsTheCellsItCrossesAndNotTheOneItEndsIn) {
  // Every cell a reported obstacle; a beam clears exactly the cells whose inside the segment
  // crosses, its end cell excepted (random segments: no exact grid corner on the way).
  const geometry::MapGeometry g{64, 48, 0.1, {}};
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> x(0.01, 6.39), y(0.01, 4.79);
  for (int k = 0; k < 400; ++k) {
    Blob map(DType::Int16, {48, 64});
    BlobEdit<std::int16_t> edit(map);
    for (std::size_t i = 0; i < map.size(); ++i) edit.set(i, kSeenCell);
    ObstacleBits bits;
    bits.sync(map, g);
    const double x0 = x(rng), y0 = y(rng), x1 = k % 2 ? x(rng) : x0 + (k % 8) * 0.9, y1 = k % 2 ? y(rng) : y0 + 0.05;
    if (x1 >= 6.4) continue;
    const int n = k % 3 ? clear_along(edit, g, bits, x0, y0, x1, y1) : carve_free(edit, g, x0, y0, x1, y1);
    const auto cells = map.view<std::int16_t>();
    const int end_row = static_cast<int>(y1 / 0.1), end_col = static_cast<int>(x1 / 0.1);
    int expected = 0;
    for (int r = 0; r < 48; ++r) {
      for (int c = 0; c < 64; ++c) {
        const bool crossed = crosses_inside(x0 / 0.1, y0 / 0.1, x1 / 0.1, y1 / 0.1, r, c) && !(r == end_row && c == end_col);
        expected += crossed;
        ASSERT_EQ(cells[static_cast<std::size_t>(r) * 64 + c] == kFreeCell, crossed) << "beam " << k << " cell " << r << "," << c;
      }
    }
    EXPECT_EQ(n, expected);
  }
}

TEST(ObstacleBits, MarkingReadsTheBitsAndLeavesWallsAndMarkers) {
  const geometry::MapGeometry g{16, 16, 0.1, {}};
  Blob map(DType::Int16, {16, 16});
  BlobEdit<std::int16_t> edit(map);
  edit.set(3 * 16 + 4, kWallCell);
  ObstacleBits bits;
  bits.sync(map, g);
  EXPECT_TRUE(bits.obstacle(3, 4) && !bits.seen(3, 4));
  EXPECT_FALSE(mark_obstacle(edit, g, 0.45, 0.35, &bits)) << "a wall stays a wall";
  EXPECT_TRUE(mark_marker(edit, g, 0.95, 0.95, 7, &bits));
  EXPECT_FALSE(mark_obstacle(edit, g, 0.95, 0.95, &bits)) << "a marker stays a marker";
  EXPECT_TRUE(mark_obstacle(edit, g, 1.25, 0.15, &bits));
  bits.keep(map);
  EXPECT_TRUE(bits.seen(1, 12) && bits.obstacle(1, 12) && bits.block_flag(0, 1) && !bits.block_flag(1, 1));
  const auto cells = map.view<std::int16_t>();
  EXPECT_EQ(cells[3 * 16 + 4], kWallCell);
  EXPECT_EQ(cells[9 * 16 + 9], kMarkerBase + 7);
  EXPECT_EQ(cells[1 * 16 + 12], kSeenCell);
  // A map changed behind its back (another revision) is read again.
  ObstacleBits fresh;
  fresh.sync(map, g);
  EXPECT_TRUE(fresh.seen(1, 12) && fresh.obstacle(9, 9) && !fresh.seen(9, 9));
}

TEST(SenseScan, TheMapIsTheSameAsClearingAndMarkingBeamByBeam) {
  // Random maps of walls, markers, unknown, free cells and reported obstacles; scans from
  // anywhere, from cell and block corners and from grid lines, with beams in order or not, along
  // the axes and diagonals, of no length, ending on grid lines or outside the map. Each scan is
  // applied beam by beam with carve_free and mark_obstacle (no bits: every cell read), and at once
  // with sense_scan; the maps and the bits must agree.
  const geometry::MapGeometry g{60, 45, 0.1, {}};
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> kind(0, 99);
  int changed_cells = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Blob reference(DType::Int16, {45, 60}), fast(DType::Int16, {45, 60});
    BlobEdit<std::int16_t> a(reference), b(fast);
    for (std::size_t i = 0; i < reference.size(); ++i) {
      const int k = kind(rng);
      const std::int16_t v = k < 6 ? kWallCell : k < 7 ? kMarkerBase + 3 : k < 10 ? kUnknownCell : k < 10 + trial % 30 ? kSeenCell : kFreeCell;
      a.set(i, v), b.set(i, v);
    }
    ObstacleBits bits;
    bits.sync(fast, g);
    double x0 = 0.05 + unit(rng) * 5.9, y0 = 0.05 + unit(rng) * 4.4;
    if (trial % 4 == 1) x0 = std::round(x0 * 10) / 10, y0 = std::round(y0 * 10) / 10;  // a cell corner
    if (trial % 4 == 2) x0 = std::round(x0 / 0.8) * 0.8, y0 = std::round(y0 / 0.8) * 0.8;  // a block corner
    if (trial % 4 == 3) x0 = std::round(x0 * 10) / 10;                                      // a grid line
    const int n = std::vector<int>{1, 7, 180, 360}[trial % 4];
    const double heading = unit(rng) * 2 * M_PI - M_PI;
    std::vector<ScanBeam> scan;
    for (int i = 0; i < n; ++i) {
      double angle = heading + (n == 1 ? 0.0 : -M_PI + 2 * M_PI * i / n);
      if (trial % 5 == 0) angle = unit(rng) * 2 * M_PI;                      // not in order
      if (trial % 7 == 0 && i % 3 == 0) angle = std::round(angle / (M_PI / 4)) * (M_PI / 4);  // axes and diagonals
      double range = unit(rng) * 4.0;
      if (i % 17 == 0) range = 0.0;
      if (i % 13 == 0) range = 7.0;  // out of the map
      double hx = x0 + range * std::cos(angle), hy = y0 + range * std::sin(angle);
      if (i % 11 == 0) hx = std::round(hx * 10) / 10;  // on a grid line
      scan.push_back(ScanBeam{hx, hy, hx + 0.05 * std::cos(angle), hy + 0.05 * std::sin(angle)});
    }
    const bool carve = trial % 9 != 0;
    for (const ScanBeam& beam : scan) {
      if (carve) carve_free(a, g, x0, y0, beam.end_x, beam.end_y);
      mark_obstacle(a, g, beam.mark_x, beam.mark_y);
    }
    sense_scan(b, g, bits, x0, y0, scan, carve);
    bits.keep(fast);
    const auto pa = reference.view<std::int16_t>(), pb = fast.view<std::int16_t>();
    for (std::size_t i = 0; i < pa.size(); ++i) {
      ASSERT_EQ(pa[i], pb[i]) << "trial " << trial << ", cell " << i / 60 << "," << i % 60;
    }
    ObstacleBits fresh;
    fresh.sync(reference, g);
    for (int r = 0; r < 45; ++r) {
      for (int c = 0; c < 60; ++c) {
        ASSERT_EQ(bits.seen(r, c), fresh.seen(r, c)) << "trial " << trial;
        ASSERT_EQ(bits.obstacle(r, c), fresh.obstacle(r, c)) << "trial " << trial;
      }
    }
    changed_cells += static_cast<int>(std::count(pa.begin(), pa.end(), kSeenCell));
  }
  EXPECT_GT(changed_cells, 1000);
}

TEST(NoWayMemo, AWayKnownShutIsShutForAFreshSearchAndOpensWithItsBorder) {
  // Random grids cut in two by a wall with gaps; a start on one side, a goal on the other. After a
  // search finds no way, cells are blocked and freed at random: whenever the memo says the way is
  // shut, A* from scratch must find none; and with no change it must say shut (it saves work).
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> cell(0, 39), coin(0, 99);
  int shut_answers = 0, opened = 0;
  for (int trial = 0; trial < 80; ++trial) {
    geometry::BlockedGrid grid(40, 40);
    for (int r = 0; r < 40; ++r) {
      for (int c = 0; c < 40; ++c) grid.set_blocked({r, c}, coin(rng) < 20 || c == 20);
    }
    const geometry::Cell start{cell(rng), cell(rng) % 18}, goal{cell(rng), 22 + cell(rng) % 18};
    grid.set_blocked(start, false), grid.set_blocked(goal, false);
    plan::AStar astar;
    if (astar.search(grid, start, goal).found()) continue;
    NoWayMemo memo;
    memo.learn(grid, start);
    ASSERT_TRUE(memo.shut(grid, start, goal)) << "trial " << trial;
    for (int step = 0; step < 60; ++step) {
      const geometry::Cell c{cell(rng), cell(rng)};
      if (c == start || c == goal) continue;
      grid.set_blocked(c, coin(rng) < 50);
      const bool way = astar.search(grid, start, goal).found();
      if (memo.shut(grid, start, goal)) {
        ++shut_answers;
        ASSERT_FALSE(way) << "trial " << trial << " step " << step << ": the memo said shut, A* found a way";
      }
      if (way) {
        ++opened;
        break;
      }
    }
  }
  EXPECT_GT(shut_answers, 100) << "the memo saves searches";
  EXPECT_GT(opened, 10) << "ways did open";
}

TEST(ClearPathMemo, AnswersAsPathClearWhileTheMapAndThePlanChange) {
  // A plan kept over many frames while cells near it and far from it are written (obstacles, unknown, free), the
  // robot moves along it and sometimes back, and a new plan comes now and then: the memo's answer is path_clear's
  // (every segment checked: the second method) at every step, and on a clear plan it checks fewer than half the
  // segments path_clear does.
  const int rows = 60, cols = 110;  // 11 × 6 m, the plans 7–10 m long
  const geometry::MapGeometry g{cols, rows, 0.1, {0.5, -0.25, 0.0}};
  auto map = std::make_shared<Blob>(DType::Int16, std::vector<std::int64_t>{rows, cols});
  std::mt19937 rng(11);
  auto random_plan = [&] {
    std::vector<double> xy;
    double x = 1.5 + 0.01 * (rng() % 100), y = 0.5 + 0.01 * (rng() % 100);
    for (int k = 0; k < 30; ++k) {
      xy.push_back(x), xy.push_back(y);
      x += 0.2 + 0.001 * (rng() % 100);
      y += 0.1 * (static_cast<int>(rng() % 5) - 2) * 0.5;
      y = std::clamp(y, 0.5, 5.0);
    }
    return std::make_shared<const Blob>(DType::Float64, std::vector<std::int64_t>{30, 2}, xy.data(), xy.size() * sizeof(double));
  };
  std::shared_ptr<const Blob> plan = random_plan();
  ClearPathMemo memo;
  const std::int16_t values[] = {kFreeCell, kFreeCell, kUnknownCell, kWallCell, kSeenCell};
  std::size_t steps_clear = 0, steps_blocked = 0, checked = 0, segments = 0;
  int at = 0;
  for (int step = 0; step < 600; ++step) {
    if (rng() % 40 == 0) {
      plan = random_plan();
      at = 0;
    }
    {
      BlobEdit<std::int16_t> edit(*map);
      // A few cells a frame, near the plan or anywhere.
      const auto xy = plan->view<double>();
      for (int k = rng() % 4 == 0 ? 1 : 0; k > 0; --k) {
        int row, col;
        const std::size_t p = 2 * (rng() % (xy.size() / 2));
        if (rng() % 4 == 0 && g.cell_of(xy[p] + 0.1 * (static_cast<int>(rng() % 9) - 4),
                                        xy[p + 1] + 0.1 * (static_cast<int>(rng() % 9) - 4), row, col)) {
          edit.set(static_cast<std::size_t>(row) * cols + col, values[rng() % 5]);
        } else {
          edit.set(rng() % map->size(), rng() % 2 ? std::int16_t{kFreeCell} : values[rng() % 5]);
        }
      }
      // Now and then the three bottom rows, away from the plans, all marked or all cleared: more obstacle cells
      // written than the memo follows.
      if (rng() % 25 == 0) {
        const std::int16_t band = rng() % 2 ? kSeenCell : kFreeCell;
        for (std::size_t k = 0; k < 3 * static_cast<std::size_t>(cols); ++k) edit.set(k, band);
      }
      // The map clears itself slowly, so that plans stay clear for a while.
      for (int k = 0; k < 40; ++k) edit.set(rng() % map->size(), kFreeCell);
    }
    const unsigned move = rng() % 8;  // on along the plan now and then, back sometimes
    at = std::clamp(at + (move < 2 ? 1 : move == 2 ? -1 : 0), 0, 28);
    const auto xy = plan->view<double>();
    DecisionInput in;
    in.map = map;
    in.geometry = &g;
    in.radius = 0.23;
    in.pose = {xy[2 * at] + 0.01, xy[2 * at + 1] - 0.01, 0.0};
    in.path_owner = plan;
    in.path = xy;
    const bool truth = path_clear(in, xy);
    ASSERT_EQ(memo.clear(in), truth) << "step " << step;
    (truth ? steps_clear : steps_blocked) += 1;
    if (truth) {  // path_clear checked every segment from the robot's on
      checked += memo.checked();
      segments += 29 - static_cast<std::size_t>(at);
    }
    map = std::make_shared<Blob>(*map);  // the next frame's map: a copy, as an actor's edit makes one
  }
  EXPECT_GT(steps_clear, 100u);
  EXPECT_GT(steps_blocked, 100u);
  EXPECT_LT(checked, segments / 2) << "the memo checked " << checked << " of " << segments << " segments ("
                                    << steps_clear << " steps clear, " << steps_blocked << " blocked)";
}
