"""Planning on grids and in continuous space: A*, Jump Point Search and D* Lite on occupancy grids,
the OMPL planners (bounded by iterations, so runs are reproducible). Maps come from vwg.io.maps.

    path = vwg.plan.astar(grid.inflate(0.2), (row0, col0), (row1, col1))
"""

from __future__ import annotations

from vwg._core import DStarLite, OmplPlan, OmplPlanner, astar, jps, plan_ompl

__all__ = ["DStarLite", "OmplPlan", "OmplPlanner", "astar", "jps", "plan_ompl"]
