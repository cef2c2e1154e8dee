#include "vwg/robot/planning_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <tuple>

#include "geometry/inflate.hpp"

namespace vwg::robot {

namespace {

bool planning_obstacle(std::int16_t v) { return is_obstacle(v) || v == kUnknownCell; }

}  // namespace

void PlanningMap::rebuild(std::span<const std::int16_t> cells, const geometry::MapGeometry& g, double radius) {
  std::vector<std::uint8_t> mask(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) mask[i] = planning_obstacle(cells[i]);
  rebuild_mask(std::move(mask), g, radius);
}

void PlanningMap::save(StateWriter& out) const {
  const bool pending = loaded_.has_value();  // loaded and not yet brought up to a map
  out.f64(pending ? loaded_radius_ : radius_);
  (pending ? *loaded_ : obstacles_).save(out);
}

void PlanningMap::load(StateReader& in) {
  const double radius = in.f64();
  geometry::BlockedGrid obstacles = geometry::BlockedGrid::load(in);
  if (radius != -1.0 && (!(radius >= 0.0) || !std::isfinite(radius))) in.fail("a planning radius that is not a finite number >= 0");
  const unsigned looks = looks_;  // the robot's count (reshare_phase) stays
  *this = PlanningMap();
  looks_ = looks;
  if (radius < 0.0) return;  // saved before its first update
  loaded_ = std::move(obstacles);
  loaded_radius_ = radius;
}

void PlanningMap::rebuild_mask(std::vector<std::uint8_t> mask, const geometry::MapGeometry& g, double radius) {
  const int rows = g.height, cols = g.width;
  const double rc = radius / g.resolution;
  obstacles_ = geometry::BlockedGrid::from_mask(std::span<const std::uint8_t>(mask), rows, cols);
  radius_ = radius;
  // The disc of geometry::inflate; per row offset it is one run of columns [-w, w].
  disc_ = geometry::inflation_disc(rc);
  counted_ = rc >= 0 && disc_.size() + 1 < std::numeric_limits<std::uint16_t>::max();
  if (!counted_) {
    inflated_ = geometry::inflate(obstacles_, rc);
    return;
  }
  int reach = 0;
  for (const geometry::Cell& d : disc_) reach = std::max(reach, std::abs(d.row));
  std::vector<int> half(static_cast<std::size_t>(2 * reach + 1), -1);
  for (const geometry::Cell& d : disc_) {
    half[static_cast<std::size_t>(d.row + reach)] = std::max(half[static_cast<std::size_t>(d.row + reach)], std::abs(d.col));
  }
  // cover = the number of obstacle cells whose disc holds the cell (a sum over the disc, by row
  // prefix sums), plus one within rc of the map's edge (as geometry::inflate's outside_blocked).
  cover_at_ = TiledIndex<5, 6>(rows, cols);
  cover_.assign(cover_at_.size(), 0);
  std::vector<std::int32_t> prefix(static_cast<std::size_t>(rows) * (cols + 1), 0);
  for (int r = 0; r < rows; ++r) {
    std::int32_t* p = &prefix[static_cast<std::size_t>(r) * (cols + 1)];
    for (int c = 0; c < cols; ++c) p[c + 1] = p[c] + mask[static_cast<std::size_t>(r) * cols + c];
  }
  inflated_ = geometry::BlockedGrid(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      std::int32_t n = 0;
      for (int dr = -reach; dr <= reach; ++dr) {
        const int w = half[static_cast<std::size_t>(dr + reach)], rr = r + dr;
        if (w < 0 || rr < 0 || rr >= rows) continue;
        const std::int32_t* p = &prefix[static_cast<std::size_t>(rr) * (cols + 1)];
        n += p[std::min(cols, c + w + 1)] - p[std::max(0, c - w)];
      }
      if (geometry::centre_near_edge(r, c, rows, cols, rc)) ++n;
      cover_.set(cover_at_(r, c), static_cast<std::uint16_t>(n));
      if (n > 0) inflated_.set_blocked({r, c}, true);
    }
  }
}

void PlanningMap::set_obstacle(int row, int col, bool blocked) {
  obstacles_.set_blocked({row, col}, blocked);
  const int rows = obstacles_.rows(), cols = obstacles_.cols();
  for (const geometry::Cell& d : disc_) {
    const int r = row + d.row, c = col + d.col;
    if (r < 0 || c < 0 || r >= rows || c >= cols) continue;
    const std::size_t at = cover_at_(r, c);
    const auto n = static_cast<std::uint16_t>(blocked ? cover_[at] + 1 : cover_[at] - 1);
    cover_.set(at, n);
    if (n == (blocked ? 1 : 0)) inflated_.set_blocked({r, c}, blocked);
  }
}

bool PlanningMap::start_from_original(const Blob& map, const geometry::MapGeometry& g, double radius) {
  // One set of grids per shared content, cell size and radius, for every robot of every decider.
  static OriginCache<std::tuple<int, int, double, double>, PlanningMap> originals;
  const auto original = originals.get(map.origin(), std::tuple{g.height, g.width, g.resolution, radius}, [&] {
    PlanningMap m;
    m.rebuild(map.original_view<std::int16_t>(), g, radius);
    m.obstacles_.share();
    m.inflated_.share();
    m.cover_.share();
    return m;
  });
  if (original == nullptr) return false;
  PlanningMap copy = *original;  // all or nothing: a copy that fails leaves this map as it was
  copy.looks_ = looks_;          // this robot's count (reshare_phase), not the original's
  *this = std::move(copy);
  return true;
}

std::size_t PlanningMap::private_pages() const {
  return obstacles_.private_pages() + inflated_.private_pages() + cover_.private_pages();
}

bool PlanningMap::follow(std::size_t i, std::int16_t value, int cols) {
  const geometry::Cell cell{static_cast<int>(i / static_cast<std::size_t>(cols)), static_cast<int>(i % static_cast<std::size_t>(cols))};
  // The obstacle grid holds what the cell was, as far as planning goes.
  const bool is = planning_obstacle(value);
  if (obstacles_.blocked(cell) == is) return false;
  if (counted_) {
    set_obstacle(cell.row, cell.col, is);
  } else {
    obstacles_.set_blocked(cell, is);
  }
  return true;
}

bool PlanningMap::follow_all(std::span<const std::int16_t> cells, int cols) {
  // Row by row, 64 cells at a time against the obstacle grid's bytes (a loop the compiler makes
  // vector code of): a robot's map differs from its grids in a few cells, if any.
  bool changed = false;
  const std::uint8_t* grid = obstacles_.padded().data();
  for (int r = 0; r < obstacles_.rows(); ++r) {
    const std::size_t first = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols);
    const std::int16_t* row = cells.data() + first;
    const std::uint8_t* was = grid + obstacles_.index({r, 0});
    for (int c0 = 0; c0 < cols; c0 += 64) {
      const int end = std::min(cols, c0 + 64);
      bool differ = false;
      for (int c = c0; c < end; ++c) differ |= planning_obstacle(row[c]) != (was[c] != 0);
      if (!differ) continue;
      for (int c = c0; c < end; ++c) changed |= follow(first + static_cast<std::size_t>(c), row[c], cols);
    }
  }
  return changed;
}

bool PlanningMap::update(const Blob& map, const geometry::MapGeometry& g, double radius) {
  check_robot_map(map, g);
  const auto cells = map.view<std::int16_t>();
  if (loaded_) {  // a saved run's grids, made now that the geometry is known; then compared with the map
    std::optional<geometry::BlockedGrid> saved;
    saved.swap(loaded_);
    // For the radius in use and the map's size only: a state of another radius (or a damaged one) is the
    // first look, as for a robot never seen (its grids made from the map; update() reports a change).
    if (saved->rows() == g.height && saved->cols() == g.width && loaded_radius_ == radius) {
      std::vector<std::uint8_t> mask(static_cast<std::size_t>(g.height) * g.width);
      for (int r = 0; r < g.height; ++r) {
        for (int c = 0; c < g.width; ++c) mask[static_cast<std::size_t>(r) * g.width + c] = saved->blocked({r, c});
      }
      rebuild_mask(std::move(mask), g, radius);
      looked_ = Blob::Mark{};  // of no revision: the map is compared cell by cell
    }
  }
  const Blob::Mark then = looked_;
  bool changed = false;
  if (radius != radius_ || obstacles_.rows() != g.height || obstacles_.cols() != g.width) {
    if (!map.shared() || !start_from_original(map, g, radius)) {
      rebuild(cells, g, radius);
      looked_ = map.mark();
      return true;
    }
    // A first look: the cells this copy changed from the shared content.
    for_each_changed_cell(cells, map.original_view<std::int16_t>(), [&](std::size_t i) { follow(i, cells[i], g.width); });
    changed = true;
  } else if (then.revision == map.revision()) {
    return false;
  } else if (!map.written_since(then, [&](std::size_t i) { changed |= follow(i, cells[i], g.width); })) {
    changed = follow_all(cells, g.width);  // it cannot tell which
  }
  looked_ = map.mark();
  if (changed && !counted_) inflated_ = geometry::inflate(obstacles_, radius / g.resolution);
  // The pages of what has gone again go back to the shared grids, every kReshareEvery looks at a
  // new revision.
  if (++looks_ % kReshareEvery == 0) reshare();
  return changed;
}

void PlanningMap::reshare() {
  obstacles_.reshare();
  inflated_.reshare();
  cover_.reshare();
}

}  // namespace vwg::robot
