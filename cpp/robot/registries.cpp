#include "vwg/robot/registries.hpp"

#include <mutex>

#include "vwg/robot/planners.hpp"

namespace vwg::robot {

Registry<Decider>& deciders() {
  static Registry<Decider> registry("decider");
  static std::once_flag built_in;
  std::call_once(built_in, [] {
    auto* r = &registry;
    r->add("random", [] { return std::make_shared<RandomDecider>(); });
    r->add("astar", [] { return std::make_shared<GridDecider>(GridDecider::Algorithm::AStar); });
    r->add("dstar", [] { return std::make_shared<GridDecider>(GridDecider::Algorithm::DStarLite); });
    r->add("jps", [] { return std::make_shared<GridDecider>(GridDecider::Algorithm::JumpPoint); });
    // The same searches with the octile heuristic: the same path lengths, fewer cells expanded
    // (the paper's A* uses the Euclidean distance, which "astar" keeps).
    r->add("astar-octile", [] { return std::make_shared<GridDecider>(GridDecider::Algorithm::AStar, plan::Heuristic::Octile); });
    r->add("jps-octile",
           [] { return std::make_shared<GridDecider>(GridDecider::Algorithm::JumpPoint, plan::Heuristic::Octile); });
    // RRT-Connect stops at its first solution; RRT* improves its path for all its iterations; "prm" is
    // OMPL's LazyPRM (PRM proper builds its roadmap on a second thread and is not reproducible).
    r->add("rrtconnect", [] { return std::make_shared<OmplDecider>("RRTConnect", OmplDecider::kDefaultIterations); });
    r->add("rrtstar", [] { return std::make_shared<OmplDecider>("RRTstar", 5000); });
    r->add("prm", [] { return std::make_shared<OmplDecider>("LazyPRM", 5000); });
  });
  return registry;
}

}  // namespace vwg::robot
