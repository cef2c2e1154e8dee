// The robot's own map: the `grid` attribute of ARobot (paper eq. 11), an int16 blob of the world
// map's geometry. It starts as the known map (or empty, eq. 13) and grows with what the sensors
// report (eq. 12): obstacles from eLaser, markers from eCamera.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <vector>

#include "vwg/blob_edit.hpp"
#include "vwg/geometry/map_geometry.hpp"
#include "vwg/detail/tiled_index.hpp"

namespace vwg::robot {

/// What a robot map cell holds.
enum RobotCell : std::int16_t {
  kUnknownCell = -1,
  kFreeCell = 0,
  kWallCell = 100,     ///< an obstacle of the prior map
  kSeenCell = 101,     ///< an obstacle the sensors reported (may be cleared again: moving things)
  kMarkerBase = 1000,  ///< 1000 + tag id: a marker the camera saw there
};

inline bool is_obstacle(std::int16_t v) { return v >= kWallCell; }

/// Calls each(i) for every cell i at which `now` differs from `before` (of the same size), in
/// order, comparing 64 cells at a time first: most of a robot's map is as it was.
template <class Each>
void for_each_changed_cell(std::span<const std::int16_t> now, std::span<const std::int16_t> before, Each&& each) {
  constexpr std::size_t kRun = 64;
  for (std::size_t first = 0; first < now.size(); first += kRun) {
    const std::size_t n = std::min(kRun, now.size() - first);
    if (std::memcmp(&now[first], &before[first], n * sizeof(std::int16_t)) == 0) continue;
    for (std::size_t i = first; i < first + n; ++i) {
      if (now[i] != before[i]) each(i);
    }
  }
}

/// Throws SchemaError("grid") unless `map` is an int16 array of the geometry's shape.
void check_robot_map(const Blob& map, const geometry::MapGeometry& g);

/// A robot map of the world's geometry: the known map (walls 100, free 0, unknown -1) when
/// `knows_map`, else all free (the empty grid of eq. 13). Shared (Blob::share): give every robot
/// this one blob, and each robot's copy keeps only the memory pages its sensors change.
std::shared_ptr<Blob> make_robot_map(const geometry::OccupancyGrid& world, bool knows_map, int threshold = geometry::kObstacleThreshold);

/// The cells of a robot map being written (in place and journaled during a frame: ActorState::edit_blob).
using MapEdit = BlobEdit<std::int16_t>;

/// How many edits of a robot's map (and looks at it by its planner) pass between two reshare()
/// calls of its shared arrays: the map, its ObstacleBits, its PlanningMap's grids. A page given
/// back is faulted in again, with a TLB shootdown on every core, when the robot next writes it;
/// resharing after every edit cost 20 % at 1,000 robots (7,500 against 8,800-9,600 robot-steps/s,
/// with the same memory after 23 frames).
inline constexpr int kReshareEvery = 16;

/// Where robot `robot`'s reshare counters start: robots of a crowd give their pages back in different
/// frames. Counted from 0, they all did in the same frame, every kReshareEvery-th: with ten thousand robots
/// that frame took 1.5-1.7 s where the frames beside it took 1.1-1.3 s.
inline unsigned reshare_phase(std::int64_t robot) {
  return static_cast<unsigned>((robot % kReshareEvery + kReshareEvery) % kReshareEvery);
}

/// A robot map's obstacles as bits, 8 × 8 cells to a 64-bit word: one plane for the reported
/// obstacles (kSeenCell), one for every obstacle (is_obstacle). Each robot has a map of its own,
/// far larger than the caches for a crowd, so reading its cells was most of the cost of a laser
/// robot's frame; a scan (sense_scan) finds the reported obstacles in its reach block by block (a
/// bit a block: a few hundred bytes, which stay in cache) and reads the planes, not the map. A
/// cache of one map, valid for the map's revision it was made or kept up to date for; made again
/// from the map otherwise.
class ObstacleBits {
 public:
  static constexpr int kShift = 3;  // 8 × 8 cells a block
  ObstacleBits() = default;
  /// For robot `robot`: its edits counted from reshare_phase(robot).
  explicit ObstacleBits(std::int64_t robot) : edits_(reshare_phase(robot)) {}
  /// Make it valid for `map` unless it already is: from the bits of its original content when it
  /// is a copy of a shared map (made once for all robots, shared page by page) and the cells it
  /// changed, else by scanning the map.
  void sync(const Blob& map, const geometry::MapGeometry& g);
  /// After the edits that went through it: valid for the map as it is now.
  void keep(const Blob& map) { revision_ = map.revision(); }
  /// See SharedPages::reshare.
  std::size_t reshare() { return words_.reshare(); }
  /// Count an edit of the robot's map: true every kReshareEvery-th, when the map and these bits
  /// are to give back the pages equal to the shared ones again.
  bool reshare_due_after_edit() { return ++edits_ % kReshareEvery == 0; }
  /// Whether block (block_row, block_col), inside the map, holds a reported obstacle.
  bool block_flag(int block_row, int block_col) const {
    const std::size_t w = word(block_row, block_col);
    return (blocks_[w >> 6] >> (w & 63)) & 1;
  }
  /// The reported obstacles of block (block_row, block_col), inside the map: bit (row % 8) · 8 +
  /// (col % 8) for cell (row, col).
  std::uint64_t seen_cells(int block_row, int block_col) const { return words_[word(block_row, block_col)].seen; }
  /// Cell (row, col), inside the map: a reported obstacle / any obstacle.
  bool seen(int row, int col) const { return (words_[word(row >> kShift, col >> kShift)].seen >> bit(row, col)) & 1; }
  bool obstacle(int row, int col) const { return (words_[word(row >> kShift, col >> kShift)].obstacle >> bit(row, col)) & 1; }
  /// Start reading the words of cell (row, col)'s block, inside the map, into the cache: a crowd's
  /// bits are far larger than the caches, and a scan reads a few hundred scattered blocks.
  void prefetch(int row, int col) const { __builtin_prefetch(&words_[word(row >> kShift, col >> kShift)]); }
  /// Cell (row, col), inside the map, now holds `value`.
  void set(int row, int col, std::int16_t value) {
    const std::size_t w = word(row >> kShift, col >> kShift);
    const std::uint64_t b = std::uint64_t{1} << bit(row, col);
    Words words = words_[w];
    words.seen = value == kSeenCell ? words.seen | b : words.seen & ~b;
    words.obstacle = is_obstacle(value) ? words.obstacle | b : words.obstacle & ~b;
    words_.set(w, words);
    const std::uint64_t flag = std::uint64_t{1} << (w & 63);
    blocks_[w >> 6] = words.seen != 0 ? blocks_[w >> 6] | flag : blocks_[w >> 6] & ~flag;
  }

 private:
  static int bit(int row, int col) { return ((row & 7) << 3) | (col & 7); }
  std::size_t word(int block_row, int block_col) const { return word_at_(block_row, block_col); }
  void scan(std::span<const std::int16_t> cells, const geometry::MapGeometry& g);

  std::uint64_t revision_ = 0;
  unsigned edits_ = 0;  // of the map, counted for reshare_due_after_edit
  int columns_ = 0, rows_ = 0;  // of blocks
  // The words in tiles of 16 × 16 blocks (128 × 128 cells, a 4 KB page): a sighting writes one
  // page of a robot's bits, seldom two, where rows of a map 1,600 cells wide put 10 rows of cells
  // on a page.
  TiledIndex<4, 4> word_at_;
  struct Words {  // a block's cells, a bit each; side by side, so one read of memory finds both
    std::uint64_t seen = 0, obstacle = 0;
  };
  SharedArray<Words> words_;           // a block's (shared with the bits of the original map)
  std::vector<std::uint64_t> blocks_;  // a bit a block: whether its seen word is not 0
};

/// Mark a reported obstacle at (x, y); returns true if the cell changed. Markers and walls stay.
/// `bits`, if given, is read instead of the map and kept valid (see ObstacleBits).
bool mark_obstacle(MapEdit& map, const geometry::MapGeometry& g, double x, double y, ObstacleBits* bits = nullptr);
/// Mark marker `tag` at (x, y); returns true if the cell changed.
bool mark_marker(MapEdit& map, const geometry::MapGeometry& g, double x, double y, int tag, ObstacleBits* bits = nullptr);
/// Clear reported obstacles (kSeenCell) on the cells the segment from (x0, y0) to (x1, y1)
/// crosses, the end cell excluded (a laser beam passed through them, so they are free now).
/// Returns how many cells changed. (A robot's laser goes through sense_scan, which gives the same
/// map without walking the cells; this walk is its reference.)
int carve_free(MapEdit& map, const geometry::MapGeometry& g, double x0, double y0, double x1, double y1);
/// A beam of a laser scan, in world coordinates: where it stopped, and the point half a cell
/// beyond, whose cell is marked.
struct ScanBeam {
  double end_x, end_y, mark_x, mark_y;
};
/// A laser scan from (x0, y0) on a robot map: for each beam in order, carve_free from the start to
/// its end (when `carve`), then mark_obstacle at its mark point. The map afterwards is the same as
/// after those calls one after another, but it is worked out from the cells that can change — the
/// reported obstacles within the scan's reach and the cells it marks — each tested against the
/// beams whose direction can cross it, instead of walking every beam's cells. `bits` must be valid
/// for the map (ObstacleBits::sync) and is kept valid. Returns how many cells changed.
int sense_scan(MapEdit& map, const geometry::MapGeometry& g, ObstacleBits& bits, double x0, double y0,
                std::span<const ScanBeam> beams, bool carve = true);
/// Whether a disc of `radius` moved along the segment stays off every obstacle of the map
/// (unknown cells count as obstacles when `unknown_blocked`).
bool segment_clear(const Blob& map, const geometry::MapGeometry& g, double x0, double y0, double x1, double y1, double radius,
                   bool unknown_blocked = false);
/// Distance from (x, y) to the nearest obstacle square of the map, or `cap` if none is nearer.
double clearance(const Blob& map, const geometry::MapGeometry& g, double x, double y, double cap);
/// The radius a move from (x, y) is tested with: `radius`, or what the robot has now when it is already nearer
/// an obstacle (a wall it had not seen): it may move as long as it gets no nearer.
double move_radius(const Blob& map, const geometry::MapGeometry& g, double x, double y, double radius);
/// Where marker `tag` was seen (the centre of its cell); false if it never was.
bool find_marker(const Blob& map, const geometry::MapGeometry& g, int tag, double& x, double& y);

}  // namespace vwg::robot
