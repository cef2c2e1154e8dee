"""The deciders written in C++ (vwg/robot/registries.hpp), each a factory the ``vwg.deciders`` entry
points of vwg's pyproject.toml name: the paper's A* and its relatives, D* Lite, the OMPL planners and a
random walk. The C++ registry holds their settings (the OMPL planners' budgets); these only make them."""

from __future__ import annotations

from collections.abc import Callable

import vwg._core as _core

__all__ = ["astar", "astar_octile", "dstar", "jps", "jps_octile", "prm", "random", "rrtconnect", "rrtstar"]


def _factory(name: str, doc: str) -> Callable[[], _core.Decider]:
    """A factory of the C++ decider registered as `name`."""

    def make() -> _core.Decider:
        return _core.create_decider(name)

    make.__name__ = make.__qualname__ = name.replace("-", "_")
    make.__doc__ = doc
    return make


astar = _factory("astar", "A* on the robot's own grid, 8-connected, Euclidean heuristic (the paper's decision).")
astar_octile = _factory("astar-octile", "A* with the octile heuristic (tighter on an 8-connected grid, the same "
                                        "paths' lengths).")
jps = _factory("jps", "Jump Point Search: A*'s optimal paths, fewer expansions (Euclidean heuristic).")
jps_octile = _factory("jps-octile", "Jump Point Search with the octile heuristic.")
dstar = _factory("dstar", "D* Lite: replans incrementally as the robot's map changes.")
rrtconnect = _factory("rrtconnect", "OMPL's RRT-Connect, bounded by iterations (the same run on any machine).")
rrtstar = _factory("rrtstar", "OMPL's RRT*, bounded by iterations.")
prm = _factory("prm", "OMPL's LazyPRM, bounded by iterations.")
random = _factory("random", "A random walk (the paper's baseline of a decision without a plan).")
