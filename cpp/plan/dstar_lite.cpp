#include "vwg/plan/dstar_lite.hpp"

#include "plan/dstar_lite_search.hpp"

namespace vwg::plan {

template class DStarLiteSearch<RealKeys>;
template class DStarLiteSearch<ExactKeys>;

namespace {
std::variant<DStarLiteSearch<ExactKeys>, DStarLiteSearch<RealKeys>> make_search(BlockedGrid grid, Cell start, Cell goal,
                                                                                const GridSearchOptions& options) {
  if (ExactKeys::fits(options, grid.padded().size())) {
    return DStarLiteSearch<ExactKeys>(std::move(grid), start, goal, options);
  }
  return DStarLiteSearch<RealKeys>(std::move(grid), start, goal, options);
}
}  // namespace

DStarLite::DStarLite(BlockedGrid grid, Cell start, Cell goal, const GridSearchOptions& options)
    : search_(make_search(std::move(grid), start, goal, options)) {}

void DStarLite::save(StateWriter& out) const {
  out.boolean(exact());
  std::visit([&](const auto& s) { s.save(out); }, search_);
}

DStarLite DStarLite::load(StateReader& in) {
  if (in.boolean()) return DStarLite(DStarLiteSearch<ExactKeys>::load(in));
  return DStarLite(DStarLiteSearch<RealKeys>::load(in));
}

}  // namespace vwg::plan
