#include "vwg/detail/disc_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vwg::sim {

void DiscIndex::rebuild(std::span<const Disc> discs) {
  items_.resize(discs.size());
  max_radius_ = 0.0;
  if (discs.empty()) return;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double x1 = -kInf, y1 = -kInf;
  x0_ = y0_ = kInf;
  for (const Disc& d : discs) {
    max_radius_ = std::max(max_radius_, d.radius);
    if (!std::isfinite(d.x) || !std::isfinite(d.y)) continue;  // clamped to a corner's square
    x0_ = std::min(x0_, d.x), x1 = std::max(x1, d.x);
    y0_ = std::min(y0_, d.y), y1 = std::max(y1, d.y);
  }
  if (!std::isfinite(x1 - x0_) || !std::isfinite(y1 - y0_)) {  // no finite disc, or a spread beyond doubles: one square
    x0_ = y0_ = 0.0, side_ = kSquare, cols_ = rows_ = 1;
  } else {
    // cols × rows <= (w/side + 1)(h/side + 1) <= w·h/side² + w/side + h/side + 1 <= 3 · cap + 1.
    const double w = x1 - x0_, h = y1 - y0_, cap = static_cast<double>(std::max(kMinSquares, 4 * discs.size()));
    side_ = std::max({kSquare, std::sqrt(w * h / cap), w / (cap - 1), h / (cap - 1)});
    cols_ = static_cast<int>(std::min(w / side_, cap)) + 1;
    rows_ = static_cast<int>(std::min(h / side_, cap)) + 1;
  }
  start_.assign(static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_) + 1, 0);
  auto square_of = [&](const Disc& d) {
    return static_cast<std::size_t>(square(d.y, y0_, rows_)) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(square(d.x, x0_, cols_));
  };
  for (const Disc& d : discs) ++start_[square_of(d) + 1];
  for (std::size_t q = 1; q < start_.size(); ++q) start_[q] += start_[q - 1];
  next_.assign(start_.begin(), start_.end() - 1);
  for (std::uint32_t i = 0; i < discs.size(); ++i) items_[next_[square_of(discs[i])]++] = i;
}

}  // namespace vwg::sim
