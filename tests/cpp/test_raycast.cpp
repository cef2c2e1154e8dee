// The laser raycaster: distances worked out by hand on small maps, then the fast paths (cast,
// range, scan) against the reference cell walk (cast_dda), bit for bit, on generated maps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "vwg/error.hpp"
#include "vwg/sim/raycast.hpp"

using namespace vwg;
using namespace vwg::sim;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTol = 1e-12;  // for expected values computed by hand with decimals

OccupancyGrid make_grid(int width, int height, double resolution = 1.0, Pose2 origin = {}) {
  OccupancyGrid grid;
  grid.width = width;
  grid.height = height;
  grid.resolution = resolution;
  grid.origin = origin;
  grid.data.assign(static_cast<std::size_t>(width) * height, kFree);
  return grid;
}

void set(OccupancyGrid& grid, int row, int col, std::int8_t value = kOccupied) {
  grid.data[static_cast<std::size_t>(row) * grid.width + col] = value;
}

/// 10 x 10 cells of 1 m, origin at (0, 0): column 7 is a wall (x in [7, 8)).
OccupancyGrid wall_at_column_7(double resolution = 1.0, Pose2 origin = {}) {
  OccupancyGrid grid = make_grid(10, 10, resolution, origin);
  for (int row = 0; row < 10; ++row) set(grid, row, 7);
  return grid;
}

void expect_hit(const RayHit& hit, double distance, int row, int col, int face, double x, double y) {
  EXPECT_TRUE(hit.hit);
  EXPECT_NEAR(hit.distance, distance, kTol);
  EXPECT_EQ(hit.row, row);
  EXPECT_EQ(hit.col, col);
  EXPECT_EQ(hit.face, face);
  EXPECT_NEAR(hit.x, x, kTol);
  EXPECT_NEAR(hit.y, y, kTol);
}

/// Both walks, which must agree exactly, checked against the hand values.
void expect_both_hit(const GridRaycaster& rc, double x0, double y0, double angle, double max_range, double distance,
                     int row, int col, int face, double x, double y) {
  SCOPED_TRACE(::testing::Message() << "from (" << x0 << ", " << y0 << ") at " << angle);
  expect_hit(rc.cast(x0, y0, angle, max_range), distance, row, col, face, x, y);
  expect_hit(rc.cast_dda(x0, y0, angle, max_range), distance, row, col, face, x, y);
  EXPECT_NEAR(rc.range(x0, y0, angle, max_range), distance, kTol);
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

// ---- distances by hand ------------------------------------------------------------------------

TEST(Raycast, AlongTheAxesToAWall) {
  const GridRaycaster rc(wall_at_column_7());
  // From (2.5, 4.5) going +x the ray enters cell (4, 7) through its left face at x = 7.
  expect_both_hit(rc, 2.5, 4.5, 0.0, 20.0, 4.5, 4, 7, 0, 7.0, 4.5);
  // From (9.5, 4.5) going -x it enters the same wall through the right face, x = 8.
  expect_both_hit(rc, 9.5, 4.5, kPi, 20.0, 1.5, 4, 7, 1, 8.0, 4.5);
  // Going -x from (2.5, 4.5) nothing is in the way: the ray leaves the map at x = 0.
  const RayHit away = rc.cast(2.5, 4.5, kPi, 20.0);
  EXPECT_FALSE(away.hit);
  EXPECT_EQ(away.distance, 20.0);
  EXPECT_EQ(away.row, -1);
  EXPECT_EQ(away.face, -1);
  EXPECT_NEAR(away.x, 2.5 - 20.0, kTol);  // a miss reports the point at max_range
  EXPECT_NEAR(away.y, 4.5, kTol);
  EXPECT_FALSE(rc.cast_dda(2.5, 4.5, kPi, 20.0).hit);
  // Going +y along the wall's left neighbour column: leaves through the top.
  EXPECT_FALSE(rc.cast(6.5, 0.5, kPi / 2, 20.0).hit);
  EXPECT_EQ(rc.range(6.5, 0.5, kPi / 2, 20.0), 20.0);
}

TEST(Raycast, At45Degrees) {
  const GridRaycaster rc(wall_at_column_7());
  // From (2.5, 1) the ray u = 2.5 + s, v = 1 + s (s = t / sqrt 2) meets x = 7 at s = 4.5, y = 5.5,
  // never through a grid corner on the way (x integer needs s = k + 0.5, then y = k + 1.5).
  expect_both_hit(rc, 2.5, 1.0, kPi / 4, 20.0, 4.5 * std::sqrt(2.0), 5, 7, 0, 7.0, 5.5);
  // Mirrored, from (9.5, 1) going up-left: meets x = 8 at s = 1.5, y = 2.5.
  expect_both_hit(rc, 9.5, 1.0, 3 * kPi / 4, 20.0, 1.5 * std::sqrt(2.0), 2, 7, 1, 8.0, 2.5);
}

TEST(Raycast, BottomAndTopFaces) {
  OccupancyGrid grid = make_grid(10, 10);
  for (int col = 0; col < 10; ++col) set(grid, 7, col);  // row 7 is a wall: y in [7, 8)
  const GridRaycaster rc(grid);
  // Direction (3, 4) / 5 from (1, 1): y = 7 at t = 6 / 0.8 = 7.5, where x = 1 + 0.6 * 7.5 = 5.5.
  expect_both_hit(rc, 1.0, 1.0, std::atan2(4.0, 3.0), 20.0, 7.5, 7, 5, 2, 5.5, 7.0);
  // Straight down from (5.5, 9.5): enters row 7 through its top, y = 8, after 1.5.
  expect_both_hit(rc, 5.5, 9.5, -kPi / 2, 20.0, 1.5, 7, 5, 3, 5.5, 8.0);
}

TEST(Raycast, OriginAndResolution) {
  // Cells of 0.25 m, lower-left corner of cell (0, 0) at (-1, 2): cell (r, c) spans
  // x in [-1 + c/4, -1 + (c+1)/4), y in [2 + r/4, ...). The wall (column 7) spans x in [0.75, 1).
  const GridRaycaster rc(wall_at_column_7(0.25, {-1.0, 2.0, 0.0}));
  // From (-0.375, 3.125) = cell coordinates (2.5, 4.5): 4.5 cells = 1.125 m to x = 0.75.
  expect_both_hit(rc, -0.375, 3.125, 0.0, 5.0, 1.125, 4, 7, 0, 0.75, 3.125);
  // The same at 45 degrees from (2.5, 1) in cells = (-0.375, 2.25): 4.5 * sqrt 2 cells, meeting
  // x = 0.75 at cell row 5.5, y = 2 + 5.5 / 4 = 3.375.
  expect_both_hit(rc, -0.375, 2.25, kPi / 4, 5.0, 4.5 * std::sqrt(2.0) * 0.25, 5, 7, 0, 0.75, 3.375);
}

TEST(Raycast, OriginYawOf90Degrees) {
  // Yaw 90 degrees: the grid's u axis (columns) points along world +y, v (rows) along world -x,
  // so cell (r, c) spans x in (-(r+1), -r], y in [c, c+1). The wall, column 7, is y in [7, 8).
  const GridRaycaster rc(wall_at_column_7(1.0, {0.0, 0.0, kPi / 2}));
  // World (-4.5, 2.5) is cell coordinates (2.5, 4.5); going world +y is going +u: 4.5 to y = 7.
  expect_both_hit(rc, -4.5, 2.5, kPi / 2, 20.0, 4.5, 4, 7, 0, -4.5, 7.0);
  // Going world -y from (-4.5, 9.5) (u = 9.5) meets the wall's far side y = 8 after 1.5.
  expect_both_hit(rc, -4.5, 9.5, -kPi / 2, 20.0, 1.5, 4, 7, 1, -4.5, 8.0);
  // Going world +x is going -v: out of the map through row 0 (x = 0), no hit.
  EXPECT_FALSE(rc.cast(-4.5, 2.5, 0.0, 20.0).hit);
  EXPECT_FALSE(rc.cast_dda(-4.5, 2.5, 0.0, 20.0).hit);
}

TEST(Raycast, RaysFromOutsideTheMap) {
  const GridRaycaster rc(wall_at_column_7());
  // From x = -3.5 the ray enters the map at x = 0 and meets the wall at x = 7: 10.5.
  expect_both_hit(rc, -3.5, 4.5, 0.0, 20.0, 10.5, 4, 7, 0, 7.0, 4.5);
  // From above the map going down-right at 45 degrees: (1.5, 12) reaches y = 10 at x = 3.5,
  // and x = 7 at y = 6.5 (row 6), after 5.5 * sqrt 2.
  expect_both_hit(rc, 1.5, 12.0, -kPi / 4, 20.0, 5.5 * std::sqrt(2.0), 6, 7, 0, 7.0, 6.5);
  // Moving away from the map, or passing beside it: no hit.
  EXPECT_FALSE(rc.cast(-3.5, 4.5, kPi, 20.0).hit);
  EXPECT_FALSE(rc.cast(-3.5, 12.5, 0.0, 100.0).hit);
  EXPECT_FALSE(rc.cast_dda(-3.5, 12.5, 0.0, 100.0).hit);
}

TEST(Raycast, StartInsideAWall) {
  const GridRaycaster rc(wall_at_column_7());
  const RayHit hit = rc.cast(7.5, 3.5, 1.0, 20.0);
  expect_hit(hit, 0.0, 3, 7, -1, 7.5, 3.5);
  EXPECT_FALSE(std::signbit(hit.distance));
  expect_hit(rc.cast_dda(7.5, 3.5, 1.0, 20.0), 0.0, 3, 7, -1, 7.5, 3.5);
  std::vector<double> angles = {0.0, 1.0, 2.0};
  std::vector<float> out(3, -1.0f);
  rc.scan({7.5, 3.5, 0.3}, angles, 20.0, out);
  EXPECT_EQ(out, std::vector<float>({0.0f, 0.0f, 0.0f}));
}

TEST(Raycast, MaxRangeCutoff) {
  const GridRaycaster rc(wall_at_column_7());
  // The wall is 4.5 away: a hit exactly at max_range counts, a shorter max_range misses.
  expect_both_hit(rc, 2.5, 4.5, 0.0, 4.5, 4.5, 4, 7, 0, 7.0, 4.5);
  const RayHit short_ray = rc.cast(2.5, 4.5, 0.0, 4.0);
  EXPECT_FALSE(short_ray.hit);
  EXPECT_EQ(short_ray.distance, 4.0);
  EXPECT_NEAR(short_ray.x, 6.5, kTol);
  EXPECT_EQ(rc.range(2.5, 4.5, 0.0, 4.0), 4.0);
  EXPECT_FALSE(rc.cast_dda(2.5, 4.5, 0.0, 4.0).hit);
  EXPECT_EQ(rc.range(2.5, 4.5, 0.0, 0.0), 0.0);  // max_range 0 is allowed
  EXPECT_NEAR(rc.range(2.5, 4.5, 0.0, INFINITY), 4.5, kTol);
  EXPECT_EQ(rc.range(2.5, 4.5, kPi, INFINITY), INFINITY);  // leaves the map: nothing to hit
}

TEST(Raycast, StartOnAGridLine) {
  OccupancyGrid grid = make_grid(10, 10);
  set(grid, 2, 4);
  const GridRaycaster rc(grid);
  // (5, 2.5) lies on the line x = 5: it belongs to cell (2, 5) (half-open cells). Going -x it
  // enters the blocked cell (2, 4) at once, through its right face.
  expect_both_hit(rc, 5.0, 2.5, kPi, 10.0, 0.0, 2, 4, 1, 5.0, 2.5);
  // Going +x it moves away from it.
  EXPECT_FALSE(rc.cast(5.0, 2.5, 0.0, 10.0).hit);
  EXPECT_FALSE(rc.cast_dda(5.0, 2.5, 0.0, 10.0).hit);
}

TEST(Raycast, ThroughAGridCornerTouchesBothSideCells) {
  // From the corner (5, 5) going down-left (any angle strictly between pi and 3pi/2), both lines
  // x = 5 and y = 5 are crossed at t = 0 exactly: the x side is cell (5, 4), the y side (4, 5),
  // the diagonal (4, 4). The start cell is (5, 5), free.
  const double down_left = 1.25 * kPi;
  {
    OccupancyGrid grid = make_grid(10, 10);
    set(grid, 5, 4);  // x side only
    const GridRaycaster rc(grid);
    expect_both_hit(rc, 5.0, 5.0, down_left, 10.0, 0.0, 5, 4, 1, 5.0, 5.0);
  }
  {
    OccupancyGrid grid = make_grid(10, 10);
    set(grid, 4, 5);  // y side only
    const GridRaycaster rc(grid);
    expect_both_hit(rc, 5.0, 5.0, down_left, 10.0, 0.0, 4, 5, 3, 5.0, 5.0);
  }
  {
    OccupancyGrid grid = make_grid(10, 10);
    set(grid, 4, 4);  // the diagonal only: reported as entered through its x face
    const GridRaycaster rc(grid);
    expect_both_hit(rc, 5.0, 5.0, down_left, 10.0, 0.0, 4, 4, 1, 5.0, 5.0);
  }
  {
    OccupancyGrid grid = make_grid(10, 10);
    set(grid, 5, 4);  // both sides: the x side first
    set(grid, 4, 5);
    const GridRaycaster rc(grid);
    expect_both_hit(rc, 5.0, 5.0, down_left, 10.0, 0.0, 5, 4, 1, 5.0, 5.0);
  }
  {
    OccupancyGrid grid = make_grid(10, 10);
    set(grid, 5, 5);  // the start cell itself
    const GridRaycaster rc(grid);
    expect_both_hit(rc, 5.0, 5.0, down_left, 10.0, 0.0, 5, 5, -1, 5.0, 5.0);
  }
}

TEST(Raycast, DiagonalChainOfCellsIsAClosedWall) {
  OccupancyGrid grid = make_grid(10, 10);
  for (int k = 0; k < 10; ++k) set(grid, k, k);  // cells touching only at their corners
  const GridRaycaster rc(grid);
  // From the corner (3, 7) going down-right at 45 degrees the ray runs along x + y = 10, through
  // the corner (5, 5) shared by chain cells (4, 4) and (5, 5): it stops there, 2 * sqrt 2 away.
  for (const RayHit& hit : {rc.cast(3.0, 7.0, -kPi / 4, 20.0), rc.cast_dda(3.0, 7.0, -kPi / 4, 20.0)}) {
    EXPECT_TRUE(hit.hit);
    EXPECT_NEAR(hit.distance, 2.0 * std::sqrt(2.0), 1e-9);
    EXPECT_TRUE((hit.row == 4 && hit.col == 4) || (hit.row == 5 && hit.col == 5)) << hit.row << " " << hit.col;
  }
}

TEST(Raycast, ThresholdAndUnknownCells) {
  OccupancyGrid grid = make_grid(10, 1);
  set(grid, 0, 3, kUnknown);  // unknown: never an obstacle
  set(grid, 0, 5, 60);
  set(grid, 0, 8, 90);
  // From (0.5, 0.5) going +x: with threshold 50 the 60 at column 5 stops it (4.5 away);
  // with threshold 70 the 90 at column 8 does (7.5 away).
  EXPECT_NEAR(GridRaycaster(grid, 50).range(0.5, 0.5, 0.0, 20.0), 4.5, kTol);
  EXPECT_NEAR(GridRaycaster(grid, 70).range(0.5, 0.5, 0.0, 20.0), 7.5, kTol);
  EXPECT_NEAR(GridRaycaster(grid, 70).cast_dda(0.5, 0.5, 0.0, 20.0).distance, 7.5, kTol);
  EXPECT_FALSE(GridRaycaster(grid, 70).blocked(0, 5));
  EXPECT_TRUE(GridRaycaster(grid, 50).blocked(0, 5));
  EXPECT_FALSE(GridRaycaster(grid, 50).blocked(0, 3));
  EXPECT_FALSE(GridRaycaster(grid, 50).blocked(0, 10));  // outside
}

TEST(Raycast, ScanMatchesHandValues) {
  const GridRaycaster rc(wall_at_column_7());
  // From (2.5, 4) facing +y. Beam -pi/2 looks along +x: the wall, 4.5 away. Beam +pi/2 looks
  // along -x: leaves the map. Beam -3pi/4 looks down-right at 45 degrees: u = 2.5 + s,
  // v = 4 - s leaves through y = 0 at x = 6.5, before the wall. Beam 3 aims at (7, 4.5): the
  // wall, sqrt(4.5^2 + 0.5^2) away. None passes through a grid corner.
  const std::vector<double> angles = {-kPi / 2, kPi / 2, -3 * kPi / 4, -kPi / 2 + std::atan2(0.5, 4.5)};
  std::vector<float> out(angles.size());
  rc.scan({2.5, 4.0, kPi / 2}, angles, 8.0, out);
  EXPECT_EQ(out[0], 4.5f);
  EXPECT_EQ(out[1], 8.0f);
  EXPECT_EQ(out[2], 8.0f);
  EXPECT_NEAR(out[3], std::sqrt(20.5), 1e-6);
}

TEST(Raycast, RefusesBadInput) {
  OccupancyGrid grid = make_grid(4, 4);
  const GridRaycaster rc(grid);
  EXPECT_THROW(rc.cast(NAN, 1.0, 0.0, 1.0), Error);
  EXPECT_THROW(rc.cast(1.0, 1.0, INFINITY, 1.0), Error);
  EXPECT_THROW(rc.range(1.0, 1.0, 0.0, -1.0), Error);
  EXPECT_THROW(rc.cast_dda(1.0, 1.0, 0.0, NAN), Error);
  std::vector<double> angles = {0.0, NAN};
  std::vector<float> out(2), short_out(1);
  EXPECT_THROW(rc.scan({1.0, 1.0, 0.0}, angles, 1.0, out), Error);
  EXPECT_THROW(rc.scan({1.0, 1.0, 0.0}, angles, 1.0, short_out), Error);
  grid.data.pop_back();
  EXPECT_THROW(GridRaycaster{grid}, Error);
  OccupancyGrid no_resolution = make_grid(4, 4, 0.0);
  EXPECT_THROW(GridRaycaster{no_resolution}, Error);
  // An empty map is allowed: nothing to hit.
  const GridRaycaster empty(make_grid(0, 0));
  EXPECT_FALSE(empty.cast(0.0, 0.0, 0.3, 5.0).hit);
}

// ---- the fast paths against the reference walk ------------------------------------------------

namespace {

/// Random maps of several kinds: sparse or dense noise (with unknown and grey cells), diagonal
/// chains and rectangles; random sizes, resolutions, origins and yaws (0, 90 degrees, any).
OccupancyGrid random_map(std::mt19937_64& rng, int kind) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const int width = 3 + static_cast<int>(uniform(rng) * 80), height = 3 + static_cast<int>(uniform(rng) * 80);
  const double yaw = kind % 3 == 0 ? 0.0 : kind % 3 == 1 ? kPi / 2 : uniform(rng) * 7.0 - 3.5;
  OccupancyGrid grid = make_grid(width, height, 0.03 + uniform(rng) * 0.2,
                                 {uniform(rng) * 6.0 - 3.0, uniform(rng) * 6.0 - 3.0, yaw});
  if (kind % 4 == 3) {
    for (int k = 0; k < 5; ++k) {
      int col = static_cast<int>(uniform(rng) * width), row = static_cast<int>(uniform(rng) * height);
      const int step_c = uniform(rng) < 0.5 ? 1 : -1, step_r = uniform(rng) < 0.5 ? 1 : -1;
      for (; grid.inside(row, col); col += step_c, row += step_r) set(grid, row, col);
    }
    for (int k = 0; k < 3; ++k) {
      const int c0 = static_cast<int>(uniform(rng) * width), r0 = static_cast<int>(uniform(rng) * height);
      for (int r = r0; r < std::min(height, r0 + 6); ++r)
        for (int c = c0; c < std::min(width, c0 + 9); ++c) set(grid, r, c);
    }
  } else {
    const double density = kind % 4 == 0 ? 0.02 : kind % 4 == 1 ? 0.15 : 0.45;
    for (auto& value : grid.data) {
      const double draw = uniform(rng);
      value = draw < density ? static_cast<std::int8_t>(50 + uniform(rng) * 51)
              : draw < density + 0.05 ? kUnknown
                                      : static_cast<std::int8_t>(uniform(rng) * 50);
    }
  }
  return grid;
}

/// Starts on a quarter-cell lattice, at cell centres, anywhere, or outside the map; directions
/// through lattice points (which make exact corner ties) or random.
/// simd: "" for the code preferred on this CPU, or a choice for VWG_RAYCAST_SIMD ("avx512", "avx2",
/// "none"; at most what the CPU has).
void check_agreement(std::uint64_t seed, int maps, int poses_per_map, const char* simd = "") {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const int lattice[][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 1},  {-1, 1}, {-1, -1}, {1, -1},
                            {2, 1}, {1, 2}, {-2, 1}, {3, 4}, {-4, 3}, {2, -3}, {1, 3},  {-3, -1}};
  long rays = 0, hits = 0, mismatches = 0;
  for (int m = 0; m < maps; ++m) {
    const OccupancyGrid grid = random_map(rng, m);
    if (*simd) setenv("VWG_RAYCAST_SIMD", simd, 1);
    const GridRaycaster rc(grid);
    if (*simd) unsetenv("VWG_RAYCAST_SIMD");
    for (int p = 0; p < poses_per_map; ++p) {
      const double a = uniform(rng), b = uniform(rng);
      double u = a * grid.width, v = b * grid.height;  // anywhere
      if (p % 4 == 0) u = std::floor(u * 4) / 4, v = std::floor(v * 4) / 4;
      if (p % 4 == 1) u = std::floor(u) + 0.5, v = std::floor(v) + 0.5;
      if (p % 4 == 3) u = a * (grid.width + 30) - 15, v = b * (grid.height + 30) - 15;
      Pose2 pose;
      grid.grid_to_world(u, v, pose.x, pose.y);
      pose.theta = p % 2 ? 0.0 : uniform(rng) * 6.3;
      const double max_range =
          p % 7 == 0 ? INFINITY : p % 7 == 1 ? 0.0 : uniform(rng) * (grid.width_m() + grid.height_m());
      std::vector<double> angles;
      for (const auto& d : lattice) angles.push_back(std::atan2(d[1], d[0]) + grid.origin.theta - pose.theta);
      for (int i = 0; i < 24; ++i) angles.push_back(uniform(rng) * 8.0 - 4.0);
      std::vector<float> out(angles.size());
      rc.scan(pose, angles, max_range, out);
      for (std::size_t i = 0; i < angles.size(); ++i) {
        const double angle = pose.theta + angles[i];
        const RayHit ref = rc.cast_dda(pose.x, pose.y, angle, max_range);
        const RayHit fast = rc.cast(pose.x, pose.y, angle, max_range);
        const double range = rc.range(pose.x, pose.y, angle, max_range);
        const bool same = fast.hit == ref.hit && fast.row == ref.row && fast.col == ref.col && fast.face == ref.face &&
                          same_bits(fast.distance, ref.distance) && same_bits(fast.x, ref.x) &&
                          same_bits(fast.y, ref.y) && same_bits(range, ref.distance) &&
                          out[i] == static_cast<float>(ref.distance);
        ++rays;
        hits += ref.hit;
        if (!same && ++mismatches <= 5)
          ADD_FAILURE() << "map " << m << " from (" << pose.x << ", " << pose.y << ") angle " << angle << " max "
                        << max_range << ": dda " << ref.distance << " at (" << ref.row << ", " << ref.col << ") face "
                        << ref.face << "; cast " << fast.distance << " at (" << fast.row << ", " << fast.col
                        << ") face " << fast.face << "; range " << range << "; scan " << out[i];
      }
    }
  }
  EXPECT_EQ(mismatches, 0) << "of " << rays << " rays";
  EXPECT_GT(hits, rays / 4);  // the maps are not empty
}

}  // namespace

TEST(Raycast, FastPathsAgreeExactlyWithTheCellWalk) { check_agreement(1, 100, 30); }

// Each code, chosen here by VWG_RAYCAST_SIMD (this CPU's preferred code may be another: AVX2 on a
// Zen 4, which has AVX-512 too).
TEST(Raycast, Avx512PathsAgreeExactlyWithTheCellWalk) { check_agreement(4, 40, 30, "avx512"); }
TEST(Raycast, Avx2PathsAgreeExactlyWithTheCellWalk) { check_agreement(2, 40, 30, "avx2"); }
TEST(Raycast, PortablePathsAgreeExactlyWithTheCellWalk) { check_agreement(3, 40, 30, "none"); }

// A scan's beams on a CPU with AVX2 but not AVX-512 take their directions from 4-lane code, single
// rays from the scalar code: the two must give the same bits, or a beam through a grid corner
// could stop in a scan and go on as a single ray. Both are also checked against libm.
TEST(Raycast, Avx2DirectionsAreTheScalarCodesBits) {
  std::vector<double> angles = {0.0, -0.0, 1e-300, -1e-300, 99999.9, -99999.9, 1e5, -1e5, 1e5 + 1, -3e6};
  for (int k = -64; k <= 64; ++k)  // quarter turns and their neighbours, where the reduction changes
    for (double a = k * std::numbers::pi / 4, n = 0; n < 3; ++n, a = std::nextafter(a, 10.0)) {
      angles.push_back(a);
      angles.push_back(std::nextafter(k * std::numbers::pi / 4, -10.0));
    }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> wide(-1000.0, 1000.0), near(-8.0, 8.0);
  for (int i = 0; i < 100000; ++i) angles.push_back(i % 2 ? wide(rng) : near(rng));
  for (std::size_t n : {1u, 2u, 3u, 5u, 7u}) angles.resize(angles.size() + n, 0.3 * n);  // odd tails
  std::vector<double> du(angles.size()), dv(angles.size()), scalar_du(angles.size()), scalar_dv(angles.size());
  ASSERT_EQ(beam_directions(angles, "none", scalar_du, scalar_dv), "none");
  if (beam_directions(angles, "avx2", du, dv) != "avx2") GTEST_SKIP() << "this CPU has no AVX2";
  long differ = 0;
  for (std::size_t i = 0; i < angles.size(); ++i) {
    if (!same_bits(du[i], scalar_du[i]) || !same_bits(dv[i], scalar_dv[i])) {
      if (++differ <= 5)
        ADD_FAILURE() << std::hexfloat << "angle " << angles[i] << ": avx2 (" << du[i] << ", " << dv[i]
                      << "), scalar (" << scalar_du[i] << ", " << scalar_dv[i] << ")";
    }
    // Within 2e-16 of libm (1 ulp near 1), and +0 for a zero component.
    EXPECT_NEAR(du[i], std::cos(angles[i]), 2.3e-16) << angles[i];
    EXPECT_NEAR(dv[i], std::sin(angles[i]), 2.3e-16) << angles[i];
  }
  EXPECT_EQ(differ, 0) << "of " << angles.size() << " angles";
  EXPECT_FALSE(std::signbit(dv[1])) << "sin(-0) is made +0";
}

TEST(Raycast, BeamDirectionsRefusesBadInput) {
  std::vector<double> angles(3), du(3), dv(2);
  EXPECT_THROW(beam_directions(angles, "none", du, dv), Error);
  EXPECT_THROW(beam_directions(angles, "sse", du, du), Error);
}

TEST(Raycast, AMisspeltSimdChoiceIsAnErrorNamingTheVariable) {
  const OccupancyGrid grid = make_grid(8, 8, 0.1, {0.0, 0.0, 0.0});
  for (const char* bad : {"avx-512", "AVX2", "sse4"}) {
    setenv("VWG_RAYCAST_SIMD", bad, 1);
    try {
      const GridRaycaster rc(grid);
      ADD_FAILURE() << bad << " was taken for " << rc.simd();
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("VWG_RAYCAST_SIMD: expected avx512, avx2 or none"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(std::string("got '") + bad + "'"), std::string::npos) << e.what();
    }
  }
  setenv("VWG_RAYCAST_SIMD", "", 1);  // empty, as unset: this CPU's preferred code
  EXPECT_NO_THROW(GridRaycaster{grid});
  unsetenv("VWG_RAYCAST_SIMD");
}

TEST(Raycast, ScansAgreeOnABiggerMap) {
  // Rooms of random rectangles on 300 x 300 cells, so the free squares get large; full scans.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  OccupancyGrid grid = make_grid(300, 300, 0.05, {-2.0, 1.0, 0.2});
  for (int k = 0; k < 60; ++k) {
    const int c0 = static_cast<int>(uniform(rng) * 300), r0 = static_cast<int>(uniform(rng) * 300);
    const int w = 1 + static_cast<int>(uniform(rng) * 40), h = 1 + static_cast<int>(uniform(rng) * 4);
    for (int r = r0; r < std::min(300, r0 + (k % 2 ? h : w)); ++r)
      for (int c = c0; c < std::min(300, c0 + (k % 2 ? w : h)); ++c) set(grid, r, c);
  }
  std::vector<double> angles(360);  // more than the 256 beams a scan sets up at a time
  for (int i = 0; i < 360; ++i) angles[i] = -kPi + 2.0 * kPi * i / 360.0;
  std::vector<float> out(360);
  long compared = 0;
  for (const char* simd : {"", "avx512", "avx2"}) {  // this CPU's preferred code, its widest, and the AVX2 code
    if (*simd) setenv("VWG_RAYCAST_SIMD", simd, 1);
    const GridRaycaster rc(grid);
    if (*simd) unsetenv("VWG_RAYCAST_SIMD");
    for (int p = 0; p < 40; ++p) {
      Pose2 pose;
      grid.grid_to_world(uniform(rng) * 300, uniform(rng) * 300, pose.x, pose.y);
      pose.theta = uniform(rng) * 6.0;
      rc.scan(pose, angles, 10.0, out);
      for (int i = 0; i < 360; ++i, ++compared)
        ASSERT_EQ(out[i], static_cast<float>(rc.cast_dda(pose.x, pose.y, pose.theta + angles[i], 10.0).distance))
            << rc.simd() << " pose " << p << " beam " << i;
    }
  }
  EXPECT_EQ(compared, 3 * 40 * 360);
}
