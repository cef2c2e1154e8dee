"""The deciders written in C++ (vwg/robot/registries.hpp), each a factory the ``vwg.deciders`` entry
points of vwg's pyproject.toml name: the paper's A* and its relatives, D* Lite, the OMPL planners and a
random walk. The C++ registry holds their settings (the OMPL planners' budgets); these only make them."""

from __future__ import annotations

import vwg._core as _core

__all__ = ["astar", "astar_octile", "dstar", "jps", "jps_octile", "prm", "random", "rrtconnect", "rrtstar"]


def astar() -> _core.Decider:
    """A* on the robot's own grid, 8-connected, Euclidean heuristic (the paper's decision)."""
    return _core.create_decider("astar")


def astar_octile() -> _core.Decider:
    """A* with the octile heuristic (tighter on an 8-connected grid, the same paths' lengths)."""
    return _core.create_decider("astar-octile")


def jps() -> _core.Decider:
    """Jump Point Search: A*'s optimal paths, fewer expansions (Euclidean heuristic)."""
    return _core.create_decider("jps")


def jps_octile() -> _core.Decider:
    """Jump Point Search with the octile heuristic."""
    return _core.create_decider("jps-octile")


def dstar() -> _core.Decider:
    """D* Lite: replans incrementally as the robot's map changes."""
    return _core.create_decider("dstar")


def rrtconnect() -> _core.Decider:
    """OMPL's RRT-Connect, bounded by iterations (the same run on any machine)."""
    return _core.create_decider("rrtconnect")


def rrtstar() -> _core.Decider:
    """OMPL's RRT*, bounded by iterations."""
    return _core.create_decider("rrtstar")


def prm() -> _core.Decider:
    """OMPL's LazyPRM, bounded by iterations."""
    return _core.create_decider("prm")


def random() -> _core.Decider:
    """A random walk (the paper's baseline of a decision without a plan)."""
    return _core.create_decider("random")
