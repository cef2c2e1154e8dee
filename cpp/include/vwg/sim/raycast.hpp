// Exact laser raycasting over an occupancy grid: the simulated lidar of every robot.
//
// A ray stops where it enters the first blocked cell it passes through. Every method below gives
// the same cell and the same distance (bit for bit) as the reference cell walk `cast_dda`; the
// fast ones only skip free space faster, they never approximate.
//
// Rules, in grid axes (u along columns, v along rows, in cells):
// - the start belongs to the cell whose half-open box [c, c+1) × [r, r+1) holds it; if that cell
//   is blocked the distance is 0 (face -1);
// - a ray passing exactly through a grid corner touches both cells beside the corner: it stops
//   at the corner if the one across the vertical line (x side) or else the one across the
//   horizontal line (y side) is blocked; otherwise it goes on into the diagonal cell (reported,
//   if blocked, as entered through its x face). So a diagonal chain of cells is a closed wall;
// - a hit exactly at max_range counts; cells outside the map and unknown cells are free.
// Angles become directions through vwg's own sine and cosine (geometry::beam_directions, within
// about 2e-16 of libm's), the same code for every method.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "vwg/geometry/directions.hpp"
#include "vwg/sim/grid.hpp"

namespace vwg::sim {

/// Where a ray stopped.
struct RayHit {
  /// Metres from the start to where the ray enters the first blocked cell; max_range if none.
  double distance = 0.0;
  /// False when nothing blocked was met within max_range (also when the ray left the map first).
  bool hit = false;
  /// The blocked cell when hit, else -1.
  int row = -1, col = -1;
  /// The side of that cell the ray entered, in grid axes: 0 = -x (left), 1 = +x (right),
  /// 2 = -y (bottom), 3 = +y (top); -1 on a miss or when the start cell itself is blocked.
  int face = -1;
  /// World coordinates of the entry point (the start if its cell is blocked; on a miss, the
  /// point at max_range).
  double x = 0.0, y = 0.0;
};

/// The beams' directions (vwg/geometry/directions.hpp), here by their old name.
using geometry::beam_directions;

/// Raycasting on one occupancy grid. Construction precomputes clearance tables (linear in the
/// cells: about 12 ms for 1000 x 1000); the grid is copied in that form, so the raycaster does
/// not refer to it afterwards. All methods are const and safe to call from several threads.
class GridRaycaster {
 public:
  /// Cells with a value >= threshold are obstacles. Throws vwg::Error if the grid is malformed
  /// (data size, resolution not positive) or has 2^29 cells or more, counted in whole blocks of
  /// 8 x 8. Takes 4 bytes per cell of the map padded to whole blocks of 8 x 8 cells.
  explicit GridRaycaster(const OccupancyGrid& grid, int threshold = kObstacleThreshold);

  /// The ray from (x, y) along `angle` (radians, world frame), up to max_range metres (may be
  /// +infinity). Throws vwg::Error on a non-finite start or angle, or a negative or NaN max_range.
  RayHit cast(double x, double y, double angle, double max_range) const;
  /// cast(...).distance, without working out the entry point.
  double range(double x, double y, double angle, double max_range) const;
  /// A scan: out[i] = range(pose.x, pose.y, pose.theta + angles[i], max_range), as float. The hot
  /// path of the laser: 16 beams are traced at once when the CPU has AVX-512 or AVX2 (the AVX2
  /// code on AMD's Zen 4 too, where it is the faster). The environment variable
  /// VWG_RAYCAST_SIMD=avx512, =avx2 or =none, set when the raycaster is made, chooses the code,
  /// at most what the CPU has (for tests and comparisons; every code gives the same ranges); the
  /// constructor throws vwg::Error naming the variable for any other value. Throws vwg::Error if
  /// out.size() != angles.size() or on the inputs cast() refuses.
  void scan(const Pose2& pose, std::span<const double> angles, double max_range, std::span<float> out) const;

  /// The plain reference: an Amanatides-Woo cell walk (crossing parameters computed from the
  /// start rather than accumulated, so they equal the fast methods' to the last bit). Used by the
  /// tests and as the benchmark baseline.
  RayHit cast_dda(double x, double y, double angle, double max_range) const;

  /// The code scan() runs on this CPU: "avx512", "avx2" or "none" (VWG_RAYCAST_SIMD chooses it).
  std::string_view simd() const { return simd_ == Simd::kAvx512 ? "avx512" : simd_ == Simd::kAvx2 ? "avx2" : "none"; }

  int width() const { return width_; }
  int height() const { return height_; }
  /// Whether cell (row, col) is an obstacle for this raycaster (false outside the map).
  bool blocked(int row, int col) const {
    return row >= 0 && col >= 0 && row < height_ && col < width_ && clearance_[cell_index(row, col)] == 0;
  }

 private:
  struct Ray;
  struct Walk;

  /// Where cell (row, col) is in a quadrant's table: blocks of 8 x 8 cells, 64 bytes each (a cache
  /// line's worth), rows of blocks one after another; rows of 8 cells in a block. A scan's beams
  /// that end on the same stretch of wall, along a row or a column, read the same few lines.
  std::size_t cell_index(int row, int col) const {
    return ((static_cast<std::size_t>(row >> 3) * static_cast<std::size_t>(block_cols_) +
             static_cast<std::size_t>(col >> 3))
            << 6) +
           static_cast<std::size_t>(((row & 7) << 3) + (col & 7));
  }
  /// The start of a ray in grid cells: OccupancyGrid::world_to_grid with the yaw's cosine and
  /// sine computed once. Throws on a non-finite or far-away start.
  void set_start(double x, double y, Ray& ray) const;
  /// The direction in grid axes. Every method builds it here, so all see the same bits.
  static void set_direction(double angle, double yaw, bool avx512, Ray& ray);
  Ray make_ray(double x, double y, double angle, double max_range) const;
  /// Where the clearance table of the ray's quadrant of travel starts in clearance_.
  std::size_t quadrant_table(const Ray& ray) const;
  Walk trace(const Ray& ray) const;
  Walk trace_dda(const Ray& ray) const;
  static Walk miss(const Ray& ray);
  /// Whether a ray in cell (col, row), outside the map, can never come back in.
  bool gone_for_good(const Ray& ray, int col, int row) const;
  /// Crosses the grid line(s) met at parameter t from cell (col, row); true, with `stop`, when
  /// the ray stops there.
  bool cross_lines(const Ray& ray, double t, bool cross_u, bool cross_v, int& col, int& row, Walk& stop) const;
  RayHit to_hit(const Ray& ray, const Walk& walk) const;

  int width_ = 0, height_ = 0;
  double resolution_ = 0.05;
  Pose2 origin_{};
  double yaw_cos_ = 1.0, yaw_sin_ = 0.0;  ///< of origin_.theta
  enum class Simd : unsigned char { kNone, kAvx2, kAvx512 };
  Simd simd_ = Simd::kNone;  ///< what scan() and the directions use, chosen at construction
  int block_cols_ = 0;    ///< blocks of 8 x 8 cells in a row of the tables
  std::size_t cells_ = 0;  ///< the size of one quadrant's table: whole blocks
  /// Four tables, one per quadrant of travel (+u+v, -u+v, +u-v, -u-v), of one byte per cell in the
  /// order of cell_index(): the side d (in cells, capped at 255) of the largest free square with the
  /// cell at its corner and extending the way the ray goes; 0 on a blocked cell. Padded with zero
  /// bytes at the end so SIMD gathers of 4 bytes stay inside.
  std::vector<std::uint8_t> clearance_;
};

}  // namespace vwg::sim
