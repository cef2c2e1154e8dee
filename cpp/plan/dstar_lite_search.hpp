// The definitions of DStarLiteSearch (dstar_lite.hpp), for dstar_lite.cpp to instantiate with
// RealKeys and ExactKeys, and for tests to instantiate with keys of their own.
// Private to vwg's libraries (beside their sources, under cpp/): not installed.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "vwg/error.hpp"
#include "vwg/plan/dstar_lite.hpp"

namespace vwg::plan {

template <class Keys>
DStarLiteSearch<Keys>::DStarLiteSearch(BlockedGrid grid, Cell start, Cell goal, const GridSearchOptions& options)
    : grid_(std::move(grid)), options_(options), start_(start), goal_(goal) {
  validate(options_);
  exact_keys_ = ExactKeys::whole(options_);
  check_cell(grid_, start, "start", true);
  check_cell(grid_, goal, "goal", false);
  const std::size_t n = grid_.padded().size();
  g_ = FilledArray<Cost>(n, Keys::kInf);
  rhs_ = FilledArray<Cost>(n, Keys::kInf);
  slot_ = FilledArray<std::uint32_t>(n, kNotQueued);
  start_node_ = last_node_ = grid_.index(start);
  goal_node_ = grid_.index(goal);
  rhs_.set(goal_node_, 0);
  queue_insert(goal_node_, calculate_key(goal_node_));
}

template <class Keys>
void DStarLiteSearch<Keys>::save(StateWriter& out) const {
  grid_.save(out);
  out.boolean(options_.diagonal);
  out.boolean(options_.corner_cutting);
  out.u8(static_cast<std::uint8_t>(options_.heuristic));
  for (const std::int32_t v : {start_.row, start_.col, goal_.row, goal_.col, start_node_, goal_node_, last_node_}) out.i64(v);
  out.f64(static_cast<double>(km_));  // a double holds every Cost exactly (a double, or 32 bits)
  g_.save(out);
  rhs_.save(out);
  slot_.save(out);
  out.u64(queue_.size());
  for (const Entry& e : queue_) {  // field by field: Entry has padding
    out.u64(static_cast<std::uint64_t>(e.order));
    if constexpr (sizeof(Order) > 8) out.u64(static_cast<std::uint64_t>(e.order >> 64));
    out.i64(e.node);
  }
  out.u64(expanded_);
  out.boolean(dive_);
  out.boolean(exact_keys_);
}

template <class Keys>
DStarLiteSearch<Keys> DStarLiteSearch<Keys>::load(StateReader& in) {
  DStarLiteSearch s;
  s.grid_ = BlockedGrid::load(in);
  s.options_.diagonal = in.boolean();
  s.options_.corner_cutting = in.boolean();
  const std::uint8_t heuristic = in.u8();
  if (heuristic > static_cast<std::uint8_t>(Heuristic::Zero)) in.fail("a heuristic of unknown kind");
  s.options_.heuristic = static_cast<Heuristic>(heuristic);
  const std::size_t n = s.grid_.padded().size();
  auto node = [&] {
    const std::int64_t v = in.i64();
    if (v < 0 || static_cast<std::uint64_t>(v) >= n) in.fail("a search node outside the grid");
    return static_cast<std::int32_t>(v);
  };
  auto cell = [&] {
    const std::int64_t row = in.i64(), col = in.i64();
    const Cell c{static_cast<int>(row), static_cast<int>(col)};
    if (row != c.row || col != c.col || !s.grid_.inside(c)) in.fail("a cell outside the grid");
    return c;
  };
  s.start_ = cell();
  s.goal_ = cell();
  s.start_node_ = node();
  s.goal_node_ = node();
  s.last_node_ = node();
  const double km = in.f64();
  // A key offset the search could have reached (ExactKeys keeps km below kKmLimit).
  if (!(km >= 0.0) || !std::isfinite(km) || (std::is_integral_v<Cost> && (km >= static_cast<double>(Keys::kKmLimit) ||
                                                                          km != std::floor(km)))) {
    in.fail("a key offset km out of range");
  }
  s.km_ = static_cast<Cost>(km);
  s.g_ = FilledArray<Cost>::load(in, n);
  s.rhs_ = FilledArray<Cost>::load(in, n);
  s.slot_ = FilledArray<std::uint32_t>::load(in, n);
  s.queue_.resize(in.count(sizeof(Order) + 8, "queue entries"));
  for (Entry& e : s.queue_) {
    const std::uint64_t low = in.u64();
    if constexpr (sizeof(Order) > 8) {
      e.order = (static_cast<Order>(in.u64()) << 64) | low;
    } else {
      e.order = static_cast<Order>(low);
    }
    e.node = node();
  }
  // Every queued node knows its place, and no other node claims one (the heap's operations index by both).
  for (std::size_t k = 0; k < s.queue_.size(); ++k) {
    if (s.slot_[static_cast<std::size_t>(s.queue_[k].node)] != k) in.fail("a queue whose positions disagree");
  }
  std::size_t queued = 0;
  for (std::size_t i = 0; i < n; ++i) queued += s.slot_[i] != kNotQueued;
  if (queued != s.queue_.size()) in.fail("a queue whose positions disagree");
  s.expanded_ = in.u64();
  s.dive_ = in.boolean();
  s.exact_keys_ = in.boolean();
  return s;
}

template <class Keys>
typename DStarLiteSearch<Keys>::Cost DStarLiteSearch<Keys>::heuristic_from_start(std::int32_t node) const {
  const std::int32_t s = grid_.stride();
  return Keys::heuristic(options_.heuristic, node / s - start_node_ / s, node % s - start_node_ % s);
}

template <class Keys>
typename DStarLiteSearch<Keys>::Key DStarLiteSearch<Keys>::calculate_key(std::int32_t node) const {
  const Cost m = std::min(g_[node], rhs_[node]);
  // h and km are finite: only m may be infinite (an unreached start).
  return {m == Keys::kInf ? Keys::kInf : m + heuristic_from_start(node) + km_, m};
}

template <class Keys>
typename DStarLiteSearch<Keys>::Cost DStarLiteSearch<Keys>::best_rhs(std::int32_t node) const {
  if (grid_.padded()[node]) return Keys::kInf;
  std::array<Step, 8> steps;
  const int count = moves_from(grid_, node, options_, steps);
  Cost best = Keys::kInf;
  for (int k = 0; k < count; ++k) best = std::min(best, Keys::add(Keys::cost_of(steps[k]), g_[steps[k].to]));
  return best;
}

template <class Keys>
void DStarLiteSearch<Keys>::catch_up_km() {
  if (start_node_ == last_node_) return;
  // The robot moved since the keys in the queue were computed. Adding h(s_last, s_start) to km
  // keeps every queued key a lower bound of its current value (paper, §"km"), so the queue need
  // not be reordered.
  const std::int32_t s = grid_.stride();
  const Cost moved = Keys::heuristic(options_.heuristic, last_node_ / s - start_node_ / s, last_node_ % s - start_node_ % s);
  last_node_ = start_node_;
  if (km_ < Keys::kKmLimit - moved) {
    km_ += moved;
    return;
  }
  // km would pass what the keys' type holds: compute every queued key anew from the robot's cell
  // with km = 0. Exact keys are at least as good a bound as the paper's, so the search goes on
  // as if km had grown.
  km_ = 0;
  for (Entry& e : queue_) e.order = order_of(calculate_key(e.node));
  reorder_queue();
}

template <class Keys>
void DStarLiteSearch<Keys>::update_vertex(std::int32_t node) {
  const bool queued = slot_[node] != kNotQueued;
  if (g_[node] != rhs_[node]) {
    if (queued) queue_update(node, calculate_key(node));
    else queue_insert(node, calculate_key(node));
  } else if (queued) {
    queue_remove(node);
  }
}

template <class Keys>
void DStarLiteSearch<Keys>::compute_shortest_path() {
  std::array<Step, 8> steps;
  while (!queue_.empty()) {
    const Key top = key_of(queue_.front());
    // The paper stops once TopKey >= key(s_start) and s_start is consistent. With exact keys that
    // holds as written. In floating point, a vertex whose key ties with the start's in k1 (and so
    // comes first by k2) can compute a k1 one ulp above it and be left inconsistent on the
    // shortest path. So there, keep going through every k1 within rounding of the start's: a few
    // extra expansions, never a wrong path. An unreachable start (k1 = ∞) empties the queue, as
    // in the paper.
    const Key start_key = calculate_key(start_node_);
    if (rhs_[start_node_] == g_[start_node_]) {
      if (exact_keys_ && !before(top, start_key)) break;
      if (!exact_keys_) {
        const double slack = 1e-9 * std::max(1.0, std::abs(static_cast<double>(start_key.k1)));
        if (static_cast<double>(top.k1) > static_cast<double>(start_key.k1) + slack) break;
      }
    }
    const std::int32_t u = queue_.front().node;
    const Key fresh = calculate_key(u);
    ++expanded_;
    if (before(top, fresh)) {
      // The key was computed before the robot moved (km grew): requeue with the current one.
      queue_update(u, fresh);
      continue;
    }
    // Moves are symmetric, so the moves out of u are the predecessors of u. A blocked u has none.
    const int count = grid_.padded()[u] ? 0 : moves_from(grid_, u, options_, steps);
    if (g_[u] > rhs_[u]) {
      const Cost g_u = rhs_[u];
      g_.set(u, g_u);
      queue_remove(u);
      for (int k = 0; k < count; ++k) {
        const std::int32_t s = steps[k].to;
        // Only a lowered rhs changes s (an unchanged one leaves its key, or its consistency, as is).
        const Cost through = Keys::add(Keys::cost_of(steps[k]), g_u);
        if (s == goal_node_ || !(through < rhs_[s])) continue;
        rhs_.set(s, through);
        update_vertex(s);
      }
    } else {
      const Cost g_old = g_[u];
      g_.set(u, Keys::kInf);
      for (int k = 0; k < count; ++k) {
        const std::int32_t s = steps[k].to;
        // Only the vertices whose best move went through u need a new rhs (same arithmetic as
        // best_rhs, so the comparison is exact).
        if (s != goal_node_ && rhs_[s] == Keys::add(Keys::cost_of(steps[k]), g_old)) rhs_.set(s, best_rhs(s));
        update_vertex(s);
      }
      if (u != goal_node_) rhs_.set(u, best_rhs(u));
      update_vertex(u);
    }
  }
}

template <class Keys>
GridPath DStarLiteSearch<Keys>::path() {
  GridPath result;
  catch_up_km();
  if (grid_.blocked(start_)) return result;
  compute_shortest_path();
  if (g_[start_node_] == Keys::kInf) return result;

  // Follow the g-values down to the goal: each step to a neighbour minimising c(s, s') + g(s').
  std::array<Step, 8> steps;
  std::int32_t cur = start_node_;
  double length = 0.0;
  result.cells.push_back(start_);
  const std::size_t max_steps = g_.size();
  while (cur != goal_node_) {
    const int count = moves_from(grid_, cur, options_, steps);
    std::int32_t next = -1;
    Cost best = Keys::kInf;
    double cost = 0.0;
    for (int k = 0; k < count; ++k) {
      const Cost through = Keys::add(Keys::cost_of(steps[k]), g_[steps[k].to]);
      if (through < best) {
        best = through;
        next = steps[k].to;
        cost = steps[k].cost;
      }
    }
    if (next < 0 || result.cells.size() > max_steps) {
      throw Error("D* Lite: no consistent path from " + to_string(start_) + " although g(start) is finite");
    }
    length += cost;
    cur = next;
    result.cells.push_back(grid_.cell(cur));
  }
  result.length = length;
  return result;
}

template <class Keys>
void DStarLiteSearch<Keys>::move_to(Cell cell) {
  check_cell(grid_, cell, "cell", true);
  start_ = cell;
  start_node_ = grid_.index(cell);
}

template <class Keys>
void DStarLiteSearch<Keys>::update_cells(std::span<const Cell> cells, bool blocked) {
  for (const Cell& c : cells) {
    if (!grid_.inside(c)) {
      throw SchemaError("cells", "cell " + to_string(c) + " is outside the grid of " + std::to_string(grid_.rows()) +
                                     " rows × " + std::to_string(grid_.cols()) + " columns");
    }
  }
  catch_up_km();
  std::vector<Cell> changed;
  for (const Cell& c : cells) {
    if (grid_.blocked(c) == blocked) continue;
    grid_.set_blocked(c, blocked);
    changed.push_back(c);
  }
  if (blocked && !changed.empty() && dive_) stop_diving();  // costs rise: g < rhs becomes possible
  // A cell's state changes the cost of the moves into and out of it and, without corner cutting,
  // of the diagonal moves that pass by it: all between cells of its 3 × 3 block.
  for (const Cell& c : changed) {
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        const Cell u{c.row + dr, c.col + dc};
        if (!grid_.inside(u)) continue;
        const std::int32_t node = grid_.index(u);
        if (node != goal_node_) rhs_.set(node, best_rhs(node));
        update_vertex(node);
      }
    }
  }
}

// --- the priority queue ---

template <class Keys>
void DStarLiteSearch<Keys>::stop_diving() {
  for (Entry& e : queue_) {
    const Key key = key_of(e);
    e.order = dstar_order::encode(key.k1, key.k2, false);
  }
  dive_ = false;
  reorder_queue();
}

template <class Keys>
void DStarLiteSearch<Keys>::reorder_queue() {
  // Floyd's heap construction (place() keeps the positions up to date).
  for (std::size_t slot = queue_.size() / 2; slot-- > 0;) sift_down(slot);
}

template <class Keys>
void DStarLiteSearch<Keys>::place(std::size_t slot, const Entry& e) {
  queue_[slot] = e;
  slot_.set(e.node, static_cast<std::uint32_t>(slot));
}

template <class Keys>
void DStarLiteSearch<Keys>::sift_up(std::size_t slot) {
  const Entry e = queue_[slot];
  while (slot > 0) {
    const std::size_t parent = (slot - 1) / 2;
    if (!(e.order < queue_[parent].order)) break;
    place(slot, queue_[parent]);
    slot = parent;
  }
  place(slot, e);
}

template <class Keys>
void DStarLiteSearch<Keys>::sift_down(std::size_t slot) {
  const Entry e = queue_[slot];
  const std::size_t n = queue_.size();
  for (;;) {
    std::size_t child = 2 * slot + 1;
    if (child >= n) break;
    if (child + 1 < n) child += queue_[child + 1].order < queue_[child].order;
    if (!(queue_[child].order < e.order)) break;
    place(slot, queue_[child]);
    slot = child;
  }
  place(slot, e);
}

template <class Keys>
void DStarLiteSearch<Keys>::queue_insert(std::int32_t node, Key key) {
  queue_.push_back({order_of(key), node});
  sift_up(queue_.size() - 1);
}

template <class Keys>
void DStarLiteSearch<Keys>::queue_update(std::int32_t node, Key key) {
  const std::size_t slot = slot_[node];
  const Order old = queue_[slot].order;
  queue_[slot].order = order_of(key);
  if (queue_[slot].order < old) sift_up(slot);
  else sift_down(slot);
}

template <class Keys>
void DStarLiteSearch<Keys>::queue_remove(std::int32_t node) {
  const std::size_t slot = slot_[node];
  slot_.set(node, kNotQueued);
  const Entry last = queue_.back();
  queue_.pop_back();
  if (slot == queue_.size()) return;
  place(slot, last);
  // The moved entry may belong above or below its new slot.
  sift_up(slot);
  sift_down(slot_[last.node]);
}

}  // namespace vwg::plan
