// D* Lite (Koenig & Likhachev, "D* Lite", AAAI 2002, optimized version of Fig. 4): shortest paths
// on the grid graph of A* that are repaired, not recomputed, when cells become blocked or free
// and when the robot moves. It searches backwards, from the goal, so the g-values it keeps stay
// valid as the start (the robot) moves. Two departures from the paper's pseudocode: a changed
// cell has its rhs and its 8 neighbours' recomputed from their moves (a cell changes the cost of
// every move into, out of and, without corner cutting, diagonally past it), rather than edge by
// edge; and where keys carry rounding (diagonal moves, a Euclidean or octile heuristic), the
// search stops only once the queue's keys exceed the start's by more than rounding error, which
// floating-point ties otherwise break the wrong way (see compute_shortest_path).
//
// Ties in k1 go toward the start until a cell is first blocked (see dive_). On a 4-connected grid
// with the Manhattan heuristic every cell of an open start-goal rectangle has the same k1; the
// paper's tie-break (smaller k2, nearer the goal, first) sweeps that whole plateau before it
// reaches the start, while the other way reaches the start along one path, as A* does.
//
// Costs and keys come in two kinds (DStarLiteSearch's Keys): whole numbers in 32 bits where every
// move costs 1 and the heuristic is Manhattan or none (ExactKeys: 12 bytes a cell and 16-byte
// queue entries), doubles otherwise (RealKeys: 20 and 32). DStarLite picks one from the options.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <variant>
#include <vector>

#include "vwg/detail/filled_array.hpp"
#include "vwg/plan/grid_graph.hpp"

namespace vwg::plan {

/// D* Lite's keys [k1; k2] as single numbers for its queue (here for the tests).
namespace dstar_order {
__extension__ typedef unsigned __int128 Order;  // __extension__: GCC's and Clang's, not ISO C++'s

/// A key (k1, k2 >= 0, not NaN) as a number that orders as D* Lite's keys come out: smaller k1
/// first; on equal k1, larger k2 first when `dive`, else smaller. k1's bits above k2's (the bits
/// of non-negative doubles order like the doubles), k2's inverted when diving.
inline Order encode(double k1, double k2, bool dive) {
  const auto low = std::bit_cast<std::uint64_t>(k2);
  return (static_cast<Order>(std::bit_cast<std::uint64_t>(k1)) << 64) | (dive ? ~low : low);
}
/// The key that encode(k1, k2, dive) made.
inline void decode(Order order, bool dive, double& k1, double& k2) {
  const auto low = static_cast<std::uint64_t>(order);
  k1 = std::bit_cast<double>(static_cast<std::uint64_t>(order >> 64));
  k2 = std::bit_cast<double>(dive ? ~low : low);
}
/// The same for whole-number keys in 32 bits, in 64.
inline std::uint64_t encode(std::uint32_t k1, std::uint32_t k2, bool dive) {
  return (static_cast<std::uint64_t>(k1) << 32) | (dive ? ~k2 : k2);
}
inline void decode(std::uint64_t order, bool dive, std::uint32_t& k1, std::uint32_t& k2) {
  const auto low = static_cast<std::uint32_t>(order);
  k1 = static_cast<std::uint32_t>(order >> 32);
  k2 = dive ? ~low : low;
}
}  // namespace dstar_order

/// Costs and keys as doubles: any moves, any admissible heuristic.
struct RealKeys {
  using Cost = double;
  using Order = dstar_order::Order;
  static constexpr Cost kInf = std::numeric_limits<double>::infinity();
  static constexpr Cost kKmLimit = kInf;  // km never needs bringing back to 0
  static Cost add(Cost a, Cost b) { return a + b; }
  static Cost cost_of(const Step& step) { return step.cost; }
  static Cost heuristic(Heuristic h, int drow, int dcol) { return heuristic_distance(h, drow, dcol); }
};

/// Whole-number costs and keys in 32 bits, for 4-connected moves (each costs 1) with the Manhattan
/// heuristic or none, on grids of fewer than 2^30 cells. Then g <= the cells, h <= rows + columns,
/// and km stays below kKmLimit (past it the queue's keys are computed anew with km = 0), so k1 stays
/// below 3 * 2^30 and never reaches kInf.
struct ExactKeys {
  using Cost = std::uint32_t;
  using Order = std::uint64_t;
  static constexpr Cost kInf = 0xFFFFFFFFu;
  static constexpr Cost kKmLimit = Cost{1} << 30;
  static constexpr std::size_t kMaxCells = std::size_t{1} << 30;
  static Cost add(Cost a, Cost b) { return a == kInf || b == kInf ? kInf : a + b; }
  static Cost cost_of(const Step&) { return 1; }
  static Cost heuristic(Heuristic h, int drow, int dcol) {
    return h == Heuristic::Manhattan ? static_cast<Cost>((drow < 0 ? -drow : drow) + (dcol < 0 ? -dcol : dcol)) : 0;
  }
  /// Whether with these options every key is a whole number (moves of cost 1, Manhattan or no heuristic).
  static bool whole(const GridSearchOptions& options) {
    return !options.diagonal && (options.heuristic == Heuristic::Manhattan || options.heuristic == Heuristic::Zero);
  }
  /// Whether these options and this grid allow exact keys.
  static bool fits(const GridSearchOptions& options, std::size_t padded_cells) {
    return whole(options) && padded_cells < kMaxCells;
  }
};

/// The search itself, for one kind of keys (see DStarLite for the interface).
template <class Keys>
class DStarLiteSearch {
 public:
  using Cost = typename Keys::Cost;
  using Order = typename Keys::Order;

  DStarLiteSearch(BlockedGrid grid, Cell start, Cell goal, const GridSearchOptions& options);
  GridPath path();
  void move_to(Cell cell);
  void update_cells(std::span<const Cell> cells, bool blocked);
  Cell start() const { return start_; }
  Cell goal() const { return goal_; }
  const BlockedGrid& grid() const { return grid_; }
  const GridSearchOptions& options() const { return options_; }
  std::size_t expanded() const { return expanded_; }
  /// km of the paper: the sum of h between the robot's successive starts since the keys were last
  /// computed from scratch (here for the tests).
  Cost km() const { return km_; }
  /// Everything it keeps, for a saved run (vwg/state.hpp).
  void save(StateWriter& out) const;
  /// A search as save() wrote it; SchemaError (StateReader::fail) for one that cannot be (a node
  /// outside the grid, a queue whose positions disagree).
  static DStarLiteSearch load(StateReader& in);

 private:
  DStarLiteSearch() = default;  // for load()
  /// A priority [k1; k2], compared lexicographically by before().
  struct Key {
    Cost k1;
    Cost k2;
  };
  /// Whether a comes out of the queue before b: smaller k1 first; on equal k1, larger k2 while
  /// diving (nearer the start), else smaller k2 (the paper's order). By the queue's own numbers,
  /// so the stop rule and the heap cannot disagree.
  bool before(const Key& a, const Key& b) const { return order_of(a) < order_of(b); }
  /// Puts the queue in order again after every entry's order was rewritten.
  void reorder_queue();
  /// Leaves the dive for the paper's order and rebuilds the heap in it.
  void stop_diving();
  /// A queue entry: its key as one number (dstar_order), so the heap compares with one comparison
  /// instead of two branches, which on plateaus of equal k1 went either way at random.
  struct Entry {
    Order order;
    std::int32_t node;
  };
  Order order_of(const Key& key) const { return dstar_order::encode(key.k1, key.k2, dive_); }
  Key key_of(const Entry& e) const {
    Key key;
    dstar_order::decode(e.order, dive_, key.k1, key.k2);
    return key;
  }
  static constexpr std::uint32_t kNotQueued = 0xFFFFFFFFu;

  Cost heuristic_from_start(std::int32_t node) const;
  Key calculate_key(std::int32_t node) const;
  /// rhs(u) = min over moves u → s of c(u, s) + g(s); infinite for a blocked u (it has no moves).
  Cost best_rhs(std::int32_t node) const;
  void update_vertex(std::int32_t node);
  void catch_up_km();
  void compute_shortest_path();

  // The priority queue U: a binary heap with positions, for the paper's Update and Remove.
  void queue_insert(std::int32_t node, Key key);
  void queue_update(std::int32_t node, Key key);
  void queue_remove(std::int32_t node);
  void sift_up(std::size_t slot);
  void sift_down(std::size_t slot);
  void place(std::size_t slot, const Entry& e);

  BlockedGrid grid_;
  GridSearchOptions options_;
  Cell start_, goal_;
  std::int32_t start_node_ = 0, goal_node_ = 0;
  std::int32_t last_node_ = 0;  ///< s_last of the paper: the start when km was last brought up to date
  Cost km_ = 0;
  FilledArray<Cost> g_, rhs_;        ///< Keys::kInf where never set
  FilledArray<std::uint32_t> slot_;  ///< position in queue_, or kNotQueued
  std::vector<Entry> queue_;
  std::size_t expanded_ = 0;
  /// Ties in k1 toward the start. Safe while no vertex can be underconsistent (g < rhs), that is
  /// until a cell is first blocked: every queued vertex is then overconsistent, and one that comes
  /// out at its k1 with a key below the start's has its final g whatever the tie order (the
  /// argument for A* with a consistent heuristic). An underconsistent vertex tied with the start
  /// in k1 but nearer the goal would, in this order, be left behind with a stale g: so the first
  /// blocked cell ends the dive for good (stop_diving).
  bool dive_ = true;
  /// Every key is an exact integer (4-connected moves of cost 1, Manhattan or no heuristic): the
  /// paper's stop rule holds as written, with no allowance for rounding.
  bool exact_keys_ = false;
};

extern template class DStarLiteSearch<RealKeys>;
extern template class DStarLiteSearch<ExactKeys>;

/// Incremental replanning for a robot walking to a fixed goal. path() always returns a shortest
/// path (same length as A* on the current grid from the current start, with the same options).
///
///     DStarLite planner(grid, start, goal);
///     GridPath p = planner.path();
///     planner.move_to(p.cells[1]);                  // the robot took a step
///     planner.update_cells(new_obstacles, true);    // it saw something
///     p = planner.path();                           // repaired, usually far cheaper than A*
class DStarLite {
 public:
  /// Throws SchemaError("start"/"goal") for a cell outside the grid or a blocked start, and
  /// SchemaError("heuristic") for options that would not give shortest paths. A blocked goal has no path.
  DStarLite(BlockedGrid grid, Cell start, Cell goal, const GridSearchOptions& options = {});

  /// The shortest path from the current start to the goal, repairing the search as needed; no path
  /// (empty, infinite length) when there is none, also when the start cell has become blocked.
  GridPath path() {
    return std::visit([](auto& s) { return s.path(); }, search_);
  }

  /// The robot is now at `cell` (any free cell, not necessarily a neighbour of the last one).
  /// Throws SchemaError("cell") outside the grid or on a blocked cell.
  void move_to(Cell cell) {
    std::visit([&](auto& s) { s.move_to(cell); }, search_);
  }

  /// Cells became blocked (or free). Throws SchemaError("cells") naming a cell outside the grid
  /// (and then changes nothing).
  void update_cells(std::span<const Cell> cells, bool blocked) {
    std::visit([&](auto& s) { s.update_cells(cells, blocked); }, search_);
  }
  void set_blocked(Cell cell, bool blocked) { update_cells(std::span<const Cell>(&cell, 1), blocked); }

  Cell start() const {
    return std::visit([](const auto& s) { return s.start(); }, search_);
  }
  Cell goal() const {
    return std::visit([](const auto& s) { return s.goal(); }, search_);
  }
  const BlockedGrid& grid() const {
    return std::visit([](const auto& s) -> const BlockedGrid& { return s.grid(); }, search_);
  }
  const GridSearchOptions& options() const {
    return std::visit([](const auto& s) -> const GridSearchOptions& { return s.options(); }, search_);
  }
  /// Vertex expansions since construction (the work the incremental searches did).
  std::size_t expanded() const {
    return std::visit([](const auto& s) { return s.expanded(); }, search_);
  }
  /// Whether costs and keys are whole numbers in 32 bits (ExactKeys) rather than doubles.
  bool exact() const { return std::holds_alternative<DStarLiteSearch<ExactKeys>>(search_); }
  /// For a saved run (vwg/state.hpp): the kind of keys, then the search.
  void save(StateWriter& out) const;
  static DStarLite load(StateReader& in);

 private:
  explicit DStarLite(std::variant<DStarLiteSearch<ExactKeys>, DStarLiteSearch<RealKeys>> search) : search_(std::move(search)) {}
  std::variant<DStarLiteSearch<ExactKeys>, DStarLiteSearch<RealKeys>> search_;
};

}  // namespace vwg::plan
