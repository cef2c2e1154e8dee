// Exact grid raycasting by free-square skipping.
//
// For each quadrant of travel (+u+v, -u+v, +u-v, -u-v) each cell stores the side d of the largest
// free square that has the cell at its corner and extends the way the ray goes. From a cell the
// ray jumps straight to where it leaves that square, then looks again; near walls the squares
// shrink to one cell and the walk becomes the plain DDA. Exactness comes from two rules shared
// with the reference walk:
// - the parameter at which the ray crosses a grid line is always `crossing(line, start, 1/dir)`,
//   computed from the start (never accumulated), so both walks compare identical numbers;
// - after a jump, the cell held just before the crossing is found by rounding and then checked
//   against those same crossings, so ties (the ray through a grid corner) are seen exactly as the
//   reference sees them.
// scan() runs the same jumps on 16 beams at once with AVX-512 or AVX2 when the CPU has them (a
// beam that ends is replaced at once by the next one, so the lanes stay busy), else beam by beam.
#include "vwg/sim/raycast.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <string>
#include <string_view>

#include "geometry/directions_detail.hpp"
#include "vwg/error.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define VWG_RAYCAST_X86 1
#endif

namespace vwg::sim {

namespace {

// A ray's direction is the cosine and sine of its angle in grid axes, from the geometry library's
// sine and cosine (vwg/geometry/directions.hpp). Every method takes its directions from
// grid_directions(), so all see the same bits: on a CPU with AVX-512 every ray, single or in a
// scan, uses the AVX-512 code; without it, single rays use the scalar code and a scan's beams the
// same operations on 4 lanes of AVX2.
using geometry::detail::grid_directions;
using geometry::detail::is_simd_name;
using geometry::detail::simd_level;

constexpr int kMaxClearance = 255;
/// Starts farther than this from the grid (in cells) are refused, so cell indices fit an int.
constexpr double kMaxStartCells = 1e9;

/// The ray parameter (cells travelled) at which the ray crosses grid line `line` of one axis.
/// The one expression every walk uses, so equal crossings compare equal everywhere.
inline double crossing(double line, double start, double inv_dir) { return (line - start) * inv_dir; }

/// floor() for |x| < 2^31, without a libm call on baseline x86-64.
inline int floor_to_int(double x) {
  const int truncated = static_cast<int>(x);
  return truncated - (x < truncated ? 1 : 0);
}

/// Along one axis: the cell the ray holds just before parameter t (it holds `current` now, at a
/// parameter <= t), and whether it crosses a grid line exactly at t. `step` is the direction
/// (+1/-1). Rounding start + t * dir is at most one cell off; the crossings settle it.
inline int cell_before(int current, double start, double dir, double inv_dir, int step, double t, bool& crosses_at_t) {
  int cell = floor_to_int(start + t * dir);
  const double exit_side = step > 0 ? 1.0 : 0.0;  // which line of a cell the ray leaves it by
  double exit = crossing(cell + exit_side, start, inv_dir);
  if (exit < t) {
    cell += step;
    exit = crossing(cell + exit_side, start, inv_dir);
  } else if (cell != current) {
    const double entry = crossing(cell + (1.0 - exit_side), start, inv_dir);
    if (entry >= t) {
      cell -= step;
      exit = entry;
    }
  }
  crosses_at_t = exit == t;
  return cell;
}

/// What the SIMD scan kernels need besides the beams' directions.
struct ScanSetup {
  const std::uint8_t* clearance;
  int width, height;
  double block_cols;  ///< blocks of 8 x 8 cells in a row of the tables (GridRaycaster::cell_index)
  double cells;       ///< the size of one quadrant's table
  double u0, v0;      ///< start, cells
  int col0, row0;     ///< start cell, inside the map and free
  double t_max;       ///< cells
  double resolution;  ///< metres per cell
  double max_range;   ///< metres, written for misses
};

/// The directions of a run of beams, as set_direction makes them.
struct BeamDirections {
  const double *du, *dv, *inv_du, *inv_dv;
};

#ifdef VWG_RAYCAST_X86

// GCC 12's AVX-512 headers pass _mm512_undefined_pd() around, which -Wmaybe-uninitialized flags.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#define VWG_AVX512 __attribute__((target("avx2,avx512f"), always_inline)) inline

/// cell_before() on 8 lanes, with the same expressions. exit_side: 1 forward, 0 backward.
__attribute__((target("avx2,avx512f"), always_inline)) inline __m512d cell_before_x8(
    __m512d start, __m512d dir, __m512d inv_dir, __m512d step, __m512d exit_side, __m512d current, __m512d t,
    __mmask8& crosses_at_t) {
  const __m512d one = _mm512_set1_pd(1.0);
  const __m512d guess = _mm512_add_pd(start, _mm512_mul_pd(t, dir));
  __m512d cell = _mm512_roundscale_pd(guess, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  const __m512d exit = _mm512_mul_pd(_mm512_sub_pd(_mm512_add_pd(cell, exit_side), start), inv_dir);
  const __m512d entry_side = _mm512_sub_pd(one, exit_side);
  const __m512d entry = _mm512_mul_pd(_mm512_sub_pd(_mm512_add_pd(cell, entry_side), start), inv_dir);
  const __mmask8 behind = _mm512_cmp_pd_mask(exit, t, _CMP_LT_OQ);
  const __mmask8 moved = _mm512_mask_cmp_pd_mask(static_cast<__mmask8>(~behind), cell, current, _CMP_NEQ_UQ);
  const __mmask8 ahead = static_cast<__mmask8>(moved & _mm512_cmp_pd_mask(entry, t, _CMP_GE_OQ));
  cell = _mm512_mask_add_pd(cell, behind, cell, step);
  cell = _mm512_mask_sub_pd(cell, ahead, cell, step);
  const __m512d settled_exit = _mm512_mul_pd(_mm512_sub_pd(_mm512_add_pd(cell, exit_side), start), inv_dir);
  crosses_at_t = _mm512_cmp_pd_mask(settled_exit, t, _CMP_EQ_OQ);
  return cell;
}

/// GridRaycaster::cell_index() of 8 cells inside the map, in doubles, as table_cell_x4() (below).
VWG_AVX512 __m512d table_cell_x8(__m512d row, __m512d col, double block_cols) {
  const __m512d eight = _mm512_set1_pd(8.0), eighth = _mm512_set1_pd(0.125);
  const __m512d block_row = _mm512_roundscale_pd(_mm512_mul_pd(row, eighth), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  const __m512d block_col = _mm512_roundscale_pd(_mm512_mul_pd(col, eighth), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  const __m512d block = _mm512_add_pd(_mm512_mul_pd(block_row, _mm512_set1_pd(block_cols)), block_col);
  const __m512d within = _mm512_add_pd(_mm512_mul_pd(_mm512_sub_pd(row, _mm512_mul_pd(block_row, eight)), eight),
                                       _mm512_sub_pd(col, _mm512_mul_pd(block_col, eight)));
  return _mm512_add_pd(_mm512_mul_pd(block, _mm512_set1_pd(64.0)), within);
}

/// 8 beams in flight: which beams, their directions, where they are (the cell, and the
/// parameter at which they entered it).
struct Lanes {
  __m512i beam;
  __m512d du, dv, inv_du, inv_dv;
  __m512d exit_u, exit_v;  ///< which line of a cell the ray leaves it by: 1 forward, 0 backward
  __m512d table;           ///< where the clearance of the beam's quadrant starts
  __m512d col, row, t;
  __mmask8 active;
};

VWG_AVX512 void start_lanes(Lanes& lanes) {
  const __m512d one = _mm512_set1_pd(1.0);
  lanes.beam = _mm512_setzero_si512();
  lanes.du = lanes.dv = lanes.inv_du = lanes.inv_dv = lanes.exit_u = lanes.exit_v = one;
  lanes.col = lanes.row = lanes.t = lanes.table = _mm512_setzero_pd();
  lanes.active = 0;
}

/// Starts beams next, next + 1, ... in the idle lanes, while there are beams left.
VWG_AVX512 void refill(Lanes& lanes, const ScanSetup& s, const BeamDirections& beams, int n, int& next) {
  __mmask8 starting = static_cast<__mmask8>(~lanes.active);
  if (starting == 0 || next >= n) return;
  // Fewer beams left than idle lanes: keep the lowest ones.
  for (int extra = std::popcount(static_cast<unsigned>(starting)) - (n - next); extra > 0; --extra)
    starting = static_cast<__mmask8>(starting & ~(1u << (31 - std::countl_zero(static_cast<unsigned>(starting)))));
  const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0);
  lanes.du = _mm512_mask_expandloadu_pd(lanes.du, starting, beams.du + next);
  lanes.dv = _mm512_mask_expandloadu_pd(lanes.dv, starting, beams.dv + next);
  lanes.inv_du = _mm512_mask_expandloadu_pd(lanes.inv_du, starting, beams.inv_du + next);
  lanes.inv_dv = _mm512_mask_expandloadu_pd(lanes.inv_dv, starting, beams.inv_dv + next);
  const __m512i ids = _mm512_add_epi64(_mm512_set1_epi64(next), _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0));
  lanes.beam = _mm512_mask_expand_epi64(lanes.beam, starting, ids);
  const __mmask8 back_u = _mm512_cmp_pd_mask(lanes.du, zero, _CMP_LT_OQ);
  const __mmask8 back_v = _mm512_cmp_pd_mask(lanes.dv, zero, _CMP_LT_OQ);
  lanes.exit_u = _mm512_mask_blend_pd(back_u, one, zero);
  lanes.exit_v = _mm512_mask_blend_pd(back_v, one, zero);
  const __m512d cells = _mm512_set1_pd(s.cells);  // quadrant_table()
  const __m512d two_cells = _mm512_add_pd(cells, cells);
  lanes.table = _mm512_add_pd(_mm512_maskz_mov_pd(back_u, cells), _mm512_maskz_mov_pd(back_v, two_cells));
  lanes.col = _mm512_mask_mov_pd(lanes.col, starting, _mm512_set1_pd(s.col0));
  lanes.row = _mm512_mask_mov_pd(lanes.row, starting, _mm512_set1_pd(s.row0));
  lanes.t = _mm512_mask_mov_pd(lanes.t, starting, zero);
  next += std::popcount(static_cast<unsigned>(starting));
  lanes.active = static_cast<__mmask8>(lanes.active | starting);
}

/// One jump of GridRaycaster::trace for every active lane. Beams that end are written to out
/// (the hit range, max_range on a miss, -1 for the scalar code when the jump ends exactly on a
/// grid corner) and their lanes go idle.
VWG_AVX512 void advance(Lanes& lanes, const ScanSetup& s, float* out) {
  const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0), two = _mm512_set1_pd(2.0);
  const __m512d u0 = _mm512_set1_pd(s.u0), v0 = _mm512_set1_pd(s.v0);
  const __m512d width = _mm512_set1_pd(s.width), height = _mm512_set1_pd(s.height);
  const __mmask8 active = lanes.active;
  const __m512d col = lanes.col, row = lanes.row;

  // The clearance of each lane's cell (all inside the map); 0 means the ray stopped there.
  const __m512d index = _mm512_maskz_add_pd(active, table_cell_x8(row, col, s.block_cols), lanes.table);
  const __m256i raw = _mm256_i32gather_epi32(reinterpret_cast<const int*>(s.clearance),
                                             _mm512_maskz_cvttpd_epi32(0xFF, index), 1);
  const __m512d d = _mm512_maskz_cvtepi32_pd(0xFF, _mm256_and_si256(raw, _mm256_set1_epi32(0xFF)));
  const __mmask8 hit = _mm512_mask_cmp_pd_mask(active, d, zero, _CMP_EQ_OQ);
  const __mmask8 moving = static_cast<__mmask8>(active & ~hit);

  // Leave the free square: its far line is col + d going forward, col + 1 - d going back.
  const __m512d step_u = _mm512_sub_pd(_mm512_mul_pd(two, lanes.exit_u), one);
  const __m512d step_v = _mm512_sub_pd(_mm512_mul_pd(two, lanes.exit_v), one);
  const __m512d line_u = _mm512_add_pd(_mm512_sub_pd(col, _mm512_sub_pd(lanes.exit_u, one)), _mm512_mul_pd(step_u, d));
  const __m512d line_v = _mm512_add_pd(_mm512_sub_pd(row, _mm512_sub_pd(lanes.exit_v, one)), _mm512_mul_pd(step_v, d));
  const __m512d t_u = _mm512_mul_pd(_mm512_sub_pd(line_u, u0), lanes.inv_du);
  const __m512d t_v = _mm512_mul_pd(_mm512_sub_pd(line_v, v0), lanes.inv_dv);
  const __m512d t_next = _mm512_min_pd(t_u, t_v);
  const __mmask8 out_of_range = _mm512_mask_cmp_pd_mask(moving, t_next, _mm512_set1_pd(s.t_max), _CMP_NLE_UQ);

  __mmask8 cross_u, cross_v;
  __m512d next_col = cell_before_x8(u0, lanes.du, lanes.inv_du, step_u, lanes.exit_u, col, t_next, cross_u);
  __m512d next_row = cell_before_x8(v0, lanes.dv, lanes.inv_dv, step_v, lanes.exit_v, row, t_next, cross_v);
  next_col = _mm512_mask_add_pd(next_col, cross_u, next_col, step_u);
  next_row = _mm512_mask_add_pd(next_row, cross_v, next_row, step_v);
  const __mmask8 corner = static_cast<__mmask8>(moving & cross_u & cross_v & ~out_of_range);
  const __mmask8 outside = static_cast<__mmask8>(_mm512_mask_cmp_pd_mask(moving, next_col, zero, _CMP_LT_OQ) |
                                                 _mm512_mask_cmp_pd_mask(moving, next_col, width, _CMP_GE_OQ) |
                                                 _mm512_mask_cmp_pd_mask(moving, next_row, zero, _CMP_LT_OQ) |
                                                 _mm512_mask_cmp_pd_mask(moving, next_row, height, _CMP_GE_OQ));
  const __mmask8 missed = static_cast<__mmask8>(out_of_range | (outside & ~corner));

  const __mmask8 done = static_cast<__mmask8>(hit | missed | corner);
  if (done != 0) {  // the range as range() computes it
    __m512d value = _mm512_add_pd(_mm512_mul_pd(lanes.t, _mm512_set1_pd(s.resolution)), zero);
    value = _mm512_mask_mov_pd(value, missed, _mm512_set1_pd(s.max_range));
    value = _mm512_mask_mov_pd(value, corner, _mm512_set1_pd(-1.0));
    _mm512_mask_i64scatter_ps(out, done, lanes.beam, _mm512_cvtpd_ps(value), 4);
  }
  lanes.col = _mm512_mask_mov_pd(col, moving, next_col);
  lanes.row = _mm512_mask_mov_pd(row, moving, next_row);
  lanes.t = _mm512_mask_mov_pd(lanes.t, moving, t_next);
  lanes.active = static_cast<__mmask8>(active & ~done);
}

/// The jumps of GridRaycaster::trace on 16 beams at once, in two independent groups of 8 so
/// one group computes while the other waits for its gather.
__attribute__((target("avx2,avx512f"))) void scan_avx512(const ScanSetup& s, const BeamDirections& beams, int n,
                                                         float* out) {
  Lanes first, second;
  start_lanes(first);
  start_lanes(second);
  int next = 0;
  for (;;) {
    refill(first, s, beams, n, next);
    refill(second, s, beams, n, next);
    if ((first.active | second.active) == 0) break;
    advance(first, s, out);
    advance(second, s, out);
  }
}
#undef VWG_AVX512

#pragma GCC diagnostic pop

// ---- The scan on CPUs with AVX2 but not AVX-512 ----------------------------------------------
// The same jumps on 4 lanes of doubles, four groups in flight, each step made for all four before
// the next so that their chains overlap. No FMA is enabled here, so no expression is fused: every
// product and sum is rounded on its own, as in the scalar code. A lane whose beam ends writes its
// range and takes the next beam without a branch.
#define VWG_AVX2 __attribute__((target("avx2"), always_inline)) inline

/// GridRaycaster::cell_index() of 4 cells inside the map, in doubles (exact: all are integers
/// below 2^31): the cell's block of 8 x 8 cells, 64 bytes to a block, rows of blocks one after
/// another; in the block, rows of 8 cells.
VWG_AVX2 __m256d table_cell_x4(__m256d row, __m256d col, double block_cols) {
  const __m256d eight = _mm256_set1_pd(8.0), eighth = _mm256_set1_pd(0.125);
  const __m256d block_row = _mm256_floor_pd(_mm256_mul_pd(row, eighth));
  const __m256d block_col = _mm256_floor_pd(_mm256_mul_pd(col, eighth));
  const __m256d block = _mm256_add_pd(_mm256_mul_pd(block_row, _mm256_set1_pd(block_cols)), block_col);
  const __m256d within = _mm256_add_pd(_mm256_mul_pd(_mm256_sub_pd(row, _mm256_mul_pd(block_row, eight)), eight),
                                       _mm256_sub_pd(col, _mm256_mul_pd(block_col, eight)));
  return _mm256_add_pd(_mm256_mul_pd(block, _mm256_set1_pd(64.0)), within);
}

/// 4 beams in flight, in registers: which beams (-1: idle lane), their directions, where they
/// are (the cell, and the parameter at which they entered it).
struct QuadLanes {
  __m128i beam;
  __m256d du, dv, inv_du, inv_dv, col, row, t;
};

/// For each pattern of idle lanes (bit i: lane i idle), how many idle lanes come before each
/// lane: the i-th idle lane takes beam next + i. `rank` as 4 ints; `pick` as the indices of
/// _mm256_permutevar8x32 that move double `rank` of the 4 read from beam next into each lane.
struct IdleRanks {
  alignas(16) std::int32_t rank[16][4];
  alignas(32) std::int32_t pick[16][8];
};
constexpr IdleRanks kIdleRanks = [] {
  IdleRanks table{};
  for (unsigned idle = 0; idle < 16; ++idle)
    for (unsigned lane = 0; lane < 4; ++lane) {
      const int rank = std::popcount(idle & ((1u << lane) - 1));
      table.rank[idle][lane] = rank;
      table.pick[idle][2 * lane] = 2 * rank;
      table.pick[idle][2 * lane + 1] = 2 * rank + 1;
    }
  return table;
}();

VWG_AVX2 void start_lanes(QuadLanes& lanes) {
  const __m256d one = _mm256_set1_pd(1.0);
  lanes.beam = _mm_set1_epi32(-1);
  lanes.du = lanes.dv = lanes.inv_du = lanes.inv_dv = one;
  lanes.col = lanes.row = lanes.t = _mm256_setzero_pd();
}

/// The 4 doubles from `values` moved to the lanes `pick` says.
VWG_AVX2 __m256d picked(const double* values, __m256i pick) {
  return _mm256_castsi256_pd(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(_mm256_loadu_pd(values)), pick));
}

/// Starts beams next, next + 1, ... in the idle lanes, while there are beams left. Without a
/// branch, as advance() ends its lanes: the four beams from `next` are read whole (the beam arrays
/// hold 4 more past n, as next may be n) and moved to the lanes that take them.
VWG_AVX2 void refill(QuadLanes& lanes, const ScanSetup& s, const BeamDirections& beams, int n, int& next) {
  const int idle = _mm_movemask_ps(_mm_castsi128_ps(lanes.beam));
  const __m128i ids = _mm_add_epi32(_mm_set1_epi32(next), _mm_load_si128(reinterpret_cast<const __m128i*>(kIdleRanks.rank[idle])));
  // Idle lanes (beam -1) that get a beam: those whose id is below n.
  const __m128i starting =
      _mm_and_si128(_mm_cmpgt_epi32(_mm_set1_epi32(n), ids), lanes.beam);
  const __m128i start_mask = _mm_srai_epi32(starting, 31);  // all ones where starting
  const __m256d take = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(start_mask));
  lanes.beam = _mm_blendv_epi8(lanes.beam, ids, start_mask);
  const __m256i pick = _mm256_load_si256(reinterpret_cast<const __m256i*>(kIdleRanks.pick[idle]));
  lanes.du = _mm256_blendv_pd(lanes.du, picked(beams.du + next, pick), take);
  lanes.dv = _mm256_blendv_pd(lanes.dv, picked(beams.dv + next, pick), take);
  lanes.inv_du = _mm256_blendv_pd(lanes.inv_du, picked(beams.inv_du + next, pick), take);
  lanes.inv_dv = _mm256_blendv_pd(lanes.inv_dv, picked(beams.inv_dv + next, pick), take);
  lanes.col = _mm256_blendv_pd(lanes.col, _mm256_set1_pd(s.col0), take);
  lanes.row = _mm256_blendv_pd(lanes.row, _mm256_set1_pd(s.row0), take);
  lanes.t = _mm256_blendv_pd(lanes.t, _mm256_setzero_pd(), take);
  next += std::popcount(static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(start_mask))));
}

/// cell_before() on 4 lanes, with the same expressions. exit_side: 1 forward, 0 backward.
VWG_AVX2 __m256d cell_before_x4(__m256d start, __m256d dir, __m256d inv_dir, __m256d step, __m256d exit_side,
                                __m256d current, __m256d t, __m256d& crosses_at_t) {
  __m256d cell = _mm256_floor_pd(_mm256_add_pd(start, _mm256_mul_pd(t, dir)));
  const __m256d exit = _mm256_mul_pd(_mm256_sub_pd(_mm256_add_pd(cell, exit_side), start), inv_dir);
  const __m256d entry_side = _mm256_sub_pd(_mm256_set1_pd(1.0), exit_side);
  const __m256d entry = _mm256_mul_pd(_mm256_sub_pd(_mm256_add_pd(cell, entry_side), start), inv_dir);
  const __m256d behind = _mm256_cmp_pd(exit, t, _CMP_LT_OQ);
  const __m256d ahead = _mm256_andnot_pd(
      behind, _mm256_and_pd(_mm256_cmp_pd(cell, current, _CMP_NEQ_UQ), _mm256_cmp_pd(entry, t, _CMP_GE_OQ)));
  cell = _mm256_add_pd(cell, _mm256_and_pd(behind, step));
  cell = _mm256_sub_pd(cell, _mm256_and_pd(ahead, step));
  const __m256d settled_exit = _mm256_mul_pd(_mm256_sub_pd(_mm256_add_pd(cell, exit_side), start), inv_dir);
  crosses_at_t = _mm256_cmp_pd(settled_exit, t, _CMP_EQ_OQ);
  return cell;
}

constexpr int kGroups = 4;  ///< groups of 4 beams in flight
/// Each statement of advance() is made for every group before the next statement: the four
/// groups' chains of dependent operations then sit side by side in the core's window, where one
/// group's whole jump after another (about 90 operations each) let only two overlap.
#define VWG_EACH(statement)                                   \
  _Pragma("GCC unroll 4") for (int k = 0; k < kGroups; ++k) { \
    statement;                                                \
  }

/// One jump of GridRaycaster::trace for every active lane of every group. Beams that end are
/// written to out (the hit range, max_range on a miss, -1 for the scalar code when the jump ends
/// exactly on a grid corner) and their lanes go idle.
VWG_AVX2 void advance(QuadLanes (&groups)[kGroups], const ScanSetup& s, float* out) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0), minus_one = _mm256_set1_pd(-1.0);
  const __m256d u0 = _mm256_set1_pd(s.u0), v0 = _mm256_set1_pd(s.v0);
  const __m256d width = _mm256_set1_pd(s.width), height = _mm256_set1_pd(s.height);
  const __m256d cells = _mm256_set1_pd(s.cells);
  __m256d active[kGroups], col[kGroups], row[kGroups], back_u[kGroups], back_v[kGroups], exit_u[kGroups],
      exit_v[kGroups], index[kGroups];
  VWG_EACH(active[k] = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm_cmpgt_epi32(groups[k].beam, _mm_set1_epi32(-1)))));
  VWG_EACH(col[k] = groups[k].col; row[k] = groups[k].row);

  // Which way each beam goes, from the signs of its direction (the 8-lane code keeps these in its
  // lanes; here they are worked out again, which costs less than keeping them in registers).
  VWG_EACH(back_u[k] = _mm256_cmp_pd(groups[k].du, zero, _CMP_LT_OQ); back_v[k] = _mm256_cmp_pd(groups[k].dv, zero, _CMP_LT_OQ));
  VWG_EACH(exit_u[k] = _mm256_andnot_pd(back_u[k], one); exit_v[k] = _mm256_andnot_pd(back_v[k], one));

  // The clearance of each lane's cell (all inside the map); 0 means the ray stopped there. Read
  // by byte loads: AMD's Zen cores microcode gathers, and these were faster there.
  VWG_EACH(index[k] = _mm256_and_pd(active[k], _mm256_add_pd(table_cell_x4(row[k], col[k], s.block_cols),
                                                               _mm256_add_pd(_mm256_and_pd(back_u[k], cells),
                                                                             _mm256_and_pd(back_v[k], _mm256_add_pd(cells, cells))))));
  __m128i at[kGroups];
  VWG_EACH(at[k] = _mm256_cvttpd_epi32(index[k]));
  __m256d d[kGroups];
  VWG_EACH(d[k] = _mm256_cvtepi32_pd(_mm_setr_epi32(
               s.clearance[_mm_cvtsi128_si32(at[k])], s.clearance[_mm_extract_epi32(at[k], 1)],
               s.clearance[_mm_extract_epi32(at[k], 2)], s.clearance[_mm_extract_epi32(at[k], 3)])));
  __m256d hit[kGroups], moving[kGroups];
  VWG_EACH(hit[k] = _mm256_and_pd(active[k], _mm256_cmp_pd(d[k], zero, _CMP_EQ_OQ)));
  VWG_EACH(moving[k] = _mm256_andnot_pd(hit[k], active[k]));

  // Leave the free square: its far line is col + d going forward, col + 1 - d going back.
  __m256d step_u[kGroups], step_v[kGroups], t_next[kGroups], out_of_range[kGroups];
  VWG_EACH(step_u[k] = _mm256_blendv_pd(one, minus_one, back_u[k]); step_v[k] = _mm256_blendv_pd(one, minus_one, back_v[k]));
  VWG_EACH({
    const __m256d line_u = _mm256_add_pd(_mm256_sub_pd(col[k], _mm256_sub_pd(exit_u[k], one)), _mm256_mul_pd(step_u[k], d[k]));
    const __m256d line_v = _mm256_add_pd(_mm256_sub_pd(row[k], _mm256_sub_pd(exit_v[k], one)), _mm256_mul_pd(step_v[k], d[k]));
    t_next[k] = _mm256_min_pd(_mm256_mul_pd(_mm256_sub_pd(line_u, u0), groups[k].inv_du),
                              _mm256_mul_pd(_mm256_sub_pd(line_v, v0), groups[k].inv_dv));
  });
  VWG_EACH(out_of_range[k] = _mm256_and_pd(moving[k], _mm256_cmp_pd(t_next[k], _mm256_set1_pd(s.t_max), _CMP_NLE_UQ)));

  __m256d cross_u[kGroups], cross_v[kGroups], next_col[kGroups], next_row[kGroups];
  VWG_EACH(next_col[k] = cell_before_x4(u0, groups[k].du, groups[k].inv_du, step_u[k], exit_u[k], col[k], t_next[k], cross_u[k]));
  VWG_EACH(next_row[k] = cell_before_x4(v0, groups[k].dv, groups[k].inv_dv, step_v[k], exit_v[k], row[k], t_next[k], cross_v[k]));
  VWG_EACH(next_col[k] = _mm256_add_pd(next_col[k], _mm256_and_pd(cross_u[k], step_u[k]));
           next_row[k] = _mm256_add_pd(next_row[k], _mm256_and_pd(cross_v[k], step_v[k])));
  __m256d corner[kGroups], missed[kGroups], done[kGroups];
  VWG_EACH(corner[k] = _mm256_andnot_pd(out_of_range[k], _mm256_and_pd(moving[k], _mm256_and_pd(cross_u[k], cross_v[k]))));
  VWG_EACH({
    const __m256d outside = _mm256_or_pd(
        _mm256_or_pd(_mm256_cmp_pd(next_col[k], zero, _CMP_LT_OQ), _mm256_cmp_pd(next_col[k], width, _CMP_GE_OQ)),
        _mm256_or_pd(_mm256_cmp_pd(next_row[k], zero, _CMP_LT_OQ), _mm256_cmp_pd(next_row[k], height, _CMP_GE_OQ)));
    missed[k] = _mm256_or_pd(out_of_range[k], _mm256_andnot_pd(corner[k], _mm256_and_pd(moving[k], outside)));
  });
  VWG_EACH(done[k] = _mm256_or_pd(hit[k], _mm256_or_pd(missed[k], corner[k])));

  // The range as range() computes it, written by every lane without a branch (a mispredicted one
  // would throw away all four groups' work in flight): a lane that ended writes out[beam], the
  // others out[-1], a spare slot. Ended lanes go idle (-1).
  VWG_EACH({
    __m256d value = _mm256_add_pd(_mm256_mul_pd(groups[k].t, _mm256_set1_pd(s.resolution)), zero);
    value = _mm256_blendv_pd(value, _mm256_set1_pd(s.max_range), missed[k]);
    value = _mm256_blendv_pd(value, minus_one, corner[k]);
    const __m128i ended = _mm256_castsi256_si128(
        _mm256_permutevar8x32_epi32(_mm256_castpd_si256(done[k]), _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6)));
    alignas(16) float range[4];
    alignas(16) std::int32_t beam[4];
    _mm_store_ps(range, _mm256_cvtpd_ps(value));
    _mm_store_si128(reinterpret_cast<__m128i*>(beam), _mm_blendv_epi8(_mm_set1_epi32(-1), groups[k].beam, ended));
    for (int lane = 0; lane < 4; ++lane) out[beam[lane]] = range[lane];
    groups[k].beam = _mm_or_si128(groups[k].beam, ended);
  });
  VWG_EACH(groups[k].col = _mm256_blendv_pd(col[k], next_col[k], moving[k]);
           groups[k].row = _mm256_blendv_pd(row[k], next_row[k], moving[k]);
           groups[k].t = _mm256_blendv_pd(groups[k].t, t_next[k], moving[k]));
}
#undef VWG_EACH

/// The jumps of GridRaycaster::trace on 16 beams at once, in four independent groups of 4. out[-1]
/// must be writable (a spare slot) and the beams' arrays readable up to beam n + 3.
__attribute__((target("avx2"))) void scan_avx2(const ScanSetup& s, const BeamDirections& beams, int n,
                                               float* out) {
  QuadLanes groups[kGroups];
  for (QuadLanes& lanes : groups) start_lanes(lanes);
  int next = 0;
  for (;;) {
    __m128i busy = _mm_set1_epi32(-1);
    for (QuadLanes& lanes : groups) {
      refill(lanes, s, beams, n, next);
      busy = _mm_and_si128(busy, lanes.beam);  // stays -1 only while every lane of every group is idle
    }
    if (_mm_movemask_ps(_mm_castsi128_ps(busy)) == 0xF) break;
    advance(groups, s, out);
  }
}
#undef VWG_AVX2
#endif  // VWG_RAYCAST_X86

/// The code a raycaster runs unless VWG_RAYCAST_SIMD says: the widest, but AVX2 on AMD's family
/// 19h (Zen 3, which has no AVX-512, and Zen 4, which runs a 512-bit operation as two 256-bit
/// halves). On a Zen 4 the AVX2 code, its four groups of beams interleaved, scanned 24.7-26.3 M
/// rays/s against 22.2-24.6 for the AVX-512 code (bench_sensors.py's maps and poses, CPU time,
/// alternating runs in one process); both give the same ranges.
std::string_view preferred_simd() {
#ifdef VWG_RAYCAST_X86
  __builtin_cpu_init();
  if (__builtin_cpu_is("amdfam19h")) return "avx2";
#endif
  return "avx512";
}

}  // namespace

/// A ray in grid axes (cells).
struct GridRaycaster::Ray {
  double u0 = 0, v0 = 0;          ///< start
  double du = 0, dv = 0;          ///< unit direction
  double inv_du = 0, inv_dv = 0;  ///< 1 / direction
  double t_max = 0;               ///< max range in cells
  double max_range = 0;           ///< max range in metres
  int step_u = 1, step_v = 1;     ///< direction of travel along columns / rows
  int col0 = 0, row0 = 0;         ///< start cell
  std::size_t table = 0;          ///< where the clearance of its quadrant of travel starts
};

/// Where a walk ended: parameter t (cells), and the blocked cell and face when it hit.
struct GridRaycaster::Walk {
  double t = 0;
  int col = -1, row = -1, face = -1;
  bool hit = false;
};

GridRaycaster::GridRaycaster(const OccupancyGrid& grid, int threshold)
    : width_(grid.width),
      height_(grid.height),
      resolution_(grid.resolution),
      origin_(grid.origin),
      yaw_cos_(std::cos(grid.origin.theta)),
      yaw_sin_(std::sin(grid.origin.theta)) {
  if (grid.width < 0 || grid.height < 0) throw Error("GridRaycaster: negative grid size");
  const auto cells = static_cast<std::uint64_t>(grid.width) * static_cast<std::uint64_t>(grid.height);
  // The tables hold whole 8 x 8 blocks; their indices, four tables deep, must fit an int32.
  const std::uint64_t block_cols = (static_cast<std::uint64_t>(grid.width) + 7) / 8;
  const std::uint64_t padded = block_cols * ((static_cast<std::uint64_t>(grid.height) + 7) / 8) * 64;
  if (padded >= (std::uint64_t{1} << 29))
    throw Error("GridRaycaster: grids of 2^29 cells or more (in whole blocks of 8 x 8) are not supported");
  if (grid.data.size() != cells)
    throw Error("GridRaycaster: the grid has " + std::to_string(grid.data.size()) + " values for " +
                std::to_string(grid.width) + " x " + std::to_string(grid.height) + " cells");
  if (!(grid.resolution > 0.0) || !std::isfinite(grid.resolution))
    throw Error("GridRaycaster: the resolution must be a positive number of metres per cell");
  if (!std::isfinite(grid.origin.x) || !std::isfinite(grid.origin.y) || !std::isfinite(grid.origin.theta))
    throw Error("GridRaycaster: the grid origin must be finite");
  // VWG_RAYCAST_SIMD=avx512, =avx2 or =none chooses the code (at most what the CPU has); unset or
  // empty, the preferred code for this CPU. A misspelt choice is an error, not the default.
  const char* env = std::getenv("VWG_RAYCAST_SIMD");
  const std::string_view asked = env == nullptr ? "" : env;
  if (!asked.empty() && !is_simd_name(asked))
    throw Error("VWG_RAYCAST_SIMD: expected avx512, avx2 or none (or unset, for this CPU's preferred code), got '" +
                std::string(asked) + "'");
  const std::string_view level = simd_level(asked.empty() ? preferred_simd() : asked);
  simd_ = level == "avx512" ? Simd::kAvx512 : level == "avx2" ? Simd::kAvx2 : Simd::kNone;

  // Per quadrant, the largest free square anchored at each cell: 1 + the smallest of its three
  // neighbours ahead (the maximal-square recurrence), sweeping from the far corner back.
  // Outside cells count as free and unbounded.
  block_cols_ = static_cast<int>(block_cols);
  cells_ = static_cast<std::size_t>(padded);
  clearance_.assign(4 * cells_ + 4, 0);  // + 4: 4-byte gathers at the last cell stay inside
  const int w = width_, h = height_;
  for (int quadrant = 0; quadrant < 4; ++quadrant) {
    std::uint8_t* square = clearance_.data() + quadrant * cells_;
    const int step_u = quadrant & 1 ? -1 : 1, step_v = quadrant & 2 ? -1 : 1;
    auto ahead = [&](int row, int col) -> int {
      return row < 0 || col < 0 || row >= h || col >= w ? kMaxClearance : square[cell_index(row, col)];
    };
    for (int i = 0; i < h; ++i)
      for (int j = 0; j < w; ++j) {
        const int row = step_v > 0 ? h - 1 - i : i, col = step_u > 0 ? w - 1 - j : j;
        if (grid.data[static_cast<std::size_t>(row) * w + col] >= threshold) continue;  // blocked: 0
        const std::size_t at = cell_index(row, col);
        const int smallest =
            std::min({ahead(row, col + step_u), ahead(row + step_v, col), ahead(row + step_v, col + step_u)});
        square[at] = static_cast<std::uint8_t>(std::min(kMaxClearance, smallest + 1));
      }
  }
}

void GridRaycaster::set_start(double x, double y, Ray& ray) const {
  if (!std::isfinite(x) || !std::isfinite(y)) throw Error("raycast: the start (x, y) must be finite");
  const double dx = x - origin_.x, dy = y - origin_.y;  // as OccupancyGrid::world_to_grid
  ray.u0 = (yaw_cos_ * dx + yaw_sin_ * dy) / resolution_;
  ray.v0 = (-yaw_sin_ * dx + yaw_cos_ * dy) / resolution_;
  if (!(std::abs(ray.u0) < kMaxStartCells) || !(std::abs(ray.v0) < kMaxStartCells))
    throw Error("raycast: the start is too far from the grid");
  ray.col0 = floor_to_int(ray.u0);
  ray.row0 = floor_to_int(ray.v0);
}

void GridRaycaster::set_direction(double angle, double yaw, bool avx512, Ray& ray) {
  if (!std::isfinite(angle)) throw Error("raycast: the angle must be finite");
  const double relative = angle - yaw;
  grid_directions(&relative, 1, &ray.du, &ray.dv, avx512);
  ray.inv_du = 1.0 / ray.du;
  ray.inv_dv = 1.0 / ray.dv;
  ray.step_u = ray.du >= 0.0 ? 1 : -1;
  ray.step_v = ray.dv >= 0.0 ? 1 : -1;
}

std::size_t GridRaycaster::quadrant_table(const Ray& ray) const {
  return cells_ * ((ray.step_u > 0 ? 0 : 1) + (ray.step_v > 0 ? 0 : 2));
}

GridRaycaster::Ray GridRaycaster::make_ray(double x, double y, double angle, double max_range) const {
  if (!(max_range >= 0.0)) throw Error("raycast: max_range must be >= 0 (it may be infinite)");
  Ray ray;
  set_start(x, y, ray);
  set_direction(angle, origin_.theta, simd_ == Simd::kAvx512, ray);
  ray.max_range = max_range;
  ray.t_max = max_range / resolution_;
  ray.table = quadrant_table(ray);
  return ray;
}

GridRaycaster::Walk GridRaycaster::miss(const Ray& ray) {
  Walk walk;
  walk.t = ray.t_max;
  return walk;
}

bool GridRaycaster::gone_for_good(const Ray& ray, int col, int row) const {
  return (col < 0 && ray.du <= 0.0) || (col >= width_ && ray.du >= 0.0) || (row < 0 && ray.dv <= 0.0) ||
         (row >= height_ && ray.dv >= 0.0);
}

bool GridRaycaster::cross_lines(const Ray& ray, double t, bool cross_u, bool cross_v, int& col, int& row,
                                Walk& stop) const {
  const int face_u = ray.step_u > 0 ? 0 : 1, face_v = ray.step_v > 0 ? 2 : 3;
  if (cross_u && cross_v) {  // through a corner: the x side, then the y side, then the diagonal
    if (blocked(row, col + ray.step_u)) return stop = Walk{t, col + ray.step_u, row, face_u, true}, true;
    if (blocked(row + ray.step_v, col)) return stop = Walk{t, col, row + ray.step_v, face_v, true}, true;
  }
  if (cross_u) col += ray.step_u;
  if (cross_v) row += ray.step_v;
  if (blocked(row, col)) return stop = Walk{t, col, row, cross_u ? face_u : face_v, true}, true;
  return false;
}

GridRaycaster::Walk GridRaycaster::trace_dda(const Ray& ray) const {
  int col = ray.col0, row = ray.row0;
  if (blocked(row, col)) return Walk{0.0, col, row, -1, true};
  double line_u = ray.step_u > 0 ? col + 1.0 : col;  // the next grid line ahead on each axis
  double line_v = ray.step_v > 0 ? row + 1.0 : row;
  double t_u = crossing(line_u, ray.u0, ray.inv_du);
  double t_v = crossing(line_v, ray.v0, ray.inv_dv);
  for (;;) {
    const double t = std::min(t_u, t_v);
    if (!(t <= ray.t_max)) return miss(ray);
    const bool cross_u = t_u == t, cross_v = t_v == t;
    Walk stop;
    if (cross_lines(ray, t, cross_u, cross_v, col, row, stop)) return stop;
    if (cross_u) t_u = crossing(line_u += ray.step_u, ray.u0, ray.inv_du);
    if (cross_v) t_v = crossing(line_v += ray.step_v, ray.v0, ray.inv_dv);
    if (gone_for_good(ray, col, row)) return miss(ray);
  }
}

GridRaycaster::Walk GridRaycaster::trace(const Ray& ray) const {
  int col = ray.col0, row = ray.row0;
  if (blocked(row, col)) return Walk{0.0, col, row, -1, true};
  for (;;) {
    // Where the ray leaves a free box around the current cell, on each axis.
    double t_u, t_v;
    if (row >= 0 && col >= 0 && row < height_ && col < width_) {
      const int d = clearance_[ray.table + cell_index(row, col)];
      t_u = crossing(ray.step_u > 0 ? col + d : col + 1 - d, ray.u0, ray.inv_du);
      t_v = crossing(ray.step_v > 0 ? row + d : row + 1 - d, ray.v0, ray.inv_dv);
    } else {  // outside, free up to the next line of the map's edges (bounded, so cells fit an int)
      if (gone_for_good(ray, col, row)) return miss(ray);
      const bool right = ray.step_u > 0, up = ray.step_v > 0;
      const double edge_u = col < 0 ? 0.0 : col >= width_ ? width_ : right ? width_ : 0.0;
      const double edge_v = row < 0 ? 0.0 : row >= height_ ? height_ : up ? height_ : 0.0;
      t_u = crossing(edge_u, ray.u0, ray.inv_du);
      t_v = crossing(edge_v, ray.v0, ray.inv_dv);
    }
    const double t = std::min(t_u, t_v);
    if (!(t <= ray.t_max)) return miss(ray);
    bool cross_u = false, cross_v = false;
    col = cell_before(col, ray.u0, ray.du, ray.inv_du, ray.step_u, t, cross_u);
    row = cell_before(row, ray.v0, ray.dv, ray.inv_dv, ray.step_v, t, cross_v);
    Walk stop;
    if (cross_lines(ray, t, cross_u, cross_v, col, row, stop)) return stop;
  }
}

RayHit GridRaycaster::to_hit(const Ray& ray, const Walk& walk) const {
  RayHit hit;
  hit.hit = walk.hit;
  hit.row = walk.row;
  hit.col = walk.col;
  hit.face = walk.face;
  hit.distance = walk.hit ? walk.t * resolution_ + 0.0 : ray.max_range;  // + 0.0: no -0 at the start
  double u = ray.u0 + walk.t * ray.du, v = ray.v0 + walk.t * ray.dv;
  if (walk.face == 0 || walk.face == 1) u = walk.col + (walk.face == 0 ? 0.0 : 1.0);  // exactly on the line
  if (walk.face == 2 || walk.face == 3) v = walk.row + (walk.face == 2 ? 0.0 : 1.0);
  if (walk.hit && walk.face == -1) u = ray.u0, v = ray.v0;
  hit.x = origin_.x + (yaw_cos_ * u - yaw_sin_ * v) * resolution_;  // as OccupancyGrid::grid_to_world
  hit.y = origin_.y + (yaw_sin_ * u + yaw_cos_ * v) * resolution_;
  return hit;
}

RayHit GridRaycaster::cast(double x, double y, double angle, double max_range) const {
  const Ray ray = make_ray(x, y, angle, max_range);
  return to_hit(ray, trace(ray));
}

double GridRaycaster::range(double x, double y, double angle, double max_range) const {
  const Ray ray = make_ray(x, y, angle, max_range);
  const Walk walk = trace(ray);
  return walk.hit ? walk.t * resolution_ + 0.0 : max_range;
}

RayHit GridRaycaster::cast_dda(double x, double y, double angle, double max_range) const {
  const Ray ray = make_ray(x, y, angle, max_range);
  return to_hit(ray, trace_dda(ray));
}

void GridRaycaster::scan(const Pose2& pose, std::span<const double> angles, double max_range,
                         std::span<float> out) const {
  if (out.size() != angles.size())
    throw Error("scan: " + std::to_string(out.size()) + " outputs for " + std::to_string(angles.size()) + " angles");
  Ray ray = make_ray(pose.x, pose.y, pose.theta, max_range);
  auto scalar = [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) {
      set_direction(pose.theta + angles[i], origin_.theta, simd_ == Simd::kAvx512, ray);
      ray.table = quadrant_table(ray);
      const Walk walk = trace(ray);
      out[i] = static_cast<float>(walk.hit ? walk.t * resolution_ + 0.0 : max_range);
    }
  };
#ifdef VWG_RAYCAST_X86
  const bool start_free_inside =
      ray.row0 >= 0 && ray.col0 >= 0 && ray.row0 < height_ && ray.col0 < width_ && !blocked(ray.row0, ray.col0);
  if (start_free_inside && simd_ != Simd::kNone) {
    const ScanSetup setup{clearance_.data(),
                          width_,
                          height_,
                          static_cast<double>(block_cols_),
                          static_cast<double>(cells_),
                          ray.u0,
                          ray.v0,
                          ray.col0,
                          ray.row0,
                          ray.t_max,
                          resolution_,
                          max_range};
    constexpr std::size_t kChunk = 256;  // beams set up at a time, on the stack
    // + 4: the AVX2 code reads 4 beams' directions from any beam up to n on; ranges[0] is its
    // spare slot.
    std::array<double, kChunk> relative;
    std::array<double, kChunk + 4> du, dv, inv_du, inv_dv;
    std::array<float, kChunk + 1> ranges;
    for (std::size_t first = 0; first < angles.size(); first += kChunk) {
      const std::size_t count = std::min(kChunk, angles.size() - first);
      for (std::size_t i = 0; i < count; ++i) {
        const double angle = pose.theta + angles[first + i];  // as the caller of range() would
        if (!std::isfinite(angle)) throw Error("raycast: the angle must be finite");
        relative[i] = angle - origin_.theta;
      }
      grid_directions(relative.data(), count, du.data(), dv.data(), simd_ == Simd::kAvx512, simd_ == Simd::kAvx2);
      for (std::size_t i = 0; i < count; ++i) inv_du[i] = 1.0 / du[i], inv_dv[i] = 1.0 / dv[i];
      for (std::size_t i = count; i < count + 4; ++i) du[i] = dv[i] = inv_du[i] = inv_dv[i] = 1.0;  // read, not used
      const BeamDirections beams{du.data(), dv.data(), inv_du.data(), inv_dv.data()};
      if (simd_ == Simd::kAvx512)
        scan_avx512(setup, beams, static_cast<int>(count), ranges.data() + 1);
      else
        scan_avx2(setup, beams, static_cast<int>(count), ranges.data() + 1);
      std::copy(ranges.begin() + 1, ranges.begin() + 1 + static_cast<std::ptrdiff_t>(count), out.begin() + static_cast<std::ptrdiff_t>(first));
      for (std::size_t i = first; i < first + count; ++i)
        if (out[i] < 0.0f) scalar(i, i + 1);  // the rare beam through a grid corner
    }
    return;
  }
#endif
  scalar(0, angles.size());
}

}  // namespace vwg::sim
