#include "vwg/robot/robot_map.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include "geometry/clearance.hpp"
#include "robot/segment_cells.hpp"
#include "vwg/error.hpp"

namespace vwg::robot {

std::shared_ptr<Blob> make_robot_map(const geometry::OccupancyGrid& world, bool knows_map, int threshold) {
  auto map = std::make_shared<Blob>(DType::Int16, std::vector<std::int64_t>{world.height, world.width});
  auto cells = map->mutable_view<std::int16_t>();
  if (knows_map) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::int8_t v = world.data[i];
      cells[i] = v < 0 ? kUnknownCell : (v >= threshold ? kWallCell : kFreeCell);
    }
  }
  map->share();  // every robot starts from a copy of it; each keeps only the pages it changes
  return map;
}

namespace {
std::size_t index(const geometry::MapGeometry& g, int row, int col) { return static_cast<std::size_t>(row) * g.width + col; }
std::int16_t cell(const Blob& map, const geometry::MapGeometry& g, int row, int col) {
  return map.view<std::int16_t>()[static_cast<std::size_t>(row) * g.width + col];
}
void check(const Blob& map, const geometry::MapGeometry& g) { check_robot_map(map, g); }

/// A cell walk (Amanatides-Woo) along the segment from (u0, v0) to (u1, v1) in cell units: the
/// cells it crosses, from the start cell to the end cell, in order. The parameter (0 at the start,
/// 1 at the end) at which the segment crosses a grid line is computed from the start for every
/// line, never accumulated step by step, so whether the walk passes a cell can be told without
/// walking to it (visits). At a grid corner (both lines crossed at once) the row steps first.
struct CellWalk {
  CellWalk(double u0_, double v0_, double u1, double v1)
      : col(static_cast<int>(std::floor(u0_))), end_col(static_cast<int>(std::floor(u1))),
        row(static_cast<int>(std::floor(v0_))), end_row(static_cast<int>(std::floor(v1))), col0(col), row0(row),
        u0(u0_), v0(v0_) {
    const double du = u1 - u0, dv = v1 - v0;
    step_u = du > 0 ? 1 : -1;
    step_v = dv > 0 ? 1 : -1;
    exit_u = du > 0 ? 1 : 0;
    exit_v = dv > 0 ? 1 : 0;
    moves_u = du != 0;
    moves_v = dv != 0;
    inv_du = moves_u ? 1.0 / du : 0.0;
    inv_dv = moves_v ? 1.0 / dv : 0.0;
    t_u = crossing_u(col + exit_u);
    t_v = crossing_v(row + exit_v);
  }
  /// Cells from the start to the end cell, both counted, on a straight walk.
  int length() const { return std::abs(end_col - col) + std::abs(end_row - row) + 1; }
  bool at_end() const { return col == end_col && row == end_row; }
  /// Where the segment crosses the column line `line` / the row line `line` (infinity if never).
  double crossing_u(int line) const { return moves_u ? (line - u0) * inv_du : kNever; }
  double crossing_v(int line) const { return moves_v ? (line - v0) * inv_dv : kNever; }
  /// Whether the walk, from its start on and never stopping, passes through cell (r, c).
  bool visits(int r, int c) const {
    // The walk is in column c between the crossings of the line into it and the line out of it
    // (the start column from the outset), and likewise in row r; at a grid corner the row line is
    // crossed first. It is in the cell while in both.
    struct Key {  // a crossing, in the walk's order
      double t;
      int row_first;
      bool operator<(const Key& o) const { return t < o.t || (t == o.t && row_first < o.row_first); }
    };
    const auto span = [](int cell, int first, int step, int exit, bool moves, auto crossing, int order, Key& in, Key& out) {
      if ((cell - first) * step < 0 || (!moves && cell != first)) return false;
      in = cell == first ? Key{-kNever, order} : Key{crossing(cell - step + exit), order};
      out = Key{crossing(cell + exit), order};
      return true;
    };
    Key in_u, out_u, in_v, out_v;
    if (!span(c, col0, step_u, exit_u, moves_u, [this](int line) { return crossing_u(line); }, 1, in_u, out_u)) return false;
    if (!span(r, row0, step_v, exit_v, moves_v, [this](int line) { return crossing_v(line); }, 0, in_v, out_v)) return false;
    const Key& in = in_u < in_v ? in_v : in_u;
    const Key& out = out_u < out_v ? out_u : out_v;
    return in < out;
  }
  void advance() {
    if (t_u < t_v) {
      col += step_u;
      t_u = crossing_u(col + exit_u);
    } else {
      row += step_v;
      t_v = crossing_v(row + exit_v);
    }
  }

  static constexpr double kNever = std::numeric_limits<double>::infinity();
  // Not {col, row} beside {end_col, end_row}: GCC then compares the pairs as one 8-byte word read
  // back from the stack, a store-forwarding stall on every step (the walk ran at half speed).
  int col;
  const int end_col;
  int row;
  const int end_row;
  const int col0, row0;  // the start cell
  double u0, v0;
  int step_u, step_v, exit_u, exit_v;
  bool moves_u, moves_v;
  double inv_du, inv_dv, t_u, t_v;
};
}  // namespace

void check_robot_map(const Blob& map, const geometry::MapGeometry& g) {
  if (map.dtype() != DType::Int16 || map.ndim() != 2 || map.shape()[0] != g.height || map.shape()[1] != g.width) {
    throw SchemaError("grid", "a robot map is an int16 array of the world map's shape");
  }
}

void ObstacleBits::scan(std::span<const std::int16_t> cells, const geometry::MapGeometry& g) {
  columns_ = (g.width + (1 << kShift) - 1) >> kShift;
  rows_ = (g.height + (1 << kShift) - 1) >> kShift;
  word_at_ = TiledIndex<4, 4>(rows_, columns_);
  words_ = SharedArray<Words>(word_at_.size());
  blocks_.assign((words_.size() + 63) / 64, 0);
  for (int r = 0; r < g.height; ++r) {
    for (int c = 0; c < g.width; ++c) {
      if (const std::int16_t v = cells[index(g, r, c)]; is_obstacle(v)) set(r, c, v);
    }
  }
}

void ObstacleBits::sync(const Blob& map, const geometry::MapGeometry& g) {
  check(map, g);
  const int columns = (g.width + (1 << kShift) - 1) >> kShift, rows = (g.height + (1 << kShift) - 1) >> kShift;
  if (revision_ == map.revision() && columns == columns_ && rows == rows_) return;
  const auto cells = map.view<std::int16_t>();
  static OriginCache<std::pair<int, int>, ObstacleBits> originals;  // one per shared content, for every robot
  const auto original = map.shared() ? originals.get(map.origin(), std::pair{g.height, g.width}, [&] {
    ObstacleBits bits;
    bits.scan(map.original_view<std::int16_t>(), g);
    bits.words_.share();
    return bits;
  })
                                     : nullptr;
  if (original == nullptr) {
    scan(cells, g);
  } else {
    ObstacleBits copy = *original;  // all or nothing (see PlanningMap::start_from_original)
    copy.edits_ = edits_;           // this robot's count (reshare_phase), not the original's
    *this = std::move(copy);
    // The cells this copy changed.
    for_each_changed_cell(cells, map.original_view<std::int16_t>(), [&](std::size_t i) {
      set(static_cast<int>(i / static_cast<std::size_t>(g.width)), static_cast<int>(i % static_cast<std::size_t>(g.width)), cells[i]);
    });
  }
  revision_ = map.revision();
}

bool mark_obstacle(MapEdit& map, const geometry::MapGeometry& g, double x, double y, ObstacleBits* bits) {
  check(map.blob(), g);
  int r, c;
  if (!g.cell_of(x, y, r, c)) return false;
  if (bits ? bits->obstacle(r, c) : is_obstacle(map[index(g, r, c)])) return false;  // walls and markers stay
  map.set(index(g, r, c), kSeenCell);
  if (bits) bits->set(r, c, kSeenCell);
  return true;
}

bool mark_marker(MapEdit& map, const geometry::MapGeometry& g, double x, double y, int tag, ObstacleBits* bits) {
  check(map.blob(), g);
  int r, c;
  if (!g.cell_of(x, y, r, c)) return false;
  const auto value = static_cast<std::int16_t>(kMarkerBase + tag);
  if (map[index(g, r, c)] == value) return false;
  map.set(index(g, r, c), value);
  if (bits) bits->set(r, c, value);
  return true;
}

int carve_free(MapEdit& map, const geometry::MapGeometry& g, double x0, double y0, double x1, double y1) {
  check(map.blob(), g);
  const geometry::OccupancyGrid f = g.frame();
  double u0, v0, u1, v1;
  f.world_to_grid(x0, y0, u0, v0);
  f.world_to_grid(x1, y1, u1, v1);
  // The cells the beam crossed, from the start cell to the end cell, which is left alone.
  CellWalk walk(u0, v0, u1, v1);
  const int limit = walk.length() + 1;
  const auto rows = static_cast<unsigned>(g.height), cols = static_cast<unsigned>(g.width);
  int changed = 0;
  for (int k = 0; k < limit && !walk.at_end(); ++k, walk.advance()) {
    if (static_cast<unsigned>(walk.row) < rows && static_cast<unsigned>(walk.col) < cols &&
        map[index(g, walk.row, walk.col)] == kSeenCell) {
      map.set(index(g, walk.row, walk.col), kFreeCell);
      ++changed;
    }
  }
  return changed;
}

namespace {

/// A number that grows with the direction of (dx, dy) from -π to π, in (-2, 2], cheaper than the
/// angle (a division instead of atan2): the order of directions, for finding beams by direction.
double pseudo_angle(double dx, double dy) {
  const double r = dy / (std::abs(dx) + std::abs(dy));
  return dx >= 0 ? r : dy >= 0 ? 2 - r : -2 - r;
}

/// What sense_scan knows of one beam.
struct BeamWalk {
  CellWalk walk;
  double bearing;  // pseudo_angle of its direction in grid axes
  double reach;    // cells from the start to the end
  int stop;        // the walk clears the cells it reaches in fewer steps than this
  bool reaches_end;
};

/// A cell inside the map as one number, in the order of the map's cells (row-major), from which
/// the row and column come back without a division.
std::uint64_t place_of(int row, int col) { return (static_cast<std::uint64_t>(row) << 32) | static_cast<std::uint32_t>(col); }
int row_of(std::uint64_t place) { return static_cast<int>(place >> 32); }
int col_of(std::uint64_t place) { return static_cast<int>(place & 0xFFFFFFFFu); }

/// What a scan's beams do to the cells they change, cell by cell: the last beam that marks the
/// cell and the last whose walk clears it (beam j counted as j + 1; 0 for none). Beams act in
/// order, each clearing its walk before marking its end, so these two say how the cell ends (see
/// sense_scan) and the order of the rest does not matter. An open-addressing table keyed by
/// place, its entries kept in the order they came (that order, fixed by the beams, is the order
/// the cells are written in).
class CellFates {
 public:
  struct Fate {
    std::uint64_t place;
    std::uint32_t last_mark = 0, last_clear = 0;
  };
  void clear() {  // only the slots in use: a scan that once grew the table does not cost the next ones
    for (const std::uint32_t s : used_) slots_[s] = 0;
    fates_.clear(), used_.clear();
  }
  /// The cell's entry, made if it has none.
  Fate& at(std::uint64_t place) {
    if (2 * (fates_.size() + 1) > slots_.size()) grow();
    for (std::size_t s = slot(place);; s = (s + 1) & (slots_.size() - 1)) {
      if (slots_[s] == 0) {
        fates_.push_back(Fate{place});
        slots_[s] = static_cast<std::uint32_t>(fates_.size());
        used_.push_back(static_cast<std::uint32_t>(s));
        return fates_.back();
      }
      if (fates_[slots_[s] - 1].place == place) return fates_[slots_[s] - 1];
    }
  }
  /// The cell's entry, or nullptr.
  const Fate* find(std::uint64_t place) const {
    if (slots_.empty()) return nullptr;
    for (std::size_t s = slot(place);; s = (s + 1) & (slots_.size() - 1)) {
      if (slots_[s] == 0) return nullptr;
      if (fates_[slots_[s] - 1].place == place) return &fates_[slots_[s] - 1];
    }
  }
  std::span<const Fate> entries() const { return fates_; }
  std::size_t size() const { return fates_.size(); }
  const Fate& operator[](std::size_t k) const { return fates_[k]; }

 private:
  std::size_t slot(std::uint64_t place) const {
    return static_cast<std::size_t>((place * 0x9E3779B97F4A7C15ull) >> (64 - std::countr_zero(slots_.size())));
  }
  void grow() {
    slots_.assign(std::max<std::size_t>(1024, 2 * slots_.size()), 0u);
    for (std::size_t k = 0; k < fates_.size(); ++k) {
      std::size_t s = slot(fates_[k].place);
      while (slots_[s] != 0) s = (s + 1) & (slots_.size() - 1);
      slots_[s] = static_cast<std::uint32_t>(k + 1);
      used_[k] = static_cast<std::uint32_t>(s);
    }
  }
  std::vector<Fate> fates_;
  std::vector<std::uint32_t> slots_;  // fates_ index + 1; 0 empty; a power of two long
  std::vector<std::uint32_t> used_;   // the slot of each entry
};

/// Where a sorted list of bearings (pseudo-angles in [-2, 2]) crosses a value: a table of 256
/// equal slices of [-2, 2], each with the first bearing at or past its start, so a search starts
/// a step or two from its answer (a binary search's mispredicted branches were much of a scan).
class BearingIndex {
 public:
  template <class Bearings>
  void build(const Bearings& sorted) {
    std::size_t i = 0;
    for (int k = 0; k <= kSlices; ++k) {
      const double start = -2.0 + 4.0 * k / kSlices;
      while (i < sorted.size() && sorted[i].bearing < start) ++i;
      first_[k] = static_cast<std::uint32_t>(i);
    }
  }
  /// The first position whose bearing is >= x (std::lower_bound's answer), settled by comparisons.
  template <class Bearings>
  std::size_t lower_bound(const Bearings& sorted, double x) const {
    const double slice = (x + 2.0) * (kSlices / 4.0);
    std::size_t i = first_[!(slice > 0.0) ? 0 : slice >= kSlices ? kSlices : static_cast<int>(slice)];
    while (i > 0 && sorted[i - 1].bearing >= x) --i;
    while (i < sorted.size() && sorted[i].bearing < x) ++i;
    return i;
  }

 private:
  static constexpr int kSlices = 256;
  std::uint32_t first_[kSlices + 1] = {};
};

}  // namespace

int sense_scan(MapEdit& map, const geometry::MapGeometry& g, ObstacleBits& bits, double x0, double y0,
               std::span<const ScanBeam> beams, bool carve) {
  check(map.blob(), g);
  const geometry::OccupancyGrid f = g.frame();
  double u0, v0;
  f.world_to_grid(x0, y0, u0, v0);
  const int rows = g.height, cols = g.width;
  struct Bearing {
    double bearing;
    std::uint32_t beam;
    bool operator<(const Bearing& o) const { return bearing < o.bearing; }
  };
  // Kept from scan to scan (no allocation a frame), and named once here: a thread_local used
  // inside the loops was looked up again (__tls_get_addr) after every call.
  thread_local struct {
    std::vector<BeamWalk> walks;
    std::vector<Bearing> by_bearing;  // normal beams (those that reach their end cell), by bearing
    BearingIndex bearing_index;
    CellFates fates;
    std::vector<std::pair<int, int>> crossed;  // blocks of reported obstacles some beam crosses
  } scratch;
  auto& [walks, by_bearing, bearing_index, fates, crossed] = scratch;
  walks.clear(), by_bearing.clear(), fates.clear(), crossed.clear();
  // The rows and columns any beam's walk can reach (beams that miss their end cell aside).
  int lo_row = static_cast<int>(std::floor(v0)), hi_row = lo_row, lo_col = static_cast<int>(std::floor(u0)), hi_col = lo_col;
  for (std::uint32_t j = 0; j < beams.size(); ++j) {
    double u1, v1;
    f.world_to_grid(beams[j].end_x, beams[j].end_y, u1, v1);
    CellWalk walk(u0, v0, u1, v1);
    const int end_steps = walk.length() - 1;
    const bool reaches_end = walk.visits(walk.end_row, walk.end_col);
    // A walk stops at its end cell; one that misses it (rounding) stops after length() + 1 cells.
    const double du = u1 - u0, dv = v1 - v0;
    walks.push_back(BeamWalk{walk, pseudo_angle(du, dv), std::sqrt(du * du + dv * dv), reaches_end ? end_steps : end_steps + 2,
                             reaches_end});
    // A beam of no length clears nothing (it stops where it starts).
    if (reaches_end && end_steps > 0) {
      by_bearing.push_back(Bearing{walks.back().bearing, j});
      lo_row = std::min(lo_row, walk.end_row), hi_row = std::max(hi_row, walk.end_row);
      lo_col = std::min(lo_col, walk.end_col), hi_col = std::max(hi_col, walk.end_col);
    }
    int r, c;
    if (g.cell_of(beams[j].mark_x, beams[j].mark_y, r, c)) fates.at(place_of(r, c)).last_mark = j + 1;
  }
  const std::size_t marked = fates.size();  // the cells the beams mark: the first entries
  // A laser's beams come in the order of their angles: sorted already, or sorted but for where
  // they pass the direction -π = π (then rotated into order).
  const auto descent = std::is_sorted_until(by_bearing.begin(), by_bearing.end());
  if (descent != by_bearing.end()) {
    if (std::is_sorted(descent, by_bearing.end()) && !(by_bearing.front() < by_bearing.back())) {
      std::rotate(by_bearing.begin(), descent, by_bearing.end());
    } else {
      std::sort(by_bearing.begin(), by_bearing.end());
    }
  }
  bearing_index.build(by_bearing);

  // The normal beams whose walk clears cell (row, col): those whose direction meets the disc
  // round the cell (or the block) of radius `radius` about (cu, cv), and whose walk then reaches
  // the cell before it stops.
  double farthest = 0.0;  // the longest normal beam, cells
  for (const Bearing& b : by_bearing) farthest = std::max(farthest, walks[b.beam].reach);
  // each(j) returns false to stop. The beams come from the last bearing back (a laser's beams
  // by falling index, but where they pass -π = π), so the first that clears a cell is about the
  // last beam that does.
  auto beams_across = [&](double cu, double cv, double radius, auto&& each) {
    const double du = cu - u0, dv = cv - v0, d = std::sqrt(du * du + dv * dv);
    if (d - radius - 1e-6 > farthest) return;  // beyond every beam
    auto try_beam = [&](std::uint32_t j) { return walks[j].reach >= d - radius - 1e-6 ? each(j) : true; };
    auto span = [&](std::size_t first, std::size_t end) {
      for (std::size_t k = end; k > first;)
        if (!try_beam(by_bearing[--k].beam)) return false;
      return true;
    };
    // The directions that meet the disc: within asin(radius / d) of its centre's, between the two
    // tangents (the sine a little larger than radius / d, against rounding).
    const double sine = radius / d + 1e-9;
    if (!(sine < 0.9)) {  // the start is in the disc or near it: any direction
      span(0, by_bearing.size());
      return;
    }
    const double cosine = std::sqrt(1 - sine * sine);
    const double lo = pseudo_angle(du * cosine + dv * sine, dv * cosine - du * sine);
    const double hi = pseudo_angle(du * cosine - dv * sine, dv * cosine + du * sine);
    // Positions of the bearings in [lo, hi] (the last: the first bearing past hi).
    const auto at = [&](double x) { return bearing_index.lower_bound(by_bearing, x); };
    auto past = [&](double x) {
      std::size_t i = at(x);
      while (i < by_bearing.size() && by_bearing[i].bearing <= x) ++i;
      return i;
    };
    if (lo <= hi) {
      span(at(lo), past(hi));
    } else if (span(0, past(hi))) {  // across the direction -π = π
      span(at(lo), by_bearing.size());
    }
  };
  auto clears = [&](std::uint32_t j, int row, int col) {
    const BeamWalk& b = walks[j];
    const int steps = std::abs(col - b.walk.col0) + std::abs(row - b.walk.row0);
    return steps < b.stop && b.walk.visits(row, col);
  };
  // The last beam whose walk clears cell (row, col), into the cell's fate.
  auto note_clears = [&](int row, int col) {
    std::uint32_t last = 0;
    beams_across(col + 0.5, row + 0.5, 0.7072, [&](std::uint32_t j) {
      if (j + 1 > last && clears(j, row, col)) last = j + 1;
      return true;
    });
    if (last) {
      CellFates::Fate& fate = fates.at(place_of(row, col));
      fate.last_clear = std::max(fate.last_clear, last);
    }
  };

  if (carve) {
    // The reported obstacles within reach (the marks one cell beyond included), by blocks.
    constexpr int kShift = ObstacleBits::kShift, kSide = 1 << kShift;
    const int first_br = std::max(0, lo_row - 1) >> kShift, last_br = std::min(rows - 1, hi_row + 1) >> kShift;
    const int first_bc = std::max(0, lo_col - 1) >> kShift, last_bc = std::min(cols - 1, hi_col + 1) >> kShift;
    // First the blocks some beam crosses, their words read ahead (each a likely cache miss), then
    // their cells.
    for (int br = first_br; br <= last_br; ++br) {
      for (int bc = first_bc; bc <= last_bc; ++bc) {
        if (!bits.block_flag(br, bc)) continue;
        bool any = false;
        beams_across((bc + 0.5) * kSide, (br + 0.5) * kSide, 0.7072 * kSide, [&](std::uint32_t) { return any = true, false; });
        if (!any) continue;
        bits.prefetch(br << kShift, bc << kShift);
        crossed.emplace_back(br, bc);
      }
    }
    for (const auto& [br, bc] : crossed) {
      for (std::uint64_t cells = bits.seen_cells(br, bc); cells != 0; cells &= cells - 1) {
        const int bit = std::countr_zero(cells);
        note_clears((br << kShift) | (bit >> 3), (bc << kShift) | (bit & 7));
      }
    }
    // Cells this scan marks that were not reported obstacles before: later beams may clear them.
    for (std::size_t k = 0; k < marked; ++k) {
      const std::uint64_t place = fates[k].place;
      if (!bits.seen(row_of(place), col_of(place))) note_clears(row_of(place), col_of(place));
    }
    // Beams that miss their end cell (rounding): walked cell by cell, as carve_free walks them.
    for (std::uint32_t j = 0; j < walks.size(); ++j) {
      if (walks[j].reaches_end) continue;
      CellWalk walk = walks[j].walk;
      for (int k = 0; k < walks[j].stop && !walk.at_end(); ++k, walk.advance()) {
        if (static_cast<unsigned>(walk.row) >= static_cast<unsigned>(rows) || static_cast<unsigned>(walk.col) >= static_cast<unsigned>(cols)) continue;
        const std::uint64_t place = place_of(walk.row, walk.col);
        const CellFates::Fate* known = fates.find(place);
        if (bits.seen(walk.row, walk.col) || (known && known->last_mark)) {
          CellFates::Fate& fate = fates.at(place);
          fate.last_clear = std::max(fate.last_clear, j + 1);
        }
      }
    }
  }

  // How each cell ends, from what the bits say it holds: a wall or a marker (where most beams
  // stop) stays; a reported obstacle may be cleared; any other cell (free or unknown) may be
  // marked, then cleared. Beams act in order, each clearing before it marks: a cell some beam
  // marks is left marked by the last one, then cleared if a later beam's walk clears it; a cell
  // none marks is cleared if it was a reported obstacle and some walk clears it. The map is read
  // only where a cell changes.
  // The cells' words and map values, read ahead: in a crowd each is likely a cache miss, and the
  // loop below would wait for them one by one.
  for (const CellFates::Fate& fate : fates.entries()) {
    const int row = row_of(fate.place), col = col_of(fate.place);
    bits.prefetch(row, col);
    __builtin_prefetch(map.view().data() + index(g, row, col));
  }
  enum State { kOther, kSeen, kCleared };
  int changed = 0;
  for (const CellFates::Fate& fate : fates.entries()) {
    const int row = row_of(fate.place), col = col_of(fate.place);
    const std::size_t cell = index(g, row, col);
    const bool seen = bits.seen(row, col);
    if (!seen && bits.obstacle(row, col)) continue;
    const State was = seen ? kSeen : kOther;
    const State now = fate.last_mark ? (fate.last_clear > fate.last_mark ? kCleared : kSeen)
                                     : (was == kSeen && fate.last_clear ? kCleared : was);
    const std::int16_t value = now == kCleared ? kFreeCell : kSeenCell;
    if (now == was || (was == kOther && now == kCleared && map[cell] == kFreeCell)) continue;  // marked, then cleared
    map.set(cell, value);
    bits.set(row, col, value);
    ++changed;
  }
  return changed;
}

SegmentInCells segment_in_cells(const geometry::MapGeometry& g, double x0, double y0, double x1, double y1, double radius) {
  const geometry::OccupancyGrid f = g.frame();
  SegmentInCells s{};
  f.world_to_grid(x0, y0, s.u0, s.v0);
  f.world_to_grid(x1, y1, s.u1, s.v1);
  s.radius = radius / g.resolution;
  return s;
}

bool segment_clear(const Blob& map, const geometry::MapGeometry& g, double x0, double y0, double x1, double y1, double radius,
                   bool unknown_blocked) {
  check(map, g);
  const auto [u0, v0, u1, v1, rc] = segment_in_cells(g, x0, y0, x1, y1, radius);
  // Touching is allowed: `radius` already holds the margin the robot keeps (ARobotConfig::margin).
  const bool clear = geometry::segment_clear_of_blocked(u0, v0, u1, v1, rc, geometry::Touch::Allowed, g.height, g.width,
                                                        [&](int r, int c) {
                                                          const std::int16_t v = cell(map, g, r, c);
                                                          return is_obstacle(v) || (unknown_blocked && v == kUnknownCell);
                                                        });
  // Leaving the map is not allowed either.
  return clear && u0 >= rc && v0 >= rc && u1 >= rc && v1 >= rc && u0 <= g.width - rc && u1 <= g.width - rc &&
         v0 <= g.height - rc && v1 <= g.height - rc;
}

double move_radius(const Blob& map, const geometry::MapGeometry& g, double x, double y, double radius) {
  return std::min(radius, std::max(0.0, clearance(map, g, x, y, radius) - 1e-3));
}

double clearance(const Blob& map, const geometry::MapGeometry& g, double x, double y, double cap) {
  check(map, g);
  double u, v;
  g.frame().world_to_grid(x, y, u, v);
  const double rc = cap / g.resolution;
  return geometry::clearance_to_blocked(u, v, rc, g.height, g.width, [&](int r, int c) { return is_obstacle(cell(map, g, r, c)); }) *
         g.resolution;
}

bool find_marker(const Blob& map, const geometry::MapGeometry& g, int tag, double& x, double& y) {
  check(map, g);
  const auto cells = map.view<std::int16_t>();
  const auto value = static_cast<std::int16_t>(kMarkerBase + tag);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (cells[i] == value) {
      g.centre_of(static_cast<int>(i / g.width), static_cast<int>(i % g.width), x, y);
      return true;
    }
  }
  return false;
}

}  // namespace vwg::robot
