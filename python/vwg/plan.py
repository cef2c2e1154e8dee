"""Planning on grids and in continuous space: A*, Jump Point Search and D* Lite on occupancy grids,
the OMPL planners (bounded by iterations, so runs are reproducible). Maps come from vwg.io.maps.

    grid = vwg.io.maps.load_map("maps/office/map.yaml")
    path, length = vwg.plan.astar(grid.blocked(), grid.world_to_cell(1.5, 9.0), grid.world_to_cell(5.5, 16.8))
    # path: the (row, col) cells from start to goal, or None when there is no way; length in cells
"""

from __future__ import annotations

from vwg._core import DStarLite, OmplPlan, OmplPlanner, astar, jps, plan_ompl

__all__ = ["DStarLite", "OmplPlan", "OmplPlanner", "astar", "jps", "plan_ompl"]
