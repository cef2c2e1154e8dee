"""How well the robots' own maps agree with the true map (paper test 2, device independence): the
precision and recall of the occupied cells they marked with their sensors.

- precision: of the cells the robots marked occupied, the share within one cell of a truly occupied cell;
- recall: of the wall surface (occupied cells beside a free one) within ``reach`` metres of where a
  robot went, the share a robot marked (within one cell).

Both take the union of the robots' maps; marker cells (camera) are not counted.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

__all__ = ["map_quality"]


def _grow(mask: np.ndarray) -> np.ndarray:
    """`mask` and its 8 neighbours."""
    from scipy.ndimage import binary_dilation

    return binary_dilation(mask, structure=np.ones((3, 3), bool))


def map_quality(true_grid: object, robot_grids: Iterable[np.ndarray], paths: Iterable[np.ndarray],
                reach: float = 2.0) -> tuple[float, float]:
    """(precision, recall) of the robots' maps (int16: 100 wall, 101 seen, 1000+ marker) against
    `true_grid` (a vwg.io.maps.OccupancyGrid), the robots having gone along `paths` (N×2 metres each);
    NaN where there is nothing to count."""
    from scipy.ndimage import distance_transform_edt

    occupied = true_grid.blocked()  # type: ignore[attr-defined]
    marked = np.zeros(occupied.shape, bool)
    for grid in robot_grids:
        g = np.asarray(grid)
        marked |= (g >= 100) & (g < 1000)
    precision = float((marked & _grow(occupied)).sum() / marked.sum()) if marked.any() else math.nan
    visited = np.zeros(occupied.shape, bool)
    rows, cols = occupied.shape
    for path in paths:
        for x, y in np.asarray(path, dtype=float).reshape(-1, 2):
            r, c = true_grid.world_to_cell(x, y)  # type: ignore[attr-defined]
            if 0 <= r < rows and 0 <= c < cols:
                visited[r, c] = True
    if not visited.any():
        return precision, math.nan
    near = distance_transform_edt(~visited) * true_grid.resolution <= reach  # type: ignore[attr-defined]
    surface = occupied & _grow(~occupied) & near
    recall = float((surface & _grow(marked)).sum() / surface.sum()) if surface.any() else math.nan
    return precision, recall
