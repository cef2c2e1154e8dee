// Where the robots' discs are, by squares of the floor: a laser looks only at the robots in the
// squares its reach covers. Every scan used to test every other robot, so ten thousand robots cost
// a hundred million tests a frame, almost all of them robots tens of metres away.
//
// Not part of vwg's API (vwg/detail/): installed only because
// sim::PhysicsWorld (vwg/sim/physics.hpp) holds one by value.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace vwg::sim {

/// A robot's body as the lasers see it: a disc.
struct Disc {
  double x = 0.0, y = 0.0, radius = 0.0;
  int id = 0;
};

class DiscIndex {
 public:
  /// The side of a square, metres, unless the discs spread so far that there would be more than
  /// about three times max(kMinSquares, 4 × the discs) squares (then it grows to keep that: one
  /// robot far from the rest must not cost a table of millions of squares).
  static constexpr double kSquare = 2.0;
  static constexpr std::size_t kMinSquares = 1024;

  /// Sort `discs` into squares (a counting sort, linear in their number). Their positions are
  /// read now: call it again whenever they move.
  void rebuild(std::span<const Disc> discs);

  /// The largest radius of the discs (0 for none).
  double max_radius() const { return max_radius_; }
  /// The side of a square now, metres (kSquare or more) and how many there are.
  double side() const { return side_; }
  std::size_t squares() const { return start_.empty() ? 0 : start_.size() - 1; }

  /// Calls visit(i) for the index i (in the span given to rebuild) of every disc whose centre lies
  /// within `reach` of (x, y) on each axis, and for some beyond (those in the same squares), each
  /// once; within a square in the order of the span.
  template <class Visit>
  void near(double x, double y, double reach, Visit&& visit) const {
    within(x - reach, x + reach, y - reach, y + reach, visit);
  }
  /// The same for the box [x_lo, x_hi] × [y_lo, y_hi].
  template <class Visit>
  void within(double x_lo, double x_hi, double y_lo, double y_hi, Visit&& visit) const {
    if (items_.empty()) return;
    const int c0 = square(x_lo, x0_, cols_), c1 = square(x_hi, x0_, cols_);
    const int r0 = square(y_lo, y0_, rows_), r1 = square(y_hi, y0_, rows_);
    for (int r = r0; r <= r1; ++r) {
      const std::size_t row = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols_);
      for (std::uint32_t k = start_[row + static_cast<std::size_t>(c0)], end = start_[row + static_cast<std::size_t>(c1) + 1]; k < end; ++k) visit(items_[k]);
    }
  }

 private:
  /// The square of coordinate v along an axis starting at `origin` with `count` squares; clamped
  /// to the first and last (also for a coordinate that is not finite), which keeps the order of
  /// coordinates, so a query's range of squares always holds the squares of the discs within it.
  int square(double v, double origin, int count) const {
    const double s = (v - origin) / side_;
    if (!(s >= 0.0)) return 0;
    return s >= count - 1 ? count - 1 : static_cast<int>(s);
  }

  double x0_ = 0.0, y0_ = 0.0, side_ = kSquare, max_radius_ = 0.0;
  int cols_ = 1, rows_ = 1;
  // Squares row by row, columns within; the discs of square q are items_[start_[q] .. start_[q + 1]).
  // A row's squares are contiguous, so a query reads one run of items per row.
  std::vector<std::uint32_t> start_, items_;
  std::vector<std::uint32_t> next_;  // rebuild's scratch, kept to spare an allocation each time
};

}  // namespace vwg::sim
